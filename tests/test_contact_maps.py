"""Hertz maps (lcpfric.analysis.contact_maps): the batched MDR equals MDRSphere point by point; NaN where
pure load control has no equilibrium; the small-amplitude law W ∝ Q1³; sweeps with resume."""

import numpy as np
import lcpfric
import pytest

from lcpfric.analysis.contact_maps import mdr_W_normalized
from lcpfric.model.continuum import MDRSphere
from lcpfric.errors import InputError
from lcpfric.model import Harmonic

POINTS = [(0.5, 0.4, 0.5), (0.0, 0.5, 0.0), (1.5, 0.6, 0.3), (0.9, 0.8, 2.0), (0.3, 0.2, 0.0)]


@pytest.mark.parametrize("ks", [0.0, 0.5])
def test_batch_equals_the_model_point_by_point(ks):
    P1, Q1, phi = (np.array(c) for c in zip(*POINTS))
    got = mdr_W_normalized(P1, Q1, phi, nodes=120, steps_per_cycle=120, k_support=ks, tol=1e-10)
    k_t0 = MDRSphere(10.0, 200e3, 0.3, 0.5, 100.0, 0.0, nodes=1).k_t0
    for (p1, q1, ph), w in zip(POINTS, got):
        m = MDRSphere(10.0, 200e3, 0.3, 0.5, Harmonic(100.0, 100 * p1),
                      Harmonic(0.0, 50 * q1, ph), nodes=120, k_support=ks * k_t0)
        if ks == 0.0 and np.isnan(w):  # gross sliding under load control: refused there too
            with pytest.raises(InputError):
                lcpfric.steady_state(m, steps_per_cycle=120)
            continue
        assert w == pytest.approx(lcpfric.steady_state(m, steps_per_cycle=120, tol=1e-10).W_normalized, rel=1e-9)
    assert np.isnan(got).sum() == (2 if ks == 0.0 else 0)


def test_zero_amplitude_and_small_amplitude_law():
    """Q̂1 = 0 gives 0; at fixed Q1/(μ P1) and φ, W grows as Q1³ (ratio 8 per doubling)."""
    assert mdr_W_normalized([0.5], [0.0], [0.3])[0] == 0.0
    q = np.array([0.01, 0.02, 0.04])
    w = mdr_W_normalized(q / 0.8, q, np.full(3, 1.5), nodes=4000, steps_per_cycle=200,
                         tol=1e-10)
    np.testing.assert_allclose(w[1:] / w[:-1], 8.0, rtol=0.02)


def test_sweep_of_a_contact_map_resumes(tmp_path):
    pytest.importorskip("xarray")
    from lcpfric.analysis.sweep import sweep

    P1, Q1, phi = np.linspace(0, 2, 4), np.linspace(0, 1, 3), [0.0, 0.3 * np.pi]
    spec = {"k_support": 1.0, "nodes": 60}
    ds = sweep(P1, Q1, phi, contact=spec, steps_per_cycle=60, progress=False)
    pp, qq = np.meshgrid(P1, Q1, indexing="ij")
    direct = mdr_W_normalized(pp.ravel(), qq.ravel(), np.full(pp.size, 0.3 * np.pi), nodes=60,
                              steps_per_cycle=60, k_support=1.0)
    np.testing.assert_array_equal(ds.W_normalized.sel(phi=0.3 * np.pi).values.ravel(), direct)
    out = tmp_path / "m.nc"

    class Stop(Exception):
        pass

    def stop(index, done, total):
        raise Stop

    with pytest.raises(Stop):
        sweep(P1, Q1, phi, contact=spec, steps_per_cycle=60, progress=False, out=out,
              chunk_size=6, processes=1, on_chunk=stop)
    again = sweep(P1, Q1, phi, contact=spec, steps_per_cycle=60, progress=False, out=out,
                  chunk_size=6, processes=1)
    assert again.attrs["chunks_reused"] == 1 and again.attrs["chunks_computed"] == 3
    np.testing.assert_array_equal(again.W_normalized.values, ds.W_normalized.values)
