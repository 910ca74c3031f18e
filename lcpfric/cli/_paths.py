"""Output paths of the subcommands, checked before any work, and the clean-up of what a failed
run created. One rule for ``map``, ``figures`` and ``bench`` (:data:`OUTPUT_RULE`)."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

from ..errors import InputError

if TYPE_CHECKING:  # pathlib imports urllib and ipaddress: not for --help
    from pathlib import Path

__all__ = [
    "OUTPUT_RULE",
    "output_file",
    "output_dir",
    "snapshot",
    "written_files",
    "remove_created",
]

OUTPUT_RULE = (
    "The output's parent directory must exist; lcpfric creates only the output itself "
    "and removes what it created if the run fails."
)


def _parent_writable(path: Path, option: str) -> None:
    parent = path.parent
    if not parent.is_dir():
        raise InputError(
            option,
            f"the directory {str(parent)!r} does not exist; create it "
            "first (lcpfric creates only the output itself)",
        )
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(
            option, f"cannot write in the directory {str(parent)!r} (permission denied)"
        )


def _cannot(option: str, text: str, exc: OSError) -> InputError:
    reason = exc.strerror or type(exc).__name__
    return InputError(option, f"cannot create {text!r}: {reason}")


def _probe_file(path: Path, text: str, option: str) -> None:
    """Open the output for writing once (without changing it), so that a path the checks let
    through but the system refuses (``/proc/x``, a full or read-only file system) fails here,
    before any work, and not after it."""
    try:
        if path.exists():
            with open(path, "ab"):
                pass
        else:
            with open(path, "xb"):
                pass
            path.unlink()
    except OSError as exc:
        raise _cannot(option, text, exc) from None


def _probe_dir(path: Path, text: str, option: str) -> None:
    """Create a file in the output directory (or the directory itself) once, and remove it."""
    import tempfile

    try:
        if path.is_dir():
            fd, name = tempfile.mkstemp(dir=path, prefix=".lcpfric-probe-")
            os.close(fd)
            os.unlink(name)
        else:
            path.mkdir()
            path.rmdir()
    except OSError as exc:
        raise _cannot(option, text, exc) from None


def output_file(text, option: str, suffix) -> Path:
    """Check an output file path before any work: not empty, ending in ``suffix`` (one, or a
    tuple of allowed ones), not a directory, in an existing writable directory."""
    from pathlib import Path

    suffixes = (suffix,) if isinstance(suffix, str) else tuple(suffix)
    name = {".nc": "map", ".png": "loop", ".pdf": "loop", ".svg": "loop"}.get(suffixes[0], "out")
    text = "" if text is None else str(text)
    if not text.strip():
        raise InputError(
            option, f"is empty; give a file name ending in {suffixes[0]}, e.g. {name}{suffixes[0]}"
        )
    path = Path(text)
    if path.is_dir() or text.endswith(("/", os.sep)):
        raise InputError(
            option,
            f"{text!r} is a directory; give a file name ending in "
            f"{suffixes[0]}, e.g. {str(path / (name + suffixes[0]))!r}",
        )
    if path.suffix.lower() not in suffixes:
        what = (
            " (the file is written as NetCDF-4)"
            if suffixes == (".nc",)
            else f" (one of {', '.join(suffixes)})"
        )
        raise InputError(option, f"must end in {suffixes[0]}{what}, got {text!r}")
    if path.exists() and not path.is_file():
        raise InputError(option, f"{text!r} exists and is not a regular file")
    _parent_writable(path, option)
    if path.exists() and not os.access(path, os.R_OK):
        raise InputError(option, f"{text!r} exists and cannot be read (permission denied)")
    _probe_file(path, text, option)
    return path


def output_dir(text, option: str) -> Path:
    """Check an output directory path before any work: not empty, not an existing file, its
    parent an existing writable directory (or itself an existing writable directory)."""
    from pathlib import Path

    text = "" if text is None else str(text)
    if not text.strip():
        raise InputError(
            option, "is empty; give a directory, e.g. figures (use . for the working directory)"
        )
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise InputError(option, f"{text!r} exists and is not a directory")
    if path.is_dir():
        if not os.access(path, os.W_OK | os.X_OK):
            raise InputError(option, f"cannot write in {text!r} (permission denied)")
        _probe_dir(path, text, option)
        return path
    _parent_writable(path, option)
    _probe_dir(path, text, option)
    return path


def _stat_key(path: Path):
    try:
        st = path.stat()
    except OSError:
        return None
    return (st.st_ino, st.st_size, st.st_mtime_ns)


def snapshot(directory: Path) -> dict:
    """What files ``directory`` holds now (to tell afterwards which ones a run wrote)."""
    if not directory.is_dir():
        return {}
    return {p.name: _stat_key(p) for p in directory.iterdir()}


def written_files(directory: Path, before: dict, names=None) -> list[Path]:
    """The files of ``directory`` (among ``names`` if given) that are new or changed since the
    ``before`` snapshot."""
    if not directory.is_dir():
        return []
    out = []
    for p in sorted(directory.iterdir()):
        if names is not None and p.name not in names:
            continue
        if p.is_file() and before.get(p.name) != _stat_key(p):
            out.append(p)
    return out


def remove_created(directory: Path, before: dict, existed: bool) -> None:
    """After a failed run: delete the files the run created in ``directory`` (never one that
    was there before), and the directory itself if the run created it and it is now empty."""
    if not directory.is_dir():
        return
    for p in directory.iterdir():
        if p.name not in before and p.is_file():
            p.unlink(missing_ok=True)
    if not existed:
        try:
            directory.rmdir()
        except OSError:
            pass
