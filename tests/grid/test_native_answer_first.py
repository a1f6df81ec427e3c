"""The answer-first engine: the game-graph check (Python and Rust) against the
independent verifier, and winning programs from the default and --minimize paths."""

from __future__ import annotations

import time
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.budget import Budget
from plansynth.grid.native import reference
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.check import GameGraph, simplify
from plansynth.grid.native.cone import influence_cone, with_relevant
from plansynth.grid.native.engine import Engine
from plansynth.grid.problem import load_grid_problem
from plansynth.grid.result import GridStatus
from plansynth.grid.verify import verify

from .strategies import grid_problems, problems_and_programs

ROOT = Path(__file__).resolve().parents[2]
small = grid_problems(max_side=4, max_obstacles=2, max_obstacle_moves=3, max_robot_moves=5, max_steps=4)


def _graph(problem, steps, use_rust):
    read = tuple(range(len(problem.obstacles)))
    cone = with_relevant(influence_cone(problem, steps), read)
    arena = Arena.build(problem, steps, cone, read)
    if not arena.layers[0] or not arena.solve_game():
        return None
    return GameGraph.from_arena(arena, use_rust=use_rust)


@settings(max_examples=200, deadline=None)
@given(problems_and_programs(max_depth=5, max_side=4, max_obstacles=2, max_steps=4))
def test_game_graph_check_agrees_with_the_verifier_in_python_and_rust(pp):
    problem, program = pp
    steps = problem.steps
    wins = verify(problem, program, steps).wins
    g = _graph(problem, steps, use_rust=True)
    if g is None:  # the obstacles win the game: no program wins
        assert not wins
        return
    ref = g.check_reference(program)
    assert g.check(program) == ref  # the compiled check (game.rs) finds the same pair
    assert (ref is None) == wins


@settings(max_examples=80, deadline=None)
@given(problems_and_programs(max_depth=6, max_side=4, max_obstacles=2, max_steps=4))
def test_simplify_keeps_a_winning_program_winning(pp):
    problem, program = pp
    g = _graph(problem, problem.steps, use_rust=None)
    if g is None or g.check(program) is not None:
        return
    smaller = simplify(program, g)
    assert verify(problem, smaller, problem.steps).wins
    assert g.check(smaller) is None


@settings(max_examples=80, deadline=None)
@given(small, st.booleans())
def test_answer_first_and_minimize_return_winning_programs(problem, minimize):
    steps = problem.steps
    out = Engine(minimize=minimize).solve_length(problem, steps, Budget(seconds=20))
    assert out.status is not GridStatus.UNKNOWN, out.message
    if out.status is GridStatus.REALIZABLE:
        assert verify(problem, out.program, steps).wins
        assert out.counters["depth_minimal"] in ("proved", "not proved")
        if not minimize:
            assert out.counters["depth_minimal"] == "not proved"
    else:
        try:  # unrealizable agrees with brute force
            assert not reference.stationary_exists(problem, steps, limit=5_000, max_seconds=2.0)
        except reference.TooLarge:
            pass


def test_effort_zero_returns_the_first_program_and_says_so():
    problem = load_grid_problem(ROOT / "examples" / "grid" / "door.yaml")
    out = Engine(effort=0).solve_length(problem, 10, Budget(seconds=30))
    assert out.status is GridStatus.REALIZABLE
    assert out.counters["effort_seconds"] == 0
    assert out.counters["program_depth"] == out.counters["first_depth"] <= out.counters["greedy_depth"]
    assert set(out.counters["phase_seconds"]) >= {"game", "stationary", "answer", "improve"}
    assert verify(problem, out.program, 10).wins


def test_a_two_second_budget_on_a_huge_field_answers_unknown_within_ten_seconds():
    """examples/grid/field30.yaml needs far more than 2 s (a 30x30 field, four obstacles
    that never stop, l = 30): the budget is kept and the phase is named."""
    problem = load_grid_problem(ROOT / "examples" / "grid" / "field30.yaml")
    t0 = time.perf_counter()
    out = Engine().solve_length(problem, problem.steps, Budget(seconds=2))
    took = time.perf_counter() - t0
    assert took < 10, took
    assert out.status is GridStatus.UNKNOWN
    assert "budget exhausted" in out.message


def test_the_corridor_example_is_solved_and_verified():
    problem = load_grid_problem(ROOT / "examples" / "grid" / "corridor.yaml")
    out = Engine(effort=0).solve_length(problem, problem.steps, Budget(seconds=120))
    assert out.status is GridStatus.REALIZABLE
    assert out.counters["stage"] == "joint"  # it must read the cars
    assert verify(problem, out.program, problem.steps).wins


@settings(max_examples=120, deadline=None)
@given(small)
def test_the_compiled_game_graph_is_the_reference_graph(problem):
    read = tuple(range(len(problem.obstacles)))
    cone = with_relevant(influence_cone(problem, problem.steps), read)
    arena = Arena.build(problem, problem.steps, cone, read)
    if not arena.layers[0] or not arena.solve_game():
        return
    fast_g = GameGraph.from_arena(arena, use_rust=True)
    ref_g = GameGraph.from_arena_reference(arena, use_rust=False)
    assert fast_g._compiled is not None
    assert (fast_g.n_pairs, fast_g.n_states) == (ref_g.n_pairs, ref_g.n_states)
    fast_g.materialize()
    assert (fast_g.state_of, fast_g.win, fast_g.off, fast_g.succ, fast_g.inputs) == (
        ref_g.state_of,
        ref_g.win,
        ref_g.off,
        ref_g.succ,
        ref_g.inputs,
    )


def test_minimize_proves_unrealizable_when_no_positional_strategy_exists():
    """Found by hypothesis: the robot must press against the border (down at y = 0)
    and then step up, twice at the same cell; a controller that sees the time wins, one
    that sees only positions cannot. Both paths must prove it, not give up on depth."""
    from plansynth.grid.problem import grid_problem_from_dict

    problem = grid_problem_from_dict(
        {
            "grid": [2, 3],
            "robot": {"start": [1, 0], "goal": [1, 1], "moves": ["up", {"name": "m1", "to": [0, 1]}, "down"]},
            "obstacles": [],
            "steps": 2,
            "walls": [[0, 0]],
        },
        source="<regression>",
    )
    assert reference.game_won(problem, 2)  # a controller that sees the time wins
    for minimize in (False, True):
        out = Engine(minimize=minimize).solve_length(problem, 2, Budget(seconds=20))
        assert out.status is GridStatus.UNREALIZABLE, (minimize, out.message)
        assert "sees only positions" in out.message


def _plain_greedy_depth(problem, steps):
    """The depth of a plain greedy tree over the engine's strategy, built here: every
    condition to the default condition depth, the greedy tree, checked on the game."""
    from plansynth.grid.native import fast
    from plansynth.grid.native.check import program_checker
    from plansynth.grid.native.conditions import condition_limit
    from plansynth.grid.native.stationary import stationary_strategy
    from plansynth.grid.programs import depth

    read = tuple(range(len(problem.obstacles)))
    cone = with_relevant(influence_cone(problem, steps), read)
    arena = Arena.build(problem, steps, cone, read)
    if not arena.layers[0] or not arena.solve_game():
        return None
    strategy = stationary_strategy(arena)
    if strategy is None:
        return None
    states = sorted(strategy.allowed)
    allowed = [strategy.allowed[s] for s in states]
    inputs = [arena.inputs(r, oc) for r, oc in states]
    plain = fast.greedy_from_enumeration(
        inputs,
        arena.variables(),
        problem.max_constant,
        4,
        condition_limit(len(inputs)),
        allowed,
        len(problem.robot.moves),
        10_000,
    )
    assert program_checker(arena).check(plain) is None
    return depth(plain)


SUITE = ROOT.parent / "shared" / "grid-reactive"


def test_the_default_never_loses_to_a_plain_greedy_tree():
    """On the shared suite's realizable problems where the engine reads obstacles (the
    kind of problem the default was deeper than a plain greedy tree on), the default
    answer is at most as deep as a plain greedy tree over the same strategy."""
    import json

    checked = 0
    for path in sorted(SUITE.glob("*.yaml"))[:24]:
        label = json.loads((SUITE / (path.stem + ".label.json")).read_text())
        if label["expected"] != "realizable":
            continue
        problem = load_grid_problem(path)
        out = Engine().solve_length(problem, problem.steps, Budget(seconds=30))
        assert out.status is GridStatus.REALIZABLE
        plain = out.counters.get("plain_greedy_depth")
        if plain is None:
            continue  # an obstacle-blind answer: no joint strategy to compare on
        assert out.counters["program_depth"] <= plain, path.name
        assert out.counters["program_depth"] <= _plain_greedy_depth(problem, problem.steps), path.name
        checked += 1
    assert checked >= 8
