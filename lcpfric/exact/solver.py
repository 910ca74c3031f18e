"""Closed-form methods: the periodic steady state without time steps (``method="exact"``).

:class:`ExactSolver` is what the registry gives for ``"exact"``: it checks that the model is
the paper's single node with harmonic loads, computes the periodic orbit event by event
(:mod:`lcpfric.exact`) and returns the same :class:`~lcpfric.results.SteadyState` as the
periodic driver, with the time series sampled at ``steps_per_cycle + 1`` instants (which does
not affect W).
"""

from __future__ import annotations

from dataclasses import replace

import time

import numpy as np

from .. import _checks
from ..errors import InputError
from ..methods import CLOSED_FORM, methods_for
from ..model import ContactSystem, SingleNode
from ..results import SteadyState

__all__ = ["ExactSolver"]


class ExactSolver:
    """The exact steady state: the single node in closed form (:mod:`lcpfric.exact`), a
    discrete system (d = 1) event by event (:mod:`lcpfric.exact.discrete`)."""

    name = "exact"
    kind = CLOSED_FORM
    label = "exact"

    def __init__(self):
        pass

    def check(self, model):
        """Return the single node or system to solve, or raise InputError naming the methods
        that can."""
        from ..scene import Scene

        if isinstance(model, Scene):
            model = model.model if model.model is not None else model.system
        if not isinstance(model, (SingleNode, ContactSystem)):
            what = type(model).__name__
            raise InputError(
                "method",
                f"'exact' solves a SingleNode or a ContactSystem, not "
                f"{what}; methods for {what}: "
                f"{', '.join(methods_for(model)) or 'none'}",
            )
        if not isinstance(model, SingleNode):
            from .discrete import check_system

            check_system(model)
            return model
        if not model.is_harmonic:
            other = (
                "no method yet: a node with a mass is solved under harmonic loads only"
                if model.is_dynamic
                else "use 'explicit' or 'projection'"
            )
            raise InputError(
                "method",
                "'exact' needs harmonic loads P0 + P1 sin(ωt), Q0 + Q1 sin(ωt + φ); for other "
                f"periodic loads {other}",
            )
        return model

    def steady_state(
        self, model, steps_per_cycle: int = 2000, max_cycles: int = 100, u0=None
    ) -> SteadyState:
        """The exact steady state, its time series sampled at ``steps_per_cycle + 1`` instants.

        ``max_cycles`` caps the cycles of a discrete system (its steady state is found by
        Newton's method on the cycle map, periodic to 1e-12: see :mod:`lcpfric.exact.discrete`);
        the single node's orbit is entered directly, in one cycle. ``u0``: an admissible start
        (checked by the driver, :func:`lcpfric.steady_state`), followed event by event; the
        single node from a start is solved as its one-node system (where it shakes down its
        steady state is the start's own)."""
        from . import exact_cycle

        start = time.perf_counter()
        model = self.check(model)
        samples = _checks.positive_int("steps_per_cycle", steps_per_cycle, 4)
        if isinstance(model, ContactSystem):
            return self._system_steady_state(model, samples, start, max_cycles, u0)
        if model.is_dynamic:  # a mass: the dynamic node's orbit (lcpfric.exact.dynamic)
            from .dynamic_api import dynamic_steady_state

            return dynamic_steady_state(model, samples, u0, self.name)
        if u0 is not None or model.k21:  # a start, or Klarbring's node: its one-node system
            res = self._system_steady_state(model.system(), samples, start, max_cycles, u0)
            fields = model.from_system(res.W_cycles, res.v[:, 0], res.F[:, 0], res.N[:, 0])
            return replace(res, state=res.state[:, 0], **fields)
        P1, Q1, phi = model.normalized_parameters()
        cyc = exact_cycle(P1, Q1, phi)
        t = np.linspace(0.0, model.period, samples + 1)
        theta = model.omega * t + model.normal_load.phase
        u = cyc.w(theta)
        F = Q1 * np.sin(theta + phi) + u
        N = np.maximum(1.0 + P1 * np.sin(theta), 0.0)
        v, F, N = model.series(u, F, N)
        W_hat = np.array([cyc.W_hat])
        return SteadyState(
            W=float(model.W(cyc.W_hat)),
            W_cycles=np.atleast_1d(model.W(W_hat)),
            cycles=1,
            converged=True,
            method=self.name,
            steps_requested=samples,
            steps_used=0,
            t=t,
            v=v,
            F=F,
            N=N,
            state=cyc.state(theta),
            seconds=time.perf_counter() - start,
            change=0.0,
            message=f"exact steady state (closed form, no time steps; series "
            f"sampled at {samples + 1} instants)",
            normalization=model.normalization(),
            W_hat_cycles=W_hat,
        )

    def _system_steady_state(self, system, samples, start, max_cycles, u0=None) -> SteadyState:
        from .discrete import exact_system_cycle

        cyc = exact_system_cycle(system, samples, max_cycles=max_cycles, u0=u0)
        t = cyc.theta / cyc.omega
        stats = dict(cyc.stats)
        return SteadyState(
            W=float(cyc.W),
            W_cycles=cyc.W_cycles,
            cycles=cyc.cycles,
            converged=True,
            method=self.name,
            steps_requested=samples,
            steps_used=0,
            t=t,
            v=cyc.u,
            F=cyc.F,
            N=cyc.N,
            state=cyc.state,
            seconds=time.perf_counter() - start,
            change=cyc.change,
            message=f"exact steady state (event by event, {cyc.events} events per cycle, "
            f"periodic after {cyc.cycles} cycles; series sampled at {samples + 1} "
            f"instants)",
            solver_stats=stats,
        )
