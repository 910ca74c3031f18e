"""The dynamic single node through resonance as a figure (:func:`figure_dynamic_node`): the
dissipation per cycle Ŵ and the displacement amplitude against the frequency ratio β = ω/Ω0 for
several damping ratios, with the quasi-static Ŵ and Den Hartog's closed form marked; a journal
column wide (:mod:`lcpfric.exact.dynamic`)."""

from __future__ import annotations

import numpy as np

from .describing import CURVES
from .style import COLUMN_WIDTH, SMALL, figure, finish, style

__all__ = ["figure_dynamic_node", "figure_motor_dynamic", "figure_frequency_response"]


def figure_dynamic_node(beta, curves, quasi_static: float, den_hartog=None, title: str = ""):
    r"""Two panels, one above the other: (a) Ŵ, (b) the amplitude ``k11 X / Q1`` against β
    (log axes), one curve per damping ratio; the quasi-static Ŵ a dotted line in (a); Den
    Hartog's closed form (ζ = 0, constant N, no stops) open circles.

    Parameters
    ----------
    beta : array_like
        The frequency ratios of the curves.
    curves : sequence of (str, array_like, array_like)
        Label, Ŵ and the amplitude ``k11 X / Q1`` at each β.
    quasi_static : float
        The quasi-static Ŵ (β -> 0).
    den_hartog : tuple of (array_like, array_like, array_like), optional
        β, Ŵ and amplitude of the closed form.
    title : str, optional
        The load case, in the top panel's title.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (its ``savefig`` embeds TrueType fonts).
    """
    b = np.asarray(beta, dtype=float)
    with style():
        fig = figure(figsize=(COLUMN_WIDTH, 4.3), layout="constrained")
        ax, bx = fig.subplots(2, 1, sharex=True)
        for i, (label, W, X) in enumerate(curves):
            colour, ls = CURVES[i % len(CURVES)]
            ax.plot(b, W, ls=ls, color=colour, label=label)
            bx.plot(b, X, ls=ls, color=colour, label=label)
        ax.axhline(quasi_static, color="0.45", lw=0.8, ls=":", label="quasi-static")
        if den_hartog is not None:
            db, dW, dX = (np.asarray(x, dtype=float) for x in den_hartog)
            kw = dict(ls="none", marker="o", ms=3.4, mfc="none", mew=0.7, color="black",
                      label="Den Hartog")  # fmt: skip
            ax.plot(db, dW, **kw)
            bx.plot(db, dX, **kw)
        for axes in (ax, bx):
            axes.set_xscale("log")
            axes.axvline(1.0, color="0.6", lw=0.6, ls=":")
            axes.grid(True, which="major", color="0.88", lw=0.5)
            axes.set_yscale("log")
        ax.set_ylabel(r"dissipation $\hat W$")
        bx.set_ylabel(r"amplitude $k_{11} X / Q_1$")
        bx.set_xlabel(r"frequency ratio $\beta = \omega / \Omega_0$")
        ax.set_title(f"(a) dissipation per cycle{title}", loc="left")
        bx.set_title("(b) displacement amplitude", loc="left")
        ax.legend(loc="upper left", fontsize=SMALL, frameon=False)
        return finish(fig)


def figure_motor_dynamic(ratio, rows, zeta: float, band: float = 0.05):
    r"""The paper's motor (Fig. 9) through resonance: (a) W per revolution against Ω/Ω0 for
    each friction coefficient, dynamic (solid) and quasi-static (dotted, same colour), log axes;
    (b) the quasi-static estimate's relative error ``W_qs / W - 1`` with the ±``band`` band.

    Parameters
    ----------
    ratio : array_like
        Ω/Ω0 of the curves.
    rows : sequence of (float, array_like, array_like)
        f, the dynamic W and the quasi-static W [J] at each ratio.
    zeta : float
        The damping ratio (in the title).
    band : float, optional
        The tolerance band drawn in (b).

    Returns
    -------
    matplotlib.figure.Figure
        The figure (its ``savefig`` embeds TrueType fonts).
    """
    from .style import ramp

    r = np.asarray(ratio, dtype=float)
    colours = ramp(len(rows))
    with style():
        fig = figure(figsize=(COLUMN_WIDTH, 4.6), layout="constrained")
        ax, bx = fig.subplots(2, 1, sharex=True)
        for colour, (f, W, Wqs) in zip(colours, rows):
            W, Wqs = np.asarray(W, dtype=float), np.asarray(Wqs, dtype=float)
            pos = W > 0
            ax.plot(r[pos], 1e3 * W[pos], color=colour, lw=1.1, label=f"$f = {f:g}$")
            ax.plot(r[Wqs > 0], 1e3 * Wqs[Wqs > 0], color=colour, lw=0.9, ls=":")
            with np.errstate(divide="ignore", invalid="ignore"):
                err = np.where(pos, Wqs / W - 1.0, np.nan)
            bx.plot(r, 100.0 * err, color=colour, lw=1.0)
        ax.plot([], [], color="0.3", ls=":", lw=0.9, label="quasi-static")
        bx.axhspan(-100 * band, 100 * band, color="0.9", lw=0)
        for axes in (ax, bx):
            axes.set_xscale("log")
            axes.axvline(1.0, color="0.6", lw=0.6, ls=":")
            axes.grid(True, which="major", color="0.88", lw=0.5)
        ax.set_yscale("log")
        bx.set_yscale("symlog", linthresh=10.0)
        ax.set_ylabel("W per revolution [mJ]")
        bx.set_ylabel(r"$W_\mathrm{qs}/W - 1$ [%]")
        bx.set_xlabel(r"speed ratio $\Omega / \Omega_0$")
        ax.set_title(rf"(a) dissipation, $\zeta = {zeta:g}$", loc="left")
        bx.set_title(rf"(b) quasi-static error (band $\pm{100 * band:g}$ %)", loc="left")
        ax.legend(loc="upper left", fontsize=SMALL, frameon=False, ncol=2)
        return finish(fig)


def figure_frequency_response(res, title: str = ""):
    r"""A frequency response (:class:`~lcpfric.analysis.frequency_response.FrequencyResponse`)
    in three panels, one above the other: (a) W, (b) the amplitude, (c) the phase against ω
    (Ω0 marked); unstable orbits as open circles.

    Parameters
    ----------
    res : FrequencyResponse
        The response.
    title : str, optional
        Appended to the top panel's title.

    Returns
    -------
    matplotlib.figure.Figure
        The figure (its ``savefig`` embeds TrueType fonts).
    """
    w = np.asarray(res.omega)
    omega0 = float(np.median(w / np.asarray(res.beta)))
    colour = CURVES[0][0]
    with style():
        fig = figure(figsize=(COLUMN_WIDTH, 5.2), layout="constrained")
        ax, bx, cx = fig.subplots(3, 1, sharex=True)
        for axes, y in ((ax, res.W), (bx, res.amplitude), (cx, res.phase)):
            axes.plot(w, y, color=colour, lw=1.1, marker="." if w.size < 40 else None, ms=3)
            bad = ~np.asarray(res.stable)
            if bad.any():
                axes.plot(w[bad], np.asarray(y)[bad], ls="none", marker="o", ms=3.4, mfc="none",
                          mew=0.7, color="black", label="unstable orbit")  # fmt: skip
            axes.axvline(omega0, color="0.6", lw=0.6, ls=":")
            axes.grid(True, which="major", color="0.88", lw=0.5)
        if w.max() > w.min() * 20:
            for axes in (ax, bx, cx):
                axes.set_xscale("log")
        if np.all(np.asarray(res.W) > 0) and res.W.max() > 50 * res.W.min():
            ax.set_yscale("log")
        if res.amplitude.max() > 50 * res.amplitude.min() > 0:
            bx.set_yscale("log")
        cx.set_yticks([0.0, np.pi / 2, np.pi], ["0", r"$\pi/2$", r"$\pi$"])
        ax.set_ylabel("W per cycle")
        bx.set_ylabel("amplitude")
        cx.set_ylabel("phase lag")
        cx.set_xlabel(r"forcing frequency $\omega$ ($\Omega_0$ dotted)")
        ax.set_title(f"(a) dissipation{title}", loc="left")
        bx.set_title("(b) amplitude (max v - min v)/2", loc="left")
        cx.set_title(r"(c) lag of $v$ behind $-Q$", loc="left")
        if (~np.asarray(res.stable)).any():
            ax.legend(loc="upper left", fontsize=SMALL, frameon=False)
        return finish(fig)


def figure_hb_shooting(hb_omega, hb_amplitude, omega, amplitude, difference, harmonics: int):
    r"""A structure's frequency response by harmonic balance (a curve) and by shooting (points),
    and the relative difference of the two at the points.

    Parameters
    ----------
    hb_omega, hb_amplitude : array_like
        The harmonic balance's curve: ω and the first harmonic's amplitude of one degree of
        freedom.
    omega, amplitude : array_like
        Shooting's points: ω and the same amplitude.
    difference : array_like
        The relative difference at shooting's points.
    harmonics : int
        The harmonic balance's H (for the legend).

    Returns
    -------
    matplotlib.figure.Figure
        The figure (its ``savefig`` embeds TrueType fonts).
    """
    with style():
        fig = figure(figsize=(COLUMN_WIDTH, 3.6), layout="constrained")
        ax, bx = fig.subplots(2, 1, sharex=True, height_ratios=(2.2, 1))
        ax.plot(hb_omega, hb_amplitude, color=CURVES[0][0], lw=1.0,
                label=f"harmonic balance\n(H = {harmonics})")  # fmt: skip
        ax.plot(omega, amplitude, ls="none", marker="o", ms=3.2, mfc="none", mew=0.8,
                color="black", label="shooting")  # fmt: skip
        ax.set_ylabel("amplitude, 1st harmonic")
        ax.set_title("(a) the last mass", loc="left")
        ax.legend(loc="center right", fontsize=SMALL, frameon=False)
        ax.grid(True, color="0.88", lw=0.5)
        bx.semilogy(omega, difference, ls="none", marker="s", ms=2.6, color="black")
        bx.axhline(1e-3, color="0.5", lw=0.6, ls="--")
        bx.set_ylabel("difference")
        bx.set_xlabel(r"forcing frequency $\omega$")
        bx.set_title("(b) |HB - shooting| / |HB| (dashed: 1e-3)", loc="left")
        bx.grid(True, color="0.88", lw=0.5)
        return finish(fig)
