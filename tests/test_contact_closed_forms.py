"""The classical closed forms of lcpfric.model.continuum.closed_forms: consistent with each other
(Mindlin-Deresiewicz is the Ciavarella-Jäger chord area of the Hertz approach), with their
small-amplitude limits, and with the loads they carry (the Hertz pressures integrate to P)."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from lcpfric.model.continuum import (
    cattaneo_stick_ratio,
    ciavarella_jager_W,
    cylinder_contact,
    cylinder_W,
    hertz_contact,
    mindlin_deresiewicz_W,
    moduli,
)
from lcpfric.errors import InputError

E, NU, R, MU = 210e3, 0.3, 10.0, 0.4


def test_moduli_and_hertz_pressures_carry_the_load():
    m = moduli(E, NU)
    assert m["E*"] == pytest.approx(E / (2 * (1 - NU**2)))
    assert m["eta"] == pytest.approx(2 * (1 - NU) / (2 - NU))
    assert moduli(E, 0.0)["eta"] == 1.0
    P = 100.0
    h = hertz_contact(P, R, E, NU)
    assert h["a"] ** 3 == pytest.approx(3 * P * R / (4 * m["E*"]), rel=1e-14)
    load = quad(lambda r: h["p0"] * math.sqrt(1 - (r / h["a"]) ** 2) * 2 * math.pi * r, 0, h["a"])[
        0
    ]
    assert load == pytest.approx(P, rel=1e-10)
    assert h["k_t0"] == pytest.approx(2 * h["a"] * m["G*"])
    c = cylinder_contact(P, R, E, NU)
    assert quad(lambda x: c["p0"] * math.sqrt(1 - (x / c["a"]) ** 2), -c["a"], c["a"])[
        0
    ] == pytest.approx(P, rel=1e-10)


@pytest.mark.parametrize("x", [1e-3, 0.1, 0.25, 0.5, 0.9, 1.0])
def test_mindlin_deresiewicz_is_the_chord_area_of_the_hertz_approach(x):
    P = 100.0
    eta = moduli(E, NU)["eta"]
    k_t0 = hertz_contact(P, R, E, NU)["k_t0"]
    W = mindlin_deresiewicz_W(P, x * MU * P, MU, k_t0)
    W_cj = ciavarella_jager_W(
        lambda p: hertz_contact(p, R, E, NU)["d"] if p > 0 else 0.0, P, x * MU * P, MU, eta
    )
    assert W == pytest.approx(W_cj, rel=1e-9)


def test_small_amplitude_limits_and_the_series_switch():
    P, k = 2.0, 3.0
    for x in (1e-6, 1e-4):
        Q = x * MU * P
        assert mindlin_deresiewicz_W(P, Q, MU, k) == pytest.approx(
            2 * Q**3 / (9 * MU * P * k), rel=2 * x
        )
        Es = moduli(E, NU)["E*"]
        assert cylinder_W(P, Q, MU, E, NU) == pytest.approx(
            2 * Q**3 / (3 * math.pi * MU * Es * P), rel=2 * x
        )
    # the series and the closed form agree where one hands over to the other
    from lcpfric.model.continuum import closed_forms as cf

    x = cf._SERIES
    direct = 1 - (1 - x) ** (5 / 3) - (5 * x / 6) * (1 + (1 - x) ** (2 / 3))
    assert sum(c * x**j for j, c in enumerate(cf._MD_SERIES)) == pytest.approx(direct, rel=1e-12)
    direct = (1 - x) * math.log1p(-x) + x - x * x / 2
    assert sum(x**j / (j * (j - 1)) for j in range(3, cf._TERMS)) == pytest.approx(
        direct, rel=1e-12
    )
    # gross-slip limit: the bracket of the sphere is 1/6, of the cylinder 1/2
    assert mindlin_deresiewicz_W(P, MU * P, MU, k) == pytest.approx(36 / 5 * (MU * P) ** 2 / k / 6)


def test_cattaneo_and_errors():
    assert cattaneo_stick_ratio(0.0) == 1.0
    assert cattaneo_stick_ratio(0.875) == pytest.approx(0.5)
    assert cattaneo_stick_ratio(0.75, "cylinder") == pytest.approx(0.5)
    for bad, name in (
        (lambda: moduli(E, 0.5), "nu"),
        (lambda: moduli(-1, 0.3), "E"),
        (lambda: cattaneo_stick_ratio(1.2), "Q"),
        (lambda: cattaneo_stick_ratio(0.5, "cube"), "geometry"),
        (lambda: hertz_contact(0.0, R, E, NU), "P"),
        (lambda: mindlin_deresiewicz_W(1.0, np.nan, MU, 1.0), "Q"),
    ):
        with pytest.raises(InputError) as err:
            bad()
        assert err.value.parameter == name
