"""lcpfric's tight default settings per underlying solver, shared by the direct backends,
qpsolvers and cvxpy. Every entry overrides the solver's default; the comment says why.
A user's settings (``steady_state(..., **settings)``) override these in turn.
"""

from __future__ import annotations

from typing import Any

__all__ = ["TIGHT_SETTINGS", "CONIC_METHODS", "settings_for"]

#: The methods that can express the d = 2 friction cone, in words: named by the error of a QP
#: backend given a d = 2 system (:meth:`lcpfric.backends.ConvexStepper.check_system`).
CONIC_METHODS = (
    "'clarabel', 'cvxpy:CLARABEL' (or 'cvxpy:ECOS', 'cvxpy:SCS'), or "
    "'projection' for a diagonal K isotropic within each node"
)

#: lcpfric's tight default settings per underlying solver (solver key -> settings), shared by
#: the direct backends, qpsolvers and cvxpy; a key ending in ``_soc`` is added for d = 2
#: problems. Every entry overrides the solver's default (the source comment says why), and a
#: user's settings override these in turn (:func:`settings_for`).
TIGHT_SETTINGS: dict[str, dict[str, Any]] = {
    "clarabel": {
        # at the default 1e-8 a one-variable projection is off by ~2e-5; 1e-12 gives ~1e-8
        # (1e-14 is below what the IPM reaches reliably)
        "tol_gap_abs": 1e-12,
        "tol_gap_rel": 1e-12,
        "tol_feas": 1e-12,
        "verbose": False,  # lcpfric reports through its results, not the solver's log
    },
    "clarabel_soc": {
        # with second-order cones (d = 2) Clarabel stalls at AlmostSolved below ~1e-10; the
        # active-set Newton refinement takes its answer to machine precision from here
        "tol_gap_abs": 1e-9,
        "tol_gap_rel": 1e-9,
        "tol_feas": 1e-9,
    },
    "osqp": {
        # defaults (1e-3) are off by ~2e-3 on a one-variable projection
        "eps_abs": 1e-10,
        "eps_rel": 1e-10,
        # more room for the tight tolerances above (default 4000)
        "max_iter": 20000,
        # the default (0) sets the rho-update interval from the measured setup time, so
        # iteration counts, and unrefined answers, vary from run to run; a fixed interval keeps
        # runs reproducible at the same speed
        "adaptive_rho_interval": 25,
        # lcpfric's own active-set refinement does this job; OSQP's polish prints to stdout
        # even with verbose=False and can report success on a poor answer
        "polishing": False,
        "verbose": False,  # lcpfric reports through its results, not the solver's log
    },
    "proxqp": {
        # defaults (1e-5 abs) are far too loose; 1e-10 still leaves ~1e-6 on some steps
        "eps_abs": 1e-12,
        "eps_rel": 0.0,
        "check_duality_gap": True,  # off by default: the primal-dual residuals alone stop early
    },
    "scs": {
        # defaults (1e-4) are far too loose; SCS is first order, hence the iteration room
        "eps_abs": 1e-10,
        "eps_rel": 1e-10,
        "max_iters": 200000,
        "verbose": False,  # lcpfric reports through its results, not the solver's log
    },
    "ecos": {"abstol": 1e-10, "reltol": 1e-10, "feastol": 1e-10},  # defaults are 1e-8/1e-7
    "highs": {
        # defaults are 1e-7
        "primal_feasibility_tolerance": 1e-10,
        "dual_feasibility_tolerance": 1e-10,
        # the default adds 1e-7 to the Hessian, which moves every answer by ~1e-7; P = C_AA is
        # positive definite and needs none
        "qp_regularization_value": 0.0,
    },
}


def settings_for(key: str, dims: int, user: dict[str, Any]) -> dict[str, Any]:
    """The settings of solver ``key`` for problems with d = ``dims``.

    Parameters
    ----------
    key : str
        The solver's entry in :data:`TIGHT_SETTINGS` (none: no tight defaults).
    dims : int
        d of the problems, 1 or 2 (2 adds the ``_soc`` variant of the tight defaults).
    user : dict
        The user's settings, which override the tight defaults.

    Returns
    -------
    dict
        A new dict: the tight defaults (with their ``_soc`` variant for d = 2), then the
        user's.
    """
    out = dict(TIGHT_SETTINGS.get(key, {}))
    if dims == 2:
        out.update(TIGHT_SETTINGS.get(key + "_soc", {}))
    out.update(user)
    return out
