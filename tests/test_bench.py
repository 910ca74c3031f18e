"""`lcpfric bench` end to end on a tiny set (the full run is benchmarks/compare_backends.py)."""

import csv
import json
import subprocess
import sys


def test_bench_cli_small(tmp_path):
    out = tmp_path / "b"
    p = subprocess.run([sys.executable, "-m", "lcpfric", "bench", "--cases", "separation",
                        "--methods", "explicit,projection,exact", "--steps", "100,200,400,800,1600",
                        "--out", str(out), "--json"], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    headline = json.loads(p.stdout.strip().splitlines()[-1])
    assert headline["orders"]["projection"]["separation"] > 1.7
    rows = list(csv.DictReader(open(out / "compare.csv")))
    assert {"case", "method", "steps_per_cycle", "rel_error", "seconds"} <= set(rows[0])
    errs = [float(r["rel_error"]) for r in rows if r["method"] == "projection"]
    assert errs == sorted(errs, reverse=True)  # refining lowers the error
    assert (out / "compare.md").exists() and (out / "compare.png").exists()


def test_bench_cli_bad_input_exit_2(tmp_path):
    p = subprocess.run([sys.executable, "-m", "lcpfric", "bench", "--cases", "nope", "--out",
                        str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "--cases" in p.stderr and "Traceback" not in p.stderr
