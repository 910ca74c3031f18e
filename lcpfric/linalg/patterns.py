"""The pattern update of a box-constrained problem: the primal-dual active-set (semismooth
Newton) step, with Murty's least-index rule once a pattern repeats."""

from __future__ import annotations

import numpy as np

__all__ = ["PatternUpdate"]


class PatternUpdate:
    """The pattern update of a box-constrained problem (d = 1), shared by the stiffness and
    compliance forms here and by the half-plane contact: from the natural map ``z`` (``z >
    hi``: on the upper bound; ``z < lo``: on the lower; else stick), the semismooth Newton
    (primal-dual active-set) step; once a pattern repeats, Murty's least-index rule (change only
    the lowest-numbered node whose state is wrong), which terminates for a symmetric positive
    definite matrix. ``bounded``: the nodes that can be on a bound (the others are free)."""

    def __init__(self, bounded: np.ndarray, stats: dict | None = None):
        self.bounded = bounded
        self.stats = stats if stats is not None else {"iterations": 0, "single_changes": 0}
        self.seen: set = set()
        self.single = False

    def first(self, F_tr, lo, hi, warm=None):
        """The first pattern: the nodes whose trial force is out of its bounds, and those on
        their bounds at the start (``warm = (upper, lower)``)."""
        b = self.bounded
        nup, ndn = b & (F_tr > hi), b & (F_tr < lo)
        if warm is not None:
            nup = nup | (b & warm[0] & ~ndn)
            ndn = ndn | (b & warm[1] & ~nup)
        return nup, ndn

    def next(self, z, lo, hi, up, dn):
        """The next ``(upper, lower)``, or None when the pattern ``(up, dn)`` is the answer."""
        b = self.bounded
        nup, ndn = b & (z > hi), b & (z < lo)
        changed = (nup != up) | (ndn != dn)
        self.stats["iterations"] += 1
        if not changed.any():
            return None
        if not self.single:
            key = np.packbits(nup).tobytes() + np.packbits(ndn).tobytes()
            if key in self.seen:
                self.single = True
            self.seen.add(key)
        if self.single:
            i = int(np.flatnonzero(changed)[0])
            nup, ndn = up.copy(), dn.copy()
            nup[i], ndn[i] = (z[i] > hi[i]) & b[i], (z[i] < lo[i]) & b[i]
            self.stats["single_changes"] += 1
        return nup, ndn
