r"""The half-space's increment by a semismooth Newton method (:class:`HalfSpaceIncrements`,
for the ``newton-cg`` stepper of :mod:`.newton_cg`, where problem (P) is set out): the friction
forces on the nodes in contact, their limits b, the slips and the body's rigid displacement δ.

It is solved as the nonsmooth equation ``F = proj_b(F − Δs(F)/c)`` (c the diagonal of C) by a
semismooth Newton method, warm-started from the previous increment (its forces extrapolated,
its pattern), or from the same increment of the previous cycle; the state carries ``C F`` and
the change's ``C ΔF`` (C is linear), so a start costs no product. With the pattern of a
Newton iterate fixed, the step is one symmetric positive definite linear system on the
sticking components and, for d = 2, the components of the slipping nodes' forces tangent to
their circle (with the diagonal term ``|Δs_i| / b_i``), under the equilibrium as a linear
constraint; it is solved by conjugate gradients, projected onto the constraint
(``k_support = 0``) or with the support's rank-d term (``k_support > 0``), one product with C
per iteration (and one for the known forces and the start together) and one with the
preconditioner, the inverse of the padded circulant operator; on the slipping nodes' tangential
unknowns, whose operator adds the diagonal term to C's c, it is scaled by ``sqrt(c / (c +
term))`` on both sides (symmetric). For d = 1
this is the primal-dual active-set iteration of the ``active-set`` backend (the slipping forces
are known), and its answer is exact once the pattern is right: a step with a new pattern is
solved to a hundredth of the residual (it only decides the next pattern; on a rough contact the
first patterns are often wrong), and a pattern that repeats once more to full accuracy. Where
the patterns stall (a large increment on a fine grid changes the state of thousands of nodes,
and Murty's rule, the pattern rule's fallback, changes one per iteration), d = 1 turns to the
damped steps of d = 2. For d = 2 each step is damped by a line search on the natural map's
residual, and the slip directions converge quadratically near the answer. The answer is
accepted when the natural-map residual is below ``tol × force scale`` on every node (the
force scale: the largest limit μ p h², or the force that moves a node by the loads'
displacement scale ``Q/k_t0``, if smaller: a small tangential load is solved as accurately as
a large one); an iteration that does not get there raises :class:`~lcpfric.errors.SolverError`.

The state an increment takes and gives (:class:`Tangential`) carries the slips, δ, the forces,
the last changes and their products with C. The Newton steps themselves are in
:mod:`.newton_step`.
"""

from __future__ import annotations

import copy
import time
from dataclasses import dataclass

import numpy as np

from ..errors import SolverError
from ..linalg import PatternUpdate
from ..model.continuum.halfspace import compliance, pad
from ..model.continuum.influence import Counted
from .newton_step import CG_TOL, ETA, NewtonSteps, nearest_to_sticking

__all__ = ["HalfSpaceIncrements", "Tangential"]

_MAX_NEWTON = 60
#: d = 1: pattern iterations from the extrapolated start before the safe restart
_RESTART = 8
_EPS = np.finfo(float).eps
#: d = 1: the linear solves of the steps with a new pattern are to this fraction of the
#: residual (the repeated pattern's to full accuracy)
_ETA1 = 1e-2
#: d = 1: single changes by Murty's rule before the damped Newton steps of d = 2 take over
_SINGLE_MAX = 32


@dataclass
class Tangential:
    """The tangential state: slips of every node (``v``, flat, n·d), the rigid displacement δ,
    the forces and the last increment's changes (the next increment's warm start), and the
    products ``C F`` and ``C ΔF`` (node-major ``(n, d)``), so that a start from these forces
    and changes costs no product. The forces are the solver's last iterate, within the
    tolerance of their limits (the increment returns them projected onto them)."""

    v: np.ndarray
    delta: np.ndarray
    F: np.ndarray
    dF: np.ndarray
    ddelta: np.ndarray
    side: np.ndarray  # d = 1: +1 / -1 on the upper / lower limit, else 0
    CF: np.ndarray
    CdF: np.ndarray


class HalfSpaceIncrements(NewtonSteps):
    """What the increments of one scene need: the grid's constants, the operator (its products
    counted), the increments' tolerance and the loads' displacement scale, the statistics and
    (d = 1) whether the last increment's first pattern held."""

    #: slips added to ``C F`` in the state's ``CF`` (None: none; :meth:`_safe_start`)
    offset = None

    def __init__(self, model, tol: float, load_scale: float):
        self.model = model
        self.nodes, self.dims, self.k_support, self.c = (
            model.nodes,
            model.dims,
            model.k_support,
            model.c,
        )
        self.N, self.h, self.pos, self.cpos = model.N, model.h, model.pos, model.cpos
        self.force_scale = model.force_scale
        self.op = Counted(model.op)
        # the compiled kernels (numba: imported by a half-space's stepper only)
        from ..model.continuum import halfspace_kernels

        self.kernels = halfspace_kernels
        self.tol = tol
        self.load_scale = load_scale
        self.stats = {
            "tangential_seconds": 0.0,
            "tangential_products": 0,
            "increments": 0,
            "newton": 0,
            "cg": 0,
            "stalled": 0,
        }
        self.first_right = True  # d = 1: the last increment's first pattern held

    def copy(self) -> "HalfSpaceIncrements":
        out = copy.copy(self)
        out.op = Counted(self.op.op, self.op.products)
        out.stats = dict(self.stats)
        return out

    def compliance(self, F) -> np.ndarray:
        """``C F`` (one counted product)."""
        return compliance(self.model, self.op, F)

    def pad(self, F):
        return pad(self.model, F)

    def increment(self, state: Tangential, b: np.ndarray, Q: float, guess=None, tol=None):
        """Problem (P) (module docstring): ``(state, F, Δs)``. ``guess``: the same increment's
        :meth:`~lcpfric.steppers.newton_cg.NewtonCGStepper.guess` from the previous cycle, the
        start (else the last increment's changes, extrapolated); ``tol``: this increment's
        tolerance, if not the stepper's own."""
        start, count = time.perf_counter(), self.op.products
        try:
            return self._increment(state, b, Q, guess, self.tol if tol is None else tol)
        finally:
            self.stats["tangential_seconds"] += time.perf_counter() - start
            self.stats["tangential_products"] += self.op.products - count
            self.stats["increments"] += 1

    def _increment(self, state, b, Q, guess, tol):
        n, d, ks, c = self.nodes, self.dims, self.k_support, self.c
        scale = self.force_scale
        tolF = tol * self._tolerance_scale()
        contact = b > 1e-10 * scale
        s0 = state.v.reshape(n, d)
        if guess is not None:
            # the start: this increment's changes in the previous cycle (exact once the
            # cycles repeat, so a converging steady state costs less and less per cycle)
            dF0, dd0, side0, CdF0 = guess
        elif np.any(state.F != state.dF):
            # else the last increment's changes, extrapolated (unless that one started from
            # the virgin contact: its change is a load applied at once, not a trend)
            dF0, dd0, side0, CdF0 = state.dF, state.ddelta, state.side, state.CdF
        else:
            dF0, dd0, side0, CdF0 = 0.0, 0.0, state.side, 0.0
        # no product: C is linear. The start may lie off the limits, or carry forces on nodes
        # that left the contact: the first step puts them right
        F = (state.F + dF0).reshape(n, d)
        delta = state.delta + dd0
        CF = state.CF + CdF0
        Qv = np.zeros(d)
        Qv[0] = Q
        updates = PatternUpdate(contact) if d == 1 else None
        up = dn = None
        restarted = loose = fresh = changed = False
        close = 0  # damped steps begun within ten times the tolerance
        # d = 1: Murty's rule changes one node per iteration, so allow one per node
        in_contact = int(np.count_nonzero(contact))
        limit = _MAX_NEWTON + (in_contact if d == 1 else 0)
        eq_tol = tolF * max(1, in_contact)
        ev = None  # d = 2: the residual at the iterate, if the line search has it
        damped = d == 2  # d = 1 turns to the damped steps if its patterns stall
        for it in range(limit):
            if not damped:
                # Δs, z = F − Δs/c, the pattern's bounds, the residual and the equilibrium
                # (compiled)
                ds, zz, lo, hi, zn, worst, eq = self.kernels.pattern_residual(
                    F, CF, delta, s0, c, b, ks, Qv, tolF, _EPS, contact
                )
                # the primal-dual active-set pattern, with Murty's rule once one repeats
                if up is None:  # the previous increment's pattern, where still in contact,
                    # and (unless restarted) the nodes the extrapolated forces put beyond
                    side = state.side if restarted else side0
                    warm = (contact & (side > 0), contact & (side < 0))
                    up, dn = warm if restarted else updates.first(zz, lo, hi, warm)
                    fresh = True
                else:
                    nxt = updates.next(zz, lo, hi, up, dn)
                    if nxt is None and not loose:
                        break
                    fresh = nxt is not None  # else: a loose step's pattern repeats
                    if fresh:
                        up, dn = nxt
                        changed = True
                    if it == _RESTART and not restarted:
                        # a poor start (a large extrapolated change) can send the pattern
                        # astray: restart once from the previous increment's forces and
                        # pattern, the safe start
                        F, delta, CF = self._safe_start(state, b, contact)
                        updates = PatternUpdate(contact)
                        up, restarted = None, True
                        continue
                slip = up | dn
                z = np.where(up, 1.0, -1.0)[:, None]  # the slip nodes' sides
                if updates.stats["single_changes"] > _SINGLE_MAX:
                    # the patterns stall (a large increment on a fine grid: thousands of
                    # nodes change state, and Murty's rule changes one per iteration): the
                    # damped semismooth Newton steps of d = 2, on intervals, from the previous
                    # increment's forces. From the stalled iterate (a wrong pattern, loosely
                    # solved) the line search crawled: 4153 Newton steps against 171 on grid
                    # 120 with 8 steps per cycle, the same W
                    damped = True
                    ev = None
                    F, delta, CF = self._safe_start(state, b, contact)
                    self.stats["stalled"] += 1
            if damped:
                if ev is None:
                    ev = self._natural(F, CF, delta, s0, b, contact, Qv)
                ds, z, zn, slip, worst, merit, eq = ev
                ev = None
                if worst <= tolF and float(np.abs(eq).max()) <= eq_tol:
                    break
                if it == 2 * _RESTART and not restarted:  # as for d = 1 below
                    F, delta, CF = self._safe_start(state, b, contact)
                    restarted = True
                    continue
            if ks <= 0.0 and in_contact and not (contact & ~slip).any():
                # an iterate with every node slipping has no equilibrium: unless the load
                # exceeds every limit (gross sliding), the nodes nearest to sticking stick,
                # as many as can carry what the others' slip forces leave of the load
                total = float(b[contact].sum())
                if abs(Q) > total * (1.0 + 1e-12):
                    raise SolverError(
                        f"half-space: |Q| = {abs(Q):.6g} exceeds the sum of "
                        f"the friction limits {total:.6g} (gross sliding)",
                        backend="halfspace",
                        status="gross_sliding",
                    )
                stuck = nearest_to_sticking(z, zn, b, contact, Qv)
                slip[stuck] = False
                if d == 1:
                    up[stuck] = dn[stuck] = False
            self.stats["newton"] += 1
            # d = 1: a step whose pattern is new is solved loosely (its answer only says
            # which pattern comes next), once a pattern repeats to full accuracy; the first
            # pattern too, unless the last increment's first pattern was its answer
            loose = (
                not damped
                and fresh
                and _ETA1 * worst > 0.1 * tolF
                and (it > 0 or not self.first_right)
            )
            # the damped steps' linear solves stop at CG_TOL of the tolerance; where a step
            # that began near it did not end the increment (the natural map's residual can
            # then hover about the tolerance), the next ones stop ten times lower each
            frac = CG_TOL
            if damped and worst <= 10.0 * tolF:
                frac = max(CG_TOL * 0.1**close, 1e-3)
                close += 1
            dF, dd, CdF = self.newton_step(
                F,
                ds,
                z,
                zn,
                b,
                contact,
                slip,
                eq,
                worst,
                tolF,
                _ETA1 if loose else (ETA if damped else None),
                frac,
            )
            if not damped:
                F += dF
                CF += CdF
                delta = delta + dd
            else:
                F, CF, delta, ev = self._step(merit, F, CF, delta, dF, CdF, dd, s0, b, contact, Qv)
        else:
            total = float(b[contact].sum())
            near = (
                f"; |Q| is {abs(Q) / total:.6f} of the sum of the friction limits, so "
                f"close to gross sliding that the stick zone spans about one element: "
                f"refine the grid or lower Q"
                if ks <= 0.0 and total > 0.0 and abs(Q) >= 0.999 * (1.0 - 1e-9) * total
                else ""
            )
            raise SolverError(
                f"half-space tangential increment: residual {worst:.3g} above "
                f"{tolF:.3g} after {limit} Newton iterations{near}",
                backend="halfspace",
                status="max_iter",
            )
        if d == 1:
            self.first_right = not changed
            if damped:
                up, dn = slip & (z[:, 0] > 0.0), slip & (z[:, 0] < 0.0)
        # F projected onto the discs and Δs zeroed on the sticking nodes, in place (compiled)
        F_end, v, dF, dCF = self.kernels.finish(F, ds, s0, b, contact, slip, state.F, CF, state.CF)
        side = np.zeros(n, dtype=np.int8)
        if d == 1:
            side[up] = 1
            side[dn] = -1
        new = Tangential(v, delta, F_end, dF, delta - state.delta, side, CF, dCF)
        return new, F.ravel(), ds.ravel()

    def _tolerance_scale(self) -> float:
        """The increments' force scale: the largest limit, or, if smaller, the force that moves
        a node by the loads' displacement scale (the cycle criterion's), so an increment's
        error c·r stays below the criterion's tolerance however small the tangential load (at
        Q1 = 1e-4 μP0 the cycles never repeated: their change hovered at the increments'
        errors). From the scene's loads."""
        u = self.load_scale
        return min(self.force_scale, u / self.c) if u > 0.0 else self.force_scale

    def _safe_start(self, state, b, contact):
        """The previous increment's forces and rigid displacement (no extrapolation); their
        ``C F`` plus :attr:`offset` (the slips that are not C F's: the pressures' with
        dissimilar materials, :mod:`.coupled_halfspace`), if any."""
        F = state.F.reshape(self.nodes, self.dims).copy()
        F[~contact] = 0.0
        self.kernels.project_discs(F, b)
        CF = self.compliance(F)
        return F, state.delta.copy(), CF if self.offset is None else CF + self.offset

    def _natural(self, F, CF, delta, s0, b, contact, Qv):
        """d = 2 (and d = 1 once its patterns stall): the natural map's residual at ``(F, CF =
        C F, δ)`` (``contact``: the nodes in contact): ``(Δs, z, |z|, slipping, its largest
        component, the line search's merit |F - proj(z)|² + |equilibrium|², the
        equilibrium)`` with ``z = F - Δs/c`` (compiled:
        :func:`~lcpfric.model.continuum.halfspace_kernels.natural`)."""
        return self.kernels.natural(F, CF, delta, s0, self.c, b, contact, Qv, float(self.k_support))

    def _step(self, m0, F, CF, delta, dF, CdF, dd, s0, b, contact, Qv):
        """d = 2 (and d = 1 once its patterns stall): the Newton step, its length halved from
        1 until the merit (``m0`` at the start) decreases (products are linear: ``C(F + α ΔF)
        = CF + α CΔF``, so a trial costs no FFT): ``(F, CF, δ)`` there and :meth:`_natural`
        of it."""
        alpha = 1.0
        for _ in range(12):
            trial = F + alpha * dF, CF + alpha * CdF, delta + alpha * dd
            ev = self._natural(*trial, s0, b, contact, Qv)
            if ev[5] <= (1.0 - 1e-4 * alpha) * m0:
                break
            alpha *= 0.5
        return (*trial, ev)
