"""Optional dependencies, imported where they are used.

A missing one raises :class:`~lcpfric.errors.MissingExtra` (an :class:`ImportError`) that
names the extra to install.
"""

from __future__ import annotations

import importlib

from .errors import MissingExtra

__all__ = ["MissingExtra", "require"]


def require(module: str, extra: str, feature: str):
    """Import ``module``, or raise :class:`MissingExtra` naming ``extra``."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingExtra(feature, extra, module) from None
