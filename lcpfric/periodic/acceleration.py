"""Where a cycle's start is moved to reach the periodic steady state in fewer cycles: the one place
every acceleration of the cycle map lives.

The cycle maps the state at a cycle's start ``x`` to its end ``G(x)``; the steady state is its
fixed point. The driver goes on from ``G(x)``, unless :class:`Acceleration` gives another start:

* Aitken's jump (:func:`aitken`) where one slow mode shows (three differences shrinking at one
  steady ratio): a weakly grounded system drifting back;
* with d = 2, each node's Newton step on what the cycle remembers of its start
  (:class:`~lcpfric.steppers.slip_memory.SlipMemory`, exact for uncoupled nodes), then, for
  coupled ones, Anderson's acceleration of the map (:class:`Anderson`);
* Anderson's acceleration alone for a stepper that can restart a cycle but tracks no memory
  (the half-space with d = 1).

Nothing is taken from an extrapolation but a starting point: convergence is still confirmed by
a whole cycle that repeats (:mod:`.measure`). The stepper puts the start it is given back where
its model allows (``Stepper.restart``: the forces inside the friction cone).
"""

from __future__ import annotations

import numpy as np

from ..steppers.slip_memory import SlipMemory

__all__ = ["Acceleration", "Anderson", "aitken", "choose", "FrictionLimits"]


def aitken(starts: list):
    """Aitken's jump ``s + ρ/(1 - ρ) d`` from the last of the cycles' starting states, when the
    last three differences d shrink at one steady ratio ρ in [0.3, 0.999]; else None.

    Near the steady state, with the stick/slip pattern settled, the cycle map is affine, and a
    slow approach (a weakly grounded system drifting back, ratio ρ close to 1 per cycle) is
    dominated by one mode; the jump moves the start to that mode's fixed point."""
    if len(starts) < 4:
        return None
    d = [np.linalg.norm(starts[i + 1] - starts[i]) for i in range(len(starts) - 4, len(starts) - 1)]
    if d[0] == 0 or d[1] == 0:
        return None
    r1, r2 = d[1] / d[0], d[2] / d[1]
    if not (0.3 <= r2 <= 0.999 and abs(r2 - r1) <= 0.05 * r2):
        return None
    return starts[-1] + r2 / (1.0 - r2) * (starts[-1] - starts[-2])


class Anderson:
    """Anderson's acceleration (type II, depth m, 10 by default) of a cycle map ``x -> G(x)``:
    from the last ``m + 1`` pairs ``(x_k, G(x_k))``, the next start is ``G(x_k) - ΔG γ`` with
    γ the least-squares coefficients of the residuals' differences ``ΔF`` that best cancel
    ``f_k = G(x_k) - x_k``. Near the steady state the map is affine with a few slow modes (the
    stick/slip pattern has settled), which this removes in about as many cycles as there are
    modes, where the plain iteration contracts only by the slowest mode's ratio per cycle. A
    history whose residuals grow is dropped (the map is not in its affine regime yet). Where
    it stalls (the residual shrinks by less than a tenth per cycle, three cycles running: the
    map is not affine at that scale), the plain iteration goes on, with Aitken's jumps
    (:func:`aitken`) when one slow mode shows."""

    def __init__(self, depth: int = 10):
        self.depth = depth
        self.x: list = []
        self.g: list = []
        self.norms: list = []
        self.starts: list | None = None  # the plain iteration's starts, once stalled

    def __call__(self, x: np.ndarray, g: np.ndarray):
        """The next start after the cycle from ``x`` that ended at ``g``, or None (go on
        from g)."""
        f = g - x
        self.norms.append(float(np.linalg.norm(f)))
        if (
            self.starts is None
            and len(self.norms) >= 4
            and all(b > 0.9 * a for a, b in zip(self.norms[-4:-1], self.norms[-3:]))
        ):
            self.starts = [x]
        if self.starts is not None:
            self.starts.append(g)
            jump = aitken(self.starts)
            if jump is not None:
                self.starts = [jump]
            return jump
        if self.x and self.norms[-1] > self.norms[-2]:
            self.x, self.g = [], []
        self.x = (self.x + [x])[-(self.depth + 1) :]
        self.g = (self.g + [g])[-(self.depth + 1) :]
        if len(self.x) < 2:
            return None
        G = np.array(self.g).T
        R = G - np.array(self.x).T
        gamma = np.linalg.lstsq(np.diff(R, axis=1), f, rcond=1e-12)[0]
        return g - np.diff(G, axis=1) @ gamma


class Acceleration:
    """The next start of the cycle map after a cycle (module docstring): ``memory``
    (a :class:`SlipMemory`, or None), ``anderson`` (apply :class:`Anderson`) and ``aitken``
    (Aitken's jumps on the plain iteration's starts)."""

    def __init__(
        self,
        memory: SlipMemory | None = None,
        anderson: bool = False,
        aitken: bool = False,
        first=None,
    ):
        self.memory = memory
        self.anderson = Anderson() if anderson else None
        self.starts = [first] if aitken else None

    def __call__(self, cyc, limits=None):
        """The next start after the recorded cycle ``cyc`` (its first and last rows are the
        cycle's start and end), or None (go on from its end). ``limits``: the friction limits
        at each instant, for a memory taken from the recorded cycle."""
        x0, end = cyc.u[0], cyc.u[-1]
        if self.memory is not None:
            R = cyc.memory if cyc.memory is not None else self.memory.of_cycle(cyc.u, limits)
            end = x0 + self.memory.step(R, end - x0)
        nxt = self.anderson(x0, end) if self.anderson is not None else None
        if self.starts is not None:
            self.starts.append(cyc.u[-1])
            nxt = aitken(self.starts)
        if nxt is None and self.memory is not None:
            nxt = end
        return nxt

    def restarted(self, start) -> None:
        """The start the stepper took (Aitken's next jump is measured from it)."""
        if self.starts is not None:
            self.starts = [start]


class FrictionLimits:
    """The friction limits ``f N`` at each instant of a discrete system's scene, row by row."""

    def __init__(self, scene):
        self.N, self.f = scene.N, scene.system.friction

    def __getitem__(self, k):
        return np.asarray(self.N[k], dtype=float) * self.f


def choose(scene, stepper, history: bool, start) -> Acceleration | None:
    """The acceleration of a scene's cycles by a stepper (``start``: the first cycle's
    displacements):

    * a continuum contact's stepper that can restart a cycle: its memory (d = 2), then
      Anderson's acceleration;
    * a discrete system with d = 2 whose cycles are kept whole: the memory taken from the
      recorded cycle, then Anderson's acceleration where the nodes are coupled;
    * a coupled system (``N = P + B u``): none, its steady state depends on the start and a
      jump could land on another one;
    * any other discrete system: Aitken's jumps."""
    if scene.system is None:
        if not stepper.can_restart:
            return None
        return Acceleration(stepper.memory(scene), anderson=True)
    system = scene.system
    if getattr(system, "coupling", None) is not None:
        return None  # a start-dependent steady state: the cycles as they happen, no jumps
    if history and system.dims == 2:
        c = np.asarray(system.compliance_diagonal(), dtype=float).reshape(system.n, -1)
        return Acceleration(SlipMemory(c.mean(axis=1), system.n), anderson=not system.is_diagonal())
    return Acceleration(aitken=True, first=start)
