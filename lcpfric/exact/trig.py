"""Real trigonometric polynomials ``f(θ) = c_0 + Σ_k (c_k cos kθ + s_k sin kθ)``: products,
exact integrals and Fourier moments over any interval, and every sign change in an interval.

The sign changes are what the displacement-driven element's events are (:mod:`.driven`). They are
found without sampling: ``z^H f`` is a polynomial of degree 2H in ``z = e^{iθ}``, whose roots on
the unit circle (the eigenvalues of its companion matrix, :func:`numpy.polynomial.polynomial.
polyroots`) are the real roots of ``f``. The roots of ``f'`` split the interval into pieces on
which ``f`` is monotone; a piece whose ends differ in sign holds exactly one root, refined by
Newton's method kept inside the bracket, to the last bit. Roots of ``f'`` are taken generously
(up to 1e-4 off the circle): an extra piece boundary costs one evaluation, a missing one could
hide two roots. A tangency (``f`` touching zero) is not a sign change.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["TrigPoly", "sign_changes", "periodic_sign_changes", "solve_bracket"]

TWO_PI = 2.0 * math.pi
#: how far off the unit circle a root of f' may be and still split f's pieces
CIRCLE_TOL = 1e-4


class TrigPoly:
    """A real trigonometric polynomial in θ, immutable.

    Parameters
    ----------
    cos : array_like
        ``c_0, c_1, ..., c_H``: the mean and the cosine coefficients.
    sin : array_like, optional
        ``s_0, ..., s_H`` (``s_0`` is ignored); default zeros.

    Attributes
    ----------
    cos, sin : ndarray
        The coefficients, of one length ``H + 1`` (``sin[0] = 0``).
    """

    __slots__ = ("cos", "sin")

    def __init__(self, cos, sin=None):
        c = np.atleast_1d(np.asarray(cos, dtype=float)).ravel()
        s = np.zeros(1) if sin is None else np.atleast_1d(np.asarray(sin, dtype=float)).ravel()
        n = max(c.size, s.size, 1)
        cc, ss = np.zeros(n), np.zeros(n)
        cc[: c.size], ss[: s.size] = c, s
        ss[0] = 0.0
        self.cos, self.sin = cc, ss

    @classmethod
    def from_load(cls, load, omega: float) -> TrigPoly:
        """A :class:`~lcpfric.model.Fourier` load ``mean + Σ a_k sin(k ω_L t + ψ_k)`` in
        θ = ω t, where ``ω_L`` is a whole multiple of ``omega``.

        Parameters
        ----------
        load : Fourier
            The load (a :class:`~lcpfric.model.Harmonic` is one).
        omega : float
            The fundamental ω of θ = ω t.

        Returns
        -------
        TrigPoly
            The same function of θ.
        """
        amps, phases = np.asarray(load.amplitudes, float), np.asarray(load.phases, float)
        ratio = 1 if not np.any(amps) else round(load.omega / omega)
        n = ratio * amps.size + 1
        c, s = np.zeros(n), np.zeros(n)
        c[0] = load.mean
        k = ratio * np.arange(1, amps.size + 1)
        c[k], s[k] = amps * np.sin(phases), amps * np.cos(phases)
        return cls(c, s)

    @property
    def degree(self) -> int:
        """The highest harmonic with a nonzero coefficient (0 for a constant)."""
        nz = np.nonzero((self.cos[1:] != 0) | (self.sin[1:] != 0))[0]
        return int(nz[-1] + 1) if nz.size else 0

    def __call__(self, theta):
        """``f(θ)`` at the angles ``theta`` (a float for a scalar)."""
        th = np.asarray(theta, dtype=float)
        k = np.arange(1, self.cos.size)
        arg = th[..., None] * k
        out = self.cos[0] + np.cos(arg) @ self.cos[1:] + np.sin(arg) @ self.sin[1:]
        return float(out) if out.ndim == 0 else out

    def derivative(self) -> TrigPoly:
        """``df/dθ``.

        Returns
        -------
        TrigPoly
            The derivative.
        """
        k = np.arange(self.cos.size, dtype=float)
        return TrigPoly(k * self.sin, -k * self.cos)

    def __add__(self, other):
        if not isinstance(other, TrigPoly):
            return TrigPoly(np.r_[self.cos[0] + other, self.cos[1:]], self.sin)
        n = max(self.cos.size, other.cos.size)
        c, s = np.zeros(n), np.zeros(n)
        c[: self.cos.size] += self.cos
        s[: self.sin.size] += self.sin
        c[: other.cos.size] += other.cos
        s[: other.sin.size] += other.sin
        return TrigPoly(c, s)

    __radd__ = __add__

    def __neg__(self):
        return TrigPoly(-self.cos, -self.sin)

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        if not isinstance(other, TrigPoly):
            return TrigPoly(other * self.cos, other * self.sin)
        full = np.convolve(self.complex(), other.complex())
        h = (full.size - 1) // 2
        return TrigPoly(
            np.r_[full[h].real, 2.0 * full[h + 1 :].real], np.r_[0.0, -2.0 * full[h + 1 :].imag]
        )

    __rmul__ = __mul__

    def complex(self) -> np.ndarray:
        """The coefficients ``d_j`` of ``f = Σ_{j=-H}^{H} d_j e^{ijθ}``, index ``j + H``.

        Returns
        -------
        ndarray of complex
            Length ``2H + 1`` (H = ``len(cos) - 1``).
        """
        half = 0.5 * (self.cos[1:] - 1j * self.sin[1:])
        return np.r_[np.conj(half[::-1]), self.cos[0], half]

    def integral(self, a: float, b: float) -> float:
        """``∫_a^b f dθ`` in closed form (differences of sines as products: short intervals keep
        their digits).

        Parameters
        ----------
        a, b : float
            The limits.

        Returns
        -------
        float
            The integral.
        """
        k = np.arange(1, self.cos.size)
        c, h = 0.5 * (a + b), 0.5 * (b - a)
        sh = 2.0 * np.sin(k * h) / k
        return float(
            self.cos[0] * (b - a) + np.sum((self.cos[1:] * np.cos(k * c) + self.sin[1:] *
                                            np.sin(k * c)) * sh)
        )  # fmt: skip

    def moments(self, a: float, b: float, harmonics: int) -> np.ndarray:
        """``∫_a^b f(θ) e^{-ikθ} dθ`` for ``k = 0..harmonics``.

        Parameters
        ----------
        a, b : float
            The limits.
        harmonics : int
            The highest k.

        Returns
        -------
        ndarray of complex
            Length ``harmonics + 1``.
        """
        d = self.complex()
        H = self.cos.size - 1
        j = np.arange(-H, H + 1)
        m = j[None, :] - np.arange(harmonics + 1)[:, None]
        c, h = 0.5 * (a + b), 0.5 * (b - a)
        if b - a == TWO_PI:  # a whole period: only the k-th coefficient remains, exactly
            out = np.zeros(harmonics + 1, dtype=complex)
            k = np.arange(min(harmonics, H) + 1)
            out[k] = TWO_PI * d[H + k]
            return out
        safe = np.where(m == 0, 1, m)
        E = np.where(m == 0, b - a, 2.0 * np.sin(m * h) / safe) * np.exp(1j * m * c)
        return E @ d

    def circle_angles(self, tol: float = CIRCLE_TOL) -> np.ndarray:
        """Angles in ``[0, 2π)`` of the roots of ``z^H f`` within ``tol`` of the unit circle.

        Parameters
        ----------
        tol : float, optional
            The largest ``||z| - 1|`` kept.

        Returns
        -------
        ndarray
            Sorted candidate roots of f (every real root, and perhaps some near misses).
        """
        H = self.degree
        if H == 0:
            return np.empty(0)
        d = TrigPoly(self.cos[: H + 1], self.sin[: H + 1]).complex()
        z = np.polynomial.polynomial.polyroots(d / np.max(np.abs(d)))
        z = z[np.abs(np.abs(z) - 1.0) < tol]
        return np.sort(np.mod(np.angle(z), TWO_PI))


def _in_interval(angles, t0, t1):
    """The angles (mod 2π) that fall in the open interval (t0, t1), t1 - t0 <= 2π, sorted."""
    if angles.size == 0:
        return angles
    shifted = t0 + np.mod(angles - t0, TWO_PI)
    return np.sort(shifted[(shifted > t0) & (shifted < t1)])


def solve_bracket(f: TrigPoly, df: TrigPoly, left: float, right: float, sign_left: float):
    """The root of ``f`` in ``[left, right]`` where ``f`` changes sign (``sign_left`` is the sign
    of f at ``left``), monotone there: Newton's method kept inside the bracket.

    Parameters
    ----------
    f, df : TrigPoly
        The function and its derivative.
    left, right : float
        The bracket.
    sign_left : float
        +1 or -1.

    Returns
    -------
    float
        The root, to the last bit.
    """
    t = 0.5 * (left + right)
    for _ in range(200):
        v = f(t)
        if v == 0.0:
            return t
        if (v > 0.0) == (sign_left > 0.0):
            left = t
        else:
            right = t
        d = df(t)
        nxt = t - v / d if d != 0.0 else math.nan
        if abs(nxt - t) <= 4.0 * math.ulp(t) and left <= nxt <= right:
            return nxt  # Newton's step is below round-off: converged
        if not (left < nxt < right):
            nxt = 0.5 * (left + right)  # keep to the bracket
            if right - left <= 4.0 * math.ulp(max(abs(left), abs(right))):
                return nxt
        t = nxt
    return t  # pragma: no cover - the bracket halves at worst


def sign_changes(f: TrigPoly, t0: float, t1: float) -> tuple[np.ndarray, np.ndarray]:
    """Every instant in (t0, t1) where ``f`` changes sign, and the direction.

    Parameters
    ----------
    f : TrigPoly
        The function.
    t0, t1 : float
        The interval, ``0 < t1 - t0 <= 2π``.

    Returns
    -------
    roots : ndarray
        Sorted instants in (t0, t1).
    directions : ndarray of int
        +1 where f rises through zero, -1 where it falls.
    """
    if f.degree == 0:
        return np.empty(0), np.empty(0, dtype=int)
    df = f.derivative()
    cuts = np.r_[t0, _in_interval(df.circle_angles(), t0, t1), t1]
    vals = f(cuts)
    roots, dirs = [], []
    last, last_at = 0.0, None  # the last nonzero sign and its index
    for i, v in enumerate(vals):
        if v == 0.0:
            continue
        s = 1.0 if v > 0.0 else -1.0
        if last != 0.0 and s != last:
            if last_at == i - 1:
                roots.append(solve_bracket(f, df, cuts[i - 1], cuts[i], last))
            else:  # zeros in between: f is monotone between cuts, so the root is a zero cut
                roots.append(cuts[last_at + 1])
            dirs.append(int(s))
        last, last_at = s, i
    return np.asarray(roots, dtype=float), np.asarray(dirs, dtype=int)


def periodic_sign_changes(f: TrigPoly) -> tuple[np.ndarray, np.ndarray]:
    """Every sign change of ``f`` over one period, as angles in ``[0, 2π)``.

    The period is searched from the piece boundary where ``|f|`` is largest, so that no root
    sits on the ends of the search.

    Parameters
    ----------
    f : TrigPoly
        The function.

    Returns
    -------
    roots : ndarray
        Sorted angles in ``[0, 2π)``.
    directions : ndarray of int
        +1 where f rises through zero, -1 where it falls.
    """
    if f.degree == 0:
        return np.empty(0), np.empty(0, dtype=int)
    cand = np.r_[0.0, f.derivative().circle_angles()]
    t0 = float(cand[np.argmax(np.abs(f(cand)))])
    roots, dirs = sign_changes(f, t0, t0 + TWO_PI)
    roots = np.mod(roots, TWO_PI)
    roots[roots >= TWO_PI] = 0.0
    order = np.argsort(roots, kind="stable")
    return roots[order], dirs[order]
