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
:func:`~lcpfric.shakedown.shakedown_margin`, computed on a finer grid than the map). Figures are
built as :class:`matplotlib.figure.Figure` objects without pyplot, so nothing here touches the
user's matplotlib backend or global settings; files are written with the Agg renderer.

Print rules (checked by the tests): every figure is at most :data:`PAGE_WIDTH` (7.2 in) wide, or
:data:`COLUMN_WIDTH` (3.5 in) for the one-column Figs. 3, 5-7 and 9; no text is smaller than
:data:`MIN_FONT_SIZE` (7 pt) at that size; curves differ in line style and marker as well as
colour (greyscale prints); every mark has a legend entry. The returned figures save PDF and PS
with TrueType (Type 42) fonts and raster formats at :data:`DPI` (300) dots per inch, whatever the
caller's rcParams, because their ``savefig`` applies these settings locally.
"""

from __future__ import annotations

import math
import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from .. import _checks
from .._optional import require
from ..errors import InputError

__all__ = ["map_data", "figure_maps", "figure_phase", "figure_motor", "write_figures",
           "FIG5_Q1", "FIG7_Q1", "MOTOR", "MOTOR_FRICTION", "COLUMN_WIDTH", "PAGE_WIDTH",
           "MIN_FONT_SIZE", "DPI"]

PI = math.pi
FIG4_PHASES = tuple(k * PI / 10 for k in range(1, 11))
FIG5_Q1 = (1.0, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0)
FIG7_Q1 = (0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0)
#: The motor drawn in Fig. 9 (SI units): a 20 kg rotor 0.5 mm out of balance, 2 kN bolt preload,
#: joint stiffness 5e8 N/m (natural frequency sqrt(k11/M) = 5000 rad/s, well above the speeds).
MOTOR = {"M": 20.0, "delta": 0.5e-3, "P0": 2000.0, "k11": 5e8}
MOTOR_FRICTION = (0.1, 0.2, 0.3, 0.5, 0.8)

#: Width of a journal column and of a full page [in].
COLUMN_WIDTH = 3.5
PAGE_WIDTH = 7.2
#: Smallest font size used in any figure [pt], at the figure's own (printed) size.
MIN_FONT_SIZE = 7.0
#: Resolution of raster files (PNG) [dots per inch].
DPI = 300

_SMALL = MIN_FONT_SIZE  # ticks, legends, contour labels, annotations
_NORMAL = 8.0  # axis labels and titles
_CMAP = "viridis"
_BOUNDARY = {"colors": "#e8402a", "linewidths": 1.8}  # the shakedown boundary: red, solid
_NO_SLIP_HATCH = "////"
#: Local matplotlib settings for building and saving every figure (never set globally).
_RC = {
    "font.size": _NORMAL, "axes.titlesize": _NORMAL, "axes.labelsize": _NORMAL,
    "xtick.labelsize": _SMALL, "ytick.labelsize": _SMALL, "legend.fontsize": _SMALL,
    "legend.title_fontsize": _SMALL, "figure.titlesize": _NORMAL + 1,
    "axes.linewidth": 0.6, "lines.linewidth": 1.2, "patch.linewidth": 0.6,
    "xtick.major.width": 0.6, "ytick.major.width": 0.6, "xtick.minor.width": 0.45,
    "ytick.minor.width": 0.45, "xtick.major.size": 3.0, "ytick.major.size": 3.0,
    "xtick.minor.size": 1.8, "ytick.minor.size": 1.8, "grid.linewidth": 0.5,
    "legend.handlelength": 2.6, "legend.borderaxespad": 0.3, "legend.columnspacing": 1.2,
    "hatch.linewidth": 0.6, "mathtext.fontset": "dejavusans",
    "pdf.fonttype": 42, "ps.fonttype": 42, "savefig.dpi": DPI,
}


@contextmanager
def _style():
    """The figures' matplotlib settings, applied only inside the ``with`` block."""
    require("matplotlib", "plot", "Figures")
    import matplotlib

    with matplotlib.rc_context(_RC):
        yield


_FIGURE_CLASS = None


def _figure_class():
    """A :class:`~matplotlib.figure.Figure` whose ``savefig`` applies :data:`_RC` locally (TrueType
    fonts in PDF/PS, 300 dpi), created on first use so that matplotlib stays optional."""
    global _FIGURE_CLASS
    if _FIGURE_CLASS is None:
        from matplotlib.figure import Figure

        class PaperFigure(Figure):
            """A figure that saves with TrueType (Type 42) fonts and at 300 dpi by default."""

            def savefig(self, fname, *args, **kwargs):
                with _style():
                    return super().savefig(fname, *args, **kwargs)

        PaperFigure.__module__ = __name__
        PaperFigure.__qualname__ = PaperFigure.__name__ = "_PaperFigure"
        _FIGURE_CLASS = PaperFigure
    return _FIGURE_CLASS


def __getattr__(name):  # lets pickle find the lazily created figure class
    if name == "_PaperFigure":
        return _figure_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _figure(**kwargs):
    require("matplotlib", "plot", "Figures")
    return _figure_class()(**kwargs)


def _finish(fig):
    """Fix tick label sizes on every axes (ticks are created at draw time, possibly outside
    :func:`_style`), so the figure renders the same under any rcParams."""
    for ax in fig.axes:
        for axes in (ax, *getattr(ax, "child_axes", ())):
            axes.tick_params(which="both", labelsize=_SMALL)
    return fig


def _phi_label(phi: float) -> str:
    k = phi / PI
    if abs(k) < 1e-12:
        return "φ = 0"
    return "φ = π" if abs(k - 1) < 1e-12 else f"φ = {k:.3g}π"


def _sci(x: float) -> str:
    """``x`` for mathtext: 5e8 -> ``5\\times10^{8}``, 2000 -> ``2000``."""
    if x == 0 or 1e-3 <= abs(x) < 1e5:
        return f"{x:g}"
    exponent = math.floor(math.log10(abs(x)))
    mantissa = x / 10**exponent
    if abs(mantissa - round(mantissa)) < 1e-9:
        mantissa = round(mantissa)
    head = "" if mantissa == 1 else rf"{mantissa:g}\times"
    return rf"{head}10^{{{exponent}}}"


def _ramp(n: int):
    """``n`` colours of a perceptually uniform map, dark to light, in the order of the curves
    (their lightness also orders them in greyscale)."""
    from matplotlib import colormaps

    return colormaps[_CMAP](np.linspace(0.0, 0.82, n) if n > 1 else [0.0])


#: (line style, marker) of successive curves: every curve differs in marker, and neighbours also
#: in line style, so that curves stay distinct in greyscale.
_STYLES = (("-", "s"), ("--", "^"), ("-.", "v"), (":", "D"), ("-", "P"), ("--", "X"),
           ("-.", "p"), (":", "h"), ("-", "<"), ("--", ">"))


def _curve_style(i: int, n: int, points: int) -> dict:
    ls, marker = _STYLES[i % len(_STYLES)]
    step = max(points // 7, 1)
    return {"ls": ls, "marker": marker, "ms": 3.6, "markevery": ((i * step) // max(n, 1), step),
            "mew": 0.6}


def map_data(grid: int = 101, extent: float = 10.0, phases=None, **sweep_options):
    """The maps of Figs. 3 and 4: Ŵ on ``grid x grid`` points of [0, extent]² at
    ``phases`` (default φ = kπ/10, k = 0..10), as an ``xarray.Dataset`` from
    :func:`lcpfric.sweep.sweep`."""
    from ..analysis.sweep import sweep

    grid = _checks.positive_int("grid", grid, minimum=3)
    extent = _checks.positive("extent", extent)
    axis = np.linspace(0.0, extent, grid)
    phases = (0.0, *FIG4_PHASES) if phases is None else phases
    sweep_options.setdefault("progress", False)
    return sweep(axis, axis, phases, **sweep_options)


# -- maps (Figs. 3 and 4) --------------------------------------------------------------------------
def _map_levels(tops):
    """Contour levels for panels whose maxima are ``tops``, and whether they are uneven.

    One panel, or panels of similar range: about 16 even levels. Panels of very different range
    (Fig. 4: max Ŵ from 3.6 to 14.6): levels 0.25 apart below 1, then 1, 1.2, 1.5, 2, 2.5, 3, 4, 5,
    6, 8 per decade, each band one colour step, so that the low panels keep many bands.
    """
    from matplotlib.ticker import MaxNLocator

    top = max(tops) if len(tops) and max(tops) > 0 else 1.0
    low = min(t for t in tops if t > 0) if any(t > 0 for t in tops) else top
    if top <= 2.0 * low:
        return MaxNLocator(nbins=16).tick_values(0.0, top), False
    levels = [0.0, 0.25, 0.5, 0.75]
    decade = 1.0
    while levels[-1] < top:
        levels += [m * decade for m in (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8)]
        decade *= 10
    end = next(i for i, v in enumerate(levels) if v >= top)
    return np.array(levels[:end + 1]), True


def _luminance(rgba) -> float:
    r, g, b = rgba[:3]
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def _boundary_effects():
    """A thin dark outline around the (red) shakedown boundary, so that it stands out on every
    colour of the map, also in greyscale."""
    from matplotlib import patheffects

    return [patheffects.Stroke(linewidth=_BOUNDARY["linewidths"] + 1.0, foreground="0.1"),
            patheffects.Normal()]


def _separation_line(ax, x: float = 1.0):
    """The line P̂1 = 1: black dashes on a white line, visible on dark and light colours."""
    ax.axvline(x, color="white", lw=1.3, zorder=3)
    ax.axvline(x, color="black", lw=1.3, ls=(0, (3, 2)), zorder=3.1)


def _separation_handle():
    from matplotlib.lines import Line2D

    return (Line2D([], [], color="white", lw=1.3),
            Line2D([], [], color="black", lw=1.3, ls=(0, (3, 2))))


def _label_spots(lines, levels, xlim, ylim):
    """A point on each labelled contour, as far as possible from the panel's edges and from the
    line P̂1 = 1, so that contour labels sit inside the panel instead of on its frame."""
    (x0, x1), (y0, y1) = xlim, ylim
    sx, sy = max(x1 - x0, 1e-12), max(y1 - y0, 1e-12)
    spots = []
    for level, path in zip(lines.levels, lines.get_paths()):
        if level not in levels or not len(path.vertices):
            continue
        xy = path.vertices
        x, y = (xy[:, 0] - x0) / sx, (xy[:, 1] - y0) / sy
        score = np.minimum.reduce([x, 1 - x, y, 1 - y, 1.5 * np.abs(xy[:, 0] - 1.0) / sx])
        score = score + 0.1 * np.minimum(x, 1 - x)  # along a flat contour: mid-panel
        k = int(np.argmax(score))
        if score[k] > 0.05:
            spots.append((level, (float(xy[k, 0]), float(xy[k, 1]))))
    return spots


def _draw_map(ax, W2d, P1, Q1, phi, levels, norm, boundary_points: int = 401,
              line_levels=None, label_levels=None):
    from matplotlib.patches import Polygon

    from ..analysis.shakedown import shakedown_margin

    filled = ax.contourf(P1, Q1, W2d.T, levels=levels, cmap=_CMAP, norm=norm)
    line_levels = [v for v in (levels[1:-1] if line_levels is None else line_levels)
                   if levels[0] < v < W2d.max()]
    if line_levels:
        colors = ["white" if _luminance(filled.cmap(norm(v))) < 0.45 else "black"
                  for v in line_levels]
        lines = ax.contour(P1, Q1, W2d.T, levels=line_levels, colors=colors, linewidths=0.45,
                           alpha=0.75)
        shown = [v for v in line_levels if label_levels is None or v in label_levels]
        spots = _label_spots(lines, shown, (P1.min(), P1.max()), (Q1.min(), Q1.max()))
        if spots:
            ax.clabel(lines, levels=[v for v, _ in spots], fmt="%g", fontsize=_SMALL,
                      inline_spacing=2, manual=[xy for _, xy in spots])
    p = np.linspace(P1.min(), P1.max(), boundary_points)
    q = np.linspace(Q1.min(), Q1.max(), boundary_points)
    margin = shakedown_margin(p[:, None], q[None, :], phi)
    if margin.min() < 0 < margin.max():
        # above the line P̂1 = 1, which it partly follows at φ = 0 and π
        boundary = ax.contour(p, q, margin.T, levels=[0.0], zorder=3.5, **_BOUNDARY)
        boundary.set_path_effects(_boundary_effects())
    no_slip = abs(math.sin(phi)) < 1e-12 and P1.max() > 1.0
    if no_slip:  # φ = 0 or π: Ŵ = 0 also for P̂1 > 1, Q̂1 <= P̂1 (Section 3.1)
        big = 10.0 * max(P1.max(), Q1.max(), 1.0)
        ax.add_patch(Polygon([(1, 0), (big, 0), (big, big), (1, 1)], closed=True,
                             facecolor="none", edgecolor="white", hatch=_NO_SLIP_HATCH, lw=0,
                             alpha=0.55, zorder=2))
    if P1.min() < 1.0 < P1.max():
        _separation_line(ax)
    ax.set_xlim(P1.min(), P1.max())
    ax.set_ylim(Q1.min(), Q1.max())
    ax.set_box_aspect(1)
    ax.set_title(_phi_label(phi), fontsize=_NORMAL, pad=3)
    return filled, no_slip


def _map_legend_handles(no_slip: bool, cmap_low):
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = [Line2D([], [], color=_BOUNDARY["colors"], lw=_BOUNDARY["linewidths"],
                      path_effects=_boundary_effects()),
               _separation_handle()]
    labels = [r"shakedown boundary ($\hat W$ = 0 inside)",
              r"$\hat P_1 = 1$ (separation for $\hat P_1 > 1$)"]
    if no_slip:
        handles.append(Patch(facecolor=cmap_low, edgecolor="white", hatch=_NO_SLIP_HATCH, lw=0))
        labels.append(r"$\hat W$ = 0 without shakedown: $\hat Q_1 \leq \hat P_1$, no slip "
                      r"(φ = 0, π)")
    return handles, labels


def figure_maps(ds, phases=(0.0,), ncols: int = 5, title: str | None = None):
    """Contour maps of ``ds.W_hat`` at the phases nearest to ``phases``, on one colour scale.

    One phase gives a one-column figure (3.5 in wide, Fig. 3); several give a page-wide figure
    (7.2 in, Fig. 4). When the panels' ranges differ a lot, the colour bands are finer at small Ŵ
    (0.25 apart below 1, about 20 % apart above), one colour step each, so that every panel shows
    many bands on the shared scale; the colour bar says so.

    Parameters
    ----------
    ds : xarray.Dataset
        A dataset from :func:`lcpfric.sweep.sweep` (coordinates ``phi``, ``P1``, ``Q1``).
    phases : sequence of float
        Phases to draw (radians), one panel each.
    ncols : int
        Panels per row.
    title : str, optional
        Figure title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    with _style():
        return _figure_maps(ds, phases, ncols, title)


def _figure_maps(ds, phases, ncols, title):
    from matplotlib import colormaps
    from matplotlib.colors import BoundaryNorm, Normalize
    from matplotlib.legend_handler import HandlerTuple
    from matplotlib.ticker import MultipleLocator

    phases = [float(p) for p in np.atleast_1d(phases)]
    ncols = min(_checks.positive_int("ncols", ncols), len(phases))
    nrows = math.ceil(len(phases) / ncols)
    single = len(phases) == 1
    P1, Q1 = ds["P1"].values, ds["Q1"].values
    panels = [ds["W_hat"].sel(phi=p, method="nearest") for p in phases]
    levels, uneven = _map_levels([float(w.max()) for w in panels])
    cmap = colormaps[_CMAP]
    norm = (BoundaryNorm(levels, cmap.N) if uneven
            else Normalize(vmin=levels[0], vmax=levels[-1]))
    if single:
        width, height = COLUMN_WIDTH, 3.5 + (0.2 if title else 0.0)
    else:
        panel = (PAGE_WIDTH - 1.35) / ncols  # room for the Q̂1 label and the colour bar
        height = nrows * (panel + 0.2) + 0.55 + (0.2 if title else 0.0)
        width = PAGE_WIDTH
    fig = _figure(figsize=(width, height), layout="constrained")
    fig.get_layout_engine().set(w_pad=0.02, h_pad=0.02, wspace=0.0 if single else 0.06,
                                hspace=0.02)
    axes = np.atleast_1d(fig.subplots(nrows, ncols, sharex=True, sharey=True, squeeze=False))
    extent = max(P1.max() - P1.min(), Q1.max() - Q1.min())
    if uneven:
        line_levels = [v for v in levels[1:-1] if v in (0.5, 1, 2, 3, 4, 6, 8, 10, 12, 15, 20)]
        label_levels = [v for v in levels if v in (1, 2, 4, 8, 12, 20)]
    else:
        line_levels = levels[2:-1:2]  # every other level
        label_levels = None
    filled, no_slip = None, False
    for ax, w in zip(axes.flat, panels):
        filled, ns = _draw_map(ax, w.transpose("P1", "Q1").values, P1, Q1, float(w["phi"]),
                               levels, norm, line_levels=line_levels, label_levels=label_levels)
        no_slip |= ns
        if extent >= 4:
            step = 2.0 if single else 5.0
            ax.xaxis.set_major_locator(MultipleLocator(step))
            ax.yaxis.set_major_locator(MultipleLocator(step))
            if not single:
                ax.xaxis.set_minor_locator(MultipleLocator(1.0))
                ax.yaxis.set_minor_locator(MultipleLocator(1.0))
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    for ax in axes[-1, :]:
        ax.set_xlabel(r"$\hat P_1$", labelpad=1)
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$\hat Q_1$", labelpad=1)
    label = r"$\hat W = k_{11} W / (f P_0 Q_1)$"
    if uneven:
        label += ", one scale, uneven bands"
    spacing = "uniform" if uneven else "proportional"
    if single:  # as tall as the (square) map
        bar = fig.colorbar(filled, cax=axes[0, 0].inset_axes([1.05, 0.0, 0.06, 1.0]),
                           label=label, spacing=spacing)
    else:
        bar = fig.colorbar(filled, ax=axes, label=label, shrink=0.95, aspect=30, pad=0.02,
                           spacing=spacing)
    bar.set_ticks(levels if uneven else levels[::2])
    bar.ax.yaxis.set_major_formatter("{x:g}")
    bar.ax.minorticks_off()
    bar.outline.set_linewidth(0.5)
    handles, labels = _map_legend_handles(no_slip, cmap(0.0))
    fig.legend(handles, labels, loc="outside lower center", ncols=1 if single else len(handles),
               frameon=False, handler_map={tuple: HandlerTuple(ndivide=1)},
               handlelength=2.4)
    if title:
        fig.suptitle(title, fontsize=_NORMAL + 1)
    return _finish(fig)


# -- Ŵ against phase (Figs. 5-7) -------------------------------------------------------------------
def _phase_data(P1: float, Q1s, points: int):
    from ..analysis.sweep import sweep

    phi = np.linspace(0.0, PI, _checks.positive_int("points", points, minimum=3))
    return sweep([P1], list(Q1s), phi, progress=False)["W_hat"].sel(P1=P1)


def figure_phase(P1: float, Q1s, points: int = 361, title: str | None = None,
                 mark_peaks: bool = True):
    """Ŵ against φ in [0, π] for one P̂1 and several Q̂1 (Figs. 5-7), maxima marked.

    One column wide (3.5 in). Curves differ in colour (dark to light with Q̂1), marker and line
    style; the maxima (:func:`lcpfric.paper.claims.peak_phase`) are open black circles; the
    dotted line is φ = π/2. With one curve (Fig. 6), the maximum is also written out.

    Returns
    -------
    matplotlib.figure.Figure
    """
    with _style():
        return _figure_phase(P1, Q1s, points, title, mark_peaks)


def _figure_phase(P1, Q1s, points, title, mark_peaks):
    from matplotlib.lines import Line2D

    from .claims import peak_phase

    P1 = _checks.nonnegative("P1", P1)
    data = _phase_data(P1, Q1s, points)
    Q1_values = data["Q1"].values
    n = len(Q1_values)
    fig = _figure(figsize=(COLUMN_WIDTH, 2.6 if n == 1 else 3.3), layout="constrained")
    fig.get_layout_engine().set(w_pad=0.03, h_pad=0.03)
    ax = fig.subplots()
    x = data["phi"].values / PI
    handles, labels = [], []
    tops = []
    for i, (q, color) in enumerate(zip(Q1_values, _ramp(n))):
        style = {} if n == 1 else _curve_style(i, n, len(x))
        line, = ax.plot(x, data.sel(Q1=q).values, lw=1.2, color=color, zorder=2,
                        label=rf"$\hat Q_1 = {q:g}$", **style)
        if n > 1:
            handles.append(line)
            labels.append(line.get_label())
        if mark_peaks:
            best, top = peak_phase(P1, float(q))
            if top > 0:
                tops.append((best, top))
                ax.plot(best / PI, top, "o", ms=5, mfc="white", mec="black", mew=0.9,
                        zorder=4, label="_maximum")
    ax.axvline(0.5, color="0.35", lw=0.9, ls=":", zorder=1)
    ax.set_xlim(0, 1)
    ymax = float(data.max()) if data.size else 1.0
    ax.set_ylim(0, 1.06 * ymax if ymax > 0 else 1.0)
    if n == 1 and tops:
        best, top = tops[0]
        ax.set_ylim(0, 1.2 * max(top, ymax))
        ax.annotate(rf"maximum $\hat W$ = {top:.4f}" + f"\nat φ = {best / PI:.4f}π",
                    (best / PI, top), xytext=(0.03, 0.96), textcoords="axes fraction",
                    ha="left", va="top", fontsize=_SMALL,
                    arrowprops={"arrowstyle": "-", "lw": 0.5, "color": "0.3",
                                "shrinkA": 2, "shrinkB": 4})
    ax.set_xlabel(r"$\varphi / \pi$", labelpad=2)
    ax.set_ylabel(r"$\hat W$", labelpad=2)
    ax.grid(alpha=0.25)
    if tops:
        handles.append(Line2D([], [], ls="", marker="o", ms=5, mfc="white", mec="black",
                              mew=0.9))
        labels.append(r"maximum over φ")
    handles.append(Line2D([], [], color="0.35", lw=0.9, ls=":"))
    labels.append("φ = π/2")
    fig.legend(handles, labels, loc="outside lower center", ncols=3 if n > 1 else 2,
               frameon=False, handlelength=2.8, columnspacing=1.0)
    ax.set_title(title or rf"$\hat P_1 = {P1:g}$", fontsize=_NORMAL)
    return _finish(fig)


# -- the motor (Fig. 9) ----------------------------------------------------------------------------
def _motor_speeds(motor, friction, points: int):
    """Speeds for Fig. 9: ``points`` logarithmically spaced from 0.25 to 3 times the separation
    speed, plus speeds crowding just above each shakedown speed (where W rises from 0)."""
    unit = motor.separation_speed()
    base = np.geomspace(0.25 * unit, 3.0 * unit, points)
    extra = [motor.shakedown_speed(f) * (1.0 + np.geomspace(1e-7, 0.05, 24))
             for f in friction]
    return np.unique(np.concatenate([base, *extra]))


def figure_motor(M: float = MOTOR["M"], delta: float = MOTOR["delta"], P0: float = MOTOR["P0"],
                 k11: float = MOTOR["k11"], friction=MOTOR_FRICTION, speeds=None,
                 points: int = 400, log: bool = True):
    """Fig. 9: energy dissipated per revolution against rotational speed, several f.

    One column wide (3.5 in), on logarithmic axes by default: W rises from 0 at each shakedown
    speed (ticks on the speed axis), and its growth changes where separation begins.

    Parameters
    ----------
    M, delta, P0, k11 : float
        Rotor mass [kg], out-of-balance offset [m], bolt preload [N], joint tangential stiffness
        [N/m] (see :class:`lcpfric.motor.Motor`).
    friction : sequence of float
        Coefficients of friction, one curve each.
    speeds : array_like, optional
        Rotational speeds Ω [rad/s]; default 0.25 to 3 times the separation speed, logarithmically
        spaced, refined just above each shakedown speed.
    points : int
        Number of speeds when ``speeds`` is not given.
    log : bool
        Logarithmic speed and dissipation axes (default); False: linear axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    with _style():
        return _figure_motor(M, delta, P0, k11, friction, speeds, points, log)


def _figure_motor(M, delta, P0, k11, friction, speeds, points, log):
    from matplotlib.lines import Line2D
    from matplotlib.ticker import LogLocator
    from matplotlib.transforms import blended_transform_factory

    from .motor import Motor

    motor = Motor(M=M, delta=delta, P0=P0, k11=k11)
    unit = motor.separation_speed()
    friction = [float(f) for f in friction]
    if speeds is None:
        speeds = _motor_speeds(motor, friction,
                               _checks.positive_int("points", points, 3))
    speeds = _checks.finite_array("speeds", speeds, nonneg=True)
    fig = _figure(figsize=(COLUMN_WIDTH, 3.5), layout="constrained")
    fig.get_layout_engine().set(w_pad=0.03, h_pad=0.03)
    ax = fig.subplots()
    if log:
        ax.set_xscale("log")
        ax.set_yscale("log", nonpositive="clip")
    n = len(friction)
    curves, tops = [], []
    on_axis = blended_transform_factory(ax.transData, ax.transAxes)
    for i, (f, color) in enumerate(zip(friction, _ramp(n))):
        W = 1e3 * motor.dissipation(speeds, f)
        tops.append(float(W.max()) if W.size else 0.0)
        style = _curve_style(i, n, min(len(speeds), points))
        style["markevery"] = _log_markevery(speeds, i, n) if log else style["markevery"]
        line, = ax.plot(speeds, W, lw=1.2, color=color, label=f"f = {f:g}", **style)
        curves.append(line)
        ax.plot([motor.shakedown_speed(f)], [0.0], ls="", marker="|", ms=9, mew=1.4, color=color,
                transform=on_axis, clip_on=False, zorder=5, label="_shakedown")
    ax.axvline(unit, color="0.35", ls="--", lw=0.9, zorder=1)
    positive = speeds[speeds > 0]
    low = positive.min() if log and positive.size else speeds.min()
    ax.set_xlim(low, speeds.max())
    top = max(tops) if tops and max(tops) > 0 else 1.0
    if log:
        ax.set_ylim(top * 1e-5, top * 3.0)
        ax.yaxis.set_major_locator(LogLocator(numticks=10))
    else:
        ax.set_ylim(0, 1.05 * top)
    ax.set_xlabel(r"rotational speed $\Omega$ [rad/s]", labelpad=2)
    ax.set_ylabel(r"dissipation per revolution $W$ [mJ]", labelpad=2)
    sec = ax.secondary_xaxis("top", functions=(lambda w: w / unit, lambda s: s * unit))
    sec.set_xlabel(r"$\Omega \sqrt{M\delta / P_0}$", labelpad=3)
    if log:
        from matplotlib.ticker import FixedLocator, ScalarFormatter

        sec.xaxis.set_major_locator(FixedLocator([0.25, 0.5, 1, 2, 3]))
        sec.xaxis.set_major_formatter("{x:g}")
        sec.xaxis.set_minor_locator(FixedLocator([]))
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(_minor_speed_formatter())
    ax.grid(alpha=0.25, which="major")
    # the curves' legend in the empty upper left (log axes: W is small at low speed); the
    # marks' legend below the axes
    ax.legend(handles=curves, loc="upper left", frameon=True, framealpha=0.9, edgecolor="none",
              handlelength=2.8, borderaxespad=0.4)
    fig.legend([Line2D([], [], ls="", marker="|", ms=9, mew=1.4, color="black"),
                Line2D([], [], color="0.35", ls="--", lw=0.9)],
               ["shakedown speed (W = 0 below)", "separation begins"],
               loc="outside lower center", ncols=2, frameon=False, handlelength=2.2,
               columnspacing=1.0)
    ax.set_title(rf"motor: $M$ = {M:g} kg, $\delta$ = {1e3 * delta:g} mm, $P_0$ = {_sci(P0)} N,"
                 "\n" rf"$k_{{11}}$ = ${_sci(k11)}$ N/m, $\varphi = \pi/2$",
                 fontsize=_SMALL + 0.5, pad=4)
    return _finish(fig)


def _log_markevery(speeds, i: int, n: int):
    """Marker positions evenly spaced on a log speed axis, offset per curve."""
    positive = speeds[speeds > 0]
    if positive.size < 2:
        return None
    marks = np.geomspace(positive.min(), positive.max(), 7)[:-1]
    shift = (np.log(marks[1]) - np.log(marks[0])) * (i + 0.5) / max(n, 1)
    marks = np.exp(np.log(marks) + shift)
    return sorted({int(np.argmin(np.abs(speeds - m))) for m in marks})


def _minor_speed_formatter():
    """Labels on a few minor ticks of a log speed axis (200, 500) so that it reads easily."""
    from matplotlib.ticker import FuncFormatter

    def fmt(x, _pos):
        mantissa = x / 10 ** math.floor(math.log10(x)) if x > 0 else 0
        return f"{x:g}" if round(mantissa, 6) in (2.0, 5.0) else ""

    return FuncFormatter(fmt)


# -- writing files ---------------------------------------------------------------------------------
def _save(fig, out_dir: Path, name: str, formats) -> list[Path]:
    paths = []
    for fmt in formats:
        path = out_dir / f"{name}.{fmt}"
        with _style():
            fig.savefig(path, dpi=DPI)
        if fig.get_layout_engine() is not None:
            fig.set_layout_engine("none")  # laid out by the first save: keep it (faster)
        paths.append(path)
    return paths


def write_figures(out_dir, grid: int = 101, points: int = 361, formats=("png", "pdf"),
                  data=None, progress=None, **sweep_options) -> list[Path]:
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
        Passed to :func:`lcpfric.sweep.sweep` for the maps (``scheduler``, ``processes``...).

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
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("out", f"{out_dir} exists and is not a directory")
    out_dir.mkdir(parents=True, exist_ok=True)
    say = progress if progress is not None else (lambda message: None)
    if data is None:
        t0 = time.perf_counter()
        ds = map_data(grid, **sweep_options)
        say(f"maps: Ŵ on {grid}x{grid} points x {ds.sizes['phi']} phases "
            f"({time.perf_counter() - t0:.1f} s)")
    else:
        ds = data
    figures = {
        "fig3_map_phi0": lambda: figure_maps(ds, [0.0]),
        "fig4_maps": lambda: figure_maps(ds, FIG4_PHASES, ncols=5),
        "fig5_phase_P1_0.5": lambda: figure_phase(0.5, FIG5_Q1, points,
                                                  r"$\hat P_1 = 0.5$ (full contact)"),
        "fig6_phase_P1_Q1_5": lambda: figure_phase(5.0, (5.0,), points,
                                                   r"$\hat P_1 = \hat Q_1 = 5$"),
        "fig7_phase_P1_1.5": lambda: figure_phase(1.5, FIG7_Q1, points,
                                                  r"$\hat P_1 = 1.5$ (separation)"),
        "fig9_motor": lambda: figure_motor(points=points),
    }
    written = []
    for k, (name, make) in enumerate(figures.items(), 1):
        t0 = time.perf_counter()
        fig = make()
        paths = _save(fig, out_dir, name, formats)
        written += paths
        width, height = fig.get_size_inches()
        say(f"[{k}/{len(figures)}] {name}: {', '.join(p.suffix[1:] for p in paths)}, "
            f"{width:.2f} x {height:.2f} in ({time.perf_counter() - t0:.1f} s)")
    return written
