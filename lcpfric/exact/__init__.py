"""The exact periodic steady state of the single node (``method="exact"``).

Discrete systems (a ContactSystem with d = 1, any K, harmonic loads) are solved event by event
in :mod:`lcpfric.exact.discrete` (:func:`exact_system_cycle`); this docstring is about the single
node, whose orbit is entered in one step and vectorized over parameter grids.

Why it is exact
---------------
Write ``w = F̂ - Q̂ = Q̂1 v̂`` (the tangential displacement in units of f P0 / k11) and
``L(θ) = max(P̂(θ), 0)`` with ``θ = ωt``. Coulomb's law (Eq. 8) keeps w inside the moving interval
``[lo(θ), hi(θ)] = [-L - Q̂, L - Q̂]`` and w moves only when an end of the interval pushes it: a
one-dimensional sweeping process (``docs/paper-notes.md``). The dissipation is
``Ŵ = ∮ L |dv̂| = (1/Q̂1) ∮ L |dw|``.

While in contact both ends are pure sinusoids (Eqs. 9-10 with Q0 = 0)::

    lo(θ) = -(1 + R_lo sin(θ + α_lo)),   R_lo e^{iα_lo} = (P̂1 + Q̂1 cos φ) + i Q̂1 sin φ
    hi(θ) =   1 - R_hi sin(θ + α_hi),    R_hi e^{iα_hi} = (Q̂1 cos φ - P̂1) + i Q̂1 sin φ

so every event has a closed form: forward slip (w = lo) ends at the maximum of lo,
``θ + α_lo = 3π/2``, with ``w = R_lo - 1``; backward slip (w = hi) ends at the minimum of hi,
``θ + α_hi = π/2``, with ``w = 1 - R_hi``; the stick that follows ends where the other bound
reaches w; separation starts and ends where ``P̂ = 0``, at ``θ_s = 3π/2 - β`` and
``θ_c = 3π/2 + β``, ``β = atan(g)``, ``g = sqrt(P̂1² - 1)``. A slip segment dissipates
``∫ L |dw| = ½ (L_a² - L_b²) ± Q̂1 ∫ L cos(θ + φ) dθ`` (on a slip segment w = ∓L - Q̂).

Entering the periodic orbit in one step
---------------------------------------
The sweeping process is a contraction, and its steady state is reached exactly:

* with separation (P̂1 >= 1) the interval shrinks to the point ``w = -Q̂`` at re-contact, so
  every history passes through ``(θ_c, -Q̂(θ_c))``: start there;
* without separation, forward slip on the periodic orbit (if there is any slip) ends at the
  maximum of lo, so the orbit passes through ``(3π/2 - α_lo, R_lo - 1)``: start there. If the
  orbit does not slip (shakedown, R_lo + R_hi <= 2) that start sticks for the whole cycle.

One cycle from that start is the steady state; no cycles are iterated. All points of a grid are
advanced together, one event per numpy pass, so a whole map costs a few array operations.

Keeping the digits of short segments
------------------------------------
Event angles are near 10 rad, so an angle computed as a difference of absolute angles carries
an error of ~1e-15 rad. Segments far shorter than 1 rad, or far smaller than the terms that
describe them, decide Ŵ in four places, and each is written in a variable measured from where it
happens:

1. *The last slip before separation* (Q̂1 ≪ P̂1, or φ near 0 or π). Stuck since re-contact,
   w sits ``e = w + Q̂(θ_s) = -2 Q̂1 sin φ sin β`` from the point the interval closes on
   (``Q̂(θ_s) - Q̂(θ_c)`` in closed form), and the bound on the side of e reaches it a short angle
   s before θ_s. In ``s = θ_s - θ``::

       L(s) = g sin s + (1 - cos s),     Q̂(s) = q cos s - q' sin s   (q, q': Q̂, dQ̂/dθ at θ_s)
       lo(s) - w = -e - a sin s - b (1 - cos s),   a = g - q',  b = 1 - q   (forward, e < 0)
       hi(s) - w = -e + a sin s + b (1 - cos s),   a = g + q',  b = 1 + q   (backward, e > 0)

   so the slip starts at the smallest root of ``a sin s + b (1 - cos s) = c = |e|``; with
   t = tan(s/2) that is ``(2b - c) t² + 2a t - c = 0``, whose root
   ``t = c / (a + sqrt(a² + (2b - c) c))`` has no cancellation however small c (:func:`crossing`).
   Its dissipation is ``∫_0^x L(s) (a cos s + b sin s) ds``, in closed form::

       2 J = g a S² + g b (D + S V) + a (S V - D) + b V²,
       S = sin x, V = 1 - cos x = 2 sin²(x/2), D = x - sin x (Taylor series below 0.5)

   for small c every term positive and of the size of the result (:func:`sform_W`, with x/c and
   c/Q̂1 so that x below the smallest double still gives Ŵ). With x ≈ c/a, J ≈ g c²/(2a), hence
   for Q̂1 ≪ g the asymptote ``Ŵ ≈ 2 Q̂1 sin²φ (1 - 1/P̂1²)`` (checked in the tests). The
   earlier θ-form lost this segment entirely below Q̂1/P̂1 ≈ 1e-15 (``exact_W_hat(2, 1e-15, 1)``
   returned 0 for 1.06e-15) and lost digits as eps/x above. If the bound turns before θ_s
   (a < 0) the slip ends at its extremum ``s_m = atan2(-a, b)``, also in s.
2. *The stick at an extremum when Q̂1 ≫ 1*: after forward slip, hi falls to ``w = R_lo - 1`` at
   the angle ``τ`` after the maximum with ``τ + Δ = 2 asin(sqrt((2 - (R_lo - R_hi)) / (2 R_hi)))``,
   ``R_lo - R_hi = 4 P̂1 Q̂1 cos φ / (R_lo + R_hi)``, ``Δ = α_hi - α_lo
   = atan2(2 P̂1 Q̂1 sin φ, Q̂1² - P̂1²)`` (and symmetrically after backward slip;
   :func:`_stick_angles`). The arcsine of ``(1 - w)/R_hi`` next to -1 used before lost half the
   digits of τ ~ Q̂1^(-1/2): at Q̂1 = 1e17 Ŵ came out 2 instead of 4.
3. *Slips next to the minimum of P̂ when P̂1 is close to 1* (L ~ Q̂1²): L and ``∫ L cos(θ + φ)``
   are written in ``u = θ - 3π/2`` with half-angle products (:func:`slip_integral`), and
   ``R_lo - 1 = (R_lo² - 1)/(R_lo + 1)`` with ``R_lo² - 1 = (P̂1 - 1)(P̂1 + 1) + Q̂1 (2 P̂1 cos φ
   + Q̂1)`` (:func:`_extrema`).
4. *A bound that barely moves while L and Q̂ change by O(1)* (R ≪ P̂1, e.g. Q̂1 = P̂1 with φ
   small): there ``½ (L_a² - L_b²) ± Q̂1 ∫ L cos(θ + φ)`` is the difference of terms a million
   times larger than the result, and the slip is integrated as ``R ∫ L cos(θ + α)`` instead; each
   slip takes the form whose terms are smaller (:func:`slip_integral`). At
   (P̂1, Q̂1, φ) = (1e3, 1e3, 1e-9) the split form alone was 19 % off.

φ enters through sin φ and cos φ of the caller's value (exact to round-off for any φ); angles use
φ reduced through them. Dissipation is accumulated as Ŵ, slip by slip, so no product of two
amplitudes is formed: P̂1, Q̂1 up to :data:`MAX_AMPLITUDE` = 1e300 are accepted.

Accuracy
--------
Checked against an independent mpmath solution (``tests/support/exact_reference.py``: 60 digits
plus twice the decimal exponents of the inputs, started from w = 0 and run to the periodic
cycle, slip integrals from a different antiderivative; itself checked against Eqs. (11)/(12),
the energy identity ∮ L|dw| = ∮ w dQ̂, a fine-grid simulation and the asymptote above) by
``benchmarks/validation/exact_audit.py``. On 20000 points (P̂1 and Q̂1 log-uniform over [1e-20, 1e20],
Q̂1/P̂1 log-uniform over [1e-20, 1e20], and the borders below; ``benchmarks/results/
exact-audit.md``) the worst relative error where Ŵ is well-conditioned is 1.5e-12, scalar and
vectorized paths alike: the result is within 1e-9 relative of the exact Ŵ, however small Ŵ is.
Where Ŵ is ill-conditioned — next to the border of a zero régime (shakedown, or Q̂1 = P̂1 at
φ = 0 or π), and next to P̂1 = 1 with Q̂1 ≲ 1e-4, where the minimum of L is below the round-off
of P̂ — the error is within the change of the exact Ŵ when the inputs move by 16 units of
round-off (relative for P̂1 and Q̂1, absolute ``16 eps max(1, |φ|)`` for φ): the answer is exact
for inputs indistinguishable from the given ones. Results in the subnormal range (below
2.2e-308) carry the absolute error of that range.
"""

from .api import ExactCycle, exact_cycle, exact_W_hat
from .formulas import BACKWARD, FORWARD, MAX_AMPLITUDE, SEPARATION, STICK


def __getattr__(name):
    # the discrete systems' event solver is imported when it is first asked for: the single
    # node's closed form (and the command line's start-up) does not pay for it
    if name == "exact_system_cycle":
        from .discrete import exact_system_cycle

        return exact_system_cycle
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "exact_W_hat",
    "ExactCycle",
    "exact_cycle",
    "exact_system_cycle",
    "STICK",
    "FORWARD",
    "BACKWARD",
    "SEPARATION",
    "MAX_AMPLITUDE",
]
