"""``lcpfric describe``: a Jenkins element's describing functions on the command line (issue 39,
item 3); its bad input is in tests/test_cli_bad_input_table.py."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from lcpfric.analysis.describing import describing_functions, jenkins_closed_form
from lcpfric.cli import main
from lcpfric.model.jenkins import JenkinsElement

BASE = ["describe", "--kt", "2", "--mu", "0.3", "--N0", "5"]
FIELDS = ("W", "k_eq", "c_eq_omega", "loss_factor", "force_amplitude")


def _json(capsys, *argv):
    assert main([*BASE, *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_one_amplitude_gives_one_value_per_field(capsys):
    out = _json(capsys, "--amplitude", "3")
    assert set(FIELDS) <= set(out) and out["amplitude"] == 3.0
    cf = jenkins_closed_form(2.0, 0.3, 5.0, [3.0])
    for name in FIELDS:
        assert isinstance(out[name], float)
        assert out[name] == pytest.approx(float(cf[name][0]), rel=1e-12)
    assert out["slip_limit"] == 0.75 and out["method"] == "single-node"


def test_a_range_gives_lists_log_spaced(capsys):
    out = _json(capsys, "--amplitude", "0.5:1000:7")
    a = np.asarray(out["amplitude"])
    np.testing.assert_allclose(a, np.geomspace(0.5, 1000.0, 7))
    df = describing_functions(JenkinsElement(2.0, 0.3, 5.0), a)
    for name in FIELDS:
        assert out[name] == getattr(df, name).tolist()
    assert out["c_eq_omega"][0] == 0.0 and out["k_eq"][0] == 2.0  # below the slip limit


def test_a_varying_normal_load_and_a_normal_spring(capsys):
    """--N1 with --phi, and --kn with --un1 (N1 = kn un1), give the API's values; the event
    solver agrees."""
    a = _json(capsys, "--N1", "7", "--phi", "0.5pi", "--amplitude", "1,3")
    b = _json(capsys, "--kn", "70", "--un1", "0.1", "--phi", "pi/2", "--amplitude", "1,3")
    c = _json(capsys, "--N1", "7", "--phi", "0.5pi", "--amplitude", "1,3", "--method", "driven")
    df = describing_functions(JenkinsElement(2.0, 0.3, 5.0, 7.0, math.pi / 2), [1.0, 3.0])
    for name in FIELDS:
        assert a[name] == getattr(df, name).tolist()
        np.testing.assert_allclose(b[name], a[name], rtol=1e-14)
        np.testing.assert_allclose(c[name], a[name], rtol=1e-12)
    assert c["method"] == "driven"


def test_harmonics_and_the_start(capsys):
    out = _json(capsys, "--amplitude", "0.5,3", "--harmonics", "3")
    assert len(out["force_cos"]) == 2 and len(out["force_cos"][0]) == 4
    np.testing.assert_allclose(-np.asarray(out["force_sin"])[:, 1] / [0.5, 3.0],
                               out["c_eq_omega"], atol=1e-15)  # fmt: skip
    moved = _json(capsys, "--amplitude", "0.5", "--start", "0.1", "--harmonics", "2")
    assert moved["force_cos"][0] == pytest.approx(-0.2)  # the mean force kt (0 - w0)
    assert moved["force_amplitude"] == pytest.approx(1.2) and moved["W"] == 0.0


def test_the_table(capsys):
    assert main([*BASE, "--amplitude", "0.5:1000:5", "--harmonics", "3"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "slip limit mu N0/kt = 0.75" in lines[0]
    assert lines[1].split() == ["amplitude", *FIELDS, "|T_2|", "|T_3|"]
    assert len(lines) == 2 + 5
    first = [float(v) for v in lines[2].split()]
    assert first[:3] == [0.5, 0.0, 2.0]


SPHERE = ["describe", "--contact", "sphere", "--R", "10", "--E", "2e5", "--nu", "0.3",
          "--mu", "0.5", "--N0", "100"]  # fmt: skip


def test_the_sphere_against_mindlin(capsys):
    """Below gross slip the MDR sphere's W is Mindlin-Deresiewicz's at the force amplitude
    reached (the springs' closed forms, 2000 springs)."""
    from lcpfric.model.continuum.closed_forms import mindlin_deresiewicz_W, moduli

    assert main([*SPHERE, "--amplitude", "1e-4:1e-3:4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["method"] == "closed-form"
    a0 = (3 * 100 * 10 / (4 * moduli(2e5, 0.3)["E*"])) ** (1 / 3)
    k_t0 = 2 * a0 * moduli(2e5, 0.3)["G*"]
    for W, Q in zip(out["W"], out["force_amplitude"]):
        assert Q < 0.5 * 100
        assert W == pytest.approx(mindlin_deresiewicz_W(100, Q, 0.5, k_t0), rel=5e-3)


def test_the_sphere_with_a_varying_normal_load(capsys):
    assert main([*SPHERE, "--N1", "30", "--phi", "0.5pi", "--amplitude", "1e-3", "--nodes",
                 "400", "--samples", "256", "--json"]) == 0  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    assert out["method"] == "march" and out["W"] > 0 and out["k_eq"] > 0
