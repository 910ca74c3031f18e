"""Where the chunks of a sweep run: in this process, in local worker processes, or on Dask.

Each runner takes the tasks ``{index: args}`` and a module-level function ``compute(*args)``, and
calls ``on_result(index, values)`` in *this* process as each chunk finishes, in whatever order they
finish. The caller stores the chunk there, so the workers need no shared file system and a chunk
counts as done only once it is on disk. If ``on_result`` raises, or the user interrupts, the
chunks not yet started are cancelled, the local workers are stopped (those still computing a
chunk too) and the exception propagates: the finished ones are kept.

Interrupting the local pool: its workers ignore SIGINT, so a Ctrl-C (which the terminal sends to
the whole process group) and a ``kill -INT`` of the main process alone (what ``timeout -s INT``
and batch schedulers send) act the same way: the main process gets ``KeyboardInterrupt``,
terminates its workers and re-raises at once, without waiting for the chunks being computed.
"""

from __future__ import annotations

import os
import re
import signal
import warnings
from typing import Callable

from .._optional import require
from ..errors import InputError

__all__ = ["run_serial", "run_processes", "run_dask", "default_workers"]

#: a scheduler address: [tcp://|tls://|inproc://]host:port
_ADDRESS = re.compile(r"^(?:(?:tcp|tls|ucx)://)?\[?[A-Za-z0-9_.:-]+\]?:\d{1,5}$|^inproc://\S+$")


def default_workers() -> int:
    """All the cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def run_serial(tasks: dict, compute: Callable, on_result: Callable) -> str:
    for index, args in tasks.items():
        on_result(index, compute(*args))
    return "serial"


def _ignore_sigint() -> None:
    """In a worker: leave Ctrl-C to the parent, which cancels the chunks not yet started, and
    let SIGTERM end the worker (the parent's handler, inherited by a fork, must not)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _stop_workers(pool) -> None:
    """Cancel what has not started and terminate ``pool``'s workers now.

    ``shutdown(wait=False, cancel_futures=True)`` alone leaves the chunks already handed to a
    worker running (and those in the executor's call queue), and the interpreter joins the
    pool's threads at exit: a ``kill -INT`` of the main process would then wait for them, since
    the workers ignore SIGINT. This is ``ProcessPoolExecutor.terminate_workers`` of Python 3.14.
    """
    terminate = getattr(pool, "terminate_workers", None)
    if terminate is not None:  # pragma: no cover - Python >= 3.14
        terminate()
        return
    processes = dict(getattr(pool, "_processes", None) or {})  # shutdown() clears it
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in processes.values():
        try:
            if proc.is_alive():
                proc.terminate()
        except (ValueError, ProcessLookupError):  # already ended, or closed
            pass


def _run_pool(remaining: dict, compute: Callable, on_result: Callable, workers: int) -> None:
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    pool = ProcessPoolExecutor(max_workers=workers, initializer=_ignore_sigint)
    pending = {}
    try:
        for index, args in remaining.items():
            pending[pool.submit(compute, *args)] = index
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                index = pending.pop(fut)
                on_result(index, fut.result())
                del remaining[index]
    except BaseException:
        # Cancel each future ourselves (a cancelled future is never started even if the pool
        # object lingers), then stop the workers: nothing computed from here on would be saved.
        for fut in pending:
            fut.cancel()
        _stop_workers(pool)
        raise
    pool.shutdown(wait=True)


def run_processes(
    tasks: dict, compute: Callable, on_result: Callable, workers: int, restarts: int = 2
) -> str:
    """Run on a local process pool; a pool broken by a killed worker is restarted ``restarts``
    times for the chunks not yet finished."""
    from concurrent.futures.process import BrokenProcessPool

    workers = max(1, min(workers, len(tasks)))
    remaining = dict(tasks)
    for attempt in range(restarts + 1):
        try:
            _run_pool(remaining, compute, on_result, workers)
            break
        except BrokenProcessPool:
            if attempt == restarts:
                raise
            warnings.warn(
                f"a sweep worker process died; restarting the pool for the "
                f"{len(remaining)} unfinished chunks",
                RuntimeWarning,
                stacklevel=2,
            )
    return f"processes:{workers}"


def connect(scheduler):
    """A ``dask.distributed.Client`` for ``scheduler`` (a Client, or a scheduler address).

    Returns ``(client, owned)``; ``owned`` is True when the caller must close the client.
    """
    Client = require("dask.distributed", "dist", "Dask distributed sweeps").Client
    if isinstance(scheduler, Client):
        return scheduler, False
    if not isinstance(scheduler, str) or not _ADDRESS.match(scheduler.strip()):
        raise InputError(
            "scheduler",
            "must be a dask.distributed.Client or a scheduler address "
            f"such as tcp://10.0.0.5:8786, got {scheduler!r}",
        )
    try:
        return Client(scheduler.strip(), timeout="20s"), True
    except Exception as exc:  # OSError, TimeoutError, and whatever a non-Dask peer provokes
        raise InputError(
            "scheduler",
            f"cannot connect to the Dask scheduler at {scheduler!r}: {type(exc).__name__}: {exc}",
        ) from exc


def run_dask(tasks: dict, compute: Callable, on_result: Callable, scheduler) -> str:
    """Submit every chunk to a Dask cluster; a lost worker's chunks are rescheduled by Dask."""
    from dask.distributed import as_completed

    client, owned = connect(scheduler)
    futures = {}
    try:
        for index, args in tasks.items():
            futures[client.submit(compute, *args, pure=False)] = index
        for fut, values in as_completed(list(futures), with_results=True):
            on_result(futures[fut], values)
    except BaseException:
        client.cancel(list(futures))
        raise
    finally:
        address = getattr(client.scheduler, "address", "") or "client"
        if owned:
            client.close()
    return f"dask:{address}"
