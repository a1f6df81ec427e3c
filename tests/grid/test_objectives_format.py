"""The problem file's objectives and obstacle extensions: reading, validation, round
trips, and one step of the game for each rule (plansynth.grid.objective,
plansynth.grid.semantics)."""

from __future__ import annotations

import re
from typing import Any

import pytest
from hypothesis import given, settings

from plansynth.errors import InvalidProblem
from plansynth.grid.objective import CollisionRule, ObjectiveKind
from plansynth.grid.problem import grid_problem_from_dict
from plansynth.grid.semantics import (
    State,
    controller_inputs,
    initial_state,
    joint_choices,
    legal_moves,
    obstacle_move,
    step,
)

from .strategies import objective_documents

KING = ["stay", "up", "down", "left", "right", "up-right", "up-left", "down-right", "down-left"]


def doc(**over: Any) -> dict[str, Any]:
    d: dict[str, Any] = {
        "grid": [6, 6],
        "robot": {"start": [0, 0], "goal": [5, 5], "moves": ["stay", "right", "up"]},
        "obstacles": [{"start": [3, 3], "moves": ["stay", "left", "down"]}],
    }
    d.update(over)
    return d


def test_a_file_without_the_new_keys_means_what_it_meant():
    p = grid_problem_from_dict(doc())
    assert p.objective is ObjectiveKind.EXACT and p.collision is CollisionRule.SWEEP and not p.fair
    assert p.paper_model and not p.stateful
    assert p.variables == ("rx", "ry", "o0x", "o0y") and p.max_constant == 5
    assert p.to_dict() == {**doc(), "walls": []}
    assert (
        initial_state(p) == State((0, 0), ((3, 3),))
        and repr(initial_state(p)) == "State(robot=(0, 0), obstacles=((3, 3),))"
    )


@settings(max_examples=150, deadline=None)
@given(objective_documents())
def test_round_trip(d):
    p = grid_problem_from_dict(d)
    assert grid_problem_from_dict(p.to_dict()) == p


def test_inputs_of_each_extension():
    p = grid_problem_from_dict(
        {
            "grid": [8, 8],
            "objective": "recurrence",
            "fair": True,
            "robot": {"start": [0, 0], "goals": [[7, 7], [0, 7]], "moves": KING},
            "obstacles": [
                {"start": [3, 3], "size": [2, 2], "moves": KING, "period": 2, "glitches": 3},
                {"start": [5, 0], "moves": KING},
            ],
        }
    )
    assert p.variables == ("rx", "ry", "o0x", "o0y", "o0p", "o0g", "o1x", "o1y", "m", "f")
    s = initial_state(p)
    assert controller_inputs(p, s) == (0, 0, 3, 3, 1, 3, 5, 0, 0, 0)
    assert p.stateful and not p.paper_model and p.mode_count == 2 and p.fair_count == 2


@pytest.mark.parametrize(
    "over, field, reason",
    [
        ({"objective": "liveness"}, "objective", "expected one of exact, reach, safety, recurrence"),
        ({"objective": "safety"}, "robot.goal", "objective safety takes no goal, not goal"),
        ({"objective": "recurrence"}, "robot.goals", "missing"),
        (
            {"objective": "safety", "robot": {"start": [0, 0], "moves": ["stay"]}, "steps": 3},
            "steps",
            "objective safety has no path length",
        ),
        ({"fair": True}, "fair", "fairness is an assumption of the recurrence objective"),
        ({"fair": "yes"}, "fair", "expected true or false"),
        ({"collision": "touch"}, "collision", "expected one of sweep, position"),
        (
            {"obstacles": [{"start": [5, 5], "size": [2, 2], "moves": ["stay"]}]},
            "obstacles[0].start",
            "the 2x2 block at [5, 5] is outside",
        ),
        ({"obstacles": [{"start": [1, 1], "moves": ["stay"], "period": 0}]}, "obstacles[0].period", "must be >= 1"),
        (
            {"obstacles": [{"start": [1, 1], "moves": ["left", "right"], "period": 2}]},
            "obstacles[0].moves",
            "must be able to wait",
        ),
        (
            {"obstacles": [{"start": [1, 1], "moves": ["stay"], "period": 2, "phase": 2}]},
            "obstacles[0].phase",
            "must be in 0..1",
        ),
        (
            {"obstacles": [{"start": [1, 1], "moves": ["stay"], "glitches": 2}]},
            "obstacles[0].glitches",
            "has nothing to glitch",
        ),
        (
            {"obstacles": [{"start": [1, 1], "moves": ["stay"], "schedule": "daily", "period": 2}]},
            "obstacles[0].schedule",
            "expected one of rest, fixed",
        ),
        (
            {"obstacles": [{"start": [1, 1], "moves": ["stay"], "keep_out": [[9, 9]]}]},
            "obstacles[0].keep_out",
            "is outside",
        ),
        ({"obstacles": [{"start": [1, 1], "moves": ["stay"], "speed": 2}]}, "obstacles[0]", "speed"),
    ],
)
def test_bad_fields_are_named(over, field, reason):
    with pytest.raises(InvalidProblem, match=re.escape(field) + ".*" + re.escape(reason)):
        grid_problem_from_dict(doc(**over), source="p.yaml")


def test_a_block_sweeps_its_cells_and_stops_at_keep_out_cells():
    p = grid_problem_from_dict(
        doc(obstacles=[{"start": [2, 2], "size": [2, 2], "moves": ["stay", "left", "up"], "keep_out": [[2, 4]]}])
    )
    end, swept = obstacle_move(p, 0, (2, 2), 1)
    assert end == (1, 2) and set(swept) == {(1, 2), (2, 2), (3, 2), (1, 3), (2, 3), (3, 3)}
    assert obstacle_move(p, 0, (2, 2), 2) == ((2, 2), ((2, 2), (3, 2), (2, 3), (3, 3)))  # (2, 4) kept out
    # the robot moving into the block's far cell collides (sweep rule)
    assert step(p, State((4, 3), ((2, 2),)), 0, (1,)).collided is False
    assert step(p, State((3, 1), ((2, 2),)), 2, (0,)).collided is True


def test_position_rule_counts_only_cells_after_the_step():
    base = doc(
        obstacles=[{"start": [2, 0], "moves": ["stay", "left"]}],
        robot={"start": [1, 0], "goal": [5, 5], "moves": ["stay", "right", "left"]},
    )
    sweep = grid_problem_from_dict(base)
    pos = grid_problem_from_dict({**base, "collision": "position"})
    s = initial_state(sweep)
    # the robot steps into the cell the obstacle leaves: swept cells meet, positions do not
    assert step(sweep, s, 1, (0,)).collided and step(pos, s, 1, (0,)).collided
    assert step(sweep, State((1, 0), ((3, 0),)), 1, (1,)).collided  # they swap into (2, 0)
    assert step(pos, State((1, 0), ((3, 0),)), 1, (1,)).collided
    assert step(sweep, State((2, 0), ((1, 0),)), 0, (0,)).collided is False
    assert step(sweep, State((1, 0), ((2, 0),)), 1, (1,)).collided  # a swap: swept cells meet
    assert step(pos, State((1, 0), ((2, 0),)), 1, (1,)).collided is False  # positions only: they cross


def test_rest_schedule_and_glitches_follow_ehlers():
    """period 2, schedule rest: the obstacle must wait one step after each change unless
    it spends a glitch; it waits in the first step (phase 1: the robot moves first)."""
    p = grid_problem_from_dict(
        {
            "grid": [6, 6],
            "objective": "safety",
            "collision": "position",
            "robot": {"start": [0, 0], "moves": ["stay"]},
            "obstacles": [{"start": [4, 4], "size": [2, 2], "moves": KING, "period": 2, "glitches": 1}],
        }
    )
    s = initial_state(p)
    assert (s.phases, s.glitches) == ((1,), (1,))
    assert len(list(joint_choices(p, s))) == 9  # a glitch is left: every move
    s1 = step(p, s, 0, (KING.index("left"),)).state  # a glitch: moves while waiting
    assert (s1.obstacles, s1.phases, s1.glitches) == (((3, 4),), (1,), (0,))
    assert legal_moves(p, s1, 0) == (0,) or all(
        obstacle_move(p, 0, (3, 4), k)[0] == (3, 4) for k in legal_moves(p, s1, 0)
    )
    with pytest.raises(ValueError, match="may not change its cell"):
        step(p, s1, 0, (KING.index("left"),))
    s2 = step(p, s1, 0, (0,)).state  # it rests: may move next step
    assert s2.phases == (0,)
    s3 = step(p, s2, 0, (KING.index("down"),)).state
    assert (s3.obstacles, s3.phases, s3.glitches) == (((3, 3),), (1,), (0,))


def test_fixed_schedule_moves_only_at_its_phase():
    p = grid_problem_from_dict(
        {
            "grid": [5, 1],
            "objective": "safety",
            "robot": {"start": [0, 0], "moves": ["stay"]},
            "obstacles": [{"start": [4, 0], "moves": ["stay", "left"], "period": 2, "schedule": "fixed"}],
        }
    )
    s = initial_state(p)
    seen = []
    for _ in range(5):
        seen.append(legal_moves(p, s, 0))
        s = step(p, s, 0, (0,)).state  # it never moves: the phase still turns
    assert seen == [(0,), (0, 1), (0,), (0, 1), (0,)]


def test_mode_and_fairness_counters():
    p = grid_problem_from_dict(
        {
            "grid": [3, 1],
            "objective": "recurrence",
            "fair": True,
            "robot": {"start": [0, 0], "goals": [[1, 0], [0, 0]], "moves": ["stay", "right", "left"]},
            "obstacles": [{"start": [2, 0], "moves": ["stay"]}, {"start": [2, 0], "moves": ["stay"]}],
        }
    )
    s = step(p, initial_state(p), 1, (0, 0)).state
    assert s.mode == 1 and s.fair == 0  # reached goal 0; no obstacle moved
    assert step(p, s, 0, (0, 0)).state.mode == 1  # staying on goal 0 does not count for goal 1
    assert step(p, s, 2, (0, 0)).state.mode == 0
