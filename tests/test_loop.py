"""The hysteresis loop: its enclosed area is W (closed form and time steppers), per node for a
system, from the API and from `lcpfric loop`."""

import json

import numpy as np
import pytest

from lcpfric import InputError, SingleNode, steady_state
from lcpfric.analysis.loop import hysteresis_loop, loop_area
from lcpfric.cli import main
from lcpfric.model import chain

from support import need_modules, CASES


@pytest.mark.parametrize("case", ["separation", "contact-phase", "large"])
def test_area_of_the_exact_loop_is_W(case):
    node = SingleNode(
        k11=3e4,
        f=0.35,
        P0=120.0,
        P1=120.0 * CASES[case][0],
        Q1=0.35 * 120.0 * CASES[case][1],
        phi=CASES[case][2],
        omega=7.0,
    )
    errors = []
    for samples in (1000, 4000):
        r = steady_state(node, "exact", samples)
        loop = hysteresis_loop(r)
        errors.append(abs(loop.area - r.W) / r.W)
    assert errors[0] < 1e-4 and errors[1] < 1e-5
    assert errors[1] < errors[0] / 8  # the sampled trapezoid converges at second order


def test_area_of_a_time_stepper_loop_is_W():
    """The projection's W is the trapezoidal sum over the grid: the polygon's area exactly. The
    explicit stepper's W integrates exactly between its events inside the increments, which the
    polygon through the grid points cuts: they agree to second order."""
    node = SingleNode.normalized(*CASES["separation"])
    r = steady_state(node, "projection", 800)
    assert hysteresis_loop(r).area == pytest.approx(r.W, rel=1e-12)
    gaps = []
    for steps in (800, 3200):
        r = steady_state(node, "explicit", steps)
        gaps.append(abs(hysteresis_loop(r).area - r.W) / r.W)
    assert gaps[0] < 1e-4 and gaps[1] < gaps[0] / 8


def test_loops_of_a_system_add_up_to_W():
    system = chain(4, k_coupling=0.7, P1=1.4, Q1=2.0, phi=1.0, normal_phase=[0, 0.4, 0.8, 1.2])
    r = steady_state(system, "explicit", 400)
    areas = [hysteresis_loop(r, node=i).area for i in range(4)]
    assert sum(areas) == pytest.approx(r.W, rel=1e-4)  # explicit: to second order (see above)
    with pytest.raises(InputError, match="node"):
        hysteresis_loop(r, node=4)
    assert loop_area([0.0, 1.0, 1.0, 0.0, 0.0], [-1.0, -1.0, 1.0, 1.0, -1.0]) == 2.0


def test_loop_command(tmp_path, capsys):
    need_modules("matplotlib")
    out = tmp_path / "loop.pdf"
    assert (
        main(["loop", "--P1", "1.5", "--Q1", "2", "--phi", "0.6pi", "--out", str(out), "--json"])
        == 0
    )
    res = json.loads(capsys.readouterr().out)
    assert res["area"] == pytest.approx(res["W"], rel=1e-5) and out.stat().st_size > 0
    assert b"/Type3" not in out.read_bytes()  # TrueType fonts, like every figure
    assert set(res["shares"]) == {"stick", "forward slip", "backward slip", "separation"}
    assert main(["loop", "--P1", "1.5", "--Q1", "2", "--out", str(tmp_path / "x.txt")]) == 2
    assert "--out" in capsys.readouterr().err
    assert (
        main(
            [
                "loop",
                "--P1",
                "1.5",
                "--Q1",
                "2",
                "--phi",
                "-0.5pi",
                "--method",
                "projection",
                "--steps",
                "400",
            ]
        )
        == 0
    )
    assert "enclosed area" in capsys.readouterr().out
    assert not np.isnan(res["W_hat"])
