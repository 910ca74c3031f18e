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
from .jenkins import BACKWARD, SEPARATION, SLIP, STICK

__all__ = ["jacobian_d1", "jacobian_d2", "jacobian_bytes", "tables"]

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


def jacobian_bytes(n: int, d: int, K: int, samples: int) -> float:
    """Bytes of the Jacobian blocks of n elements and of the work to build them.

    Parameters
    ----------
    n, d, K, samples : int
        Elements, tangential directions, coefficients per signal (2H + 1), samples per period.

    Returns
    -------
    float
        The estimate (the blocks, their products' temporaries, and the d = 2 chunks).
    """
    m = (d + 1) * K
    blocks = 8.0 * n * m * m
    work = 8.0 * n * (3 * K * K + 6 * samples)
    if d == 2:
        work += _CHUNK_BYTES * 1.5
    return blocks + work


def _normal_rows(J, basis, N_raw, nu):
    K = basis.size
    DE, _ = tables(basis)
    w = (N_raw > 0.0) * nu[None, :]  # (Ns, n)
    d = J.shape[1] // K - 1
    J[:, d * K :, d * K :] = (w.T @ DE).reshape(-1, K, K)


def jacobian_d1(basis: FourierBasis, state, kt, mu, nu, N_raw) -> np.ndarray:
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

    Returns
    -------
    numpy.ndarray
        (n, 2K, 2K): rows ``[T, N]``, columns ``[x, n]``.
    """
    ns, n = state.shape
    K = basis.size
    E = basis.E
    DE, S = tables(basis)
    J = np.zeros((n, 2 * K, 2 * K))
    anchor = state != STICK
    sign = (state == SLIP).astype(float) - (state == BACKWARD)
    # Σ_anchors D_a ⊗ h_a: D diag(w) E for the x and the n columns, one product each
    wx = anchor * (-kt)[None, :]
    wn = sign * (mu * nu)[None, :]
    J[:, :K, :K] = (wx.T @ DE).reshape(n, K, K)
    J[:, :K, K:] = (wn.T @ DE).reshape(n, K, K)
    J[:, np.arange(K), np.arange(K)] += kt[:, None]
    # Σ_stick runs (S_end - S_a [+ e0]) ⊗ h_a, a = the anchor before the run
    stick = ~anchor
    start = stick & np.roll(anchor, 1, axis=0)  # a stick sample after an anchor
    end = stick & np.roll(anchor, -1, axis=0)  # a stick sample before an anchor
    es, ks = np.nonzero(start.T)  # sorted by element, then sample
    if es.size:
        ee, ke = np.nonzero(end.T)
        counts = np.bincount(es, minlength=n)
        first = np.cumsum(counts) - counts
        pos = np.arange(es.size) - first[es]
        # the run that starts at an element's first start ends at its first end after it:
        # when the element's first end comes before its first start, that end closes the
        # run that wraps past the period's end, and the ends shift by one
        shift = (ke[first[es]] < ks[first[es]]).astype(np.int64)
        kend = ke[first[es] + (pos + shift) % counts[es]]
        a = (ks - 1) % ns
        V = S[kend] - np.where(ks[:, None] > 0, S[ks - 1], 0.0)
        V[:, 0] += kend < ks  # the run wraps: + Σ_k D_k = e0
        hx = (-kt[es])[:, None] * E[a]
        hn = (sign[a, es] * mu[es] * nu[es])[:, None] * E[a]
        _add_outer(J, es, pos, counts, V, np.concatenate([hx, hn], axis=1))
    _normal_rows(J, basis, N_raw, nu)
    return J


def _add_outer(J, e, pos, counts, V, Hrow):
    """``J[e, :K, :] += Σ_p V_p ⊗ Hrow_p`` per element, padded to the most terms, in chunks."""
    n = J.shape[0]
    K = V.shape[1]
    R = int(counts.max())
    rows = max(1, int(_CHUNK_BYTES // (8 * R * (K + Hrow.shape[1]))))
    for lo in range(0, n, rows):
        hi = min(n, lo + rows)
        sel = (e >= lo) & (e < hi)
        Vp = np.zeros((hi - lo, R, K))
        Hp = np.zeros((hi - lo, R, Hrow.shape[1]))
        Vp[e[sel] - lo, pos[sel]] = V[sel]
        Hp[e[sel] - lo, pos[sel]] = Hrow[sel]
        J[lo:hi, :K, :] += np.matmul(Vp.transpose(0, 2, 1), Hp)


def jacobian_d2(basis: FourierBasis, x, T, state, kt, mu, nu, N, N_raw) -> np.ndarray:
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

    Returns
    -------
    numpy.ndarray
        (n, 3K, 3K): rows ``[T_1, T_2, N]``, columns ``[x_1, x_2, n]``.
    """
    ns, n, _ = x.shape
    K = basis.size
    m = 3 * K
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
        )
    J[:, np.arange(2 * K), np.arange(2 * K)] += np.repeat(kt, 1)[:, None]
    _normal_rows(J, basis, N_raw, nu)
    return J


def _tangential_d2(basis, trial, T, state, kt, mu, nu, N):
    ns, c, _ = T.shape
    K = basis.size
    m = 3 * K
    E, D = basis.E, basis.D
    A = np.broadcast_to(np.eye(2), (c, 2, 2)).copy()
    B = np.zeros((c, 2, m))
    As = np.empty((ns, c, 2, 2))
    Bs = np.empty((ns, c, 2, m))
    for k in range(ns):
        st = state[k]
        sl = np.flatnonzero(st == SLIP)
        if sl.size:
            t = T[k, sl]
            u = t / np.linalg.norm(t, axis=1)[:, None]
            beta = mu[sl] * N[k, sl] / np.linalg.norm(trial[k, sl], axis=1)
            P = beta[:, None, None] * (np.eye(2)[None] - u[:, :, None] * u[:, None, :])
            base = B[sl]
            ek = kt[sl, None] * E[k][None, :]
            base[:, 0, :K] += ek
            base[:, 1, K : 2 * K] += ek
            Bn = np.matmul(P, base)
            Bn[:, :, 2 * K :] += (mu[sl] * nu[sl])[:, None, None] * u[:, :, None] * E[k]
            Bn[:, 0, :K] -= ek
            Bn[:, 1, K : 2 * K] -= ek
            B[sl] = Bn
            A[sl] = np.matmul(P, A[sl])
        sp = np.flatnonzero(st == SEPARATION)
        if sp.size:
            A[sp] = 0.0
            B[sp] = 0.0
            ek = kt[sp, None] * E[k][None, :]
            B[sp, 0, :K] = -ek
            B[sp, 1, K : 2 * K] = -ek
        As[k] = A
        Bs[k] = B
    # the steady cycle: H_{-1} = A H_{-1} + B at the period's end; no slip and no separation
    # (A = I): the slider is the element's history, H = 0
    moved = (state != STICK).any(axis=0)
    H0 = np.zeros((c, 2, m))
    if moved.any():
        H0[moved] = np.linalg.solve(np.eye(2)[None] - A[moved], B[moved])
    DB = (D @ Bs.reshape(ns, -1)).reshape(K, c, 2, m)
    DA = (D @ As.reshape(ns, -1)).reshape(K, c, 2, 2)
    DH = DB + np.einsum("kcij,cjm->kcim", DA, H0)
    return np.ascontiguousarray(DH.transpose(1, 2, 0, 3)).reshape(c, 2 * K, m)
