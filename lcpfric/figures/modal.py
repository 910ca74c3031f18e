"""The amplitude-dependent frequency and damping of jointed structures as a figure
(:func:`figure_modal_damping`): ω(a)/ω0 and ζ(a) against the modal amplitude, relative to the
amplitude of the first slip, on a log axis (:mod:`lcpfric.analysis.modal`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .style import COLUMN_WIDTH, SMALL, figure, finish, style

if TYPE_CHECKING:
    from collections.abc import Sequence

    from ..analysis.modal import ModalDamping

__all__ = ["figure_modal_damping"]

#: (colour, line style, marker) of successive computed curves
_LOOKS = (("#08519c", "none", "o"), ("#a63603", "--", "s"), ("#238b45", "-.", "^"))


def figure_modal_damping(
    curves: Sequence[tuple[str, ModalDamping]],
    closed_form: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
    title: str = "",
):
    """Two panels, a column wide: (a) ω(a)/ω0 and (b) ζ(a) against ``a / a_slip``, log axis.

    Parameters
    ----------
    curves : sequence of (str, ModalDamping)
        Labelled results of :func:`lcpfric.analysis.modal.modal_damping`; each is drawn
        against its own ``a / a_slip`` (the first curve as markers only, so that a closed form
        under it shows).
    closed_form : (a / a_slip, ω/ω0, ζ), optional
        A closed form drawn as a thin black line (the one-mass oscillator's,
        :func:`lcpfric.analysis.modal.jenkins_oscillator`).
    title : str, optional
        A title over the figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (its ``savefig`` embeds TrueType fonts).
    """
    with style():
        fig = figure(figsize=(COLUMN_WIDTH, 3.9))
        ax, bx = fig.subplots(2, 1, sharex=True)
        if closed_form is not None:
            x, ratio, zeta = (np.asarray(v, dtype=float) for v in closed_form)
            for axis, y in ((ax, ratio), (bx, zeta)):
                axis.plot(x, y, "-", color="black", lw=0.9, label="closed form", zorder=3)
        for i, (label, res) in enumerate(curves):
            colour, ls, marker = _LOOKS[i % len(_LOOKS)]
            x = res.a / res.a_slip
            every = max(len(x) // 12, 1) if ls != "none" else 1
            for axis, y in ((ax, res.omega_ratio), (bx, res.zeta)):
                axis.plot(x, y, ls=ls, marker=marker, color=colour, ms=3.2, mew=0.7,
                          mfc="none", markevery=every, label=label, zorder=2)  # fmt: skip
        ax.set_xscale("log")
        ax.set_ylabel(r"$\omega(a)\,/\,\omega_0$")
        ax.set_title("(a) frequency", loc="left")
        bx.set_ylabel(r"damping ratio $\zeta(a)$")
        bx.set_title("(b) damping", loc="left")
        bx.set_xlabel(r"modal amplitude $a\,/\,a_{\mathrm{slip}}$")
        bx.set_ylim(bottom=0.0)
        for axis in (ax, bx):
            axis.grid(True, which="major", alpha=0.3)
        ax.legend(loc="upper right", fontsize=SMALL, frameon=False)
        if title:
            fig.suptitle(title)
        fig.subplots_adjust(left=0.17, right=0.97, top=0.94, bottom=0.11, hspace=0.32)
        return finish(fig)
