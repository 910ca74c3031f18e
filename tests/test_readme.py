"""Every Python snippet of the README and of the documentation's pages runs as written (the
snippets of one page share one namespace, as a reader running them in order would; lines that
need a cluster, or stand for a call already shown (``...``), are left out)."""

import re
from pathlib import Path

import pytest

from support import need_modules

ROOT = Path(__file__).resolve().parents[1]
PAGES = [
    p
    for p in [
        ROOT / "README.md",
        *sorted((ROOT / "docs").glob("*.md")),
        *sorted((ROOT / "docs" / "guide").glob("*.md")),
    ]
    if "```python" in p.read_text()
]


def _runnable(block: str) -> str:
    return "\n".join(
        line
        for line in block.splitlines()
        if "tcp://" not in line and "(..." not in line and "..., " not in line
    )


@pytest.mark.slow
@pytest.mark.parametrize("page", PAGES, ids=[p.stem for p in PAGES])
def test_snippets_run(page, tmp_path, monkeypatch):
    need_modules("xarray", "matplotlib", "clarabel")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(), re.S)
    namespace = {}
    for block in blocks:
        exec(compile(_runnable(block), str(page), "exec"), namespace)  # noqa: S102 - our docs


def test_readme_fits_a_screen_or_two():
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 150
    assert not re.search(r"\b(at|since|before) [0-9a-f]{7}\b", text)  # no commit hashes
