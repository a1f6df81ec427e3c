"""The team page's data: a team problem and its result, as JSON.

What the page draws (teams of robots and moving obstacles, docs/explanation/teams.md;
each robot plans as in Shoukry et al., CDC 2016): the workspace and static obstacles as
the reach page draws them (:mod:`~plansynth.view.reach_data`); each robot's start, goal,
footprint and trajectory in its own colour (the colours of ``plansynth reach plot``);
every moving obstacle's shape around its reference point and its waypoints, which the
page interpolates linearly at each step's time as the team validator reads them (at the
first waypoint before its time, at the last after); the answer as ``plansynth reach
solve`` words it and the independent team validator's verdict
(:func:`plansynth.reach.team.validate.validate_team`).

3-D problems are drawn as their projection on the first two axes.

>>> from plansynth.reach.team.families import patrol_gap
>>> d = team_page_data(patrol_gap(), None)
>>> d["kind"], [r["name"] for r in d["robots"]], d["moving"][0]["positions"][:2], d["steps"]
('team', ['robot'], [[28.0, 12.5], [28.0, 17.5]], 200)
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.reach.team.problem import GoalPoint, TeamProblem, TeamRobot
from plansynth.reach.trajectory import Trajectory
from plansynth.view.reach_data import reach_words, shape_json, vector_text, world_json
from plansynth.view.status import result_status

__all__ = ["team_page_data", "read_team_result"]


def _robot_json(problem: TeamProblem, r: int, robot: TeamRobot) -> dict[str, Any]:
    from plansynth.reach.team.plot import robot_colour

    rs = robot.robot_shape
    footprint: dict[str, Any] | None = None
    if rs is not None and not rs.is_point:
        footprint = {"radius": rs.radius} if rs.radius is not None else {"half": list(rs.margins(problem.dim)[:2])}
    goal = robot.goal
    return {
        "name": robot.name,
        "colour": robot_colour(r),
        "start": [float(v) for v in robot.start_position[:2]],
        "goal": None
        if goal is None
        else ({"point": list(goal.point[:2])} if isinstance(goal, GoalPoint) else shape_json(goal)),
        "mission": robot.mission,
        "footprint": footprint,
        "position": list(robot.dynamics.position[:2]),
    }


def read_team_result(doc: Any, problem: TeamProblem, source: str) -> tuple[str, list[Trajectory] | None]:
    """Status and the robots' trajectories (or None) of a team result document, checked
    against ``problem``: a single-robot result, robots other than the problem's, or a
    robot's states of another dimension or from another start is an
    :class:`InvalidProblem` naming ``source`` and the field."""
    from plansynth.reach.team.result import team_trajectories_from_dict

    status = result_status(doc, source, "reach")
    if "robots" not in doc:
        raise InvalidProblem(
            source,
            "robots",
            f"missing: a single-robot result (states, inputs), and {problem.name} is a team of "
            f"{problem.n_robots}: give it with a single-robot problem",
        )
    if doc.get("robots") is None:
        return status, None
    names = [r.name for r in problem.robots]
    trajectories, _ = team_trajectories_from_dict(doc, source, names)
    horizons = {t.horizon for t in trajectories}
    if len(horizons) != 1:
        raise InvalidProblem(source, "robots", f"the robots' trajectories have different horizons {sorted(horizons)}")
    index = {str(e.get("name", names[k])): k for k, e in enumerate(doc["robots"])}  # as read above
    for robot, t in zip(problem.robots, trajectories):
        k = index.get(robot.name, 0)
        n, m = robot.dynamics.n_states, robot.dynamics.n_inputs
        if t.n_states != n:
            raise InvalidProblem(
                source,
                f"robots[{k}].states[0]",
                f"has {t.n_states} components, but robot {robot.name} of {problem.name} has {n} states: "
                "a result of another problem",
            )
        if t.horizon > 0 and t.n_inputs != m:
            raise InvalidProblem(
                source,
                f"robots[{k}].inputs[0]",
                f"has {t.n_inputs} components, but robot {robot.name} of {problem.name} has {m} inputs: "
                "a result of another problem",
            )
        start = np.asarray(robot.start, float)
        if not np.allclose(t.states[0], start, rtol=0, atol=1e-6 * max(1.0, float(np.abs(start).max()))):
            raise InvalidProblem(
                source,
                f"robots[{k}].states[0]",
                f"{vector_text(t.states[0])} is not the start {vector_text(start)} of robot {robot.name} "
                f"of {problem.name}: a result of another problem",
            )
    return status, trajectories


def _last_waypoint_step(problem: TeamProblem) -> int:
    """The first step at or after every moving obstacle's last waypoint (at most
    ``max_horizon``): how far the page plays the obstacles without a plan."""
    last = max((o.times[-1] for o in problem.moving_obstacles), default=0.0)
    dt = problem.time_of(1)
    return int(min(problem.max_horizon, max(0, int(np.ceil(last / dt - 1e-9)))))


def team_page_data(
    problem: TeamProblem, result: Mapping[str, Any] | None, *, source: str = "<result>"
) -> dict[str, Any]:
    """Everything the team page shows (see the module docstring); ``result`` is a team
    result document (``plansynth reach solve -o`` on a team problem) or None for the
    problem alone."""
    data: dict[str, Any] = {
        "kind": "team",
        **world_json(problem),
        "dt": problem.time_of(1),
        "separation": problem.separation.distance,
        "robots": [_robot_json(problem, r, robot) for r, robot in enumerate(problem.robots)],
        "moving": [
            {
                "name": o.name,
                "shape": shape_json(o.shape),
                "times": list(o.times),
                "positions": [list(p[:2]) for p in o.positions],
            }
            for o in problem.moving_obstacles
        ],
        "steps": _last_waypoint_step(problem),
        "status": None,
        "words": [],
        "trajectories": None,
        "validation": None,
    }
    if result is None:
        return data
    status, trajectories = read_team_result(result, problem, source)
    data.update(status=status, words=[*reach_words(result), f"robots: {problem.n_robots}"])
    if trajectories is None:
        return data
    from plansynth.reach.team.validate import validate_team

    data["trajectories"] = [
        {
            "states": t.states.tolist(),
            "inputs": t.inputs.tolist(),
            "positions": t.states[:, list(robot.dynamics.position[:2])].tolist(),
        }
        for robot, t in zip(problem.robots, trajectories)
    ]
    data["steps"] = trajectories[0].horizon
    report = validate_team(problem, trajectories)
    data["validation"] = {"ok": report.ok, "summary": report.summary()}
    return data
