"""Compiled kernels of the half-space's inner iterations (numba; ``docs/architecture.md``,
"Compiled kernels"): the Cerruti operator's spectral product (d = 2), the natural map's
residual of the Newton iterations (d = 1: the pattern iteration's residual and bounds), the
d = 2 Newton step's setup (its unknowns, tangents, diagonal term, right-hand side and weights)
and its first product's array and residual, the conjugate gradients' vector updates, the
increment's end (the disc projection, the slips) and the slip memory's per-node update.

Imported when a half-space's operator first multiplies (:class:`~.influence.Convolution`) or its
stepper starts, never by ``import lcpfric``, so the command line's start-up does not pay for
numba. Compiled on first use and cached on disk (``cache=True``).

Each kernel does what the numpy expressions it replaced did, element by element with the same
operations (no fused multiply-add, no reassociation); the sums and inner products are summed in
order, where numpy summed pairwise or by BLAS, and a node's length ``|(x, y)|`` is ``sqrt(x² +
y²)`` where numpy took ``hypot`` (within an ulp), so they differ from those in the last bits
(``tests/test_halfspace_kernels.py`` checks every kernel against a plain computation).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "cerruti_product",
    "natural",
    "slip_memory_update",
    "embed",
    "restrict1",
    "restrict2",
    "project2",
    "add_bt",
    "add_corner",
    "pattern_residual",
    "newton2_setup",
    "add_at",
    "start2",
    "residual2",
    "project_discs",
    "finish",
]


@njit(cache=True, nogil=True)
def cerruti_product(Z, A, B):  # pragma: no cover - compiled
    """``Z <- A Z + B conj(Z(−k))`` in place on the whole ``M x M`` plane (the transform of z̄
    at the wave vector k is ``conj(Z(−k))``), each pair ``(k, −k)`` at once."""
    M = Z.shape[0]
    for i in range(M // 2 + 1):
        mi = M - i if i else 0
        self_row = mi == i  # rows 0 and M/2 pair with themselves
        for j in range(M):
            mj = M - j if j else 0
            if self_row and mj < j:
                continue  # done with its pair
            z1 = Z[i, j]
            z2 = Z[mi, mj]
            Z[i, j] = A[i, j] * z1 + B[i, j] * z2.conjugate()
            if not self_row or mj != j:
                Z[mi, mj] = A[mi, mj] * z2 + B[mi, mj] * z1.conjugate()


@njit(cache=True, nogil=True)
def _length(x, y):  # pragma: no cover - compiled
    """``|(x, y)|`` as ``sqrt(x² + y²)``: within an ulp or so of ``hypot`` (the forces and
    slips are far from overflow), at a sixth of its cost (libm's hypot: 9 ns)."""
    return np.sqrt(x * x + y * y)


@njit(cache=True, nogil=True)
def natural(F, CF, delta, s0, c, b, contact, Qv, ks):  # pragma: no cover - compiled
    """The natural map's residual at ``(F, CF = C F, δ)`` (node-major ``(n, d)``): ``(Δs, z,
    |z|, slipping, the largest component of F − proj(z), the merit |F − proj(z)|² +
    |equilibrium|², the equilibrium)`` with ``Δs = CF + δ − s0`` and ``z = F − Δs/c``."""
    n, d = F.shape
    ds = np.empty((n, d))
    z = np.empty((n, d))
    zn = np.empty(n)
    slip = np.zeros(n, dtype=np.bool_)
    eq = np.zeros(d)
    worst = 0.0
    rr = 0.0
    for i in range(n):
        for k in range(d):
            v = CF[i, k] + delta[k]
            v -= s0[i, k]
            ds[i, k] = v
            w = v / -c
            w += F[i, k]
            z[i, k] = w
            eq[k] += F[i, k]
        zi = abs(z[i, 0]) if d == 1 else _length(z[i, 0], z[i, 1])
        zn[i] = zi
        scale = 0.0
        if contact[i]:
            scale = 1.0
            if zi > b[i]:
                slip[i] = True
                scale = b[i] / zi
        for k in range(d):
            r = F[i, k] - z[i, k] * scale
            a = abs(r)
            if a > worst:
                worst = a
            rr += r * r
    ee = 0.0
    for k in range(d):
        if ks != 0.0:
            eq[k] -= ks * delta[k]
        eq[k] += Qv[k]
        ee += eq[k] * eq[k]
    return ds, z, zn, slip, worst, rr + ee, eq


@njit(cache=True, nogil=True)
def slip_memory_update(R, dv, b, c, cscalar):  # pragma: no cover - compiled
    """``R_i <- r p pᵀ R_i`` on every node that moved (``dv`` node-major ``(n, 2)``), in place:
    :meth:`lcpfric.steppers.slip_memory.SlipMemory.update`. ``c``: one self-compliance per
    node, or ``cscalar`` where c is empty."""
    n = dv.shape[0]
    for i in range(n):
        dx, dy = dv[i, 0], dv[i, 1]
        m = _length(dx, dy)
        if not m > 0.0:
            continue
        ci = cscalar if c.size == 0 else c[i]
        cb = ci * b[i]
        rm = cb / ((cb + m) * m * m)
        px, py = -dy, dx
        q0 = (px * R[i, 0, 0] + py * R[i, 1, 0]) * rm
        q1 = (px * R[i, 0, 1] + py * R[i, 1, 1]) * rm
        R[i, 0, 0], R[i, 0, 1] = px * q0, px * q1
        R[i, 1, 0], R[i, 1, 1] = py * q0, py * q1


@njit(cache=True, nogil=True)
def embed(flat, idx, x, weights):  # pragma: no cover - compiled
    """``flat[idx] = x`` (a padded array's entries; the others untouched), times ``weights``
    where it is not empty."""
    if weights.size:
        for k in range(idx.size):
            flat[idx[k]] = x[k] * weights[k]
    else:
        for k in range(idx.size):
            flat[idx[k]] = x[k]


@njit(cache=True, nogil=True)
def restrict1(flat, idx):  # pragma: no cover - compiled
    """d = 1: ``flat[idx]``, a new array."""
    out = np.empty(idx.size)
    for k in range(idx.size):
        out[k] = flat[idx[k]]
    return out


@njit(cache=True, nogil=True)
def restrict2(flat, idx, ns, tau, scale, u, diag):  # pragma: no cover - compiled
    """d = 2: the unknowns' components of a padded complex array (``flat[idx]``; on the
    slipping ones, ``k >= ns``, the part along their tangent τ, times ``scale`` if it is not
    empty), plus ``diag u`` on those where ``diag`` is not empty: a new complex array."""
    size = idx.size
    out = np.empty(size, dtype=np.complex128)
    for k in range(ns):
        out[k] = flat[idx[k]]
    for k in range(ns, size):
        w = flat[idx[k]]
        t = tau[k - ns]
        v = t.real * w.real + t.imag * w.imag  # Re(τ̄ w)
        if scale.size:
            v *= scale[k - ns]
        o = t * v
        if diag.size:
            o += diag[k - ns] * u[k]
        out[k] = o
    return out


@njit(cache=True, nogil=True)
def project2(r, ns, tau, Winv):  # pragma: no cover - compiled
    """d = 2: ``r − Bᵀ W⁻¹ B r`` (a new complex array), B the force sums (``B r = Σ r``) and
    ``Bᵀ λ`` λ on the sticking unknowns (``k < ns``), ``τ Re(τ̄ λ)`` on the slipping ones."""
    sx = 0.0
    sy = 0.0
    for k in range(r.size):
        sx += r[k].real
        sy += r[k].imag
    lx = Winv[0, 0] * sx + Winv[0, 1] * sy
    ly = Winv[1, 0] * sx + Winv[1, 1] * sy
    out = np.empty_like(r)
    add_bt(out, r, ns, tau, -lx, -ly)
    return out


@njit(cache=True, nogil=True)
def add_bt(out, r, ns, tau, lx, ly):  # pragma: no cover - compiled
    """d = 2: ``out = r + Bᵀ λ`` with ``λ = (lx, ly)`` (:func:`project2`)."""
    lam = complex(lx, ly)
    for k in range(ns):
        out[k] = r[k] + lam
    for k in range(ns, r.size):
        t = tau[k - ns]
        out[k] = r[k] + t * (t.real * lx + t.imag * ly)


@njit(cache=True, nogil=True)
def add_corner(total, alpha, last):  # pragma: no cover - compiled
    """``total += α last[:N, :N]`` in place (``total`` ``(N, N)``, ``last`` a padded array)."""
    N = total.shape[0]
    for i in range(N):
        for j in range(N):
            total[i, j] += alpha * last[i, j]


@njit(cache=True, nogil=True)
def pattern_residual(F, CF, delta, s0, c, b, ks, Qv, tolF, eps, contact):  # pragma: no cover
    """d = 1: what a pattern iteration of the Newton loop needs at ``(F, CF = C F, δ)``
    (node-major ``(n, 1)``): ``(Δs, z, the pattern's lower and upper bounds −b − band and b +
    band, |z|, the largest |F − clip(z, −b, b)| on the contact, the equilibrium)`` with ``Δs
    = δ + CF − s0``, ``z = F − Δs/c`` and ``band = tolF + 64 eps (b + |F|)``."""
    n = F.shape[0]
    ds = np.empty((n, 1))
    z = np.empty(n)
    lo = np.empty(n)
    hi = np.empty(n)
    zn = np.empty(n)
    total = 0.0
    worst = 0.0
    for i in range(n):
        f = F[i, 0]
        v = delta[0] + CF[i, 0]
        v -= s0[i, 0]
        ds[i, 0] = v
        w = f - v / c
        z[i] = w
        zn[i] = abs(w)
        band = tolF + 64 * eps * (b[i] + abs(f))
        lo[i] = -b[i] - band
        hi[i] = b[i] + band
        total += f
        if contact[i]:
            p = min(max(w, -b[i]), b[i])
            a = abs(f - p)
            if a > worst:
                worst = a
    eq = np.empty(1)
    eq[0] = total - ks * delta[0] + Qv[0]
    return ds, z, lo, hi, zn, worst, eq


@njit(cache=True, nogil=True)
def newton2_setup(F, z, zn, ds, b, contact, slip, cpos, c):  # pragma: no cover - compiled
    """d = 2: the Newton step's unknowns and constants
    (:meth:`lcpfric.steppers.newton_step.NewtonSteps._newton2`) from the iterate (node-major
    ``(n, 2)``): ``(nodes, ns, known, τ, the diagonal term, the padded entries, the right-hand
    side, the preconditioner's weights, Σ τ_x², Σ τ_x τ_y, Σ τ_y², Σ known)``. ``nodes``: the
    sticking nodes (the first ``ns``) then the slipping ones; ``known`` the forces fixed by the
    pattern (−F off the contact, e (b − Re(ē F)) on the slipping nodes, e = z/|z|); τ = i e;
    the diagonal term ``c (1 − β)/β`` (β = b/|z|); the right-hand side ``−Δs`` on the sticking
    nodes and ``τ (−c/β) Re(τ̄ F)`` on the slipping ones; the weights 1 on the sticking nodes
    and ``sqrt(c/(c + term))`` on the slipping ones."""
    n = F.shape[0]
    ns = 0
    nl = 0
    for i in range(n):
        if slip[i]:
            nl += 1
        elif contact[i]:
            ns += 1
    size = ns + nl
    nodes = np.empty(size, dtype=np.int64)
    known = np.empty(n, dtype=np.complex128)
    tau = np.empty(nl, dtype=np.complex128)
    tdiag = np.empty(nl)
    idx = np.empty(size, dtype=np.int64)
    rhs = np.empty(size, dtype=np.complex128)
    weights = np.empty(size)
    ks = 0
    kl = ns
    for i in range(n):
        if not contact[i]:
            known[i] = complex(-F[i, 0], -F[i, 1])
        else:
            known[i] = 0.0
            if not slip[i]:
                nodes[ks] = i
                idx[ks] = cpos[i]
                rhs[ks] = complex(-ds[i, 0], -ds[i, 1])
                weights[ks] = 1.0
                ks += 1
        if slip[i]:
            nodes[kl] = i
            kl += 1
    sxx = 0.0
    sxy = 0.0
    syy = 0.0
    for k in range(nl):
        i = nodes[ns + k]
        zl = zn[i]
        inv = 1.0 / zl  # numpy's complex / real: times the reciprocal
        er = z[i, 0] * inv
        ei = z[i, 1] * inv
        fr = F[i, 0]
        fi = F[i, 1]
        t = b[i] - (er * fr + ei * fi)
        known[i] = complex(er * t, ei * t)
        tr = -ei
        ti = er
        tau[k] = complex(tr, ti)
        beta = b[i] / zl
        td = c * (1.0 - beta) / beta
        tdiag[k] = td
        v = (-c / beta) * (tr * fr + ti * fi)
        rhs[ns + k] = complex(tr * v, ti * v)
        idx[ns + k] = cpos[i]
        weights[ns + k] = np.sqrt(c / (c + td))
        sxx += tr * tr
        sxy += tr * ti
        syy += ti * ti
    ksum = 0j
    for i in range(n):
        ksum += known[i]
    return nodes, ns, known, tau, tdiag, idx, rhs, weights, sxx, sxy, syy, ksum


@njit(cache=True, nogil=True)
def start2(buf, known, N, idx, u0):  # pragma: no cover - compiled
    """d = 2: the known forces (N² complex, row-major) in the ``N x N`` corner of the padded
    array ``buf`` (C-contiguous ``(M, M)``, zero elsewhere), plus the start ``u0`` at the
    unknowns' entries ``idx``, in place."""
    for i in range(N):
        for j in range(N):
            buf[i, j] = known[i * N + j]
    flat = buf.reshape(buf.size)
    for k in range(idx.size):
        flat[idx[k]] += u0[k]


@njit(cache=True, nogil=True)
def residual2(first, buf, N, idx, ns, tau, rhs, tdiag, u0):  # pragma: no cover - compiled
    """d = 2: after the product ``first`` of :func:`start2`'s array, the residual ``(rhs −
    restrict2(first)) − tdiag u0`` (the last term on the slipping unknowns, ``k >= ns``) and
    the product's ``N x N`` corner (a copy); ``buf``'s corner is zeroed again."""
    flat = first.reshape(first.size)
    size = idx.size
    res = np.empty(size, dtype=np.complex128)
    for k in range(ns):
        res[k] = rhs[k] - flat[idx[k]]
    for k in range(ns, size):
        w = flat[idx[k]]
        t = tau[k - ns]
        v = t.real * w.real + t.imag * w.imag  # Re(τ̄ w)
        res[k] = (rhs[k] - t * v) - tdiag[k - ns] * u0[k]
    total = np.empty((N, N), dtype=np.complex128)
    for i in range(N):
        for j in range(N):
            total[i, j] = first[i, j]
            buf[i, j] = 0.0
    return res, total


@njit(cache=True, nogil=True)
def add_at(base, nodes, u):  # pragma: no cover - compiled
    """``base`` with ``u[k]`` added at ``nodes[k]`` (distinct nodes): a new array."""
    out = base.copy()
    for k in range(nodes.size):
        out[nodes[k]] += u[k]
    return out


@njit(cache=True, nogil=True)
def project_discs(F, b):  # pragma: no cover - compiled
    """Forces (node-major ``(n, d)``) onto their discs of radii b (d = 1: the intervals), in
    place."""
    n, d = F.shape
    for i in range(n):
        if d == 1:
            F[i, 0] = min(max(F[i, 0], -b[i]), b[i])
        else:
            norm = _length(F[i, 0], F[i, 1])
            if norm > b[i]:
                scale = b[i] / norm
                F[i, 0] *= scale
                F[i, 1] *= scale


@njit(cache=True, nogil=True)
def finish(F, ds, s0, b, contact, slip, F_prev, CF, CF_prev):  # pragma: no cover - compiled
    """An increment's end (node-major ``(n, d)``): ``(the forces before their projection,
    flat; the slips v = s0 + Δs, Δs zeroed on the sticking nodes; ΔF = F − F_prev; C ΔF = CF −
    CF_prev)``, and F projected onto the discs (d = 1: the intervals) and Δs zeroed on the
    sticking nodes, in place."""
    n, d = F.shape
    F_end = F.copy().reshape(n * d)
    dF = F_end - F_prev
    dCF = CF - CF_prev
    project_discs(F, b)
    for i in range(n):
        if contact[i] and not slip[i]:
            for k in range(d):
                ds[i, k] = 0.0
    v = s0 + ds
    return F_end, v.reshape(n * d), dF, dCF
