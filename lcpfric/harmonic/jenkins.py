"""The Jenkins element (a spring kt in series with a Coulomb slider, slip force μN) marched over
sampled periodic input, vectorized over many elements; d = 1 and d = 2 tangential directions.

The element's force is ``T = kt (x - s)``, x the relative tangential displacement, s the
slider's displacement, ``|T| <= μ N``; N = max(0, N_raw) with N_raw the prescribed normal load or
``N0 + kn un``. Where N = 0 (separation) T = 0 and the slider follows (s = x). The march keeps
the slider, not the force: at each sample

    d = 1:  s_k = clip(s_{k-1}, x_k - μN_k/kt, x_k + μN_k/kt),    T_k = kt (x_k - s_k)
    d = 2:  s_k = the projection of s_{k-1} on the disk |s - x_k| <= μN_k/kt  (radial return)

(equivalently ``T_k = clip(T_{k-1} + kt (x_k - x_{k-1}), ±μN_k)``, the return map).

**d = 1 is exact for piecewise-linear input**: x and the clipped N = max(0, N_raw) linear
between samples (the polygon through the clipped samples; a raw N that changes sign between
two samples would, interpolated before clipping, separate inside the interval). On one
interval the stick force ``T_{k-1} + kt (x(t) - x_{k-1})`` and the limits ``±μN(t)`` are
linear in t, so the distance to each limit is linear: a limit is reached at most once in the
interval, and once reached the element slips along it to the interval's end (the relative
rate ``kt x' ∓ μN'`` that drove it there is constant). It cannot reach both limits (that would
need N to vanish inside the interval, which a linear N >= 0 does only at an end: a separation
at t_k clips T_k to 0, and a re-contact from N_{k-1} = 0 starts from T = 0 = ±μN). So the
clipped trial is T(t_k) exactly, for every sample spacing, separation and re-contact included
(checked against an independent event-driven solution, and by subdividing the polygon, in
``tests/test_harmonic_aft.py``); only the sampled input differs from the smooth one.
Against smooth input the first harmonics converge at order 2 in the samples (the trapezoidal
DFT across the slip onset's kink), W at order 2 (the turning points' sampling).

**d = 1 is steady after one period, exactly.** Each sample's map ``s -> clip(s, l_k, u_k)`` is
a clip, and clips compose into a clip, ``clip(clip(s, a, b), a', b') = clip(s, clip(a, a',
b'), clip(b, a', b'))``, in floating point too (comparisons and selections only). The period
map is therefore ``s -> clip(s, L, U)``, which is idempotent: the slider at the start of the
second period is a fixed point and the second period repeats the first's end bit for bit. An
element that never reaches a limit keeps its initial slider (its history).

**d = 2** (radial return) is the backward-Euler (catching-up) step of the sweeping process; it
is not exact for piecewise-linear input: the direction of slip turns inside an interval. Its
error against the same polygon finely subdivided falls like 1/Ns (measured order 0.9 to 0.96
from 128 to 1024 samples); against smooth input the force coefficients and W converge at
order 1 (measured 1.01 and 1.08, 32 to 4096 samples, three harmonics with a varying load).
Along one axis it is the d = 1 map. Its period map is a composition of projections on convex
sets (non-expansive, contracting once the element slips); after the first period (the
transient from the given slider, marched as it is) each period starts from a Newton step on
the period map, whose 2 x 2 derivative is propagated over the samples, until a period repeats
its own start to ``tol`` (measured: at most 6 periods over 10^4 random elements, where plain
periods took up to 97). A cycle without slips found that way is marched again without Newton
steps: its slider is the history of the plain periods, not a point a step happened to reach.

The dissipation W per cycle is ``∮ T · dx`` (the stored energy ``|T|²/2kt`` returns) over the
piecewise-linear cycle: on an interval that ends in slip, T is linear up to the instant the
limit is reached (a root of ``|T_{k-1} + θ kt Δx| = μ N(θ)``, located) and linear along the limit
after it. In d = 1 that is the exact W of the piecewise-linear input.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .._checks import NONCONVERGENCE, finite_array, positive_int
from ..errors import ConvergenceError, ConvergenceWarning, InputError
from .march import STATES, march_d1, march_d2, quantities_d1, quantities_d2

__all__ = ["JenkinsCycle", "jenkins_march", "element_parameters", "initial_slider", "steady_cycle"]

STICK, SLIP, BACKWARD, SEPARATION = STATES


@dataclass(frozen=True, eq=False)
class JenkinsCycle:
    """The steady cycle of many Jenkins elements on their samples.

    Parameters
    ----------
    force, normal, state, slider, dissipation, periods, converged
        Kept as the attributes of the same names (see Attributes).

    Attributes
    ----------
    force : numpy.ndarray
        The tangential force samples T_k, shape (n, d, Ns).
    normal : numpy.ndarray
        The normal force samples N_k = max(0, N_raw), shape (n, Ns).
    state : numpy.ndarray
        int8, shape (n, Ns): :class:`~lcpfric.results.State` codes, 0 stick, 1 forward slip (the
        slider moves in +x, T = +μN; every slip in d = 2), 2 backward slip (T = -μN),
        3 separation (N = 0, T = 0).
    slider : numpy.ndarray
        The slider displacement at the start of the steady cycle (before sample 0), (n, d).
    dissipation : numpy.ndarray
        W per element, ``∮ T · dx`` over the piecewise-linear cycle, shape (n,).
    periods : numpy.ndarray
        The periods marched per element (the last one is the cycle returned), shape (n,).
    converged : numpy.ndarray
        bool, shape (n,): the slider at the period start repeated to ``tol``.
    """

    force: np.ndarray
    normal: np.ndarray
    state: np.ndarray
    slider: np.ndarray
    dissipation: np.ndarray
    periods: np.ndarray
    converged: np.ndarray


def element_parameters(n: int, kt, mu) -> tuple[np.ndarray, np.ndarray]:
    """``kt`` and ``mu`` checked (finite, kt > 0, mu >= 0) and broadcast to shape (n,).

    Parameters
    ----------
    n : int
        The number of elements.
    kt, mu : float or array_like
        The tangential stiffness and the friction coefficient, scalar or one per element.

    Returns
    -------
    tuple of numpy.ndarray
        ``(kt, mu)``, each of shape (n,).
    """
    out = []
    for name, value, nonneg in (("kt", kt, False), ("mu", mu, True)):
        a = finite_array(name, value, nonneg=nonneg)
        if not nonneg and np.any(a <= 0):
            raise InputError(
                name, f"must be > 0 (allowed range (0, inf)); smallest given is {a.min()}"
            )
        if a.ndim > 1 or (a.ndim == 1 and a.shape[0] != n):
            raise InputError(
                name, f"must be a number or one per element (shape ({n},)), got shape {a.shape}"
            )
        out.append(np.broadcast_to(a, (n,)).astype(float))
    return out[0], out[1]


def jenkins_march(
    displacement,
    normal,
    kt,
    mu,
    *,
    slider=None,
    max_periods: int = 2000,
    tol: float = 1e-12,
    on_nonconvergence: str = "raise",
) -> JenkinsCycle:
    """The steady cycle of many Jenkins elements driven by sampled periodic input.

    Parameters
    ----------
    displacement : array_like
        The relative tangential displacement samples over one period, shape (n, Ns) for d = 1
        or (n, d, Ns) with d = 1 or 2.
    normal : array_like
        The normal load samples N_raw, shape (n, Ns); clipped at 0 (separation).
    kt, mu : float or array_like
        Tangential stiffness (> 0) and friction coefficient (>= 0), scalar or (n,).
    slider : array_like, optional
        The slider displacement at the start (before sample 0), shape (n,), (n, d) or scalar;
        default 0.
    max_periods : int, optional
        The cap on the periods marched (d = 1 needs 2).
    tol : float, optional
        The slider's repeat tolerance at the period start, relative to the element's span
        ``max |x| + max μN/kt`` (d = 1 repeats exactly).
    on_nonconvergence : {"raise", "warn", "ignore"}, optional
        What to do when an element has not repeated after ``max_periods``.

    Returns
    -------
    JenkinsCycle
        The forces, states, W and the periods marched.
    """
    x = finite_array("displacement", displacement)
    if x.ndim == 2:
        x = x[:, None, :]
    if x.ndim != 3 or x.shape[1] not in (1, 2) or x.shape[2] < 2:
        raise InputError(
            "displacement", f"must have shape (n, Ns) or (n, d, Ns) with d = 1 or 2, got {x.shape}"
        )
    n, d, ns = x.shape
    N = finite_array("normal", normal)
    if N.shape != (n, ns):
        raise InputError(
            "normal", f"must have shape ({n}, {ns}) like the displacement, got {N.shape}"
        )
    kt, mu = element_parameters(n, kt, mu)
    s0 = initial_slider(slider, n, d)
    max_periods = positive_int("max_periods", max_periods)
    tol = finite_array("tol", tol, nonneg=True)
    if tol.ndim:
        raise InputError("tol", f"must be one number >= 0, got shape {tol.shape}")
    xs = np.ascontiguousarray(np.moveaxis(x, 2, 0))
    Ns = np.ascontiguousarray(np.maximum(N.T, 0.0))
    return steady_cycle(xs, Ns, kt, mu, s0, max_periods, float(tol), on_nonconvergence)


def initial_slider(slider, n: int, d: int) -> np.ndarray:
    """The initial slider displacement checked and broadcast to shape (n, d) (None: zeros).

    Parameters
    ----------
    slider : array_like or None
        Scalar, (n,) (d = 1), (d,), or (n, d).
    n, d : int
        The number of elements and of tangential directions.

    Returns
    -------
    numpy.ndarray
        Shape (n, d).
    """
    if slider is None:
        return np.zeros((n, d))
    s = finite_array("slider", slider)
    if s.ndim == 1 and d == 1 and s.shape[0] == n:
        s = s[:, None]
    try:
        return np.array(np.broadcast_to(s, (n, d)), dtype=float)
    except ValueError:
        raise InputError(
            "slider",
            f"must be a number, shape ({n},) (d = 1), ({d},) or ({n}, {d}); got shape {s.shape}",
        ) from None


def steady_cycle(x, N, kt, mu, slider, max_periods, tol, on_nonconvergence) -> JenkinsCycle:
    """:func:`jenkins_march` on checked, sample-major arrays (x (Ns, n, d), N (Ns, n) >= 0).

    Parameters
    ----------
    x, N, kt, mu, slider : numpy.ndarray
        See :func:`lcpfric.harmonic.march.march_d1` (x (Ns, n, d), N (Ns, n) >= 0, kt, mu
        (n,), slider (n, d)).
    max_periods : int
        The cap on the periods.
    tol : float
        The repeat tolerance.
    on_nonconvergence : str
        "raise", "warn" or "ignore".

    Returns
    -------
    JenkinsCycle
        With arrays that are element-major views of the sample-major ones.
    """
    if on_nonconvergence not in NONCONVERGENCE:
        raise InputError(
            "on_nonconvergence", f"must be one of {NONCONVERGENCE}, got {on_nonconvergence!r}"
        )
    r = N * (mu / kt)
    if x.shape[2] == 1:
        x1 = x[..., 0]
        s, start, periods, converged = march_d1(x1, r, slider[:, 0], max_periods, tol)
        T, state, W = quantities_d1(x1, N, s, start, kt, mu)
        force, start = T.T[:, None, :], start[:, None]
    else:
        s, start, periods, converged = march_d2(x, r, slider, max_periods, tol)
        T, state, W = quantities_d2(x, N, s, start, kt, mu)
        force = np.moveaxis(T, 0, 2)
    cycle = JenkinsCycle(
        force=force,
        normal=N.T,
        state=state.T,
        slider=start,
        dissipation=W,
        periods=periods,
        converged=converged,
    )
    if not converged.all() and on_nonconvergence != "ignore":
        bad = int((~converged).sum())
        msg = (
            f"{bad} of {converged.size} elements did not reach a steady cycle within "
            f"max_periods={max_periods} (slider change at the period start above tol={tol:g} "
            "of the element's span); raise max_periods or tol"
        )
        if on_nonconvergence == "raise":
            raise ConvergenceError(msg, cycle)
        warnings.warn(msg, ConvergenceWarning, stacklevel=3)
    return cycle
