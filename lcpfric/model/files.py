"""A user's discrete system from a file: JSON for small systems, NumPy's ``.npz`` for large ones.

Keys (the paper's convention ``F = Q + K v``, ``N = P + B v``; n nodes, d = 1)::

    K          n x n   tangential stiffness (symmetric positive definite)
    friction   n       friction coefficients (or one number for all)
    P0 P1 psi  n each  P_i(t) = P0_i + P1_i sin(ω t + psi_i)
    Q0 Q1 phi  n each  Q_i(t) = Q0_i + Q1_i sin(ω t + phi_i)
    B          n x n   the coupling block (optional; absent or zero: uncoupled)
    omega      1       ω (optional, default 1)
    start      n       initial tangential displacements (optional; ``steady_state(..., u0=)``)

Every field is checked before any work, and a bad one raises :class:`InputError` naming it.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["load_system", "FIELDS"]

#: the keys a system file may hold: required ones first
FIELDS = ("K", "friction", "P0", "P1", "psi", "Q0", "Q1", "phi", "B", "omega", "start")
_REQUIRED = FIELDS[:8]


def _read(path: Path) -> dict:
    if not path.is_file():
        raise InputError("file", f"{str(path)!r} is not a readable file")
    if path.suffix == ".npz":
        try:
            with np.load(path, allow_pickle=False) as data:
                return {k: data[k] for k in data.files}
        except (OSError, ValueError) as exc:
            raise InputError("file", f"{str(path)!r} is not a NumPy .npz archive ({exc})") from None
    try:
        raw = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError("file", f"{str(path)!r} is not JSON ({exc})") from None
    if not isinstance(raw, dict):
        raise InputError("file", f"{str(path)!r} must hold one JSON object with the keys {FIELDS}")
    return raw


def _field(data: dict, key: str, shape: tuple) -> np.ndarray:
    try:
        value = np.asarray(data[key], dtype=float)
    except (TypeError, ValueError):
        raise InputError(key, "must be numbers") from None
    if (
        value.ndim == 0
        and len(shape) == 1
        and key in ("friction", "P0", "P1", "psi", "Q0", "Q1", "phi")
    ):
        value = np.full(shape, float(value))
    if value.shape != shape:
        raise InputError(key, f"must have the shape {shape}, got {value.shape}")
    if not np.all(np.isfinite(value)):
        raise InputError(key, "must be finite")
    return value


def load_system(path) -> tuple:
    """The system a file describes (module docstring), and its start.

    Parameters
    ----------
    path : str or path-like
        A ``.json`` file (one object) or a ``.npz`` archive with the keys of :data:`FIELDS`.

    Returns
    -------
    system : ContactSystem
        d = 1, IndependentSprings normal loads, the coupling block if B is given and not zero.
    start : ndarray or None
        The initial displacements, if the file gives them.

    Raises
    ------
    InputError
        Naming the field: a missing or unknown key, a wrong shape, a value that is not finite,
        K not symmetric positive definite, a friction coefficient <= 0, amplitudes < 0, ω <= 0,
        a coupled system that is not well posed (``coupling``); or the file itself (``file``).
    """
    from .loads import Harmonic
    from .normal import IndependentSprings
    from .system import ContactSystem

    data = _read(Path(path))
    unknown = sorted(set(data) - set(FIELDS))
    if unknown:
        raise InputError(
            unknown[0], f"is not a system file's key; the keys are {', '.join(FIELDS)}"
        )
    missing = [k for k in _REQUIRED if k not in data]
    if missing:
        raise InputError(missing[0], f"is missing; a system file needs {', '.join(_REQUIRED)}")
    K = np.asarray(data["K"], dtype=float)
    if K.ndim != 2 or K.shape[0] != K.shape[1] or K.shape[0] == 0:
        raise InputError("K", f"must be a square n x n matrix, got the shape {K.shape}")
    n = K.shape[0]
    v = {k: _field(data, k, (n,)) for k in ("friction", "P0", "P1", "psi", "Q0", "Q1", "phi")}
    for k in ("P1", "Q1"):
        if np.any(v[k] < 0):
            raise InputError(k, "amplitudes must be >= 0 (a phase carries the sign)")
    omega = float(_field(data, "omega", ())) if "omega" in data else 1.0
    if not omega > 0:
        raise InputError("omega", f"must be > 0, got {omega}")
    B = _field(data, "B", (n, n)) if "B" in data else None
    start = _field(data, "start", (n,)) if "start" in data else None
    system = ContactSystem(
        K,
        v["friction"],
        tuple(Harmonic(v["Q0"][i], v["Q1"][i], v["phi"][i], omega) for i in range(n)),
        IndependentSprings(
            tuple(Harmonic(v["P0"][i], v["P1"][i], v["psi"][i], omega) for i in range(n))
        ),
        coupling=B,
    )
    return system, start
