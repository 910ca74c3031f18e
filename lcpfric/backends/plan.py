"""What every step of a scene needs from the convex backends, built once (:class:`ScenePlan`), and
the problems of the contact sets, kept under a byte budget (:class:`ProblemCache`): a contact
whose set changes at every step runs in bounded memory (:mod:`lcpfric.backends.problem` for the
problem itself)."""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from .problem import DEFAULT_PLAN_BUDGET, IncrementProblem, set_dofs

if TYPE_CHECKING:
    from ..scene import Scene

__all__ = ["ProblemCache", "ScenePlan"]


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
    budget : float
        The ``budget`` given.
    """

    def __init__(
        self,
        C: np.ndarray,
        n: int,
        dims: int,
        diagonal: bool,
        build: Callable[[IncrementProblem], Any] | None = None,
        handle_bytes: Callable[[IncrementProblem], int] | None = None,
        budget: float = DEFAULT_PLAN_BUDGET,
    ) -> None:
        self.C, self.n, self.dims, self.diagonal = C, n, dims, diagonal
        self._build, self._handle_bytes = build, handle_bytes
        self.budget = budget
        self._held: OrderedDict[bytes, IncrementProblem] = OrderedDict()
        self.nbytes = self.peak_bytes = 0
        self.built = self.evicted = 0

    def __len__(self) -> int:
        return len(self._held)

    def held(self) -> list[IncrementProblem]:
        """The problems held, least recently used first.

        Returns
        -------
        list of IncrementProblem
            A new list; the cache itself is not changed.
        """
        return list(self._held.values())

    def counts(self) -> dict[str, int]:
        """The cache's counters, as the backends report them in their stats.

        Returns
        -------
        dict
            ``plans_built`` (:attr:`built`), ``plans_evicted`` (:attr:`evicted`) and
            ``plan_peak_bytes`` (:attr:`peak_bytes`).
        """
        return {
            "plans_built": self.built,
            "plans_evicted": self.evicted,
            "plan_peak_bytes": self.peak_bytes,
        }

    def get(self, row: np.ndarray, key: bytes | None = None) -> IncrementProblem | None:
        """The problem of a contact set, built if not held.

        Parameters
        ----------
        row : (n,) bool ndarray
            The contact set: the nodes in contact.
        key : bytes, optional
            ``row.tobytes()``, if the caller has it already.

        Returns
        -------
        IncrementProblem or None
            The set's problem, now the most recently used; None for the empty set (every node
            separated).

        Raises
        ------
        lcpfric.errors.SolverError
            From ``build`` (a backend's, which
            :meth:`~lcpfric.backends.base.ConvexStepper.guarded` turns every solver error
            into); the problem is then not held. Whatever else ``build`` raises passes through
            the same way.
        """
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
        prob = IncrementProblem(
            nodes,
            dofs,
            self.dims,
            np.ascontiguousarray(C[np.ix_(dofs, dofs)]),
            np.ascontiguousarray(C[:, dofs]),
            self.diagonal,
            full=bool(nodes.size == self.n),
            reserve=self.reserve,
        )
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
        """Make room for ``need`` more bytes of ``prob`` and count them.

        While the bytes held would exceed the budget, drop the least recently used other
        problem, then ``prob``'s least recently used operators. The problem in use is always
        kept, so the bytes held may exceed a budget below one problem.

        Parameters
        ----------
        prob : IncrementProblem or None
            The problem in use (None for one not held yet).
        need : int
            The bytes about to be added.
        """
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
    """Everything about a scene the steps need, computed once before the first step.

    The problems of its contact sets are built on first use and held under a byte budget (see
    the module docstring).

    Parameters
    ----------
    scene : Scene
        A discrete system's scene (:class:`~lcpfric.scene.Scene` with a ``system``): its grid,
        loads, normal reactions and contact pattern.
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
    n, m, dims : int
        Nodes, unknowns (n·d) and d.
    N : (N+1, n) ndarray
        The normal reactions on the grid.
    friction : (n,) ndarray
        The friction coefficients f_i.
    diagonal : bool
        K (and so C) is diagonal.

    Raises
    ------
    lcpfric.errors.InputError
        ``scene``: a tangential load or normal reaction on the grid is NaN or inf.
    """

    def __init__(
        self,
        scene: Scene,
        build: Callable[[IncrementProblem], Any] | None = None,
        handle_bytes: Callable[[IncrementProblem], int] | None = None,
        budget: float = DEFAULT_PLAN_BUDGET,
    ) -> None:
        system = scene.system
        Q = np.asarray(scene.Q, dtype=float)
        N = np.asarray(scene.N, dtype=float)
        if not (np.all(np.isfinite(Q)) and np.all(np.isfinite(N))):
            raise InputError(
                "scene",
                "the tangential loads and normal reactions on the grid "
                "must be finite; found NaN or inf",
            )
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
        self.node_bounds = [
            self.bound[k, nodes[s]] if nodes[s].size else None for k, s in enumerate(set_of_step)
        ]
        self.neg_CQ = [
            None if not nodes[s].size else -(self.CQ[k] if dofs[s] is None else self.CQ[k, dofs[s]])
            for k, s in enumerate(set_of_step)
        ]
        # per grid instant j, the nodes in contact at t_{j-1} that separate at t_j (None if none)
        leaving = np.zeros_like(contact)
        leaving[1:] = contact[:-1] & ~contact[1:]
        self.separating = [row if row.any() else None for row in leaving]
        self.problems = ProblemCache(
            self.C, self.n, self.dims, self.diagonal, build, handle_bytes, budget
        )
        scale = max(float(np.max(self.bound, initial=0.0)), float(np.max(np.abs(Q), initial=0.0)))
        self.force_scale = scale if scale > 0 else 1.0
        self.compliance_scale = float(np.max(np.diag(self.C)))

    def problem(self, j: int) -> IncrementProblem | None:
        """The problem of a grid instant, built on first use.

        Parameters
        ----------
        j : int
            The grid instant, ``0 <= j <= N``.

        Returns
        -------
        IncrementProblem or None
            The problem of the instant's contact set (None where every node is separated).

        Raises
        ------
        lcpfric.errors.SolverError
            From the backend's ``build`` when the problem is built.
        """
        s = self.set_of_step[j]
        row = self._set_rows[s]
        return None if row is None else self.problems.get(row, self._set_keys[s])

    def interior_problem(self, k: int) -> IncrementProblem | None:
        """The problem for an instant inside an increment.

        Its nodes are those in contact at either end (N > 0 over the open increment); the same
        object as a grid instant's when the set is the same.

        Parameters
        ----------
        k : int
            The increment, from t_k to t_{k+1} (``0 <= k < N``).

        Returns
        -------
        IncrementProblem or None
            The problem (None when no node is in contact at either end).

        Raises
        ------
        lcpfric.errors.SolverError
            From the backend's ``build`` when the problem is built.
        """
        return self.problems.get(self.contact[k] | self.contact[k + 1])
