"""The independent robust validator: does a nominal plan with its gain K keep every
disturbed closed loop safe and reaching?

It knows the problem (dynamics, bounds, obstacles, goal, W) and the plan (the nominal
states and inputs, and K), and nothing of the planner: it uses neither the tube of
:mod:`plansynth.reach.tube` nor the tightened problem nor the decomposition, and it
recomputes everything itself.

**The error sets.** Under ``u_t = v_t + K (x_t - x_nom_t)`` the error obeys
``e_{t+1} = A_K e_t + w_t`` (``A_K = A + B K``) from ``e_0 = 0``, so e_t ranges exactly
over ``E_t = sum_{i<t} A_K^i W``. The validator evaluates support functions
``h_{E_t}(c) = sum_{i<t} h_W((A_K^T)^i c)`` by iterating the direction (no truncation:
every step of the plan exactly), and draws the position part of E_t as an exact convex
polygon: a zonotope's from its sorted generators (box W), a polytope's by convex hulls
of vertex sums.

**The worst case, at every step t = 0..N** (a violation names its kind and step):

``input``        ``v_t +- h_{E_t}(+-K_j)`` outside ``[-ubar, ubar]`` (the disturbed input
                 ``v_t + K e_t`` over every e_t);
``state-bound``  ``x_nom_t,i +- h_{E_t}(+-e_i)`` outside the state bounds;
``workspace``    the same on the positions (with a sized robot, its extent);
``goal``         the final tube ``p_N + E_N`` not inside the (convex) goal:
                 ``H p_N + h_{E_N}(H) <= h`` row by row;
``obstacle``     the tube ``p_t + E_t`` (a polygon) meets an obstacle's interior (deeper
                 than tol; a disc robot: closer than its radius; a box robot: the tube
                 grown by its box);
``segment``      the convex hull of the tubes at both ends of a segment meets an
                 obstacle: every disturbed segment ``(1-s)(p_t+e_t) + s(p_{t+1}+e_{t+1})``
                 lies in it.

Every check at the samples is exact: a violation is reached by some disturbance
sequence within W. The segment check is sufficient, not necessary (the hull contains
every disturbed segment but may be larger than their union): a ``segment`` violation
says the hull touches an obstacle, which a disturbance may or may not realise.
``clearance`` is the smallest distance between a tube (or a segment's hull) and an
obstacle: how much room the worst case leaves.

For a lasso (``loop_start``), the loop repeats forever while the error sets keep
growing, so the loop's steps are checked once more with the limit set, bounded above:
the sum continued until the terms fall below 1e-12 and the rest bounded by a geometric
series (:func:`~plansynth.reach.robust.error_sets.limit_supports`).

>>> from dataclasses import replace
>>> from plansynth.reach.families import maze
>>> from plansynth.reach.disturbance import Disturbance
>>> from plansynth.reach.lazy.planner import plan_lazy
>>> from plansynth.reach.robust.tighten import tightened
>>> p = replace(maze(1), disturbance=Disturbance(box=(0.02, 0.02, 0.05, 0.05)))
>>> t = tightened(p)
>>> plan = plan_lazy(t.problem).trajectory
>>> r = check_robust(p, plan, t.design.K)
>>> r.ok, r.clearance > 0
(True, True)
>>> nominal = plan_lazy(maze(1)).trajectory
>>> bad = check_robust(p, nominal, t.design.K)
>>> bad.ok, sorted(bad.counts)
(False, ['goal', 'input', 'obstacle', 'segment', 'state-bound', 'workspace'])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import shapely

from plansynth.reach.geometry import convex_hull, halfspaces, shape_to_shapely
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robust.error_sets import error_supports, limit_supports, tube_polygons
from plansynth.reach.robust.error_sets import limit_polygon as _limit_polygon
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import Violation

__all__ = ["RobustReport", "check_robust", "error_supports", "tube_polygons"]


@dataclass(frozen=True)
class RobustReport:
    """The robust validator's verdict: ``ok`` (no violation), ``violations`` (the first
    few of each kind), ``counts`` (per kind), ``clearance`` (the worst case's smallest
    distance to an obstacle; inf without obstacles), ``slack`` (per kind of bound, the
    smallest room the worst case leaves), and the ``simulation`` when one was run."""

    ok: bool
    violations: tuple[Violation, ...]
    counts: dict[str, int]
    horizon: int
    clearance: float
    slack: dict[str, float]
    tol: float
    simulation: Any = None
    notes: tuple[str, ...] = field(default_factory=tuple)

    def __bool__(self) -> bool:
        raise TypeError("a RobustReport has no truth value; read .ok")

    def with_violation(self, kind: str, step: int | None, detail: str) -> RobustReport:
        """This report with one more violation."""
        counts = {**self.counts, kind: self.counts.get(kind, 0) + 1}
        return replace(self, ok=False, violations=(*self.violations, Violation(kind, step, detail)), counts=counts)

    def summary(self) -> str:
        verdict = "robust" if self.ok else "NOT robust"
        room = f"worst-case clearance {self.clearance:.4g}" if math.isfinite(self.clearance) else "no obstacles"
        counts = ", ".join(f"{k} x{n}" for k, n in self.counts.items())
        return f"{verdict}: worst case at every step of {self.horizon}, {room}" + (
            f"; violations: {counts}" if counts else ""
        )

    def to_json_dict(self) -> dict[str, Any]:
        return {
            "ok": self.ok,
            "horizon": self.horizon,
            "clearance": self.clearance if math.isfinite(self.clearance) else None,
            "slack": {k: (v if math.isfinite(v) else None) for k, v in self.slack.items()},
            "tol": self.tol,
            "counts": dict(self.counts),
            "violations": [{"kind": v.kind, "step": v.step, "detail": v.detail} for v in self.violations],
            "notes": list(self.notes),
            **({} if self.simulation is None else {"simulation": self.simulation.to_json_dict()}),
        }


# ------------------------------------------------------------------ the checks


class _Report:
    """Violations as they are found, at most :data:`MAX_PER_KIND` listed per kind."""

    MAX_PER_KIND = 20

    def __init__(self) -> None:
        self.violations: list[Violation] = []
        self.counts: dict[str, int] = {}
        self.slack: dict[str, float] = {}

    def room(self, kind: str, values: np.ndarray) -> None:
        if values.size:
            self.slack[kind] = min(self.slack.get(kind, math.inf), float(np.min(values)))

    def add(self, kind: str, step: int | None, detail: str) -> None:
        self.counts[kind] = self.counts.get(kind, 0) + 1
        if self.counts[kind] <= self.MAX_PER_KIND:
            self.violations.append(Violation(kind, step, detail))


def _bound_checks(
    problem: ReachProblem,
    X: np.ndarray,
    U: np.ndarray,
    K: np.ndarray,
    steps_of: np.ndarray,
    sup,
    tol: float,
    rep: _Report,
) -> None:
    """Inputs, state bounds, workspace: the nominal value plus the error's support."""
    n = X.shape[1]
    K = np.asarray(K, float)
    m = K.shape[0]
    ub = problem.input_bound
    if len(U):
        s = sup(np.vstack([K, -K]))[steps_of[:-1]]
        hi_u = U + s[:, :m]
        lo_u = U - s[:, m:]
        room = np.minimum(ub - hi_u, lo_u + ub)
        rep.room("input", room)
        for t, j in zip(*np.nonzero(room < -tol)):
            rep.add(
                "input",
                int(t),
                f"u_{t}[{j}] = v + K e reaches [{lo_u[t, j]:.6g}, {hi_u[t, j]:.6g}], the bound is {ub:g}",
            )
    lo = np.full(n, -np.inf)
    hi = np.full(n, np.inf)
    if problem.state_bounds is not None:
        lo, hi = np.array(problem.state_bounds.lo), np.array(problem.state_bounds.hi)
    pos = list(problem.dynamics.position)
    ws_lo, ws_hi = np.array(problem.workspace.lo, float), np.array(problem.workspace.hi, float)
    if problem.robot_shape is not None:
        margin = np.array(problem.robot_shape.margins(problem.dim))
        ws_lo, ws_hi = ws_lo + margin, ws_hi - margin
    s = sup(np.vstack([np.eye(n), -np.eye(n)]))[steps_of]
    top, bottom = X + s[:, :n], X - s[:, n:]
    for kind, lo_k, hi_k, cols in (
        ("state-bound", lo, hi, list(range(n))),
        ("workspace", ws_lo, ws_hi, pos),
    ):
        room = np.minimum(hi_k[None, :] - top[:, cols], bottom[:, cols] - lo_k[None, :])
        finite = np.isfinite(room)
        rep.room(kind, room[finite])
        for t, k in zip(*np.nonzero(finite & (room < -tol))):
            i = cols[k]
            rep.add(
                kind,
                int(t),
                f"x_{t}[{i}] + e reaches [{bottom[t, i]:.6g}, {top[t, i]:.6g}] outside [{lo_k[k]:g}, {hi_k[k]:g}]",
            )


class _ObstacleTest:
    """One obstacle against tubes: the interior (shrunk by tol) must not meet a tube; a
    disc robot keeps its radius away (a box robot's tubes are grown by its box first,
    :func:`_bodies`)."""

    def __init__(self, problem: ReachProblem, shape: Any, tol: float) -> None:
        geom = shape_to_shapely(shape)
        self.geom = geom
        self.inner = geom.buffer(-tol, join_style="mitre") if tol > 0 else geom
        shapely.prepare(geom)
        if not self.inner.is_empty:
            shapely.prepare(self.inner)
        robot = problem.robot_shape
        self.radius = robot.radius if robot is not None and robot.radius is not None else None
        self.tol = tol

    def clearance(self, g: np.ndarray) -> float:
        d = float(np.min(shapely.distance(self.geom, g), initial=math.inf))
        return d if self.radius is None else d - self.radius

    def hits(self, g: np.ndarray) -> np.ndarray:
        """Which of the geometries ``g`` (an array) come too close."""
        out = np.zeros(len(g), dtype=bool)
        if self.radius is not None:
            out |= shapely.distance(self.geom, g) < self.radius - self.tol
        if not self.inner.is_empty:
            out |= shapely.relate_pattern(self.inner, g, "T********")
        return out


def _bodies(problem: ReachProblem, point_sets: list[np.ndarray]) -> np.ndarray:
    """The convex hulls of the point sets (a box robot's grown by its box): an array of
    shapely geometries (points, segments or polygons)."""
    robot = problem.robot_shape
    if robot is not None and robot.half_extent is not None and not robot.is_point:
        hx, hy = robot.half_extent[:2]
        corners = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
        point_sets = [(pts[:, None, :] + corners[None, :, :]).reshape(-1, 2) for pts in point_sets]
    return np.array([convex_hull(pts) for pts in point_sets], dtype=object)


def check_robust(
    problem: ReachProblem,
    trajectory: Trajectory,
    K: np.ndarray,
    *,
    tol: float = 1e-6,
    loop_start: int | None = None,
    segments: bool = True,
) -> RobustReport:
    """The worst case of the closed loop around ``trajectory`` with gain ``K`` under the
    problem's disturbance, at every step (module doc). ``segments``: segment
    violations are errors (a plan that claims only its samples: they are noted).
    ``loop_start``: the plan repeats its steps loop_start..N forever (a lasso; a finite
    mission plan that rests at its end is the loop of its last step). The nominal
    trajectory itself is the plain validator's business
    (:func:`plansynth.reach.validate.validate`)."""
    if problem.disturbance is None:
        raise ValueError("the problem has no disturbance")
    X, U = np.asarray(trajectory.states, float), np.asarray(trajectory.inputs, float)
    N = len(X) - 1
    K = np.atleast_2d(np.asarray(K, float))
    n, m = problem.dynamics.n_states, problem.dynamics.n_inputs
    rep = _Report()
    notes: list[str] = []
    if K.shape != (m, n) or not np.all(np.isfinite(K)):
        rep.add("gain", None, f"the gain must be an {m} x {n} matrix of finite numbers, got shape {K.shape}")
        return _finish(rep, N, math.inf, tol, notes)
    # steps whose error set is E_t; a lasso's loop is checked again with the limit set
    steps_of = np.arange(N + 1)
    cache: dict[bytes, np.ndarray] = {}

    def sup(D: np.ndarray) -> np.ndarray:
        key = D.tobytes()
        if key not in cache:
            S = error_supports(problem, K, D, N)
            if loop_start is not None:
                S = np.vstack([S, limit_supports(problem, K, D)[None, :]])
            cache[key] = S
        return cache[key]

    polys = tube_polygons(problem, K, N)
    if loop_start is not None:
        limit = _limit_polygon(problem, K)
        polys.append(limit)
        notes.append(f"a lasso: the loop's steps {loop_start}..{N} are checked again with the limit of the error sets")
    _bound_checks(problem, X, U, K, steps_of, sup, tol, rep)
    if loop_start is not None:  # the loop again, with the limit set
        loop = np.arange(loop_start, N + 1)
        _bound_checks(problem, X[loop], U[loop[:-1]], K, np.full(len(loop), N + 1), sup, tol, rep)
    pos = list(problem.dynamics.position)
    P = X[:, pos]
    if problem.goal is not None and problem.mission is None:
        H, h = halfspaces(problem.goal)
        D = np.zeros((len(H), n))
        D[:, pos] = H
        room = h - (H @ P[N] + sup(D)[N])
        rep.room("goal", room)
        if np.any(room < -tol):
            rep.add("goal", N, f"the final tube leaves the goal by {float(-room.min()):.6g}")
    clearance = _obstacle_checks(problem, P, polys, tol, rep, loop_start, segments)
    if not segments and "segment" in rep.counts:
        notes.append(f"segments not claimed: {rep.counts['segment']} segment hulls meet an obstacle")
        rep.counts.pop("segment")
        rep.violations = [v for v in rep.violations if v.kind != "segment"]
    return _finish(rep, N, clearance, tol, notes)


def _obstacle_checks(
    problem: ReachProblem,
    P: np.ndarray,
    polys: list[np.ndarray],
    tol: float,
    rep: _Report,
    loop_start: int | None,
    segments: bool = True,
) -> float:
    """Tubes at the samples and hulls along the segments against every obstacle; the
    smallest clearance."""
    N = len(P) - 1
    tests = [_ObstacleTest(problem, o, tol) for o in problem.obstacles]
    if not tests:
        return math.inf
    if loop_start is not None and not np.all(np.isfinite(polys[-1])):
        rep.add("obstacle", None, "the closed loop is not stable: its error grows without bound")
        return -math.inf
    clearance = math.inf
    samples = [(t, polys[t]) for t in range(N + 1)]
    if loop_start is not None:
        samples += [(t, polys[-1]) for t in range(loop_start, N + 1)]
    segs = [(t, polys[t], polys[t + 1]) for t in range(N)]
    if loop_start is not None:
        segs += [(t, polys[-1], polys[-1]) for t in range(loop_start, N)]
    for kind, steps, bodies in (
        ("obstacle", [t for t, _ in samples], _bodies(problem, [P[t][None, :] + E for t, E in samples])),
        (
            "segment",
            [t for t, _, _ in segs],
            _bodies(problem, [np.vstack([P[t][None, :] + E0, P[t + 1][None, :] + E1]) for t, E0, E1 in segs]),
        ),
    ):
        if not len(bodies):
            continue
        for i, test in enumerate(tests):
            if kind == "obstacle" or segments:
                clearance = min(clearance, test.clearance(bodies))
            for k in np.nonzero(test.hits(bodies))[0]:
                t = steps[k]
                what = f"the tube at step {t}" if kind == "obstacle" else f"the hull of the tubes along segment {t}"
                rep.add(kind, t, f"{what} meets obstacles[{i}]")
    return clearance


def _finish(rep: _Report, N: int, clearance: float, tol: float, notes: list[str]) -> RobustReport:
    return RobustReport(
        ok=not rep.counts,
        violations=tuple(rep.violations),
        counts=dict(rep.counts),
        horizon=N,
        clearance=clearance,
        slack=dict(rep.slack),
        tol=tol,
        notes=tuple(notes),
    )
