"""Issue 35, what a new user hits (round two): each item's behaviour, beyond the one-line error
that tests/test_cli_bad_input_table.py checks for every option."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from support import needs

from lcpfric.cli import main
from lcpfric.errors import InputError

SPHERE = ("--R", "10", "--E", "200e3", "--nu", "0.3", "--mu", "0.5", "--P0", "100")


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def one_line(code, err, option, expected=2):
    assert code == expected, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert option in lines[0], err
    return lines[0]


# -- 12: the version on stdout ---------------------------------------------------------------------
def test_version_is_printed_on_stdout():
    p = subprocess.run(
        [sys.executable, "-m", "lcpfric", "--version"], capture_output=True, text=True, timeout=60
    )
    assert p.returncode == 0 and p.stdout.startswith("lcpfric ") and p.stderr == ""


# -- 3: one meaning of the support stiffness -------------------------------------------------------
def test_contact_prints_k_t0_and_its_support_is_absolute(capsys):
    base = ("contact", *SPHERE, "--P1", "50", "--Q1", "20", "--phi", "0.5pi", "--nodes", "100")
    code, out, _ = run(capsys, *base, "--steps", "100", "--json")
    k_t0 = json.loads(out)["k_t0"]
    code, out, err = run(capsys, *base, "--steps", "100")
    assert code == 0 and f"k_t0 = {k_t0:.6g}" in out, err
    # --k-support k_t0 in contact is --k-support-ratio 1 in map: the same W k_t0/(mu^2 P0^2)
    code, out, err = run(capsys, *base, "--steps", "100", "--k-support", k_t0, "--json")
    W = json.loads(out)["W_normalized"]
    from lcpfric.analysis.contact_maps import mdr_W_normalized

    ratio = mdr_W_normalized(
        [0.5], [0.4], [np.pi / 2], nodes=100, steps_per_cycle=100, k_support_ratio=1.0
    )[0]
    assert W == pytest.approx(ratio, rel=1e-9)


def test_map_support_is_named_as_a_ratio(capsys, tmp_path):
    argv = ("map", "--P1", "0.5", "--Q1", "0.4", "--phi", "0", "--out", tmp_path / "m.nc")
    line = one_line(*run(capsys, *argv, "--contact", "sphere", "--k-support", "1")[::2], "--k-")
    assert "--k-support-ratio" in line and "absolute" in line
    with pytest.raises(InputError, match="k_support_ratio"):
        from lcpfric.analysis.contact_maps import map_spec

        map_spec({"k_support": 1.0}, None)


# -- 13: the grid asked for ------------------------------------------------------------------------
def test_halfspace_json_reports_the_grid_asked_for(capsys):
    code, out, err = run(
        capsys, "contact", "--model", "halfspace", *SPHERE, "--P1", "50", "--Q1", "20",
        "--grid", "20", "--steps", "40", "--json",
    )  # fmt: skip
    r = json.loads(out)
    assert code == 0 and r["grid"] == 20 and r["grid_side"] == 24 and r["nodes"] == 24 * 24


# -- 6: an existing output is not overwritten ------------------------------------------------------
@needs("xarray", "h5netcdf")
def test_map_refuses_an_output_of_another_map_or_a_foreign_file(capsys, tmp_path):
    out = tmp_path / "m.nc"
    grid = ("--phi", "0", "--P1", "0.5", "--out", out)
    assert run(capsys, "map", "--Q1", "0.3", *grid)[0] == 0
    before = out.read_bytes()
    assert run(capsys, "map", "--Q1", "0.3", *grid)[0] == 0  # the same map: reused
    line = one_line(*run(capsys, "map", "--Q1", "0.4", *grid)[::2], "--out")
    assert "other parameters" in line and "--restart" in line and out.read_bytes() == before
    assert run(capsys, "map", "--Q1", "0.4", *grid, "--restart")[0] == 0
    foreign = tmp_path / "x.nc"
    foreign.write_text("not a map")
    line = one_line(*run(capsys, "map", "--Q1", "0.3", *grid[:-1], foreign)[::2], "--out")
    assert "no lcpfric map" in line and foreign.read_text() == "not a map"


@needs("xarray", "h5netcdf")
def test_duplicate_coordinates_are_refused(capsys, tmp_path):
    out = tmp_path / "m.nc"
    one_line(
        *run(capsys, "map", "--P1", "1,1,2", "--Q1", "1", "--phi", "0", "--out", out)[::2], "--P1"
    )
    one_line(
        *run(capsys, "map", "--P1", "1", "--Q1", "1:1:3", "--phi", "0", "--out", out)[::2], "--Q1"
    )
    from lcpfric.analysis.sweep import sweep

    with pytest.raises(InputError, match="phi: the value 0 is given more than once"):
        sweep([1.0], [1.0], [0.0, 0.0], progress=False)
    assert not out.exists()


def test_bench_refuses_to_overwrite_an_earlier_run(tmp_path):
    (tmp_path / "compare.csv").write_text("earlier")
    p = subprocess.run(
        [sys.executable, "benchmarks/perf/compare_backends.py", "--quick", "--out", tmp_path],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert p.returncode == 2 and "--overwrite" in p.stderr and "Traceback" not in p.stderr
    assert (tmp_path / "compare.csv").read_text() == "earlier"


# -- 7: masked height maps -------------------------------------------------------------------------
def test_masked_height_map_is_refused():
    from lcpfric import HalfSpace

    x = np.linspace(-1, 1, 24)
    h = np.add.outer(x**2, x**2)
    masked = np.ma.masked_greater(h, 1.5)
    with pytest.raises(InputError, match=r"heights: a masked array \(\d+ points masked\)"):
        HalfSpace(1.0, 0.0, 0.5, 1.0, 0.1, heights=masked, spacing=0.1)


# -- 9: paths the checks let through but the system refuses ----------------------------------------
@pytest.mark.parametrize(
    "argv, option",
    [
        pytest.param(
            ("loop", "--P1", "1", "--Q1", "1", "--out", "/proc/loop.pdf"),
            "--out",
            marks=needs("matplotlib"),
        ),
        pytest.param(
            ("map", "--P1", "1", "--Q1", "1", "--phi", "0", "--out", "/proc/m.nc"),
            "--out",
            marks=needs("xarray", "h5netcdf"),
        ),
        pytest.param(
            ("figures", "--out", "/proc/figs"), "--out", marks=needs("matplotlib", "xarray")
        ),
        (
            (
                "contact",
                "--model",
                "halfspace",
                *SPHERE,
                "--P1",
                "1",
                "--Q1",
                "1",
                "--figures",
                "/proc/lcpf",
            ),
            "--figures",
        ),  # fmt: skip
        (
            (
                "contact",
                "--model",
                "halfspace",
                *SPHERE,
                "--P1",
                "1",
                "--Q1",
                "1",
                "--animation",
                "/proc/z.gif",
            ),
            "--animation",
        ),  # fmt: skip
    ],
    ids=["loop", "map", "figures", "contact-figures", "contact-animation"],
)
def test_unusable_output_is_refused_before_any_work(capsys, argv, option):
    if not __import__("os").path.isdir("/proc/self"):
        pytest.skip("needs /proc")
    line = one_line(*run(capsys, *argv)[::2], option)
    assert "cannot create" in line


def test_an_oserror_during_the_run_names_the_option(capsys, tmp_path, monkeypatch):
    """A file the system refuses only while writing: one line naming the option, exit 2."""
    from lcpfric.cli import loop as loop_cli

    out = tmp_path / "loop.png"

    def refuse(*args, **kwargs):
        raise OSError(28, "No space left on device", str(out))

    monkeypatch.setattr(loop_cli, "run", refuse)
    line = one_line(*run(capsys, "loop", "--P1", "1", "--Q1", "1", "--out", out)[::2], "--out")
    assert "No space left on device" in line


# -- 10: messages name the option and the real minimum ---------------------------------------------
def test_counts_are_parsed_alike_with_their_real_minimums(capsys):
    code, out, err = run(capsys, "dissipation", "--P1", "1", "--Q1", "1", "--method",
                         "explicit", "--steps", "4e2", "--json")  # fmt: skip
    assert code == 0 and json.loads(out)["steps_requested"] == 400, err
    base = ("contact", *SPHERE, "--P1", "1", "--Q1", "1")
    assert "whole number >= 4" in one_line(*run(capsys, *base, "--steps", "1")[::2], "--steps")
    assert "whole number >= 10" in one_line(*run(capsys, *base, "--nodes", "5")[::2], "--nodes")
    hs = (*base, "--model", "halfspace")
    assert "whole number >= 8" in one_line(*run(capsys, *hs, "--grid", "0")[::2], "--grid")


def test_height_map_messages_name_the_option_and_no_infinite_range(capsys, tmp_path):
    h = np.zeros((12, 12))
    h[3, 4] = np.nan
    np.save(tmp_path / "h.npy", h)
    line = one_line(
        *run(capsys, "contact", "--heightmap", tmp_path / "h.npy", "--spacing", "1",
             "--E", "1", "--nu", "0", "--mu", "0.5", "--P0", "1", "--P1", "0", "--Q1", "0.1")[::2],
        "--heightmap",
    )  # fmt: skip
    assert "index (3, 4)" in line and "inf)" not in line


@needs("xarray", "h5netcdf")
def test_memory_guard_names_options_that_exist(capsys, tmp_path):
    base = ("contact", *SPHERE, "--P1", "1", "--Q1", "1")
    line = one_line(*run(capsys, *base, "--steps", "1e12")[::2], "--steps")
    assert "--max-memory" in line  # contact has it now
    line = one_line(
        *run(capsys, "map", "--contact", "sphere", "--P1", "0.5", "--Q1", "0.3", "--phi", "0",
             "--steps", "1e8", "--max-memory", "1G", "--out", tmp_path / "m.nc")[::2],
        "--steps",
    )  # fmt: skip
    assert "--max-memory" in line and not (tmp_path / "m.nc").exists()


# -- 4, 8: options that do not apply -------------------------------------------------------------
@pytest.mark.parametrize(
    "extra, option",
    [
        (("--nu", "0.7"), "--nu"),
        (("--contact", "sphere", "--nu", "0.2"), "--nu"),
        (("--contact", "sphere", "--contact-model", "halfspace", "--nodes", "40"), "--nodes"),
        (("--grid", "40"), "--grid"),
        (("--nodes", "40"), "--nodes"),
        (("--contact-model", "halfspace"), "--contact-model"),
        (("--k-support-ratio", "1"), "--k-support-ratio"),
    ],
)
def test_map_options_that_do_not_apply_are_refused(capsys, tmp_path, extra, option):
    argv = ("map", "--P1", "0.5", "--Q1", "0.3", "--phi", "0", "--out", tmp_path / "m.nc")
    one_line(*run(capsys, *argv, *extra)[::2], option)


def test_instants_without_figures_and_exact_only_options(capsys):
    base = ("contact", "--model", "halfspace", *SPHERE, "--P1", "1", "--Q1", "1")
    assert "--figures" in one_line(*run(capsys, *base, "--instants", "0.3")[::2], "--instants")
    for option, value in (("--tol", "1e-6"), ("--max-cycles", "5"), ("--placement", "uniform")):
        line = one_line(
            *run(capsys, "dissipation", "--P1", "1", "--Q1", "1", option, value)[::2], option
        )
        assert "closed form" in line
