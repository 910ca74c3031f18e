"""Example jointed structures (:class:`~lcpfric.model.structure.JointedStructure`): a rod with
a lap joint and a friction support, the benchmark's and the figure's 100-degree-of-freedom
chain."""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..errors import InputError
from .structure import JointedStructure

__all__ = ["jointed_rod"]


def jointed_rod(
    n: int = 100,
    contacts: int = 10,
    *,
    joint_stiffness: float = 5.0,
    support_stiffness: float = 1.0,
    slip_forces: tuple[float, float] = (0.002, 0.2),
    friction: float = 0.5,
    sparse: bool = True,
) -> JointedStructure:
    """A fixed-free rod of n masses with a lap joint in its middle and a friction support.

    The rod: n equal masses ``1/n`` (total mass 1) in a line, neighbours joined by springs
    ``k = n`` and the first mass tied to the ground by k (a uniform bar of axial stiffness
    EA/L = 1 and mass 1, fixed at its left end: its lowest mode ``ω ≈ π/2``). The contacts,
    half of them (rounded up) across the lap joint: Jenkins elements of stiffness
    ``joint_stiffness`` between consecutive masses at the middle of the rod (in parallel with
    the rod's springs there); the others a friction support: elements of stiffness
    ``support_stiffness`` from evenly spaced masses (the last is the free end) to the ground.
    The slip forces ``mu N`` are spaced geometrically over ``slip_forces``, in the order of
    the contacts (joint first), so that the contacts slip one after the other as the
    amplitude grows.

    Parameters
    ----------
    n : int, optional
        Masses, >= 4.
    contacts : int, optional
        Jenkins elements, from 1 to n // 2.
    joint_stiffness, support_stiffness : float, optional
        kt of the joint's and of the support's elements, > 0.
    slip_forces : (float, float), optional
        The smallest and largest slip force, 0 < low <= high.
    friction : float, optional
        mu > 0 of every contact (N = slip force / mu).
    sparse : bool, optional
        Keep M and K as scipy.sparse matrices.

    Returns
    -------
    JointedStructure
        The rod and its contacts.

    Raises
    ------
    InputError
        A parameter out of range.
    """
    import scipy.sparse as sp

    n = _checks.positive_int("n", n, 4)
    contacts = _checks.positive_int("contacts", contacts)
    if contacts > n // 2:
        raise InputError("contacts", f"must be <= n // 2 = {n // 2}, got {contacts}")
    kj = _checks.positive("joint_stiffness", joint_stiffness)
    ks = _checks.positive("support_stiffness", support_stiffness)
    friction = _checks.positive("friction", friction)
    low, high = (_checks.positive("slip_forces", s) for s in slip_forces)
    if low > high:
        raise InputError("slip_forces", f"needs low <= high, got ({low}, {high})")
    k = float(n)
    main = np.full(n, 2.0 * k)
    main[-1] = k
    off = -k * np.ones(n - 1)
    K = sp.diags([off, main, off], [-1, 0, 1], format="csc")
    M = sp.identity(n, format="csc") / n
    joint = (contacts + 1) // 2
    first = n // 2 - joint // 2 - 1
    pairs = [[first + j, first + j + 1] for j in range(joint)]
    support = contacts - joint
    grounded = [[int(round((j + 1) * n / support)) - 1, -1] for j in range(support)]
    kt = np.array([kj] * joint + [ks] * support)
    slip = np.geomspace(low, high, contacts)
    if not sparse:
        M, K = M.toarray(), K.toarray()
    return JointedStructure(M, K, np.array(pairs + grounded), kt, friction, slip / friction)
