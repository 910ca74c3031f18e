"""Compiled kernels of the exact solver's event loop (numba; ``docs/architecture.md``,
"Compiled kernels").

Imported when a discrete system's exact solve starts (:class:`~lcpfric.exact.pattern.Pattern`),
never by ``import lcpfric`` or the single node's closed form, so the command line's start-up
does not pay for numba. Compiled on first use and cached on disk (``cache=True``: next to this
file, or numba's user-wide cache when the package directory is not writable).

Each kernel does what its numpy expression did, element by element in the same order and with
the same operations (no fused multiply-add, no reassociation), so results are bit-identical
(``tests/test_exact_kernels.py``): it only avoids numpy's temporaries, which at a free set of
hundreds of nodes made the update of ``G = K_BB⁻¹`` a matter of memory traffic.
"""

from __future__ import annotations

from numba import njit

__all__ = ["rank_one", "rank_one_on"]


@njit(cache=True, nogil=True)
def rank_one(G, m, x, y, sign):  # pragma: no cover - compiled
    """``G[:m, :m] += sign * outer(x, y)`` in place, ``sign`` +1 or -1 (as ``G += outer``
    or ``G -= outer``: the product rounded, then added)."""
    if sign > 0:
        for i in range(m):
            xi = x[i]
            row = G[i]
            for j in range(m):
                row[j] += xi * y[j]
    else:
        for i in range(m):
            xi = x[i]
            row = G[i]
            for j in range(m):
                row[j] -= xi * y[j]


@njit(cache=True, nogil=True)
def rank_one_on(G, idx, x, y, sign):  # pragma: no cover - compiled
    """``G[ix_(idx, idx)] += sign * outer(x, y)`` in place (x, y on ``idx``)."""
    k = idx.size
    if sign > 0:
        for a in range(k):
            i = idx[a]
            xi = x[a]
            for b in range(k):
                G[i, idx[b]] += xi * y[b]
    else:
        for a in range(k):
            i = idx[a]
            xi = x[a]
            for b in range(k):
                G[i, idx[b]] -= xi * y[b]
