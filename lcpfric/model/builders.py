"""Builders of general discrete uncoupled systems (:class:`~lcpfric.model.ContactSystem`).

``chain``
    n contact nodes in a row, each tied to the ground by a tangential spring ``k_ground`` and to
    its neighbours by ``k_coupling``: ``K = k_ground I + k_coupling L`` with L the path graph's
    Laplacian (tridiagonal ``[-1, 2, -1]``, 1 at the ends), symmetric positive definite for
    ``k_ground > 0``. With d = 2 each node has two tangential directions and ``K ⊗ I₂``.
``block_diagonal``
    independent systems (single nodes, for instance a grid of parameter points) stacked into one
    system with a block-diagonal K; its dissipation is the sum of theirs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .. import _checks
from ..errors import InputError
from .loads import Harmonic, Load
from .normal import IndependentSprings
from .single_node import SingleNode
from .system import ContactSystem

if TYPE_CHECKING:
    from collections.abc import Sequence

    import scipy.sparse
    from numpy.typing import ArrayLike

__all__ = ["chain", "chain_stiffness", "block_diagonal"]


def chain_stiffness(
    n: int, k_coupling: float = 1.0, k_ground: float = 1.0, dims: int = 1, sparse: bool = False
) -> np.ndarray | scipy.sparse.csc_matrix:
    """The (n·d x n·d) stiffness of a chain: ``(k_ground I + k_coupling L) ⊗ I_d``.

    L is the path graph's Laplacian (tridiagonal ``[-1, 2, -1]``, 1 at the ends; zero for a
    single node), so K is symmetric positive definite.

    Parameters
    ----------
    n : int
        Number of nodes, >= 1.
    k_coupling : float, optional
        Spring between neighbours, >= 0.
    k_ground : float, optional
        Spring from each node to the ground, > 0.
    dims : int, optional
        Tangential directions per node, 1 or 2.
    sparse : bool, optional
        Return a scipy.sparse CSC matrix instead of a dense array.

    Returns
    -------
    ndarray or scipy.sparse.csc_matrix
        K, (n·d, n·d).

    Raises
    ------
    InputError
        ``n``, ``k_coupling``, ``k_ground`` or ``dims`` out of range.
    """
    import scipy.sparse as sp

    n = _checks.positive_int("n", n)
    k_coupling = _checks.nonnegative("k_coupling", k_coupling)
    k_ground = _checks.positive("k_ground", k_ground)
    if dims not in (1, 2):
        raise InputError("dims", f"must be 1 or 2 tangential directions, got {dims!r}")
    deg = np.full(n, 2.0)
    if n > 1:
        deg[[0, -1]] = 1.0
    else:
        deg[:] = 0.0
    off = -k_coupling * np.ones(n - 1)
    K = sp.diags([off, k_ground + k_coupling * deg, off], [-1, 0, 1], format="csc")
    if dims == 2:
        K = sp.kron(K, sp.identity(2), format="csc")
    return K if sparse else K.toarray()


def chain(
    n: int,
    *,
    k_coupling: float = 1.0,
    k_ground: float = 1.0,
    friction: ArrayLike = 1.0,
    normal_loads: Sequence[Load] | None = None,
    tangential_loads: Sequence[Load] | None = None,
    P0: ArrayLike = 1.0,
    P1: ArrayLike = 0.0,
    Q1: ArrayLike = 0.0,
    phi: ArrayLike = 0.0,
    normal_phase: ArrayLike = 0.0,
    omega: float = 1.0,
    dims: int = 1,
    sparse: bool = False,
) -> ContactSystem:
    """A chain of n contact nodes with coupled tangential stiffness.

    Give the loads either as Load objects or as harmonic amplitudes and phases (Eq. 1 per node):
    ``P_i(t) = P0_i + P1_i sin(ωt + ψ_i)`` and ``Q_i(t) = Q1_i sin(ωt + ψ_i + φ_i)``, with
    ``ψ`` = ``normal_phase``. Scalars broadcast over the nodes; for d = 2, ``Q1`` and ``phi``
    may have shape (n, 2) (one amplitude and phase per direction).

    Parameters
    ----------
    n : int
        Number of nodes, >= 1.
    k_coupling, k_ground : float
        Spring between neighbours (>= 0) and from each node to the ground (> 0).
    friction : float or (n,) array_like
        Friction coefficients f_i > 0.
    normal_loads : sequence of n Load, optional
        P_i(t); replaces P0, P1, normal_phase.
    tangential_loads : sequence of n·d Load, optional
        Q(t) node by node; replaces Q1, phi.
    P0, P1, Q1, phi, normal_phase : float or array_like
        Harmonic loads (see above): finite; P1 and Q1 >= 0. P0 and P1 a scalar or one value
        per node; Q1 and phi a scalar, n values or (for d = 2) an (n, 2) array.
    omega : float
        Angular frequency of the harmonic loads, > 0.
    dims : int
        Tangential directions per node, 1 or 2.
    sparse : bool
        Keep K as a scipy.sparse matrix.

    Returns
    -------
    ContactSystem
        The chain, with :class:`~lcpfric.model.IndependentSprings` normal loads.

    Raises
    ------
    InputError
        A parameter out of range, of the wrong shape, or loads that are not Load objects or do
        not share one period.

    Examples
    --------
    >>> sys = chain(3, k_coupling=2.0, P1=0.5, Q1=1.5, phi=0.3)
    >>> sys.n, sys.m, sys.stiffness[0, :2].tolist()
    (3, 3, [3.0, -2.0])
    """
    K = chain_stiffness(n, k_coupling, k_ground, dims, sparse)
    f = np.broadcast_to(_checks.finite_array("friction", friction), (n,)).astype(float)
    omega = _checks.positive("omega", omega)
    if normal_loads is None:
        P0 = _node_values("P0", P0, n)
        P1 = _node_values("P1", P1, n, nonneg=True)
        psi = _node_values("normal_phase", normal_phase, n)
        normal_loads = [Harmonic(P0[i], P1[i], psi[i], omega) for i in range(n)]
    else:
        psi = _node_values("normal_phase", normal_phase, n)
    if tangential_loads is None:
        Q1 = _dof_values("Q1", Q1, n, dims, nonneg=True)
        ph = _dof_values("phi", phi, n, dims)
        tangential_loads = [
            Harmonic(0.0, Q1[i, j], psi[i] + ph[i, j], omega) for i in range(n) for j in range(dims)
        ]
    normal_loads = tuple(normal_loads)
    tangential_loads = tuple(tangential_loads)
    if not all(isinstance(p, Load) for p in normal_loads + tangential_loads):
        raise InputError("normal_loads", "normal_loads and tangential_loads must be Load objects")
    return ContactSystem(K, f, tangential_loads, IndependentSprings(normal_loads), dims=dims)


def block_diagonal(nodes: Sequence[SingleNode | ContactSystem]) -> ContactSystem:
    """Stack independent systems into one with a block-diagonal K.

    Parameters
    ----------
    nodes : sequence of SingleNode or ContactSystem
        All with the same period and the same d. A :class:`SingleNode` enters in its normalized
        units (``SingleNode.system()``: K = 1, f = 1, loads Q̂ and P̂), so that the stacked
        system's dissipation per cycle is ``Σ_i Q̂1_i Ŵ_i``.

    Returns
    -------
    ContactSystem
        The stacked system: K block diagonal (dense up to 2000 unknowns, else CSC sparse),
        the friction coefficients and loads of the systems one after the other.

    Raises
    ------
    InputError
        ``nodes`` empty or not all SingleNode or ContactSystem, systems with different d, or
        loads that do not share one period.
    """
    import scipy.sparse as sp

    systems = [nd.system() if isinstance(nd, SingleNode) else nd for nd in nodes]
    if not systems or not all(isinstance(s, ContactSystem) for s in systems):
        raise InputError("nodes", "needs one or more SingleNode or ContactSystem objects")
    dims = {s.dims for s in systems}
    if len(dims) != 1:
        raise InputError("nodes", f"all systems must have the same d, got {sorted(dims)}")
    blocks = [s.stiffness for s in systems]
    m = sum(s.m for s in systems)
    # a sparse-matrix first block keeps block_diag's sparse-matrix result on every SciPy
    K = sp.block_diag([sp.coo_matrix(blocks[0]), *blocks[1:]], format="csc")
    if m <= 2000:
        K = K.toarray()
    return ContactSystem(
        K,
        np.concatenate([s.friction for s in systems]),
        tuple(q for s in systems for q in s.tangential_loads),
        IndependentSprings(tuple(p for s in systems for p in s.normal.loads)),
        dims=dims.pop(),
    )


def _node_values(name, value, n, nonneg=False):
    arr = _checks.finite_array(name, value, nonneg=nonneg)
    try:
        return np.broadcast_to(arr, (n,)).astype(float)
    except ValueError:
        raise InputError(
            name, f"needs a scalar or {n} values (one per node), got shape {arr.shape}"
        ) from None


def _dof_values(name, value, n, dims, nonneg=False):
    arr = _checks.finite_array(name, value, nonneg=nonneg)
    if arr.ndim == 1 and arr.size == n:
        arr = arr[:, None]
    try:
        return np.broadcast_to(arr, (n, dims)).astype(float)
    except ValueError:
        raise InputError(
            name, f"needs a scalar, {n} values or an ({n}, {dims}) array, got shape {arr.shape}"
        ) from None
