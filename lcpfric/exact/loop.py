"""The exact solver's event loop, compiled (numba): the next event of a pattern, the pivots that
decide the pattern after an event from a guess, and one cycle integrated event by event
(:mod:`lcpfric.exact.discrete`, "At an event"; :mod:`lcpfric.exact.kernels` for the state).

:func:`run` integrates from the current angle and returns to the caller only at the end of the
cycle, at an error, or at an event the pivots cannot settle on their own: one that needs a
fresh factorization of ``K_BB`` or the slip-rate LCP (:meth:`~lcpfric.exact.events.EventSolver.
decide` finishes it and calls :func:`run` again). Imported by a discrete exact solve only.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .kernels import (
    ANY_DIRTY,
    ATTEMPT,
    BACKWARD,
    BUDGET,
    ERASED,
    EVENTS,
    FLIPS_OK,
    FORWARD,
    HAS_TROW,
    KN,
    KS,
    LAST,
    M,
    MAX_EVENTS,
    PIVOT_CODE,
    PIVOT_K,
    REL,
    RELTOL,
    SEPARATION,
    SINCE,
    SKIPPED,
    STICK,
    THETA,
    TRACK,
    TWO_PI,
    JIT_OPTIONS,
    entry,
    flip,
    settle,
    theta_sensitivity,
)

__all__ = ["next_event", "violation", "set_flips", "pivots", "run"]

SAME = 64 * float(np.finfo(float).eps) * TWO_PI  # events closer than this happen together
N_ETAS = 4  # look-ahead steps of a degenerate instant (lcpfric.exact.events._ETAS)
# codes: pivots
DONE, FULL, LCP = 0, 1, 2
# codes: run
END, DECIDE, TOO_MANY, UNSETTLED = 0, 1, 2, 3


@njit(**JIT_OPTIONS)
def next_event(theta, tri, flg, scales, t_all, ints, fl):  # pragma: no cover - compiled
    """Entry angles of every constraint of the pattern into ``t_all`` (2n): rows 0..n-1 the
    upper margin ``f P - F`` of a stuck node or the slip rate ``±du/dθ`` of a slipping one;
    rows n..2n-1 the lower margin ``f P + F`` of a stuck node (inf elsewhere). Only the dirty
    rows are recomputed."""
    if not ints[ANY_DIRTY]:
        return
    U, Ft, bt, sign, status, B, a_seg = tri
    dirty, touched, flipped = flg
    fscale, rate_scale = scales
    n = status.size
    rel = fl[RELTOL]
    ints[ANY_DIRTY] = 0
    deepest = 0.0
    for r in range(n):
        if not dirty[r]:
            continue
        dirty[r] = False
        st = status[r]
        if st == STICK:
            tol = rel * fscale[r]
            t1, s1 = entry(
                bt[r, 0] - Ft[r, 0], bt[r, 1] - Ft[r, 1], bt[r, 2] - Ft[r, 2], theta, tol
            )
            t2, s2 = entry(
                bt[r, 0] + Ft[r, 0], bt[r, 1] + Ft[r, 1], bt[r, 2] + Ft[r, 2], theta, tol
            )
            deepest = max(deepest, s1, s2)
        else:
            D = 1.0 if st == FORWARD else (-1.0 if st == BACKWARD else 0.0)
            tol = rel * rate_scale[r]
            t1, s1 = entry(D * 0.0, D * -U[r, 2], D * U[r, 1], theta, tol)
            t2 = math.inf
            deepest = max(deepest, s1)
        t_all[r] = t1
        t_all[r + n] = t2
    fl[SKIPPED] = max(fl[SKIPPED], deepest * REL)


@njit(**JIT_OPTIONS)
def violation(theta, tri, flg, scales, t_all, ints, fl):  # pragma: no cover - compiled
    """The least-index node, among those changed since the event began, whose constraint is
    entered now, and the state that removes it (-2: on both limits at N = 0, for the LCP), or
    (-1, 0)."""
    next_event(theta, tri, flg, scales, t_all, ints, fl)
    U, Ft, bt, sign, status, B, a_seg = tri
    touched = flg[1]
    n = status.size
    horizon = theta + SAME
    for i in range(n):
        if not touched[i]:
            continue
        first, second = t_all[i] <= horizon, t_all[i + n] <= horizon
        if first or second:
            if status[i] != STICK:
                return i, STICK
            if first and second:
                return i, -2
            return i, (BACKWARD if first else FORWARD)
    return -1, 0


@njit(**JIT_OPTIONS)
def set_flips(pattern, theta, lin, tri, flg, tan, wk, ints, fl):  # pragma: no cover - compiled
    """Reach ``pattern`` by single changes of state (at most four, and fewer than
    max(64, |B|) since the last factorization), else FULL: the caller refactorizes."""
    status = tri[4]
    if not ints[FLIPS_OK] or ints[SINCE] >= max(64, ints[M]):
        return FULL
    changed = 0
    for i in range(status.size):
        if status[i] != pattern[i]:
            changed += 1
    if changed > 4:
        return FULL
    for i in range(status.size):
        if status[i] != pattern[i]:
            code = flip(i, pattern[i], theta, lin, tri, flg, tan, wk, ints, fl)
            if code < 0:
                return code
    return DONE


@njit(**JIT_OPTIONS)
def pivots(pattern, k, budget, skip_set, theta, lin, tri, flg, tan, wk, scales, t_all, ints, fl):  # noqa: E501  # pragma: no cover - compiled
    """Principal pivots from ``pattern`` (iterations k..budget-1; ``skip_set``: the pattern is
    already set): a slipping node whose rate turns sticks, a stuck node driven through its
    limit slips. Returns (code, k): DONE; FULL at iteration k (refactorize ``pattern``, then
    resume with ``skip_set``); LCP (a tie, or the budget spent); or an error code < 0."""
    for it in range(k, budget):
        if not skip_set:
            code = set_flips(pattern, theta, lin, tri, flg, tan, wk, ints, fl)
            if code != DONE:
                return code, it
        skip_set = False
        i, new = violation(theta, tri, flg, scales, t_all, ints, fl)
        if i < 0:
            return DONE, it
        if new < 0:
            return LCP, it
        pattern[i] = new
    return LCP, budget


@njit(**JIT_OPTIONS)
def run(theta_s, samples, normal, ev, lin, tri, flg, tan, wk, scales, t_all, ints, fl):  # noqa: E501  # pragma: no cover - compiled
    """Integrate the cycle from ``fl[THETA]`` event by event: sample u, F and the states at
    ``theta_s`` (into ``samples = (Us, Fs, Ss)``), settle the dissipation, and at each event
    guess the pattern (``ev = (guess, touch_lo, touch_hi, recontact, pattern)``) and pivot.
    Returns END at 2π (settled), DECIDE at an event the caller must finish (``ints``: ATTEMPT,
    PIVOT_CODE, PIVOT_K, BUDGET), TOO_MANY, UNSETTLED, or an error code < 0."""
    Us, Fs, Ss = samples
    nang, nnode, nkind = normal
    guess, touch_lo, touch_hi, recontact, pattern = ev
    U, Ft, bt, sign, status, B, a_seg = tri
    touched = flg[1]
    rows = wk[1]
    n = status.size
    theta = fl[THETA]
    while True:
        next_event(theta, tri, flg, scales, t_all, ints, fl)
        t_next = TWO_PI
        for r in range(2 * n):
            if t_all[r] < t_next:
                t_next = t_all[r]
        if ints[KN] < nang.size and nang[ints[KN]] < t_next:
            t_next = nang[ints[KN]]
        # samples in [theta, t_next)
        k_s = ints[KS]
        while k_s < theta_s.size and (t_next >= TWO_PI or theta_s[k_s] < t_next):
            th = theta_s[k_s]
            s, c = math.sin(th), math.cos(th)
            for i in range(n):
                Us[k_s, i] = U[i, 0] + U[i, 1] * s + U[i, 2] * c
                Fs[k_s, i] = Ft[i, 0] + Ft[i, 1] * s + Ft[i, 2] * c
                Ss[k_s, i] = status[i]
            k_s += 1
        ints[KS] = k_s
        if t_next >= TWO_PI:
            for i in range(n):
                rows[i] = i
            settle(rows, n, TWO_PI, tri, fl)
            fl[THETA] = TWO_PI
            return END
        ints[EVENTS] += 1
        if ints[EVENTS] > ints[MAX_EVENTS]:
            return TOO_MANY
        # who acts now
        horizon = t_next + SAME
        hit = -1
        for i in range(n):
            guess[i] = status[i]
            touch_hi[i] = touch_lo[i] = recontact[i] = touched[i] = False
        for r in range(2 * n):
            if t_all[r] <= horizon:
                if r < n:
                    touched[r] = True
                    if status[r] == STICK:
                        touch_hi[r] = True
                        guess[r] = BACKWARD
                    else:
                        guess[r] = STICK
                else:
                    touched[r - n] = touch_lo[r - n] = True
                    guess[r - n] = FORWARD
                hit = 0
        while ints[KN] < nang.size and nang[ints[KN]] <= horizon:
            i = nnode[ints[KN]]
            guess[i] = SEPARATION if nkind[ints[KN]] == 0 else STICK
            touch_hi[i] = touch_lo[i] = False
            recontact[i] = nkind[ints[KN]] == 1
            touched[i] = True
            ints[KN] += 1
        ints[ATTEMPT] = ints[ATTEMPT] + 1 if t_next <= fl[LAST] + SAME else 0
        if ints[ATTEMPT] > N_ETAS + 2:
            fl[THETA] = t_next
            return UNSETTLED
        theta = fl[THETA] = fl[LAST] = t_next
        ints[HAS_TROW] = 0
        if ints[TRACK] and hit == 0:
            for i in range(n):
                if touch_hi[i] or touch_lo[i]:
                    theta_sensitivity(i, touch_hi[i], theta, lin, tri, tan, ints, fl)
                    break
        if ints[ATTEMPT] == 0:
            budget = 4
            for i in range(n):
                pattern[i] = guess[i]
                if guess[i] != status[i]:
                    budget += 1
            code, k = pivots(
                pattern, 0, budget, False, theta, lin, tri, flg, tan, wk, scales, t_all, ints, fl
            )
            if code < 0:
                return code
            if code != DONE:
                ints[PIVOT_CODE], ints[PIVOT_K], ints[BUDGET] = code, k, budget
                return DECIDE
            ints[HAS_TROW] = 0
            if ints[M] == n:
                ints[ERASED] = 1
        else:
            return DECIDE


def _depend_on_kernels():
    """Numba keys a cached function by its own file's stamp only: :func:`run` and the others
    here link the kernels of :mod:`lcpfric.exact.kernels`, so a change there must recompile
    them too. Their cache key gets that file's stamp as well (numba's cache index; where a numba
    lays it out otherwise, they are not cached rather than loaded stale)."""
    import os

    from numba.core.caching import NullCache

    from . import kernels

    st = os.stat(kernels.__file__)
    stamp = (st.st_mtime, st.st_size)
    for dispatcher in (next_event, violation, set_flips, pivots, run):
        try:
            index = dispatcher._cache._cache_file
            index._source_stamp = (index._source_stamp, stamp)
        except AttributeError:  # pragma: no cover - another numba
            dispatcher._cache = NullCache()


_depend_on_kernels()
