"""Speed and accuracy of the Fig. 3 + Fig. 4 map set, against a per-point loop and on Dask.

The set: 11 phases φ = kπ/10 (k = 0..10) on a 101 x 101 grid of P̂1, Q̂1 in [0, 10] (112 211
points), computed by ``lcpfric.analysis.sweep.sweep`` with the exact method. Measured in one run:

* the sweep's wall time, serial and on a local process pool (best of ``--repeat``);
* its accuracy: against Eqs. (11)-(12) at φ = 0 on every grid point, the symmetry
  Ŵ(φ + π) = Ŵ(φ) on every point, and an independent method (the explicit stepper at 20000 steps
  per cycle) on a random sample of points, half of them near the separation onset P̂1 = 1;
* a per-point loop of ``steady_state(..., method="explicit")`` (default 2000 steps per cycle) on a
  random sample of grid points, extrapolated to the whole set, and the ratio to the sweep;
* the same sweep through a Dask ``LocalCluster`` (start-up and run time) against the serial run.

    PYTHONPATH=. python benchmarks/perf/sweep_speed.py [--quick] [--json]
"""

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

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse
import json
import math
import platform
import sys
import time

import numpy as np


import lcpfric  # noqa: E402
from lcpfric.analysis.analytic import jang_barber  # noqa: E402
from lcpfric.analysis.sweep import sweep  # noqa: E402


def best_time(fn, repeat):
    times, result = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t0)
    return min(times), result


def sample_points(ds, n, rng, positive=False, band=False):
    """``n`` random grid points (phi, P1, Q1), optionally only where Ŵ > 0, and optionally half
    of them from the band 0.9 <= P̂1 <= 2, Q̂1 <= 2 around the separation onset, where the
    cycle's structure changes fastest."""
    W = ds["W_hat"].values
    ok = W > 1e-9 if positive else np.ones(W.shape, bool)
    flat = np.flatnonzero(ok)
    idx = rng.choice(flat, size=min(n, flat.size), replace=False)
    if band:
        P1, Q1 = ds["P1"].values[None, :, None], ds["Q1"].values[None, None, :]
        near = np.flatnonzero(ok & (P1 >= 0.9) & (P1 <= 2.0) & (Q1 <= 2.0))
        idx = np.concatenate(
            [idx[: n - n // 2], rng.choice(near, size=min(n // 2, near.size), replace=False)]
        )
    i, j, k = np.unravel_index(idx, W.shape)
    return (ds["phi"].values[i], ds["P1"].values[j], ds["Q1"].values[k], W.ravel()[idx])


def per_point(points, steps):
    """Ŵ and the mean seconds per point of a loop of steady_state(method="explicit")."""
    phi, P1, Q1 = points[:3]
    out = np.empty(phi.size)
    t0 = time.perf_counter()
    for n in range(phi.size):
        node = lcpfric.SingleNode.normalized(P1=P1[n], Q1=Q1[n], phi=phi[n])
        out[n] = lcpfric.steady_state(node, method="explicit", steps_per_cycle=steps).W_hat
    return out, (time.perf_counter() - t0) / phi.size


def dask_run(grid, phases, serial, quick):
    from dask.distributed import Client, LocalCluster

    t0 = time.perf_counter()
    kw = {"n_workers": 1, "processes": False} if quick else {"n_workers": 2, "processes": True}
    cluster = LocalCluster(threads_per_worker=1, dashboard_address=None, **kw)
    client = Client(cluster)
    startup = time.perf_counter() - t0
    try:
        chunk = grid.size * grid.size  # one phase per task
        run, ds = best_time(
            lambda: sweep(grid, grid, phases, scheduler=client, chunk_size=chunk, progress=False), 2
        )
    finally:
        client.close()
        cluster.close()
    return {
        "cluster": ("1 worker, threads" if quick else "2 worker processes, 1 thread each"),
        "startup_seconds": startup,
        "sweep_seconds": run,
        "tasks": len(phases),
        "overhead_seconds": run - serial["seconds"],
        "identical_to_serial": bool(
            np.array_equal(ds["W_hat"].values, serial["ds"]["W_hat"].values)
        ),
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--quick", action="store_true", help="41 x 41 grid, small samples, in-process Dask (for CI)"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--sample",
        type=int,
        default=None,
        help="points in the explicit per-point loop (default 200; quick 20)",
    )
    parser.add_argument("--repeat", type=int, default=3, help="timing repeats (best is kept)")
    parser.add_argument("--no-dask", action="store_true", help="skip the Dask measurement")
    parser.add_argument(
        "--out",
        default=str(_ROOT / "benchmarks" / "results" / "sweep-speed.md"),
        help='the results file (default: %(default)s; "-": print only)',
    )
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "The paper's maps: sweep speed and accuracy",
        "perf/sweep_speed.py" + "".join(f" {a}" for a in (sys.argv[1:] if argv is None else argv)),
    ):
        quick = args.quick
        n = 41 if quick else 101
        sample = args.sample or (20 if quick else 200)
        grid = np.linspace(0.0, 10.0, n)
        phases = np.arange(11) * math.pi / 10
        rng = np.random.default_rng(2024)
        sweep([1.0], [1.0], [0.0], progress=False)  # import xarray & co. outside the timings

        serial_t, ds = best_time(
            lambda: sweep(grid, grid, phases, processes=1, progress=False), args.repeat
        )
        pool_t, ds_pool = best_time(
            lambda: sweep(grid, grid, phases, processes=2, chunk_size=n * n, progress=False),
            args.repeat,
        )
        serial = {"seconds": serial_t, "ds": ds}
        W = ds["W_hat"]

        # accuracy
        ref0 = jang_barber(grid[:, None], grid[None, :])
        err0 = np.abs(W.sel(phi=0.0).values - ref0)
        rel0 = float(np.max(err0[ref0 > 1e-12] / ref0[ref0 > 1e-12]))
        shifted = sweep(grid, grid, phases + math.pi, progress=False)["W_hat"].values
        sym = np.abs(shifted - W.values)
        pts = sample_points(ds, 10 if quick else 40, rng, positive=True, band=True)
        fine, _ = per_point(pts, 20000)
        rel_fine = np.abs(pts[3] - fine) / np.abs(fine)

        # the per-point loop
        loop_pts = sample_points(ds, sample, rng)
        loop_W, per_point_s = per_point(loop_pts, 2000)
        loop_rel = (
            np.abs(loop_W - loop_pts[3])[loop_pts[3] > 1e-9] / loop_pts[3][loop_pts[3] > 1e-9]
        )
        extrapolated = per_point_s * W.size

        result = {
            "grid": f"{len(phases)} phases x {n} x {n} (P1, Q1 in [0, 10])",
            "points": int(W.size),
            "machine": {
                "cores": lcpfric.analysis.runners.default_workers(),
                "python": platform.python_version(),
                "platform": platform.platform(),
            },
            "sweep_serial_seconds": serial_t,
            "sweep_pool2_seconds": pool_t,
            "pool_identical": bool(np.array_equal(ds_pool["W_hat"].values, W.values)),
            "accuracy": {
                "phi0_vs_eq11_12_max_abs": float(err0.max()),
                "phi0_vs_eq11_12_max_rel": rel0,
                "symmetry_phi_plus_pi_max_abs": float(sym.max()),
                "symmetry_points_off_by_1e-9": int(np.sum(sym > 1e-9)),
                "explicit_20000_steps_sample": int(rel_fine.size),
                "explicit_20000_steps_max_rel_diff": float(rel_fine.max()),
                "explicit_20000_steps_median_rel_diff": float(np.median(rel_fine)),
            },
            "explicit_loop": {
                "sample_points": int(loop_pts[0].size),
                "steps_per_cycle": 2000,
                "seconds_per_point": per_point_s,
                "extrapolated_seconds": extrapolated,
                "ratio_to_sweep": extrapolated / serial_t,
                "explicit_2000_max_rel_error": float(loop_rel.max()) if loop_rel.size else 0.0,
            },
            "goals": {"seconds_le_30": serial_t <= 30.0},
        }
        if not args.no_dask:
            try:
                result["dask"] = dask_run(grid, phases, serial, quick)
            except ImportError as exc:
                result["dask"] = {"skipped": str(exc)}
        argv_text = " ".join(
            ["--quick"] * quick
            + ([f"--sample {args.sample}"] if args.sample else [])
            + ["--no-dask"] * args.no_dask
        )
        result["reproduce"] = (
            f"PYTHONPATH=. python benchmarks/perf/sweep_speed.py {argv_text}".strip()
        )

        if args.json:
            print(json.dumps(result, indent=1))
            return 0
        acc, loop = result["accuracy"], result["explicit_loop"]
        print(
            f"# Fig. 3 + Fig. 4 set: {result['grid']} = {result['points']} points, "
            f"{result['machine']['cores']} cores"
        )
        print(f"sweep (exact), serial:            {serial_t:.3f} s")
        print(
            f"sweep (exact), 2 processes:       {pool_t:.3f} s (identical: "
            f"{result['pool_identical']})"
        )
        print(
            f"accuracy, φ = 0 vs Eqs. (11)-(12), all {n * n} points: max abs "
            f"{acc['phi0_vs_eq11_12_max_abs']:.1e}, max rel {acc['phi0_vs_eq11_12_max_rel']:.1e}"
        )
        print(
            f"accuracy, Ŵ(φ+π) = Ŵ(φ) on all points: max abs "
            f"{acc['symmetry_phi_plus_pi_max_abs']:.1e} ({acc['symmetry_points_off_by_1e-9']} "
            "points off by more than 1e-9)"
        )
        print(
            f"accuracy, vs explicit at 20000 steps/cycle on {acc['explicit_20000_steps_sample']} "
            f"random points with Ŵ > 0 (half near P̂1 = 1): max rel diff "
            f"{acc['explicit_20000_steps_max_rel_diff']:.1e} (median "
            f"{acc['explicit_20000_steps_median_rel_diff']:.1e})"
        )
        print(
            f"per-point explicit loop (2000 steps/cycle), {loop['sample_points']} random points: "
            f"{1e3 * loop['seconds_per_point']:.2f} ms/point -> "
            f"{loop['extrapolated_seconds']:.0f} s for the set; "
            f"the sweep is {loop['ratio_to_sweep']:.0f}x faster "
            f"(explicit's own max rel error there: {loop['explicit_2000_max_rel_error']:.1e})"
        )
        d = result.get("dask")
        if d and "skipped" not in d:
            print(
                f"Dask LocalCluster ({d['cluster']}): start-up {d['startup_seconds']:.2f} s, sweep "
                f"{d['sweep_seconds']:.3f} s in {d['tasks']} tasks (overhead vs serial "
                f"{d['overhead_seconds']:+.3f} s), identical to serial: {d['identical_to_serial']}"
            )
        elif d:
            print(f"Dask: skipped ({d['skipped']})")
        print(f"reproduce: {result['reproduce']}")
        return 0


if __name__ == "__main__":
    sys.exit(main())
