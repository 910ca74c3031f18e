"""The ``active-set`` stepper's pattern iterations for d = 1 (:mod:`.active_set`, "The method
(d = 1)" and "Matrix-free systems"): the primal-dual active-set iteration on K (the blocks of
:mod:`lcpfric.linalg.blocks`, refined on K) and on a compliance known by its products (conjugate
gradients on the sticking nodes, :class:`~lcpfric.linalg.OperatorBlock`)."""

from __future__ import annotations

import math

import numpy as np

from ..linalg import PatternUpdate

__all__ = ["BoxPatterns"]

_EPS = np.finfo(float).eps


def _through_stick(updates, up, dn, nup, ndn):
    """The next pattern, a node going from one bound to the other passing through stick once
    Murty's single changes are in force (``updates.single``): a node on its lower bound whose
    natural map lies above its upper one first sticks. Jumping straight across can cycle
    between two patterns (met on a 3-node chain with k_coupling = 19: the least-index node
    flipping between its bounds for ever); one bound at a time, as the least-index rule moves
    a node of the box problem written as an LCP in the split slips."""
    if not updates.single:
        return nup, ndn
    across = (up & ndn) | (dn & nup)
    if not across.any():
        return nup, ndn
    return nup & ~across, ndn & ~across


class BoxPatterns:
    """The d = 1 iterations of :class:`~lcpfric.steppers.active_set.ActiveSetStepper`."""

    def box_pattern(self, plan, F_tr, lo, hi, free_always, stats, k, warm=None):
        """The pattern iteration (d = 1): ``δ`` (zero on the sticking unknowns) and
        ``F = F^tr + K δ`` with every node either sticking (``δ_i = 0``, ``lo_i <= F_i <=
        hi_i``), on its upper bound with ``δ_i <= 0``, on its lower bound with ``δ_i >= 0``, or,
        in ``free_always``, at ``F_i = 0``; also the final ``(upper, lower)`` masks.

        Each iteration corrects the previous one rather than solving afresh: the nodes that
        stop are put back (``δ_i = 0``), and ``K_FF Δ = (r - F)_F`` is solved for the nodes
        whose force is off its target by more than round-off, so that a block that can solve
        locally (:class:`~lcpfric.linalg.blocks.BandedBlock`) touches only the parts of the
        free set that changed. The first iteration starts from everything stuck (``δ = 0``,
        ``F = F^tr``) and the pattern of the nodes whose trial force is out of its limits,
        with, if ``warm`` is given, the nodes on their limits at the start of the increment
        (the previous increment's pattern: between two increments few nodes change, so the
        first guess is then nearly the answer and the block changes little)."""
        kd = plan.kdiag
        bounded = ~free_always
        delta = np.zeros(plan.m)
        F = F_tr.copy()
        free = np.zeros(plan.m, dtype=bool)
        up = dn = free
        updates = PatternUpdate(bounded, stats)
        nup, ndn = updates.first(F_tr, lo, hi, warm)
        for _ in range(self.max_iter):
            nfree = nup | ndn | free_always
            stop = np.flatnonzero(free & ~nfree)
            if stop.size:  # nodes that stick again keep their start displacement
                F += plan.block.product(stop, -delta[stop])
                delta[stop] = 0.0
            up, dn, free = nup, ndn, nfree
            r = np.where(up, hi, np.where(dn, lo, 0.0))
            self._correct(plan, F_tr, r, free, delta, F, stats)
            nxt = updates.next(F - delta * kd, lo, hi, up, dn)
            if nxt is None:
                return delta, F, (up, dn)
            nup, ndn = _through_stick(updates, up, dn, *nxt)
        raise self.unsettled(k, "the pattern")

    def operator_pattern(self, plan, F_tr, lo, hi, free_always, stats, k, warm=None):
        """The pattern iteration of :meth:`box_pattern` in the compliance form, for a matrix-free
        system: the same answer ``(δ, F, (upper, lower))``, with ``δ = C (F - F^tr)``.

        With the pattern fixed, the forces of the nodes on a limit (and of the separated ones,
        0) are known; those of the sticking nodes S solve ``C_SS (F - F^tr)_S = -C_SA (F -
        F^tr)_A`` (``δ_S = 0``), corrected from the previous iteration's forces by conjugate
        gradients (:class:`~lcpfric.linalg.blocks.OperatorBlock`) to ``max |δ_S| <=
        1e-13 s_C s_F`` (the compliance and force scales: 1e7 below the residual check).
        The pattern update, the warm start and the least-index fallback are :meth:`box_pattern`'s:
        ``z_i = F_i - δ_i / C_ii``."""
        block, kd = plan.block, plan.kdiag
        bounded = ~free_always
        tol = 1e-13 * plan.compliance_scale * plan.force_scale
        F = F_tr.copy()
        updates = PatternUpdate(bounded, stats)
        nup, ndn = updates.first(F_tr, lo, hi, warm)
        for _ in range(self.max_iter):
            up, dn = nup, ndn
            F[up], F[dn], F[free_always] = hi[up], lo[dn], 0.0
            delta = block.apply(F - F_tr)
            S = np.flatnonzero(~(up | dn | free_always))
            if S.size:
                x, Cx = block.solve(S, -delta[S], tol)
                F[S] += x
                delta += Cx
            nxt = updates.next(F - delta * kd, lo, hi, up, dn)
            if nxt is None:
                return delta, F, (up, dn)
            nup, ndn = _through_stick(updates, up, dn, *nxt)
        raise self.unsettled(k, "the pattern")

    @staticmethod
    def _correct(plan, F_tr, r, free, delta, F, stats):
        """Correct ``δ`` and ``F = F^tr + K δ`` (in place) so that ``F_F = r_F`` on the free
        set, solving ``K_FF Δ_F = (r - F)_F`` where the forces are off by more than round-off,
        then refining on K (iterative refinement) until they are at round-off. After a solve
        only the unknowns it changed are checked again (the others were at round-off)."""
        block = plan.block
        sel = np.flatnonzero(free)
        block.set(sel)
        best = math.inf
        for it in range(6):
            e = r[sel] - F[sel]
            # round-off of the forces: a few ulps of the largest of the terms summed
            floor = 8 * _EPS * (np.abs(F_tr[sel]) + np.abs(r[sel]) + plan.force_scale)
            off = np.abs(e) > floor
            if not off.any():
                return
            if it:
                size = float(np.max(np.abs(e) / floor))
                if size >= 0.5 * best:
                    return  # refinement no longer gains: at the attainable accuracy
                best = size
                stats["refinements"] += 1
            rhs = np.zeros(plan.m)
            rhs[sel] = e
            sel, y = block.solve(rhs, sel[off])
            delta[sel] += y
            F += block.product(sel, y)
