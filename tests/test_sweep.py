"""Sweeps: values, inputs, parallel and Dask runs, chunked saving and resuming, the map command."""

import json
import math
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from support import need_modules

need_modules("xarray")

from lcpfric.analysis.analytic import jang_barber  # noqa: E402
from lcpfric.errors import InputError  # noqa: E402
from lcpfric.exact import exact_W_hat  # noqa: E402
from lcpfric.analysis.sweep import sweep  # noqa: E402
from lcpfric.cli._grids import parse_grid, parse_phi_list  # noqa: E402
from lcpfric.methods import CLOSED_FORM, Method, register, unregister  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
AXIS = np.linspace(0.0, 4.0, 9)  # includes 0, 0.5, 1 (the régime borders) and 1.5
PHASES = np.array([0.0, 0.3, 0.6, 1.0, 2.0]) * math.pi / 2


def grid_method(name, func):
    """A registry entry with a grid form (closed form, so sweeps run it whole-chunk)."""
    return Method(
        name,
        CLOSED_FORM,
        "test method",
        "lcpfric.closed_form:ExactSolver",
        grid=func,
        seconds_per_point=1.2e-6,
    )


@pytest.fixture
def slow_exact():
    """The killed subprocess below runs "slow-exact" (exact with a pause per chunk, so that it
    can be killed mid-sweep); here the name is exact without the pause, so the restart is
    quick. Registered for the test only."""
    register(grid_method("slow-exact", exact_W_hat))
    yield
    unregister("slow-exact")


def test_dataset_layout_and_attrs():
    ds = sweep(AXIS, AXIS[:5], PHASES, progress=False)
    assert ds["W_hat"].dims == ("phi", "P1", "Q1")
    assert ds["W_hat"].shape == (PHASES.size, AXIS.size, 5)
    np.testing.assert_array_equal(ds["phi"], PHASES)
    assert ds.attrs["method"] == "exact"
    assert ds.attrs["chunks_computed"] == ds.attrs["chunks"]
    assert ds.attrs["lcpfric_version"]
    assert ds.attrs["seconds"] >= 0
    assert ds["phi"].attrs["units"] == "rad"


def test_exact_sweep_equals_jang_barber_at_phi0():
    P = np.linspace(0.0, 10.0, 41)
    ds = sweep(P, P, [0.0], progress=False)
    ref = jang_barber(P[:, None], P[None, :])
    np.testing.assert_allclose(ds["W_hat"].sel(phi=0.0).values, ref, rtol=1e-12, atol=1e-12)


def test_period_pi():
    # Ŵ(φ + π) = Ŵ(φ) exactly (Q -> -Q mirrors the cycle); the grid crosses the separation
    # onset P̂1 = 1 where both slip directions compete at re-contact.
    P = np.linspace(0.0, 3.0, 31)
    phi = np.linspace(0.0, math.pi, 13)
    a = sweep(P, P, phi, progress=False)["W_hat"].values
    b = sweep(P, P, phi + math.pi, progress=False)["W_hat"].values
    np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("method", ["exact", "explicit"])
def test_zero_amplitudes_give_zero(method):
    kw = {} if method == "exact" else {"steps_per_cycle": 64}
    ds = sweep([0.0, 0.5, 2.0], [0.0, 1.5], [0.0, 1.0], method=method, progress=False, **kw)
    W = ds["W_hat"]
    assert not np.isnan(W).any()
    np.testing.assert_array_equal(W.sel(Q1=0.0), 0.0)
    assert float(W.sel(P1=0.0, Q1=1.5, phi=1.0)) > 0  # P̂1 = 0 is an ordinary point


def test_per_point_method_matches_exact():
    ds = sweep(
        [0.5, 1.5],
        [2.0],
        [0.0, 0.6 * math.pi],
        method="explicit",
        steps_per_cycle=2000,
        progress=False,
    )
    ref = exact_W_hat(
        np.array([0.5, 1.5])[None, :, None], 2.0, np.array([0.0, 0.6 * math.pi])[:, None, None]
    )
    np.testing.assert_allclose(ds["W_hat"].values, ref, rtol=1e-4)
    assert ds.attrs["steps_per_cycle"] == 2000


def test_vectorized_registry_dispatch():
    calls = []

    def fake(P1, Q1, phi):
        calls.append(P1.size)
        return np.ones_like(P1)

    register(grid_method("fake", fake))
    try:
        ds = sweep([0.0, 1.0], [0.0, 1.0, 2.0], [0.0], method="fake", chunk_size=4, progress=False)
    finally:
        unregister("fake")
    assert calls == [4, 2]  # whole chunks, never point by point
    np.testing.assert_array_equal(ds["W_hat"].sel(Q1=0.0), 0.0)  # the Q̂1 = 0 limit is enforced
    np.testing.assert_array_equal(ds["W_hat"].sel(Q1=[1.0, 2.0]), 1.0)


@pytest.mark.parametrize(
    "kwargs, parameter",
    [
        ({"P1": [-1.0]}, "P1"),
        ({"Q1": [np.nan]}, "Q1"),
        ({"phi": [np.inf]}, "phi"),
        ({"P1": []}, "P1"),
        ({"Q1": [[1.0, 2.0]]}, "Q1"),
        ({"method": "no-such-method"}, "method"),
        ({"steps_per_cycle": 100}, "steps_per_cycle"),
        ({"method": "explicit", "steps_per_cycle": 2}, "steps_per_cycle"),
        ({"chunk_size": 0}, "chunk_size"),
        ({"processes": 0}, "processes"),
        ({"out": "/no/such/dir/x.nc"}, "out"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, parameter):
    args = {"P1": [1.0], "Q1": [1.0], "phi": [0.0], **kwargs}
    with pytest.raises(InputError) as info:
        sweep(args.pop("P1"), args.pop("Q1"), args.pop("phi"), progress=False, **args)
    assert info.value.parameter == parameter


def test_parse_grid_and_phases():
    np.testing.assert_allclose(parse_grid("0:10:11", "P1"), np.linspace(0, 10, 11))
    np.testing.assert_allclose(parse_grid("0.5, 1,2", "Q1"), [0.5, 1.0, 2.0])
    np.testing.assert_allclose(
        parse_phi_list("0,0.6pi,pi/2,1.2"), [0.0, 0.6 * math.pi, math.pi / 2, 1.2]
    )
    np.testing.assert_allclose(parse_phi_list("0:pi:3"), [0.0, math.pi / 2, math.pi])
    for text in ("0:10", "a:b:3", "0:1:0", ""):
        with pytest.raises(InputError):
            parse_grid(text, "P1")


def test_process_pool_equals_serial():
    P = np.linspace(0.0, 6.0, 13)
    serial = sweep(P, P, PHASES, processes=1, chunk_size=50, progress=False)
    pooled = sweep(P, P, PHASES, processes=2, chunk_size=50, progress=False)
    assert serial.attrs["executor"] == "serial"
    assert pooled.attrs["executor"].startswith("processes")
    np.testing.assert_array_equal(serial["W_hat"].values, pooled["W_hat"].values)


def test_dask_local_cluster_equals_serial():
    need_modules("dask.distributed")
    from dask import distributed

    P = np.linspace(0.0, 6.0, 13)
    serial = sweep(P, P, PHASES, processes=1, progress=False)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        with distributed.Client(cluster) as client:
            by_client = sweep(P, P, PHASES, scheduler=client, chunk_size=40, progress=False)
        by_address = sweep(
            P, P, PHASES, scheduler=cluster.scheduler_address, chunk_size=100, progress=False
        )
    for ds in (by_client, by_address):
        assert ds.attrs["executor"].startswith("dask")
        np.testing.assert_array_equal(ds["W_hat"].values, serial["W_hat"].values)


def test_bad_scheduler_address():
    need_modules("dask.distributed")
    with pytest.raises(InputError) as info:
        sweep([1.0], [1.0], [0.0], scheduler=42, progress=False)
    assert info.value.parameter == "scheduler"


class _Stop(Exception):
    pass


def test_resume_after_interruption(tmp_path):
    P = np.linspace(0.0, 5.0, 11)
    full = sweep(P, P, PHASES, progress=False)
    out = tmp_path / "map.nc"
    parts = tmp_path / "map.nc.parts"

    def stop_after_3(index, done, total):
        if done == 3:
            raise _Stop

    with pytest.raises(_Stop):
        sweep(
            P,
            P,
            PHASES,
            chunk_size=100,
            out=out,
            processes=1,
            progress=False,
            on_chunk=stop_after_3,
        )
    assert not out.exists()
    assert len(list(parts.glob("chunk-*.npy"))) == 3
    computed = []
    ds = sweep(
        P,
        P,
        PHASES,
        chunk_size=100,
        out=out,
        processes=1,
        progress=False,
        on_chunk=lambda i, done, total: computed.append(i),
    )
    total = math.ceil(P.size * P.size * PHASES.size / 100)
    assert ds.attrs["chunks"] == total
    assert ds.attrs["chunks_reused"] == 3 and ds.attrs["chunks_computed"] == total - 3
    assert len(computed) == total - 3
    np.testing.assert_array_equal(ds["W_hat"].values, full["W_hat"].values)
    assert out.exists() and not parts.exists()  # everything is in the file now
    again = sweep(P, P, PHASES, chunk_size=100, out=out, processes=1, progress=False)
    assert again.attrs["chunks_computed"] == 0  # read back, not recomputed
    np.testing.assert_array_equal(again["W_hat"].values, full["W_hat"].values)


def test_store_rejects_another_sweep_and_recovers_from_bad_chunks(tmp_path):
    store = tmp_path / "store"
    sweep([1.0, 2.0], [1.0, 3.0], [0.0, 1.0], chunk_size=2, store=store, progress=False)
    with pytest.raises(InputError) as info:
        sweep([1.0, 2.5], [1.0, 3.0], [0.0, 1.0], chunk_size=2, store=store, progress=False)
    assert info.value.parameter == "store"
    redone = sweep(
        [1.0, 2.5], [1.0, 3.0], [0.0, 1.0], chunk_size=2, store=store, resume=False, progress=False
    )
    assert redone.attrs["chunks_computed"] == 4
    chunk = store / "chunk-000001.npy"
    chunk.write_bytes(chunk.read_bytes()[:20])  # a damaged file is never trusted
    (store / ".chunk-000002.npy.abc.tmp").write_bytes(b"partial")  # left by a killed writer
    again = sweep([1.0, 2.5], [1.0, 3.0], [0.0, 1.0], chunk_size=2, store=store, progress=False)
    assert again.attrs["chunks_computed"] == 1 and again.attrs["chunks_reused"] == 3
    np.testing.assert_array_equal(again["W_hat"].values, redone["W_hat"].values)
    assert not list(store.glob(".*.tmp"))


def test_resume_after_killed_process(tmp_path, slow_exact):
    """A sweep process killed with SIGKILL mid-run: the restart computes only what is missing."""
    P = np.linspace(0.0, 4.0, 9)
    store = tmp_path / "store"
    script = textwrap.dedent(f"""
        import sys, time
        import numpy as np
        sys.path.insert(0, {str(ROOT)!r})
        from lcpfric.exact import exact_W_hat
        from lcpfric.analysis.sweep import sweep
        from lcpfric.methods import CLOSED_FORM, Method, register
        def slow(P1, Q1, phi):
            time.sleep(0.05)
            return exact_W_hat(P1, Q1, phi)
        register(Method("slow-exact", CLOSED_FORM, "test", "lcpfric.closed_form:ExactSolver",
                        grid=slow, seconds_per_point=1.2e-6))
        P = np.linspace(0.0, 4.0, 9)
        sweep(P, P, {PHASES.tolist()!r}, method="slow-exact", chunk_size=9, store={str(store)!r},
              processes=1, progress=False)
    """)
    proc = subprocess.Popen([sys.executable, "-c", script])
    try:
        deadline = time.monotonic() + 60
        while len(list(store.glob("chunk-*.npy"))) < 4:
            assert proc.poll() is None, "the sweep ended before it could be killed"
            assert time.monotonic() < deadline
            time.sleep(0.01)
    finally:
        proc.kill()
        proc.wait()
    saved = len(list(store.glob("chunk-*.npy")))
    total = P.size * P.size * PHASES.size // 9
    assert 4 <= saved < total
    ds = sweep(
        P, P, PHASES, method="slow-exact", chunk_size=9, store=store, progress=False, processes=1
    )
    assert ds.attrs["chunks_reused"] == saved
    assert ds.attrs["chunks_computed"] == total - saved
    np.testing.assert_array_equal(
        ds["W_hat"].values, sweep(P, P, PHASES, progress=False)["W_hat"].values
    )


def test_map_command(tmp_path, capsys):
    from lcpfric.cli import main

    out = tmp_path / "m.nc"
    code = main(
        [
            "map",
            "--P1",
            "0:2:5",
            "--Q1",
            "0,1,2",
            "--phi",
            "0,0.6pi,pi/2",
            "--out",
            str(out),
            "--no-progress",
            "--json",
        ]
    )
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["shape"] == {"phi": 3, "P1": 5, "Q1": 3}
    import xarray as xr

    from lcpfric.analysis.sweep import netcdf_engine

    ds = xr.load_dataset(out, engine=netcdf_engine())
    np.testing.assert_allclose(ds["phi"], [0.0, 0.6 * math.pi, math.pi / 2])
    np.testing.assert_allclose(
        ds["W_hat"].sel(phi=0.0).values,
        jang_barber(np.linspace(0, 2, 5)[:, None], [[0.0, 1.0, 2.0]]),
        atol=1e-12,
    )
    assert main(["map", "--P1", "0:2", "--Q1", "1", "--phi", "0", "--out", str(out)]) == 2
    assert "--P1" in capsys.readouterr().err
    assert main(["map", "--P1", "1", "--Q1", "1", "--phi", "0.6pie", "--out", str(out)]) == 2


def test_progress_bar_only_on_a_terminal(monkeypatch):
    need_modules("tqdm")
    import io

    from lcpfric.analysis import sweep as module

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    monkeypatch.setattr(sys, "stderr", Terminal())
    assert module._progress_bar(False, 3, 0, "exact") is None
    bar = module._progress_bar(True, 3, 1, "exact")
    assert bar is not None and bar.n == 1
    bar.close()
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert module._progress_bar(True, 3, 0, "exact") is None
