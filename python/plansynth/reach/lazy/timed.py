"""The timed route: a first candidate plan, timed by an LP and repaired where CON-PLAN
finds it too tight, checked before DIS-PLAN is built (beyond Shoukry et al., CDC 2016).

On a large abstraction most of the lazy loop's time goes into DIS-PLAN's encoding of
long horizons (the GCS paper's 50 x 50 maze, 1,571 regions: a window of horizons up to
1,146 encoded, 772,000 learned clauses, 20 of 28 s), and the plan it returns sits at
its window's top, twice as long as needed. Yet the plans it ends up realising follow
the shortest route through the region graph; what is hard is their *timing*: how long
to stay in each region. This module guesses that timing from the geometry, lets
CON-PLAN say where the guess is too tight, and relaxes it there:

1. **Route** (:func:`~plansynth.reach.lazy.guide.route`): the shortest start-to-goal
   path through region centres, r_0..r_m.
2. **Crossing points** (:func:`crossing_times`, one LP): a point on the common boundary
   of every two consecutive regions (and a goal point in the last one) minimising the
   sum over the legs of the per-axis travel time ``max_k |dx_k| / D_k``, where ``D`` is
   the largest displacement per step (:func:`~plansynth.reach.lazy.bounds.step_reach`).
   Each leg lies in one region, so its time is the time a robot at full speed would
   spend in that region: the stays of a first plan. A robot that starts at rest needs
   longer on its first leg: at least the fewest steps the transit layer proves
   (:meth:`~plansynth.reach.lazy.transit.TransitCheck.first_gap`).
3. **Repair** (:func:`timed_route`): the plan's LP with a free slack on every region,
   segment and goal row (:meth:`~plansynth.reach.lazy.conplan.ConPlan.violations`)
   shows every place the timing is too tight at once (turns taken too fast, a start too
   quick); the stays around each such place are lengthened by a fraction
   :data:`STRETCH` of its span (at least one step), and the LP is solved again, until
   no slack is left (a handful of rounds on the mazes). The last LP's trajectory then
   realises the plan (polished as CON-PLAN polishes its plans' trajectories).

The plan is a DIS-PLAN plan (consecutive regions equal or adjacent, a start region at
t = 0, a goal region at the end) and its trajectory is CON-PLAN's, so the answer is
what the loop would answer had DIS-PLAN proposed it; only no horizon below it is
refuted, so the planner claims no minimality for it (``lazy-smt-minimal`` proves it
from there). Maze-1..4: horizons 57 / 86 / 115 / 143 in 3-4 LP rounds (proved minimal:
57 / 85 / 113 / 141). When the repair does not converge within :data:`MAX_ROUNDS`
rounds, or CON-PLAN refutes the repaired plan, the loop runs as before.

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.abstraction import abstract
>>> from plansynth.reach.lazy.conplan import ConPlan
>>> from plansynth.reach.lazy.guide import route
>>> p = maze(1); a = abstract(p); path = route(p, a)
>>> [round(float(s), 1) for s in crossing_times(p, a, path)]   # 1 m per step at |v| <= 2
[26.0, 1.0, 24.0]
>>> out = timed_route(p, a, path, ConPlan(p, a, generalize=True), Budget().clock(), {})
>>> out.status.value, out.horizon, out.minimal
('found', 57, False)
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence

import highspy
import numpy as np

from plansynth.budget import Budget, BudgetExhausted, Clock  # noqa: F401 - Budget: the doctest's
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import halfspaces
from plansynth.reach.highs import csc_lp, new_highs
from plansynth.reach.lazy.bounds import step_reach
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.conplan.runs import LpFailure
from plansynth.reach.lazy.loop import LoopOutcome
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachStatus

__all__ = ["timed_route", "crossing_times", "stays_plan", "STRETCH", "MAX_ROUNDS", "SLACK_TOL"]

#: Each too-tight place gets this fraction of its span in extra steps (at least one).
STRETCH = 0.1
#: Steps on either side of a too-tight place whose stays are lengthened with it.
MARGIN = 1
#: Repair rounds (one slack LP each) before the timed route gives up.
MAX_ROUNDS = 25
#: A slack above this (relative to the workspace's size) marks a too-tight place.
SLACK_TOL = 1e-7


def crossing_times(
    problem: ReachProblem, abstraction: Abstraction, path: Sequence[int], turn: float = 0.0
) -> np.ndarray:
    """The steps a robot at full speed spends in each region of ``path`` (step 2 of the
    module doc; real numbers, at least one step each): one LP over a crossing point on
    every common boundary and a goal point in the last region. ``turn``: the steps a
    full change of direction along one axis costs (the steps a start at rest loses);
    each crossing point adds that times the largest change, over the axes, of the
    velocity at full speed, half to the region before it and half to the one after."""
    down, up = step_reach(problem)
    D = np.minimum(np.asarray(down, float), np.asarray(up, float))
    D = np.where(np.isfinite(D) & (D > 0), D, np.inf)
    d, m = problem.dim, len(path)
    n_pts = m + 1  # x_0 = start, x_1..x_{m-1} on the boundaries, x_m in the goal
    n_x = n_pts * d
    n_col = n_x + m  # then the leg times tau_0..tau_{m-1}
    rows: list[int] = []
    cols: list[int] = []
    vals: list[float] = []
    lo: list[float] = []
    hi: list[float] = []

    def add(entries: list[tuple[int, float]], low: float, high: float) -> None:
        r = len(lo)
        for c, v in entries:
            rows.append(r)
            cols.append(c)
            vals.append(v)
        lo.append(low)
        hi.append(high)

    goal = halfspaces(problem.goal)  # type: ignore[arg-type]
    for i in range(1, n_pts):
        shapes = [(abstraction.regions[path[i - 1]].H, abstraction.regions[path[i - 1]].h)]
        shapes.append((abstraction.regions[path[i]].H, abstraction.regions[path[i]].h) if i < m else goal)
        for H, h in shapes:
            for row, rhs in zip(np.asarray(H, float), np.asarray(h, float)):
                add([(i * d + k, float(row[k])) for k in range(d) if row[k] != 0.0], -math.inf, float(rhs))
    for i in range(m):
        for k in range(d):
            if math.isinf(D[k]):
                continue
            for sign in (1.0, -1.0):  # tau_i D_k >= +-(x_{i+1} - x_i)_k
                add([(n_x + i, float(D[k])), ((i + 1) * d + k, -sign), (i * d + k, sign)], 0.0, math.inf)
    col_lo = np.full(n_col, -math.inf)
    col_hi = np.full(n_col, math.inf)
    start = np.asarray(problem.start_position, float)
    col_lo[:d] = col_hi[:d] = start
    col_lo[n_x:] = 0.0
    cost = np.zeros(n_col)
    cost[n_x:] = 1.0
    lp = csc_lp(
        n_col,
        len(lo),
        np.array(rows, dtype=np.int64),
        np.array(cols, dtype=np.int64),
        np.array(vals, dtype=float),
        cost,
        col_lo,
        col_hi,
        np.array(lo, dtype=float),
        np.array(hi, dtype=float),
    )
    h = new_highs()
    h.passModel(lp)
    h.run()
    if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
        return np.ones(m)  # (no crossing points: every stay one step, the repair decides)
    x = np.asarray(h.getSolution().col_value, float)
    tau = x[n_x:]
    if turn > 0 and m > 1:
        pts = x[:n_x].reshape(n_pts, d)
        with np.errstate(invalid="ignore", divide="ignore"):
            vel = (pts[1:] - pts[:-1]) / (np.where(tau > 0, tau, 1.0)[:, None] * np.where(np.isinf(D), 1.0, D))
        change = np.max(np.abs(vel[1:] - vel[:-1]), axis=1)  # at crossing points 1..m-1
        tau = tau.copy()
        tau[:-1] += 0.5 * turn * change
        tau[1:] += 0.5 * turn * change
    return np.maximum(tau, 1.0)


def stays_plan(path: Sequence[int], stays: np.ndarray) -> tuple[int, ...]:
    """The plan that stays ``stays[i]`` steps (real numbers, rounded cumulatively, at
    least one step each) in ``path[i]``, then takes one more sample in the last region.

    >>> stays_plan((4, 5, 6), np.array([1.4, 1.4, 2.0]))
    (4, 5, 5, 6, 6, 6)
    """
    ends = np.round(np.cumsum(stays)).astype(int)
    plan: list[int] = []
    for r, e in zip(path, ends):
        plan += [int(r)] * max(1, int(e) - len(plan))
    plan.append(int(path[-1]))
    return tuple(plan)


def _route_index(path: Sequence[int], plan: Sequence[int]) -> np.ndarray:
    """For each step of ``plan`` (a :func:`stays_plan` of ``path``) its index in ``path``."""
    idx = np.zeros(len(plan), dtype=np.int64)
    k = 0
    for t, r in enumerate(plan):
        while path[k] != r:
            k += 1
        idx[t] = k
    return idx


def timed_route(
    problem: ReachProblem,
    abstraction: Abstraction,
    path: Sequence[int] | None,
    conplan: ConPlan,
    clock: Clock,
    timings: dict[str, float],
    *,
    max_horizon: int | None = None,
    first_leg: int | None = None,
    counters: dict | None = None,
) -> LoopOutcome | None:
    """The timed route's plan and trajectory (see the module doc), or None when the
    repair does not converge, CON-PLAN refutes the repaired plan or the budget runs out
    (the lazy loop then runs as before), or when a plan would be longer than
    ``max_horizon`` (default: the problem's). ``first_leg``: the fewest steps from the
    start into ``path[1]``. Each repair round is one iteration of the budget (one
    theory check, no SAT call)."""
    if path is None or len(path) < 2:
        return None  # (the start's region meets the goal: the loop decides the short horizons)
    L_max = problem.max_horizon if max_horizon is None else int(max_horizon)
    t0 = time.perf_counter()
    rounds = 0
    try:
        stays = crossing_times(problem, abstraction, path)
        if first_leg is not None and len(stays) > 1 and first_leg > stays[0]:
            # a turn costs about what the start loses accelerating from rest
            stays = crossing_times(problem, abstraction, path, turn=first_leg - stays[0])
        down, up = step_reach(problem)
        per_step = float(np.min(np.minimum(down, up)))
        if not (math.isfinite(per_step) and per_step > 0):
            per_step = math.inf
        if first_leg is not None and len(stays) > 1:
            stays[0] = max(stays[0], float(first_leg))
        scale = max(h - lo for lo, h in zip(problem.workspace.lo, problem.workspace.hi))
        while rounds < MAX_ROUNDS:
            plan = stays_plan(path, stays)
            if len(plan) - 1 > L_max or clock.exhausted():
                return None
            rounds += 1
            clock.tick()
            tol = SLACK_TOL * max(1.0, scale)
            elastic = conplan.violations(plan, tol)
            if elastic is None:
                return None
            slack, realised = elastic
            bad = np.flatnonzero(slack > tol)
            if realised is not None:  # no slack left: the LP's trajectory realises the plan
                answer = realised
                h = len(plan) - 1
                return LoopOutcome(
                    ReachStatus.FOUND,
                    h,
                    f"found at horizon {h} (the timed route, {rounds} repair round{'s' * (rounds != 1)})",
                    answer.trajectory,
                    plan,
                    minimal=False,
                )
            idx = _route_index(path, plan)
            N = len(plan) - 1
            runs: list[list[int]] = []
            for t in bad.tolist():
                if runs and t <= runs[-1][1] + 2:
                    runs[-1][1] = t
                else:
                    runs.append([t, t])
            for a, b in runs:
                # the violation in steps of full speed, at least a fraction of its span
                extra = max(1.0, STRETCH * (b - a + 2 * MARGIN), float(slack[a : b + 1].max()) / per_step)
                a, b = max(0, a - MARGIN), min(N, b + MARGIN)
                ks = np.unique(idx[a : b + 1])
                stays[ks] += extra * stays[ks] / stays[ks].sum()
        return None
    except (BudgetExhausted, LpFailure):
        return None
    finally:
        timings["timed_route"] = timings.get("timed_route", 0.0) + time.perf_counter() - t0
        if counters is not None:
            counters["timed_route_rounds"] = rounds
