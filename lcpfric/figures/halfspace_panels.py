"""The parts the half-space's figures share (:mod:`.halfspace`): the grid and its crop, the
zone codes and outlines, the Hertz circle, legends, labels and captions."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = [
    "caption",
    "check_result",
    "codes",
    "crop",
    "draw_zones",
    "edge_handles",
    "grid",
    "halo",
    "hertz_radius",
    "hertz_style",
    "index",
    "loads_label",
    "nice",
    "outline",
    "peak_pressure",
    "ticks",
    "zone_legend",
]

#: the zones' colours: stick, forward slip, backward slip, separated
ZONE_COLOURS = ("#23395d", "#c51b7d", "#f4a259", "#ececec")


def check_result(model, result):
    if getattr(result, "contact", None) is None or result.t.size != result.steps_used + 1:
        raise InputError(
            "result",
            "has no recorded cycle: solve the model with lcpfric.steady_state(model, history=True)",
        )
    if result.state.shape[1] != model.nodes:
        raise InputError(
            "result",
            f"has {result.state.shape[1]} nodes, the model {model.nodes}: not this model's result",
        )


def index(result, fraction: float, name: str = "fractions") -> int:
    """The recorded instant nearest to ``fraction`` of the period. The first instant (t = 0)
    is taken at the end of the cycle instead (t = T, the same instant of the periodic
    state)."""
    t = np.asarray(result.t, dtype=float)
    f = float(fraction)
    if not math.isfinite(f) or not 0.0 <= f <= 1.0:
        raise InputError(name, f"must be fractions of the period in [0, 1], got {f!r}")
    j = int(np.argmin(np.abs(t / t[-1] - f)))
    return t.size - 1 if j == 0 else j


def codes(state: np.ndarray) -> np.ndarray:
    """State codes (:class:`~lcpfric.results.State`) as indices into :data:`ZONE_COLOURS`."""
    from ..results import State

    order = (State.STICK, State.FORWARD, State.BACKWARD, State.SEPARATION)
    out = np.full(state.shape, 3.0)
    for i, s in enumerate(order):
        out[state == int(s)] = i
    return out


def grid(model):
    """Element-centre coordinates along x and y over a0, and the element side over a0."""
    N = model.N
    x = model.xy[:, 0].reshape(N, N)[:, 0] / model.a0
    y = model.xy[:, 1].reshape(N, N)[0, :] / model.a0
    return x, y, model.h / model.a0


def outline(mask: np.ndarray, x, y, w):
    """The element edges between the elements in ``mask`` ((N, N), ``[i, j]`` at
    ``(x_i, y_j)``) and the others: line segments ``(k, 2, 2)``."""
    m = np.pad(mask.astype(bool), 1)
    half = w / 2.0
    xs = np.concatenate([[x[0] - w], x, [x[-1] + w]])
    ys = np.concatenate([[y[0] - w], y, [y[-1] + w]])
    segs = []
    i, j = np.nonzero(m[1:, :] != m[:-1, :])  # edges normal to x, between i and i+1
    for a, b in zip(i, j):
        xe = xs[a] + half
        segs.append(((xe, ys[b] - half), (xe, ys[b] + half)))
    i, j = np.nonzero(m[:, 1:] != m[:, :-1])  # edges normal to y
    for a, b in zip(i, j):
        ye = ys[b] + half
        segs.append(((xs[a] - half, ye), (xs[a] + half, ye)))
    return np.asarray(segs, dtype=float).reshape(-1, 2, 2)


def crop(model, result, margin: float = 0.15):
    """Half the side of the square (over a0, centred on the grid's centre) that holds every
    element ever in contact over the cycle, plus ``margin`` a0 (and one element)."""
    from ..results import State

    ever = np.any(result.state != int(State.SEPARATION), axis=0)
    if not ever.any():
        ever = np.ones(model.nodes, dtype=bool)
    x, y, w = grid(model)
    X, Y = np.meshgrid(x, y, indexing="ij")
    reach = float(np.max(np.maximum(np.abs(X.ravel()[ever]), np.abs(Y.ravel()[ever]))))
    half = reach + w / 2.0 + max(margin, w)
    edge = float(max(np.abs(x).max(), np.abs(y).max())) + w / 2.0
    return min(half, edge)


def loads_label(model, t: float, period: float) -> str:
    P = float(np.asarray(model.P(t))) / model.P0 + 0.0
    Q = float(np.asarray(model.Q(t))) / (model.mu * model.P0)
    Q = 0.0 if abs(Q) < 5e-3 else Q  # no "-0.00"
    f = t / period
    f = 0.0 if abs(f - 1.0) < 1e-9 else f  # t = T is t = 0 of the periodic state
    return (
        f"t/T = {f:.3g}\n"
        rf"$P/P_0$ = {P:.2f}, $Q/(\mu P_0)$ = {Q:+.2f}"
    )


def zone_legend(model, extra=()):
    from matplotlib.patches import Patch

    labels = ("stick", "slip towards +x", "slip towards −x", "separated")
    handles = [
        Patch(facecolor=c, edgecolor="0.3", lw=0.4, label=k) for k, c in zip(labels, ZONE_COLOURS)
    ]
    return handles + list(extra)


def halo():
    from matplotlib import patheffects

    return [patheffects.withStroke(linewidth=1.8, foreground="white")]


def hertz_style():
    """Black dashes on a white halo: visible on every zone colour."""
    return {"ec": "black", "lw": 0.8, "ls": (0, (2.5, 1.5)), "path_effects": halo()}


def hertz_radius(model, P: float):
    """The sphere's Hertz contact radius at P over a0 (None for the other surfaces)."""
    if getattr(model, "geometry", None) != "sphere" or P <= 0.0:
        return None
    return (P / model.P0) ** (1.0 / 3.0)


def draw_zones(ax, model, result, j, x, y, w, half):
    """One zone map on ``ax`` at the recorded instant j: (mesh, contact-edge lines, Hertz
    circle or None)."""
    from matplotlib.collections import LineCollection
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Circle

    from ..results import State

    N = model.N
    state = result.state[j].reshape(N, N)
    mesh = ax.pcolormesh(
        x,
        y,
        codes(state).T,
        cmap=ListedColormap(ZONE_COLOURS),
        vmin=-0.5,
        vmax=3.5,
        shading="nearest",
        rasterized=True,
    )
    edge = LineCollection(
        outline(state != int(State.SEPARATION), x, y, w),
        colors="black",
        linewidths=0.8,
        capstyle="projecting",
    )
    ax.add_collection(edge)
    circle = None
    rho = hertz_radius(model, float(np.asarray(model.P(result.t[j]))))
    if rho is not None:
        circle = Circle((0.0, 0.0), rho, fill=False, **hertz_style())
        ax.add_patch(circle)
    ax.set_xlim(-half, half)
    ax.set_ylim(-half, half)
    ax.set_aspect("equal")
    return mesh, edge, circle


def edge_handles(model, stick_edge: bool = False):
    from matplotlib.lines import Line2D

    out = [Line2D([], [], color="black", lw=0.8, label="contact edge (elements)")]
    if stick_edge:
        out.append(
            Line2D(
                [], [], color="black", lw=0.8, ls=(0, (1.2, 1.2)), label="edge of the stick zone"
            )
        )
    if getattr(model, "geometry", None) == "sphere":
        hs = hertz_style()
        out.append(
            Line2D(
                [],
                [],
                color=hs["ec"],
                lw=hs["lw"],
                ls=hs["ls"],
                path_effects=hs["path_effects"],
                label="Hertz contact radius at P(t)",
            )
        )
    return out


def ticks(ax):
    from matplotlib.ticker import MaxNLocator

    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(MaxNLocator(nbins=4, steps=[1, 2, 2.5, 5, 10], symmetric=True))


# -- figures --------------------------------------------------------------------------------------
def caption(model, sides: bool = True) -> str:
    """The legend's title: the surface, the grid (as asked: for a sphere or a punch the
    elements across the largest contact, ``grid_across``, then the whole grid with its margins),
    the tangential directions, a0."""
    across = getattr(model, "grid_across", None)
    N = model.N
    if across is not None and across != N:
        head = (
            f"{model.geometry}, {across} elements across the largest contact ({N} x {N} in all)\n"
        )
    else:
        head = f"{model.geometry}, {N} x {N} elements, "
    if model.dims == 1:
        head += "tractions along x"
    elif sides:
        head += "tractions in the plane\n(slip towards ±x: the sign of the slip's x-component)"
    else:
        head += "tractions in the plane"
    return head + "\n" + r"$a_0$: contact radius at the mean load $P_0$"


def peak_pressure(model):
    """The pressure scale p0 and its description: Hertz's at P0 for the sphere, else the
    largest pressure of the discrete contact at P0."""
    if getattr(model, "geometry", None) == "sphere":
        return 3.0 * model.P0 / (2.0 * math.pi * model.a0**2), r"$p_0$: Hertz's peak pressure"
    return float(np.max(model.pressure(model.P0))), r"$p_0$: peak pressure at $P_0$"


def nice(x: float) -> float:
    """A round number (1, 2, 2.5 or 5 times a power of ten) at most ``x``."""
    if x <= 0:
        return 1.0
    e = math.floor(math.log10(x))
    for m in (5.0, 2.5, 2.0, 1.0):
        if m * 10**e <= x:
            return m * 10**e
    return 10**e
