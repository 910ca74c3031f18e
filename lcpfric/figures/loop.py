"""The hysteresis loop of a steady state as a figure (:func:`figure_loop`): F against v over the
steady cycle, each increment in its state's colour (:mod:`lcpfric.analysis.loop`).

The axes are labelled by :func:`loop_labels`: a dimensional single node's F and v are in the
units of its inputs (F in the loads' unit, v in the loads' unit over k11's), a normalized one's
in the units of Eq. (6) where f P0 = k11 = 1 (F̂ = F / (f P0) and k11 v / (f P0) = Q̂1 v̂). The
tick labels are at most six per axis, fewer when they would run into each other at the printed
(one-column) size, with a power of ten of very large or small magnitudes moved into the axis
label (``[10⁻⁴ load units]``).
"""

from __future__ import annotations

import numpy as np

from ..analysis.loop import HysteresisLoop
from ..results import State

__all__ = ["figure_loop", "loop_labels", "STATE_STYLES"]

#: How each state is drawn: (label, colour, line style); greyscale-safe by style.
STATE_STYLES = {
    State.STICK: ("stick", "#1b4f9c", "-"),
    State.FORWARD: ("forward slip", "#d1495b", "-"),
    State.BACKWARD: ("backward slip", "#e39b2d", "--"),
    State.SEPARATION: ("separation (F = 0)", "0.45", ":"),
}

NAMES = ("tangential displacement v", "friction force F")


def loop_labels(model=None) -> tuple[tuple[str, str], tuple[str, str]]:
    """The axis names and units of a loop of ``model``'s steady state, for :func:`figure_loop`.

    Parameters
    ----------
    model : SingleNode or ContactSystem, optional
        The model: a normalized :class:`~lcpfric.model.SingleNode` (``dimensional=False``) gets
        the normalized quantities of Eq. (6) (no units), a dimensional one the units of its
        inputs; any other model (or None) plain names and no units.

    Returns
    -------
    names, units : tuple of (str, str)
        The names and the units of the displacement (x) and force (y) axes.

    Examples
    --------
    >>> from lcpfric import SingleNode
    >>> loop_labels(SingleNode(k11=1e6, f=0.3, P0=100.0, P1=50.0, Q1=20.0))[1]
    ('load / k11 units', 'load units')
    """
    from ..model import SingleNode

    if isinstance(model, SingleNode):
        if not model.dimensional:
            names = (
                r"tangential displacement $k_{11}v\,/\,(fP_0)$",
                r"friction force $\hat{F} = F\,/\,(fP_0)$",
            )
            return names, ("", "")
        return NAMES, ("load / k11 units", "load units")
    return NAMES, ("", "")


def _power(values) -> int:
    """The power of ten taken out of an axis' tick labels: 0 for magnitudes in [1e-3, 1e4)."""
    top = float(np.max(np.abs(values))) if np.size(values) else 0.0
    if not np.isfinite(top) or top == 0.0 or 1e-3 <= top < 1e4:
        return 0
    return int(np.floor(np.log10(top)))


def _label(name: str, unit: str, power: int) -> str:
    scale = "" if power == 0 else f"10$^{{{power}}}$"
    if unit:
        return f"{name} [{scale} {unit}]" if scale else f"{name} [{unit}]"
    return f"{name} [×{scale}]" if scale else name


def _ticks(axis, power: int, bins: int) -> None:
    """At most ``bins + 1`` ticks, labelled in units of ``10**power`` (no offset text)."""
    from matplotlib.ticker import MaxNLocator, ScalarFormatter

    axis.set_major_locator(MaxNLocator(nbins=bins, steps=[1, 2, 2.5, 5, 10]))
    fmt = ScalarFormatter(useOffset=False, useMathText=True)
    fmt.set_powerlimits((power, power) if power else (-1000, 1000))
    axis.set_major_formatter(fmt)
    axis.get_offset_text().set_visible(False)


def _collide(fig, axis) -> bool:
    """Whether two of the axis' tick labels overlap (or nearly: 1 pt apart), as last drawn."""
    boxes = [
        t.get_window_extent() for t in axis.get_ticklabels() if t.get_visible() and t.get_text()
    ]
    lo, hi = ("x0", "x1") if axis.axis_name == "x" else ("y0", "y1")
    boxes.sort(key=lambda b: getattr(b, lo))
    pad = fig.dpi / 72.0
    return any(getattr(a, hi) + pad > getattr(b, lo) for a, b in zip(boxes, boxes[1:]))


def figure_loop(
    loop: HysteresisLoop,
    title: str | None = None,
    units: tuple = ("", ""),
    names: tuple | None = None,
):
    """The loop as a one-column figure: F against v, each increment drawn in its state's colour
    and line style, the enclosed area stated in the legend title.

    Parameters
    ----------
    loop : HysteresisLoop
        The loop (:func:`~lcpfric.analysis.loop.hysteresis_loop`).
    title : str, optional
        The axes' title.
    units : tuple of str, optional
        Units of v and F, written in brackets after the axis names (``("mm", "N")``); empty
        strings for none. A power of ten taken out of the tick labels (magnitudes outside
        [1e-3, 1e4)) joins them: ``[10⁻⁴ mm]``.
    names : tuple of str, optional
        The axis names (x, y); by default ``"tangential displacement v"`` and
        ``"friction force F"``. :func:`loop_labels` gives the names and units of a model.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (3.5 in wide); its ``savefig`` applies the print settings.
    """
    from .style import COLUMN_WIDTH, figure, finish, style

    names = NAMES if names is None else names
    with style():
        fig = figure(figsize=(COLUMN_WIDTH, 3.0), layout="constrained")
        ax = fig.add_subplot()
        # each run of increments in one state is one polyline, so dashes and dots show
        states = loop.state[1:]
        cuts = np.flatnonzero(np.diff(states)) + 1
        drawn = set()
        for a, b in zip(np.r_[0, cuts], np.r_[cuts, states.size]):
            code = State(int(states[a]))
            label, color, ls = STATE_STYLES[code]
            ax.plot(
                loop.v[a : b + 1],
                loop.F[a : b + 1],
                color=color,
                ls=ls,
                lw=1.4,
                label=None if code in drawn else label,
                zorder=3 if code else 2,
            )
            drawn.add(code)
        axes = list(zip((ax.xaxis, ax.yaxis), map(_power, (loop.v, loop.F))))
        for (axis, power), name, unit in zip(axes, names, units):
            axis.set_label_text(_label(name, unit, power))
            _ticks(axis, power, 5)
        ax.grid(True, alpha=0.3)
        handles, texts = ax.get_legend_handles_labels()  # in the order of the states
        order = [s[0] for s in STATE_STYLES.values()]
        ranked = sorted(zip(handles, texts), key=lambda h: order.index(h[1]))
        ax.legend(
            [h for h, _ in ranked],
            [t for _, t in ranked],
            title=f"enclosed area -∮F dv = {loop.area:.6g}\n(W per cycle = {loop.W:.6g})",
            loc="upper center",
            bbox_to_anchor=(0.5, -0.22),
            ncol=2,
            frameon=False,
        )
        if title:
            ax.set_title(title)
        finish(fig)
        bins = [5, 5]
        while True:  # fewer ticks until their labels fit, as laid out at the printed size
            fig.draw_without_rendering()  # lays the figure out and updates the ticks
            crowded = [i for i, (axis, _) in enumerate(axes) if bins[i] > 2 and _collide(fig, axis)]
            if not crowded:
                return fig
            for i in crowded:
                bins[i] -= 1
                _ticks(axes[i][0], axes[i][1], bins[i])
