"""``lcpfric modal``: a jointed structure from a .npz file (issue 39, items 4 and 6)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from lcpfric.analysis.modal import jenkins_oscillator, modal_damping
from lcpfric.cli import main
from lcpfric.cli.modal import KEYS, read_structure
from lcpfric.model.jointed import jointed_rod

ONE = dict(M=[[2.0]], K=[[1.0]], contact_dofs=[[0, -1]], kt=3.0, mu=0.25, N=2.0)


@pytest.fixture
def one(tmp_path):
    path = tmp_path / "one.npz"
    np.savez(path, **ONE)
    return path


def test_json_against_the_closed_form(one, capsys):
    assert main(["modal", "--file", str(one), "--amplitude", "0.1:50:6", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    a = np.geomspace(0.1, 50, 6)  # A:B:N is log-spaced
    omega, zeta, W, _ = jenkins_oscillator(a, 1.0, 3.0, 0.5, mass=2.0)
    np.testing.assert_allclose(out["a"], a, rtol=1e-12)
    np.testing.assert_allclose(out["omega"], omega, rtol=1e-12)
    np.testing.assert_allclose(out["zeta"], zeta, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(out["W"], W, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(out["omega_ratio"], omega / np.sqrt(2.0), rtol=1e-12)
    assert out["sticks"] == [True] + [False] * 5 and out["mode"] == 0
    assert out["omega0"] == pytest.approx(np.sqrt(2.0), rel=1e-14)


def test_one_amplitude_gives_one_value_per_field(one, capsys):
    assert main(["modal", "--file", str(one), "--amplitude", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert isinstance(out["zeta"], float) and isinstance(out["sticks"], bool)


def test_the_text_table(one, capsys):
    assert main(["modal", "--file", str(one), "--amplitude", "0.1,2"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("mode 0 of the stuck structure: omega0 = 1.414213562")
    assert lines[1].split() == ["a", "omega/omega0", "zeta", "W"]
    assert lines[2].endswith("(sticks)") and not lines[3].endswith("(sticks)")
    assert len(lines) == 4


def test_the_rod_and_a_higher_mode_agree_with_the_api(tmp_path, capsys):
    rod = jointed_rod(n=20, contacts=4, sparse=False)
    path = tmp_path / "rod.npz"
    fields = dict(M=rod.mass, K=rod.stiffness, contact_dofs=rod.contact_dofs,
                  kt=rod.contact_stiffness, mu=rod.friction, N=rod.normal_load)  # fmt: skip
    np.savez(path, **fields)
    assert main(["modal", "--file", str(path), "--amplitude", "0.01,0.3,3", "--mode", "1",
                 "--json"]) == 0  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    res = modal_damping(read_structure(str(path)), [0.01, 0.3, 3.0], mode=1)
    assert out["zeta"] == res.zeta.tolist() and out["omega_ratio"] == res.omega_ratio.tolist()
    assert out["mode"] == 1 and set(KEYS.values()) == set(fields)


def test_the_command_line_entry_point(one):
    run = subprocess.run(
        [sys.executable, "-m", "lcpfric", "modal", "--file", str(one), "--amplitude", "-2"],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 2 and "Traceback" not in run.stderr
    assert (
        run.stderr.strip()
        == "lcpfric modal: error: --amplitude: every amplitude must be > 0, got -2"
    )
