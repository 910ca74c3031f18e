"""Curves of the paper: Ŵ against φ (Figs. 5-7) and the motor's dissipation against speed
(Fig. 9)."""

from __future__ import annotations

import math

import numpy as np

from .. import _checks
from ..figures.style import COLUMN_WIDTH, PI
from ..figures.style import NORMAL as _NORMAL
from ..figures.style import SMALL as _SMALL
from ..figures.style import curve_style as _curve_style
from ..figures.style import figure as _figure
from ..figures.style import finish as _finish
from ..figures.style import ramp as _ramp
from ..figures.style import sci as _sci
from ..figures.style import style as _style

__all__ = ["FIG5_Q1", "FIG7_Q1", "MOTOR", "MOTOR_FRICTION", "figure_phase", "figure_motor"]

FIG5_Q1 = (1.0, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0)
FIG7_Q1 = (0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0)
#: The motor drawn in Fig. 9 (SI units): a 20 kg rotor 0.5 mm out of balance, 2 kN bolt preload,
#: joint stiffness 5e8 N/m (natural frequency sqrt(k11/M) = 5000 rad/s, well above the speeds).
MOTOR = {"M": 20.0, "delta": 0.5e-3, "P0": 2000.0, "k11": 5e8}
MOTOR_FRICTION = (0.1, 0.2, 0.3, 0.5, 0.8)


def _phase_data(P1: float, Q1s, points: int):
    from ..analysis.sweep import sweep

    phi = np.linspace(0.0, PI, _checks.positive_int("points", points, minimum=3))
    return sweep([P1], list(Q1s), phi, progress=False)["W_hat"].sel(P1=P1)


def figure_phase(
    P1: float, Q1s, points: int = 361, title: str | None = None, mark_peaks: bool = True
):
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
        (line,) = ax.plot(
            x,
            data.sel(Q1=q).values,
            lw=1.2,
            color=color,
            zorder=2,
            label=rf"$\hat Q_1 = {q:g}$",
            **style,
        )
        if n > 1:
            handles.append(line)
            labels.append(line.get_label())
        if mark_peaks:
            best, top = peak_phase(P1, float(q))
            if top > 0:
                tops.append((best, top))
                ax.plot(
                    best / PI,
                    top,
                    "o",
                    ms=5,
                    mfc="white",
                    mec="black",
                    mew=0.9,
                    zorder=4,
                    label="_maximum",
                )
    ax.axvline(0.5, color="0.35", lw=0.9, ls=":", zorder=1)
    ax.set_xlim(0, 1)
    ymax = float(data.max()) if data.size else 1.0
    ax.set_ylim(0, 1.06 * ymax if ymax > 0 else 1.0)
    if n == 1 and tops:
        best, top = tops[0]
        ax.set_ylim(0, 1.2 * max(top, ymax))
        ax.annotate(
            rf"maximum $\hat W$ = {top:.4f}" + f"\nat φ = {best / PI:.4f}π",
            (best / PI, top),
            xytext=(0.03, 0.96),
            textcoords="axes fraction",
            ha="left",
            va="top",
            fontsize=_SMALL,
            arrowprops={"arrowstyle": "-", "lw": 0.5, "color": "0.3", "shrinkA": 2, "shrinkB": 4},
        )
    ax.set_xlabel(r"$\varphi / \pi$", labelpad=2)
    ax.set_ylabel(r"$\hat W$", labelpad=2)
    ax.grid(alpha=0.25)
    if tops:
        handles.append(Line2D([], [], ls="", marker="o", ms=5, mfc="white", mec="black", mew=0.9))
        labels.append(r"maximum over φ")
    handles.append(Line2D([], [], color="0.35", lw=0.9, ls=":"))
    labels.append("φ = π/2")
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=3 if n > 1 else 2,
        frameon=False,
        handlelength=2.8,
        columnspacing=1.0,
    )
    ax.set_title(title or rf"$\hat P_1 = {P1:g}$", fontsize=_NORMAL)
    return _finish(fig)


# -- the motor (Fig. 9) ----------------------------------------------------------------------------
def _motor_speeds(motor, friction, points: int):
    """Speeds for Fig. 9: ``points`` logarithmically spaced from 0.25 to 3 times the separation
    speed, plus speeds crowding just above each shakedown speed (where W rises from 0)."""
    unit = motor.separation_speed()
    base = np.geomspace(0.25 * unit, 3.0 * unit, points)
    extra = [motor.shakedown_speed(f) * (1.0 + np.geomspace(1e-7, 0.05, 24)) for f in friction]
    return np.unique(np.concatenate([base, *extra]))


def figure_motor(
    M: float = MOTOR["M"],
    delta: float = MOTOR["delta"],
    P0: float = MOTOR["P0"],
    k11: float = MOTOR["k11"],
    friction=MOTOR_FRICTION,
    speeds=None,
    points: int = 400,
    log: bool = True,
):
    """Fig. 9: energy dissipated per revolution against rotational speed, several f.

    One column wide (3.5 in), on logarithmic axes by default: W rises from 0 at each shakedown
    speed (ticks on the speed axis), and its growth changes where separation begins.

    Parameters
    ----------
    M, delta, P0, k11 : float
        Rotor mass [kg], out-of-balance offset [m], bolt preload [N], joint tangential stiffness
        [N/m] (see :class:`lcpfric.paper.motor.Motor`).
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
        speeds = _motor_speeds(motor, friction, _checks.positive_int("points", points, 3))
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
        (line,) = ax.plot(speeds, W, lw=1.2, color=color, label=f"f = {f:g}", **style)
        curves.append(line)
        ax.plot(
            [motor.shakedown_speed(f)],
            [0.0],
            ls="",
            marker="|",
            ms=9,
            mew=1.4,
            color=color,
            transform=on_axis,
            clip_on=False,
            zorder=5,
            label="_shakedown",
        )
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
    ax.legend(
        handles=curves,
        loc="upper left",
        frameon=True,
        framealpha=0.9,
        edgecolor="none",
        handlelength=2.8,
        borderaxespad=0.4,
    )
    fig.legend(
        [
            Line2D([], [], ls="", marker="|", ms=9, mew=1.4, color="black"),
            Line2D([], [], color="0.35", ls="--", lw=0.9),
        ],
        ["shakedown speed (W = 0 below)", "separation begins"],
        loc="outside lower center",
        ncols=2,
        frameon=False,
        handlelength=2.2,
        columnspacing=1.0,
    )
    ax.set_title(
        rf"motor: $M$ = {M:g} kg, $\delta$ = {1e3 * delta:g} mm, $P_0$ = {_sci(P0)} N,"
        "\n"
        rf"$k_{{11}}$ = ${_sci(k11)}$ N/m, $\varphi = \pi/2$",
        fontsize=_SMALL + 0.5,
        pad=4,
    )
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
