"""An independent extended-precision reference for the discretized periodic steady state of small
stiff systems (d = 1, n <= 8; needs mpmath).

    python tests/support/stiff_reference.py [--only NAME,...] [--dps D]   # W of the stiff cases
    python tests/support/stiff_reference.py --table > tests/support/stiff_references.py

What it computes
----------------
Exactly the discretization of lcpfric's convex backends with ``locate_events=False`` (and of
the ``active-set`` backend), on the scene's grid (:func:`lcpfric.scene.make_scene`): increment
k -> k+1 is the maximum-dissipation projection, in stiffness form

    u_{k+1} = argmin_u  ½ uᵀ K u + Q_{k+1}ᵀ u + Σ_i b_i |u_i - u_{k,i}|,   b_i = f_i N_i(t_{k+1}),

with ``F_{k+1} = Q_{k+1} + K u_{k+1}``; a node with b_i = 0 (separated) has F_i = 0. Its
optimality conditions, node by node (Δ = u_{k+1} - u_k, slip against the force):

* stick:    Δ_i = 0 and |F_i| <= b_i;
* forward:  Δ_i >= 0 and F_i = -b_i;     backward: Δ_i <= 0 and F_i = +b_i;
* free:     b_i = 0 and F_i = 0 (Δ_i whatever the others impose).

The cycle's dissipation is the clipped trapezoid of lcpfric.steppers.dissipation,
``W = Σ_k Σ_i max(0, -½ (F_{k,i} + F_{k+1,i}) Δ_i)``, and the periodic steady state is the
cycle reached from u = 0 (``F_0 = Q_0``) once u over a cycle repeats.

How, independently of lcpfric's solvers (only the scene's grid and data are taken from it)
------------------------------------------------------------------------------------------
* Arithmetic: mpmath at ``dps`` digits (default 50 plus the decimal exponent of cond(K)); every
  float64 input (K, f, the scene's Q and N) is promoted exactly, and b_i = f_i N_i is formed in
  mpmath.
* One increment: the box-constrained complementarity problem above is solved on its
  stick / forward / backward pattern (a *principal pivoting* method): for a pattern, the free
  nodes' displacements solve ``K_JJ Δ_J = F_J - F_tr,J`` (F_tr = Q_{k+1} + K u_k, F_J the
  limits), the stick nodes' forces follow; every node violating its condition changes state
  (block pivoting, Júdice & Pires), and after three steps that do not reduce the number of
  violations only the least-index violator changes (Murty's rule, finite for a positive
  definite K) until they do. The search starts from the previous increment's pattern, so most
  increments need one solve. The accepted answer is verified by its conditions in mpmath, with
  F recomputed as ``Q + K u``: a failure raises.
* Periodicity: cycles run first in float64 (the same code, ``strict=False``: only a start) and
  then in mpmath until the change of u over a cycle is at most ``tol`` (default 1e-30) of each
  node's displacement scale. Cycle to cycle the map u_0 -> u_N is piecewise affine, with
  Jacobian A the product of the increments' Jacobians (stick rows keep u, free rows follow
  ``-K_JJ⁻¹ K_J·``); weakly grounded systems contract slowly (ρ(A) close to 1), so the start is
  moved to the fixed point of the cycle's affine piece, ``u* = u + (I - A)⁻¹ (Φ(u) - u)``
  (Newton's method for a piecewise affine map; exact once the pieces repeat). The cycle map is
  non-expansive in the K-norm, so with I - A non-singular the fixed point is the unique periodic
  state, the one iteration from u = 0 approaches. Nothing is taken from a jump but a start: the
  result is the W of a final mpmath cycle started from the end of a cycle whose u repeated to
  ``tol``, and whose own u repeats too.

:func:`reference_W` returns W as a float and an info dict (digits, cycles, Newton steps, the
final changes, cond(I - A), the states per node, seconds); :func:`input_spread` the change of
that W when the float64 inputs move by a few units of round-off (the conditioning of W, what no
float64 method can beat).
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import mpmath as mp
import numpy as np

from lcpfric.scene import make_scene

__all__ = ["reference_W", "input_spread", "default_dps", "table_source"]

STICK, FORWARD, BACKWARD, FREE = 0, 1, -1, 2
_BLOCK_FAILURES = 3  # block pivots without fewer violations before Murty's single pivots


def default_dps(system) -> int:
    """Digits for a system: 50 plus the decimal exponent of cond(K) (a solve loses that many)."""
    cond = np.linalg.cond(system.dense_stiffness())
    return 50 + max(0, math.ceil(math.log10(cond)))


class _Arithmetic:
    """The number type of a run: Python floats (the warm start) or mpmath's mpf."""

    def __init__(self, exact: bool):
        self.num = mp.mpf if exact else float
        self.zero = self.num(0)
        self.dot = mp.fdot if exact else (lambda a, b: sum(x * y for x, y in zip(a, b)))


def _solve(M, rhs):
    """X with ``M X = rhs`` (n x n and n x r lists of lists, any number type) by Gaussian
    elimination with partial pivoting; None if a pivot vanishes."""
    n = len(M)
    A = [list(M[i]) + list(rhs[i]) for i in range(n)]
    w = len(A[0])
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(A[r][c]))
        if A[p][c] == 0:
            return None
        A[c], A[p] = A[p], A[c]
        piv = A[c][c]
        for r in range(c + 1, n):
            m = A[r][c] / piv
            if m:
                A[r] = [A[r][j] - m * A[c][j] if j >= c else A[r][j] for j in range(w)]
    X = [[None] * (w - n) for _ in range(n)]
    for j in range(w - n):
        for r in range(n - 1, -1, -1):
            s = A[r][n + j] - sum(A[r][c] * X[c][j] for c in range(r + 1, n))
            X[r][j] = s / A[r][r]
    return X


def _identity(n, ar):
    return [[ar.num(1) if i == j else ar.zero for j in range(n)] for i in range(n)]


class _Cycle:
    """One cycle: u and F at every grid instant, the patterns, W, and the Jacobian A of
    u_N with respect to u_0 (None unless asked for)."""

    def __init__(self, U, F, patterns, W, A):
        self.U, self.F, self.patterns, self.W, self.A = U, F, patterns, W, A


class _Stepper:
    """The increment and the cycle of one scene in one arithmetic.

    ``tol_rel`` sets the tie tolerances of the pivoting (a violation smaller than ``tol_rel``
    of the node's force or displacement scale is none) and, in strict mode, the KKT check (10⁶
    times looser). Scales: s_F,i the node's largest |Q_i| or b_i over the cycle; s_u,i
    ``Σ_j |C_ij| s_F,j`` (C = K⁻¹).
    """

    def __init__(self, K, friction, Q, N, ar: _Arithmetic, tol_rel, strict: bool):
        num = ar.num
        self.ar, self.strict = ar, strict
        self.n = n = len(K)
        self.K = [[num(float(x)) for x in row] for row in K]
        self.Q = [[num(float(x)) for x in row] for row in Q]
        f = [num(float(x)) for x in friction]
        self.b = [[f[i] * num(float(x)) for i, x in enumerate(row)] for row in N]
        self.steps = len(self.Q) - 1
        sF = [
            max(max(abs(self.Q[k][i]), self.b[k][i]) for k in range(self.steps + 1))
            for i in range(n)
        ]
        sF = [s if s > 0 else num(1) for s in sF]
        C = _solve(self.K, _identity(n, ar))
        self.sF = sF
        self.su = [ar.dot([abs(c) for c in C[i]], sF) for i in range(n)]
        self.tol_F = [tol_rel * s for s in sF]
        self.tol_u = [tol_rel * s for s in self.su]
        self.check = num(10) ** 6 * tol_rel
        self._inverses = {}
        self._slopes = {}
        self.max_pivots = 0

    def _inverse(self, J):
        G = self._inverses.get(J)
        if G is None:
            KJJ = [[self.K[i][j] for j in J] for i in J]
            G = self._inverses[J] = _solve(KJJ, _identity(len(J), self.ar))
        return G

    def _slope(self, J):
        """``H = K_JJ⁻¹ K_J·``: the free rows of the increment's Jacobian are ``-H``."""
        H = self._slopes.get(J)
        if H is None:
            G = self._inverse(J)
            cols = [[self.K[i][c] for i in J] for c in range(self.n)]
            H = self._slopes[J] = [[self.ar.dot(g, col) for col in cols] for g in G]
        return H

    def increment(self, k, u, pattern):
        """``(u, F, pattern)`` at t_{k+1} from u at t_k, the search started from ``pattern``."""
        n, K, dot = self.n, self.K, self.ar.dot
        Q, b = self.Q[k + 1], self.b[k + 1]
        zero = self.ar.zero
        Ftr = [Q[i] + dot(K[i], u) for i in range(n)]
        pat = [FREE if b[i] == 0 else (STICK if p == FREE else p) for i, p in enumerate(pattern)]
        fewest, failures = n + 1, 0
        for it in range(50 + 10 * 3**n):
            J = tuple(i for i in range(n) if pat[i] != STICK)
            target = {
                i: (-b[i] if pat[i] == FORWARD else (b[i] if pat[i] == BACKWARD else zero))
                for i in J
            }
            delta = [zero] * n
            if J:
                r = [target[i] - Ftr[i] for i in J]
                for g, i in zip(self._inverse(J), J):
                    delta[i] = dot(g, r)
            dJ = [delta[j] for j in J]
            F = [
                target[i] if i in target else Ftr[i] + dot([K[i][j] for j in J], dJ)
                for i in range(n)
            ]
            bad = []
            for i in range(n):
                p = pat[i]
                if p == STICK:
                    if F[i] > b[i] + self.tol_F[i]:
                        bad.append((i, BACKWARD))
                    elif F[i] < -b[i] - self.tol_F[i]:
                        bad.append((i, FORWARD))
                elif (p == FORWARD and delta[i] < -self.tol_u[i]) or (
                    p == BACKWARD and delta[i] > self.tol_u[i]
                ):
                    bad.append((i, STICK))
            if not bad:
                break
            if len(bad) < fewest:
                fewest, failures = len(bad), 0
            else:
                failures += 1
            for i, new in bad if failures <= _BLOCK_FAILURES else bad[:1]:
                pat[i] = new
        else:
            if self.strict:
                raise RuntimeError(
                    f"increment {k}: no pattern satisfies the conditions after {it + 1} pivots"
                )
        self.max_pivots = max(self.max_pivots, it)
        u1 = [u[i] + delta[i] for i in range(n)]
        if self.strict:
            self._verify(k, u1, F, delta, pat, b)
        return u1, F, pat

    def _verify(self, k, u1, F, delta, pat, b):
        """The optimality conditions of the increment, F recomputed as Q + K u."""
        Q, K = self.Q[k + 1], self.K
        tol = self.check
        for i in range(self.n):
            tF, tu = tol * self.sF[i], tol * self.su[i]
            ok = abs(Q[i] + self.ar.dot(K[i], u1) - F[i]) <= tF
            p = pat[i]
            if p == STICK:
                ok = ok and delta[i] == 0 and abs(F[i]) <= b[i] + tF
            elif p == FORWARD:
                ok = ok and delta[i] >= -tu and F[i] == -b[i]
            elif p == BACKWARD:
                ok = ok and delta[i] <= tu and F[i] == b[i]
            else:
                ok = ok and b[i] == 0 and F[i] == 0
            if not ok:
                raise RuntimeError(
                    f"increment {k}: node {i} fails its optimality conditions "
                    f"(state {p}, F = {F[i]}, b = {b[i]}, Δ = {delta[i]})"
                )

    def cycle(self, u, F, pattern, jacobian=False):
        """One cycle from ``(u, F)`` at t_0; with ``jacobian``, also A = ∂u_N/∂u_0."""
        n, dot, zero = self.n, self.ar.dot, self.ar.zero
        U, Fs, P = [u], [F], [pattern]
        A = _identity(n, self.ar) if jacobian else None
        W = zero
        half = self.ar.num(0.5)
        for k in range(self.steps):
            u1, F1, pattern = self.increment(k, u, pattern)
            for i in range(n):
                share = -half * (F[i] + F1[i]) * (u1[i] - u[i])
                if share > 0:
                    W += share
            if jacobian:
                J = tuple(i for i in range(n) if pattern[i] != STICK)
                if J:
                    H = self._slope(J)
                    cols = [[A[r][c] for r in range(n)] for c in range(n)]
                    rows = {i: [A[i][c] - dot(h, cols[c]) for c in range(n)] for h, i in zip(H, J)}
                    A = [rows.get(i, A[i]) for i in range(n)]
            u, F = u1, F1
            U.append(u)
            Fs.append(F)
            P.append(pattern)
        return _Cycle(U, Fs, P, W, A)

    def change(self, cyc):
        """The largest change of u over the cycle, per node relative to the larger of the
        node's range over the cycle and its displacement scale s_u."""
        out = self.ar.zero
        for i in range(self.n):
            col = [row[i] for row in cyc.U]
            scale = max(max(col) - min(col), self.su[i])
            out = max(out, abs(cyc.U[-1][i] - cyc.U[0][i]) / scale)
        return out

    def fixed_point(self, cyc):
        """``u_0 + (I - A)⁻¹ (u_N - u_0)``, the fixed point of the cycle's affine piece, or None
        when I - A is singular."""
        n = self.n
        M = [[(1 if i == j else 0) - cyc.A[i][j] for j in range(n)] for i in range(n)]
        step = _solve(M, [[cyc.U[-1][i] - cyc.U[0][i]] for i in range(n)])
        if step is None:
            return None
        return [cyc.U[0][i] + step[i][0] for i in range(n)]

    def states(self, cyc):
        """Per node, the increments of the cycle it sticks, slips (on its limit and moving by
        more than 1e-12 of its range over the cycle) and is separated."""
        out = []
        for i in range(self.n):
            col = [row[i] for row in cyc.U]
            small = 1e-12 * (max(col) - min(col))
            counts = {"stick": 0, "slip": 0, "separated": 0}
            for k in range(self.steps):
                if self.b[k + 1][i] == 0:
                    counts["separated"] += 1
                elif (
                    cyc.patterns[k + 1][i] in (FORWARD, BACKWARD)
                    and abs(cyc.U[k + 1][i] - cyc.U[k][i]) > small
                ):
                    counts["slip"] += 1
                else:
                    counts["stick"] += 1
            out.append(counts)
        return out


def _periodic(st: _Stepper, u, F, pattern, tol, max_cycles):
    """Cycles (with Newton jumps to the fixed point of the cycle's affine piece) until u repeats
    to ``tol``. Returns ``(cycle, cycles run, jumps, converged)``, the cycle being the last
    one, whose start repeated."""
    jumps, hold, jumped, prev = 0, 0, False, None
    for c in range(1, max_cycles + 1):
        cyc = st.cycle(u, F, pattern, jacobian=hold == 0)
        change = st.change(cyc)
        if change <= tol:
            return cyc, c, jumps, True
        if jumped and change > prev / 2:
            hold = 3  # the jump did not help (pieces not settled): plain cycles for a while
        u, F, pattern = cyc.U[-1], cyc.F[-1], cyc.patterns[-1]
        jumped = False
        if hold:
            hold -= 1
        else:
            target = st.fixed_point(cyc)
            if target is not None:
                u, jumped = target, True
                jumps += 1
        prev = change
    return cyc, max_cycles, jumps, False


def _data(system, steps):
    """``(K, f, Q, N)`` of ``make_scene(system, steps)``, float64 as lcpfric has them."""
    if system.dims != 1 or system.n > 8:
        raise ValueError("the reference treats d = 1 systems of at most 8 nodes")
    scene = make_scene(system, steps)
    return system.dense_stiffness(), system.friction, scene.Q, scene.N


def _steady(data, dps, tol, max_cycles):
    """The steady cycle of ``data``: float64 warm start from u = 0, then mpmath.

    Returns ``(stepper, final cycle, info)``; the caller reads W in mpmath (inside the same
    precision) from the cycle."""
    K, _, Q, _ = data
    n = len(K)
    # warm start in float64: same algorithm, no verification, any number of cycles
    flt = _Stepper(*data, _Arithmetic(False), 1e-12, strict=False)
    cyc, fc, fj, _ = _periodic(
        flt, [0.0] * n, [float(x) for x in Q[0]], [STICK] * n, 1e-13, 4 * max_cycles
    )
    st = _Stepper(*data, _Arithmetic(True), mp.mpf(10) ** (15 - dps), strict=True)
    u = [mp.mpf(x) for x in cyc.U[-1]]
    F = [mp.mpf(x) for x in cyc.F[-1]]
    cyc, mc, mj, ok = _periodic(st, u, F, cyc.patterns[-1], tol, max_cycles)
    if not ok:
        raise RuntimeError(f"no periodic state to {tol:g} after {mc} mpmath cycles")
    final = st.cycle(cyc.U[-1], cyc.F[-1], cyc.patterns[-1], jacobian=True)
    change = st.change(final)
    if not change <= tol:
        raise RuntimeError(f"the confirming cycle changed u by {float(change):.3g}")
    A = np.array([[float(x) for x in row] for row in final.A])
    info = dict(
        dps=dps,
        float_cycles=fc,
        float_jumps=fj,
        mp_cycles=mc + 1,
        mp_jumps=mj,
        change=float(max(change, st.change(cyc))),
        cond=float(np.linalg.cond(np.eye(n) - A)),
        rho=float(np.max(np.abs(np.linalg.eigvals(A)))),
        states=st.states(final),
        pivots=st.max_pivots,
    )
    return final, info


def reference_W(
    system, steps, *, dps: int | None = None, tol: float = 1e-30, max_cycles: int = 40
) -> tuple[float, dict]:
    """The periodic steady state's W on ``make_scene(system, steps)``, to ``tol``.

    Returns ``(W, info)``; info holds ``dps``, ``float_cycles`` and ``mp_cycles`` (with their
    Newton ``jumps``), ``change`` (of u over the last two mpmath cycles, relative), ``W_mp``
    (the mpmath value as a string), ``cond`` (of I - A, the fixed point's conditioning),
    ``rho`` (the spectral radius of A: plain cycling contracts by rho per cycle),
    ``states`` (per node, its stick / slip / separated increments over the cycle), ``pivots``
    (the largest number of pivots an increment needed) and ``seconds``.
    """
    start = time.perf_counter()
    dps = default_dps(system) if dps is None else dps
    with mp.workdps(dps):
        final, info = _steady(_data(system, steps), dps, tol, max_cycles)
        info["W_mp"] = mp.nstr(final.W, dps - 5)
        info["seconds"] = time.perf_counter() - start
        return float(final.W), info


def input_spread(system, steps, W, *, rel: float = 1e-15, seeds=(1, 2)) -> float:
    """The conditioning of W: the largest relative change of the reference W when every input
    (each entry of K, kept symmetric, of the scene's Q and N) is multiplied by ``1 ± rel``
    (random signs, one draw per seed; 1e-15 is about 4.5 units of round-off). A float64
    method cannot be asked for more than this of W."""
    K, f, Q, N = _data(system, steps)
    dps = default_dps(system)
    out = 0.0
    for seed in seeds:
        rng = np.random.default_rng(seed)
        E = np.triu(rng.choice([-1.0, 1.0], K.shape))
        data = (
            K * (1 + rel * (E + np.triu(E, 1).T)),
            f,
            Q * (1 + rel * rng.choice([-1.0, 1.0], Q.shape)),
            N * (1 + rel * rng.choice([-1.0, 1.0], N.shape)),
        )
        with mp.workdps(dps):
            final, _ = _steady(data, dps, 1e-30, 40)
            out = max(out, abs(float(final.W) - W) / abs(W))
    return out


def table_source(names=None) -> str:
    """Python source of tests/support/stiff_references.py (runs every stiff case in mpmath, three
    times: the case and two perturbations of its inputs)."""
    from .stiff_cases import stiff_cases

    lines = [
        '"""W of the stiff cases (tests/support/stiff_cases.py) from the independent mpmath',
        "reference (tests/support/stiff_reference.py), pinned so that tests need no mpmath run.",
        "",
        "Generated by ``python tests/support/stiff_reference.py --table``. STIFF_REFERENCE:",
        "``name: (W, steps per cycle, mpmath digits, seconds the reference took)``; the",
        "comment gives the mpmath cycles, the spectral radius ρ of the cycle map's Jacobian A",
        "(plain cycling contracts by ρ per cycle), cond(I - A) and, per node, the increments",
        "of the steady cycle it sticks / slips / is separated. INPUT_SPREAD: the",
        "relative change of W when every input moves by 1e-15 relative (input_spread), what",
        "a float64 method cannot be asked to beat.",
        '"""',
        "",
        "STIFF_REFERENCE = {",
    ]
    spreads = []
    for name, (system, steps) in stiff_cases().items():
        if names and name not in names:
            continue
        W, info = reference_W(system, steps)
        if not (
            all(s["stick"] and s["slip"] for s in info["states"])
            and any(s["separated"] for s in info["states"])
        ):
            raise RuntimeError(
                f"{name}: a node never sticks or never slips, or none separates: {info['states']}"
            )
        states = " ".join(f"{s['stick']}/{s['slip']}/{s['separated']}" for s in info["states"])
        lines.append(
            f"    {name!r}: ({W!r}, {steps}, {info['dps']}, "
            f"{info['seconds']:.1f}),  # cycles {info['mp_cycles']}, "
            f"ρ {info['rho']:.1e}, cond {info['cond']:.1e}; {states}"
        )
        spreads.append(f"    {name!r}: {input_spread(system, steps, W):.1e},")
    lines += ["}", "", "INPUT_SPREAD = {", *spreads, "}"]
    return "\n".join(lines) + "\n"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--table", action="store_true", help="print tests/support/stiff_references.py")
    p.add_argument("--only", default=None, help="comma-separated case names")
    p.add_argument("--dps", type=int, default=None)
    args = p.parse_args(argv)
    names = args.only.split(",") if args.only else None
    if args.table:
        sys.stdout.write(table_source(names))
        return 0
    from .stiff_cases import stiff_cases

    for name, (system, steps) in stiff_cases().items():
        if names and name not in names:
            continue
        W, info = reference_W(system, steps, dps=args.dps)
        print(f"{name:24s} W = {W!r:24s} {info}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
