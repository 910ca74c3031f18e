"""Alternating frequency-time (AFT) for Jenkins elements: force coefficients and their exact
Jacobian from displacement coefficients, vectorized over the elements of an interface.

``jenkins_aft`` samples the coefficients (``E``, :mod:`lcpfric.harmonic.fourier`), marches the
element to its steady cycle on the samples (:mod:`lcpfric.harmonic.jenkins`: exact for the
piecewise-linear input in d = 1, the radial return in d = 2), transforms the forces back (``D``)
and differentiates the steady cycle through its stick, slip and separation samples
(:mod:`lcpfric.harmonic.jacobian`). ``jenkins_residual`` is the same in the shape a harmonic-
balance code consumes: one flat coefficient vector in, the force vector and a block-diagonal
sparse Jacobian out.

Signs: the tangential force is the element's spring force ``T = kt (x - s)`` (in stick
``T = kt x`` plus a constant), the term that enters an equation of motion like a spring's,
``M q'' + C q' + K q + f(q) = f_ext``; x is the relative displacement of the element's two
sides. The normal force is ``N = max(0, N_raw)`` >= 0 (compression), with N_raw the prescribed
normal load, or ``N0 + kn un`` with un the normal approach (closing positive).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import memory
from .._checks import finite_array, positive_int
from ..errors import InputError
from .fourier import FourierBasis, check_samples, fourier_basis, harmonics_of
from .jacobian import jacobian_bytes, jacobian_d1, jacobian_d2, shaken_down
from .jenkins import element_parameters, initial_slider, steady_cycle

__all__ = ["AFTResult", "jenkins_aft", "jenkins_residual"]


@dataclass(frozen=True, eq=False)
class AFTResult:
    """The AFT of many Jenkins elements: force coefficients, Jacobian, W and the cycle.

    Coefficient vectors follow :mod:`lcpfric.harmonic.fourier`: ``[c0, a1, b1, ..., aH, bH]``.

    Parameters
    ----------
    tangential_force, normal_force, jacobian, dissipation, force_samples, normal_samples
        Kept as the attributes of the same names (see Attributes).
    state, slider, periods, converged, basis
        Kept as the attributes of the same names (see Attributes).

    Attributes
    ----------
    tangential_force : numpy.ndarray
        The coefficients of T, shape (n, d, 2H + 1).
    normal_force : numpy.ndarray
        The coefficients of N = max(0, N_raw), shape (n, 2H + 1).
    jacobian : numpy.ndarray or None
        Per element the derivatives of the force coefficients with respect to the input
        coefficients, K = 2H + 1: with ``normal_displacement``, d[T_1, ..., T_d, N] /
        d[x_1, ..., x_d, un], shape (n, (d+1)K, (d+1)K); with a prescribed ``normal_load``
        (not a variable), d[T_1, ..., T_d] / d[x_1, ..., x_d], shape (n, dK, dK). None when
        not asked for.
    dissipation : numpy.ndarray
        W per element and cycle, ``∮ T · dx`` of the sampled (piecewise-linear) cycle, (n,).
    force_samples : numpy.ndarray
        T at the samples of the steady cycle, (n, d, Ns).
    normal_samples : numpy.ndarray
        N at the samples, (n, Ns).
    state : numpy.ndarray
        int8 (n, Ns), :class:`~lcpfric.results.State` codes: 0 stick, 1 forward slip (every
        slip in d = 2), 2 backward slip, 3 separation.
    slider : numpy.ndarray
        The slider at the start of the steady cycle (before sample 0), (n, d).
    periods : numpy.ndarray
        The periods marched per element (d = 1: at most 2; 1 when the first repeats).
    converged : numpy.ndarray
        bool (n,): the slider at the period start repeated.
    basis : FourierBasis
        The harmonics and samples used (E and D).
    """

    tangential_force: np.ndarray
    normal_force: np.ndarray
    jacobian: np.ndarray | None
    dissipation: np.ndarray
    force_samples: np.ndarray
    normal_samples: np.ndarray
    state: np.ndarray
    slider: np.ndarray
    periods: np.ndarray
    converged: np.ndarray
    basis: FourierBasis


def _tangential(tangential):
    x = finite_array("tangential", tangential)
    if x.ndim == 2:
        x = x[:, None, :]
    if x.ndim != 3 or x.shape[1] not in (1, 2) or x.shape[0] < 1:
        raise InputError(
            "tangential",
            "must have shape (n, 2H + 1) (d = 1) or (n, d, 2H + 1) with d = 1 or 2, got "
            f"shape {np.shape(tangential)}",
        )
    return x


def _normal(n, K, normal_load, normal_displacement, kn, preload):
    """(N_raw coefficients (n, K), ν (n,))."""
    if (normal_load is None) == (normal_displacement is None):
        raise InputError(
            "normal_load",
            "give exactly one of normal_load (the prescribed normal load) and "
            "normal_displacement (with kn and preload)",
        )
    if normal_load is not None:
        if kn is not None:
            raise InputError("kn", "goes with normal_displacement, not with normal_load")
        c = _coefficients("normal_load", normal_load, n, K)
        return c, np.ones(n)
    if kn is None:
        raise InputError("kn", "normal_displacement needs the normal stiffness kn >= 0")
    kn = _per_element("kn", kn, n, nonneg=True)
    n0 = _per_element("preload", preload, n)
    c = _coefficients("normal_displacement", normal_displacement, n, K) * kn[:, None]
    c[:, 0] += n0
    return c, kn


def _per_element(name, value, n, nonneg=False):
    a = finite_array(name, value, nonneg=nonneg)
    if a.ndim > 1 or (a.ndim == 1 and a.shape[0] != n):
        raise InputError(
            name, f"must be a number or one per element (shape ({n},)), got shape {a.shape}"
        )
    return np.broadcast_to(a, (n,)).astype(float)


def _coefficients(name, value, n, K):
    a = finite_array(name, value)
    if a.ndim <= 1 and a.shape in ((), (n,)):
        c = np.zeros((n, K))
        c[:, 0] = a  # a constant: its mean
        return c
    if a.shape != (n, K):
        raise InputError(
            name,
            f"must be a constant, one per element ({n},) or coefficients ({n}, {K}) like "
            f"the tangential input, got shape {a.shape}",
        )
    return a.copy()


def jenkins_aft(
    tangential,
    samples,
    kt,
    mu,
    *,
    normal_load=None,
    normal_displacement=None,
    kn=None,
    preload=0.0,
    slider=None,
    jacobian: bool = True,
    max_periods: int = 2000,
    tol: float = 1e-12,
    on_nonconvergence: str = "raise",
) -> AFTResult:
    """Force coefficients of Jenkins elements and their exact Jacobian from displacement
    coefficients (alternating frequency-time on the steady cycle).

    Parameters
    ----------
    tangential : array_like
        The relative tangential displacement's coefficients ``[c0, a1, b1, ..., aH, bH]``,
        shape (n, 2H + 1) for d = 1 or (n, d, 2H + 1) with d = 1 or 2.
    samples : int
        Ns, samples per period, > 2H.
    kt, mu : float or array_like
        Tangential stiffness (> 0) and friction coefficient (>= 0), scalar or (n,).
    normal_load : float or array_like, optional
        The prescribed normal load N_raw: a constant, one per element (n,), or coefficients
        (n, 2H + 1). N = max(0, N_raw).
    normal_displacement : float or array_like, optional
        Instead of ``normal_load``: the normal approach un (same shapes), with
        ``N = max(0, preload + kn un)``.
    kn : float or array_like, optional
        The normal stiffness (>= 0), with ``normal_displacement``.
    preload : float or array_like, optional
        N0, with ``normal_displacement`` (default 0).
    slider : array_like, optional
        The slider displacement at the start, (n,), (n, d) or a number (default 0): it
        decides where an element that never slips sticks.
    jacobian : bool, optional
        Compute the Jacobian (default True).
    max_periods : int, optional
        The cap on the periods marched (d = 1 needs 2).
    tol : float, optional
        The slider's repeat tolerance at the period start (relative to the element's span).
    on_nonconvergence : {"raise", "warn", "ignore"}, optional
        What to do when an element's cycle has not repeated within ``max_periods``.

    Returns
    -------
    AFTResult
        The force coefficients, the Jacobian, W, the samples, states and periods.

    Raises
    ------
    InputError
        A parameter is not finite or out of range (kt <= 0, mu < 0, kn < 0, samples <= 2H), or
        the Jacobian would exceed the memory limit (:mod:`lcpfric.memory`).
    ConvergenceError
        A cycle did not repeat within ``max_periods`` (``on_nonconvergence="raise"``).
    """
    X = _tangential(tangential)
    n, d, K = X.shape
    H = harmonics_of(K)
    ns = check_samples(H, samples)
    kt, mu = element_parameters(n, kt, mu)
    Nc, nu = _normal(n, K, normal_load, normal_displacement, kn, preload)
    normal = normal_displacement is not None  # the normal input is a variable
    s0 = initial_slider(slider, n, d)
    max_periods = positive_int("max_periods", max_periods)
    tol = float(finite_array("tol", tol, nonneg=True))
    need = 8.0 * n * ns * (4 * d + 8)
    if jacobian:
        need += jacobian_bytes(n, d, K, ns, normal)
    memory.check(
        need, "tangential", f"the AFT of {n} elements ({H} harmonics, {ns} samples, d = {d})"
    )
    basis = fourier_basis(H, ns)
    E = basis.E
    # sample-major: each sample's values of all elements are contiguous for the march
    x = (E @ X.reshape(n * d, K).T).reshape(ns, n, d)
    N_raw = E @ Nc.T
    N = np.maximum(N_raw, 0.0)
    cycle = steady_cycle(x, N, kt, mu, s0, max_periods, tol, on_nonconvergence)
    T = np.moveaxis(cycle.force, 2, 0)  # (Ns, n, d), a view of the march's array
    D = basis.D
    FT = (D @ T.reshape(ns, n * d)).T.reshape(n, d, K)
    FN = (D @ N).T
    J = None
    if jacobian:
        state = cycle.state.T
        if d == 1:
            J = jacobian_d1(basis, state, kt, mu, nu, N_raw, normal)
        else:
            J = jacobian_d2(basis, x, T, state, kt, mu, nu, N, N_raw, normal)
        shaken_down(J, basis, x, N, cycle.slider, s0, state, cycle.periods, kt, mu, nu, normal)
    return AFTResult(
        tangential_force=FT,
        normal_force=FN,
        jacobian=J,
        dissipation=cycle.dissipation,
        force_samples=cycle.force,
        normal_samples=cycle.normal,
        state=cycle.state,
        slider=cycle.slider,
        periods=cycle.periods,
        converged=cycle.converged,
        basis=basis,
    )


def jenkins_residual(
    q,
    harmonics,
    samples,
    kt,
    mu,
    *,
    directions: int = 1,
    normal_load=None,
    kn=None,
    preload=0.0,
    slider=None,
    blocks: bool = False,
    **options,
):
    """The Jenkins elements' force vector and its Jacobian for a flat coefficient vector, as a
    harmonic-balance residual consumes them.

    The flat vector holds the elements one after the other; per element the signals one after
    the other, each as 2H + 1 coefficients ``[c0, a1, b1, ..., aH, bH]`` (cosine before sine;
    c0 the mean, no 1/2; amplitudes): ``[x_1, ..., x_d]`` with a prescribed ``normal_load``,
    ``[x_1, ..., x_d, un]`` with ``kn`` (the normal approach is then an unknown). The force
    vector has the same layout, ``[T_1, ..., T_d(, N)]``, and enters the residual like a
    spring force: ``r(q) = Z q + f(q) - f_ext`` with ``dr/dq = Z + J``.

    Parameters
    ----------
    q : array_like
        The flat coefficients, length n (d + [kn given]) (2H + 1).
    harmonics : int
        H >= 1.
    samples : int
        Ns > 2H.
    kt, mu : float or array_like
        Tangential stiffness (> 0) and friction (>= 0), scalar or one per element.
    directions : int, optional
        d, 1 or 2.
    normal_load : float or array_like, optional
        The prescribed normal load (constant, (n,), or coefficients (n, 2H + 1)); give either
        it or ``kn``.
    kn : float or array_like, optional
        The normal stiffness: the normal approach is then the last signal of each element and
        ``N = max(0, preload + kn un)``.
    preload : float or array_like, optional
        N0, with ``kn``.
    slider : array_like, optional
        The slider displacement at the start (see :func:`jenkins_aft`).
    blocks : bool, optional
        Return the Jacobian as its (n, m, m) diagonal blocks instead of a sparse matrix.
    **options
        ``max_periods``, ``tol``, ``on_nonconvergence`` of :func:`jenkins_aft`.

    Returns
    -------
    f : numpy.ndarray
        The force coefficients, the layout of ``q``.
    J : scipy.sparse.bsr_array or numpy.ndarray
        df/dq, block diagonal (one m x m block per element, m = len(q) / n).
    """
    import scipy.sparse

    H = positive_int("harmonics", harmonics)
    K = 2 * H + 1
    if directions not in (1, 2):
        raise InputError("directions", f"must be 1 or 2, got {directions!r}")
    d = directions
    if (normal_load is None) == (kn is None):
        raise InputError("kn", "give exactly one of normal_load and kn (with the approach in q)")
    signals = d + (kn is not None)
    q = finite_array("q", q)
    m = signals * K
    if q.ndim != 1 or q.size == 0 or q.size % m:
        raise InputError(
            "q",
            f"must be flat with a multiple of {m} = {signals} signals x (2H + 1) values, "
            f"got shape {q.shape}",
        )
    n = q.size // m
    Q = q.reshape(n, signals, K)
    r = jenkins_aft(
        Q[:, :d],
        samples,
        kt,
        mu,
        slider=slider,
        normal_load=normal_load,
        normal_displacement=None if kn is None else Q[:, d],
        kn=kn,
        preload=preload,
        **options,
    )
    f = r.tangential_force
    J = r.jacobian
    if kn is not None:
        f = np.concatenate([f, r.normal_force[:, None]], axis=1)
    f = f.reshape(-1)
    if blocks:
        return f, np.ascontiguousarray(J)
    idx = np.arange(n)
    return f, scipy.sparse.bsr_array((J, idx, np.arange(n + 1)), shape=(n * m, n * m))
