"""The start dependence of a coupled system's steady dissipation as a figure
(:func:`figure_start_dependence`): W over the plane of the two nodes' start mobilization ratios,
with the starts that shake down marked, and the range of W over the starts against the coupling
strength (:mod:`lcpfric.analysis.starts`)."""

from __future__ import annotations

import numpy as np

from .style import CMAP, PAGE_WIDTH, SMALL, figure, finish, style

__all__ = ["figure_start_dependence"]


def figure_start_dependence(r, W, shakedown, scales, W_min, W_max, share, title: str = ""):
    """Two panels, a page wide: (a) the steady W over the start ratios ``(r1, r2)`` of a
    two-node system, the starts that shake down hatched; (b) the range of the steady W over
    random starts against the coupling factor c (``B -> c B``), with the share of the starts
    that shake down.

    Parameters
    ----------
    r : (m,) array_like
        The ratios of each axis (:func:`lcpfric.analysis.starts.start_map`).
    W : (m, m) array_like
        ``W[i, j]`` from the start ``(r[j], r[i])``; NaN where not admissible.
    shakedown : (m, m) bool array_like
        The starts from which no node slips in the steady cycle.
    scales, W_min, W_max, share : (k,) array_like
        The coupling factors and, per factor, the range of W and the shakedown share
        (:func:`lcpfric.analysis.starts.coupling_band`).
    title : str, optional
        A title over the figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (its ``savefig`` embeds TrueType fonts).
    """
    with style():
        r, W = np.asarray(r, dtype=float), np.asarray(W, dtype=float)
        still = np.asarray(shakedown, dtype=bool)
        fig = figure(figsize=(PAGE_WIDTH, 2.7))
        ax, bx = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.0, 1.15], "wspace": 0.45})
        top = float(np.nanmax(W)) if np.any(np.isfinite(W)) else 1.0
        mesh = ax.pcolormesh(r, r, W, cmap=CMAP, vmin=0.0, vmax=top, shading="nearest")
        if still.any():
            ax.contourf(r, r, still.astype(float), levels=[0.5, 1.5], colors="none",
                        hatches=["////"])  # fmt: skip
            ax.contour(r, r, still.astype(float), levels=[0.5], colors="white", linewidths=0.8)
        cb = fig.colorbar(mesh, ax=ax, pad=0.03)
        cb.set_label("steady W per cycle")
        cb.ax.tick_params(labelsize=SMALL)
        ax.set_xlabel(r"start ratio $r_1 = F_1(0)\,/\,(f_1N_1(0))$")
        ax.set_ylabel(r"start ratio $r_2$")
        ax.set_aspect("equal")
        from matplotlib.patches import Patch

        ax.legend(
            handles=[
                Patch(
                    facecolor="none", edgecolor="black", hatch="////", label="shakes down (W = 0)"
                )
            ],  # fmt: skip
            loc="upper center",
            bbox_to_anchor=(0.5, -0.2),
            fontsize=SMALL,
            frameon=False,
        )
        ax.set_title("(a) W from each start", loc="left")
        c = np.asarray(scales, dtype=float)
        lo, hi = np.asarray(W_min, dtype=float), np.asarray(W_max, dtype=float)
        bx.fill_between(c, lo, hi, color="#9ecae1", label="range of W over the starts")
        bx.plot(c, hi, "-", color="#08519c", marker="o", ms=3, label="largest W")
        bx.plot(c, lo, "--", color="#08519c", marker="s", ms=3, label="smallest W")
        bx.set_xlabel(r"coupling factor $c$ ($B \to cB$; 0: uncoupled)")
        bx.set_ylabel("steady W per cycle")
        bx.set_ylim(bottom=0.0)
        tx = bx.twinx()
        tx.plot(c, np.asarray(share, dtype=float), ":", color="#a63603", marker="^", ms=3,
                label="share of starts that shake down")  # fmt: skip
        tx.set_ylim(0.0, 1.0)
        tx.set_ylabel("shakedown share", color="#a63603")
        tx.tick_params(axis="y", colors="#a63603", labelsize=SMALL)
        h1, l1 = bx.get_legend_handles_labels()
        h2, l2 = tx.get_legend_handles_labels()
        bx.legend(h1 + h2, l1 + l2, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2,
                  fontsize=SMALL, frameon=False)  # fmt: skip
        bx.set_title("(b) W against the coupling", loc="left")
        if title:
            fig.suptitle(title)
        fig.subplots_adjust(bottom=0.33, top=0.88, left=0.08, right=0.92)
        return finish(fig)
