"""Nearly rigid chains against their merged node, and random stiff systems against their
merged limits (issue 36).

Usage::

    python benchmarks/validation/stiff_chains.py [--quick] [--random N]

A chain of n nodes, each grounded by a spring of stiffness 1 and tied to its neighbours by
couplings k_c, each node with its own normal and tangential load phases (seeded), no separation.
As k_c grows the nodes move as one: the chain tends to the merged single node (stiffness n,
friction limit f Σ N_i, load Σ Q_i), which ``exact`` solves in closed form. For each chain and
k_c the table gives each method's relative difference from the merged node (or the error it
raised), and two measures of what float64 can give: ``eps cond(K)``, and how far one ulp on
``K[0, 0]`` moves ``exact``'s W (the conditioning of W on K given as float64 entries: one ulp
of K[0, 0] moves node 0's grounding by eps k_c). The difference from the merged node holds the
O(1/k_c) coupling effect of the chain itself, c / k_c; ``exact - c/k_c`` takes it out with c
measured at k_c = 1e4.

Then N random stiff systems (tests/support/stiff_random.py: 2 to 8 nodes, clusters tied by
springs 2^20 to 2^40 times the groundings, soft springs between them, seeded loads): ``exact``'s
W at k and 8 k, extrapolated to the merged limit (Richardson), against the merged system's
exact W; an error raised counts as an error, a difference above 1e-9 as a silent drift.
Writes ``benchmarks/results/stiff-chains.md``.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "tests")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
from support.stiff_random import chain_loads, merged_chain_W  # noqa: E402 (tests/, above)
import argparse
import math
import sys
import time

import numpy as np

import lcpfric

METHODS = ("exact", "active-set", "explicit")
COUPLINGS = (1e2, 1e4, 1e6, 1e8, 1e10, 1e12)


def one_ulp(system, W) -> float:
    """The largest relative change of ``exact``'s W when K[0, 0] moves by one ulp."""
    K = np.array(system.stiffness, dtype=float)
    worst = 0.0
    for direction in (np.inf, -np.inf):
        K2 = K.copy()
        K2[0, 0] = np.nextafter(K2[0, 0], direction)
        moved = lcpfric.ContactSystem(
            K2, system.friction, system.tangential_loads, system.normal, dims=1
        )
        worst = max(worst, abs(lcpfric.steady_state(moved, "exact").W / W - 1.0))
    return worst


def run_case(n: int, kc: float, seed: int, c: float | None) -> tuple[str, float]:
    """One row of the table, and exact's relative difference from the merged node."""
    P1, Q1, psi, phi = chain_loads(n, seed)
    Wm = merged_chain_W(P1, Q1, psi, phi)
    system = lcpfric.chain(n, k_coupling=kc, P0=1.0, P1=P1, Q1=Q1, phi=phi, normal_phase=psi)
    cond = np.linalg.cond(np.array(system.stiffness, dtype=float))
    cells = [f"{n}", f"{kc:.0e}", f"{np.finfo(float).eps * cond:.1e}"]
    W_exact, rel = None, math.nan
    for method in METHODS:
        t0 = time.perf_counter()
        try:
            W = lcpfric.steady_state(system, method).W
        except lcpfric.LcpfricError as exc:
            named = " (names 'exact')" if "'exact' solves such systems" in str(exc) else ""
            cells.append(f"{type(exc).__name__}{named} ({time.perf_counter() - t0:.2f} s)")
            continue
        seconds = time.perf_counter() - t0
        if method == "exact":
            W_exact, rel = W, W / Wm - 1
            minus = "-" if c is None else f"{rel - c / kc:+.1e}"
            cells.append(f"{rel:+.2e} ({seconds:.2f} s) | {minus}")
        else:
            cells.append(f"{W / Wm - 1:+.1e} ({seconds:.2f} s)")
    cells.append("-" if W_exact is None else f"{one_ulp(system, W_exact):.1e}")
    return "| " + " | ".join(cells) + " |", rel


def random_systems(count: int) -> None:
    """The random stiff systems against their merged limits (module docstring)."""
    from support.stiff_random import energy_scale, extrapolated, merged, random_stiff

    errors: dict[str, int] = {}
    worst, drifts, answered, t0 = 0.0, [], 0, time.perf_counter()
    for seed in range(count):
        p = random_stiff(seed)
        try:
            W_k = lcpfric.steady_state(p.system(p.k), "exact").W
            W_8k = lcpfric.steady_state(p.system(8 * p.k), "exact").W
        except lcpfric.LcpfricError as exc:
            errors[type(exc).__name__] = errors.get(type(exc).__name__, 0) + 1
            continue
        answered += 1
        Wm = lcpfric.steady_state(merged(p), "exact").W
        err = abs(extrapolated(W_k, W_8k) - Wm) / max(Wm, energy_scale(p))
        worst = max(worst, err)
        if err > 1e-9:
            drifts.append(seed)
    listed = ", ".join(f"{v} {k}" for k, v in sorted(errors.items())) or "none"
    print(
        f"\n{count} random stiff systems (seeds 0..{count - 1}), exact at k and 8 k, "
        f"{time.perf_counter() - t0:.0f} s in all:\n\n"
        f"| answered | errors raised | silent drifts (> 1e-9) | largest difference |\n"
        f"|---|---|---|---|\n"
        f"| {answered} | {listed} | {len(drifts)} {drifts[:10] if drifts else ''} | "
        f"{worst:.1e} |"
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="chains of 2 nodes, 20 systems")
    parser.add_argument("--random", type=int, default=1000, help="random stiff systems")
    args = parser.parse_args(argv)
    sizes = (2,) if args.quick else (2, 4, 8)
    count = 20 if args.quick else args.random
    out = None if args.quick else _ROOT / "benchmarks" / "results" / "stiff-chains.md"
    command = "validation/stiff_chains.py" + (" --quick" if args.quick else "")
    with results_file(out, "Nearly rigid chains against the merged node", command, True):
        print(
            "Relative difference of W from the merged node's closed form (seeded loads, the "
            "chain's own O(1/k_c) effect included), or the error raised (whether its message "
            "names 'exact'), and the time; `exact - c/k_c`: exact's difference with the "
            "chain's c / k_c taken out (c measured at k_c = 1e4); `eps cond(K)` and `1 ulp of "
            "K[0,0]` (how far one ulp moves exact's W) are what float64 entries of K "
            "determine.\n"
        )
        print(
            "| n | k_c | eps cond(K) | exact | exact - c/k_c | active-set | explicit "
            "| 1 ulp of K[0,0] |\n|" + "---|" * 8
        )
        for n in sizes:
            c = None
            for kc in COUPLINGS:
                row, rel = run_case(n, kc, seed=n, c=c)
                if kc == 1e4:
                    c = rel * kc
                print(row, flush=True)
        random_systems(count)
    return 0


if __name__ == "__main__":
    sys.exit(main())
