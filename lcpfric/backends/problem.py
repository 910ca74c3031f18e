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
  contact sets of a cycle are enumerated before the first step; the problem of a set (and its
  solver object) is built when a step first needs it (see the plan below). A node whose normal
  load never vanishes is in every set and needs no separation logic at all; a scene without
  separation has a single set.
* d = 1 gives intervals, ``-f_i N_i <= F_i <= f_i N_i``: a QP with box constraints (any QP
  solver). d = 2 gives second-order cones ``(f_i N_i, F_i) ∈ SOC(3)``: only conic solvers
  (Clarabel, cvxpy with CLARABEL/ECOS/SCS) can express it. Nobody approximates a disc by a
  polygon: a backend that cannot express the cone refuses the scene.

The plan, and its memory budget
-------------------------------
The problem of a contact set A holds O((a·d)²) bytes: dense copies of ``P = C_AA`` and of
``C[:, A]``, the backend's solver object (its own copy of P, and a factorization) and the
refinement's active-set operators (two a·d × a·d matrices per pattern of limit nodes). A scene
whose contact area changes with the normal load (a continuum contact under a varying load, or
nodes separating one after another) has a different set at nearly every grid instant: one
problem per set would hold hundreds of them. So the plan (:class:`ScenePlan`) keeps the
problems in one LRU cache keyed by the contact set (:class:`ProblemCache`), under a byte budget
(the backends' ``plan_budget``, :data:`DEFAULT_PLAN_BUDGET` by default): a set's problem is
built on first use, grid instants and the instants inside an increment alike; before anything
is built that would take the bytes held over the budget, the least recently used problems are
dropped, then the least recently used operators of the problem in use. The problem in use is
always kept (a budget below one problem means one problem at a time). The bytes counted are P,
``C[:, A]``, the operators and the backend's estimate of its solver object
(:meth:`~lcpfric.backends.ConvexStepper.handle_bytes`). Outside the budget: the scene's dense C
and K (one each) and, per grid instant, only vectors (the loads, the limits and ``-(C Q)_A``,
O(steps · m) in all) and the index of its set. A dropped problem is rebuilt when its set comes
back, and its solver starts cold (no warm start from a dropped object); the answers do not
change, every one being refined and checked. A scene with few sets builds each once: the
backends' stats ``plans_built``, ``plans_evicted`` and ``plan_peak_bytes`` show the reuse.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["IncrementProblem", "ProblemCache", "ScenePlan", "DEFAULT_PLAN_BUDGET", "triu_csc",
           "set_dofs", "matrix_bytes"]

#: Bytes a plan's problems may hold (P, C[:, A], operators, solver objects) unless the backend
#: is given ``plan_budget``.
DEFAULT_PLAN_BUDGET = 256 * 2**20


def triu_csc(P):
    """The upper triangle of a dense or sparse symmetric matrix, as scipy CSC (what Clarabel and
    OSQP read)."""
    import scipy.sparse as sp

    return sp.triu(sp.csc_matrix(P), format="csc")


def set_dofs(nodes: np.ndarray, dims: int) -> np.ndarray:
    """The tangential unknowns of ``nodes``, node by node (the variable order of a problem)."""
    return (nodes[:, None] * dims + np.arange(dims)[None, :]).ravel()


def matrix_bytes(M) -> int:
    """Bytes of the arrays of a dense or scipy-sparse matrix (0 for None)."""
    if M is None:
        return 0
    if isinstance(M, np.ndarray):
        return int(M.nbytes)
    return sum(int(getattr(M, name).nbytes) for name in ("data", "indices", "indptr", "offsets")
               if hasattr(M, name))


@dataclass(eq=False)
class IncrementProblem:
    """Problem (P) for one contact set: ``min ½ Fᵀ P F + qᵀ F`` over the cone of the set's nodes.

    Built once per contact set (while its plan holds it); per step only ``q`` and the bounds
    change.

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
    handle_bytes : int
        The backend's estimate of the bytes ``handle`` holds (counted in the plan's budget).
    reserve : callable or None
        ``reserve(problem, bytes)``, called before an operator is added to the cache: the plan's
        :meth:`ProblemCache.reserve`. None outside a plan: the operators alone are then kept
        under :data:`DEFAULT_PLAN_BUDGET`.
    """

    nodes: np.ndarray
    dofs: np.ndarray
    dims: int
    P: Any
    Cf: np.ndarray | None = None
    diagonal: bool = False
    full: bool = False
    handle: Any = None
    handle_bytes: int = 0
    reserve: Callable[[IncrementProblem, int], None] | None = field(default=None, repr=False)
    q: np.ndarray = field(init=False)
    pdiag: np.ndarray = field(init=False)
    _ops: OrderedDict = field(default_factory=OrderedDict, init=False, repr=False)

    def __post_init__(self):
        self.q = np.zeros(self.dofs.size)
        self.pdiag = np.asarray(self.P.diagonal(), dtype=float).copy()

    @property
    def size(self) -> int:
        """Number of variables, a·d."""
        return int(self.dofs.size)

    @property
    def triu_nnz(self) -> int:
        """Entries of the upper triangle of P as a solver gets it (the diagonal alone when P is
        diagonal): the base of the backends' estimates of their solver objects."""
        s = self.size
        return s if self.diagonal else s * (s + 1) // 2

    @property
    def operator_bytes(self) -> int:
        """Bytes of one cached active-set operator: ``Tq``, ``Tb``, the stick mask, the key."""
        s = self.size
        return 8 * s * (2 * s + 1) + s

    @property
    def ops_bytes(self) -> int:
        """Bytes of the cached active-set operators."""
        return len(self._ops) * self.operator_bytes

    @property
    def nbytes(self) -> int:
        """Bytes held for this set: P, Cf, the cached operators and ``handle_bytes``."""
        return matrix_bytes(self.P) + matrix_bytes(self.Cf) + self.ops_bytes + self.handle_bytes

    def active_set_operator(self, at: np.ndarray):
        """``(Tq, Tb, stick)`` with ``F = Tq q + Tb (±b on the limit nodes)`` solving
        ``P_SS F_S = -(q_S + P_SB F_B)`` for the stick nodes S = ~at; cached per pattern, the
        least recently used dropped first when the budget is reached (see ``reserve``)."""
        key = at.tobytes()
        ops = self._ops
        op = ops.get(key)
        if op is not None:
            ops.move_to_end(key)
            return op
        need = self.operator_bytes
        if self.reserve is not None:
            self.reserve(self, need)
        else:
            self.trim_ops(DEFAULT_PLAN_BUDGET - need - (self.nbytes - self.ops_bytes))
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
        op = ops[key] = (Tq, Tb, (~at).astype(float))
        return op

    def trim_ops(self, room: float) -> int:
        """Drop cached operators, least recently used first, until they take at most ``room``
        bytes; return the bytes freed."""
        ops = self._ops
        before = len(ops)
        while ops and self.ops_bytes > room:
            ops.popitem(last=False)
        return (before - len(ops)) * self.operator_bytes


class ProblemCache:
    """The problems of a scene's contact sets, built on first use and held under a byte budget.

    An LRU cache keyed by the contact set (its row of booleans, as bytes): :meth:`get` returns
    the set's problem, building it (with its solver object, through ``build``) when it is not
    held. Before anything is built that would take the bytes held (:attr:`nbytes`, the sum of
    the problems' :attr:`IncrementProblem.nbytes`) over ``budget``, :meth:`reserve` drops the
    least recently used problems, then the least recently used operators of the problem in use;
    the problem in use is always kept. A dropped problem is only forgotten: one still referenced
    elsewhere keeps working (outside the budget).

    Parameters
    ----------
    C : (m, m) ndarray
        The scene's compliance (its one dense copy; a problem copies its set's part).
    n, dims : int
        Nodes and tangential directions per node.
    diagonal : bool
        C is diagonal.
    build : callable, optional
        ``build(problem) -> handle``: the backend's solver object for a new problem (None: the
        problems get none).
    handle_bytes : callable, optional
        ``handle_bytes(problem) -> int``: the estimated bytes of that object, reserved before
        it is built.
    budget : float
        Bytes (``math.inf``: no bound).

    Attributes
    ----------
    nbytes, peak_bytes : int
        Bytes held now, and at most so far.
    built, evicted : int
        Problems built and dropped so far.
    """

    def __init__(self, C: np.ndarray, n: int, dims: int, diagonal: bool,
                 build: Callable[[IncrementProblem], Any] | None = None,
                 handle_bytes: Callable[[IncrementProblem], int] | None = None,
                 budget: float = DEFAULT_PLAN_BUDGET):
        self.C, self.n, self.dims, self.diagonal = C, n, dims, diagonal
        self._build, self._handle_bytes = build, handle_bytes
        self.budget = budget
        self._held: OrderedDict[bytes, IncrementProblem] = OrderedDict()
        self.nbytes = self.peak_bytes = 0
        self.built = self.evicted = 0

    def __len__(self) -> int:
        return len(self._held)

    def held(self) -> list[IncrementProblem]:
        """The problems held, least recently used first."""
        return list(self._held.values())

    def counts(self) -> dict:
        """``plans_built``, ``plans_evicted`` and ``plan_peak_bytes`` (the backends' stats)."""
        return {"plans_built": self.built, "plans_evicted": self.evicted,
                "plan_peak_bytes": self.peak_bytes}

    def get(self, row: np.ndarray, key: bytes | None = None) -> IncrementProblem | None:
        """The problem of the contact set ``row`` (n booleans; ``key`` its bytes, if known),
        built if not held; None for the empty set (every node separated)."""
        key = row.tobytes() if key is None else key
        held = self._held
        prob = held.get(key)
        if prob is not None:
            held.move_to_end(key)
            return prob
        nodes = np.flatnonzero(row)
        if nodes.size == 0:
            return None
        dofs = set_dofs(nodes, self.dims)
        s, C = dofs.size, self.C
        self.reserve(None, 8 * s * (s + C.shape[0]))  # P and Cf, float64
        prob = IncrementProblem(nodes, dofs, self.dims,
                                np.ascontiguousarray(C[np.ix_(dofs, dofs)]),
                                np.ascontiguousarray(C[:, dofs]), self.diagonal,
                                full=bool(nodes.size == self.n), reserve=self.reserve)
        held[key] = prob
        if self._build is not None:
            try:
                need = int(self._handle_bytes(prob)) if self._handle_bytes is not None else 0
                self.reserve(prob, need)
                prob.handle_bytes = need
                prob.handle = self._build(prob)
            except BaseException:
                del held[key]
                self.nbytes -= prob.nbytes
                raise
        self.built += 1
        return prob

    def reserve(self, prob: IncrementProblem | None, need: int) -> None:
        """Make room for ``need`` more bytes of ``prob`` (the problem in use; None for one not
        held yet) and count them: while the bytes held would exceed the budget, drop the least
        recently used other problem, then ``prob``'s least recently used operators."""
        held = self._held
        while self.nbytes + need > self.budget and held:
            key = next(iter(held))
            old = held[key]
            if old is prob:
                if len(held) == 1:
                    break
                held.move_to_end(key)  # the problem in use is the most recently used
                continue
            del held[key]
            self.nbytes -= old.nbytes
            old.reserve = None  # forgotten: its operators are bounded on their own
            self.evicted += 1
        if prob is not None and self.nbytes + need > self.budget:
            self.nbytes -= prob.trim_ops(self.budget - need - (self.nbytes - prob.ops_bytes))
        self.nbytes += need
        self.peak_bytes = max(self.peak_bytes, self.nbytes)


class ScenePlan:
    """Everything about a scene the steps need, computed once before the first step; the
    problems of its contact sets are built on first use and held under a byte budget (see the
    module docstring).

    Parameters
    ----------
    scene : Scene
    build, handle_bytes : callable, optional
        The backend's solver object for a new problem and its estimated bytes (see
        :class:`ProblemCache`).
    budget : float
        Bytes the problems may hold (:data:`DEFAULT_PLAN_BUDGET`).

    Attributes
    ----------
    C, K : (m, m) ndarray
        Compliance and stiffness (dense).
    Q, CQ : (N+1, m) ndarray
        ``Q(t_k)`` and ``C Q(t_k)`` on the grid.
    bound : (N+1, n) ndarray
        ``f_i N_i(t_k)``, the friction limits.
    contact : (N+1, n) bool ndarray
        The nodes in contact at each grid instant.
    set_of_step : (N+1,) int ndarray
        Index of the contact set of each grid instant (the sets in order of first appearance).
    problems : ProblemCache
        The problems held (:meth:`problem` and :meth:`interior_problem` get them).
    node_bounds, neg_CQ : list of ndarray
        Per grid instant, for the nodes of its set: the limits (one per node) and ``-(C Q)_A``
        (None where every node is separated).
    separating : list
        Per grid instant, the nodes that separate there (None if none).
    force_scale, compliance_scale : float
        ``s_F`` and ``c`` of the residuals (see :mod:`~lcpfric.backends.checks`).
    """

    def __init__(self, scene, build: Callable[[IncrementProblem], Any] | None = None,
                 handle_bytes: Callable[[IncrementProblem], int] | None = None,
                 budget: float = DEFAULT_PLAN_BUDGET):
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
        self.diagonal = system.is_diagonal()
        # per set: its row (None for the empty set) and key; per grid instant, vectors only
        self._set_rows = [row if row.any() else None for row in rows]
        self._set_keys = list(keys)
        nodes = [np.flatnonzero(row) for row in rows]
        dofs = [None if row.all() else set_dofs(idx, self.dims) for row, idx in zip(rows, nodes)]
        self.node_bounds = [self.bound[k, nodes[s]] if nodes[s].size else None
                            for k, s in enumerate(set_of_step)]
        self.neg_CQ = [None if not nodes[s].size else
                       -(self.CQ[k] if dofs[s] is None else self.CQ[k, dofs[s]])
                       for k, s in enumerate(set_of_step)]
        # per grid instant j, the nodes in contact at t_{j-1} that separate at t_j (None if none)
        leaving = np.zeros_like(contact)
        leaving[1:] = contact[:-1] & ~contact[1:]
        self.separating = [row if row.any() else None for row in leaving]
        self.problems = ProblemCache(self.C, self.n, self.dims, self.diagonal, build,
                                     handle_bytes, budget)
        scale = max(float(np.max(self.bound, initial=0.0)), float(np.max(np.abs(Q), initial=0.0)))
        self.force_scale = scale if scale > 0 else 1.0
        self.compliance_scale = float(np.max(np.diag(self.C)))

    def problem(self, j: int) -> IncrementProblem | None:
        """The problem of grid instant j (None where every node is separated)."""
        s = self.set_of_step[j]
        row = self._set_rows[s]
        return None if row is None else self.problems.get(row, self._set_keys[s])

    def interior_problem(self, k: int) -> IncrementProblem:
        """The problem for an instant inside increment k: its nodes are those in contact at
        either end (N > 0 over the open increment); the same object as a grid instant's when
        the set is the same."""
        return self.problems.get(self.contact[k] | self.contact[k + 1])
