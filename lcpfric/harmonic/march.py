"""The Jenkins element's march over the samples of a period, vectorized over elements: the
slider's clip (d = 1) or projection (d = 2) per sample, periods until the slider at the period
start repeats, then the forces, states and W of the last period. The method, its exactness
in d = 1 and the steady cycle after one period are in :mod:`lcpfric.harmonic.jenkins`.

Arrays are sample-major, each sample's values of all elements contiguous: d = 1 ``(Ns, n)``,
d = 2 ``(Ns, n, 2)``; ``r = μN/kt`` is the slider's reach around x (0 in separation).
"""

from __future__ import annotations

import numpy as np

from ..results.cycle import State

__all__ = ["march_d1", "march_d2", "quantities_d1", "quantities_d2", "STATES", "ROUNDING"]

#: the state codes (lcpfric.results.State): stick, forward slip (every slip in d = 2),
#: backward slip, separation
STATES = (int(State.STICK), int(State.FORWARD), int(State.BACKWARD), int(State.SEPARATION))
STICK, SLIP, BACKWARD, SEPARATION = STATES
#: a d = 2 slider closer to its circle than this factor of the radius is inside (rounding)
ROUNDING = 1.0 + 8.0 * np.finfo(float).eps


def _periods(step, x, r, slider, max_periods, tol, span_axes):
    """Periods of ``step(s0, columns, out) -> (s, jump)`` until the slider at the start
    repeats. From the second period on, the next period starts from ``jump`` (a Newton step
    on the period map) when it is not None, else from ``s``; a period is accepted only when it
    repeats its own start. Returns also which elements jumped."""
    n = x.shape[1]
    s_all = np.empty_like(x)
    start = np.array(slider, dtype=float)
    begin = start.copy()
    periods = np.zeros(n, dtype=np.int64)
    converged = np.zeros(n, dtype=bool)
    jumped = np.zeros(n, dtype=bool)
    todo = np.arange(n)
    span = None
    for p in range(max_periods):
        full = todo.size == n
        cols = slice(None) if full else todo
        s0 = start[cols].copy()
        out = s_all if full else np.empty((x.shape[0], todo.size) + x.shape[2:])
        s, jump = step(s0, cols, out)
        if not full:
            s_all[:, todo] = out
        begin[todo] = s0
        periods[todo] += 1
        diff = np.abs(s - s0)
        if diff.ndim > 1:
            diff = diff.max(axis=1)
        done = diff == 0.0  # d = 1 repeats bit for bit (the period map is a clip)
        if not done.all():
            if span is None:
                span = np.abs(x).max(axis=span_axes) + r.max(axis=0)
            done |= diff <= tol * span[todo]
        converged[todo[done]] = True
        # the first period is the transient from the given slider: marched as it is
        use = jump is not None and p > 0
        start[todo] = jump if use else s
        if use:
            jumped[todo[~done]] = True
        todo = todo[~done]
        if todo.size == 0:
            break
    return s_all, begin, periods, converged, jumped


def march_d1(x, r, slider, max_periods: int, tol: float):
    """d = 1: ``s_k = clip(s_{k-1}, x_k - r_k, x_k + r_k)`` over periods.

    Parameters
    ----------
    x, r : numpy.ndarray
        (Ns, n): displacement samples and the slider's reach μN/kt.
    slider : numpy.ndarray
        (n,): the slider before the first period.
    max_periods : int
        The cap on the periods.
    tol : float
        The repeat tolerance, relative to ``max |x| + max r``.

    Returns
    -------
    tuple
        ``(s, begin, periods, converged)``: the slider after each sample of the last period
        (Ns, n), at its start (n,), the periods (n,), the repeat flags (n,).
    """
    lo = x - r
    hi = x + r

    def step(s, cols, out):
        lk, hk = (lo, hi) if isinstance(cols, slice) else (lo[:, cols], hi[:, cols])
        prev = s
        for k in range(x.shape[0]):
            np.maximum(prev, lk[k], out=out[k])
            np.minimum(out[k], hk[k], out=out[k])
            prev = out[k]
        return prev.copy(), None  # steady after one period: no acceleration needed

    return _periods(step, x, r, slider, max_periods, tol, 0)[:4]


def march_d2(x, r, slider, max_periods: int, tol: float, accelerate: bool = True):
    """d = 2: s_k = the projection of s_{k-1} on the disk ``|s - x_k| <= r_k`` (radial return).

    Parameters
    ----------
    x : numpy.ndarray
        (Ns, n, 2) displacement samples.
    r : numpy.ndarray
        (Ns, n) the slider's reach μN/kt.
    slider : numpy.ndarray
        (n, 2): the slider before the first period.
    max_periods : int
        The cap on the periods.
    tol : float
        The repeat tolerance, relative to ``max |x| + max r``.
    accelerate : bool, optional
        From the second period on, start each period from a Newton step on the period map
        (its derivative is propagated over the samples); a cycle without slips found that way
        is marched again without (its slider is the history of the plain periods).

    Returns
    -------
    tuple
        As :func:`march_d1`, with the slider's arrays (Ns, n, 2) and (n, 2).
    """

    def step(s0, cols, out):
        xs, rs = (x, r) if isinstance(cols, slice) else (x[:, cols], r[:, cols])
        s = s0.copy()
        # A = ds_end/ds0, the period map's derivative: a projection's is (r/|g|)(I - n nᵀ)
        a00, a01, a10, a11 = (np.ones(s.shape[0]), np.zeros(s.shape[0]),
                              np.zeros(s.shape[0]), np.ones(s.shape[0]))  # fmt: skip
        for k in range(x.shape[0]):
            g = s - xs[k]
            g0, g1 = g[:, 0], g[:, 1]
            norm = np.sqrt(g0 * g0 + g1 * g1)
            # a slider within rounding of its circle (put there by an earlier projection) is
            # inside: re-projecting it would move it by an ulp, a slip of nothing
            over = norm > rs[k] * ROUNDING
            with np.errstate(divide="ignore", invalid="ignore"):
                f = np.where(over, rs[k] / norm, 1.0)
            s = np.where(over[:, None], xs[k] + g * f[:, None], s)
            out[k] = s
            # the projection's derivative (r/|g|)(I - n nᵀ) = (f/|g|²) [[g1², -g0 g1],
            # [-g0 g1, g0²]] on the slips, I elsewhere
            with np.errstate(divide="ignore", invalid="ignore"):
                c = np.where(over, f / (norm * norm), 0.0)
            q00 = np.where(over, c * g1 * g1, 1.0)
            q11 = np.where(over, c * g0 * g0, 1.0)
            q01 = -c * g0 * g1
            a00, a01, a10, a11 = (
                q00 * a00 + q01 * a10,
                q00 * a01 + q01 * a11,
                q01 * a00 + q11 * a10,
                q01 * a01 + q11 * a11,
            )
        A = np.stack([np.stack([a00, a01], -1), np.stack([a10, a11], -1)], -2)
        # Newton on the period map s0 -> s (piecewise smooth: exact once the slips' pattern
        # repeats); the next period, marched from the jump, decides whether it is steady
        M = np.eye(2) - A
        det = M[:, 0, 0] * M[:, 1, 1] - M[:, 0, 1] * M[:, 1, 0]
        ok = np.abs(det) > 1e-8
        jump = s.copy()
        if ok.any():
            jump[ok] = s0[ok] + np.linalg.solve(M[ok], (s - s0)[ok][..., None])[..., 0]
        return s, (jump if accelerate else None)

    s, begin, periods, converged, jumped = _periods(step, x, r, slider, max_periods, tol, (0, 2))
    # a cycle without slips has a slider that is history: the Newton steps may have put it
    # elsewhere than the plain periods from the given slider would, so those are marched again
    redo = np.flatnonzero(jumped & (s == np.concatenate([begin[None], s[:-1]])).all(axis=(0, 2)))
    if redo.size and accelerate:
        again = march_d2(x[:, redo], r[:, redo], slider[redo], max_periods, tol, False)
        s[:, redo], begin[redo], periods[redo], converged[redo] = again
    return s, begin, periods, converged


def _difference(a, first):
    """``a_k - a_{k-1}`` along axis 0, ``a_{-1}`` = ``first``."""
    out = np.empty_like(a)
    np.subtract(a[0], first, out=out[0])
    np.subtract(a[1:], a[:-1], out=out[1:])
    return out


def quantities_d1(x, N, s, begin, kt, mu):
    """Forces, states and W of the last period, d = 1.

    In slip the force is the limit ±μN itself, in separation 0, in stick ``kt (x - s)``. W is
    ``∮ T dx`` of the piecewise-linear cycle, exact for it: on an interval ending in slip
    (sign σ = the slider's), stick up to ``θ = (σμN_{k-1} - T_{k-1}) / (kt Δx - σμΔN)`` and
    slip along the limit after it, so ``W_k = Δs_k (T_θ + T_k) / 2`` with
    ``T_θ = T_{k-1} + θ kt Δx`` (the slider does not move before θ).

    Parameters
    ----------
    x, N, s : numpy.ndarray
        (Ns, n): displacement, normal load (>= 0), the slider after each sample.
    begin : numpy.ndarray
        (n,): the slider at the period start.
    kt, mu : numpy.ndarray
        (n,).

    Returns
    -------
    tuple of numpy.ndarray
        ``(T, state, W)``: (Ns, n), int8 (Ns, n), (n,).
    """
    # masked assignments (np.where, copyto(where=)) cost several passes each on random masks:
    # the forces and W are blended with 0/1 factors instead
    ds = _difference(s, begin)
    sep = N <= 0.0
    sigma = np.sign(ds)  # +1 forward slip, -1 backward, 0 stick (and a still separation)
    state = sigma.astype(np.int8)
    state[state < 0] = BACKWARD
    state |= sep.view(np.int8) * np.int8(SEPARATION)  # SEPARATION = 3 covers the slip bits
    smu = sigma * mu  # σμ
    stick = (sigma == 0.0) & ~sep
    T = x - s
    T *= kt
    T *= stick
    lim = smu * N  # the limit σμN on slip, 0 in stick and in separation
    T += lim
    # W = Σ Δs_k (T_θ + T_k) / 2 (Δs = 0 in stick), T_θ = T_{k-1} + θ kt Δx,
    # θ = (σμN_{k-1} - T_{k-1}) / (kt Δx - σμΔN) in [0, 1]
    a = _difference(x, x[-1])
    a *= kt
    Tp = np.concatenate([T[-1:], T[:-1]])
    g = np.concatenate([N[-1:], N[:-1]])
    g *= smu
    g -= Tp  # the distance to the limit at the interval's start
    q = _difference(N, N[-1])
    q *= smu
    np.subtract(a, q, out=q)  # the rate towards the limit (> 0 where the slider moved)
    g *= ~stick  # θ = 0 where it does not matter: no 0/0 or overflow there
    q += q == 0.0
    g /= q
    np.clip(g, 0.0, 1.0, out=g)
    g *= a
    g += Tp
    g += T
    g *= ds
    W = 0.5 * g.sum(axis=0)
    return T, state, W


def quantities_d2(x, N, s, begin, kt, mu):
    """Forces, states and W of the last period, d = 2.

    W is ``∮ T · dx`` with T linear from T_{k-1} up to the instant ``θ`` where
    ``|T_{k-1} + θ kt Δx| = μ N(θ)`` (a root of a quadratic) and linear to T_k after it; along
    one axis this is the d = 1 value.

    Parameters
    ----------
    x, s : numpy.ndarray
        (Ns, n, 2): displacement and the slider after each sample.
    N : numpy.ndarray
        (Ns, n): the normal load (>= 0).
    begin : numpy.ndarray
        (n, 2): the slider at the period start.
    kt, mu : numpy.ndarray
        (n,).

    Returns
    -------
    tuple of numpy.ndarray
        ``(T, state, W)``: (Ns, n, 2), int8 (Ns, n), (n,).
    """
    ds = _difference(s, begin)
    sep = N <= 0.0
    moved = ((ds[..., 0] != 0.0) | (ds[..., 1] != 0.0)) & ~sep
    T = x - s
    T *= kt[:, None]
    T *= ~sep[..., None]
    state = moved.view(np.int8) * np.int8(SLIP)
    state |= sep.view(np.int8) * np.int8(SEPARATION)
    dx = _difference(x, x[-1])
    Tp = np.concatenate([T[-1:], T[:-1]])
    # on every interval (full arrays: slips are most of them) the instant θ the stick path
    # T_{k-1} + θ kt Δx reaches μN(θ): 1 in stick
    delta = dx * kt[:, None]
    m = mu[None, :]
    n0 = np.concatenate([N[-1:], N[:-1]])
    dn = N - n0
    a = _dot(delta, delta) - (m * dn) ** 2
    b = 2.0 * (_dot(Tp, delta) - m * m * n0 * dn)
    c = np.minimum(_dot(Tp, Tp) - (m * n0) ** 2, 0.0)
    root = np.sqrt(np.maximum(b * b - 4.0 * a * c, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        # the upward crossing (-b + √disc) / 2a, in the form without cancellation
        theta = np.where(b > 0, -2.0 * c / (b + root), (root - b) / (2.0 * a))
    theta = np.where(state == STICK, 1.0, np.nan_to_num(theta, nan=0.0, posinf=0.0, neginf=0.0))
    theta = np.clip(theta, 0.0, 1.0)[..., None]
    # W = Σ Δx · (the mean of T along its path: linear to the kink T_θ, then linear to T_k)
    path = Tp * (1.0 + theta) + delta * theta + T * (1.0 - theta)
    return T, state, 0.5 * _dot(dx, path).sum(axis=0)


def _dot(u, v):
    """The scalar product over the last axis of length 2 (a sum over it is slow)."""
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1]
