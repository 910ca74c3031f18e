"""Randomized accuracy audit of ``lcpfric.exact_W_hat`` against the mpmath reference.

    python benchmarks/validation/exact_audit.py [--n 4000] [--seed 0] [--processes 8]
        [--out FILE.md]

Points are drawn from a mixture (each family ``n / 9`` points, φ uniform on [0, 2π) unless
stated): P̂1 and Q̂1 log-uniform on [1e-20, 1e20]; P̂1 log-uniform and Q̂1/P̂1 log-uniform on
[1e-20, 1e20]; separation with Q̂1/P̂1 in [1e-20, 1e-3]; P̂1 within 10^U(-16, 0) of 1; φ within
10^U(-12, 0) of 0 or π; Q̂1 equal to P̂1 or within 10^U(-16, 0) of it (the border of the
φ = 0 zero régime), φ uniform or within 10^U(-12, -1) of 0 or π; moderate values
in [0, 4]; P̂1 in [0, 50] with Q̂1 within 3 of it and φ at or within 10^U(-8, 0) of 0 or π;
and exact boundary values (P̂1 or Q̂1 in {0, 0.5, 1, 2, 1e10}, Q̂1 = P̂1).

Each point is computed by the scalar path (``exact_W_hat(float, float, float)``) and by the
vectorized path (one array call) and compared with :func:`exact_reference.reference_W_hat`.
A point passes when ``|Ŵ - ref| <= 1e-9 ref``, or, where Ŵ is ill-conditioned, when the error is
within the spread of the exact Ŵ over the inputs perturbed by 16 units of round-off
(relative 16 eps for P̂1 and Q̂1, absolute 16 eps max(1, |φ|) for φ): the answer is then exact
for inputs indistinguishable from the given ones. The report also gives the worst relative error
over the well-conditioned points (that spread below 1e-10 of Ŵ).
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

import argparse
import os
import sys
import time
from multiprocessing import Pool

import numpy as np


from support.exact_reference import draw, input_spread, reference_W_hat  # noqa: E402

EPS = np.finfo(float).eps
REL = 1e-9
ULPS = 16


def _reference(point):
    P1, Q1, phi = (float(x) for x in point)
    return reference_W_hat(P1, Q1, phi)


def _spread(point):
    """Largest change of the exact Ŵ when one input moves by ULPS units of round-off."""
    return input_spread(*(float(x) for x in point), ulps=ULPS)


def audit(points: np.ndarray, processes: int = 1) -> dict:
    from lcpfric.exact import exact_W_hat

    t0 = time.perf_counter()
    with Pool(processes) as pool:
        ref = np.array(pool.map(_reference, points, chunksize=16))
    t_ref = time.perf_counter() - t0
    scalar = np.array([exact_W_hat(float(p), float(q), float(f)) for p, q, f in points])
    vector = exact_W_hat(points[:, 0], points[:, 1], points[:, 2])
    out = dict(n=len(points), reference_seconds=t_ref)
    for name, val in (("scalar", scalar), ("vectorized", vector)):
        err = np.abs(val - ref)
        with np.errstate(divide="ignore", invalid="ignore"):
            rel = np.where(ref > 0, err / ref, np.where(err > 0, np.inf, 0.0))
        bad = np.nonzero(err > REL * ref)[0]
        # the conditioning of every point not accurate to 1e-12, to tell the ill-conditioned
        look = np.nonzero(err > 1e-12 * ref)[0]
        spread = np.zeros(len(points))
        if look.size:
            with Pool(processes) as pool:
                spread[look] = pool.map(_spread, points[look], chunksize=4)
        fail = bad[err[bad] > REL * ref[bad] + spread[bad]]
        ok_rel = rel[err <= REL * ref]
        well = spread <= 1e-10 * ref  # Ŵ moves by < 1e-10 under 16-ulp input perturbations
        out[name] = dict(
            well_conditioned=int(np.sum(well)),
            worst_rel_well=float(np.max(rel[well])) if well.any() else 0.0,
            worst_rel_well_point=(
                points[np.nonzero(well)[0][np.argmax(rel[well])]].tolist() if well.any() else None
            ),
            worst_rel=float(np.max(rel)),
            worst_rel_point=points[int(np.argmax(rel))].tolist(),
            within_rel=int(np.sum(err <= REL * ref)),
            ill_conditioned=int(bad.size - fail.size),
            fail=[(points[j].tolist(), float(val[j]), float(ref[j])) for j in fail],
            worst_rel_of_passing=float(np.max(ok_rel)) if ok_rel.size else 0.0,
            worst_ill=(
                max(
                    (
                        (float(err[j] / spread[j]) if spread[j] else float("inf")),
                        points[j].tolist(),
                        float(val[j]),
                        float(ref[j]),
                    )
                    for j in bad
                )
                if bad.size
                else None
            ),
        )
    out["scalar_vs_vector_max_rel"] = float(
        np.max(np.abs(scalar - vector) / np.maximum(np.abs(ref), 1e-300))
    )
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=4000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--processes", type=int, default=os.cpu_count() or 1)
    p.add_argument("--out", default=None)
    args = p.parse_args(argv)
    pts = draw(args.n, args.seed)
    t0 = time.perf_counter()
    res = audit(pts, args.processes)
    lines = [
        f"Reproduce: `python benchmarks/validation/exact_audit.py --n {args.n} --seed {args.seed}`",
        "",
        f"{res['n']} points (mixture of the module docstring), mpmath reference "
        f"({res['reference_seconds']:.0f} s), total {time.perf_counter() - t0:.0f} s.",
        "",
    ]
    for name in ("scalar", "vectorized"):
        r = res[name]
        lines += [
            f"- {name}: worst relative error {r['worst_rel_well']:.2e} over the "
            f"{r['well_conditioned']} well-conditioned points (16-ulp input spread of Ŵ "
            f"below 1e-10 relative), at {r['worst_rel_well_point']}",
            f"- {name}: {r['within_rel']} within 1e-9 relative (worst there "
            f"{r['worst_rel_of_passing']:.2e}); {r['ill_conditioned']} ill-conditioned "
            f"points within the 16-ulp input spread; {len(r['fail'])} failures; worst "
            f"relative error overall {r['worst_rel']:.2e} at {r['worst_rel_point']}",
        ]
        if r["worst_ill"]:
            lines.append(
                f"  - largest error / spread among the ill-conditioned: "
                f"{r['worst_ill'][0]:.2e} at {r['worst_ill'][1]} "
                f"(value {r['worst_ill'][2]!r}, reference {r['worst_ill'][3]!r})"
            )
        for pt, val, ref in r["fail"][:20]:
            lines.append(f"  - FAIL {pt}: {val!r} vs reference {ref!r}")
    lines.append(
        f"- scalar vs vectorized: max difference {res['scalar_vs_vector_max_rel']:.2e} "
        f"of the reference"
    )
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text)
    return 1 if (res["scalar"]["fail"] or res["vectorized"]["fail"]) else 0


if __name__ == "__main__":
    sys.exit(main())
