"""An independent reference for the displacement-driven Jenkins element: the fine-sample,
piecewise-linear return map (Moreau's catching-up).

The motion and the normal load are sampled at ``steps`` equally spaced instants of the period,
and at the instants where the linear interpolant of the (unclipped) normal load crosses zero
(there N = 0: without them a re-contact would be placed at the sample before it, an error of
order ``1/steps`` in the slider where it sticks from a re-contact). Between samples the slider's
bounds ``lo = x - μN/kt`` and ``hi = x + μN/kt`` are taken as linear, for which the sweeping
process is solved exactly by projecting the slider onto the next sample's interval:
``w_{i+1} = clip(w_i, lo_{i+1}, hi_{i+1})``. Cycles are repeated until the slider at t = 0
repeats. W is ``∮ T dx`` and the Fourier coefficients of T by the trapezoidal rule. It shares
nothing with lcpfric's event solvers but the element's definition; its errors fall like
``steps^-2`` (a slip's end or a re-contact between samples, the trapezoid across a kink).
"""

from __future__ import annotations

import math

import numpy as np


def return_map_cycle(kt, mu, x_of_t, N_of_t, period, steps, start=None, harmonics=1, cycles=50):
    """The steady cycle of the sampled element.

    Parameters
    ----------
    kt, mu : float
        The element.
    x_of_t, N_of_t : callable
        The motion and the (unclipped) normal load, vectorized over t.
    period : float
        The period.
    steps : int
        Samples per period.
    start : float, optional
        The slider at t = 0 (default: the mean of x), projected into the allowed interval.
    harmonics : int, optional
        Highest harmonic of T.
    cycles : int, optional
        Cap on the cycles.

    Returns
    -------
    dict
        ``W``, ``force_cos``, ``force_sin`` (k = 0..harmonics), ``force_amplitude``, ``cycles``,
        ``t``, ``T``, ``w``.
    """
    t = np.linspace(0.0, period, steps + 1)
    P = np.asarray(N_of_t(t), dtype=float)
    cross = np.nonzero((P[:-1] < 0) != (P[1:] < 0))[0]
    t_zero = t[cross] - P[cross] * (t[cross + 1] - t[cross]) / (P[cross + 1] - P[cross])
    t = np.concatenate((t, t_zero))
    order = np.argsort(t, kind="stable")
    t = t[order]
    P = np.concatenate((P, np.zeros(t_zero.size)))[order]
    steps = t.size - 1
    x = np.asarray(x_of_t(t), dtype=float)
    N = np.maximum(P, 0.0)
    lo, hi = (x - mu * N / kt).tolist(), (x + mu * N / kt).tolist()
    w = float(np.mean(x[:-1])) if start is None else float(start)
    w = min(max(w, lo[0]), hi[0])
    scale = float(np.ptp(x)) + mu * float(np.max(N)) / kt + 1e-300
    for n in range(1, cycles + 1):
        ws = [w]
        cur = w
        for i in range(1, steps + 1):
            cur = min(max(cur, lo[i]), hi[i])
            ws.append(cur)
        if abs(cur - w) <= 1e-14 * scale:
            break
        w = cur
    ws = np.asarray(ws)
    T = kt * (x - ws)
    W = float(np.sum(0.5 * (T[1:] + T[:-1]) * np.diff(x)))
    theta = 2.0 * math.pi * t / period
    k = np.arange(harmonics + 1)
    c = np.trapezoid(np.cos(np.outer(k, theta)) * T, theta, axis=1) / math.pi
    s = np.trapezoid(np.sin(np.outer(k, theta)) * T, theta, axis=1) / math.pi
    c[0] *= 0.5
    s[0] = 0.0
    return {
        "W": W,
        "force_cos": c,
        "force_sin": s,
        "force_amplitude": float(np.max(np.abs(T))),
        "cycles": n,
        "t": t,
        "T": T,
        "w": ws,
    }
