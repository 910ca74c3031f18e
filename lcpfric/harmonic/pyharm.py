"""lcpfric's Jenkins element inside pyHarm (``pip install pyharm-os``), a harmonic-balance code.

pyHarm builds its elements by name from a factory dictionary
(``pyHarm.Elements.FactoryElements.ElementDictionary``, keyed by each class's
``factory_keyword``); ``pyHarm.BaseUtilFuncs.pyHarm_plugin(cls)`` adds a class to it, and is
what pyHarm's two extension routes call: the ``"plugin"`` list of a ``Maestro`` input
(``Maestro({"plugin": [cls], ...})``) and the ``pyharm.extensions`` entry points (a callable
returning the classes to plug, enabled in pyHarm's ``extensions.toml``). This module gives:

``pyharm_element_class()``   the element class, a ``NodeToNodeElement`` whose residual and
                             Jacobian are :func:`~lcpfric.harmonic.jenkins_aft`'s (factory
                             keyword ``"LcpfricJenkins"``, the input keys of pyHarm's own
                             ``"Jenkins"``: ``connect``, ``dirs``, ``mu``, ``N0``, ``k``)
``register_pyharm_element()`` plugs it into pyHarm's factory (once)
``pyharm_extension()``       the same class list for a ``pyharm.extensions`` entry point
``pyharm_harmonic_index(nh)`` where pyHarm's harmonic blocks sit in lcpfric's coefficients
``oscillator_input(...)``, ``pyharm_frequency_response(...)``  one mass with a Jenkins
                             element to ground as a pyHarm input, and its continuation run

**The mapping.** pyHarm orders a signal's coefficients by its harmonic list ``nh`` (an int H:
0, 1, ..., H; or a sorted list of harmonics, with or without 0): ``[c0, a_h, b_h, ...]`` with
``x(τ_k) = c0 + Σ a_h cos hτ_k + b_h sin hτ_k`` at ``τ_k = 2πk/nti`` (its ``D["ft"]`` is
lcpfric's ``E.T``, its ``D["tf"]`` lcpfric's ``D.T``: the mean without 1/2, amplitudes, cosine
before sine, the same samples). So a pyHarm vector is lcpfric's vector of ``H = max(nh)``
harmonics restricted to the positions :func:`pyharm_harmonic_index` returns (0 for c0,
2h - 1 and 2h for a_h and b_h), the others zero; the force is read back at the same positions
and the Jacobian is the corresponding sub-block: exact, no rescaling. pyHarm's
non-dimensionalisation (``adim``: displacements in units of lc) enters as the input times lc
and the Jacobian times lc, the force staying in force units as pyHarm's own Jenkins element
keeps it (its ``k`` times lc, the slip force unchanged).

Importing pyHarm writes ``.pyHarm/context.json`` into the working directory unless the
environment variable ``PYHARM_CONTEXT_FILE`` names another file.
"""

from __future__ import annotations

import functools
import importlib
import logging
import time
import warnings

import numpy as np

from ..errors import InputError, MissingDependency
from .aft import jenkins_aft
from .fourier import check_samples

__all__ = [
    "FACTORY_KEYWORD",
    "pyharm_element_class",
    "register_pyharm_element",
    "pyharm_extension",
    "pyharm_harmonic_index",
    "oscillator_input",
    "pyharm_frequency_response",
]

#: the name pyHarm's input uses for lcpfric's Jenkins element (``"type"`` of a connector)
FACTORY_KEYWORD = "LcpfricJenkins"


def _import_pyharm():
    """pyHarm, or a :class:`~lcpfric.errors.MissingDependency` naming what to install."""
    try:
        return importlib.import_module("pyHarm")
    except ImportError:
        err = MissingDependency(
            "lcpfric's pyHarm element needs the optional package 'pyHarm', which is not "
            'installed; install it with: pip install pyharm-os (or pip install "lcpfric[pyharm]")'
        )
        err.name = "pyHarm"
        raise err from None


def pyharm_harmonic_index(nh) -> np.ndarray:
    """The positions of pyHarm's coefficients in lcpfric's coefficient vector.

    Parameters
    ----------
    nh : int or list of int
        pyHarm's harmonics: H (0, 1, ..., H) or a list of harmonics (0 included or not).

    Returns
    -------
    numpy.ndarray
        int, one position per pyHarm coefficient, into lcpfric's ``[c0, a1, b1, ..., aH,
        bH]`` with H = max(nh): ``x_pyharm = x_lcpfric[index]``.

    Raises
    ------
    InputError
        ``nh`` holds a negative or repeated harmonic, or no harmonic >= 1.
    """
    if isinstance(nh, (int, np.integer)) and not isinstance(nh, bool):
        harm = list(range(int(nh) + 1))
    else:
        harm = [int(h) for h in nh]
    if len(set(harm)) != len(harm) or min(harm, default=-1) < 0 or max(harm, default=0) < 1:
        raise InputError("nh", f"must be H >= 1 or distinct harmonics >= 0 with one >= 1: {nh!r}")
    index = []
    for h in sorted(harm):
        index += [0] if h == 0 else [2 * h - 1, 2 * h]
    return np.array(index)


@functools.lru_cache(maxsize=None)
def pyharm_element_class():
    """The pyHarm element class computed by lcpfric's AFT (built once, on first use).

    A ``pyHarm`` ``NodeToNodeElement`` with ``factory_keyword = "LcpfricJenkins"``. Its input
    keys are those of pyHarm's ``"Jenkins"``: ``connect``, ``dirs`` (one or two tangential
    directions), ``mu``, ``N0`` (the constant normal load), ``k`` (kt), and optionally
    ``slider`` (the slider at the start of each evaluation, default 0, as pyHarm's element
    starts) and :func:`~lcpfric.harmonic.jenkins_aft`'s ``max_periods`` (default 2000, for
    d = 2), ``tol`` and ``on_nonconvergence``. Its residual is the element's force coefficients
    (:func:`~lcpfric.harmonic.jenkins_aft`, the steady cycle on pyHarm's ``nti`` samples),
    its Jacobian their exact derivative; the derivative in ω is zero (rate independent). The
    last AFT is kept as ``last_aft`` (states, W, the cycle).

    Returns
    -------
    type
        The class (a subclass of ``pyHarm.Elements.ABCElement``).

    Raises
    ------
    MissingDependency
        pyHarm is not installed.
    """
    _import_pyharm()
    from pyHarm.Elements.NodeToNodeElements.NodeToNodeElement import NodeToNodeElement

    class LcpfricJenkins(NodeToNodeElement):
        """A Jenkins element (kt in series with a Coulomb slider at μ N0) computed by lcpfric:
        the force coefficients of its steady cycle and their exact Jacobian."""

        factory_keyword: str = FACTORY_KEYWORD

        def __post_init__(self):
            self.mu = float(self.data["mu"])
            self.N0 = float(self.data["N0"])
            self.k = float(self.data["k"])
            self.slider = self.data.get("slider", 0.0)
            self.options = {
                # d = 2: a barely slipping element can take some 200 periods to repeat to tol
                "max_periods": int(self.data.get("max_periods", 2000)),
                "tol": float(self.data.get("tol", 1e-12)),
                "on_nonconvergence": self.data.get("on_nonconvergence", "raise"),
            }
            self.index = pyharm_harmonic_index(self.nh)
            self.harmonics = int(self.index.max() + 1) // 2
            check_samples(self.harmonics, self.nti, "nti")
            self.lc = 1.0
            self.last_aft = None
            self._cache = (None, None, None)

        def __flag_update__(self):
            self.flag_nonlinear = True
            self.flag_AFT = True

        def adim(self, lc, wc):
            """Displacements in units of ``lc`` (forces unchanged), as pyHarm's Jenkins."""
            self.lc = float(lc)
            self.flag_adim = True

        def generateIndices(self, expl_dofs):
            """pyHarm's indices, then the maps from the element's dofs to its directions."""
            super().generateIndices(expl_dofs)
            # G[d]: the element's dofs -> the relative displacement's coefficients, direction d
            self.G = np.einsum("dbc,cx->dbx", self.Pdir, self.Pslave - self.Pmaster)
            if self.G.shape[0] not in (1, 2):
                raise InputError("dirs", f"one or two directions, got {self.G.shape[0]}")

        def _evaluate(self, xg):
            x = np.asarray(xg, dtype=float)[self.indices]
            key = (x.tobytes(), self.lc)
            if self._cache[0] == key:
                return self._cache[1], self._cache[2]
            d, K = self.G.shape[0], 2 * self.harmonics + 1
            U = np.zeros((1, d, K))
            U[0][:, self.index] = self.lc * (self.G @ x)
            r = jenkins_aft(
                U, self.nti, self.k, self.mu, normal_load=self.N0, slider=self.slider,
                **self.options,
            )  # fmt: skip
            F = r.tangential_force[0][:, self.index]
            J = r.jacobian[0].reshape(d, K, d, K)[:, self.index][:, :, :, self.index]
            R = np.einsum("dbx,db->x", self.G, F)
            dR = self.lc * np.einsum("dbx,dbec,ecy->xy", self.G, J, self.G)
            self.last_aft = r
            self._cache = (key, R, dR)
            return R, dR

        def evalResidual(self, xg, om):
            """The element's force coefficients on its dofs (pyHarm's ordering)."""
            self.R = self._evaluate(xg)[0].copy()
            return self.R

        def evalJacobian(self, xg, om):
            """Their Jacobian in the element's dofs, and the (zero) derivative in ω."""
            self.J = self._evaluate(xg)[1].copy()
            self.dJdom = np.zeros(len(self.indices))
            return self.J, self.dJdom

    return LcpfricJenkins


def register_pyharm_element():
    """Plug lcpfric's element into pyHarm's element factory (``pyHarm_plugin``), once.

    After it, a pyHarm input builds it by ``"type": "LcpfricJenkins"``. Equivalent to passing
    ``"plugin": [pyharm_element_class()]`` to ``pyHarm.Maestro``.

    Returns
    -------
    type
        The registered class.

    Raises
    ------
    MissingDependency
        pyHarm is not installed.
    """
    cls = pyharm_element_class()
    from pyHarm.BaseUtilFuncs import pyHarm_plugin
    from pyHarm.Elements.FactoryElements import ElementDictionary

    if ElementDictionary.get(cls.factory_keyword) is not cls:
        pyHarm_plugin(cls)
    return cls


def pyharm_extension() -> list:
    """The classes a ``pyharm.extensions`` entry point returns: lcpfric's element.

    Declared as ``lcpfric = "lcpfric.harmonic.pyharm:pyharm_extension"`` in the group
    ``pyharm.extensions``, pyHarm lists it (``pyHarm.extension.get_available()``) and plugs it
    in at import once enabled (``pyHarm.extension.activate("lcpfric")``), or on demand
    (``pyHarm.extension.load("lcpfric")``).

    Returns
    -------
    list of type
        ``[pyharm_element_class()]``.
    """
    return [pyharm_element_class()]


def oscillator_input(
    mass, damping, stiffness, force, omega, *, kt, mu, normal_load,
    element: str = FACTORY_KEYWORD, harmonics=5, samples: int = 128, step: float = 0.01,
    max_step: float = 0.05, min_step: float = 1e-6, solver: dict | None = None,
) -> dict:  # fmt: skip
    """pyHarm's input for one mass on a spring and a damper with a Jenkins element to ground,
    forced by ``force cos ωt``, its frequency response over ``omega`` (analysis ``"frf"``).

    Parameters
    ----------
    mass, damping, stiffness, force : float
        m, c, k and the forcing amplitude F.
    omega : tuple of float
        ``(low, high)``: the continuation runs upwards from ``low``.
    kt, mu, normal_load : float
        The Jenkins element: ``k``, ``mu`` and ``N0`` of pyHarm's input.
    element : str, optional
        ``"LcpfricJenkins"`` (lcpfric's, registered first) or ``"Jenkins"`` (pyHarm's own).
    harmonics : int or list of int, optional
        pyHarm's ``nh`` (default 5).
    samples : int, optional
        pyHarm's ``nti``, the AFT's samples per period (default 128).
    step, max_step, min_step : float, optional
        pyHarm's ``ds0``, ``ds_max`` and ``ds_min``.
    solver : dict, optional
        pyHarm's ``solver_options`` (default: its ``scipyroot``).

    Returns
    -------
    dict
        The input of ``pyHarm.Maestro``.
    """
    if element == FACTORY_KEYWORD:
        register_pyharm_element()
    frf = {
        "study": "frf", "puls_inf": float(omega[0]), "puls_sup": float(omega[1]),
        "ds0": step, "ds_min": min_step, "ds_max": max_step, "sign_ds": 1,
        "verbose": False, "stepsizer": "acceptance", "predictor": "tangent",
        "corrector": "arc_length", "stopper": "bounds",
    }  # fmt: skip
    if solver is not None:
        frf["solver_options"] = solver
    matrix = {key: np.array([[float(v)]]) for key, v in
              (("M", mass), ("C", damping), ("K", stiffness), ("G", 0.0))}  # fmt: skip
    return {
        "analysis": {"frf": frf},
        "system": {"type": "Base", "nh": harmonics, "nti": int(samples)},
        "substructures": {"mass": {"matrix": matrix, "ndofs": 1}},
        "connectors": {
            "forcing": {"type": "CosinusForcing", "connect": {"mass": [0]}, "dirs": [0],
                        "amp": float(force)},
            "jenkins": {"type": element, "connect": {"mass": [0]}, "dirs": [0],
                        "mu": float(mu), "N0": float(normal_load), "k": float(kt)},
        },
    }  # fmt: skip


def pyharm_frequency_response(data: dict, analysis: str = "frf") -> dict:
    """Run a pyHarm input (``Maestro(data).operate()``) quietly and return its accepted points.

    Parameters
    ----------
    data : dict
        The input of ``pyHarm.Maestro`` (:func:`oscillator_input`, for one).
    analysis : str, optional
        The analysis whose points are returned (default ``"frf"``).

    Returns
    -------
    dict
        ``omega`` (m,), ``x`` (m, ndofs): the accepted points' coefficients in pyHarm's
        ordering, ``dofs``: pyHarm's table of them (a pandas DataFrame), ``seconds``: the
        wall time of ``operate``, ``rejected``: the points pyHarm did not accept, ``system``:
        its system (its elements in ``system.LE``).

    Raises
    ------
    MissingDependency
        pyHarm is not installed.
    """
    _import_pyharm()
    from pyHarm.Maestro import Maestro

    previous = logging.root.manager.disable
    logging.disable(logging.INFO)  # pyHarm logs each point at INFO on its own handlers
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # numba's NumbaPerformanceWarning on pyHarm's arrays
            maestro = Maestro(data)
            t = time.perf_counter()
            maestro.operate()
            seconds = time.perf_counter() - t
    finally:
        logging.disable(previous)
    sols = maestro.nls[analysis].SolList
    ok = [s for s in sols if s.flag_accepted]
    X = np.array([s.x for s in ok])
    return {
        "omega": X[:, -1],
        "x": X[:, :-1],
        "dofs": maestro.system.expl_dofs,
        "seconds": seconds,
        "rejected": len(sols) - len(ok),
        "system": maestro.system,
    }
