"""The maps of the paper's Figs. 3 and 4: Ŵ(P̂1, Q̂1) at fixed φ, with the exact shakedown
boundary (the zero contour of :func:`~lcpfric.analysis.shakedown.shakedown_margin`, computed on a
finer grid than the map), the line P̂1 = 1 and the no-slip region at φ = 0 and π."""

from __future__ import annotations

import math

import numpy as np

from .. import _checks
from ..figures.style import COLUMN_WIDTH, PAGE_WIDTH, PI
from ..figures.style import CMAP as _CMAP
from ..figures.style import NORMAL as _NORMAL
from ..figures.style import SMALL as _SMALL
from ..figures.style import figure as _figure
from ..figures.style import finish as _finish
from ..figures.style import phi_label as _phi_label
from ..figures.style import style as _style

__all__ = ["FIG4_PHASES", "map_data", "figure_maps"]

FIG4_PHASES = tuple(k * PI / 10 for k in range(1, 11))
_BOUNDARY = {"colors": "#e8402a", "linewidths": 1.8}  # the shakedown boundary: red, solid
_NO_SLIP_HATCH = "////"


def map_data(grid: int = 101, extent: float = 10.0, phases=None, **sweep_options):
    """The maps of Figs. 3 and 4: Ŵ on ``grid x grid`` points of [0, extent]² at
    ``phases`` (default φ = kπ/10, k = 0..10), as an ``xarray.Dataset`` from
    :func:`lcpfric.analysis.sweep.sweep`."""
    from ..analysis.sweep import sweep

    grid = _checks.positive_int("grid", grid, minimum=3)
    extent = _checks.positive("extent", extent)
    axis = np.linspace(0.0, extent, grid)
    phases = (0.0, *FIG4_PHASES) if phases is None else phases
    sweep_options.setdefault("progress", False)
    return sweep(axis, axis, phases, **sweep_options)


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
    return np.array(levels[: end + 1]), True


def _luminance(rgba) -> float:
    r, g, b = rgba[:3]
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def _boundary_effects():
    """A thin dark outline around the (red) shakedown boundary, so that it stands out on every
    colour of the map, also in greyscale."""
    from matplotlib import patheffects

    return [
        patheffects.Stroke(linewidth=_BOUNDARY["linewidths"] + 1.0, foreground="0.1"),
        patheffects.Normal(),
    ]


def _separation_line(ax, x: float = 1.0):
    """The line P̂1 = 1: black dashes on a white line, visible on dark and light colours."""
    ax.axvline(x, color="white", lw=1.3, zorder=3)
    ax.axvline(x, color="black", lw=1.3, ls=(0, (3, 2)), zorder=3.1)


def _separation_handle():
    from matplotlib.lines import Line2D

    return (
        Line2D([], [], color="white", lw=1.3),
        Line2D([], [], color="black", lw=1.3, ls=(0, (3, 2))),
    )


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


def _draw_map(
    ax,
    W2d,
    P1,
    Q1,
    phi,
    levels,
    norm,
    boundary_points: int = 401,
    line_levels=None,
    label_levels=None,
):
    from matplotlib.patches import Polygon

    from ..analysis.shakedown import shakedown_margin

    filled = ax.contourf(P1, Q1, W2d.T, levels=levels, cmap=_CMAP, norm=norm)
    line_levels = [
        v
        for v in (levels[1:-1] if line_levels is None else line_levels)
        if levels[0] < v < W2d.max()
    ]
    if line_levels:
        colors = [
            "white" if _luminance(filled.cmap(norm(v))) < 0.45 else "black" for v in line_levels
        ]
        lines = ax.contour(
            P1, Q1, W2d.T, levels=line_levels, colors=colors, linewidths=0.45, alpha=0.75
        )
        shown = [v for v in line_levels if label_levels is None or v in label_levels]
        spots = _label_spots(lines, shown, (P1.min(), P1.max()), (Q1.min(), Q1.max()))
        if spots:
            ax.clabel(
                lines,
                levels=[v for v, _ in spots],
                fmt="%g",
                fontsize=_SMALL,
                inline_spacing=2,
                manual=[xy for _, xy in spots],
            )
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
        ax.add_patch(
            Polygon(
                [(1, 0), (big, 0), (big, big), (1, 1)],
                closed=True,
                facecolor="none",
                edgecolor="white",
                hatch=_NO_SLIP_HATCH,
                lw=0,
                alpha=0.55,
                zorder=2,
            )
        )
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

    handles = [
        Line2D(
            [],
            [],
            color=_BOUNDARY["colors"],
            lw=_BOUNDARY["linewidths"],
            path_effects=_boundary_effects(),
        ),
        _separation_handle(),
    ]
    labels = [
        r"shakedown boundary ($\hat W$ = 0 inside)",
        r"$\hat P_1 = 1$ (separation for $\hat P_1 > 1$)",
    ]
    if no_slip:
        handles.append(Patch(facecolor=cmap_low, edgecolor="white", hatch=_NO_SLIP_HATCH, lw=0))
        labels.append(
            r"$\hat W$ = 0 without shakedown: $\hat Q_1 \leq \hat P_1$, no slip "
            r"(φ = 0, π)"
        )
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
        A dataset from :func:`lcpfric.analysis.sweep.sweep` (coordinates ``phi``, ``P1``, ``Q1``).
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
    norm = BoundaryNorm(levels, cmap.N) if uneven else Normalize(vmin=levels[0], vmax=levels[-1])
    if single:
        width, height = COLUMN_WIDTH, 3.5 + (0.2 if title else 0.0)
    else:
        panel = (PAGE_WIDTH - 1.35) / ncols  # room for the Q̂1 label and the colour bar
        height = nrows * (panel + 0.2) + 0.55 + (0.2 if title else 0.0)
        width = PAGE_WIDTH
    fig = _figure(figsize=(width, height), layout="constrained")
    fig.get_layout_engine().set(w_pad=0.02, h_pad=0.02, wspace=0.0 if single else 0.06, hspace=0.02)
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
        filled, ns = _draw_map(
            ax,
            w.transpose("P1", "Q1").values,
            P1,
            Q1,
            float(w["phi"]),
            levels,
            norm,
            line_levels=line_levels,
            label_levels=label_levels,
        )
        no_slip |= ns
        if extent >= 4:
            step = 2.0 if single else 5.0
            ax.xaxis.set_major_locator(MultipleLocator(step))
            ax.yaxis.set_major_locator(MultipleLocator(step))
            if not single:
                ax.xaxis.set_minor_locator(MultipleLocator(1.0))
                ax.yaxis.set_minor_locator(MultipleLocator(1.0))
    for ax in axes.flat[len(panels) :]:
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
        bar = fig.colorbar(
            filled, cax=axes[0, 0].inset_axes([1.05, 0.0, 0.06, 1.0]), label=label, spacing=spacing
        )
    else:
        bar = fig.colorbar(
            filled, ax=axes, label=label, shrink=0.95, aspect=30, pad=0.02, spacing=spacing
        )
    bar.set_ticks(levels if uneven else levels[::2])
    bar.ax.yaxis.set_major_formatter("{x:g}")
    bar.ax.minorticks_off()
    bar.outline.set_linewidth(0.5)
    handles, labels = _map_legend_handles(no_slip, cmap(0.0))
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=1 if single else len(handles),
        frameon=False,
        handler_map={tuple: HandlerTuple(ndivide=1)},
        handlelength=2.4,
    )
    if title:
        fig.suptitle(title, fontsize=_NORMAL + 1)
    return _finish(fig)
