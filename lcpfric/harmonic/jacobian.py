"""The exact Jacobian of the Jenkins element's force coefficients with respect to the
displacement coefficients, from the piecewise structure of the steady sampled cycle.

Per element the input is ``X = [x_1, ..., x_d, n]`` (each 2H + 1 Fourier coefficients; n the
normal input: the load's coefficients, or the normal displacement's, ν = dN/dn = 1 or kn), the
output ``[T_1, ..., T_d, N]``; ``T = D T_samples``, ``x_samples = E x``
(:mod:`lcpfric.harmonic.fourier`). The sample derivatives G_k = dT_k/dX are

* stick:  ``G_k = G_{k-1} + kt (E_k - E_{k-1})``, so ``G_k = G_s + kt (E_k - E_s)`` back to the
  sample s where the stick began;
* slip (d = 1, sign σ): ``G_k = σ μ ν E_k`` on the normal columns (T_k = σ μ N_k);
* separation: ``G_k = 0``; an element that never reaches its limit keeps its slider
  (its history), ``G_k = kt E_k``.

d = 1. Write ``H_k = G_k - kt E_k`` (on the x columns): H is constant on a stick run and
``h_a = -kt E_a ⊕ σ_a μ ν E_a`` at the sample a that starts it (a slip or separated sample,
the anchor). Then ``dT/dX = kt I + Σ_k D_k ⊗ H_k`` and, with ``S_j = Σ_{k<=j} D_k``,

    dT/dX = kt I + Σ_anchors D_a ⊗ h_a + Σ_stick runs (S_end - S_a [+ e0 on wrapping]) ⊗ h_a

Each row of dT/dx_samples has at most 3 nonzeros (x_k, x_a, n_a): the first sum is
``D diag(w) E`` for two weight vectors, one matrix product ``(n, Ns) @ (Ns, K²)`` with the fixed
table ``D_k ⊗ E_k`` for all elements at once; the second has one outer product per stick run
(a handful per cycle), summed per element by a batched product padded to the most runs.
The normal rows are ``D diag(ν [N_raw > 0]) E``, the same table.

d = 2. The radial return's slip sample is ``T_k = μ N_k u``, ``u = T_k/|T_k|``, with
``dT_k = μ ν u E^n_k + β P (dT_{k-1} + kt (dx_k - dx_{k-1}))``, ``P = I - u uᵀ``,
``β = μN_k/|trial_k| < 1``: a slip keeps the tangential part of the history. H_k is affine in
the value H_{-1} it had before the period, ``H_k = A_k H_{-1} + B_k`` (A 2x2, B 2 x 3K),
propagated over the samples for a chunk of elements; the steady cycle's
``H_{-1} = (I - A_{Ns-1})^{-1} B_{Ns-1}`` (‖A‖ <= Π β < 1 once it slips), and
``dT/dX = kt I + Σ_k D_k ⊗ (A_k H_{-1} + B_k)``, two matrix products with D over the samples.
"""

from __future__ import annotations

import functools

import numpy as np

from .fourier import FourierBasis
from .march import BACKWARD, ROUNDING, SEPARATION, SLIP, STICK

__all__ = ["jacobian_d1", "jacobian_d2", "shaken_down", "jacobian_bytes", "tables"]

#: float64 values per element and sample held by the d = 2 propagation (A: 4, B: 2 x 3K)
_CHUNK_BYTES = 64e6


@functools.lru_cache(maxsize=16)
def tables(basis: FourierBasis):
    """The fixed tables of a basis: ``D_k ⊗ E_k`` (Ns, K²) and ``S_j = Σ_{k<=j} D_k`` (Ns, K).

    Parameters
    ----------
    basis : FourierBasis
        The harmonics and samples.

    Returns
    -------
    tuple of numpy.ndarray
        ``(DE, S)``.
    """
    D, E = basis.D, basis.E
    K = basis.size
    DE = (D.T[:, :, None] * E[:, None, :]).reshape(basis.samples, K * K)
    S = np.cumsum(D.T, axis=0)
    S[-1] = 0.0
    S[-1, 0] = 1.0  # Σ_k D_k = e0 (the mean of a constant), without the sum's rounding
    for a in (DE, S):
        a.setflags(write=False)
    return DE, S


def jacobian_bytes(n: int, d: int, K: int, samples: int, normal: bool) -> float:
    """Bytes of the Jacobian blocks of n elements and of the work to build them.

    Parameters
    ----------
    n, d, K, samples : int
        Elements, tangential directions, coefficients per signal (2H + 1), samples per period.
    normal : bool
        Whether the normal input is a variable (rows and columns of N).

    Returns
    -------
    float
        The estimate (the blocks, their products' temporaries, and the d = 2 chunks).
    """
    m = (d + normal) * K
    blocks = 8.0 * n * m * m
    work = 8.0 * n * (3 * K * K + 6 * samples)
    if d == 2:
        work += _CHUNK_BYTES * 1.5
    return blocks + work


def _normal_rows(J, basis, N_raw, nu):
    K = basis.size
    DE, _ = tables(basis)
    w = (N_raw > 0.0) * nu[None, :]  # (Ns, n)
    J[:, -K:, -K:] = (w.T @ DE).reshape(-1, K, K)


def jacobian_d1(basis: FourierBasis, state, kt, mu, nu, N_raw, normal: bool) -> np.ndarray:
    """The Jacobian blocks of d = 1 elements (see the module's docstring).

    Parameters
    ----------
    basis : FourierBasis
        The harmonics and samples.
    state : numpy.ndarray
        int8 (Ns, n), the steady cycle's states.
    kt, mu, nu : numpy.ndarray
        (n,): stiffness, friction, dN/dn (1 for a prescribed load, kn for a displacement).
    N_raw : numpy.ndarray
        (Ns, n), the normal load before clipping (N_raw > 0: in contact).
    normal : bool
        Include the normal input's columns and the normal force's rows.

    Returns
    -------
    numpy.ndarray
        (n, m, m), m = 2K (rows ``[T, N]``, columns ``[x, n]``) or K (``T`` and ``x`` alone).
    """
    ns, n = state.shape
    K = basis.size
    E = basis.E
    DE, S = tables(basis)
    m = 2 * K if normal else K
    J = np.empty((n, m, m))
    anchor = state != STICK
    # Σ_anchors D_a ⊗ h_a: D diag(w) E for the x and the n columns, one product each
    J[:, :K, :K] = ((anchor * (-kt)).T @ DE).reshape(n, K, K)
    J[:, np.arange(K), np.arange(K)] += kt[:, None]
    if normal:
        sign = (state == SLIP).view(np.int8) - (state == BACKWARD).view(np.int8)
        J[:, :K, K:] = ((sign * (mu * nu)).T @ DE).reshape(n, K, K)
        J[:, K:, :K] = 0.0
        _normal_rows(J, basis, N_raw, nu)
    # Σ_stick runs (S_end - S_{a} [+ e0]) ⊗ h_a, a = the anchor before the run: the runs'
    # first and last samples, from one scan (1: first, 2: last, 3: a run of one sample)
    after = np.empty_like(anchor)
    after[0], after[1:] = anchor[-1], anchor[:-1]
    before = np.empty_like(anchor)
    before[-1], before[:-1] = anchor[0], anchor[1:]
    code = (after.view(np.int8) + 2 * before.view(np.int8)) * ~anchor
    e, k = np.nonzero(code.T)  # sorted by element, then sample
    if e.size == 0:
        return J
    c = code[k, e]
    es, ks = e[c & 1 > 0], k[c & 1 > 0]
    ke = k[c & 2 > 0]
    counts = np.bincount(es, minlength=n)
    first = np.cumsum(counts) - counts
    pos = np.arange(es.size) - first[es]
    # the run that starts at an element's first start ends at its first end after it: when
    # the element's first end comes before its first start, that end closes the run that wraps
    # past the period's end, and the ends shift by one
    shift = ke[first[es]] < ks[first[es]]
    kend = ke[first[es] + (pos + shift) % counts[es]]
    a = ks - 1  # the anchor (-1: the last sample)
    V = S[kend] - S[a] * (a >= 0)[:, None]
    V[:, 0] += kend < ks  # the run wraps: + Σ_k D_k = e0
    Ea = E[a]
    if normal:
        hn = (sign[a, es] * (mu * nu)[es])[:, None] * V
        _add_outer(J[:, :K, K:], es, pos, counts, hn, Ea)
    V *= -kt[es][:, None]
    _add_outer(J[:, :K, :K], es, pos, counts, V, Ea)
    return J


def _add_outer(J, e, pos, counts, V, U):
    """``J[e] += Σ_p V_p ⊗ U_p`` per element, padded to the most terms, in chunks."""
    n = J.shape[0]
    K = V.shape[1]
    R = int(counts.max())
    rows = max(1, int(_CHUNK_BYTES // (8 * R * (K + U.shape[1]))))
    for lo in range(0, n, rows):
        hi = min(n, lo + rows)
        if lo == 0 and hi == n:
            sel, el = slice(None), e
        else:
            sel = (e >= lo) & (e < hi)
            el = e[sel] - lo
        Vp = np.zeros((hi - lo, R, K))
        Up = np.zeros((hi - lo, R, U.shape[1]))
        Vp[el, pos[sel]] = V[sel]
        Up[el, pos[sel]] = U[sel]
        J[lo:hi] += np.matmul(Vp.transpose(0, 2, 1), Up)


def jacobian_d2(basis: FourierBasis, x, T, state, kt, mu, nu, N, N_raw, normal: bool) -> np.ndarray:
    """The Jacobian blocks of d = 2 elements (radial return; see the module's docstring).

    Parameters
    ----------
    basis : FourierBasis
        The harmonics and samples.
    x, T : numpy.ndarray
        (Ns, n, 2): the displacement and force samples of the steady cycle.
    state : numpy.ndarray
        int8 (Ns, n).
    kt, mu, nu : numpy.ndarray
        (n,): stiffness, friction, dN/dn.
    N, N_raw : numpy.ndarray
        (Ns, n): the normal load, clipped and not.
    normal : bool
        Include the normal input's columns and the normal force's rows.

    Returns
    -------
    numpy.ndarray
        (n, m, m), m = 3K (rows ``[T_1, T_2, N]``, columns ``[x_1, x_2, n]``) or 2K.
    """
    ns, n, _ = x.shape
    K = basis.size
    m = (2 + normal) * K
    J = np.zeros((n, m, m))
    chunk = max(1, int(_CHUNK_BYTES // (8 * ns * (4 + 2 * m))))
    trial = np.roll(T, 1, axis=0) + kt[None, :, None] * (x - np.roll(x, 1, axis=0))
    for lo in range(0, n, chunk):
        hi = min(n, lo + chunk)
        J[lo:hi, : 2 * K, :] = _tangential_d2(
            basis,
            trial[:, lo:hi],
            T[:, lo:hi],
            state[:, lo:hi],
            kt[lo:hi],
            mu[lo:hi],
            nu[lo:hi],
            N[:, lo:hi],
            m,
        )
    J[:, np.arange(2 * K), np.arange(2 * K)] += kt[:, None]
    if normal:
        _normal_rows(J, basis, N_raw, nu)
    return J


def _tangential_d2(basis, trial, T, state, kt, mu, nu, N, m):
    ns, c, _ = T.shape
    K = basis.size
    E, D = basis.E, basis.D
    # per sample the map H_{k-1} -> H_k is P (H_{k-1} + kt E_k) + μν u E^n_k - kt E_k with
    # P = β (I - u uᵀ) on a slip, I in stick, 0 in separation: blended, no subsets
    slip = state == SLIP
    sep = state == SEPARATION
    with np.errstate(divide="ignore", invalid="ignore"):
        norm = np.sqrt(T[..., 0] ** 2 + T[..., 1] ** 2)
        u0 = np.where(slip, T[..., 0] / norm, 0.0)
        u1 = np.where(slip, T[..., 1] / norm, 0.0)
        beta = np.where(slip, mu * N / np.sqrt(trial[..., 0] ** 2 + trial[..., 1] ** 2), 0.0)
    rest = np.where(sep, 0.0, 1.0)
    p00 = np.where(slip, beta * u1 * u1, rest)
    p11 = np.where(slip, beta * u0 * u0, rest)
    p01 = -beta * u0 * u1
    a = [np.ones(c), np.zeros(c), np.zeros(c), np.ones(c)]
    As = np.empty((ns, c, 2, 2))
    Bs = np.empty((ns, 2, c, m))  # each row's block contiguous
    B0, B1 = np.zeros((c, m)), np.zeros((c, m))
    for k in range(ns):
        kE = kt[:, None] * E[k]
        X0, X1 = B0.copy(), B1.copy()
        X0[:, :K] += kE
        X1[:, K : 2 * K] += kE
        B0, B1 = Bs[k, 0], Bs[k, 1]
        np.multiply(p00[k, :, None], X0, out=B0)
        B0 += p01[k, :, None] * X1
        np.multiply(p11[k, :, None], X1, out=B1)
        B1 += p01[k, :, None] * X0
        B0[:, :K] -= kE
        B1[:, K : 2 * K] -= kE
        if m > 2 * K:
            B0[:, 2 * K :] += (mu * nu * u0[k])[:, None] * E[k]
            B1[:, 2 * K :] += (mu * nu * u1[k])[:, None] * E[k]
        a = [
            p00[k] * a[0] + p01[k] * a[2],
            p00[k] * a[1] + p01[k] * a[3],
            p01[k] * a[0] + p11[k] * a[2],
            p01[k] * a[1] + p11[k] * a[3],
        ]
        As[k, :, 0, 0], As[k, :, 0, 1], As[k, :, 1, 0], As[k, :, 1, 1] = a
    A, B = As[-1], Bs[-1].transpose(1, 0, 2)
    # the steady cycle: H_{-1} = A H_{-1} + B at the period's end; no slip and no separation
    # (A = I): the slider is the element's history, H = 0
    moved = (state != STICK).any(axis=0)
    H0 = np.zeros((c, 2, m))
    if moved.any():
        H0[moved] = np.linalg.solve(np.eye(2)[None] - A[moved], B[moved])
    DB = (D @ Bs.reshape(ns, -1)).reshape(K, 2, c, m).transpose(0, 2, 1, 3)
    DA = (D @ As.reshape(ns, -1)).reshape(K, c, 2, 2)
    DH = DB + np.einsum("kcij,cjm->kcim", DA, H0)
    return np.ascontiguousarray(DH.transpose(1, 2, 0, 3)).reshape(c, 2 * K, m)


def shaken_down(J, basis, x, N, begin, slider, state, periods, kt, mu, nu, normal) -> None:
    """Correct, in place, the blocks of elements that do not slip in their steady cycle but
    were carried there by slips before it (shakedown).

    Such an element's slider s* is not its history: it is where the slips of the periods
    before the steady one left it, a function of x and N. Its derivative is propagated
    forward through those periods from the given slider (fixed): a clip to a bound takes the
    bound's, ``ds = dx_k ∓ dr_k`` (d = 1); a projection on a disk
    ``ds = dx_k + n dr_k + (r/|g|)(I - n nᵀ)(ds - dx_k)`` (d = 2, n the outward normal,
    ``r = μN/kt``). In d = 1 that is the last clip's bound alone. The slider is then constant
    over the steady cycle, so only the mean rows change: ``dT_0 -= kt ds*``. An element whose
    slider never moved keeps ``kt I``.

    Parameters
    ----------
    J : numpy.ndarray
        (n, m, m) the blocks, updated in place.
    basis : FourierBasis
        The harmonics and samples.
    x : numpy.ndarray
        (Ns, n, d) the displacement samples.
    N : numpy.ndarray
        (Ns, n) the normal load (clipped).
    begin, slider : numpy.ndarray
        (n, d): the steady cycle's slider at its start, and the one given before the march.
    state : numpy.ndarray
        int8 (Ns, n).
    periods : numpy.ndarray
        (n,) the periods marched (the last one is the steady cycle).
    kt, mu, nu : numpy.ndarray
        (n,).
    normal : bool
        Whether the blocks have the normal input's columns.
    """
    e = np.flatnonzero((begin != slider).any(axis=1) & (state == STICK).all(axis=0))
    if e.size == 0:
        return
    K = basis.size
    ns, _, d = x.shape
    m = J.shape[2]
    xs, r = x[:, e], N[:, e] * (mu / kt)[e]
    dr_scale = (mu * nu / kt)[e]
    s = slider[e].copy()
    ds = np.zeros((e.size, d, m))
    rows = np.arange(e.size)
    for p in range(int(periods[e].max()) - 1):
        active = p < periods[e] - 1  # the periods before each element's steady one
        for k in range(ns):
            dx = np.zeros((d, m))
            for i in range(d):
                dx[i, i * K : (i + 1) * K] = basis.E[k]
            dr = np.zeros((e.size, m))
            if normal:
                dr[:, d * K :] = (dr_scale * (N[k, e] > 0.0))[:, None] * basis.E[k]
            g = s - xs[k]
            norm = np.sqrt((g * g).sum(axis=1))
            if d == 1:  # the march's max then min
                lo, hi = xs[k, :, 0] - r[k], xs[k, :, 0] + r[k]
                for side, mask in ((-1.0, s[:, 0] < lo), (1.0, s[:, 0] > hi)):
                    mask &= active
                    ds[mask] = dx[None] + side * dr[mask][:, None, :]
                s[:, 0] = np.minimum(np.maximum(s[:, 0], lo), hi)
                continue
            over = rows[(norm > r[k] * ROUNDING) & active]
            if over.size:
                n_ = g[over] / norm[over, None]
                q = (r[k, over] / norm[over])[:, None, None] * (
                    np.eye(d)[None] - n_[:, :, None] * n_[:, None, :]
                )
                ds[over] = (
                    dx[None] + n_[:, :, None] * dr[over][:, None, :] + q @ (ds[over] - dx[None])
                )
                s[over] = xs[k, over] + g[over] * (r[k, over] / norm[over])[:, None]
    for i in range(d):
        J[e, i * K, :] -= kt[e, None] * ds[:, i, :]
