"""benchmarks/scaling.py: the quick mode's core on tiny sizes (the full run is the script)."""

import csv
import math

import scaling
from support import need


def test_scaling_core_in_process(tmp_path):
    need("clarabel")
    need("osqp")
    lines = []
    settings = scaling.quick_settings(systems={"chain": (10, 40)}, isolate=False,
                                      log=lines.append)
    rows = scaling.run(settings)
    files = scaling.write(rows, settings, tmp_path)
    assert {p.name for p in files} >= {"scaling.csv", "scaling.md"}
    assert len(lines) == len(rows) == 2 * len(scaling.METHODS)  # each case printed as it ends
    assert all(r["status"] == "ok" for r in rows), [r["note"] for r in rows]
    assert all(math.isfinite(r["ratio"]) and r["ratio"] > 0 for r in rows)
    assert all(r["scene_steps"] > settings.steps for r in rows)  # separation instants added
    agree = scaling.agreement(rows)
    assert [a["n"] for a in agree] == [10, 40]
    for a in agree:
        assert a["methods"] == "active-set, clarabel, osqp"
        assert a["spread"] <= 1e-10 and a["ok"]
        assert a["explicit"] <= 1e-8
    with open(tmp_path / "scaling.csv", newline="") as fh:
        table = list(csv.DictReader(fh))
    assert [(r["n"], r["method"]) for r in table] == [(str(r["n"]), r["method"]) for r in rows]
    md = (tmp_path / "scaling.md").read_text()
    assert "| chain | 40 | active-set |" in md and "## Agreement" in md


def test_scaling_child_reports_memory_and_floor():
    floor = scaling.child("floor", system="chain", n=10, steps=50)
    assert floor["floor_s"] > 0 and floor["baseline_mb"] > 0 and floor["scene_steps"] > 50
    case = scaling.child("case", system="chain", n=10, method="active-set", cycles=1,
                         agree=False, budget=30.0, steps=50)
    assert case["status"] == "ok" and case["cycles"] == 1 and case["peak_mb"] > 0
    assert case["scene_steps"] == floor["scene_steps"]
