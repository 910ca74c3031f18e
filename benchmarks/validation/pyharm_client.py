"""A real client (issue 39, item 5): lcpfric's Jenkins element inside pyHarm's forced-response
computation, against pyHarm's own Jenkins element and the notes' closed forms.

``OPENBLAS_NUM_THREADS=1 python benchmarks/validation/pyharm_client.py [--out DIR]``

writes ``DIR/pyharm-client.md`` (default ``benchmarks/results``); about 20 seconds. Without
pyHarm (``pip install pyharm-os``) it says so and writes nothing.

The oscillator: one mass m on a spring k and a damper c, a Jenkins element (kt, μN) to ground,
forced by F cos ωt; 5 harmonics, 128 samples per period, ω from 0.5 to 2 (through the
resonance, stuck at both ends, up to 3.5 slip limits at the peak).

1. The frequency-response curves: (a) pyHarm's continuation with its own ``Jenkins`` element,
   (b) the same with lcpfric's element (``"type": "LcpfricJenkins"``, plugged into pyHarm's
   element factory by :func:`lcpfric.harmonic.pyharm.register_pyharm_element`), (c) lcpfric's
   own harmonic-balance loop (:func:`lcpfric.harmonic.balance.forced_response`); their
   agreement point by point, each curve's points in the other code's equations, and wall
   times (best of 3).
2. The force harmonics at three points of the curve (stuck, the peak, slipping above it): the
   motion's first harmonic alone, ``a cos(ωt - φ)``, through both elements, against the notes'
   closed form ``(k_eq a, -ω c_eq a)`` in the motion's frame, at 64 to 1024 samples, with the
   fitted order.
3. One element's residual and Jacobian as pyHarm calls them (``evalResidual`` +
   ``evalJacobian``), both elements, microseconds per call.
4. Two tangential directions (``dirs: [0, 1]``): pyHarm's element marches three periods from a
   zero slider, lcpfric's to the steady cycle; both against a plain march of 1000 periods.
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [str(_ROOT), str(_ROOT / "benchmarks"), str(_ROOT / "tests")]

from _report import results_file  # noqa: E402 (benchmarks/ on the path above)
import argparse  # noqa: E402
import os  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

from lcpfric.analysis.describing import jenkins_closed_form  # noqa: E402
from lcpfric.harmonic import fourier_basis  # noqa: E402
from lcpfric.harmonic.balance import forced_response, harmonic_residual  # noqa: E402
from support import fitted_order  # noqa: E402

# importing pyHarm writes .pyHarm/context.json into the working directory: a scratch file
os.environ.setdefault(
    "PYHARM_CONTEXT_FILE", str(_Path(tempfile.gettempdir()) / "lcpfric-pyharm" / "context.json")
)

M, C, K, KT, MU, N, F = 1.0, 0.02, 1.0, 1.0, 0.3, 1.0, 0.3
FS = MU * N
H, NS, BAND = 5, 128, (0.5, 2.0)
NAMES = {"Jenkins": "pyHarm, its Jenkins element", "LcpfricJenkins": "pyHarm, lcpfric's element"}


def element(cls, nh, samples, dirs=(0,)):
    """A pyHarm element on one node (to ground), its dof table built as pyHarm's systems do."""
    import pandas as pd
    from pyHarm.CoordinateSystem import GlobalCoordinateSystem

    d = len(dirs)
    data = {"connect": {"sub": [0]}, "dirs": list(dirs), "mu": MU, "N0": N, "k": KT}
    e = cls(nh, samples, "jenkins", data, GlobalCoordinateSystem(d))
    blocks = [(h, cs) for h in range(nh + 1) for cs in (("c",) if h == 0 else ("c", "s"))]
    rows = [(h, cs, j) for h, cs in blocks for j in range(d)]
    e.generateIndices(
        pd.DataFrame({"sub": "sub", "node_num": 0, "harm": [r[0] for r in rows],
                      "cs": [r[1] for r in rows], "dof_num": [r[2] for r in rows]})
    )  # fmt: skip
    return e


def classes():
    from pyHarm.Elements.NodeToNodeElements.Jenkins import Jenkins

    from lcpfric.harmonic.pyharm import pyharm_element_class

    return {"Jenkins": Jenkins, "LcpfricJenkins": pyharm_element_class()}


def curves():
    from lcpfric.harmonic.pyharm import oscillator_input, pyharm_frequency_response

    print("## 1. The frequency-response curves\n")
    print(
        f"m = {M}, c = {C}, k = {K}, kt = {KT}, μ = {MU}, N = {N}, F = {F} (slip limit μN/kt = "
        f"{FS / KT}); H = {H} harmonics, {NS} samples per period, ω from {BAND[0]} to "
        f"{BAND[1]}; pyHarm's defaults (tangent predictor, arc-length corrector, scipy's "
        "`root` (hybr), `ds0` 0.01, `ds_max` 0.05); lcpfric's loop with `tol=1e-12`. Wall "
        "seconds of the continuation, best of 3.\n"
    )
    out = {}
    for name in NAMES:
        data = oscillator_input(
            M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, element=name, harmonics=H, samples=NS
        )
        runs = [pyharm_frequency_response(data) for _ in range(3)]
        out[name] = min(runs, key=lambda r: r["seconds"])
    runs = [
        forced_response(
            M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, harmonics=H, samples=NS, tol=1e-12
        )
        for _ in range(3)
    ]
    own = min(runs, key=lambda r: r.seconds)
    print("| curve | points | rejected | seconds | peak ω | peak a / (μN/kt) |")
    print("|---|---|---|---|---|---|")
    for name, label in NAMES.items():
        r = out[name]
        a = np.hypot(r["x"][:, 1], r["x"][:, 2])
        print(
            f"| {label} | {r['omega'].size} | {r['rejected']} | {r['seconds']:.2f} | "
            f"{r['omega'][a.argmax()]:.5f} | {a.max() / FS:.5f} |"
        )
    a = own.amplitude()
    print(
        f"| lcpfric's loop (`forced_response`) | {own.omega.size} | - | {own.seconds:.2f} | "
        f"{own.omega[a.argmax()]:.5f} | {a.max() / FS:.5f} |\n"
    )
    pa, pb = out["Jenkins"], out["LcpfricJenkins"]
    if pa["omega"].size == pb["omega"].size:
        dx = np.abs(pa["x"] - pb["x"]).max() / np.abs(pa["x"]).max()
        dw = np.abs(pa["omega"] - pb["omega"]).max()
        print(
            f"- (a) and (b), point by point: the same {pa['omega'].size} points; coefficients "
            f"differ by {dx:.1e} (relative to the largest), ω by {dw:.1e}."
        )
    else:
        print(f"- (a) and (b) took {pa['omega'].size} and {pb['omega'].size} points.")
    kw = dict(kt=KT, mu=MU, normal_load=N, samples=NS)
    for name in NAMES:
        r = out[name]
        worst_r = worst_a = 0.0
        for x, w in zip(r["x"], r["omega"]):
            q = x.reshape(1, -1)
            res, J, _ = harmonic_residual(q, w, M, C, K, F, **kw)
            worst_r = max(worst_r, np.linalg.norm(res) / F)
            for _ in range(10):
                q = q - np.linalg.solve(J, res.ravel()).reshape(q.shape)
                res, J, _ = harmonic_residual(q, w, M, C, K, F, **kw)
                if np.linalg.norm(res) <= 1e-13 * F:
                    break
            worst_a = max(worst_a, abs(np.hypot(*q[0, 1:3]) - np.hypot(*x[1:3])) / FS)
        print(
            f"- {NAMES[name]}: its points in lcpfric's harmonic-balance equations "
            f"(`harmonic_residual`), largest residual {worst_r:.1e} F (pyHarm's solver "
            f"tolerance); Newton on them at the same ω moves the amplitude by at most "
            f"{worst_a:.1e} slip limits."
        )
    system = pa["system"]
    worst = max(
        np.linalg.norm(system.Residual(np.append(q.ravel(), w))) / F
        for q, w in zip(own.coefficients, own.omega)
    )
    print(
        f"- (c) lcpfric's loop: its points in pyHarm's system equations (pyHarm's own element), "
        f"largest residual {worst:.1e} F; its own Newton tolerance 1e-12 F, at most "
        f"{own.iterations.max()} iterations per point."
    )
    print(
        "\nThe peaks differ only by where the points fall (pyHarm's step is in raw (x, ω), "
        "lcpfric's follows the turning of the curve): every point of each curve solves the "
        "other code's equations.\n"
    )
    return own


def harmonics(own):
    print("## 2. Force harmonics against the closed form\n")
    a = own.amplitude()
    peak = int(a.argmax())
    picks = {"stuck": 0, "peak": peak, "slipping": peak + int(np.abs(a[peak:] - 2 * FS).argmin())}
    cls = classes()
    print(
        "The motion's first harmonic at each point alone, `a cos(ωt - φ)`, through each "
        "element (as pyHarm calls it); its force's first harmonic rotated into the motion's "
        "frame against `(k_eq a, -ω c_eq a)`: the larger of the two errors, in units of μN.\n"
    )
    sizes = (64, 128, 256, 512, 1024)
    print("| point | ω | a / (μN/kt) | φ | element | " + " | ".join(f"Ns = {s}" for s in sizes)
          + " | fitted order |")  # fmt: skip
    print("|---|---|---|---|---|" + "---|" * (len(sizes) + 1))
    for label, i in picks.items():
        x = np.zeros(2 * H + 1)
        x[1:3] = own.coefficients[i, 0, 1:3]
        amp, phase = np.hypot(x[1], x[2]), np.arctan2(x[2], x[1])
        cf = jenkins_closed_form(KT, MU, N, [amp])
        kc, cq = cf["k_eq"][0] * amp, -cf["c_eq_omega"][0] * amp
        for name in NAMES:
            errs = []
            for ns in sizes:
                R = element(cls[name], H, ns).evalResidual(x, own.omega[i])
                ip = R[1] * np.cos(phase) + R[2] * np.sin(phase)
                qu = -R[1] * np.sin(phase) + R[2] * np.cos(phase)
                errs.append(max(abs(ip - kc), abs(qu - cq)) / FS)
            order = f"{fitted_order(sizes, errs):.2f}" if min(errs) > 1e-13 else "exact"
            print(
                f"| {label} | {own.omega[i]:.4f} | {amp / FS:.3f} | {phase:+.3f} | "
                f"{NAMES[name].split(', ')[1]} | " + " | ".join(f"{e:.1e}" for e in errs)
                + f" | {order} |"
            )  # fmt: skip
    print(
        "\nBoth elements take the discrete transform of the same sampled steady cycle (d = 1, "
        "constant N: pyHarm's three periods from a zero slider are already steady), so their "
        "errors are the same: the trapezoidal DFT across the slip onset's kink, order about 2 "
        "in the samples (not monotone: the kink's place between samples). Stuck, the force is "
        "kt x: exact.\n"
    )


def timing():
    print("## 3. One element as pyHarm calls it\n")
    rng = np.random.default_rng(0)
    X = rng.normal(size=(200, 2 * H + 1)) * FS * 3
    cls = classes()
    print(f"`evalResidual` + `evalJacobian`, {H} harmonics, {NS} samples, 200 random motions "
          "(best of 3), microseconds per call pair:\n")  # fmt: skip
    for name in NAMES:
        e = element(cls[name], H, NS)
        e.evalResidual(X[0], 1.0)
        e.evalJacobian(X[0], 1.0)  # compile (numba) / warm up
        best = np.inf
        for _ in range(3):
            t = time.perf_counter()
            for x in X:
                e.evalResidual(x, 1.0)
                e.evalJacobian(x, 1.0)
            best = min(best, (time.perf_counter() - t) / X.shape[0])
        print(f"- {NAMES[name]}: {1e6 * best:.0f} µs")
    print(
        "\nlcpfric's element evaluates the AFT once per point (the residual and the Jacobian "
        "together, kept for the Jacobian call) where pyHarm's marches once for each; per "
        "element lcpfric is dominated by its Python overhead (it is built for many elements "
        "per call: benchmarks/results/aft.md).\n"
    )


def two_directions():
    print("## 4. Two tangential directions\n")
    rng = np.random.default_rng(5)
    ns, nh, n = 64, 2, 200
    cls = classes()
    els = {name: element(cls[name], nh, ns, dirs=(0, 1)) for name in NAMES}
    X = rng.normal(size=(n, 2 * (2 * nh + 1))) * FS * rng.choice([0.3, 3.0, 30.0], (n, 1))
    basis = fourier_basis(nh, ns)
    xs = np.einsum("nkd,sk->nds", X.reshape(n, -1, 2), basis.E)  # (n, 2, Ns)
    s = np.zeros((n, 2))
    for _ in range(1000):  # a plain radial-return march, all motions at once
        T = np.empty_like(xs)
        for k in range(ns):
            gap = xs[:, :, k] - s
            norm = np.linalg.norm(gap, axis=1)
            slip = KT * norm > FS
            s[slip] = xs[slip, :, k] - FS / KT * gap[slip] / norm[slip, None]
            T[:, :, k] = KT * (xs[:, :, k] - s)
    ref = np.einsum("nds,ks->nkd", T, basis.D).reshape(n, -1)
    print(f"{n} random motions, {nh} harmonics, {ns} samples, amplitudes 0.3 to 30 slip "
          "limits; the force coefficients against a plain march of 1000 periods:\n")  # fmt: skip
    for name in NAMES:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            err = np.abs(np.array([els[name].evalResidual(x, 1.0) for x in X]) - ref).max(1)
        print(f"- {NAMES[name]}: largest error {err.max() / FS:.1e} μN; "
              f"{(err > 1e-9 * FS).sum()} of {n} motions off by more than 1e-9 μN")  # fmt: skip
    print(
        "\npyHarm's element marches three periods from a zero slider; in d = 2 the slider "
        "keeps moving after that where the slip direction turns. lcpfric's element is the "
        "steady cycle (Newton steps on the period map from the second period).\n"
    )


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(_ROOT / "benchmarks" / "results"))
    args = p.parse_args(argv)
    try:
        import pyHarm  # noqa: F401
    except ImportError:
        print("pyHarm is not installed (pip install pyharm-os): nothing to compare; skipped.")
        return 0
    out = _Path(args.out) / "pyharm-client.md"
    with results_file(out, "lcpfric's Jenkins element inside pyHarm",
                      "validation/pyharm_client.py", markdown=True):  # fmt: skip
        own = curves()
        harmonics(own)
        timing()
        two_directions()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
