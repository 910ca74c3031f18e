"""The paper's figures, drawn from data lcpfric computes (PNG and PDF).

* Fig. 3 (:func:`figure_maps`): Ŵ(P̂1, Q̂1) at φ = 0, with the line P̂1 = 1;
* Fig. 4 (:func:`figure_maps`): Ŵ(P̂1, Q̂1) for φ = kπ/10, k = 1..10 (k = 10 repeats φ = 0);
* Fig. 5 (:func:`figure_phase`): Ŵ against φ for P̂1 = 0.5 and several Q̂1;
* Fig. 6 (:func:`figure_phase`): Ŵ against φ for P̂1 = Q̂1 = 5;
* Fig. 7 (:func:`figure_phase`): Ŵ against φ for P̂1 = 1.5 and several Q̂1;
* Fig. 9 (:func:`figure_motor`): the motor of Section 3.3, W against speed for several f.

Every map carries the exact shakedown boundary (the zero contour of
:func:`~lcpfric.shakedown.shakedown_margin`, computed on a finer grid than the map). Figures are
built as :class:`matplotlib.figure.Figure` objects without pyplot, so nothing here touches the
user's matplotlib backend; files are written with the Agg renderer.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .. import _checks
from .._optional import require
from ..errors import InputError

__all__ = ["map_data", "figure_maps", "figure_phase", "figure_motor", "write_figures",
           "FIG5_Q1", "FIG7_Q1", "MOTOR", "MOTOR_FRICTION"]

PI = math.pi
FIG4_PHASES = tuple(k * PI / 10 for k in range(1, 11))
FIG5_Q1 = (1.0, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0)
FIG7_Q1 = (0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0)
#: The motor drawn in Fig. 9 (SI units): a 20 kg rotor 0.5 mm out of balance, 2 kN bolt preload,
#: joint stiffness 5e8 N/m (natural frequency sqrt(k11/M) = 5000 rad/s, well above the speeds).
MOTOR = {"M": 20.0, "delta": 0.5e-3, "P0": 2000.0, "k11": 5e8}
MOTOR_FRICTION = (0.1, 0.2, 0.3, 0.5, 0.8)
_CMAP = "viridis"
_BOUNDARY = {"colors": "#e8402a", "linewidths": 1.6}


def _figure(**kwargs):
    require("matplotlib", "plot", "Figures")
    from matplotlib.figure import Figure

    return Figure(**kwargs)


def _phi_label(phi: float) -> str:
    k = phi / PI
    if abs(k) < 1e-12:
        return "φ = 0"
    return "φ = π" if abs(k - 1) < 1e-12 else f"φ = {k:.3g}π"


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


def _draw_map(ax, W2d, P1, Q1, phi, levels, boundary_points: int = 401):
    from ..analysis.shakedown import shakedown_margin

    filled = ax.contourf(P1, Q1, W2d.T, levels=levels, cmap=_CMAP)
    lines = ax.contour(P1, Q1, W2d.T, levels=levels[::2][1:], colors="white", linewidths=0.5,
                       alpha=0.7)
    ax.clabel(lines, fmt="%.3g", fontsize=6)
    p = np.linspace(P1.min(), P1.max(), boundary_points)
    q = np.linspace(Q1.min(), Q1.max(), boundary_points)
    margin = shakedown_margin(p[:, None], q[None, :], phi)
    if margin.min() < 0 < margin.max():
        ax.contour(p, q, margin.T, levels=[0.0], **_BOUNDARY)
    if P1.min() < 1.0 < P1.max():
        ax.axvline(1.0, color="black", linestyle="--", linewidth=1.0)
    ax.set_xlim(P1.min(), P1.max())
    ax.set_ylim(Q1.min(), Q1.max())
    ax.set_title(_phi_label(phi), fontsize=10)
    return filled


def figure_maps(ds, phases=(0.0,), ncols: int = 5, title: str | None = None):
    """Contour maps of ``ds.W_hat`` at the phases nearest to ``phases``, on one colour scale.

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
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MaxNLocator

    phases = [float(p) for p in np.atleast_1d(phases)]
    ncols = min(_checks.positive_int("ncols", ncols), len(phases))
    nrows = math.ceil(len(phases) / ncols)
    single = len(phases) == 1
    fig = _figure(figsize=(6.4, 5.2) if single else (3.1 * ncols + 1.2, 3.0 * nrows + 0.9),
                  layout="constrained")
    axes = np.atleast_1d(fig.subplots(nrows, ncols, sharex=True, sharey=True, squeeze=False))
    P1, Q1 = ds["P1"].values, ds["Q1"].values
    panels = [ds["W_hat"].sel(phi=p, method="nearest") for p in phases]
    top = max(float(w.max()) for w in panels)
    levels = MaxNLocator(nbins=16).tick_values(0.0, top if top > 0 else 1.0)
    filled = None
    for ax, w in zip(axes.flat, panels):
        filled = _draw_map(ax, w.transpose("P1", "Q1").values, P1, Q1, float(w["phi"]), levels)
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    for ax in axes[-1, :]:
        ax.set_xlabel(r"$\hat P_1$")
    for ax in axes[:, 0]:
        ax.set_ylabel(r"$\hat Q_1$")
    fig.colorbar(filled, ax=axes, label=r"$\hat W = k_{11} W / (f P_0 Q_1)$", shrink=0.9)
    handles = [Line2D([], [], color=_BOUNDARY["colors"], lw=1.6, label="shakedown boundary"),
               Line2D([], [], color="black", ls="--", lw=1.0, label=r"$\hat P_1 = 1$")]
    if single:
        axes[0, 0].legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.85)
    else:
        fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=9)
    if title:
        fig.suptitle(title)
    return fig


def _phase_data(P1: float, Q1s, points: int):
    from ..analysis.sweep import sweep

    phi = np.linspace(0.0, PI, _checks.positive_int("points", points, minimum=3))
    return sweep([P1], list(Q1s), phi, progress=False)["W_hat"].sel(P1=P1)


def figure_phase(P1: float, Q1s, points: int = 361, title: str | None = None,
                 mark_peaks: bool = True):
    """Ŵ against φ in [0, π] for one P̂1 and several Q̂1 (Figs. 5-7), maxima marked.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from .claims import peak_phase

    P1 = _checks.nonnegative("P1", P1)
    data = _phase_data(P1, Q1s, points)
    fig = _figure(figsize=(7.2, 4.4), layout="constrained")
    ax = fig.subplots()
    x = data["phi"].values / PI
    for q in data["Q1"].values:
        line, = ax.plot(x, data.sel(Q1=q).values, lw=1.5, label=rf"$\hat Q_1 = {q:g}$")
        if mark_peaks:
            best, top = peak_phase(P1, float(q))
            if top > 0:
                ax.plot(best / PI, top, "o", ms=4, color=line.get_color())
                if len(data["Q1"]) == 1:
                    ax.annotate(f"maximum at φ = {best / PI:.4f}π\n" + rf"$\hat W$ = {top:.4f}",
                                (best / PI, top), textcoords="offset points", xytext=(12, -30),
                                fontsize=9, arrowprops={"arrowstyle": "-", "lw": 0.6})
    ax.axvline(0.5, color="grey", lw=0.8, ls=":")
    ax.set_xlim(0, 1)
    ax.set_ylim(bottom=0)
    ax.set_xlabel(r"$\varphi / \pi$")
    ax.set_ylabel(r"$\hat W$")
    ax.grid(alpha=0.3)
    if len(data["Q1"]) > 1:
        ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    ax.set_title(title or rf"$\hat P_1 = {P1:g}$")
    return fig


def figure_motor(M: float = MOTOR["M"], delta: float = MOTOR["delta"], P0: float = MOTOR["P0"],
                 k11: float = MOTOR["k11"], friction=MOTOR_FRICTION, speeds=None,
                 points: int = 400):
    """Fig. 9: energy dissipated per revolution against rotational speed, several f.

    Parameters
    ----------
    M, delta, P0, k11 : float
        Rotor mass [kg], out-of-balance offset [m], bolt preload [N], joint tangential stiffness
        [N/m] (see :class:`lcpfric.motor.Motor`).
    friction : sequence of float
        Coefficients of friction, one curve each.
    speeds : array_like, optional
        Rotational speeds Ω [rad/s]; default 0 to 2.5 times the separation speed.
    points : int
        Number of speeds when ``speeds`` is not given.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from .motor import Motor

    motor = Motor(M=M, delta=delta, P0=P0, k11=k11)
    unit = motor.separation_speed()
    if speeds is None:
        speeds = np.linspace(0.0, 2.5 * unit, _checks.positive_int("points", points, 3))
    speeds = _checks.finite_array("speeds", speeds, nonneg=True)
    fig = _figure(figsize=(6.4, 4.6), layout="constrained")
    ax = fig.subplots()
    for f in friction:
        line, = ax.plot(speeds, 1e3 * motor.dissipation(speeds, f), lw=1.5, label=f"f = {f:g}")
        ax.plot(motor.shakedown_speed(f), 0.0, "|", ms=10, mew=1.5, color=line.get_color(),
                clip_on=False)
    ax.plot([], [], "|", ms=10, mew=1.5, color="black", label="shakedown limit\n(W = 0 below)")
    ax.axvline(unit, color="grey", ls="--", lw=0.9)
    ax.text(unit, ax.get_ylim()[1] * 0.97, " separation\n begins", va="top", fontsize=8,
            color="grey")
    ax.set_xlim(speeds.min(), speeds.max())
    ax.set_ylim(bottom=0)
    ax.set_xlabel(r"rotational speed $\Omega$ [rad/s]")
    ax.set_ylabel(r"dissipation per revolution $W$ [mJ]")
    top = ax.secondary_xaxis("top", functions=(lambda w: w / unit, lambda s: s * unit))
    top.set_xlabel(r"$\Omega \sqrt{M\delta / P_0}$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(rf"motor: $M$ = {M:g} kg, $\delta$ = {1e3 * delta:g} mm, $P_0$ = {P0:g} N, "
                 rf"$k_{{11}}$ = {k11:.3g} N/m, $\varphi = \pi/2$", fontsize=9)
    return fig


def _save(fig, out_dir: Path, name: str, formats) -> list[Path]:
    paths = []
    for fmt in formats:
        path = out_dir / f"{name}.{fmt}"
        fig.savefig(path, dpi=150)
        paths.append(path)
    return paths


def write_figures(out_dir, grid: int = 101, points: int = 361, formats=("png", "pdf"),
                  data=None, **sweep_options) -> list[Path]:
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
        File formats, among ``"png"``, ``"pdf"``, ``"svg"``.
    data : xarray.Dataset, optional
        Precomputed maps (from :func:`map_data`); computed when not given.
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
    out_dir = Path(out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError("out", f"{out_dir} exists and is not a directory")
    out_dir.mkdir(parents=True, exist_ok=True)
    ds = map_data(grid, **sweep_options) if data is None else data
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
    for name, make in figures.items():
        written += _save(make(), out_dir, name, formats)
    return written
