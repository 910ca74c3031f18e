"""Time per step and peak memory against the number of nodes n, for every time-stepping method.

Usage (from the repository root)::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. python benchmarks/perf/scaling.py [--quick] [--out DIR]
        [--budget SECONDS] [--cycles N] [--partial] [--methods a,b] [--systems a,b]

writes ``DIR/scaling.csv``, ``scaling.md``, ``scaling.png`` and ``scaling.pdf`` (default
``benchmarks/results``) and prints each case as it finishes. ``--quick`` is about a minute of
CPU: the dense chain to n = 400 with every method, the sparse chain to n = 1e4 with the two
active-set variants only, 100 steps per cycle, one cycle per case, 20 CPU s per case; its core
function is what ``tests/test_scaling_bench.py`` runs, in-process, on n = 10 and 40.

What is measured
----------------
Methods ``explicit``, ``clarabel``, ``osqp`` and ``active-set``, each at its defaults; the three
last locate the events inside an increment (``locate_events=True``) and so compute one and the
same discretization; ``explicit`` always locates its events (its own discretization: its first
cycle differs, its steady state agrees). Also ``active-set-no-events`` (``locate_events=False``:
one projection per step, first order on coupled systems, so a different W), timed only: on the
sparse chain the event location costs a factorization per event and the events per cycle grow
with n, so it is what reaches n = 1e5. Systems (d = 1, friction 1, P0 = 1, seeded loads):

* ``chain``: ``lcpfric.chain(n, k_coupling=0.5, P1 ~ U(1.2, 2), Q1 ~ U(0.5, 2),
  phi ~ U(0, 2π))`` with K stored dense, n = 10 to 4000. Every node separates at its own two
  instants, which the scene puts on the grid: the scene has about 500 + 2n steps;
* ``dense-spd``: a genuinely dense K = A Aᵀ/n + I (``dense()`` of ``exact_discrete.py``), loads
  as above, n = 10 to 4000;
* ``chain-sparse``: the ``chain`` system with K kept sparse, n = 1000;
* ``chain-sparse-common``: a sparse chain whose nodes all separate at the same instants (P1 =
  1.5 and the same normal phase everywhere; Q1 and phi per node), so the grid stays at 500 steps
  (2000 at n = 1e5, run with the driver's ``history=False``, skipped if the driver has none),
  n = 1e3 to 1e5.

Every (system, n) is built once per process from fixed seeds into one Scene, so every method
steps the same grid. Each case runs in its own child process (``--child``): it builds the
scene, warms the method up on a 3-node system (imports and first calls out of the timing), then
runs ``cycles`` cycles (``max_cycles=3``, ``on_nonconvergence="ignore"``, one cycle with
``--quick``) and reports

* **s/step**: CPU seconds of the child (``time.process_time``) over cycles × scene steps. The
  dense K⁻¹ is formed by the convex backends (their problem is written in C) and by the driver
  up to 2000 unknowns (``lcpfric.model.system.COMPLIANCE_DENSE``; its displacement scale,
  ``max diag K⁻¹``), even for a sparse K. The child forms it (cached on the system) before the
  timed cycles when the case would, and reports its CPU time apart (**K⁻¹ s**, blank when not
  formed): O(n³) once, it would otherwise be spread over the steps. Its memory, 8 n² bytes, is
  in the peak; a case that forms it where three such arrays exceed half the memory is skipped;
* **floor s**: the time of one product with the compliance C = K⁻¹ (n x n, dense systems) or
  with the sparse K (sparse systems), median of 7 batches, measured by one child per (system, n)
  in the same run; **ratio** = s/step / floor;
* **peak MB**: the child's peak resident memory minus that of a baseline child that only
  imports lcpfric and builds the system. On Linux ``getrusage(RUSAGE_SELF).ru_maxrss`` carries
  the parent's peak across fork and exec (measured here: a child of a 1 GB parent reports
  980 MB), so the peak is read from ``VmHWM`` in ``/proc/self/status``, the child's own address
  space; ``ru_maxrss`` only where that file does not exist;
* **W**: the dissipation of the last cycle run; at n <= 400 (40 with ``--quick``) the child then
  runs the steady state to ``tol=1e-12`` (up to 50 cycles) and the **agreement** table gives the
  largest relative difference of that W among clarabel, osqp and active-set (target 1e-10), and
  separately explicit's largest difference to them.

A case is skipped when its predicted CPU time exceeds ``--budget`` (default 600 s; 20 s with
``--quick``): the time per step extrapolated in n from the method's two largest finished sizes
(log-log slope, between 0.5 and 3; slope 1 from one size) times the scene's steps and the cycles
of the timed and converged runs, plus K⁻¹ (n³ from the last size measured). A child that runs
over the budget anyway is stopped by a watchdog at the budget: its time per step is then taken
over the steps it finished (status ``partial``, ringed in the plot; with the run's setup, so an
upper bound), and larger sizes of that method on that system are skipped. With ``--partial`` the
cases predicted over the budget are run too, each for the budget, and nothing is skipped for
time. A method that fails records its error class and message.

Caveats
-------
The machine is shared (2 cores, other sessions running): times are CPU times of a
single-threaded process (BLAS pinned to one thread), but cache and memory bandwidth are shared,
so repeat runs differ by up to 2x; compare ratios within one run. The floor is a lower bound for
a method that reads C or K once a step, not a cost model: the event location adds solves, and
the convex solvers factor a KKT system per problem.
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
import csv
import json
import math
import os
import platform
import resource
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
#: the rows' method -> (lcpfric method, options)
METHODS = {
    "explicit": ("explicit", {}),
    "clarabel": ("clarabel", {"locate_events": True}),
    "osqp": ("osqp", {"locate_events": True}),
    "active-set": ("active-set", {"locate_events": True}),
    "active-set-no-events": ("active-set", {"locate_events": False}),
}
#: methods with one discretization (events located inside the increment by the same rule)
LOCATED = ("clarabel", "osqp", "active-set")
AGREE_TOL = 1e-10
AGREE_CYCLES = 50
#: system -> (description, sizes, sizes with --quick)
SYSTEMS = {
    "chain": (
        "chain, k_coupling 0.5, per-node separation, dense K",
        (10, 40, 100, 400, 1000, 4000),
        (10, 40, 100, 400),
    ),
    "dense-spd": (
        "dense SPD K = A Aᵀ/n + I, per-node separation",
        (10, 40, 100, 400, 1000, 4000),
        (),
    ),
    "chain-sparse": ("chain, k_coupling 0.5, per-node separation, sparse K", (1000,), ()),
    "chain-sparse-common": (
        "chain, k_coupling 0.5, separation common to all nodes, sparse K",
        (1000, 10000, 100000),
        (1000, 10000),
    ),
}
SPARSE = ("chain-sparse", "chain-sparse-common")
FIELDS = (
    "system",
    "n",
    "method",
    "status",
    "scene_steps",
    "cycles",
    "setup_s",
    "cpu_s",
    "s_per_step",
    "floor_s",
    "ratio",
    "peak_mb",
    "W",
    "W_converged",
    "converged",
    "cycles_converged",
    "note",
)


# -- the systems ------------------------------------------------------------------------------
def build(system: str, n: int):
    """The ContactSystem ``system`` with n nodes (fixed seeds: every process builds the same)."""
    import lcpfric

    rng = np.random.default_rng(n)
    if system == "dense-spd":
        from exact_discrete import dense

        return dense(n, sep=True, seed=n)
    if system == "chain-sparse-common":
        return lcpfric.chain(
            n,
            k_coupling=0.5,
            P0=1.0,
            P1=1.5,
            Q1=rng.uniform(0.5, 2.0, n),
            phi=rng.uniform(0, 2 * np.pi, n),
            sparse=True,
        )
    return lcpfric.chain(
        n,
        k_coupling=0.5,
        P0=1.0,
        P1=rng.uniform(1.2, 2.0, n),
        Q1=rng.uniform(0.5, 2.0, n),
        phi=rng.uniform(0, 2 * np.pi, n),
        sparse=system in SPARSE,
    )


def steps_per_cycle(n: int, steps: int = 500) -> int:
    """The steps per cycle asked for: ``steps``, four times that at n >= 1e5."""
    return 4 * steps if n >= 100_000 else steps


def history_option() -> bool:
    """Whether the driver takes ``history=False`` (keep the cycle's first and last rows)."""
    import inspect

    from lcpfric import periodic

    return (
        "history" in getattr(periodic, "DRIVER_OPTIONS", ())
        or "history" in inspect.signature(periodic.steady_state).parameters
    )


# -- what one child measures --------------------------------------------------------------------
def peak_mb() -> float:
    """This process's peak resident memory (MB): VmHWM (its own address space) on Linux,
    ``ru_maxrss`` elsewhere (see the module docstring)."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return float(line.split()[1]) / 1024.0
    except OSError:
        pass
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return rss / 2**20 if sys.platform == "darwin" else rss / 1024.0


def median_seconds(fn, repeats: int = 7, batch_seconds: float = 0.02) -> float:
    """CPU seconds of one call of ``fn``: the median over ``repeats`` batches, each batch long
    enough (>= ``batch_seconds``) for the clock."""
    reps = 1
    while True:
        t = time.process_time()
        for _ in range(reps):
            fn()
        if time.process_time() - t >= batch_seconds or reps >= 1 << 20:
            break
        reps *= 4
    times = []
    for _ in range(repeats):
        t = time.process_time()
        for _ in range(reps):
            fn()
        times.append((time.process_time() - t) / reps)
    return float(np.median(times))


def measure_floor(system: str, n: int, steps: int = 500) -> dict:
    """Baseline peak memory (imports and the system), the scene's steps, and the floor."""
    import lcpfric

    model = build(system, n)
    base = peak_mb()
    scene_steps = lcpfric.make_scene(model, steps_per_cycle(n, steps)).steps
    out = {"baseline_mb": base, "scene_steps": scene_steps}
    if system in SPARSE:
        A = model.stiffness
    else:  # C = K⁻¹, which the cases form too
        out["setup_s"] = inverse_seconds(model, None)
        A = model.compliance_matrix()
    x = np.random.default_rng(0).standard_normal(n)
    out["floor_s"] = median_seconds(lambda: A @ x)
    return out


def forms_inverse(m: int, method: str | None) -> bool:
    """Whether a steady state of ``method`` (None: of any) on a coupled system with m unknowns
    forms the dense K⁻¹: the convex backends always (their problem is written in C), the driver
    up to ``lcpfric.model.system.COMPLIANCE_DENSE`` unknowns (its displacement scale, ``max diag
    K⁻¹``)."""
    from lcpfric.model.system import COMPLIANCE_DENSE

    return method in (None, "clarabel", "osqp") or m <= COMPLIANCE_DENSE


def inverse_seconds(model, method: str | None) -> float | None:
    """Form the dense K⁻¹ (cached on the system) if ``method``'s steady state would; its CPU
    seconds (None if it would not)."""
    if model.is_diagonal() or not forms_inverse(model.m, method):
        return None
    t = time.process_time()
    model.compliance_matrix()
    return time.process_time() - t


class OverBudget(BaseException):
    """Raised by the :class:`Watchdog` (a BaseException: no ``except Exception`` may swallow
    it)."""


class Watchdog:
    """Raise :class:`OverBudget` in the main thread once this process has used ``budget`` CPU
    seconds from now: a thread polls ``time.process_time`` every 0.2 s and signals the main
    thread (SIGUSR1). Not ``setitimer(ITIMER_PROF)``: with that timer armed, Linux reports
    ``process_time`` in ticks of 4 ms (measured), too coarse for the short runs."""

    def __init__(self, budget: float):
        import threading

        self.end = time.process_time() + budget
        self.done = threading.Event()
        self.previous = signal.signal(signal.SIGUSR1, self._raise)
        self.thread = threading.Thread(target=self._poll, daemon=True)
        self.thread.start()

    @staticmethod
    def _raise(signum, frame):
        """Raise OverBudget carrying the steps the driver had finished: the loop variable k of
        the stepper's ``cycle`` and the cycles in the driver's ``W_cycles``, read from the
        interrupted frames (None where a method's loop is not found)."""
        k = cycles = None
        f = frame
        while f is not None:
            name, local = f.f_code.co_name, f.f_locals
            if k is None and name == "cycle" and isinstance(local.get("k"), int):
                k = local["k"]
            if name == "steady_state" and isinstance(local.get("W_cycles"), list):
                cycles = len(local["W_cycles"])
                break
            f = f.f_back
        raise OverBudget(None if k is None or cycles is None else (cycles, k))

    def _poll(self):
        while not self.done.wait(0.2):
            if time.process_time() >= self.end:
                os.kill(os.getpid(), signal.SIGUSR1)
                return

    def stop(self):
        self.done.set()
        self.thread.join()
        signal.signal(signal.SIGUSR1, self.previous)


def measure_case(
    system: str,
    n: int,
    method: str,
    cycles: int,
    agree: bool,
    budget: float | None = None,
    steps: int = 500,
) -> dict:
    """One (system, n, method): timed cycles, peak memory, and the converged W if ``agree``."""
    import lcpfric

    model = build(system, n)
    scene = lcpfric.make_scene(model, steps_per_cycle(n, steps))
    name, opts = METHODS[method]
    extra = {"history": False} if n >= 100_000 else {}
    out = {"scene_steps": scene.steps}
    lcpfric.steady_state(
        build("chain", 3), name, 50, max_cycles=1, on_nonconvergence="ignore", **opts
    )  # imports, first calls
    watch = Watchdog(budget) if budget is not None else None  # covers K⁻¹ and the runs
    t = time.process_time()
    try:
        out["setup_s"] = inverse_seconds(model, method)
        t = time.process_time()
        r = lcpfric.steady_state(
            scene, name, tol=1e-300, max_cycles=cycles, on_nonconvergence="ignore", **opts, **extra
        )
        cpu = time.process_time() - t
        out.update(
            status="ok",
            cycles=r.cycles,
            cpu_s=cpu,
            s_per_step=cpu / (r.cycles * scene.steps),
            W=r.W,
            peak_mb=peak_mb(),
        )
        if agree:
            c = lcpfric.steady_state(
                scene,
                name,
                tol=1e-12,
                max_cycles=AGREE_CYCLES,
                on_nonconvergence="ignore",
                **opts,
                **extra,
            )
            out.update(W_converged=c.W, converged=c.converged, cycles_converged=c.cycles)
    except OverBudget as stop:
        cpu = time.process_time() - t
        where = stop.args[0] if stop.args else None
        if out.get("status") == "ok":  # the timed cycles finished; the agreement run did not
            out["note"] = f"the agreement run stopped at the budget of {budget:g} CPU s"
            return {**out, "peak_mb": peak_mb()}
        done = None if where is None or "setup_s" not in out else where[0] * scene.steps + where[1]
        if done:  # the steps finished before the budget ran out: timed over them
            out.update(
                status="partial",
                cpu_s=cpu,
                s_per_step=cpu / done,
                peak_mb=peak_mb(),
                note=f"the budget of {budget:g} CPU s ran out after {done} of "
                f"{cycles * scene.steps} steps: s/step over those (with the run's "
                f"setup)",
            )
        else:
            out.update(
                status="over budget",
                cpu_s=cpu,
                note=f"stopped at the budget of {budget:g} CPU s"
                + ("" if "setup_s" in out else ", forming K⁻¹"),
            )
    except Exception as exc:  # recorded, not raised: a failing method is a result
        out.update(
            status="error", cpu_s=time.process_time() - t, note=f"{type(exc).__name__}: {exc}"
        )
    finally:
        if watch is not None:
            watch.stop()
    out.setdefault("peak_mb", peak_mb())
    return out


# -- the parent: children, budget, tables, plot -------------------------------------------------
@dataclass
class Settings:
    systems: dict
    methods: tuple = tuple(METHODS)
    cycles: int = 3
    steps: int = 500  # per cycle (four times that at n >= 1e5)
    budget: float = 600.0
    agree_max: int = 400
    sparse_methods: tuple | None = None  # the methods run on the sparse systems (None: all)
    isolate: bool = True  # each case in its own process (else in this one: no peak memory)
    partial: bool = False  # run cases predicted over the budget, timed over part of a cycle
    command: str = ""
    log: object = field(default=print, repr=False)


def child(kind: str, **spec) -> dict:
    """Run ``measure_floor`` or ``measure_case`` in a fresh interpreter; its JSON answer."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p)
    budget = spec.get("budget") or 600.0
    try:
        p = subprocess.run(
            [
                sys.executable,
                str(Path(__file__).resolve()),
                "--child",
                json.dumps({"kind": kind, **spec}),
            ],
            env=env,
            capture_output=True,
            text=True,
            timeout=4 * budget + 120,
        )
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "note": f"no answer after {4 * budget + 120:.0f} s wall"}
    if p.returncode != 0:
        tail = (p.stderr.strip().splitlines() or ["no output"])[-1]
        return {"status": "error", "note": f"child exit {p.returncode}: {tail}"}
    return json.loads(p.stdout.strip().splitlines()[-1])


def too_big(n: int, method: str) -> str:
    """Why ``method`` cannot run at n here ('' if it can): a steady state that forms the dense
    K⁻¹ (:func:`forms_inverse`) holds about three n x n arrays at once."""
    from lcpfric import memory

    need = 3 * 8.0 * n * n
    have = memory.physical_memory() or math.inf
    if not forms_inverse(n, method) or need <= 0.5 * have:
        return ""
    return (
        f"it forms the dense K⁻¹ ({memory.format_bytes(need)} at its peak; memory "
        f"{memory.format_bytes(have)})"
    )


def predict(done: list, n: int, steps: int, runs: float) -> float | None:
    """Predicted CPU seconds at n from the (n, s/step) of the finished smaller sizes."""
    if not done:
        return None
    n0, t0 = done[-1]
    slope = 1.0
    if len(done) > 1:
        n1, t1 = done[-2]
        slope = min(3.0, max(0.5, math.log(t0 / t1) / math.log(n0 / n1)))
    return t0 * (n / n0) ** slope * steps * runs


def run(settings: Settings) -> list[dict]:
    """Every case of ``settings``: the rows of scaling.csv."""
    rows = []
    has_history = history_option()
    for system, sizes in settings.systems.items():
        done = {m: [] for m in settings.methods}
        setups = []  # (n, CPU s of K⁻¹): one per system, whatever the method
        stopped = {}
        for n in sizes:
            base = dict(system=system, n=n)
            fixed = {
                m: _fixed_reason(settings, system, n, m, stopped, has_history)
                for m in settings.methods
            }
            if all(fixed.values()):
                rows += [
                    _row(settings, {**base, "method": m, "status": "skipped", "note": fixed[m]})
                    for m in settings.methods
                ]
                continue
            floor = (
                child("floor", system=system, n=n, steps=settings.steps)
                if settings.isolate
                else measure_floor(system, n, settings.steps)
            )
            if "floor_s" not in floor:
                floor = {
                    "floor_s": math.nan,
                    "scene_steps": 0,
                    "baseline_mb": math.nan,
                    "note": floor.get("note", ""),
                }
            if floor.get("setup_s") is not None:
                setups.append((n, floor["setup_s"]))
            agree = n <= settings.agree_max
            runs = settings.cycles + (3 if agree else 0)  # the converged runs take ~3 cycles
            for m in settings.methods:
                row = {
                    **base,
                    "method": m,
                    "floor_s": floor["floor_s"],
                    "scene_steps": floor["scene_steps"],
                }
                guess = predict(done[m], n, floor["scene_steps"], runs)
                inverse = (
                    setups[-1][1] * (n / setups[-1][0]) ** 3  # K⁻¹: O(n³)
                    if setups and setups[-1][0] >= 100 and forms_inverse(n, m)
                    else 0.0
                )
                if fixed[m]:
                    row.update(status="skipped", note=fixed[m])
                elif (
                    guess is not None and guess + inverse > settings.budget and not settings.partial
                ):
                    part = f" (K⁻¹ {inverse:.2g})" if inverse else ""
                    row.update(
                        status="skipped",
                        note=f"predicted {guess + inverse:.3g} CPU s"
                        f"{part} > budget {settings.budget:g}",
                    )
                else:
                    over = guess is not None and guess + inverse > settings.budget
                    spec = dict(
                        system=system,
                        n=n,
                        method=m,
                        cycles=settings.cycles,
                        agree=agree and not over,
                        budget=settings.budget,
                        steps=settings.steps,
                    )
                    got = child("case", **spec) if settings.isolate else measure_case(**spec)
                    row.update(got)
                    if settings.isolate and "peak_mb" in got:
                        row["peak_mb"] = got["peak_mb"] - floor["baseline_mb"]
                    else:
                        row["peak_mb"] = math.nan
                    if got.get("setup_s") is not None and (not setups or setups[-1][0] < n):
                        setups.append((n, got["setup_s"]))
                    if row.get("status") == "ok":
                        done[m].append((n, row["s_per_step"]))
                    elif row.get("status") == "partial":
                        done[m].append((n, row["s_per_step"]))
                        if not settings.partial:
                            stopped[m] = f"over budget at n = {n}"
                    elif row.get("status") in ("over budget", "timeout"):
                        stopped[m] = f"over budget at n = {n}"
                rows.append(_row(settings, row))
    return rows


def _fixed_reason(
    settings, system: str, n: int, method: str, stopped: dict, has_history: bool
) -> str:
    """Why (system, n, method) is not run, before any measurement ('' if it may be)."""
    if system in SPARSE and method not in (settings.sparse_methods or (method,)):
        return "the sparse systems run only " + ", ".join(settings.sparse_methods)
    if n >= 100_000 and not has_history:
        return "the driver has no history=False yet"
    return stopped.get(method) or too_big(n, method)


def _row(settings, row: dict) -> dict:
    out = {k: row.get(k, "") for k in FIELDS}
    if row.get("status") in ("ok", "partial") and row.get("floor_s"):
        out["ratio"] = row["s_per_step"] / row["floor_s"]
    settings.log(_line(out))
    return out


def _fmt(x, spec=".3g") -> str:
    if x == "" or x is None:
        return ""
    if isinstance(x, float) and math.isnan(x):
        return "-"
    return format(x, spec) if isinstance(x, (int, float)) and not isinstance(x, bool) else str(x)


def _line(r: dict) -> str:
    """One row of the main table (markdown)."""
    what = _fmt(r["W"], ".15g") if r["status"] == "ok" else f"{r['status']}: {r['note']}"
    return (
        f"| {r['system']} | {r['n']} | {r['method']} | {_fmt(r['scene_steps'], 'd')} "
        f"| {_fmt(r['cycles'])} | {_fmt(r['setup_s'])} | {_fmt(r['s_per_step'])} "
        f"| {_fmt(r['floor_s'])} "
        f"| {_fmt(r['ratio'], '.3g')} | {_fmt(r['peak_mb'], '.0f')} | {what} |"
    )


def agreement(rows: list[dict]) -> list[dict]:
    """Per (system, n): the largest relative difference of the converged W among the methods
    of one discretization (LOCATED), and explicit's largest difference to them."""
    out = []
    keys = sorted({(r["system"], r["n"]) for r in rows}, key=lambda k: (k[0], k[1]))
    for system, n in keys:
        W = {
            r["method"]: r["W_converged"]
            for r in rows
            if (r["system"], r["n"]) == (system, n) and r["converged"] is True
        }
        same = {m: w for m, w in W.items() if m in LOCATED}
        if not W:
            continue
        spread = (
            (max(same.values()) - min(same.values())) / max(abs(w) for w in same.values())
            if len(same) > 1
            else math.nan
        )
        expl = (
            max(abs(W["explicit"] - w) / abs(w) for w in same.values())
            if "explicit" in W and same
            else math.nan
        )
        out.append(
            dict(
                system=system,
                n=n,
                methods=", ".join(sorted(same)),
                spread=spread,
                explicit=expl,
                ok=bool(spread <= AGREE_TOL) if len(same) > 1 else None,
            )
        )
    return out


def write(rows: list[dict], settings: Settings, out_dir: Path) -> list[Path]:
    out_dir.mkdir(parents=True, exist_ok=True)
    with open(out_dir / "scaling.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    agree = agreement(rows)
    lines = [
        "# Time per step and peak memory against n",
        "",
        f"`{settings.command}`" + _revision(),
        "",
        f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, "
        f"numpy {np.__version__}; CPU seconds, one thread; {settings.cycles} cycle(s) per case; "
        f"budget {settings.budget:g} CPU s per case; steps per cycle {settings.steps} "
        f"({4 * settings.steps} at n = 1e5) "
        "plus the separation instants (scene steps).",
        "",
        "Systems: " + "; ".join(f"**{k}**: {SYSTEMS[k][0]}" for k in settings.systems) + ".",
        "",
        "Floor: one product with C = K⁻¹ (dense systems) or with the sparse K, median of 7; "
        "ratio = s/step / floor. K⁻¹ s: the dense K⁻¹ that the case's steady state forms "
        "(the convex backends; the driver up to 2000 unknowns), formed before the timed "
        "cycles and so not in s/step. Peak MB: the case's child over a child that only builds "
        "the system. active-set-no-events: a different (coarser) discretization, timed only.",
        "",
        "| system | n | method | scene steps | cycles | K⁻¹ s | s/step | floor s "
        "| ratio to floor | peak MB | W |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
        *(_line(r) for r in rows),
        "",
        f"## Agreement (tol = 1e-12, up to {AGREE_CYCLES} cycles; target {AGREE_TOL:g})",
        "",
        "Largest relative difference of the converged W among the methods of one "
        "discretization (events located inside the increment), and explicit's (its own "
        "discretization) largest difference to them.",
        "",
        "| system | n | methods compared | max rel. difference | <= 1e-10 | explicit's |",
        "|---|---|---|---|---|---|",
        *(
            f"| {a['system']} | {a['n']} | {a['methods']} | {_fmt(a['spread'], '.2e')} "
            f"| {'-' if a['ok'] is None else ('yes' if a['ok'] else '**no**')} "
            f"| {_fmt(a['explicit'], '.2e')} |"
            for a in agree
        ),
        "",
    ]
    (out_dir / "scaling.md").write_text("\n".join(lines))
    return [out_dir / "scaling.csv", out_dir / "scaling.md", *plot(rows, out_dir)]


MARKERS = {
    "explicit": "o",
    "clarabel": "s",
    "osqp": "^",
    "active-set": "D",
    "active-set-no-events": "v",
}
#: line style per system (dashes are the floors')
LINES = {
    "chain": "-",
    "dense-spd": ":",
    "chain-sparse": (0, (4, 1, 1, 1, 1, 1)),
    "chain-sparse-common": "-.",
}


def plot(rows: list[dict], out_dir: Path) -> list[Path]:
    """scaling.png and scaling.pdf: s/step against n, one colour and marker per method, one
    line style per system, the floors dashed (nothing written without matplotlib)."""
    try:
        from lcpfric.figures import style as plotting

        fig = plotting.figure(figsize=(6.5, 4.0))
    except Exception:
        return []
    from matplotlib.lines import Line2D

    ok = [r for r in rows if r["status"] in ("ok", "partial")]
    colors = dict(zip(METHODS, ("#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e")))
    with plotting.style():
        ax = fig.add_subplot()
        systems = [s for s in SYSTEMS if any(r["system"] == s for r in rows)]
        for s in systems:
            for m in METHODS:
                pts = sorted(
                    (r["n"], r["s_per_step"], r["status"])
                    for r in ok
                    if r["system"] == s and r["method"] == m
                )
                if pts:
                    ax.loglog(
                        [p[0] for p in pts],
                        [p[1] for p in pts],
                        color=colors[m],
                        marker=MARKERS[m],
                        ms=4,
                        ls=LINES[s],
                        lw=1.0,
                        mfc="none" if s in SPARSE else colors[m],
                    )
                    part = [p for p in pts if p[2] == "partial"]
                    if part:  # timed over part of a cycle: ringed
                        ax.loglog(
                            [p[0] for p in part],
                            [p[1] for p in part],
                            ls="none",
                            marker="o",
                            ms=9,
                            mfc="none",
                            mec="0.2",
                            mew=0.7,
                        )
        for kind, gray in (("dense", "0.15"), ("sparse", "0.55")):
            pts = sorted(
                {
                    (r["n"], r["floor_s"])
                    for r in rows
                    if (r["system"] in SPARSE) == (kind == "sparse")
                    and isinstance(r["floor_s"], float)
                    and r["floor_s"] > 0
                    and r["system"] in ("chain", "chain-sparse-common")
                }
            )
            if pts:
                ax.loglog(*zip(*pts), color=gray, ls=(0, (5, 3)), lw=1.2)
        ax.set_xlabel("nodes n", fontsize=9)
        ax.set_ylabel("CPU seconds per step", fontsize=9)
        ax.tick_params(which="both", labelsize=8)
        ax.grid(True, which="major", alpha=0.3, lw=0.5)
        h1 = [
            Line2D([], [], color=colors[m], marker=MARKERS[m], ms=4, lw=1.0, label=m)
            for m in METHODS
            if any(r["method"] == m for r in ok)
        ]
        h2 = [
            Line2D(
                [],
                [],
                color="0.3",
                ls=LINES[s],
                lw=1.0,
                marker="o",
                ms=4,
                mfc="none" if s in SPARSE else "0.3",
                label=s,
            )
            for s in systems
        ]
        h3 = (
            [
                Line2D(
                    [],
                    [],
                    ls="none",
                    marker="o",
                    ms=9,
                    mfc="none",
                    mec="0.2",
                    mew=0.7,
                    label="ringed: part of a cycle\n(budget ran out)",
                )
            ]
            if any(r["status"] == "partial" for r in ok)
            else []
        )
        h3 += [
            Line2D([], [], color="0.15", ls=(0, (5, 3)), lw=1.2, label="floor: C x (dense)"),
            Line2D([], [], color="0.55", ls=(0, (5, 3)), lw=1.2, label="floor: K x (sparse)"),
        ]
        ax.legend(
            handles=h1 + h2 + h3,
            fontsize=8,
            loc="center left",
            bbox_to_anchor=(1.01, 0.5),
            frameon=False,
        )
        fig.tight_layout()
    return plotting.save(fig, out_dir, "scaling", ("png", "pdf"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--quick",
        action="store_true",
        help="dense chain to n = 400, sparse (active-set only) to 1e4, 100 steps, "
        "one cycle (about a minute)",
    )
    ap.add_argument("--out", default=str(HERE.parent / "results"), help="output directory")
    ap.add_argument(
        "--budget",
        type=float,
        default=None,
        help="CPU seconds per case (default 600; 20 with --quick)",
    )
    ap.add_argument(
        "--cycles", type=int, default=None, help="cycles timed per case (default 3; 1 with --quick)"
    )
    ap.add_argument(
        "--partial",
        action="store_true",
        help="run the cases predicted over the budget too, timed over the steps "
        "the budget allows (status 'partial')",
    )
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--systems", default=None, help=f"from {', '.join(SYSTEMS)}")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child is not None:
        spec = json.loads(args.child)
        kind = spec.pop("kind")
        print(json.dumps(measure_floor(**spec) if kind == "floor" else measure_case(**spec)))
        return 0
    settings = (
        quick_settings() if args.quick else Settings(systems={k: v[1] for k, v in SYSTEMS.items()})
    )
    if args.systems:
        names = args.systems.split(",")
        settings.systems = {k: SYSTEMS[k][2 if args.quick else 1] for k in names}
    settings.methods = tuple(args.methods.split(","))
    if args.budget is not None:
        settings.budget = args.budget
    if args.cycles is not None:
        if args.cycles < 1:
            ap.error(f"--cycles must be >= 1, got {args.cycles}")
        settings.cycles = args.cycles
    settings.partial = args.partial
    settings.command = "OPENBLAS_NUM_THREADS=1 python benchmarks/perf/scaling.py " + " ".join(
        argv if argv is not None else sys.argv[1:]
    )
    rows = run(settings)
    for path in write(rows, settings, Path(args.out)):
        print(f"wrote {path}")
    return 0


def _revision() -> str:
    """`` (lcpfric at commit abc1234)`` when run from a git checkout, else nothing."""
    try:
        rev = subprocess.run(
            ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            timeout=10,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""
    return f" (lcpfric at commit {rev})" if rev else ""


def quick_settings(**changes) -> Settings:
    """The ``--quick`` subset (``changes`` override it: the test's tiny sizes, in-process)."""
    base = Settings(
        systems={k: v[2] for k, v in SYSTEMS.items() if v[2]},
        cycles=1,
        steps=100,
        budget=20.0,
        agree_max=40,
        sparse_methods=("active-set", "active-set-no-events"),
    )
    for k, v in changes.items():
        setattr(base, k, v)
    return base


if __name__ == "__main__":
    sys.exit(main())
