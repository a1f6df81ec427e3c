"""The native engine against brute force, the verifier and the paper's families."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.bench.families import paper_depth
from plansynth.bench.families import paper_problems as families
from plansynth.budget import Budget, Clock
from plansynth.grid.native import reference
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.bitgrid import AgentGeometry, cell_mask, cells
from plansynth.grid.native.cone import influence_cone
from plansynth.grid.native.engine import Engine, program_wins
from plansynth.grid.problem import grid_problem_from_dict, load_grid_problem
from plansynth.grid.programs import depth, reads_obstacles
from plansynth.grid.reference import reachable_cells, reference_wins
from plansynth.grid.result import GridStatus, get_backend
from plansynth.grid.semantics import obstacle_move, robot_move
from plansynth.grid.verify import verify

from .strategies import grid_problems

ROOT = Path(__file__).resolve().parents[2]

small = grid_problems(max_side=4, max_obstacles=2, max_obstacle_moves=3, max_robot_moves=5, max_steps=4)


def _brute(problem, steps):
    try:
        return reference.stationary_exists(problem, steps, limit=5_000, max_seconds=2.0)
    except reference.TooLarge:
        return None


@settings(max_examples=150)
@given(small, st.booleans())
def test_native_agrees_with_brute_force(problem, quick):
    """Both ways of finding a stationary strategy: read off the game, or SAT only."""
    steps = problem.steps
    out = Engine(quick=quick).solve_length(problem, steps, Budget(seconds=20))
    assert out.status is not GridStatus.UNKNOWN, out.message
    if out.status is GridStatus.REALIZABLE:
        assert verify(problem, out.program, steps).wins
        assert reference_wins(problem, out.program, steps)
    else:
        # unrealizable: confirmed by brute force (time-dependent game or stationary search)
        if out.witness is not None and out.witness.kind in ("goal", "game"):
            assert not reference.game_won(problem, steps)
    expected = _brute(problem, steps)
    if expected is not None:
        assert expected == (out.status is GridStatus.REALIZABLE)


@settings(max_examples=60)
@given(small)
def test_minimize_finds_a_program_no_larger_than_the_default(problem):
    steps = problem.steps
    plain = Engine().solve_length(problem, steps, Budget(seconds=20))
    mini = Engine(minimize=True).solve_length(problem, steps, Budget(seconds=20))
    assert mini.status in (plain.status, GridStatus.UNKNOWN)
    if mini.status is GridStatus.REALIZABLE:
        assert reference_wins(problem, mini.program, steps)
        assert depth(mini.program) <= depth(plain.program)


@settings(max_examples=80)
@given(small)
def test_cone_drops_only_obstacles_that_never_meet_the_robot(problem):
    """An obstacle outside the cone sweeps no cell the robot can sweep on a path of
    exactly l steps to the goal (checked against the reference reachable sets)."""
    steps = problem.steps
    cone = influence_cone(problem, steps)
    robot_cells = [set(cells(m, problem.width)) for m in cone.live]
    for i in range(len(problem.obstacles)):
        reach = reachable_cells(problem, i, steps)
        assert {cell_mask(problem, c) for c in reach[steps]} == {
            cell_mask(problem, c) for c in cells(cone.positions[i][steps], problem.width)
        }
        if i in cone.relevant:
            continue
        for t in range(steps):
            for p in reach[t]:
                for k in range(len(problem.obstacles[i].moves)):
                    _, o_swept = obstacle_move(problem, i, p, k)
                    for r in robot_cells[t]:
                        for kr in range(len(problem.robot.moves)):
                            end, r_swept = robot_move(problem, r, kr)
                            if (end[0] + end[1] * problem.width) in [
                                c[0] + c[1] * problem.width for c in robot_cells[t + 1]
                            ]:
                                assert not set(o_swept) & set(r_swept)


@settings(max_examples=80)
@given(small, st.data())
def test_bitset_moves_match_the_semantics(problem, data):
    robot = AgentGeometry.robot(problem)
    c = data.draw(st.tuples(st.integers(0, problem.width - 1), st.integers(0, problem.height - 1)))
    for k in range(len(problem.robot.moves)):
        end, swept = robot_move(problem, c, k)
        hits_wall = any(s in problem.walls for s in swept)
        img = robot.image(cell_mask(problem, c), k)
        if c in problem.walls or hits_wall:
            assert img == 0
        else:
            assert img == cell_mask(problem, end)
            assert robot.sweep(cell_mask(problem, c), k) == sum({cell_mask(problem, s) for s in swept})
    for i in range(len(problem.obstacles)):
        g = AgentGeometry.obstacle(problem, i)
        for k in range(len(problem.obstacles[i].moves)):
            end, swept = obstacle_move(problem, i, c, k)
            assert g.image(cell_mask(problem, c), k) == cell_mask(problem, end)
            assert g.sweep(cell_mask(problem, c), k) == sum({cell_mask(problem, s) for s in swept})


@pytest.mark.parametrize("name", sorted(set(families()) - {"figure1"}))
def test_paper_instances_are_solved_with_the_papers_depth(name):
    """No regression on the paper's families: every instance of
    Section 4.1 is realizable at its length with a program no deeper than the paper's
    (the times are the bench's business: ``plansynth bench grid --family depth,...``)."""
    problem = grid_problem_from_dict(families()[name])
    out = Engine().solve_length(problem, problem.steps, Budget(seconds=30))
    assert out.status is GridStatus.REALIZABLE
    assert verify(problem, out.program, problem.steps).wins
    paper = paper_depth(name)
    assert depth(out.program) <= paper


@pytest.mark.parametrize("name,minimal", [("depth-1", 1), ("depth-4", 4), ("depth-5", 5), ("depth-6", 5)])
def test_minimize_proves_the_depth_family(name, minimal):
    """``--minimize`` proves the smallest depth on the whole depth family (depth-6 has a
    depth-5 program under the spec's semantics)."""
    problem = grid_problem_from_dict(families()[name])
    out = Engine(minimize=True).solve_length(problem, problem.steps, Budget(seconds=30))
    assert out.status is GridStatus.REALIZABLE
    assert depth(out.program) == minimal
    assert out.counters["minimal_depth_proved"] is True
    assert out.counters["depth_minimal"] == "proved"
    assert verify(problem, out.program, problem.steps).wins


def test_figure1_through_the_solve_loop():
    from plansynth.grid.solve import solve

    problem = load_grid_problem(ROOT / "examples" / "grid" / "figure1.yaml")
    result = solve(problem, "native", Budget(seconds=30))
    assert result.status is GridStatus.REALIZABLE
    assert result.steps == 6 and result.verified is True
    assert [a.status for a in result.attempts[:5]] == [GridStatus.UNREALIZABLE] * 5


@pytest.mark.parametrize("use_rust", [True, False])
def test_a_spent_budget_gives_unknown(use_rust):
    """A budget that has run out before the engine starts gives ``unknown`` at once,
    saying so, with no program: not a controller found by ignoring the budget (the
    engine solves steps-25 in milliseconds), not ``unrealizable``."""
    problem = grid_problem_from_dict(families()["steps-25"])
    t0 = time.perf_counter()
    out = get_backend("native", improve=False, use_rust=use_rust).solve_length(problem, 25, Budget(seconds=1e-9))
    assert out.status is GridStatus.UNKNOWN, (out.status, out.message)
    assert out.program is None and out.message.startswith("budget exhausted: "), out.message
    assert time.perf_counter() - t0 < 1.0


class _Countdown(Clock):
    """A clock whose time runs out at its ``reads``-th reading, whatever the machine's
    speed: the compiled core then gets no seconds either."""

    def __init__(self, budget: _CountdownBudget) -> None:
        super().__init__(budget)
        self.reads_left = budget.reads

    def out_of_time(self) -> bool:
        self.reads_left -= 1
        return self.reads_left < 0

    def remaining(self) -> float:
        return 0.0 if self.out_of_time() else 3600.0


@dataclass(frozen=True)
class _CountdownBudget(Budget):
    reads: int = 0

    def clock(self) -> Clock:
        return _Countdown(self)


#: Problems whose solves pass through every stage (the blind controller, the joint game
#: and its strategy, the clock obstacles, the game and stationary refutations), with
#: whether a controller exists at the length.
COUNTDOWN_CASES = {
    "steps-25 (blind)": (lambda: grid_problem_from_dict(families()["steps-25"]), 25, True),
    "crossing (reads the car)": (lambda: load_grid_problem(ROOT / "examples" / "grid" / "crossing.yaml"), 9, True),
    "stationary refutation": (lambda: grid_problem_from_dict(STATIONARY_REFUTED[0]), 3, False),
    "clock obstacle": (
        lambda: grid_problem_from_dict(
            {
                **STATIONARY_REFUTED[0],
                "grid": [3, 8],
                "obstacles": [*STATIONARY_REFUTED[0]["obstacles"], {"start": [0, 4], "moves": ["up"]}],
            }
        ),
        3,
        True,
    ),
    "game refutation": (
        lambda: grid_problem_from_dict(
            {
                "grid": [3, 1],
                "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]},
                "obstacles": [{"start": [2, 0], "moves": ["stay"]}],
                "steps": 2,
            }
        ),
        2,
        False,
    ),
}


@pytest.mark.parametrize("use_rust", [True, False])
@pytest.mark.parametrize("case", sorted(COUNTDOWN_CASES))
def test_running_out_at_any_budget_check_gives_unknown_never_a_wrong_answer(case, use_rust):
    """The budget runs out at the engine's first clock reading, then its second, and so
    on until one is enough: every phase meets a spent budget in turn. Each run answers
    ``unknown`` because the budget ran out (never an internal error, never a guess), or,
    once the budget suffices, the true answer: a controller only if the independent
    verifier accepts it."""
    make, steps, exists = COUNTDOWN_CASES[case]
    problem = make()
    backend = get_backend("native", improve=False, use_rust=use_rust)
    phases = set()
    for reads in range(5000):
        out = backend.solve_length(problem, steps, _CountdownBudget(seconds=3600, reads=reads))
        if out.status is not GridStatus.UNKNOWN:
            break
        assert out.program is None and out.message.startswith("budget exhausted: "), (reads, out.message)
        phases.add(out.message.split(":")[1].split(" at ")[0])
    else:
        raise AssertionError(f"no answer after {reads} clock readings: {out.message}")
    assert reads > 0 and len(phases) >= 5, (reads, phases)  # it did run out, in several phases
    if exists:
        assert out.status is GridStatus.REALIZABLE and verify(problem, out.program, steps).wins, out
    else:
        assert out.status is GridStatus.UNREALIZABLE and out.program is None, out


def test_unknown_options_are_rejected():
    from plansynth.errors import InvalidOption

    with pytest.raises(InvalidOption, match="option 'minimise': not an option of this solver"):
        get_backend("native", minimise=True)


def test_program_wins_agrees_with_the_verifier_on_figure1():
    from plansynth.grid.programs import parse_program

    problem = load_grid_problem(ROOT / "examples" / "grid" / "figure1.yaml")
    for text, steps in [("(ite (<= 4 rx) 1 2)", 6), ("(ite (<= rx 3) 2 1)", 6), ("1", 3), ("(ite (<= ry 3) 1 2)", 6)]:
        prog = parse_program(text)
        assert (
            program_wins(problem, steps, prog)
            == verify(problem, prog, steps).wins
            == reference_wins(problem, prog, steps)
        )


def test_game_refutation_on_an_unavoidable_obstacle():
    # A 3x1 corridor: the obstacle can sit on the goal at the last step.
    problem = grid_problem_from_dict(
        {
            "grid": [3, 1],
            "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]},
            "obstacles": [{"start": [2, 0], "moves": ["stay"]}],
            "steps": 2,
        }
    )
    out = Engine().solve_length(problem, 2, Budget(seconds=5))
    assert out.status is GridStatus.UNREALIZABLE
    assert out.witness.kind == "game"
    assert not reference.game_won(problem, 2)


def test_blind_program_reads_no_obstacle_on_the_paper_families():
    problem = grid_problem_from_dict(families()["obstacles-25"])
    out = Engine().solve_length(problem, 5, Budget(seconds=10))
    assert not reads_obstacles(out.program)
    arena = Arena.build(problem, 5, influence_cone(problem, 5), ())
    assert arena.solve_game()


STATIONARY_REFUTED = [
    # The robot must come back to its start in 3 steps without `stay`: with the time it
    # can (down, down clamped at the border, up); with positions only, the cell it
    # reaches after one step would need two different moves.
    {
        "grid": [3, 4],
        "robot": {"start": [1, 1], "goal": [1, 1], "moves": ["up", "right", "down", "left"]},
        "obstacles": [{"start": [2, 0], "moves": ["up", "down"]}],
        "steps": 3,
    },
    {
        "grid": [3, 2],
        "robot": {"start": [2, 1], "goal": [1, 1], "moves": ["right", "left"]},
        "obstacles": [{"start": [1, 0], "moves": ["down"]}],
        "steps": 4,
    },
]


@pytest.mark.parametrize("doc", STATIONARY_REFUTED)
def test_time_dependent_wins_but_no_stationary_controller_does(doc):
    problem = grid_problem_from_dict(doc)
    out = Engine().solve_length(problem, problem.steps, Budget(seconds=10))
    assert out.status is GridStatus.UNREALIZABLE
    assert out.witness.kind == "stationary"
    assert reference.game_won(problem, problem.steps)
    assert reference.stationary_exists(problem, problem.steps) is False


def test_an_obstacle_outside_the_cone_can_serve_as_a_clock():
    """The first stationary refutation again, plus a far-away obstacle that can only move
    up: it never meets the robot, but its height tells the time, so a program that reads
    it wins (and the engine finds it rather than answering unrealizable)."""
    doc = dict(STATIONARY_REFUTED[0])
    doc["grid"] = [3, 8]
    doc["obstacles"] = doc["obstacles"] + [{"start": [0, 4], "moves": ["up"]}]
    problem = grid_problem_from_dict(doc)
    out = Engine().solve_length(problem, 3, Budget(seconds=10))
    assert out.status is GridStatus.REALIZABLE
    assert "o1y" in str(out.program)
    assert verify(problem, out.program, 3).wins
    assert reference.stationary_exists(problem, 3)
    # and if the far obstacle can stay put, it tells nothing: unrealizable again
    doc["obstacles"][1]["moves"] = ["up", "stay"]
    parked = grid_problem_from_dict(doc)
    out = Engine().solve_length(parked, 3, Budget(seconds=10))
    assert out.status is GridStatus.UNREALIZABLE and out.witness.kind == "stationary"
    small = grid_problem_from_dict(dict(doc, grid=[3, 5]))  # same game, fewer far cells
    assert Engine().solve_length(small, 3, Budget(seconds=10)).status is GridStatus.UNREALIZABLE
    assert reference.stationary_exists(small, 3, limit=50_000) is False
