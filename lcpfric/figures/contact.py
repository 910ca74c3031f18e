"""Figures of the continuum contacts, sized and styled like the paper's
(:mod:`lcpfric.figures.style`).

* :func:`figure_hertz_maps`: ``W k_t0/(μ² P0²)`` of the Hertz contact (MDR) over (P1/P0,
  Q1/(μ P0)) for several phases (the continuum Fig. 4), one colour scale (logarithmic: the
  values span decades), the separation line P1 = P0 and the points without equilibrium marked;
* :func:`figure_phase`: W against φ for a few load amplitudes, each curve's maximum marked, and
  the phase of the largest W over the (P1, Q1) plane (where the maximum over φ lies);
* :func:`figure_zones`: stick, slip and separation over the contact and over the cycle (position
  on one axis, time on the other), with the contact edge;
* :func:`figure_tractions`: shear tractions of the plane contact and of the sphere at chosen
  instants of the first loading, beside Cattaneo's.

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
    "slip, forward": "#d9531e",
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


def phase_data(cases=PHASE_CASES, points: int = 61, k_support: float = K_SUPPORT, **options):
    """W_normalized against φ in [0, π] for each (P1/P0, Q1/(μ P0)) of ``cases``."""
    from ..analysis.contact_maps import mdr_W_normalized

    phi = np.linspace(0.0, PI, points)
    out = []
    for p1, q1 in cases:
        out.append(
            mdr_W_normalized(
                np.full(points, p1), np.full(points, q1), phi, k_support=k_support, **options
            )
        )
    return phi, np.array(out)


def figure_phase(phi, curves, cases, ds=None):
    """(a) W against φ for each case, its maximum marked; (b) with a map dataset ``ds``, the
    phase of the largest W at each (P1, Q1)."""
    with style():
        from matplotlib.lines import Line2D

        from .style import curve_style, ramp

        two = ds is not None
        fig = figure(figsize=(PAGE_WIDTH if two else COLUMN_WIDTH, 2.9), layout="constrained")
        axes = fig.subplots(1, 2 if two else 1, squeeze=False)[0]
        ax = axes[0]
        colours = ramp(len(cases))
        for i, ((p1, q1), W) in enumerate(zip(cases, curves)):
            ax.plot(
                phi / PI,
                W,
                color=colours[i],
                **curve_style(i, len(cases), phi.size),
                label=rf"$P_1/P_0$ = {p1:g}, $Q_1/(\mu P_0)$ = {q1:g}",
            )
            if np.any(np.isfinite(W)):
                j = int(np.nanargmax(W))
                ax.plot(
                    phi[j] / PI,
                    W[j],
                    ls="none",
                    marker="*",
                    ms=8,
                    color=colours[i],
                    mec="black",
                    mew=0.5,
                )
        ax.set_xlabel(r"$\varphi/\pi$")
        ax.set_ylabel(r"$W k_{t0}/(\mu^2 P_0^2)$")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1.6 * float(np.nanmax(curves)) if np.any(np.isfinite(curves)) else 1)
        handles, labels = ax.get_legend_handles_labels()
        handles.append(
            Line2D([], [], ls="none", marker="*", ms=8, color="0.6", mec="black", mew=0.5)
        )
        labels.append("largest W over φ")
        ax.legend(handles, labels, fontsize=SMALL, frameon=False, loc="upper left")
        ax.set_title("(a) W against the phase" if two else "", fontsize=SMALL + 1)
        if two:
            W = ds["W_normalized"].transpose("phi", "Q1", "P1").values
            best = np.full(W.shape[1:], np.nan)
            with np.errstate(invalid="ignore"):
                spread = np.nanmax(W, axis=0) - np.nanmin(W, axis=0)
                # W that does not depend on φ (P1 = 0: no phase) or vanishes has no maximum
                ok = spread > 1e-6 * np.nanmax(W, axis=0)
            filled = np.where(np.isfinite(W), W, -np.inf)
            best[ok] = ds["phi"].values[np.argmax(filled, axis=0)][ok] / PI
            ax2 = axes[1]
            mesh = ax2.pcolormesh(
                ds["P1"].values,
                ds["Q1"].values,
                best,
                cmap="cividis",
                vmin=0,
                vmax=1,
                shading="nearest",
                rasterized=True,
            )
            ax2.set_xlabel(r"$P_1/P_0$")
            ax2.set_ylabel(r"$Q_1/(\mu P_0)$")
            ax2.set_title(
                r"(b) the phase of the largest W ($\varphi$ grid of the maps)", fontsize=SMALL + 1
            )
            fig.colorbar(
                mesh,
                ax=ax2,
                label=r"$\varphi_{\max}/\pi$ (white: W does not "
                r"depend on $\varphi$)",
            )
        return finish(fig)


def figure_zones(result, title: str = ""):
    """Stick, slip and separation over the contact (vertical: position over the largest contact
    size) and over the cycle (horizontal), with the contact edge; needs ``record=True``."""
    from ..results import State

    with style():
        from matplotlib.colors import ListedColormap
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        order = [int(State.STICK), int(State.FORWARD), int(State.BACKWARD), int(State.SEPARATION)]
        code = np.full(result.state.shape, 3, dtype=float)
        for i, s in enumerate(order):
            code[result.state == s] = i
        x = result.contact.x
        keep = x >= 0
        xs = x[keep] / result.contact.contact_size_max
        t = result.t / result.t[-1]
        fig = figure(figsize=(COLUMN_WIDTH, 2.9), layout="constrained")
        ax = fig.add_subplot()
        cmap = ListedColormap(list(ZONE_COLOURS.values()))
        ax.pcolormesh(
            t,
            xs,
            code[:, keep].T,
            cmap=cmap,
            vmin=-0.5,
            vmax=3.5,
            shading="nearest",
            rasterized=True,
        )
        ax.plot(t, result.contact.size / result.contact.contact_size_max, color="black", lw=0.9)
        ax.set_xlabel("time over the period, t/T")
        ax.set_ylabel("position over the largest contact size")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, max(1.0, xs.max()))
        handles = [
            Patch(facecolor=c, edgecolor="0.3", lw=0.4, label=k) for k, c in ZONE_COLOURS.items()
        ]
        handles.append(Line2D([], [], color="black", lw=0.9, label="contact edge"))
        fig.legend(
            handles=handles, loc="outside lower center", ncols=3, frameon=False, fontsize=SMALL
        )
        if title:
            ax.set_title(title, fontsize=SMALL + 1)
        return finish(fig)


def figure_tractions(result, model, fractions=(0.3, 0.6, 0.9)):
    """Shear tractions at the instants of the first loading where Q = x μ P, beside Cattaneo's
    ``q/(μ p0) = √(1 - ξ²) - (c/a) √(1 - ξ² a²/c²)`` with ``c/a = √(1 - x)`` (cylinder, the
    element tractions) or ``(1 - x)^(1/3)`` (sphere, the inverse MDR transform of the spring forces,
    :meth:`~lcpfric.model.continuum.mdr.MDRSphere.tractions`); ``result`` is the first cycle of a
    constant-P, sinusoidal-Q run with ``record=True``."""
    from ..model.continuum.closed_forms import cattaneo_stick_ratio, cylinder_contact, hertz_contact

    plane = hasattr(model, "pressure")
    with style():
        from matplotlib.lines import Line2D

        from .style import ramp

        ref = (cylinder_contact if plane else hertz_contact)(model.P0, model.R, model.E, model.nu)
        a, p0, mu = ref["a"], ref["p0"], model.mu
        Q = np.asarray(model.Q(result.t))
        quarter = result.t.size // 4 + 1
        fig = figure(figsize=(COLUMN_WIDTH, 3.2), layout="constrained")
        ax = fig.add_subplot()
        colours = ramp(len(fractions))
        xi = np.linspace(-1, 1, 801)
        for i, x in enumerate(fractions):
            j = int(np.argmin(np.abs(Q[:quarter] - x * mu * model.P0)))
            xj = Q[j] / (mu * model.P0)
            if plane:
                q = -result.F[j] / model.dx * np.sign(Q[j])
            else:
                q = -model.tractions(result.F[j]) * np.sign(Q[j])
            ax.plot(
                model.x / a,
                q / (mu * p0),
                ls="none",
                marker="o",
                ms=2.2,
                color=colours[i],
                label=f"Q/(μP) = {xj:.3f}",
                markevery=1 if plane else max(1, model.nodes // 150),
            )
            c = cattaneo_stick_ratio(xj, "cylinder" if plane else "sphere")
            exact = np.sqrt(np.clip(1 - xi**2, 0, None)) - c * np.sqrt(
                np.clip(1 - (xi / c) ** 2 if c > 0 else 0.0, 0, None)
            )
            ax.plot(xi, exact, color=colours[i], lw=0.9)
        ax.set_xlabel("x/a" if plane else "r/a")
        ax.set_ylabel(r"shear traction $q/(\mu p_0)$")
        ax.set_xlim(-1.1 if plane else 0.0, 1.1)
        handles, labels = ax.get_legend_handles_labels()
        handles.append(Line2D([], [], color="0.3", lw=0.9))
        labels.append("Cattaneo (closed form)")
        handles.append(Line2D([], [], color="0.3", ls="none", marker="o", ms=2.2))
        labels.append(
            f"half-plane elements ({model.nodes_across} across)"
            if plane
            else f"MDR, inverse transform ({model.nodes} springs)"
        )
        fig.legend(
            handles, labels, fontsize=SMALL, frameon=False, loc="outside lower center", ncols=2
        )
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
    """Compute and write every figure of this module into ``out_dir``."""
    from ..analysis.sweep import sweep
    from ..model import Harmonic
    from ..model.continuum.halfplane import HalfPlaneCylinder
    from ..model.continuum.mdr import MDRSphere
    from ..periodic import steady_state

    say = progress or (lambda line: None)
    out_dir = Path(out_dir)
    out_dir.mkdir(exist_ok=True)
    paths = []
    t0 = time.perf_counter()
    axis = np.linspace(0.0, 2.0, grid)
    ds = sweep(
        axis,
        axis,
        list(MAP_PHASES),
        contact={"k_support": K_SUPPORT, "nodes": nodes},
        steps_per_cycle=steps,
        progress=False,
    )
    say(f"Hertz maps ({grid} x {grid} x {len(MAP_PHASES)}): {time.perf_counter() - t0:.1f} s")
    paths += save(figure_hertz_maps(ds), out_dir, "hertz-maps", formats)
    phi, curves = phase_data(nodes=nodes, steps_per_cycle=steps)
    paths += save(figure_phase(phi, curves, PHASE_CASES, ds), out_dir, "hertz-phase", formats)
    # zones: a separating sphere held by its support, and the plane contact at constant P
    k_t0 = MDRSphere(1.0, 1.0, 0.0, 1.0, 1.0, 0.0, nodes=1).k_t0
    sphere = MDRSphere(
        1.0,
        1.0,
        0.0,
        1.0,
        Harmonic(1.0, 1.5),
        Harmonic(0.0, 0.6, 0.3 * PI),
        nodes=nodes,
        k_support=K_SUPPORT * k_t0,
    )
    r = steady_state(sphere, steps_per_cycle=steps)
    paths += save(
        figure_zones(r, "sphere (MDR): P1/P0 = 1.5, Q1/(μP0) = 0.6, φ = 0.3π"),
        out_dir,
        "hertz-zones",
        formats,
    )
    plane = HalfPlaneCylinder(
        1.0, 1.0, 0.0, 1.0, Harmonic(1.0, 0.0), Harmonic(0.0, 0.95), nodes=200
    )
    first = steady_state(plane, steps_per_cycle=400, max_cycles=1, on_nonconvergence="ignore")
    paths += save(figure_tractions(first, plane), out_dir, "cylinder-tractions", formats)
    ball = MDRSphere(1.0, 1.0, 0.0, 1.0, Harmonic(1.0, 0.0), Harmonic(0.0, 0.95), nodes=1000)
    first = steady_state(ball, steps_per_cycle=400, max_cycles=1, on_nonconvergence="ignore")
    paths += save(figure_tractions(first, ball), out_dir, "sphere-tractions", formats)
    say(f"all contact figures: {time.perf_counter() - t0:.1f} s")
    return paths
