"""Time stepping with inertia for systems, every backend; shooting; harmonic balance against
shooting (issue 40, items 3-5, on :class:`lcpfric.DynamicSystem`).

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/newmark_system.py [--out PATH]

1. The paper's dynamic node as a one-degree-of-freedom system with a rigid contact
   (``DynamicSystem.from_node``) against ``exact``: W's relative error at 100-1600 increments
   a period, and its order, with every backend for the increments (the clip of one contact,
   Clarabel, OSQP, qpsolvers with ProxQP, cvxpy), on a case with stops, one with separation and
   one with a constant normal load.
2. A coupled 3-mass chain (rigid contacts, varying normal loads, one separating; Rayleigh
   damping): no exact answer; the order from successive differences of W (100-3200
   increments, which needs no reference) and the errors against the Richardson extrapolation
   of the two finest, every backend.
3. Shooting on a 10-DOF chain with one Jenkins contact and ζ = 1e-3 (the chain of
   ``benchmarks/perf/frc_chain.py``): Newton iterations and periods over ω through the first
   resonance; cycle iteration to the same tolerance at three frequencies; increments of each.
4. Harmonic balance (H = 15, ``lcpfric.harmonic.forced_response``) against shooting (1600
   increments a period, started from the HB point; its own error bounded by its difference
   with 800) on the same chain: the first harmonic of every degree of freedom at the curve's
   points.
5. d = 2 Jenkins contacts: a chain in two directions against the d = 1 chain under a load
   along one direction, and the order under a load turning in the plane.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import lcpfric  # noqa: E402
from lcpfric.periodic.first_guess import equivalent_linear_start, harmonic_start  # noqa: E402
from lcpfric.periodic.shooting import iterate_cycles, shoot  # noqa: E402
from lcpfric.periodic.newmark_steady import shooting_tolerance  # noqa: E402
from lcpfric.steppers.newmark_system import NewmarkSystem  # noqa: E402

BACKENDS = (None, "clarabel", "osqp", "qpsolvers:proxqp", "cvxpy")
NODES = {  # (P1, Q1, phi, beta, zeta): what the steady cycle holds
    "stops": (0.5, 2.0, 0.3, 0.7, 0.2),
    "separation": (1.5, 2.0, 0.3, 0.7, 0.2),
    "constant N": (0.0, 3.0, 0.0, 0.5, 0.1),
}


def order(steps, err):
    """Least-squares slope of log err against log steps."""
    return float(-np.polyfit(np.log(steps), np.log(err), 1)[0])


def chain3():
    """The coupled 3-mass chain of section 2."""
    K = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1.5]])
    M = np.diag([1.0, 1.5, 0.8])
    Nh = np.array([0.6 * np.exp(-0.5j * np.pi), 1.4 * np.exp(1j * (0.7 - 0.5 * np.pi)),
                   0.5 * np.exp(1j * (2.0 - 0.5 * np.pi))])  # fmt: skip
    return lcpfric.DynamicSystem(
        mass=M, stiffness=K, damping=lcpfric.rayleigh(M, K, 0.05, 0.02), contacts=[0, 1, 2],
        friction=[0.3, 0.4, 0.35], normal_load=[1.0, 1.0, 1.0], normal_amplitude=Nh, omega=0.7,
        force=[1.2 * np.exp(0.3j), 0.0, 0.9 * np.exp(-1.1j)], force_mean=[0.1, 0.0, -0.2],
    )  # fmt: skip


def chain10(omega):
    """The 10-DOF chain of ``benchmarks/perf/frc_chain.py`` as a DynamicSystem."""
    n = 10
    K = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    K[-1, -1] = 1.0
    M = np.eye(n)
    w1 = float(np.sqrt(np.linalg.eigvalsh(K)[0]))
    f = np.zeros(n)
    f[-1] = 0.05
    return lcpfric.DynamicSystem(mass=M, stiffness=K, damping=2e-3 * w1 * M, contacts=[n - 1],
                                 friction=0.3, normal_load=1.0, omega=omega, force=f,
                                 contact_stiffness=1.0)  # fmt: skip


def section_node():
    print("\n## 1. The dynamic node as a system against `exact`, every backend\n")
    print("relative error of W (the increments' solver: `clip` = the closed form of one "
          "contact); orders are least-squares slopes over 100-1600 increments\n")  # fmt: skip
    steps = (100, 200, 400, 800, 1600)
    print("| case | backend | " + " | ".join(str(s) for s in steps) + " | order | solver "
          "objects rebuilt cold | s |")  # fmt: skip
    print("|---|---|" + "---|" * (len(steps) + 3))
    for case, p in NODES.items():
        node = lcpfric.SingleNode.normalized(P1=p[0], Q1=p[1], phi=p[2], beta=p[3], zeta=p[4])
        ref = lcpfric.steady_state(node, method="exact").W
        system = lcpfric.DynamicSystem.from_node(node)
        for b in BACKENDS:
            errs, start, rebuilt = [], time.perf_counter(), 0
            for n in steps:
                opts = {} if b is None else {"backend": b}
                r = lcpfric.steady_state(system, method="newmark", steps_per_cycle=n, **opts)
                errs.append(abs(r.W / ref - 1))
                rebuilt += r.solver_stats["rebuilt"]
            sec = time.perf_counter() - start
            print(f"| {case} | {b or 'clip'} | " + " | ".join(f"{e:.2e}" for e in errs)
                  + f" | {order(steps, errs):.2f} | {rebuilt} | {sec:.1f} |")  # fmt: skip


def section_chain3():
    print("\n## 2. A coupled 3-mass chain (rigid contacts, one separating), every backend\n")
    steps = (100, 200, 400, 800, 1600, 3200)
    system = chain3()
    print("| backend | W at 3200 | orders of successive differences | error vs Richardson "
          "(100 ... 1600) | order vs Richardson | s |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for b in BACKENDS[1:]:
        Ws, start = [], time.perf_counter()
        for n in steps:
            opts = {} if b is None else {"backend": b}
            Ws.append(lcpfric.steady_state(system, method="newmark", steps_per_cycle=n, **opts).W)
        Ws = np.array(Ws)
        d = np.abs(np.diff(Ws))
        p_succ = np.log2(d[:-1] / d[1:])
        rich = Ws[-1] + (Ws[-1] - Ws[-2]) / 3.0
        err = np.abs(Ws[:-1] / rich - 1)
        sec = time.perf_counter() - start
        print(f"| {b} | {Ws[-1]:.12f} | " + ", ".join(f"{x:.2f}" for x in p_succ) + " | "
              + ", ".join(f"{e:.1e}" for e in err)
              + f" | {order(steps[:-1], err):.2f} | {sec:.1f} |")  # fmt: skip


def section_shooting(steps=200):
    print(f"\n## 3. Shooting on the 10-DOF chain, ζ = 1e-3, {steps} increments a period\n")
    tol = shooting_tolerance(steps)
    print(f"tolerance: max |Φ(z) - z| / max |z| <= {tol:.1e}; start: the equivalent linear "
          "response\n")  # fmt: skip
    print("| ω | Newton iterations | periods | W | amplitude (last mass) | s |")
    print("|---|---|---|---|---|---|")
    its, pers = [], []
    grid = np.unique(np.round(np.concatenate([np.linspace(0.05, 0.5, 10),
                                              np.arange(0.27, 0.30001, 0.0025)]), 4))  # fmt: skip
    for om in grid:
        s = chain10(om)
        path = NewmarkSystem(s)
        start = time.perf_counter()
        r = shoot(lambda z, path=path: path.period(z, steps, jacobian=True)[::2],
                  equivalent_linear_start(s), tol)  # fmt: skip
        sec = time.perf_counter() - start
        z1, W, _, (t, rec) = path.period(r.z, steps, record=True)
        x = np.array([q[0][0][-1, 0] for q in rec])
        its.append(r.iterations)
        pers.append(r.periods)
        print(f"| {om:.4f} | {r.iterations} | {r.periods} | {W:.6e} | "
              f"{0.5 * (x.max() - x.min()):.6f} | {sec:.2f} |")  # fmt: skip
    print(f"\nNewton iterations: median {np.median(its):.0f}, largest {max(its)}; periods: "
          f"median {np.median(pers):.0f}, largest {max(pers)}\n")  # fmt: skip
    print("the resonance's points (0.27 to 0.30) started from the neighbouring frequency's orbit "
          "instead (natural continuation), Newton iterations:\n")  # fmt: skip
    near = grid[(grid >= 0.27) & (grid <= 0.30)]
    for label, order_ in (("upwards", near), ("downwards", near[::-1])):
        z, counts = None, []
        for om in order_:
            s = chain10(om)
            path = NewmarkSystem(s)
            r = shoot(lambda q, path=path: path.period(q, steps, jacobian=True)[::2],
                      equivalent_linear_start(s) if z is None else z, tol)  # fmt: skip
            z = r.z
            counts.append(r.iterations if r.converged else f"{r.iterations} (not converged)")
        print(f"- {label}: " + ", ".join(str(c) for c in counts))
    print()
    print("cycle iteration from the same start to the same tolerance:\n")
    print("(where the slider sticks over the whole period its position is a family of orbits: "
          "cycles and shooting may end on different members, the W of both being 0)\n")  # fmt: skip
    print("| ω | shooting periods | cycle periods | increments, shooting | increments, cycles | "
          "ratio | max |z_cycles - z_shooting| / max |z| | s, shooting | s, cycles |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    for om in (0.2, 0.282, 0.2875):
        s = chain10(om)
        path = NewmarkSystem(s)
        z0 = equivalent_linear_start(s)
        start = time.perf_counter()
        r = shoot(lambda z, path=path: path.period(z, steps, jacobian=True)[::2], z0, tol)
        sec_s = time.perf_counter() - start
        inc_s = path.increments
        cpath = NewmarkSystem(s)
        start = time.perf_counter()
        zc, res, periods, conv = iterate_cycles(lambda z, p=cpath: p.period(z, steps)[0], z0,
                                                tol, 40000)  # fmt: skip
        sec_c = time.perf_counter() - start
        inc_c = cpath.increments
        gap = float(np.max(np.abs(zc - r.z)) / np.max(np.abs(r.z)))
        note = "" if conv else " (not converged)"
        print(f"| {om} | {r.periods} | {periods}{note} | {inc_s} | {inc_c} | "
              f"{inc_c / inc_s:.0f} | {gap:.1e} | {sec_s:.1f} | {sec_c:.1f} |")  # fmt: skip


def first_harmonic(t, x, omega):
    """(a1, b1) of samples over one period on a uniform grid (the last sample dropped)."""
    tt, xx = t[:-1], x[:-1]
    n = tt.size
    return (2.0 / n) * (xx.T @ np.cos(omega * tt)), (2.0 / n) * (xx.T @ np.sin(omega * tt))


def section_hb(H=15):
    from lcpfric.harmonic import forced_response

    print(f"\n## 4. Harmonic balance (H = {H}) against shooting on the 10-DOF chain\n")
    n = 10
    ch = chain10(0.3)
    f = np.zeros(n)
    f[-1] = 0.05
    hb = forced_response(ch.mass, ch.damping, ch.stiffness, f, (0.05, 0.5), contacts=(9,),
                         kt=1.0, mu=0.3, normal_load=1.0, harmonics=H, samples=8 * H)  # fmt: skip
    print(f"the HB curve: {len(hb.omega)} points in {hb.seconds:.2f} s; compared at 12 of "
          "them, shooting started from the HB point's state (so that both follow one branch "
          "where the curve folds): max over the degrees of freedom of |(a1, b1)_HB - (a1, "
          "b1)_shooting| / max |(a1, b1)|; shooting's own error is below its difference "
          "between 800 and 1600 increments (shown)\n")  # fmt: skip
    print("κ = |(ω/a) da/dω| of the HB curve at the point (a: the last mass's first harmonic; "
          "from the neighbouring points): where the curve folds κ is large and a frequency "
          "error δ of a method moves a by κ δ a; Newmark's average acceleration lowers a "
          "natural frequency Ω by about Ω (Ωh)²/12 (1.3e-6 relative at 1600 increments), so "
          "that the fixed-ω comparison is meaningful only where κ is moderate. Richardson: "
          "(4 c_1600 - c_800)/3.\n")  # fmt: skip
    print("| ω | κ | HB vs shooting (1600) | HB vs Richardson | shooting 800 vs 1600 | Newton "
          "iterations (1600) | amplitude (last mass) | W |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|")
    a_hb = hb.amplitude(dof=9)
    picks = np.unique(np.linspace(0, len(hb.omega) - 1, 12).round().astype(int))
    rows = []
    for i in picks:
        om = float(hb.omega[i])
        s = chain10(om)
        coef = {}
        z0 = harmonic_start(s, hb.coefficients[i], hb.contact_force[i])
        for steps in (800, 1600):
            path = NewmarkSystem(s)
            r = shoot(lambda z, p=path, k=steps: p.period(z, k, jacobian=True)[::2], z0,
                      shooting_tolerance(steps))  # fmt: skip
            _, W, _, (t, rec) = path.period(r.z, steps, record=True)
            x = np.array([q[0][0][:, 0] for q in rec])
            coef[steps] = np.stack(first_harmonic(t, x, om), axis=1)
        hbc = hb.coefficients[i][:, 1:3]
        scale = np.max(np.hypot(hbc[:, 0], hbc[:, 1]))
        e_hb = np.max(np.hypot(*(hbc - coef[1600]).T)) / scale
        e_sh = np.max(np.hypot(*(coef[800] - coef[1600]).T)) / scale
        rich = (4.0 * coef[1600] - coef[800]) / 3.0
        e_r = np.max(np.hypot(*(hbc - rich).T)) / scale
        lo, hi = max(i - 1, 0), min(i + 1, len(hb.omega) - 1)
        kappa = abs(om / a_hb[i] * (a_hb[hi] - a_hb[lo]) / (hb.omega[hi] - hb.omega[lo]))
        rows.append((kappa, e_hb, e_r, e_sh, om))
        print(f"| {om:.5f} | {kappa:.3g} | {e_hb:.2e} | {e_r:.2e} | {e_sh:.2e} | {r.iterations} "
              f"| {np.hypot(*hbc[-1]):.6f} | {W:.6e} |")  # fmt: skip
    rows = np.array(rows)
    sure = rows[:, 3] < 1e-3
    print(f"\nwhere shooting is converged in its increments (800 vs 1600 below 1e-3: "
          f"{int(sure.sum())} points), the largest difference HB vs shooting (1600) is "
          f"{rows[sure, 1].max():.2e} (goal 1e-3); at the other {int((~sure).sum())} points "
          f"(ω from {rows[~sure, 4].min():.4f} to {rows[~sure, 4].max():.4f}, where the curve "
          f"folds) shooting at 1600 increments still moves by "
          f"{rows[~sure, 3].min():.1e} to {rows[~sure, 3].max():.1e} from 800: the comparison "
          f"there is limited by the time step, not by the harmonics (HB differs by "
          f"{rows[~sure, 1].min():.1e} to {rows[~sure, 1].max():.1e})")  # fmt: skip


def section_discs():
    print("\n## 5. d = 2 Jenkins contacts (events not located; Jacobian by differences)\n")
    K = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1.5]])
    M = np.diag([1.0, 1.5, 0.8])
    C = lcpfric.rayleigh(M, K, 0.05, 0.02)
    common = dict(friction=0.3, normal_load=1.0, normal_amplitude=-0.6j, omega=0.7,
                  contact_stiffness=2.0)  # fmt: skip
    one = lcpfric.DynamicSystem(mass=M, stiffness=K, damping=C, contacts=[2],
                                force=[0, 0, 1.0], **common)  # fmt: skip
    big = dict(mass=np.kron(np.eye(2), M), stiffness=np.kron(np.eye(2), K),
               damping=np.kron(np.eye(2), C), contacts=[(2, 5)], dims=2, **common)  # fmt: skip
    collinear = lcpfric.DynamicSystem(force=[0, 0, 1.0, 0, 0, 0], **big)
    rotating = lcpfric.DynamicSystem(force=[0, 0, 1.0, 0, 0, 0.7j], **big)
    steps = (100, 200, 400, 800)
    print("the 3-mass chain in two directions, one d = 2 Jenkins contact on the last mass "
          "(N = 1 - 0.6 sin ωt), by `steady_state(..., 'newmark')` (shooting): under a load "
          "along x only it is the d = 1 system (whose events are located)\n")  # fmt: skip
    print("| increments | W, d = 1 (x only) | W, d = 2 (x only) | relative difference | "
          "Newton iterations | s |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    for n in steps:
        W1 = lcpfric.steady_state(one, "newmark", n).W
        start = time.perf_counter()
        r = lcpfric.steady_state(collinear, "newmark", n)
        print(f"| {n} | {W1:.10f} | {r.W:.10f} | {abs(r.W / W1 - 1):.2e} | "
              f"{r.dynamics.newton_iterations} | {time.perf_counter() - start:.1f} |")  # fmt: skip
    print("\nunder a load turning in the plane (f = (cos ωt, -0.7 sin ωt) on the last mass), by "
          "cycle iteration from the equivalent linear start to 1e-11 (the Rayleigh damping "
          "settles it in tens of periods; shooting at 400 increments gives W = "
          f"{lcpfric.steady_state(rotating, 'newmark', 400).W:.10f}):\n")  # fmt: skip
    print("| increments | W | periods |")
    print("|---|---|---|")
    turning, steps = [], (200, 400, 800, 1600, 3200)
    for n in steps:
        path = NewmarkSystem(rotating)
        z0 = equivalent_linear_start(rotating)
        z, res, periods, conv = iterate_cycles(lambda q, p=path, k=n: p.period(q, k)[0], z0,
                                               1e-11, 2000)  # fmt: skip
        W = path.period(z, n)[1]
        turning.append(W)
        print(f"| {n} | {W:.10f} | {periods}{'' if conv else ' (not converged)'} |")
    d = np.abs(np.diff(turning))
    print("\norders of successive differences: "
          + ", ".join(f"{x:.2f}" for x in np.log2(d[:-1] / d[1:])))  # fmt: skip


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(_ROOT / "benchmarks/results/newmark-system.md"))
    args = parser.parse_args(argv)
    with results_file(
        None if args.out == "-" else args.out,
        "Time stepping with inertia for systems, shooting, harmonic balance against shooting",
        "validation/newmark_system.py",
        markdown=True,
    ):
        section_node()
        section_chain3()
        section_shooting()
        section_hb()
        section_discs()


if __name__ == "__main__":
    main()
