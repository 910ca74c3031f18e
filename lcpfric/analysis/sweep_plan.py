"""What a dissipation map runs and how it is cut (for :func:`~lcpfric.analysis.sweep.sweep`).

:func:`plan_sweep` gives the function each chunk calls and its options (a method's grid form,
:func:`per_point_W_hat` point by point, or a contact map's), the estimated cost per point, and
the map's geometry; :func:`chunk_bounds` cuts the grid into chunks sized by that cost (the
same on any machine, so a sweep resumes anywhere); :func:`sweep_bytes` is the memory the map
needs and :func:`describe_sweep` the description, fingerprint and attributes its stored chunks
and its dataset carry.
"""

from __future__ import annotations

import hashlib
import json
import math

import numpy as np

from .. import _checks, memory
from ..errors import InputError
from ..methods import CLOSED_FORM, get_stepper, grid_function
from .chunkstore import fingerprint
from .sweep_io import DIMS, version

__all__ = [
    "plan_sweep",
    "chunk_bounds",
    "sweep_bytes",
    "describe_sweep",
    "per_point_W_hat",
    "PARALLEL_SECONDS",
]

# Sizing of the chunks (the methods' own cost estimates are in the registry, lcpfric.methods)
_DEFAULT_STEPS = 2000  # steady_state's default
_CHUNK_SECONDS = 2.0  # a chunk this long is worth saving on its own, and short enough to lose
PARALLEL_SECONDS = 3.0  # starting worker processes costs ~0.1-0.3 s; below this, stay serial
_MIN_CHUNKS = 64  # when parallel work pays: enough chunks to balance many workers
_MIN_BATCH = 4096  # points per chunk of a batched stepper (its per-step overhead is fixed)


def _cost(entry, batched: bool, steps: int) -> float:
    """Estimated seconds per grid point of ``entry`` (a registry :class:`Method`)."""
    if entry.seconds_per_point is not None:
        return entry.seconds_per_point
    per_step = entry.seconds_per_point_step or 3e-6
    return per_step * steps


def per_point_W_hat(P1, Q1, phi, *, method: str, **options):
    """Ŵ point by point through :func:`lcpfric.steady_state` (the fallback for any method)."""
    from ..periodic import steady_state
    from ..model import SingleNode

    out = np.zeros(np.shape(P1))
    for n in np.flatnonzero(np.asarray(Q1) > 0):  # Q̂1 = 0: the limit Ŵ = 0, nothing to run
        node = SingleNode.normalized(P1=float(P1[n]), Q1=float(Q1[n]), phi=float(phi[n]))
        out[n] = steady_state(node, method=method, **options).W_hat
    return out


def _options(entry, steps_per_cycle) -> dict:
    if entry.kind == CLOSED_FORM:
        if steps_per_cycle is not None:
            raise InputError(
                "steps_per_cycle",
                f"is not used by method {entry.name!r} (it has "
                f"no time steps); leave it unset or choose "
                f"another method",
            )
        return {}
    if steps_per_cycle is None:
        return {}
    return {"steps_per_cycle": _checks.positive_int("steps_per_cycle", steps_per_cycle, minimum=4)}


def _check_method(method):
    """``(name, function, entry)``: the method's grid function (None: point by point) and its
    registry entry; an unknown name or a missing extra fails here, not in a worker."""
    if not isinstance(method, str) or not method.strip():
        raise InputError(
            "method", f"must be a method name such as 'exact' or 'projection', got {method!r}"
        )
    method = method.strip()
    func, entry = grid_function(method)
    if func is None:
        get_stepper(method)
    return method, func, entry


def chunk_bounds(n: int, chunk_size, cost: float, batched: bool) -> list[tuple[int, int]]:
    """Chunk boundaries. They depend only on the grid and the method (not on where the chunks
    run), so that a sweep interrupted on one machine resumes on another."""
    if chunk_size is None:
        size = max(1, int(_CHUNK_SECONDS / cost))
        if n * cost > PARALLEL_SECONDS:  # work enough to share: chunks for many workers
            size = min(size, math.ceil(n / _MIN_CHUNKS))
        if batched:  # a batched stepper pays a fixed cost per step of a chunk, however small
            size = max(size, _MIN_BATCH)
    else:
        size = _checks.positive_int("chunk_size", chunk_size)
    return [(a, min(a + size, n)) for a in range(0, n, size)]


def plan_sweep(P1, Q1, phi, method, steps_per_cycle, contact) -> dict:
    """What the sweep runs: the chunk function and its options, the cost per point, whether it
    is batched, the method's name and the map's geometry (None: the single node)."""
    if contact is not None:
        from .contact_maps import map_spec

        func, options, cost, own = map_spec(contact, steps_per_cycle, method)
        return dict(
            func=func,
            options=options,
            cost=cost,
            batched=False,
            geometry="sphere",
            method=own if method is None else str(method).strip(),
            model=contact.get("model", "mdr"),
        )
    method, func, entry = _check_method("exact" if method is None else method)
    options = _options(entry, steps_per_cycle)
    steps = options.get("steps_per_cycle", _DEFAULT_STEPS)
    batched = func is not None and entry.kind != CLOSED_FORM
    if func is None:
        func, options = per_point_W_hat, {"method": method, **options}
    return dict(
        func=func,
        options=options,
        cost=_cost(entry, batched, steps),
        batched=batched,
        geometry=None,
        method=method,
        steps=steps,
    )


def sweep_bytes(plan, n, chunks, phi, P1, Q1, scheduler, workers) -> float:
    largest = max(b - a for a, b in chunks)
    axes = P1.size + Q1.size + phi.size
    if plan["geometry"] is None:
        return memory.map_bytes(
            n, axes, plan["method"], plan["steps"], largest, 1 if scheduler is not None else workers
        )
    from .contact_maps import map_bytes

    return map_bytes(
        plan["options"], n, largest * (1 if scheduler is not None else workers), workers, axes
    )


def sweep_memory(plan, chunks, phi, P1, Q1, scheduler, workers) -> tuple[float, str, str]:
    """``(bytes, parameter, what)`` of a sweep, for :func:`lcpfric.memory.check`."""
    n = phi.size * P1.size * Q1.size
    return (
        sweep_bytes(plan, n, chunks, phi, P1, Q1, scheduler, workers),
        sweep_parameter(plan, n, phi, P1, Q1),
        f"a map of {n} points ({phi.size} x {P1.size} x {Q1.size})",
    )


def sweep_parameter(plan, n, phi, P1, Q1) -> str:
    """The parameter a memory error names: the grid of points when its values alone take half
    the limit (or for the single node), else what sets the contact map's work per point."""
    values = 8.0 * (4 * n + P1.size + Q1.size + phi.size)
    if plan["geometry"] is None or values > 0.5 * memory.default_limit()[0]:
        return "P1"
    from .contact_maps import memory_parameter

    return memory_parameter(plan["options"])


def describe_sweep(plan, phi, P1, Q1, chunks):
    """The sweep's description (what its chunks store keys on), fingerprint and attributes."""
    options = {k: v for k, v in plan["options"].items() if k not in ("method",)}
    digest = hashlib.sha256(b"".join(a.tobytes() for a in (phi, P1, Q1))).hexdigest()[:16]
    description = {
        "dims": list(DIMS),
        "shape": [phi.size, P1.size, Q1.size],
        "coords_sha256": digest,
        "method": plan["method"],
        "options": json.loads(json.dumps(options, default=repr)),
    }
    if plan["geometry"] is not None:
        description["contact"] = plan["geometry"]
    key = fingerprint({**description, "chunks": chunks})
    attrs = {
        "title": "lcpfric dissipation map",
        "method": plan["method"],
        "steps_per_cycle": options.get("steps_per_cycle", -1),
        "lcpfric_version": version(),
        "fingerprint": key,
        "chunks": len(chunks),
    }
    if plan["geometry"] is not None:
        attrs.update(
            geometry=plan["geometry"],
            model=plan["model"],
            k_support_over_k_t0=options["k_support_ratio"],
            tol=options["tol"],
        )
        attrs.update({k: options[k] for k in ("nodes", "grid", "dims", "nu") if k in options})
    return description, key, attrs
