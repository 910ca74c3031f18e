"""Figures of the three-dimensional half-space contact (:class:`~.halfspace.HalfSpace`), sized
and styled like the paper's (:mod:`lcpfric.figures.style`).

* :func:`figure_zone_maps`: the grid's elements coloured by their state (stick, slip towards +x
  or -x, separated) at a few instants of the cycle, with the contact edge, each panel titled
  with t/T, P/P0 and Q/(μ P0);
* :func:`figure_traction_vectors` (``dims = 2``): the shear tractions at one instant as
  arrows, over the ratio ``|F|/(μ p h²)`` of each element (1: slipping), with the contact edge
  and the edge of the stick zone;
* :func:`animate_zones`: the zone map over the cycle as an animated GIF.

:func:`write_halfspace_figures` writes the first two. Every function needs the steady state
solved with ``record=True``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from ..errors import InputError
from . import halfspace_panels as panels
from .style import COLUMN_WIDTH, PAGE_WIDTH, SMALL, figure, finish, save, style

__all__ = [
    "figure_zone_maps",
    "figure_traction_vectors",
    "animate_zones",
    "write_halfspace_figures",
]

#: state colours, in the order of the codes shown (stick, +x, -x, separated); the same as the
#: other contact figures' (:mod:`.contact`), distinct in lightness too (greyscale prints)
ZONE_COLOURS = panels.ZONE_COLOURS
#: colour map of |F|/(μ p h²), cut before its darkest end so that black arrows stay visible
RATIO_CMAP = "YlGnBu"
RATIO_CMAP_TOP = 0.72
#: at most this many arrows across the contact (the grid is subsampled beyond)
MAX_ARROWS_ACROSS = 18
#: default number of frames of the animation (at most; fewer if fewer instants were recorded)
ANIMATION_FRAMES = 60
#: resolution of the animation's frames
ANIMATION_DPI = 110


def figure_zone_maps(model, result, fractions=(0.0, 0.25, 0.5, 0.75), title: str = ""):
    """The elements' states (stick, slipping towards +x or -x, separated) over the grid at the
    recorded instants nearest to ``fractions`` of the period, one panel each (up to four in a
    row, page wide), cropped to the region ever in contact, with the contact edge (and, for
    the sphere, Hertz's contact radius at P(t)); needs ``record=True``."""
    panels.check_result(model, result)
    fractions = [float(f) for f in np.atleast_1d(fractions)]
    if not fractions:
        raise InputError("fractions", "must name at least one instant")
    steps = [panels.index(result, f) for f in fractions]
    with style():
        ncols = min(4, len(steps))
        nrows = math.ceil(len(steps) / ncols)
        width = PAGE_WIDTH if ncols > 1 else COLUMN_WIDTH
        panel = (width - 0.55) / ncols  # square panels; 0.55 in: y labels
        handles = panels.zone_legend(model, panels.edge_handles(model))
        legend_cols = 3 if ncols > 1 else 2
        caption = panels.caption(model)
        lines = caption.count("\n") + 1 + math.ceil(len(handles) / legend_cols)
        # per row: the panel, its two-line title and the x tick labels and label; then the
        # legend (about 0.15 in a line) and the title
        height = nrows * (panel + 0.62) + 0.14 * lines + 0.1 + (0.2 if title else 0.0)
        fig = figure(figsize=(width, height), layout="constrained")
        axes = fig.subplots(nrows, ncols, squeeze=False, sharex=True, sharey=True)
        x, y, w = panels.grid(model)
        half = panels.crop(model, result)
        period = float(result.t[-1])
        for ax, j in zip(axes.flat, steps):
            panels.draw_zones(ax, model, result, j, x, y, w, half)
            panels.ticks(ax)
            ax.set_title(
                panels.loads_label(model, float(result.t[j]), period),
                fontsize=SMALL,
                pad=3,
                linespacing=1.3,
            )
        for ax in axes.flat[len(steps) :]:
            ax.set_visible(False)
        for col in range(ncols):  # x labels on each column's last panel
            last = axes[(len(steps) - 1 - col) // ncols, col]
            last.xaxis.set_tick_params(labelbottom=True)
            last.set_xlabel(r"$x/a_0$", labelpad=1)
        for ax in axes[:, 0]:
            ax.set_ylabel(r"$y/a_0$", labelpad=1)
        fig.legend(
            handles=handles,
            loc="outside lower center",
            ncols=legend_cols,
            frameon=False,
            fontsize=SMALL,
            title=caption,
            title_fontsize=SMALL,
        )
        if title:
            fig.suptitle(title, fontsize=SMALL + 1)
        return finish(fig)


def figure_traction_vectors(model, result, fraction: float = 0.25, title: str = ""):
    """The shear tractions ``q = -F/h²`` at the recorded instant nearest to ``fraction`` of the
    period, as arrows (one per element in contact, every k-th element on large grids) in units
    of ``μ p0``, over each element's ``|F|/(μ p h²)`` (1: slipping), with the contact edge and
    the edge of the stick zone; column wide. Needs ``dims = 2`` and ``record=True``."""
    if model.dims != 2:
        raise InputError(
            "dims",
            f"the traction vectors need the tractions in the plane "
            f"(dims=2); this model has dims={model.dims} (tractions "
            f"along x only): build it with dims=2",
        )
    panels.check_result(model, result)
    j = panels.index(result, fraction, "fraction")
    from ..results import State

    with style():
        from matplotlib import colormaps
        from matplotlib.collections import LineCollection
        from matplotlib.colors import ListedColormap

        N = model.N
        x, y, w = panels.grid(model)
        half = panels.crop(model, result)
        b = model.normal_solution(result.t[j : j + 1])[0][0]
        F = np.asarray(result.F[j], dtype=float).reshape(N * N, 2)
        contact = b > 0.0
        ratio = np.full(N * N, np.nan)
        ratio[contact] = np.hypot(F[contact, 0], F[contact, 1]) / b[contact]
        p0, p0_text = panels.peak_pressure(model)
        q = -F / model.h**2 / (model.mu * p0)  # in units of μ p0
        fig = figure(figsize=(COLUMN_WIDTH, 4.1 + (0.25 if title else 0.0)), layout="constrained")
        ax = fig.add_subplot()
        cmap = ListedColormap(
            colormaps[RATIO_CMAP](np.linspace(0.0, RATIO_CMAP_TOP, 256))
        ).with_extremes(bad="white")
        mesh = ax.pcolormesh(
            x,
            y,
            np.ma.masked_invalid(ratio.reshape(N, N)).T,
            cmap=cmap,
            vmin=0.0,
            vmax=1.0,
            shading="nearest",
            rasterized=True,
        )
        state = result.state[j].reshape(N, N)
        ax.add_collection(
            LineCollection(
                panels.outline(contact.reshape(N, N), x, y, w), colors="black", linewidths=0.8
            )
        )
        stick = (state == int(State.STICK)) & contact.reshape(N, N)
        stick_edge = bool(stick.any()) and bool(np.any(stick != contact.reshape(N, N)))
        if stick_edge:
            ax.add_collection(
                LineCollection(
                    panels.outline(stick, x, y, w),
                    colors="black",
                    linewidths=0.8,
                    linestyles=[(0, (1.2, 1.2))],
                )
            )
        rho = panels.hertz_radius(model, float(np.asarray(model.P(result.t[j]))))
        if rho is not None:
            from matplotlib.patches import Circle

            ax.add_patch(Circle((0.0, 0.0), rho, fill=False, **panels.hertz_style()))
        # arrows: every k-th element (centred on the grid's centre), at most
        # MAX_ARROWS_ACROSS across the contact
        across = (
            max(1, int(np.ptp(np.flatnonzero(contact.reshape(N, N).any(axis=1))))) + 1
            if contact.any()
            else N
        )
        k = max(1, math.ceil(across / MAX_ARROWS_ACROSS))
        c = (N - 1) // 2
        keep = np.zeros((N, N), dtype=bool)
        keep[c % k :: k, c % k :: k] = True
        show = keep.ravel() & contact
        X, Y = np.meshgrid(x, y, indexing="ij")
        mags = np.hypot(q[show, 0], q[show, 1])
        top = float(mags.max()) if mags.size else 1.0
        top = top if top > 0 else 1.0
        # the longest arrow spans 0.9 of the spacing of the arrows
        scale = top / (0.9 * k * w)
        arrows = ax.quiver(
            X.ravel()[show],
            Y.ravel()[show],
            q[show, 0],
            q[show, 1],
            angles="xy",
            scale_units="xy",
            scale=scale,
            pivot="middle",
            color="black",
            width=0.006,
            headwidth=3.5,
            headlength=4.0,
            headaxislength=3.5,
            zorder=3,
        )
        ref = panels.nice(top)
        # the key in the upper right corner, outside the (round) contact
        ax.quiverkey(
            arrows,
            0.9,
            0.94,
            ref,
            rf"{ref:g} $\mu p_0$",
            labelpos="N",
            coordinates="axes",
            fontproperties={"size": SMALL},
            labelsep=0.04,
        )
        ax.set_xlim(-half, half)
        ax.set_ylim(-half, half)
        ax.set_aspect("equal")
        panels.ticks(ax)
        ax.set_xlabel(r"$x/a_0$", labelpad=1)
        ax.set_ylabel(r"$y/a_0$", labelpad=1)
        ax.set_title(
            panels.loads_label(model, float(result.t[j]), float(result.t[-1])).replace("\n", ": "),
            fontsize=SMALL,
            pad=3,
        )
        bar = fig.colorbar(mesh, ax=ax, shrink=0.85, aspect=25, pad=0.02)
        bar.set_label(r"$|q|/(\mu p)$ (1: slipping; white: separated)")
        from matplotlib.lines import Line2D

        handles = [
            Line2D(
                [],
                [],
                ls="none",
                marker=r"$\rightarrow$",
                ms=8,
                color="black",
                label=r"shear traction $q = -F/h^2$ on the element"
                + (f",\none arrow per {k} x {k} elements; " if k > 1 else "\n")
                + p0_text,
            )
        ]
        handles += panels.edge_handles(model, stick_edge=stick_edge)
        fig.legend(
            handles=handles,
            loc="outside lower center",
            ncols=1,
            frameon=False,
            fontsize=SMALL,
            title=panels.caption(model, sides=False),
            title_fontsize=SMALL,
        )
        if title:
            fig.suptitle(title, fontsize=SMALL + 1)
        return finish(fig)


def animate_zones(model, result, path, frames=None, fps: int = 10, progress=None):
    """The zone map (:func:`figure_zone_maps`'s panel) over the last cycle as an animated GIF at
    ``path`` (matplotlib's PillowWriter): ``frames`` instants evenly spread over the recorded
    ones (default: all of them, at most :data:`ANIMATION_FRAMES`), ``fps`` frames a second;
    ``progress(line)``, if given (e.g. a printer to stderr), hears a line at every tenth of the
    frames drawn. Returns the path."""
    path = Path(path)
    if path.suffix.lower() != ".gif":
        raise InputError(
            "path",
            f"the animation is written as a GIF: the file name must end in .gif, got {path.name!r}",
        )
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError("path", f"the directory {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise InputError(
            "path", f"cannot write {str(path)!r}: the directory or the file is not writable"
        )
    fps = float(fps)
    if not math.isfinite(fps) or fps <= 0:
        raise InputError("fps", f"must be > 0, got {fps!r}")
    panels.check_result(model, result)
    recorded = result.t.size - 1  # instants 1..steps (t = T for t = 0)
    if frames is None:
        count = min(recorded, ANIMATION_FRAMES)
    else:
        if isinstance(frames, bool) or int(frames) != frames or int(frames) < 2:
            raise InputError("frames", f"must be a whole number >= 2, got {frames!r}")
        count = min(int(frames), recorded)
    # evenly spread instants over the period, the last frame before the first one repeats
    index = np.unique(np.round(np.linspace(0.0, recorded, count, endpoint=False)).astype(int))
    index[index == 0] = recorded
    index = np.roll(index, -1) if index.size > 1 and index[0] == recorded else index
    with style():
        from matplotlib.animation import FuncAnimation, PillowWriter

        fig = figure(figsize=(COLUMN_WIDTH, 4.6), layout="constrained")
        ax = fig.add_subplot()
        x, y, w = panels.grid(model)
        half = panels.crop(model, result)
        period = float(result.t[-1])
        mesh, edge, circle = panels.draw_zones(ax, model, result, int(index[0]), x, y, w, half)
        panels.ticks(ax)
        ax.set_xlabel(r"$x/a_0$", labelpad=1)
        ax.set_ylabel(r"$y/a_0$", labelpad=1)
        head = ax.set_title(
            panels.loads_label(model, float(result.t[index[0]]), period),
            fontsize=SMALL,
            pad=3,
            linespacing=1.3,
        )
        handles = panels.zone_legend(model, panels.edge_handles(model))
        fig.legend(
            handles=handles,
            loc="outside lower center",
            ncols=2,
            frameon=False,
            fontsize=SMALL,
            title=panels.caption(model),
            title_fontsize=SMALL,
        )
        finish(fig)
        fig.draw_without_rendering()  # the layout, at the first frame
        fig.set_layout_engine("none")  # laid out once: the frames keep it
        N = model.N
        from ..results import State

        def update(j):
            j = int(j)
            state = result.state[j].reshape(N, N)
            mesh.set_array(panels.codes(state).T.ravel())
            edge.set_segments(panels.outline(state != int(State.SEPARATION), x, y, w))
            if circle is not None:
                rho = panels.hertz_radius(model, float(np.asarray(model.P(result.t[j]))))
                circle.set_radius(rho if rho is not None else 0.0)
            head.set_text(panels.loads_label(model, float(result.t[j]), period))
            return mesh, edge, head

        said = [0]

        def drawn(k, total):
            tenth = 10 * (k + 1) // max(total, 1)
            if progress is not None and tenth > said[0]:
                said[0] = tenth
                progress(f"animation {path.name}: frame {k + 1} of {total} ({10 * tenth} %)")

        anim = FuncAnimation(fig, update, frames=[int(i) for i in index], blit=False)
        anim.save(
            str(path), writer=PillowWriter(fps=fps), dpi=ANIMATION_DPI, progress_callback=drawn
        )
    return path


def write_halfspace_figures(
    out_dir,
    model,
    result,
    formats=("png", "pdf"),
    fractions=(0.0, 0.25, 0.5, 0.75),
    progress=None,
) -> list[Path]:
    """Write the zone maps at ``fractions`` of the period (``halfspace-zones``) and, for
    ``dims = 2``, the traction vectors at the first of them with a tangential load (``halfspace-
    tractions``, at the largest |Q| if none has one) of a solved half-space contact into
    ``out_dir``: the paths. ``progress(line)``, if given, hears a line per figure written."""
    panels.check_result(model, result)
    say = progress or (lambda line: None)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = save(figure_zone_maps(model, result, fractions), out_dir, "halfspace-zones", formats)
    say(f"figures: halfspace-zones written to {out_dir}")
    if model.dims == 2:
        T = float(result.t[-1])
        Q = [abs(float(model.Q(f * T))) for f in fractions]
        big = max(Q) > 1e-12 * max(abs(float(model.Q.amplitude)), 1e-300)
        if big:
            fraction = float(fractions[int(np.argmax(np.asarray(Q) > 0.5 * max(Q)))])
        else:
            qs = np.abs(np.asarray(model.Q(result.t), dtype=float))
            fraction = float(result.t[int(np.argmax(qs))] / T)
        paths += save(
            figure_traction_vectors(model, result, fraction),
            out_dir,
            "halfspace-tractions",
            formats,
        )
        say(f"figures: halfspace-tractions written to {out_dir}")
    return paths
