"""What a journal reviewer found in the figures, kept fixed (issue 35, item 16), on small inputs:
the phase figure's log axis and discrete legend of the best phases, the zone map's forward slip
in a colour of its own and drawn over the contact edge, Cattaneo's lines over the models'
markers and a title naming the contact, the backend comparison's 7 pt titles, equal panels,
attached legend naming the target line and the zero errors; the half-space caption giving the
grid asked for (item 13); the progress lines of the long figure runs (item 14)."""

import colorsys
import json
import math
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from support import need_modules, renderer, texts

need_modules("matplotlib")

from lcpfric.figures.style import MIN_FONT_SIZE  # noqa: E402

PI = math.pi
ROOT = Path(__file__).resolve().parents[1]


def _lightness(colour) -> float:
    from matplotlib.colors import to_rgb

    return colorsys.rgb_to_hls(*to_rgb(colour))[1]


def _distinct(a, b) -> bool:
    """Distinct in colour and in greyscale (lightness)."""
    from matplotlib.colors import to_rgb

    return np.abs(np.subtract(to_rgb(a), to_rgb(b))).sum() > 0.5 and (
        abs(_lightness(a) - _lightness(b)) > 0.15
    )


def _hue_gap(a, b) -> float:
    """The angle between two colours' hues [degrees]."""
    from matplotlib.colors import to_rgb

    gap = abs(colorsys.rgb_to_hls(*to_rgb(a))[0] - colorsys.rgb_to_hls(*to_rgb(b))[0]) * 360.0
    return min(gap, 360.0 - gap)


def _legend_labels(fig) -> list[str]:
    legends = [*fig.legends, *(ax.get_legend() for ax in fig.axes)]
    return [t.get_text() for lg in legends if lg is not None for t in lg.get_texts()]


def _phase_map():
    """A map whose largest W is at φ = 0.5π on one side of a line and 0.6π on the other."""
    need_modules("xarray")
    import xarray as xr

    phi = np.linspace(0, PI, 11)
    P1 = Q1 = np.linspace(0, 2, 6)
    p, q = np.meshgrid(P1, Q1, indexing="ij")
    best = np.where(q > 0.7 * p, 0.6 * PI, 0.5 * PI)
    W = (1.0 + p + q)[None] * np.exp(-((phi[:, None, None] - best[None]) ** 2))
    ds = xr.Dataset({"W_normalized": (("phi", "P1", "Q1"), W)}, coords=dict(phi=phi, P1=P1, Q1=Q1))
    curves = np.array([k * np.sin(np.linspace(0, PI, 21)) ** 2 for k in (0.005, 0.02, 0.07, 0.3)])
    return np.linspace(0, PI, 21), curves, ds


def test_phase_log_axis_and_discrete_phases():
    from lcpfric.figures.contact import PHASE_CASES, figure_phase

    phi, curves, ds = _phase_map()
    fig = figure_phase(phi, curves, PHASE_CASES, ds)
    a, b = fig.axes[:2]
    assert len(fig.axes) == 2  # no colour bar: the phases are named in a legend
    assert a.get_yscale() == "log"  # the lowest curve is not flat at 0
    low, high = a.get_ylim()
    assert low < curves[0].max() / 10 and high >= curves.max()
    labels = _legend_labels(fig)
    assert any("0.5π" in t for t in labels) and any("0.6π" in t for t in labels)
    assert any("independent of φ" in t for t in labels)
    patches = [h for lg in fig.legends for h in lg.legend_handles if "max" in h.get_label()]
    faces = [p.get_facecolor() for p in patches]
    assert len(faces) == 2 and _distinct(*faces)


def _zones_result():
    from lcpfric.results import State

    n, steps = 20, 30
    state = np.full((steps + 1, n), int(State.STICK))
    state[:, 15:] = int(State.SEPARATION)
    state[5:10, 14] = int(State.FORWARD)
    state[12:20, 10:14] = int(State.BACKWARD)
    contact = SimpleNamespace(
        x=np.linspace(0, 1.9, n), contact_size_max=1.5, size=np.full(steps + 1, 1.45)
    )
    return SimpleNamespace(state=state, t=np.linspace(0, 1, steps + 1), contact=contact)


def test_zones_forward_slip_visible():
    from lcpfric.figures.contact import ZONE_COLOURS, figure_zones
    from lcpfric.figures.halfspace_panels import ZONE_COLOURS as HALFSPACE

    colours = list(ZONE_COLOURS.values())
    assert tuple(colours) == tuple(HALFSPACE)  # the same states, the same colours
    forward = ZONE_COLOURS["slip, forward"]
    for name, other in ZONE_COLOURS.items():
        if name != "slip, forward":
            assert _distinct(forward, other), name
    # not a shade of backward slip's hue (two oranges were told apart by lightness alone)
    assert _hue_gap(forward, ZONE_COLOURS["slip, backward"]) > 45.0
    fig = figure_zones(_zones_result(), "zones")
    ax = fig.axes[0]
    edge = max(line.get_zorder() for line in ax.get_lines())
    over = [m for m in ax.collections if np.ma.count(m.get_array()) < m.get_array().size]
    assert over and over[0].get_zorder() > edge  # forward slip drawn over the edge line
    labels = _legend_labels(fig)
    assert any(t.startswith("slip, forward (") and "%" in t for t in labels)


@pytest.fixture(scope="module")
def tractions():
    import lcpfric
    from lcpfric.figures.contact import figure_tractions
    from lcpfric.model import Harmonic
    from lcpfric.model.continuum import HalfPlaneCylinder, MDRSphere

    run = dict(steps_per_cycle=40, max_cycles=1, on_nonconvergence="ignore")
    out = {}
    for name, model in (
        ("cylinder", HalfPlaneCylinder(1.0, 1.0, 0.0, 1.0, 1.0, Harmonic(0.0, 0.95), nodes=40)),
        ("sphere", MDRSphere(1.0, 1.0, 0.0, 1.0, 1.0, Harmonic(0.0, 0.95), nodes=200)),
    ):
        out[name] = figure_tractions(lcpfric.steady_state(model, **run), model)
    return out


@pytest.mark.parametrize("name", ["cylinder", "sphere"])
def test_tractions_closed_form_on_top_and_titled(tractions, name):
    fig = tractions[name]
    ax = fig.axes[0]
    assert name in ax.get_title()
    lines = [ln for ln in ax.get_lines() if len(ln.get_xdata())]
    closed = [ln for ln in lines if ln.get_marker() in ("None", "", None)]
    marked = [ln for ln in lines if ln.get_marker() not in ("None", "", None)]
    assert len(closed) == len(marked) == 3
    assert min(ln.get_zorder() for ln in closed) > max(ln.get_zorder() for ln in marked)
    for ln in marked:  # hollow markers, sparse enough to see the line through them
        assert ln.get_markerfacecolor() == "none"
        every = ln.get_markevery()
        step = every[1] if isinstance(every, tuple) else 1
        assert len(ln.get_xdata()) / step <= 60
    assert "Cattaneo (closed form)" in _legend_labels(fig)


def test_figure_text_at_least_7pt(tractions):
    from lcpfric.figures.contact import PHASE_CASES, figure_phase, figure_zones

    phi, curves, ds = _phase_map()
    for fig in (
        *tractions.values(),
        figure_phase(phi, curves, PHASE_CASES, ds),
        figure_zones(_zones_result(), "zones"),
    ):
        renderer(fig)
        assert min(t.get_fontsize() for t in texts(fig)) >= MIN_FONT_SIZE


#: run in a separate interpreter: the benchmark script is not imported by the tests
COMPARE = r"""
import json, runpy, sys
mod = runpy.run_path(sys.argv[1])
Case = mod["Case"]
cases = (Case("contact", 0.5, 2.0, 0.0), Case("separation", 1.5, 2.0, 1.885),
         Case("multi-node", nodes=((0.5, 2.0, 0.0), (1.5, 2.0, 1.885))))
rows = []
for c in cases:
    rows.append(dict(case=c.name, method="exact", steps_per_cycle=0, rel_error=0.0, seconds=1e-5))
    for n, e in ((50, 1e-3), (200, 1e-5), (1000, 0.0)):
        rows.append(dict(case=c.name, method="explicit", steps_per_cycle=n, rel_error=e,
                         seconds=n * 1e-5))
fig = mod["figure_compare"](rows, cases, ["exact", "explicit"], {"exact"})
from matplotlib.backends.backend_agg import FigureCanvasAgg
FigureCanvasAgg(fig).draw()
panels = [ax for ax in fig.axes if ax.axison]
legends = [lg for lg in [*fig.legends, *(ax.get_legend() for ax in fig.axes)] if lg]
box = legends[0].get_window_extent()
print(json.dumps(dict(
    size=list(fig.get_size_inches()),
    titles=[min(t.get_fontsize() for t in ax.texts + [ax.title]) for ax in panels],
    widths=[ax.get_position().width for ax in panels],
    labels=[t.get_text() for lg in legends for t in lg.get_texts()],
    legend=[box.x0, box.y0, box.x1, box.y1],
    figure=[fig.bbox.x1, fig.bbox.y1],
    floor=[min(ax.get_ylim()) for ax in panels],
)))
"""


def test_compare_figure():
    script = ROOT / "benchmarks" / "perf" / "comparison.py"
    run = subprocess.run(
        [sys.executable, "-c", COMPARE, str(script)], capture_output=True, text=True, timeout=120
    )
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["size"][0] <= 7.2 + 1e-9  # printed at page width, so the fonts are as set
    assert len(out["titles"]) == 3 and min(out["titles"]) >= MIN_FONT_SIZE
    assert max(out["widths"]) - min(out["widths"]) < 1e-3  # every case gets the same width
    labels = out["labels"]
    assert any("1e-6" in t for t in labels)  # the dashed line is named
    assert any(t.startswith("error 0 (exact to round-off), drawn at") for t in labels)
    assert {"exact", "explicit"} <= set(labels)
    x0, y0, x1, y1 = out["legend"]
    assert 0 <= x0 and x1 <= out["figure"][0] and 0 <= y0 and y1 <= out["figure"][1]
    assert max(out["floor"]) < 1e-17  # the zeros' floor is inside the axes


def test_halfspace_caption_gives_the_grid_asked_for():
    from lcpfric.figures.halfspace_panels import caption
    from lcpfric.model.continuum.halfspace import HalfSpace
    from lcpfric.model.loads import Harmonic

    model = HalfSpace.sphere(1.0, 1.0, 0.3, 0.5, Harmonic(1.0, 0.5), 0.1, grid=10)
    assert model.N != 10
    text = caption(model)
    assert "10 elements across the largest contact" in text
    assert f"({model.N} x {model.N} in all)" in text
    surface = HalfSpace(1.0, 0.3, 0.5, 1.0, 0.1, heights=model.g0, spacing=model.h)
    assert f"{surface.N} x {surface.N} elements" in caption(surface)


def test_animation_reports_its_frames(tmp_path):
    import lcpfric
    from lcpfric.figures.halfspace import animate_zones
    from lcpfric.model.continuum.halfspace import HalfSpace
    from lcpfric.model.loads import Harmonic

    model = HalfSpace.sphere(1.0, 1.0, 0.3, 0.5, Harmonic(1.0, 0.5), Harmonic(0.0, 0.2), grid=12)
    result = lcpfric.steady_state(model, steps_per_cycle=20)
    lines = []
    animate_zones(model, result, tmp_path / "z.gif", frames=5, progress=lines.append)
    assert len(lines) == 5 and lines[-1].endswith("frame 5 of 5 (100 %)")


@pytest.mark.slow
def test_contact_figures_report_each_stage(tmp_path):
    need_modules("xarray")
    from lcpfric.figures.contact import write_contact_figures

    lines = []
    write_contact_figures(
        tmp_path, grid=3, formats=("png",), nodes=20, steps=40, progress=lines.append
    )
    text = "\n".join(lines)
    for stage in ("Hertz maps", "started", "W against the phase", "zones", "tractions"):
        assert stage in text
    assert all(line.endswith(" s)") for line in lines)
