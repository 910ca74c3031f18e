"""The periodic steady state: the one driver and what it uses.

``driver``        :func:`steady_state`: whole cycles of any model by any method until the cycle
                  repeats (the one cycle loop of a single steady state)
``measure``       how far a cycle is from repeating (:func:`cycle_change`, the one criterion;
                  the exact solver's cycle Newton uses it too)
``acceleration``  where a cycle's start is moved: Aitken's jumps, the slip memory, Anderson's
                  acceleration
``assemble``      the driver's result from its last cycle (a single node's normalization, a
                  contact's geometry), the shakedown test, the unresolved slip zone's warning
``batched``       the one cycle loop of many points advanced together (single-node grids, the
                  MDR sphere's maps)
"""

__all__ = ["steady_state", "cycle_change", "CycleProgress", "DRIVER_OPTIONS"]


def __getattr__(name: str):
    # imported on first use: the measure alone must not pull in the driver and the steppers
    if name in ("steady_state", "CycleProgress", "DRIVER_OPTIONS"):
        from . import driver

        return getattr(driver, name)
    if name == "cycle_change":
        from .measure import cycle_change

        return cycle_change
    raise AttributeError(f"module 'lcpfric.periodic' has no attribute {name!r}")
