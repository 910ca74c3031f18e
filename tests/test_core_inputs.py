"""Bad input raises InputError naming the parameter; the CLI exits 2 with one line."""

import json
import subprocess
import sys

import numpy as np
import pytest

import lcpfric
from lcpfric import InputError, SingleNode, steady_state
from lcpfric._checks import parse_angle


@pytest.mark.parametrize(
    "kwargs,param",
    [
        (dict(k11=-1.0), "k11"),
        (dict(k11=0.0), "k11"),
        (dict(f=-0.1), "f"),
        (dict(f=0.0), "f"),
        (dict(P0=0.0), "P0"),
        (dict(P0=-2.0), "P0"),
        (dict(P1=-1.0), "P1"),
        (dict(Q1=-1.0), "Q1"),
        (dict(k22=-5.0), "k22"),
        (dict(omega=0.0), "omega"),
        (dict(phi=np.nan), "phi"),
        (dict(P1=np.inf), "P1"),
        (dict(Q0=np.nan), "Q0"),
        (dict(k11="abc"), "k11"),
    ],
)
def test_bad_model_inputs(kwargs, param):
    with pytest.raises(InputError) as info:
        SingleNode(**kwargs)
    assert info.value.parameter == param
    assert param in str(info.value)


def test_bad_driver_inputs():
    node = SingleNode.normalized(1.0, 1.0, 0.0)
    for kw, param in [
        (dict(steps_per_cycle=2), "steps_per_cycle"),
        (dict(tol=-1), "tol"),
        (dict(max_cycles=0), "max_cycles"),
        (dict(method="nope"), "method"),
        (dict(on_nonconvergence="x"), "on_nonconvergence"),
        (dict(method="explicit", placement="x"), "placement"),
    ]:
        with pytest.raises(InputError) as info:
            steady_state(node, **kw)
        assert info.value.parameter == param
    with pytest.raises(InputError, match="model"):
        steady_state("not a model")


@pytest.mark.parametrize(
    "text,value",
    [
        ("0.6pi", 0.6 * np.pi),
        ("pi/2", np.pi / 2),
        ("3*pi/10", 0.3 * np.pi),
        ("-pi", -np.pi),
        ("1.25", 1.25),
        ("π", np.pi),
        ("2e-1pi", 0.2 * np.pi),
    ],
)
def test_parse_angle(text, value):
    assert parse_angle(text) == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize("text", ["pie", "0.6 pi pi", "", "nan", "inf", "pi/0"])
def test_parse_angle_rejects(text):
    with pytest.raises(InputError):
        parse_angle(text)


def run_cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "lcpfric", *args], capture_output=True, text=True, timeout=120
    )


def test_cli_dissipation_json():
    p = run_cli("dissipation", "--P1", "1.5", "--Q1", "2", "--phi", "0.6pi", "--json")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    for key in (
        "W_hat",
        "method",
        "steps_requested",
        "steps_used",
        "cycles",
        "converged",
        "seconds",
    ):
        assert key in out
    assert out["W_hat"] == pytest.approx(lcpfric.exact_W_hat(1.5, 2, 0.6 * np.pi), rel=1e-12)
    p = run_cli(
        "dissipation",
        "--P1",
        "300",
        "--Q1",
        "200",
        "--k11",
        "1e6",
        "--f",
        "0.3",
        "--P0",
        "100",
        "--phi",
        "pi/2",
        "--method",
        "explicit",
        "--steps",
        "800",
        "--json",
    )
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


@pytest.mark.parametrize(
    "args,name",
    [
        (["--P1", "-1", "--Q1", "2"], "--P1"),
        (["--P1", "nan", "--Q1", "2"], "--P1"),
        (["--P1", "1", "--Q1", "x"], "--Q1"),
        (["--P1", "1", "--Q1", "2", "--phi", "0.6pie"], "--phi"),
        (["--P1", "1", "--Q1", "2", "--P0", "0"], "--P0"),
        (["--P1", "1", "--Q1", "2", "--k11", "-3"], "--k11"),
        (["--P1", "1", "--Q1", "2", "--f", "-0.2"], "--f"),
        (["--P1", "1", "--Q1", "2", "--method", "nope"], "--method"),
        (["--P1", "1", "--Q1", "2", "--steps", "2"], "--steps"),
        (["--P1", "1", "--Q1", "2", "--steps", "abc"], "--steps"),
    ],
)
def test_cli_bad_input_exit_2_no_traceback(args, name):
    p = run_cli("dissipation", *args)
    assert p.returncode == 2
    assert "Traceback" not in p.stderr and name in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1


def test_cli_missing_option_exit_2():
    p = run_cli("dissipation", "--Q1", "2")
    assert p.returncode == 2 and "Traceback" not in p.stderr


# -- the fast paths validate too ------------------------------------------------------------------


@pytest.mark.parametrize(
    "args,param",
    [
        ((np.nan, 2, 0), "P1"),
        ((-1, 2, 0), "P1"),
        ((1e400, 2, 0), "P1"),
        ((10**400, 2, 0), "P1"),
        ((2, -1.0, 0), "Q1"),
        ((2, np.inf, 0), "Q1"),
        ((2, 1e301, 0), "Q1"),
        ((2, 1, np.nan), "phi"),
        ((2, 1, np.inf), "phi"),
        ((True, 2, 0), "P1"),
        ((2, False, 0), "Q1"),
        ((2, 1, True), "phi"),
        (("1.5", 2, 0), "P1"),
        ((2, "2", 0), "Q1"),
        ((2, 1, "0.3"), "phi"),
        ((1j, 2, 0), "P1"),
        ((None, 2, 0), "P1"),
        ((np.bool_(True), 2, 0), "P1"),
    ],
)
def test_exact_W_hat_scalar_validates(args, param):
    from lcpfric.exact import exact_W_hat

    with pytest.raises(InputError) as info:
        exact_W_hat(*args)
    assert info.value.parameter == param
    if param != "phi" and not isinstance(
        args[0 if param == "P1" else 1], (str, bool, complex, type(None), np.bool_)
    ):
        assert "[0, 1e+300]" in str(info.value)  # names the allowed range


@pytest.mark.parametrize(
    "args,param",
    [
        (([1.0, np.nan], 2.0, 0.0), "P1"),
        (([1.0, -2.0], 2.0, 0.0), "P1"),
        ((np.array([1.0, 2e300]), 2.0, 0.0), "P1"),
        ((1.0, np.array([1.0, np.inf]), 0.0), "Q1"),
        ((1.0, 2.0, [0.0, np.nan]), "phi"),
        ((np.array(["1"]), 2.0, 0.0), "P1"),
        ((np.array([True, False]), 2.0, 0.0), "P1"),
        (([1.0, "x"], 2.0, 0.0), "P1"),
        (([1.0, 2.0], [1.0, 2.0, 3.0], 0.0), "P1, Q1, phi"),
    ],
)
def test_exact_W_hat_arrays_validate(args, param):
    from lcpfric.exact import exact_W_hat

    with pytest.raises(InputError) as info:
        exact_W_hat(*args)
    assert info.value.parameter == param


def test_exact_W_hat_accepts_numbers_of_every_numeric_type():
    from lcpfric.exact import exact_W_hat

    ref = exact_W_hat(1.5, 2.0, 0.5)
    for args in [
        (np.float64(1.5), np.float32(2.0), 0.5),
        (1.5, 2, np.int64(0) + 0.5),
        (np.array(1.5), 2.0, 0.5),
        ([1.5], [2.0], [0.5]),
    ]:
        assert float(np.ravel(exact_W_hat(*args))[0]) == pytest.approx(ref, rel=1e-6)
    assert exact_W_hat(2, 3, 0) == exact_W_hat(2.0, 3.0, 0.0)


def test_exact_cycle_validates():
    from lcpfric.exact import exact_cycle

    for args, param in [
        ((np.nan, 1.0, 0.0), "P1"),
        ((1.0, -1.0, 0.0), "Q1"),
        ((1.0, 1.0, np.inf), "phi"),
        (([1.0, 2.0], 1.0, 0.0), "P1"),
    ]:
        with pytest.raises(InputError) as info:
            exact_cycle(*args)
        assert info.value.parameter == param


def test_jang_barber_validates():
    from lcpfric.analysis.analytic import jang_barber

    for args, param in [
        ((-0.5, 2.0), "P1"),
        ((0.5, -2.0), "Q1"),
        ((np.nan, 2.0), "P1"),
        (("0.5", 2.0), "P1"),
        ((True, 2.0), "P1"),
    ]:
        with pytest.raises(InputError) as info:
            jang_barber(*args)
        assert info.value.parameter == param
    # factored: no overflow at large amplitudes
    assert jang_barber(0.5, 1e200) == pytest.approx(4.0, rel=1e-12)
    assert jang_barber(1e200, 2e200) == pytest.approx(1e200 / 3 * (1 + 1e-200), rel=1e-12)


@pytest.mark.parametrize(
    "kwargs,param",
    [
        (dict(P1="1.5"), "P1"),
        (dict(P1=True), "P1"),
        (dict(Q1="2"), "Q1"),
        (dict(phi="0.3"), "phi"),
        (dict(Q1=np.bool_(False)), "Q1"),
    ],
)
def test_single_node_normalized_strict_types(kwargs, param):
    args = dict(P1=1.0, Q1=1.0, phi=0.0) | kwargs
    with pytest.raises(InputError) as info:
        SingleNode.normalized(**args)
    assert info.value.parameter == param


@pytest.mark.parametrize(
    "kwargs,param",
    [
        (dict(P0=1e-320), "P0"),  # subnormal: 1/P0 overflows
        (dict(f=1e308, P0=1e308), "f"),  # f P0 overflows (Q̂1 would be 0)
        (dict(f=1e-200, P0=1e-200), "f"),  # f P0 underflows
        (dict(P0=1e-300, P1=1e10), "P1"),  # P̂1 = 1e310 overflows
        (dict(P0=1e300, Q1=1e-20, f=1e-5), "Q1"),  # Q̂1 = 1e-315 is subnormal
        (dict(P0=1e200, P1=1e-200), "P1"),  # P̂1 underflows to 0
        (dict(k11=1e-320), "k11"),  # subnormal stiffness
        (dict(k11=1e-300, f=1e10, P0=1e10), "k11"),  # displacement unit f P0 / k11 = 1e320
        (dict(omega=1e-320), "omega"),  # period 2π/ω overflows
        (dict(k11=True), "k11"),
        (dict(f="0.3"), "f"),
        (dict(dimensional="yes"), "dimensional"),
        (dict(dimensional=1), "dimensional"),
    ],
)
def test_single_node_refuses_unrepresentable_units(kwargs, param):
    with pytest.raises(InputError) as info:
        SingleNode(**kwargs)
    assert info.value.parameter == param
    assert param in str(info.value)


def test_single_node_accepts_wide_but_representable_units():
    node = SingleNode(k11=1e-200, f=1e-150, P0=1e150, P1=3e149, Q1=2.0, phi=0.4)
    assert node.P1_hat == pytest.approx(0.3) and node.Q1_hat == pytest.approx(2.0)
    assert SingleNode(dimensional=np.bool_(False)).dimensional is False


def test_exact_method_refuses_amplitudes_beyond_its_range():
    node = SingleNode(P0=1e-10, P1=1e295, Q1=1.0)  # P̂1 = 1e305: representable, above 1e300
    with pytest.raises(InputError) as info:
        steady_state(node, "exact")
    assert info.value.parameter == "P1"


def test_checks_boolean_helper():
    from lcpfric._checks import boolean

    assert boolean("refine", True) is True and boolean("refine", np.bool_(False)) is False
    for bad in ("yes", 1, 0, None, 1.0, "True"):
        with pytest.raises(InputError) as info:
            boolean("refine", bad)
        assert info.value.parameter == "refine" and "True or False" in str(info.value)


def test_parsers_keep_accepting_text_and_refuse_bools():
    from lcpfric._checks import finite, parse_number, positive_int

    assert parse_number("1.5", "--P1") == 1.5 and parse_number(2, "--P1") == 2.0
    assert parse_angle("0.6pi") == pytest.approx(0.6 * np.pi) and parse_angle(0.5) == 0.5
    assert positive_int("n", "12") == 12  # the CLI passes its text
    for func, args in [
        (parse_number, (True, "--P1")),
        (parse_angle, (False,)),
        (positive_int, ("n", True)),
        (finite, ("x", "1.0")),
        (finite, ("x", np.array("1.0"))),
    ]:
        with pytest.raises(InputError):
            func(*args)
