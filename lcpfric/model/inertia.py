"""A node's inertia and viscous damping (issue 40): the mass m and damping c of the dynamic
single node, ``m v'' + c v' + k11 v = F - Q``, and their dimensionless groups β = ω/Ω0
(Ω0 = sqrt(k11/m)) and ζ = c / (2 sqrt(k11 m)). Mass 0 is the paper's
quasi-static node."""

from __future__ import annotations

import math

from ..errors import InputError

__all__ = ["Inertia", "dynamic_method", "DYNAMIC_METHODS"]

#: the methods that solve a node with a mass
DYNAMIC_METHODS = ("exact", "newmark")


class Inertia:
    """The dynamic properties of a node with ``k11``, ``omega``, ``mass``, ``damping`` and
    ``k21`` attributes (a mixin of :class:`~lcpfric.model.SingleNode`)."""

    k11: float
    mass: float
    damping: float
    k21: float
    omega: float

    def _check_dynamics(self) -> None:
        """Refuse damping without mass, inertia with coupling, the undamped resonance."""
        if self.damping > 0 and self.mass == 0:
            raise InputError("damping", "needs a mass > 0 (a massless node is quasi-static)")
        if self.mass > 0 and self.k21:
            raise InputError("mass", "Klarbring's coupled node (k21 != 0) has no dynamics yet")
        if self.mass > 0 and self.damping == 0 and math.isclose(self.beta, 1.0, rel_tol=1e-9):
            raise InputError(
                "omega",
                f"ω = Ω0 = sqrt(k11/m) = {self.natural_frequency:.6g} without damping is the "
                "undamped resonance: the response is unbounded; give a damping > 0 or another ω",
            )

    @property
    def is_dynamic(self) -> bool:
        """Whether the node has a mass (its steady state is the dynamic one)."""
        return self.mass > 0.0

    @property
    def natural_frequency(self) -> float:
        """Ω0 = sqrt(k11/m) (inf for the quasi-static node)."""
        return math.sqrt(self.k11 / self.mass) if self.mass > 0 else math.inf

    @property
    def beta(self) -> float:
        """β = ω/Ω0 (0 for the quasi-static node)."""
        return self.omega / self.natural_frequency

    @property
    def zeta(self) -> float:
        """ζ = c / (2 sqrt(k11 m)) (0 for the quasi-static node)."""
        return self.damping / (2.0 * math.sqrt(self.k11 * self.mass)) if self.mass > 0 else 0.0


def dynamic_method(model, method: str) -> bool:
    """Whether ``model`` has a mass; if it has, refuse a method that is not in
    :data:`DYNAMIC_METHODS`.

    Parameters
    ----------
    model : object
        The driver's model.
    method : str
        The method's registry name.

    Returns
    -------
    bool
        The model is dynamic.

    Raises
    ------
    InputError
        A quasi-static method for a dynamic model (named ``method``).
    """
    dynamic = bool(getattr(model, "is_dynamic", False))
    allowed = getattr(model, "dynamic_methods", DYNAMIC_METHODS)
    if dynamic and method not in allowed:
        what = "a node with a mass (the dynamic node)" if allowed is DYNAMIC_METHODS else \
            f"a {type(model).__name__}"  # fmt: skip
        raise InputError(
            "method",
            f"{method!r} does not solve {what}: use {', '.join(repr(m) for m in allowed)}",
        )
    return dynamic
