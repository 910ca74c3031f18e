"""What the tests share: the load cases, the measured order, the convex backends under test and
their tolerances (one table), the skips that name what to install, the figures' text
inspection, and (in submodules) the exact references and scenarios that the benchmarks use too.

The backends' table
-------------------
The convex backends under test and their tolerances, in one table.

``unrefined`` is the relative agreement of Ŵ with the closed-form projection on the same grid
when the backend's own answer is used (``refine=False``) with lcpfric's default (tight)
settings; with refinement (the default) every backend reproduces the projection to rounding,
``REFINED``. ``steps`` keeps the slow backends' tests short. ``max_iter`` is the setting that
caps the iterations (for the failure-path test) and the start of the status it must report.
"""

import importlib.util

import numpy as np
import pytest

from lcpfric import available_methods

# Cases (P̂1, Q̂1, φ) used across the suite: full contact, separation, near shakedown, large loads.
CASES = {
    "contact": (0.5, 2.0, 0.0),
    "contact-phase": (0.5, 2.0, 0.6 * np.pi),
    "separation": (1.5, 2.0, 0.6 * np.pi),
    "large": (5.0, 5.0, 0.6 * np.pi),
    "near-shakedown": (0.5, 1.01, 0.3 * np.pi),
}


def fitted_order(steps, errors):
    """Least-squares slope of -log(error) against log(steps): the measured order."""
    steps, errors = np.asarray(steps, float), np.asarray(errors, float)
    return -np.polyfit(np.log(steps), np.log(errors), 1)[0]


#: the pip extra that installs each optional module the tests use
EXTRAS = {
    "matplotlib": "plot",
    "xarray": "dist",
    "h5netcdf": "dist",
    "h5py": "dist",
    "dask": "dist",
    "distributed": "dist",
    "dask.distributed": "dist",
    "tqdm": "dist",
    "mpmath": "test",
    "numpydoc": "docs",
    "clarabel": "clarabel",
    "osqp": "osqp",
    "qpsolvers": "qpsolvers",
    "cvxpy": "cvxpy",
    "pyHarm": "pyharm",
}


def need_modules(*modules: str) -> None:
    """Skip the test when one of ``modules`` is not installed, naming the extra to install."""
    for module in modules:
        if _missing(module):
            pytest.skip(
                f'needs {module} (pip install "lcpfric[{EXTRAS.get(module, "all")}]")',
                allow_module_level=True,
            )


def _missing(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is None
    except ModuleNotFoundError:  # a submodule of a missing package
        return True


def needs(*modules: str):
    """The same as a mark: ``@needs("matplotlib")``."""
    missing = [m for m in modules if _missing(m)]
    extras = sorted({EXTRAS.get(m, "all") for m in missing})
    return pytest.mark.skipif(
        bool(missing),
        reason=f'needs {", ".join(missing)} (pip install "lcpfric[{",".join(extras)}]")',
    )


REFINED = 1e-12  # relative, Ŵ against the projection on the same grid

BACKENDS = {
    # method              extra        unrefined  steps  (iteration-cap setting, status prefix)
    "clarabel": ("clarabel", 2e-6, 2000, ({"max_iter": 1}, "MaxIterations")),
    "osqp": ("osqp", 1e-8, 2000, ({"max_iter": 1}, "maximum iterations")),
    "qpsolvers:clarabel": ("qpsolvers", 2e-6, 100, ({"max_iter": 1}, "MaxIterations")),
    "qpsolvers:highs": ("qpsolvers", 1e-10, 100, ({"qp_iteration_limit": 0}, "not found")),
    "qpsolvers:osqp": ("qpsolvers", 1e-8, 100, ({"max_iter": 1}, "maximum iterations")),
    "qpsolvers:proxqp": ("qpsolvers", 1e-9, 100, ({"max_iter": 1}, "QPSolverOutput.PROXQP")),
    "qpsolvers:scs": ("qpsolvers", 1e-7, 100, ({"max_iters": 1}, "solved (inaccurate")),
    "cvxpy:CLARABEL": ("cvxpy", 2e-6, 60, ({"max_iter": 1}, "user_limit")),
    "cvxpy:OSQP": ("cvxpy", 1e-7, 60, ({"max_iter": 1}, "user_limit")),
    "cvxpy:SCS": ("cvxpy", 1e-7, 60, ({"max_iters": 1}, "optimal_inaccurate")),
    "cvxpy:ECOS": ("ecos", 1e-7, 60, ({"max_iters": 1}, "user_limit")),
}

FAST = ("clarabel", "osqp")  # the direct APIs: cheap enough for every case


def need(method: str) -> None:
    """Skip the test when ``method`` is not installed, naming the extra to install."""
    if method not in available_methods():
        extra = BACKENDS[method][0]
        hint = "pip install ecos" if extra == "ecos" else f'pip install "lcpfric[{extra}]"'
        pytest.skip(f"{method} is not installed here ({hint})")


def params(methods=None):
    """pytest parameters over the table, every installed backend (the rest skip)."""
    return [pytest.param(m, id=m) for m in (methods or BACKENDS)]


# -- figures -------------------------------------------------------------------------------------
def renderer(fig):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    canvas.draw()
    return canvas.get_renderer()


def texts(fig):
    """Every visible, non-empty Text artist of a drawn figure: tick labels (all axes, colour bars,
    secondary axes), axis labels, titles, legends, contour labels, annotations."""
    from matplotlib.text import Text

    found = {id(t): t for t in fig.findobj(Text)}
    for ax in fig.axes:
        for axes in (ax, *ax.child_axes):
            for t in (*axes.get_xticklabels(which="both"), *axes.get_yticklabels(which="both")):
                found[id(t)] = t
    return [t for t in found.values() if t.get_visible() and t.get_text().strip()]


# -- contacts ----------------------------------------------------------------------------------
def halfspace_sphere(P1=0.0, Q1=0.25, phi=0.0, nu=0.0, grid=16, dims=1, k_support=0.0, **kw):
    """The half-space sphere of the contact tests: R = E = 1, μ = 0.5, P0 = 1, period 2π."""
    import math

    from lcpfric.model import Harmonic
    from lcpfric.model.continuum import HalfSpace

    two_pi = 2.0 * math.pi
    return HalfSpace.sphere(
        1.0,
        1.0,
        nu,
        0.5,
        Harmonic(1.0, P1, 0.0, two_pi),
        Harmonic(0.0, Q1, phi, two_pi),
        grid=grid,
        dims=dims,
        k_support=k_support,
        **kw,
    )
