"""Progress of long runs (issue 35, item 14): the driver's ``progress`` hook reports every cycle
and changes no bit of the result; the CLI's reporter draws a bar on a terminal, writes lines
otherwise, and nothing when it is off."""

import io
import math
import subprocess
import sys

import numpy as np
import pytest

import lcpfric
from lcpfric import SingleNode, steady_state
from lcpfric.cli._progress import Progress
from lcpfric.errors import InputError
from lcpfric.model import chain
from lcpfric.model.continuum import HalfSpace, MDRSphere
from lcpfric.model.loads import Harmonic
from lcpfric.periodic.driver import DRIVER_OPTIONS, CycleProgress

P, Q = Harmonic(1.0, 0.5), Harmonic(0.0, 0.3, 0.5 * np.pi)
CASES = {
    "single node, projection": (SingleNode.normalized(0.5, 2.0, 0.6 * np.pi), "projection", 200),
    "single node, barely slipping": (SingleNode.normalized(1e-6, 1.0, 0.0), "explicit", 400),
    "chain, active set": (
        chain(5, k_coupling=2.0, k_ground=0.5, P1=0.5, Q1=1.5),
        "active-set",
        100,
    ),
    "MDR sphere": (MDRSphere(1.0, 1.0, 0.0, 0.5, P, Q, nodes=100), None, 100),
    # d = 2: early cycles solved loosely, their change ignored until full accuracy
    "half-space, d = 2": (HalfSpace.sphere(1.0, 1.0, 0.0, 0.5, P, Q, grid=12, dims=2), None, 40),
}


def _same(x, y, name="result") -> None:
    """Two results equal to the bit (all but the wall times)."""
    if isinstance(x, np.ndarray):
        assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes(), name
    elif isinstance(x, dict):
        assert x.keys() == y.keys(), name
        for k in x:
            if "seconds" not in k:
                _same(x[k], y[k], f"{name}[{k!r}]")
    elif hasattr(x, "__dict__"):
        assert type(x) is type(y), name
        for k, v in vars(x).items():
            if k != "seconds":
                _same(v, getattr(y, k), f"{name}.{k}")
    elif isinstance(x, float) and math.isnan(x):
        assert math.isnan(y), name
    else:
        assert x == y, name


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_hook_sees_every_cycle_and_changes_no_bit(name):
    model, method, steps = CASES[name]
    plain = steady_state(model, method, steps)
    records = []
    watched = steady_state(model, method, steps, progress=records.append)
    _same(plain, watched)
    assert [r.cycle for r in records] == list(range(1, plain.cycles + 1))
    assert all(isinstance(r, CycleProgress) for r in records)
    assert math.isinf(records[0].change)
    assert [r.change for r in records[1:]] == list(plain.changes)
    assert [r.W for r in records] == list(plain.W_cycles)
    assert records[-1].change == plain.change and records[-1].W == plain.W
    assert {(r.tol, r.max_cycles) for r in records} == {(1e-10, model.default_max_cycles)}


def test_the_hook_reports_the_cycles_of_a_run_that_does_not_converge():
    model, method, steps = CASES["half-space, d = 2"]
    records = []
    r = steady_state(
        model, method, steps, max_cycles=3, on_nonconvergence="ignore", progress=records.append
    )
    assert not r.converged and [x.cycle for x in records] == [1, 2, 3]
    assert records[-1] == CycleProgress(3, r.change, 1e-10, 3, r.W)


def test_the_hook_is_checked_and_may_stop_the_run():
    node = SingleNode.normalized(0.5, 2.0, 0.6 * np.pi)
    with pytest.raises(InputError) as err:
        steady_state(node, "projection", 200, progress="yes")
    assert err.value.parameter == "progress" and "callable" in str(err.value)
    assert "progress" in DRIVER_OPTIONS

    def stop(record):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        steady_state(node, "projection", 200, progress=stop)
    calls = []
    steady_state(node, "exact", 200, progress=calls.append)  # a closed form: no cycles
    assert calls == []


# -- the CLI's reporter ----------------------------------------------------------------------------
def _record(n, change=2.1e-4, tol=1e-10, max_cycles=200):
    return CycleProgress(n, change, tol, max_cycles, 0.5)


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_lines_without_a_terminal():
    log = io.StringIO()
    with Progress(True, what="contact", stream=log, delay=0.0, interval=0.0) as reporter:
        reporter.stage("building the model")
        reporter.cycle(_record(1, math.inf))
        reporter.cycle(_record(2, 3.0e-3))
        reporter.cycle(_record(3))
        reporter.stage("writing the figures")
    assert log.getvalue().splitlines() == [
        "contact: building the model",
        "contact: cycle 1 of at most 200 (tol 1e-10)",
        "contact: cycle 2: residual 3.0e-03 (tol 1e-10)",
        "contact: cycle 3: residual 2.1e-04 (tol 1e-10)",
        "contact: writing the figures",
    ]
    reporter.close()  # twice is harmless
    assert log.getvalue().count("\n") == 5


def test_a_quick_run_writes_no_cycle_and_a_long_one_ends_with_its_last():
    log = io.StringIO()
    quick = Progress(True, stream=log, delay=60.0)
    for n in range(1, 5):
        quick.cycle(_record(n))
    quick.close()
    assert log.getvalue() == ""
    # lines at most one per interval, and the last cycle always written at the end
    throttled = Progress(True, stream=log, delay=0.0, interval=60.0)
    for n in range(1, 5):
        throttled.cycle(_record(n, 10.0**-n))
    throttled.close()
    assert log.getvalue().splitlines() == [
        "cycle 1: residual 1.0e-01 (tol 1e-10)",
        "cycle 4: residual 1.0e-04 (tol 1e-10)",
    ]


def test_disabled_writes_nothing(capsys):
    reporter = Progress(False, what="contact", delay=0.0, interval=0.0)
    reporter.stage("building the model")
    reporter.cycle(_record(1))
    reporter.close()
    assert capsys.readouterr() == ("", "")


def test_stderr_by_default_never_stdout(capsys, monkeypatch):
    monkeypatch.setattr("lcpfric.cli._progress.DELAY", 0.0)  # what a CLI test may do
    reporter = Progress(True, what="contact")
    reporter.cycle(_record(2))
    reporter.close()
    assert capsys.readouterr() == ("", "contact: cycle 2: residual 2.1e-04 (tol 1e-10)\n")


def test_a_bar_on_a_terminal():
    pytest.importorskip("tqdm")
    screen = _Terminal()
    with Progress(True, what="contact", stream=screen, delay=0.0) as reporter:
        for n in range(1, 4):
            reporter.cycle(_record(n, 10.0**-n))
        reporter.stage("writing the figures")
    text = screen.getvalue()
    assert "contact: 3 cycles [" in text and "residual 1.0e-03 (tol 1e-10)" in text
    assert text.endswith("contact: writing the figures\n")
    quiet = _Terminal()
    with Progress(True, what="contact", stream=quiet, delay=60.0) as reporter:
        reporter.cycle(_record(1))
    assert quiet.getvalue() == ""  # a quick run draws no bar


def test_lines_on_a_terminal_without_tqdm(monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)  # import tqdm now fails
    screen = _Terminal()
    with Progress(True, stream=screen, delay=0.0, interval=0.0) as reporter:
        reporter.cycle(_record(5))
    assert screen.getvalue() == "cycle 5: residual 2.1e-04 (tol 1e-10)\n"


def test_the_reporter_follows_the_driver():
    log = io.StringIO()
    model, method, steps = CASES["MDR sphere"]
    with Progress(True, what="contact", stream=log, delay=0.0, interval=0.0) as reporter:
        r = steady_state(model, method, steps, progress=reporter.cycle)
    lines = log.getvalue().splitlines()
    assert len(lines) == r.cycles and lines[0].startswith("contact: cycle 1 of at most")
    assert lines[-1] == f"contact: cycle {r.cycles}: residual {r.change:.1e} (tol 1e-10)"


def test_the_module_imports_only_the_standard_library():
    code = (
        "import sys; import lcpfric.cli._progress; "
        "print(sorted(m for m in ('numpy', 'tqdm', 'lcpfric.periodic') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
    assert lcpfric.steady_state is steady_state
