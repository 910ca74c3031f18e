"""What a convex backend implements, and what it is called through: :class:`SolverInterface`.

The class attributes and methods a backend subclass of
:class:`~lcpfric.backends.base.ConvexStepper` sets or overrides (``build``, ``bounds``,
``solve``, ``handle_bytes``, ``STATUS_MAP``), its settings, and :meth:`SolverInterface.guarded`,
through which every call into a solver goes (its own exceptions become
:class:`~lcpfric.errors.SolverError`). :func:`quiet` silences a solver's warnings.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import InputError, SolverError
from .problem import IncrementProblem
from .settings import settings_for
from .status import UNKNOWN

__all__ = ["SolverInterface", "quiet"]


class SolverInterface:
    """The solver side of :class:`~lcpfric.backends.base.ConvexStepper` (a mixin).

    The class attributes are documented in :class:`~lcpfric.backends.base.ConvexStepper`.
    """

    name = ""
    can_soc = False
    STATUS_MAP: dict[str, str] = {}
    settings_key = ""  # key into TIGHT_SETTINGS (default: the name)
    # the size of a solver object, for the plan's budget: bytes per entry of the upper triangle
    # of P (its copies of P, its KKT system, the factor) and per object
    handle_size: tuple[int, int] = (64, 128 * 1024)
    solver: str | None = None  # the solver of a ':<solver>' backend

    @property
    def label(self) -> str:
        """The name to report: ``name``, or ``"name:solver"`` for a ``:<solver>`` backend."""
        return f"{self.name}:{self.solver}" if self.solver else self.name

    def settings_for(self, dims: int) -> dict[str, Any]:
        """The solver settings for problems with d = ``dims``.

        Parameters
        ----------
        dims : int
            d of the problems, 1 or 2.

        Returns
        -------
        dict
            A new dict: lcpfric's tight defaults
            (:data:`~lcpfric.backends.settings.TIGHT_SETTINGS` under ``settings_key`` or the
            name, with its ``_soc`` variant for d = 2), then the user's.
        """
        return settings_for(self.settings_key or self.name, dims, self.user_settings)

    @property
    def settings(self) -> dict[str, Any]:
        """The settings for d = 1 problems (:meth:`settings_for` of 1)."""
        return self.settings_for(1)

    # -- the backend interface (see the class docstring) ------------------------------------
    def build(
        self, prob: IncrementProblem, settings: dict[str, Any]
    ) -> Any:  # pragma: no cover - abstract
        """Build the solver object for a new problem (each backend implements it).

        Called when the plan builds the problem of a contact set. A set whose problem was
        dropped from the plan is built again: the object must not rely on an earlier one (it
        starts cold). The base class raises :class:`NotImplementedError`.

        Parameters
        ----------
        prob : IncrementProblem
            The problem: ``P``, the set's ``nodes``, ``dims`` (``q`` is zero here).
        settings : dict
            The solver settings for its d (:meth:`settings_for`).

        Returns
        -------
        Any
            The solver object, stored as ``prob.handle`` and passed back to :meth:`solve`.
        """
        raise NotImplementedError

    def bounds(self, prob: IncrementProblem, b: np.ndarray) -> Any:
        """The limits of a grid instant in the form the backend's update takes.

        Called once per grid instant, and kept: the result must not refer to ``prob``. The
        default is the box ``(l, u) = (-b, b)`` of d = 1 (QP backends); conic backends
        override it.

        Parameters
        ----------
        prob : IncrementProblem
            The problem of the instant's contact set.
        b : (a,) ndarray
            The friction limits f_i N_i, one per node of the set.

        Returns
        -------
        Any
            What :meth:`solve` takes as ``bdata``; by default the tuple ``(-b, b)`` of two new
            arrays.
        """
        return -b, b.copy()

    def solve(
        self, prob: IncrementProblem, q: np.ndarray, bdata: Any
    ) -> tuple[np.ndarray, Any, bool]:  # pragma: no cover
        """Solve (P) for one step (each backend implements it).

        Update the linear term and the bounds of the solver object ``prob.handle``, solve, and
        return the answer. Called through :meth:`guarded`. The base class raises
        :class:`NotImplementedError`.

        Parameters
        ----------
        prob : IncrementProblem
            The problem of the step's contact set.
        q : (a·d,) ndarray
            The linear term ``-(C F_tr)_A`` (``prob.q``, overwritten by the next step).
        bdata : Any
            The bounds, as :meth:`bounds` made them.

        Returns
        -------
        x : (a·d,) array_like
            The forces F_A.
        status : Any
            The backend's own status (its ``str`` is looked up in ``STATUS_MAP``).
        ok : bool
            Whether that status means solved.
        """
        raise NotImplementedError

    def handle_bytes(self, prob: IncrementProblem) -> int:
        """Estimated bytes of the solver object of ``prob``, counted in the plan's budget.

        From ``handle_size``: bytes per entry of the upper triangle of P, and per object. A
        backend whose object does not scale so overrides this method.

        Parameters
        ----------
        prob : IncrementProblem
            The problem about to be built.

        Returns
        -------
        int
            The estimate, in bytes.
        """
        per_entry, per_object = self.handle_size
        return per_entry * prob.triu_nnz + per_object

    def status_category(self, status: Any) -> str:
        """Map the backend's own ``status`` to lcpfric's.

        Parameters
        ----------
        status : Any
            The backend's status (its ``str`` is looked up in ``STATUS_MAP``).

        Returns
        -------
        str
            One of :mod:`~lcpfric.backends.status`'s outcomes (``SOLVED``, ``MAX_ITER``,
            ...); ``UNKNOWN`` for a status the map does not list.
        """
        return self.STATUS_MAP.get(str(status), UNKNOWN)

    def guarded(self, fn: Callable[..., Any], *args: Any) -> Any:
        """Call a backend function, re-raising the backend's own exceptions as SolverError.

        Parameters
        ----------
        fn : callable
            The function (:meth:`build` or :meth:`solve`).
        *args
            Its arguments.

        Returns
        -------
        Any
            What ``fn`` returns.

        Raises
        ------
        lcpfric.errors.SolverError
            ``fn`` raised one (re-raised unchanged) or any other exception but InputError
            (wrapped, the exception's type name as the status).
        lcpfric.errors.InputError
            ``fn`` raised one (re-raised unchanged).
        """
        try:
            return fn(*args)
        except (SolverError, InputError):
            raise
        except Exception as exc:  # the backend's own error types vary
            raise SolverError(
                f"{self.label}: the solver failed: {type(exc).__name__}: {exc}",
                backend=self.label,
                status=type(exc).__name__,
            ) from exc


def quiet(fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
    """Call ``fn`` with the backend's warnings silenced (lcpfric raises its own errors).

    Parameters
    ----------
    fn : callable
        A solver's function.
    *args, **kwargs
        Its arguments.

    Returns
    -------
    Any
        What ``fn`` returns; its exceptions pass through.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)
