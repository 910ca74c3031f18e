"""Figures: written from a fresh `lcpfric figures`, built from computed data, boundary drawn."""

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")
pytest.importorskip("xarray")

from lcpfric.paper import figures  # noqa: E402
from lcpfric._optional import MissingExtra  # noqa: E402
from lcpfric.errors import InputError  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
NAMES = ("fig3_map_phi0", "fig4_maps", "fig5_phase_P1_0.5", "fig6_phase_P1_Q1_5",
         "fig7_phase_P1_1.5", "fig9_motor")


def test_figures_command_fresh_process(tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH",
                                                                                   "")]))
    out = tmp_path / "figs"
    run = subprocess.run([sys.executable, "-m", "lcpfric", "figures", "--out", str(out),
                          "--grid", "21", "--points", "41", "--format", "png,pdf", "--json"],
                         capture_output=True, text=True, env=env, timeout=120)
    assert run.returncode == 0, run.stderr
    files = {Path(p).name for p in json.loads(run.stdout)["files"]}
    assert files == {f"{n}.{ext}" for n in NAMES for ext in ("png", "pdf")}
    for name in NAMES:
        assert (out / f"{name}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert (out / f"{name}.pdf").read_bytes()[:5] == b"%PDF-"


@pytest.fixture(scope="module")
def maps():
    return figures.map_data(grid=11)


def _red_lines(ax):
    red = np.array([0xE8, 0x40, 0x2A, 0xFF]) / 255
    found = []
    for coll in ax.collections:
        colors = np.atleast_2d(coll.get_edgecolor())
        if colors.size and np.allclose(colors[0], red, atol=1e-3):
            found.append(coll)
    return found


def test_maps_have_boundary_line_and_colorbar(maps):
    fig = figures.figure_maps(maps, figures.FIG4_PHASES, ncols=5)
    panels = [ax for ax in fig.axes if ax.get_title().startswith("φ")]
    assert len(panels) == 10
    assert [ax.get_title() for ax in panels][-1] == "φ = π"
    assert any(ax.get_label() == "<colorbar>" for ax in fig.axes)
    for ax in panels:
        assert _red_lines(ax), f"no shakedown boundary on {ax.get_title()}"
        assert any(line.get_xdata()[0] == 1.0 for line in ax.lines)  # the line P̂1 = 1
    single = figures.figure_maps(maps, [0.0])
    assert single.axes[0].get_xlabel() == r"$\hat P_1$"
    assert single.axes[0].get_legend() is not None


def test_boundary_follows_shakedown_region(maps):
    # At φ = π/2 the shakedown region is the unit disc P̂1² + Q̂1² <= 1.
    fig = figures.figure_maps(maps, [math.pi / 2])
    (coll,) = _red_lines(fig.axes[0])
    xy = np.concatenate([p.vertices for p in coll.get_paths()])
    np.testing.assert_allclose(np.hypot(xy[:, 0], xy[:, 1]), 1.0, atol=1e-3)


def test_phase_figure_marks_the_maximum():
    fig = figures.figure_phase(5.0, (5.0,), points=41)
    ax = fig.axes[0]
    marker = [line for line in ax.lines if line.get_marker() == "o"]
    assert len(marker) == 1
    assert marker[0].get_xdata()[0] == pytest.approx(0.6016, abs=1e-3)


def test_motor_figure_curves_start_at_zero():
    fig = figures.figure_motor(points=50)
    ax = fig.axes[0]
    curves = [line for line in ax.lines if line.get_label().startswith("f = ")]
    assert len(curves) == len(figures.MOTOR_FRICTION)
    for line in curves:
        y = line.get_ydata()
        assert y[0] == 0.0 and y[-1] > 0 and np.all(np.diff(y) >= -1e-12)


def test_bad_inputs(tmp_path):
    with pytest.raises(InputError):
        figures.write_figures(tmp_path, formats=("gif",))
    with pytest.raises(InputError):
        figures.map_data(grid=1)
    (tmp_path / "file").write_text("")
    with pytest.raises(InputError):
        figures.write_figures(tmp_path / "file", grid=5)


def test_missing_matplotlib_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(MissingExtra, match=r'lcpfric\[plot\]'):
        figures._figure()
