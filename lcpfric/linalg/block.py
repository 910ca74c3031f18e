"""What every block of :mod:`lcpfric.linalg.blocks` shares: the current set, the counters, the
products with K, and the error of a block that is not positive definite."""

from __future__ import annotations

import numpy as np

from ..errors import SolverError

__all__ = ["Block", "not_spd", "columns_product", "MAX_BANDWIDTH", "FOLD_RANK"]

#: largest bandwidth (after reordering) for which the banded Cholesky is used: beyond it the
#: band holds more than a sparse factor would
MAX_BANDWIDTH = 64
#: rank of the dense block's low-rank correction at which it is folded into its inverse
FOLD_RANK = 48


def not_spd(what: str) -> SolverError:
    return SolverError(
        f"active-set: {what} is not positive definite (K must be SPD)",
        backend="active-set",
        status="not_spd",
    )


class Block:
    """Common part: the current set (sorted unknowns) and the counters."""

    def __init__(self, K):
        self.K = K
        self.m = K.shape[0]
        self.index = np.empty(0, dtype=np.intp)
        self.stats = {"factorizations": 0, "updates": 0}

    @property
    def size(self) -> int:
        return int(self.index.size)

    def matvec(self, x: np.ndarray) -> np.ndarray:
        """``K x``."""
        return self.K @ x

    def product(self, cols: np.ndarray, y: np.ndarray) -> np.ndarray:
        """``K x`` for the x that is ``y`` on the unknowns ``cols`` and zero elsewhere."""
        return columns_product(self.K, cols, y)


def columns_product(K, cols: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``K x`` for the x that is ``y`` on the unknowns ``cols`` and zero elsewhere: from those
    columns (rows: K is symmetric) when they are few, else with the whole K."""
    m = K.shape[0]
    if 8 * cols.size < m:
        return K[:, cols] @ y if hasattr(K, "tocsc") else y @ K[cols]
    x = np.zeros(m)
    x[cols] = y
    return K @ x
