"""The pattern update of a box-constrained problem: the primal-dual active-set (semismooth
Newton) step, with Murty's least-index rule once a pattern repeats."""

from __future__ import annotations

import numpy as np

__all__ = ["PatternUpdate"]


class PatternUpdate:
    """The pattern update of a box-constrained problem (d = 1).

    Shared by the stiffness and compliance forms here and by the half-plane contact: from the
    natural map ``z`` (``z > hi``: on the upper bound; ``z < lo``: on the lower; else stick),
    the semismooth Newton (primal-dual active-set) step; once a pattern repeats, Murty's
    least-index rule (change only the lowest-numbered node whose state is wrong), which
    terminates for a symmetric positive definite matrix.

    One object serves one solve: it remembers the patterns seen.

    Parameters
    ----------
    bounded : (n,) bool ndarray
        The nodes that can be on a bound (the others are free).
    stats : dict, optional
        The counters to add to (a dict with ``iterations`` and ``single_changes``, updated in
        place); default a new one.

    Attributes
    ----------
    bounded : (n,) bool ndarray
        As given.
    stats : dict
        ``iterations`` (calls of :meth:`next`) and ``single_changes`` (Murty steps).
    seen : set
        The patterns met so far (as bytes).
    single : bool
        Whether a pattern repeated, so that Murty's rule is in force.
    """

    def __init__(self, bounded: np.ndarray, stats: dict[str, int] | None = None) -> None:
        self.bounded = bounded
        self.stats = stats if stats is not None else {"iterations": 0, "single_changes": 0}
        self.seen: set = set()
        self.single = False

    def first(
        self,
        F_tr: np.ndarray,
        lo: np.ndarray,
        hi: np.ndarray,
        warm: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """The first pattern, from the trial forces and the pattern at the start.

        The nodes whose trial force is out of its bounds, and those on their bounds at the
        start (``warm = (upper, lower)``).

        Parameters
        ----------
        F_tr : (n,) ndarray
            The trial forces.
        lo, hi : (n,) ndarray
            The lower and upper bounds.
        warm : tuple of two (n,) bool ndarrays, optional
            ``(upper, lower)``: the nodes on their upper and lower bounds at the start (a trial
            force out of the other bound wins).

        Returns
        -------
        upper : (n,) bool ndarray
            The bounded nodes on their upper bound.
        lower : (n,) bool ndarray
            The bounded nodes on their lower bound.
        """
        b = self.bounded
        nup, ndn = b & (F_tr > hi), b & (F_tr < lo)
        if warm is not None:
            nup = nup | (b & warm[0] & ~ndn)
            ndn = ndn | (b & warm[1] & ~nup)
        return nup, ndn

    def next(
        self, z: np.ndarray, lo: np.ndarray, hi: np.ndarray, up: np.ndarray, dn: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The next ``(upper, lower)``, or None when the pattern ``(up, dn)`` is the answer.

        Parameters
        ----------
        z : (n,) ndarray
            The natural map of the current pattern's solution.
        lo, hi : (n,) ndarray
            The lower and upper bounds.
        up, dn : (n,) bool ndarray
            The current pattern: the nodes on their upper and on their lower bound.

        Returns
        -------
        tuple of two (n,) bool ndarrays, or None
            The next ``(upper, lower)``: every wrong node changed (the semismooth Newton
            step) or, once a pattern has repeated, only the lowest-numbered one (Murty's
            rule). None when no node is wrong.
        """
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
