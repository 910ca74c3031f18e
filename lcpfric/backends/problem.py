r"""The incremental problem every convex backend solves: its derivation, and its data.

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
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["IncrementProblem", "ScenePlan", "triu_csc"]


def triu_csc(P):
    """The upper triangle of a dense or sparse symmetric matrix, as scipy CSC (what Clarabel and
    OSQP read)."""
    import scipy.sparse as sp

    return sp.triu(sp.csc_matrix(P), format="csc")


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
        self.N = N
        self.friction = np.asarray(system.friction, dtype=float)
        self._set_keys = keys
        d = self.dims
        self.diagonal = diagonal = system.is_diagonal()
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
        # per grid instant j, the nodes in contact at t_{j-1} that separate at t_j (None if none)
        leaving = np.zeros_like(contact)
        leaving[1:] = contact[:-1] & ~contact[1:]
        self.separating = [row if row.any() else None for row in leaving]
        self._interior: dict[bytes, IncrementProblem] = {}
        scale = max(float(np.max(self.bound, initial=0.0)), float(np.max(np.abs(Q), initial=0.0)))
        self.force_scale = scale if scale > 0 else 1.0
        self.compliance_scale = float(np.max(np.diag(self.C)))

    def interior_problem(self, k: int) -> IncrementProblem:
        """The problem for an instant inside increment k: its nodes are those in contact at
        either end (N > 0 over the open increment). One of the grid's problems when it has the
        same set, else built on first use (its ``handle`` None until the backend builds it)."""
        row = self.contact[k] | self.contact[k + 1]
        key = row.tobytes()
        index = self._set_keys.get(key)
        if index is not None:
            return self.problems[index]
        prob = self._interior.get(key)
        if prob is None:
            d = self.dims
            nodes = np.flatnonzero(row)
            dofs = (nodes[:, None] * d + np.arange(d)[None, :]).ravel()
            prob = self._interior[key] = IncrementProblem(
                nodes, dofs, d, np.ascontiguousarray(self.C[np.ix_(dofs, dofs)]),
                np.ascontiguousarray(self.C[:, dofs]), self.diagonal,
                full=bool(nodes.size == self.n))
        return prob
