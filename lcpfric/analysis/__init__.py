"""Analyses built on the steady states: closed forms, shakedown, dissipation maps, and the
comparison of methods.

``analytic``     the paper's analytical results at φ = 0 (Eqs. 11-12, corrected)
``shakedown``    the exact shakedown test of the single node
``sweep``        dissipation maps over (P̂1, Q̂1, φ): chunked, resumable, parallel, on Dask
``chunkstore``   the on-disk store that makes a sweep resumable
``runners``      where a sweep's chunks run: serially, on local processes, on Dask
``convergence``  error against run time and convergence orders of every method
                 (``lcpfric bench``)
"""

from . import analytic
from .shakedown import Shakedown, shakedown

__all__ = ["analytic", "Shakedown", "shakedown"]
