"""The reach page's data: a problem, the regions its planner saw and a result, as JSON.

What the page draws (Shoukry et al., CDC 2016, Sections II-III): the workspace,
obstacles, goal and labels; the convex regions of the abstraction (for a mission, the
label-refined regions the mission planner plans in, as ``plansynth reach plot`` draws
them); the trajectory x_0..x_N with its inputs, every state and input component beside
its bounds (``state_bounds`` met with the workspace, ``input_bound``); the independent
validator's verdict (:func:`plansynth.reach.validate`, and for missions the mission
checker); for a mission, the labels that hold at each step (the checker's word of the
trajectory) and the loop of a lasso (``mission.loop_start``: x_N = x_k).

3-D problems are drawn as their projection on the first two axes.

>>> from plansynth.reach import load
>>> d = reach_page_data(load("examples/reach/maze-1.yaml"), None)
>>> d["kind"], d["workspace"], len(d["regions"]) > 0, d["trajectory"]
('reach', [[0.0, 0.0], [30.0, 30.0]], True, None)
>>> reach_words({"status": "infeasible", "horizon": 40, "message": "no plan"})
['status: infeasible', 'horizon: none up to 40', 'message: no plan']
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.io import show
from plansynth.reach import Box, ReachProblem, validate
from plansynth.reach.planner_regions import planner_abstraction
from plansynth.view.status import result_status


def shape_json(shape: Any) -> dict[str, Any]:
    """A box as ``{"box": [lo, hi]}``, a polygon as ``{"poly": [[x, y], ...]}`` (the
    first two axes)."""
    if isinstance(shape, Box):
        return {"box": [list(shape.lo[:2]), list(shape.hi[:2])]}
    return {"poly": [[float(x), float(y)] for x, y, *_ in np.asarray(shape.vertices, float)]}


def world_json(problem: Any) -> dict[str, Any]:
    """What a reach page and a team page both draw of a problem's world: its name and
    dimension, the workspace, the static obstacles and the labels (the first two axes)."""
    return {
        "name": problem.name,
        "dim": problem.dim,
        "workspace": [list(problem.workspace.lo[:2]), list(problem.workspace.hi[:2])],
        "obstacles": [shape_json(o) for o in problem.obstacles],
        "labels": [{"name": name, "shape": shape_json(s)} for name, s in problem.labels],
    }


def _region_outline(vertices: np.ndarray) -> list[list[float]]:
    v = np.asarray(vertices, float)
    if v.shape[1] == 2:
        return [[float(x), float(y)] for x, y in v]
    lo, hi = v.min(axis=0), v.max(axis=0)  # a 3-D box: its rectangle on the first two axes
    return [[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]]


def _names(problem: ReachProblem) -> tuple[list[str], list[str]]:
    """Names of the state and input components: ``x y vx vy ...`` for a named model
    (ordered by derivative, then axis), else ``x0 x1 ...`` and ``u0 u1 ...``."""
    dyn = problem.dynamics
    n, m, d = dyn.n_states, dyn.n_inputs, problem.dim
    axes = "xyz"[:d]
    if dyn.model != "explicit" and n % d == 0:
        prefixes = ["", "v", "a", "j"]
        states = [f"{prefixes[i // d] if i // d < 4 else f'd{i // d}'}{axes[i % d]}" for i in range(n)]
        return states, [f"u{a}" for a in axes][:m] if m == d else [f"u{j}" for j in range(m)]
    return [f"x{i}" for i in range(n)], [f"u{j}" for j in range(m)]


def _finite(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def read_reach_result(doc: Any, problem: ReachProblem, source: str) -> tuple[str, Any]:
    """Status and trajectory (or None) of a reach result document, checked against
    ``problem``: a grid result, or states and inputs of another dimension than the
    problem's dynamics, is an :class:`InvalidProblem` naming ``source`` and the field."""
    from plansynth.reach.trajectory import trajectory_from_dict

    status = result_status(doc, source, "reach")
    if "robots" in doc and "states" not in doc:
        raise InvalidProblem(
            source,
            "states",
            f"missing: a team result (robots), and {problem.name} has one robot: give it with a team problem",
        )
    if doc.get("states") is None:
        return status, None
    trajectory = trajectory_from_dict(doc, source)
    n, m = problem.dynamics.n_states, problem.dynamics.n_inputs
    if trajectory.n_states != n:
        raise InvalidProblem(
            source,
            "states[0]",
            f"has {trajectory.n_states} components, but the dynamics of "
            f"{problem.name} have {n} states: a result of another problem",
        )
    if trajectory.horizon > 0 and trajectory.n_inputs != m:
        raise InvalidProblem(
            source,
            "inputs[0]",
            f"has {trajectory.n_inputs} components, but the dynamics of "
            f"{problem.name} have {m} inputs: a result of another problem",
        )
    start = np.asarray(problem.start, float)
    if not np.allclose(trajectory.states[0], start, rtol=0, atol=1e-6 * max(1.0, float(np.abs(start).max()))):
        raise InvalidProblem(
            source,
            "states[0]",
            f"{vector_text(trajectory.states[0])} is not the start "
            f"{vector_text(start)} of {problem.name}: a result of another problem",
        )
    planned_mission = isinstance(doc.get("mission"), Mapping) and doc["mission"].get("formula") is not None
    if planned_mission != (problem.mission is not None):
        has = "has a mission" if problem.mission is not None else "has no mission"
        raise InvalidProblem(
            source,
            "mission",
            f"the result {'is' if planned_mission else 'is not'} a mission's "
            f"plan, and {problem.name} {has}: a result of another problem",
        )
    return status, trajectory


def vector_text(v: Any) -> str:
    """A vector as ``(1, 2.5)``, for messages."""
    return "(" + ", ".join(f"{float(x):g}" for x in v) + ")"


def reach_words(doc: Mapping[str, Any]) -> list[str]:
    """The answer as ``plansynth reach solve`` words it, one ``item: value`` line per row
    of its table that says what was found: status, horizon (with what a minimal horizon
    or an infeasible one is relative to), validation, guarantee, mission, message."""
    status = doc.get("status")
    c = doc.get("counters") or {}
    lines = [f"status: {status}"]
    horizon = "-" if doc.get("horizon") is None else str(doc["horizon"])
    if status == "infeasible":
        horizon = f"none up to {doc.get('horizon')}"
    if status == "found" and c.get("minimal") is not None:
        relative = c.get("minimal_relative_to", "problem")
        if c["minimal"] and relative != "problem":
            horizon += f" (minimal through the {relative} only)"
        else:
            horizon += " (proved minimal)" if c["minimal"] else " (not proved minimal)"
    lines.append(f"horizon: {horizon}")
    if doc.get("validated") is not None:
        lines.append(f"validated: {'yes' if doc['validated'] else 'NO'}")
    if doc.get("guarantee") is not None:
        safe = doc.get("segment_safe")
        held = "" if safe is None else (", segments safe" if safe else ", segments NOT safe")
        lines.append(f"guarantee: {doc['guarantee']}{held}")
    mission = doc.get("mission") or {}
    if mission.get("semantics"):
        loop = "" if mission.get("loop_start") is None else f", loop from step {mission['loop_start']} (x_N = x_k)"
        verdict = {True: ", mission checked", False: ", mission check FAILED"}.get(mission.get("ok"), "")
        lines.append(f"mission: {mission.get('formula')}: {mission['semantics']} plan{loop}{verdict}")
    if doc.get("message"):
        lines.append(f"message: {doc['message']}")
    return lines


def reach_page_data(
    problem: ReachProblem, result: Mapping[str, Any] | None, *, source: str = "<result>"
) -> dict[str, Any]:
    """Everything the reach page shows (see the module docstring); ``result`` is a
    result document (spec: Result file) or None for the problem and its regions alone."""
    dyn = problem.dynamics
    state_names, input_names = _names(problem)
    lo, hi = problem.state_box
    abstraction = planner_abstraction(problem)
    data: dict[str, Any] = {
        "kind": "reach",
        **world_json(problem),
        "goal": None if problem.goal is None else shape_json(problem.goal),
        "mission_text": problem.mission,
        "start": [float(v) for v in problem.start],
        "position": list(dyn.position),
        "regions": [_region_outline(r.vertices) for r in abstraction.regions],
        "state_names": state_names,
        "input_names": input_names,
        "state_bounds": [[_finite(v) for v in lo], [_finite(v) for v in hi]],
        "input_bound": problem.input_bound,
        "dt": dyn.dt,
        "status": None,
        "words": [],
        "trajectory": None,
        "result_regions": None,
        "validation": None,
        "mission": None,
    }
    if result is None:
        return data
    status, trajectory = read_reach_result(result, problem, source)
    data.update(status=status, words=reach_words(result))
    raw_regions = result.get("regions")
    if isinstance(raw_regions, list) and all(
        isinstance(r, int) and 0 <= r < abstraction.n_regions for r in raw_regions
    ):
        data["result_regions"] = raw_regions
    if trajectory is None:
        return data
    data["trajectory"] = {"states": trajectory.states.tolist(), "inputs": trajectory.inputs.tolist()}
    claimed = result.get("segment_safe") is True or result.get("guarantee") == "segments"
    mission = result.get("mission") or {}
    loop_start = mission.get("loop_start") if isinstance(mission, Mapping) else None
    if loop_start is not None and (
        isinstance(loop_start, bool) or not isinstance(loop_start, int) or not 0 <= loop_start < trajectory.horizon
    ):
        raise InvalidProblem(
            source, "mission.loop_start", f"expected a step in 0..{trajectory.horizon - 1}, got {show(loop_start)}"
        )
    if problem.mission is not None:
        from rich.text import Text

        from plansynth.reach.mission.check import trajectory_word, validate_mission_file

        ok, lines = validate_mission_file(problem, trajectory, dict(result), segment_safe=claimed)
        data["validation"] = {"ok": ok, "summary": Text.from_markup(lines[0]).plain}
        letters, _ = trajectory_word(problem, problem.position_of(trajectory.states), loop_start)
        names = [name for name in problem.mission_labels]
        data["mission"] = {
            "formula": problem.mission,
            "loop_start": loop_start,
            "holding": [sorted(n for n in names if n in letter) for letter in letters],
        }
    else:
        report = validate(
            problem,
            trajectory,
            require_segment_safe=claimed,
            dynamics="curve" if result.get("guarantee") == "curve" else "exact",
        )
        data["validation"] = {"ok": report.ok, "summary": report.summary()}
    return data
