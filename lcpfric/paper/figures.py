"""The paper's figures, drawn from data lcpfric computes (PNG and PDF), sized for print.

* Fig. 3 (:func:`figure_maps`): Ŵ(P̂1, Q̂1) at φ = 0, with the line P̂1 = 1 (one column wide);
* Fig. 4 (:func:`figure_maps`): Ŵ(P̂1, Q̂1) for φ = kπ/10, k = 1..10 (k = 10 repeats φ = 0; one
  page wide, one colour scale with bands finer at small Ŵ);
* Fig. 5 (:func:`figure_phase`): Ŵ against φ for P̂1 = 0.5 and several Q̂1;
* Fig. 6 (:func:`figure_phase`): Ŵ against φ for P̂1 = Q̂1 = 5;
* Fig. 7 (:func:`figure_phase`): Ŵ against φ for P̂1 = 1.5 and several Q̂1;
* Fig. 9 (:func:`figure_motor`): the motor of Section 3.3, W against speed for several f
  (logarithmic axes, so that the onset of slip and of separation show).

Every map carries the exact shakedown boundary (the zero contour of
:func:`~lcpfric.analysis.shakedown.shakedown_margin`, computed on a finer grid than the map).
Figures are built as :class:`matplotlib.figure.Figure` objects without pyplot, so nothing here
touches the user's matplotlib backend or global settings; files are written with the Agg renderer.

Print rules (checked by the tests): every figure is at most :data:`PAGE_WIDTH` (7.2 in) wide, or
:data:`COLUMN_WIDTH` (3.5 in) for the one-column Figs. 3, 5-7 and 9; no text is smaller than
:data:`MIN_FONT_SIZE` (7 pt) at that size; curves differ in line style and marker as well as
colour (greyscale prints); every mark has a legend entry. The returned figures save PDF and PS
with TrueType (Type 42) fonts and raster formats at :data:`DPI` (300) dots per inch, whatever the
caller's rcParams, because their ``savefig`` applies these settings locally.
"""

from __future__ import annotations

import time
from pathlib import Path

from ..errors import InputError
from ..figures.style import COLUMN_WIDTH, DPI, MIN_FONT_SIZE, PAGE_WIDTH  # noqa: F401
from ..figures.style import figure as _figure  # noqa: F401
from ..figures.style import save as _save
from .curves import FIG5_Q1, FIG7_Q1, MOTOR, MOTOR_FRICTION, figure_motor, figure_phase
from .maps import FIG4_PHASES, figure_maps, map_data

__all__ = [
    "map_data",
    "figure_maps",
    "figure_phase",
    "figure_motor",
    "write_figures",
    "FIG4_PHASES",
    "FIG5_Q1",
    "FIG7_Q1",
    "MOTOR",
    "MOTOR_FRICTION",
    "COLUMN_WIDTH",
    "PAGE_WIDTH",
    "MIN_FONT_SIZE",
    "DPI",
]


def write_figures(
    out_dir,
    grid: int = 101,
    points: int = 361,
    formats=("png", "pdf"),
    data=None,
    progress=None,
    **sweep_options,
) -> list[Path]:
    """Compute and write Figs. 3-7 and 9 into ``out_dir``.

    Parameters
    ----------
    out_dir : str or Path
        Directory for the files (created if needed).
    grid : int
        Points per axis of the maps (the paper's figures: 101 on [0, 10]).
    points : int
        Phases per curve in Figs. 5-7, and speeds in Fig. 9.
    formats : sequence of str
        File formats, among ``"png"``, ``"pdf"``, ``"svg"`` (PNG at 300 dpi; PDF with TrueType
        fonts).
    data : xarray.Dataset, optional
        Precomputed maps (from :func:`map_data`); computed when not given.
    progress : callable, optional
        Called with a one-line message when the maps are computed and as each figure is written
        (e.g. ``lambda m: print(m, file=sys.stderr)``); default: silent.
    **sweep_options
        Passed to :func:`lcpfric.analysis.sweep.sweep` for the maps (``scheduler``,
        ``processes``...).

    Returns
    -------
    list of Path
        The files written.
    """
    formats = tuple(formats)
    bad = [f for f in formats if f not in ("png", "pdf", "svg")]
    if bad or not formats:
        raise InputError("formats", f"choose among png, pdf, svg; got {', '.join(formats)}")
    if progress is not None and not callable(progress):
        raise InputError("progress", f"must be callable or None, got {progress!r}")
    if not isinstance(out_dir, (str, Path)) or not str(out_dir).strip():
        raise InputError("out", f"must be a directory path, got {out_dir!r}")
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("out", f"{out_dir} exists and is not a directory")
    if not out_dir.parent.is_dir():  # the rule of every output: the parent must exist
        raise InputError("out", f"the directory {str(out_dir.parent)!r} does not exist")
    out_dir.mkdir(exist_ok=True)
    say = progress if progress is not None else (lambda message: None)
    if data is None:
        t0 = time.perf_counter()
        ds = map_data(grid, **sweep_options)
        say(
            f"maps: Ŵ on {grid}x{grid} points x {ds.sizes['phi']} phases "
            f"({time.perf_counter() - t0:.1f} s)"
        )
    else:
        ds = data
    figures = {
        "fig3_map_phi0": lambda: figure_maps(ds, [0.0]),
        "fig4_maps": lambda: figure_maps(ds, FIG4_PHASES, ncols=5),
        "fig5_phase_P1_0.5": lambda: figure_phase(
            0.5, FIG5_Q1, points, r"$\hat P_1 = 0.5$ (full contact)"
        ),
        "fig6_phase_P1_Q1_5": lambda: figure_phase(
            5.0, (5.0,), points, r"$\hat P_1 = \hat Q_1 = 5$"
        ),
        "fig7_phase_P1_1.5": lambda: figure_phase(
            1.5, FIG7_Q1, points, r"$\hat P_1 = 1.5$ (separation)"
        ),
        "fig9_motor": lambda: figure_motor(points=points),
    }
    written = []
    for k, (name, make) in enumerate(figures.items(), 1):
        t0 = time.perf_counter()
        fig = make()
        paths = _save(fig, out_dir, name, formats)
        written += paths
        width, height = fig.get_size_inches()
        say(
            f"[{k}/{len(figures)}] {name}: {', '.join(p.suffix[1:] for p in paths)}, "
            f"{width:.2f} x {height:.2f} in ({time.perf_counter() - t0:.1f} s)"
        )
    return written
