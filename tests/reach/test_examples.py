"""The example files: they load, are what the families generate, have a region path from
start to goal; and the Dubins example's mapping back to the car (Section VI-A)."""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path

import numpy as np
import pytest

from plansynth.reach.abstraction import abstract
from plansynth.reach.dubins import linearising_feedback, simulate_unicycle, unicycle_controls
from plansynth.reach.families import dubins_example, examples, maze, write_examples
from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.geometry import Box
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import validate

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "reach"
NAMES = ["maze-1", "maze-2", "maze-3", "maze-4", "chain-maze-2", "dubins", "cluttered", "maze-3-windy"]


def test_every_example_is_there() -> None:
    # (the hand-written LTL mission examples, mission-*.yaml, are tested in test_mission_planner.py)
    assert sorted(p.stem for p in EXAMPLES.glob("*.yaml") if not p.stem.startswith("mission-")) == sorted(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_example_loads_and_matches_its_family(name: str) -> None:
    p = load_reach_problem(EXAMPLES / f"{name}.yaml")
    assert p.name == name
    assert p == examples()[name]


def test_example_files_are_up_to_date(tmp_path: Path) -> None:
    for path in write_examples(tmp_path):
        assert path.read_text() == (EXAMPLES / path.name).read_text(), f"regenerate {path.name}"


@pytest.mark.parametrize("name", NAMES)
def test_goal_is_reachable_in_the_region_graph(name: str) -> None:
    p = load_reach_problem(EXAMPLES / f"{name}.yaml")
    a = abstract(p)
    seen = set(a.start_regions)
    queue = deque(a.start_regions)
    while queue:
        i = queue.popleft()
        for j in a.adjacency[i]:
            if j not in seen:
                seen.add(j)
                queue.append(j)
    assert seen & set(a.goal_regions)


def test_maze_family_matches_the_benchmark_text() -> None:
    for n in (1, 2, 3, 4):
        p = maze(n)
        assert p.workspace == Box((0, 0), (30, 30)) and len(p.obstacles) == 2 * n
        for i in range(1, n + 1):
            left, right = p.obstacles[2 * i - 2], p.obstacles[2 * i - 1]
            yc = 30 * i / (n + 1)
            assert left.lo[1] == right.lo[1] == yc - 0.5 and left.hi[1] == right.hi[1] == yc + 0.5
            gap = (left.hi[0], right.lo[0])
            assert gap == ((27, 29) if i % 2 == 1 else (1, 3))
        last_gap_right = n % 2 == 1
        assert p.goal == (Box((1, 27), (3, 29)) if last_gap_right else Box((27, 27), (29, 29)))
        assert p.start.tolist() == [1, 1, 0, 0] and p.input_bound == 1
        assert p.state_bounds == Box((0, 0, -2, -2), (30, 30, 2, 2)) and p.dynamics.dt == 0.5
    chain = maze(2, order=4)
    assert chain.state_bounds == Box((0, 0) + (-2,) * 6, (30, 30) + (2,) * 6)


# ----------------------------------------------------------------- Dubins mapping


def rollout(problem, inputs) -> Trajectory:
    X = [problem.start]
    for u in inputs:
        X.append(problem.dynamics.step(X[-1], u))
    return Trajectory(np.array(X), np.array(inputs))


def test_unicycle_follows_the_double_integrator() -> None:
    p = dubins_example()
    t = np.arange(12) * 0.5
    inputs = np.stack([0.3 * np.cos(t), 0.6 * np.sin(0.7 * t)], axis=1)  # |u| <= 1, speed stays > 0
    traj = rollout(p, inputs)
    c = unicycle_controls(p, traj)
    assert c.singular == () and c.singular_steps == () and c.min_speed > 0.5
    car = simulate_unicycle(p, traj)
    np.testing.assert_allclose(car[:, :2], traj.states[:, :2], atol=1e-6)
    np.testing.assert_allclose(car[:, 3], c.speed, atol=1e-6)
    np.testing.assert_allclose(np.cos(car[:, 2]), np.cos(c.heading), atol=1e-6)


def test_feedback_inverts_the_flat_map() -> None:
    rng = np.random.default_rng(1)
    for _ in range(50):
        s, th = rng.uniform(0.1, 3), rng.uniform(-math.pi, math.pi)
        u = rng.normal(size=2)
        a, w = linearising_feedback(s, th, u)
        M = np.array([[math.cos(th), -s * math.sin(th)], [math.sin(th), s * math.cos(th)]])
        np.testing.assert_allclose(M @ [a, w], u, atol=1e-12)


def test_singular_where_the_speed_vanishes() -> None:
    p = dubins_example()
    # brake to a stop in two steps (1 m/s east, -1 m/s^2 for 1 s), then go north
    traj = rollout(p, [[-1, 0], [-1, 0], [0, 1], [0, 1]])
    c = unicycle_controls(p, traj)
    assert c.singular == (2,) and math.isnan(c.turn_rate[2])
    assert c.speed[2] == 0 and c.heading[2] == c.heading[1]
    with pytest.raises(ValueError, match="singular"):
        simulate_unicycle(p, traj)
    # passing through zero velocity between samples: reverse from 1 m/s with -1 for 2 s
    traj2 = rollout(p, [[-1, 0], [-1, 0], [-1, 0], [-1, 0]])
    c2 = unicycle_controls(p, traj2)
    assert c2.singular_steps == (1, 2) and c2.step_min_speed is not None and c2.step_min_speed[1] == 0
    with pytest.raises(ValueError, match="singular"):
        simulate_unicycle(p, traj2)


def test_dubins_needs_a_double_integrator() -> None:
    p = maze(1, order=3)
    traj = rollout(p, [[0, 0]])
    with pytest.raises(ValueError, match="double integrator"):
        unicycle_controls(p, traj)


def test_rollouts_in_the_dubins_example_are_valid_until_they_hit_something() -> None:
    p = dubins_example()
    traj = rollout(p, [[0, 0]] * 4)  # coast east at 1 m/s for 2 s
    r = validate(p, traj)
    assert [v.kind for v in r.violations] == ["goal"]  # dynamics exact, only the goal is missed
