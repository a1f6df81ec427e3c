"""The file format of reach-avoid problems (the project's reach-problem spec, YAML or
JSON): :func:`load_reach_problem` checks every field at the door, and every bad input
raises :class:`~plansynth.errors.InvalidProblem` naming the file, the field and the
reason; :func:`reach_problem_to_dict` writes a problem back, so that problems
round-trip.

>>> reach_problem_from_dict({
...     "workspace": {"min": [0, 0], "max": [10, 10]},
...     "obstacles": [{"min": [2, 2], "max": [4, 4]}],
...     "goal": {"min": [8, 8], "max": [9, 9]},
...     "robot": {"dynamics": {"model": "single-integrator", "dt": 1.0},
...               "start": [3, 3], "input_bound": 1.0}}, source="p.yaml")
Traceback (most recent call last):
...
plansynth.errors.InvalidProblem: p.yaml: robot.start: position (3, 3) lies inside obstacles[0]
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.io import (
    Fields,
    as_float,
    as_float_vector,
    as_int,
    as_int_vector,
    as_name,
    load_document,
    show,
    type_name,
)
from plansynth.reach.disturbance import MAX_VERTICES as MAX_DISTURBANCE_VERTICES
from plansynth.reach.disturbance import Disturbance
from plansynth.reach.dynamics import NAMED_MODELS, LinearDynamics, named_model
from plansynth.reach.geometry import Box, Polygon, Shape, polygon_problem
from plansynth.reach.problem import (
    DEFAULT_MAX_HORIZON,
    MAX_COORDINATE,
    MAX_DT,
    MAX_HORIZON,
    MAX_OBSTACLES,
    MAX_ORDER,
    MAX_STATES,
    MAX_VERTICES,
    ReachProblem,
)
from plansynth.reach.robot import RobotShape

__all__ = ["load_reach_problem", "reach_problem_from_dict", "reach_problem_to_dict"]


_TOP_KEYS = {"workspace", "obstacles", "goal", "robot", "max_horizon", "name", "labels", "mission"}
_ROBOT_KEYS = {"dynamics", "start", "input_bound", "state_bounds", "radius", "half_extent", "disturbance"}


def load_reach_problem(path: str | Path) -> ReachProblem:
    """Read a reach-avoid problem file (YAML or JSON) per the spec.

    The problem's ``name`` defaults to the file's stem.
    """
    doc, name = load_document(path)
    return reach_problem_from_dict(doc, source=name, default_name=Path(path).stem)


def reach_problem_from_dict(doc: Any, source: str | None = None, *, default_name: str = "reach") -> ReachProblem:
    """Build a problem from a parsed document; every bad input raises InvalidProblem."""
    top = Fields(doc, source, "")
    top.reject_unknown(_TOP_KEYS)
    workspace = _parse_box(top.require("workspace"), source, "workspace")
    d = workspace.dim
    if d not in (2, 3):
        raise InvalidProblem(source, "workspace", f"must be 2-D or 3-D, got {d}-D")
    raw_obs = top.optional("obstacles", [])
    if not isinstance(raw_obs, Sequence) or isinstance(raw_obs, (str, bytes)):
        raise InvalidProblem(source, "obstacles", f"expected a list of boxes or polygons, got {type_name(raw_obs)}")
    if len(raw_obs) > MAX_OBSTACLES:
        raise InvalidProblem(source, "obstacles", f"at most {MAX_OBSTACLES} obstacles, got {len(raw_obs)}")
    obstacles = tuple(_parse_shape(o, source, f"obstacles[{i}]", d) for i, o in enumerate(raw_obs))
    mission = top.optional("mission")
    goal_raw = top.optional("goal") if mission is not None else top.require("goal")
    goal = None if goal_raw is None else _parse_shape(goal_raw, source, "goal", d)
    labels = _parse_labels(top.optional("labels", {}), source, d)

    robot = Fields(top.require("robot"), source, "robot")
    robot.reject_unknown(_ROBOT_KEYS)
    dynamics = _parse_dynamics(robot.require("dynamics"), source, d)
    n = dynamics.n_states
    start = as_float_vector(robot.require("start"), source, "robot.start", n, max_abs=MAX_COORDINATE)
    input_bound = as_float(
        robot.require("input_bound"), source, "robot.input_bound", positive=True, max_abs=MAX_COORDINATE
    )
    sb_raw = robot.optional("state_bounds")
    state_bounds = None if sb_raw is None else _parse_box(sb_raw, source, "robot.state_bounds", allow_flat=True)
    if state_bounds is not None and state_bounds.dim != n:
        raise InvalidProblem(
            source, "robot.state_bounds", f"must be {n}-dimensional like the state, got {state_bounds.dim}"
        )
    radius_raw, half_raw = robot.optional("radius"), robot.optional("half_extent")
    robot_shape = None
    if radius_raw is not None and half_raw is not None:
        raise InvalidProblem(source, "robot.radius", "give either radius (a disc) or half_extent (a box), not both")
    if radius_raw is not None:
        r = as_float(radius_raw, source, "robot.radius")
        if not math.isfinite(r) or r < 0:
            raise InvalidProblem(source, "robot.radius", f"must be a non-negative number, got {r}")
        robot_shape = RobotShape(radius=r)
    elif half_raw is not None:
        robot_shape = RobotShape(half_extent=tuple(as_float_vector(half_raw, source, "robot.half_extent", d)))
    dist_raw = robot.optional("disturbance")
    disturbance = None if dist_raw is None else _parse_disturbance(dist_raw, source, n, dynamics.n_inputs)
    max_horizon = as_int(top.optional("max_horizon", DEFAULT_MAX_HORIZON), source, "max_horizon", hi=MAX_HORIZON)
    if max_horizon <= 0:
        raise InvalidProblem(source, "max_horizon", f"must be positive, got {max_horizon}")
    name = as_name(top.optional("name", default_name), source)
    return ReachProblem(
        workspace=workspace,
        obstacles=obstacles,
        goal=goal,
        dynamics=dynamics,
        start=np.array(start),
        input_bound=input_bound,
        state_bounds=state_bounds,
        max_horizon=max_horizon,
        name=name,
        source=source,
        robot_shape=robot_shape,
        labels=labels,
        mission=mission,
        disturbance=disturbance,
    )


def _parse_disturbance(value: Any, src: str | None, n: int, m: int) -> Disturbance:
    """``robot.disturbance``: ``{box: [n half-widths]}`` or ``{polytope: [[n numbers],
    ...]}`` (W's vertices), and ``feedback``: ``lqr`` (default), ``deadbeat``,
    ``{lqr: {q: [n], r: [m]}}`` or ``{gain: [[n numbers] x m]}``."""
    where = "robot.disturbance"
    f = Fields(value, src, where)
    f.reject_unknown({"box", "polytope", "feedback"})
    box_raw, poly_raw = f.optional("box"), f.optional("polytope")
    if (box_raw is None) == (poly_raw is None):
        raise InvalidProblem(src, where, "give either box (half-widths) or polytope (vertices of W), exactly one")
    box, vertices = None, None
    if box_raw is not None:
        box = as_float_vector(box_raw, src, f"{where}.box", n, max_abs=MAX_COORDINATE)
        if any(not v >= 0 for v in box):
            raise InvalidProblem(src, f"{where}.box", f"half-widths must be >= 0, got {list(box)}")
    else:
        if not isinstance(poly_raw, Sequence) or isinstance(poly_raw, (str, bytes)) or not poly_raw:
            raise InvalidProblem(src, f"{where}.polytope", f"expected a list of vertices, got {show(poly_raw)}")
        if len(poly_raw) > MAX_DISTURBANCE_VERTICES:
            raise InvalidProblem(
                src, f"{where}.polytope", f"at most {MAX_DISTURBANCE_VERTICES} vertices, got {len(poly_raw)}"
            )
        vertices = np.array(
            [
                as_float_vector(v, src, f"{where}.polytope[{i}]", n, max_abs=MAX_COORDINATE)
                for i, v in enumerate(poly_raw)
            ]
        )
    design, q, r, gain = _parse_feedback(f.optional("feedback", "lqr"), src, f"{where}.feedback", n, m)
    return Disturbance(box=box, vertices=vertices, feedback=design, q=q, r=r, gain=gain)


def _parse_feedback(value: Any, src: str | None, where: str, n: int, m: int) -> tuple[str, Any, Any, Any]:
    if isinstance(value, str):
        if value not in ("lqr", "deadbeat"):
            raise InvalidProblem(
                src, where, f"unknown design {show(value)} (known: lqr, deadbeat, {{lqr: {{q, r}}}}, {{gain: K}})"
            )
        return value, None, None, None
    f = Fields(value, src, where)
    f.reject_unknown({"lqr", "gain"})
    if ("lqr" in value) == ("gain" in value):
        raise InvalidProblem(src, where, "give either lqr (its weights) or gain (the matrix K), exactly one")
    if "gain" in value:
        K = _parse_matrix(value["gain"], src, f"{where}.gain")
        if K.shape != (m, n):
            raise InvalidProblem(
                src, f"{where}.gain", f"must be {m} x {n} (inputs x states), got {K.shape[0]} x {K.shape[1]}"
            )
        return "gain", None, None, K
    w = Fields(value["lqr"], src, f"{where}.lqr")
    w.reject_unknown({"q", "r"})
    q_raw, r_raw = w.optional("q"), w.optional("r")
    q = None if q_raw is None else as_float_vector(q_raw, src, f"{where}.lqr.q", n, max_abs=MAX_COORDINATE)
    r = None if r_raw is None else as_float_vector(r_raw, src, f"{where}.lqr.r", m, max_abs=MAX_COORDINATE)
    for key, vec in (("q", q), ("r", r)):
        if vec is not None and any(not v > 0 for v in vec):
            raise InvalidProblem(src, f"{where}.lqr.{key}", f"weights must be positive, got {list(vec)}")
    return "lqr", q, r, None


def _parse_labels(value: Any, src: str | None, d: int) -> tuple[tuple[str, Shape], ...]:
    """``labels:`` maps names to boxes ``{min, max}``, polygons ``{polygon: [...]}`` (or
    ``{vertices: [...]}``, or a bare vertex list)."""
    if not isinstance(value, Mapping):
        raise InvalidProblem(
            src, "labels", f"expected a mapping from names to boxes or polygons, got {type_name(value)}"
        )
    out = []
    for name, shape in value.items():
        where = f"labels.{name}"
        if isinstance(shape, Mapping) and "polygon" in shape:
            Fields(shape, src, where).reject_unknown({"polygon"})
            out.append((str(name), _parse_polygon(shape["polygon"], src, f"{where}.polygon", d)))
        else:
            out.append((str(name), _parse_shape(shape, src, where, d)))
    return tuple(out)


def _parse_box(value: Any, src: str | None, where: str, *, dim: int | None = None, allow_flat: bool = False) -> Box:
    f = Fields(value, src, where)
    f.reject_unknown({"min", "max"})
    lo = as_float_vector(f.require("min"), src, f"{where}.min", dim, max_abs=MAX_COORDINATE)
    hi = as_float_vector(f.require("max"), src, f"{where}.max", len(lo), max_abs=MAX_COORDINATE)
    if len(lo) == 0:
        raise InvalidProblem(src, f"{where}.min", "must not be empty")
    if allow_flat:
        if any(not l <= h for l, h in zip(lo, hi)):
            raise InvalidProblem(src, where, f"min {list(lo)} exceeds max {list(hi)}")
    elif any(not l < h for l, h in zip(lo, hi)):
        raise InvalidProblem(src, where, f"degenerate box: min {list(lo)} is not below max {list(hi)}")
    return Box(lo, hi)


def _parse_shape(value: Any, src: str | None, where: str, d: int) -> Shape:
    if isinstance(value, Mapping):
        if "vertices" in value:
            f = Fields(value, src, where)
            f.reject_unknown({"vertices"})
            return _parse_polygon(value["vertices"], src, f"{where}.vertices", d)
        return _parse_box(value, src, where, dim=d)
    if isinstance(value, Sequence) and not isinstance(value, (str, bytes)):
        return _parse_polygon(value, src, where, d)
    raise InvalidProblem(
        src, where, f"expected a box {{min, max}} or a polygon (list of vertices), got {type_name(value)}"
    )


def _parse_polygon(value: Any, src: str | None, where: str, d: int) -> Polygon:
    if d != 2:
        raise InvalidProblem(src, where, f"polygons are 2-D but the workspace is {d}-D (use boxes)")
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)):
        raise InvalidProblem(src, where, f"expected a list of [x, y] vertices, got {type_name(value)}")
    if len(value) > MAX_VERTICES:
        raise InvalidProblem(src, where, f"at most {MAX_VERTICES} vertices, got {len(value)}")
    verts = tuple(as_float_vector(v, src, f"{where}[{i}]", 2, max_abs=MAX_COORDINATE) for i, v in enumerate(value))
    poly = Polygon(verts)
    why = polygon_problem(poly)
    if why is not None:
        raise InvalidProblem(src, where, why)
    return poly


def _parse_dynamics(value: Any, src: str | None, d: int) -> LinearDynamics:
    where = "robot.dynamics"
    f = Fields(value, src, where)
    if "model" in value and value["model"] != "explicit":
        f.reject_unknown({"model", "dt", "order"})
        model = f.require("model")
        if not isinstance(model, str) or model not in NAMED_MODELS:
            raise InvalidProblem(
                src,
                f"{where}.model",
                f"unknown model {show(model)} (known: {', '.join(NAMED_MODELS)}, or give A and B)",
            )
        dt = as_float(f.require("dt"), src, f"{where}.dt", positive=True, max_abs=MAX_DT)
        order_raw = f.optional("order")
        order = None if order_raw is None else as_int(order_raw, src, f"{where}.order", hi=MAX_ORDER)
        implied = {"single-integrator": 1, "double-integrator": 2}.get(model)
        if implied is None and order is None:
            raise InvalidProblem(src, f"{where}.order", "missing required field (integrator-chain needs its order)")
        if order is not None and order < 1:
            raise InvalidProblem(src, f"{where}.order", f"must be a positive integer, got {order}")
        if implied is not None and order is not None and order != implied:
            raise InvalidProblem(src, f"{where}.order", f"{model} has order {implied}, got {order}")
        return named_model(model, d, dt, order)
    f.reject_unknown({"model", "A", "B", "position", "dt"})
    A = _parse_matrix(f.require("A"), src, f"{where}.A")
    B = _parse_matrix(f.require("B"), src, f"{where}.B")
    n = A.shape[0]
    if A.shape != (n, n):
        raise InvalidProblem(src, f"{where}.A", f"must be square, got {A.shape[0]} x {A.shape[1]}")
    if B.shape[0] != n:
        raise InvalidProblem(src, f"{where}.B", f"must have {n} rows like A, got {B.shape[0]} x {B.shape[1]}")
    position = as_int_vector(f.require("position"), src, f"{where}.position", d)
    if len(set(position)) != d or any(not 0 <= i < n for i in position):
        raise InvalidProblem(
            src, f"{where}.position", f"must be {d} distinct state indices in 0..{n - 1}, got {list(position)}"
        )
    dt_raw = f.optional("dt")
    dt = None if dt_raw is None else as_float(dt_raw, src, f"{where}.dt", positive=True, max_abs=MAX_DT)
    return LinearDynamics(A=A, B=B, position=position, dt=dt, model="explicit", order=None)


def _parse_matrix(value: Any, src: str | None, where: str) -> np.ndarray:
    if not isinstance(value, Sequence) or isinstance(value, (str, bytes)) or len(value) == 0:
        raise InvalidProblem(src, where, f"expected a non-empty list of rows, got {show(value)}")
    if len(value) > MAX_STATES:
        raise InvalidProblem(src, where, f"at most {MAX_STATES} rows, got {len(value)}")
    for i, r in enumerate(value):
        if isinstance(r, Sequence) and len(r) > MAX_STATES:
            raise InvalidProblem(src, f"{where}[{i}]", f"at most {MAX_STATES} columns, got {len(r)}")
    rows = [as_float_vector(r, src, f"{where}[{i}]", max_abs=MAX_COORDINATE) for i, r in enumerate(value)]
    width = len(rows[0])
    if width == 0:
        raise InvalidProblem(src, f"{where}[0]", "empty row")
    for i, r in enumerate(rows):
        if len(r) != width:
            raise InvalidProblem(src, f"{where}[{i}]", f"row of length {len(r)}, expected {width} like row 0")
    return np.array(rows, dtype=float)


# --------------------------------------------------------------------------- writing


def _num(x: float) -> float | int:
    return int(x) if float(x).is_integer() and abs(x) < 2**53 else float(x)


def _box_to_dict(b: Box) -> dict:
    return {"min": [_num(v) for v in b.lo], "max": [_num(v) for v in b.hi]}


def _shape_to_dict(s: Shape) -> Any:
    if isinstance(s, Box):
        return _box_to_dict(s)
    return [[_num(x), _num(y)] for x, y in s.vertices]


def _disturbance_to_dict(w: Disturbance) -> dict:
    out: dict[str, Any] = (
        {"box": [_num(v) for v in w.box]}
        if w.box is not None
        else {"polytope": [[_num(v) for v in row] for row in np.asarray(w.vertices).tolist()]}
    )
    if w.feedback == "gain":
        out["feedback"] = {"gain": [[_num(v) for v in row] for row in np.asarray(w.gain).tolist()]}
    elif w.feedback == "lqr" and (w.q is not None or w.r is not None):
        weights = {k: [_num(v) for v in getattr(w, k)] for k in ("q", "r") if getattr(w, k) is not None}
        out["feedback"] = {"lqr": weights}
    elif w.feedback != "lqr":
        out["feedback"] = w.feedback
    return out


def reach_problem_to_dict(problem: ReachProblem) -> dict:
    """The spec document of a problem; ``reach_problem_from_dict`` reads it back equal.

    >>> from plansynth.reach.families import maze
    >>> p = maze(1)
    >>> reach_problem_from_dict(reach_problem_to_dict(p)) == p
    True
    """
    dyn = problem.dynamics
    if dyn.model == "explicit":
        dd: dict[str, Any] = {
            "A": [[_num(v) for v in row] for row in dyn.A.tolist()],
            "B": [[_num(v) for v in row] for row in dyn.B.tolist()],
            "position": list(dyn.position),
        }
        if dyn.dt is not None:
            dd["dt"] = _num(dyn.dt)
    else:
        dd = {"model": dyn.model, "dt": _num(dyn.dt)}  # type: ignore[arg-type]
        if dyn.model == "integrator-chain":
            dd["order"] = dyn.order
    robot: dict[str, Any] = {
        "dynamics": dd,
        "start": [_num(v) for v in problem.start.tolist()],
        "input_bound": _num(problem.input_bound),
    }
    if problem.state_bounds is not None:
        robot["state_bounds"] = _box_to_dict(problem.state_bounds)
    w = problem.disturbance
    if w is not None:
        robot["disturbance"] = _disturbance_to_dict(w)
    rs = problem.robot_shape
    if rs is not None and not rs.is_point:
        if rs.radius is not None:
            robot["radius"] = _num(rs.radius)
        else:
            robot["half_extent"] = [_num(v) for v in rs.half_extent]  # type: ignore[union-attr]
    out = {
        "name": problem.name,
        "workspace": _box_to_dict(problem.workspace),
        "obstacles": [_shape_to_dict(o) for o in problem.obstacles],
        "goal": None if problem.goal is None else _shape_to_dict(problem.goal),
        "robot": robot,
        "max_horizon": problem.max_horizon,
    }
    if problem.goal is None:
        del out["goal"]
    if problem.labels:
        out["labels"] = {
            k: (_box_to_dict(v) if isinstance(v, Box) else {"polygon": _shape_to_dict(v)}) for k, v in problem.labels
        }
    if problem.mission is not None:
        out["mission"] = problem.mission
    return out
