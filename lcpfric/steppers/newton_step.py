r"""The semismooth Newton steps of the half-space's increments (:mod:`.newton_increment`):
with the pattern of an iterate fixed, one symmetric positive definite linear system on the
sticking components and, for d = 2, the components of the slipping nodes' forces tangent to
their circle (with the diagonal term ``|Δs_i| / b_i``), under the equilibrium as a linear
constraint, solved by conjugate gradients (:func:`lcpfric.linalg.cg.cg`) on FFT products,
preconditioned by the inverse of the padded circulant operator.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import SolverError
from ..linalg.cg import cg

__all__ = [
    "NewtonSteps",
    "nearest_to_sticking",
    "column_sums",
    "every_node_slips",
    "CG_TOL",
    "ETA",
]

#: d = 2: the linear solves of the Newton steps are to this fraction of the residual
ETA = 1e-2
#: the linear solves end with their residual below this fraction of the increment's
#: tolerance where the natural map's residual is checked after the step (d = 2, and d = 1's
#: loose or damped steps; ten times lower for each further step once one that began within ten
#: times the tolerance did not end the increment); d = 1's step with a repeated pattern ends
#: the increment unchecked, so it keeps a margin (``_CG_TOL1``): at 0.9 a cycle tolerance of
#: 1e-12 with increments at 1e-10 (the backends' cross-check) took 46 cycles, their errors
#: keeping the change about 1e-11
CG_TOL, _CG_TOL1 = 0.9, 0.1


class NewtonSteps:
    """The Newton steps of :class:`~lcpfric.steppers.newton_increment.HalfSpaceIncrements` (which
    holds the grid: ``nodes``, ``k_support``, ``c``, ``N``, ``h``, ``pos``, ``cpos``, the
    counted operator ``op``, ``stats``, and ``compliance`` and ``pad``)."""

    def newton_step(self, F, ds, z, zn, b, contact, slip, eq, worst, tolF, eta=None, frac=CG_TOL):
        """One semismooth Newton step (module docstring): ``(ΔF, Δδ, C ΔF)``. For d = 2
        (:meth:`_newton2`) the linear solve is inexact while the residual ``worst`` is large
        (to ``1e-2`` of it: the slip directions are corrected by the next step anyway); for
        d = 1 it is to a tenth of the tolerance (``_CG_TOL1``), which ends the iteration when
        the pattern is right."""
        if self.dims == 2:
            return self._newton2(F, ds, z, zn, b, contact, slip, eq, worst, tolF, eta, frac)
        n, ks, c = self.nodes, self.k_support, self.c
        stick = np.flatnonzero(contact & ~slip)
        L = np.flatnonzero(slip)
        known = np.where(contact[:, None], 0.0, -F)  # off the contact: no force
        known[L, 0] = np.sign(z[L, 0]) * b[L] - F[L, 0]
        space = _Space(stick, self.pos, self.op)
        rhs = -ds[stick, 0]
        if space.size == 0:
            if ks <= 0.0:
                every_node_slips()
            return known, (eq + column_sums(known)) / ks, self.compliance(known)
        cons = -(eq + column_sums(known))
        if ks > 0.0:
            x0 = np.zeros(space.size)
        else:
            x0 = np.full(space.size, float(cons[0]) / space.size)  # B = 1ᵀ: B⁺ cons
        # the known forces and the start in one product (linearity); the residual from it
        h2 = self.h**2
        N = self.N
        if np.any(known) or np.any(x0):
            start = self.pad(known)
            space.add(start, x0)
            first = self.op.padded("tangential", start, 1.0 / h2)
            res = rhs - space.restrict(first)
            total = self.op.view(first)[:N, :N].copy()
        else:
            res = rhs.copy()
            total = np.zeros((N, N, 1))
        # C of the step on the grid's nodes, summed from the products (the padded arrays'
        # corner: the rest is the wrap-around)
        acc = {"last": None}

        def M(x):
            acc["last"] = self.op.padded("tangential", space.embed(x), 1.0 / h2)
            return space.restrict(acc["last"])

        def step(alpha):
            np.add(total, alpha * self.op.view(acc["last"])[:N, :N], out=total)

        def pre(r):
            return space.restrict(self.op.padded("precondition", space.embed(r), h2))

        tol = (_CG_TOL1 if eta is None else frac) * c * tolF
        if eta is not None:
            tol = max(tol, eta * c * worst)
        if ks > 0.0:
            x, _ = cg(
                lambda y: M(y) + y.sum() / ks,
                None,
                x0,
                None,
                pre,
                tol,
                self.stats,
                step,
                res=res + float(cons[0]) / ks,
            )
            dd = (np.array([x.sum()]) - cons) / ks
        else:

            def project(r):
                return r - r.sum() / r.size  # r.mean(), without its overhead

            x, res = cg(M, None, x0, project, pre, tol, self.stats, step, res=res)
            dd = np.array([res.sum() / space.size])
        return space.nodes(x, known), dd, total.reshape(n, 1)

    def _newton2(self, F, ds, z, zn, b, contact, slip, eq, worst, tolF, eta, frac):
        """d = 2: the Newton step of :meth:`newton_step`, each node's force (and slip) one complex
        number x + i y, as in the FFT's padded layout. The unknowns: the sticking nodes'
        forces, and each slipping node's force along the tangent τ = i e of its circle (e its
        slip direction), held as t τ; the operator there adds the diagonal term
        ``c (1 − β)/β`` (β = b/|z|) to the τ-component of C's. The conjugate gradients see
        the unknowns as the floats of those complex numbers: their inner product is the real
        one, and a slipping node's two floats t τ_x, t τ_y carry the length t. The
        equilibrium's constraint B sums the forces: ``B u = Σ u`` (complex), and ``Bᵀ λ`` is λ
        on the sticking nodes and ``τ Re(τ̄ λ)`` on the slipping ones."""
        n, ks, c, N = self.nodes, self.k_support, self.c, self.N
        op = self.op
        kern = self.kernels
        # the unknowns, τ, the diagonal term, the right-hand side and B Bᵀ in one pass (compiled)
        nodes, ns, known, tau, tdiag, idx, rhs, weights, sxx, sxy, syy, ksum = kern.newton2_setup(
            F, z, zn, ds, b, contact, slip, self.cpos, float(c)
        )
        size = nodes.size
        if size == 0:
            if ks <= 0.0:
                every_node_slips()
            kn = _floats(known, n)
            return kn, (eq + column_sums(kn)) / ks, self.compliance(kn)
        tx, ty = tau.real, tau.imag
        wL = weights[ns:]
        cons = -(eq + np.array([ksum.real, ksum.imag]))
        # B Bᵀ: ns I plus the tangents' outer products
        BBt = np.array([[ns + sxx, sxy], [sxy, ns + syy]])

        def bt(lam):
            """Bᵀ λ (λ: the two floats of a force sum) as the unknowns' floats."""
            out = np.empty(size, dtype=complex)
            out[:ns] = complex(lam[0], lam[1])
            out[ns:] = tau * (tx * lam[0] + ty * lam[1])
            return out.view(float)

        def bsum(r):  # B r: the force sums
            t = r.view(complex).sum()
            return np.array([t.real, t.imag])

        if ks > 0.0:
            x0 = np.zeros(2 * size)
        else:
            if _condition(BBt) > 1e12:
                raise SolverError(
                    "half-space: the sticking nodes cannot carry the load in "
                    "every direction (gross sliding)",
                    backend="halfspace",
                    status="gross_sliding",
                )
            Winv = _inverse(BBt)
            x0 = bt(Winv @ cons)  # Bᵀ (B Bᵀ)⁻¹ cons
        h2 = self.h**2
        buf = op.empty()
        flat = buf.reshape(-1)

        none, nonec = np.empty(0), np.empty(0, dtype=complex)

        def restrict(full, scale=none, u=nonec, diag=none):
            """The unknowns' components of a padded array (the slipping nodes' along τ, times
            ``scale``), plus ``diag u`` on the slipping ones."""
            return kern.restrict2(full.reshape(-1), idx, ns, tau, scale, u, diag)

        # the known forces and the start in one product (linearity); the residual from it
        if x0.any() or known.any():
            u0 = x0.view(complex)
            kern.start2(buf, known, N, idx, u0)
            first = op.padded("tangential", buf, 1.0 / h2)
            res, total = kern.residual2(first, buf, N, idx, ns, tau, rhs, tdiag, u0)
        else:
            res = rhs.copy()
            total = np.zeros((N, N), dtype=complex)
        # C of the step on the grid's nodes, summed from the products (the padded arrays'
        # corner: the rest is the wrap-around)
        last = None

        def M(x):
            nonlocal last
            u = x.view(complex)
            kern.embed(flat, idx, u, none)
            last = op.padded("tangential", buf, 1.0 / h2)
            return restrict(last, none, u, tdiag).view(float)

        def step(alpha):
            kern.add_corner(total, alpha, last)

        # the slipping nodes' unknowns carry the diagonal term besides C (the operator there
        # is about c + tdiag, where C's inverse assumes c): the preconditioner scaled
        # symmetrically by sqrt(c / (c + tdiag)) on those (M-D, grid 40: 21432 products to
        # 18894, the same cycles)
        def pre(r):
            kern.embed(flat, idx, r.view(complex), weights)
            return restrict(op.padded("precondition", buf, h2), wL).view(float)

        tol = frac * c * tolF
        tol = max(tol, (ETA if eta is None else eta) * c * worst)
        if ks > 0.0:
            x, _ = cg(
                lambda y: M(y) + bt(bsum(y) / ks),
                None,
                x0,
                None,
                pre,
                tol,
                self.stats,
                step,
                res=res.view(float) + bt(cons / ks),
            )
            dd = (bsum(x) - cons) / ks
        else:

            def project(r):
                return kern.project2(r.view(complex), ns, tau, Winv).view(float)

            x, res = cg(M, None, x0, project, pre, tol, self.stats, step, res=res.view(float))
            dd = Winv @ bsum(res)
        dF = kern.add_at(known, nodes, x.view(complex))
        return _floats(dF, n), dd, _floats(total.reshape(-1), n)


def _floats(Z, n):
    """n complex numbers as node-major ``(n, 2)`` floats (a view)."""
    return Z.view(float).reshape(n, 2)


def every_node_slips():
    raise SolverError(
        "half-space: every node in contact slips or is separated under pure "
        "load control (gross sliding)",
        backend="halfspace",
        status="gross_sliding",
    )


def nearest_to_sticking(z, zn, b, contact, Qv):
    """For an iterate with every node in contact slipping (its forces ``b z/|z|``) under pure
    load control: the nodes to stick, those nearest to sticking (the smallest ``|z|/b``),
    the fewest whose limits add up to what the other nodes' forces leave of the load (so
    the Newton step can balance it within their limits; one node alone, the old rule, made
    the line search crawl on a large increment: 2808 Newton steps on grid 96, 8 steps per
    cycle)."""
    inside = np.flatnonzero(contact)
    order = inside[np.argsort(zn[inside] / b[inside], kind="stable")]
    e = np.sign(z[order]) if z.shape[1] == 1 else z[order] / zn[order, None]
    pull = b[order, None] * e  # each node's force while it slips
    # the load left to the stuck nodes with the first k + 1 of the order stuck
    left = Qv + pull.sum(axis=0) - np.cumsum(pull, axis=0)
    need = np.sqrt(np.einsum("ij,ij->i", left, left))
    k = int(np.argmax(np.cumsum(b[order]) >= need * (1.0 - 1e-12)))
    return order[: k + 1]


def _condition(A):
    """The condition number of a symmetric positive semi-definite 1 x 1 or 2 x 2 matrix
    (inf when singular)."""
    if A.shape[0] == 1:
        return 1.0 if A[0, 0] > 0.0 else math.inf
    m, r = 0.5 * (A[0, 0] + A[1, 1]), math.hypot(0.5 * (A[0, 0] - A[1, 1]), A[0, 1])
    return (m + r) / (m - r) if m - r > 0.0 else math.inf


def _inverse(A):
    """The inverse of a 1 x 1 or 2 x 2 matrix (closed form)."""
    if A.shape[0] == 1:
        return 1.0 / A
    det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
    return np.array([[A[1, 1], -A[0, 1]], [-A[1, 0], A[0, 0]]]) / det


class _Space:
    """d = 1: the unknowns of a Newton step, the sticking nodes' forces. They live in the FFT's
    padded layout (``op.empty``; ``pos``: each node's entry in it): ``embed`` puts them in a
    padded array (zero elsewhere), ``add`` adds them to one, ``restrict`` takes them out of
    one, and ``nodes`` gives them as node-major forces."""

    def __init__(self, stick, pos, op):
        self.stick, self.op = stick, op
        self.idx = pos[stick]
        self.size = stick.size
        self.buf = op.empty()
        self.flat = self.buf.reshape(-1)

    def embed(self, x):
        """x in the space's own padded array (its other entries stay zero)."""
        self.flat[self.idx] = x
        return self.buf

    def add(self, buf, x):
        """``buf += embed(x)``, in place (a padded array)."""
        buf.reshape(-1)[self.idx] += x

    def restrict(self, full):
        """The unknowns' components of a padded array."""
        return full.reshape(-1).take(self.idx)

    def nodes(self, x, base):
        """``base`` (node-major ``(n, 1)``) plus the unknowns x, a new array."""
        out = base.copy()
        out[self.stick, 0] += x
        return out


def column_sums(X):
    """The column sums of an ``(n, d)`` array (a product with ones: ``sum(axis=0)`` of a
    narrow array is several times slower)."""
    return np.ones(X.shape[0]) @ X
