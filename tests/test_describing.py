"""Describing functions of the Jenkins element (issue 39, item 3): constant N against the notes'
closed forms (evaluated in 50 digits) to 1e-12 over amplitudes from 0.5 to 1000 slip limits, the
shakedown below the slip limit, and a varying normal load against the independent event solver
and the fine-sample return map."""

import json
import math

import numpy as np
import pytest

from lcpfric.analysis.describing import (
    DescribingFunctions,
    describing_functions,
    jenkins_closed_form,
)
from lcpfric.errors import InputError
from lcpfric.model.jenkins import JenkinsElement
from support import fitted_order, need_modules
from support.jenkins_reference import return_map_cycle

ELEMENTS = [(1.0, 1.0, 1.0), (2.3, 0.37, 5.1), (1e3, 0.2, 7.0)]


def _mp_closed_form(kt, mu, N, a):
    """k_eq, ω c_eq, W of the notes in 50 digits (the doubles given taken as exact)."""
    import mpmath as mp

    mp.mp.dps = 50
    kt, Fs, a = mp.mpf(kt), mp.mpf(mu) * mp.mpf(N), mp.mpf(a)
    if a <= Fs / kt:
        return float(kt), 0.0, 0.0
    tau = mp.acos(1 - 2 * Fs / (kt * a))
    return (
        float(kt / mp.pi * (tau - mp.sin(2 * tau) / 2)),
        float(4 * Fs / (mp.pi * a) * (1 - Fs / (kt * a))),
        float(4 * Fs * (a - Fs / kt)),
    )


@pytest.mark.parametrize("method", ["single-node", "driven"])
@pytest.mark.parametrize("params", ELEMENTS)
def test_constant_normal_load_against_the_closed_forms(params, method):
    """200 amplitudes from 0.5 to 1000 slip limits: k_eq, ω c_eq and W within 1e-12 relative
    (measured: k_eq 1.8e-13, ω c_eq and W 5e-15)."""
    need_modules("mpmath")
    el = JenkinsElement(*params)
    a = el.slip_limit * np.geomspace(0.5, 1000.0, 200)
    df = describing_functions(el, a, method=method)
    ref = np.array([_mp_closed_form(*params, ai) for ai in a])
    slips = ref[:, 2] > 0
    assert np.max(np.abs(df.k_eq / ref[:, 0] - 1)) < 1e-12
    assert np.max(np.abs(df.c_eq_omega[slips] / ref[slips, 1] - 1)) < 1e-12
    assert np.max(np.abs(df.W[slips] / ref[slips, 2] - 1)) < 1e-12
    # the quadrature harmonic of the cycle is -W/(π a), the identity W = π a² ω c_eq
    c_from_B = -df.force_sin[:, 1] / a
    assert np.max(np.abs(c_from_B[slips] / ref[slips, 1] - 1)) < 1e-12
    np.testing.assert_allclose(df.force_amplitude, np.minimum(el.kt * a, el.mu * el.N0),
                               rtol=1e-13)  # fmt: skip


def test_small_amplitudes_stick():
    """Below the slip limit: k_eq = kt, c_eq = 0, W = 0, loss factor 0, whatever the start."""
    el = JenkinsElement(2.0, 0.5, 3.0)
    a = el.slip_limit * np.array([0.01, 0.5, 0.999, 1.0])
    for start in (None, 0.2):
        for method in ("single-node", "driven"):
            df = describing_functions(el, a, start=start, method=method)
            np.testing.assert_allclose(df.k_eq, el.kt, rtol=1e-15)
            assert np.all(df.c_eq_omega == 0.0) and np.all(df.W == 0.0)
            assert np.all(df.loss_factor == 0.0)


def test_the_closed_form_keeps_its_digits():
    need_modules("mpmath")
    a = np.geomspace(0.5, 1e4, 300)
    cf = jenkins_closed_form(1.0, 1.0, 1.0, a)
    ref = np.array([_mp_closed_form(1.0, 1.0, 1.0, ai) for ai in a])
    assert np.max(np.abs(cf["k_eq"] / ref[:, 0] - 1)) < 1e-14
    np.testing.assert_allclose(cf["loss_factor"], cf["c_eq_omega"] / cf["k_eq"])


VARYING = [
    JenkinsElement(1.0, 0.6, 1.0, N1=0.5, phi=0.0),
    JenkinsElement(1.0, 0.6, 1.0, N1=0.5, phi=0.5 * math.pi),
    JenkinsElement(1.5, 0.3, 2.0, N1=3.0, phi=2.0),  # separates
    JenkinsElement(1.0, 0.6, 1.0, kn=10.0, un1=0.08, phi=-1.0),
]


@pytest.mark.parametrize("el", VARYING, ids=lambda e: repr(e))
def test_varying_normal_load_two_exact_paths(el):
    """The exact single node and the event solver: W and the first harmonics agree to 1e-12
    (goal 1e-9) over amplitudes from 0.3 to 300 slip limits."""
    a = el.slip_limit * np.geomspace(0.3, 300.0, 40)
    one = describing_functions(el, a, harmonics=3)
    two = describing_functions(el, a, harmonics=3, method="driven")
    scale = el.mu * (el.N0 + el.N1)
    assert np.max(np.abs(one.W - two.W) / (scale * a)) < 1e-12
    assert np.max(np.abs(one.force_cos - two.force_cos)) / scale < 1e-12
    assert np.max(np.abs(one.force_sin - two.force_sin)) / scale < 1e-12
    np.testing.assert_allclose(one.k_eq, two.k_eq, rtol=1e-11, atol=1e-12 * el.kt)
    np.testing.assert_allclose(one.force_amplitude, two.force_amplitude, rtol=1e-12)


def test_varying_normal_load_against_the_return_map():
    """The fine-sample return map converges to the exact W and first harmonics at second order
    (error x n² bounded)."""
    el = VARYING[2]
    a = 5.0 * el.slip_limit
    df = describing_functions(el, [a])
    x = el.motion(a)
    N = el.normal_load()
    steps = [1000, 2000, 4000, 8000, 16000]
    errors = []
    for n in steps:
        ref = return_map_cycle(el.kt, el.mu, x, N, 2 * math.pi, n, start=0.0)
        errors.append(
            max(
                abs(ref["W"] - df.W[0]),
                abs(ref["force_cos"][1] - df.force_cos[0, 1]),
                abs(ref["force_sin"][1] - df.force_sin[0, 1]),
            )
        )
    assert max(e * n * n for e, n in zip(errors, steps)) < 200.0
    assert fitted_order(steps, errors) > 1.7


def test_the_varying_load_changes_the_answer():
    """With N1 the steady cycle is not the constant-N one: W differs, and the phase matters."""
    a = np.array([3.0])
    base = describing_functions(JenkinsElement(1.0, 1.0, 1.0), a)
    w0 = describing_functions(JenkinsElement(1.0, 1.0, 1.0, N1=0.5, phi=0.0), a)
    w1 = describing_functions(JenkinsElement(1.0, 1.0, 1.0, N1=0.5, phi=math.pi / 2), a)
    assert abs(w0.W[0] - base.W[0]) > 1e-3 and abs(w1.W[0] - w0.W[0]) > 1e-3


def test_results_as_json():
    el = JenkinsElement(1.0, 1.0, 1.0)
    df = describing_functions(el, [0.5, 2.0, 8.0], harmonics=3)
    assert isinstance(df, DescribingFunctions) and df.force_cos.shape == (3, 4)
    out = json.loads(json.dumps(df.as_dict(harmonics=True)))
    assert out["k_eq"][0] == 1.0 and out["W"][1] == pytest.approx(4.0)
    assert len(out["force_cos"]) == 3 and len(out["force_cos"][0]) == 4
    # odd harmonics only under constant N (half-wave symmetry)
    assert np.max(np.abs(df.force_cos[:, [0, 2]])) < 1e-13


def test_no_friction():
    df = describing_functions(JenkinsElement(1.0, 0.0, 1.0), [1.0, 2.0])
    assert df.method == "driven"
    assert np.all(df.k_eq == 0.0) and np.all(df.W == 0.0) and np.all(np.isnan(df.loss_factor))
    assert df.as_dict()["loss_factor"] == [None, None]


@pytest.mark.parametrize(
    ("args", "kwargs", "name"),
    [
        (([0.0],), {}, "amplitude"),
        (([1.0, -2.0],), {}, "amplitude"),
        (([float("nan")],), {}, "amplitude"),
        (([],), {}, "amplitude"),
        (([1.0],), dict(harmonics=0), "harmonics"),
        (([1.0],), dict(method="fft"), "method"),
        (([1.0],), dict(omega=0.0), "omega"),
        (([1.0],), dict(start=float("inf")), "start"),
    ],
)
def test_bad_input_is_refused_by_name(args, kwargs, name):
    with pytest.raises(InputError, match=f"^{name}: "):
        describing_functions(JenkinsElement(1.0, 1.0, 1.0), *args, **kwargs)


def test_the_figure(tmp_path):
    """A column wide, no text under 7 pt, the closed form in the legend, TrueType in the PDF."""
    need_modules("matplotlib")
    from lcpfric.figures.describing import figure_describing_functions
    from lcpfric.figures.style import COLUMN_WIDTH, MIN_FONT_SIZE, save
    from support import renderer, texts

    a = np.geomspace(0.3, 1000.0, 40)
    marks = np.geomspace(0.3, 1000.0, 9)
    fig = figure_describing_functions(
        [("constant N", describing_functions(JenkinsElement(1.0, 0.6, 1.0), a)),
         ("varying N", describing_functions(VARYING[1], a))],
        kt=1.0,
        slip_limit=0.6,
        closed=(marks, jenkins_closed_form(1.0, 0.6, 1.0, marks)),
    )  # fmt: skip
    renderer(fig)
    assert fig.get_size_inches()[0] <= COLUMN_WIDTH
    assert min(t.get_fontsize() for t in texts(fig)) >= MIN_FONT_SIZE
    assert all(ax.get_xscale() == ax.get_yscale() == "log" for ax in fig.axes)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["constant N", "varying N", "closed form (constant N)"]
    (pdf,) = save(fig, tmp_path, "describing", ("pdf",))
    data = pdf.read_bytes()
    assert b"/FontFile2" in data and b"/Type3" not in data
