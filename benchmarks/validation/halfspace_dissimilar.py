"""Dissimilar materials on the half-space (issue 38, item 5): lcpfric against tamaas.

    OPENBLAS_NUM_THREADS=1 python benchmarks/validation/halfspace_dissimilar.py [--quick]

writes ``benchmarks/results/halfspace-dissimilar.md``. Needs tamaas (``pip install
tamaas==2.9.0``; an optional dependency: lcpfric's tests that use it skip without it).

The problem: a rigid paraboloid (effective radius R) on an elastic half-space (E, ν) (lcpfric:
``HalfSpace.sphere(..., E2=inf)``, body 1 the elastic one, Dundurs' β = (1 − 2ν)/(2(1 − ν))),
friction μ, the normal load P and the tangential load Q along x, from the undeformed state.
tamaas's ``PolonskyKeerTan`` solves it in one shot (Coulomb friction, the slip measured from the
undeformed surface, the periodic Westergaard operator of the ``surface_2d`` model, the full
3 x 3 coupling); lcpfric's is one increment of its coupled stepper from the undeformed state
(``first_loading(model, Q, steps=1)``, d = 2: tractions in the plane, as tamaas's), the same
problem on the same grid: h and the element centres equal, tamaas's periodic cell ``fac``
times lcpfric's grid side (the periodic images far away), the rigid surface ``−r²/(2R)`` and
the mean traction ``(ΣF, 0, P)/L²`` (lcpfric's friction forces F on body 1 sum to −Q).

Compared on lcpfric's N x N window: the contact set, the stick set (|q| < μ p (1 − 1e-4) for
both; lcpfric's own set, the elements that do not slip, is printed too), the peak pressure and
the peak traction, the stick zone's centroid and the pressure's centroid (over a, the Hertz
radius of the composite E*), the pressure's asymmetry ``max |p(x, y) − p(−x, y)| / max p``, and
the largest differences of the fields. lcpfric's path-dependent first loading (P first, which
is Spence's frictional indentation where β ≠ 0, then Q in 8 increments) is given beside it.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _report import Report, stamp  # noqa: E402

from lcpfric.model.continuum import HalfSpace  # noqa: E402
from lcpfric.steppers.coupled_halfspace import first_loading  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "results" / "halfspace-dissimilar.md"
R, E, P = 1.0, 1.0, 3e-4
#: stick: |q| < μ p (1 − STICK) (both codes)
STICK = 1e-4


def tamaas_solve(N, h, fac, nu, mu, Q, tol=1e-10, max_iter=1500):
    """tamaas's one-shot coupled problem on an (fac N)² periodic cell; its fields on the
    centre N x N window: ``(p, q (2, N, N), seconds)``."""
    import tamaas as tm

    tm.set_log_level(tm.LogLevel.error)
    Nt = fac * N
    L = Nt * h
    model = tm.ModelFactory.createModel(tm.model_type.surface_2d, [L, L], [Nt, Nt])
    model.E, model.nu = E, nu
    c = (np.arange(Nt) - (Nt - 1) / 2) * h
    X, Y = np.meshgrid(c, c, indexing="ij")
    solver = tm.PolonskyKeerTan(model, -(X**2 + Y**2) / (2 * R), tol, mu)
    solver.max_iter = max_iter
    t0 = time.perf_counter()
    solver.solve([-Q / L**2, 0.0, P / L**2])  # lcpfric's ΣF = −Q
    seconds = time.perf_counter() - t0
    o = (Nt - N) // 2
    tr = np.array(model.traction)[o : o + N, o : o + N]
    return tr[..., 2].copy(), np.moveaxis(tr[..., :2], -1, 0).copy(), seconds


def summary(model, p, q, mu, stick=None):
    """The compared quantities of fields on lcpfric's grid."""
    N, a = model.N, model.a0
    X = model.xy[:, 0].reshape(N, N)
    contact = p > 0
    ratio = np.hypot(*q) / np.where(contact, mu * p, 1.0)
    by_traction = contact & (ratio < 1 - STICK)
    st = by_traction if stick is None else stick
    return {
        "contact": int(contact.sum()),
        "stick": int(st.sum()),
        "p_max": float(p.max()),
        "q_max": float(np.hypot(*q).max()),
        "stick_x": float(X[st].mean() / a) if st.any() else float("nan"),
        "p_x": float((X * p).sum() / p.sum() / a),
        "asym": float(np.abs(p - p[::-1, :]).max() / p.max()),
    }


def case(rep, grid, nu, mu, x, fac, dims=2, paths=True):
    """One case: lcpfric (one increment from the undeformed state, and the path P then Q)
    against tamaas."""
    model = HalfSpace.sphere(R, E, nu, mu, P, 0.0, grid=grid, dims=dims, E2=np.inf)
    Q = x * mu * P
    t0 = time.perf_counter()
    one = first_loading(model, Q, steps=1)
    t_l = time.perf_counter() - t0
    pt, qt, t_t = tamaas_solve(model.N, model.h, fac, nu, mu, Q)
    tau = one["tau"] if dims == 2 else np.stack([one["tau"][0], 0 * one["tau"][0]])
    L = summary(model, one["p"], tau, mu)
    Ls = summary(model, one["p"], tau, mu, one["stick"])
    T = summary(model, pt, qt, mu)
    dp = float(np.abs(one["p"] - pt).max() / pt.max())
    dq = float(np.abs(tau - qt).max() / (mu * pt.max()))
    rel = {k: (L[k] - T[k]) / T[k] for k in ("stick", "p_max", "q_max", "contact")}
    rep.emit(
        f"| {grid} | {model.N} | {fac * model.N} | {nu} | {model.beta:.4f} | {mu} | {x} | {dims} "
        f"| {L['contact']} / {T['contact']} | {L['stick']} ({Ls['stick']}) / {T['stick']} "
        f"| {100 * rel['stick']:+.2f} | {L['p_max']:.5g} / {T['p_max']:.5g} "
        f"| {100 * rel['p_max']:+.2f} | {L['q_max']:.5g} / {T['q_max']:.5g} "
        f"| {100 * rel['q_max']:+.2f} | {L['stick_x']:+.4f} / {T['stick_x']:+.4f} "
        f"| {L['p_x']:+.5f} / {T['p_x']:+.5f} | {L['asym']:.4f} / {T['asym']:.4f} "
        f"| {100 * dp:.2f} | {100 * dq:.2f} | {one['iterations'][0]} | {t_l:.2f} / {t_t:.1f} |"
    )
    out = {"L": L, "T": T, "rel": rel, "model": model}
    if paths:
        path = first_loading(model, Q, steps=8, start="normal")
        out["path"] = summary(model, path["p"], path["tau"], mu, path["stick"])
        out["path_iterations"] = path["iterations"]
    return out


HEAD = (
    "| grid | N | tamaas cell | ν | β | μ | Q/μP | d | contact (elements) lcpfric / tamaas "
    "| stick lcpfric (its own set) / tamaas | Δ stick % | p_max | Δ % | |q|_max | Δ % "
    "| stick centroid x/a | pressure centroid x/a | asymmetry | max Δp % | max Δq % of μ p_max "
    "| alternations | seconds lcpfric / tamaas |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
)


CELL = (
    "## tamaas's periodic cell (grid 24, ν = 0.3, μ = 0.3)\n\n"
    "tamaas's operator is periodic and drops the tractions' mean: its contact sits in a "
    "uniform traction −(Q, 0, P)/L² over the cell, whose coupled slip is a uniform radial "
    "strain of order β P/(E* L²), about (a/L)² of the contact's own (2 % at the cell 4 N). "
    "With the cell grown, tamaas's stick set becomes lcpfric's:"
)


ITERATIONS = (
    "## tamaas's iterations on the larger cells\n\n"
    "With a net tangential load, tamaas's 1500 iterations do not suffice on the larger cells: "
    "its answer still moves at 4000 (towards lcpfric's):"
)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    quick = "--quick" in argv
    try:
        import tamaas
    except ImportError:
        print("needs tamaas: pip install tamaas==2.9.0", file=sys.stderr)
        return 2
    rep = Report()
    rep.emit("# Dissimilar materials on the half-space: lcpfric against tamaas")
    rep.emit("")
    rep.emit(stamp("validation/halfspace_dissimilar.py" + (" --quick" if quick else "")))
    rep.emit("")
    rep.emit(
        f"tamaas {tamaas.__version__} (`PolonskyKeerTan`, tolerance 1e-10, at most 1500 "
        "iterations, which it reaches: its stick sets are those of 4000 iterations on grids "
        "40 and 64 with the cell 4 N (the traction ratios to 1e-6 on grid 40), its fields "
        "those of 3000 iterations to 1e-9 on grid 24; not so on the larger cells with a "
        "tangential load: see the section on its iterations). A rigid paraboloid "
        f"(R = {R}) on an elastic half-space (E = {E}, ν), P = {P}, Q along x from the "
        "undeformed state; lcpfric: `HalfSpace.sphere(R, E, nu, mu, P, 0, grid=..., dims=2, "
        "E2=inf)` and `first_loading(model, Q, steps=1)`. Each pair `a / b` is lcpfric / "
        "tamaas; Δ is lcpfric's relative difference; the stick set is |q| < μp(1 − 1e-4) for "
        "both (in parentheses lcpfric's own: the elements that did not slip). The "
        "centroids are over a (Hertz's radius with the composite E*); asymmetry is max|p(x, "
        "y) − p(−x, y)|/max p. Alternations: lcpfric's normal/tangential fixed-point "
        "iterations (to 1e-9 of the pressures)."
    )
    rep.emit("")
    rep.emit(
        "## Cases (grid 40: 40 elements across the contact diameter; tamaas's cell 8 times "
        "lcpfric's grid side)"
    )
    rep.emit("")
    rep.emit(HEAD)
    grids = (24,) if quick else (40,)
    results = []
    for grid in grids:
        for nu, mu, x in (
            (0.3, 0.3, 0.5),
            (0.3, 0.5, 0.3),
            (0.3, 0.3, 0.8),
            (0.2, 0.4, 0.5),
            (0.45, 0.3, 0.5),
            (0.499, 0.3, 0.5),
        ):
            results.append(case(rep, grid, nu, mu, x, 4 if quick else 8))
    rep.emit("")
    rep.emit(
        "## Discretization and the periodic cell (ν = 0.3, μ = 0.3, Q = 0.5 and 0.8 μP; "
        "last, ν = 0.45)"
    )
    rep.emit("")
    rep.emit(HEAD)
    runs = (
        ((16, 4, 0.5), (24, 4, 0.5), (24, 8, 0.5), (24, 4, 0.8))
        if quick
        else ((24, 4, 0.5), (40, 4, 0.5), (64, 4, 0.5), (24, 4, 0.8), (40, 4, 0.8), (64, 4, 0.8))
    )
    for grid, fac, x in runs:
        case(rep, grid, 0.3, 0.3, x, fac, paths=False)
    if not quick:  # a smaller β on the finest grid
        case(rep, 64, 0.45, 0.3, 0.5, 4, paths=False)
        rep.emit("")
        rep.emit(CELL)
        rep.emit("")
        rep.emit(HEAD)
        for x, fac in ((0.0, 4), (0.0, 8), (0.0, 12), (0.5, 12), (0.8, 12)):
            case(rep, 24, 0.3, 0.3, x, fac, paths=False)
        rep.emit("")
        rep.emit(ITERATIONS)
        rep.emit("")
        rep.emit(
            "| grid | tamaas cell | Q/μP | iterations | seconds | stick tamaas (lcpfric) "
            "| stick centroid x/a tamaas (lcpfric) | \\|q\\|_max tamaas (lcpfric) |\n"
            "|---|---|---|---|---|---|---|---|"
        )
        for grid, fac, x in ((24, 12, 0.8), (40, 8, 0.8), (24, 12, 0.5), (40, 8, 0.5)):
            m = HalfSpace.sphere(R, E, 0.3, 0.3, P, 0.0, grid=grid, dims=2, E2=np.inf)
            Q = x * 0.3 * P
            one = first_loading(m, Q, steps=1)
            L = summary(m, one["p"], one["tau"], 0.3)
            for it in (1500, 4000):
                pt, qt, sec = tamaas_solve(m.N, m.h, fac, 0.3, 0.3, Q, max_iter=it)
                T = summary(m, pt, qt, 0.3)
                rep.emit(
                    f"| {grid} | {fac * m.N} | {x} | {it} | {sec:.0f} | {T['stick']} "
                    f"({L['stick']}) | {T['stick_x']:+.4f} ({L['stick_x']:+.4f}) "
                    f"| {T['q_max']:.5g} ({L['q_max']:.5g}) |"
                )
    rep.emit("")
    rep.emit("## d = 1 (tractions along x only) against tamaas's full problem (grid 40)")
    rep.emit("")
    rep.emit(HEAD)
    case(rep, grids[0], 0.3, 0.3, 0.5, 4, dims=1, paths=False)
    case(rep, grids[0], 0.499, 0.3, 0.5, 4, dims=1, paths=False)
    rep.emit("")
    rep.emit("## lcpfric's first loading along a path: P first, then Q in 8 increments (d = 2)")
    rep.emit("")
    rep.emit(
        "| ν | β | μ | Q/μP | stick (elements) one-shot / path | stick centroid x/a one-shot / "
        "path | pressure centroid x/a one-shot / path | p_max one-shot / path "
        "| alternations per increment |\n|---|---|---|---|---|---|---|---|---|"
    )
    for r, (nu, mu, x) in zip(
        results,
        (
            (0.3, 0.3, 0.5),
            (0.3, 0.5, 0.3),
            (0.3, 0.3, 0.8),
            (0.2, 0.4, 0.5),
            (0.45, 0.3, 0.5),
            (0.499, 0.3, 0.5),
        ),
    ):
        L, Pth = r["L"], r["path"]
        rep.emit(
            f"| {nu} | {r['model'].beta:.4f} | {mu} | {x} | {L['stick']} / {Pth['stick']} "
            f"| {L['stick_x']:+.4f} / {Pth['stick_x']:+.4f} | {L['p_x']:+.5f} / "
            f"{Pth['p_x']:+.5f} | {L['p_max']:.5g} / {Pth['p_max']:.5g} "
            f"| {r['path_iterations']} |"
        )
    rep.emit("")
    rep.emit("## Spence's frictional indentation (Q = 0): the stick radius at two loads")
    rep.emit("")
    rep.emit(
        "Spence (1975) showed the normal loading of dissimilar spheres with finite friction "
        "is self-similar: a central stick disc whose radius c/a depends on β/μ only, not on "
        "P. lcpfric, one increment from the undeformed state to P at Q = 0 (d = 2), "
        "c = sqrt(stick area/π), at P and 2P on the same grid (the elements of the grid "
        "sized for 2P: the discrete problems are not scaled copies of each other):"
    )
    rep.emit("")
    rep.emit(
        "| ν | β | μ | β/μ | elements across 2a at P / 2P | c/a at P | c/a at 2P |\n"
        "|---|---|---|---|---|---|---|"
    )
    grid = grids[0]
    for nu, mu in ((0.3, 0.3), (0.3, 0.5), (0.2, 0.2)):
        big = HalfSpace.sphere(R, E, nu, mu, 2 * P, 0.0, grid=grid, dims=2, E2=np.inf)
        cs, across = [], []
        for load in (P, 2 * P):
            m = HalfSpace(E, nu, mu, load, 0.0, heights=big.g0, spacing=big.h, dims=2, E2=np.inf)
            r0 = first_loading(m, 0.0, steps=1)
            a = (3 * load * R / (4 * m.moduli["E*"])) ** (1 / 3)
            cs.append(np.sqrt(r0["stick"].sum() * m.h**2 / np.pi) / a)
            across.append(f"{2 * a / m.h:.1f}")
        rep.emit(
            f"| {nu} | {m.beta:.4f} | {mu} | {m.beta / mu:.3f} | {' / '.join(across)} "
            f"| {cs[0]:.3f} | {cs[1]:.3f} |"
        )
    rep.emit("")
    rep.emit("## The steady dissipation: d = 1 and d = 2, with the coupling and without it")
    rep.emit("")
    rep.emit(
        "`lcpfric.steady_state(model, steps_per_cycle=40)` at constant P with Q = Q1 sin ωt, "
        "a rigid base (ν = 0.3, β = 0.2857, μ = 0.3); 'uncoupled' is the same model with its "
        "coupling removed (`model.coupling = None`: the composite moduli only, Goodman's "
        "approximation), W normalized by k_t0/(μ P0)²:"
    )
    rep.emit("")
    rep.emit(
        "| grid | Q1/μP | d | W coupled | W uncoupled | coupled/uncoupled − 1 | cycles "
        "| alternations per increment (mean, max) | seconds |\n"
        "|---|---|---|---|---|---|---|---|---|"
    )
    from lcpfric import steady_state
    from lcpfric.model.loads import Harmonic

    for x in (0.3, 0.7):
        for dims in (1, 2):
            Ws = []
            for coupled in (True, False):
                m = HalfSpace.sphere(
                    R,
                    E,
                    0.3,
                    0.3,
                    P,
                    Harmonic(0.0, x * 0.3 * P),
                    grid=grid,
                    dims=dims,
                    E2=np.inf,
                )
                if not coupled:
                    m.coupling = None
                t0 = time.perf_counter()
                r = steady_state(m, steps_per_cycle=40)
                Ws.append((r.W_normalized, r.cycles, r.solver_stats, time.perf_counter() - t0))
            (w1, c1, st, sec), (w0, *_) = Ws
            mean = st["coupling_iterations"] / st["coupling_increments"]
            rep.emit(
                f"| {grid} | {x} | {dims} | {w1:.6g} | {w0:.6g} | {w1 / w0 - 1:+.3e} | {c1} "
                f"| {mean:.2f}, {st['coupling_max']} | {sec:.1f} |"
            )
    rep.write(OUT)
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
