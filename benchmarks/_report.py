"""What the half-space benchmarks' results files share: the line that says how and when they
were made, and a list of lines that prints as it grows."""

from __future__ import annotations

import subprocess
import time
from pathlib import Path


def stamp(command: str) -> str:
    """``\\`OPENBLAS_NUM_THREADS=1 python benchmarks/<command>\\` at <commit>, <UTC time>``: a
    results file's provenance (the commit of the checkout it ran in)."""
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, cwd=Path(__file__).parent).stdout.strip()
    return (f"`OPENBLAS_NUM_THREADS=1 python benchmarks/{command}` at {commit}, "
            f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")


class Report(list):
    """A results file's lines; ``emit`` prints one and keeps it."""

    def emit(self, text: str = "") -> None:
        print(text, flush=True)
        self.append(text)

    def write(self, path) -> None:
        Path(path).write_text("\n".join(self) + "\n", encoding="utf-8")
