"""Bad input raises InputError naming the parameter; the CLI exits 2 with one line."""

import json
import subprocess
import sys

import numpy as np
import pytest

import lcpfric
from lcpfric import InputError, SingleNode, steady_state
from lcpfric._checks import parse_angle


@pytest.mark.parametrize("kwargs,param", [
    (dict(k11=-1.0), "k11"), (dict(k11=0.0), "k11"), (dict(f=-0.1), "f"), (dict(f=0.0), "f"),
    (dict(P0=0.0), "P0"), (dict(P0=-2.0), "P0"), (dict(P1=-1.0), "P1"), (dict(Q1=-1.0), "Q1"),
    (dict(k22=-5.0), "k22"), (dict(omega=0.0), "omega"), (dict(phi=np.nan), "phi"),
    (dict(P1=np.inf), "P1"), (dict(Q0=np.nan), "Q0"), (dict(k11="abc"), "k11"),
])
def test_bad_model_inputs(kwargs, param):
    with pytest.raises(InputError) as info:
        SingleNode(**kwargs)
    assert info.value.parameter == param
    assert param in str(info.value)


def test_bad_driver_inputs():
    node = SingleNode.normalized(1.0, 1.0, 0.0)
    for kw, param in [(dict(steps_per_cycle=2), "steps_per_cycle"), (dict(tol=-1), "tol"),
                      (dict(max_cycles=0), "max_cycles"), (dict(method="nope"), "method"),
                      (dict(on_nonconvergence="x"), "on_nonconvergence"),
                      (dict(method="explicit", placement="x"), "placement")]:
        with pytest.raises(InputError) as info:
            steady_state(node, **kw)
        assert info.value.parameter == param
    with pytest.raises(InputError, match="model"):
        steady_state("not a model")


@pytest.mark.parametrize("text,value", [("0.6pi", 0.6 * np.pi), ("pi/2", np.pi / 2),
                                        ("3*pi/10", 0.3 * np.pi), ("-pi", -np.pi),
                                        ("1.25", 1.25), ("π", np.pi), ("2e-1pi", 0.2 * np.pi)])
def test_parse_angle(text, value):
    assert parse_angle(text) == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize("text", ["pie", "0.6 pi pi", "", "nan", "inf", "pi/0"])
def test_parse_angle_rejects(text):
    with pytest.raises(InputError):
        parse_angle(text)


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "lcpfric", *args], capture_output=True,
                          text=True, timeout=120)


def test_cli_dissipation_json():
    p = run_cli("dissipation", "--P1", "1.5", "--Q1", "2", "--phi", "0.6pi", "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    for key in ("W_hat", "method", "steps_requested", "steps_used", "cycles", "converged",
                "seconds"):
        assert key in out
    assert out["W_hat"] == pytest.approx(lcpfric.exact_W_hat(1.5, 2, 0.6 * np.pi), rel=1e-12)
    p = run_cli("dissipation", "--P1", "300", "--Q1", "200", "--k11", "1e6", "--f", "0.3",
                "--P0", "100", "--phi", "pi/2", "--method", "explicit", "--steps", "800",
                "--json")
    out = json.loads(p.stdout)
    assert out["W"] == pytest.approx(0.3 * 100 * 200 * out["W_hat"] / 1e6, rel=1e-12)
    p = run_cli("dissipation", "--P1", "0.5", "--Q1", "2")
    assert p.returncode == 0 and "W_hat" in p.stdout


def test_cli_shakedown_json():
    p = run_cli("shakedown", "--P1", "0.5", "--Q1", "0.7", "--phi", "0.3pi", "--json")
    out = json.loads(p.stdout)
    assert out["shakedown"] is True and isinstance(out["shift"], float)
    out = json.loads(run_cli("shakedown", "--P1", "1.5", "--Q1", "2", "--json").stdout)
    assert out == {"shakedown": False, "shift": None, "margin": out["margin"]}


@pytest.mark.parametrize("args,name", [
    (["--P1", "-1", "--Q1", "2"], "--P1"), (["--P1", "nan", "--Q1", "2"], "--P1"),
    (["--P1", "1", "--Q1", "x"], "--Q1"), (["--P1", "1", "--Q1", "2", "--phi", "0.6pie"], "--phi"),
    (["--P1", "1", "--Q1", "2", "--P0", "0"], "--P0"),
    (["--P1", "1", "--Q1", "2", "--k11", "-3"], "--k11"),
    (["--P1", "1", "--Q1", "2", "--f", "-0.2"], "--f"),
    (["--P1", "1", "--Q1", "2", "--method", "nope"], "--method"),
    (["--P1", "1", "--Q1", "2", "--steps", "2"], "--steps"),
    (["--P1", "1", "--Q1", "2", "--steps", "abc"], "--steps"),
])
def test_cli_bad_input_exit_2_no_traceback(args, name):
    p = run_cli("dissipation", *args)
    assert p.returncode == 2
    assert "Traceback" not in p.stderr and name in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1


def test_cli_missing_option_exit_2():
    p = run_cli("dissipation", "--Q1", "2")
    assert p.returncode == 2 and "Traceback" not in p.stderr
