"""``lcpfric system``: a user's system file, from one start or over many (issue 38, item 6)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import lcpfric
from lcpfric.cli import main

SYSTEM = dict(
    K=[[4.0, -1.0, 0.5], [-1.0, 3.0, -1.0], [0.5, -1.0, 5.0]],
    B=[[0.9, -1.2, 0.4], [1.1, 0.3, -0.8], [-0.5, 0.9, 1.0]],
    friction=[0.5, 0.6, 0.4],
    P0=[4.0, 3.5, 4.5],
    P1=[1.0, 0.5, 1.2],
    psi=[0.0, 1.0, 2.0],
    Q0=[0.0, 0.0, 0.0],
    Q1=[2.5, 2.0, 2.8],
    phi=[0.3, 2.0, 4.0],
)


@pytest.fixture
def sysfile(tmp_path):
    path = tmp_path / "s.json"
    path.write_text(json.dumps(SYSTEM))
    return path


def test_json_fields_and_the_api_agree(sysfile, capsys):
    assert main(["system", "--file", str(sysfile), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"W", "W_min", "W_max", "shakedown", "converged", "cycles"} <= set(out)
    system, start = lcpfric.load_system(sysfile)
    assert out["W"] == lcpfric.steady_state(system, "exact", u0=start).W
    assert out["W_min"] == out["W_max"] == out["W"] and out["converged"]


def test_a_start_file_is_followed(sysfile, tmp_path, capsys):
    start = tmp_path / "u0.txt"
    start.write_text("0.1 0 0\n")
    assert main(["system", "--file", str(sysfile), "--start", str(start), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    system, _ = lcpfric.load_system(sysfile)
    assert out["W"] == lcpfric.steady_state(system, "exact", u0=[0.1, 0, 0]).W


def test_many_starts_give_the_range(sysfile, capsys):
    assert main(["system", "--file", str(sysfile), "--starts", "12", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["W"]) == 12 and len(out["cycles"]) == 12
    assert out["W_min"] == min(out["W"]) and out["W_max"] == max(out["W"])
    assert 0.0 <= out["shakedown"] <= 1.0
    assert main(["system", "--file", str(sysfile), "--starts", "12"]) == 0
    assert "W over 12 starts" in capsys.readouterr().out


def test_uncoupled_file_has_one_w(tmp_path, capsys):
    path = tmp_path / "u.npz"
    np.savez(path, **{k: np.asarray(v) for k, v in SYSTEM.items() if k != "B"})
    assert main(["system", "--file", str(path), "--starts", "8", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["unique"] and out["W_max"] - out["W_min"] <= 1e-9 * out["W_max"]
