"""Hertz maps (lcpfric.analysis.contact_maps): the batched MDR equals MDRSphere point by point; NaN
where pure load control has no equilibrium; the small-amplitude law W ∝ Q1³; sweeps with resume."""

import numpy as np
import lcpfric
import pytest

from support import need_modules

from lcpfric.analysis.contact_maps import mdr_W_normalized
from lcpfric.model.continuum import MDRSphere
from lcpfric.errors import InputError
from lcpfric.model import Harmonic

POINTS = [(0.5, 0.4, 0.5), (0.0, 0.5, 0.0), (1.5, 0.6, 0.3), (0.9, 0.8, 2.0), (0.3, 0.2, 0.0)]


@pytest.mark.parametrize("ks", [0.0, 0.5])
def test_batch_equals_the_model_point_by_point(ks):
    P1, Q1, phi = (np.array(c) for c in zip(*POINTS))
    got = mdr_W_normalized(
        P1, Q1, phi, nodes=120, steps_per_cycle=120, k_support_ratio=ks, tol=1e-10
    )
    k_t0 = MDRSphere(10.0, 200e3, 0.3, 0.5, 100.0, 0.0, nodes=10).k_t0
    for (p1, q1, ph), w in zip(POINTS, got):
        m = MDRSphere(
            10.0,
            200e3,
            0.3,
            0.5,
            Harmonic(100.0, 100 * p1),
            Harmonic(0.0, 50 * q1, ph),
            nodes=120,
            k_support=ks * k_t0,
        )
        if ks == 0.0 and np.isnan(w):  # gross sliding under load control: refused there too
            with pytest.raises(InputError):
                lcpfric.steady_state(m, steps_per_cycle=120)
            continue
        assert w == pytest.approx(
            lcpfric.steady_state(m, steps_per_cycle=120, tol=1e-10).W_normalized, rel=1e-9
        )
    assert np.isnan(got).sum() == (2 if ks == 0.0 else 0)


def test_zero_amplitude_and_small_amplitude_law():
    """Q̂1 = 0 gives 0; at fixed Q1/(μ P1) and φ, W grows as Q1³ (ratio 8 per doubling)."""
    assert mdr_W_normalized([0.5], [0.0], [0.3])[0] == 0.0
    q = np.array([0.01, 0.02, 0.04])
    w = mdr_W_normalized(q / 0.8, q, np.full(3, 1.5), nodes=4000, steps_per_cycle=200, tol=1e-10)
    np.testing.assert_allclose(w[1:] / w[:-1], 8.0, rtol=0.02)


def test_sweep_of_a_contact_map_resumes(tmp_path):
    need_modules("xarray")
    from lcpfric.analysis.sweep import sweep

    P1, Q1, phi = np.linspace(0, 2, 4), np.linspace(0, 1, 3), [0.0, 0.3 * np.pi]
    spec = {"k_support_ratio": 1.0, "nodes": 60}
    ds = sweep(P1, Q1, phi, contact=spec, steps_per_cycle=60, progress=False)
    pp, qq = np.meshgrid(P1, Q1, indexing="ij")
    direct = mdr_W_normalized(
        pp.ravel(),
        qq.ravel(),
        np.full(pp.size, 0.3 * np.pi),
        nodes=60,
        steps_per_cycle=60,
        k_support_ratio=1.0,
    )
    np.testing.assert_array_equal(ds.W_normalized.sel(phi=0.3 * np.pi).values.ravel(), direct)
    out = tmp_path / "m.nc"

    class Stop(Exception):
        pass

    def stop(index, done, total):
        raise Stop

    with pytest.raises(Stop):
        sweep(
            P1,
            Q1,
            phi,
            contact=spec,
            steps_per_cycle=60,
            progress=False,
            out=out,
            chunk_size=6,
            processes=1,
            on_chunk=stop,
        )
    again = sweep(
        P1,
        Q1,
        phi,
        contact=spec,
        steps_per_cycle=60,
        progress=False,
        out=out,
        chunk_size=6,
        processes=1,
    )
    assert again.attrs["chunks_reused"] == 1 and again.attrs["chunks_computed"] == 3
    np.testing.assert_array_equal(again.W_normalized.values, ds.W_normalized.values)


def test_points_that_do_not_converge_are_reported_never_returned():
    """A map point that reaches no steady state in max_cycles is NaN (never its last cycle's
    value, as lcpfric 0.1 returned it), counted in a ConvergenceWarning, or an error on
    request; the MDR batch and the half-space map alike."""
    from lcpfric.analysis.contact_maps import halfspace_W_normalized
    from lcpfric.errors import ConvergenceError, ConvergenceWarning

    P1, Q1, phi = np.array([0.5, 0.3, 0.5]), np.array([0.4, 0.2, 0.0]), np.array([0.5, 0.0, 0.0])
    with pytest.warns(ConvergenceWarning, match=r"2 of 3 points reached no periodic steady"):
        got = mdr_W_normalized(P1, Q1, phi, nodes=40, steps_per_cycle=40, max_cycles=1)
    assert np.isnan(got[:2]).all() and got[2] == 0.0  # Q̂1 = 0: the limit 0
    with pytest.raises(ConvergenceError, match="2 of 3 points"):
        mdr_W_normalized(
            P1, Q1, phi, nodes=40, steps_per_cycle=40, max_cycles=1, on_nonconvergence="raise"
        )
    ok = mdr_W_normalized(P1, Q1, phi, nodes=40, steps_per_cycle=40)
    assert np.isfinite(ok).all()
    with pytest.warns(ConvergenceWarning, match=r"1 of 1 half-space map points"):
        hs = halfspace_W_normalized(
            np.array([0.3]),
            np.array([0.3]),
            np.array([0.5]),
            grid=10,
            steps_per_cycle=20,
            max_cycles=1,
        )
    assert np.isnan(hs).all()


def test_sweep_counts_the_points_that_do_not_converge(tmp_path, capsys):
    """A contact map whose points cannot converge (one cycle allowed): NaN there, and the
    dataset and the command line's summary say how many, apart from the loads without
    equilibrium."""
    need_modules("xarray")
    from lcpfric.analysis.sweep import sweep
    from lcpfric.cli.map import _report

    ds = sweep(
        [0.5, 1.5],
        [0.2, 0.3],
        [0.0],
        contact={"nodes": 20, "max_cycles": 1},
        steps_per_cycle=8,
        progress=False,
    )
    # P̂1 = 1.5 separates under pure load control: no equilibrium while Q ≠ 0
    assert ds.attrs["no_equilibrium_points"] == 2 and ds.attrs["unconverged_points"] == 2
    assert int(ds.W_normalized.isnull().sum()) == 4
    _report(ds, tmp_path / "m.nc", False)
    line = capsys.readouterr().out
    assert "NaN at 4 points (2 without equilibrium, 2 that reached no steady state)" in line
    assert "no point has a W_normalized" in line
