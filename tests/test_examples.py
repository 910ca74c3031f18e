"""Each example script runs (small sizes) and prints what it promises."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from support import need_modules

ROOT = Path(__file__).resolve().parents[1]


def run(name, *args, tmp_path):
    env = dict(
        os.environ,
        LCPFRIC_EXAMPLE_STEPS="500",
        LCPFRIC_EXAMPLE_POINTS="40",
        MPLBACKEND="Agg",
        PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
    )
    proc = subprocess.run(
        [sys.executable, str(ROOT / "examples" / name), *args],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp_path,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


@pytest.mark.slow
def test_motor(tmp_path):
    need_modules("matplotlib")
    out = run("motor.py", "--out", str(tmp_path), tmp_path=tmp_path)
    assert (tmp_path / "fig9_motor.png").stat().st_size > 0
    a, b = map(
        float, re.search(r"gives W = ([\d.]+) mJ; Motor.dissipation gives ([\d.]+)", out).groups()
    )
    assert a == pytest.approx(b, rel=1e-9)


@pytest.mark.slow
def test_two_harmonic(tmp_path):
    out = run("two_harmonic.py", tmp_path=tmp_path)
    errors = [float(e) for e in re.findall(r"relative error ([\d.e+-]+)", out)]
    assert len(errors) == 2 and max(errors) < 1e-3
    assert len(re.findall(r"^\s*\d\.\d\d\s+\d\.\d\d\s+(True|False)", out, re.M)) == 5


def test_pyharm_forced_response(tmp_path):
    """Runs with or without pyHarm (without it, lcpfric's own harmonic-balance loop alone)."""
    need_modules("matplotlib")
    out = run("pyharm_forced_response.py", tmp_path=tmp_path)
    assert "closed form" in out


def test_multi_node(tmp_path):
    out = run("multi_node.py", tmp_path=tmp_path)
    assert "converged True" in out
    diff = float(re.search(r"relative difference ([\d.e+-]+)", out).group(1))
    assert diff < 1e-3


@pytest.mark.slow
def test_hertz_sphere(tmp_path):
    need_modules("matplotlib")
    out = run("hertz_sphere.py", tmp_path=tmp_path)
    diff = float(re.search(r"relative difference ([\d.e+-]+)\)", out).group(1))
    assert abs(diff) < 1e-3  # Mindlin-Deresiewicz at constant P
    assert len(re.findall(r"largest at φ ≈ 0\.[4-6]\dπ", out)) == 3


@pytest.mark.slow  # also run by the documentation build (the gallery)
def test_halfspace_contact(tmp_path):
    need_modules("matplotlib")
    env_grid = {"LCPFRIC_EXAMPLE_GRID": "12"}
    proc = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "halfspace_contact.py")],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
        env=dict(
            os.environ,
            MPLBACKEND="Agg",
            **env_grid,
            PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
        ),
    )
    assert proc.returncode == 0, proc.stderr
    assert re.search(r"W k_t0/\(μ² P0²\) = 0\.\d+", proc.stdout)
    assert not list(tmp_path.iterdir())  # nothing written: the figure is shown
