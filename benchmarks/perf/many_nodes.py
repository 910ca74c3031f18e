"""The many-node goals of the active-set backend, measured side by side in one run.

``OPENBLAS_NUM_THREADS=1 python benchmarks/perf/many_nodes.py [--quick] [--out benchmarks/results]``

1. **n = 400, dense K** (the chain of the issue: k_coupling = 0.5, P1 per node in [1.2, 2] so
   every node separates, Q1 in [0.5, 2], random phases; 500 steps per cycle plus the 800
   separation instants placed on the grid): CPU seconds per step of one cycle of ``active-set``,
   ``osqp`` and ``clarabel`` on the same scene (events located: the default of all three),
   their ratios, and the largest relative difference of W.
2. **n = 4000, dense SPD K** (``K = A Aᵀ/n + I``, full contact, 500 steps per cycle, events
   not located: one problem per step, first order): CPU seconds per step of the third cycle
   (the steady regime), and the same in products of the dense compliance C with a vector (the
   floor), timed in the same run.
3. **n = 1e5, sparse chain** (common normal load P = 1 + 1.5 sin ωt, so the grid keeps its 2000
   steps; Q1 and phases per node): a full steady state with ``history=False``, in a child
   process: wall seconds, cycles, peak resident memory.
4. **n = 4000, matrix-free** (a Toeplitz compliance ``C_ij = δ_ij + exp(-|i - j|/3)`` known
   only by its products, each one FFT pair, :func:`scipy.linalg.matmul_toeplitz`; loads as in
   2, 500 steps, events not located): CPU seconds per step of the second cycle, products with
   C per step, the time of one product (the floor), and W against the same system given by
   its stiffness matrix ``K = C⁻¹`` (the dense path) over the same two cycles.

``--quick`` runs n = 100, 1000, 1e4 and 1000 instead (about a minute). The results are written to
``many-nodes.md``. CPU times are taken with ``time.process_time`` (the machine is shared).
"""

from __future__ import annotations

import sys as _sys
from pathlib import Path as _Path

# the repository, the shared report writer, the perf scripts (halfspace's cases) and the tests'
# shared cases and references (tests/support)
_ROOT = _Path(__file__).resolve().parents[2]
_sys.path[:0] = [
    str(_ROOT),
    str(_ROOT / "benchmarks"),
    str(_ROOT / "benchmarks" / "perf"),
    str(_ROOT / "tests"),
]

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import lcpfric
from lcpfric.methods import get_stepper
from lcpfric.scene import make_scene


def separating_chain(n, seed=0):
    rng = np.random.default_rng(seed)
    return lcpfric.chain(
        n,
        k_coupling=0.5,
        P1=rng.uniform(1.2, 2.0, n),
        Q1=rng.uniform(0.5, 2.0, n),
        phi=rng.uniform(0, 2 * np.pi, n),
    )


def dense_spd(n, seed=0):
    from lcpfric.model import ContactSystem, Harmonic, IndependentSprings

    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n)) / np.sqrt(n)
    K = A @ A.T + np.eye(n)
    P1, Q1, phi = rng.uniform(0.1, 0.8, n), rng.uniform(0.5, 2.0, n), rng.uniform(0, 6.3, n)
    return ContactSystem(
        K,
        np.ones(n),
        tuple(Harmonic(0.0, Q1[i], phi[i]) for i in range(n)),
        IndependentSprings(tuple(Harmonic(1.0, P1[i]) for i in range(n))),
    )


def cycle_seconds(method, scene, cycles=1, **options):
    """CPU seconds per step of the last of ``cycles`` cycles, and its W."""
    stepper = get_stepper(method, **options)
    state = stepper.init(scene)
    for _ in range(cycles):
        t = time.process_time()
        state, cyc = stepper.cycle(scene, state)
        dt = time.process_time() - t
    return dt / scene.steps, cyc.W


def product_seconds(M, reps=20):
    x = np.random.default_rng(1).standard_normal(M.shape[0])
    M @ x
    t = time.process_time()
    for _ in range(reps):
        M @ x
    return (time.process_time() - t) / reps


def goal_ratios(n, steps=500):
    scene = make_scene(separating_chain(n), steps)
    out = {"n": n, "steps": scene.steps}
    for m in ("active-set", "osqp", "clarabel"):
        out[m] = cycle_seconds(m, scene)
    return out


def goal_products(n, steps=500):
    system = dense_spd(n)
    scene = make_scene(system, steps)
    sec, W = cycle_seconds("active-set", scene, cycles=3, locate_events=False)
    floor = product_seconds(np.linalg.inv(system.stiffness))
    return {"n": n, "steps": scene.steps, "seconds": sec, "floor": floor, "W": W}


def toeplitz_system(n, seed=0):
    """The system of goal 4: matrix-free (FFT products) and, for the check, with K = C⁻¹."""
    from scipy.linalg import matmul_toeplitz, toeplitz
    from scipy.sparse.linalg import LinearOperator

    from lcpfric.model import ContactSystem, Harmonic, IndependentSprings

    rng = np.random.default_rng(seed)
    c = np.exp(-np.arange(n) / 3.0)
    c[0] += 1.0
    P1, Q1, phi = rng.uniform(0.1, 0.8, n), rng.uniform(0.5, 2.0, n), rng.uniform(0, 6.3, n)
    Q = tuple(Harmonic(0.0, Q1[i], phi[i]) for i in range(n))
    normal = IndependentSprings(tuple(Harmonic(1.0, P1[i]) for i in range(n)))
    op = LinearOperator((n, n), matvec=lambda x: matmul_toeplitz(c, x), dtype=float)
    free = ContactSystem(None, np.ones(n), Q, normal, compliance=op)
    K = np.linalg.inv(toeplitz(c))
    return free, ContactSystem(0.5 * (K + K.T), np.ones(n), Q, normal), op


def goal_matrix_free(n, steps=500):
    free, dense, op = toeplitz_system(n)
    scene = make_scene(free, steps)
    stepper = get_stepper("active-set", locate_events=False)
    state = stepper.init(scene)
    state, _ = stepper.cycle(scene, state)
    before = stepper.stats(state)
    t = time.process_time()
    state, cyc = stepper.cycle(scene, state)
    sec = (time.process_time() - t) / scene.steps
    after = stepper.stats(state)
    products = (after["products"] - before["products"]) / scene.steps
    cg = (after["cg_iterations"] - before["cg_iterations"]) / scene.steps
    floor = product_seconds(op)
    _, W_dense = cycle_seconds(
        "active-set", make_scene(dense, steps), cycles=2, locate_events=False
    )
    return {
        "n": n,
        "steps": scene.steps,
        "seconds": sec,
        "products": products,
        "cg": cg,
        "floor": floor,
        "W": cyc.W,
        "W_dense": W_dense,
    }


def goal_sparse(n, steps=2000):
    code = f"""
import json, time
import numpy as np, lcpfric
t0 = time.perf_counter()
rng = np.random.default_rng(0)
s = lcpfric.chain({n}, k_coupling=0.5, P0=1.0, P1=1.5, Q1=rng.uniform(0.5, 2.0, {n}),
                  phi=rng.uniform(0, 2 * np.pi, {n}), sparse=True)
r = lcpfric.steady_state(s, "active-set", {steps}, history=False, locate_events=False)
# the peak of this process's own memory (ru_maxrss would include the parent's at the fork)
hwm = [ln for ln in open("/proc/self/status") if ln.startswith("VmHWM")][0].split()[1]
print(json.dumps({{"seconds": time.perf_counter() - t0, "cycles": r.cycles, "W": r.W,
                  "converged": r.converged, "steps": r.steps_used,
                  "rss_mb": int(hwm) / 1024}}))
"""
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return {"n": n, **json.loads(res.stdout.strip().splitlines()[-1])}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default="benchmarks/results")
    args = ap.parse_args(argv)
    n1, n2, n3, n4 = (100, 1000, 10_000, 1000) if args.quick else (400, 4000, 100_000, 4000)
    lines = [
        "# Many nodes: the active-set backend's goals",
        "",
        f"Reproduce: `OPENBLAS_NUM_THREADS=1 python benchmarks/perf/many_nodes.py"
        f"{' --quick' if args.quick else ''}` (CPU seconds; wall seconds for the sparse "
        f"steady state).",
        "",
    ]
    r = goal_ratios(n1)
    Ws = [r[m][1] for m in ("active-set", "osqp", "clarabel")]
    spread = (max(Ws) - min(Ws)) / max(abs(w) for w in Ws)
    a, o, c = (r[m][0] for m in ("active-set", "osqp", "clarabel"))
    lines += [
        f"## Dense chain, n = {n1} ({r['steps']} steps in the cycle, events located)",
        "",
        "| method | ms per step | active-set faster by | W |",
        "|---|---|---|---|",
        f"| active-set | {1e3 * a:.3g} | 1 | {Ws[0]!r} |",
        f"| osqp | {1e3 * o:.3g} | {o / a:.1f}x | {Ws[1]!r} |",
        f"| clarabel | {1e3 * c:.3g} | {c / a:.1f}x | {Ws[2]!r} |",
        "",
        f"Largest relative difference of W: {spread:.1e}.",
        "",
    ]
    print("\n".join(lines[-9:]), flush=True)
    p = goal_products(n2)
    lines += [
        f"## Dense SPD K, n = {n2} (full contact, {p['steps']} steps, third cycle, "
        f"events not located)",
        "",
        f"{1e3 * p['seconds']:.3g} ms per step; one product with C: "
        f"{1e3 * p['floor']:.3g} ms; **{p['seconds'] / p['floor']:.1f} products per "
        f"step**.",
        "",
    ]
    print("\n".join(lines[-3:]), flush=True)
    s = goal_sparse(n3)
    lines += [
        f"## Sparse chain, n = {n3:g} (2000 steps per cycle, history=False)",
        "",
        f"Full steady state (build, scene, cycles): {s['seconds']:.1f} s wall, "
        f"{s['cycles']} cycles (converged: {s['converged']}), {s['steps']} steps per "
        f"cycle, peak resident memory {s['rss_mb']:.0f} MB, W = {s['W']!r}.",
        "",
    ]
    print("\n".join(lines[-3:]), flush=True)
    f = goal_matrix_free(n4)
    lines += [
        f"## Matrix-free, n = {n4} (FFT Toeplitz compliance, {f['steps']} steps, second "
        f"cycle, events not located)",
        "",
        f"{1e3 * f['seconds']:.3g} ms per step; {f['products']:.1f} products with C per "
        f"step ({f['cg']:.1f} of them conjugate-gradient iterations); one product (one "
        f"FFT pair): {1e3 * f['floor']:.3g} ms; **{f['seconds'] / f['floor']:.1f} "
        f"products' time per step**. W = {f['W']!r}; with K = C⁻¹ (dense path) "
        f"{f['W_dense']!r}: relative difference "
        f"{abs(f['W'] - f['W_dense']) / abs(f['W_dense']):.1e}.",
        "",
    ]
    print("\n".join(lines[-3:]), flush=True)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    name = "many-nodes-quick.md" if args.quick else "many-nodes.md"
    (out / name).write_text("\n".join(lines))
    print(f"wrote {out / name}")


if __name__ == "__main__":
    main()
