"""Every Python snippet of the README runs as written (they share one namespace, as a reader
running them in order would; the Dask scheduler line needs a cluster and is left out)."""

import re
from pathlib import Path

import pytest

from support import need_modules

README = Path(__file__).resolve().parents[1] / "README.md"


@pytest.mark.slow
def test_readme_snippets_run(tmp_path, monkeypatch):
    need_modules("xarray")
    need_modules("matplotlib")
    need_modules("clarabel")
    monkeypatch.chdir(tmp_path)
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)
    assert len(blocks) >= 3
    namespace = {}
    for block in blocks:
        code = "\n".join(line for line in block.splitlines() if "tcp://scheduler" not in line)
        exec(compile(code, str(README), "exec"), namespace)  # noqa: S102 - our own README
    assert (tmp_path / "maps.nc").exists() and (tmp_path / "loop.pdf").exists()
    assert namespace["loop"].area == pytest.approx(namespace["r"].W, rel=1e-5)
