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
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import scipy.sparse as sp
    from numpy.typing import ArrayLike


__all__ = ["IncrementProblem", "DEFAULT_PLAN_BUDGET", "triu_csc", "set_dofs", "matrix_bytes"]

#: Bytes a plan's problems may hold (P, C[:, A], operators, solver objects) unless the backend
#: is given ``plan_budget``: 256 MiB (268435456).
DEFAULT_PLAN_BUDGET = 256 * 2**20


def triu_csc(P: ArrayLike | sp.spmatrix) -> sp.csc_matrix:
    """The upper triangle of a dense or sparse symmetric matrix, as scipy CSC.

    Parameters
    ----------
    P : (s, s) array_like or scipy sparse matrix
        A symmetric matrix (only its upper triangle is read).

    Returns
    -------
    scipy.sparse.csc_matrix
        The upper triangle of P, diagonal included (what Clarabel and OSQP read).
    """
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
    return sum(
        int(getattr(M, name).nbytes)
        for name in ("data", "indices", "indptr", "offsets")
        if hasattr(M, name)
    )


@dataclass(eq=False)
class IncrementProblem:
    """Problem (P) for one contact set: ``min ½ Fᵀ P F + qᵀ F`` over the cone of the set's nodes.

    Built once per contact set (while its plan holds it); per step only ``q`` and the bounds
    change.

    Parameters
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
        The backend's solver object for this problem (set by the plan once it is built).
    handle_bytes : int
        The backend's estimate of the bytes ``handle`` holds (counted in the plan's budget).
    reserve : callable or None
        ``reserve(problem, bytes)``, called before an operator is added to the cache: the plan's
        :meth:`ProblemCache.reserve`. None outside a plan: the operators alone are then kept
        under :data:`DEFAULT_PLAN_BUDGET`.

    Attributes
    ----------
    nodes, dofs, dims, P, Cf, diagonal, full, handle, handle_bytes, reserve
        The parameters, as given (``handle``, ``handle_bytes`` and ``reserve`` change while a
        plan holds the problem).
    q : (a·d,) ndarray
        The linear term ``-(C F_tr)_A`` of the current step, overwritten in place by every
        step (a backend's ``solve`` receives it).
    pdiag : (a·d,) ndarray
        The diagonal of P.
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
        """Entries of the upper triangle of P as a solver gets it.

        The diagonal alone when P is diagonal: the base of the backends' estimates of their
        solver objects.
        """
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

    def active_set_operator(
        self, at: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
        """The operators of the refinement's linear solve for one pattern of limit variables.

        ``F = Tq q + Tb (±b on the limit nodes)`` solves ``P_SS F_S = -(q_S + P_SB F_B)`` for
        the stick variables S = ~at. Cached per pattern, the least recently used dropped first
        when the budget is reached (see ``reserve``).

        Parameters
        ----------
        at : (a·d,) bool ndarray
            The variables on their limit (B); the others stick (S).

        Returns
        -------
        Tq : (a·d, a·d) ndarray
            ``-P_SS⁻¹`` on the stick block, zero elsewhere.
        Tb : (a·d, a·d) ndarray or None
            ``-P_SS⁻¹ P_SB`` on the stick rows, the identity on the limit block (None when no
            variable is on its limit).
        stick : (a·d,) float ndarray
            1.0 on the stick variables, 0.0 on the limit ones.
        """
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
        """Drop cached operators, least recently used first, until they fit in ``room`` bytes.

        Parameters
        ----------
        room : float
            Bytes the cached operators may keep (negative: drop them all).

        Returns
        -------
        int
            The bytes freed.
        """
        ops = self._ops
        before = len(ops)
        while ops and self.ops_bytes > room:
            ops.popitem(last=False)
        return (before - len(ops)) * self.operator_bytes
