"""A minimal harmonic-balance solver: the forced response of a linear structure with Jenkins
elements, through the resonance, by pseudo-arclength continuation over the frequency.

The structure ``M q'' + C q' + K q + Σ_e b_e T_e(b_e · q) = f(t)`` with n degrees of freedom,
each Jenkins element e acting on the relative displacement ``u_e = b_e · q`` of two degrees of
freedom (or of one and the ground), is written for the Fourier coefficients of q, in the
conventions of :mod:`lcpfric.harmonic.fourier` (per degree of freedom ``[c0, a1, b1, ..., aH,
bH]``, τ = ωt): for each harmonic h the linear part acts on ``(a_h, b_h)`` as

    [[K - h²ω² M,  hω C], [-hω C,  K - h²ω² M]]          (c0: K alone)

and the elements' force coefficients and their exact Jacobian come from
:func:`~lcpfric.harmonic.jenkins_aft` (alternating frequency-time on the steady cycle, each
evaluation marched from the slider at 0, as pyHarm's own Jenkins element does). The residual
``r(q, ω) = Z(ω) q + B^T T(B q) - f`` is solved by Newton's method, first at the start
frequency, then along the curve: predictor along the tangent of ``r = 0`` in (q, ω), corrector
on the plane orthogonal to it through the predicted point (pseudo-arclength), in the scaled
variables ``(q / x_ref, ω / Δω)`` (x_ref the largest displacement coefficient reached so far,
at first the static deflection of the stuck structure; Δω the frequency range). The step
aims at a turn of the tangent of 0.1 rad per step, is shortened when Newton needs more than
six iterations and halved when it fails. The matrices are dense: a few degrees of freedom.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._checks import finite_array, positive, positive_int
from ..errors import ConvergenceError, InputError
from .aft import jenkins_aft
from .fourier import check_samples
from .jenkins import element_parameters

#: the turning of the tangent per step (radians) the step length aims at
_TURN = 0.1

__all__ = ["ForcedResponse", "forced_response", "harmonic_residual", "STATUS"]

#: the ends of a continuation, with what they mean and what to do about them
STATUS = {
    "bounds": "The curve reached the end of the frequency range.",
    "max_points": "The number of points reached max_points. Increase max_points or step.",
    "min_step": (
        "Newton's method failed at the smallest step (min_step). Try more harmonics or "
        "samples, a smaller min_step, or a larger max_iterations."
    ),
}


@dataclass(frozen=True, eq=False)
class ForcedResponse:
    """The forced response along the continuation: one row per converged point.

    Parameters
    ----------
    omega, coefficients, contact_force, iterations, residual
        Kept as the attributes of the same names (see Attributes).
    harmonics, samples, status, seconds
        Kept as the attributes of the same names (see Attributes).

    Attributes
    ----------
    omega : numpy.ndarray
        The forcing frequencies ω of the points, (m,).
    coefficients : numpy.ndarray
        The displacements' coefficients, (m, n, 2H + 1), per degree of freedom
        ``[c0, a1, b1, ..., aH, bH]``.
    contact_force : numpy.ndarray
        The elements' force coefficients T_e at the points, (m, n_elements, 2H + 1).
    iterations : numpy.ndarray
        Newton iterations per point, (m,).
    residual : numpy.ndarray
        The final residual norm of each point relative to the forcing's norm, (m,).
    harmonics : int
        H.
    samples : int
        The AFT's samples per period.
    status : str
        Why the continuation ended: a key of :data:`STATUS`.
    seconds : float
        Wall time of the continuation.
    """

    omega: np.ndarray
    coefficients: np.ndarray
    contact_force: np.ndarray
    iterations: np.ndarray
    residual: np.ndarray
    harmonics: int
    samples: int
    status: str
    seconds: float

    @property
    def message(self) -> str:
        """What :attr:`status` means, and what to do about it."""
        return STATUS[self.status]

    def amplitude(self, dof: int = 0, harmonic: int = 1) -> np.ndarray:
        """The amplitude ``sqrt(a_h² + b_h²)`` of one harmonic of one degree of freedom.

        Parameters
        ----------
        dof : int, optional
            The degree of freedom (default 0).
        harmonic : int, optional
            h, 1 <= h <= H (default 1, the first harmonic).

        Returns
        -------
        numpy.ndarray
            Shape (m,), one per point.
        """
        h = positive_int("harmonic", harmonic)
        if h > self.harmonics:
            raise InputError("harmonic", f"must be <= H = {self.harmonics}, got {h}")
        c = self.coefficients[:, dof]
        return np.hypot(c[:, 2 * h - 1], c[:, 2 * h])


def _square(name, value, n=None):
    a = finite_array(name, value)
    a = a.reshape(1, 1) if a.ndim == 0 else a
    if a.ndim != 2 or a.shape[0] != a.shape[1] or (n is not None and a.shape[0] != n):
        want = "square" if n is None else f"{n} x {n}"
        raise InputError(name, f"must be a number or a {want} matrix, got shape {np.shape(value)}")
    return a


def _coupling(contacts, n):
    """B (n_elements, n): row e is +1 at the element's first degree of freedom and -1 at its
    second (none: the ground)."""
    rows = []
    for item in contacts:
        pair = (item, None) if np.ndim(item) == 0 else tuple(item)
        if len(pair) == 1:
            pair = (pair[0], None)
        if len(pair) != 2:
            raise InputError("contacts", f"each contact is a dof or a pair of dofs, got {item!r}")
        row = np.zeros(n)
        for sign, dof in zip((1.0, -1.0), pair):
            if dof is None:
                continue
            if not (isinstance(dof, (int, np.integer)) and 0 <= dof < n):
                raise InputError("contacts", f"degrees of freedom are 0 .. {n - 1}, got {dof!r}")
            row[dof] += sign
        rows.append(row)
    if not rows:
        raise InputError("contacts", "give at least one contact (a dof, or a pair of dofs)")
    return np.array(rows)


class _Problem:
    """The residual of the harmonic balance and its Jacobian, in physical variables."""

    def __init__(self, M, C, K, F, B, H, ns, kt, mu, normal_load):
        self.M, self.C, self.K, self.F, self.B = M, C, K, F, B
        self.n, self.H, self.ns = K.shape[0], H, ns
        self.kt, self.mu, self.normal_load = kt, mu, normal_load
        Kc = 2 * H + 1
        h = np.arange(1, H + 1)
        self.h2 = np.diag(np.concatenate([[0.0], np.repeat(h**2, 2)]).astype(float))
        nab = np.zeros((Kc, Kc))
        nab[1::2, 2::2] = np.diag(h)  # cosine row of harmonic h, sine column: +h (C q')
        nab[2::2, 1::2] = -np.diag(h)
        self.nab = nab
        self.eye = np.eye(Kc)
        self.size = self.n * Kc

    def __call__(self, q, omega):
        """(r, dr/dq, dr/dω, T) at the flat coefficients q (dof-major) and ω."""
        n, Kc = self.n, 2 * self.H + 1
        X = q.reshape(n, Kc)
        Lq = np.kron(self.K, self.eye) - omega**2 * np.kron(self.M, self.h2)
        Lq += omega * np.kron(self.C, self.nab)
        Lw = -2.0 * omega * np.kron(self.M, self.h2) + np.kron(self.C, self.nab)
        aft = jenkins_aft(self.B @ X, self.ns, self.kt, self.mu, normal_load=self.normal_load)
        T = aft.tangential_force[:, 0]
        J = np.einsum("ei,ej,eab->iajb", self.B, self.B, aft.jacobian).reshape(self.size, -1)
        r = Lq @ q + (self.B.T @ T).reshape(-1) - self.F.reshape(-1)
        return r, Lq + J, Lw @ q, T


def harmonic_residual(
    coefficients, omega, mass, damping, stiffness, force, *, contacts=(0,), kt, mu,
    normal_load, samples: int = 128,
):  # fmt: skip
    """The harmonic-balance residual of :func:`forced_response`'s structure and its Jacobian.

    ``r(q, ω) = Z(ω) q + B^T T(B q) - f``, the equations a point of the forced response
    satisfies (use it to check a point computed elsewhere, pyHarm's for one).

    Parameters
    ----------
    coefficients : array_like
        q, the displacements' coefficients (n, 2H + 1) (or flat, dof-major).
    omega : float
        ω.
    mass, damping, stiffness, force, contacts, kt, mu, normal_load, samples
        As in :func:`forced_response`.

    Returns
    -------
    r : numpy.ndarray
        The residual, (n, 2H + 1).
    dr_dq : numpy.ndarray
        Its Jacobian, (n (2H + 1), n (2H + 1)), dof-major.
    dr_domega : numpy.ndarray
        Its derivative in ω, (n, 2H + 1).
    """
    problem, _ = _build(mass, damping, stiffness, force, contacts, kt, mu, normal_load,
                        None, samples, coefficients)  # fmt: skip
    q = finite_array("coefficients", coefficients).reshape(-1)
    r, Jq, Jw, _ = problem(q, float(finite_array("omega", omega)))
    return r.reshape(problem.n, -1), Jq, Jw.reshape(problem.n, -1)


def _build(mass, damping, stiffness, force, contacts, kt, mu, normal_load, harmonics, samples,
           coefficients=None):  # fmt: skip
    """(_Problem, F) from the user's parameters, checked."""
    K = _square("stiffness", stiffness)
    n = K.shape[0]
    M, C = _square("mass", mass, n), _square("damping", damping, n)
    if coefficients is not None:
        size = np.size(coefficients)
        if size % n or size // n < 3 or (size // n) % 2 == 0:
            raise InputError(
                "coefficients", f"must hold n = {n} vectors of 2H + 1 values, got {size} values"
            )
        harmonics = (size // n - 1) // 2
    H = positive_int("harmonics", harmonics)
    ns = check_samples(H, samples)
    Kc = 2 * H + 1
    f = finite_array("force", force)
    F = np.zeros((n, Kc))
    if f.size == n and f.ndim <= 1:
        F[:, 1] = f.reshape(n)
    elif f.shape == (n, Kc):
        F = f.copy()
    else:
        raise InputError("force", f"must have shape ({n},) or ({n}, {Kc}), got {f.shape}")
    B = _coupling(contacts, n)
    return _Problem(M, C, K, F, B, H, ns, kt, mu, normal_load), F


def forced_response(
    mass,
    damping,
    stiffness,
    force,
    omega,
    *,
    contacts=(0,),
    kt,
    mu,
    normal_load,
    harmonics: int = 5,
    samples: int = 128,
    step: float = 0.02,
    max_step: float = 0.2,
    min_step: float = 1e-6,
    max_points: int = 2000,
    tol: float = 1e-10,
    max_iterations: int = 25,
) -> ForcedResponse:
    """The forced response of a linear structure with Jenkins elements by harmonic balance and
    pseudo-arclength continuation over the frequency (lcpfric's AFT as the elements).

    Parameters
    ----------
    mass, damping, stiffness : float or array_like
        M, C and K: numbers (one degree of freedom) or n x n matrices.
    force : float or array_like
        The forcing: the amplitudes (n,) of ``f cos ωt`` (a number when n = 1), or the
        coefficients (n, 2H + 1) of a periodic forcing.
    omega : tuple of float
        ``(start, stop)``: the continuation starts at ω = start and ends when the curve leaves
        the range (start > stop sweeps downwards).
    contacts : sequence, optional
        One entry per Jenkins element: a degree of freedom (the element between it and the
        ground) or a pair ``(i, j)`` (on ``q_i - q_j``). Default ``(0,)``.
    kt, mu, normal_load : float or array_like
        The elements' stiffness (> 0), friction coefficient (>= 0) and constant normal load,
        scalars or one per element; the slip force is ``mu * max(0, normal_load)``.
    harmonics : int, optional
        H >= 1 (default 5).
    samples : int, optional
        The AFT's samples per period, > 2H (default 128).
    step, max_step, min_step : float, optional
        The first, largest and smallest continuation steps, in the scaled arc length (the
        frequency range is 1 in it).
    max_points : int, optional
        The largest number of points.
    tol : float, optional
        Newton's tolerance on the residual's norm relative to the forcing's.
    max_iterations : int, optional
        Newton iterations per point before the step is halved.

    Returns
    -------
    ForcedResponse
        The points (ω, coefficients, contact forces), Newton's iterations and the end status.

    Raises
    ------
    InputError
        A parameter is out of range or of the wrong shape.
    ConvergenceError
        Newton's method fails at the start frequency.
    """
    t0 = time.perf_counter()
    problem, F = _build(
        mass, damping, stiffness, force, contacts, kt, mu, normal_load, harmonics, samples
    )
    n, H, ns, K, B = problem.n, problem.H, problem.ns, problem.K, problem.B
    Kc = 2 * H + 1
    w = finite_array("omega", omega)
    if w.shape != (2,) or w[0] == w[1] or w.min() < 0:
        raise InputError("omega", f"must be (start, stop), distinct and >= 0, got {omega!r}")
    steps = [positive(nm, v) for nm, v in (("step", step), ("max_step", max_step))]
    min_step, tol = positive("min_step", min_step), positive("tol", tol)
    max_points = positive_int("max_points", max_points)
    max_iterations = positive_int("max_iterations", max_iterations)
    kt_e, _ = element_parameters(B.shape[0], kt, mu)
    x_ref = np.abs(np.linalg.solve(K + B.T @ (kt_e[:, None] * B), F[:, 1:3])).max()
    x_ref = x_ref if x_ref > 0 else 1.0
    w_ref = abs(w[1] - w[0])
    r_ref = max(np.linalg.norm(F), np.finfo(float).tiny)

    def newton(z, plane=None):
        """Newton on r = 0 (fixed ω) or on [r; t · (z - z_p)] = 0; (z, iterations, r, T)."""
        for it in range(max_iterations + 1):
            q, om = z[:-1] * x_ref, z[-1] * w_ref
            r, Jq, Jw, T = problem(q, om)
            res = np.linalg.norm(r) / r_ref
            if res <= tol:
                return z, it, res, T, Jq, Jw
            if it == max_iterations or not np.isfinite(res):
                return None, it, res, T, Jq, Jw
            if plane is None:
                z = z.copy()
                z[:-1] -= np.linalg.solve(Jq * x_ref, r)
                continue
            t, zp = plane
            A = np.vstack([np.hstack([Jq * x_ref, (Jw * w_ref)[:, None]]), t[None]])
            z = z - np.linalg.solve(A, np.concatenate([r, [t @ (z - zp)]]))
        return None, it, res, T, Jq, Jw  # pragma: no cover

    z0 = np.concatenate([np.zeros(problem.size), [w[0] / w_ref]])
    z, it, res, T, Jq, Jw = newton(z0)
    if z is None:
        raise ConvergenceError(
            f"Newton's method did not converge at the start frequency ω = {w[0]:g} "
            f"(residual {res:.2e} after {it} iterations): start further from the resonance "
            "or increase max_iterations"
        )
    points, forces, its, resids = [np.append(z[:-1] * x_ref, z[-1] * w_ref)], [T], [it], [res]
    t = np.zeros(problem.size + 1)
    t[-1] = np.sign(w[1] - w[0])
    ds, status = steps[0], "max_points"
    lo, hi = sorted(w / w_ref)
    while len(points) < max_points:
        grow = np.abs(z[:-1]).max()
        if grow > 1.0:  # displacements scaled by the largest reached so far
            x_ref *= grow
            z = np.concatenate([z[:-1] / grow, z[-1:]])
            t = np.concatenate([t[:-1] / grow, t[-1:]])
            t /= np.linalg.norm(t)
        A = np.vstack([np.hstack([Jq * x_ref, (Jw * w_ref)[:, None]]), t[None]])
        t_new = np.linalg.solve(A, np.concatenate([np.zeros(problem.size), [1.0]]))
        t_new /= np.linalg.norm(t_new)
        if len(points) > 1:
            # the step follows the curve's turning (in the scaled variables) and Newton's effort
            turn = np.arccos(np.clip(t_new @ t, -1.0, 1.0))
            factor = min(1.5, max(0.5, _TURN / max(turn, 1e-12)))
            ds = min(max(ds * (factor if it <= 6 else min(factor, 0.7)), min_step), steps[1])
        t = t_new
        while True:
            zp = z + ds * t
            znew, it, res, T, Jq, Jw = newton(zp, (t, zp))
            if znew is not None:
                break
            ds /= 2.0
            if ds < min_step:
                status = "min_step"
                break
        if znew is None:
            break
        if not lo <= znew[-1] <= hi:
            status = "bounds"
            break
        z = znew
        points.append(np.append(z[:-1] * x_ref, z[-1] * w_ref))
        forces.append(T)
        its.append(it)
        resids.append(res)
    Z = np.array(points)
    return ForcedResponse(
        omega=Z[:, -1],
        coefficients=Z[:, :-1].reshape(-1, n, Kc),
        contact_force=np.array(forces),
        iterations=np.array(its),
        residual=np.array(resids),
        harmonics=H,
        samples=ns,
        status=status,
        seconds=time.perf_counter() - t0,
    )
