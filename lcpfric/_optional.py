"""Optional dependencies, imported where they are used.

A missing one raises :class:`MissingExtra` (an :class:`ImportError` and a
:class:`~lcpfric.errors.SolverNotFound`) that names the extra to install.
"""

from __future__ import annotations

import importlib

from .errors import SolverNotFound

__all__ = ["MissingExtra", "require"]


class MissingExtra(SolverNotFound):
    """A feature needs an optional package that is not installed.

    Attributes
    ----------
    feature : str
        What the user asked for (``"sweeps"``, ``"figures"``).
    extra : str
        The extra that installs it: ``pip install "lcpfric[<extra>]"``.
    """

    def __init__(self, feature: str, extra: str, module: str = ""):
        self.feature = self.method = feature
        self.extra = extra
        ImportError.__init__(
            self, f"{feature} need the optional package {module or extra!r}, which is not "
                  f'installed; install it with: pip install "lcpfric[{extra}]"', name=module)

    def __reduce__(self):  # keep the arguments when a worker process sends it back
        return (type(self), (self.feature, self.extra, self.name or ""))


def require(module: str, extra: str, feature: str):
    """Import ``module``, or raise :class:`MissingExtra` naming ``extra``."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingExtra(feature, extra, module) from None
