"""Figures of the continuum contacts, sized and styled like the paper's
(:mod:`lcpfric.figures.style`).

* :func:`figure_hertz_maps`: ``W k_t0/(μ² P0²)`` of the Hertz contact (MDR) over (P1/P0,
  Q1/(μ P0)) for several phases (the continuum Fig. 4), one colour scale (logarithmic: the
  values span decades), the separation line P1 = P0 and the points without equilibrium marked;
* :func:`figure_phase`: W against φ for a few load amplitudes (log axis), each curve's maximum
  marked, and the phase of the largest W over the (P1, Q1) plane, one named colour per phase;
* :func:`figure_zones`: stick, slip and separation over the contact and over the cycle (position
  on one axis, time on the other), with the contact edge and each state's share;
* :func:`figure_tractions`: shear tractions of the plane contact and of the sphere at chosen
  instants of the first loading, under Cattaneo's lines, titled with the contact.

:func:`write_contact_figures` computes the data and writes all of them (``lcpfric figures
--contact``).
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from .style import COLUMN_WIDTH, PAGE_WIDTH, SMALL, figure, finish, phi_label, save, style

__all__ = [
    "figure_hertz_maps",
    "figure_phase",
    "figure_zones",
    "figure_tractions",
    "write_contact_figures",
    "MAP_PHASES",
    "PHASE_CASES",
    "K_SUPPORT",
]

PI = math.pi
#: φ = kπ/10, k = 0..10 (the paper's Fig. 4 phases, with φ = 0)
MAP_PHASES = tuple(k * PI / 10 for k in range(11))
#: (P1/P0, Q1/(μ P0)) of the phase curves
PHASE_CASES = ((0.5, 0.2), (0.5, 0.4), (0.9, 0.5), (1.5, 0.6))
#: the support stiffness of the maps and curves, in units of k_t0 (loads with separation and
#: Q != 0 have no equilibrium without one)
K_SUPPORT = 1.0
#: state colours (distinct in lightness too: greyscale prints)
ZONE_COLOURS = {
    "stick": "#23395d",
    "slip, forward": "#c51b7d",
    "slip, backward": "#f4a259",
    "separated": "#ececec",
}


def figure_hertz_maps(ds, phases=MAP_PHASES, ncols: int = 4):
    """Panels of ``ds.W_normalized`` at the phases nearest to ``phases`` on one logarithmic
    colour scale."""
    with style():
        from matplotlib.colors import LogNorm
        from matplotlib.patches import Patch
        from matplotlib.lines import Line2D

        phases = [float(p) for p in np.atleast_1d(phases)]
        ncols = min(ncols, len(phases))
        nrows = math.ceil(len(phases) / ncols)
        P1, Q1 = ds["P1"].values, ds["Q1"].values
        panels = [ds["W_normalized"].sel(phi=p, method="nearest") for p in phases]
        values = np.concatenate([w.values.ravel() for w in panels])
        positive = values[np.isfinite(values) & (values > 0)]
        top = float(positive.max()) if positive.size else 1.0
        norm = LogNorm(vmin=top * 1e-4, vmax=top)
        panel = (PAGE_WIDTH - 1.3) / ncols
        fig = figure(figsize=(PAGE_WIDTH, nrows * (panel + 0.15) + 0.75), layout="constrained")
        axes = np.atleast_1d(fig.subplots(nrows, ncols, sharex=True, sharey=True, squeeze=False))
        mesh, any_undefined = None, False
        for ax, w in zip(axes.flat, panels):
            W = w.transpose("Q1", "P1").values
            shown = np.where(np.isfinite(W) & (W >= norm.vmin), W, np.nan)
            ax.set_facecolor("white")
            undefined = ~np.isfinite(W)
            any_undefined |= bool(undefined.any())
            if undefined.any():
                ax.contourf(
                    P1,
                    Q1,
                    undefined.astype(float),
                    levels=[0.5, 1.5],
                    colors="none",
                    hatches=["////"],
                )
            mesh = ax.pcolormesh(
                P1, Q1, shown, norm=norm, cmap="viridis", shading="nearest", rasterized=True
            )
            if P1.max() > 1.0:
                ax.axvline(1.0, color="white", ls="--", lw=0.8)
                ax.axvline(1.0, color="black", ls=(0, (2, 2)), lw=0.8)
            ax.set_title(phi_label(float(w["phi"])), fontsize=SMALL + 1, pad=2)
            ax.set_aspect("auto")
        for ax in axes.flat[len(panels) :]:
            ax.set_visible(False)
        for ax in axes[-1, :]:
            ax.set_xlabel(r"$P_1/P_0$", labelpad=1)
        for ax in axes[:, 0]:
            ax.set_ylabel(r"$Q_1/(\mu P_0)$", labelpad=1)
        bar = fig.colorbar(mesh, ax=axes, shrink=0.9, aspect=30, pad=0.02)
        bar.set_label(r"$W k_{t0}/(\mu^2 P_0^2)$, log scale")
        handles = [
            Line2D(
                [],
                [],
                color="black",
                ls=(0, (2, 2)),
                lw=0.8,
                label=r"$P_1 = P_0$: complete separation beyond",
            ),
            Patch(
                facecolor="white",
                edgecolor="0.3",
                lw=0.5,
                label=f"white: W below {norm.vmin:.1e} (1e-4 of the largest; 0 in a shakedown)",
            ),
        ]
        if any_undefined:
            handles.append(
                Patch(
                    facecolor="white",
                    edgecolor="black",
                    hatch="////",
                    lw=0.5,
                    label="no equilibrium (pure load control)",
                )
            )
        ks = ds.attrs.get("k_support_over_k_t0")
        title = "Hertz contact (MDR)" + (
            f", support stiffness {ks:g} k_t0" if ks is not None else ""
        )
        fig.legend(
            handles=handles,
            loc="outside lower center",
            ncols=len(handles),
            frameon=False,
            fontsize=SMALL,
            title=title,
            title_fontsize=SMALL,
        )
        return finish(fig)


def phase_data(cases=PHASE_CASES, points: int = 61, k_support_ratio: float = K_SUPPORT, **options):
    """W_normalized against φ in [0, π] for each (P1/P0, Q1/(μ P0)) of ``cases``."""
    from ..analysis.contact_maps import mdr_W_normalized

    phi = np.linspace(0.0, PI, points)
    out = []
    for p1, q1 in cases:
        out.append(
            mdr_W_normalized(
                np.full(points, p1),
                np.full(points, q1),
                phi,
                k_support_ratio=k_support_ratio,
                **options,
            )
        )
    return phi, np.array(out)


def best_phase(ds):
    """φ/π of the largest ``W_normalized`` over the map's phases at each (Q1, P1) (NaN where W
    does not depend on φ (P1 = 0: no phase) or vanishes: no maximum)."""
    W = ds["W_normalized"].transpose("phi", "Q1", "P1").values
    best = np.full(W.shape[1:], np.nan)
    with np.errstate(invalid="ignore"):
        spread = np.nanmax(W, axis=0) - np.nanmin(W, axis=0)
        ok = spread > 1e-6 * np.nanmax(W, axis=0)
    filled = np.where(np.isfinite(W), W, -np.inf)
    best[ok] = ds["phi"].values[np.argmax(filled, axis=0)][ok] / PI
    return best


def figure_phase(phi, curves, cases, ds=None):
    """(a) W against φ for each case on a logarithmic axis (the curves span decades), its
    maximum marked; (b) with a map dataset ``ds``, the phase of the largest W at each (P1, Q1):
    one colour per phase found, named in a legend, the regions outlined."""
    with style():
        from matplotlib.colors import ListedColormap
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        from .style import curve_style, ramp

        two = ds is not None
        fig = figure(figsize=(PAGE_WIDTH if two else COLUMN_WIDTH, 3.1), layout="constrained")
        axes = fig.subplots(1, 2 if two else 1, squeeze=False)[0]
        ax = axes[0]
        colours = ramp(len(cases))
        for i, ((p1, q1), W) in enumerate(zip(cases, curves)):
            label = rf"$P_1/P_0$ = {p1:g}, $Q_1/(\mu P_0)$ = {q1:g}"
            ax.plot(phi / PI, W, color=colours[i], **curve_style(i, len(cases), phi.size))
            ax.plot([], [], color=colours[i], label=label, **curve_style(i, len(cases), 2))
            if np.any(np.isfinite(W)):
                j = int(np.nanargmax(W))
                star = dict(ls="none", marker="*", ms=8, mec="black", mew=0.5, zorder=4)
                ax.plot(phi[j] / PI, W[j], color=colours[i], **star)
        peaks = np.nanmax(np.where(np.asarray(curves) > 0, curves, np.nan), axis=1)
        low = float(np.nanmin(peaks)) if np.any(np.isfinite(peaks)) else 1e-3
        high = float(np.nanmax(peaks)) if np.any(np.isfinite(peaks)) else 1.0
        ax.set_yscale("log")
        ax.set_ylim(10 ** math.floor(math.log10(low / 30)), 10 ** math.ceil(math.log10(high)))
        ax.set_xlabel(r"$\varphi/\pi$")
        ax.set_ylabel(r"$W k_{t0}/(\mu^2 P_0^2)$, log scale")
        ax.set_xlim(0, 1)
        handles, labels = ax.get_legend_handles_labels()
        handles.append(Line2D([], [], color="0.6", **star))
        labels.append("largest W over φ")
        fig.legend(handles, labels, loc="outside lower left", ncols=2 if two else 1, frameon=False)
        ax.set_title("(a) W against the phase" if two else "", fontsize=SMALL + 1)
        if two:
            best = best_phase(ds)
            found = np.unique(best[np.isfinite(best)])
            colours = ramp(max(found.size, 1))
            code = np.full(best.shape, np.nan)
            for k, v in enumerate(found):
                code[best == v] = k
            ax2 = axes[1]
            P1, Q1 = ds["P1"].values, ds["Q1"].values
            ax2.pcolormesh(
                P1,
                Q1,
                code,
                cmap=ListedColormap(colours[: max(found.size, 1)]),
                vmin=-0.5,
                vmax=max(found.size, 1) - 0.5,
                shading="nearest",
                rasterized=True,
            )
            ax2.set_xlabel(r"$P_1/P_0$")
            ax2.set_ylabel(r"$Q_1/(\mu P_0)$")
            ax2.set_title(r"(b) the phase of the largest W", fontsize=SMALL + 1)
            marks = [
                Patch(facecolor=c, edgecolor="0.3", lw=0.4, label=rf"$\varphi_{{\max}}$ = {v:g}π")
                for c, v in zip(colours, found)
            ]
            marks.append(
                Patch(facecolor="white", edgecolor="0.3", lw=0.4, label="W independent of φ")
            )
            fig.legend(
                handles=marks,
                loc="outside lower right",
                ncols=2,
                frameon=False,
                title=f"(b): the largest W among the maps' {ds['phi'].size} phases",
            )
        return finish(fig)


def figure_zones(result, title: str = ""):
    """Stick, slip and separation over the contact (vertical: position over the largest contact
    size) and over the cycle (horizontal), with the contact edge, each state's share of the
    contact (position x time) in the legend; forward slip, often a band one element wide along
    the edge, is drawn over the edge line. Needs ``record=True``."""
    from .halfspace_panels import codes

    with style():
        from matplotlib.colors import ListedColormap
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        keep = result.contact.x >= 0
        code = codes(result.state[:, keep]).T
        xs = result.contact.x[keep] / result.contact.contact_size_max
        t = result.t / result.t[-1]
        fig = figure(figsize=(COLUMN_WIDTH, 3.0), layout="constrained")
        ax = fig.add_subplot()
        zones = dict(cmap=ListedColormap(list(ZONE_COLOURS.values())), vmin=-0.5, vmax=3.5)
        zones.update(shading="nearest", rasterized=True)
        ax.pcolormesh(t, xs, code, **zones)
        edge = result.contact.size / result.contact.contact_size_max
        ax.plot(t, edge, color="black", lw=0.7, zorder=2)
        ax.pcolormesh(t, xs, np.ma.masked_not_equal(code, 1), zorder=3, **zones)
        ax.set_xlabel("time over the period, t/T")
        ax.set_ylabel("position over the largest contact size")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, max(1.0, xs.max()))
        touching = max(int(np.count_nonzero(code < 3)), 1)
        handles = []
        for k, (name, c) in enumerate(ZONE_COLOURS.items()):
            share = 100.0 * np.count_nonzero(code == k) / touching
            label = name if k == 3 else f"{name} ({share:.2g} %)"
            handles.append(Patch(facecolor=c, edgecolor="0.3", lw=0.4, label=label))
        handles.append(Line2D([], [], color="black", lw=0.7, label="contact edge"))
        fig.legend(
            handles=handles,
            loc="outside lower center",
            ncols=2,
            frameon=False,
            title="%: share of the contact (position x time)",
        )
        if title:
            ax.set_title(title, fontsize=SMALL + 1)
        return finish(fig)


def figure_tractions(result, model, fractions=(0.3, 0.6, 0.9)):
    """Shear tractions at the instants of the first loading where Q = x μ P, beside Cattaneo's
    ``q/(μ p0) = √(1 - ξ²) - (c/a) √(1 - ξ² a²/c²)`` with ``c/a = √(1 - x)`` (cylinder, the
    element tractions) or ``(1 - x)^(1/3)`` (sphere, the inverse MDR transform of the spring forces,
    :meth:`~lcpfric.model.continuum.mdr.MDRSphere.tractions`); ``result`` is the first cycle of a
    constant-P, sinusoidal-Q run with ``record=True``. Cattaneo's lines are drawn over the
    model's (hollow, about 25 a curve) markers; the title names the contact."""
    from ..model.continuum.closed_forms import cattaneo_stick_ratio, cylinder_contact, hertz_contact

    plane = hasattr(model, "pressure")
    with style():
        from matplotlib.lines import Line2D

        from .style import STYLES, ramp

        ref = (cylinder_contact if plane else hertz_contact)(model.P0, model.R, model.E, model.nu)
        a, p0, mu = ref["a"], ref["p0"], model.mu
        Q = np.asarray(model.Q(result.t))
        quarter = result.t.size // 4 + 1
        fig = figure(figsize=(COLUMN_WIDTH, 3.4), layout="constrained")
        ax = fig.add_subplot()
        colours = ramp(len(fractions))
        xi = np.linspace(-1, 1, 801)
        inside = int(np.count_nonzero(np.abs(model.x) <= (1.1 if plane else 1.0) * a))
        step = max(1, inside // (50 if plane else 25))
        dots = dict(ls="none", ms=3.0, mew=0.6, mfc="none", zorder=2)
        for i, x in enumerate(fractions):
            j = int(np.argmin(np.abs(Q[:quarter] - x * mu * model.P0)))
            xj = Q[j] / (mu * model.P0)
            if plane:
                q = -result.F[j] / model.dx * np.sign(Q[j])
            else:
                q = -model.tractions(result.F[j]) * np.sign(Q[j])
            marker = STYLES[i % len(STYLES)][1]
            ax.plot(
                model.x / a,
                q / (mu * p0),
                color=colours[i],
                marker=marker,
                markevery=((i * step) // len(fractions), step),
                **dots,
            )
            c = cattaneo_stick_ratio(xj, "cylinder" if plane else "sphere")
            exact = np.sqrt(np.clip(1 - xi**2, 0, None)) - c * np.sqrt(
                np.clip(1 - (xi / c) ** 2 if c > 0 else 0.0, 0, None)
            )
            ax.plot(xi, exact, color=colours[i], lw=1.0, zorder=3)
            key = {**dots, "ls": "-", "lw": 1.0}
            ax.plot([], [], color=colours[i], marker=marker, label=f"Q/(μP) = {xj:.3f}", **key)
        ax.set_xlabel("x/a" if plane else "r/a")
        ax.set_ylabel(r"shear traction $q/(\mu p_0)$")
        ax.set_xlim(-1.1 if plane else 0.0, 1.1)
        ax.set_title(
            "cylinder (plane strain), P constant, Q rising"
            if plane
            else "sphere (MDR), P constant, Q rising",
            fontsize=SMALL + 1,
        )
        handles, labels = ax.get_legend_handles_labels()
        handles.append(Line2D([], [], color="0.3", lw=1.0))
        labels.append("Cattaneo (closed form)")
        handles.append(Line2D([], [], color="0.3", marker="o", **dots))
        labels.append(
            f"half-plane elements ({model.nodes_across} across)"
            if plane
            else f"MDR, inverse transform ({model.nodes} springs)"
        )
        fig.legend(handles, labels, frameon=False, loc="outside lower center", ncols=2)
        ax.set_ylim(-0.03, 1.05)
        return finish(fig)


def write_contact_figures(
    out_dir,
    grid: int = 41,
    formats=("png", "pdf"),
    nodes: int = 200,
    steps: int = 200,
    progress=None,
) -> list[Path]:
    """Compute and write every figure of this module into ``out_dir``; ``progress(line)`` (a
    callable, e.g. a printer to stderr) hears a line at every tenth of the maps' chunks and
    one at the end of each stage, with the time so far."""
    from ..analysis.sweep import sweep
    from ..model import Harmonic
    from ..model.continuum.halfplane import HalfPlaneCylinder
    from ..model.continuum.mdr import MDRSphere
    from ..periodic import steady_state

    out_dir = Path(out_dir)
    out_dir.mkdir(exist_ok=True)
    paths = []
    t0 = time.perf_counter()

    def say(line):
        if progress is not None:
            progress(f"{line} ({time.perf_counter() - t0:.1f} s)")

    maps = f"Hertz maps ({grid} x {grid} x {len(MAP_PHASES)} points)"
    said = [0]

    def on_chunk(index, done, total):
        tenth = 10 * done // total
        if tenth > said[0] and done < total:
            said[0] = tenth
            say(f"{maps}: {done} of {total} chunks")

    say(f"{maps}: started")
    axis = np.linspace(0.0, 2.0, grid)
    contact = {"k_support_ratio": K_SUPPORT, "nodes": nodes}
    ds = sweep(
        axis,
        axis,
        list(MAP_PHASES),
        contact=contact,
        steps_per_cycle=steps,
        progress=False,
        on_chunk=on_chunk,
    )
    say(f"{maps}: done")
    paths += save(figure_hertz_maps(ds), out_dir, "hertz-maps", formats)
    phi, curves = phase_data(nodes=nodes, steps_per_cycle=steps)
    paths += save(figure_phase(phi, curves, PHASE_CASES, ds), out_dir, "hertz-phase", formats)
    say(f"W against the phase ({len(PHASE_CASES)} curves): done")
    # zones: a separating sphere held by its support, and the plane contact at constant P
    k_t0 = MDRSphere(1.0, 1.0, 0.0, 1.0, 1.0, 0.0, nodes=nodes).k_t0
    P, Q = Harmonic(1.0, 1.5), Harmonic(0.0, 0.6, 0.3 * PI)
    sphere = MDRSphere(1.0, 1.0, 0.0, 1.0, P, Q, nodes=nodes, k_support=K_SUPPORT * k_t0)
    r = steady_state(sphere, steps_per_cycle=steps)
    title = "sphere (MDR): P1/P0 = 1.5, Q1/(μP0) = 0.6, φ = 0.3π"
    paths += save(figure_zones(r, title), out_dir, "hertz-zones", formats)
    say("zones over the cycle: done")
    first = dict(steps_per_cycle=400, max_cycles=1, on_nonconvergence="ignore")
    P, Q = Harmonic(1.0, 0.0), Harmonic(0.0, 0.95)
    plane = HalfPlaneCylinder(1.0, 1.0, 0.0, 1.0, P, Q, nodes=200)
    r = steady_state(plane, **first)
    paths += save(figure_tractions(r, plane), out_dir, "cylinder-tractions", formats)
    ball = MDRSphere(1.0, 1.0, 0.0, 1.0, P, Q, nodes=1000)
    r = steady_state(ball, **first)
    paths += save(figure_tractions(r, ball), out_dir, "sphere-tractions", formats)
    say("tractions beside Cattaneo's: done; all contact figures written")
    return paths
