r"""The incremental problem every convex backend solves, and what the backends share.

Derivation
----------
Paper convention (Eq. 2): the friction force is ``F = Q + K u``, with K the symmetric positive
definite tangential stiffness and C = K⁻¹ its compliance. Coulomb's law (Eq. 3) asks, node by node,
``||F_i|| <= f_i N_i``, and a node slips only against its force: ``Δu_i = -λ_i F_i / ||F_i||``
with ``λ_i >= 0`` and ``λ_i (f_i N_i - ||F_i||) = 0``. Write the set of admissible forces

    C(N) = { F : ||F_i|| <= f_i N_i for every node i }        (a box for d = 1, discs for d = 2).

Over an increment t_k -> t_{k+1} hold the displacement at u_k and load the system to Q_{k+1}: the
force would be the trial force ``F_tr = Q_{k+1} + K u_k``. The step must end at ``F = Q_{k+1} +
K u_{k+1}``, so the slip is ``Δu = u_{k+1} - u_k = C (F - F_tr)``. The flow rule says ``-Δu`` lies
in the normal cone of C(N) at F, i.e. ``-C (F - F_tr) ∈ N_C(N)(F)``: that is exactly the
optimality condition of

    minimize_F  ½ (F - F_tr)ᵀ C (F - F_tr)   subject to  F ∈ C(N),                          (P)

the projection of F_tr onto the friction cone in the metric of K⁻¹ (maximum dissipation). Then
``u_{k+1} = u_k + C (F - F_tr) = C (F - Q_{k+1})``. (P) is strictly convex, so the step is unique.

Equivalently, in the displacements: by conjugate duality (the support function of C(N) is
``Σ f_i N_i ||·||``), (P) is the dual of

    minimize_u  ½ uᵀ K u + Q_{k+1}ᵀ u + Σ_i f_i N_i ||u_i - u_{k,i}||,

whose optimality condition ``-(Q_{k+1} + K u) ∈ ∂(Σ f_i N_i ||u_i - u_{k,i}||)`` says precisely
that ``F = Q_{k+1} + K u`` lies in C(N) and that ``-F_i·Δu_i = f_i N_i ||Δu_i||`` (a node slips
only at its limit, against its force): the same step. lcpfric solves the force form (P), in
which the variables are the friction forces and the constraints are the cones themselves, so
that only the vectors change from step to step:

    P = C_AA,   q = -(C F_tr)_A = -(C Q_{k+1} + u_k)_A,   bounds f_i N_i(t_{k+1}),

where A is the set of nodes in contact at t_{k+1}.

What is left out
----------------
* A separated node (N_i = 0) has ``F_i = 0``: it carries no variable. The contact pattern of
  every grid instant is known from the scene (an uncoupled normal model), so the distinct
  contact sets of a cycle are enumerated before the first step and one problem (one solver
  object) is built for each. A node whose normal load never vanishes is in every set and needs
  no separation logic at all; a scene without separation has a single set.
* d = 1 gives intervals, ``-f_i N_i <= F_i <= f_i N_i``: a QP with box constraints (any QP
  solver). d = 2 gives second-order cones ``(f_i N_i, F_i) ∈ SOC(3)``: only conic solvers
  (Clarabel, cvxpy with CLARABEL/ECOS/SCS) can express it. Nobody approximates a disc by a
  polygon: a backend that cannot express the cone refuses the scene.

Checking every answer
---------------------
A solver's status flag is not trusted alone (OSQP, for one, can report success on a poor answer).
After every step lcpfric computes, from the returned forces only, with the slip
``Δu_A = P F_A + q`` (the gradient of (P)), relative to the scene's force scale ``s_F`` and
compliance scale ``c = max C_ii``:

``cone``            ``max_i (||F_i|| - f_i N_i)_+ / s_F``: primal feasibility;
``complementarity`` ``max_i (F_i·Δu_i + f_i N_i ||Δu_i||) / (c s_F²)``: >= 0 always, and 0 iff
                    the slip opposes the force and vanishes below the limit;
``stationarity``    ``max_i ||F_i - Π_i(F_i - Δu_i / c)|| / s_F``, the natural-map residual of
                    (P) (Π_i the projection on node i's interval or disc): zero iff F solves (P);
``equilibrium``     ``max |Q + K u - F| / s_F`` with ``u = C (F - Q)``, which catches a
                    compliance that is not K⁻¹.

A step whose status is not "solved", or whose largest residual exceeds ``check_tol``, raises
:class:`~lcpfric.errors.SolverError` with the backend's own status and the residuals.

Active-set refinement
---------------------
Interior-point answers sit a little inside the cone (Clarabel at its default tolerances is off by
about 2e-5 on a one-variable projection; OSQP at its defaults by about 2e-3). With ``refine=True``
the answer is only used to *identify* the active set: nodes with ``|F_i| >= f_i N_i - δ`` are put
on the limit with their sign, the remaining (stick) nodes solve ``P_SS F_S = -(q_S + P_SB F_B)``
exactly, and the identification is corrected (a stick node over its limit goes to the limit, a
limit node whose slip has the wrong sign goes to stick) until the KKT conditions hold: a
primal-dual active-set iteration started from the solver's answer. For d = 2 the limit nodes
sit on their circles, ``F_i = f_i N_i e_i`` with slip ``-λ_i F_i``, and the KKT system is solved
by Newton's method (:func:`refine_disc`); interior-point solvers stall short of tight tolerances
on these cones, and the refinement takes their answer to machine precision. A stick node keeps
its displacement exactly (no rounding drift while the whole system sticks, which the periodic
driver would otherwise see as a change). If the refined point passes the residual check it is
used; otherwise the solver's own answer must pass on its own.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._checks import positive
from ..errors import InputError, SolverError
from ..results import CycleResult, State
from ..steppers.base import Stepper, StepState, slip_dissipation

__all__ = ["ConvexStepper", "IncrementProblem", "ScenePlan", "residuals", "refine_box",
           "refine_disc", "triu_csc", "quiet", "TIGHT_SETTINGS", "CONIC_METHODS", "SOLVED",
           "INACCURATE", "INFEASIBLE", "MAX_ITER", "TIME_LIMIT", "NUMERICAL", "UNKNOWN"]

# lcpfric's small set of solver outcomes: each backend maps its own codes onto these (its
# STATUS_MAP, cvxpy-style); an unknown code maps to UNKNOWN. Only SOLVED is accepted; the
# others raise SolverError with the advice below and the backend's own status.
SOLVED = "solved"
INACCURATE = "inaccurate"
INFEASIBLE = "infeasible"
MAX_ITER = "max_iter"
TIME_LIMIT = "time_limit"
NUMERICAL = "numerical"
UNKNOWN = "unknown"

_ADVICE = {
    INACCURATE: "the solver reached only its reduced accuracy; tighten or rescale, or try "
                "another backend",
    INFEASIBLE: "the solver reports the step infeasible, which the data of a consistent scene "
                "never are (F = 0 is always admissible): check the scene for negative normal "
                "reactions on nodes marked in contact, or NaN loads",
    MAX_ITER: "the solver stopped at its iteration limit; raise max_iter (max_iters for SCS)",
    TIME_LIMIT: "the solver stopped at its time limit; raise time_limit",
    NUMERICAL: "the solver ran into numerical trouble; check that K is well conditioned, or "
               "try another backend",
    UNKNOWN: "the solver returned a status lcpfric does not know; see its documentation",
}

# Backends that can express the d = 2 cone, for the error of those that cannot.
CONIC_METHODS = ("'clarabel', 'cvxpy:CLARABEL' (or 'cvxpy:ECOS', 'cvxpy:SCS'), or "
                 "'projection' for a diagonal K isotropic within each node")

# Tight defaults per underlying solver, shared by the direct backends, qpsolvers and cvxpy.
# Every entry overrides the solver's default; the comment says why.
TIGHT_SETTINGS: dict[str, dict[str, Any]] = {
    "clarabel": {
        # at the default 1e-8 a one-variable projection is off by ~2e-5; 1e-12 gives ~1e-8
        # (1e-14 is below what the IPM reaches reliably)
        "tol_gap_abs": 1e-12, "tol_gap_rel": 1e-12, "tol_feas": 1e-12,
        "verbose": False,  # lcpfric reports through its results, not the solver's log
    },
    "clarabel_soc": {
        # with second-order cones (d = 2) Clarabel stalls at AlmostSolved below ~1e-10; the
        # active-set Newton refinement takes its answer to machine precision from here
        "tol_gap_abs": 1e-9, "tol_gap_rel": 1e-9, "tol_feas": 1e-9,
    },
    "osqp": {
        # defaults (1e-3) are off by ~2e-3 on a one-variable projection
        "eps_abs": 1e-10, "eps_rel": 1e-10,
        # more room for the tight tolerances above (default 4000)
        "max_iter": 20000,
        # the default (0) sets the rho-update interval from the measured setup time, so
        # iteration counts, and unrefined answers, vary from run to run; a fixed interval keeps
        # runs reproducible at the same speed
        "adaptive_rho_interval": 25,
        # lcpfric's own active-set refinement does this job; OSQP's polish prints to stdout
        # even with verbose=False and can report success on a poor answer
        "polishing": False,
        "verbose": False,  # lcpfric reports through its results, not the solver's log
    },
    "proxqp": {
        # defaults (1e-5 abs) are far too loose; 1e-10 still leaves ~1e-6 on some steps
        "eps_abs": 1e-12, "eps_rel": 0.0,
        "check_duality_gap": True,  # off by default: the primal-dual residuals alone stop early
    },
    "scs": {
        # defaults (1e-4) are far too loose; SCS is first order, hence the iteration room
        "eps_abs": 1e-10, "eps_rel": 1e-10, "max_iters": 200000,
        "verbose": False,  # lcpfric reports through its results, not the solver's log
    },
    "ecos": {"abstol": 1e-10, "reltol": 1e-10, "feastol": 1e-10},  # defaults are 1e-8/1e-7
    "highs": {
        # defaults are 1e-7
        "primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10,
        # the default adds 1e-7 to the Hessian, which moves every answer by ~1e-7; P = C_AA is
        # positive definite and needs none
        "qp_regularization_value": 0.0,
    },
}


def triu_csc(P):
    """The upper triangle of a dense or sparse symmetric matrix, as scipy CSC (what Clarabel and
    OSQP read)."""
    import scipy.sparse as sp

    return sp.triu(sp.csc_matrix(P), format="csc")

# ---------------------------------------------------------------------------------------------
# The problem of one contact set, and the plan of a scene
# ---------------------------------------------------------------------------------------------
@dataclass(eq=False)
class IncrementProblem:
    """Problem (P) for one contact set: ``min ½ Fᵀ P F + qᵀ F`` over the cone of the set's nodes.

    Built once per contact set; per step only ``q`` and the bounds change.

    Attributes
    ----------
    nodes : (a,) int ndarray
        The nodes in contact (the set).
    dofs : (a·d,) int ndarray
        Their tangential unknowns, node by node (the variable order).
    dims : int
        d, 1 (intervals) or 2 (second-order cones).
    P : (a·d, a·d) ndarray or sparse
        C restricted to the set (sparse only when diagonal, as in a batch).
    Cf : (m, a·d) ndarray or None
        The columns of C for the set, mapping F_A to u (None in a batch).
    diagonal : bool
        P is diagonal (uncoupled nodes): the refinement needs no linear solve.
    full : bool
        The set holds every unknown (no indexing needed).
    handle : Any
        The backend's solver object for this problem.
    """

    nodes: np.ndarray
    dofs: np.ndarray
    dims: int
    P: Any
    Cf: np.ndarray | None = None
    diagonal: bool = False
    full: bool = False
    handle: Any = None
    q: np.ndarray = field(init=False)
    pdiag: np.ndarray = field(init=False)
    _ops: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self):
        self.q = np.zeros(self.dofs.size)
        self.pdiag = np.asarray(self.P.diagonal(), dtype=float).copy()

    @property
    def size(self) -> int:
        """Number of variables, a·d."""
        return int(self.dofs.size)

    def active_set_operator(self, at: np.ndarray):
        """``(Tq, Tb, stick)`` with ``F = Tq q + Tb (±b on the limit nodes)`` solving
        ``P_SS F_S = -(q_S + P_SB F_B)`` for the stick nodes S = ~at; cached per pattern."""
        key = at.tobytes()
        op = self._ops.get(key)
        if op is None:
            a = at.size
            S, B = np.flatnonzero(~at), np.flatnonzero(at)
            Tq = np.zeros((a, a))
            Tb = np.zeros((a, a)) if B.size else None
            if S.size:
                inv = np.linalg.inv(self.P[np.ix_(S, S)])
                Tq[np.ix_(S, S)] = -inv
                if B.size:
                    Tb[np.ix_(S, B)] = -inv @ self.P[np.ix_(S, B)]
            if B.size:
                Tb[B, B] = 1.0
            if len(self._ops) > 512:  # a cycle revisits few patterns; bound the memory anyway
                self._ops.clear()
            op = self._ops[key] = (Tq, Tb, (~at).astype(float))
        return op


class ScenePlan:
    """Everything about a scene the steps need, computed once before the first step.

    Attributes
    ----------
    C, K : (m, m) ndarray
        Compliance and stiffness (dense).
    Q, CQ : (N+1, m) ndarray
        ``Q(t_k)`` and ``C Q(t_k)`` on the grid.
    bound : (N+1, n) ndarray
        ``f_i N_i(t_k)``, the friction limits.
    set_of_step : (N+1,) int ndarray
        Index into ``problems`` of the contact set at each grid instant.
    problems : list of IncrementProblem
        One per distinct contact set (``None`` for the empty set: everything separated).
    step_problem : list
        The problem of each grid instant.
    node_bounds, neg_CQ : list of ndarray
        Per grid instant, for the nodes of its set: the limits (one per node) and ``-(C Q)_A``.
    separated : list of ndarray
        Per grid instant, the separated nodes.
    force_scale, compliance_scale : float
        ``s_F`` and ``c`` of the residuals (see the module docstring).
    """

    def __init__(self, scene):
        system = scene.system
        Q = np.asarray(scene.Q, dtype=float)
        N = np.asarray(scene.N, dtype=float)
        if not (np.all(np.isfinite(Q)) and np.all(np.isfinite(N))):
            raise InputError("scene", "the tangential loads and normal reactions on the grid "
                                      "must be finite; found NaN or inf")
        self.n, self.m, self.dims = system.n, system.m, system.dims
        self.C = np.ascontiguousarray(system.compliance_matrix(), dtype=float)
        self.K = np.ascontiguousarray(system.dense_stiffness(), dtype=float)
        self.Q = Q
        self.CQ = Q @ self.C  # C symmetric: rows are C Q(t_k)
        self.bound = N * system.friction
        contact = np.asarray(scene.contact, dtype=bool)
        keys: dict[bytes, int] = {}
        set_of_step = np.empty(Q.shape[0], dtype=np.intp)
        rows = []
        for k, row in enumerate(contact):
            key = row.tobytes()
            if key not in keys:
                keys[key] = len(keys)
                rows.append(row)
            set_of_step[k] = keys[key]
        self.set_of_step = set_of_step
        self.contact = contact
        d = self.dims
        diagonal = system.is_diagonal()
        self.problems: list[IncrementProblem | None] = []
        for row in rows:
            nodes = np.flatnonzero(row)
            if nodes.size == 0:
                self.problems.append(None)
                continue
            dofs = (nodes[:, None] * d + np.arange(d)[None, :]).ravel()
            P = np.ascontiguousarray(self.C[np.ix_(dofs, dofs)])
            self.problems.append(IncrementProblem(
                nodes, dofs, d, P, np.ascontiguousarray(self.C[:, dofs]), diagonal,
                full=bool(nodes.size == self.n)))
        self.step_problem = [self.problems[s] for s in set_of_step]
        self.node_bounds = [self.bound[k, p.nodes] if p is not None else None
                            for k, p in enumerate(self.step_problem)]
        self.neg_CQ = [-(self.CQ[k] if p.full else self.CQ[k, p.dofs]) if p is not None else None
                       for k, p in enumerate(self.step_problem)]
        sep_sets = [np.flatnonzero(~row) for row in rows]
        self.separated = [sep_sets[s] for s in set_of_step]
        scale = max(float(np.max(self.bound, initial=0.0)), float(np.max(np.abs(Q), initial=0.0)))
        self.force_scale = scale if scale > 0 else 1.0
        self.compliance_scale = float(np.max(np.diag(self.C)))


# ---------------------------------------------------------------------------------------------
# Residuals and refinement (array forms, shared by the steppers and the batch)
# ---------------------------------------------------------------------------------------------
def residuals(F, g, b, dims: int, fscale: float, cscale: float) -> dict:
    """The residuals of a candidate answer of (P) (see the module docstring).

    Parameters
    ----------
    F : (a·d,) ndarray
        Friction forces of the nodes in contact.
    g : (a·d,) ndarray
        Their slip ``Δu = P F + q``.
    b : (a,) ndarray
        Their friction limits f_i N_i.
    dims : int
    fscale, cscale : float
        Force and compliance scales.
    """
    if F.size == 0:
        return {"cone": 0.0, "complementarity": 0.0, "stationarity": 0.0}
    if dims == 1:
        normF, normg = np.abs(F), np.abs(g)
        proj = np.minimum(np.maximum(F - g / cscale, -b), b)
        dot = F * g
        stat = np.abs(F - proj)
    else:
        F2, g2 = F.reshape(-1, 2), g.reshape(-1, 2)
        normF, normg = np.hypot(F2[:, 0], F2[:, 1]), np.hypot(g2[:, 0], g2[:, 1])
        t2 = F2 - g2 / cscale
        nt = np.hypot(t2[:, 0], t2[:, 1])
        scale = np.where(nt > b, b / np.where(nt > 0, nt, 1.0), 1.0)
        dot = np.einsum("ij,ij->i", F2, g2)
        diff = F2 - t2 * scale[:, None]
        stat = np.hypot(diff[:, 0], diff[:, 1])
    return {
        "cone": max(float((normF - b).max()), 0.0) / fscale,
        "complementarity": float(np.abs(dot + b * normg).max()) / (cscale * fscale * fscale),
        "stationarity": float(stat.max()) / fscale,
    }


def refine_box(prob: IncrementProblem, F, q, b, delta: float, fscale: float, cscale: float,
               max_iter: int = 8):
    """Active-set refinement of a d = 1 answer (see the module docstring).

    Identify the limit nodes of ``F`` (``|F_i| >= b_i - delta``), solve the stick nodes exactly,
    and correct the identification until the KKT conditions hold.

    Returns
    -------
    (F, stick, res) or None
        The refined forces, the mask of the variables that stick (their slip is zero by
        construction) and the residuals (as :func:`residuals`); None when no KKT point was
        reached within ``max_iter`` corrections.
    """
    at = np.abs(F) >= b - delta
    sb = np.copysign(b, F)
    for _ in range(max_iter):
        sb *= at
        if prob.diagonal:
            Fr = np.where(at, sb, q / -prob.pdiag)
            g = prob.P @ Fr
            g += q
            stick_slip = float(np.abs(g * ~at).max())
        else:
            Tq, Tb, stick = prob.active_set_operator(at)
            Fr = Tq @ q
            if Tb is not None:
                Fr += Tb @ sb
            g = prob.P @ Fr
            g += q
            stick_slip = float(np.abs(g * stick).max())
        # KKT of (P): stick nodes within their limits and not slipping (g_S = 0 up to
        # rounding), limit nodes slipping against their force (F = +b needs g <= 0)
        over = float((np.abs(Fr) - b).max())
        wrong = float((sb * g).max())
        if over <= 1e-14 * fscale and wrong <= 0.0:
            return Fr, ~at, {"cone": max(over, 0.0) / fscale, "complementarity": 0.0,
                             "stationarity": stick_slip / (cscale * fscale)}
        # correct: a stick node over its limit goes to the limit, a limit node slipping the
        # wrong way goes to stick
        over_nodes = ~at & (np.abs(Fr) > b)
        wrong_nodes = at & (sb * g > 0.0)
        if not (over_nodes.any() or wrong_nodes.any()):
            return None  # violations at rounding level only, yet not a KKT point: give up
        sb = np.where(over_nodes, np.copysign(b, Fr), np.copysign(b, sb))
        at = (at & ~wrong_nodes) | over_nodes
    return None


def refine_disc(prob: IncrementProblem, F, q, b, delta: float, fscale: float, cscale: float,
                max_corrections: int = 4, max_newton: int = 30):
    """Active-set refinement of a d = 2 answer.

    The nodes with ``||F_i|| >= b_i - delta`` are put on their circle, ``F_i = b_i e_i`` with
    slip ``Δu_i = -λ_i F_i`` (λ_i >= 0), the others stick (``Δu_i = 0``); the resulting KKT
    system of (P),

        P F + q + Λ F = 0,   ½ (||F_i||² - b_i²) = 0 on the limit nodes   (Λ = diag λ_i there),

    is solved by Newton's method from the solver's answer (its Jacobian is the symmetric KKT
    matrix ``[[P + Λ, E], [Eᵀ, 0]]``, E holding the limit nodes' forces), and the identification
    is corrected (λ_i < 0 -> stick, ``||F_i|| > b_i`` -> limit) until the conditions hold.

    Returns
    -------
    (F, g, res) or None
        As :func:`refine_box`.
    """
    import scipy.sparse as sp

    a = b.size
    P = prob.P.toarray() if sp.issparse(prob.P) else prob.P
    F2 = np.array(F, dtype=float).reshape(a, 2)
    norm = np.hypot(F2[:, 0], F2[:, 1])
    at = norm >= b - delta
    for _ in range(max_corrections):
        B = np.flatnonzero(at)
        nb = B.size
        x = F2.copy()
        nB = np.hypot(x[B, 0], x[B, 1])
        g = (P @ x.ravel() + q).reshape(a, 2)
        # on the circle, along the force (or against the slip where the force vanishes)
        dirn = np.where(nB[:, None] > 0, x[B], -g[B])
        dn = np.hypot(dirn[:, 0], dirn[:, 1])
        x[B] = b[B, None] * dirn / np.where(dn > 0, dn, 1.0)[:, None]
        g = (P @ x.ravel() + q).reshape(a, 2)
        lam = np.maximum(-np.einsum("ij,ij->i", g[B], x[B]) / np.maximum(b[B] ** 2, 1e-300),
                         0.0)
        rows = (2 * B[:, None] + np.arange(2)).ravel()
        for _it in range(max_newton):
            g = P @ x.ravel() + q
            r1 = g.copy()
            r1[rows] += np.repeat(lam, 2) * x[B].ravel()
            r2 = 0.5 * (np.einsum("ij,ij->i", x[B], x[B]) - b[B] ** 2)
            J = np.zeros((2 * a + nb, 2 * a + nb))
            J[:2 * a, :2 * a] = P
            J[rows, rows] += np.repeat(lam, 2)
            E = np.zeros((2 * a, nb))
            E[rows, np.repeat(np.arange(nb), 2)] = x[B].ravel()
            J[:2 * a, 2 * a:] = E
            J[2 * a:, :2 * a] = E.T
            try:
                step = np.linalg.solve(J, -np.concatenate([r1, r2]))
            except np.linalg.LinAlgError:
                return None
            x = (x.ravel() + step[:2 * a]).reshape(a, 2)
            lam = lam + step[2 * a:]
            if float(np.abs(step).max()) <= 1e-15 * (fscale + 1.0):
                break
        g = P @ x.ravel() + q
        normx = np.hypot(x[:, 0], x[:, 1])
        negative = np.zeros(a, dtype=bool)
        negative[B] = lam < 0.0
        over = ~at & (normx > b)
        if not (negative.any() or over.any()):
            Fr = x.ravel()
            return Fr, np.repeat(~at, 2), residuals(Fr, g, b, 2, fscale, cscale)
        at = (at & ~negative) | over
        F2 = x
    return None


# ---------------------------------------------------------------------------------------------
# The stepper every backend specializes
# ---------------------------------------------------------------------------------------------
class ConvexStepper(Stepper):
    """A stepper that solves problem (P) with a convex solver at every increment.

    A backend subclass sets ``name`` (registry name), ``can_soc`` (whether it expresses the d = 2
    cone), ``STATUS_MAP`` and, where it differs from the name, ``settings_key`` (its entry in
    :data:`TIGHT_SETTINGS`), and implements three methods:

    ``build(prob)``
        Build the solver object for an :class:`IncrementProblem` (called once per contact set)
        and return it; it is stored as ``prob.handle``.
    ``bounds(prob, b)``
        Turn the limits ``b`` (one per node of the set) into whatever the backend's update
        takes (called once per grid instant, in ``init``).
    ``solve(prob, q, bdata) -> (x, status, ok)``
        Update the linear term and the bounds, solve, and return the forces, the backend's own
        status and whether that status means solved.

    Parameters
    ----------
    refine : bool
        Refine the solver's answers on their active set (see the module docstring).
    check_tol : float
        Largest residual accepted (relative to the problem scale).
    active_tol : float
        δ / s_F of the active-set identification.
    **settings
        Solver settings, overriding lcpfric's tight defaults (:data:`TIGHT_SETTINGS`).
    """

    name = ""
    can_soc = False
    STATUS_MAP: dict[str, str] = {}
    settings_key = ""  # key into TIGHT_SETTINGS (default: the name)

    def __init__(self, *, refine: bool = True, check_tol: float = 1e-6,
                 active_tol: float = 1e-6, **settings):
        self.refine = bool(refine)
        self.check_tol = positive("check_tol", check_tol)
        self.active_tol = positive("active_tol", active_tol)
        self._user_settings = dict(settings)
        self.settings = self.settings_for(1)
        self.label = self.name
        self._plan: ScenePlan | None = None
        self._bdata: list = []

    def settings_for(self, dims: int) -> dict:
        """The solver settings for problems with d = ``dims``: lcpfric's tight defaults
        (:data:`TIGHT_SETTINGS`, with their ``_soc`` variant for d = 2), then the user's."""
        key = self.settings_key or self.name
        out = dict(TIGHT_SETTINGS.get(key, {}))
        if dims == 2:
            out.update(TIGHT_SETTINGS.get(key + "_soc", {}))
        out.update(self._user_settings)
        return out

    # -- the backend interface (see the class docstring) ------------------------------------
    def build(self, prob: IncrementProblem):  # pragma: no cover - abstract
        raise NotImplementedError

    def bounds(self, prob: IncrementProblem, b: np.ndarray):
        """The box ``(l, u) = (-b, b)`` of d = 1 (QP backends); conic backends override it."""
        return -b, b.copy()

    def solve(self, prob: IncrementProblem, q: np.ndarray, bdata):  # pragma: no cover
        raise NotImplementedError

    def status_category(self, status) -> str:
        """lcpfric's status (SOLVED, MAX_ITER, ...) for the backend's own ``status``."""
        return self.STATUS_MAP.get(str(status), UNKNOWN)

    # -- the stepper contract ----------------------------------------------------------------
    def check(self, system) -> None:
        if system.dims == 2 and not self.can_soc:
            raise InputError("method", f"{self.label!r} solves QPs only and cannot express the "
                                       f"d = 2 friction cone (a disc per node); use "
                                       f"{CONIC_METHODS}")

    def init(self, scene, u0=None) -> StepState:
        self.check(scene.system)
        plan = ScenePlan(scene)
        for prob in plan.problems:
            if prob is not None:
                prob.handle = self.guarded(self.build, prob)
        self._bdata = [self.bounds(p, b) if p is not None else None
                       for p, b in zip(plan.step_problem, plan.node_bounds)]
        self._plan = plan
        state = super().init(scene, u0)
        state.data = {"solves": 0, "refined": 0, "unrefined": 0, "max_residual": 0.0}
        return state

    def guarded(self, fn, *args):
        """Call a backend function, re-raising the backend's own exceptions as SolverError."""
        try:
            return fn(*args)
        except (SolverError, InputError):
            raise
        except Exception as exc:  # the backend's own error types vary
            raise SolverError(f"{self.label}: the solver failed: {type(exc).__name__}: {exc}",
                              backend=self.label, status=type(exc).__name__) from exc

    def step(self, scene, k, state):
        plan = self._plan
        u1, F1 = self._increment(scene, k, state.u, state.data)
        rows = np.array([k + 1])
        U, Fs = u1[None, :], F1[None, :]
        self._check_equilibrium(scene, rows, U, Fs)
        du = u1 - state.u
        s = self._states(rows, du[None, :])[0]
        return StepState(u1, F1, s, slip_dissipation(state.F, F1, du, plan.dims), state.data)

    def cycle(self, scene, state):
        plan = self._plan
        if plan.m == 1:
            return self._cycle_scalar(scene, state)
        steps = scene.steps
        U = np.empty((steps + 1, plan.m))
        Fs = np.empty_like(U)
        U[0], Fs[0] = state.u, state.F
        u, data = state.u, state.data
        increment = self._increment
        for k in range(steps):
            u, F = increment(scene, k, u, data)
            U[k + 1] = u
            Fs[k + 1] = F
        # what needs no solver is done for the whole cycle at once: the equilibrium check of
        # every increment, the node states and the dissipation
        rows = np.arange(1, steps + 1)
        self._check_equilibrium(scene, rows, U[1:], Fs[1:])
        dU = np.diff(U, axis=0)
        S = np.empty((steps + 1, plan.n), dtype=np.int8)
        S[0] = state.state
        S[1:] = self._states(rows, dU)
        # slip_dissipation of every increment: each node's trapezoid share, clipped at zero
        share = -0.5 * (Fs[:-1] + Fs[1:]) * dU
        if plan.dims == 2:
            share = share[:, 0::2] + share[:, 1::2]
        W = float(np.maximum(share, 0.0).sum())
        end = StepState(U[-1].copy(), Fs[-1].copy(), S[-1].copy(), 0.0, data)
        return end, CycleResult(scene.t, U, Fs, S, W, self.stats(end))

    def stats(self, state) -> dict:
        return dict(state.data)

    # -- one increment, any size --------------------------------------------------------------
    def _increment(self, scene, k, u, data):
        """Solve, refine and check increment k; return ``(u, F)`` at t_{k+1}."""
        plan = self._plan
        j = k + 1
        prob = plan.step_problem[j]
        if prob is None:  # everything separated: F = 0, u = -C Q
            return -plan.CQ[j], np.zeros(plan.m)
        q = prob.q
        np.subtract(plan.neg_CQ[j], u if prob.full else u[prob.dofs], out=q)
        x, status, ok = self.guarded(self.solve, prob, q, self._bdata[j])
        data["solves"] += 1
        if not ok:
            self._fail(scene, k, status, None)
        FA, stick = self._accept(scene, k, prob, np.array(x, dtype=float), q,
                                 plan.node_bounds[j], status, data)
        u1 = prob.Cf @ FA
        u1 -= plan.CQ[j]
        if stick is not None:  # a refined stick node keeps its displacement exactly
            st = prob.dofs[stick]
            u1[st] = u[st]
        if prob.full:
            return u1, FA
        F1 = np.zeros(plan.m)
        F1[prob.dofs] = FA
        return u1, F1

    def _check_equilibrium(self, scene, rows, U, Fs):
        """``max |Q + K u - F| / s_F`` of the increments ending at ``rows``; raise on the first
        over ``check_tol``."""
        plan = self._plan
        R = U @ plan.K  # K symmetric
        R += plan.Q[rows]
        R -= Fs
        eq = np.abs(R).max(axis=1) / plan.force_scale
        bad = np.flatnonzero(~(eq <= self.check_tol))
        if bad.size:
            i = bad[0]
            self._fail(scene, int(rows[i]) - 1, "solved",
                       {"equilibrium": float(eq[i])})

    def _states(self, rows, dU):
        """Node states (stick, forward, backward slip, separation) over the increments ending
        at ``rows``, from their slips ``dU``."""
        plan = self._plan
        eps = self.check_tol * plan.compliance_scale * plan.force_scale
        if plan.dims == 1:
            S = (dU > eps).view(np.int8)
            S[dU < -eps] = State.BACKWARD
        else:
            S = (np.hypot(dU[:, 0::2], dU[:, 1::2]) > eps).view(np.int8)
        S[~plan.contact[rows]] = State.SEPARATION
        return S

    def _accept(self, scene, k, prob, FA, q, b, status, data):
        """Refine and check; return the accepted forces and, for a refined answer, the mask
        of its stick variables."""
        plan = self._plan
        fs, cs = plan.force_scale, plan.compliance_scale
        tol = self.check_tol
        answer = None
        if self.refine:
            refine = refine_box if prob.dims == 1 else refine_disc
            refined = refine(prob, FA, q, b, self.active_tol * fs, fs, cs)
            if refined is not None and _worst(refined[2]) <= tol:
                answer, stick, res, kind = *refined, "refined"
        if answer is None:  # the solver's own answer, checked on its own
            g = prob.P @ FA
            g += q
            res = residuals(FA, g, b, prob.dims, fs, cs)
            if not _worst(res) <= tol:  # also catches NaN
                self._fail(scene, k, status, res)
            answer, stick, kind = FA, None, "unrefined"
        data[kind] += 1
        data["max_residual"] = max(data["max_residual"], _worst(res))
        return answer, stick

    def _fail(self, scene, k, status, res):
        """Raise the SolverError of step k (status not solved, or residuals over tolerance)."""
        t0, t1 = scene.t[k], scene.t[k + 1]
        where = f"{self.label}: increment {k} (t = {t0:.6g} -> {t1:.6g})"
        if res is None:
            mapped = self.status_category(status)
            msg = (f"{where} ended with solver status {status!s} ({mapped}): "
                   f"{_ADVICE.get(mapped, _ADVICE[UNKNOWN])}")
        else:
            worst = max(res, key=lambda r: math.inf if res[r] != res[r] else res[r])
            msg = (f"{where}: the solver reported {status!s} but its answer fails lcpfric's "
                   f"residual check ({worst} {res[worst]:.3g} > check_tol {self.check_tol:g}); "
                   f"tighten the solver's tolerances"
                   + ("" if self.refine else " or pass refine=True"))
            if any(v != v for v in res.values()):
                msg += " (the answer contains NaN: check the loads for NaN or inf)"
        raise SolverError(msg, backend=self.label, status=str(status), residuals=res)

    # -- one node, d = 1: the same step in float arithmetic -----------------------------------
    def _cycle_scalar(self, scene, state):
        """The cycle of a one-unknown scene (the paper's node) in Python floats: the per-step
        overhead around the solver call is a few float operations, not numpy calls."""
        plan = self._plan
        steps = scene.steps
        k11 = float(plan.K[0, 0])
        c = float(plan.C[0, 0])
        Q = plan.Q[:, 0].tolist()
        CQ = plan.CQ[:, 0].tolist()
        B = plan.bound[:, 0].tolist()
        probs = plan.step_problem
        bdata = self._bdata
        solve, guarded = self.solve, self.guarded
        fs = plan.force_scale
        tol = self.check_tol
        delta = self.active_tol * fs
        refine = self.refine
        data = state.data
        res_scale = (fs, c * fs * fs)
        eps = tol * c * fs
        U = [0.0] * (steps + 1)
        Fs = [0.0] * (steps + 1)
        S = [0] * (steps + 1)
        u, F = float(state.u[0]), float(state.F[0])
        U[0], Fs[0], S[0] = u, F, int(state.state[0])
        W = 0.0
        nsolve = nref = 0
        worst_seen = data["max_residual"]
        for j in range(1, steps + 1):
            prob = probs[j]
            if prob is None:
                F1, u1, st = 0.0, -CQ[j], 3
            else:
                b = B[j]
                qb = prob.q
                qv = -(CQ[j] + u)
                qb[0] = qv
                x, status, ok = guarded(solve, prob, qb, bdata[j])
                nsolve += 1
                if not ok:
                    self._fail(scene, j - 1, status, None)
                Fx = float(x[0])
                worst = math.inf
                stuck = False
                if refine:
                    # identify (on the limit with the solver's sign, or stick), then correct:
                    # a limit node whose slip has the wrong sign sticks, a stick node over
                    # its limit goes to the limit
                    ftr = -qv / c
                    on_limit = abs(Fx) >= b - delta
                    if on_limit:
                        F1 = b if Fx >= 0.0 else -b
                        on_limit = F1 * ftr >= b * b
                    if not on_limit:
                        if -b <= ftr <= b:
                            F1, stuck = ftr, True
                        else:
                            F1 = b if ftr > 0 else -b
                    worst = _scalar_worst(F1, c * F1 + qv, b, c, res_scale)
                    if worst <= tol:
                        nref += 1
                if not worst <= tol:
                    stuck = False
                    F1 = Fx
                    worst = _scalar_worst(F1, c * F1 + qv, b, c, res_scale)
                    if not worst <= tol:
                        g = c * F1 + qv
                        self._fail(scene, j - 1, status, _scalar_residuals(F1, g, b, c,
                                                                           res_scale))
                if worst > worst_seen:
                    worst_seen = worst
                # a refined stick node keeps its displacement exactly
                u1 = u if stuck else c * F1 - CQ[j]
                eq = abs(Q[j] + k11 * u1 - F1) / fs
                if not eq <= tol:
                    res = _scalar_residuals(F1, c * F1 + qv, b, c, res_scale)
                    res["equilibrium"] = eq
                    self._fail(scene, j - 1, status, res)
                du = u1 - u
                st = 1 if du > eps else (2 if du < -eps else 0)
                if b <= 0.0:
                    st = 3
            dW = -0.5 * (F + F1) * (u1 - u)
            if dW > 0.0:  # slip_dissipation in floats: a node's share is never negative
                W += dW
            u, F = u1, F1
            U[j], Fs[j], S[j] = u, F, st
        data["solves"] += nsolve
        data["refined"] += nref
        data["unrefined"] += nsolve - nref
        data["max_residual"] = worst_seen
        Ua = np.array(U)[:, None]
        Fa = np.array(Fs)[:, None]
        Sa = np.array(S, dtype=np.int8)[:, None]
        end = StepState(Ua[-1].copy(), Fa[-1].copy(), Sa[-1].copy(), 0.0, data)
        return end, CycleResult(scene.t, Ua, Fa, Sa, W, self.stats(end))


def _worst(res: dict) -> float:
    worst = 0.0
    for v in res.values():
        if v != v:
            return math.nan
        if v > worst:
            worst = v
    return worst


def _scalar_residuals(F, g, b, c, scale) -> dict:
    fs, cfs2 = scale
    t = F - g / c
    return {"cone": max(abs(F) - b, 0.0) / fs,
            "complementarity": abs(F * g + b * abs(g)) / cfs2,
            "stationarity": abs(F - min(max(t, -b), b)) / fs}


def _scalar_worst(F, g, b, c, scale) -> float:
    """max of :func:`_scalar_residuals` without building the dict (NaN propagates)."""
    fs, cfs2 = scale
    t = F - g / c
    r1 = (abs(F) - b) / fs
    r2 = abs(F * g + b * abs(g)) / cfs2
    r3 = abs(F - min(max(t, -b), b)) / fs
    if r1 != r1 or r2 != r2 or r3 != r3:
        return math.nan
    return max(r1, r2, r3)


def quiet(fn, *args, **kwargs):
    """Call ``fn`` with the backend's warnings silenced (lcpfric raises its own errors)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)
