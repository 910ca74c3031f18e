"""The hysteresis loop of a steady state as a figure (:func:`figure_loop`): F against v over the
steady cycle, each increment in its state's colour (:mod:`lcpfric.analysis.loop`)."""

from __future__ import annotations

import numpy as np

from ..analysis.loop import HysteresisLoop
from ..results import State

__all__ = ["figure_loop", "STATE_STYLES"]

STATE_STYLES = {
    State.STICK: ("stick", "#1b4f9c", "-"),
    State.FORWARD: ("forward slip", "#d1495b", "-"),
    State.BACKWARD: ("backward slip", "#e39b2d", "--"),
    State.SEPARATION: ("separation (F = 0)", "0.45", ":"),
}


def figure_loop(loop: HysteresisLoop, title: str | None = None, units: tuple = ("", "")):
    """The loop as a one-column figure: F against v, each increment drawn in its state's colour
    and line style, the enclosed area stated in the legend title."""
    from .style import COLUMN_WIDTH, figure, finish, style

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
        vu, fu = units
        ax.set_xlabel(f"tangential displacement v{f' [{vu}]' if vu else ''}")
        ax.set_ylabel(f"friction force F{f' [{fu}]' if fu else ''}")
        ax.grid(True, alpha=0.3)
        ax.legend(
            title=f"enclosed area -∮F dv = {loop.area:.6g}\n(W per cycle = {loop.W:.6g})",
            loc="upper center",
            bbox_to_anchor=(0.5, -0.22),
            ncol=2,
            frameon=False,
        )
        if title:
            ax.set_title(title)
        return finish(fig)
