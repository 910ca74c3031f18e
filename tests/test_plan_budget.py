"""The plan's byte budget (``plan_budget``): a scene whose contact set changes at almost every grid
instant runs in bounded memory, with the same answers whatever the budget; the problems dropped
are rebuilt (cold) and nothing else keeps them alive."""

import gc
import math
import tracemalloc
import weakref

import numpy as np
import pytest

from lcpfric import InputError, SingleNode, get_stepper, make_scene, steady_state
from lcpfric.backends import ScenePlan
from lcpfric.backends.problem import DEFAULT_PLAN_BUDGET
from lcpfric.model import chain

from support import need
from support import CASES

MIB = 2**20


def staggered(n: int, steps: int):
    """A chain whose nodes separate one after another (one normal phase per node, spread over
    the cycle): a different contact set at almost every grid instant."""
    system = chain(
        n,
        k_coupling=0.5,
        P0=1.0,
        P1=1.5,
        Q1=1.2,
        phi=0.6,
        normal_phase=np.linspace(0.0, 2.0 * np.pi, n, endpoint=False),
    )
    return make_scene(system, steps)


@pytest.fixture(scope="module")
def scene():
    scene = staggered(30, 120)
    assert len(set(map(bytes, scene.contact))) >= 50  # of ~150 grid instants
    return scene


@pytest.mark.parametrize("method", ["clarabel", "osqp", "qpsolvers:proxqp"])
def test_a_tiny_budget_gives_the_same_steady_state(scene, method):
    need(method)
    ref = steady_state(scene, method)
    tiny = steady_state(scene, method, plan_budget=1)
    assert ref.converged and tiny.converged and tiny.cycles == ref.cycles
    assert tiny.W == pytest.approx(ref.W, rel=1e-12, abs=0.0)
    assert np.allclose(tiny.v, ref.v, rtol=0.0, atol=1e-12)
    # the default budget holds every set: each problem built once, and reused every cycle
    sets = len(set(map(bytes, scene.contact)))
    assert ref.solver_stats["plans_evicted"] == 0
    assert ref.solver_stats["plans_built"] == sets
    assert ref.solver_stats["plan_peak_bytes"] <= DEFAULT_PLAN_BUDGET
    # a budget under one problem: one problem at a time, rebuilt whenever the set changes
    assert tiny.solver_stats["plans_built"] > ref.cycles * sets
    assert tiny.solver_stats["plans_evicted"] == tiny.solver_stats["plans_built"] - 1


@pytest.mark.slow
def test_cvxpy_with_a_tiny_budget_gives_the_same_cycle(scene):
    """cvxpy compiles a problem when it is built: one cycle, not a steady state."""
    need("cvxpy:CLARABEL")
    W = []
    for budget in (DEFAULT_PLAN_BUDGET, 1):
        stepper = get_stepper("cvxpy:CLARABEL", plan_budget=budget)
        state, cyc = stepper.cycle(scene, stepper.init(scene))
        W.append(cyc.W)
    assert W[1] == pytest.approx(W[0], rel=1e-12, abs=0.0)
    assert cyc.stats["plans_evicted"] == cyc.stats["plans_built"] - 1 > 0


@pytest.mark.parametrize("method", ["clarabel", "osqp"])
def test_the_plan_holds_what_its_budget_allows(scene, method):
    need(method)
    stepper = get_stepper(method)
    full = ScenePlan(scene).problems.get(np.ones(scene.system.n, dtype=bool))
    # a few of the largest problems, with their solvers and two operators each
    budget = 3 * (full.nbytes + stepper.handle_bytes(full) + 2 * full.operator_bytes)
    stepper = get_stepper(method, plan_budget=budget)
    state = stepper.init(scene)
    built = []  # every problem built, by weak reference
    build = stepper.build
    stepper.build = lambda prob, settings: built.append(weakref.ref(prob)) or build(prob, settings)
    for _ in range(2):
        state, cyc = stepper.cycle(scene, state)
        problems = state.data.plan.problems
        held = problems.held()
        assert 1 <= len(held) < len(set(map(bytes, scene.contact)))
        assert problems.nbytes == sum(p.nbytes for p in held) <= budget
        assert problems.peak_bytes <= budget
        assert cyc.stats["plan_peak_bytes"] == problems.peak_bytes
        assert cyc.stats["plans_evicted"] > 0
    # nothing per grid instant keeps a dropped problem alive
    del held, cyc
    gc.collect()
    alive = [r() for r in built if r() is not None]
    assert len(built) > len(alive) and all(p in problems.held() for p in alive)


def test_a_budget_below_one_problem_keeps_the_problem_in_use(scene):
    need("clarabel")
    stepper = get_stepper("clarabel", plan_budget=1)
    state, cyc = stepper.cycle(scene, stepper.init(scene))
    problems = state.data.plan.problems
    assert len(problems) == 1 and problems.held()[0].handle is not None
    ref = get_stepper("clarabel")
    assert cyc.W == pytest.approx(ref.cycle(scene, ref.init(scene))[1].W, rel=1e-12, abs=0.0)


def test_the_operators_are_held_under_the_budget(scene):
    """The refinement's active-set operators count in the budget: the least recently used are
    dropped first, the problem in use is kept."""
    row = scene.contact[0]
    plan = ScenePlan(scene)
    prob = plan.problems.get(row)
    base = prob.nbytes
    plan = ScenePlan(scene, budget=base + 2 * prob.operator_bytes)
    problems = plan.problems
    prob = problems.get(row)
    patterns = [np.arange(prob.size) % k == 0 for k in (2, 3, 4, 5)]
    for at in patterns:
        prob.active_set_operator(at)
        assert problems.nbytes == prob.nbytes <= problems.budget
    assert len(prob._ops) == 2  # the two most recent patterns
    assert patterns[-1].tobytes() in prob._ops and patterns[0].tobytes() not in prob._ops
    # a new set drops this one: the problem in use is the new one
    other = problems.get(scene.contact[len(scene.contact) // 2])
    assert problems.held() == [other] and problems.evicted == 1


def test_the_single_node_fast_path_with_a_tiny_budget():
    need("clarabel")
    node = SingleNode.normalized(*CASES["separation"])
    ref = steady_state(node, "clarabel", 300)
    tiny = steady_state(node, "clarabel", 300, plan_budget=1)
    assert tiny.W == ref.W
    assert tiny.solver_stats["plans_built"] == ref.solver_stats["plans_built"] == 1


@pytest.mark.slow
def test_peak_memory_stays_within_the_budget():
    """n = 200 nodes separating one after another (~200 contact sets of up to 200 unknowns):
    their problems alone would take hundreds of MiB; the traced peak of a cycle stays within
    the budget plus what the scene itself needs (its C, K and per-instant vectors)."""
    need("osqp")
    scene = staggered(200, 50)
    contact = scene.contact
    rows = {row.tobytes(): row for row in contact}
    assert len(rows) > 150
    m = scene.system.m
    unbounded = sum(8 * s * (s + m) for s in (int(r.sum()) for r in rows.values()))
    budget, overhead = 8 * MIB, 12 * MIB
    assert unbounded > 3 * (budget + overhead)  # P and Cf alone, without solvers or operators
    stepper = get_stepper("osqp", plan_budget=budget)
    gc.collect()
    tracemalloc.start()
    try:
        state, cyc = stepper.cycle(scene, stepper.init(scene))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert cyc.stats["plans_evicted"] > 0 and cyc.stats["plan_peak_bytes"] <= budget
    assert peak < budget + overhead, f"traced peak {peak / MIB:.1f} MiB"


@pytest.mark.parametrize("bad", [0, 0.5, -1, math.nan, "64M", True, None, 1j])
def test_an_invalid_budget_is_refused(bad):
    need("clarabel")
    with pytest.raises(InputError, match=r"plan_budget.*\[1, inf\]") as err:
        get_stepper("clarabel", plan_budget=bad)
    assert err.value.parameter == "plan_budget"


def test_an_unbounded_budget_is_accepted():
    need("clarabel")
    assert get_stepper("clarabel", plan_budget=math.inf).plan_budget == math.inf
    assert get_stepper("clarabel", plan_budget=2**40).plan_budget == 2.0**40
