"""Analyses built on the steady states: closed forms, shakedown, dissipation maps, loops.

``analytic``      the paper's analytical results at φ = 0 (Eqs. 11-12, corrected)
``shakedown``     the exact shakedown test of the single node (and of systems: ``safe_state``)
``starts``        the steady states reached from many starts (coupled systems)
``loop``          the hysteresis loop of a steady state (its area is W)
``sweep``         dissipation maps over (P̂1, Q̂1, φ): chunked, resumable, parallel, on Dask
``sweep_plan``    what a sweep's chunks run, their cost, boundaries and fingerprint
``sweep_io``      a map's dataset and its NetCDF file
``chunkstore``    the on-disk store that makes a sweep resumable
``runners``       where a sweep's chunks run: serially, on local processes, on Dask
``contact_maps``  the continuum contacts' maps (the MDR sphere batched, the half-space point by
                  point on shared scenes)
"""

from . import analytic
from .shakedown import Shakedown, shakedown

__all__ = ["analytic", "Shakedown", "shakedown"]
