r"""The half-space's stepper (``method="newton-cg"``): problem (P) on a grid of boundary
elements, d = 1 or 2, by a semismooth Newton method on FFT products.

Friction forces ``F_i`` on the nodes in contact (lcpfric's sign: the slip opposes F; the shear
traction transmitted is ``-F_i/h²``), ``|F_i| <= b_i``; the relative slips s and the rigid
tangential displacement δ of the body satisfy ``s = δ + C F`` with C the Cerruti operator per
unit force (:mod:`.influence` divided by h²); the body is held by Q(t) and by a support of
stiffness ``k_support``: ``Σ F_i − k_support δ + Q = 0``. Each increment is problem (P), the
maximum-dissipation projection: the sticking nodes keep their slip, the slipping ones sit on
their limit with the slip opposite to the force.

Each increment is solved by :class:`~lcpfric.steppers.newton_increment.HalfSpaceIncrements`
(:mod:`.newton_increment`: the semismooth Newton iteration, its starts, its tolerance and its
statistics); :class:`NewtonCGStepper` is the stepper around them: its options, the state a
cycle starts and restarts from, the guesses kept from cycle to cycle, and the slip memory and
loose early cycles it asks of the driver.

Two different materials with Dundurs' β ≠ 0: each increment alternates the tangential and the
normal problems (:mod:`.coupled_halfspace`). Nodes out of contact carry no force and no
unknown. d = 1 with ν > 0 takes the tractions along
the load with the x-x Cerruti coefficient (Mindlin's approximation); d = 2 adds the
transverse tractions and the coupling.

The model (:class:`~lcpfric.model.continuum.halfspace.HalfSpace`) gives the grid, the influence
operators and the friction limits; the increments' own state (the counted operator, the
statistics, whether the last increment's first pattern held) is the stepper's
(:class:`HalfSpaceIncrements`, carried in the step state with the tangential state,
:class:`~lcpfric.steppers.newton_increment.Tangential`). The Newton steps themselves are in
:mod:`.newton_step`.
"""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..model.continuum.halfspace import HalfSpace
from .continuum import ContinuumStepper
from .newton_increment import HalfSpaceIncrements, Tangential
from .slip_memory import SlipMemory

__all__ = ["NewtonCGStepper", "HalfSpaceIncrements"]


class NewtonCGStepper(ContinuumStepper):
    """The half-space's stepper (module docstring; its increments:
    :class:`~lcpfric.steppers.newton_increment.HalfSpaceIncrements`).

    Parameters
    ----------
    increment_tol : float
        Relative tolerance of the increments (natural-map residual / force scale). With d = 2
        the driver solves the early cycles more loosely, and the last ones to a tenth of its
        cycle tolerance, or to ``increment_tol`` if that is tighter (down to a hundredth of the
        cycle tolerance).
    warm_start : bool
        Start each increment from the same increment of the previous cycle (where it fits in
        memory): once the cycles nearly repeat, the increments are nearly solved before they
        begin.
    accelerate : bool
        Let the driver move each cycle's start towards the cycle map's fixed point (Anderson's
        acceleration, :mod:`lcpfric.periodic.acceleration`).
    slip_memory : bool
        d = 2: scale each cycle's change node by node by what the cycle remembers of its start
        before accelerating (:mod:`lcpfric.steppers.slip_memory`).
    loose_cycles : bool
        d = 2: solve the early cycles' increments loosely (the driver's schedule).
    """

    name = "newton-cg"
    model_type = HalfSpace

    def __init__(
        self,
        *,
        increment_tol: float = 1e-10,
        warm_start: bool = True,
        accelerate: bool = True,
        slip_memory: bool = True,
        loose_cycles: bool = True,
    ):
        self.increment_tol = _checks.positive("increment_tol", increment_tol)
        self.guesses = _checks.boolean("warm_start", warm_start)
        self.can_restart = _checks.boolean("accelerate", accelerate)
        self.slip_memory = _checks.boolean("slip_memory", slip_memory)
        self.loose_cycles = _checks.boolean("loose_cycles", loose_cycles)

    def context(self, scene):
        model = scene.model
        inner = HalfSpaceIncrements(model, self.increment_tol, scene.scales[0])
        if model.coupling is None:  # β = 0: the uncoupled increments, bit for bit
            return inner
        from .coupled_halfspace import CoupledIncrements

        return CoupledIncrements(inner, scene.limits[0] / (model.mu * model.h**2))

    def copy_context(self, context):
        return context.copy()

    def context_stats(self, context) -> dict:
        return dict(context.stats)

    def start(self, scene, context) -> Tangential:
        n, d = scene.model.nodes, scene.model.dims
        m = n * d
        return Tangential(
            np.zeros(m),
            np.zeros(d),
            np.zeros(m),
            np.zeros(m),
            np.zeros(d),
            np.zeros(n, dtype=np.int8),
            np.zeros((n, d)),
            np.zeros((n, d)),
        )

    def increment(self, context, state, b, Q, guess=None, tol=None):
        return context.increment(state, b, Q, guess, tol)

    def guess(self, state: Tangential):
        """What the same increment of the next cycle starts from: this increment's changes of
        the forces and of δ, its pattern and ``C ΔF`` (one per increment is kept)."""
        return state.dF, state.ddelta, state.side, state.CdF

    def restart(self, scene, state, v):
        """The state with the slips v (the driver's extrapolation): the slips are the state,
        the forces only the next solve's starting point. ``C F`` is formed afresh (one product
        a cycle: the sums carried from increment to increment gather no round-off beyond a
        cycle's)."""
        from dataclasses import replace

        data = state.data
        context = data.context.copy()
        context.stats["tangential_products"] += 1
        t = data.tangential
        new = Tangential(
            np.asarray(v, dtype=float).copy(),
            t.delta,
            t.F,
            np.zeros_like(t.dF),
            np.zeros_like(t.ddelta),
            t.side,
            context.compliance(t.F),
            np.zeros_like(t.CF),
        )
        return replace(state, u=new.v.copy(), data=replace(data, tangential=new, context=context))

    def memory(self, scene):
        """d = 2: the per-node memory of a cycle's starting slips, the driver's preconditioner
        of the cycle map (:class:`~lcpfric.steppers.slip_memory.SlipMemory`); None for
        d = 1 (a node that slips forgets its start)."""
        model = scene.model
        return SlipMemory(model.c, model.nodes) if model.dims == 2 and self.slip_memory else None

    def loose(self, scene) -> bool:
        """d = 2 settles over many cycles: the driver solves the early ones loosely."""
        return scene.model.dims == 2 and self.loose_cycles
