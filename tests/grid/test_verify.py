"""The independent verifier against the brute-force reference, its counterexamples, the
paper's Figure 1 program, and the reductions that let it scale to the paper's families."""

from __future__ import annotations

import os
import re
import time
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.grid.problem import GridProblem, grid_problem_from_dict, load_grid_problem
from plansynth.grid.programs import App, Const, ProgramSyntaxError, Term, evaluate, parse_program, reads_obstacles
from plansynth.grid.reference import all_runs, reachable_cells, reference_wins
from plansynth.grid.semantics import State, initial_state, obstacle_move, step
from plansynth.grid.verify import Counterexample, Verdict, read_obstacles, verify

from .strategies import b_terms, grid_problems, problem_documents, problems_and_programs

#: Hypothesis examples per property test below; PLANSYNTH_TEST_SCALE=N runs N times as
#: many (a longer hunt than CI's, which runs each of them in three random orders).
SCALE = max(1, int(os.environ.get("PLANSYNTH_TEST_SCALE", "1")))

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "grid"
MOVES = ["stay", "up", "right", "down", "left"]
UP_DOWN = ["up", "down"]


def check_counterexample(p: GridProblem, program: Term, steps: int, cex: Counterexample) -> None:
    """Replay a counterexample through semantics.step: it must be the program's run and lose."""
    env_of = lambda s: dict(zip(p.variables, s.inputs()))  # noqa: E731
    assert cex.states[0] == initial_state(p)
    n = len(cex.robot_moves)
    assert len(cex.obstacle_moves) == n and len(cex.states) == n + 1 and 1 <= n <= steps
    for t in range(n):
        assert cex.robot_moves[t] == evaluate(program, env_of(cex.states[t]))
        assert len(cex.obstacle_moves[t]) == len(p.obstacles)
        assert all(0 <= k < len(o.moves) for k, o in zip(cex.obstacle_moves[t], p.obstacles))
        out = step(p, cex.states[t], cex.robot_moves[t], cex.obstacle_moves[t])
        assert out.state == cex.states[t + 1]
        if out.collided:
            assert t == n - 1, "the run must stop at its first collision"
            assert re.fullmatch(
                rf"collision at step {t} (in cell \(\d+, \d+\) with obstacle \d+|with the wall at \(\d+, \d+\))",
                cex.reason,
            )
            return
    assert n == steps and cex.states[-1].robot != p.robot.goal
    gx, gy = p.robot.goal
    assert cex.reason.startswith(f"not on the goal ({gx}, {gy}) after step {steps - 1}")


# -- verify == brute force -------------------------------------------------------------------


@settings(max_examples=75 * SCALE)
@given(problems_and_programs(max_depth=5))
def test_verify_agrees_with_brute_force(pp: tuple[GridProblem, Term]) -> None:
    p, program = pp
    v = verify(p, program, p.steps)
    assert isinstance(v, Verdict) and v.steps == p.steps and v.seconds >= 0
    assert v.wins == reference_wins(p, program, p.steps)
    if v.wins:
        assert v.counterexample is None
    else:
        check_counterexample(p, program, p.steps, v.counterexample)


@settings(max_examples=50 * SCALE)
@given(problems_and_programs(max_depth=5, reading_obstacles=True, max_obstacles=3, max_steps=4))
def test_verify_agrees_with_brute_force_on_programs_reading_obstacles(pp: tuple[GridProblem, Term]) -> None:
    p, program = pp
    assert reads_obstacles(program)
    expected = reference_wins(p, program, p.steps)
    # probe_nodes=0: straight to the exhaustive layered search over product sets.
    for v in (verify(p, program, p.steps), verify(p, program, p.steps, probe_nodes=0)):
        assert v.wins == expected
        if not v.wins:
            check_counterexample(p, program, p.steps, v.counterexample)


@st.composite
def pinned_robot_cases(draw: st.DrawFn) -> tuple[GridProblem, Term]:
    """A robot in the corner (0, 0) whose every move keeps it there or steps out, under
    a program that compares obstacles with each other: it wins often, so the layered
    search must cover every split product set to say so."""
    doc = draw(problem_documents(max_side=6, min_obstacles=2, max_obstacles=3, max_steps=8, walls=False))
    doc["robot"] = {"start": [0, 0], "goal": [0, 0], "moves": ["stay", "left", "down", "right", "up"]}
    p = grid_problem_from_dict(doc)

    def tree(budget: int) -> Term:
        if budget < 3 or draw(st.booleans()):
            return Const(draw(st.sampled_from([0, 0, 1, 2, 3])))
        cond = draw(b_terms(p.variables[2:], p.max_constant, budget - 1))
        return App("ite", (cond, tree(budget - 1), tree(budget - 1)))

    return p, tree(6)


@settings(max_examples=60)
@given(pinned_robot_cases())
def test_layered_search_agrees_with_brute_force_where_controllers_often_win(pp: tuple[GridProblem, Term]) -> None:
    p, program = pp
    v = verify(p, program, p.steps, probe_nodes=0)
    assert v.wins == reference_wins(p, program, p.steps)
    if not v.wins:
        check_counterexample(p, program, p.steps, v.counterexample)


@settings(max_examples=60)
@given(problems_and_programs(max_depth=4, max_side=3, max_obstacles=2, max_steps=3))
def test_a_loss_is_exactly_a_losing_run(pp: tuple[GridProblem, Term]) -> None:
    """On tiny problems enumerate every run: the program loses iff one of them loses."""
    p, program = pp
    lost = any(lost for _, lost in all_runs(p, program, p.steps))
    assert verify(p, program, p.steps).wins is not lost


# -- counterexamples and reasons -------------------------------------------------------------


def corridor(**extra: Any) -> GridProblem:
    doc = {
        "grid": [4, 1],
        "robot": {"start": [0, 0], "goal": [3, 0], "moves": ["stay", "right"]},
        "obstacles": [{"start": [3, 0], "moves": ["stay", "left"]}],
    }
    return grid_problem_from_dict(doc | extra)


def test_counterexample_for_a_collision_with_an_obstacle() -> None:
    p = corridor()
    v = verify(p, parse_program("1"), 3)
    assert not v.wins
    cex = v.counterexample
    check_counterexample(p, parse_program("1"), 3, cex)
    assert cex.reason == "collision at step 1 in cell (2, 0) with obstacle 0"
    assert cex.robot_moves == (1, 1)
    assert cex.states == (State((0, 0), ((3, 0),)), State((1, 0), ((2, 0),)), State((2, 0), ((2, 0),)))


def test_counterexample_for_a_wall() -> None:
    p = corridor(walls=[[2, 0]], obstacles=[])
    v = verify(p, parse_program("1"), 3)
    assert v.counterexample.reason == "collision at step 1 with the wall at (2, 0)"
    check_counterexample(p, parse_program("1"), 3, v.counterexample)


def test_counterexample_for_missing_the_goal() -> None:
    p = corridor(obstacles=[])
    v = verify(p, parse_program("(ite (<= rx 1) 1 0)"), 3)
    assert v.counterexample.reason == "not on the goal (3, 0) after step 2: the robot is at (2, 0)"
    assert not verify(p, parse_program("1"), 2).wins
    assert verify(p, parse_program("1"), 3).wins
    assert verify(p, parse_program("1"), 4).wins  # `right` at the border is clamped: it stays on the goal


def test_counterexample_steers_an_unread_obstacle_from_far_away() -> None:
    # A 1-wide corridor of height 8; the obstacle 6 cells up can come down in time.
    p = grid_problem_from_dict(
        {
            "grid": [3, 8],
            "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]},
            "obstacles": [{"start": [1, 6], "moves": ["up", "down", "stay"]}] + [{"start": [2, 7], "moves": ["stay"]}],
        }
    )
    program = parse_program("(ite (<= rx 0) (ite (<= ry 0) 0 1) 1)")  # waits forever at (0, 0)
    assert not verify(p, program, 3).wins
    wait_then_go = parse_program("1")
    v = verify(p, wait_then_go, 2)
    assert v.wins  # the obstacle needs 6 steps to come down
    late = grid_problem_from_dict(p.to_dict() | {"obstacles": [{"start": [1, 2], "moves": ["up", "down", "stay"]}]})
    v = verify(late, wait_then_go, 2)
    assert not v.wins and read_obstacles(wait_then_go, 1) == ()
    check_counterexample(late, wait_then_go, 2, v.counterexample)
    assert v.counterexample.reason == "collision at step 1 in cell (1, 0) with obstacle 0"
    assert [s.obstacles[0] for s in v.counterexample.states] == [(1, 2), (1, 1), (1, 0)]


def test_invalid_programs_are_rejected() -> None:
    p = corridor()
    with pytest.raises(ProgramSyntaxError, match="move number 2 is not in 0..1"):
        verify(p, parse_program("(ite (<= rx 1) 2 0)"), 3)
    with pytest.raises(ProgramSyntaxError, match="unknown input 'o1x'"):
        verify(p, parse_program("(ite (<= o1x 1) 1 0)"), 3)
    with pytest.raises(ValueError, match="steps must be >= 1"):
        verify(p, parse_program("1"), 0)


# -- the paper's Figure 1 ---------------------------------------------------------------------


def test_figure1_program_wins_exactly_at_six_steps() -> None:
    """Figure 1 of Chasins & Newcomb (SYNT 2016): ``(ite (<= rx 3) 2 1)`` goes right to
    column 4, then up. Under the spec's semantics it wins at l = 6 only: sooner it has
    not arrived, later it walks past the goal (and then stays clamped at (4, 6))."""
    p = load_grid_problem(EXAMPLES / "figure1.yaml")
    program = parse_program("(ite (<= rx 3) 2 1)")
    verdicts = {l: verify(p, program, l) for l in range(1, 13)}
    assert [l for l, v in verdicts.items() if v.wins] == [6]
    assert verdicts[5].counterexample.reason == "not on the goal (4, 4) after step 4: the robot is at (4, 3)"
    assert verdicts[9].counterexample.reason == "not on the goal (4, 4) after step 8: the robot is at (4, 6)"
    for l in (5, 6, 7):
        assert verdicts[l].wins == reference_wins(p, program, l)


# -- scaling: the reductions, on the paper's families ------------------------------------------


def family(name: str, n: int) -> GridProblem:
    """Instances of the paper's families (spec: benchmarks.md)."""
    if name == "obstacles":
        obstacles = [((i % 20, 19 - i // 20), UP_DOWN) for i in range(n)]
        w = h = 20
        start, goal, steps = (0, 0), (2, 3), 5
    elif name == "steps":
        obstacles = [((0, y), UP_DOWN) for y in range(5)]
        w = h = 20
        start, goal, steps = (1, 1), (3, 1), n
    else:  # dimensions
        obstacles = [((0, y), UP_DOWN) for y in range(5)]
        w = h = n
        start, goal, steps = (1, 0), (4, 2), 5
    return grid_problem_from_dict(
        {
            "grid": [w, h],
            "robot": {"start": list(start), "goal": list(goal), "moves": MOVES},
            "obstacles": [{"start": list(c), "moves": m} for c, m in obstacles],
            "steps": steps,
        }
    )


def test_obstacles_50_with_a_program_that_reads_no_obstacle() -> None:
    """2^50 joint obstacle moves per step; the verifier expands one state per step."""
    p = family("obstacles", 50)
    t0 = time.perf_counter()
    v = verify(p, parse_program("(ite (<= rx 1) 2 1)"), 5)
    assert v.wins and v.states_explored == 5
    assert time.perf_counter() - t0 < 10  # about 0.01 s; generous for a loaded CI machine


def test_obstacles_50_reading_two_obstacles() -> None:
    p = family("obstacles", 50)
    v = verify(p, parse_program("(ite (<= o0y o49y) (ite (<= rx 1) 2 1) 1)"), 5)
    assert not v.wins  # when o0y > o49y the robot goes up first and arrives elsewhere
    check_counterexample(p, parse_program("(ite (<= o0y o49y) (ite (<= rx 1) 2 1) 1)"), 5, v.counterexample)
    assert verify(p, parse_program("(ite (<= o0y o49y) (ite (<= rx 1) 2 1) (ite (<= rx 1) 2 1))"), 5).wins


@pytest.mark.parametrize("steps", [5, 25])
def test_steps_family(steps: int) -> None:
    p = family("steps", steps)
    v = verify(p, parse_program("(ite (<= 3 rx) 0 2)"), steps)
    assert v.wins and v.states_explored == steps
    assert not verify(p, parse_program("(ite (<= 3 rx) 1 2)"), steps).wins


def test_steps_25_with_a_program_comparing_three_obstacles() -> None:
    """Relational reads are the hard case: explicit enumeration would meet ~20^3 joint
    positions per step; product sets split where the program looks keep it small."""
    p = family("steps", 25)
    program = parse_program(
        "(ite (and (= rx 3) (= ry 3)) 0 (ite (= rx 3) 1 (ite (= ry 3) 2 (ite (and (<= o0y o1y) (= o2y o3y)) 2 1))))"
    )
    p = grid_problem_from_dict(p.to_dict() | {"robot": p.to_dict()["robot"] | {"goal": [3, 3]}})
    v = verify(p, program, 25)
    assert v.wins and v.states_explored < 5000


def test_scale64_instance() -> None:
    p = load_grid_problem(EXAMPLES / "scale64.yaml")
    v = verify(p, parse_program("(ite (<= 32 rx) 1 2)"), 60)
    assert v.wins and v.states_explored == 60
    bad = parse_program("(ite (<= o7y 40) (ite (<= 32 rx) 1 2) (ite (<= 32 ry) 2 1))")
    v = verify(p, bad, 60)
    assert not v.wins
    check_counterexample(p, bad, 60, v.counterexample)


@given(grid_problems())
def test_reachable_cells_reference(p: GridProblem) -> None:
    """The reference BFS of obstacle positions is what one step of every move gives."""
    for i in range(len(p.obstacles)):
        sets = reachable_cells(p, i, 3)
        assert sets[0] == {p.obstacles[i].start}
        for a, b in zip(sets, sets[1:]):
            assert b == {obstacle_move(p, i, c, k)[0] for c in a for k in range(len(p.obstacles[i].moves))}


# -- the two table representations -----------------------------------------------------------


def _same_verdicts(p: GridProblem, program: Term, steps: int, **kw: Any) -> Verdict:
    py = verify(p, program, steps, tables="python", **kw)
    arrays = verify(p, program, steps, tables="numpy", **kw)
    assert (py.status, py.counterexample, py.states_explored) == (
        arrays.status,
        arrays.counterexample,
        arrays.states_explored,
    )
    return py


@settings(max_examples=75 * SCALE)
@given(problems_and_programs(max_depth=5, max_obstacles=3))
def test_python_and_numpy_tables_give_the_same_verdict_and_counterexample(pp: tuple[GridProblem, Term]) -> None:
    """Small grids keep their tables in plain Python (no numpy import on a small solve),
    large ones in numpy arrays: the same search over either, so the same answer, the
    same counterexample and the same count of states."""
    p, program = pp
    v = _same_verdicts(p, program, p.steps)
    assert v.wins == reference_wins(p, program, p.steps)


@settings(max_examples=40 * SCALE)
@given(problems_and_programs(max_depth=5, reading_obstacles=True, max_obstacles=3, max_steps=4))
def test_python_and_numpy_tables_agree_on_programs_reading_obstacles(pp: tuple[GridProblem, Term]) -> None:
    p, program = pp
    _same_verdicts(p, program, p.steps, probe_nodes=0)
    _same_verdicts(p, program, p.steps)


def test_the_table_representation_follows_the_grid_size() -> None:
    """A far unread obstacle steers into the robot (the hit walked back through its
    reachable sets), over either representation; a bad name is an error."""
    p = grid_problem_from_dict(
        {
            "grid": [9, 3],
            "robot": {"start": [0, 1], "goal": [8, 1], "moves": ["stay", "right"]},
            "obstacles": [{"start": [8, 0], "moves": MOVES}],
        }
    )
    v = _same_verdicts(p, parse_program("1"), 8)
    assert not v.wins and "with obstacle 0" in v.counterexample.reason
    check_counterexample(p, parse_program("1"), 8, v.counterexample)
    with pytest.raises(ValueError, match="tables must be 'python' or 'numpy'"):
        verify(p, parse_program("1"), 8, tables="arrays")
