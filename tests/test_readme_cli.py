"""Every ``lcpfric ...`` command in the code blocks of the README and of the documentation's pages
runs as written and exits with code 0.

Each command runs in its own empty directory, in this process (``lcpfric.cli.main``). A command
that reads a file a Python snippet of the same page writes (``surface.npy``) gets that snippet run
first, as a reader following the page would. Optional parts in brackets are left out; the
command is run a second time with them where they hold no placeholder (an upper-case word such
as ``N`` or ``DIR``). Lines joined by ``\\`` are one command, and ``a && lcpfric ...`` runs the
``lcpfric`` part. The long commands (the figures, contact maps, the 3-D half-space at grid 40) are
marked slow; the others take a few seconds in all.
"""

import re
import shlex
from pathlib import Path

import pytest

from support import need_modules

ROOT = Path(__file__).resolve().parents[1]
PAGES = [
    ROOT / "README.md",
    *sorted((ROOT / "docs").glob("*.md")),
    *sorted((ROOT / "docs").glob("*/*.md")),
]
SHELLS = ("bash", "sh", "shell", "console", "")
OPTIONAL = re.compile(r"\s+\[(--[^\]]*)\]")
PLACEHOLDER = re.compile(r"\b[A-Z]+\b")
OPERATORS = {"&&", "||", ";", "|", "&"}
#: a line that runs lcpfric: at its start (after a ``$`` prompt) or after an operator
RUNS = re.compile(r"(^|&&|;|\|)\s*(\$\s+)?lcpfric\s")


def _blocks(text: str, languages) -> list[str]:
    """The page's fenced code blocks in one of ``languages``, in order."""
    out, language, lines = [], None, []
    for line in text.splitlines():
        fence = re.match(r"^\s*```\s*([\w+-]*)", line)
        if fence and language is None:
            language, lines = fence.group(1).lower(), []
        elif fence:
            if language in languages:
                out.append("\n".join(lines) + "\n")
            language = None
        elif language is not None:
            lines.append(line)
    return out


def _split(line: str) -> list[list[str]]:
    """The line's commands (split at ``&&``, ``;``, ``|``; comments dropped)."""
    lexer = shlex.shlex(line, posix=True, punctuation_chars="&|;")
    lexer.whitespace_split = True
    commands, current = [], []
    for token in lexer:
        if token in OPERATORS:
            commands.append(current)
            current = []
        else:
            current.append(token)
    return [c for c in [*commands, current] if c]


def _variants(line: str) -> list[str]:
    """The line without its optional parts, and with those that hold no placeholder."""
    bare = OPTIONAL.sub("", line)
    full = OPTIONAL.sub(lambda m: "" if PLACEHOLDER.search(m.group(1)) else " " + m.group(1), line)
    return [bare] if full == bare else [bare, full]


def _commands() -> list:
    """(page, argv) of every command, each distinct argv once (at its first page)."""
    out, seen = [], []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for block in _blocks(text, SHELLS):
            joined = re.sub(r"\\\n\s*", " ", block)
            for line in joined.splitlines():
                if not RUNS.search(line):
                    continue
                line = re.sub(r"^\s*\$\s+", "", line)
                for variant in _variants(line):
                    for argv in _split(variant):
                        if argv[0] == "lcpfric" and argv[1:] not in seen:
                            seen.append(argv[1:])
                            out.append((page, argv[1:]))
    return out


COMMANDS = _commands()


def _slow(argv: list[str]) -> bool:
    """More than a few seconds: every figure set, contact maps, and the 3-D half-space except a
    small height map."""
    command = argv[0] if argv else ""
    if command == "figures":
        return True
    if command == "map" and "--contact" in argv:
        return True
    return command == "contact" and "--model" in argv and "halfspace" in argv


def _id(page: Path, argv: list[str]) -> str:
    return f"{page.stem}:{' '.join(argv)}"


PARAMS = [
    pytest.param(page, argv, id=_id(page, argv), marks=[pytest.mark.slow] if _slow(argv) else [])
    for page, argv in COMMANDS
]


def _prepare(page: Path, argv: list[str]) -> None:
    """Run the page's Python snippets that write a file the command names."""
    for block in _blocks(page.read_text(encoding="utf-8"), ("python",)):
        if any(f'"{token}"' in block for token in argv if "." in token):
            exec(compile(block, str(page), "exec"), {})  # noqa: S102 - our docs


def test_the_commands_are_found():
    """The collection itself: every page's commands are seen, none is a placeholder (``...``)."""
    assert len(COMMANDS) >= 15
    assert {argv[0] for _, argv in COMMANDS} >= {
        "dissipation",
        "loop",
        "shakedown",
        "contact",
        "map",
        "figures",
        "paper-claims",
        "methods",
    }
    assert not [argv for _, argv in COMMANDS if "..." in argv]
    assert any("--heightmap" in argv for _, argv in COMMANDS)


@pytest.mark.parametrize("page, argv", PARAMS)
def test_command_runs_as_written(page, argv, tmp_path, monkeypatch, capsys):
    need_modules("xarray", "matplotlib", "h5netcdf")
    from lcpfric.cli import main

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    _prepare(page, argv)
    try:
        code = main(list(argv))
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    assert code in (0, None), f"lcpfric {shlex.join(argv)} exited {code}:\n{err[-2000:]}"
