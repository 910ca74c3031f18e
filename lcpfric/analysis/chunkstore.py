"""A directory of finished sweep chunks, so that an interrupted sweep loses nothing.

Layout of a store directory::

    manifest.json        what sweep the chunks belong to (grid, method, options, chunking)
    chunk-000000.npy     the Ŵ values of chunk 0 (flat, C order), written when chunk 0 finished
    chunk-000007.npy     ...

Every file is written to a temporary name in the same directory, flushed to disk and then renamed
over its final name (``os.replace`` is atomic on POSIX and Windows), so a reader sees either the
whole chunk or none of it: a process killed mid-write leaves at most a stray ``.tmp`` file, which
the next run removes. A chunk file whose shape does not match the manifest is treated as missing.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["ChunkStore", "atomic_write_bytes", "fingerprint", "temp_path"]

MANIFEST = "manifest.json"
_FORMAT = 1


def fingerprint(description: dict) -> str:
    """A short stable hash of a JSON-serializable sweep description."""
    text = json.dumps(description, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def temp_path(path: Path) -> str:
    """A new empty file next to ``path`` (same file system, so renaming it is atomic), with the
    permissions an ordinary new file gets (``mkstemp`` would make it private)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(tmp, 0o666 & ~mask)
    return tmp


def _atomic_write(path: Path, write) -> None:
    """Call ``write(fileobj)`` on a temporary file next to ``path``, then rename it to ``path``."""
    tmp = temp_path(path)
    try:
        with open(tmp, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def atomic_write_bytes(path, data: bytes) -> None:
    """Write ``data`` to ``path`` so that readers see the old file or the new one, never a part."""
    _atomic_write(Path(path), lambda fh: fh.write(data))


class ChunkStore:
    """Finished chunks of one sweep, one ``.npy`` file each, described by a manifest.

    Parameters
    ----------
    path : str or Path
        The store directory (created if needed).
    description : dict
        JSON-serializable description of the sweep (grid, method, options, chunking). A store
        whose manifest describes another sweep is never mixed with this one.
    chunk_sizes : sequence of int
        Number of values in each chunk.
    resume : bool
        True: keep the finished chunks of the same sweep. False: delete them and start again.
    """

    def __init__(self, path, description: dict, chunk_sizes, resume: bool = True):
        self.path = Path(path)
        self.chunk_sizes = [int(s) for s in chunk_sizes]
        # through JSON once, so that it compares equal to the manifest read back (tuples -> lists)
        self.description = json.loads(
            json.dumps({"format": _FORMAT, **description, "chunk_sizes": self.chunk_sizes})
        )
        self.key = fingerprint(self.description)
        self._open(resume)

    # -- opening -----------------------------------------------------------------------------------
    def _open(self, resume: bool) -> None:
        if self.path.exists() and not self.path.is_dir():
            raise InputError("store", f"{self.path} exists and is not a directory")
        self.path.mkdir(parents=True, exist_ok=True)
        for stray in self.path.glob(".*.tmp"):  # left by a process killed while writing
            stray.unlink(missing_ok=True)
        manifest = self.path / MANIFEST
        if manifest.exists():
            try:
                old = json.loads(manifest.read_text())
            except (OSError, ValueError):
                old = None
            if old != self.description and resume and self._chunk_files():
                raise InputError(
                    "store",
                    f"{self.path} holds chunks of a different sweep (other grid, method "
                    "or options); choose another store directory, or pass resume=False "
                    "(CLI: --restart) to discard them",
                )
            if old != self.description or not resume:
                self.clear_chunks()
        elif not resume:
            self.clear_chunks()
        atomic_write_bytes(manifest, json.dumps(self.description, indent=1).encode())

    def _chunk_files(self):
        return sorted(self.path.glob("chunk-*.npy"))

    def _file(self, index: int) -> Path:
        return self.path / f"chunk-{index:06d}.npy"

    # -- chunks ------------------------------------------------------------------------------------
    def load(self, index: int) -> np.ndarray | None:
        """The values of a finished chunk, or None if it is missing or unreadable."""
        f = self._file(index)
        if not f.exists():
            return None
        try:
            values = np.load(f, allow_pickle=False)
        except (OSError, ValueError, EOFError):
            values = None
        if (
            values is None
            or values.shape != (self.chunk_sizes[index],)
            or values.dtype != np.float64
        ):
            f.unlink(missing_ok=True)  # never trust it; the chunk is computed again
            return None
        return values

    def save(self, index: int, values) -> None:
        """Store a finished chunk atomically."""
        values = np.ascontiguousarray(values, dtype=np.float64).ravel()
        if values.shape != (self.chunk_sizes[index],):
            raise ValueError(
                f"chunk {index}: expected {self.chunk_sizes[index]} values, got {values.size}"
            )
        _atomic_write(self._file(index), lambda fh: np.save(fh, values, allow_pickle=False))

    def clear_chunks(self) -> None:
        for f in self._chunk_files():
            f.unlink(missing_ok=True)

    def remove(self) -> None:
        """Delete the store directory (after its contents were written elsewhere)."""
        for f in self._chunk_files():
            f.unlink(missing_ok=True)
        (self.path / MANIFEST).unlink(missing_ok=True)
        try:
            self.path.rmdir()
        except OSError:  # the user keeps other files there: leave them alone
            pass
