"""Print-ready matplotlib figures: journal sizes, fonts, styles, saving.

Figures are built as :class:`matplotlib.figure.Figure` objects without pyplot, so nothing here
touches the user's matplotlib backend or global settings; files are written with the Agg
renderer. Every figure is at most :data:`PAGE_WIDTH` (7.2 in) wide, or :data:`COLUMN_WIDTH`
(3.5 in) for one-column figures; no text is smaller than :data:`MIN_FONT_SIZE` (7 pt) at that
size; curves differ in line style and marker as well as colour (greyscale prints). The figures
returned save PDF and PS with TrueType (Type 42) fonts and raster formats at :data:`DPI` (300),
whatever the caller's rcParams, because their ``savefig`` applies these settings locally.

Used by the paper's figures (:mod:`lcpfric.paper.figures`) and the hysteresis loop
(:mod:`lcpfric.analysis.loop`).
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from .._optional import require

__all__ = [
    "COLUMN_WIDTH",
    "PAGE_WIDTH",
    "MIN_FONT_SIZE",
    "DPI",
    "SMALL",
    "NORMAL",
    "CMAP",
    "style",
    "figure",
    "finish",
    "phi_label",
    "sci",
    "ramp",
    "curve_style",
    "save",
]

PI = math.pi

#: Width of a journal column and of a full page [in].
COLUMN_WIDTH = 3.5
PAGE_WIDTH = 7.2
#: Smallest font size used in any figure [pt], at the figure's own (printed) size.
MIN_FONT_SIZE = 7.0
#: Resolution of raster files (PNG) [dots per inch].
DPI = 300

SMALL = MIN_FONT_SIZE  # ticks, legends, contour labels, annotations
NORMAL = 8.0  # axis labels and titles
CMAP = "viridis"
#: Local matplotlib settings for building and saving every figure (never set globally).
RC = {
    "font.size": NORMAL,
    "axes.titlesize": NORMAL,
    "axes.labelsize": NORMAL,
    "xtick.labelsize": SMALL,
    "ytick.labelsize": SMALL,
    "legend.fontsize": SMALL,
    "legend.title_fontsize": SMALL,
    "figure.titlesize": NORMAL + 1,
    "axes.linewidth": 0.6,
    "lines.linewidth": 1.2,
    "patch.linewidth": 0.6,
    "xtick.major.width": 0.6,
    "ytick.major.width": 0.6,
    "xtick.minor.width": 0.45,
    "ytick.minor.width": 0.45,
    "xtick.major.size": 3.0,
    "ytick.major.size": 3.0,
    "xtick.minor.size": 1.8,
    "ytick.minor.size": 1.8,
    "grid.linewidth": 0.5,
    "legend.handlelength": 2.6,
    "legend.borderaxespad": 0.3,
    "legend.columnspacing": 1.2,
    "hatch.linewidth": 0.6,
    "mathtext.fontset": "dejavusans",
    "pdf.fonttype": 42,
    "ps.fonttype": 42,
    "savefig.dpi": DPI,
}


@contextmanager
def style():
    """The figures' matplotlib settings, applied only inside the ``with`` block."""
    require("matplotlib", "plot", "Figures")
    import matplotlib

    with matplotlib.rc_context(RC):
        yield


FIGURE_CLASS = None


def figure_class():
    """A :class:`~matplotlib.figure.Figure` whose ``savefig`` applies :data:`RC` locally (TrueType
    fonts in PDF/PS, 300 dpi), created on first use so that matplotlib stays optional."""
    global FIGURE_CLASS
    if FIGURE_CLASS is None:
        from matplotlib.figure import Figure

        class PaperFigure(Figure):
            """A figure that saves with TrueType (Type 42) fonts and at 300 dpi by default."""

            def savefig(self, fname, *args, **kwargs):
                with style():
                    return super().savefig(fname, *args, **kwargs)

        PaperFigure.__module__ = __name__
        PaperFigure.__qualname__ = PaperFigure.__name__ = "_PaperFigure"
        FIGURE_CLASS = PaperFigure
    return FIGURE_CLASS


def __getattr__(name):  # lets pickle find the lazily created figure class
    if name == "_PaperFigure":
        return figure_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def figure(**kwargs):
    require("matplotlib", "plot", "Figures")
    return figure_class()(**kwargs)


def finish(fig):
    """Fix tick label sizes on every axes (ticks are created at draw time, possibly outside
    :func:`_style`), so the figure renders the same under any rcParams."""
    for ax in fig.axes:
        for axes in (ax, *getattr(ax, "child_axes", ())):
            axes.tick_params(which="both", labelsize=SMALL)
    return fig


def phi_label(phi: float) -> str:
    k = phi / PI
    if abs(k) < 1e-12:
        return "φ = 0"
    return "φ = π" if abs(k - 1) < 1e-12 else f"φ = {k:.3g}π"


def sci(x: float) -> str:
    """``x`` for mathtext: 5e8 -> ``5\\times10^{8}``, 2000 -> ``2000``."""
    if x == 0 or 1e-3 <= abs(x) < 1e5:
        return f"{x:g}"
    exponent = math.floor(math.log10(abs(x)))
    mantissa = x / 10**exponent
    if abs(mantissa - round(mantissa)) < 1e-9:
        mantissa = round(mantissa)
    head = "" if mantissa == 1 else rf"{mantissa:g}\times"
    return rf"{head}10^{{{exponent}}}"


def ramp(n: int):
    """``n`` colours of a perceptually uniform map, dark to light, in the order of the curves
    (their lightness also orders them in greyscale)."""
    from matplotlib import colormaps

    return colormaps[CMAP](np.linspace(0.0, 0.82, n) if n > 1 else [0.0])


#: (line style, marker) of successive curves: every curve differs in marker, and neighbours also
#: in line style, so that curves stay distinct in greyscale.
STYLES = (
    ("-", "s"),
    ("--", "^"),
    ("-.", "v"),
    (":", "D"),
    ("-", "P"),
    ("--", "X"),
    ("-.", "p"),
    (":", "h"),
    ("-", "<"),
    ("--", ">"),
)


def curve_style(i: int, n: int, points: int) -> dict:
    ls, marker = STYLES[i % len(STYLES)]
    step = max(points // 7, 1)
    return {
        "ls": ls,
        "marker": marker,
        "ms": 3.6,
        "markevery": ((i * step) // max(n, 1), step),
        "mew": 0.6,
    }


def save(fig, out_dir: Path, name: str, formats) -> list[Path]:
    """Write ``fig`` as ``out_dir/name.<fmt>`` for each format (print settings applied)."""
    paths = []
    for fmt in formats:
        path = out_dir / f"{name}.{fmt}"
        with style():
            fig.savefig(path, dpi=DPI)
        if fig.get_layout_engine() is not None:
            fig.set_layout_engine("none")  # laid out by the first save: keep it (faster)
        paths.append(path)
    return paths
