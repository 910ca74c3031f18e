"""The dynamic single node's exact steady state (issue 40, item 2): against Den Hartog's closed
form, against an independent event-driven integration, its cost per point, and the
quasi-static limit.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/dynamic_node.py [--out PATH]

* Den Hartog (1930): ζ = 0, constant N, motion without stops: ``Ŵ = 4 sqrt(V² - (U/Q̂1)²)``,
  ``V = 1/(1 - β²)``, ``U = tan(π/(2β))/β``, and the amplitude ``Q̂1 Ŵ / 4`` (W = 4 F X);
* random inputs with stops, damping, a varying normal load and separation: the orbit's start
  integrated over one period by DOP853 (rtol 1e-12) with its own events
  (``tests/support/dynamic_reference.py``) returns to itself with the same W and amplitude;
* the time per point (median over those inputs; two starts each, rest and the linear
  response) and the periods of motion it took;
* β -> 0: the relative difference with the quasi-static ``exact`` Ŵ, and its rate;
* the figure ``docs/dynamic_node.png`` / ``.pdf``: Ŵ and the amplitude through resonance.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "tests")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from lcpfric import exact_W_hat  # noqa: E402
from lcpfric.exact.dynamic_api import dynamic_cycle  # noqa: E402
from support.dynamic_reference import one_period  # noqa: E402


def den_hartog() -> None:
    print("## 1. Den Hartog: ζ = 0, constant N, no stops\n")
    print("| β | Q̂1 | Ŵ (closed form) | rel. error in Ŵ | rel. error in the amplitude |")
    print("|---|---|---|---|---|")
    worst = 0.0
    for beta, Q1 in [
        (0.6, 4.0),
        (0.7, 5.0),
        (0.8, 2.0),
        (0.9, 8.0),
        (1.2, 3.0),
        (1.5, 2.0),
        (2.5, 3.0),
        (4.0, 3.0),
    ]:
        V = 1.0 / (1.0 - beta**2)
        U = math.tan(math.pi / (2 * beta)) / beta
        W = 4.0 * math.sqrt(V**2 - (U / Q1) ** 2)
        cyc = dynamic_cycle(0.0, Q1, 0.3, beta, 0.0)
        eW = abs(cyc.W_hat / W - 1)
        eA = abs(cyc.orbit.amplitude / (Q1 * W / 4) - 1)
        worst = max(worst, eW, eA)
        print(f"| {beta} | {Q1} | {W:.12g} | {eW:.1e} | {eA:.1e} |")
    print(f"\nlargest relative error: {worst:.1e} (goal 1e-9)\n")


def reference(count: int = 60) -> list:
    print("## 2. Against an independent integration (DOP853, rtol 1e-12)\n")
    rng = np.random.default_rng(40)
    rows, times, periods = [], [], []
    kinds = {"stops": 0, "separation": 0, "damped": 0, "varying N": 0}
    for _ in range(count):
        P1 = float(rng.choice([0.0, rng.uniform(0.1, 0.95), rng.uniform(1.05, 3.0)]))
        Q1, phi = rng.uniform(0.5, 5.0), rng.uniform(0, 2 * math.pi)
        beta, zeta = rng.uniform(0.2, 3.0), float(rng.choice([0.0, 0.02, 0.1, 0.5]))
        if zeta == 0.0 and abs(beta - 1.0) < 0.05:
            continue
        start = time.perf_counter()
        cyc = dynamic_cycle(P1, Q1, phi, beta, zeta)
        times.append(time.perf_counter() - start)
        o = cyc.orbit
        periods.append(sum(x.periods for x, _ in cyc.orbits))
        z, J, lo, hi = one_period(P1, Q1, phi, beta, zeta, o.z)
        scale = max(1.0, float(np.max(np.abs(o.z))))
        rows.append(
            (
                float(np.max(np.abs(z - o.z))) / scale,
                abs(J - o.J) / max(1.0, o.J),
                abs((hi - lo) / 2 - o.amplitude) / max(1.0, o.amplitude),
            )
        )
        kinds["stops"] += int(np.min(np.abs(o.floquet)) < 1e-12)
        kinds["separation"] += int(P1 > 1)
        kinds["damped"] += int(zeta > 0)
        kinds["varying N"] += int(P1 > 0)
    r = np.array(rows)
    print(
        f"{len(rows)} random inputs ({', '.join(f'{v} {k}' for k, v in kinds.items())}; "
        "'stops': a stick phase on the orbit)\n"
    )
    print("| quantity | largest relative difference |")
    print("|---|---|")
    for name, col in zip(("state after one period", "W", "amplitude"), r.T):
        print(f"| {name} | {col.max():.1e} |")
    print("\ngoal: 1e-9\n")
    return [times, periods]


def _extreme_inputs(seed: int, count: int):
    """Random (P̂1, Q̂1, φ, β, ζ): P̂1 0 to 20, Q̂1 0.1 to 100, β 0.05 to 10, ζ 0 to 2.5 (the
    undamped resonance left out)."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        P1 = float(rng.choice([0.0, rng.uniform(0.1, 0.99), rng.uniform(1.01, 20.0)]))
        Q1, phi = float(10 ** rng.uniform(-1, 2)), rng.uniform(0, 2 * math.pi)
        beta = float(10 ** rng.uniform(-1.3, 1.0))
        zeta = float(rng.choice([0.0, 1e-3, 0.3, 1.0, 2.5]))
        if not (zeta == 0.0 and abs(beta - 1.0) < 0.02):
            yield P1, Q1, phi, beta, zeta


def extreme(count: int = 150) -> None:
    print("## 2b. Extreme inputs against the same integration\n")
    worst, where, n = [0.0, 0.0, 0.0], None, 0
    for P1, Q1, phi, beta, zeta in _extreme_inputs(7, count):
        o = dynamic_cycle(P1, Q1, phi, beta, zeta).orbit
        z, J, lo, hi = one_period(P1, Q1, phi, beta, zeta, o.z)
        e = (
            float(np.max(np.abs(z - o.z))) / max(1.0, float(np.max(np.abs(o.z)))),
            abs(J - o.J) / max(1.0, o.J),
            abs((hi - lo) / 2 - o.amplitude) / max(1.0, o.amplitude),
        )
        if e[0] > worst[0]:
            where = (P1, Q1, phi, beta, zeta)
        worst = [max(a, b) for a, b in zip(worst, e)]
        n += 1
    print(f"{n} inputs: P̂1 0 to 20, Q̂1 0.1 to 100, β 0.05 to 10, ζ 0 to 2.5 (critically and "
          "over-damped included)\n")  # fmt: skip
    print("| quantity | largest relative difference |")
    print("|---|---|")
    for name, x in zip(("state after one period", "W", "amplitude"), worst):
        print(f"| {name} | {x:.1e} |")
    print(f"\nthe largest state difference at (P̂1, Q̂1, φ, β, ζ) = "
          f"{tuple(round(x, 4) for x in where)}; each segment of the exact path integrated "
          f"by DOP853 from its start to its end: {_segments_check(*where):.1e} (largest "
          "difference at the segments' ends): the paths differ in a decision at an event, "
          "not in the segments\n")  # fmt: skip


def _segments_check(P1, Q1, phi, beta, zeta) -> float:
    """Integrate each segment of the exact path (its mode, from its start) to its end."""
    from scipy.integrate import solve_ivp

    from lcpfric.exact.dynamic import period_map

    cyc = dynamic_cycle(P1, Q1, phi, beta, zeta)
    segs = period_map(cyc.node, cyc.orbit.z).segments
    worst = 0.0
    for i in range(segs.shape[0] - 1):
        a, b, mode, u, du = segs[i]
        if mode == 0:
            continue
        s = 0.0 if mode == 2 else -mode

        def rhs(t, y, s=s):
            F = s * (1.0 + P1 * math.sin(t))
            return [y[1], (F - Q1 * math.sin(t + phi) - 2 * zeta * beta * y[1] - y[0]) / beta**2]

        sol = solve_ivp(rhs, (a, b), [u, du], method="DOP853", rtol=1e-13, atol=1e-16)
        end = segs[i + 1, 3:5].copy()
        if segs[i + 1, 2] == 0 or (mode != 2 and segs[i + 1, 2] == -mode):
            end[1] = sol.y[1, -1]  # a stop: the next segment starts at rest by definition
        worst = max(worst, float(np.max(np.abs(sol.y[:, -1] - end))))
    return worst


def robustness(count: int = 1500) -> None:
    import warnings

    print("## 2c. Robustness: extreme inputs solved and verified\n")
    solved, warned, failed, slowest = 0, 0, [], 0.0
    for P1, Q1, phi, beta, zeta in _extreme_inputs(11, count):
        start = time.perf_counter()
        try:
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                dynamic_cycle(P1, Q1, phi, beta, zeta)  # verified over its cycle, or raises
            solved += 1
            warned += bool(w)
        except Exception as exc:  # noqa: BLE001 - counted and shown
            failed.append(((P1, Q1, phi, beta, zeta), str(exc)[:100]))
        slowest = max(slowest, time.perf_counter() - start)
    print(f"{solved} of {solved + len(failed)} inputs solved and verified (P̂1 0 to 20, Q̂1 0.1 "
          f"to 100, β 0.05 to 10, ζ 0 to 2.5); {warned} with several orbits; slowest "
          f"{slowest:.2f} s")  # fmt: skip
    for case, text in failed:
        print(f"- failed at {case}: {text}")
    print()


def timing(times, periods) -> None:
    print("## 3. Time per point\n")
    t = np.array(times) * 1e3
    print(
        f"median {np.median(t):.2f} ms, 90th percentile {np.percentile(t, 90):.2f} ms "
        f"(goal: median <= 2 ms); periods of motion per point: median "
        f"{np.median(periods):.0f} (two starts)\n"
    )


def quasi_static() -> None:
    print("## 4. The quasi-static limit β -> 0 (ζ = 0.05)\n")
    print("| P̂1, Q̂1, φ | β | Ŵ dynamic | rel. difference with quasi-static | rate |")
    print("|---|---|---|---|---|")
    for P1, Q1, phi in [(0.5, 2.0, 0.7), (1.5, 1.5, 2.0), (0.0, 3.0, 0.0)]:
        qs = float(exact_W_hat(P1, Q1, phi))
        prev = None
        for beta in (0.1, 0.03, 0.01, 0.003, 0.001):
            W = dynamic_cycle(P1, Q1, phi, beta, 0.05).W_hat
            d = abs(W / qs - 1)
            rate = f"{math.log(prev[1] / d) / math.log(prev[0] / beta):.2f}" if prev else ""
            print(f"| {P1}, {Q1}, {phi} | {beta} | {W:.12g} | {d:.2e} | {rate} |")
            prev = (beta, d)
    print()


def figure(out_dir: _Path) -> None:
    from lcpfric.figures.dynamic import figure_dynamic_node
    from lcpfric.figures.style import save

    print("## 5. Through resonance (the figure)\n")
    P1, Q1, phi = 0.0, 2.0, 0.0
    beta = np.geomspace(0.05, 4.0, 240)
    curves, counts = [], []
    start = time.perf_counter()
    for zeta in (0.0, 0.05, 0.2):
        b = beta[np.abs(beta - 1.0) > 2e-3] if zeta == 0.0 else beta
        cyc = [dynamic_cycle(P1, Q1, phi, x, zeta) for x in b]
        W = np.interp(beta, b, [c.W_hat for c in cyc])
        X = np.interp(beta, b, [c.orbit.amplitude / Q1 for c in cyc])  # u / Q̂1 = k11 v / Q1
        counts.append(len(b))
        curves.append((rf"$\zeta = {zeta:g}$", W, X))
    seconds = time.perf_counter() - start
    dh = []
    for x in np.geomspace(0.1, 4.0, 25):
        V, U = 1.0 / (1.0 - x * x), math.tan(math.pi / (2 * x)) / x
        # where the motion has no stops (no stick phase: no Floquet multiplier 0)
        if abs(x - 1.0) > 0.02 and V * V - (U / Q1) ** 2 > 0:
            if np.min(np.abs(dynamic_cycle(P1, Q1, phi, x, 0.0).orbit.floquet)) > 1e-12:
                dh.append((x, 4 * math.sqrt(V * V - (U / Q1) ** 2)))
    dh = np.array(dh)
    fig = figure_dynamic_node(
        beta, curves, float(exact_W_hat(P1, Q1, phi)), (dh[:, 0], dh[:, 1], dh[:, 1] / 4),
        title=r" ($\hat Q_1 = 2$, constant N)",
    )  # fmt: skip
    paths = save(fig, out_dir, "dynamic_node", ("png", "pdf"))
    print(f"{sum(counts)} points in {seconds:.2f} s; wrote {', '.join(p.name for p in paths)} "
          "(Den Hartog's closed form where the motion has no stops)\n")  # fmt: skip


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/dynamic-node.md"))
    parser.add_argument("--figures", default=str(_ROOT / "docs"))
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "The dynamic single node, exact",
        "validation/dynamic_node.py",
        markdown=True,
    ):
        den_hartog()
        times, periods = reference()
        extreme()
        robustness()
        timing(times, periods)
        quasi_static()
        figure(_Path(args.figures))


if __name__ == "__main__":
    main()
