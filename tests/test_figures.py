"""Figures: written from a fresh `lcpfric figures`, built from computed data, boundary drawn,
and fit for print (size, fonts, resolution, greyscale, every mark explained)."""

import json
import math
import os
import pickle
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from support import need_modules, renderer as _renderer, texts as _texts

need_modules("matplotlib")
need_modules("xarray")

from lcpfric.paper import figures  # noqa: E402
from lcpfric._optional import MissingExtra  # noqa: E402
from lcpfric.errors import InputError  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
NAMES = (
    "fig3_map_phi0",
    "fig4_maps",
    "fig5_phase_P1_0.5",
    "fig6_phase_P1_Q1_5",
    "fig7_phase_P1_1.5",
    "fig9_motor",
)


@pytest.mark.slow
def test_figures_command_fresh_process(tmp_path):
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])
    )
    out = tmp_path / "figs"
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "lcpfric",
            "figures",
            "--out",
            str(out),
            "--grid",
            "21",
            "--points",
            "41",
            "--format",
            "png,pdf",
            "--json",
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert run.returncode == 0, run.stderr
    files = {Path(p).name for p in json.loads(run.stdout)["files"]}
    assert files == {f"{n}.{ext}" for n in NAMES for ext in ("png", "pdf")}
    for name in NAMES:
        assert (out / f"{name}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert (out / f"{name}.pdf").read_bytes()[:5] == b"%PDF-"


@pytest.fixture(scope="module")
def maps():
    return figures.map_data(grid=11)


def _red_lines(ax):
    red = np.array([0xE8, 0x40, 0x2A, 0xFF]) / 255
    found = []
    for coll in ax.collections:
        colors = np.atleast_2d(coll.get_edgecolor())
        if colors.size and np.allclose(colors[0], red, atol=1e-3):
            found.append(coll)
    return found


def test_maps_have_boundary_line_and_colorbar(maps):
    fig = figures.figure_maps(maps, figures.FIG4_PHASES, ncols=5)
    panels = [ax for ax in fig.axes if ax.get_title().startswith("φ")]
    assert len(panels) == 10
    assert [ax.get_title() for ax in panels][-1] == "φ = π"
    assert any(ax.get_label() == "<colorbar>" for ax in fig.axes)
    for ax in panels:
        assert _red_lines(ax), f"no shakedown boundary on {ax.get_title()}"
        assert any(line.get_xdata()[0] == 1.0 for line in ax.lines)  # the line P̂1 = 1
    single = figures.figure_maps(maps, [0.0])
    assert single.axes[0].get_xlabel() == r"$\hat P_1$"
    assert single.legends  # below the map, off the data


def test_boundary_follows_shakedown_region(maps):
    # At φ = π/2 the shakedown region is the unit disc P̂1² + Q̂1² <= 1.
    fig = figures.figure_maps(maps, [math.pi / 2])
    (coll,) = _red_lines(fig.axes[0])
    xy = np.concatenate([p.vertices for p in coll.get_paths()])
    np.testing.assert_allclose(np.hypot(xy[:, 0], xy[:, 1]), 1.0, atol=1e-3)


def test_phase_figure_marks_the_maximum():
    fig = figures.figure_phase(5.0, (5.0,), points=41)
    ax = fig.axes[0]
    marker = [line for line in ax.lines if line.get_marker() == "o"]
    assert len(marker) == 1
    assert marker[0].get_xdata()[0] == pytest.approx(0.6016, abs=1e-3)


def test_motor_figure_curves_start_at_zero():
    fig = figures.figure_motor(points=50)
    ax = fig.axes[0]
    curves = [line for line in ax.lines if line.get_label().startswith("f = ")]
    assert len(curves) == len(figures.MOTOR_FRICTION)
    for line in curves:
        y = line.get_ydata()
        assert y[0] == 0.0 and y[-1] > 0 and np.all(np.diff(y) >= -1e-12)


def test_bad_inputs(tmp_path):
    with pytest.raises(InputError):
        figures.write_figures(tmp_path, formats=("gif",))
    with pytest.raises(InputError):
        figures.map_data(grid=1)
    (tmp_path / "file").write_text("")
    with pytest.raises(InputError):
        figures.write_figures(tmp_path / "file", grid=5)


def test_missing_matplotlib_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(MissingExtra, match=r"lcpfric\[plot\]"):
        figures._figure()


# -- print quality ---------------------------------------------------------------------------------
COLUMN = {
    "fig3_map_phi0",
    "fig5_phase_P1_0.5",
    "fig6_phase_P1_Q1_5",
    "fig7_phase_P1_1.5",
    "fig9_motor",
}
POINTS = 41


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    out = tmp_path_factory.mktemp("figures")
    messages = []
    paths = figures.write_figures(
        out, grid=11, points=POINTS, formats=("png", "pdf"), progress=messages.append
    )
    return out, paths, messages


@pytest.fixture(scope="module")
def built(maps):
    """The figures of ``write_figures``, as objects."""
    return {
        "fig3_map_phi0": figures.figure_maps(maps, [0.0]),
        "fig4_maps": figures.figure_maps(maps, figures.FIG4_PHASES, ncols=5),
        "fig5_phase_P1_0.5": figures.figure_phase(0.5, figures.FIG5_Q1, POINTS),
        "fig6_phase_P1_Q1_5": figures.figure_phase(5.0, (5.0,), POINTS),
        "fig7_phase_P1_1.5": figures.figure_phase(1.5, figures.FIG7_Q1, POINTS),
        "fig9_motor": figures.figure_motor(points=POINTS),
    }


def _png_dpi(path):
    """Horizontal and vertical resolution from the PNG pHYs chunk [dots per inch]."""
    data = Path(path).read_bytes()
    pos = 8
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos : pos + 8])
        if kind == b"pHYs":
            x, y, unit = struct.unpack(">IIB", data[pos + 8 : pos + 17])
            assert unit == 1  # pixels per metre
            return round(x * 0.0254, 1), round(y * 0.0254, 1)  # 300 dpi: 11811 px/m
        pos += 12 + length
    raise AssertionError(f"{path} has no pHYs chunk")


def _png_size(path):
    width, height = struct.unpack(">II", Path(path).read_bytes()[16:24])
    return width, height


def _curves(ax):
    return [
        line
        for line in ax.lines
        if not line.get_label().startswith("_") and len(line.get_xdata()) > 2
    ]


@pytest.mark.slow
def test_write_figures_reports_progress(written, tmp_path):
    out, paths, messages = written
    assert len(messages) == len(NAMES) + 1  # the maps, then one line per figure
    assert messages[0].startswith("maps:")
    for name, message in zip(NAMES, messages[1:]):
        assert name in message and "\n" not in message
    assert {p.name for p in paths} == {f"{n}.{ext}" for n in NAMES for ext in ("png", "pdf")}
    with pytest.raises(InputError):
        figures.write_figures(tmp_path, grid=5, progress="yes")


def test_pdfs_embed_truetype_not_type3(written):
    out, _, _ = written
    for name in NAMES:
        pdf = (out / f"{name}.pdf").read_bytes()
        assert b"/Type3" not in pdf, f"{name}.pdf embeds a Type 3 font"
        assert b"/CIDFontType2" in pdf or b"/TrueType" in pdf, name


def test_type42_whatever_the_callers_rcparams(maps, tmp_path):
    import matplotlib

    with matplotlib.rc_context(
        {
            "pdf.fonttype": 3,
            "font.size": 4,
            "xtick.labelsize": 4,
            "legend.fontsize": 4,
            "savefig.dpi": 72,
        }
    ):
        fig = figures.figure_phase(1.5, (1.0, 2.0), points=21)
        fig.savefig(tmp_path / "user.pdf")
        fig.savefig(tmp_path / "user.png")
        _renderer(fig)
        assert min(t.get_fontsize() for t in _texts(fig)) >= figures.MIN_FONT_SIZE
    assert b"/Type3" not in (tmp_path / "user.pdf").read_bytes()
    assert min(_png_dpi(tmp_path / "user.png")) >= 300
    # nothing was set globally
    assert matplotlib.rcParams["pdf.fonttype"] == matplotlib.rcParamsDefault["pdf.fonttype"]
    assert matplotlib.rcParams["savefig.dpi"] == matplotlib.rcParamsDefault["savefig.dpi"]


def test_pngs_are_300_dpi_and_print_size(written):
    out, _, _ = written
    for name in NAMES:
        path = out / f"{name}.png"
        dpi_x, dpi_y = _png_dpi(path)
        assert dpi_x >= 300 and dpi_y >= 300, name
        width_px, _ = _png_size(path)
        limit = figures.COLUMN_WIDTH if name in COLUMN else figures.PAGE_WIDTH
        assert width_px / dpi_x <= limit + 0.01, name


def test_figure_sizes_fit_column_or_page(built):
    for name, fig in built.items():
        width, height = fig.get_size_inches()
        limit = figures.COLUMN_WIDTH if name in COLUMN else figures.PAGE_WIDTH
        assert width <= limit + 1e-9, (name, width)
        assert height <= 9.0, (name, height)
    assert built["fig4_maps"].get_size_inches()[0] == pytest.approx(figures.PAGE_WIDTH)


@pytest.mark.slow
def test_no_text_below_7pt(built):
    for name, fig in built.items():
        _renderer(fig)
        texts = _texts(fig)
        small = [
            (t.get_text(), t.get_fontsize())
            for t in texts
            if t.get_fontsize() < figures.MIN_FONT_SIZE
        ]
        assert not small, f"{name}: {small}"
        kinds = {type(t).__name__ for t in texts}
        assert "Text" in kinds, name
    # the kinds of text the issue measured are all there and checked
    contour_labels = [t for ax in built["fig4_maps"].axes for t in ax.texts]
    assert contour_labels and all(t.get_fontsize() >= 7 for t in contour_labels)
    annotations = [t for t in built["fig6_phase_P1_Q1_5"].axes[0].texts]
    assert annotations and all(t.get_fontsize() >= 7 for t in annotations)


def test_line_figures_distinct_in_greyscale(built):
    for name in ("fig5_phase_P1_0.5", "fig7_phase_P1_1.5", "fig9_motor"):
        curves = _curves(built[name].axes[0])
        assert len(curves) >= 5, name
        markers = [line.get_marker() for line in curves]
        styles = [(line.get_linestyle(), line.get_marker()) for line in curves]
        assert len(set(markers)) == len(curves) and "None" not in markers, name
        assert len(set(styles)) == len(curves), name
        for a, b in zip(curves, curves[1:]):  # neighbours also differ in line style
            assert a.get_linestyle() != b.get_linestyle(), name


def test_boundary_and_separation_differ_in_colour_and_style(built):
    ax = built["fig3_map_phi0"].axes[0]
    (boundary,) = _red_lines(ax)
    separation = [line for line in ax.lines if line.get_xdata()[0] == 1.0]
    dashed = [line for line in separation if line.get_linestyle() not in ("-", "None")]
    assert dashed and all(line.get_color() == "black" for line in dashed)
    assert all(dashes is None for _, dashes in boundary.get_linestyle())  # solid


def _legend_texts(fig):
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    return " | ".join(t.get_text() for leg in legends for t in leg.get_texts())


def test_every_mark_is_explained(built):
    for name in ("fig3_map_phi0", "fig4_maps"):
        text = _legend_texts(built[name])
        assert "shakedown boundary" in text and r"$\hat P_1 = 1$" in text, name
    # the Ŵ = 0 region beyond P̂1 = 1 at φ = 0 (and π) is hatched and explained
    assert "without shakedown" in _legend_texts(built["fig3_map_phi0"])
    assert any(p.get_hatch() for p in built["fig3_map_phi0"].axes[0].patches)
    for name in ("fig5_phase_P1_0.5", "fig6_phase_P1_Q1_5", "fig7_phase_P1_1.5"):
        text = _legend_texts(built[name])
        assert "maximum" in text and "φ = π/2" in text, name
        if name != "fig6_phase_P1_Q1_5":
            for q in figures.FIG5_Q1 if "0.5" in name else figures.FIG7_Q1:
                assert rf"$\hat Q_1 = {q:g}$" in text
    text = _legend_texts(built["fig9_motor"])
    assert "shakedown speed" in text and "separation" in text
    assert all(f"f = {f:g}" in text for f in figures.MOTOR_FRICTION)


@pytest.mark.slow
def test_legends_and_annotations_stay_off_the_data(built):
    from matplotlib.text import Text

    for name, fig in built.items():
        renderer = _renderer(fig)
        data_axes = [ax for ax in fig.axes if ax.get_label() != "<colorbar>" and ax.get_visible()]
        boxes = [leg.get_window_extent(renderer) for leg in fig.legends]
        boxes += [
            ax.get_legend().get_window_extent(renderer) for ax in data_axes if ax.get_legend()
        ]
        if name.startswith("fig3") or name.startswith("fig4"):  # maps: data fill the axes
            for box in boxes:
                for ax in data_axes:
                    assert not box.overlaps(ax.get_window_extent(renderer)), name
            continue
        boxes += [Text.get_window_extent(t, renderer) for t in data_axes[0].texts]
        assert boxes, name
        for ax in data_axes:
            for line in ax.lines:
                xy = line.get_transform().transform(line.get_xydata())
                frame = ax.get_window_extent(renderer)  # only the points drawn (not clipped)
                xy = xy[
                    np.isfinite(xy).all(axis=1)
                    & (xy[:, 0] >= frame.x0)
                    & (xy[:, 0] <= frame.x1)
                    & (xy[:, 1] >= frame.y0)
                    & (xy[:, 1] <= frame.y1)
                ]
                for box in boxes:
                    inside = (
                        (xy[:, 0] > box.x0)
                        & (xy[:, 0] < box.x1)
                        & (xy[:, 1] > box.y0)
                        & (xy[:, 1] < box.y1)
                    )
                    assert not inside.any(), f"{name}: {line.get_label()} crosses a legend/text"


def test_fig4_panels_keep_many_colour_bands(maps):
    fig = figures.figure_maps(maps, figures.FIG4_PHASES, ncols=5)
    panels = [ax for ax in fig.axes if ax.get_title().startswith("φ")]
    for ax, phi in zip(panels, figures.FIG4_PHASES):
        levels = ax.collections[0].levels
        top = float(maps["W_hat"].sel(phi=phi, method="nearest").max())
        bands = int(np.sum(levels < top))
        assert bands >= 8, f"{ax.get_title()}: {bands} colour bands"
    bar = next(ax for ax in fig.axes if ax.get_label() == "<colorbar>")
    assert "uneven" in bar.get_ylabel()  # the scale says it is not linear


def test_motor_figure_log_axes_and_title():
    fig = figures.figure_motor(points=50)
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    title = ax.get_title()
    assert r"5\times10^{8}" in title and "e+08" not in title
    from lcpfric.paper.motor import Motor

    lo, hi = ax.get_xlim()  # the range shows every shakedown speed and the separation speed
    motor = Motor(**figures.MOTOR)
    for f in figures.MOTOR_FRICTION:
        assert lo < motor.shakedown_speed(f) < hi
    assert lo < motor.separation_speed() < hi
    linear = figures.figure_motor(points=20, log=False).axes[0]
    assert linear.get_xscale() == "linear"


def test_figures_pickle(built):
    fig = pickle.loads(pickle.dumps(built["fig6_phase_P1_Q1_5"]))
    assert type(fig).__name__ == "_PaperFigure"
    assert fig.get_size_inches()[0] == pytest.approx(figures.COLUMN_WIDTH)
