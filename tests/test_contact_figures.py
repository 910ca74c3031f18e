"""The contact figures: written by ``lcpfric figures --contact``, page or column wide, no text
below 7 pt, TrueType fonts in the PDFs, every mark in a legend."""

import json

import numpy as np
import lcpfric
import pytest

from support import need_modules, renderer as _renderer, texts as _texts

need_modules("matplotlib")
need_modules("xarray")

from lcpfric.cli import main  # noqa: E402
from lcpfric.figures.style import COLUMN_WIDTH, MIN_FONT_SIZE, PAGE_WIDTH  # noqa: E402


NAMES = ("hertz-maps", "hertz-phase", "hertz-zones", "cylinder-tractions", "sphere-tractions")
COLUMN = ("hertz-zones", "cylinder-tractions", "sphere-tractions")


@pytest.fixture(scope="module")
def built():
    from lcpfric.analysis.sweep import sweep
    from lcpfric.figures import contact as cf
    from lcpfric.model.continuum import HalfPlaneCylinder, MDRSphere
    from lcpfric.model import Harmonic

    axis = np.linspace(0, 2, 5)
    ds = sweep(
        axis,
        axis,
        list(cf.MAP_PHASES),
        contact={"k_support_ratio": 1.0, "nodes": 30},
        steps_per_cycle=40,
        progress=False,
    )
    phi, curves = cf.phase_data(points=9, nodes=30, steps_per_cycle=40)
    sphere = MDRSphere(
        1.0, 1.0, 0.0, 1.0, Harmonic(1.0, 1.5), Harmonic(0.0, 0.6, 1.0), nodes=30, k_support=1.0
    )
    plane = HalfPlaneCylinder(1.0, 1.0, 0.0, 1.0, 1.0, Harmonic(0.0, 0.95), nodes=40)
    first = lcpfric.steady_state(
        plane, steps_per_cycle=80, max_cycles=1, on_nonconvergence="ignore"
    )
    ball = MDRSphere(1.0, 1.0, 0.0, 1.0, 1.0, Harmonic(0.0, 0.95), nodes=60)
    ball_first = lcpfric.steady_state(
        ball, steps_per_cycle=80, max_cycles=1, on_nonconvergence="ignore"
    )
    return {
        "hertz-maps": cf.figure_hertz_maps(ds),
        "sphere-tractions": cf.figure_tractions(ball_first, ball),
        "hertz-phase": cf.figure_phase(phi, curves, cf.PHASE_CASES, ds),
        "hertz-zones": cf.figure_zones(lcpfric.steady_state(sphere, steps_per_cycle=60), "zones"),
        "cylinder-tractions": cf.figure_tractions(first, plane),
    }


@pytest.mark.slow
def test_sizes_fonts_and_legends(built):
    for name, fig in built.items():
        width, height = fig.get_size_inches()
        assert width <= (COLUMN_WIDTH if name in COLUMN else PAGE_WIDTH) + 1e-9, name
        assert height <= 9.0
        _renderer(fig)
        assert min(t.get_fontsize() for t in _texts(fig)) >= MIN_FONT_SIZE, name
        legends = [*fig.legends, *(ax.get_legend() for ax in fig.axes)]
        assert any(lg is not None for lg in legends), f"{name} has no legend"


@pytest.mark.slow
def test_figures_command_writes_truetype_pdfs(tmp_path, capsys):
    out = tmp_path / "contact"
    code = main(
        ["figures", "--contact", "--out", str(out), "--grid", "3", "--format", "png,pdf", "--json"]
    )
    captured = capsys.readouterr()
    assert code == 0, captured.err
    files = json.loads(captured.out)["files"]
    assert {p.rsplit("/", 1)[-1] for p in files} == {
        f"{n}.{e}" for n in NAMES for e in ("png", "pdf")
    }
    for name in NAMES:
        pdf = (out / f"{name}.pdf").read_bytes()
        assert b"/Type3" not in pdf and (b"/CIDFontType2" in pdf or b"/TrueType" in pdf)
