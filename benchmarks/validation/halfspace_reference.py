"""Independent reference: frictionless, non-periodic Hertz-like contact on an elastic half-space.

    # writes tests/data/halfspace_reference.npz
    python benchmarks/validation/halfspace_reference.py

Produced with **ContactMechanics 1.8.3** (Pastewka group, github pastewka/ContactMechanics;
with SurfaceTopography 1.27.1, NuMPI 0.18.1, muGrid 1.6.1), *not* with lcpfric. It needs
that library installed, in its own environment so as not to touch lcpfric's::

    python3 -m venv /tmp/venv-cm && /tmp/venv-cm/bin/pip install ContactMechanics==1.8.3
    /tmp/venv-cm/bin/python benchmarks/validation/halfspace_reference.py

(All wheels, pure Python or manylinux: no compiler. It took about 30 s on the project's machine.)
lcpfric's tests read only the stored ``.npz`` and do not need ContactMechanics.

Problem
-------
A rigid paraboloid ``z = r²/(2R)`` is pressed with total load ``P`` onto an elastic half-space
of contact modulus ``E*`` (``1/E* = (1-ν1²)/E1 + (1-ν2²)/E2``), frictionless, no adhesion.
The surface is an N×N grid of square elements of side ``h``; element centres are
``x_i = (i - (N-1)/2)·h`` (same in y), and ``r`` is measured from the grid centre.

Library calls and conventions (read from the installed source):

* ``FreeFFTElasticHalfSpace((N, N), young=E*, physical_sizes=(N h, N h))`` -- non-periodic
  half-space; ``young`` *is* the contact modulus E* (its docstring: "Equiv. Young's modulus
  E'"; with no Poisson ratio nothing else is applied). Its influence coefficients are Love's
  closed form (Johnson 1985, eq. 3.25) for a *uniform pressure over an h×h rectangle*,
  ``1/(π E*) [ (x+a) ln(...) + (y+b) ln(...) + (x-a) ln(...) + (y-b) ln(...) ]`` with
  ``a = b = h/2``, evaluated at element-centre offsets; the convolution is done by FFT on a
  2N×2N zero-padded grid (Hockney), so there is no periodic image.
  ``evaluate_disp(forces)`` takes *forces per element* (divides by h² internally).
* ``make_system(surface=Topography(-z, ...), substrate=...)`` and
  ``system.minimize_proxy(external_force=P, ...)`` -- the Polonsky-Keer constrained conjugate
  gradient solver at prescribed total force ``P = Σ element forces``.
  ContactMechanics' topography is the *indenter*, apex up: its heights are ``-z`` (as its own
  ``make_sphere(kind="paraboloid")`` gives). Its gap is ``u - (heights + offset)`` with ``u``
  the displacement into the body; so the returned ``result.offset`` is the rigid approach
  (penetration) δ, Hertz's ``a²/R``. ``result.jac`` is the (compressive, positive) force per
  element; pressure = ``jac / h²``.

Stored (one set of keys per case, suffix ``_a`` for N=32, ``_b`` for N=64):
``N, h, R, Estar, P`` (scalars); ``heights`` (N×N, ``z = r²/(2R)``: the gap at zero approach,
positive away from the contact; the library was given ``-heights``); ``pressure`` (N×N, force
per element / h², ≥ 0); ``approach`` (δ found by the library); ``iterations``; and shared
``library``, ``version`` strings. Index ``[i, j]`` is (x_i, y_j).

Check with it: in contact ``z - δ + (K p) = 0``, elsewhere ``≥ 0``, where ``K`` is the
Love matrix above; the script checks this by direct summation (:func:`direct_displacement`),
independent of the library's FFT.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the repository, the shared report writer, the perf scripts (halfspace's cases) and the tests'
# shared cases and references (tests/support)
_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [
    str(_ROOT),
    str(_ROOT / "benchmarks"),
    str(_ROOT / "benchmarks" / "perf"),
    str(_ROOT / "tests"),
]

import math
import os
import sys

import numpy as np

try:
    import ContactMechanics
    import SurfaceTopography
    from ContactMechanics import FreeFFTElasticHalfSpace, make_system
    from SurfaceTopography import Topography
except ImportError as exc:  # pragma: no cover - only run by hand
    raise SystemExit(
        "benchmarks/validation/halfspace_reference.py needs the ContactMechanics library "
        f"({exc}). Install it in a separate environment:\n"
        "    python3 -m venv /tmp/venv-cm && /tmp/venv-cm/bin/pip install ContactMechanics==1.8.3\n"
        "and run this script with /tmp/venv-cm/bin/python."
    )

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, os.pardir, os.pardir, "tests", "data", "halfspace_reference.npz")

R = 1.0
ESTAR = 1.0
A_HERTZ = 0.5
P = 4.0 * ESTAR * A_HERTZ**3 / (3.0 * R)  # Hertz: a = (3PR/(4E*))^(1/3) = 0.5, so P = 1/6

CASES = {"a": (32, 0.05), "b": (64, 0.025)}


def grid_heights(N: int, h: float, R: float) -> np.ndarray:
    x = (np.arange(N) - (N - 1) / 2.0) * h
    X, Y = np.meshgrid(x, x, indexing="ij")
    return (X**2 + Y**2) / (2.0 * R)


def love_kernel(N: int, h: float, Estar: float) -> np.ndarray:
    """Influence coefficients by centre offset: ``k[N-1+di, N-1+dj]`` is the displacement at the
    centre of element (i, j) per unit uniform pressure on element (i-di, j-dj), from Love's
    closed form (Johnson 1985, eq. 3.25), written here independently of the library's FFT."""
    d = np.arange(-(N - 1), N) * h
    dx, dy = np.meshgrid(d, d, indexing="ij")
    a = b = h / 2.0
    xp, xm, yp, ym = dx + a, dx - a, dy + b, dy - b

    # ∫∫ dξ dη / √(ξ²+η²) over [xm, xp]×[ym, yp] is F(xp,yp) - F(xp,ym) - F(xm,yp) + F(xm,ym)
    # with F(u, v) = u asinh(v/|u|) + v asinh(u/|v|) (the log form of Johnson's eq. 3.25 up to
    # terms -u ln|u| - v ln|v| that cancel in the difference; asinh avoids the cancellation in
    # v + √(u²+v²) for v < 0). u, v are never 0 here: offsets are multiples of h, a = b = h/2.
    def F(u, v):
        return u * np.arcsinh(v / np.abs(u)) + v * np.arcsinh(u / np.abs(v))

    return (F(xp, yp) - F(xp, ym) - F(xm, yp) + F(xm, ym)) / (math.pi * Estar)


def direct_displacement(p: np.ndarray, h: float, Estar: float) -> np.ndarray:
    """Surface displacement (into the body) of the pressure field ``p``, by direct summation."""
    N = p.shape[0]
    k = love_kernel(N, h, Estar)
    w = np.zeros_like(p)
    for j1, j2 in zip(*np.nonzero(p)):
        w += p[j1, j2] * k[N - 1 - j1 : 2 * N - 1 - j1, N - 1 - j2 : 2 * N - 1 - j2]
    return w


def solve_case(N: int, h: float):
    z = grid_heights(N, h, R)
    L = N * h
    substrate = FreeFFTElasticHalfSpace((N, N), ESTAR, physical_sizes=(L, L), check_boundaries=True)
    topography = Topography(-z, physical_sizes=(L, L), periodic=False)
    system = make_system(surface=topography, substrate=substrate)
    res = system.minimize_proxy(
        external_force=P, pentol=1e-13, forcetol=1e-16, thermotol=1e-15, maxiter=100000
    )
    if not res.success:
        raise RuntimeError(f"ContactMechanics did not converge for N={N}: {res.message}")
    pressure = np.asarray(res.jac, dtype=float) / h**2
    return z, pressure, float(res.offset), int(res.nit)


def check_case(N: int, h: float, z: np.ndarray, p: np.ndarray, delta: float) -> dict:
    w = direct_displacement(p, h, ESTAR)
    gap = z - delta + w
    c = p > 0
    return {
        "force_error": abs(p.sum() * h * h - P) / P,
        "gap_in_contact": float(np.max(np.abs(gap[c]))) / delta,
        "min_gap_outside": float(np.min(gap[~c])) / delta if (~c).any() else float("nan"),
        "min_contact_pressure": float(p[c].min()),
        "edge_pressure": float(
            max(
                np.abs(p[0]).max(),
                np.abs(p[-1]).max(),
                np.abs(p[:, 0]).max(),
                np.abs(p[:, -1]).max(),
            )
        ),
    }


def main() -> int:
    data = {
        "library": np.array("ContactMechanics"),
        "version": np.array(
            f"ContactMechanics {ContactMechanics.__version__} "
            f"(SurfaceTopography {SurfaceTopography.__version__}); "
            "FreeFFTElasticHalfSpace + make_system(...).minimize_proxy(external_force=P) "
            "[Polonsky-Keer CCG]"
        ),
    }
    a = (3.0 * P * R / (4.0 * ESTAR)) ** (1.0 / 3.0)
    p0 = 3.0 * P / (2.0 * math.pi * a * a)
    print(f"{data['version']}")
    print(
        f"Hertz: P = {P:.12g}, a = {a:.6g}, p0 = {p0:.6f}, pi a^2 = {math.pi * a * a:.6f}, "
        f"delta = a^2/R = {a * a / R:.6f}"
    )
    for suffix, (N, h) in CASES.items():
        z, p, delta, nit = solve_case(N, h)
        chk = check_case(N, h, z, p, delta)
        area = np.count_nonzero(p > 0) * h * h
        print(f"case {suffix}: N = {N}, h = {h}: iterations {nit}")
        print(f"  max pressure   {p.max():.6f}   (Hertz p0 {p0:.6f}, ratio {p.max() / p0:.4f})")
        print(
            f"  contact area   {area:.6f}   (Hertz pi a^2 {math.pi * a * a:.6f}, "
            f"ratio {area / (math.pi * a * a):.4f}; {np.count_nonzero(p > 0)} elements)"
        )
        print(f"  approach       {delta:.8f}   (Hertz a^2/R {a * a / R:.6f})")
        print(f"  total force    {p.sum() * h * h:.15g}   (rel. error {chk['force_error']:.2e})")
        print(
            f"  direct Love check: max |gap| in contact / delta = {chk['gap_in_contact']:.2e}, "
            f"min gap outside / delta = {chk['min_gap_outside']:.3e},\n"
            f"                     min pressure in contact = {chk['min_contact_pressure']:.3e}, "
            f"max edge pressure = {chk['edge_pressure']:.1e}"
        )
        data.update(
            {
                f"N_{suffix}": np.int64(N),
                f"h_{suffix}": np.float64(h),
                f"R_{suffix}": np.float64(R),
                f"Estar_{suffix}": np.float64(ESTAR),
                f"P_{suffix}": np.float64(P),
                f"heights_{suffix}": z,
                f"pressure_{suffix}": p,
                f"approach_{suffix}": np.float64(delta),
                f"iterations_{suffix}": np.int64(nit),
            }
        )
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    np.savez_compressed(OUT, **data)
    print(f"wrote {os.path.normpath(OUT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
