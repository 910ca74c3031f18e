"""Compiled kernels of the exact solver (numba; ``docs/architecture.md``, "Compiled kernels"):
the trig triples' closed forms, a node's change of state (the update of ``G = K_BB⁻¹``, of the
triples of u and F) and the tangent map's rows. The event loop that drives them is
:mod:`lcpfric.exact.loop`.

Imported when a discrete system's exact solve starts (:class:`~lcpfric.exact.pattern.Pattern`),
never by ``import lcpfric`` or the single node's closed form, so the command line's start-up
does not pay for numba. Compiled on first use and cached on disk (``cache=True``: next to this
file, or numba's user-wide cache when the package directory is not writable).

State is passed in and out explicitly, as arrays the caller owns and the kernels update in
place, grouped in tuples:

* ``lin = (K, KT, cptr, cidx, cval, G, Bidx, pos)``: K, its transpose (K itself when
  symmetric), its columns as compressed sparse (``cptr`` empty when K is dense),
  ``G = K_BB⁻¹`` in its leading m x m block, the nodes of B in G's order and each node's
  position there (-1 when stuck);
* ``tri = (U, Ft, bt, sign, status, B, a_seg)``: the triples of u and F, the friction limit's,
  each node's slip sign (F = sign f P on B), state, membership of B and segment start;
* ``flg = (dirty, touched, flipped)``: rows whose event angles are stale, rows changed at this
  event, nodes that changed state in this cycle;
* ``tan = (Jt, Kt, Xs, trow, dbt)``: the tangent map (rows of the state), the operator from
  the state to the forces, the state's triples, the event angle's sensitivity, the limit's rate;
* ``wk``: work arrays; ``ints`` and ``fl``: the integer and float scalars (slots below).

Products with K are taken only on the rows where they are not known: on B, ``K_BB z = e_j``
holds by construction, so a change of state computes ``K z`` on the stuck rows alone.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["rank_one", "rank_one_on", "entry", "segment", "settle", "flip", "tangent_stick"]

STICK, FORWARD, BACKWARD, SEPARATION = 0, 1, 2, 3
TWO_PI = 2.0 * math.pi
REL = 1e-13  # lcpfric.exact.triples.REL
SMALL = 256  # G blocks up to this size are updated whole (cheaper than indexing)
# ints slots
M, SINCE, FLIPS, FREE_SUM, ANY_DIRTY, TRACK, HAS_TROW, ERR_NODE, FLIPS_OK, SPARSE = range(10)
EVENTS, KS, KN, ATTEMPT, ERASED, PIVOT_K, BUDGET, PIVOT_CODE, MAX_EVENTS = range(10, 19)
N_INTS = 19
# fl slots
W, RELTOL, SKIPPED, THETA, LAST, ERR_VALUE, T_SIGMA, T_DG = range(8)
N_FL = 8
# error code: K_BB lost positive definiteness (node ints[ERR_NODE], pivot fl[ERR_VALUE])
NOT_SPD = -1
PENDING = 2  # ints[HAS_TROW]: the event angle's sensitivity waits for a node that sticks

JIT_OPTIONS = dict(cache=True, nogil=True, error_model="numpy")


@njit(**JIT_OPTIONS)
def rank_one(G, m, x, y, sign):  # pragma: no cover - compiled
    """``G[:m, :m] += sign * outer(x, y)`` in place, ``sign`` +1 or -1 (as ``G += outer``
    or ``G -= outer``: the product rounded, then added)."""
    if sign > 0:
        for i in range(m):
            xi = x[i]
            row = G[i]
            for j in range(m):
                row[j] += xi * y[j]
    else:
        for i in range(m):
            xi = x[i]
            row = G[i]
            for j in range(m):
                row[j] -= xi * y[j]


@njit(**JIT_OPTIONS)
def rank_one_on(G, idx, k, x, y, sign):  # pragma: no cover - compiled
    """``G[ix_(idx[:k], idx[:k])] += sign * outer(x[idx], y[idx])`` in place."""
    for a in range(k):
        i = idx[a]
        xi = sign * x[i]
        for b in range(k):
            G[i, idx[b]] += xi * y[idx[b]]


# -- trig triples -----------------------------------------------------------------------------
@njit(**JIT_OPTIONS)
def _mod(a, b):  # pragma: no cover - compiled
    """numpy's float ``mod`` (the result has the divisor's sign)."""
    r = np.fmod(a, b)
    if r != 0.0:
        if r < 0.0:
            r += b
    else:
        r = 0.0
    return r


@njit(**JIT_OPTIONS)
def entry(c0, cs, cc, theta, tol):  # pragma: no cover - compiled
    """The first angle >= theta where ``c0 + cs sin + cc cos`` enters the arc below ``-tol``
    (inf when it never does), and, for a dip too shallow to count, its depth over ``tol``
    (0 otherwise). :func:`lcpfric.exact.triples.next_entry` documents the closed form."""
    R = math.hypot(cs, cc)
    depth = R - c0
    if depth <= tol:
        return math.inf, depth / tol
    if depth >= 2.0 * R:
        return theta, 0.0
    h = 2.0 * math.asin(math.sqrt(depth / (2.0 * R)))
    x = theta + math.atan2(cc, cs)
    d = _mod(x - (1.5 * math.pi - h), TWO_PI)
    if d < 2.0 * h and (d <= h or c0 + R * math.sin(x) < -tol):
        return theta, 0.0
    return theta + (TWO_PI - d), 0.0


@njit(**JIT_OPTIONS)
def segment(b, u, a, e):  # pragma: no cover - compiled
    """``∫_a^e b(θ) du/dθ dθ`` for the triples b and u, in closed form
    (:func:`lcpfric.exact.triples.segment_dissipation`)."""
    m, h = 0.5 * (a + e), 0.5 * (e - a)
    sh = math.sin(h)
    dS = 2.0 * math.cos(m) * sh
    dC = -2.0 * math.sin(m) * sh
    dS2 = dS * (math.sin(a) + math.sin(e)) * 0.5
    d2 = 2.0 * math.cos(2.0 * m) * math.sin(2.0 * h)
    b0, bs, bc = b[0], b[1], b[2]
    us, uc = u[1], u[2]
    return (
        b0 * (us * dS + uc * dC)
        + (bs * us - bc * uc) * dS2
        + (bc * us - bs * uc) * h
        + (bc * us + bs * uc) * (0.25 * d2)
    )


@njit(**JIT_OPTIONS)
def settle(rows, k, theta, tri, fl):  # pragma: no cover - compiled
    """Add the dissipation of ``rows[:k]`` from their segment starts to theta to ``fl[W]``;
    restart their segments there."""
    U, Ft, bt, sign, status, B, a_seg = tri
    acc = 0.0
    for q in range(k):
        r = rows[q]
        if sign[r] != 0.0:
            acc += -sign[r] * segment(bt[r], U[r], a_seg[r], theta)
    fl[W] += acc
    for q in range(k):
        a_seg[rows[q]] = theta


# -- G = K_BB⁻¹ -------------------------------------------------------------------------------
@njit(**JIT_OPTIONS)
def _sum_rows(out, size, M, rows, w, k):  # pragma: no cover - compiled
    """``out[:size] = Σ_q w[q] M[rows[q], :size]`` (q < k): a product as a sum of rows, which
    the compiler vectorizes where a dot product per output entry would be a serial
    reduction."""
    for i in range(size):
        out[i] = 0.0
    for q in range(k):
        wq = w[q]
        Mq = M[rows[q]]
        for i in range(size):
            out[i] += wq * Mq[i]


@njit(**JIT_OPTIONS)
def _add(j, lin, wk, ints, fl):  # pragma: no cover - compiled
    """Border G with node j; G's new column on its support in ``sup``/``zs``; returns its
    size (or NOT_SPD)."""
    K, KT, cptr, cidx, cval, G, Bidx, pos = lin
    sup, rows, idx, zs, Kz, g, y, tmp, mark = wk
    m = ints[M]
    nk = 0
    for b in range(m):
        v = K[j, Bidx[b]]
        if v != 0.0:
            idx[nk] = b
            tmp[nk] = v
            nk += 1
    s = K[j, j]
    # g = G kb, as a sum of G's rows (G = K_BB⁻¹ is symmetric: rows for columns)
    _sum_rows(g, m, G, idx, tmp, nk)
    for q in range(nk):
        s -= tmp[q] * g[idx[q]]
    if not s > 0.0:
        ints[ERR_NODE] = j
        fl[ERR_VALUE] = s
        return NOT_SPD
    ns = 0
    for i in range(m):
        y[i] = g[i] / s
        if g[i] != 0.0:
            idx[ns] = i
            ns += 1
    if m <= SMALL or 4 * ns > m:
        rank_one(G, m, g, y, 1)
    elif ns:
        rank_one_on(G, idx, ns, g, y, 1.0)
    for i in range(m):
        G[i, m] = G[m, i] = -y[i]
    G[m, m] = 1.0 / s
    Bidx[m] = j
    pos[j] = m
    ints[M] = m + 1
    for q in range(ns):
        sup[q] = Bidx[idx[q]]
        zs[q] = G[idx[q], m]
    sup[ns] = j
    zs[ns] = G[m, m]
    return ns + 1


@njit(**JIT_OPTIONS)
def _remove(j, lin, wk, ints):  # pragma: no cover - compiled
    """Downdate G for B without node j (the last node takes its place)."""
    K, KT, cptr, cidx, cval, G, Bidx, pos = lin
    sup, rows, idx, zs, Kz, g, y, tmp, mark = wk
    m, p = ints[M], pos[j]
    ns = 0
    cp = G[p, p]
    for i in range(m):
        g[i] = G[i, p]
        y[i] = g[i] / cp
        if g[i] != 0.0:
            idx[ns] = i
            ns += 1
    if m <= SMALL or 4 * ns > m:
        rank_one(G, m, g, y, -1)
    else:
        rank_one_on(G, idx, ns, g, y, -1.0)
    last = m - 1
    if p != last:
        for i in range(last):
            G[p, i] = G[last, i]
        for i in range(last):
            G[i, p] = G[i, last]
        G[p, p] = G[last, last]
        k = Bidx[last]
        Bidx[p] = k
        pos[k] = p
    for i in range(m):
        G[last, i] = 0.0
        G[i, last] = 0.0
    pos[j] = -1
    ints[M] = last


@njit(**JIT_OPTIONS)
def flip(j, new, theta, lin, tri, flg, tan, wk, ints, fl):  # pragma: no cover - compiled
    """Change node j's state to ``new`` at theta: G by bordering or a rank-one downdate, U on
    G's column, F on the stuck rows K couples to it (``K z`` there only: on B it is ``e_j``);
    settles the rows it changes. Returns 0, or NOT_SPD."""
    K, KT, cptr, cidx, cval, G, Bidx, pos = lin
    U, Ft, bt, sign, status, B, a_seg = tri
    dirty, touched, flipped = flg
    sup, rows, idx, zs, Kz, g, y, tmp, mark = wk
    n = status.size
    old = status[j]
    if old == new:
        return 0
    ints[FLIPS] += 1
    ints[FREE_SUM] += ints[M]
    sgn = -1.0 if new == FORWARD else (1.0 if new == BACKWARD else 0.0)
    d = np.empty(3)
    if old == STICK:  # j joins B with a prescribed force
        ns = _add(j, lin, wk, ints, fl)
        if ns < 0:
            return ns
        for c in range(3):
            d[c] = sgn * bt[j, c] - Ft[j, c]
    else:
        m, p = ints[M], pos[j]
        ns = 0
        cp = G[p, p]
        for i in range(m):
            if G[i, p] != 0.0:
                sup[ns] = Bidx[i]
                zs[ns] = G[i, p]
                ns += 1
        if new == STICK:  # j leaves B: u_j keeps its value at theta
            if ints[TRACK]:
                tangent_stick(j, theta, lin, tri, tan, wk, ints, fl)
            s, c = math.sin(theta), math.cos(theta)
            val = U[j, 0] + U[j, 1] * s + U[j, 2] * c
            d[0] = (-U[j, 0] + val) / cp
            d[1] = -U[j, 1] / cp
            d[2] = -U[j, 2] / cp
            _remove(j, lin, wk, ints)
        else:  # prescribed force changes (slip <-> separation)
            for c in range(3):
                d[c] = sgn * bt[j, c] - Ft[j, c]
    # the rows that change: G's column, and the stuck rows K couples to it
    nr = 0
    for q in range(ns):
        mark[sup[q]] = True
        rows[nr] = sup[q]
        nr += 1
    if cptr.size:
        for q in range(ns):
            s_, z = sup[q], zs[q]
            for e in range(cptr[s_], cptr[s_ + 1]):
                r = cidx[e]
                if B[r] or r == j:
                    continue
                if not mark[r]:
                    mark[r] = True
                    rows[nr] = r
                    nr += 1
                    Kz[r] = 0.0
                Kz[r] += cval[e] * z
    else:  # dense K: the product on every row as a sum of K's columns (vectorized), kept
        # on the stuck rows
        _sum_rows(Kz, n, KT, sup, zs, ns)
        for r in range(n):
            if B[r] or r == j or Kz[r] == 0.0:
                continue
            mark[r] = True
            rows[nr] = r
            nr += 1
    settle(rows, nr, theta, tri, fl)
    for q in range(ns):
        r = sup[q]
        for c in range(3):
            U[r, c] += zs[q] * d[c]
    for q in range(nr):
        r = rows[q]
        mark[r] = False
        if r == j:
            for c in range(3):
                Ft[j, c] += d[c]
        elif not B[r]:
            for c in range(3):
                Ft[r, c] += Kz[r] * d[c]
    status[j] = new
    flipped[j] = True
    sign[j] = sgn
    B[j] = new != STICK
    if new == STICK:
        U[j, 0] = U[j, 0] + U[j, 1] * math.sin(theta) + U[j, 2] * math.cos(theta)
        U[j, 1] = 0.0
        U[j, 2] = 0.0
    # the nodes of B carry their prescribed forces exactly
    for q in range(nr):
        r = rows[q]
        if B[r]:
            for c in range(3):
                Ft[r, c] = sign[r] * bt[r, c]
        dirty[r] = True
        touched[r] = True
    ints[ANY_DIRTY] = 1
    ints[SINCE] += 1
    return 0


# -- the tangent map --------------------------------------------------------------------------
@njit(**JIT_OPTIONS)
def tangent_stick(j, theta, lin, tri, tan, wk, ints, fl):  # pragma: no cover - compiled
    """Node j (in B) sticks at theta: its row of the tangent, ``-(G K_BS)_j J_S``, plus its
    rate times the event angle's sensitivity ``trow`` when another node's limit stopped it
    (:meth:`lcpfric.exact.tangent.Tangent.tangent_stick`)."""
    K, KT, cptr, cidx, cval, G, Bidx, pos = lin
    U, Ft, bt, sign, status, B, a_seg = tri
    Jt, Kt, Xs, trow, dbt = tan
    sup, rows, idx, zs, Kz, g, y, tmp, mark = wk
    n = status.size
    resolve_trow(tan, ints, fl)
    m, p = ints[M], pos[j]
    row = np.zeros(n)
    for k in range(m):
        gk = G[p, k]
        if gk != 0.0:
            Kb = Kt[Bidx[k]]
            for c in range(n):
                row[c] -= gk * Kb[c]
    out = np.zeros(Jt.shape[1])
    for k in range(n):
        if row[k] != 0.0 and not B[k]:
            rk = row[k]
            Jk = Jt[k]
            for c in range(out.size):
                out[c] += rk * Jk[c]
    if ints[HAS_TROW]:
        rate = -Xs[j, 2] * math.sin(theta) + Xs[j, 1] * math.cos(theta)
        for c in range(out.size):
            out[c] += rate * trow[c]
    Jt[j] = out


@njit(**JIT_OPTIONS)
def theta_sensitivity(j, upper, theta, lin, tri, tan, ints, fl):  # pragma: no cover - compiled
    """d(event angle)/d(start state) into ``trow`` for stuck node j reaching its upper (or
    lower) limit: ``-(∂g/∂u_S · J_S) / g'``, ``∂F_j/∂u_S = K_jS - K_jB G K_BS``. Sets
    ``ints[HAS_TROW]`` (0 when the margin is not falling)."""
    K, KT, cptr, cidx, cval, G, Bidx, pos = lin
    U, Ft, bt, sign, status, B, a_seg = tri
    Jt, Kt, Xs, trow, dbt = tan
    n = status.size
    m = ints[M]
    s_row = Kt[j].copy()
    if m:
        w = np.zeros(m)
        for a in range(m):
            kj = Kt[j, Bidx[a]]
            if kj != 0.0:
                Ga = G[a]
                for c in range(m):
                    w[c] += kj * Ga[c]
        for c in range(m):
            if w[c] != 0.0:
                Kb = Kt[Bidx[c]]
                for q in range(n):
                    s_row[q] -= w[c] * Kb[q]
    sigma = 1.0 if upper else -1.0
    s, c_ = math.sin(theta), math.cos(theta)
    dg = (dbt[j, 0] + dbt[j, 1] * s + dbt[j, 2] * c_) - sigma * (-Ft[j, 2] * s + Ft[j, 1] * c_)
    ints[HAS_TROW] = 0
    if not dg < 0.0:
        return
    # the product with the tangent's rows waits until a node sticks at this event (most
    # events have none): those rows (of nodes stuck before it) change only when one does
    for k in range(n):
        trow[k] = 0.0 if B[k] else s_row[k]
    fl[T_SIGMA], fl[T_DG] = sigma, dg
    ints[HAS_TROW] = PENDING


@njit(**JIT_OPTIONS)
def resolve_trow(tan, ints, fl):  # pragma: no cover - compiled
    """The event angle's sensitivity ``sigma (s_row · J_S) / g'`` from the row ``s_row`` that
    :func:`theta_sensitivity` left pending in ``trow`` (before the tangent's rows change)."""
    if ints[HAS_TROW] != PENDING:
        return
    Jt, Kt, Xs, trow, dbt = tan
    acc = np.zeros(trow.size)
    for k in range(trow.size):
        if trow[k] != 0.0:
            sk = trow[k]
            Jk = Jt[k]
            for c in range(acc.size):
                acc[c] += sk * Jk[c]
    sigma, dg = fl[T_SIGMA], fl[T_DG]
    for c in range(acc.size):
        trow[c] = sigma * acc[c] / dg
    ints[HAS_TROW] = 1
