"""The half-space contact's figures (:mod:`lcpfric.figures.halfspace`): page or column
wide, no text below 7 pt, TrueType fonts in the PDFs, every mark in a legend; the traction
vectors need dims = 2; the animation refuses what it cannot write before any work."""

import numpy as np
import lcpfric
import pytest

from support import need_modules, renderer as _renderer, texts as _texts

need_modules("matplotlib")

from lcpfric.errors import InputError  # noqa: E402
from lcpfric.figures.style import COLUMN_WIDTH, MIN_FONT_SIZE, PAGE_WIDTH  # noqa: E402


PI = np.pi


def _solved(dims, grid, steps):
    from lcpfric.model.continuum.halfspace import HalfSpace
    from lcpfric.model.loads import Harmonic

    model = HalfSpace.sphere(
        1.0,
        1.0,
        0.3,
        0.5,
        Harmonic(1.0, 0.5, 0.0, 2 * PI),
        Harmonic(0.0, 0.22, 0.5, 2 * PI),
        grid=grid,
        dims=dims,
    )
    return model, lcpfric.steady_state(model, steps_per_cycle=steps)


@pytest.fixture(scope="module")
def plane():
    """dims = 2 (the tractions in the plane)."""
    return _solved(2, 12, 40)


@pytest.fixture(scope="module")
def line():
    """dims = 1 (the tractions along x)."""
    return _solved(1, 12, 40)


def _check_print(fig, width):
    w, h = fig.get_size_inches()
    assert w <= width + 1e-9 and h <= 9.0
    _renderer(fig)
    sizes = [t.get_fontsize() for t in _texts(fig)]
    assert sizes and min(sizes) >= MIN_FONT_SIZE
    assert any(lg is not None for lg in [*fig.legends, *(ax.get_legend() for ax in fig.axes)])
    # nothing drawn outside the figure (titles, legend, labels): inches
    tight = fig.get_tightbbox(_renderer(fig))
    assert tight.x0 >= -0.02 and tight.y0 >= -0.02
    assert tight.x1 <= w + 0.02 and tight.y1 <= h + 0.02


def test_zone_maps(plane, line):
    from lcpfric.figures.halfspace import ZONE_COLOURS, figure_zone_maps
    from lcpfric.results import State

    model, result = plane
    fig = figure_zone_maps(model, result, title="sphere, d = 2")
    assert abs(fig.get_size_inches()[0] - PAGE_WIDTH) < 1e-9
    _check_print(fig, PAGE_WIDTH)
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert len(panels) == 4
    titles = [ax.get_title() for ax in panels]
    assert titles[0].startswith("t/T = 0\n") and titles[2].startswith("t/T = 0.5\n")
    assert all("P/P_0" in t and r"\mu P_0" in t for t in titles)
    for ax in panels:
        assert ax.get_aspect() == 1.0
        lo, hi = ax.get_xlim()
        assert lo < -0.9 and hi > 0.9  # the whole contact (x/a0 up to ~1.15) ...
        assert hi - lo < 2 * model.N * model.h / model.a0  # ... cropped from the grid
    # one legend entry per colour, and the edges
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert len(labels) >= len(ZONE_COLOURS) + 1 and "stick" in labels and "separated" in labels
    # the mesh's colours are the element states
    j = result.t.size - 1  # t/T = 0 is drawn from t = T
    mesh = panels[0].collections[0]
    codes = np.asarray(mesh.get_array()).reshape(model.N, model.N)  # [j, i]
    stick = result.state[j].reshape(model.N, model.N).T == int(State.STICK)
    assert np.all(codes[stick] == 0)
    # one panel, dims = 1: column wide
    model1, result1 = line
    fig = figure_zone_maps(model1, result1, fractions=0.5)
    _check_print(fig, COLUMN_WIDTH)


def test_zone_maps_refuse_bad_input(plane):
    from lcpfric.figures.halfspace import figure_zone_maps

    model, result = plane
    with pytest.raises(InputError) as err:
        figure_zone_maps(model, result, fractions=(0.2, 1.5))
    assert err.value.parameter == "fractions"
    ends = lcpfric.steady_state(model, steps_per_cycle=20, history=False)  # no recorded cycle
    with pytest.raises(InputError) as err:
        figure_zone_maps(model, ends)
    assert err.value.parameter == "result"


def test_traction_vectors(plane, line):
    from lcpfric.figures.halfspace import figure_traction_vectors

    model, result = plane
    fig = figure_traction_vectors(model, result, 0.5, title="d = 2")
    _check_print(fig, COLUMN_WIDTH)
    ax = fig.axes[0]
    (arrows,) = [c for c in ax.collections if type(c).__name__ == "Quiver"]
    contact = model.normal_solution(result.t[20:21])[0][0] > 0
    assert arrows.N == np.count_nonzero(contact)  # small grid: every element
    (key,) = [a for a in ax.get_children() if type(a).__name__ == "QuiverKey"]
    assert r"\mu p_0" in key.text.get_text() and key.text.get_fontsize() >= MIN_FONT_SIZE
    assert len(fig.axes) == 2  # the colour bar
    with pytest.raises(InputError) as err:
        figure_traction_vectors(*line)
    assert err.value.parameter == "dims" and "dims=2" in str(err.value)


@pytest.mark.slow
def test_write_figures_truetype(tmp_path, plane, line):
    from lcpfric.figures.halfspace import write_halfspace_figures

    paths = write_halfspace_figures(tmp_path / "d2", *plane)
    assert sorted(p.name for p in paths) == sorted(
        f"halfspace-{n}.{e}" for n in ("zones", "tractions") for e in ("png", "pdf")
    )
    for p in paths:
        assert p.is_file() and p.stat().st_size > 1000
    for p in paths:
        if p.suffix == ".pdf":
            pdf = p.read_bytes()
            assert b"/Type3" not in pdf and (b"/CIDFontType2" in pdf or b"/TrueType" in pdf)
    paths = write_halfspace_figures(tmp_path / "d1", *line, formats=("png",))
    assert [p.name for p in paths] == ["halfspace-zones.png"]


def test_animation_refuses_before_work(tmp_path, plane):
    from lcpfric.figures.halfspace import animate_zones

    model, result = plane
    for bad in (tmp_path / "zones.mp4", tmp_path / "zones", tmp_path / "missing" / "z.gif"):
        with pytest.raises(InputError) as err:
            animate_zones(model, result, bad)
        assert err.value.parameter == "path"
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        import os

        if not os.access(locked, os.W_OK):  # root can write anyway
            with pytest.raises(InputError) as err:
                animate_zones(model, result, locked / "z.gif")
            assert err.value.parameter == "path"
    finally:
        locked.chmod(0o700)
    assert not list(tmp_path.rglob("*.gif"))


@pytest.mark.slow
def test_animation_written(tmp_path, plane):
    from PIL import Image

    from lcpfric.figures.halfspace import animate_zones

    out = animate_zones(*plane, tmp_path / "zones.gif", frames=6, fps=5)
    assert out == tmp_path / "zones.gif" and out.is_file()
    with Image.open(out) as im:
        assert im.format == "GIF" and im.n_frames == 6
