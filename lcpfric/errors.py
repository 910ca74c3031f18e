"""Exception types raised by lcpfric.

Every error lcpfric raises derives from :class:`LcpfricError`, so a caller can catch them all at
once. Bad input raises :class:`InputError` (also a :class:`ValueError`), whose message names the
parameter and its allowed range. A solver that fails, or whose answer does not pass lcpfric's own
residual checks, raises :class:`SolverError` carrying the backend's own status.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "LcpfricError",
    "InputError",
    "SolverError",
    "SolverNotFound",
    "MissingDependency",
    "MissingExtra",
    "ConvergenceError",
    "ConvergenceWarning",
    "UndefinedQuantity",
]


class LcpfricError(Exception):
    """Base class of every error raised by lcpfric."""


class InputError(LcpfricError, ValueError):
    """A parameter is outside its allowed range, not finite, or cannot be parsed.

    The message reads ``"<parameter>: <message>"``, so that the command line can print it as
    it is.

    Parameters
    ----------
    parameter : str
        The name of the offending parameter, as the user typed it.
    message : str
        What is wrong with it, with its allowed range.

    Attributes
    ----------
    parameter : str
        The name of the offending parameter, as the user typed it.
    detail : str
        The ``message`` given (without the parameter's name).
    """

    def __init__(self, parameter: str, message: str) -> None:
        self.parameter = parameter
        self.detail = message
        super().__init__(f"{parameter}: {message}")

    def __reduce__(self):  # picklable, so it crosses process and Dask worker boundaries
        return (type(self), (self.parameter, self.detail))


class SolverError(LcpfricError, RuntimeError):
    """A step's convex problem was not solved to the requested accuracy.

    Parameters
    ----------
    message : str
        What failed, in words.
    backend : str, optional
        Registry name of the backend (``"clarabel"``, ``"osqp"``, ...).
    status : str, optional
        The backend's own status string, unchanged.
    residuals : dict or None, optional
        lcpfric's independent residual checks of the returned answer, when one was returned.

    Attributes
    ----------
    backend : str
        Registry name of the backend (``"clarabel"``, ``"osqp"``, ...).
    status : str
        The backend's own status string, unchanged.
    residuals : dict
        lcpfric's independent residual checks of the returned answer, when one was returned
        (empty otherwise).
    """

    def __init__(
        self, message: str, *, backend: str = "", status: str = "", residuals: dict | None = None
    ) -> None:
        self.backend = backend
        self.status = status
        self.residuals = dict(residuals or {})
        super().__init__(message)

    def __reduce__(self):
        return (
            _rebuild_solver_error,
            (type(self), self.args[0], self.backend, self.status, self.residuals),
        )


class MissingDependency(LcpfricError, ImportError):
    """Something the user asked for needs an optional package that is not installed.

    It is a method (:class:`SolverNotFound`) or a feature such as sweeps or figures
    (:class:`MissingExtra`). The message names what to install.
    """


class MissingExtra(MissingDependency):
    """A feature (sweeps, figures, progress bars) needs an optional package that is missing.

    Parameters
    ----------
    feature : str
        What the user asked for (``"Sweeps"``, ``"Figures"``).
    extra : str
        The extra that installs it: ``pip install "lcpfric[<extra>]"``.
    module : str, optional
        The missing module's name, when it differs from ``extra`` (it is then the one the
        message names, and ``name``).

    Attributes
    ----------
    feature : str
        What the user asked for (``"Sweeps"``, ``"Figures"``).
    extra : str
        The extra that installs it: ``pip install "lcpfric[<extra>]"``.
    name : str or None
        The missing module (:attr:`ImportError.name`), None when only the extra is known.
    """

    def __init__(self, feature: str, extra: str, module: str = "") -> None:
        self.feature = feature
        self.extra = extra
        super().__init__(
            f"{feature} need the optional package {module or extra!r}, which is "
            f'not installed; install it with: pip install "lcpfric[{extra}]"'
        )
        self.name = module or None

    def __reduce__(self):  # keep the arguments when a worker process sends it back
        return (type(self), (self.feature, self.extra, self.name or ""))


class SolverNotFound(MissingDependency):
    """A method needs an optional dependency that is not installed.

    The message names what to install: the extra (``pip install "lcpfric[clarabel]"``) or, for
    one solver of a ``:<solver>`` method, its own package (``pip install ecos``).

    Parameters
    ----------
    method : str
        The method name as the user gave it (``"clarabel"``, ``"qpsolvers:ecos"``).
    extra : str or None
        The pip extra that installs what the method needs.
    installed : list of str or None, optional
        The methods usable now (:func:`lcpfric.methods.available_methods`), listed in the
        message when given.
    package : str or None, optional
        The package to install instead of the extra (one solver of a ``:<solver>`` method).

    Attributes
    ----------
    method : str
        The method name as the user gave it.
    extra : str or None
        The pip extra that installs what the method needs.
    installed : list of str or None
        The methods usable now, when known.
    package : str or None
        The package to install instead of the extra, when there is one.
    """

    def __init__(
        self,
        method: str,
        extra: str | None,
        installed: list[str] | None = None,
        package: str | None = None,
    ) -> None:
        self.method = method
        self.extra = extra
        self.installed = installed
        self.package = package
        how = f"pip install {package}" if package else f'pip install "lcpfric[{extra}]"'
        msg = (
            f"method {method!r} needs an optional dependency that is not installed; "
            f"install it with: {how}"
        )
        if installed is not None:
            msg += f" (methods available now: {', '.join(installed)})"
        super().__init__(msg)

    def __reduce__(self):
        return (
            _rebuild_not_found,
            (type(self), self.method, self.extra, self.installed, self.package),
        )


class ConvergenceError(LcpfricError, RuntimeError):
    """The periodic driver did not reach a steady state within ``max_cycles``.

    Parameters
    ----------
    message : str
        What happened, in words.
    result : SteadyState or None, optional
        The (unconverged) result, for inspection.

    Attributes
    ----------
    result : SteadyState or None
        The (unconverged) result, for inspection
        (:class:`~lcpfric.results.SteadyState`).
    """

    def __init__(self, message: str, result: Any = None) -> None:
        self.result = result
        super().__init__(message)


class UndefinedQuantity(LcpfricError, AttributeError):
    """A result was asked for a quantity it does not define (Ŵ of a general system).

    It is also an :class:`AttributeError`, so ``hasattr`` and ``getattr`` with a default
    treat the quantity as absent.

    Parameters
    ----------
    quantity : str
        The name of the quantity asked for (``"W_hat"``).
    message : str
        Why the result does not define it.

    Attributes
    ----------
    quantity : str
        The name of the quantity asked for.
    detail : str
        The ``message`` given (without the quantity's name).
    """

    def __init__(self, quantity: str, message: str) -> None:
        self.quantity = quantity
        self.detail = message
        super().__init__(f"{quantity}: {message}")

    def __reduce__(self):
        return (type(self), (self.quantity, self.detail))


def _rebuild_not_found(cls, method, extra, installed, package):
    return cls(method, extra, installed, package=package)


def _rebuild_solver_error(cls, message, backend, status, residuals):
    return cls(message, backend=backend, status=status, residuals=residuals)


class ConvergenceWarning(UserWarning):
    """Warning issued instead of :class:`ConvergenceError` when ``on_nonconvergence="warn"``."""


class ResolutionWarning(UserWarning):
    """A continuum contact's answer that its grid cannot resolve.

    No element slipped over the steady cycle (W = 0), where the exact contact may slip in a
    zone thinner than an element (:func:`lcpfric.steady_state`).
    """


class MultipleSteadyStates(UserWarning):
    """Several periodic steady states of different dissipation were found for one input (the
    dynamic single node, from different starts): the result is the one reached from the given
    start (or the first start), and lists all (:attr:`lcpfric.results.DynamicExtras.orbits`)."""
