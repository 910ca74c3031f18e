"""Normal models: what gives the normal reactions N_i(t) of the contact nodes.

The protocol
------------
lcpfric treats *uncoupled* systems (paper, Section 2): the normal reactions do not depend on the
tangential displacements, so they are known over the whole cycle before any tangential
computation, and so are the instants where a node separates or re-enters contact. A normal model
is any object with:

``n`` : int
    The number of contact nodes.
``period`` : float or None
    The period of its loads (None when nothing varies in time).
``reactions(t) -> ndarray``
    ``N(t)`` with shape ``t.shape + (n,)``, every entry >= 0 (0 = separated).
``transitions(t0, t1) -> ndarray``
    The sorted instants in the open interval (t0, t1) where some node separates or re-enters
    contact. The scene puts them on its time grid, so that every node is in contact or separated
    for a whole increment.
``scale(t) -> ndarray``
    Per node, the magnitude of the normal load at ``t`` (shape ``t.shape + (n,)``): reactions
    within a few ulps of it are round-off and are set to exactly zero by the scene.
``always_in_contact() -> ndarray``
    Per node, True where N_i > 0 over the whole cycle (no separation logic needed).

:class:`NormalModel` states this as a :class:`typing.Protocol`; the scene and the steppers use
nothing else, so a contact model whose area changes with the load (a Hertz contact, a half-space
on a grid) plugs in by providing these members. :class:`IndependentSprings` is the paper's model
(a normal spring per node, Eq. 2) and the first implementation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol, runtime_checkable

import numpy as np

from ..errors import InputError
from .loads import Load, LoadSet

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["NormalModel", "IndependentSprings", "check_normal_model"]


@runtime_checkable
class NormalModel(Protocol):  # a protocol, never instantiated: numpydoc ignore=PR01
    """What a normal model provides (see the module docstring).

    A protocol: any object with these members is a normal model (``isinstance(x,
    NormalModel)`` checks that they are present); it is not instantiated.

    Attributes
    ----------
    n : int
        The number of contact nodes.
    period : float or None
        The period of its loads (None when nothing varies in time).
    """

    @property
    def n(self) -> int:
        """The number of contact nodes."""
        ...

    @property
    def period(self) -> float | None:
        """The period of its loads (None when nothing varies in time)."""
        ...

    def reactions(self, t: ArrayLike) -> np.ndarray:
        """The normal reactions N(t).

        Parameters
        ----------
        t : float or array_like
            Times.

        Returns
        -------
        ndarray
            ``N(t)`` with shape ``t.shape + (n,)``, every entry >= 0 (0 = separated).
        """
        ...

    def transitions(self, t0: float, t1: float) -> np.ndarray:
        """The instants where some node separates or re-enters contact.

        The scene puts them on its time grid, so that every node is in contact or separated
        for a whole increment.

        Parameters
        ----------
        t0, t1 : float
            The open interval searched, ``t0 < t1``.

        Returns
        -------
        ndarray
            The sorted instants in (t0, t1), 1-D.
        """
        ...

    def scale(self, t: ArrayLike) -> np.ndarray:
        """Per node, the magnitude of the normal load.

        Reactions within a few ulps of it are round-off and are set to exactly zero by the
        scene.

        Parameters
        ----------
        t : float or array_like
            Times.

        Returns
        -------
        ndarray
            Shape ``t.shape + (n,)``.
        """
        ...

    def always_in_contact(self) -> np.ndarray:
        """Per node, True where N_i > 0 over the whole cycle (no separation logic needed).

        Returns
        -------
        ndarray of bool
            Shape ``(n,)``.
        """
        ...


def check_normal_model(normal) -> None:
    """Raise :class:`InputError` if ``normal`` does not provide the :class:`NormalModel`
    members."""
    missing = [
        name
        for name in ("n", "period", "reactions", "transitions", "scale", "always_in_contact")
        if not hasattr(normal, name)
    ]
    if missing:
        raise InputError(
            "normal",
            f"must be a normal model (lcpfric.model.NormalModel, e.g. "
            f"IndependentSprings); {type(normal).__name__} lacks "
            f"{', '.join(missing)}",
        )


@dataclass(frozen=True)
class IndependentSprings:
    """Independent normal springs (paper, Eq. 2): ``N_i(t) = max(P_i(t), 0)``.

    Parameters
    ----------
    loads : sequence of Load
        The normal load P_i(t) of each node (at least one).

    Attributes
    ----------
    loads : tuple of Load
        The normal loads, one per node.
    n : int
        The number of nodes.
    period : float or None
        The period of the loads that vary (None when none does).

    Raises
    ------
    InputError
        ``loads`` empty, or not all :class:`~lcpfric.model.loads.Load` objects (named
        ``normal_loads``).
    """

    loads: tuple

    def __post_init__(self):
        loads = tuple(self.loads)
        if not loads or not all(isinstance(p, Load) for p in loads):
            raise InputError("normal_loads", "needs one Load object per node")
        object.__setattr__(self, "loads", loads)
        object.__setattr__(self, "_set", LoadSet(loads))

    @property
    def n(self) -> int:
        """The number of nodes."""
        return len(self.loads)

    @property
    def period(self) -> float | None:
        """The period of the first load that varies (None when none does)."""
        periods = [p.period for p in self.loads if not p.is_constant]
        return periods[0] if periods else None

    def periods(self) -> list[float]:
        """The period of every load that varies (for the system's check that they agree).

        Returns
        -------
        list of float
            One period per varying load, in node order.
        """
        return [p.period for p in self.loads if not p.is_constant]

    def loads_at(self, t: ArrayLike) -> np.ndarray:
        """P(t) with shape ``t.shape + (n,)`` (negative in separation).

        Parameters
        ----------
        t : float or array_like
            Times.

        Returns
        -------
        ndarray
            The normal loads, shape ``t.shape + (n,)``.
        """
        return self._set(t)

    def reactions(self, t: ArrayLike) -> np.ndarray:
        """N(t) = max(P(t), 0) with shape ``t.shape + (n,)``.

        Parameters
        ----------
        t : float or array_like
            Times.

        Returns
        -------
        ndarray
            The normal reactions, >= 0, shape ``t.shape + (n,)``.
        """
        return np.maximum(self.loads_at(t), 0.0)

    def scale(self, t: ArrayLike) -> np.ndarray:
        """``|P(t)|``, the magnitude against which a round-off zero of N is judged.

        Parameters
        ----------
        t : float or array_like
            Times.

        Returns
        -------
        ndarray
            Shape ``t.shape + (n,)``.
        """
        return np.abs(self.loads_at(t))

    def transitions(self, t0: float, t1: float) -> np.ndarray:
        """Sorted instants in (t0, t1) where some node separates or re-enters contact.

        Parameters
        ----------
        t0, t1 : float
            The open interval searched, ``t0 < t1``.

        Returns
        -------
        ndarray
            The zero crossings of the varying loads, sorted and unique, 1-D.
        """
        parts = [p.zeros(t0, t1) for p in self.loads if not p.is_constant]
        return np.unique(np.concatenate(parts)) if parts else np.empty(0)

    def always_in_contact(self) -> np.ndarray:
        """Per node: True where P_i(t) > 0 throughout the cycle (no separation logic needed).

        Returns
        -------
        ndarray of bool
            Shape ``(n,)``.
        """
        return np.array([p.extrema()[0] > 0 for p in self.loads])
