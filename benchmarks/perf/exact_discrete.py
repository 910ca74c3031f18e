"""Cost of ``method="exact"`` on discrete systems, and the ratio against ``explicit``.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/perf/exact_discrete.py [--quick] [--out FILE]

(the committed results: ``--out benchmarks/results/exact-discrete.md``)

Part 1: exact at n = 1, 10, 100, 1000 (chains with k_coupling = 10 and random per-node loads, in
full contact and with separation; a dense random SPD K at n = 100 and 1000): seconds, cycles
until periodic, Newton steps, events per cycle, and the cost of one event against its floor (one
product K z and one in-place rank-one update of K_BB⁻¹ over the run's mean free set, the
solver's compiled kernel, timed in the same run).
Part 2: the 100-node chain in full contact: the time for ``explicit`` to reach 1e-6 relative
error (steps doubled from 1000 until it does) against the time for ``exact``, in the same run.
Times are CPU seconds of this process (``time.process_time``), the machines being shared.
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
import sys
import time

import numpy as np

import lcpfric
from lcpfric.model import ContactSystem, IndependentSprings
from lcpfric.model.loads import Harmonic


def chain(n, sep=False, seed=0):
    """n nodes, k_coupling = 10, k_ground = 1; P1 in [0.1, 0.8] (full contact) or [1.2, 2]."""
    rng = np.random.default_rng(seed)
    P1 = rng.uniform(1.2, 2.0, n) if sep else rng.uniform(0.1, 0.8, n)
    return lcpfric.chain(
        n, k_coupling=10.0, P1=P1, Q1=rng.uniform(0.5, 2.0, n), phi=rng.uniform(0, 2 * np.pi, n)
    )


def dense(n, sep=False, seed=0):
    """K = A Aᵀ/n + I with A standard normal (dense SPD, cond about 5), loads as for
    :func:`chain`; ``sep="mixed"``: the case users have, every node its own normal amplitude
    P1 in [0.1, 2] (about half of them separating) and phase, and its own tangential phase."""
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n)) / np.sqrt(n)
    K = A @ A.T + np.eye(n)
    if sep == "mixed":
        P1, psi = rng.uniform(0.1, 2.0, n), rng.uniform(0, 2 * np.pi, n)
    else:
        P1, psi = (rng.uniform(1.2, 2.0, n) if sep else rng.uniform(0.1, 0.8, n)), np.zeros(n)
    Q1, phi = rng.uniform(0.5, 2.0, n), rng.uniform(0, 2 * np.pi, n)
    return ContactSystem(
        K,
        np.ones(n),
        tuple(Harmonic(0.0, Q1[i], phi[i] + psi[i]) for i in range(n)),
        IndependentSprings(tuple(Harmonic(1.0, P1[i], psi[i]) for i in range(n))),
    )


def single(sep):
    return lcpfric.SingleNode.normalized(1.5 if sep else 0.5, 2.0, 0.6 * np.pi).system()


def floor_seconds(K, m):
    """One event's floor: the in-place rank-one update of an m x m block of G = K_BB⁻¹ (the
    solver's own compiled kernel, lcpfric.exact.kernels) and the product of the stuck rows'
    block of K (n - m rows, m columns, as K is stored: dense, or compressed when it is mostly
    zeros) with G's column, m the mean free-set size of the run."""
    import scipy.sparse as sp

    from lcpfric.exact import kernels

    n = K.shape[0]
    rng = np.random.default_rng(1)
    block = np.ascontiguousarray(K[m:, :m]) if m < n else np.zeros((0, max(m, 1)))
    if np.count_nonzero(K) <= 0.25 * n * n:
        block = sp.csr_matrix(block)
    z = rng.standard_normal(max(m, 1))[: block.shape[1]]
    G, g = rng.standard_normal((max(m, 1), max(m, 1))), rng.standard_normal(max(m, 1))
    kernels.rank_one(G, m, g, g, -1)  # compiled (or loaded) out of the timing
    reps = int(min(5000, max(3, 2e7 / (n * n + m * m))))
    t = time.process_time()
    for _ in range(reps):
        block @ z
        kernels.rank_one(G, m, g, g, -1)
    return (time.process_time() - t) / reps


def first_call():
    """Seconds of a first discrete exact solve in a fresh process: with an empty numba cache
    (the kernels compiled) and again with the cache it left (loaded), beside the same solve
    in the second process once loaded (the solve itself)."""
    import os
    import subprocess
    import tempfile

    code = (
        "import time, lcpfric\n"
        "s = lcpfric.chain(3, P1=0.5, Q1=1.2, phi=0.4)\n"
        "t = time.perf_counter(); lcpfric.steady_state(s, 'exact')\n"
        "t1 = time.perf_counter(); lcpfric.steady_state(s, 'exact')\n"
        "print(t1 - t, time.perf_counter() - t1)"
    )
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(_ROOT))
        out = []
        for _ in range(2):
            run = subprocess.run(
                [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
            )
            out.append([float(v) for v in run.stdout.split()])
    return out[0][0], out[1][0], out[1][1]


def run_exact(system):
    t = time.process_time()
    r = lcpfric.steady_state(system, method="exact", steps_per_cycle=64)
    return r, time.process_time() - t


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="n <= 100 and no part 2")
    ap.add_argument("--out", default=None, help="write the markdown tables here")
    args = ap.parse_args(argv)
    run_exact(single(True))  # imports and first calls out of the timings
    run_exact(chain(3))  # the compiled kernels: compiled or loaded from numba's cache
    lines = [
        "| system | n | CPU s | cycles | Newton steps | events per cycle | ms per event "
        "| mean free set | floor ms | ratio to floor | W |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    cases = [
        ("single node (0.5, 2, 0.6π)", lambda n, s: single(False), 1, False),
        ("single node (1.5, 2, 0.6π)", lambda n, s: single(True), 1, True),
        ("chain, full contact", chain, 10, False),
        ("chain, separation", chain, 10, True),
        ("chain, full contact", chain, 100, False),
        ("chain, separation", chain, 100, True),
        ("dense SPD, full contact", dense, 100, False),
        ("dense SPD, separation", dense, 100, True),
        ("dense SPD, mixed amplitudes and phases", dense, 100, "mixed"),
    ]
    if not args.quick:
        cases += [
            ("chain, full contact", chain, 1000, False),
            ("chain, separation", chain, 1000, True),
            ("dense SPD, full contact", dense, 1000, False),
            ("dense SPD, separation", dense, 1000, True),
            ("dense SPD, mixed amplitudes and phases", dense, 1000, "mixed"),
        ]
    for name, make, n, sep in cases:
        system = make(n, sep)
        r, sec = run_exact(system)
        st = r.solver_stats
        events = st["events_per_cycle"] * st["cycles"]
        per = 1e3 * sec / max(events, 1)
        free = round(st.get("free_set_sum", 0) / max(st.get("flips", 0), 1))
        floor = 1e3 * floor_seconds(system.dense_stiffness(), free)
        lines.append(
            f"| {name} | {n} | {sec:.3g} | {st['cycles']} | {st['newton_steps']} "
            f"| {st['events_per_cycle']} | {per:.3g} | {free} | {floor:.2g} "
            f"| {per / floor:.3g} | {r.W:.15g} |"
        )
        print(lines[-1], flush=True)
    command = "OPENBLAS_NUM_THREADS=1 python benchmarks/perf/exact_discrete.py" + (
        " --quick" if args.quick else ""
    )
    out = [
        "## exact on discrete systems",
        "",
        f"`{command}`; CPU seconds; floor: one in-place rank-one update of G over the "
        "run's mean free set m (the compiled kernel) and the product of the stuck rows' "
        "(n - m) x m block of K with a vector (as K is stored: dense, or compressed for a chain)",
        "",
        *lines,
        "",
    ]
    cold, cached, solve = first_call()
    out += [
        "## The first call (a 3-node chain, a fresh process each)",
        "",
        "| numba cache | first solve s | second solve s |",
        "|---|---|---|",
        f"| empty (the kernels compiled) | {cold:.3g} | |",
        f"| the one the first process left (loaded) | {cached:.3g} | {solve:.3g} |",
        "",
    ]
    print("\n".join(out[-5:]), flush=True)
    if not args.quick:
        system = chain(100)
        ref, t_exact = run_exact(system)
        out += [
            "## 100-node chain (k_coupling = 10, full contact): explicit to 1e-6 against exact",
            "",
            "| method | steps per cycle | cycles | relative error | CPU s |",
            "|---|---|---|---|---|",
            f"| exact | events | {ref.cycles} | reference | {t_exact:.3g} |",
        ]
        print(out[-1], flush=True)
        steps = 1000
        while True:
            t = time.process_time()
            r = lcpfric.steady_state(
                system, method="explicit", steps_per_cycle=steps, max_cycles=200
            )
            sec = time.process_time() - t
            err = abs(r.W - ref.W) / ref.W
            out.append(f"| explicit | {steps} | {r.cycles} | {err:.2e} | {sec:.3g} |")
            print(out[-1], flush=True)
            if err <= 1e-6 or steps >= 64000:
                break
            steps *= 2
        out += ["", f"explicit (first grid reaching 1e-6) / exact: **{sec / t_exact:.0f}x**", ""]
        print(out[-2], flush=True)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write("\n".join(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
