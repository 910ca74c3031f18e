"""A map's dataset and its file: the ``xarray.Dataset`` of a sweep (:mod:`.sweep`), written to
NetCDF-4 atomically, and read back for resuming."""

from __future__ import annotations

import os
from pathlib import Path


from .._optional import require
from ..errors import InputError
from .chunkstore import temp_path

__all__ = [
    "check_output",
    "netcdf_engine",
    "write_dataset",
    "read_dataset",
    "dataset",
    "version",
    "DIMS",
]

DIMS = ("phi", "P1", "Q1")


def check_output(out) -> Path:
    """Check the NetCDF output path before any work: a ``.nc`` file (not a directory) in an
    existing directory."""
    if not isinstance(out, (str, os.PathLike)) or not str(out).strip():
        raise InputError("out", f"must be a file path ending in .nc, got {out!r}")
    out = Path(out)
    if out.suffix == ".zarr":
        raise InputError("out", "Zarr output is not supported; write NetCDF (e.g. map.nc)")
    if out.suffix != ".nc":
        raise InputError(
            "out", f"must end in .nc (the map is written as NetCDF-4), got {str(out)!r}"
        )
    if out.is_dir():
        raise InputError("out", f"{str(out)!r} is a directory; give a file path ending in .nc")
    if not out.parent.is_dir():
        raise InputError("out", f"the directory {str(out.parent)!r} does not exist")
    return out


def xarray_module():
    return require("xarray", "dist", "Sweeps (xarray datasets)")


def netcdf_engine() -> str:
    """``"h5netcdf"`` (the dist extra's writer) when its HDF5 layer h5py is installed, else
    ``"netcdf4"``; both write NetCDF-4 files."""
    import importlib.util

    if importlib.util.find_spec("h5netcdf") and importlib.util.find_spec("h5py"):
        return "h5netcdf"
    if importlib.util.find_spec("netCDF4"):
        return "netcdf4"
    require("h5py", "dist", "NetCDF output")  # raises, naming the extra
    return "h5netcdf"  # pragma: no cover


def write_dataset(ds, out) -> Path:
    """Write ``ds`` to the NetCDF-4 file ``out`` atomically (see :func:`netcdf_engine`): a
    temporary file in the same directory, renamed over ``out`` once complete."""
    out = Path(out)
    engine = netcdf_engine()
    tmp = temp_path(out)
    try:
        ds.to_netcdf(tmp, engine=engine)
        os.replace(tmp, out)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return out


def read_dataset(out: Path):
    return xarray_module().load_dataset(out, engine=netcdf_engine())


def version() -> str:
    try:
        from .. import __version__

        return str(__version__)
    except ImportError:
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("lcpfric")
        except PackageNotFoundError:
            return "unknown"


#: the map's variable: single node, and a continuum contact (``contact=``)
_VARIABLES = {
    None: (
        "W_hat",
        {
            "long_name": "dimensionless dissipation per cycle",
            "description": "W_hat = k11 W / (f P0 Q1), Eq. (6) of the paper",
        },
    ),
    "sphere": (
        "W_normalized",
        {
            "long_name": "dimensionless dissipation per cycle",
            "description": "W k_t0 / (mu^2 P0^2), k_t0 = 2 a0 G*: the "
            "Hertz contact (the attribute 'model': mdr, "
            "dimensionality reduction; halfspace, "
            "boundary elements)",
        },
    ),
}


def dataset(values, phi, P1, Q1, attrs: dict, geometry=None):
    xr = xarray_module()
    name, meta = _VARIABLES[geometry]
    q_name = "Q1/(f P0)" if geometry is None else "Q1/(mu P0)"
    return xr.Dataset(
        {name: (DIMS, values.reshape(phi.size, P1.size, Q1.size), meta)},
        coords={
            "phi": ("phi", phi, {"long_name": "phase of Q relative to P", "units": "rad"}),
            "P1": ("P1", P1, {"long_name": "normal load amplitude P1/P0"}),
            "Q1": ("Q1", Q1, {"long_name": f"tangential load amplitude {q_name}"}),
        },
        attrs={k: v for k, v in attrs.items() if v is not None},
    )
