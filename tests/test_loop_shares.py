"""The shares of the cycle's time in each state (`state_shares`, `lcpfric loop`): time shares on
any grid, so the steppers' default event-adapted placement, which crosses a whole separation in
one step, agrees with the closed form's exact shares (issue 35)."""

import json

import pytest

from lcpfric import InputError, SingleNode, State, steady_state
from lcpfric.analysis.loop import state_shares, time_shares
from lcpfric.cli import main

from support import CASES

STEPS = 4000


def test_time_shares_weigh_each_increment_by_its_duration():
    shares = time_shares([0.0, 1.0, 4.0, 5.0], [3, 0, 3, 1])  # states over the increments' ends
    assert shares == {
        State.STICK: 0.2,
        State.FORWARD: 0.2,
        State.BACKWARD: 0.0,
        State.SEPARATION: 0.6,
    }
    for t, s in (([0.0], [0]), ([0.0, 1.0], [0]), ([1.0, 0.0], [0, 0])):
        with pytest.raises(InputError, match="t"):
            time_shares(t, s)


@pytest.mark.parametrize("case", ["separation", "contact-phase"])
def test_stepper_shares_are_the_exact_time_shares(case):
    node = SingleNode.normalized(*CASES[case])
    exact = state_shares(steady_state(node, "exact", STEPS), model=node)  # from the events
    assert sum(exact.values()) == pytest.approx(1.0, abs=1e-12)
    assert (exact[State.SEPARATION] > 0.25) == (case == "separation")
    sampled = state_shares(steady_state(node, "exact", STEPS))  # the sampled series
    for method in ("explicit", "projection"):
        res = steady_state(node, method, STEPS)  # default placement: event-adapted
        got = state_shares(res)
        for state in State:  # to a few steps' length (1/4000 of the cycle each)
            assert got[state] == pytest.approx(exact[state], abs=0.01), (method, state)
            assert sampled[state] == pytest.approx(exact[state], abs=0.01), state


def test_shares_of_a_system_node_add_up_to_one():
    from lcpfric.model import chain

    system = chain(2, k_coupling=0.7, P1=1.4, Q1=2.0, phi=1.0, normal_phase=[0, 0.8])
    res = steady_state(system, "explicit", 400)
    for node in (0, 1):
        assert sum(state_shares(res, node).values()) == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(InputError, match="node"):
        state_shares(res, 2)


def test_loop_command_prints_time_shares(capsys):
    """The issue's case: 26.8 % of the cycle is separation, whatever the method."""
    case = ["loop", "--P1", "1.5", "--Q1", "2", "--phi", "0.6pi", "--steps", str(STEPS)]
    expected = {"stick": 0.412, "forward slip": 0.315, "backward slip": 0.005, "separation": 0.268}
    for method in ("explicit", "projection", "exact"):
        assert main([*case, "--method", method, "--json"]) == 0
        shares = json.loads(capsys.readouterr().out)["shares"]
        assert list(shares) == list(expected)
        for state, share in expected.items():
            assert shares[state] == pytest.approx(share, abs=0.002), (method, state)
    assert main([*case, "--method", "explicit"]) == 0
    assert "separation 26.8%" in capsys.readouterr().out
