"""The public entries: :func:`exact_W_hat` (any shape, validated) and :func:`exact_cycle` (one
point, with its segments)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .formulas import BACKWARD, FORWARD, MAX_AMPLITUDE, SEPARATION, STICK, TWO_PI
from .scalar import run_scalar
from .vectorized import run_vectorized
from dataclasses import dataclass

from .. import _checks
from ..errors import InputError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


# -- public entry points ------------------------------------------------------------------------

_FAST_TYPES = frozenset((float, int, np.float64, np.int64))  # not bool (a subclass of int)
_INF = math.inf


def _validated(P1, Q1, phi):
    """The checked, flattened inputs: (P̂1, Q̂1, φ reduced to [0, 2π), sin φ, cos φ, shape)."""
    P1 = _checks.finite_array("P1", P1, nonneg=True, upper=MAX_AMPLITUDE)
    Q1 = _checks.finite_array("Q1", Q1, nonneg=True, upper=MAX_AMPLITUDE)
    phi = _checks.finite_array("phi", phi)
    try:
        P1, Q1, phi = np.broadcast_arrays(P1, Q1, phi)
    except ValueError:
        raise InputError(
            "P1, Q1, phi",
            f"shapes {P1.shape}, {Q1.shape} and {phi.shape} do not broadcast together",
        ) from None
    shape = P1.shape
    phi = phi.ravel()
    # sin and cos of the caller's φ are exact to round-off for any φ; φ reduced through them
    # stays consistent with them (φ mod the double 2π would drift by 2.4e-16 per turn)
    sphi, cphi = np.sin(phi), np.cos(phi)
    return (
        P1.ravel().astype(float),
        Q1.ravel().astype(float),
        np.mod(np.arctan2(sphi, cphi), TWO_PI),
        sphi,
        cphi,
        shape,
    )


def _scalar_error(P1, Q1, phi):
    """Raise the InputError, naming the parameter, for scalars the fast path refused."""
    _checks.amplitude("P1", P1, MAX_AMPLITUDE)
    _checks.amplitude("Q1", Q1, MAX_AMPLITUDE)
    _checks.finite("phi", phi)
    raise AssertionError("unreachable: the fast path refused valid input")  # pragma: no cover


def exact_W_hat(P1: ArrayLike, Q1: ArrayLike, phi: ArrayLike) -> float | np.ndarray:
    """Exact steady-state Ŵ for arrays of (P̂1, Q̂1, φ), broadcast together.

    The single node's periodic orbit is entered in one step and its events computed in closed
    form, all points of a grid together (see :mod:`lcpfric.exact`).

    Parameters
    ----------
    P1, Q1 : float or array_like
        P̂1 and Q̂1, in ``[0, MAX_AMPLITUDE]`` (1e300). Q̂1 = 0 gives the limit Ŵ = 0.
    phi : float or array_like
        φ in radians, any finite value.

    Returns
    -------
    float or ndarray
        Ŵ >= 0, the dissipation per cycle in the units of Eq. (6): a float for scalar input,
        else an array of the broadcast shape.

    Raises
    ------
    lcpfric.errors.InputError
        Naming the parameter, for anything else: NaN, inf, negative amplitudes, amplitudes
        over :data:`~lcpfric.exact.MAX_AMPLITUDE`, strings, booleans; or shapes that do not
        broadcast together.

    Notes
    -----
    Accuracy: within 1e-9 relative of the exact Ŵ, however small Ŵ is (worst 1.5e-12 measured
    over 20000 points from 1e-20 to 1e20, see the module docstring), except where Ŵ itself is
    ill-conditioned: next to the border of a zero régime (shakedown, or Q̂1 = P̂1 at φ = 0 or π),
    or next to P̂1 = 1 with small Q̂1. There the error is within the change of the exact Ŵ when
    the inputs move by 16 units of round-off.

    Examples
    --------
    >>> from lcpfric.exact import exact_W_hat
    >>> round(exact_W_hat(0.5, 2.0, 0.0), 12)
    1.866666666667
    >>> exact_W_hat([0.5, 0.5], 0.0, 0.0).tolist()
    [0.0, 0.0]
    """
    if type(P1) in _FAST_TYPES and type(Q1) in _FAST_TYPES and type(phi) in _FAST_TYPES:
        try:
            p, q, f = float(P1), float(Q1), float(phi)
        except OverflowError:  # an int beyond the double range
            _scalar_error(P1, Q1, phi)
        # one comparison chain rejects NaN, inf, negatives and the too large
        if not (0.0 <= p <= MAX_AMPLITUDE and 0.0 <= q <= MAX_AMPLITUDE and -_INF < f < _INF):
            _scalar_error(P1, Q1, phi)
        if q == 0.0:
            return 0.0
        sf, cf = math.sin(f), math.cos(f)
        W = run_scalar(p, q, math.atan2(sf, cf) % TWO_PI, sf, cf, False)[0]
        return W if W > 0.0 else 0.0
    p, q, f, sf, cf, shape = _validated(P1, Q1, phi)
    W = np.zeros(p.shape)
    pos = q > 0.0
    if pos.all():
        W = run_vectorized(p, q, f, sf, cf)
    elif pos.any():
        W[pos] = run_vectorized(p[pos], q[pos], f[pos], sf[pos], cf[pos])
    W = np.maximum(W, 0.0)  # Ŵ >= 0 analytically; clip round-off of exact-zero cycles
    W = W.reshape(shape)
    return W if W.ndim else float(W)


@dataclass(frozen=True)
class ExactCycle:
    """The exact steady cycle of one point, as segments in θ = ωt.

    Made by :func:`exact_cycle`, which checks the inputs; the constructor does not.

    Parameters
    ----------
    P1, Q1 : float
        P̂1 and Q̂1.
    phi : float
        φ, reduced to ``[0, 2π)``.
    W_hat : float
        Ŵ, the dissipation per cycle (>= 0).
    segments : tuple
        The segments of the cycle in order, each ``(theta_start, theta_end, state,
        w_start)``: the angles (rad) where it starts and ends, the node's state
        (:data:`~lcpfric.exact.STICK`, :data:`~lcpfric.exact.FORWARD`,
        :data:`~lcpfric.exact.BACKWARD`, :data:`~lcpfric.exact.SEPARATION`) and w at its
        start (NaN for a separation). Together they cover one period.

    Attributes
    ----------
    P1, Q1, phi, W_hat, segments
        The parameters, as given.
    """

    P1: float
    Q1: float
    phi: float
    W_hat: float
    segments: tuple

    def __post_init__(self):
        arr = np.array([s[:3] for s in self.segments], dtype=float)
        object.__setattr__(self, "_starts", arr[:, 0])
        object.__setattr__(self, "_states", arr[:, 2].astype(np.int8))
        object.__setattr__(self, "_w0", np.array([s[3] for s in self.segments]))

    def _locate(self, theta):
        x = self._starts[0] + np.mod(np.asarray(theta, dtype=float) - self._starts[0], TWO_PI)
        idx = np.clip(np.searchsorted(self._starts, x, side="right") - 1, 0, self._starts.size - 1)
        return x, idx

    def state(self, theta: ArrayLike) -> np.ndarray | np.int8:
        """The state (STICK, FORWARD, BACKWARD, SEPARATION) at the angles ``theta``.

        Parameters
        ----------
        theta : float or array_like
            Angles θ = ωt in radians, any real values (the cycle repeats with period 2π).

        Returns
        -------
        ndarray of int8, or numpy.int8
            The states, in the shape of ``theta`` (a numpy scalar for a scalar); at a
            segment's start angle, that segment's state.
        """
        return self._states[self._locate(theta)[1]]

    def w(self, theta: ArrayLike) -> np.ndarray:
        """The tangential displacement ``w = F̂ - Q̂ = Q̂1 v̂`` at the angles ``theta``.

        Parameters
        ----------
        theta : float or array_like
            Angles θ = ωt in radians, any real values (the cycle repeats with period 2π).

        Returns
        -------
        ndarray
            The values of w, in the shape of ``theta`` (a 0-d array for a scalar): constant while
            the node sticks, ``∓L - Q̂`` while it slips forward / backward, ``-Q̂`` while separated.
        """
        x, idx = self._locate(theta)
        st = self._states[idx]
        L = np.maximum(1.0 + self.P1 * np.sin(x), 0.0)
        Qh = self.Q1 * np.sin(x + self.phi)
        out = self._w0[idx].copy()
        out = np.where(st == FORWARD, -L - Qh, out)
        out = np.where(st == BACKWARD, L - Qh, out)
        return np.where(st == SEPARATION, -Qh, out)


def exact_cycle(P1: float, Q1: float, phi: float) -> ExactCycle:
    """The exact steady cycle of one point, with its segments (for time series and plots).

    Inputs are checked as in :func:`exact_W_hat`; one point only.

    Parameters
    ----------
    P1, Q1 : float
        P̂1 and Q̂1, in ``[0, MAX_AMPLITUDE]`` (1e300). With Q̂1 = 0 nothing slips and w stays
        at 0.
    phi : float
        φ in radians, any finite value.

    Returns
    -------
    ExactCycle
        The cycle: Ŵ (as :func:`exact_W_hat`) and its segments.

    Raises
    ------
    lcpfric.errors.InputError
        An input :func:`exact_W_hat` refuses, or arrays of more than one point.

    Examples
    --------
    >>> from lcpfric.exact import exact_cycle
    >>> cyc = exact_cycle(0.5, 2.0, 0.0)
    >>> round(cyc.W_hat, 12)
    1.866666666667
    >>> cyc.state([0.0, 3.0, 4.0]).tolist()  # backward slip, stick, forward slip
    [2, 0, 1]
    """
    p, q, f, sf, cf, _ = _validated(P1, Q1, phi)
    if p.size != 1:
        raise InputError("P1", "exact_cycle takes one point (scalars); use exact_W_hat for arrays")
    p, q, f, sf, cf = float(p[0]), float(q[0]), float(f[0]), float(sf[0]), float(cf[0])
    if q > 0.0:
        W, segments = run_scalar(p, q, f, sf, cf)
    else:  # Q̂1 = 0: w stays where it is (any constant; 0 here) and nothing slips
        W, segments = 0.0, _zero_load_segments(p)
    segs = tuple(
        (float(a), float(b), int(s), float(w0)) for a, b, s, w0 in segments if b > a or s == STICK
    )
    return ExactCycle(p, q, f, max(W, 0.0), segs)


def _zero_load_segments(P1):
    if P1 >= 1.0:
        a = math.asin(1.0 / P1)
        return [
            (TWO_PI - a, 3 * math.pi + a, STICK, 0.0),
            (3 * math.pi + a, 4 * math.pi - a, SEPARATION, float("nan")),
        ]
    return [(0.0, TWO_PI, STICK, 0.0)]
