"""Problem (P) in a given metric, by any convex backend: :class:`MetricIncrements`.

The quasi-static steppers build (P) from a scene's plan (``P = C_AA``). A time stepper with
inertia (:mod:`lcpfric.steppers.newmark_system`) has its own metric, the contacts' compliance
in the effective stiffness of its scheme, and its own contact sets; it hands (P) over as
``(key, P, q, b)`` and gets the forces back, solved by the backend it names, refined and
checked as every increment is (:func:`~lcpfric.backends.refine.accept`). A problem is built
once per contact set and metric and re-solved with new data; where the solver's status is not
solved, the problem is built again and solved cold once before the increment fails (a solver
object re-solved many times can stall: cvxpy with Clarabel was seen to return
``optimal_inaccurate`` after 774 warm re-solves of a one-variable problem that it solves cold).
One contact needs no solver: d = 1, its projection is a clip; d = 2, a scalar equation
(:func:`disc_projection`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError, SolverError
from .problem import IncrementProblem, set_dofs
from .refine import accept

__all__ = ["MetricIncrements", "CLOSED_FORM", "disc_projection"]

#: the name of the closed-form projection (one d = 1 contact)
CLOSED_FORM = "clip"


def disc_projection(P, q, b):
    """``min ½ Fᵀ P F + qᵀ F`` over ``||F|| <= b`` for one d = 2 contact (P 2 x 2, symmetric
    positive definite): the trial ``-P⁻¹ q`` if inside, else ``F(λ) = -(P + λ I)⁻¹ q`` with
    ``||F(λ)|| = b``, λ > 0 by Brent's method (``||F(λ)||`` decreases with λ). Returns
    ``(F, stick)``."""
    from scipy.optimize import brentq

    trial = -np.linalg.solve(P, q)
    if np.hypot(*trial) <= b:
        return trial, np.array([True, True])
    eye = np.eye(2)

    def excess(lam):
        return float(np.hypot(*np.linalg.solve(P + lam * eye, q))) - b

    hi = float(np.hypot(*q)) / b  # ||F(hi)|| <= ||q|| / hi = b
    lam = brentq(excess, 0.0, hi, xtol=1e-15 * hi, rtol=4 * np.finfo(float).eps)
    F = -np.linalg.solve(P + lam * eye, q)
    return F * (b / np.hypot(*F)), np.array([False, False])


class MetricIncrements:
    """Solve ``min ½ Fᵀ P F + qᵀ F`` over the friction cones, P given per contact set.

    Parameters
    ----------
    backend : str or None
        A convex backend's registry name (``"clarabel"``, ``"osqp"``, ``"qpsolvers:proxqp"``,
        ``"cvxpy"``, ...). None: the closed form for one d = 1 contact, else ``"clarabel"``.
    dims : int
        d of the contacts.
    options : dict, optional
        The backend's options (its tolerances and solver settings).

    Raises
    ------
    InputError
        ``backend`` is not a convex backend, or cannot express d = 2.
    SolverNotFound
        The backend's optional dependency is missing.
    """

    def __init__(self, backend: str | None, dims: int, options: dict | None = None):
        from ..methods import get_stepper

        self.dims = dims
        self.name = backend
        self.stepper = None
        self.problems: dict[Any, IncrementProblem] = {}
        self.stats = {"solves": 0, "closed_form": 0, "refined": 0, "unrefined": 0, "rebuilt": 0}
        if backend in (None, CLOSED_FORM):
            return
        stepper = get_stepper(backend, **(options or {}))
        if not hasattr(stepper, "build") or not hasattr(stepper, "solve"):
            raise InputError(
                "backend",
                f"{backend!r} is not a convex backend (give 'clarabel', 'osqp', "
                f"'qpsolvers:<solver>' or 'cvxpy')",
            )
        if dims == 2 and not stepper.can_soc:
            raise InputError("backend", f"{backend!r} cannot express the d = 2 cone; give "
                             f"'clarabel' or 'cvxpy'")  # fmt: skip
        self.stepper = stepper

    @property
    def label(self) -> str:
        """The backend's label (``"clip"`` for the closed form)."""
        return self.stepper.label if self.stepper is not None else CLOSED_FORM

    def solve(self, key, P: np.ndarray, q: np.ndarray, b: np.ndarray, where: str):
        """The forces F_A and the mask of the variables that stick (None when unknown).

        Parameters
        ----------
        key : hashable
            Identifies P (the caller's contact set and metric): its problem is built once.
        P : (k, k) ndarray
            The metric, symmetric positive definite (the same for every call with ``key``, up to
        a factor: the problem is built once, scaled by its diagonal's largest entry).
        q : (k,) ndarray
            The linear term.
        b : (a,) ndarray
            The friction limits, one per contact of the set.
        where : str
            What the increment is (for the error message).

        Raises
        ------
        SolverError
            The solver's status is not solved, or its answer fails the residual checks
            (the status carries the solver's own).
        """
        self.stats["solves"] += 1
        if self.stepper is None:
            if q.size == 1 and self.dims == 1:  # one contact: the projection is a clip
                self.stats["closed_form"] += 1
                trial = -q[0] / P[0, 0]
                stick = abs(trial) <= b[0]
                return np.array([trial if stick else np.copysign(b[0], trial)]), np.array([stick])
            if q.size == 2 and self.dims == 2:  # one disc: a scalar equation
                self.stats["closed_form"] += 1
                return disc_projection(P, q, b[0])
            self._default()
        st = self.stepper
        # in units of the limits and of P's diagonal: the solvers see entries of order one
        sF = max(float(np.max(b, initial=0.0)), 1e-300)
        sC = float(np.max(np.diag(P)))
        bs = b / sF
        for attempt in range(2):  # a solver object that fails is rebuilt once, cold
            prob = self.problems.get(key)
            if prob is None:
                nodes = np.arange(b.size)
                prob = IncrementProblem(nodes, set_dofs(nodes, self.dims), self.dims, P / sC,
                                        full=True)  # fmt: skip
                prob.handle = st.guarded(st.build, prob, st.settings_for(self.dims))
                self.problems[key] = prob
            prob.q[:] = q / (sC * sF)
            x, status, ok = st.guarded(st.solve, prob, prob.q, st.bounds(prob, bs))
            if ok:
                break
            del self.problems[key]
            self.stats["rebuilt"] += 1
        F, stick, res, kind = (None, None, {}, "failed") if not ok else accept(
            prob, np.array(x, dtype=float), prob.q, bs, refine=st.refine,
            active_tol=st.active_tol, check_tol=st.check_tol, fscale=1.0, cscale=1.0)  # fmt: skip
        if F is None:
            detail = "" if not res else " (residuals " + ", ".join(
                f"{k} {v:.2g}" for k, v in res.items()) + ")"  # fmt: skip
            raise SolverError(
                f"{st.label}: the increment {where} was not solved: status {status}{detail}",
                backend=st.label,
                status=str(status) if ok is False or not res else "inaccurate",
            )
        F = F * sF
        self.stats[kind] += 1
        return F, stick

    def _default(self):
        from ..methods import get_stepper

        self.stepper = get_stepper("clarabel")
        self.name = "clarabel"
