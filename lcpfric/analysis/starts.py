r"""How the start decides the steady state: the steady states a system reaches over a sample of
admissible initial states (:func:`explore_starts`).

For an uncoupled system the steady dissipation does not depend on the start (the frictional
Melan theorem and its cyclic counterpart; tested here as one W from every start). A coupled
system (``N = P + B v``, :mod:`lcpfric.model.coupling`) can shake down from some starts and slip
from others, and its steady W can vary continuously with the start: a node that never slips keeps
the displacement its transient left, and that changes the normal reactions of the nodes that do
slip (``../coupled`` notes of the project).

The starts
----------
An admissible start is parametrized by the *mobilization ratios* ``r_i ∈ [-1, 1]`` of the nodes
at t = 0: the displacements with ``F_i(0) = r_i f_i N_i(0)``, that is

    (K - diag(r f) B) u = diag(r f) P(0) - Q(0).

The matrix is non-singular on the whole cube: its determinant is affine in each ``r_i`` and
positive at every vertex (Klarbring's condition, checked when the system is built). A start whose
normal reactions are not all compressions is not admissible and is replaced by another sample
(the count is reported). Starts may also be given as displacements.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = [
    "explore_starts",
    "StartStudy",
    "SteadyBranch",
    "start_from_ratios",
    "start_map",
    "coupling_band",
]


def start_from_ratios(system, r) -> np.ndarray:
    """The displacements at t = 0 whose forces are ``F_i = r_i f_i N_i(0)`` (module docstring).

    Parameters
    ----------
    system : ContactSystem
        A d = 1 system with a stiffness matrix (coupled or not).
    r : (n,) array_like
        Mobilization ratios in [-1, 1].

    Returns
    -------
    ndarray
        The n displacements (their normal reactions are not checked here).
    """
    r = _checks.finite_array("r", r).ravel()
    if r.size != system.n or np.any(np.abs(r) > 1.0):
        raise InputError("r", f"needs {system.n} mobilization ratios in [-1, 1]")
    K = system.dense_stiffness()
    B = system.coupling if system.coupling is not None else np.zeros_like(K)
    rf = r * system.friction
    P0 = np.asarray(system.normal.loads_at(0.0), dtype=float)
    Q0 = np.asarray(system.tangential(0.0), dtype=float)
    return np.linalg.solve(K - rf[:, None] * B, rf * P0 - Q0)


@dataclass(frozen=True)
class SteadyBranch:
    """One steady state reached (to ``tol`` in W, with one set of slipping nodes).

    Attributes
    ----------
    W : float
        Its dissipation per cycle (the mean over the starts that reached it).
    slipping : tuple of int
        The nodes that slip in the steady cycle.
    shakedown : bool
        No node slips (W = 0).
    start : int
        The index of a start that reaches it.
    count : int
        How many of the starts reach it.
    """

    W: float
    slipping: tuple
    shakedown: bool
    start: int
    count: int


@dataclass(frozen=True)
class StartStudy:
    """The steady states reached from a sample of starts (:func:`explore_starts`).

    The parameters are kept as the attributes of the same names.

    Parameters
    ----------
    starts : (k, n) ndarray
        The start displacements.
    ratios : (k, n) ndarray or None
        Their mobilization ratios, when sampled (None when the starts were given).
    W : (k,) ndarray
        The steady W from each start.
    slipping : (k, n) bool ndarray
        The nodes that slip in each steady cycle.
    cycles : (k,) ndarray
        Cycles to the steady state.
    remaining : (k,) ndarray
        Each result's bound on its remaining distance to the steady state (relative; 0 for a
        finite approach).
    branches : list of SteadyBranch
        The distinct steady states, by W.
    W_min, W_max : float
        The range of W.
    start_min, start_max : int
        Indices of starts that reach the ends of the range.
    rejected : int
        Sampled starts replaced because a normal reaction was not a compression.
    seconds : float
        Wall time.
    stats : dict, optional
        ``W_tol`` (the grouping tolerance), ``method``, ``seed``.

    Attributes
    ----------
    unique : bool
        One steady W from every start.
    shakedown_share : float
        The share of the starts that shake down.
    """

    starts: np.ndarray
    ratios: np.ndarray | None
    W: np.ndarray
    slipping: np.ndarray
    cycles: np.ndarray
    remaining: np.ndarray
    branches: list
    W_min: float
    W_max: float
    start_min: int
    start_max: int
    rejected: int
    seconds: float
    stats: dict = field(default_factory=dict)

    @property
    def unique(self) -> bool:
        """One steady W from every start (to the grouping tolerance)."""
        return len({b.W for b in self.branches}) == 1 or self.W_max - self.W_min <= self.stats.get(
            "W_tol", 0.0
        )

    @property
    def shakedown_share(self) -> float:
        """The share of the starts that shake down (no node slips in the steady cycle)."""
        return float(np.mean(~self.slipping.any(axis=1)))

    def as_dict(self) -> dict:
        """The study as a JSON-serializable dict.

        Returns
        -------
        dict
            ``W`` (per start), ``W_min``, ``W_max``, ``start_min``, ``start_max`` (the
            displacements), ``unique``, ``shakedown`` (the share), ``branches``, ``cycles``,
            ``rejected``, ``seconds``.
        """
        return dict(
            W=self.W.tolist(),
            W_min=self.W_min,
            W_max=self.W_max,
            start_min=self.starts[self.start_min].tolist(),
            start_max=self.starts[self.start_max].tolist(),
            unique=self.unique,
            shakedown=self.shakedown_share,
            branches=[
                dict(W=b.W, slipping=list(b.slipping), shakedown=b.shakedown, count=b.count)
                for b in self.branches
            ],
            cycles=self.cycles.tolist(),
            rejected=self.rejected,
            seconds=self.seconds,
        )


def explore_starts(
    system,
    starts=100,
    *,
    method: str = "exact",
    seed: int = 0,
    rtol: float = 1e-8,
    steps_per_cycle: int = 256,
    **options,
) -> StartStudy:
    """The steady states reached from many admissible starts.

    Parameters
    ----------
    system : ContactSystem
        A d = 1 system with a stiffness matrix, coupled (``coupling=B``) or not.
    starts : int or (k, n) array_like
        A number of random starts (mobilization ratios uniform in [-1, 1]^n, module
        docstring), or the start displacements themselves (each checked admissible).
    method : str
        The method of :func:`lcpfric.steady_state` (``"exact"``: the only one that solves
        coupled systems today).
    seed : int
        The random sample's seed.
    rtol : float
        Two steady states are one when their W agree to ``rtol`` of the largest W (and at least
        1e-12 of the force-displacement scale) and the same nodes slip.
    steps_per_cycle : int
        Samples of each steady cycle (W does not depend on it for ``exact``).
    **options
        Passed to :func:`lcpfric.steady_state`.

    Returns
    -------
    StartStudy
        W, slipping nodes and cycles per start; the distinct steady states; the range of W
        and the starts at its ends.

    Raises
    ------
    lcpfric.errors.InputError
        ``starts`` not a positive count or not k x n finite displacements, a given start
        that is not admissible (named by its row), or no admissible sample after 20 k draws.
    """
    from ..periodic.driver import steady_state
    from ..results import State

    t0 = time.perf_counter()
    rtol = _checks.positive("rtol", rtol)
    n = system.n
    rng = np.random.default_rng(seed)
    rejected, ratios = 0, None
    if np.ndim(starts) == 0:
        k = _checks.positive_int("starts", starts)
        P0 = np.asarray(system.normal.loads_at(0.0), dtype=float)
        B = system.coupling
        rows, rs = [], []
        for _ in range(20 * k):
            r = rng.uniform(-1.0, 1.0, n)
            u = start_from_ratios(system, r)
            if B is not None and np.any(P0 + B @ u <= 0):
                rejected += 1
                continue
            rows.append(u)
            rs.append(r)
            if len(rows) == k:
                break
        else:
            raise InputError(
                "starts",
                f"only {len(rows)} admissible starts in {20 * k} draws: the normal "
                "reactions at t = 0 are rarely all compressions; give the starts",
            )
        U, ratios = np.array(rows), np.array(rs)
    else:
        U = _checks.finite_array("starts", starts)
        if U.ndim != 2 or U.shape[1] != n or U.shape[0] == 0:
            raise InputError("starts", f"must be k x {n} start displacements, got {U.shape}")
    W = np.empty(len(U))
    slipping = np.zeros((len(U), n), dtype=bool)
    cycles = np.empty(len(U), dtype=int)
    remaining = np.zeros(len(U))
    for j, u in enumerate(U):
        try:
            res = steady_state(system, method, steps_per_cycle, u0=u, **options)
        except InputError as exc:
            if exc.parameter == "u0":
                raise InputError("starts", f"row {j}: {exc.detail}") from None
            raise
        W[j] = res.W
        slipping[j] = np.any(np.asarray(res.state) != State.STICK, axis=0).reshape(n, -1).any(1)
        cycles[j] = res.cycles
        remaining[j] = (res.solver_stats or {}).get("remaining", 0.0)
    scale = float(np.max(np.abs(W), initial=0.0))
    W_tol = max(rtol * scale, 1e-12 * _force_work(system))
    branches = _branches(W, slipping, W_tol)
    return StartStudy(
        starts=U,
        ratios=ratios,
        W=W,
        slipping=slipping,
        cycles=cycles,
        remaining=remaining,
        branches=branches,
        W_min=float(W.min()),
        W_max=float(W.max()),
        start_min=int(np.argmin(W)),
        start_max=int(np.argmax(W)),
        rejected=rejected,
        seconds=time.perf_counter() - t0,
        stats=dict(W_tol=W_tol, method=method, seed=seed),
    )


def _force_work(system) -> float:
    """A work scale: the largest friction limit squared over the smallest stiffness."""
    P = np.asarray(
        [p.mean + sum(map(abs, getattr(p, "amplitudes", ()))) for p in system.normal.loads]
    )
    K = system.dense_stiffness()
    return float(np.max(system.friction * np.abs(P)) ** 2 / np.min(np.diag(K)))


def _branches(W, slipping, W_tol) -> list:
    """The distinct steady states: same slipping nodes and W within W_tol (single linkage in
    W order)."""
    out = []
    keys = {}
    for j in np.argsort(W, kind="stable"):
        key = tuple(np.nonzero(slipping[j])[0].tolist())
        keys.setdefault(key, []).append(j)
    for key, idx in keys.items():
        group = [idx[0]]
        for j in idx[1:]:
            if W[j] - W[group[-1]] <= W_tol:
                group.append(j)
                continue
            out.append(_branch(W, key, group))
            group = [j]
        out.append(_branch(W, key, group))
    return sorted(out, key=lambda b: b.W)


def _branch(W, key, group) -> SteadyBranch:
    return SteadyBranch(
        W=float(np.mean(W[group])),
        slipping=key,
        shakedown=not key,
        start=int(group[0]),
        count=len(group),
    )


def start_map(system, points: int = 41, **options):
    """The steady W over the square of the mobilization ratios of a two-node system's starts.

    Parameters
    ----------
    system : ContactSystem
        A d = 1 system of two nodes.
    points : int
        Ratios per axis (>= 2), equally spaced in [-1, 1].
    **options
        Passed to :func:`lcpfric.steady_state`.

    Returns
    -------
    r : (points,) ndarray
        The ratios of each axis.
    W : (points, points) ndarray
        ``W[i, j]``: the steady W from the start with ratios ``(r[j], r[i])``; NaN where the
        start is not admissible (a normal reaction that is not a compression).
    shakedown : (points, points) bool ndarray
        No node slips in the steady cycle.
    """
    from ..periodic.driver import steady_state
    from ..results import State

    if system.n != 2:
        raise InputError("system", f"a start map needs a two-node system, got {system.n} nodes")
    points = _checks.positive_int("points", points, 2)
    r = np.linspace(-1.0, 1.0, points)
    W = np.full((points, points), np.nan)
    still = np.zeros((points, points), dtype=bool)
    P0 = np.asarray(system.normal.loads_at(0.0), dtype=float)
    B = system.coupling if system.coupling is not None else np.zeros((2, 2))
    for i, r2 in enumerate(r):
        for j, r1 in enumerate(r):
            u = start_from_ratios(system, [r1, r2])
            if np.any(P0 + B @ u <= 0):
                continue
            res = steady_state(system, "exact", options.pop("steps_per_cycle", 64), u0=u, **options)
            W[i, j] = res.W
            still[i, j] = not np.any(np.asarray(res.state) != State.STICK)
    return r, W, still


def coupling_band(system, scales, starts: int = 60, seed: int = 0):
    """The range of steady W over random starts as the coupling block is scaled.

    Parameters
    ----------
    system : ContactSystem
        A coupled d = 1 system (its block B is scaled).
    scales : array_like
        Factors c >= 0 of the block (``B -> c B``; c = 0: the uncoupled system).
    starts : int
        Random starts per factor.
    seed : int
        Their seed.

    Returns
    -------
    W_min, W_max, shakedown : (len(scales),) ndarrays
        The range of W and the share of the starts that shake down, per factor.
    """
    from ..model import ContactSystem

    if system.coupling is None:
        raise InputError("system", "needs a coupled system (a coupling block B)")
    scales = _checks.finite_array("scales", scales).ravel()
    if np.any(scales < 0):
        raise InputError("scales", "must be >= 0")
    out = np.empty((3, scales.size))
    for k, c in enumerate(scales):
        s = ContactSystem(
            system.stiffness, system.friction, system.tangential_loads, system.normal,
            coupling=c * system.coupling,
        )  # fmt: skip
        study = explore_starts(s, starts, seed=seed)
        out[:, k] = study.W_min, study.W_max, study.shakedown_share
    return out[0], out[1], out[2]
