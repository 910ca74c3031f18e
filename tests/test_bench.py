"""The backend comparison (benchmarks/perf/compare_backends.py) end to end on a tiny set, run as
users run it: error against run time, measured orders, Richardson's check of the coupled
reference."""

import csv
import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = str(Path(__file__).resolve().parents[1] / "benchmarks" / "perf" / "compare_backends.py")


def _run(*args, timeout=300):
    return subprocess.run(
        [sys.executable, SCRIPT, *args], capture_output=True, text=True, timeout=timeout
    )


@pytest.mark.slow
def test_bench_small(tmp_path):
    out = tmp_path / "b"
    p = _run(
        "--cases",
        "separation",
        "--methods",
        "explicit,projection,exact",
        "--steps",
        "100,200,400,800,1600",
        "--out",
        str(out),
        "--json",
    )
    assert p.returncode == 0, p.stderr
    headline = json.loads(p.stdout.strip().splitlines()[-1])
    assert headline["orders"]["projection"]["separation"] > 1.7
    rows = list(csv.DictReader(open(out / "compare.csv")))
    assert {"case", "method", "steps_per_cycle", "rel_error", "seconds"} <= set(rows[0])
    errs = [float(r["rel_error"]) for r in rows if r["method"] == "projection"]
    assert errs == sorted(errs, reverse=True)  # refining lowers the error
    assert (out / "compare.md").exists()
    assert (out / "compare.png").exists() == (importlib.util.find_spec("matplotlib") is not None)


def test_bench_bad_input_exit_2(tmp_path):
    p = _run("--cases", "nope", "--out", str(tmp_path), timeout=120)
    assert p.returncode == 2 and "--cases" in p.stderr and "Traceback" not in p.stderr
    p = _run("--cases", "chain-100", "--out", str(tmp_path / "b"), timeout=120)
    assert p.returncode == 2 and "--cases" in p.stderr and "--coupled" in p.stderr


@pytest.mark.slow
def test_bench_coupled_chain_order_and_richardson(tmp_path):
    """The coupled-case machinery on the small chain: explicit against method 'exact' is second
    order, and the Richardson extrapolation of explicit (independent of 'exact') agrees."""
    out = tmp_path / "c"
    p = _run(
        "--coupled",
        "--quick",
        "--budget",
        "30",
        "--cases",
        "chain-separation",
        "--methods",
        "exact,explicit",
        "--steps",
        "400,800,1600",
        "--out",
        str(out),
        "--json",
    )
    assert p.returncode == 0, p.stderr
    headline = json.loads(p.stdout.strip().splitlines()[-1])
    assert headline["orders"]["explicit"]["chain-separation"] >= 1.8
    rich = headline["richardson"]["chain-separation"]
    assert rich["steps"] == [800, 1600]
    assert rich["rich_error"] < 1e-6 and rich["rich_error"] < rich["finest_error"]
    assert headline["reference"]["chain-separation"]["events_per_cycle"] > 0
    drawn = importlib.util.find_spec("matplotlib") is not None
    assert set(headline["files"]) == {
        "compare-coupled.csv",
        "compare-coupled.md",
        *(["compare-coupled.png"] if drawn else []),
    }
    rows = list(csv.DictReader(open(out / "compare-coupled.csv")))
    assert [r["note"].startswith("reference") for r in rows if r["method"] == "exact"] == [True]
    assert "Richardson" in (out / "compare-coupled.md").read_text()
