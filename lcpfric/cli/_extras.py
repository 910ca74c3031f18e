"""The optional packages of the subcommands: which extra installs each, and one error naming
every missing one (standard library only: imported for ``lcpfric --help``)."""

from __future__ import annotations

import importlib.util

from ..errors import LcpfricError

__all__ = ["MissingExtras", "installed", "require_extras"]


#: importable module -> the extra that installs it
EXTRA_OF = {
    "matplotlib": "plot",
    "xarray": "dist",
    "h5netcdf": "dist",
    "h5py": "dist",
    "distributed": "dist",
    "dask": "dist",
    "tqdm": "dist",
    "clarabel": "clarabel",
    "osqp": "osqp",
    "qpsolvers": "qpsolvers",
    "cvxpy": "cvxpy",
}


class MissingExtras(LcpfricError):
    """Optional packages a subcommand needs are missing (all of them named at once)."""

    def __init__(self, what: str, missing: list[tuple[str, str]]):
        self.what = what
        self.missing = missing
        extras = ",".join(dict.fromkeys(extra for _, extra in missing))
        listed = " and ".join(f"{module} ({extra})" for module, extra in missing)
        super().__init__(f'{what} need {listed}: pip install "lcpfric[{extras}]"')


def installed(module: str) -> bool:
    """Whether ``module`` can be imported (found without importing it)."""
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def require_extras(what: str, modules) -> None:
    """Raise :class:`MissingExtras` naming every one of ``modules`` that is not installed.

    ``modules``: module names, or tuples of alternatives (the first one is named if none is
    installed).
    """
    missing = []
    for entry in modules:
        choices = (entry,) if isinstance(entry, str) else tuple(entry)
        if not any(installed(m) for m in choices):
            missing.append((choices[0], EXTRA_OF.get(choices[0], choices[0])))
    if missing:
        raise MissingExtras(what, missing)
