"""Preconditioned conjugate gradients, projected onto the null space of a constraint where asked:
the linear solves of the half-space's Newton steps (:mod:`lcpfric.steppers.newton_step`) and of
its system bridge (:meth:`lcpfric.model.continuum.halfspace.HalfSpace.springs`)."""

from __future__ import annotations

import numpy as np

from ..errors import SolverError

__all__ = ["cg"]


def cg(M, g, x, project, pre, tol, stats, step=None, max_iter=None, res=None):
    """Preconditioned conjugate gradients for ``M x = g`` from x (on the null space of the
    constraint when ``project`` is given: the preconditioner is then ``Π pre Π``), until the
    (projected) residual is below ``tol`` everywhere. Returns x and the unprojected residual
    ``g - M x`` (whose part off the null space gives the constraint's multiplier). ``step(α)``
    is told each multiple of the last product of M added to x (1 for the start), so the
    caller can sum the products into ``C x`` without one more. ``res``: the residual ``g - M
    x`` at the start, if the caller has it (g is then not needed)."""
    if res is not None:
        pass
    elif np.any(x):
        res = g - M(x)
        if step is not None:
            step(1.0)
    else:
        res = g.copy()
    r = res if project is None else project(res)
    if float(np.abs(r).max()) <= tol:
        return x, res
    z = pre(r) if project is None else project(pre(r))
    p = z.copy()
    rz = float(r @ z)
    limit = max_iter or max(200, 4 * r.size)
    for _ in range(limit):
        stats["cg"] += 1
        Mp = M(p)
        alpha = rz / float(p @ Mp)
        if step is not None:
            step(alpha)
        x = x + alpha * p
        res = res - alpha * Mp
        r = res if project is None else project(res)
        if float(np.abs(r).max()) <= tol:
            return x, res
        z = pre(r) if project is None else project(pre(r))
        rz_new = float(r @ z)
        p = z + (rz_new / rz) * p
        rz = rz_new
    raise SolverError(
        f"half-space: conjugate gradients did not reach {tol:.3g} in {limit} iterations",
        backend="halfspace",
        status="max_iter",
    )
