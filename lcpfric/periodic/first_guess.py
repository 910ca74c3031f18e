"""A first guess of a dynamic system's periodic orbit for shooting: the equivalent linear
response (each contact replaced by its describing function, Jenkins' closed forms at its mean
normal load; the contacts' amplitudes balanced by a root finder), and the sliders where
Jenkins' steady loop puts them at t = 0.

Newton's method on the period map from rest first finds the stuck structure's linear
response, far from a slipping orbit near resonance, and wanders from there; from this guess it
starts on the right branch (measured in ``benchmarks/validation/newmark_system.py``).
"""

from __future__ import annotations

import math

import numpy as np

from ..model.jenkins import jenkins_closed_form

__all__ = ["equivalent_linear_start"]


def _dense(A):
    return A.toarray() if hasattr(A, "toarray") else np.asarray(A)


def equivalent_linear_start(system) -> np.ndarray:
    """``z0 = (x, x', w_J)`` at t = 0 from the equivalent linear response (module docstring).

    Parameters
    ----------
    system : DynamicSystem
        The system (d = 2: the stuck structure's response, the sliders centred).

    Returns
    -------
    ndarray
        The first guess.
    """
    M, C, K = _dense(system.mass), _dense(system.damping), _dense(system.stiffness)
    G, w = system.G, system.omega
    if system.dims == 2:  # the stuck structure's response, the sliders centred
        kt2 = np.repeat(system.contact_stiffness, 2)
        X = np.linalg.lstsq(K - w * w * M + 1j * w * C + (G * kt2) @ G.T, system.force,
                            rcond=None)[0]  # fmt: skip
        mean = np.linalg.lstsq(K + (G * kt2) @ G.T, system.force_mean, rcond=None)[0]
        x0 = mean + X.real
        return np.concatenate([x0, (1j * w * X).real, G.T @ mean])
    rigid = system.rigid
    kscale = max(float(np.max(np.abs(np.diag(K)))), float(np.max(np.abs(np.diag(M)))) * w * w)
    kt = np.where(rigid, 1e8 * kscale, system.contact_stiffness)
    Fs = system.friction * np.maximum(system.normal_load, 1e-300)
    mean = np.linalg.lstsq(K + (G * kt) @ G.T, system.force_mean, rcond=None)[0]
    base = K - w * w * M + 1j * w * C

    def response(a):
        df = [jenkins_closed_form(kt[j], 1.0, Fs[j], [a[j]]) for j in range(kt.size)]
        k = np.array([d["k_eq"][0] for d in df]) + 1j * np.array([d["c_eq_omega"][0] for d in df])
        return np.linalg.lstsq(base + (G * k) @ G.T, system.force, rcond=None)[0]

    X = np.linalg.lstsq(base + (G * kt) @ G.T, system.force, rcond=None)[0]  # stuck
    a0 = np.abs(G.T @ X)
    if np.any(a0 > Fs / kt):  # slipping: the amplitudes' balance, in log a
        from scipy.optimize import root

        def balance(s):
            return np.log(np.maximum(np.abs(G.T @ response(np.exp(s))), 1e-300)) - s

        sol = root(balance, np.log(np.maximum(a0, 1e-300)), method="hybr")
        X = response(np.exp(sol.x))
    x0 = mean + X.real
    v0 = (1j * w * X).real
    u = G.T @ X
    fin = ~rigid
    wJ = []
    for j in np.flatnonzero(fin):
        a = abs(u[j])
        c = float(G[:, j] @ mean)
        r = Fs[j] / kt[j]
        if a <= r:  # stuck: the slider centred
            wJ.append(c)
            continue
        tau = (math.atan2(u[j].imag, u[j].real)) % (2 * math.pi)  # x_c = a cos(ωt + θ): τ = θ at 0
        ts = 2.0 * math.asin(math.sqrt(r / a))
        if tau <= ts:
            s = a - r
        elif tau <= math.pi:
            s = a * math.cos(tau) + r
        elif tau <= math.pi + ts:
            s = -a + r
        else:
            s = a * math.cos(tau) - r
        wJ.append(c + s)
    return np.concatenate([x0, v0, np.array(wJ, dtype=float)])


def harmonic_start(system, coefficients, contact_force=None) -> np.ndarray:
    """``z0 = (x, x', w_J)`` at t = 0 from a harmonic-balance solution (for example a point of
    :func:`lcpfric.harmonic.forced_response`), so that shooting refines that orbit.

    Parameters
    ----------
    system : DynamicSystem
        The system (d = 1 contacts).
    coefficients : (n, 2H + 1) array_like
        x's coefficients ``[c0, a1, b1, ..., aH, bH]`` of ``c0 + Σ a_h cos hωt + b_h sin hωt``.
    contact_force : (n_J, 2H + 1) array_like, optional
        The Jenkins contacts' forces T, in the same form (their sliders ``w = gᵀx - T/kt``);
        without them the sliders start centred, ``w = gᵀ c0``.

    Returns
    -------
    ndarray
        The first guess.
    """
    c = np.asarray(coefficients, dtype=float)
    H = (c.shape[1] - 1) // 2
    h = np.arange(1, H + 1)
    x0 = c[:, 0] + c[:, 1::2].sum(axis=1)
    v0 = system.omega * (c[:, 2::2] * h).sum(axis=1)
    fin = ~system.rigid
    gx = system.G.T @ x0
    if contact_force is None:
        w = system.G.T @ c[:, 0]
    else:
        T = np.asarray(contact_force, dtype=float)
        w = gx.copy()
        w[fin] = gx[fin] - (T[:, 0] + T[:, 1::2].sum(axis=1)) / system.contact_stiffness[fin]
    return np.concatenate([x0, v0, w[fin]])
