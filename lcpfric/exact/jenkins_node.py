"""The steady cycle of a harmonically driven Jenkins element through the exact single node.

A Jenkins element under ``x = x0 + a cos ωt`` with the normal load ``N0 + N1 cos(ωt + φ)`` is the
paper's single node (:meth:`~lcpfric.model.jenkins.JenkinsElement.single_node`: ``k11 = kt``,
``f = μ``, ``Q = -kt x``, ``v = w``, ``F = -T``), so :func:`lcpfric.exact.exact_cycle` gives its
steady cycle in closed form, segment by segment, and :func:`lcpfric.exact.exact_W_hat` its W for
many amplitudes at once. Here the node's segments (in its angle ``ωt + ψ_P``, its slider in units
of ``f P0 / k11``) are turned into the element's, and :func:`.driven_result.assemble` integrates
the force over them.

Where the node slips or separates its steady cycle does not depend on the start (every history
passes through one point of the orbit: :mod:`lcpfric.exact`). Where it shakes down (nothing slips
over the steady cycle) the slider stays wherever the start's first cycle left it: that is
``lcpfric.steady_state(node, "exact", u0=...)`` (its solver, :class:`~lcpfric.exact.solver.
ExactSolver`, called here), the exact node followed event by event from the start.
"""

from __future__ import annotations

import math
import time

from .. import _checks
from ..errors import InputError
from ..model.jenkins import JenkinsElement
from ..results import State
from .api import exact_cycle
from .driven_result import DrivenCycle, Functions, assemble
from .solver import ExactSolver
from .trig import TWO_PI, TrigPoly

__all__ = ["jenkins_cycle", "node_start"]


def node_start(element: JenkinsElement, node, fns: Functions, start: float | None, x0: float):
    """The node's start ``u0`` (its system's units, f P0 / k11 with Q0 taken out) for the
    slider's start at t = 0, first pushed into the interval the friction law allows.

    Parameters
    ----------
    element : JenkinsElement
        The element.
    node : SingleNode
        Its node (:meth:`~lcpfric.model.jenkins.JenkinsElement.single_node`).
    fns : Functions
        The element's functions of θ.
    start : float or None
        The slider at t = 0 (None: the motion's mean ``x0``).
    x0 : float
        The motion's mean.

    Returns
    -------
    float
        u0.
    """
    w = x0 if start is None else float(start)
    w = min(max(w, fns.lo(0.0)), fns.hi(0.0))
    return (w - x0) / node.displacement_unit


def jenkins_cycle(
    element: JenkinsElement,
    amplitude: float,
    *,
    omega: float = 1.0,
    x0: float = 0.0,
    start: float | None = None,
    harmonics: int = 1,
    samples: int = 256,
    extrema=None,
) -> DrivenCycle:
    """The exact steady cycle of a Jenkins element under ``x = x0 + a cos ωt``, through the exact
    single node.

    Parameters
    ----------
    element : JenkinsElement
        The element (its harmonic normal side: ``N0 + N1 cos(ωt + φ)``, clipped at zero), with
        μ > 0.
    amplitude : float
        The motion's amplitude a, > 0.
    omega : float, optional
        ω > 0.
    x0 : float, optional
        The motion's mean.
    start : float, optional
        The slider at t = 0 (default ``x0``), pushed into the allowed interval first; it
        matters only where the element shakes down.
    harmonics : int, optional
        The highest harmonic of T computed, >= 1.
    samples : int, optional
        Equally spaced samples of the series (the events are added), >= 4.
    extrema : tuple of ndarray, optional
        Where x and N have their extrema over the period (angles ωt in [0, 2π)), when the
        caller has them (the same for every amplitude): default, found here.

    Returns
    -------
    DrivenCycle
        The steady cycle (``method="single-node"``); W is the exact node's.

    Raises
    ------
    InputError
        A parameter out of range (the element's checks name it), or mu = 0.
    """
    started = time.perf_counter()
    if not isinstance(element, JenkinsElement):
        raise InputError("element", f"must be a JenkinsElement, got {type(element).__name__}")
    harmonics = _checks.positive_int("harmonics", harmonics)
    samples = _checks.positive_int("samples", samples, 4)
    start = None if start is None else _checks.finite("start", start)
    node = element.single_node(amplitude, omega, x0)
    x = element.motion(amplitude, omega, x0)
    fns = Functions(
        element.kt,
        element.mu,
        TrigPoly.from_load(x, x.omega),
        TrigPoly.from_load(node.normal_load, x.omega),
        extrema,
    )
    cyc = exact_cycle(*node.normalized_parameters())
    unit, shift = node.displacement_unit, node.normal_load.phase
    stuck = all(s[2] == State.STICK for s in cyc.segments)
    cycles = 1
    if stuck:  # shakedown: where the start leaves the slider (the exact node from the start)
        u0 = [node_start(element, node, fns, start, x0)]
        res = ExactSolver().steady_state(node, 4, u0=u0)
        segs = [(0.0, TWO_PI, int(State.STICK), float(res.v[0]))]
        cycles = int(res.cycles)
    else:
        segs = _rotated([(a - shift, b - shift, s, unit * w + x0) for a, b, s, w in cyc.segments])
    return assemble(
        fns,
        x.omega,
        segs,
        harmonics=harmonics,
        samples=samples,
        cycles=cycles,
        converged=True,
        change=0.0,
        method="single-node",
        started=started,
        W=float(node.W(cyc.W_hat)),
    )


def _rotated(segments):
    """Segments covering one period from anywhere, as contiguous segments covering ``[0, 2π]``
    in order (zero-length ones dropped; the ends made to meet, across round-off at the wrap)."""
    segments = [seg for seg in segments if seg[1] > seg[0]]
    base = TWO_PI * math.floor(segments[0][0] / TWO_PI)
    out = []
    for a, b, s, w in segments:
        a, b = a - base, b - base
        if b <= TWO_PI:
            out.append((a, b, s, w))
        elif a >= TWO_PI:
            out.append((a - TWO_PI, b - TWO_PI, s, w))
        else:
            out += [(a, TWO_PI, s, w), (0.0, b - TWO_PI, s, w)]
    out.sort(key=lambda seg: (seg[0], seg[1]))
    starts = [0.0] + [seg[0] for seg in out[1:]]
    ends = starts[1:] + [TWO_PI]
    return [(a, b, s, w) for a, b, (_, _, s, w) in zip(starts, ends, out) if b > a]
