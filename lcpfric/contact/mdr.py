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
is one monotone piecewise-linear equation in u, solved exactly: its 2n breakpoints ``v_i ∓
b_i/k_i`` are sorted, the segment holding the root is found by bisection on them, and the root
by linear interpolation. O(n log n) per increment; the rank-one coupling of the springs through
the bar is never formed as a matrix. With ``k_support = 0`` the equation has a root only when
``|Q| <= μ P`` (else the whole contact slides): such loads are refused before any work, naming
the instants and the fix (a support stiffness).

Cycles are run by :func:`lcpfric.contact.steady.steady_state` (lcpfric's dissipation of an
increment, the driver's convergence criterion).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError
from .closed_forms import hertz_contact
from .steady import ContactModel

__all__ = ["MDRSphere", "MAX_NODES"]

#: largest number of springs (the arrays are nodes x steps)
MAX_NODES = 200_000


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

    def __init__(self, R, E, nu, mu, P, Q, *, k_support: float = 0.0, nodes: int = 2000):
        super().__init__(E, nu, mu, P, Q, k_support, nodes)
        self.R = _checks.positive("R", R)
        self.a_max = hertz_contact(self.P_max, self.R, self.E, self.nu)["a"]
        self.k_t0 = hertz_contact(self.P0, self.R, self.E, self.nu)["k_t0"]
        self.dx = self.a_max / self.nodes
        self.x = (np.arange(self.nodes) + 0.5) * self.dx
        self.k = np.full(self.nodes, 2.0 * self.moduli["G*"] * self.dx)

    # -- the normal problem ---------------------------------------------------------------------
    def radius(self, t) -> np.ndarray:
        """Hertz contact radius a(t) (0 in separation)."""
        P = np.maximum(np.asarray(self.P(np.asarray(t, dtype=float)), dtype=float), 0.0)
        return (3.0 * P * self.R / (4.0 * self.moduli["E*"])) ** (1.0 / 3.0)

    def normal_forces(self, t) -> np.ndarray:
        """``(len(t), nodes)`` spring normal forces: each cell's exact share of the pressure of
        the 1-D profile (their sum is P(t))."""
        a = self.radius(np.atleast_1d(t))[:, None]
        lo = self.x[None, :] - 0.5 * self.dx
        hi = np.minimum(self.x[None, :] + 0.5 * self.dx, a)
        R = self.R

        def prim(x):  # ∫ (a²/R - x²/R) dx
            return (a * a * x - x ** 3 / 3.0) / R

        return np.where(hi > lo, 2.0 * self.moduli["E*"] * (prim(hi) - prim(lo)), 0.0)

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
        k, ks = self.k, self.k_support
        lo_bp, hi_bp = v - b / k, v + b / k  # below lo: F = +b; above hi: F = -b

        def h(x):
            return float(np.sum(np.clip(k * (v - x), -b, b))) - ks * x + Q

        pts = np.sort(np.concatenate([lo_bp, hi_bp]))
        h_lo, h_hi = h(pts[0]), h(pts[-1])
        if h_lo <= 0.0:  # the root is below every breakpoint: every spring at +b
            if ks == 0.0:
                u1 = pts[0] if h_lo == 0.0 else _no_root(Q, b)
            else:
                u1 = pts[0] + h_lo / ks
        elif h_hi >= 0.0:  # above every breakpoint: every spring at -b
            if ks == 0.0:
                u1 = pts[-1] if h_hi == 0.0 else _no_root(Q, b)
            else:
                u1 = pts[-1] + h_hi / ks
        else:
            i, j = 0, pts.size - 1  # h(pts[i]) > 0 > h(pts[j])
            while j - i > 1:
                mid = (i + j) // 2
                if h(pts[mid]) > 0.0:
                    i = mid
                else:
                    j = mid
            x0, x1 = pts[i], pts[j]
            h0, h1 = h(x0), h(x1)
            u1 = x0 + (x1 - x0) * h0 / (h0 - h1) if h0 != h1 else x0
        F = np.clip(k * (v - u1), -b, b)
        stick = np.abs(k * (v - u1)) <= b
        v1 = np.where(stick, v, u1 + F / k)
        return u1, F, v1


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
