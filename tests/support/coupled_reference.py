"""An independent event-driven solution of a coupled system (d = 1), for the tests and the
validation benchmark: no trig triples, no closed-form roots or integrals, no lexicographic rule.

Within a pattern the displacements are solved numerically at each angle, events are bracketed on
a grid and refined by Brent's method, the pattern after an event is the one (of all ``3^n``, each
slipping node on its limit's side) that is admissible a little after the event, and the
dissipation ``Σ f_i N_i |du_i|`` is integrated by adaptive quadrature. Cycles are iterated as they
happen until the start repeats (or its geometric approach is within 1e-14).
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar

TWO_PI = 2.0 * np.pi


class Reference:
    def __init__(self, K, B, f, Qt, Pt):
        self.K, self.B, self.f = (np.asarray(x, dtype=float) for x in (K, B, f))
        self.Qt, self.Pt = np.asarray(Qt, dtype=float), np.asarray(Pt, dtype=float)
        self.n = self.f.size
        self.scale = float(np.max(np.abs(self.Qt)) + np.max(self.f[:, None] * np.abs(self.Pt)))

    @staticmethod
    def _load(T, th):
        th = np.atleast_1d(th)
        return T[:, :1] + T[:, 1:2] * np.sin(th) + T[:, 2:3] * np.cos(th)  # (n, m)

    @staticmethod
    def _rate(T, th):
        th = np.atleast_1d(th)
        return T[:, 1:2] * np.cos(th) - T[:, 2:3] * np.sin(th)

    def solve(self, status, u, th):
        """u (n, m), du/dθ (n, m), F, N of the pattern at the angles th."""
        th = np.atleast_1d(np.asarray(th, dtype=float))
        S = status != 0
        U = np.repeat(u[:, None], th.size, axis=1)
        dU = np.zeros_like(U)
        if S.any():
            Df = status[S] * self.f[S]
            A = self.K[S] + Df[:, None] * self.B[S]
            rhs = -(self._load(self.Qt[S], th) + Df[:, None] * self._load(self.Pt[S], th))
            rhs -= (A[:, ~S] @ u[~S])[:, None]
            U[S] = np.linalg.solve(A[:, S], rhs)
            drhs = -(self._rate(self.Qt[S], th) + Df[:, None] * self._rate(self.Pt[S], th))
            dU[S] = np.linalg.solve(A[:, S], drhs)
        F = self._load(self.Qt, th) + self.K @ U
        N = self._load(self.Pt, th) + self.B @ U
        return U, dU, F, N

    def constraints(self, status, u, th):
        """Rows that must stay >= 0 in the pattern: margins of stuck nodes, slip rates, N."""
        U, dU, F, N = self.solve(status, u, th)
        fN = self.f[:, None] * N
        stuck = status == 0
        rows = [(fN + F)[stuck], (fN - F)[stuck], (status[:, None] * dU)[~stuck], N]
        return np.vstack(rows)

    def decide(self, status, u, th):
        _, _, F, N = self.solve(status, u, th)
        F, fN = F[:, 0], self.f * N[:, 0]
        tol = 1e-9 * self.scale
        lo, hi = fN + F <= tol, fN - F <= tol
        lo |= (status == 1) & (F < 0)
        hi |= (status == -1) & (F > 0)
        cands = []
        for cand in itertools.product((0, 1, -1), repeat=self.n):
            cand = np.array(cand)
            if np.any((cand == 1) & ~lo) or np.any((cand == -1) & ~hi):
                continue
            if np.all(self.constraints(cand, u, th)[:, 0] >= -1e-8 * self.scale):
                cands.append(cand)
        # admissible a little after the event (margins and slip rates not negative): the
        # closest look first (the next event may follow within 1e-9), further looks to
        # separate the patterns that a short look cannot tell apart
        valid = cands
        for delta in (1e-9, 1e-7, 1e-5):
            ok = [
                c
                for c in valid
                if np.all(self.constraints(c, u, th + delta)[:, 0] >= -1e-12 * self.scale)
            ]
            if len(ok) == 1:
                return ok[0]
            valid = ok or valid
        if not valid:
            raise RuntimeError(f"reference: no pattern at θ = {th}")
        # every valid pattern has the same evolution (well posed); the fewest slips is one
        return min(valid, key=lambda c: np.count_nonzero(c))

    def cycle(self, u, status, grid=2000):
        th, W = 0.0, 0.0
        status = self.decide(status, u, 0.0)
        stalls = 0
        skip = {}  # rows whose touch at θ did not change the pattern: skipped just after
        while True:
            g = np.linspace(th, TWO_PI, max(3, int(grid * (TWO_PI - th) / TWO_PI) + 2))
            C = self.constraints(status, u, g)
            end, row_end = TWO_PI, None
            neg = -1e-13 * self.scale  # shallower touches are not events
            for r in range(C.shape[0]):
                row = C[r]
                j = np.nonzero(row[1:] < neg)[0]
                hits = [g[j[0] + 1]] if j.size else []
                # a shallow dip between grid points: refine the grid's local minima
                k = np.nonzero((row[1:-1] < row[:-2]) & (row[1:-1] <= row[2:]))[0] + 1
                k = np.concatenate([[0], k]) if row[1] >= row[0] else k
                for i in k[row[k] < 1e-3 * self.scale]:
                    res = minimize_scalar(
                        lambda t, r=r: self.constraints(status, u, t)[r, 0],
                        bounds=(g[max(i - 1, 0)], g[i + 1]),
                        method="bounded",
                        options={"xatol": 1e-14},
                    )
                    if res.fun < neg:
                        hits.append(res.x)
                for h in hits:
                    past = max(skip.get(r, -1.0), skip.get("all", -1.0))
                    if h <= past:
                        continue
                    a = g[max(0, np.searchsorted(g, h) - 1)]
                    if a >= h:
                        continue
                    # the crossing of neg / 2 (the start itself may sit at zero)
                    lvl = 0.5 * neg
                    if self.constraints(status, u, a)[r, 0] <= lvl:
                        continue
                    c = lambda t, r=r: self.constraints(status, u, t)[r, 0]  # noqa: E731
                    t = brentq(lambda t: c(t) - lvl, a, h, xtol=1e-15, rtol=1e-15)
                    if c(a) > 0:  # the zero crossing itself
                        t = brentq(c, a, t, xtol=1e-15, rtol=1e-15)
                    if past < t < end:
                        end, row_end = t, r

            def power(t):
                U, dU, F, N = self.solve(status, u, t)
                return float(np.sum(self.f * N[:, 0] * np.abs(dU[:, 0])))

            if np.any(status != 0) and end > th:
                W += quad(power, th, end, epsabs=1e-15, epsrel=1e-13, limit=200)[0]
            u = self.solve(status, u, end)[0][:, 0]
            if end >= TWO_PI:
                return u, status, W
            new = self.decide(status, u, end)
            if np.array_equal(new, status) and row_end is not None:
                skip[row_end] = end + 1e-7
            stalls = stalls + 1 if end - th < 1e-10 else 0
            if stalls > 4:  # a cluster of touches: step over them
                skip["all"] = end + 1e-7
            status, th = new, end

    def steady(self, u0, max_cycles=400):
        u = np.asarray(u0, dtype=float).copy()
        status = np.zeros(self.n, dtype=int)
        Ws, changes = [], []
        for _ in range(max_cycles):
            u_end, status, W = self.cycle(u, status)
            dW = abs(W - Ws[-1]) if Ws else np.inf
            Ws.append(W)
            changes.append(max(float(np.max(np.abs(u_end - u))), dW))
            u = u_end
            if changes[-1] <= 1e-14 * max(1.0, float(np.max(np.abs(u))), abs(W)):
                break
            if len(changes) >= 3 and changes[-2] > 0:
                rho = max(changes[-1] / changes[-2], changes[-2] / changes[-3])
                if rho < 0.95 and changes[-1] * rho / (1 - rho) <= 1e-14:
                    break
        return Ws[-1], np.asarray(Ws), u
