"""How many cycles the half-space needs with d = 2, by how the cycles' starts are moved.

``OPENBLAS_NUM_THREADS=1 python benchmarks/studies/cycle_acceleration.py [--out DIR]``

writes ``DIR/cycle_acceleration.md`` (default ``benchmarks/results``; about 10 minutes). With
ν > 0 and d = 2 the transverse slips settle over many cycles; the steady-state driver
(:mod:`lcpfric.periodic.driver`) scales each cycle's change node by node by what the cycle
remembers of its start (:class:`lcpfric.steppers.slip_memory.SlipMemory`) and accelerates that
map with :class:`lcpfric.periodic.acceleration.Anderson` (depth 10). This runs the same d = 2
cases (ν = 0.3) with both (the default), with Anderson alone (depth 10 and 5: the driver before
the memory; the ``newton-cg`` option ``slip_memory=False``), with the memory alone, and with
neither (``Anderson`` of :mod:`lcpfric.periodic.acceleration` replaced for one run), and gives
the cycles, the seconds, W's difference from the default run, and how fast the plain cycles
contract at their end (their slowest mode). The cases: the backends' cross-check contact (grid
10, support k_t0, the scene's steps), the maps' three load cases (grid 20, 100 steps, cycle
tolerance 1e-8), Mindlin-Deresiewicz on grids 40 and 56, and varying P with a phase on grid 32
(200 steps). A run that does not repeat within 200 cycles is marked "no".

``--discrete`` runs the discrete driver's d = 2 systems instead (the chains of
``benchmarks/validation/order_d2.py`` and the grid-10 contact as a ContactSystem) with the memory
and with Aitken's jumps alone, into ``DIR/cycle_acceleration_discrete.md`` (about 1 minute);
``--figure`` draws each cycle's change on grids 40 and 56 by strategy,
``DIR/cycle_acceleration.png`` and ``.pdf`` (about 5 minutes).
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
import math
import time
from pathlib import Path

import numpy as np

import lcpfric
import lcpfric.periodic.acceleration as acceleration
from lcpfric.periodic.acceleration import Anderson

from halfspace import PI, sphere  # noqa: E402  (the same materials and loads)


def cases():
    """(label, model factory, solve options: ``lcpfric.steady_state``'s, and ``grid``, the
    instants of the model's scene)."""
    from lcpfric.scene import make_scene

    def backends():
        m = sphere(0.0, 0.6, 0.7 * PI, nu=0.3, grid=10, dims=2, k_support=1.0)
        m = m.with_support(m.k_t0)
        return m, {"grid": make_scene(m.system(), 200).t, "tol": 1e-10}

    out = [
        (
            "grid 10, support k_t0, P1/P0 = 0, Q1/(μP0) = 0.6, φ = 0.7π (the backends' case)",
            backends,
        )
    ]
    for P1, Q1, phi in ((0.5, 0.4, 0.5), (0.3, 0.6, 0.7), (0.8, 0.2, 0.2)):
        out.append(
            (
                f"grid 20, 100 steps, tol 1e-8, P1/P0 = {P1}, Q1/(μP0) = {Q1}, φ = {phi}π "
                f"(a map's point)",
                lambda P1=P1, Q1=Q1, phi=phi: (
                    sphere(P1, Q1, phi * PI, nu=0.3, grid=20, dims=2),
                    {"steps_per_cycle": 100, "tol": 1e-8},
                ),
            )
        )
    for g in (40, 56):
        out.append(
            (
                f"grid {g}, 200 steps, Mindlin-Deresiewicz (Q1/(μP0) = 0.5)",
                lambda g=g: (
                    sphere(0.0, 0.5, 0.0, nu=0.3, grid=g, dims=2),
                    {"steps_per_cycle": 200},
                ),
            )
        )
    out.append(
        (
            "grid 32, 200 steps, P1/P0 = 0.3, Q1/(μP0) = 0.6, φ = 0.7π",
            lambda: (sphere(0.3, 0.6, 0.7 * PI, nu=0.3, grid=32, dims=2), {"steps_per_cycle": 200}),
        )
    )
    return out


class _Plain:
    """No acceleration: the next cycle starts where the last ended; records the norm of each
    cycle's change of its starting slips."""

    def __init__(self):
        self.norms = []
        self.last = None

    def __call__(self, x, g):
        self.last = g - x
        self.norms.append(float(np.linalg.norm(self.last)))
        return None


def run(factory, depth, memory=True):
    """``(result, seconds, slowest)`` with Anderson at ``depth`` (None: not accelerated) and the
    memory on or off: for the plain cycles (neither), their contraction per cycle over the last
    five or fewer (the geometric mean of the ratios of successive changes) and where the last
    cycle's change is largest: that element's distance from the centre over the contact radius
    at P0, and the share of the change that is transverse (along y)."""
    model, kw = factory()
    grid = kw.pop("grid", None)
    target = model if grid is None else lcpfric.make_scene(model, grid=grid)
    plain = _Plain()
    # the driver's acceleration builds its accelerator as Anderson(); this sets it for one run
    acceleration.Anderson = (lambda: plain) if depth is None else (lambda: Anderson(depth))
    try:
        w = time.perf_counter()
        r = lcpfric.steady_state(
            target,
            "newton-cg",
            max_cycles=200,
            on_nonconvergence="ignore",
            slip_memory=memory,
            **kw,
        )
        seconds = time.perf_counter() - w
    finally:
        acceleration.Anderson = Anderson
    n = plain.norms[-6:]
    rho = (n[-1] / n[0]) ** (1.0 / (len(n) - 1)) if len(n) >= 3 and n[0] > 0 else math.nan
    where = share = math.nan
    if plain.last is not None:
        d = plain.last.reshape(-1, 2)
        k = int(np.argmax(np.hypot(d[:, 0], d[:, 1])))
        where = float(np.hypot(*model.xy[k])) / model.a_eq0
        share = float(np.linalg.norm(d[:, 1]) / np.linalg.norm(d))
    return r, seconds, (rho, where, share)


def discrete(out: Path):
    """The discrete driver (``lcpfric.steady_state``) on d = 2 systems, with the memory (and,
    for coupled nodes, Anderson's acceleration) against Aitken's jumps alone (the driver's
    ``choose`` replaced for one run by its choice for a system whose cycles are not kept whole):
    cycles, wall seconds and W's difference; written to ``cycle_acceleration_discrete.md``."""
    import lcpfric.periodic.driver as driver
    from lcpfric.scene import make_scene
    from order_d2 import cases as chains

    def half_space():
        m = sphere(0.0, 0.6, 0.7 * PI, nu=0.3, grid=10, dims=2, k_support=1.0)
        m = m.with_support(m.k_t0)
        return make_scene(m.system(), 200)

    def aitken_alone(scene, stepper, history, start):
        return keep(scene, stepper, False, start)

    rows = [(name, (lambda s=system: s), "clarabel", {}) for name, system in chains()]
    rows.insert(
        0,
        (
            "1 node, non-collinear, projection (uncoupled)",
            lambda: dict(chains())["1 node, non-collinear"],
            "projection",
            {},
        ),
    )
    rows.append(
        (
            "grid 10 half-space (196 nodes, ν = 0.3, support k_t0, 200 steps)",
            half_space,
            "clarabel",
            {"check_tol": 1e-4, "locate_events": False},
        )
    )
    lines = [
        "# The discrete driver's d = 2 cycles, with and without the memory",
        "",
        f"`OPENBLAS_NUM_THREADS=1 python benchmarks/studies/cycle_acceleration.py --discrete`, "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. Cycle tolerance 1e-10, "
        f"200 steps per cycle (the chains of `benchmarks/validation/order_d2.py`). Cycles, wall "
        f"seconds; W's difference of Aitken's run from the memory's.",
        "",
        "| system | method | memory (default) | Aitken alone | W difference |",
        "|---|---|---|---|---|",
    ]
    print("\n".join(lines), flush=True)
    keep = driver.choose
    for name, make, method, opts in rows:
        runs = []
        for memory in (True, False):
            driver.choose = keep if memory else aitken_alone
            try:
                w = time.perf_counter()
                r = lcpfric.steady_state(make(), method, 200, tol=1e-10, **opts)
                runs.append((r, time.perf_counter() - w))
            finally:
                driver.choose = keep
        (a, sa), (b, sb) = runs
        row = (
            f"| {name} | {method} | {a.cycles}, {sa:.1f} s | {b.cycles}, {sb:.1f} s | "
            f"{(b.W - a.W) / a.W:+.1e} |"
        )
        print(row, flush=True)
        lines.append(row)
    lines.append("")
    (out / "cycle_acceleration_discrete.md").write_text("\n".join(lines))
    print(f"wrote {out / 'cycle_acceleration_discrete.md'}")


def figure(out: Path):
    """``cycle_acceleration.png`` and ``.pdf``: each cycle's relative change (``changes`` of
    the result) for Mindlin-Deresiewicz with d = 2 on grids 40 and 56, by how the cycles'
    starts are moved; page width, TrueType fonts."""
    from lcpfric.figures import style as plotting

    runs = {}
    for g in (40, 56):

        def factory(g=g):
            return sphere(0.0, 0.5, 0.0, nu=0.3, grid=g, dims=2), {"steps_per_cycle": 200}

        for depth, memory, name in (
            (10, True, "memory + Anderson (default)"),
            (10, False, "Anderson alone"),
            (None, True, "memory alone"),
            (None, False, "neither"),
        ):
            r, s, _ = run(factory, depth, memory)
            runs[g, name] = r
            print(f"grid {g}, {name}: {r.cycles} cycles, {s:.1f} s", flush=True)
    with plotting.style():
        fig = plotting.figure(figsize=(plotting.PAGE_WIDTH, 2.7), layout="constrained")
        axes = fig.subplots(1, 2, sharey=True)
        names = ["memory + Anderson (default)", "Anderson alone", "memory alone", "neither"]
        colours = plotting.ramp(len(names))
        for ax, g in zip(axes, (40, 56)):
            for i, name in enumerate(names):
                r = runs[g, name]
                y = r.changes
                ax.semilogy(
                    np.arange(2, y.size + 2),
                    y,
                    color=colours[i],
                    label=name,
                    **plotting.curve_style(i, len(names), y.size),
                )
            ax.axhline(1e-10, color="0.45", lw=0.8, ls=(0, (4, 2)))
            ax.text(
                0.5,
                0.8e-10,
                "tolerance 1e-10",
                transform=ax.get_yaxis_transform(),
                ha="center",
                va="top",
                fontsize=plotting.SMALL,
                color="0.3",
            )
            ax.set_xlim(0, 110)
            ax.set_ylim(1e-12, 0.1)
            late = [name for name in names if runs[g, name].cycles > 110]
            if late:
                ax.text(
                    0.97,
                    0.6,
                    "cut at 110:\n"
                    + "\n".join(
                        f"{name}, {runs[g, name].cycles} cycles"
                        + ("" if runs[g, name].converged else " (no repeat)")
                        for name in late
                    ),
                    transform=ax.transAxes,
                    ha="right",
                    va="top",
                    fontsize=plotting.SMALL,
                    color="0.3",
                )
            ax.set_xlabel("cycle")
            ax.set_title(
                f"grid {g} ({runs[g, names[0]].contact.nodes_in_contact_max} elements in contact)"
            )
            ax.grid(True, which="major", alpha=0.3)
        axes[0].set_ylabel("relative change of the cycle")
        axes[1].legend(loc="upper right", frameon=False)
        fig.suptitle("Mindlin-Deresiewicz, d = 2, ν = 0.3, Q*/(μP) = 0.5, 200 steps per cycle")
        plotting.finish(fig)
        paths = plotting.save(fig, out, "cycle_acceleration", ("png", "pdf"))
    print("wrote " + ", ".join(str(p) for p in paths))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "results"))
    ap.add_argument(
        "--discrete",
        action="store_true",
        help="the discrete driver's d = 2 systems only (about 1 minute)",
    )
    ap.add_argument(
        "--figure",
        action="store_true",
        help="only the figure of the cycles' changes on grids 40 and 56 (about 5 minutes)",
    )
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.discrete:
        return discrete(out)
    if args.figure:
        return figure(out)
    lines = [
        "# Cycles of the d = 2 half-space by how the cycles' starts are moved",
        "",
        f"`OPENBLAS_NUM_THREADS=1 python benchmarks/studies/cycle_acceleration.py`, "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. ν = 0.3, d = 2; cycle "
        f"tolerance 1e-10 unless given. Cycles, wall seconds, W's difference from the "
        f"default (memory and Anderson at depth 10).",
        "",
        "| case | memory + Anderson 10 (default) | Anderson 10 | Anderson 5 | memory "
        "alone | neither | its contraction per cycle | largest late change at r/a | "
        "its transverse share |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    print("\n".join(lines), flush=True)
    for label, factory in cases():
        ref, s_ref, _ = run(factory, 10)
        cells = []
        for depth, memory in ((10, True), (10, False), (5, False), (None, True), (None, False)):
            r, s, rho = (
                (ref, s_ref, None) if (depth, memory) == (10, True) else run(factory, depth, memory)
            )
            diff = (r.W - ref.W) / ref.W
            mark = "" if r.converged else " (no)"
            cells.append(f"{r.cycles}{mark}, {s:.1f} s, {diff:+.1e}")
        cells += [f"{rho[0]:.3f}", f"{rho[1]:.3f}", f"{rho[2]:.3f}"]
        row = f"| {label} | " + " | ".join(cells) + " |"
        print(row, flush=True)
        lines.append(row)
    lines.append("")
    (out / "cycle_acceleration.md").write_text("\n".join(lines))
    print(f"wrote {out / 'cycle_acceleration.md'}")


if __name__ == "__main__":
    main()
