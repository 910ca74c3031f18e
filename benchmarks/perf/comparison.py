"""Error against run time for every method: the cases, the runs and their reports
(``python benchmarks/perf/compare_backends.py``).

Every method is run on a set of cases at steps per cycle from 50 to 1e5 and judged against the
exact solution: the single node's closed form, and for the multi-node case a block-diagonal
system whose exact dissipation is the sum of its nodes' exact answers. Wall time is the median
of repeats, measured in the same run for all methods. Writes ``compare.csv``, ``compare.md`` and
``compare.png`` (log-log error against time, one panel per case, one line per method).

The coupled cases (:data:`COUPLED_CASES`, ``compare_backends.py --coupled``) are d = 1 systems with
a coupled stiffness (chains with k_coupling = 10, a dense random SPD K), judged against
``steady_state(model, method="exact").W`` computed once per case; that reference is checked
independently by Richardson extrapolation of the explicit stepper (:func:`richardson`). They
write ``compare-coupled.csv``, ``.md`` and ``.png`` (:func:`write_coupled_outputs`).
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

import csv
import math
import os
import statistics
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = [
    "CASES",
    "Case",
    "COUPLED_CASES",
    "CoupledCase",
    "run_comparison",
    "convergence_order",
    "richardson",
    "write_coupled_outputs",
    "figure_compare",
]


@dataclass(frozen=True)
class Case:
    """A benchmark case: one node (P̂1, Q̂1, φ), or several uncoupled nodes (``nodes``)."""

    name: str
    P1: float = 0.0
    Q1: float = 0.0
    phi: float = 0.0
    nodes: tuple = ()

    @property
    def multi(self) -> bool:
        return bool(self.nodes)

    def model(self):
        from lcpfric.model.loads import Harmonic
        from lcpfric.model import ContactSystem, IndependentSprings, SingleNode

        if not self.multi:
            return SingleNode.normalized(self.P1, self.Q1, self.phi)
        n = len(self.nodes)
        return ContactSystem(
            stiffness=np.eye(n),
            friction=np.ones(n),
            tangential_loads=tuple(Harmonic(0.0, q, f) for _, q, f in self.nodes),
            normal=IndependentSprings(tuple(Harmonic(1.0, p, 0.0) for p, _, _ in self.nodes)),
        )

    def exact(self) -> float:
        """Exact Ŵ (single node) or exact W = Σ Q̂1_i Ŵ_i (block-diagonal normalized nodes)."""
        from lcpfric.exact import exact_W_hat

        if not self.multi:
            return float(exact_W_hat(self.P1, self.Q1, self.phi))
        P, Q, F = (np.array(x, dtype=float) for x in zip(*self.nodes))
        return float(np.sum(Q * exact_W_hat(P, Q, F)))

    def value(self, result) -> float:
        return result.W if self.multi else result.W_hat

    def label(self) -> str:
        if self.multi:
            return f"{self.name} ({len(self.nodes)} uncoupled nodes, with and without separation)"
        return f"{self.name} (P̂1={self.P1:g}, Q̂1={self.Q1:g}, φ={self.phi / math.pi:.3g}π)"


PI = math.pi
CASES = (
    Case("contact", 0.5, 2.0, 0.0),
    Case("contact-phase", 0.5, 2.0, 0.6 * PI),
    Case("separation", 1.5, 2.0, 0.6 * PI),
    Case("large", 5.0, 5.0, 0.6 * PI),
    Case("near-shakedown", 0.5, 1.01, 0.3 * PI),
    Case("very-large", 20.0, 50.0, 0.5 * PI),
    Case(
        "multi-node",
        nodes=((0.5, 2.0, 0.0), (1.5, 2.0, 0.6 * PI), (5.0, 5.0, 0.6 * PI), (0.3, 1.5, 1.0)),
    ),
)
FULL_STEPS = (50, 100, 200, 500, 1000, 2000, 5000, 10000, 20000, 50000, 100000)
QUICK_STEPS = (50, 200, 1000, 5000, 20000)


# -- coupled d = 1 systems, judged against the exact event-by-event steady state ---------------
_REFERENCES: dict = {}  # case name -> (W, seconds, solver_stats) of steady_state(..., "exact")


@dataclass(frozen=True)
class CoupledCase:
    """A coupled d = 1 system (``build()`` returns its ContactSystem) whose reference is
    ``steady_state(model, method="exact").W``, computed once per case and process.
    ``max_steps`` caps the steps per cycle it is run at (the costly cases)."""

    name: str
    description: str
    build: Callable
    max_steps: int | None = None

    multi = True
    coupled = True

    def model(self):
        return self.build()

    def reference(self) -> tuple:
        """(W, seconds, solver_stats) of the exact steady state (cached)."""
        if self.name not in _REFERENCES:
            from lcpfric.periodic import steady_state

            t0 = time.perf_counter()
            res = steady_state(self.model(), method="exact")
            _REFERENCES[self.name] = (
                float(res.W),
                time.perf_counter() - t0,
                dict(res.solver_stats),
            )
        return _REFERENCES[self.name]

    def exact(self) -> float:
        return self.reference()[0]

    def value(self, result) -> float:
        return result.W

    def steps(self, steps) -> tuple:
        return tuple(n for n in steps if self.max_steps is None or n <= self.max_steps)

    def label(self) -> str:
        return f"{self.name} ({self.description})"


_Q3, _PHI3 = (1.5, 2.0, 2.5), (0.0, 0.6 * PI, 0.38 * PI)


def _chain3_contact():
    from lcpfric.model import chain

    return chain(3, k_coupling=10.0, P1=(0.3, 0.6, 0.8), Q1=_Q3, phi=_PHI3)


def _chain3_separation():
    from lcpfric.model import chain

    return chain(3, k_coupling=10.0, P1=(1.5, 0.6, 2.5), Q1=_Q3, phi=_PHI3)


def _dense_spd():
    """K = A Aᵀ/n + I with A standard normal (seed 1), 5 nodes, 2 of them separating."""
    from lcpfric.model import ContactSystem, IndependentSprings
    from lcpfric.model.loads import Harmonic

    n = 5
    rng = np.random.default_rng(1)
    A = rng.standard_normal((n, n))
    K = A @ A.T / n + np.eye(n)
    P1 = (0.4, 1.6, 0.8, 2.2, 0.5)
    Q1, phi = rng.uniform(1.0, 3.0, n), rng.uniform(0.0, PI, n)
    return ContactSystem(
        stiffness=K,
        friction=np.ones(n),
        tangential_loads=tuple(Harmonic(0.0, q, f) for q, f in zip(Q1, phi)),
        normal=IndependentSprings(tuple(Harmonic(1.0, p, 0.0) for p in P1)),
    )


def _chain100():
    """100 nodes, k_coupling = 10; per-node P1 ~ U(0.2, 1.5), Q1 ~ U(1, 3), φ ~ U(0, π),
    seed 100 (about a quarter of the nodes separate)."""
    from lcpfric.model import chain

    n = 100
    rng = np.random.default_rng(100)
    return chain(
        n,
        k_coupling=10.0,
        P1=rng.uniform(0.2, 1.5, n),
        Q1=rng.uniform(1.0, 3.0, n),
        phi=rng.uniform(0.0, PI, n),
    )


def _separation_reversal():
    """3 nodes, k_coupling = 19: node 0 starts to slip about 1e-4 of a cycle before node 1
    separates; node 1 stops and crosses to its other limit, node 2 stops (issue 38, item 2)."""
    from lcpfric.model import chain

    return chain(
        3,
        k_coupling=19.00222,
        friction=(0.393073, 0.687262, 0.843258),
        P1=(0.770597, 1.446758, 0.565331),
        Q1=(1.963212, 1.552373, 1.410178),
        phi=(5.486, 0.560708, 3.784577),
    )


COUPLED_CASES = (
    CoupledCase("chain-contact", "3-node chain, k_coupling = 10, full contact", _chain3_contact),
    CoupledCase(
        "chain-separation", "3-node chain, k_coupling = 10, 2 nodes separate", _chain3_separation
    ),
    CoupledCase("dense-spd", "dense random SPD K, 5 nodes, 2 separate", _dense_spd),
    CoupledCase(
        "separation-reversal",
        "3-node chain, k_coupling = 19, a separating node reverses as its neighbour starts",
        _separation_reversal,
    ),
    CoupledCase(
        "chain-100", "100-node chain, k_coupling = 10, random loads", _chain100, max_steps=1600
    ),
)
#: steps per cycle of the coupled cases (doubling: the Richardson check uses the two finest)
COUPLED_STEPS = (100, 200, 400, 800, 1600, 3200, 6400, 12800)
COUPLED_QUICK_STEPS = (100, 200, 400, 800, 1600)
#: the methods run on the coupled cases by default (those installed)
COUPLED_METHODS = (
    "exact",
    "explicit",
    "clarabel",
    "osqp",
    "active-set",
    "qpsolvers:proxqp",
    "cvxpy:CLARABEL",
)


def _closed_form(method: str) -> bool:
    """Whether the registry lists ``method`` as a closed form (timed once, no step counts)."""
    from lcpfric.methods import CLOSED_FORM, get_method

    return get_method(method)[0].kind == CLOSED_FORM


def default_methods() -> list[str]:
    from lcpfric.methods import available_methods

    return available_methods()


def _time(fn, repeats: int):
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, statistics.median(times)


def run_comparison(
    cases=CASES,
    methods=None,
    steps=FULL_STEPS,
    *,
    budget: float = 20.0,
    repeats: int = 3,
    placement: str = "contact",
    log=print,
) -> list[dict]:
    """Run every method on every case; return one row per (case, method, steps).

    A method stops refining a case once one run takes longer than ``budget`` seconds, or the
    next is predicted to. A method that cannot treat a case (or fails) gets one row saying why.
    """
    from lcpfric.errors import LcpfricError
    from lcpfric.periodic import steady_state

    methods = list(methods or default_methods())
    rows = []
    for case in cases:
        ref = case.exact()
        model = case.model()
        for method in methods:
            closed = _closed_form(method)
            coupled = getattr(case, "coupled", False)
            run_steps = (0,) if closed else (case.steps(steps) if coupled else steps)
            last, prev_n = 0.0, 1
            for n in run_steps:
                if not closed and last * n / max(prev_n, 1) > budget:
                    rows.append(
                        dict(
                            case=case.name,
                            method=method,
                            steps_per_cycle=n,
                            rel_error="",
                            seconds="",
                            cycles="",
                            steps="",
                            W="",
                            exact=ref,
                            note="skipped: over time budget",
                        )
                    )
                    continue
                try:
                    if closed and coupled:
                        # the reference itself: its cost (its error is 0 by definition)
                        ref_sec = case.reference()[1]
                        res, sec = _time(
                            lambda: steady_state(model, method), repeats if ref_sec < 2.0 else 1
                        )
                        rows.append(
                            dict(
                                case=case.name,
                                method=method,
                                steps_per_cycle=0,
                                rel_error="",
                                seconds=sec,
                                cycles=res.cycles,
                                steps=0,
                                W=res.W,
                                exact=ref,
                                note="reference: "
                                + ", ".join(
                                    f"{k} {res.solver_stats[k]}"
                                    for k in ("events_per_cycle", "cycles")
                                    if k in res.solver_stats
                                ),
                            )
                        )
                        log(f"{case.name:15s} {method:22s}       reference  {sec:9.4f} s")
                        continue
                    if closed:
                        # what computes Ŵ exactly: lcpfric.exact_W_hat (steady_state(...,
                        # "exact") adds a time series of the cycle, ~0.3 ms at 2000 points)
                        val, sec = _time(case.exact, 200)
                        res = None
                    else:
                        res, sec = _time(
                            lambda: steady_state(model, method, n or 2000, placement=placement),
                            repeats if last < 2.0 else 1,
                        )
                        val = case.value(res)
                except LcpfricError as exc:
                    rows.append(
                        dict(
                            case=case.name,
                            method=method,
                            steps_per_cycle=n,
                            rel_error="",
                            seconds="",
                            cycles="",
                            steps="",
                            W="",
                            exact=ref,
                            note=f"error: {type(exc).__name__}: {exc}",
                        )
                    )
                    log(f"{case.name:15s} {method:22s} {n:7d}  {type(exc).__name__}: {exc}")
                    break
                err = abs(val - ref) / abs(ref) if ref else abs(val)
                rows.append(
                    dict(
                        case=case.name,
                        method=method,
                        steps_per_cycle=n,
                        rel_error=err,
                        seconds=sec,
                        cycles=1 if res is None else res.cycles,
                        steps=0 if res is None else res.steps_used,
                        W=val,
                        exact=ref,
                        note="",
                    )
                )
                log(f"{case.name:15s} {method:22s} {n:7d}  err {err:9.2e}  {sec:9.4f} s")
                last, prev_n = sec, max(n, 1)
    return rows


def convergence_order(
    rows, case: str, method: str, floor: float = 1e-13, min_steps: int = 200
) -> float | None:
    """Least-squares slope of -log(error) against log(steps), over the runs at or above
    ``min_steps`` whose error is above the round-off ``floor``."""
    pts = [
        (r["steps_per_cycle"], r["rel_error"])
        for r in rows
        if r["case"] == case
        and r["method"] == method
        and r["rel_error"] != ""
        and r["steps_per_cycle"] >= min_steps
        and r["rel_error"] > floor
    ]
    if len(pts) < 3:
        return None
    n, e = np.array(pts, dtype=float).T
    return float(-np.polyfit(np.log(n), np.log(e), 1)[0])


def time_to_reach(rows, case: str, method: str, target: float) -> tuple[float, int] | None:
    """(seconds, steps) of the cheapest run of a method reaching ``target`` relative error."""
    ok = [
        (r["seconds"], r["steps_per_cycle"])
        for r in rows
        if r["case"] == case
        and r["method"] == method
        and r["rel_error"] != ""
        and r["rel_error"] <= target
    ]
    return min(ok) if ok else None


def _write_csv(path: str, rows) -> None:
    """Every run, one row each (the columns of :func:`run_comparison`'s rows)."""
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    fields = [
        "case",
        "method",
        "steps_per_cycle",
        "rel_error",
        "seconds",
        "cycles",
        "steps",
        "W",
        "exact",
        "note",
    ]
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)


def _order_table(rows, cases, methods, orders: dict) -> list:
    """Markdown table of measured orders, a row per method, a column per case; fills
    ``orders[method][case]``."""
    lines = [
        "| method | " + " | ".join(c.name for c in cases) + " |",
        "|---|" + "---|" * len(cases),
    ]
    for m in methods:
        cells = []
        for c in cases:
            o = convergence_order(rows, c.name, m)
            orders.setdefault(m, {})[c.name] = o
            cells.append("-" if o is None else f"{o:.2f}")
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    return lines


def write_outputs(rows, out_dir: str, cases=CASES, command: str = "") -> dict:
    """Write compare.csv, compare.md and compare.png; return the headline numbers."""
    _write_csv(os.path.join(out_dir, "compare.csv"), rows)
    methods = list(dict.fromkeys(r["method"] for r in rows))
    closed = {m for m in methods if _closed_form(m)}
    headline = {"orders": {}, "time_to_1e-6": {}, "exact": {}}
    lines = [
        f"Reproduce: `{command}`" if command else "",
        "",
        "## Time to reach a relative error of 1e-6 (s; steps per cycle)",
        "",
        "| method | " + " | ".join(c.name for c in cases) + " |",
        "|---|" + "---|" * len(cases),
    ]
    for m in methods:
        cells = []
        for c in cases:
            t = time_to_reach(rows, c.name, m, 1e-10 if m in closed else 1e-6)
            cells.append(
                "-" if t is None else (f"{t[0]:.2e}" + ("" if m in closed else f" ({t[1]})"))
            )
            headline["time_to_1e-6"].setdefault(m, {})[c.name] = None if t is None else t[0]
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    lines += [
        "",
        "(`exact`: one call of `lcpfric.exact_W_hat` (the sum over nodes for the "
        "multi-node case), median of 200; its error is below 1e-10 on every case.)",
        "",
    ]
    if "exact" in methods and "explicit" in methods:
        lines += [
            "## Exact to 1e-10 against explicit to 1e-6, same run",
            "",
            "| case | exact (s) | explicit to 1e-6 (s) | ratio |",
            "|---|---|---|---|",
        ]
        for c in cases:
            te = time_to_reach(rows, c.name, "exact", 1e-10)
            tx = time_to_reach(rows, c.name, "explicit", 1e-6)
            if te and tx:
                ratio = te[0] / tx[0]
                headline.setdefault("exact_over_explicit", {})[c.name] = ratio
                lines.append(f"| {c.name} | {te[0]:.2e} | {tx[0]:.2e} | 1/{1 / ratio:.0f} |")
        lines.append("")
    lines += [
        "## Measured convergence order (least-squares slope, runs with >= 200 steps and "
        "error above 1e-13)",
        "",
        *_order_table(rows, cases, [m for m in methods if m not in closed], headline["orders"]),
    ]
    lines += ["", "## Relative error of Ŵ (W for multi-node) against the exact solution", ""]
    for c in cases:
        sub = [r for r in rows if r["case"] == c.name]
        steps = sorted({r["steps_per_cycle"] for r in sub if r["method"] not in closed})
        lines += [
            f"### {c.label()}",
            "",
            "| method | " + " | ".join(str(s) for s in steps) + " |",
            "|---|" + "---|" * len(steps),
        ]
        for m in methods:
            cells = []
            for s in steps:
                hit = [r for r in sub if r["method"] == m and r["steps_per_cycle"] == s]
                cells.append(
                    f"{hit[0]['rel_error']:.1e}" if hit and hit[0]["rel_error"] != "" else ""
                )
            if m in closed:
                hit = [r for r in sub if r["method"] == m]
                cells = [
                    f"{hit[0]['rel_error']:.1e}" if hit and hit[0]["rel_error"] != "" else ""
                ] + [""] * (len(steps) - 1)
            lines.append(f"| {m} | " + " | ".join(cells) + " |")
        notes = {r["method"]: r["note"] for r in sub if r["note"].startswith("error")}
        for m, note in notes.items():
            lines.append(f"\n{m}: {note}")
        lines.append("")
    with open(os.path.join(out_dir, "compare.md"), "w") as fh:
        fh.write("\n".join(lines))
    files = ["compare.csv", "compare.md"]
    if _plot(rows, cases, methods, closed, os.path.join(out_dir, "compare.png")):
        files.append("compare.png")
    headline["files"] = files
    return headline


#: relative errors of exactly 0 (exact to round-off) are drawn at this floor of the log axis
ZERO_FLOOR = 1e-17
#: the accuracy the tables time (``time_to_reach``), drawn as a labelled line
TARGET = 1e-6


def _panel_title(case) -> str:
    """Two lines: the case's name, then its loads (or its nodes)."""
    if case.multi:
        return f"{case.name}\n{len(case.nodes)} uncoupled nodes, with and without separation"
    from lcpfric.figures.style import phi_label

    return (
        f"{case.name}\n$\\hat P_1$ = {case.P1:g}, $\\hat Q_1$ = {case.Q1:g}, {phi_label(case.phi)}"
    )


def figure_compare(rows, cases, methods, closed):
    """compare.png's figure in the house print style (:mod:`lcpfric.figures.style`): page wide,
    panels of equal width (three a row), titles and labels at 7-8 pt, one panel per case with
    log-log error against wall time, a line per method (its colour, marker and line style), the
    closed forms as stars; the target error :data:`TARGET` and the errors of exactly 0 (drawn
    at :data:`ZERO_FLOOR`) labelled in the legend, which fills the last row's empty panels (or
    sits just below the panels)."""
    from matplotlib import colormaps
    from matplotlib.lines import Line2D

    from lcpfric.figures import style as pl

    n = len(cases)
    ncol = 1 if n == 1 else (2 if n in (2, 4) else 3)
    nrow = math.ceil(n / ncol)
    spare = nrow * ncol - n
    tab = colormaps["tab20"]
    colors = [tab(i) for i in (0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 1, 3, 5, 7, 9)]
    with pl.style():
        width = pl.COLUMN_WIDTH if ncol == 1 else pl.PAGE_WIDTH
        fig = pl.figure(
            figsize=(width, 2.15 * nrow + (0.0 if spare else 1.0)), layout="constrained"
        )
        grid = fig.add_gridspec(nrow, ncol)
        axes = [fig.add_subplot(grid[k // ncol, k % ncol]) for k in range(n)]
        handles = {}
        zero_seen = False
        for ax, c in zip(axes, cases):
            steppers = [m for m in methods if m not in closed]
            for i, m in enumerate(methods):
                pts = sorted(
                    (r["steps_per_cycle"], r["seconds"], r["rel_error"])
                    for r in rows
                    if r["case"] == c.name and r["method"] == m and r["rel_error"] != ""
                )
                if not pts:
                    continue
                _, x, y = (np.asarray(v, dtype=float) for v in zip(*pts))
                color = colors[i % len(colors)]
                if m in closed:
                    kw = dict(marker="*", ms=8, ls="none", mec="black", mew=0.4)
                else:
                    j = steppers.index(m)
                    kw = pl.curve_style(j, len(steppers), len(pts))
                    kw.update(lw=0.9, ms=3.0, markevery=None)
                zero = y <= 0.0
                zero_seen |= bool(zero.any())
                # the line joins the non-zero errors; the zeros sit on the floor, unjoined
                (line,) = ax.loglog(
                    np.where(zero, np.nan, x), np.where(zero, np.nan, y), color=color, **kw
                )
                if zero.any():
                    ax.loglog(
                        x[zero],
                        np.full(int(zero.sum()), ZERO_FLOOR),
                        color=color,
                        **{**kw, "ls": "none"},
                        zorder=3,
                    )
                handles.setdefault(m, Line2D([], [], color=color, **kw))
            ax.axhline(TARGET, color="0.45", lw=0.8, ls=(0, (4, 2)), zorder=1)
            ax.axhline(ZERO_FLOOR, color="0.45", lw=0.6, ls=(0, (1, 1.5)), zorder=1)
            ax.set_ylim(ZERO_FLOOR / 5, None)
            ax.set_title(_panel_title(c), fontsize=pl.SMALL, pad=3, linespacing=1.25)
            ax.set_xlabel("wall time per steady state (s)", labelpad=1)
            ax.set_ylabel("relative error", labelpad=1)
            ax.grid(True, which="major", alpha=0.3, lw=0.4)
        handles[f"relative error {TARGET:.0e} (the tables' target)".replace("e-0", "e-")] = Line2D(
            [], [], color="0.45", lw=0.8, ls=(0, (4, 2))
        )
        if zero_seen:
            handles[f"error 0 (exact to round-off), drawn at {ZERO_FLOOR:.0e}"] = Line2D(
                [], [], color="0.45", lw=0.6, ls=(0, (1, 1.5))
            )
        labels = list(handles)
        if spare:
            box = fig.add_subplot(grid[nrow - 1, ncol - spare :])
            box.axis("off")
            box.legend(
                list(handles.values()),
                labels,
                loc="center",
                ncols=2 if spare > 1 else 1,
                frameon=False,
                fontsize=pl.SMALL,
                title="method (star: closed form)",
            )
        else:
            fig.legend(
                list(handles.values()),
                labels,
                loc="outside lower center",
                ncols=min(3, len(labels)),
                frameon=False,
                fontsize=pl.SMALL,
                title="method (star: closed form)",
            )
        return pl.finish(fig)


def _plot(rows, cases, methods, closed, path) -> bool:
    """Draw compare.png (:func:`figure_compare`); False (and nothing written) without
    matplotlib."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    from lcpfric.figures import style as pl

    fig = figure_compare(rows, cases, methods, closed)
    fig.savefig(path, dpi=pl.DPI)
    return True


def read_rows(path: str) -> list[dict]:
    """Rows of a compare.csv, with numbers as numbers (to redraw or re-tabulate a run)."""
    rows = []
    with open(path, newline="") as fh:
        for r in csv.DictReader(fh):
            for key in ("steps_per_cycle", "cycles", "steps"):
                r[key] = int(r[key]) if r[key] != "" else ""
            for key in ("rel_error", "seconds", "W", "exact"):
                r[key] = float(r[key]) if r[key] != "" else ""
            rows.append(r)
    return rows


# -- the coupled cases' outputs ------------------------------------------------------------------
def richardson(rows, case: str, method: str = "explicit", order: float = 2.0) -> dict | None:
    """Richardson extrapolation of a method's W at its two finest grids (requested steps per
    cycle n1 < n2): ``W_rich = W2 + (W2 - W1) / ((n2/n1)^order - 1)``, an estimate of the exact
    W independent of the exact solver. Returns the steps, W_rich, the reference, and the
    relative errors of W_rich and of the finest run against the reference (None with fewer
    than two runs)."""
    pts = sorted(
        (r["steps_per_cycle"], r["W"], r["exact"])
        for r in rows
        if r["case"] == case and r["method"] == method and r["rel_error"] != ""
    )
    if len(pts) < 2:
        return None
    (n1, w1, _), (n2, w2, ref) = pts[-2:]
    w = w2 + (w2 - w1) / ((n2 / n1) ** order - 1.0)
    scale = abs(ref) or 1.0
    return dict(
        case=case,
        method=method,
        steps=(n1, n2),
        W_rich=w,
        W_exact=ref,
        abs_error=abs(w - ref),
        rich_error=abs(w - ref) / scale,
        finest_error=abs(w2 - ref) / scale,
    )


def _per_cycle(rows, case: str, method: str):
    """Seconds per cycle of a method's finest run (its time over its cycles), and its steps."""
    ok = [
        r
        for r in rows
        if r["case"] == case
        and r["method"] == method
        and r["seconds"] != ""
        and r["cycles"] not in ("", 0)
    ]
    if not ok:
        return None
    r = max(ok, key=lambda r: r["steps_per_cycle"])
    return r["seconds"] / r["cycles"], r["steps_per_cycle"]


COUPLED_OUTPUTS = ("compare-coupled.csv", "compare-coupled.md", "compare-coupled.png")


def write_coupled_outputs(rows, out_dir: str, cases=COUPLED_CASES, command: str = "") -> dict:
    """Write compare-coupled.csv, .md and .png; return the headline numbers (measured orders,
    the Richardson check, the reference's cost)."""
    _write_csv(os.path.join(out_dir, COUPLED_OUTPUTS[0]), rows)
    methods = list(dict.fromkeys(r["method"] for r in rows))
    closed = {m for m in methods if _closed_form(m)}
    steppers = [m for m in methods if m not in closed]
    headline = {"orders": {}, "richardson": {}, "reference": {}}
    lines = [
        f"Reproduce: `{command}`" if command else "",
        "",
        'Reference: `steady_state(model, method="exact").W`, once per case. Errors are '
        "|W - W_exact| / W_exact.",
        "",
        "## Measured convergence order (least-squares slope of log error against log "
        "steps, runs with >= 200 steps and error above 1e-13)",
        "",
        *_order_table(rows, cases, steppers, headline["orders"]),
    ]
    lines += [
        "",
        "## Independent check of the reference: Richardson extrapolation of explicit",
        "",
        "W_rich = W(n2) + (W(n2) - W(n1))/3 at explicit's two finest grids n1 < n2 (second order).",
        "",
        "| case | W_exact | n1, n2 | explicit error at n2 | W_rich | abs. error of W_rich "
        "| relative |",
        "|---|---|---|---|---|---|---|",
    ]
    for c in cases:
        rc = richardson(rows, c.name)
        headline["richardson"][c.name] = rc
        if rc:
            lines.append(
                f"| {c.name} | {rc['W_exact']:.12g} | {rc['steps'][0]}, "
                f"{rc['steps'][1]} | {rc['finest_error']:.1e} | {rc['W_rich']:.12g} "
                f"| {rc['abs_error']:.1e} | {rc['rich_error']:.1e} |"
            )
    lines += [
        "",
        "## Cost of the reference (`exact`)",
        "",
        "| case | seconds per steady state | events per cycle | cycles |",
        "|---|---|---|---|",
    ]
    for c in cases:
        hit = [
            r for r in rows if r["case"] == c.name and r["method"] in closed and r["seconds"] != ""
        ]
        if not hit and c.name not in _REFERENCES:
            continue
        W, sec, stats = _REFERENCES.get(c.name, (None, None, {}))
        sec = hit[0]["seconds"] if hit else sec
        headline["reference"][c.name] = dict(
            seconds=sec, **{k: stats.get(k) for k in ("events_per_cycle", "cycles")}
        )
        lines.append(
            f"| {c.name} | {sec:.3g} | {stats.get('events_per_cycle', '')} | "
            f"{stats.get('cycles', '')} |"
        )
    lines += [
        "",
        "## Relative error against exact, per case",
        "",
        "Time per cycle: the finest run's wall time over the cycles the periodic driver "
        "ran (the steps per cycle in brackets).",
        "",
    ]
    for c in cases:
        sub = [r for r in rows if r["case"] == c.name]
        steps = sorted({r["steps_per_cycle"] for r in sub if r["method"] not in closed})
        lines += [
            f"### {c.label()}",
            "",
            "| method | " + " | ".join(str(s) for s in steps) + " | order | s per cycle |",
            "|---|" + "---|" * (len(steps) + 2),
        ]
        for m in steppers:
            cells = []
            for s in steps:
                hit = [r for r in sub if r["method"] == m and r["steps_per_cycle"] == s]
                cells.append(
                    f"{hit[0]['rel_error']:.1e}" if hit and hit[0]["rel_error"] != "" else ""
                )
            o = convergence_order(rows, c.name, m)
            pc = _per_cycle(rows, c.name, m)
            cells += [
                "-" if o is None else f"{o:.2f}",
                "-" if pc is None else f"{pc[0]:.2e} ({pc[1]})",
            ]
            lines.append(f"| {m} | " + " | ".join(cells) + " |")
        notes = {r["method"]: r["note"] for r in sub if r["note"].startswith("error")}
        for m, note in notes.items():
            lines.append(f"\n{m}: {note}")
        lines.append("")
    with open(os.path.join(out_dir, COUPLED_OUTPUTS[1]), "w") as fh:
        fh.write("\n".join(lines))
    files = list(COUPLED_OUTPUTS[:2])
    if _plot_coupled(rows, cases, steppers, closed, os.path.join(out_dir, COUPLED_OUTPUTS[2])):
        files.append(COUPLED_OUTPUTS[2])
    headline["files"] = files
    return headline


def _plot_coupled(rows, cases, steppers, closed, path) -> bool:
    """compare-coupled.png in the house print style (lcpfric.figures.style): page width, 7 pt text,
    one panel per case, every method a labelled line, the exact reference's cost a labelled
    vertical line. False (nothing written) without matplotlib."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    from lcpfric.figures import style as pl

    ncol = 2
    nrow = math.ceil(len(cases) / ncol)
    with pl.style():
        fig = pl.figure(figsize=(pl.PAGE_WIDTH, 2.3 * nrow + 0.4), layout="constrained")
        axes = fig.subplots(nrow, ncol, squeeze=False)
        colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#a6761d", "#666666"]
        for ax, c in zip(axes.flat, cases):
            for i, m in enumerate(steppers):
                # in the order of refinement (run times are noisy, step counts are not)
                pts = sorted(
                    (r["steps_per_cycle"], r["seconds"], max(r["rel_error"], 1e-16))
                    for r in rows
                    if r["case"] == c.name and r["method"] == m and r["rel_error"] != ""
                )
                if not pts:
                    continue
                _, x, y = zip(*pts)
                ax.loglog(
                    x,
                    y,
                    label=m,
                    color=colors[i % len(colors)],
                    **pl.curve_style(i, len(steppers), len(pts)),
                )
            ref = [
                r
                for r in rows
                if r["case"] == c.name and r["method"] in closed and r["seconds"] != ""
            ]
            if ref:
                ax.axvline(
                    ref[0]["seconds"],
                    color="k",
                    lw=0.8,
                    ls=(0, (1, 1.5)),
                    label="exact (the reference): its run time",
                )
            ax.set_title(f"{c.name}\n{c.description}", fontsize=pl.SMALL)
            ax.set_xlabel("wall time per steady state (s)")
            ax.set_ylabel(r"$|W - W_{\mathrm{exact}}|\,/\,W_{\mathrm{exact}}$")
            ax.grid(True, which="major", alpha=0.3)
        for ax in list(axes.flat)[len(cases) :]:
            ax.axis("off")
        handles = {}
        for ax in axes.flat:
            for h, lab in zip(*ax.get_legend_handles_labels()):
                handles.setdefault(lab, h)
        fig.legend(
            list(handles.values()),
            list(handles),
            loc="outside lower center",
            ncol=min(len(handles), 4),
        )
        pl.finish(fig)
        fig.savefig(path, dpi=pl.DPI)
    return True
