"""An independent reference for the quasi-static modal analysis of a jointed structure: the
return map of the full structure (no condensation), stepped over the load cycle.

At each step the displacements x and the slider positions w minimize the incremental potential
``½ xᵀ K x + ½ Σ kt_j (g_jᵀ x - w_j)² - α φᵀ M x + Σ Fs_j |w_j - w_j_old|`` (backward Euler of
Jenkins' flow rule), by alternating the exact minimization in x (a linear solve with the stuck
stiffness) and in each w_j (soft thresholding) until nothing moves. For one slider, and for
sliders that slip together, the step is exact wherever α is linear in the step; the cycle is
then exact up to the few steps where a slider starts or stops slipping. W is the sum of
``Fs_j |Δw_j|`` over the last cycle.
"""

from __future__ import annotations

import numpy as np


def relative_vectors(n, dofs):
    """G (n x n_c): ``g_jᵀ x = x_i - x_k`` (k = -1: ground)."""
    G = np.zeros((n, len(dofs)))
    for j, (i, k) in enumerate(dofs):
        G[i, j] += 1.0
        if k >= 0:
            G[k, j] -= 1.0
    return G


def return_map_cycle(M, K, dofs, kt, slip, phi, alpha_max, steps=400, cycles=3, tol=1e-15):
    """The quasi-static cycles under ``α = alpha_max sin θ`` from w = 0, ``steps`` per cycle
    (a multiple of 4). Returns a dict: ``a`` (half the range of q over the last cycle), ``W``
    (its dissipation), ``theta`` and ``q`` (the last cycle, steps + 1 values), ``virgin`` (α, q)
    of the first quarter cycle (the backbone)."""
    M, K = np.asarray(M, float), np.asarray(K, float)
    kt, slip = np.asarray(kt, float), np.asarray(slip, float)
    G = relative_vectors(K.shape[0], dofs)
    A_inv = np.linalg.inv(K + (G * kt) @ G.T)
    Mphi = M @ phi
    w = np.zeros(len(kt))
    theta = np.linspace(0.0, 2.0 * np.pi, steps + 1)
    q_all, W_last = [], 0.0
    virgin = ([0.0], [0.0])
    for c in range(cycles):
        q = [float(Mphi @ (A_inv @ (G @ (kt * w))))]
        W = 0.0
        for s in range(1, steps + 1):
            alpha = alpha_max * np.sin(theta[s])
            w_old = w.copy()
            for _ in range(100000):
                x = A_inv @ (alpha * Mphi + G @ (kt * w))
                d = G.T @ x - w_old
                w_new = w_old + np.sign(d) * np.maximum(np.abs(d) - slip / kt, 0.0)
                moved = np.max(np.abs(w_new - w), initial=0.0)
                w = w_new
                if moved <= tol * max(1.0, np.max(np.abs(w))):
                    break
            x = A_inv @ (alpha * Mphi + G @ (kt * w))
            W += float(slip @ np.abs(w - w_old))
            q.append(float(Mphi @ x))
            if c == 0 and s <= steps // 4:
                virgin[0].append(alpha)
                virgin[1].append(q[-1])
        q_all, W_last = np.array(q), W
    return {
        "a": 0.5 * (q_all.max() - q_all.min()),
        "W": W_last,
        "theta": theta,
        "q": q_all,
        "virgin": (np.array(virgin[0]), np.array(virgin[1])),
    }
