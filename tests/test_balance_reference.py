"""Harmonic balance (``lcpfric.harmonic.forced_response``) against a time-domain reference: one
mass with a Jenkins element, the steady cycle integrated event by event by DOP853
(tests/support/jenkins_oscillator_reference.py). The first harmonic converges with H (measured
6.1e-3, 1.8e-4, 3.7e-6 at H = 1, 5, 11 near ω = 1.2; the full table with its orders:
benchmarks/perf/frc_chain.py)."""

import numpy as np

from lcpfric.harmonic import forced_response
from support.jenkins_oscillator_reference import steady_cycle


def test_the_first_harmonic_converges_with_the_harmonics():
    m, c, k0, kt, mu, N, f = 1.0, 0.02, 1.0, 1.0, 0.3, 1.0, 0.5
    errors = []
    for H, ns in ((1, 256), (5, 256), (11, 512)):
        r = forced_response(m, c, k0, f, (1.0, 1.4), contacts=(0,), kt=kt, mu=mu,
                            normal_load=N, harmonics=H, samples=ns)  # fmt: skip
        i = int(np.argmin(np.abs(r.omega - 1.2)))
        a1, b1, _, _ = steady_cycle(m, c, k0, kt, mu * N, f, r.omega[i])
        co = r.coefficients[i, 0]
        errors.append(np.hypot(co[1] - a1, co[2] - b1) / np.hypot(a1, b1))
    assert errors[0] > 10 * errors[1] > 100 * errors[2]
    assert errors[2] < 1e-5
