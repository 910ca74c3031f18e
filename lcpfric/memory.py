"""Memory estimates, so that a request that would exhaust memory is refused before any work.

A steady state holds a few float64 values per time step and tangential unknown (the scene's
grid, the cycle's series, the previous cycle); each method's factor is in its registry entry
(``Method.floats_per_step``). A map holds its values plus the chunks in flight. The limit is
``$LCPFRIC_MAX_MEMORY`` (``8G``, ``500M``, ``none``) or half the physical memory; the API
(:func:`lcpfric.make_scene`, :func:`lcpfric.analysis.sweep.sweep`) and the CLI (``--max-memory``)
check it and raise :class:`~lcpfric.errors.InputError` naming the parameter, the estimate, the
limit and how to raise it.
"""

from __future__ import annotations

import math
import os
import re
from contextlib import contextmanager

from .errors import InputError

__all__ = [
    "MEMORY_ENV",
    "parse_size",
    "format_bytes",
    "physical_memory",
    "default_limit",
    "limit",
    "steady_state_bytes",
    "continuum_bytes",
    "map_bytes",
    "check",
    "fits",
]

MEMORY_ENV = "LCPFRIC_MAX_MEMORY"
_DEFAULT_FRACTION = 0.5
_UNITS = {
    "": 1,
    "b": 1,
    "k": 1e3,
    "kb": 1e3,
    "kib": 2**10,
    "m": 1e6,
    "mb": 1e6,
    "mib": 2**20,
    "g": 1e9,
    "gb": 1e9,
    "gib": 2**30,
    "t": 1e12,
    "tb": 1e12,
    "tib": 2**40,
    "p": 1e15,
    "pb": 1e15,
    "pib": 2**50,
    "e": 1e18,
    "eb": 1e18,
    "eib": 2**60,
}
_SIZE = re.compile(r"^\s*(\d+(?:\.\d*)?|\.\d+)(?:[eE]([+-]?\d+))?\s*([A-Za-z]*)\s*$")

#: float64 values held per time step (per tangential degree of freedom) by a steady state: the
#: scene's t, Q, N, the cycle's u, F, state, the previous cycle's u and the result's series.
#: Each method's factor is in its registry entry (``Method.floats_per_step``; measured peaks with
#: tracemalloc, single node: exact 10, explicit and projection 26, the convex solver backends 83
#: to 116, rounded up); this one serves a name the registry does not know.
_FLOATS_PER_STEP_SOLVER = 128
#: float64 values per grid point of a map: the values (1), and the copies made to build, write
#: and read back the dataset (3).
_FLOATS_PER_MAP_POINT = 4
#: float64 values per point of a chunk in evaluation (exact_W_hat: 39 measured; the batched
#: projection: 37; plus the chunk's coordinates and indices)
_FLOATS_PER_CHUNK_POINT = 64
_DEFAULT_CHUNK = 2_000_000  # an upper bound on the sweep's default chunk size


def parse_size(text, name: str) -> float:
    """Bytes from ``8G``, ``500MB``, ``2GiB``, ``1e10``; ``none`` (or ``0``) for no limit (inf)."""
    s = str(text).strip()
    if s.lower() in ("none", "off", "unlimited", "inf", "0"):
        return math.inf
    m = _SIZE.match(s)
    unit = m.group(3).lower() if m else None
    if m is None or unit not in _UNITS:
        raise InputError(
            name,
            f"cannot parse {text!r} as a memory size; give e.g. 8G, 500M, "
            "2GiB, or none for no limit",
        )
    try:
        value = float(m.group(1)) * 10.0 ** int(m.group(2) or 0) * _UNITS[unit]
    except OverflowError:
        value = math.inf
    if not math.isfinite(value):
        raise InputError(
            name, f"{text!r} is beyond any memory; give a size such as 8G, or none for no limit"
        )
    if value <= 0:
        raise InputError(name, f"must be a positive size, got {text!r}")
    return value


def format_bytes(n: float) -> str:
    if math.isinf(n):
        return "unlimited"
    for unit, size in (
        ("EB", 1e18),
        ("PB", 1e15),
        ("TB", 1e12),
        ("GB", 1e9),
        ("MB", 1e6),
        ("kB", 1e3),
    ):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} B"


def physical_memory() -> int | None:
    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def steady_state_bytes(steps: int, method: str = "exact", dofs: int = 1) -> float:
    """Estimated peak bytes of one steady state with ``steps`` steps per cycle."""
    return (
        8.0
        * _entry(method, "floats_per_step", _FLOATS_PER_STEP_SOLVER)
        * (float(steps) + 1.0)
        * max(1, dofs)
    )


def continuum_bytes(nodes: int, dims: int, steps: int, history: bool = True) -> float:
    """Bytes of a continuum contact's scene (the friction limits of every node at every
    instant) and, with the history, of its cycle's slips, forces and states."""
    return 8.0 * nodes * (steps + 1) * (1 + (2 * dims + 1 if history else 0))


def _entry(method, attr: str, default):
    """An attribute of ``method``'s registry entry (``default`` for an unknown name: the name
    itself is checked, and reported, where the method is resolved)."""
    from .methods import get_method

    try:
        return getattr(get_method(str(method))[0], attr)
    except InputError:
        return default


def map_bytes(
    points: float,
    axes: float = 0.0,
    method: str = "exact",
    steps: int | None = None,
    chunk_size: int | None = None,
    workers: int = 1,
) -> float:
    """Estimated peak bytes of a map of ``points`` grid points (``axes``: the total length of
    its coordinate axes) run with ``workers`` chunks in flight at once."""
    points = float(points)
    chunk = min(points, float(chunk_size or _DEFAULT_CHUNK))
    in_flight = min(points, chunk * max(1, workers))
    if _entry(method, "grid", None) is not None:  # vectorized: a chunk in one pass
        work = 8.0 * _FLOATS_PER_CHUNK_POINT * in_flight
    else:  # point by point: one steady state per worker at a time
        work = max(1, workers) * steady_state_bytes(steps or 2000, method)
    return 8.0 * (_FLOATS_PER_MAP_POINT * points + axes) + work


_OVERRIDE: list = []
_OPTION: list = []


@contextmanager
def limit(bytes_: float | None, source: str):
    """Use ``bytes_`` as the limit inside the ``with`` block (the CLI's ``--max-memory``); with
    ``bytes_=None`` keep the limit and only name ``source`` as the way to raise it."""
    _OPTION.append(source)
    if bytes_ is not None:
        _OVERRIDE.append((float(bytes_), source))
    try:
        yield
    finally:
        _OPTION.pop()
        if bytes_ is not None:
            _OVERRIDE.pop()


def default_limit() -> tuple[float, str]:
    """(limit in bytes, where it comes from): the innermost :func:`limit` block, else
    ``$LCPFRIC_MAX_MEMORY``, else half the physical memory."""
    if _OVERRIDE:
        return _OVERRIDE[-1]
    env = os.environ.get(MEMORY_ENV)
    if env is not None and env.strip():
        return parse_size(env, MEMORY_ENV), MEMORY_ENV
    phys = physical_memory()
    if phys is None:
        return 8e9, "the default when the physical memory is unknown"
    return _DEFAULT_FRACTION * phys, f"half the physical memory of {format_bytes(phys)}"


def fits(need: float) -> bool:
    """Whether ``need`` bytes fit under the limit (for what is kept only where it fits, as a
    stepper's warm starts)."""
    return need <= default_limit()[0]


def check(
    need: float,
    parameter: str,
    what: str,
    limit: tuple[float, str] | None = None,
    how: str | None = None,
) -> None:
    """Raise InputError naming ``parameter`` when ``need`` bytes exceed the limit."""
    limit_bytes, source = default_limit() if limit is None else limit
    if need <= limit_bytes:
        return
    size = format_bytes(need * 1.25).replace(" ", "")
    if how is None and _OPTION:
        how = f"{_OPTION[-1]} {size} (or ${MEMORY_ENV})"
    how = how or f"set the environment variable {MEMORY_ENV}={size}"
    raise InputError(
        parameter,
        (
            f"{what} needs about {format_bytes(need)} of memory, over the limit of "
            f"{format_bytes(limit_bytes)} ({source}); ask for less, or raise the limit: {how}"
        ),
    )
