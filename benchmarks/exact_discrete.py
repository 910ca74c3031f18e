"""Cost of ``method="exact"`` on discrete systems, and the ratio against ``explicit``.

Usage::

    python benchmarks/exact_discrete.py [--quick] [--out benchmarks/results/exact-discrete.md]

Part 1: exact at n = 1, 10, 100, 1000 (chains with k_coupling = 10, in full contact and with
separation; a dense random SPD K at n = 100 and 1000): seconds, cycles until periodic, events per
cycle. Part 2: the 100-node chain (full contact): the time for ``explicit`` to reach 1e-6 relative
error (steps doubled from 1000 until it does) against the time for ``exact`` (which is the
reference, W to round-off), in the same run.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import lcpfric
from lcpfric.model import ContactSystem, IndependentSprings
from lcpfric.model.loads import Harmonic


def chain(n, sep=False, seed=0):
    rng = np.random.default_rng(seed)
    P1 = rng.uniform(1.2, 2.0, n) if sep else rng.uniform(0.1, 0.8, n)
    return lcpfric.chain(n, k_coupling=10.0, P1=P1, Q1=rng.uniform(0.5, 2.0, n),
                         phi=rng.uniform(0, 2 * np.pi, n))


def dense(n, sep=False, seed=0):
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n)) / np.sqrt(n)
    K = A @ A.T + np.eye(n)
    P1 = rng.uniform(1.2, 2.0, n) if sep else rng.uniform(0.1, 0.8, n)
    Q1, phi = rng.uniform(0.5, 2.0, n), rng.uniform(0, 2 * np.pi, n)
    return ContactSystem(K, np.ones(n), tuple(Harmonic(0.0, Q1[i], phi[i]) for i in range(n)),
                         IndependentSprings(tuple(Harmonic(1.0, P1[i]) for i in range(n))))


def run_exact(system):
    t = time.perf_counter()
    r = lcpfric.steady_state(system, method="exact", steps_per_cycle=64)
    return r, time.perf_counter() - t


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="skip n = 1000 and part 2")
    ap.add_argument("--out", default=None, help="write the markdown tables here")
    args = ap.parse_args(argv)
    lines = ["| system | n | seconds | cycles | events per cycle | W |", "|---|---|---|---|---|---|"]
    cases = [("chain, full contact", chain, 1, False), ("chain, full contact", chain, 10, False),
             ("chain, separation", chain, 10, True), ("chain, full contact", chain, 100, False),
             ("chain, separation", chain, 100, True), ("dense SPD, full contact", dense, 100, False),
             ("dense SPD, separation", dense, 100, True)]
    if not args.quick:
        cases += [("chain, separation", chain, 1000, True),
                  ("dense SPD, separation", dense, 1000, True),
                  ("dense SPD, full contact", dense, 1000, False)]
    for name, make, n, sep in cases:
        r, sec = run_exact(make(n, sep))
        st = r.solver_stats
        lines.append(f"| {name} | {n} | {sec:.3g} | {st['cycles']} | {st['events_per_cycle']} "
                     f"| {r.W:.15g} |")
        print(lines[-1], flush=True)
    out = ["## exact on discrete systems", "", *lines, ""]
    if not args.quick:
        system = chain(100)
        ref, t_exact = run_exact(system)
        out += ["## 100-node chain (k_coupling = 10, full contact): explicit to 1e-6 vs exact", "",
                "| method | steps per cycle | relative error | seconds |", "|---|---|---|---|",
                f"| exact | - | reference | {t_exact:.3g} |"]
        print(out[-1], flush=True)
        steps = 1000
        while True:
            t = time.perf_counter()
            r = lcpfric.steady_state(system, method="explicit", steps_per_cycle=steps,
                                     max_cycles=200)
            sec = time.perf_counter() - t
            err = abs(r.W - ref.W) / ref.W
            out.append(f"| explicit | {steps} | {err:.2e} | {sec:.3g} |")
            print(out[-1], flush=True)
            if err <= 1e-6 or steps >= 64000:
                break
            steps *= 2
        out += ["", f"ratio (explicit to 1e-6) / exact: {sec / t_exact:.0f}x", ""]
        print(out[-2], flush=True)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
