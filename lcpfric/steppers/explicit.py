"""The explicit, state-based stepper of the paper (``method="explicit"``; d = 1).

Section 2.2 and Ahn & Barber (2008): assume each node keeps its state (stick, forward slip,
backward slip, separation) over the increment, compute the end of the increment, check the
inequalities of Eq. (3), and on a violation change state. Here the check does not wait for the
end of the increment:

* Within an increment the loads are interpolated linearly, so with the states fixed every force,
  displacement and Coulomb margin ``f N_i ∓ F_i`` is linear in the fraction τ of the increment.
  The first instant where a sticking node's margin reaches zero is therefore found exactly, the
  increment is split there and the state changes at that instant, not at the end of the step.
* Which nodes slip after an event is not guessed: for the nodes on the friction limit the slip
  rates solve the rate problem, a linear complementarity problem ``λ >= 0, Mλ + q >= 0,
  λ·(Mλ + q) = 0`` with ``M = D S D`` (S the Schur complement of K on the nodes that are not
  stuck, D their slip signs). K is positive definite, so M is a P-matrix and the LCP has exactly
  one solution (found by Murty's least-index principal pivoting, warm-started from the current
  slip set).
* Separation and re-contact instants are on the grid (the scene puts them there), so a node is
  in contact or separated for a whole increment.

The result is the exact solution for piecewise-linear loads, so its error comes only from the
load interpolation; the convergence order is measured in the tests and benchmarks, not assumed.
The dissipation of each sub-increment is ``-½ (F_a + F_b)·(u_b - u_a)``, exact for linear
histories.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError, SolverError
from ..results import CycleResult, State, StepState
from .base import Stepper
from .dissipation import increment_dissipation, scalar_share
from .coupled_path import compressed
from .rates import EPS8, REL, coupled_matrix, limit_crossings, slip_rates

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..model import ContactSystem
    from ..scene import Scene

__all__ = ["ExplicitStepper"]

STICK, FORWARD, BACKWARD, SEPARATION = (
    State.STICK,
    State.FORWARD,
    State.BACKWARD,
    State.SEPARATION,
)


class ExplicitStepper(Stepper):
    """State-based stepper with exact event location within each increment (d = 1).

    ``method="explicit"``: the paper's stepper (see the module docstring), for any symmetric
    positive definite K with d = 1. It takes no options.

    Attributes
    ----------
    name : str
        ``"explicit"``.
    """

    name = "explicit"

    def check_system(self, system: ContactSystem) -> None:
        """Refuse a system with d = 2.

        Parameters
        ----------
        system : ContactSystem
            The discrete system to solve.

        Raises
        ------
        lcpfric.errors.InputError
            ``method``: d = 2 (the message names the methods that can).
        """
        if system.dims != 1:
            raise InputError(
                "method",
                "'explicit' handles d = 1 (one tangential direction per "
                "node); for d = 2 use 'clarabel', 'cvxpy:CLARABEL' or "
                "'projection' (diagonal K)",
            )

    def init(self, scene: Scene, u0: ArrayLike | None = None) -> StepState:
        """The initial state at ``scene.t[0]``, with the dense K.

        Parameters
        ----------
        scene : Scene
            A discrete system's scene (d = 1).
        u0 : (m,) array_like, optional
            The initial tangential displacements (default zero).

        Returns
        -------
        StepState
            As :meth:`Stepper.init <lcpfric.steppers.base.Stepper.init>`, with ``data`` the
            dict ``{"K": dense K, "substeps": 0, "events": 0}``.

        Raises
        ------
        lcpfric.errors.InputError
            ``method``: d = 2.
        """
        self.check_system(scene.system)
        state = super().init(scene, u0)
        data = {"K": scene.system.dense_stiffness(), "substeps": 0, "events": 0}
        B = scene.system.coupling
        if B is not None:  # N = P + B u: the loads P unclipped (a coupled node never separates)
            P = np.asarray(scene.system.normal.loads_at(scene.t), dtype=float)
            data.update(B=B, P=P)
            F = scene.Q[0] + data["K"] @ state.u
            state = replace(state, F=F, state=np.full(F.size, STICK, dtype=np.int8))
        return replace(state, data=data)

    # ------------------------------------------------------------------------------------------
    def step(self, scene: Scene, k: int, state: StepState) -> StepState:
        """Increment k, split at every instant where a node's state changes.

        With the states fixed the loads, forces and margins are linear in the fraction τ of
        the increment: the first limit crossing is located exactly, the slip rates after it
        solve the rate LCP, and so on to the end of the increment.

        Parameters
        ----------
        scene : Scene
            The scene :meth:`init` was given.
        k : int
            The increment, ``0 <= k < scene.steps``.
        state : StepState
            The state at ``scene.t[k]`` (not changed).

        Returns
        -------
        StepState
            The state at ``scene.t[k+1]``; ``dW`` the sum of the sub-increments'
            ``-½ (F_a + F_b)·(u_b - u_a)``, ``data`` with the counts of substeps and events.

        Raises
        ------
        lcpfric.errors.SolverError
            ``status="too_many_events"``: more than 4 n + 16 state changes in the increment
            (the loads may be inconsistent); also a slip-rate LCP that does not settle, or
            slip directions at re-contact that cannot be decided.
        """
        data = state.data
        K = data["K"]
        f = scene.system.friction
        Qa, Qb = scene.Q[k], scene.Q[k + 1]
        B = data.get("B")  # a coupling block: N = P + B u
        Na, Nb = (scene.N[k], scene.N[k + 1]) if B is None else (data["P"][k], data["P"][k + 1])
        dQ, dN = Qb - Qa, Nb - Na
        sep = (Na + Nb) <= 0.0 if B is None else np.zeros(f.size, dtype=bool)
        u = state.u.copy()
        tau = 0.0
        W = 0.0
        node_state = np.where(sep, SEPARATION, STICK).astype(np.int8)
        slipping = state.state == FORWARD
        slipping_b = state.state == BACKWARD
        n = f.size
        touch_lo = touch_hi = np.zeros(n, dtype=bool)
        substeps = n_events = 0
        for _ in range(4 * n + 16):
            Nt = Na + tau * dN if B is None else _compressed(Na + tau * dN + B @ u, scene, k, tau)
            Qt = Qa + tau * dQ
            bound = f * Nt
            F0 = _on_limits(Qt + K @ u, bound, slipping & ~sep, slipping_b & ~sep)
            # coupled: the rate problem's matrix K + diag(s f) B on the rows on a limit
            Kr = K if B is None else coupled_matrix(K, B, f, F0, bound, touch_lo, touch_hi)
            du, node_state = slip_rates(
                Kr, f, F0, bound, dQ, dN, sep, slipping, slipping_b, touch_lo, touch_hi
            )
            dNu = dN if B is None else dN + B @ du  # N's rate with the slips
            events = limit_crossings(K, f, F0, bound, dQ, dNu, du, node_state, tau)
            t_end = min(1.0, float(np.min(events[0])), float(np.min(events[1])))
            now = tau + EPS8 * max(1.0, tau)
            if t_end <= now:
                touch_hi, touch_lo = events[0] <= now, events[1] <= now
                if touch_hi.any() or touch_lo.any():
                    # limits reached within round-off of τ: decide those nodes' slip at τ
                    continue
                # no limit is reached: only the increment's end is within round-off of τ
                # (an event just before t_{k+1}); finish the increment instead of retrying
                t_end = 1.0
            touch_lo = touch_hi = np.zeros(n, dtype=bool)
            u_new = u + (t_end - tau) * du
            F1 = _on_limits(
                Qa + t_end * dQ + K @ u_new,
                f * (Na + t_end * dN + (0.0 if B is None else B @ u_new)),
                node_state == FORWARD,
                node_state == BACKWARD,
            )
            W += increment_dissipation(F0, F1, u_new - u)
            substeps += 1
            u = u_new
            slipping = node_state == FORWARD
            slipping_b = node_state == BACKWARD
            if t_end >= 1.0:
                break
            tau = t_end
            n_events += 1
        else:
            from ..exact.clusters import stiff_hint

            hint = stiff_hint(scene.system)
            raise SolverError(
                f"explicit stepper: more than {4 * n + 16} state changes in "
                f"increment {k}" + (hint or "; the loads may be inconsistent"),
                backend="explicit",
                status="too_many_events",
            )
        F = F1
        data = dict(data, substeps=data["substeps"] + substeps, events=data["events"] + n_events)
        return StepState(u, F, node_state, W, data)

    # ------------------------------------------------------------------------------------------
    def cycle(
        self, scene: Scene, state: StepState, history: bool = True
    ) -> tuple[StepState, CycleResult]:
        """One cycle from ``state`` at ``scene.t[0]``.

        :meth:`Stepper.cycle <lcpfric.steppers.base.Stepper.cycle>`; one unknown with the
        history runs the same algorithm in scalar arithmetic (a rate LCP of size 1 is a sign
        test).

        Parameters
        ----------
        scene : Scene
            The scene :meth:`init` was given.
        state : StepState
            The state at the cycle's start.
        history : bool
            Keep every instant (default), or only the ends and each unknown's range.

        Returns
        -------
        end : StepState
            The state at the cycle's end.
        cycle : CycleResult
            The cycle's series, dissipation and :meth:`stats`.

        Raises
        ------
        lcpfric.errors.SolverError
            From :meth:`step`.
        """
        if scene.system.m != 1 or not history or "B" in state.data:
            return super().cycle(scene, state, history)
        return _single_node_cycle(scene, state)

    def stats(self, state: StepState) -> dict[str, Any]:
        """The substeps and events so far.

        Parameters
        ----------
        state : StepState
            A state this stepper made.

        Returns
        -------
        dict
            ``substeps`` (pieces of increments solved) and ``events`` (state changes located
            inside increments), counted since :meth:`init`.
        """
        return {"substeps": state.data["substeps"], "events": state.data["events"]}


def _on_limits(F, bound, forward, backward):
    """``F`` with the slipping nodes put exactly on their limits (-f N forward, +f N backward):
    ``Q + K u`` carries the round-off of Q, which is all of f N when |Q| >> f N."""
    if forward.any() or backward.any():
        F = np.where(forward, -bound, np.where(backward, bound, F))
    return F


def _compressed(N, scene, k, tau):
    """:func:`~.coupled_path.compressed` at the fraction tau of increment k."""
    return compressed(N, scene.t[k] + tau * (scene.t[k + 1] - scene.t[k]))


def _single_node_cycle(scene, state):
    """The same algorithm for one node in scalar arithmetic (one LCP of size 1 is a sign test)."""
    k = float(state.data["K"][0, 0])
    fr = float(scene.system.friction[0])
    Q = scene.Q[:, 0].tolist()
    B = (fr * scene.N[:, 0]).tolist()
    n = len(Q) - 1
    U = [0.0] * (n + 1)
    Fs = [0.0] * (n + 1)
    S = [0] * (n + 1)
    u = float(state.u[0])
    U[0], Fs[0], S[0] = u, float(state.F[0]), int(state.state[0])
    W = 0.0
    events = 0
    st = S[0]
    for j in range(n):
        Qa, Qb, ba, bb = Q[j], Q[j + 1], B[j], B[j + 1]
        if ba + bb <= 0.0:  # separated over the whole increment: F = 0
            u = -Qb / k
            U[j + 1], Fs[j + 1], S[j + 1] = u, 0.0, SEPARATION
            st = SEPARATION
            continue
        dQ, db = Qb - Qa, bb - ba
        tau = 0.0
        # a node that was slipping is on its limit (exactly: Q + k u would carry the round-off
        # of Q, which is all of f N when |Q| >> f N)
        F0 = -ba if st == FORWARD else (ba if st == BACKWARD else Qa + k * u)
        while True:
            bt = ba + tau * db
            tol = REL * (bt + abs(F0))
            r_lo, r_hi = db + dQ, db - dQ  # margin rates while stuck
            if F0 <= -bt + tol and r_lo < 0.0:
                st, du = FORWARD, -r_lo / k
                t_end = 1.0
            elif F0 >= bt - tol and r_hi < 0.0:
                st, du = BACKWARD, r_hi / k
                t_end = 1.0
            else:
                st, du = STICK, 0.0
                t_end = 1.0
                rtol = REL * (abs(db) + abs(dQ))
                t_hi = tau + (bt - F0) / -r_hi if r_hi < -rtol and bt - F0 > tol else 2.0
                t_lo = tau + (bt + F0) / -r_lo if r_lo < -rtol and bt + F0 > tol else 2.0
                if min(t_hi, t_lo) <= tau + EPS8 * max(1.0, tau):
                    # the limit is reached within round-off of τ: slip now (τ cannot advance)
                    st, du = (BACKWARD, r_hi / k) if t_hi <= t_lo else (FORWARD, -r_lo / k)
                else:
                    t_end = min(t_end, t_hi, t_lo)
            u1 = u + (t_end - tau) * du
            if st == STICK:
                F1 = Qa + t_end * dQ + k * u1
            else:  # slipping: on the limit
                F1 = (ba + t_end * db) * (-1.0 if st == FORWARD else 1.0)
            W += scalar_share(F0, F1, u1 - u)
            u, F0 = u1, F1
            if t_end >= 1.0:
                break
            tau = t_end
            events += 1
        U[j + 1], Fs[j + 1], S[j + 1] = u, F0, st
    Ua = np.array(U)[:, None]
    Fa = np.array(Fs)[:, None]
    Sa = np.array(S, dtype=np.int8)[:, None]
    data = {
        "K": state.data["K"],
        "substeps": state.data["substeps"] + n + events,
        "events": state.data["events"] + events,
    }
    end = StepState(Ua[-1].copy(), Fa[-1].copy(), Sa[-1].copy(), 0.0, data)
    return end, CycleResult(
        scene.t, Ua, Fa, Sa, W, {"substeps": data["substeps"], "events": data["events"]}
    )
