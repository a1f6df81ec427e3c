"""The compiled game (``crates/plansynth-core/src/arena/``) against its pure-Python
reference (:class:`plansynth.grid.native.arena.Arena` with ``use_rust=False``): the same
layers in the same order, the same backward induction, winning-forward layers, strategy
read off the game, allowed moves and closure, on random small problems (walls, ``via``
cells, diagonal moves, several obstacles)."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.budget import Budget, BudgetExhausted
from plansynth.grid.native import stationary
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.cone import influence_cone, with_relevant

from .strategies import grid_problems, problems_and_programs

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "grid"

small = grid_problems(max_side=5, max_obstacles=3, max_obstacle_moves=3, max_robot_moves=6, max_steps=5)


def _pair(problem, read_all: bool):
    steps = problem.steps
    cone = influence_cone(problem, steps)
    read = tuple(range(len(problem.obstacles))) if read_all else cone.relevant
    cone = with_relevant(cone, read)
    fast = Arena.build(problem, steps, cone, read, use_rust=True)
    ref = Arena.build(problem, steps, cone, read, use_rust=False)
    assert fast._core is not None and ref._core is None
    return fast, ref


def _ordered(layers):
    return [list(layer.items()) for layer in layers]


@settings(max_examples=150, deadline=None)
@given(small, st.booleans())
def test_the_compiled_game_is_the_reference_game(problem, read_all):
    fast, ref = _pair(problem, read_all)
    assert _ordered(fast.layers) == _ordered(ref.layers)  # same states, same order
    assert fast.config_count() == ref.config_count() and fast.state_count() == ref.state_count()
    assert fast.start_alive() == ref.start_alive()
    if not ref.start_alive():
        return
    won = ref.solve_game()
    assert fast.solve_game() == won
    assert _ordered(fast.win) == _ordered(ref.win)
    for t in range(problem.steps):
        for oc in ref.layers[t]:
            assert fast.winning_moves(t, oc) == ref.winning_moves(t, oc)
            assert fast.successors(oc) == ref.successors(oc)
    if not won:
        return
    fwd = stationary.winning_forward(fast)
    assert _ordered(fwd) == _ordered(stationary.winning_forward_reference(ref))
    got, want = stationary.consistent_strategy(fast, fwd), stationary.consistent_strategy(ref, fwd)
    assert (got is None) == (want is None)
    if want is not None:
        assert got.allowed == want.allowed and _ordered(got.reach) == _ordered(want.reach)
    allowed_f, allowed_r = stationary._allowed(fast, fwd), stationary._allowed(ref, fwd)
    assert allowed_f == allowed_r
    usable = {s: a for s, a in allowed_r.items() if a}
    if len(usable) == len(allowed_r):
        assert _ordered(stationary._closure(fast, usable)) == _ordered(stationary._closure(ref, usable))


def test_the_compiled_game_keeps_its_memory_limit_and_names_it():
    """A 30x30 field with four obstacles that never stop outgrows 64 MB within a few
    steps; the limit is checked against the bytes the game's structures hold."""
    from plansynth.grid.problem import load_grid_problem

    problem = load_grid_problem(EXAMPLES / "field30.yaml")
    cone = influence_cone(problem, problem.steps)
    with pytest.raises(BudgetExhausted, match="memory budget of 64 MB") as info:
        Arena.build(
            problem, problem.steps, cone, cone.relevant, Budget(seconds=60).clock(), memory_mb=64, use_rust=True
        )
    assert (info.value.phase, info.value.resource) == ("exploring the game", "memory")
    with pytest.raises(BudgetExhausted, match="out of time") as info:
        Arena.build(problem, problem.steps, cone, cone.relevant, Budget(seconds=0.2).clock(), use_rust=True)
    assert (info.value.phase, info.value.resource) == ("exploring the game", "time")


def _crossing_core():
    """The compiled game of examples/grid/crossing.yaml (the car is read), as the core's
    own object, unexplored; and the problem."""
    from plansynth.grid.native.arena import _compiled
    from plansynth.grid.problem import load_grid_problem

    problem = load_grid_problem(EXAMPLES / "crossing.yaml")
    cone = influence_cone(problem, problem.steps)
    arena = Arena.build(problem, problem.steps, cone, cone.relevant, explore=False)
    return arena._compiled_game(_compiled()), problem


def test_every_budgeted_call_of_the_compiled_core_raises_the_shared_budget_exhausted():
    """The binding raises plansynth.budget.BudgetExhausted itself (not a return code or a
    TimeoutError), naming the phase and the resource, for each call that takes a
    budget; given enough, the same calls answer."""
    core, problem = _crossing_core()
    width = problem.width
    for limits, resource in (
        ({"seconds": 0.0}, "time"),
        ({"memory": 1}, "memory"),
        ({"max_configs": 0}, "configurations"),
    ):
        with pytest.raises(BudgetExhausted) as info:
            _crossing_core()[0].explore(**limits)
        assert type(info.value) is BudgetExhausted  # the Python class itself, imported by the binding
        assert (info.value.phase, info.value.resource) == ("exploring the game", resource), info.value
    core.explore()
    with pytest.raises(BudgetExhausted, match="solving the game at step") as info:
        core.solve_game(seconds=0.0)
    assert info.value.resource == "time"
    assert core.solve_game() is True
    with pytest.raises(BudgetExhausted, match="following winning moves at step") as info:
        core.winning_forward(seconds=0.0)
    assert info.value.resource == "time"
    with pytest.raises(BudgetExhausted, match="following winning moves at step .*memory budget") as info:
        core.winning_forward(memory=1)
    assert info.value.resource == "memory"
    forward = core.winning_forward()
    calls = {
        "reading a strategy off the game": lambda seconds: core.consistent(width, seconds),
        "the allowed moves of the strategy": lambda seconds: core.allowed(forward, seconds),
    }
    for phase, call in calls.items():
        with pytest.raises(BudgetExhausted, match=f"^{phase}: out of time$") as info:
            call(0.0)
        assert (info.value.phase, info.value.resource) == (phase, "time")
        assert call(None) is not None
    allowed = core.allowed(forward)
    with pytest.raises(BudgetExhausted, match="^the states the strategy reaches: out of time$"):
        core.closure(allowed, 0.0)
    assert len(core.closure(allowed)) == problem.steps + 1


def test_the_engine_answers_unknown_when_the_compiled_game_runs_out():
    """The compiled core's BudgetExhausted reaches the engine as the shared class: the
    answer is unknown, naming the phase (never unrealizable, never an exception)."""
    from plansynth.grid.native.engine import Engine
    from plansynth.grid.problem import load_grid_problem
    from plansynth.grid.result import GridStatus

    problem = load_grid_problem(EXAMPLES / "field30.yaml")
    out = Engine(use_rust=True).solve_length(problem, problem.steps, Budget(seconds=60, memory_mb=64))
    assert out.status is GridStatus.UNKNOWN and out.program is None
    assert out.message.startswith("budget exhausted: exploring the game at step"), out.message
    assert "memory budget of 64 MB" in out.message, out.message


@settings(max_examples=150, deadline=None)
@given(problems_and_programs(max_depth=5, max_side=4, max_obstacles=2, max_steps=4))
def test_the_program_check_on_the_compiled_game_agrees_with_the_game_graph_and_the_verifier(pp):
    from plansynth.grid.native.check import ArenaCheck, GameGraph
    from plansynth.grid.verify import verify

    problem, program = pp
    fast, ref = _pair(problem, read_all=True)
    wins = verify(problem, program, problem.steps).wins
    if not ref.start_alive() or not ref.solve_game():
        assert not wins
        return
    assert fast.solve_game()
    got = ArenaCheck(fast).check(program)
    want = GameGraph.from_arena_reference(ref).check_reference(program)
    assert (got is None) == (want is None) == wins
