"""The describing functions of a Jenkins element as a figure (:func:`figure_describing_functions`):
the equivalent stiffness ``k_eq/kt`` and damping ``ω c_eq/kt`` against the amplitude in slip
limits ``a / (μN0/kt)``, log axes, a journal column wide, with the constant-N closed forms
marked (:mod:`lcpfric.analysis.describing`)."""

from __future__ import annotations

import numpy as np

from .style import COLUMN_WIDTH, SMALL, figure, finish, style

__all__ = ["figure_describing_functions"]

#: (colour, line style) of successive curves: distinct in greyscale by style
CURVES = (("#1b4f9c", "-"), ("#d1495b", "--"), ("#2a9d8f", "-."), ("#6d597a", ":"))


def figure_describing_functions(
    curves,
    kt: float,
    slip_limit: float,
    closed=None,
    *,
    stiffness: str = "k_t",
    amplitude_unit: str = r"\mu N_0/k_t",
    limit_text: str = "slip limit (constant N)",
    closed_label: str = "closed form (constant N)",
):
    r"""Two panels, one above the other: (a) ``k_eq/kt``, (b) ``ω c_eq/kt`` against
    ``a/(μN0/kt)``, log axes; where a curve's damping is zero (it sticks) it is not drawn in (b).

    Parameters
    ----------
    curves : sequence of (str, DescribingFunctions)
        Labelled results of :func:`lcpfric.analysis.describing.describing_functions`.
    kt : float
        The tangential stiffness (the curves' unit).
    slip_limit : float
        ``μN0/kt``, the amplitude unit.
    closed : tuple of (array_like, dict), optional
        Amplitudes and :func:`lcpfric.analysis.describing.jenkins_closed_form` of them (or any
        dict with ``c_eq_omega`` and optionally ``k_eq``), marked with open circles.
    stiffness, amplitude_unit : str, optional
        The stiffness unit's and the amplitude unit's TeX (the sphere: ``k_{t0}``,
        ``\mu P_0/k_{t0}``).
    limit_text, closed_label : str, optional
        The text along the line at ``a = slip_limit`` and the closed form's legend entry.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (its ``savefig`` embeds TrueType fonts).
    """
    with style():
        fig = figure(figsize=(COLUMN_WIDTH, 4.3), layout="constrained")
        ax, bx = fig.subplots(2, 1, sharex=True)
        for i, (label, df) in enumerate(curves):
            colour, ls = CURVES[i % len(CURVES)]
            r = df.amplitude / slip_limit
            ax.plot(r, df.k_eq / kt, ls=ls, color=colour, label=label)
            c = np.where(df.c_eq_omega > 0, df.c_eq_omega / kt, np.nan)
            bx.plot(r, c, ls=ls, color=colour, label=label)
        if closed is not None:
            a, cf = closed
            r = np.asarray(a, dtype=float) / slip_limit
            kw = dict(ls="none", marker="o", ms=3.4, mfc="none", mew=0.7, color="black",
                      label=closed_label)  # fmt: skip
            if "k_eq" in cf:
                ax.plot(r, cf["k_eq"] / kt, **kw)
            slips = cf["c_eq_omega"] > 0
            bx.plot(r[slips], cf["c_eq_omega"][slips] / kt, **kw)
        for axes in (ax, bx):
            axes.set_xscale("log")
            axes.set_yscale("log")
            axes.axvline(1.0, color="0.6", lw=0.6, ls=":")
            axes.grid(True, which="major", color="0.88", lw=0.5)
        bx.text(0.94, 0.04, limit_text, rotation=90, fontsize=SMALL, color="0.4",
                va="bottom", ha="right", transform=bx.get_xaxis_transform())  # fmt: skip
        ax.set_ylabel(rf"stiffness $k_\mathrm{{eq}}/{stiffness}$")
        bx.set_ylabel(rf"damping $\omega c_\mathrm{{eq}}/{stiffness}$")
        bx.set_xlabel(rf"amplitude $a\,/\,({amplitude_unit})$")
        ax.set_title("(a) equivalent stiffness", loc="left")
        bx.set_title("(b) equivalent damping", loc="left")
        lo = np.nanmin([np.nanmin(np.where(d.c_eq_omega > 0, d.c_eq_omega, np.nan))
                        for _, d in curves])  # fmt: skip
        bx.set_ylim(bottom=0.5 * lo / kt)
        handles, labels = ax.get_legend_handles_labels()
        if closed is not None and "k_eq" not in closed[1]:  # the marks are in (b) only
            handles += bx.get_legend_handles_labels()[0][-1:]
            labels += [closed_label]
        ax.legend(handles, labels, loc="lower left", fontsize=SMALL, frameon=False)
        return finish(fig)
