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
  default size depends only on the grid and the method, so a sweep resumes on any machine
  (:mod:`.sweep_plan`: what the chunks run and how the grid is cut).
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

import sys
import time
from typing import Callable

import numpy as np

from .. import _checks, memory
from .._optional import require
from ..errors import InputError, LcpfricError
from .chunkstore import ChunkStore
from .runners import default_workers, run_dask, run_processes, run_serial
from .sweep_io import (
    check_output,
    dataset,
    netcdf_engine,
    read_dataset,
    write_dataset,
    xarray_module,
)
from .sweep_plan import (
    PARALLEL_SECONDS,
    chunk_bounds,
    describe_sweep,
    per_point_W_hat,
    plan_sweep,
    sweep_memory,
)

__all__ = ["sweep", "per_point_W_hat", "write_dataset", "netcdf_engine"]


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
    unique, counts = np.unique(arr, return_counts=True)
    if unique.size < arr.size:  # a coordinate twice: xarray could not select it
        raise InputError(
            name, f"the value {unique[counts > 1][0]:g} is given more than once; give each once"
        )
    return arr.astype(float)


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
    pays = seconds > PARALLEL_SECONDS if processes is None else processes > 1
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
        Reuse finished chunks in ``store`` (and an existing ``out`` of the same sweep; an
        existing ``out`` that holds anything else is refused, not overwritten). False discards
        them and computes everything, overwriting ``out``.
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
        200, "k_support_ratio": 0.0, "tol": 1e-8}`` (the defaults) gives ``W_normalized = W k_t0 /
        (μ² P0²)`` of the Hertz contact by dimensionality reduction
        (:func:`lcpfric.analysis.contact_maps.mdr_W_normalized`) over ``P1 = P1/P0``,
        ``Q1 = Q1/(μ P0)`` and φ, with ``k_support_ratio`` in units of k_t0 and ``steps_per_cycle``
        200 by default. ``{"model": "halfspace", "grid": 20, "dims": 1, "nu": 0.0,
        "k_support_ratio": 0.0, "tol": 1e-8}`` (its defaults; ``steps_per_cycle`` 100) maps the same
        quantity on the half-space boundary elements
        (:func:`lcpfric.analysis.contact_maps.halfspace_W_normalized`). NaN marks loads that
        have no equilibrium under pure load control (``k_support_ratio = 0`` and ``|Q| > μ P`` at
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
    plan = plan_sweep(P1, Q1, phi, method, steps_per_cycle, contact)
    if processes is not None:
        processes = _checks.positive_int("processes", processes)
    out = None if out is None else check_output(out)
    xarray_module()  # fail before any work if the dist extra is missing
    t0 = time.perf_counter()
    n = phi.size * P1.size * Q1.size
    workers = processes or default_workers()
    chunks = chunk_bounds(n, chunk_size, plan["cost"], plan["batched"])
    memory.check(*sweep_memory(plan, chunks, phi, P1, Q1, scheduler, workers))
    description, key, attrs = describe_sweep(plan, phi, P1, Q1, chunks)
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
        held = (
            "a map computed with other parameters"
            if old is not None and "fingerprint" in old.attrs
            else "no lcpfric map"
        )
        raise InputError(
            "out",
            f"{str(out)!r} exists and holds {held}; it is not overwritten: choose another "
            "file, or compute it again with resume=False (lcpfric map --restart)",
        )
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
        options["k_support_ratio"],
        options.get("dims", 1),
    )
    return {"unconverged_points": bad, "no_equilibrium_points": nan - bad}
