r"""The Hertz contact (sphere) by the method of dimensionality reduction (Popov and Heß), d = 1.

Two identical elastic spheres (effective radius R, each of modulus E and ratio ν; composite
moduli E*, G* of :func:`~lcpfric.contact.closed_forms.moduli`) under a normal load P(t) and a
tangential load Q(t) along one direction. The method of dimensionality reduction maps the 3-D
contact onto a row of independent springs on a rigid bar, the 1-D profile ``g(x) = x²/R``:

* **normal** (known before any tangential computation: the problems are uncoupled): at each
  instant the approach ``d = a²/R`` with the Hertz radius ``a = (3PR/(4E*))^(1/3)``; spring i
  on the cell ``[x_i - Δx/2, x_i + Δx/2]`` of ``[0, a_max]`` carries the normal force
  ``N_i = 2 E* ∫_cell max(0, d - x²/R) dx`` (the cell's exact share: ``Σ N_i = P`` exactly;
  the factor 2 counts the springs at ``±x``, which behave alike). ``P <= 0`` is complete
  separation;
* **tangential**: spring stiffness ``k_i = 2 G* Δx`` (so ``Σ k_i = 2 a G* = k_t0`` in full
  stick), spring force ``k_i (u - v_i)`` with ``v_i`` the slip of spring i and ``u`` the bar's
  displacement, ``|k_i (u - v_i)| <= μ N_i``; the bar is held by Q(t) and, in parallel with the
  contact, by a support of stiffness ``k_support`` (the structure that holds the body; 0 is
  pure load control): ``Σ_i k_i (u - v_i) + k_support u = Q``.

Within Mindlin's approximation this reproduces the 3-D contact (exactly when ν = 0): the 1-D
stick zone ``|x| < c`` is the 3-D stick radius, and the dissipation is the 3-D one.

The increment (no solver: a closed form serves)
-----------------------------------------------
The increment to ``t_{j+1}`` is problem (P) of the other backends, the maximum-dissipation
projection of the trial state, for this system: given the bar's displacement u the springs are
independent, and each one's answer is its return mapping ``F_i(u) = clip(k_i (v_i - u), -b_i,
b_i)``, ``b_i = μ N_i(t_{j+1})`` (lcpfric's sign: ``F_i = k_i (v_i - u)`` is the friction
force, and the slip opposes it). The bar's equilibrium ``h(u) = Σ F_i(u) - k_support u + Q = 0``
is one monotone piecewise-linear equation in u, solved exactly (:func:`bar_root`: a safeguarded
Newton iteration from the previous u, exact once a step keeps every spring on its side of its
breakpoints ``v_i ∓ b_i/k_i``; usually two or three O(n) passes); the rank-one coupling of the springs through
the bar is never formed as a matrix. With ``k_support = 0`` the equation has a root only when
``|Q| <= μ P`` (else the whole contact slides): such loads are refused before any work, naming
the instants and the fix (a support stiffness).

Cycles are run by :func:`lcpfric.contact.steady.steady_state` (lcpfric's dissipation of an
increment, the driver's convergence criterion).

Other axisymmetric profiles
---------------------------
``profile=`` replaces the sphere by any axisymmetric body ``z = f(r)``: :class:`PowerLaw`
(``f = c r^n``, in closed form: ``g = κ_n c |x|^n``, ``κ_n = √π Γ(n/2 + 1) / Γ(n/2 + 1/2)``) or
:class:`Axisymmetric` (any ``f'``, the MDR transform ``g(x) = |x| ∫_0^{π/2} f'(|x| sin θ) dθ``
by Gauss-Legendre quadrature). The contact radius at a load solves ``P = 2 E* (a g(a) -
∫_0^a g)``, the approach is ``d = g(a)``, the spring forces are the cells' exact shares of
``2 E* (d - g)`` as for the sphere.
"""

from __future__ import annotations

from dataclasses import dataclass

import math

import numpy as np

from .. import _checks
from ..errors import InputError
from .steady import ContactModel

__all__ = ["MDRSphere", "MAX_NODES", "Sphere", "PowerLaw", "Axisymmetric", "bar_increment",
           "bar_root"]

#: largest number of springs (the arrays are nodes x steps)
MAX_NODES = 200_000


class Sphere:
    """The sphere ``f = r²/(2R)``: ``g = x²/R``."""

    def __init__(self, R):
        self.R = _checks.positive("R", R)

    def g(self, x):
        return np.asarray(x) ** 2 / self.R

    def G(self, x):
        """``∫_0^x g``."""
        x = np.asarray(x)
        return x * x * x / (3.0 * self.R)

    def radius(self, P, Estar):
        return (3.0 * np.maximum(P, 0.0) * self.R / (4.0 * Estar)) ** (1.0 / 3.0)


class PowerLaw:
    """``f = c r^n`` (n > 0; n = 2, c = 1/(2R) is the sphere): ``g = κ_n c |x|^n``."""

    def __init__(self, c, n):
        self.c = _checks.positive("c", c)
        self.n = _checks.positive("n", n)
        self.kappa = math.sqrt(math.pi) * math.gamma(self.n / 2 + 1) / math.gamma(self.n / 2
                                                                                  + 0.5)

    def g(self, x):
        return self.kappa * self.c * np.abs(np.asarray(x)) ** self.n

    def G(self, x):
        x = np.asarray(x)
        return self.kappa * self.c * x ** (self.n + 1) / (self.n + 1)

    def radius(self, P, Estar):
        k = 2.0 * Estar * self.kappa * self.c * self.n / (self.n + 1)
        return (np.maximum(P, 0.0) / k) ** (1.0 / (self.n + 1))


class Axisymmetric:
    """Any axisymmetric body by its slope ``f'(r)`` (vectorized, ``f'(0) = 0``, increasing
    enough that the contact is one disc): the MDR transform by 64-point Gauss-Legendre
    quadrature on a table of 4097 points, interpolated by a cubic spline (its antiderivative
    gives ``∫ g``), the table widened when asked beyond it; the contact radius by bisection."""

    _POINTS = 4097

    def __init__(self, slope):
        if not callable(slope):
            raise InputError("profile", "Axisymmetric needs the slope f'(r) as a callable")
        self.slope = slope
        self._t, self._w = np.polynomial.legendre.leggauss(64)
        self._X = 0.0

    def transform(self, x):
        """``g(x) = |x| ∫_0^{π/2} f'(|x| sin θ) dθ`` by quadrature (no table)."""
        x = np.abs(np.asarray(x, dtype=float))
        theta = 0.25 * math.pi * (self._t + 1.0)                # [0, π/2]
        vals = np.asarray(self.slope(x[..., None] * np.sin(theta)), dtype=float)
        return x * (vals @ self._w) * 0.25 * math.pi

    def _table(self, x):
        top = float(np.max(np.abs(x), initial=0.0))
        if top <= self._X:
            return
        from scipy.interpolate import CubicSpline

        X = max(top, 2.0 * self._X)
        xs = np.linspace(0.0, X, self._POINTS)
        gs = self.transform(xs)
        if not np.all(np.isfinite(gs)):
            raise InputError("profile", "the slope f'(r) gave non-finite values")
        self._g = CubicSpline(xs, gs)
        self._G = self._g.antiderivative()
        self._X = X

    def g(self, x):
        self._table(x)
        return self._g(np.abs(np.asarray(x, dtype=float)))

    def G(self, x):
        self._table(x)
        return self._G(np.asarray(x, dtype=float))

    def radius(self, P, Estar):
        P = np.atleast_1d(np.maximum(np.asarray(P, dtype=float), 0.0))
        lo, hi = np.zeros_like(P), np.ones_like(P)

        def load(a):
            return 2.0 * Estar * (a * self.g(a) - self.G(a))

        for _ in range(200):  # grow the bracket
            short = load(hi) < P
            if not short.any():
                break
            hi = np.where(short, 2.0 * hi, hi)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            below = load(mid) < P
            lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
        return np.where(P > 0, 0.5 * (lo + hi), 0.0)


class MDRSphere(ContactModel):
    """The Hertz contact of two identical spheres, by dimensionality reduction (see the module
    docstring).

    Parameters
    ----------
    R, E, nu, mu : float
        Effective radius, each body's Young's modulus and Poisson's ratio (``0 <= ν < 0.5``),
        friction coefficient.
    P, Q : Load or float
        Normal and tangential loads (total forces); floats are constant loads. P(t) <= 0 is
        complete separation.
    k_support : float
        Tangential stiffness of the support in parallel with the contact (0: pure load
        control, where ``|Q| > μP`` at any instant is refused).
    nodes : int
        Springs on ``[0, a_max]``, a_max the largest contact radius over the cycle.
    """

    max_nodes = MAX_NODES

    def __init__(self, R, E, nu, mu, P, Q, *, k_support: float = 0.0, nodes: int = 2000,
                 profile=None):
        super().__init__(E, nu, mu, P, Q, k_support, nodes)
        self.R = None if R is None else _checks.positive("R", R)
        if profile is None:
            if self.R is None:
                raise InputError("R", "give the effective radius R, or a profile")
            profile = Sphere(self.R)
        for name in ("g", "G", "radius"):
            if not callable(getattr(profile, name, None)):
                raise InputError("profile", f"needs a method {name}() (see Sphere, PowerLaw, "
                                            f"Axisymmetric)")
        self.profile = profile
        Es = self.moduli["E*"]
        self.a_max = float(np.max(profile.radius(self.P_max, Es)))
        self.a0 = float(np.max(profile.radius(self.P0, Es)))
        self.k_t0 = 2.0 * self.a0 * self.moduli["G*"]
        self.dx = self.a_max / self.nodes
        self.x = (np.arange(self.nodes) + 0.5) * self.dx
        self.k = np.full(self.nodes, 2.0 * self.moduli["G*"] * self.dx)

    # -- the normal problem ---------------------------------------------------------------------
    def radius(self, t) -> np.ndarray:
        """Contact radius a(t) (0 in separation): Hertz's for the sphere."""
        P = np.maximum(np.asarray(self.P(np.asarray(t, dtype=float)), dtype=float), 0.0)
        return np.asarray(self.profile.radius(P, self.moduli["E*"]), dtype=float).reshape(P.shape)

    def approach(self, P) -> np.ndarray:
        """The normal approach d = g(a(P)) (the C(P) of the Ciavarella-Jäger form)."""
        P = np.asarray(P, dtype=float)
        d = np.asarray(self.profile.g(self.profile.radius(P, self.moduli["E*"])), dtype=float)
        return float(d.ravel()[0]) if P.ndim == 0 else d.reshape(P.shape)

    def normal_forces(self, t) -> np.ndarray:
        """``(len(t), nodes)`` spring normal forces: each cell's exact share of the pressure of
        the 1-D profile (their sum is P(t))."""
        a = self.radius(np.atleast_1d(t))[:, None]
        lo = self.x[None, :] - 0.5 * self.dx
        hi = np.minimum(self.x[None, :] + 0.5 * self.dx, a)
        d, G = self.profile.g(a), self.profile.G
        share = d * (hi - lo) - (G(np.maximum(hi, lo)) - G(lo))   # ∫_cell (d - g) dx
        return np.where(hi > lo, 2.0 * self.moduli["E*"] * share, 0.0)

    def tractions(self, F) -> np.ndarray:
        """The 3-D shear traction at the spring positions (as radii) from spring forces F: the
        inverse MDR transform ``τ(r) = -(1/π) ∫_r^a q'(x) / √(x² - r²) dx`` of the line load
        ``q = F / (2 Δx)``, taken piecewise linear between the spring positions (flat at the
        centre, zero half a cell beyond the last spring), so that each piece integrates in
        closed form: ``∫ dx / √(x² - r²) = ln(x + √(x² - r²))``. lcpfric's force sign: the
        traction transmitted is ``-τ``; from the normal forces it gives the pressure."""
        q = np.append(np.asarray(F, dtype=float) / (2.0 * self.dx), 0.0)
        X = np.append(self.x, self.x[-1] + 0.5 * self.dx)
        slope = np.diff(q) / np.diff(X)                          # on [X_k, X_k+1]
        r = self.x[:, None]

        def L(x):
            return np.log(x + np.sqrt(np.maximum(x * x - r * r, 0.0)))

        lo = np.maximum(X[None, :-1], r)
        hi = X[None, 1:]
        piece = np.where(hi > r, L(hi) - L(np.minimum(lo, hi)), 0.0)
        return -(piece @ slope) / math.pi

    # -- as an lcpfric system ---------------------------------------------------------------
    def load_at_radius(self, a) -> np.ndarray:
        """The normal load whose contact radius is a: ``2 E* (a g(a) - ∫_0^a g)``."""
        a = np.asarray(a, dtype=float)
        return 2.0 * self.moduli["E*"] * (a * self.profile.g(a) - self.profile.G(a))

    def entry_loads(self) -> np.ndarray:
        """Per spring, the normal load at which it comes into contact (the contact radius
        reaches its cell's inner edge)."""
        return np.asarray(self.load_at_radius(self.x - 0.5 * self.dx), dtype=float)

    def springs(self):
        """``(compliance operator, C⁻¹ 1)`` of the springs alone (the bar held fixed):
        ``diag(1/k)`` and ``k``, for :meth:`ContactModel.system`."""
        from scipy.sparse.linalg import aslinearoperator
        import scipy.sparse as sp

        return aslinearoperator(sp.diags(1.0 / self.k)), self.k.copy(), 1.0 / self.k

    # -- the model protocol of lcpfric.contact.steady ------------------------------------------
    def limits(self, t) -> np.ndarray:
        """Friction limits ``μ N_i(t)``, ``(len(t), nodes)``."""
        return self.mu * self.normal_forces(t)

    def sizes(self, t) -> np.ndarray:
        return self.radius(t)

    def start(self) -> "_Bar":
        return _Bar(np.zeros(self.nodes), 0.0)

    def scales(self) -> tuple[float, float]:
        q = self.Q.amplitude if not self.Q.is_constant else abs(self.Q.mean)
        return q / self.k_t0, self.mu * self.P_max

    def normalization(self) -> tuple[str, float]:
        return "W k_t0/(mu^2 P0^2)", self.k_t0 / (self.mu * self.P0) ** 2

    def increment(self, state, b, Q):
        """The exact increment to the next instant (module docstring)."""
        u, F, v = self._increment(state.v, state.u, b, Q)
        return _Bar(v, u), F, v - state.v

    def _increment(self, v, u, b, Q):
        """The exact increment (module docstring): ``(u, F, v)`` at the next instant."""
        if self.k_support == 0.0 and abs(Q) > float(b.sum()) * (1.0 + 1e-12):
            _no_root(Q, b)
        u1, F, v1 = bar_increment(v[None], np.array([u]), self.k[None], b[None],
                                  np.array([Q]), self.k_support)
        return float(u1[0]), F[0], v1[0]


def bar_increment(v, u, k, b, Q, ks):
    """The increment of m bars at once (rows of the ``(m, n)`` arrays v, k, b; u and Q of
    length m): the bar displacements (:func:`bar_root`), then each spring's return mapping.
    Returns ``(u, F, v)``."""
    u1 = bar_root(v, u, k, b, Q, ks)
    trial = k * (v - u1[:, None])
    F = np.minimum(np.maximum(trial, -b), b)
    return u1, F, np.where(np.abs(trial) <= b, v, u1[:, None] + F / k)


def bar_root(v, u, k, b, Q, ks):
    """The bar displacement of every row: the root of ``h(u) = Σ clip(k (v - u), -b, b) - ks
    u + Q`` (decreasing in u), by a safeguarded Newton iteration from the previous u. h is
    linear between the breakpoints ``v ∓ b/k``, so a step that keeps every spring's stick/slip
    side lands on the root exactly; a bracket keeps the iteration inside. Under pure load
    control with |Q| beyond every limit there is no root: the caller checks."""
    lo = np.min(v - b / k, axis=1)   # below: every spring at +b
    hi = np.max(v + b / k, axis=1)   # above: every spring at -b
    total = b.sum(axis=1)
    h_lo = total - ks * lo + Q
    h_hi = -total - ks * hi + Q
    out = np.empty_like(u)
    below, above = h_lo <= 0.0, h_hi >= 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        out[below] = np.where(ks > 0, lo[below] + h_lo[below] / ks, lo[below])
        out[above] = np.where(ks > 0, hi[above] + h_hi[above] / ks, hi[above])
    inside = ~(below | above)
    if not inside.any():
        return out
    i = np.flatnonzero(inside)
    every = i.size == u.size
    vv, kk, bb, qq = (v, k, b, Q) if every else (v[i], k[i], b[i], Q[i])
    L, H = lo[i].copy(), hi[i].copy()
    x = np.clip(u[i], L, H)
    todo = None  # None: every point (no gathering on the first, usually last, iteration)
    eps = 4 * np.finfo(float).eps
    for _ in range(200):
        if todo is None:
            xv, Vv, Kv, Bv, qv, Lt, Ht = x, vv, kk, bb, qq, L, H
        else:
            xv, Vv, Kv, Bv, qv = x[todo], vv[todo], kk[todo], bb[todo], qq[todo]
            Lt, Ht = L[todo], H[todo]
        t = Kv * (Vv - xv[:, None])
        c = np.minimum(np.maximum(t, -Bv), Bv)
        side = np.sign(c - t)                             # 0: sticking; ±1: at -b / +b
        h = c.sum(axis=1) - ks * xv + qv
        slope = -(Kv * (side == 0)).sum(axis=1) - ks
        Lt = np.where(h > 0.0, xv, Lt)
        Ht = np.where(h < 0.0, xv, Ht)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(slope < 0.0, xv - h / slope, 0.5 * (Lt + Ht))
        step = np.where((step >= Lt) & (step <= Ht), step, 0.5 * (Lt + Ht))
        new = np.where(h == 0.0, xv, step)
        t2 = Kv * (Vv - new[:, None])
        same = np.all(np.sign(np.minimum(np.maximum(t2, -Bv), Bv) - t2) == side, axis=1)
        finished = ((h == 0.0) | (same & (slope < 0.0)) | (new == xv)
                    | (Ht - Lt <= eps * np.maximum(np.abs(Lt), np.abs(Ht))))
        if todo is None:
            x, L, H = new, Lt, Ht
            todo = np.flatnonzero(~finished)
        else:
            x[todo], L[todo], H[todo] = new, Lt, Ht
            todo = todo[~finished]
        if not todo.size:
            break
    out[i] = x
    return out


@dataclass
class _Bar:
    """The tangential state: the springs' slips v and the bar's displacement u."""

    v: np.ndarray
    u: float


def _no_root(Q, b):
    raise InputError("k_support", f"is 0 and |Q| = {abs(Q):.6g} exceeds the friction limit "
                                  f"μP = {float(np.sum(b)):.6g} of the whole contact at an "
                                  f"increment: gross sliding has no equilibrium under pure load "
                                  f"control; give k_support > 0")
