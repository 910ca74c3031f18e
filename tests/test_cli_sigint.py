"""``kill -INT`` of the main process of ``lcpfric map --processes 2`` (what ``timeout -s INT`` and
batch schedulers send; a Ctrl-C signals the whole process group instead): the command stops its
workers, exits 130 at once and keeps the finished chunks, and the same command resumes from them.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("xarray")
pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs POSIX signals, /proc"),
]

#: a map of 12 points, one per chunk, each a few seconds of projection: about 20 s on two cores
COMMAND = [
    "map",
    "--P1",
    "0.5:2:3",
    "--Q1",
    "0.5,1.5",
    "--phi",
    "0.5pi,0.6pi",
    "--method",
    "projection",
    "--steps",
    "30000",
    "--chunk-size",
    "1",
    "--processes",
    "2",
    "--no-progress",
]


def _start(out: Path) -> subprocess.Popen:
    """``python -m lcpfric map ...`` in its own session, with SIGINT at its default (a job
    started in the background of a non-interactive shell inherits SIGINT ignored)."""
    return subprocess.Popen(
        [sys.executable, "-m", "lcpfric", *COMMAND, "--out", str(out)],
        cwd=out.parent,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def _chunks(store: Path) -> dict:
    """The saved chunk files: name -> (size, mtime in ns)."""
    files = sorted(store.glob("chunk-*.npy")) if store.is_dir() else []
    return {f.name: (f.stat().st_size, f.stat().st_mtime_ns) for f in files}


def _wait_for_chunks(proc, store: Path, more_than: int, seconds: float = 120.0) -> float:
    """Wait until more than ``more_than`` chunks are saved; return the seconds waited."""
    t0 = time.monotonic()
    while len(_chunks(store)) <= more_than:
        assert proc.poll() is None, f"the map ended early: {proc.communicate()}"
        assert time.monotonic() - t0 < seconds, "no chunk was saved"
        time.sleep(0.05)
    return time.monotonic() - t0


def _descendants(pid: int) -> list[int]:
    """The processes below ``pid`` (psutil if installed, else /proc's parent ids)."""
    try:
        import psutil
    except ImportError:
        parents = {}
        for entry in Path("/proc").iterdir():
            if entry.name.isdigit():
                try:
                    stat = (entry / "stat").read_text()
                except OSError:
                    continue
                parents.setdefault(int(stat.rsplit(")", 1)[1].split()[1]), []).append(
                    int(entry.name)
                )
        found, todo = [], [pid]
        while todo:
            kids = parents.get(todo.pop(), [])
            found += kids
            todo += kids
        return found
    return [p.pid for p in psutil.Process(pid).children(recursive=True)]


def _running(pid: int) -> bool:
    """Whether ``pid`` is a live process (a zombie waiting to be reaped is not)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def _interrupt(proc, limit: float, sig=signal.SIGINT) -> tuple[int, float, str]:
    """``sig`` to the main process only; its exit code, the seconds it took, its stderr."""
    t0 = time.monotonic()
    os.kill(proc.pid, sig)
    try:
        proc.wait(timeout=limit)
    except subprocess.TimeoutExpired:
        pass
    seconds = time.monotonic() - t0
    code = proc.poll()
    return code, seconds, "" if code is None else proc.communicate()[1]


def _kill_all(proc, pids) -> None:
    for pid in [*pids, proc.pid]:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass
    proc.communicate()


def test_sigint_to_the_main_process_stops_the_workers_and_keeps_the_chunks(tmp_path):
    out = tmp_path / "map.nc"
    store = tmp_path / "map.nc.parts"
    proc = _start(out)
    workers = []
    try:
        first = _wait_for_chunks(proc, store, 0)
        workers = _descendants(proc.pid)
        assert workers, "no worker processes"
        # The chunks being computed take about as long as the first one did; the old code waited
        # for them (and for the one queued next). Stopping the workers takes a fraction of that.
        limit = min(10.0, max(2.0, 0.5 * first))
        code, seconds, err = _interrupt(proc, 10.0)
        assert code == 130 and seconds < limit, (code, seconds, limit, err)
        t0 = time.monotonic()
        while any(_running(p) for p in workers) and time.monotonic() - t0 < 2.0:
            time.sleep(0.05)
        assert not [p for p in workers if _running(p)], "worker processes left running"
    finally:
        if proc.poll() is None or any(_running(p) for p in workers):
            _kill_all(proc, workers)
    saved = _chunks(store)
    assert saved and f"interrupted: {len(saved)} finished chunks are saved" in err
    assert not out.exists()

    # The same command resumes: it keeps the saved chunks and computes the others; SIGTERM
    # (timeout's and schedulers' default) stops it as SIGINT does.
    again = _start(out)
    workers = []
    try:
        _wait_for_chunks(again, store, len(saved))
        workers = _descendants(again.pid)
        code, _, err = _interrupt(again, 10.0, signal.SIGTERM)
        assert code == 130 and "finished chunks are saved" in err, (code, err)
    finally:
        if again.poll() is None or any(_running(p) for p in workers):
            _kill_all(again, workers)
    now = _chunks(store)
    assert len(now) > len(saved)
    assert {name: now.get(name) for name in saved} == saved  # reused, not computed again
