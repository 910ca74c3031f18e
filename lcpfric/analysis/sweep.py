"""Dissipation maps: Ŵ over grids of (P̂1, Q̂1, φ), in parallel, resumable, as ``xarray``.

:func:`sweep` evaluates Ŵ on the full grid ``phi x P1 x Q1`` and returns an ``xarray.Dataset``
with coordinates ``phi`` (radians), ``P1``, ``Q1`` and the variable ``W_hat``.

How the work is done
--------------------
* **Vectorized.** A method whose registry entry has a grid form (:mod:`lcpfric.methods`)
  evaluates a whole chunk of points in one call (``exact`` is a few numpy passes over all points:
  112 211 points in ~0.1 s; ``projection`` is batched over the points). Any other method goes
  point by point through :func:`lcpfric.steady_state` (slow; for checking).
* **Chunks.** The grid is cut into chunks of ``chunk_size`` points (flat, C order over
  ``(phi, P1, Q1)``). A chunk is the unit of parallel work, of progress and of saving. The
  default size depends only on the grid and the method, so a sweep resumes on any machine.
* **Where.** Serially for small jobs; on a local process pool using all cores when the estimated
  work pays for it (or ``processes=N``); on Dask when ``scheduler`` is a ``dask.distributed.Client``
  or a scheduler address (``tcp://host:8786``: dask-jobqueue's SLURM/PBS clusters included).
* **Nothing lost.** With ``out`` or ``store`` given, every finished chunk is saved at once to a
  store directory (one file per chunk, written atomically; see :mod:`.chunkstore`). Run
  the same call again after Ctrl-C, a killed process or a lost worker and only the missing chunks
  are computed. When ``out`` is written the store is removed; calling again with an existing
  ``out`` of the same sweep just reads it.

Zero amplitudes give the limit Ŵ = 0 (never NaN) for every method. A point that reaches no
steady state is NaN, never a value that did not converge: an error for the single node (the
method's ``on_nonconvergence``), counted in the dataset's attribute ``unconverged_points`` for
a contact map (whose NaN also marks loads without equilibrium: ``no_equilibrium_points``).
"""

from __future__ import annotations

import hashlib
import json
import math
import sys
import time
from typing import Callable

import numpy as np

from .. import _checks, memory
from .._optional import require
from ..errors import InputError, LcpfricError
from ..methods import CLOSED_FORM, get_stepper, grid_function
from .chunkstore import ChunkStore, fingerprint
from .runners import default_workers, run_dask, run_processes, run_serial
from .sweep_io import (
    DIMS,
    check_output,
    dataset,
    netcdf_engine,
    read_dataset,
    version,
    write_dataset,
    xarray_module,
)

__all__ = ["sweep", "per_point_W_hat", "write_dataset", "netcdf_engine"]

# Sizing of the chunks (the methods' own cost estimates are in the registry, lcpfric.methods)
_DEFAULT_STEPS = 2000  # steady_state's default
_CHUNK_SECONDS = 2.0  # a chunk this long is worth saving on its own, and short enough to lose
_PARALLEL_SECONDS = 3.0  # starting worker processes costs ~0.1-0.3 s; below this, stay serial
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


def _picklable(exc: BaseException) -> bool:
    import pickle

    try:
        pickle.loads(pickle.dumps(exc))
        return True
    except Exception:
        return False


def _compute_chunk(func, options, P1, Q1, phi, start, stop):
    """Ŵ for the flat grid indices ``start:stop`` (runs in a worker)."""
    i, j, k = np.unravel_index(np.arange(start, stop), (phi.size, P1.size, Q1.size))
    q = Q1[k]
    try:
        W = np.asarray(func(P1[j], q, phi[i], **options), dtype=float).reshape(q.shape)
    except Exception as exc:
        if _picklable(exc):
            raise
        raise LcpfricError(f"{type(exc).__name__}: {exc}") from None
    return np.where(q == 0.0, 0.0, W)


# -- inputs ----------------------------------------------------------------------------------------
def _axis(name: str, values, nonneg: bool) -> np.ndarray:
    arr = np.atleast_1d(_checks.finite_array(name, values, nonneg=nonneg))
    if arr.ndim != 1 or arr.size == 0:
        raise InputError(name, f"must be a non-empty 1-D sequence of values, got shape {arr.shape}")
    return arr.astype(float)


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


def _chunking(n: int, chunk_size, cost: float, batched: bool) -> list[tuple[int, int]]:
    """Chunk boundaries. They depend only on the grid and the method (not on where the chunks
    run), so that a sweep interrupted on one machine resumes on another."""
    if chunk_size is None:
        size = max(1, int(_CHUNK_SECONDS / cost))
        if n * cost > _PARALLEL_SECONDS:  # work enough to share: chunks for many workers
            size = min(size, math.ceil(n / _MIN_CHUNKS))
        if batched:  # a batched stepper pays a fixed cost per step of a chunk, however small
            size = max(size, _MIN_BATCH)
    else:
        size = _checks.positive_int("chunk_size", chunk_size)
    return [(a, min(a + size, n)) for a in range(0, n, size)]


def _progress_bar(enabled: bool, total: int, initial: int, method: str):
    enabled = bool(enabled) and sys.stderr.isatty()
    if not enabled:
        return None
    tqdm = require("tqdm", "dist", "Progress bars").tqdm
    return tqdm(
        total=total,
        initial=initial,
        unit="chunk",
        desc=f"sweep ({method})",
        file=sys.stderr,
        dynamic_ncols=True,
    )


def _run(tasks: dict, on_result, scheduler, processes, workers: int, seconds: float) -> str:
    """Run the chunks on Dask, on a local pool, or here; return a description of where."""
    if not tasks:
        return "none"
    if scheduler is not None:
        return run_dask(tasks, _compute_chunk, on_result, scheduler)
    pays = seconds > _PARALLEL_SECONDS if processes is None else processes > 1
    if workers > 1 and len(tasks) > 1 and pays:
        return run_processes(tasks, _compute_chunk, on_result, workers)
    return run_serial(tasks, _compute_chunk, on_result)


# -- the sweep -------------------------------------------------------------------------------------
def sweep(
    P1,
    Q1,
    phi,
    method: str | None = None,
    *,
    steps_per_cycle: int | None = None,
    chunk_size: int | None = None,
    out=None,
    store=None,
    resume: bool = True,
    scheduler=None,
    processes: int | None = None,
    progress: bool = True,
    on_chunk: Callable | None = None,
    contact: dict | None = None,
):
    """Ŵ on the grid ``phi x P1 x Q1`` as an ``xarray.Dataset``; with ``contact``, the
    dissipation of a continuum contact instead.

    Parameters
    ----------
    P1, Q1 : array_like
        Normalized amplitudes P̂1 = P1/P0 and Q̂1 = Q1/(f P0), >= 0 (1-D, or a scalar).
    phi : array_like
        Phases φ in radians (1-D, or a scalar).
    method : str, optional
        ``"exact"`` (the default for the single node: exact to round-off and the fastest), or
        any :func:`lcpfric.steady_state` method: vectorized over the points where its registry
        entry has a grid form (``projection``), else point by point (for checking). For a
        contact map, a method that solves the contact (its default: ``mdr-bar`` or
        ``newton-cg``).
    steps_per_cycle : int, optional
        Steps per cycle of a time-stepping method (not used by ``exact``).
    chunk_size : int, optional
        Grid points per chunk; by default sized to ~2 s of work, and small enough to give every
        worker several chunks.
    out : str or Path, optional
        Write the result to this NetCDF-4 file (h5netcdf engine), atomically at the end; the
        chunks are saved meanwhile in ``store`` (default ``<out>.parts``).
    store : str or Path, optional
        Directory where every finished chunk is saved, so that an interrupted sweep resumes.
    resume : bool
        Reuse finished chunks in ``store`` (and an existing ``out`` of the same sweep). False
        discards them and computes everything.
    scheduler : dask.distributed.Client or str, optional
        Run the chunks on Dask: a ``Client`` or a scheduler address. Default: local.
    processes : int, optional
        Local worker processes. Default: all cores when the work pays for it, else serial;
        1 forces serial.
    progress : bool
        Show a progress bar (only when stderr is a terminal).
    on_chunk : callable, optional
        ``on_chunk(index, done, total)`` after each chunk is saved (raise in it to stop the sweep;
        the saved chunks are kept).
    contact : dict, optional
        Map a continuum contact instead of the single node: ``{"geometry": "sphere", "nodes":
        200, "k_support": 0.0, "tol": 1e-8}`` (the defaults) gives ``W_normalized = W k_t0 /
        (μ² P0²)`` of the Hertz contact by dimensionality reduction
        (:func:`lcpfric.analysis.contact_maps.mdr_W_normalized`) over ``P1 = P1/P0``,
        ``Q1 = Q1/(μ P0)`` and φ, with ``k_support`` in units of k_t0 and ``steps_per_cycle``
        200 by default. ``{"model": "halfspace", "grid": 20, "dims": 1, "nu": 0.0,
        "k_support": 0.0, "tol": 1e-8}`` (its defaults; ``steps_per_cycle`` 100) maps the same
        quantity on the half-space boundary elements
        (:func:`lcpfric.analysis.contact_maps.halfspace_W_normalized`). NaN marks loads that
        have no equilibrium under pure load control (``k_support = 0`` and ``|Q| > μ P`` at
        some instant), and points that reach no steady state (counted apart).

    Returns
    -------
    xarray.Dataset
        ``W_hat(phi, P1, Q1)`` (or ``W_normalized``) with attributes ``method``,
        ``steps_per_cycle``, ``lcpfric_version``, ``seconds``, ``executor``, ``chunks``,
        ``chunks_computed``, ``chunks_reused`` and ``fingerprint`` (identifies the sweep for
        resuming); a contact map adds ``unconverged_points`` and ``no_equilibrium_points``.

    Examples
    --------
    >>> import numpy as np
    >>> ds = sweep(np.linspace(0, 10, 11), np.linspace(0, 10, 11), [0, 0.6 * np.pi],
    ...            progress=False)
    >>> round(ds.W_hat.sel(phi=0.0, P1=1.0, Q1=2.0).item(), 12)  # Eq. (12)
    1.333333333333
    """
    P1 = _axis("P1", P1, nonneg=True)
    Q1 = _axis("Q1", Q1, nonneg=True)
    phi = _axis("phi", phi, nonneg=False)
    plan = _plan(P1, Q1, phi, method, steps_per_cycle, contact)
    if processes is not None:
        processes = _checks.positive_int("processes", processes)
    out = None if out is None else check_output(out)
    xarray_module()  # fail before any work if the dist extra is missing
    t0 = time.perf_counter()
    n = phi.size * P1.size * Q1.size
    workers = processes or default_workers()
    chunks = _chunking(n, chunk_size, plan["cost"], plan["batched"])
    memory.check(
        _bytes(plan, n, chunks, phi, P1, Q1, scheduler, workers),
        "P1",
        f"a map of {n} points ({phi.size} x {P1.size} x {Q1.size})",
    )
    description, key, attrs = _describe(plan, phi, P1, Q1, chunks)
    if out is not None and resume and out.exists():
        try:
            old = read_dataset(out)
        except Exception:
            old = None
        if old is not None and old.attrs.get("fingerprint") == key:
            old.attrs.update(
                chunks_computed=0,
                chunks_reused=len(chunks),
                executor="none",
                seconds=time.perf_counter() - t0,
            )
            return old
    if store is None and out is not None:
        store = out.with_name(out.name + ".parts")
    chunk_store = (
        None
        if store is None
        else ChunkStore(
            store, {**description, "chunks": chunks}, [b - a for a, b in chunks], resume=resume
        )
    )
    values = np.empty(n)
    tasks = {}
    for index, (a, b) in enumerate(chunks):
        saved = chunk_store.load(index) if chunk_store is not None else None
        if saved is not None:
            values[a:b] = saved
        else:
            tasks[index] = (plan["func"], plan["options"], P1, Q1, phi, a, b)
    reused = len(chunks) - len(tasks)
    bar = _progress_bar(progress, len(chunks), reused, plan["method"])
    finished = [reused]

    def on_result(index, chunk_values):
        a, b = chunks[index]
        values[a:b] = chunk_values
        if chunk_store is not None:
            chunk_store.save(index, chunk_values)
        finished[0] += 1
        if bar is not None:
            bar.update(1)
        if on_chunk is not None:
            on_chunk(index, finished[0], len(chunks))

    try:
        executor = _run(
            tasks,
            on_result,
            scheduler,
            processes,
            workers,
            sum(b - a for a, b in (chunks[i] for i in tasks)) * plan["cost"],
        )
    finally:
        if bar is not None:
            bar.close()
    attrs.update(executor=executor, chunks_computed=len(tasks), chunks_reused=reused)
    if contact is not None:
        attrs.update(_missing(values, phi, P1, Q1, plan["options"]))
    ds = dataset(values, phi, P1, Q1, attrs, plan["geometry"])
    ds.attrs["seconds"] = time.perf_counter() - t0
    if out is not None:
        write_dataset(ds, out)
        if chunk_store is not None and store == out.with_name(out.name + ".parts"):
            chunk_store.remove()  # everything is in ``out`` now
    return ds


def _plan(P1, Q1, phi, method, steps_per_cycle, contact) -> dict:
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


def _bytes(plan, n, chunks, phi, P1, Q1, scheduler, workers) -> float:
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


def _describe(plan, phi, P1, Q1, chunks):
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
            k_support_over_k_t0=options["k_support"],
            tol=options["tol"],
        )
        attrs.update({k: options[k] for k in ("nodes", "grid", "dims", "nu") if k in options})
    return description, key, attrs


def _missing(values, phi, P1, Q1, options) -> dict:
    """A contact map's NaN points: those that reached no steady state, and the loads without
    equilibrium."""
    from .contact_maps import unconverged_points

    grid = np.meshgrid(phi, P1, Q1, indexing="ij")
    nan = int(np.count_nonzero(np.isnan(values)))
    bad = unconverged_points(
        values,
        grid[1].ravel(),
        grid[2].ravel(),
        grid[0].ravel(),
        options["k_support"],
        options.get("dims", 1),
    )
    return {"unconverged_points": bad, "no_equilibrium_points": nan - bad}
