r"""Two bodies of different materials on the half-space grid: the composite moduli, Dundurs'
β, and the coupled influence coefficients (the normal displacements from the shear and the
tangential ones from the pressure) with their products by FFT.

Body 1 is the loaded one (it carries P and Q; lcpfric's friction forces F act on it), with
(E, ν); body 2, the base, has (E2, ν2), or is rigid (``E2 = inf``). With ``G_k = E_k/(2(1 +
ν_k))``:

* ``1/E* = (1 − ν1)/(2 G1) + (1 − ν2)/(2 G2)`` and ``1/G* = (2 − ν1)/(4 G1) + (2 − ν2)/(4 G2)``;
* Dundurs' ``β = ((1 − 2ν1)/G1 − (1 − 2ν2)/G2) / (2 ((1 − ν1)/G1 + (1 − ν2)/G2))``, i.e.
  ``(1 − 2ν1)/(4 G1) − (1 − 2ν2)/(4 G2) = β/E*``; a rigid base: ``β = (1 − 2ν)/(2(1 − ν))``.

Each body's surface displacement from a point force on its surface (Boussinesq and Cerruti;
Johnson, Contact Mechanics, §3.2): a normal force P pulls the surface radially towards it by
``(1 − 2ν) P/(4π G r)``, and a tangential force Q along x moves the surface at the offset
``(x, y)`` into the body by ``(1 − 2ν) Q x/(4π G r²)`` (reciprocal to the former). Summed over
the two bodies (the base receives the opposite tractions), the relative displacements of body
1 against body 2 at a field point get, from a shear traction τ on body 1 and a pressure p,

* the gap: ``+ (β/(π E*)) ∬ τ(x') · (x − x')/|x − x'|² dA'``;
* the slip: ``− (β/(π E*)) ∬ p(x') (x − x')/|x − x'|² dA'``;

(the combined operator is symmetric: the kernel is odd). On square elements of side h with
uniform tractions, the coefficient at the offset D (field minus source) is ``J(D) = ∬ w /|w|²``
over the square centred at D: for the x component the antiderivative of ``x/r²`` (in x and y)
is ``x atan(y/x) + (y/2) ln(x² + y²)``, summed with alternating signs over the four corners; the
y component swaps x and y. ``J(0) = 0``: an element's own pressure does not shift it.

β = 0 (identical bodies, or any pair with ``(1 − 2ν1)/G1 = (1 − 2ν2)/G2``) has no coupling:
the model keeps its uncoupled path.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.fft as sfft

from ... import _checks
from ...errors import InputError

__all__ = ["pair", "attach", "coupling_integrals", "Coupling"]


def _poisson(name, nu):
    nu = _checks.finite(name, nu)
    if not 0.0 <= nu < 0.5:
        raise InputError(name, f"Poisson's ratio must be in [0, 0.5), got {nu!r}")
    return nu


def pair(E: float, nu: float, E2=None, nu2=None) -> dict | None:
    """The composite moduli of body 1 (E, ν) on body 2 (E2, ν2), or None for identical bodies.

    Parameters
    ----------
    E, nu : float
        Body 1 (checked by the caller).
    E2, nu2 : float or None
        Body 2; ``E2 = inf`` is a rigid base (``nu2`` then ignored). Both None: identical
        bodies; a body 2 equal to body 1 is also None (the identical bodies' path).

    Returns
    -------
    dict or None
        ``{"E*", "G*", "G", "eta", "beta", "second"}``: composite moduli, body 1's G,
        ``G*/E*``, Dundurs' β (0 below 1e-12: round-off), and ``second = (E2, nu2)``
        (``(inf, nan)`` when rigid).

    Raises
    ------
    InputError
        ``E2`` not positive (or NaN), or ``nu2`` missing with a finite E2, or out of [0, 0.5).
    """
    if E2 is None and nu2 is None:
        return None
    if E2 is None:
        raise InputError("E2", "give the second body's modulus with nu2 (or E2 = inf: rigid)")
    try:
        E2 = float(E2)
    except (TypeError, ValueError):
        raise InputError("E2", f"must be a number, got {E2!r}") from None
    if math.isnan(E2) or E2 <= 0.0:
        raise InputError("E2", f"must be > 0 (inf: a rigid body), got {E2!r}")
    if math.isinf(E2):
        nu2 = math.nan
    else:
        if nu2 is None:
            raise InputError("nu2", "give the second body's Poisson's ratio with E2")
        nu2 = _poisson("nu2", nu2)
        if E2 == E and nu2 == nu:
            return None
    G1 = E / (2.0 * (1.0 + nu))
    # per body: (1 − ν)/(2G), (2 − ν)/(4G), (1 − 2ν)/(4G); a rigid body adds nothing
    terms = [((1 - nu) / (2 * G1), (2 - nu) / (4 * G1), (1 - 2 * nu) / (4 * G1))]
    if not math.isinf(E2):
        G2 = E2 / (2.0 * (1.0 + nu2))
        terms.append(((1 - nu2) / (2 * G2), (2 - nu2) / (4 * G2), -(1 - 2 * nu2) / (4 * G2)))
    Es = 1.0 / sum(t[0] for t in terms)
    Gs = 1.0 / sum(t[1] for t in terms)
    beta = Es * sum(t[2] for t in terms)
    if abs(beta) < 1e-12:  # round-off of a pair with (1 − 2ν1)/G1 = (1 − 2ν2)/G2: uncoupled
        beta = 0.0
    return {"E*": Es, "G*": Gs, "G": G1, "eta": Gs / Es, "beta": beta, "second": (E2, nu2)}


def attach(model, E2=None, nu2=None):
    """Set a half-space model's materials from body 2 (:func:`pair`): ``moduli`` (composite),
    ``beta``, ``coupling`` (a :class:`Coupling` where β ≠ 0, else None) and ``E2``, ``nu2``
    (body 1's for identical bodies). Returns ``second`` for the influence kernels (None:
    identical bodies)."""
    materials = pair(model.E, model.nu, E2, nu2)
    model.beta, model.coupling, second = 0.0, None, None
    if materials is not None:
        model.moduli, second = materials, materials["second"]
        model.beta = materials["beta"]
        if model.beta != 0.0:
            factor = model.beta / (math.pi * materials["E*"])
            model.coupling = Coupling(model.N, model.h, factor, model.dims)
    model.E2, model.nu2 = second if second is not None else (model.E, model.nu)
    return second


def _atan_term(x, y):
    """``x atan(y/x) + (y/2) ln(x² + y²)`` (0 where x = 0, resp. r = 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(x == 0.0, 0.0, x * np.arctan(y / np.where(x == 0.0, 1.0, x)))
        r2 = x * x + y * y
        b = np.where(r2 == 0.0, 0.0, 0.5 * y * np.log(np.where(r2 == 0.0, 1.0, r2)))
    return a + b


def coupling_integrals(x, y, h):
    """``(J_x, J_y)``: ``∬ w/|w|²`` over the square of side h centred at the offset ``(x, y)``
    (field point minus the element's centre; any broadcastable arrays): odd in x, resp. y."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    Jx = np.zeros(np.broadcast(x, y).shape)
    Jy = np.zeros_like(Jx)
    for sx, sy, sign in ((1, 1, 1.0), (-1, 1, -1.0), (1, -1, -1.0), (-1, -1, 1.0)):
        u, v = x + sx * h / 2, y + sy * h / 2
        Jx += sign * _atan_term(u, v)
        Jy += sign * _atan_term(v, u)
    return Jx, Jy


class Coupling:
    """The coupled influence products on an N x N grid of side h (module docstring), by
    zero-padded FFT (odd kernels: their spectra are imaginary, kept complex).

    Parameters
    ----------
    N, h : int, float
        The grid.
    factor : float
        ``β/(π E*)``.
    dims : {1, 2}
        Tangential components (1: x only).
    """

    def __init__(self, N: int, h: float, factor: float, dims: int = 1):
        self.N, self.h, self.factor, self.dims = int(N), float(h), float(factor), int(dims)
        self.M = sfft.next_fast_len(2 * self.N - 1, real=True)
        k = np.arange(-(self.N - 1), self.N) * self.h
        X, Y = np.meshgrid(k, k, indexing="ij")
        self.kernel = coupling_integrals(X, Y, self.h)[: self.dims]
        self.spectra = [self._spectrum(J) for J in self.kernel]

    def _spectrum(self, k):
        N, M = self.N, self.M
        pad = np.zeros((M, M))
        idx = np.r_[np.arange(0, N), np.arange(M - N + 1, M)]  # offsets 0..N-1, -(N-1)..-1
        src = np.r_[np.arange(N - 1, 2 * N - 1), np.arange(0, N - 1)]
        pad[np.ix_(idx, idx)] = k[np.ix_(src, src)]
        return sfft.rfft2(pad)

    def _convolve(self, field, spectrum):
        N, M = self.N, self.M
        return sfft.irfft2(sfft.rfft2(field, s=(M, M)) * spectrum, s=(M, M))[:N, :N]

    def gap(self, tau) -> np.ndarray:
        """The gap's change ``(N, N)`` from shear tractions on body 1, ``(d, N, N)`` (or
        ``(N, N)`` for d = 1)."""
        tau = np.asarray(tau, dtype=float).reshape(self.dims, self.N, self.N)
        out = np.zeros((self.N, self.N))
        for c in range(self.dims):
            if np.any(tau[c]):
                out += self._convolve(tau[c], self.spectra[c])
        return self.factor * out

    def slip(self, p) -> np.ndarray:
        """The slip's change ``(d, N, N)`` (body 1 against body 2) from pressures ``(N, N)``."""
        p = np.asarray(p, dtype=float).reshape(self.N, self.N)
        return np.stack([-self.factor * self._convolve(p, s) for s in self.spectra])

    def dense(self, component: int = 0) -> np.ndarray:
        """The ``N² x N²`` matrix of the gap from the shear component ``component`` (row-major
        nodes); the slip's component from the pressure is its negative (the same odd J)."""
        N = self.N
        i, j = np.divmod(np.arange(N * N), N)
        J = self.kernel[component]
        return self.factor * J[(i[:, None] - i[None, :]) + N - 1, (j[:, None] - j[None, :]) + N - 1]
