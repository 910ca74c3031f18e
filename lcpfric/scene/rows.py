"""The loads of a large scene on its grid, computed when asked for (:class:`Rows`), and the
reductions over a cycle that go chunk by chunk of rows, so that the whole array is never built
(:func:`column_reduce`, :func:`column_max`). Re-exported by :mod:`lcpfric.scene`.
"""

from __future__ import annotations

import numpy as np

from .. import memory

__all__ = ["Rows", "chunks", "column_reduce", "column_max"]

_CHUNK_BYTES = 32 * 2**20


class Rows:
    """The rows of Q or N on the grid, computed when asked for: a large scene (1e5 nodes, 2000
    steps: 1.6 GB each as arrays) keeps its loads as functions of time.

    ``rows[k]`` is the row at ``t[k]`` (1-D), ``rows[ks]`` (a slice or an index array) the rows
    at those instants (2-D); ``rows / s`` scales the values; ``np.asarray(rows)`` builds the
    whole array (what a method that needs it does; its memory is then checked like any
    other). A method written for large systems asks for rows one instant at a time.
    """

    ndim = 2

    def __init__(self, fn, t: np.ndarray, width: int, divisor: float = 1.0):
        self.fn, self.t, self.width, self.divisor = fn, t, int(width), float(divisor)

    @property
    def shape(self) -> tuple[int, int]:
        return (self.t.size, self.width)

    def __len__(self) -> int:
        return self.t.size

    def __getitem__(self, key):
        rest = ()
        if isinstance(key, tuple):
            key, rest = key[0], key[1:]
        x = self.fn(self.t[key])
        if self.divisor != 1.0:
            x = x / self.divisor
        return x[(slice(None),) * (x.ndim - 1) + rest] if rest else x

    def __truediv__(self, divisor):
        return Rows(self.fn, self.t, self.width, self.divisor * float(divisor))

    def __array__(self, dtype=None, copy=None):
        memory.check(
            8.0 * self.t.size * self.width,
            "steps_per_cycle",
            f"the loads of the whole cycle ({self.t.size} instants x {self.width})",
        )
        out = np.concatenate([self[a:b] for a, b in chunks(self.t.size, self.width)])
        return out if dtype is None else out.astype(dtype)


def chunks(rows: int, width: int):
    """``(start, stop)`` row ranges of about :data:`_CHUNK_BYTES` each."""
    step = max(1, int(_CHUNK_BYTES // (8 * max(1, width))))
    for a in range(0, rows, step):
        yield a, min(rows, a + step)


def column_reduce(x, fn) -> list:
    """``fn`` of each chunk of rows of an array or of :class:`Rows` (for reductions over the
    cycle that must not build the whole array)."""
    return [fn(x[a:b]) for a, b in chunks(x.shape[0], x.shape[1])]


def column_max(fn, grid, width):
    """Per column, the largest value of ``fn(t)`` over the grid, chunk by chunk."""
    parts = [np.max(fn(grid[a:b]), axis=0) for a, b in chunks(grid.size, width)]
    return np.max(parts, axis=0)
