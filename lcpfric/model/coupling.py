"""The normal-tangential coupling block of a discrete system: ``N = P(t) + B v`` beside
``F = Q(t) + K v`` (d = 1; ``../coupled`` notes of the project, Klarbring 1990; Klarbring,
Ciavarella and Barber 2007), and its well-posedness.

Well-posedness (Klarbring's condition, generalized)
---------------------------------------------------
At an event the slip rates of the nodes on their limits solve a linear complementarity problem
whose matrix is a principal submatrix of ``K + diag(s f) B``, s the slip signs (a node slipping
forward has ``F_i = -f_i N_i``, so ``dF_i = -f_i dN_i = -f_i (dP + B dv)_i`` and the rate
equation's matrix is ``K + f_i B`` on its row; backward, ``K - f_i B``). The evolution is unique
for every load exactly when, for every sign pattern ``s ∈ {-1, +1}^n``, ``K + diag(s f) B`` is a
P-matrix (every principal minor positive). For one node: ``k11 > f |k21|``.

:func:`check_coupling` decides it: first by a sufficient condition (``λmin(K) > ||diag(f) B||₂``:
then the symmetric part of every ``K + diag(s f) B`` is positive definite), else exactly, by
every principal minor of every sign pattern (``3^n`` determinants: the minor on a set S depends
on the signs of S only), up to :data:`EXACT_NODES` nodes; beyond, a system that fails the
sufficient condition is refused as not shown well posed.
"""

from __future__ import annotations

import itertools

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = ["check_coupling", "coupled_start", "static_start", "EXACT_NODES", "COUPLED_METHODS"]

#: the methods that solve a coupled system's steady state
COUPLED_METHODS = ("exact", "explicit", "active-set", "clarabel", "osqp", "cvxpy", "qpsolvers")

#: largest system whose well-posedness is decided minor by minor (3^n determinants)
EXACT_NODES = 12


def _signs(s) -> str:
    return "(" + ", ".join("+" if x > 0 else "-" for x in s) + ")"


def check_coupling(B, K: np.ndarray, friction: np.ndarray) -> np.ndarray:
    """B as an n x n float array, once the coupled system is shown well posed.

    Parameters
    ----------
    B : (n, n) array_like
        The coupling block, ``N = P(t) + B v``; any finite n x n matrix.
    K : (n, n) ndarray
        The tangential stiffness (symmetric positive definite, checked before).
    friction : (n,) ndarray
        The friction coefficients.

    Returns
    -------
    ndarray
        B, float, n x n.

    Raises
    ------
    InputError
        On ``coupling``: B not finite or not n x n; or the system is not well posed, naming
        the condition, the sign pattern and the set of nodes whose minor is not positive and
        its value (or, beyond :data:`EXACT_NODES` nodes, that the sufficient condition fails).
    """
    n = friction.size
    B = _checks.finite_array("coupling", B)
    if B.shape != (n, n):
        raise InputError("coupling", f"must be an {n} x {n} matrix (N = P + B v), got {B.shape}")
    K = np.asarray(K, dtype=float)
    fB = friction[:, None] * B
    if np.linalg.eigvalsh(K)[0] > np.linalg.norm(fB, 2):
        return B
    if n > EXACT_NODES:
        raise InputError(
            "coupling",
            f"the coupled system is not shown well posed: λmin(K) = "
            f"{np.linalg.eigvalsh(K)[0]:.6g} <= ||diag(f) B||₂ = {np.linalg.norm(fB, 2):.6g}, "
            f"and with {n} > {EXACT_NODES} nodes every principal minor of K + diag(s f) B is "
            f"not checked one by one (Klarbring's condition: each must be a P-matrix)",
        )
    worst = (np.inf, None, None)
    for k in range(1, n + 1):
        for S in itertools.combinations(range(n), k):
            idx = np.array(S)
            KS, fBS = K[np.ix_(idx, idx)], fB[np.ix_(idx, idx)]
            signs = np.array(list(itertools.product((1.0, -1.0), repeat=k)))
            mats = KS[None] + signs[:, :, None] * fBS[None]
            scale = np.prod(np.sqrt(np.diag(KS)) * 1.0) ** 2
            det = np.linalg.det(mats) / scale
            j = int(np.argmin(det))
            if det[j] < worst[0]:
                worst = (float(det[j]), S, signs[j])
    if worst[0] > 1e-12:
        return B
    value, S, s = worst
    full = np.ones(n)
    full[list(S)] = s
    raise InputError(
        "coupling",
        f"the coupled system is not well posed (Klarbring's condition: K + diag(s f) B must "
        f"be a P-matrix for every slip sign pattern s): with s = {_signs(full)} (the signs on "
        f"node(s) {list(S)} matter) the principal minor on node(s) {list(S)} is {value:.6g} "
        f"(scaled by the product of K's diagonal there) <= 0; lower the friction or the "
        f"coupling",
    )


def static_start(K, B, f, Q, P) -> np.ndarray:
    """The default start of a coupled system at t = 0 (loads ``Q``, ``P`` there): u = 0 where
    it is admissible, else the nodes that violate their limits slip to them, the others stay at
    0 (a static pattern search; every method starts from it, as the steady state depends on the
    start). :class:`InputError` (``u0``) when no pattern is found in n + 1 rounds."""
    n = f.size
    slip = np.zeros(n)  # +1 forward (F = -f N), -1 backward, 0 stuck at u = 0
    for _ in range(n + 1):
        u = np.zeros(n)
        S = slip != 0
        if S.any():
            A = K[S] + (slip[S] * f[S])[:, None] * B[S]
            u[S] = np.linalg.solve(A[:, S], -(Q[S] + slip[S] * f[S] * P[S]))
        F, fN = Q + K @ u, f * (P + B @ u)
        over = (np.abs(F) > fN * (1 + 1e-12)) & ~S
        if not over.any():
            return u
        slip[over] = np.where(F[over] < 0, 1.0, -1.0)
    raise InputError("u0", "no admissible default start found at t = 0: give u0")


def coupled_start(system, method: str, u0):
    """For the driver: refuse a coupled system for a method that does not solve it (naming the
    ones that do), and return the start (``u0``, or :func:`static_start`)."""
    if method not in COUPLED_METHODS:
        raise InputError(
            "coupling",
            f"'{method}' does not solve coupled systems (N = P + B v): use "
            + " or ".join(f"'{m}'" for m in COUPLED_METHODS),
        )
    if u0 is not None or not hasattr(system, "dense_stiffness"):
        return u0  # (a single node's steady state does not depend on its start)
    K = system.dense_stiffness()
    Q = np.asarray(system.tangential(0.0), dtype=float)
    P = np.asarray(system.normal.loads_at(0.0), dtype=float)
    return static_start(K, system.coupling, system.friction, Q, P)
