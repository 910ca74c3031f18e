"""The reported "plateau": on ``chain(2, k_coupling=1, Q1=(2, 2), phi=(0, π/2))`` every time
stepper stays 6.24e-8 (relative) below ``exact`` at 800, 1600, 3200 and 6400 steps.

``exact`` is right: it equals the independent event-driven reference
(:mod:`support.coupled_reference`, B = 0) and the closed form ``W = 4(√5 - 1)`` to rounding
(f N = 1, so W is the travel of both nodes: per half cycle node 1 goes from ``±(1 - √20/3)``
at t* to its opposite at π + t*, node 0 from ``∓√5/3`` at π/2 to its opposite at 3π/2, and
``W = 2 (2 (√20/3 - 1) + 2√5/3)``).

The steppers' error is their load sampling at the instant where node 1 (counting from 0) stops
slipping. While both nodes slip, ``u = K⁻¹(F - Q)`` with F on the limits, and node 1 stops at
the extremum of ``(K⁻¹Q)_1 = (2 sin t + 4 cos t)/3``, at ``t* = arctan(1/2)`` (and π + t*). A
stepper sees the loads interpolated linearly between grid points, so its node stops at a grid
point, short by ``(√20 - max over the two grid points around t* of (2 sin t + 4 cos t))/3``:
about ``½ |u''| δ²`` with δ the distance from t* to the nearer of them. The grids of 800·2^j
steps (j = 0..3) all have 59·2π/800 (δ = 2.63e-4) as that point, so their error is the same;
12800 puts one 2.28e-4 after t*, 25600 one 1.7e-5 before it. With t* and π + t* added to the
grid the steppers equal ``exact`` to rounding, at 100 steps already.
"""

from __future__ import annotations

import numpy as np
import pytest

import lcpfric
from support import need
from lcpfric.scene import Scene, make_scene

from support.coupled_reference import Reference

W_CLOSED = 4.0 * (np.sqrt(5.0) - 1.0)
T_STOP = np.arctan(0.5)  # node 1 stops slipping (both slipped before), and at π + T_STOP


def chain():
    return lcpfric.chain(2, k_coupling=1, Q1=(2, 2), phi=(0, np.pi / 2))


def test_exact_equals_the_independent_reference():
    s = chain()
    W = lcpfric.steady_state(s, method="exact").W
    # Q_i = 2 sin(t + φ_i): rows (mean, sin, cos); P_i = 1
    ref = Reference(s.stiffness, np.zeros((2, 2)), s.friction, [[0, 2, 0], [0, 0, 2]],
                    [[1, 0, 0], [1, 0, 0]])  # fmt: skip
    W_ref = ref.steady(np.zeros(2))[0]
    assert W == pytest.approx(W_ref, rel=1e-12, abs=0)
    assert W == pytest.approx(W_CLOSED, rel=1e-12, abs=0)


def test_the_steppers_error_is_the_sampling_of_the_stop():
    need("clarabel")
    s = chain()
    exact = lcpfric.steady_state(s, method="exact", steps_per_cycle=800)
    runs = {n: lcpfric.steady_state(s, method="explicit", steps_per_cycle=n) for n in (800, 1600)}
    runs["clarabel"] = lcpfric.steady_state(s, method="clarabel", steps_per_cycle=800)
    for r in runs.values():  # one discrete problem, one answer: the plateau
        assert r.W == pytest.approx(runs[800].W, rel=1e-13, abs=0)
    assert 1 - runs[800].W / exact.W == pytest.approx(6.2418e-8, rel=1e-4)
    # node 1's displacement after the stop, against its shortfall from the grid around t*
    r = runs[800]
    j = int(np.searchsorted(r.t, T_STOP)) - 1
    h = 2 * np.sin(r.t[j : j + 2]) + 4 * np.cos(r.t[j : j + 2])
    short = (np.sqrt(20.0) - h.max()) / 3
    assert short == pytest.approx(5.1435e-8, rel=1e-4)
    after = (r.t > T_STOP + 0.01) & (r.t < 1.5)  # node 1 sticks there
    assert np.all(r.state[after, 1] == 0)
    np.testing.assert_allclose(np.abs(r.v[after, 1] - exact.v[after, 1]), short, rtol=1e-6)


@pytest.mark.parametrize("n", [100, 800])
def test_the_stop_on_the_grid_gives_exact(n):
    s = chain()
    t = np.union1d(make_scene(s, n).t, [T_STOP, np.pi + T_STOP])
    Q = np.column_stack([q(t) for q in s.tangential_loads])
    scene = Scene(s, None, t, Q, np.ones((t.size, 2)), np.array([]), "uniform")
    r = lcpfric.steady_state(scene, method="explicit")
    assert r.W == pytest.approx(W_CLOSED, rel=1e-13, abs=0)
