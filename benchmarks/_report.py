"""What the benchmarks' results files share: the line that says how and when they were made, a
list of lines that prints as it grows, and a copy of a script's standard output."""

from __future__ import annotations

import contextlib
import io
import subprocess
import sys
import time
from pathlib import Path


def stamp(command: str) -> str:
    """``\\`OPENBLAS_NUM_THREADS=1 python benchmarks/<command>\\` at <commit>, <UTC time>``: a
    results file's provenance (the commit of the checkout it ran in)."""
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"],
        capture_output=True,
        text=True,
        cwd=Path(__file__).parent,
    ).stdout.strip()
    return (
        f"`OPENBLAS_NUM_THREADS=1 python benchmarks/{command}` at {commit}, "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}"
    )


class Report(list):
    """A results file's lines; ``emit`` prints one and keeps it."""

    def emit(self, text: str = "") -> None:
        print(text, flush=True)
        self.append(text)

    def write(self, path) -> None:
        Path(path).write_text("\n".join(self) + "\n", encoding="utf-8")


class _Tee:
    """A stream writing to two streams."""

    def __init__(self, *streams):
        self.streams = streams

    def write(self, text: str) -> int:
        for s in self.streams:
            s.write(text)
        return len(text)

    def flush(self) -> None:
        for s in self.streams:
            s.flush()


@contextlib.contextmanager
def results_file(path, title: str, command: str, markdown: bool = False):
    """Print as usual and keep a copy in the results file ``path`` (None: print only), under a
    title and the :func:`stamp` of ``command``; the output in a code block, or as it is when it
    is ``markdown``."""
    if path is None:
        yield
        return
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    buffer = io.StringIO()
    with contextlib.redirect_stdout(_Tee(sys.stdout, buffer)):
        yield
    fence = "" if markdown else "```\n"
    path.write_text(
        f"# {title}\n\n{stamp(command)}; its standard output:\n\n{fence}"
        f"{buffer.getvalue().rstrip()}\n{fence}",
        encoding="utf-8",
    )
    print(f"wrote {path}")
