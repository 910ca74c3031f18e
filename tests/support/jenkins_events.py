"""An independent event-driven reference for one Jenkins element (spring kt in series with a
Coulomb slider, slip force μN) driven by piecewise-linear periodic input, d = 1.

Written separately from :mod:`lcpfric.harmonic` and differently from it: scalar Python, time
marched event by event inside each interval between samples (stick until the force reaches a
limit, located as a root in time; slip along the limit while the slider's rate has the slip's
sign, re-stick otherwise; separation where N = 0), with no use of the return map or of the
"at most one event per interval" argument; W as ``∫ μ N |ds|`` over the slip segments (not
``∮ T dx``); the steady cycle by periods until the slider at the period start repeats.
"""

from __future__ import annotations

import numpy as np

__all__ = ["reference_cycle"]


def _interval(s, on, x0, x1, n0, n1, kt, mu):
    """March the slider over one interval (t in [0, 1], x and N linear) from slider ``s``,
    ``on`` the limit (+1, -1) the force starts on, or 0. Returns the slider at its end, the
    limit it ends on (0: inside), the slider's net motion sign and ``∫ μ N |ds|``."""
    t, w, moved = 0.0, 0.0, 0
    dx, dn = x1 - x0, n1 - n0
    if n0 <= 0.0 and n1 <= 0.0:  # separated throughout: no force, the slider follows
        return x1, 0, int(np.sign(x1 - s)), 0.0
    while t < 1.0:
        xt, nt = x0 + t * dx, n0 + t * dn
        # on a limit (both when N = 0: the force is 0 = ±μN), slip if the relative rate
        # kt x' - σμN' pushes outwards; it is constant on the interval, so to its end
        for sigma in (1.0, -1.0) if nt <= 0.0 else (on,) if on else ():
            if sigma * (kt * dx - sigma * mu * dn) > 0.0:
                s_end = x1 - sigma * mu * n1 / kt
                w += mu * 0.5 * (nt + n1) * abs(s_end - s)
                # a slip of a rounding error (a shaken-down slider on its limit) is no slip
                slid = abs(s_end - s) > 1e-13 * (abs(s) + abs(x1) + mu * n1 / kt)
                return s_end, int(sigma), int(sigma) if slid else moved, w
        # stick: the earliest instant the force kt (x - s) reaches a limit ±μN, moving out
        force = kt * (xt - s)
        tau, hit = 1.0, 0
        for sigma in (1.0, -1.0):
            rate = kt * dx - sigma * mu * dn  # d/dt of (force - σμN)
            gap = force - sigma * mu * nt
            if sigma * rate > 0.0 and sigma != on:
                tc = t - gap / rate
                if t < tc < tau:
                    tau, hit = tc, int(sigma)
        if not hit:  # stuck to the interval's end, inside the limits
            return s, 0, moved, w
        t, on = tau, hit
    return s, on, moved, w


def reference_cycle(x, N, kt, mu, slider=0.0, max_periods=20):
    """The steady cycle of one d = 1 Jenkins element on piecewise-linear input.

    Parameters
    ----------
    x, N : array_like
        The samples of one period (the input is linear between them, and from the last
        sample back to the first); N is clipped at 0 first.
    kt, mu : float
        Stiffness and friction coefficient.
    slider : float
        The slider before the first sample; at the first sample it is moved onto the
        admissible set, as if the input had jumped there.
    max_periods : int
        Periods marched at most.

    Returns
    -------
    dict
        ``force`` (Ns,) at the samples, ``state`` (Ns,) 0 stick, 1 forward, 2 backward,
        3 separation (of the interval ending at each sample), ``W``, ``periods``.
    """
    x = np.asarray(x, float)
    N = np.maximum(np.asarray(N, float), 0.0)
    ns = x.size
    r0 = mu * N[0] / kt
    s = min(max(slider, x[0] - r0), x[0] + r0)
    on = 1 if s == x[0] - r0 and r0 > 0 else (-1 if s == x[0] + r0 and r0 > 0 else 0)
    for period in range(1, max_periods + 1):
        start = s
        force = np.empty(ns)
        state = np.zeros(ns, dtype=int)
        W = 0.0
        for j in range(1, ns + 1):
            k = j % ns
            s, on, moved, w = _interval(s, on, x[j - 1], x[k], N[j - 1], N[k], kt, mu)
            W += w
            force[k] = kt * (x[k] - s)
            state[k] = 3 if N[k] <= 0.0 else (0 if moved == 0 else (1 if moved > 0 else 2))
            if N[k] <= 0.0:
                force[k] = 0.0
        if abs(s - start) <= 1e-15 * (np.abs(x).max() + mu * N.max() / kt):
            return dict(force=force, state=state, W=W, periods=period)
    raise RuntimeError("the reference did not repeat")
