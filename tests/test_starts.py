"""lcpfric.analysis.starts: the steady states over many starts (issue 38, item 3)."""

from __future__ import annotations

import numpy as np
import pytest

import lcpfric
from lcpfric.analysis.starts import explore_starts, start_from_ratios
from lcpfric.errors import InputError
from lcpfric.model import ContactSystem, Harmonic, IndependentSprings


def _system(K, B, f, P0, P1, psi, Q1, phi):
    n = len(f)
    return ContactSystem(
        np.asarray(K, float),
        np.asarray(f, float),
        tuple(Harmonic(0.0, Q1[i], phi[i], 1.0) for i in range(n)),
        IndependentSprings(tuple(Harmonic(P0[i], P1[i], psi[i], 1.0) for i in range(n))),
        coupling=None if B is None else np.asarray(B, float),
    )


K3 = [[4.0, -1.0, 0.5], [-1.0, 3.0, -1.0], [0.5, -1.0, 5.0]]
ARGS = ([0.5, 0.6, 0.4], [4.0, 3.5, 4.5], [1.0, 0.5, 1.2], [0.0, 1.0, 2.0], [2.5, 2.0, 2.8],
        [0.3, 2.0, 4.0])  # fmt: skip


def test_uncoupled_system_has_one_steady_w_from_every_start():
    """Melan and its cyclic counterpart: B = 0 gives one W whatever the start."""
    s = _system(K3, None, *ARGS)
    study = explore_starts(s, 25, seed=3)
    assert study.unique
    assert study.W_max - study.W_min <= 1e-9 * study.W_max
    assert len(study.branches) == 1 and study.branches[0].count == 25


def test_coupled_system_reports_the_range_and_its_ends():
    B = [[0.9, -1.2, 0.4], [1.1, 0.3, -0.8], [-0.5, 0.9, 1.0]]
    s = _system(K3, B, *ARGS)
    study = explore_starts(s, 30, seed=1)
    assert study.W.shape == (30,) and study.starts.shape == (30, 3)
    assert np.all(np.abs(study.ratios) <= 1.0)
    # the ends of the range are reproduced from the starts reported
    for j, W in ((study.start_min, study.W_min), (study.start_max, study.W_max)):
        again = lcpfric.steady_state(s, "exact", 64, u0=study.starts[j])
        assert again.W == pytest.approx(W, rel=1e-12, abs=1e-14)
    assert sum(b.count for b in study.branches) == 30
    assert all(b.shakedown == (not b.slipping) for b in study.branches)
    d = study.as_dict()
    assert set(d) >= {"W", "W_min", "W_max", "shakedown", "branches", "unique"}


def test_mobilization_ratios_give_those_forces():
    B = [[0.9, -1.2, 0.4], [1.1, 0.3, -0.8], [-0.5, 0.9, 1.0]]
    s = _system(K3, B, *ARGS)
    r = np.array([0.7, -0.9, 0.1])
    u = start_from_ratios(s, r)
    F = s.tangential(0.0) + s.dense_stiffness() @ u
    N = s.normal.loads_at(0.0) + np.asarray(B) @ u
    assert np.allclose(F, r * s.friction * N, atol=1e-13)


def test_given_starts_are_checked_by_row():
    s = _system(K3, None, *ARGS)
    with pytest.raises(InputError, match="row 1") as exc:
        explore_starts(s, [[0.0, 0.0, 0.0], [50.0, 0.0, 0.0]])
    assert exc.value.parameter == "starts"
    with pytest.raises(InputError, match="k x 3"):
        explore_starts(s, [[0.0, 0.0]])
    with pytest.raises(InputError) as exc:
        explore_starts(s, 0)
    assert exc.value.parameter == "starts"


def test_start_map_and_band_and_their_figure(tmp_path):
    pytest.importorskip("matplotlib")
    from support import texts

    from lcpfric.analysis.starts import coupling_band, start_map
    from lcpfric.figures.starts import figure_start_dependence
    from lcpfric.figures.style import MIN_FONT_SIZE, PAGE_WIDTH

    s = _system([[2.824, 0.764], [0.764, 2.740]], [[0.952, -0.096], [-0.015, -1.532]],
                [0.625, 0.407], [4.314, 3.202], [0.951, 0.334], [4.160, 5.216], [1.442, 1.429],
                [3.388, 1.351])  # fmt: skip
    r, W, still = start_map(s, 5)
    assert W.shape == (5, 5) and np.all(still == (W == 0))
    assert np.nanmin(W) == 0 < np.nanmax(W)  # shakes down from some starts only
    c = np.array([0.0, 1.0])
    lo, hi, share = coupling_band(s, c, starts=12)
    assert lo[0] == pytest.approx(hi[0], rel=1e-9)  # uncoupled: one W (Melan)
    assert hi[1] - lo[1] > 0.1 * hi[1]
    fig = figure_start_dependence(r, W, still, c, lo, hi, share)
    assert fig.get_figwidth() <= PAGE_WIDTH + 1e-9
    assert min(t.get_fontsize() for t in texts(fig)) >= MIN_FONT_SIZE
    fig.savefig(tmp_path / "f.pdf")
    pdf = (tmp_path / "f.pdf").read_bytes()
    assert b"/CIDFontType2" in pdf or b"/TrueType" in pdf
    with pytest.raises(InputError, match="two-node"):
        start_map(_system(K3, None, *ARGS))
