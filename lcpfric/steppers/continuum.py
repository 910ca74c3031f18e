"""The steppers of continuum contacts: what the MDR bar (``mdr-bar``), the half-plane's
primal-dual active set (``halfplane-pdas``) and the half-space's Newton-CG (``newton-cg``) share.

Each solves one increment of its model (:mod:`lcpfric.model.continuum`) to the next instant of
the scene, problem (P) of the other methods for that model: the maximum-dissipation projection
under the scene's friction limits and the total tangential load, the body held by the load and
by its support. A subclass implements the :class:`~lcpfric.steppers.base.Stepper` contract
through four hooks:

1. ``model_type`` and ``name``;
2. ``context(scene)``: what its increments need for the scene (blocks, counted operators,
   statistics), built in :meth:`init`, carried in the state and copied before each cycle (a
   cycle never changes the state passed in);
3. ``start(scene, context)``: the tangential state of the virgin contact (its slips ``v``);
4. ``increment(context, state, b, Q, guess=None, tol=None)``: the next tangential state, the
   friction forces and the slips of the increment ``(state, F, dv)`` (lcpfric's signs: the
   slip opposes F), under the limits b and the total load Q.

and, for a model that settles over many cycles, optionally: ``guess(state)`` (what the same
increment of the next cycle starts from: once the cycles nearly repeat, the increments are
nearly solved before they begin), ``restart(scene, state, v)`` (the state with the slips v: the
driver then accelerates the cycle map, :mod:`lcpfric.periodic.acceleration`), ``memory(scene)``
(a :class:`~lcpfric.steppers.slip_memory.SlipMemory`: what a cycle remembers of its start, node
by node, from the increments' slips and limits) and ``loose(scene)`` (the driver solves the early
cycles' increments loosely, and passes ``tol`` to :meth:`cycle`; such a stepper has an
``increment_tol``, the tolerance of its last cycles' increments at most).

The cycles' change is the cycle map's residual (``cycle_measure = "map"``): how far the slips
of the nodes in contact at the cycle's start moved over the cycle. A node out of contact has no
force, and its slip (the relative displacement of the surfaces there) follows from the others'
forces, so a loosely solved cycle showed its force errors there.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .. import memory as _memory
from ..errors import InputError
from ..methods import methods_for
from ..results import CycleResult, State, StepState
from .base import Recorder, Stepper
from .dissipation import increment_dissipation

__all__ = ["ContinuumStepper", "ContinuumData", "node_states"]

STICK, FORWARD, BACKWARD, SEPARATION = (
    int(State.STICK),
    int(State.FORWARD),
    int(State.BACKWARD),
    int(State.SEPARATION),
)
#: bytes per node, unknown and increment of the guesses kept (changes of the forces and their
#: products, a pattern; the previous cycle's and the current one's together)
_GUESS_BYTES = 16


@dataclass(frozen=True)
class ContinuumData:
    """What a continuum stepper carries from cycle to cycle (``StepState.data``).

    Attributes
    ----------
    tangential : Any
        The model's tangential state (slips ``v`` and the stepper's own unknowns).
    context : Any
        What the increments need for the scene (see the module docstring).
    guesses : list or None
        The last cycle's guess of every increment (steppers with ``guess``), or None.
    guessing : bool
        Whether guesses are kept (they fit in memory).
    dv : ndarray or None
        The last increment's slips (the node states at the next cycle's start).
    """

    tangential: Any
    context: Any
    guesses: list | None = None
    guessing: bool = False
    dv: np.ndarray | None = None


class ContinuumStepper(Stepper):
    """Base class of the continuum contacts' steppers (module docstring)."""

    model_type: type = object
    cycle_measure = "map"
    #: whether :meth:`guess` is implemented (the previous cycle's increments start the next)
    guesses = False
    #: whether :meth:`restart` is implemented (the driver accelerates the cycle map)
    can_restart = False

    def check(self, scene) -> None:
        if scene.system is not None or not isinstance(scene.model, self.model_type):
            model = scene.model if scene.model is not None else scene.system
            what = type(model).__name__
            raise InputError(
                "method",
                f"{self.name!r} solves {self.model_type.__name__}, not "
                f"{what}; methods for {what}: "
                f"{', '.join(methods_for(model))}",
            )

    # -- hooks ----------------------------------------------------------------------------------
    def context(self, scene):
        return None

    def start(self, scene, context):  # pragma: no cover - abstract
        raise NotImplementedError

    def increment(self, context, state, b, Q, guess=None, tol=None):  # pragma: no cover
        raise NotImplementedError

    def guess(self, state):  # pragma: no cover - optional
        raise NotImplementedError

    def memory(self, scene):
        return None

    def loose(self, scene) -> bool:
        return False

    def copy_context(self, context):
        """The context for a new cycle (its statistics copied: the state passed to
        :meth:`cycle` is never changed)."""
        return context

    def context_stats(self, context) -> dict:
        return {}

    # -- the stepper contract ---------------------------------------------------------------------
    def init(self, scene, u0=None) -> StepState:
        self.check(scene)
        if u0 is not None:
            raise InputError(
                "u0", f"{self.name!r} starts from the virgin contact; u0 is for discrete systems"
            )
        context = self.context(scene)
        tangential = self.start(scene, context)
        n, d = scene.model.nodes, scene.model.dims
        steps = scene.steps
        need = _memory.continuum_bytes(n, d, steps, True)
        guessing = self.guesses and _memory.fits(need + 2 * n * steps * (_GUESS_BYTES * d + 1))
        data = ContinuumData(tangential, context, None, guessing, None)
        state = node_states(scene.limits[0], None, d)
        return StepState(u=tangential.v.copy(), F=np.zeros(n * d), state=state, data=data)

    def cycle(
        self, scene, state: StepState, history: bool = True, tol: float | None = None
    ) -> tuple[StepState, CycleResult]:
        """One cycle from ``state`` (``tol``: its increments' tolerance, for a stepper the
        driver solves loosely in its early cycles)."""
        data = state.data
        context = self.copy_context(data.context)
        dims = scene.model.dims
        b, Q = scene.limits, scene.Q
        options = {} if tol is None else {"tol": tol}
        tangential, F, dv = data.tangential, state.F, data.dv
        previous = data.guesses
        guesses = [] if data.guessing else None
        memory = self.memory(scene) if self.can_restart else None
        R = memory.start() if memory is not None else None
        record = Recorder(scene, StepState(tangential.v, F, node_states(b[0], dv, dims)), history)
        W = 0.0
        for j in range(scene.steps):
            if guesses is None:
                tangential, F1, dv = self.increment(
                    context, tangential, b[j + 1], Q[j + 1], **options
                )
            else:
                tangential, F1, dv = self.increment(
                    context,
                    tangential,
                    b[j + 1],
                    Q[j + 1],
                    previous[j] if previous else None,
                    **options,
                )
                guesses.append(self.guess(tangential))
            W += increment_dissipation(F, F1, dv, dims)
            if memory is not None:
                memory.update(R, dv, b[j + 1])
            record(j + 1, tangential.v, F1, node_states(b[j + 1], dv, dims))
            F = F1
        stats = self.context_stats(context)
        cyc = replace(record.result(W, stats), memory=R)
        new = StepState(
            u=tangential.v.copy(),
            F=F,
            state=cyc.state[-1],
            dW=0.0,
            data=replace(data, tangential=tangential, context=context, guesses=guesses, dv=dv),
        )
        return new, cyc

    def stats(self, state: StepState) -> dict:
        return self.context_stats(state.data.context)


def node_states(b, dv, dims: int = 1) -> np.ndarray:
    """Node states: separated (no normal force), slipping (moved in the increment; for d = 2,
    forward means along +x), sticking."""
    # the codes by arithmetic on the comparisons (boolean masks and scatters cost several
    # times more on the half-space's thousands of nodes)
    if dv is None:
        s = np.zeros(b.shape, dtype=np.int8)
    else:
        if dims == 2:  # moved: |dv| > 0 (as complex numbers: hypot in one contiguous pass)
            x = dv[0::2]
            moved = np.abs(np.ascontiguousarray(dv, dtype=float).view(complex)) > 0.0
            forward, backward = moved & (x >= 0.0), moved & (x < 0.0)
        else:
            forward, backward = dv > 0.0, dv < 0.0
        s = forward.view(np.int8) * np.int8(FORWARD) + backward.view(np.int8) * np.int8(BACKWARD)
    np.putmask(s, b <= 0.0, np.int8(SEPARATION))
    return s
