"""The command line (lcpfric.cli): one module per subcommand, one option-naming mechanism, checks
before any work, exit codes 0/1/2 with one-line messages and no traceback.

Most tests call ``lcpfric.cli.main([...])`` in this process and read stdout/stderr with capsys.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from support import need_modules

import lcpfric
from lcpfric.cli import COMMANDS, _common, _extras, build_parser, main
from lcpfric.errors import InputError, SolverError

ROOT = Path(__file__).resolve().parents[1]


def run(capsys, *argv):
    """(exit code, stdout, stderr) of ``lcpfric argv``."""
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_error(code, err, option, expected=2):
    assert code == expected, err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert option in lines[0], err


CASE = ("--P1", "1.5", "--Q1", "2", "--phi", "0.6pi")
GRID = ("--P1", "0:2:3", "--Q1", "0:2:3", "--phi", "0")


# -- A. architecture -------------------------------------------------------------------------------
def test_every_subcommand_is_listed(capsys):
    code, out, _ = run(capsys, "--help")
    assert code == 0
    for name in COMMANDS:
        assert name in out
    assert set(COMMANDS) == {
        "dissipation",
        "loop",
        "shakedown",
        "system",
        "contact",
        "methods",
        "map",
        "figures",
        "paper-claims",
        "modal",
        "describe",
        "frf",
    }


def test_subcommands_listed_and_extras_named_when_extras_are_missing(capsys, monkeypatch, tmp_path):
    missing = {"matplotlib", "xarray", "h5netcdf", "netCDF4"}
    monkeypatch.setattr(_common, "installed", lambda m: m not in missing)
    monkeypatch.setattr(_extras, "installed", lambda m: m not in missing)
    code, out, _ = run(capsys, "--help")
    assert code == 0 and "map" in out and "figures" in out
    code, _, err = run(capsys, "figures", "--out", tmp_path / "f")
    assert_one_line_error(code, err, 'pip install "lcpfric[plot,dist]"')
    assert "matplotlib (plot)" in err and "xarray (dist)" in err  # both at once
    assert not (tmp_path / "f").exists()
    code, _, err = run(capsys, "map", *GRID, "--out", tmp_path / "m.nc")
    assert_one_line_error(code, err, 'pip install "lcpfric[dist]"')
    assert "xarray" in err and "h5netcdf" in err


LAZY_INIT = (
    "import sys, types; m = types.ModuleType('lcpfric'); m.__path__ = [{path!r}]; "
    "m.__version__ = 'x'; sys.modules['lcpfric'] = m; from lcpfric.cli import main; "
    "import contextlib, io\n"
    "with contextlib.redirect_stdout(io.StringIO()):\n"
    "    code = main({argv!r})\n"
    "heavy = ('numpy', 'scipy', 'xarray', 'matplotlib', 'dask', 'distributed', "
    "'cvxpy', 'qpsolvers', 'clarabel', 'osqp', 'h5py', 'tqdm')\n"
    "print(code, sorted(h for h in heavy if h in sys.modules))"
)


@pytest.mark.parametrize(
    "argv,allowed",
    [
        (["--help"], set()),
        (["dissipation", "--help"], set()),
        (["map", "--help"], set()),
        (["shakedown", "--P1", "0.5", "--Q1", "0.7", "--phi", "0.3pi"], {"numpy", "scipy"}),
        (["dissipation", "--P1", "1.5", "--Q1", "2", "--phi", "0.6pi"], {"numpy", "scipy"}),
    ],
)
def test_cli_imports_only_what_the_command_needs(argv, allowed):
    """With the package's own __init__ out of the way (it is being made lazy), the CLI imports
    nothing heavy for --help, and no extra for shakedown or exact dissipation."""
    code = LAZY_INIT.format(path=str(ROOT / "lcpfric"), argv=argv)
    p = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, cwd=ROOT
    )
    assert p.returncode == 0, p.stderr
    status, imported = p.stdout.strip().split(" ", 1)
    assert status == "0"
    assert set(eval(imported)) <= allowed, imported


def test_input_error_is_renamed_from_its_attributes(capsys, monkeypatch):
    """One mechanism: InputError.parameter -> the subcommand's option; .detail printed as is
    (even when it holds ': ')."""
    import lcpfric.periodic

    def bad(*args, **kwargs):
        raise InputError("steps_per_cycle", "bad: really bad: yes")

    monkeypatch.setattr(lcpfric.periodic, "steady_state", bad)
    code, _, err = run(capsys, "dissipation", *CASE)
    assert_one_line_error(code, err, "--steps: bad: really bad: yes")
    parser = build_parser()
    sub = parser._subparsers._group_actions[0].choices
    names = _common.option_names(sub["map"], {"steps_per_cycle": "--steps"})
    assert _common.option_for("chunk_size", names) == "--chunk-size"
    assert _common.option_for("steps_per_cycle", names) == "--steps"
    assert _common.option_for("P1 (NUM)", names) == "--P1 (NUM)"
    assert _common.option_for("--phi", names) == "--phi"
    assert _common.option_for("model", names) == "model"


def test_solver_failure_exits_1(capsys, monkeypatch):
    import lcpfric.periodic

    def fail(*args, **kwargs):
        raise SolverError("the solver gave up\nat step 3", backend="x", status="MaxIter")

    monkeypatch.setattr(lcpfric.periodic, "steady_state", fail)
    code, _, err = run(capsys, "dissipation", *CASE, "--method", "explicit")
    assert_one_line_error(
        code, err, "failed: the solver gave up at step 3 (solver status: MaxIter)", expected=1
    )


def test_missing_package_deep_inside_is_one_line(capsys, monkeypatch):
    import lcpfric.periodic

    def missing(*args, **kwargs):
        raise ModuleNotFoundError("No module named 'clarabel'", name="clarabel")

    monkeypatch.setattr(lcpfric.periodic, "steady_state", missing)
    code, _, err = run(capsys, "dissipation", *CASE, "--method", "explicit")
    assert_one_line_error(code, err, 'pip install "lcpfric[clarabel]"')


def test_closed_pipe_is_quiet(capsys, monkeypatch):
    import lcpfric.methods

    def closed():
        raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(lcpfric.methods, "available_methods", closed)
    monkeypatch.setattr(os, "dup2", lambda *args: None)  # keep this process's stdout (pytest -s)
    code, _, err = run(capsys, "methods")
    assert code == 1 and err == ""


# -- B5. negative values ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    "phi,value",
    [
        ("-0.5pi", -0.5 * math.pi),
        ("-pi/2", -0.5 * math.pi),
        ("-1.2", -1.2),
        ("-3*pi/10", -0.3 * math.pi),
    ],
)
def test_negative_phase_follows_the_option(capsys, phi, value):
    code, out, err = run(capsys, "dissipation", "--P1", "1", "--Q1", "2", "--phi", phi, "--json")
    assert code == 0, err
    res = json.loads(out)
    assert res["phi"] == pytest.approx(value, rel=1e-15)
    assert res["W_hat"] == pytest.approx(lcpfric.exact_W_hat(1.0, 2.0, value), rel=1e-12)


def test_negative_Q0_and_shakedown_phase(capsys):
    code, out, err = run(
        capsys,
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
        "--Q0",
        "-1e3",
        "--json",
    )
    assert code == 0, err
    assert json.loads(out)["W_hat"] == pytest.approx(lcpfric.exact_W_hat(3.0, 200 / 30, 0.0))
    code, out, err = run(
        capsys, "shakedown", "--P1", "0.5", "--Q1", "0.7", "--phi", "-0.3pi", "--json"
    )
    assert code == 0 and json.loads(out)["shakedown"] is True
    # an abbreviated option takes a negative value too
    code, out, err = run(capsys, "shakedown", "--P1", "0.5", "--Q1", "0.7", "--ph", "-0.3pi")
    assert code == 0, err


def test_negative_phases_in_a_map(capsys, tmp_path):
    need_modules("xarray")
    out = tmp_path / "m.nc"
    code, text, err = run(
        capsys,
        "map",
        "--P1",
        "0:2:3",
        "--Q1",
        "1,2",
        "--phi",
        "-0.5pi,0.5pi",
        "--out",
        out,
        "--no-progress",
        "--json",
    )
    assert code == 0, err
    assert json.loads(text)["shape"] == {"phi": 2, "P1": 3, "Q1": 2}


def test_a_forgotten_value_is_still_reported(capsys):
    code, _, err = run(capsys, "dissipation", "--P1", "1", "--Q1", "2", "--phi", "--json")
    assert_one_line_error(code, err, "--phi")
    assert "expected one argument" in err
    parser = build_parser()
    assert _common.values_after_options(parser, ["dissipation", "--phi", "-1", "--P1", "-2"]) == [
        "dissipation",
        "--phi=-1",
        "--P1=-2",
    ]
    assert _common.values_after_options(parser, ["dissipation", "--phi", "-h"]) == [
        "dissipation",
        "--phi",
        "-h",
    ]
    assert _common.values_after_options(parser, ["dissipation", "--json", "-1"]) == [
        "dissipation",
        "--json",
        "-1",
    ]


# -- B6. memory guard ------------------------------------------------------------------------------
def test_map_too_large_is_refused_before_allocating(capsys, tmp_path):
    need_modules("xarray", "h5netcdf", "h5py")
    code, _, err = run(
        capsys,
        "map",
        "--P1",
        "0:10:1000000000",
        "--Q1",
        "0:10:1000000000",
        "--phi",
        "0",
        "--out",
        tmp_path / "m.nc",
    )
    assert_one_line_error(code, err, "--P1, --Q1, --phi")
    assert "--max-memory" in err and "over the limit of" in err
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("method", ["explicit", "exact"])
def test_steps_too_many_are_refused(capsys, method):
    code, _, err = run(capsys, "dissipation", *CASE, "--method", method, "--steps", "1000000000000")
    assert_one_line_error(code, err, "--steps")
    assert "--max-memory" in err and "LCPFRIC_MAX_MEMORY" in err


def test_memory_limit_option_and_environment(capsys, monkeypatch):
    args = ("dissipation", *CASE, "--steps", "100000")  # exact: ~10 MB of time series
    code, _, err = run(capsys, *args, "--max-memory", "1M")
    assert_one_line_error(code, err, "--steps")
    assert "1 MB (--max-memory)" in err
    assert run(capsys, *args, "--max-memory", "100M")[0] == 0
    monkeypatch.setenv("LCPFRIC_MAX_MEMORY", "1M")
    code, _, err = run(capsys, *args)
    assert_one_line_error(code, err, "--steps")
    assert "(LCPFRIC_MAX_MEMORY)" in err
    assert run(capsys, *args, "--max-memory", "none")[0] == 0  # the option wins
    monkeypatch.setenv("LCPFRIC_MAX_MEMORY", "lots")
    assert_one_line_error(*run(capsys, *args)[::2], "LCPFRIC_MAX_MEMORY")


def test_memory_estimates():
    assert _common.parse_size("8G", "x") == 8e9
    assert _common.parse_size("2GiB", "x") == 2**31
    assert _common.parse_size("1.5e3k", "x") == 1.5e6
    assert _common.parse_size("none", "x") == math.inf
    with pytest.raises(InputError):
        _common.parse_size("-1G", "x")
    assert (
        _common.steady_state_bytes(1000, "exact")
        < _common.steady_state_bytes(1000, "explicit")
        < _common.steady_state_bytes(1000, "clarabel")
    )
    assert _common.map_bytes(1e6) < _common.map_bytes(1e8) < _common.map_bytes(1e8, workers=8)
    limit, source = _common.memory_limit(type("A", (), {"max_memory": None})())
    assert limit > 0 and source


# -- B7. output paths ------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "name,expect",
    [
        ("adir", "is a directory"),
        ("", "is empty"),
        ("map.txt", "must end in .nc"),
        ("missing/m.nc", "does not exist"),
    ],
)
def test_map_output_checked_before_any_work(capsys, tmp_path, monkeypatch, name, expect):
    need_modules("xarray", "h5netcdf", "h5py")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "adir").mkdir()
    code, _, err = run(capsys, "map", *GRID, "--out", name)
    assert_one_line_error(code, err, "--out")
    assert expect in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["adir"]  # nothing written
    assert not list((tmp_path / "adir").iterdir())


@pytest.mark.parametrize(
    "name,expect",
    [("", "is empty"), ("afile", "is not a directory"), ("missing/figs", "does not exist")],
)
def test_figures_output_checked_before_any_work(capsys, tmp_path, monkeypatch, name, expect):
    need_modules("matplotlib", "xarray")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("x")
    code, _, err = run(capsys, "figures", "--out", name)
    assert_one_line_error(code, err, "--out")
    assert expect in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]


def test_map_and_figures_share_the_parent_rule(capsys, tmp_path):
    need_modules("matplotlib", "xarray", "h5netcdf", "h5py")
    messages = []
    for argv in (
        ["map", *GRID, "--out", tmp_path / "no" / "m.nc"],
        ["figures", "--out", tmp_path / "no" / "figs"],
    ):
        code, _, err = run(capsys, *argv)
        assert_one_line_error(code, err, "--out")
        messages.append(err.split("--out: ", 1)[1])
    assert len(set(messages)) == 1  # the same rule, the same words
    assert not (tmp_path / "no").exists()
    for name in ("map", "figures"):
        code, out, _ = run(capsys, name, "--help")
        assert "parent directory must exist" in " ".join(out.split())


def test_figures_failure_leaves_no_empty_folder(capsys, tmp_path, monkeypatch):
    need_modules("matplotlib")
    import lcpfric.paper.figures as figures

    def fail(out_dir, **kwargs):
        Path(out_dir).mkdir(exist_ok=True)
        (Path(out_dir) / "fig3_map_phi0.png").write_bytes(b"partial")
        raise SolverError("boom")

    monkeypatch.setattr(figures, "write_figures", fail)
    code, _, err = run(capsys, "figures", "--out", tmp_path / "figs")
    assert_one_line_error(code, err, "boom", expected=1)
    assert not (tmp_path / "figs").exists()
    (tmp_path / "kept").mkdir()
    (tmp_path / "kept" / "mine.txt").write_text("user file")
    code, _, err = run(capsys, "figures", "--out", tmp_path / "kept")
    assert code == 1
    assert sorted(p.name for p in (tmp_path / "kept").iterdir()) == ["mine.txt"]


def _failing_sweep(saved_chunks: int, exc):
    def sweep(P1, Q1, phi, *, out, **kwargs):
        store = Path(out).with_name(Path(out).name + ".parts")
        store.mkdir(exist_ok=True)
        (store / "manifest.json").write_text("{}")
        for i in range(saved_chunks):
            np.save(store / f"chunk-{i:06d}.npy", np.zeros(3))
        raise exc

    return sweep


def test_map_failure_leaves_no_empty_parts_folder(capsys, tmp_path, monkeypatch):
    need_modules("xarray", "h5netcdf", "h5py")
    import lcpfric.analysis.sweep as sweep_module

    out = tmp_path / "m.nc"
    monkeypatch.setattr(sweep_module, "sweep", _failing_sweep(0, SolverError("no answer")))
    code, _, err = run(capsys, "map", *GRID, "--out", out)
    assert_one_line_error(code, err, "no answer", expected=1)
    assert not list(tmp_path.iterdir())
    monkeypatch.setattr(sweep_module, "sweep", _failing_sweep(2, SolverError("no answer")))
    code, _, err = run(capsys, "map", *GRID, "--out", out)
    assert_one_line_error(code, err, "2 finished chunks are kept", expected=1)
    assert (tmp_path / "m.nc.parts").is_dir()  # worth resuming
    monkeypatch.setattr(sweep_module, "sweep", _failing_sweep(0, KeyboardInterrupt()))
    code, _, err = run(capsys, "map", *GRID, "--out", tmp_path / "n.nc")
    assert code == 130 and "nothing was saved" in err
    assert not (tmp_path / "n.nc.parts").exists()


def test_interrupted_restart_does_not_leave_the_old_map(capsys, tmp_path, monkeypatch):
    need_modules("xarray")
    import lcpfric.analysis.sweep as sweep_module

    out = tmp_path / "m.nc"
    assert run(capsys, "map", *GRID, "--out", out, "--no-progress")[0] == 0
    assert out.exists()
    real = sweep_module.sweep
    monkeypatch.setattr(sweep_module, "sweep", _failing_sweep(0, KeyboardInterrupt()))
    assert run(capsys, "map", *GRID, "--out", out, "--restart")[0] == 130
    assert not out.exists() and not (tmp_path / "m.nc.parts").exists()
    monkeypatch.setattr(sweep_module, "sweep", real)
    code, text, err = run(capsys, "map", *GRID, "--out", out, "--no-progress", "--json")
    assert code == 0, err
    assert json.loads(text)["chunks_reused"] == 0  # computed again, not the old file


@pytest.mark.parametrize(
    "address,expect",
    [
        ("notanaddress", "is not a Dask scheduler address"),
        ("tcp://", "is not a Dask scheduler address"),
        ("host:99999", "is not a Dask scheduler address"),
        ("http://127.0.0.1:8786", "is not a Dask scheduler address"),
        ("tcp://127.0.0.1:1", "cannot reach the Dask scheduler"),
        ("127.0.0.1:1", "cannot reach the Dask scheduler at tcp://127.0.0.1:1"),
    ],
)
def test_scheduler_checked_before_any_work(capsys, tmp_path, address, expect):
    need_modules("distributed")
    code, _, err = run(capsys, "map", *GRID, "--out", tmp_path / "m.nc", "--scheduler", address)
    assert_one_line_error(code, err, "--scheduler")
    assert expect in err
    assert not list(tmp_path.iterdir())


def test_scheduler_that_is_not_dask_is_one_line(capsys, tmp_path):
    need_modules("distributed")
    import socket
    import threading

    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)

    def answer():
        while True:
            try:
                conn, _ = server.accept()
            except OSError:
                return
            conn.sendall(b"HTTP/1.0 400 Bad Request\r\n\r\n")
            conn.close()

    threading.Thread(target=answer, daemon=True).start()
    try:
        code, _, err = run(
            capsys,
            "map",
            *GRID,
            "--out",
            tmp_path / "m.nc",
            "--scheduler",
            f"tcp://127.0.0.1:{server.getsockname()[1]}",
        )
    finally:
        server.close()
    assert_one_line_error(code, err, "--scheduler: cannot connect to a Dask scheduler")
    assert not list(tmp_path.iterdir())


def test_dimensional_input_requires_what_sets_the_scales(capsys):
    code, _, err = run(
        capsys, "dissipation", "--k11", "1e6", "--P1", "300", "--Q1", "200", "--f", "0.3"
    )
    assert_one_line_error(code, err, "--P0: required with dimensional input")
    code, _, err = run(capsys, "shakedown", "--P1", "1", "--Q1", "1", "--k22", "5")
    assert_one_line_error(code, err, "--k11, --f, --P0: required")
    code, out, err = run(
        capsys,
        "dissipation",
        "--k11",
        "1e6",
        "--P1",
        "300",
        "--Q1",
        "200",
        "--f",
        "0.3",
        "--P0",
        "100",
    )
    assert code == 0, err
    assert "P1_hat = 3," in out
    assert "assumed: k22 = 1, Q0 = 0, omega = 1" in out
    code, out, _ = run(
        capsys,
        "dissipation",
        "--k11",
        "1e6",
        "--P1",
        "300",
        "--Q1",
        "200",
        "--f",
        "0.3",
        "--P0",
        "100",
        "--omega",
        "50",
        "--json",
    )
    assert json.loads(out)["assumed"] == {"k22": 1.0, "Q0": 0.0}
    code, out, _ = run(capsys, "dissipation", *CASE)
    assert "assumed" not in out  # normalized input assumes nothing


# -- B9. extras and hints --------------------------------------------------------------------------
def test_method_name_errors_are_one_line(capsys):
    for method in ("qpsolvers:nonexistent", "cvxpy:ECOS", "nope", "explicit:x", ""):
        code, _, err = run(capsys, "dissipation", *CASE, "--method", method)
        assert code == 2 and "Traceback" not in err, err
        assert len(err.strip().splitlines()) == 1, err


def test_unknown_qpsolvers_solver_lists_the_installed_ones(capsys):
    need_modules("qpsolvers")
    import qpsolvers

    code, _, err = run(capsys, "dissipation", *CASE, "--method", "qpsolvers:nonexistent")
    assert code == 2
    assert all(s in err for s in qpsolvers.available_solvers)
    assert 'pip install "lcpfric[qpsolvers]"' not in err  # it is installed


def test_missing_cvxpy_solver_names_its_package(capsys):
    need_modules("cvxpy")
    if _common.installed("ecos"):
        pytest.skip("ecos is installed")
    code, _, err = run(capsys, "dissipation", *CASE, "--method", "cvxpy:ECOS")
    assert code == 2 and "pip install ecos" in err


# -- B10. honest counts ----------------------------------------------------------------------------
def test_steps_requested_and_used_are_both_printed(capsys):
    code, out, _ = run(capsys, "dissipation", *CASE, "--method", "explicit", "--steps", "400")
    assert code == 0
    assert "steps per cycle: 400 requested, 401 used (separation instants added)" in out
    code, out, _ = run(
        capsys,
        "dissipation",
        "--P1",
        "0.5",
        "--Q1",
        "2",
        "--method",
        "projection",
        "--steps",
        "400",
    )
    assert "steps per cycle: 400;" in out  # no separation: as many as asked
    code, out, _ = run(
        capsys, "dissipation", *CASE, "--method", "explicit", "--steps", "400", "--json"
    )
    res = json.loads(out)
    assert (res["steps_requested"], res["steps_used"]) == (400, 401)


def test_exact_reports_no_time_steps(capsys):
    code, out, _ = run(capsys, "dissipation", *CASE)
    assert code == 0
    assert "closed form (no time steps); time series sampled at 2001 points" in out
    assert "steps per cycle" not in out and "cycles =" not in out
    code, out, _ = run(capsys, "dissipation", *CASE, "--steps", "100", "--json")
    res = json.loads(out)
    assert res["time_steps"] == 0 and res["samples"] == 101


# -- the bad-input tour ----------------------------------------------------------------------------
QUOTED = [  # the failing inputs of the new-user report
    (
        [
            "map",
            "--P1",
            "0:10:1000000000",
            "--Q1",
            "0:10:1000000000",
            "--phi",
            "0",
            "--out",
            "{tmp}/m.nc",
        ],
        "--P1",
    ),
    (["dissipation", *CASE, "--method", "explicit", "--steps", "1000000000000"], "--steps"),
    (["map", *GRID, "--out", "{tmp}/adir"], "--out"),
    (["map", *GRID, "--out", ""], "--out"),
    (["map", *GRID, "--out", "{tmp}/map.txt"], "--out"),
    (["figures", "--out", ""], "--out"),
    (["map", *GRID, "--out", "{tmp}/missing/m.nc"], "--out"),
    (["figures", "--out", "{tmp}/missing/figs"], "--out"),
    (["map", *GRID, "--out", "{tmp}/m.nc", "--scheduler", "notanaddress"], "--scheduler"),
    (["dissipation", "--k11", "1e6", "--P1", "300", "--Q1", "200", "--f", "0.3"], "--P0"),
    (["dissipation", *CASE, "--method", "qpsolvers:nonexistent"], "qpsolvers:nonexistent"),
    (["dissipation", *CASE, "--method", "cvxpy:ECOS"], "cvxpy:ECOS"),
]
OWN = [
    (["dissipation", "--P1", "nan", "--Q1", "2"], "--P1"),
    (["dissipation", "--P1", "inf", "--Q1", "2"], "--P1"),
    (["dissipation", "--P1", "1", "--Q1", "-inf"], "--Q1"),
    (["dissipation", "--P1", "1", "--Q1", "-2"], "--Q1"),
    (["dissipation", "--P1", "-1", "--Q1", "2"], "--P1"),
    (["dissipation", "--P1", "1", "--Q1", "2", "--phi", "0.6pie"], "--phi"),
    (["dissipation", "--P1", "1", "--Q1", "2", "--phi", "pi/0"], "--phi"),
    (["dissipation", "--P1", "1", "--Q1", "2", "--phi", "nan"], "--phi"),
    (["dissipation", "--P1", "1", "--Q1", "2", "--k11", "-3", "--f", "1", "--P0", "1"], "--k11"),
    (["dissipation", "--P1", "1", "--Q1", "2", "--k11", "0", "--f", "1", "--P0", "1"], "--k11"),
    (["dissipation", "--P1", "1", "--Q1", "2", "--k11", "1", "--f", "nan", "--P0", "1"], "--f"),
    (["dissipation", "--P1", "1", "--Q1", "2", "--P0", "0"], "--P0"),
    (["dissipation", "--P1", "1", "--Q1", "2", "--k11", "1", "--f", "1", "--P0", "-5"], "--P0"),
    (
        [
            "dissipation",
            "--P1",
            "1",
            "--Q1",
            "2",
            "--k11",
            "1",
            "--f",
            "1",
            "--P0",
            "1",
            "--omega",
            "0",
        ],
        "--omega",
    ),
    (
        [
            "dissipation",
            "--P1",
            "1",
            "--Q1",
            "2",
            "--k11",
            "1",
            "--f",
            "1",
            "--P0",
            "1",
            "--k22",
            "-1",
        ],
        "--k22",
    ),
    (
        [
            "dissipation",
            "--P1",
            "1",
            "--Q1",
            "2",
            "--k11",
            "1",
            "--f",
            "1",
            "--P0",
            "1",
            "--Q0",
            "inf",
        ],
        "--Q0",
    ),
    (["dissipation", *CASE, "--steps", "3"], "--steps"),
    (["dissipation", *CASE, "--steps", "1.5"], "--steps"),
    (["dissipation", *CASE, "--steps", "abc"], "--steps"),
    (["dissipation", *CASE, "--tol", "0"], "--tol"),
    (["dissipation", *CASE, "--tol", "nan"], "--tol"),
    (["dissipation", *CASE, "--max-cycles", "0"], "--max-cycles"),
    (["dissipation", *CASE, "--method", "nope"], "--method"),
    (["dissipation", *CASE, "--method", "explicit:x"], "--method"),
    (["dissipation", *CASE, "--placement", "diagonal"], "--placement"),
    (["dissipation", *CASE, "--max-memory", "lots"], "--max-memory"),
    (["dissipation", "--Q1", "2"], "--P1"),
    (["shakedown", "--P1", "1", "--Q1", "x"], "--Q1"),
    (["shakedown", "--P1", "1", "--Q1", "1", "--k22", "5"], "--k11"),
    (["map", "--P1", "0:2", "--Q1", "1", "--phi", "0", "--out", "{tmp}/m.nc"], "--P1"),
    (["map", "--P1", "1:0:0", "--Q1", "1", "--phi", "0", "--out", "{tmp}/m.nc"], "--P1"),
    (["map", "--P1", "-1:2:3", "--Q1", "1", "--phi", "0", "--out", "{tmp}/m.nc"], "--P1"),
    (["map", "--P1", "1", "--Q1", "", "--phi", "0", "--out", "{tmp}/m.nc"], "--Q1"),
    (["map", "--P1", "1", "--Q1", ",,", "--phi", "0", "--out", "{tmp}/m.nc"], "--Q1"),
    (["map", "--P1", "1", "--Q1", "1", "--phi", "nan", "--out", "{tmp}/m.nc"], "--phi"),
    (["map", *GRID, "--out", "{tmp}/m.nc", "--processes", "0"], "--processes"),
    (["map", *GRID, "--out", "{tmp}/m.nc", "--chunk-size", "-5"], "--chunk-size"),
    (["map", *GRID, "--out", "{tmp}/m.nc", "--steps", "100"], "--steps"),
    (["map", *GRID, "--out", "{tmp}/m.nc", "--method", "explicit", "--steps", "2"], "--steps"),
    (["map", *GRID, "--out", "{tmp}/m.nc", "--method", "nope"], "--method"),
    (["map", *GRID, "--out", "{tmp}/m.zarr"], "--out"),
    (["map", *GRID, "--out", "{tmp}/m.nc", "--scheduler", "tcp://127.0.0.1:1"], "--scheduler"),
    (["map", *GRID, "--out", "{tmp}/m.nc", "--scheduler", "host:99999"], "--scheduler"),
    (["figures", "--out", "{tmp}/afile"], "--out"),
    (["figures", "--out", "{tmp}/f", "--grid", "0"], "--grid"),
    (["figures", "--out", "{tmp}/f", "--grid", "-5"], "--grid"),
    (["figures", "--out", "{tmp}/f", "--points", "abc"], "--points"),
    (["figures", "--out", "{tmp}/f", "--format", "gif"], "--format"),
    (["figures", "--out", "{tmp}/f", "--grid", "1000000"], "--grid"),
]


@pytest.mark.parametrize(
    "argv,option", QUOTED + OWN, ids=[f"{i:02d}" for i in range(len(QUOTED) + len(OWN))]
)
def test_bad_input_tour(capsys, tmp_path, argv, option):
    if argv[0] == "map":
        need_modules("xarray", "h5netcdf", "h5py")
    if argv[0] == "figures":
        need_modules("matplotlib", "xarray")
    (tmp_path / "adir").mkdir()
    (tmp_path / "afile").write_text("x")
    before = sorted(p.name for p in tmp_path.iterdir())
    code, _, err = run(capsys, *[a.format(tmp=tmp_path) for a in argv])
    assert_one_line_error(code, err, option)
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing left behind


def test_tour_size():
    assert len(QUOTED) >= 12 and len(OWN) >= 20


# -- contact ---------------------------------------------------------------------------------------
SPHERE = ("contact", "--R", "10", "--E", "200e3", "--nu", "0", "--mu", "0.5", "--P0", "100")


def test_contact_json_against_mindlin_deresiewicz(capsys):
    from lcpfric.model.continuum import mindlin_deresiewicz_W

    code, out, err = run(
        capsys, *SPHERE, "--P1", "0", "--Q1", "25", "--nodes", "500", "--steps", "200", "--json"
    )
    assert code == 0, err
    res = json.loads(out)
    for key in (
        "W",
        "W_normalized",
        "k_t0",
        "contact_size_max",
        "nodes",
        "steps_per_cycle",
        "cycles",
        "converged",
        "seconds",
    ):
        assert key in res
    assert res["converged"] and res["nodes"] == 500 and res["steps_per_cycle"] == 200
    ref = mindlin_deresiewicz_W(100.0, 25.0, 0.5, res["k_t0"])
    assert res["W"] == pytest.approx(ref, rel=2e-3)
    assert res["W_normalized"] == pytest.approx(res["W"] * res["k_t0"] / 50.0**2)


@pytest.mark.parametrize(
    "extra, option",
    [
        (("--nu", "0.5"), "--nu"),
        (("--E", "-1"), "--E"),
        (("--P0", "0"), "--P0"),
        (("--nodes", "5"), "--nodes"),
        (("--nodes", "2.5"), "--nodes"),
        (("--P1", "150", "--Q1", "30", "--phi", "0.3pi"), "--k-support"),
        (("--k-support", "-2"), "--k-support"),
        (("--R", "nan"), "--R"),
        (("--method", "clarabel"), "--method"),
        (("--method", "newton-cg"), "--method"),
        (("--method", "nope"), "--method"),
    ],
)
def test_contact_bad_input_is_one_line(capsys, extra, option):
    args = dict(zip(SPHERE[1::2], SPHERE[2::2]))
    args.update({"--P1": "0", "--Q1": "10"})
    args.update(dict(zip(extra[0::2], extra[1::2])))
    code, _, err = run(capsys, "contact", *[x for kv in args.items() for x in kv])
    assert_one_line_error(code, err, option)


def test_contact_method_is_the_registrys(capsys):
    """--method chooses among the registry's names that solve the model (`lcpfric methods`):
    the result says which ran; a method of another model is refused naming the right one."""
    code, out, err = run(
        capsys,
        *SPHERE,
        "--P1",
        "0",
        "--Q1",
        "10",
        "--nodes",
        "50",
        "--steps",
        "40",
        "--method",
        "mdr-bar",
        "--json",
    )
    assert code == 0, err
    assert json.loads(out)["method"] == "mdr-bar"
    code, _, err = run(capsys, *SPHERE, "--P1", "0", "--Q1", "10", "--method", "active-set")
    assert_one_line_error(code, err, "--method")
    assert "mdr-bar" in err
    code, out, err = run(capsys, "methods", "--json")
    rows = {r["name"]: r for r in json.loads(out)}
    assert rows["mdr-bar"]["models"] == ["MDRSphere"]
    assert rows["newton-cg"]["dims"] == [1, 2] and "SingleNode" in rows["explicit"]["models"]
    code, out, _ = run(capsys, "methods")
    assert "halfplane-pdas" in out and "HalfPlaneCylinder" in out


def test_contact_cylinder_json_against_the_plane_closed_form(capsys):
    from lcpfric.model.continuum import cylinder_W

    code, out, err = run(
        capsys,
        *SPHERE,
        "--geometry",
        "cylinder",
        "--P1",
        "0",
        "--Q1",
        "25",
        "--nodes",
        "200",
        "--steps",
        "200",
        "--json",
    )
    assert code == 0, err
    res = json.loads(out)
    assert res["model"] == "halfplane" and "k_t0" not in res and res["converged"]
    assert res["W"] == pytest.approx(cylinder_W(100.0, 25.0, 0.5, 200e3, 0.0), rel=5e-3)
    code, _, err = run(
        capsys, *SPHERE, "--geometry", "cylinder", "--model", "mdr", "--P1", "0", "--Q1", "25"
    )
    assert_one_line_error(code, err, "--model")


# -- contact: the half-space ----------------------------------------------------------------------
def test_contact_halfspace_json_and_height_map(capsys, tmp_path):
    """--model halfspace: the contract's JSON fields plus dims, grid and the time split; a
    height map from a .npy file gives the sphere's W when it holds the sphere."""
    from lcpfric.model.continuum.halfspace import HalfSpace
    from lcpfric.model.loads import Harmonic

    base = (
        *SPHERE,
        "--model",
        "halfspace",
        "--P1",
        "50",
        "--Q1",
        "20",
        "--phi",
        "0.5pi",
        "--grid",
        "12",
        "--steps",
        "40",
        "--json",
    )
    code, out, err = run(capsys, *base)
    assert code == 0, err
    res = json.loads(out)
    for key in (
        "W",
        "W_normalized",
        "normalization",
        "k_t0",
        "contact_size_max",
        "nodes",
        "steps_per_cycle",
        "cycles",
        "converged",
        "seconds",
        "dims",
        "grid",
        "nodes_in_contact_max",
        "normal_seconds",
        "tangential_seconds",
    ):
        assert key in res, key
    assert res["model"] == "halfspace" and res["method"] == "newton-cg" and res["dims"] == 1
    m = HalfSpace.sphere(
        10.0, 200e3, 0.0, 0.5, Harmonic(100.0, 50.0), Harmonic(0.0, 20.0, 0.5 * np.pi), grid=12
    )
    assert res["W"] == pytest.approx(lcpfric.steady_state(m, steps_per_cycle=40).W, rel=1e-12)
    np.save(tmp_path / "h.npy", m.g0)
    code, out, err = run(
        capsys,
        "contact",
        "--heightmap",
        tmp_path / "h.npy",
        "--spacing",
        m.h,
        *[a for a in base[3:] if a not in ("--model", "halfspace")][:-5],  # no --R
        "--steps",
        "40",
        "--json",
    )
    assert code == 0, err
    assert json.loads(out)["W"] == pytest.approx(res["W"], rel=1e-12)


@pytest.mark.parametrize(
    "extra, option",
    [
        (("--grid", "4"), "--grid"),
        (("--grid", "900", "--steps", "4000"), "--grid"),
        (("--dims", "3"), "--dims"),
        (("--heightmap", "missing.npy", "--spacing", "1"), "--heightmap"),
        (("--geometry", "punch"), "--radius"),
        (("--radius", "1"), "--radius"),
        (("--spacing", "1"), "--spacing"),
        (("--animation", "zones.mp4"), "--animation"),
        (("--figures", "/nonexistent/dir/x"), "--figures"),
        (("--nodes", "30"), "--nodes"),
        (("--instants", "0.2,1.5"), "--instants"),
    ],
)
def test_contact_halfspace_bad_input_is_one_line(capsys, extra, option):
    args = dict(zip(SPHERE[1::2], SPHERE[2::2]))
    args.update({"--P1": "0", "--Q1": "10", "--model": "halfspace"})
    args.update(dict(zip(extra[0::2], extra[1::2])))
    code, _, err = run(capsys, "contact", *[x for kv in args.items() for x in kv])
    assert_one_line_error(code, err, option)


@pytest.mark.parametrize(
    "kind, words",
    [("npz", ".npz archive"), ("text", "not a .npy array file"), ("complex", "shape (12, 12)")],
)
def test_contact_heightmap_not_one_real_array(capsys, tmp_path, kind, words):
    """A height map file that is not one real array (a .npz archive, a text file, complex
    numbers) is refused in one line naming it, before any work."""
    h = np.zeros((12, 12))
    path = tmp_path / "h.npy"
    if kind == "npz":
        path = tmp_path / "h.npz"
        np.savez(path, h=h)
    elif kind == "text":
        path.write_text("0 1 2\n")
    else:
        np.save(path, h + 1j)
    args = dict(zip(SPHERE[1::2], SPHERE[2::2]))
    args.update(
        {"--P1": "0", "--Q1": "10", "--model": "halfspace", "--heightmap": path, "--spacing": "1"}
    )
    args.pop("--R", None)
    code, _, err = run(capsys, "contact", *[x for kv in args.items() for x in kv])
    assert_one_line_error(code, err, "--heightmap")
    assert words in err


def test_contact_unresolved_slip_warns_in_one_line(capsys):
    """Q1 = 1e-3 μP0 on grid 16: no element slips (W = 0); the run succeeds and says in one
    line on stderr that the grid does not resolve the slip zone."""
    code, out, err = run(
        capsys,
        *SPHERE,
        "--P1",
        "0",
        "--Q1",
        "0.05",
        "--model",
        "halfspace",
        "--grid",
        "16",
        "--steps",
        "40",
    )
    assert code == 0 and "W = 0 per cycle" in out
    lines = err.strip().splitlines()
    assert (
        len(lines) == 1
        and lines[0].startswith("lcpfric contact: warning: ")
        and ("no element slipped" in lines[0])
    ), err


def test_map_contact_halfspace_resumes(capsys, tmp_path):
    """lcpfric map --contact sphere --contact-model halfspace: through sweep, resumable, equal
    to the model's own solve."""
    need_modules("xarray", "h5netcdf", "h5py")
    from lcpfric.model.continuum.halfspace import HalfSpace
    from lcpfric.model.loads import Harmonic

    out = tmp_path / "hs.nc"
    args = (
        "map",
        "--contact",
        "sphere",
        "--contact-model",
        "halfspace",
        "--grid",
        "10",
        "--P1",
        "0:0.5:2",
        "--Q1",
        "0.2:0.4:2",
        "--phi",
        "0:pi/2:2",
        "--steps",
        "40",
        "--out",
        out,
        "--no-progress",
    )
    code, _, err = run(capsys, *args)
    assert code == 0, err
    code, text, err = run(capsys, *args)
    assert code == 0 and "1 of 1 chunks reused" in text, text + err
    import xarray as xr

    with xr.open_dataset(out) as ds:
        got = float(ds.W_normalized.sel(phi=np.pi / 2, P1=0.5, Q1=0.4))
        assert ds.attrs["model"] == "halfspace" and ds.attrs["grid"] == 10
    m = HalfSpace.sphere(
        1.0, 1.0, 0.0, 1.0, Harmonic(1.0, 0.5, 0.0), Harmonic(0.0, 0.4, np.pi / 2), grid=10
    )
    assert got == pytest.approx(
        lcpfric.steady_state(m, steps_per_cycle=40, tol=1e-8).W_normalized, rel=1e-12
    )
