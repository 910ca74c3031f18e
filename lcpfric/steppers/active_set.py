r"""Problem (P) for many nodes by a primal-dual active-set method (``method="active-set"``).

The increment is the same as every convex backend's (:mod:`~lcpfric.backends.problem`): the
maximum-dissipation projection of the trial force onto the friction cone. It is solved here in
its stiffness form, the dual of (P),

    u_{k+1} = argmin_u  ½ uᵀ K u + Q_{k+1}ᵀ u + Σ_i b_i ||u_i - u_{k,i}||,   b_i = f_i N_i(t_{k+1}),

whose optimality conditions are Coulomb's law for ``F = Q_{k+1} + K u``: a node sticks
(``Δu_i = 0``, ``||F_i|| <= b_i``) or slips on its limit against its force, and a separated node
(``b_i = 0``) carries ``F_i = 0``. Nothing is inverted but blocks of K, so a stiff K (stiffness
ratios to 1e12) keeps its digits: C = K⁻¹ is never formed.

The method (d = 1)
------------------
A *pattern* says for each node: stick, slip at ``+b`` (backward), slip at ``-b`` (forward), or
separated. With the pattern fixed the increment is linear: the sticking nodes keep ``u_k``; the
free nodes F (slipping and separated) carry the forces ``r_F`` (``±b``, 0), so

    K_FF δ_F = r_F - F^tr_F,   δ_S = 0,   F = F^tr + K δ,   F^tr = Q_{k+1} + K u_k.

The pattern is then updated node by node from the natural map ``z_i = F_i - Δu_i / k_ii``
(``z > b``: slip at +b; ``z < -b``: slip at -b; else stick): the semismooth Newton method for the
box-constrained problem, which is the primal-dual active-set method of Hintermüller, Ito and
Kunisch. It is warm-started from the previous increment's pattern (the nodes on their limits at the
start of the increment keep slipping, and those whose trial force is out of its limits start to),
ends when the pattern repeats, and converges in a few iterations when few nodes change state, which
is the case between two increments. Should it revisit a pattern (possible for a K that is not an
M-matrix), it continues with single changes, the lowest-numbered violated node first (Murty's
least-index rule), which terminates for any symmetric positive definite K.

Every solve is refined (iterative refinement on K: ``δ_F += K_FF⁻¹ (r - F)_F``) until the forces
of the free nodes are at round-off, so an inverse that lost digits (a stiff K, many updates)
does not reach the answer. The block ``K_FF`` is kept by :mod:`~lcpfric.linalg.blocks`:
updated, not rebuilt, when the pattern changes by a few nodes.

The method (d = 2)
------------------
A slipping node's force is ``b_i`` times a direction to be found. With the pattern fixed, the
objective is smooth in the free displacements (``b ||Δu||`` is smooth away from ``Δu = 0``) and
Newton's method on it, with a backtracking line search, converges quadratically; its Hessian
``K_FF + Σ_slip (b_i / ||Δu_i||)(I - ν_i ν_iᵀ)`` (ν_i the slip direction) is symmetric positive
definite. The pattern is updated from the natural map of the disc, as for d = 1.

Matrix-free systems (d = 1)
---------------------------
A system known only by the products of its compliance (``ContactSystem(None, ...,
compliance=LinearOperator)``: a half-space, where a product is an FFT pair) is solved in the
compliance form of the same iteration (:meth:`ActiveSetStepper._pattern_operator`): with the
pattern fixed, the forces of the sticking nodes solve ``C_SS (F - F^tr)_S = -C_SA (F -
F^tr)_A``, by conjugate gradients warm-started from the previous iteration's forces, one
product with C per CG iteration (:class:`~lcpfric.linalg.blocks.OperatorBlock`). Events are
located as for K. The equilibrium check compares ``u`` with ``C (F - Q)``.

Coupled systems (d = 1)
-----------------------
A system whose normal reactions move with the slips (``N = P + B u``) is solved by the coupled
pattern iteration of :mod:`.active_set_coupled` (one linear solve with the rows of
``K - diag(σ f) B`` per pattern, dense K), along the convex backends' path of an increment.

Limits
------
A matrix-free system is solved for d = 1 only. For d = 2 the Newton matrix is formed
and factorized at every iteration (correct, not fast at large n). With events located (the
default, as for the convex backends) every event inside an increment costs one more pattern
iteration; thousands of coupled nodes have several per step, and ``locate_events=False`` with
more steps is then cheaper.

Checks
------
Every answer passes the independent residual checks of the other backends
(:func:`~lcpfric.backends.checks.residuals`: cone, complementarity, stationarity, computed from
the forces ``Q + K u`` and the slips, before the slipping forces are put exactly on their
limits) and the equilibrium check ``|Q + K u - F|``; a failure raises
:class:`~lcpfric.errors.SolverError` with the residuals. Separated nodes carry no force unknown
and no constraint.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .._checks import boolean, positive, positive_int
from ..backends.checks import residuals, separating_slips_agree, worst
from ..errors import InputError, SolverError
from ..linalg import PatternUpdate
from ..results import State, StepState
from .active_set_coupled import CoupledPatterns
from .active_set_discs import DiscPatterns
from .active_set_patterns import BoxPatterns
from .active_set_plan import ActiveSetData, Plan
from .base import Recorder, Stepper
from .dissipation import increment_dissipation
from .rates import first_event, path_is_exact

__all__ = ["ActiveSetStepper", "ActiveSetData", "PatternUpdate"]

STICK, FORWARD, BACKWARD, SEPARATION = (
    int(State.STICK),
    int(State.FORWARD),
    int(State.BACKWARD),
    int(State.SEPARATION),
)
BLOCKS = ("auto", "dense", "banded", "sparse")
_EPS = np.finfo(float).eps
_CHECK_ROWS = 64  # increments checked together for equilibrium


class ActiveSetStepper(BoxPatterns, DiscPatterns, CoupledPatterns, Stepper):
    """Problem (P) by a primal-dual active-set method on K (see the module docstring).

    Parameters
    ----------
    block : {"auto", "dense", "banded", "sparse"}
        How ``K_FF`` is kept (:mod:`~lcpfric.linalg.blocks`): by default an inverse with a low-rank
        correction for a dense K; LAPACK's banded Cholesky for a sparse K of small bandwidth;
        SuperLU otherwise.
    check_tol : float
        Largest residual accepted (relative to the problem scale), as for the other backends.
    max_iter : int
        Cap on the pattern updates of one increment (then SolverError, status "max_iter").
    locate_events : bool
        On coupled d = 1 systems, split an increment at the instant where a node starts to slip
        when the single projection cannot be exact there, as the convex backends do
        (:mod:`~lcpfric.steppers.rates`).
    cg_max_iter : int
        Matrix-free systems: cap on the conjugate-gradient iterations of one solve (then
        SolverError, status "cg_max_iter").
    """

    name = "active-set"

    def __init__(
        self,
        *,
        block: str = "auto",
        check_tol: float = 1e-6,
        max_iter: int = 200,
        locate_events: bool = True,
        cg_max_iter: int = 2000,
    ):
        if block not in BLOCKS:
            raise InputError("block", f"must be one of {BLOCKS}, got {block!r}")
        self.block = block
        self.check_tol = positive("check_tol", check_tol)
        self.max_iter = positive_int("max_iter", max_iter)
        self.locate_events = boolean("locate_events", locate_events)
        self.cg_max_iter = positive_int("cg_max_iter", cg_max_iter)

    def check_system(self, system) -> None:
        if system.matrix_free and system.dims != 1:
            raise InputError(
                "method",
                "'active-set' solves a matrix-free system (a compliance "
                "operator) with d = 1 only; for d = 2 give the stiffness "
                "matrix, or use a convex backend on up to 2000 unknowns",
            )
        if system.matrix_free and self.block != "auto":
            raise InputError(
                "block",
                f"{self.block!r} applies to a stiffness matrix; a "
                f"matrix-free system is solved by conjugate gradients "
                f"(leave block='auto')",
            )

    # -- the stepper contract ----------------------------------------------------------------
    def init(self, scene, u0=None) -> StepState:
        self.check_system(scene.system)
        self._system = scene.system  # for the error messages
        plan = Plan(scene, self.block, self.cg_max_iter)
        state = super().init(scene, u0)
        stats = {
            "solves": 0,
            "iterations": 0,
            "refinements": 0,
            "single_changes": 0,
            "max_residual": 0.0,
            "events": 0,
        }
        return replace(state, data=ActiveSetData(plan, stats, np.zeros(plan.m), state.F, state.u))

    def step(self, scene, k, state):
        data = state.data
        stats = dict(data.stats)
        du, F1, Fc, s, dW = self._increment(
            data.plan, k, state.F, data.computed_forces(state), stats, state.u
        )
        u1, lo = _accumulate(state.u, data.u_lo, du)
        return StepState(u1, F1, s, dW, replace(data, stats=stats, u_lo=lo, Fc=Fc, u_of_Fc=u1))

    def cycle(self, scene, state, history: bool = True):
        data = state.data
        plan = data.plan
        record = Recorder(scene, state, history)
        u, F, lo, Fc = state.u, state.F, data.u_lo, data.computed_forces(state)
        stats = dict(data.stats)
        W = 0.0
        # the equilibrium check: for a dense K on blocks of rows (one matrix-matrix product
        # per block), for a sparse K every step (a product costs O(nnz))
        block = 1 if hasattr(plan.K, "tocsr") else min(scene.steps, _CHECK_ROWS)
        Ub, Fb, Qb = (np.empty((block, plan.m)) for _ in range(3))
        rows = np.empty(block, dtype=np.intp)
        filled = 0
        peak = float(np.max(np.abs(u), initial=0.0))
        for k in range(scene.steps):
            du, F, Fc, s, dW = self._increment(plan, k, F, Fc, stats, u)
            u, lo = _accumulate(u, lo, du)
            peak = max(peak, float(np.max(np.abs(u), initial=0.0)))
            record(k + 1, u, F, s)
            W += dW
            Ub[filled], Fb[filled], Qb[filled], rows[filled] = u, F, plan.row(k + 1)[0], k + 1
            filled += 1
            if filled == block:
                self._check_equilibrium(plan, Ub, Fb, Qb, rows, peak)
                filled = 0
        if filled:
            self._check_equilibrium(
                plan, Ub[:filled], Fb[:filled], Qb[:filled], rows[:filled], peak
            )
        u = u.copy()
        end = StepState(
            u, F.copy(), s.copy(), 0.0, replace(data, stats=stats, u_lo=lo.copy(), Fc=Fc, u_of_Fc=u)
        )
        return end, record.result(W, self.stats(end))

    def stats(self, state) -> dict:
        out = dict(state.data.stats)
        out.update(state.data.plan.block.stats)
        return out

    # -- one increment -----------------------------------------------------------------------
    def _increment(self, plan, k, F, Fc0, stats, u):
        """Increment k from the forces at t_k (``F`` on their limits, ``Fc0 = Q + K u`` as
        computed): ``(Δu, F, Fc, states, dW)`` at t_{k+1}. The trial force ``Q_{k+1} + K u_k``
        is ``Fc0 + ΔQ`` (no product with K): the computed forces are carried, not the ones put
        on the limits, so that the round-off of each solve is not dropped into a drift between
        u and F (the equilibrium check of every cycle bounds what remains).

        One projection to t_{k+1}; on a coupled d = 1 system whose answer is not the exact end
        state (:func:`~lcpfric.steppers.rates.path_is_exact`), the increment is split at its
        events as the convex backends do, the rates at an event from this backend's own pattern
        iteration (:meth:`_rate_function`). A coupled system (``N = P + B u``): the coupled
        pattern iteration along the convex backends' path (:mod:`.active_set_coupled`)."""
        if plan.coupled is not None:
            return self._coupled_increment(plan, k, u, F, stats)
        Qk, Nk, bk, ck = plan.row(k)
        Qj, Nj, b, contact = plan.row(k + 1)
        dQ = Qj - Qk
        warm = _on_limits(F, bk) if plan.dims == 1 else None
        du, Fc, limit = self._project(plan, Fc0 + dQ, b, contact, stats, k, warm)
        F1, s = self._finish(plan, du, Fc, b, contact, stats, k)
        dW = increment_dissipation(F, F1, du, plan.dims)
        if not self.locate_events or plan.dims != 1 or plan.diagonal:
            return du, F1, Fc, s, dW
        leaving = ck & ~contact
        separating = leaving if leaving.any() else None
        if self._exact_path(plan, F, bk, du, F1, limit, separating):
            return du, F1, Fc, s, dW
        f = plan.friction
        dN = Nj - Nk
        sep = (Nk + Nj) <= 0.0
        inside = ck | contact
        rates = self._rate_function(plan, stats, k)
        a, moved, Fa, Fca = 0.0, np.zeros(plan.m), F, Fc0
        dW = 0.0
        for _ in range(4 * plan.n + 16):
            tau = first_event(plan.K, f, Fa, Qk + a * dQ, Nk + a * dN, dQ, dN, sep, a, rates=rates)
            if tau is None:
                break
            bt = f * (Nk + tau * dN)
            dua, Fc, _ = self._project(
                plan, Fca + (tau - a) * dQ, bt, inside, stats, k, _on_limits(Fa, f * (Nk + a * dN))
            )
            Fb, _ = self._finish(plan, dua, Fc, bt, inside, stats, k)
            stats["events"] += 1
            dW += increment_dissipation(Fa, Fb, dua)
            a, Fa, Fca = tau, Fb, Fc
            moved += dua
            du, Fc, limit = self._project(
                plan, Fca + (1.0 - a) * dQ, b, contact, stats, k, _on_limits(Fb, bt)
            )
            F1, s = self._finish(plan, du, Fc, b, contact, stats, k)
            if self._exact_path(plan, Fa, f * (Nk + a * dN), du, F1, limit, separating):
                break
        return moved + du, F1, Fc, s, dW + increment_dissipation(Fa, F1, du)

    @staticmethod
    def _exact_path(plan, Fa, ba, du, F1, limit, separating):
        """Whether a projection from ``Fa`` (limits ``ba``), slips ``du``, is the exact end state:
        :func:`~lcpfric.steppers.rates.path_is_exact` and the separating nodes slipping against
        their start forces (:func:`~lcpfric.backends.checks.separating_slips_agree`)."""
        return path_is_exact(
            Fa, ba, F1, limit, separating, plan.force_scale
        ) and separating_slips_agree(Fa, du, separating, plan.force_scale, plan.compliance_scale)

    def _rate_function(self, plan, stats, k):
        """The rate problem at an instant inside increment k, for
        :func:`~lcpfric.steppers.rates.first_event`: the same pattern iteration, on the rates.
        A node on its upper limit may slip back (its force rate then the limit's, ``f dN``) or
        stick below it; likewise on its lower limit; a node inside its limits sticks; a node
        separated over the increment carries no force."""
        inf = np.full(plan.n, np.inf)

        def rates(F0, bound, dQ, dN, sep, touch_lo, touch_hi):
            near = 1e-12 * (bound + np.abs(F0)) + 1e-300
            on_hi = ~sep & ((F0 >= bound - near) | touch_hi)
            on_lo = ~sep & ((F0 <= -bound + near) | touch_lo)
            db = plan.friction * dN
            hi = np.where(on_hi, db, inf)
            lo = np.where(on_lo, -db, -inf)
            pattern = self.operator_pattern if plan.matrix_free else self.box_pattern
            du, dF, (up, dn) = pattern(plan, dQ, lo, hi, sep, stats, k)
            state = np.where(sep, SEPARATION, STICK).astype(np.int8)
            state[up] = BACKWARD
            state[dn] = FORWARD
            return du, state, dF

        return rates

    def _project(self, plan, F_tr, b, contact, stats, k, warm=None):
        """The increment's projection from the trial force: ``(Δu, Fc, limit)``, with
        ``Fc = F^tr + K Δu`` as computed and ``limit`` the nodes on a friction limit.
        ``warm``: the ``(upper, lower)`` masks of the nodes on their limits at the start of
        the increment (d = 1), the pattern's first guess with the nodes whose trial force is
        out of its limits.

        The slip Δu is returned as solved, not as a difference of displacements: on a weakly
        grounded system u can be 1e12 times the slips, and ``u_{k+1} - u_k`` would keep only
        the last digits of Δu (the dissipation is computed from Δu)."""
        stats["solves"] += 1
        if plan.dims == 2:
            delta, Fc, slip = self.disc_pattern(plan, F_tr, b, contact, stats, k)
            return delta, Fc, slip
        pattern = self.operator_pattern if plan.matrix_free else self.box_pattern
        delta, Fc, (up, dn) = pattern(plan, F_tr, -b, b, ~contact, stats, k, warm)
        return delta, Fc, up | dn

    def _finish(self, plan, du, Fc, b, contact, stats, k):
        """Put the slipping and separated forces exactly where they belong, check the answer,
        and return ``(F, node states)``.

        The residuals of the other backends (cone, complementarity, stationarity) are computed
        on these forces and the slips, and the equilibrium residual ``|F - Fc|`` compares them
        with the forces computed from K: a node whose pattern put it on the wrong limit, or a
        solve that lost digits, shows there. Its floor is the round-off of ``K Δu``,
        ``16 ε ||K||_∞ max |Δu|``: on a weakly grounded system the slips of a gross slip are
        1e12 times the forces' scale over the stiffness and float64 holds no more."""
        eps = self.check_tol * plan.compliance_scale * plan.force_scale
        F = Fc.copy()
        if plan.dims == 2:
            A = np.flatnonzero(contact)
            cols = (2 * A[:, None] + np.arange(2)).ravel()
            d2, F2 = du.reshape(-1, 2), F.reshape(-1, 2)
            nd = np.hypot(d2[:, 0], d2[:, 1])
            fwd = contact & (nd > eps)
            bwd = np.zeros_like(fwd)
            F2[fwd] = -(b[fwd] / nd[fwd])[:, None] * d2[fwd]
            F2[~contact] = 0.0
        else:
            A = cols = slice(None) if contact.all() else np.flatnonzero(contact)
            fwd = contact & (du > eps)
            bwd = contact & (du < -eps)
            F[fwd] = -b[fwd]
            F[bwd] = b[bwd]
            F[~contact] = 0.0
        res = residuals(F[cols], du[cols], b[A], plan.dims, plan.force_scale, plan.compliance_scale)
        floor = (
            16
            * _EPS
            * (
                plan.row_norm * float(np.max(np.abs(du), initial=0.0))
                + float(np.max(np.abs(Fc), initial=0.0))
            )
        )
        off = float(np.max(np.abs(F - Fc), initial=0.0))
        res["equilibrium"] = max(off - floor, 0.0) / plan.force_scale
        bad = worst(res)
        stats["max_residual"] = max(stats["max_residual"], bad)
        if not bad <= self.check_tol:
            self._fail(k, res)
        s = np.where(fwd, FORWARD, np.where(bwd, BACKWARD, STICK)).astype(np.int8)
        s[~contact] = SEPARATION
        return F, s

    def _check_equilibrium(self, plan, U, Fs, Qs, rows, peak):
        """``max |Q + K u - F| / s_F`` over the increments ending at ``rows`` (loads ``Qs``):
        the forces carried from step to step (``F + ΔQ``) must not drift from ``Q + K u``.

        Its floor is what float64 resolves: ``64 ε ||K||_∞ max |u|``, the largest |u| of the
        cycle so far (``peak``). On a weakly grounded system in gross slip u is huge (1e10
        times the loads' scale over the stiffness) and the forces are its small differences:
        the displacements then fix the forces only to that floor, whatever the method."""
        if plan.matrix_free:  # in displacements: u = C (F - Q), over the compliance scale
            R = plan.block.apply_many((Fs - Qs).T).T
            R -= U
            floor = 64 * _EPS * peak
            eq = np.maximum(np.abs(R).max(axis=1) - floor, 0.0) / (
                plan.compliance_scale * plan.force_scale
            )
        else:
            R = (plan.K @ U.T).T
            R += Qs
            R -= Fs
            floor = 64 * _EPS * plan.row_norm * peak
            eq = np.maximum(np.abs(R).max(axis=1) - floor, 0.0) / plan.force_scale
        bad = np.flatnonzero(~(eq <= self.check_tol))
        if bad.size:
            self._fail(int(rows[bad[0]]) - 1, {"equilibrium": float(eq[bad[0]])})

    def unsettled(self, k, what):
        from ..exact.clusters import stiff_hint

        return SolverError(
            f"active-set: increment {k}: {what} did not settle in "
            f"{self.max_iter} iterations; raise max_iter"
            + stiff_hint(getattr(self, "_system", None)),
            backend=self.name,
            status="max_iter",
        )

    def _fail(self, k, res):
        name = max(res, key=lambda r: math.inf if res[r] != res[r] else res[r])
        raise SolverError(
            f"active-set: increment {k}: the answer fails lcpfric's residual "
            f"check ({name} {res[name]:.3g} > check_tol {self.check_tol:g})",
            backend=self.name,
            status="residual",
            residuals=res,
        )


def _accumulate(u, lo, du):
    """``u + du`` by compensated (Kahan) summation; ``lo`` carries what u could not hold."""
    y = du - lo
    t = u + y
    return t, (t - u) - y


def _on_limits(F, b):
    """``(upper, lower)``: the nodes of forces F (put on their limits) that are on ``+b`` or
    ``-b`` with ``b > 0``."""
    pos = b > 0.0
    return pos & (F >= b), pos & (F <= -b)
