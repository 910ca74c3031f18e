"""Start-up time of the ``lcpfric`` command line, as a ratio to ``python -c "import numpy"``.

Each command is run ``--runs`` times (after one warm-up run), round robin so that all of them
share the machine's state, and the median wall time is compared with the median of
``python -c "import numpy"`` measured in the same run. The commands run as
``python -m lcpfric ...`` with ``PYTHONPATH`` set to this checkout, so the numbers are those of the
tree this file sits in.

Targets (ratio to the numpy import): ``lcpfric --help`` and ``lcpfric shakedown`` at most 1.5,
``lcpfric dissipation`` (method exact) at most 3; ``lcpfric methods`` is reported.

Then ``python -X importtime`` of each command lists the packages that cost the most, and any
heavy package (scipy, xarray, matplotlib, a solver) a command imports.

Run::

    PYTHONPATH=. python benchmarks/perf/startup.py [--runs 10] [--no-write]

Writes ``benchmarks/results/startup.md`` (unless ``--no-write``).
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
import platform
import statistics
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "benchmarks" / "results" / "startup.md"

COMMANDS = {
    "lcpfric --help": (["--help"], 1.5),
    "lcpfric shakedown": (["shakedown", "--P1", "0.5", "--Q1", "0.7", "--phi", "0.3pi"], 1.5),
    "lcpfric dissipation (exact)": (
        ["dissipation", "--P1", "1.5", "--Q1", "2", "--phi", "0.6pi"],
        3.0,
    ),
    "lcpfric methods": (["methods"], None),
}
BASELINE = 'python -c "import numpy"'
HEAVY = (
    "scipy",
    "xarray",
    "pandas",
    "matplotlib",
    "dask",
    "distributed",
    "h5py",
    "h5netcdf",
    "cvxpy",
    "qpsolvers",
    "clarabel",
    "osqp",
    "tqdm",
)


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH", "")) if p)
    return env


def command(args: list[str]) -> list[str]:
    return [sys.executable, "-m", "lcpfric", *args]


def _once(cmd: list[str], env: dict) -> float:
    t0 = time.perf_counter()
    run = subprocess.run(
        cmd, env=env, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    seconds = time.perf_counter() - t0
    if run.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({run.returncode}): {run.stderr.strip()}")
    return seconds


def measure(runs: int) -> dict[str, dict[str, float]]:
    """Median seconds of every command (and the numpy baseline), round robin."""
    env = _env()
    cmds = {BASELINE: ([sys.executable, "-c", "import numpy"], None)}
    for name, (args, _) in COMMANDS.items():
        cmds[name] = command(args), "as is"
    times = defaultdict(list)
    for cmd, _ in cmds.values():  # warm the file system cache
        _once(cmd, env)
    for _ in range(runs):
        for name, (cmd, _) in cmds.items():
            times[name].append(_once(cmd, env))
    return {name: {"median": statistics.median(t), "min": min(t)} for name, t in times.items()}


def import_profile(args: list[str], top: int = 6) -> tuple[float, list]:
    """(total import seconds, [(top-level package, seconds), ...]) from ``-X importtime``."""
    cmd = command(args)
    cmd.insert(1, "-X")
    cmd.insert(2, "importtime")
    run = subprocess.run(cmd, env=_env(), cwd=ROOT, capture_output=True, text=True)
    per = defaultdict(float)
    for line in run.stderr.splitlines():
        if not line.startswith("import time:") or "self [us]" in line:
            continue
        self_us, _cumulative, name = (f.strip() for f in line[len("import time:") :].split("|"))
        per[name.split(".")[0]] += int(self_us) / 1e6
    total = sum(per.values())
    return total, sorted(per.items(), key=lambda kv: -kv[1])[:top]


def heavy_imports(args: list[str]) -> list[str]:
    cmd = command(args)
    cmd.insert(1, "-X")
    cmd.insert(2, "importtime")
    run = subprocess.run(cmd, env=_env(), cwd=ROOT, capture_output=True, text=True)
    found = {
        line.split("|")[-1].strip().split(".")[0]
        for line in run.stderr.splitlines()
        if line.startswith("import time:")
    }
    return [h for h in HEAVY if h in found]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=10, help="timed runs per command (default 10)")
    p.add_argument("--no-write", action="store_true", help=f"do not write {OUT.name}")
    args = p.parse_args(argv)
    res = measure(max(1, args.runs))
    base = res[BASELINE]["median"]

    head = ["command", "median (s)", "ratio to numpy", "target", "ok"]
    rows = [[BASELINE, f"{base:.3f}", "1.00", "", ""]]
    for name, (cmd_args, target) in COMMANDS.items():
        med = res[name]["median"]
        row = [
            name,
            f"{med:.3f}",
            f"{med / base:.2f}",
            "" if target is None else f"<= {target}",
            "" if target is None else ("yes" if med / base <= target else "no"),
        ]
        rows.append(row)

    profile = [
        "| command | heavy packages imported | top packages by import time (s) |",
        "|---|---|---|",
    ]
    for name, (cmd_args, _) in COMMANDS.items():
        total, top = import_profile(cmd_args)
        heavy = ", ".join(heavy_imports(cmd_args)) or "none"
        tops = ", ".join(f"{k} {v:.3f}" for k, v in top)
        profile.append(f"| {name} | {heavy} | total {total:.3f}: {tops} |")

    table = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    table += ["| " + " | ".join(r) + " |" for r in rows]
    text = "\n".join(
        [
            "# Start-up time of the command line",
            "",
            f"Median wall time of {args.runs} runs per command (after one warm-up run, round "
            f"robin), {time.strftime('%Y-%m-%d')}, Python {platform.python_version()} on "
            f"{platform.platform()}, {os.cpu_count()} CPUs. Reproduce: "
            "`PYTHONPATH=. python benchmarks/perf/startup.py`.",
            "",
            *table,
            "",
            "## What the commands import (`python -X importtime`, self time summed per top-level "
            "package, one run)",
            "",
            *profile,
            "",
        ]
    )
    print(text)
    if not args.no_write:
        OUT.parent.mkdir(parents=True, exist_ok=True)
        OUT.write_text(text)
        print(f"wrote {OUT.relative_to(ROOT)}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
