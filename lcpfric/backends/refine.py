"""Active-set refinement
---------------------
Interior-point answers sit a little inside the cone (Clarabel at its default tolerances is off by
about 2e-5 on a one-variable projection; OSQP at its defaults by about 2e-3). With ``refine=True``
the answer is only used to *identify* the active set: nodes with ``|F_i| >= f_i N_i - δ`` are put
on the limit with their sign, the remaining (stick) nodes solve ``P_SS F_S = -(q_S + P_SB F_B)``
exactly, and the identification is corrected (a stick node over its limit goes to the limit, a
limit node whose slip has the wrong sign goes to stick) until the KKT conditions hold: a
primal-dual active-set iteration started from the solver's answer. For d = 2 the limit nodes
sit on their circles, ``F_i = f_i N_i e_i`` with slip ``-λ_i F_i``, and the KKT system is solved
by Newton's method (:func:`refine_disc`); interior-point solvers stall short of tight tolerances
on these cones, and the refinement takes their answer to machine precision. A stick node keeps
its displacement exactly (no rounding drift while the whole system sticks, which the periodic
driver would otherwise see as a change). If the refined point passes the residual check it is
used; otherwise the solver's own answer must pass on its own.
"""

from __future__ import annotations

import numpy as np

from .checks import residuals, worst
from .problem import IncrementProblem

__all__ = ["refine_box", "refine_disc", "accept"]


def refine_box(
    prob: IncrementProblem,
    F: np.ndarray,
    q: np.ndarray,
    b: np.ndarray,
    delta: float,
    fscale: float,
    cscale: float,
    max_iter: int = 8,
) -> tuple[np.ndarray, np.ndarray, dict[str, float]] | None:
    """Active-set refinement of a d = 1 answer (see the module docstring).

    Identify the limit nodes of ``F`` (``|F_i| >= b_i - delta``), solve the stick nodes exactly,
    and correct the identification until the KKT conditions hold.

    Parameters
    ----------
    prob : IncrementProblem
        The problem (P) of the contact set.
    F : (a·d,) ndarray
        The solver's answer, which identifies the active set.
    q : (a·d,) ndarray
        The linear term of (P), ``-(C F_tr)_A``.
    b : (a,) ndarray
        The friction limits f_i N_i of the set's nodes.
    delta : float
        The identification's margin δ (the backends' ``active_tol`` times ``fscale``).
    fscale, cscale : float
        Force and compliance scales (``s_F`` and ``c``) of the residuals, both > 0.
    max_iter : int
        Corrections of the identification tried before giving up.

    Returns
    -------
    tuple or None
        ``(F, stick, res)``: the refined forces, the mask of the variables that stick (their
        slip is zero by construction) and the residuals (as
        :func:`~lcpfric.backends.checks.residuals`); None when no KKT point was reached within
        ``max_iter`` corrections.
    """
    at = np.abs(F) >= b - delta
    sb = np.copysign(b, F)
    for _ in range(max_iter):
        sb *= at
        if prob.diagonal:
            Fr = np.where(at, sb, q / -prob.pdiag)
            g = prob.P @ Fr
            g += q
            stick_slip = float(np.abs(g * ~at).max())
        else:
            Tq, Tb, stick = prob.active_set_operator(at)
            Fr = Tq @ q
            if Tb is not None:
                Fr += Tb @ sb
            g = prob.P @ Fr
            g += q
            stick_slip = float(np.abs(g * stick).max())
        # KKT of (P): stick nodes within their limits and not slipping (g_S = 0 up to
        # rounding), limit nodes slipping against their force (F = +b needs g <= 0)
        over = float((np.abs(Fr) - b).max())
        wrong = float((sb * g).max())
        if over <= 1e-14 * fscale and wrong <= 0.0:
            return (
                Fr,
                ~at,
                {
                    "cone": max(over, 0.0) / fscale,
                    "complementarity": 0.0,
                    "stationarity": stick_slip / (cscale * fscale),
                },
            )
        # correct: a stick node over its limit goes to the limit, a limit node slipping the
        # wrong way goes to stick
        over_nodes = ~at & (np.abs(Fr) > b)
        wrong_nodes = at & (sb * g > 0.0)
        if not (over_nodes.any() or wrong_nodes.any()):
            return None  # violations at rounding level only, yet not a KKT point: give up
        sb = np.where(over_nodes, np.copysign(b, Fr), np.copysign(b, sb))
        at = (at & ~wrong_nodes) | over_nodes
    return None


def refine_disc(
    prob: IncrementProblem,
    F: np.ndarray,
    q: np.ndarray,
    b: np.ndarray,
    delta: float,
    fscale: float,
    cscale: float,
    max_corrections: int = 4,
    max_newton: int = 30,
) -> tuple[np.ndarray, np.ndarray, dict[str, float]] | None:
    """Active-set refinement of a d = 2 answer.

    The nodes with ``||F_i|| >= b_i - delta`` are put on their circle, ``F_i = b_i e_i`` with
    slip ``Δu_i = -λ_i F_i`` (λ_i >= 0), the others stick (``Δu_i = 0``); the resulting KKT
    system of (P)::

        P F + q + Λ F = 0,   ½ (||F_i||² - b_i²) = 0 on the limit nodes   (Λ = diag λ_i there),

    is solved by Newton's method from the solver's answer (its Jacobian is the symmetric KKT
    matrix ``[[P + Λ, E], [Eᵀ, 0]]``, E holding the limit nodes' forces), and the identification
    is corrected (λ_i < 0 -> stick, ``||F_i|| > b_i`` -> limit) until the conditions hold.

    Parameters
    ----------
    prob : IncrementProblem
        The problem (P) of the contact set.
    F : (2a,) ndarray
        The solver's answer, which identifies the active set.
    q : (2a,) ndarray
        The linear term of (P), ``-(C F_tr)_A``.
    b : (a,) ndarray
        The friction limits f_i N_i of the set's nodes.
    delta : float
        The identification's margin δ (the backends' ``active_tol`` times ``fscale``).
    fscale, cscale : float
        Force and compliance scales (``s_F`` and ``c``) of the residuals, both > 0.
    max_corrections : int
        Corrections of the identification tried before giving up.
    max_newton : int
        Newton iterations per identification.

    Returns
    -------
    tuple or None
        ``(F, stick, res)`` as :func:`refine_box` (``stick`` per variable, both of a node's
        entries alike); None when no KKT point was reached within ``max_corrections``
        corrections, or the KKT matrix was singular.
    """
    import scipy.sparse as sp

    a = b.size
    P = prob.P.toarray() if sp.issparse(prob.P) else prob.P
    F2 = np.array(F, dtype=float).reshape(a, 2)
    norm = np.hypot(F2[:, 0], F2[:, 1])
    at = norm >= b - delta
    for _ in range(max_corrections):
        B = np.flatnonzero(at)
        nb = B.size
        x = F2.copy()
        nB = np.hypot(x[B, 0], x[B, 1])
        g = (P @ x.ravel() + q).reshape(a, 2)
        # on the circle, along the force (or against the slip where the force vanishes)
        dirn = np.where(nB[:, None] > 0, x[B], -g[B])
        dn = np.hypot(dirn[:, 0], dirn[:, 1])
        x[B] = b[B, None] * dirn / np.where(dn > 0, dn, 1.0)[:, None]
        g = (P @ x.ravel() + q).reshape(a, 2)
        lam = np.maximum(-np.einsum("ij,ij->i", g[B], x[B]) / np.maximum(b[B] ** 2, 1e-300), 0.0)
        rows = (2 * B[:, None] + np.arange(2)).ravel()
        for _it in range(max_newton):
            g = P @ x.ravel() + q
            r1 = g.copy()
            r1[rows] += np.repeat(lam, 2) * x[B].ravel()
            r2 = 0.5 * (np.einsum("ij,ij->i", x[B], x[B]) - b[B] ** 2)
            J = np.zeros((2 * a + nb, 2 * a + nb))
            J[: 2 * a, : 2 * a] = P
            J[rows, rows] += np.repeat(lam, 2)
            E = np.zeros((2 * a, nb))
            E[rows, np.repeat(np.arange(nb), 2)] = x[B].ravel()
            J[: 2 * a, 2 * a :] = E
            J[2 * a :, : 2 * a] = E.T
            try:
                step = np.linalg.solve(J, -np.concatenate([r1, r2]))
            except np.linalg.LinAlgError:
                return None
            x = (x.ravel() + step[: 2 * a]).reshape(a, 2)
            lam = lam + step[2 * a :]
            if float(np.abs(step).max()) <= 1e-15 * (fscale + 1.0):
                break
        g = P @ x.ravel() + q
        normx = np.hypot(x[:, 0], x[:, 1])
        negative = np.zeros(a, dtype=bool)
        negative[B] = lam < 0.0
        over = ~at & (normx > b)
        if not (negative.any() or over.any()):
            Fr = x.ravel()
            return Fr, np.repeat(~at, 2), residuals(Fr, g, b, 2, fscale, cscale)
        at = (at & ~negative) | over
        F2 = x
    return None


def accept(
    prob: IncrementProblem,
    F: np.ndarray,
    q: np.ndarray,
    b: np.ndarray,
    *,
    refine: bool,
    active_tol: float,
    check_tol: float,
    fscale: float,
    cscale: float,
) -> tuple[np.ndarray | None, np.ndarray | None, dict[str, float], str]:
    """Accept a solver's answer ``F`` of ``prob`` (linear term ``q``, limits ``b``).

    With ``refine`` the answer identifies the active set and the refined point
    (:mod:`~lcpfric.backends.refine`) is used if it passes the residual check; otherwise the
    solver's own answer must pass on its own.

    Parameters
    ----------
    prob : IncrementProblem
        The problem (P) of the contact set (d = 1 is refined on the box, d = 2 on the discs).
    F : (a·d,) ndarray
        The solver's answer.
    q : (a·d,) ndarray
        The linear term of (P), ``-(C F_tr)_A``.
    b : (a,) ndarray
        The friction limits f_i N_i of the set's nodes.
    refine : bool
        Try the active-set refinement first.
    active_tol : float
        δ / s_F of the identification (:func:`refine_box`, :func:`refine_disc`).
    check_tol : float
        Largest residual accepted (relative, as in :mod:`~lcpfric.backends.checks`).
    fscale, cscale : float
        Force and compliance scales (``s_F`` and ``c``), both > 0.

    Returns
    -------
    F : ndarray or None
        The accepted forces (None when nothing passed).
    stick : ndarray or None
        The mask of the variables that stick exactly (None for an unrefined answer).
    res : dict
        The residuals of the accepted answer (of the solver's own answer when nothing passed).
    kind : str
        ``"refined"``, ``"unrefined"`` or ``"failed"``.
    """
    if refine:
        refine_fn = refine_box if prob.dims == 1 else refine_disc
        refined = refine_fn(prob, F, q, b, active_tol * fscale, fscale, cscale)
        if refined is not None and worst(refined[2]) <= check_tol:
            return refined[0], refined[1], refined[2], "refined"
    g = prob.P @ F
    g += q
    res = residuals(F, g, b, prob.dims, fscale, cscale)
    if not worst(res) <= check_tol:  # also catches NaN
        return None, None, res, "failed"
    return F, None, res, "unrefined"
