r"""Dissipation maps of the Hertz contact: by MDR (many load cases advanced together) and by
the half-space boundary elements (:func:`halfspace_W_normalized`, point by point, the normal
problem shared by the points of one P̂1).

:func:`mdr_W_normalized` evaluates ``W k_t0 / (μ² P0²)`` of the MDR sphere
(:class:`~lcpfric.model.continuum.mdr.MDRSphere`) at many points ``(P̂1, Q̂1, φ)`` = ``(P1/P0,
Q1/(μ P0), φ)`` at once, for :func:`lcpfric.analysis.sweep.sweep` (local processes or Dask,
resumable). In these units the answer depends on nothing else: with ``P0 = μ = k_t0 = 1`` and
lengths in units of a0 = a(P0), the spring normal forces are ``N_i = (3/2) ∫_cell (a² - x²) dx``
with ``a = P^(1/3)``, the spring stiffnesses ``k_i = Δx`` (so ``Σ k_i = 1`` at a0), and the
support stiffness is given as ``k_support_ratio`` = k_support / k_t0.

Each increment is the MDR increment (:func:`~lcpfric.steppers.mdr_bar.bar_increment`, the one
the ``mdr-bar`` stepper uses), here for all points together, and the cycles are the batched
cycle loop's (:func:`lcpfric.periodic.batched.run`). The result equals
``steady_state(MDRSphere(...))`` on the same grid to round-off (``tests/test_contact_maps.py``).
Under pure load control (``k_support_ratio = 0``) a point whose loads have ``|Q| > μ P`` at some
instant has no equilibrium: its value is NaN. A point that reaches no steady state in
``max_cycles`` is NaN too, and counted in a :class:`~lcpfric.errors.ConvergenceWarning`
(``on_nonconvergence="warn"``, the default here) or raised as an error (``"raise"``).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from .. import _checks
from ..errors import ConvergenceError, ConvergenceWarning, InputError
from ..periodic import batched
from ..steppers.dissipation import node_shares
from ..model.continuum.mdr import MIN_NODES
from ..steppers.mdr_bar import bar_increment

__all__ = [
    "mdr_W_normalized",
    "halfspace_W_normalized",
    "gross_sliding_points",
    "map_spec",
    "unconverged_points",
    "CONTACT_DEFAULTS",
    "HALFSPACE_DEFAULTS",
]

_SAMPLES = 20001


def gross_sliding_points(P1, Q1, phi, reach: bool = False) -> np.ndarray:
    """Which points have ``|Q̂1 sin(θ + φ)| > 1 + P̂1 sin θ`` at some θ (normalized units);
    with ``reach``, those where it reaches it (to 1e-9: d = 2, where the body then drifts
    across the load, :func:`~lcpfric.model.continuum.base.gross_sliding`)."""
    theta = np.linspace(0.0, 2 * math.pi, _SAMPLES)
    out = np.zeros(np.shape(P1), dtype=bool)
    for i in range(0, out.size, 256):
        sl = slice(i, min(i + 256, out.size))
        P = 1.0 + P1[sl, None] * np.sin(theta)
        Q = np.abs(Q1[sl, None] * np.sin(theta + phi[sl, None]))
        margin = -1e-9 if reach else 1e-12 * (1.0 + Q)
        out[sl] = np.any(Q > np.maximum(P, 0.0) + margin, axis=1)
    return out


def _points(P1, Q1, phi, steps_per_cycle, k_support_ratio, reach=False):
    """The points as flat arrays, the checked steps and support, the output (NaN where pure
    load control has no equilibrium, 0 where Q̂1 = 0) and the points left to compute."""
    P1, Q1, phi = (np.atleast_1d(np.asarray(x, dtype=float)).ravel() for x in (P1, Q1, phi))
    steps = _checks.positive_int("steps_per_cycle", steps_per_cycle, 4)
    ks = _checks.nonnegative("k_support_ratio", k_support_ratio)
    if not (P1.size == Q1.size == phi.size):
        raise InputError("P1", "P1, Q1 and phi must have one value per point")
    out = np.zeros(P1.size)
    run = Q1 > 0
    if ks == 0.0:
        bad = gross_sliding_points(P1, Q1, phi, reach)
        out[bad] = np.nan
        run &= ~bad
    return P1, Q1, phi, steps, ks, out, run


def mdr_W_normalized(
    P1,
    Q1,
    phi,
    *,
    nodes: int = 200,
    steps_per_cycle: int = 200,
    k_support_ratio: float = 0.0,
    tol: float = 1e-8,
    max_cycles: int = 200,
    on_nonconvergence: str = "warn",
):
    """``W k_t0 / (μ² P0²)`` of the MDR sphere at the points ``(P1, Q1, phi)`` (flat arrays of
    P̂1, Q̂1 and φ); ``k_support_ratio`` in units of k_t0. NaN where pure load control has no
    equilibrium, and where a point reaches no steady state in ``max_cycles`` (module
    docstring); 0 where Q̂1 = 0."""
    nodes = _checks.positive_int("nodes", nodes, MIN_NODES)
    tol, max_cycles, on_nonconvergence = _checks.driver_options(tol, max_cycles, on_nonconvergence)
    P1, Q1, phi, steps, ks, out, run = _points(P1, Q1, phi, steps_per_cycle, k_support_ratio)
    idx = np.flatnonzero(run)
    if idx.size:
        points = _MDRPoints(P1[idx], Q1[idx], phi[idx], nodes, steps, ks)
        res = batched.run(
            points,
            tol=tol,
            max_cycles=max_cycles,
            on_nonconvergence="ignore",
            measure="map",
            quantity="W_normalized",
            values=lambda W: W,
            method="mdr-bar",
            steps_requested=steps,
        )
        out[idx] = res.values
        late = ~res.converged
        _unconverged(
            "",
            int(late.sum()),
            P1.size,
            max_cycles,
            float(np.max(res.change[late], initial=0.0)),
            tol,
            on_nonconvergence,
        )
    return out


def _unconverged(what, failed, total, max_cycles, worst, tol, on_nonconvergence) -> None:
    """Report a map's points that reached no steady state (their values are NaN)."""
    if not failed:
        return
    msg = (
        f"{failed} of {total} {what}points reached no periodic steady state in "
        f"{max_cycles} cycles (largest relative change {worst:.3g} > tol {tol:g}; their "
        f"values are NaN); raise max_cycles or loosen tol"
    )
    if on_nonconvergence == "raise":
        raise ConvergenceError(msg)
    if on_nonconvergence == "warn":
        warnings.warn(msg, ConvergenceWarning, stacklevel=3)


class _MDRPoints:
    """The MDR spheres of many points as a batched stepper (:mod:`lcpfric.periodic.batched`),
    in the map's units (module docstring)."""

    def __init__(self, P1, Q1, phi, n, steps, ks):
        m = P1.size
        self.size, self.steps, self.ks, self.n = m, steps, ks, n
        self.P1, self.Q1 = P1, Q1
        a_max = (1.0 + P1) ** (1.0 / 3.0)  # (m,)
        dx = a_max / n
        x = (np.arange(n)[None, :] + 0.5) * dx[:, None]  # (m, n)
        self.k = dx[:, None] * np.ones((1, n))
        theta = np.linspace(0.0, 2 * math.pi, steps + 1)
        P = np.maximum(1.0 + P1[:, None] * np.sin(theta)[None, :], 0.0)  # (m, steps + 1)
        self.Q = Q1[:, None] * np.sin(theta[None, :] + phi[:, None])
        self.a = P ** (1.0 / 3.0)
        self.lo_x, self.hi_x = x - 0.5 * dx[:, None], x + 0.5 * dx[:, None]
        self.lo_cube = self.lo_x * self.lo_x * self.lo_x / 3.0

    def limits(self, j):
        """(3/2) ∫ (a² - x²) dx over each cell's part inside the contact (powers by products:
        ``**`` is several times slower)."""
        aj = self.a[:, j][:, None]
        hi = np.minimum(self.hi_x, aj)
        val = aj * aj * (hi - self.lo_x) - (hi * hi * hi / 3.0 - self.lo_cube)
        return np.where(hi > self.lo_x, 1.5 * val, 0.0)

    def init(self):
        m, n = self.size, self.n
        return np.zeros((m, n)), np.zeros(m), np.zeros((m, n))

    def step(self, j, state):
        v, u, F = state
        u1, F1, v1 = bar_increment(v, u, self.k, self.limits(j + 1), self.Q[:, j + 1], self.ks)
        return (v1, u1, F1), node_shares(F, F1, v1 - v).sum(axis=1)

    def unknowns(self, state):
        return state[0]

    def scales(self):
        return self.Q1, 1.0 + self.P1


def halfspace_W_normalized(
    P1,
    Q1,
    phi,
    *,
    grid: int = 20,
    dims: int = 1,
    nu: float = 0.0,
    steps_per_cycle: int = 100,
    k_support_ratio: float = 0.0,
    tol: float = 1e-8,
    max_cycles: int = 200,
    on_nonconvergence: str = "warn",
):
    """``W k_t0 / (μ² P0²)`` of the sphere on the half-space
    (:class:`~lcpfric.model.continuum.halfspace.HalfSpace`) at the points ``(P1, Q1, phi)``
    (flat arrays of P̂1, Q̂1, φ), ``grid`` elements across the largest contact, ``k_support_ratio``
    in units of k_t0. The points of one P̂1 share one scene, so the normal problem of each
    instant is solved once (:func:`lcpfric.scene.with_tangential_load`). NaN where pure load
    control has no equilibrium (with d = 2, also where |Q| reaches μP: the body drifts across
    the load), and where a point reaches no steady state in ``max_cycles`` (counted in a
    warning, or an error with ``on_nonconvergence="raise"``); 0 where Q̂1 = 0."""
    from ..errors import InputError as _Input
    from ..model.continuum.halfspace import HalfSpace
    from ..model.loads import Harmonic
    from ..periodic import steady_state
    from ..scene import make_scene, with_tangential_load

    tol, max_cycles, on_nonconvergence = _checks.driver_options(tol, max_cycles, on_nonconvergence)
    P1, Q1, phi, steps, ks, out, run = _points(
        P1, Q1, phi, steps_per_cycle, k_support_ratio, reach=dims == 2
    )
    two_pi = 2.0 * math.pi
    failed, worst = 0, 0.0
    for p1 in np.unique(P1[run]):
        idx = np.flatnonzero(run & (P1 == p1))
        # P0 = μ = 1, R = E = 1: W k_t0 / (μ² P0²) does not depend on them
        model = HalfSpace.sphere(
            1.0, 1.0, nu, 1.0, Harmonic(1.0, p1, 0.0, two_pi), 0.0, grid=grid, dims=dims
        )
        model = model.with_support(ks * model.k_t0)
        scene = make_scene(model, steps)
        for i in idx:
            try:
                point = with_tangential_load(
                    scene, Harmonic(0.0, float(Q1[i]), float(phi[i]), two_pi)
                )
            except _Input:  # |Q| > μP on the grid's own instants: no equilibrium
                out[i] = np.nan
                continue
            r = steady_state(
                point, "newton-cg", tol=tol, max_cycles=max_cycles, on_nonconvergence="ignore"
            )
            if r.converged:
                out[i] = r.W_normalized
            else:
                out[i] = np.nan
                failed += 1
                worst = max(worst, r.change)
    _unconverged("half-space map ", failed, P1.size, max_cycles, worst, tol, on_nonconvergence)
    return out


#: a continuum contact's map options and defaults (``sweep(..., contact=)``), per model
CONTACT_DEFAULTS = {
    "geometry": "sphere",
    "model": "mdr",
    "nodes": 200,
    "k_support_ratio": 0.0,
    "tol": 1e-8,
    "max_cycles": 200,
}
HALFSPACE_DEFAULTS = {
    "geometry": "sphere",
    "model": "halfspace",
    "grid": 20,
    "dims": 1,
    "nu": 0.0,
    "k_support_ratio": 0.0,
    "tol": 1e-8,
    "max_cycles": 200,
}
#: each map model's model class (the registry's ``models``: the methods that solve it)
MODEL_CLASSES = {"mdr": "MDRSphere", "halfspace": "HalfSpace"}
_CONTACT_STEPS = 200
_HALFSPACE_STEPS = 100


def map_spec(contact, steps_per_cycle, method=None):
    """``(function, options, seconds per point, method)`` of a contact map (``contact``: a dict
    of :data:`CONTACT_DEFAULTS` keys, or of :data:`HALFSPACE_DEFAULTS` keys with ``"model":
    "halfspace"``; ``method``: a registry name that solves the model, by default its own)."""
    from ..methods import get_method

    if not isinstance(contact, dict):
        raise InputError(
            "contact", f"must be a dict of {sorted(CONTACT_DEFAULTS)}, got {type(contact).__name__}"
        )
    model = contact.get("model", "mdr")
    if model not in MODEL_CLASSES:
        raise InputError("contact", f"model must be 'mdr' or 'halfspace', got {model!r}")
    defaults = CONTACT_DEFAULTS if model == "mdr" else HALFSPACE_DEFAULTS
    if "k_support" in contact:
        raise InputError(
            "contact",
            "the key 'k_support' is 'k_support_ratio' in a map: the support stiffness as a "
            "multiple of k_t0 (the models' k_support is absolute)",
        )
    unknown = sorted(set(contact) - set(defaults))
    if unknown:
        raise InputError(
            "contact", f"unknown key {unknown[0]!r}; keys: {', '.join(sorted(defaults))}"
        )
    spec = {**defaults, **contact}
    if spec["geometry"] != "sphere":
        raise InputError(
            "contact", f"maps are available for the sphere, got geometry {spec['geometry']!r}"
        )
    own = "mdr-bar" if model == "mdr" else "newton-cg"
    if method is not None:
        entry, _ = get_method(method)
        if MODEL_CLASSES[model] not in entry.models:
            raise InputError(
                "method",
                f"{entry.name!r} does not solve the {model} model's "
                f"{MODEL_CLASSES[model]}; its map uses {own!r}",
            )
    if model == "halfspace":
        steps = _checks.positive_int("steps_per_cycle", steps_per_cycle or _HALFSPACE_STEPS, 4)
        from ..model.continuum.halfspace import MIN_ACROSS

        grid = _checks.positive_int("grid", spec["grid"], MIN_ACROSS)
        if str(spec["dims"]) not in ("1", "2"):
            raise InputError("dims", f"must be 1 or 2, got {spec['dims']!r}")
        nu = _checks.finite("nu", spec["nu"])
        if not 0.0 <= nu < 0.5:
            raise InputError("nu", f"Poisson's ratio must be in [0, 0.5), got {nu:g}")
        options = {
            "grid": grid,
            "dims": int(spec["dims"]),
            "nu": nu,
            "k_support_ratio": _checks.nonnegative("k_support_ratio", spec["k_support_ratio"]),
            "tol": _checks.positive("tol", spec["tol"]),
            "steps_per_cycle": steps,
            "max_cycles": _checks.positive_int("max_cycles", spec["max_cycles"]),
            "on_nonconvergence": "ignore",
        }
        # measured: about 35 ns per grid node, step and cycle at d = 1 (three cycles)
        return (
            halfspace_W_normalized,
            options,
            1.1e-7 * 1.8 * grid * grid * steps * (3 if options["dims"] == 2 else 1),
            own,
        )
    steps = _checks.positive_int("steps_per_cycle", steps_per_cycle or _CONTACT_STEPS, 4)
    options = {
        "nodes": _checks.positive_int("nodes", spec["nodes"], MIN_NODES),
        "k_support_ratio": _checks.nonnegative("k_support_ratio", spec["k_support_ratio"]),
        "tol": _checks.positive("tol", spec["tol"]),
        "steps_per_cycle": steps,
        "max_cycles": _checks.positive_int("max_cycles", spec["max_cycles"]),
        "on_nonconvergence": "ignore",
    }
    # measured: about 60 ns per node, step and cycle, four cycles
    return mdr_W_normalized, options, 2.4e-7 * options["nodes"] * steps, own


def map_bytes(options, points: int, in_flight: int, workers: int, axes: int) -> float:
    """Estimated peak bytes of a contact map: its values, and the MDR batch of the points in
    flight (the springs' states and the loads at every instant) or one half-space model per
    worker."""
    work = (
        8.0 * (24 * options["nodes"] + 3 * (options["steps_per_cycle"] + 1)) * in_flight
        if "nodes" in options
        else 8.0 * 40 * 1.2 * options["grid"] ** 2 * options["steps_per_cycle"] * workers
    )
    return 8.0 * (4 * points + axes) + work


def memory_parameter(options) -> str:
    """The parameter to name when a contact map's work does not fit in memory: the steps per
    cycle when they weigh more than the model's size, else the model's size (``nodes`` or
    ``grid``)."""
    if "nodes" in options:
        heavier = 3 * options["steps_per_cycle"] > 24 * options["nodes"]
        return "steps_per_cycle" if heavier else "nodes"
    heavier = options["steps_per_cycle"] > _HALFSPACE_STEPS
    return "steps_per_cycle" if heavier else "grid"


def unconverged_points(values, P1, Q1, phi, k_support_ratio: float, dims: int = 1) -> int:
    """How many NaN values of a contact map are points that reached no steady state, not loads
    without equilibrium (flat arrays of the points' values and coordinates)."""
    values, P1, Q1, phi = (np.asarray(x, dtype=float).ravel() for x in (values, P1, Q1, phi))
    nan = np.isnan(values) & (Q1 > 0)
    if k_support_ratio == 0.0 and nan.any():
        idx = np.flatnonzero(nan)
        nan[idx[gross_sliding_points(P1[idx], Q1[idx], phi[idx], dims == 2)]] = False
    return int(np.count_nonzero(nan))
