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


def test_bench_coupled_chain_order_and_richardson(tmp_path, capsys):
    """The coupled-case machinery on the small chain: explicit against method 'exact' is second
    order, and the Richardson extrapolation of explicit (independent of 'exact') agrees."""
    from lcpfric.cli import main

    out = tmp_path / "c"
    code = main(["bench", "--coupled", "--quick", "--budget", "30", "--cases",
                 "chain-separation", "--methods", "exact,explicit", "--steps", "400,800,1600",
                 "--out", str(out), "--json"])
    assert code == 0
    headline = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert headline["orders"]["explicit"]["chain-separation"] >= 1.8
    rich = headline["richardson"]["chain-separation"]
    assert rich["steps"] == [800, 1600]
    assert rich["rich_error"] < 1e-6 and rich["rich_error"] < rich["finest_error"]
    assert headline["reference"]["chain-separation"]["events_per_cycle"] > 0
    assert set(headline["files"]) == {"compare-coupled.csv", "compare-coupled.md",
                                      "compare-coupled.png"}
    rows = list(csv.DictReader(open(out / "compare-coupled.csv")))
    assert [r["note"].startswith("reference") for r in rows if r["method"] == "exact"] == [True]
    assert "Richardson" in (out / "compare-coupled.md").read_text()


def test_richardson_is_exact_on_a_second_order_sequence():
    from lcpfric.analysis.convergence import richardson

    rows = [dict(case="c", method="explicit", steps_per_cycle=n, rel_error=1.0,
                 W=2.0 + 3.0 / n**2, exact=2.0) for n in (100, 200, 400)]
    r = richardson(rows, "c")
    assert r["steps"] == (200, 400) and abs(r["W_rich"] - 2.0) < 1e-14
    assert abs(r["finest_error"] - 3.0 / 400**2 / 2.0) < 1e-15


def test_bench_coupled_case_names_are_checked(capsys, tmp_path):
    from lcpfric.cli import main

    code = main(["bench", "--cases", "chain-100", "--out", str(tmp_path / "b")])
    err = capsys.readouterr().err
    assert code == 2 and "--cases" in err and "--coupled" in err
