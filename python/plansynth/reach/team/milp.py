"""The joint big-M MILP over the encoding of the joint lazy planner (the baseline
``milp-team``): one mixed-integer program per horizon, solved by HiGHS (Wolff, Topcu
and Murray's big-M formulation, "Optimization-based trajectory generation with linear
temporal logic specifications", ICRA 2014, for the regions; Schouwenaars et al.,
"Mixed integer programming for multi-vehicle path planning", ECC 2001, for the pairs).

Per robot r, step t and region i a binary ``b[r, t, i]`` (exactly one per step, the time
windows' forbidden ones fixed to 0, a region's successor one of its neighbours or
itself, a goal region at L): ``b = 1`` asks the position at t, and the segment's end at
t + 1, into the region (``H_i p <= h_i + M (1 - b)``). Per pair (i, j) and step t a
binary per side k of the pair's forbidden polygon, at least one set (*every* pair and
step, the full encoding the lazy planner engages lazily): ``A_k (p_i - p_j) >= b_k -
M (1 - s)`` at t and t + 1; opposite sides never on consecutive steps. Per robot and
moving obstacle the same at t, at each waypoint time inside the step, and at t + 1.
Each ``M`` is the largest violation the row can have over the robots' boxes.

The horizons run from the same lower bound as the lazy planner's
(:func:`~plansynth.reach.team.setup.prepare`) to ``max_horizon``; the first feasible one
is the smallest of the encoding, so ``found`` is minimal and ``infeasible`` means what
the lazy planner's means (relative to the encoding). Robots with missions are not
planned here. Under disturbances the MILP is the team tightened by the robots' tubes
(:mod:`plansynth.reach.team.robust`): every bound, goal and side row tightened by the
margins of its step, each big-M computed for the tightened row.
"""

from __future__ import annotations

import time
from dataclasses import asdict
from typing import Any

import highspy
import numpy as np

from plansynth.budget import Budget
from plansynth.errors import InvalidOption
from plansynth.reach.highs import Rows, csc_lp, new_highs
from plansynth.reach.result import ReachStatus
from plansynth.reach.team.conplan import _bend_fractions
from plansynth.reach.team.lazy import ENCODING
from plansynth.reach.team.options import TeamMilpOptions
from plansynth.reach.team.problem import TeamProblem
from plansynth.reach.team.result import TeamResult
from plansynth.reach.team.robust import is_disturbed, tightened_team
from plansynth.reach.team.setup import TeamSetup, prepare
from plansynth.reach.trajectory import Trajectory

__all__ = ["plan_team_milp", "run"]

INF = highspy.kHighsInf


def run(problem: Any, budget: Budget, options: TeamMilpOptions, progress: Any = None) -> TeamResult:
    """The registry's entry (:data:`plansynth.reach.planners.PLANNERS`)."""
    return plan_team_milp(problem, budget, options, progress)


def plan_team_milp(
    problem: TeamProblem, budget: Budget = Budget(), options: TeamMilpOptions | None = None, progress: Any = None
) -> TeamResult:
    """One MILP per horizon (see the module docstring); unvalidated."""
    if any(r.mission is not None for r in problem.robots):
        raise InvalidOption("milp-team", "planner", "plans no missions (plan this team with lazy-smt-team)")
    options = TeamMilpOptions() if options is None else options
    clock = budget.clock()
    t_start = time.perf_counter()
    L_max = problem.max_horizon if options.max_horizon is None else options.max_horizon
    timings: dict[str, float] = {"milp": 0.0}
    counters: dict[str, Any] = {"robots": problem.n_robots, "milp_calls": 0}
    record = {**asdict(options), "max_horizon": L_max, "budget_seconds": budget.seconds}
    names = tuple(r.name for r in problem.robots)

    def result(status: ReachStatus, horizon: int | None, message: str, trajs=None, regions=None) -> TeamResult:  # noqa: ANN001
        timings["total"] = time.perf_counter() - t_start
        return TeamResult(
            status, "milp-team", timings["total"], trajs, regions, horizon, counters, timings, record,
            message=message, guarantee="segments", names=names,
        )  # fmt: skip

    if is_disturbed(problem):  # plan the team tightened by its robots' tubes (plansynth.reach.team.robust)
        tight = tightened_team(problem)
        if tight.status is not None:
            status = ReachStatus.INFEASIBLE if tight.status == "infeasible" else ReachStatus.UNKNOWN
            return result(status, None, tight.reason)
        L_max = min(L_max, tight.max_horizon)
        record["max_horizon"] = L_max
        if options.horizon is not None and options.horizon > L_max:
            return result(
                ReachStatus.UNKNOWN, options.horizon, f"no robust plan of horizon {options.horizon}: {tight.note}"
            )
    t0 = time.perf_counter()
    setup = prepare(problem, max(L_max, options.horizon or 0), clock)
    timings["abstraction"] = time.perf_counter() - t0
    counters.update(setup.counters)
    first = setup.first
    if options.horizon is not None:
        horizons = [options.horizon]
    elif first > L_max:
        counters["infeasible_relative_to"] = "encoding"
        return result(
            ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: a robot alone cannot reach its goal"
        )
    else:
        horizons = list(range(int(first), L_max + 1))
    for L in horizons:
        if progress is not None:
            progress(L, counters["milp_calls"])
        left = clock.remaining()
        if left <= 0:
            return result(ReachStatus.UNKNOWN, L, f"budget ran out before horizon {L}")
        t0 = time.perf_counter()
        status, x, nodes = _solve(setup, L, left)
        timings["milp"] += time.perf_counter() - t0
        counters["milp_calls"] += 1
        counters["mip_nodes"] = counters.get("mip_nodes", 0) + nodes
        if status == "timeout":
            return result(ReachStatus.UNKNOWN, L, f"budget ran out in the MILP at horizon {L}")
        if status == "feasible":
            trajs, regions = _read(setup, L, x)
            counters["minimal"] = options.horizon is None
            return result(ReachStatus.FOUND, L, f"found at horizon {L}", trajs, regions)
    if options.horizon is not None:
        return result(
            ReachStatus.UNKNOWN, options.horizon, f"no plan at horizon {options.horizon} (the only one tried)"
        )
    counters["infeasible_relative_to"] = "encoding"
    return result(
        ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max} relative to the encoding ({ENCODING})"
    )


class _Layout:
    """Columns of the MILP at horizon L: each robot's states, inputs and (when it must
    end where it can stay) its resting input, then the binaries."""

    def __init__(self, setup: TeamSetup, L: int) -> None:
        self.L = L
        self.base = []
        col = 0
        for s in setup.robots:
            self.base.append(col)
            col += s.model.columns(L)
        self.n_cont = col
        self.bin0 = col
        self.b = []
        for s in setup.robots:
            self.b.append(col)
            col += (L + 1) * s.graph.n_regions
        self.side: dict[tuple[int, int], int] = {}
        for key, f in setup.pair_facets.items():
            self.side[key] = col
            col += L * f.n_sides
        self.mside: dict[tuple[int, int], int] = {}
        for key, f in setup.obstacle_facets.items():
            self.mside[key] = col
            col += L * f.n_sides
        self.n_col = col

    def x(self, setup: TeamSetup, r: int, t: int) -> int:
        return self.base[r] + t * setup.robots[r].model.n


def _boxes(setup: TeamSetup) -> list[tuple[np.ndarray, np.ndarray]]:
    out = []
    for s in setup.robots:
        m = s.model
        lo, hi = m.x_lo[list(m.pos)], m.x_hi[list(m.pos)]
        out.append((np.asarray(lo, float), np.asarray(hi, float)))
    return out


def _max_over_box(a: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    return float(np.sum(np.where(a > 0, a * hi, a * lo)))


def _solve(setup: TeamSetup, L: int, seconds: float) -> tuple[str, np.ndarray | None, int]:
    lay = _Layout(setup, L)
    rows = Rows()
    boxes = _boxes(setup)
    col_lo = np.full(lay.n_col, -INF)
    col_hi = np.full(lay.n_col, INF)
    col_lo[lay.bin0 :], col_hi[lay.bin0 :] = 0.0, 1.0
    for r, s in enumerate(setup.robots):
        _robot(setup, lay, rows, r, s, col_lo, col_hi, boxes[r])
    for (i, j), f in setup.pair_facets.items():
        lo = boxes[i][0] - boxes[j][1]
        hi = boxes[i][1] - boxes[j][0]
        pi, pj = setup.robots[i].model.pos, setup.robots[j].model.pos
        grow = setup.pair_margins.get((i, j))
        for t in range(L):
            ks = [lay.side[(i, j)] + t * f.n_sides + k for k in range(f.n_sides)]
            rows.add(np.zeros(len(ks), int), np.array(ks), np.ones(len(ks)), np.ones(1), np.full(1, INF))
            for k in range(f.n_sides):
                a = f.A[k]
                for tt in (t, t + 1):
                    b = f.b[k] + (0.0 if grow is None else grow[tt, k])  # (under disturbances: moved out)
                    M = max(0.0, b + _max_over_box(-a, lo, hi))
                    C = np.concatenate(
                        [lay.x(setup, i, tt) + np.asarray(pi), lay.x(setup, j, tt) + np.asarray(pj), [ks[k]]]
                    )
                    V = np.concatenate([a, -a, [-M]])
                    rows.add(np.zeros(len(C), int), C, V, np.array([b - M]), np.full(1, INF))
                if t + 1 < L and f.opposite[k] is not None:
                    nxt = lay.side[(i, j)] + (t + 1) * f.n_sides + f.opposite[k]
                    rows.add(np.zeros(2, int), np.array([ks[k], nxt]), np.ones(2), np.full(1, -INF), np.ones(1))
                    prv = lay.side[(i, j)] + (t + 1) * f.n_sides + k
                    opp = lay.side[(i, j)] + t * f.n_sides + f.opposite[k]
                    rows.add(np.zeros(2, int), np.array([opp, prv]), np.ones(2), np.full(1, -INF), np.ones(1))
    problem = setup.problem
    for (r, o), f in setup.obstacle_facets.items():
        ob = problem.moving_obstacles[o]
        pos = np.asarray(setup.robots[r].model.pos)
        lo, hi = boxes[r]
        grow = setup.obstacle_margins.get((r, o))
        for t in range(L):
            ks = [lay.mside[(r, o)] + t * f.n_sides + k for k in range(f.n_sides)]
            rows.add(np.zeros(len(ks), int), np.array(ks), np.ones(len(ks)), np.ones(1), np.full(1, INF))
            for k in range(f.n_sides):
                a, b = f.A[k], f.b[k]
                for lam in (0.0, *_bend_fractions(problem, o, t), 1.0):
                    c = ob.position(problem.time_of(t + lam))
                    rhs = b + float(a @ c)
                    if grow is not None:  # the robot's tube, interpolated between the step's samples
                        rhs += (1 - lam) * grow[t, k] + lam * grow[t + 1, k]
                    M = max(0.0, rhs + _max_over_box(-a, lo, hi))
                    C = np.concatenate([lay.x(setup, r, t) + pos, lay.x(setup, r, t + 1) + pos, [ks[k]]])
                    V = np.concatenate([(1 - lam) * a, lam * a, [-M]])
                    rows.add(np.zeros(len(C), int), C, V, np.array([rhs - M]), np.full(1, INF))
    R, C, V = rows.coo()
    rlo, rhi = rows.bounds()
    integrality = [highspy.HighsVarType.kContinuous] * lay.bin0 + [highspy.HighsVarType.kInteger] * (
        lay.n_col - lay.bin0
    )
    lp = csc_lp(lay.n_col, rows.n_row, R, C, V, np.zeros(lay.n_col), col_lo, col_hi, rlo, rhi, integrality)
    h = new_highs(time_limit=max(seconds, 0.01), mip_rel_gap=0.0)
    h.passModel(lp)
    h.run()
    st = h.getModelStatus()
    nodes = int(h.getInfo().mip_node_count)
    if st == highspy.HighsModelStatus.kOptimal:
        return "feasible", np.asarray(h.getSolution().col_value, float), nodes
    if st == highspy.HighsModelStatus.kInfeasible:
        return "infeasible", None, nodes
    if st == highspy.HighsModelStatus.kTimeLimit:
        sol = h.getSolution()
        if h.getInfo().primal_solution_status == 2:  # a feasible point found before the limit
            return "feasible", np.asarray(sol.col_value, float), nodes
        return "timeout", None, nodes
    return "timeout", None, nodes


def _robot(setup, lay, rows, r, s, col_lo, col_hi, box) -> None:  # noqa: ANN001 - internal
    m, g, L = s.model, s.graph, lay.L
    n = m.n
    x0 = lay.base[r]
    tm = m.margins  # under a disturbance: every bound tightened by the tube at its step
    for t in range(L + 1):
        x_lo = m.x_lo if tm is None else m.x_lo + tm.state_lo[t]
        x_hi = m.x_hi if tm is None else m.x_hi - tm.state_hi[t]
        col_lo[x0 + t * n : x0 + (t + 1) * n] = np.where(np.isfinite(x_lo), x_lo, -INF)
        col_hi[x0 + t * n : x0 + (t + 1) * n] = np.where(np.isfinite(x_hi), x_hi, INF)
    col_lo[x0 : x0 + n] = col_hi[x0 : x0 + n] = m.start
    u0 = x0 + (L + 1) * n
    end = x0 + m.columns(L)
    col_lo[u0:end], col_hi[u0:end] = -m.u_bound, m.u_bound
    if tm is not None:
        col_lo[u0 : u0 + L * m.m] += tm.input_lo[:L].ravel()
        col_hi[u0 : u0 + L * m.m] -= tm.input_hi[:L].ravel()
        if m.rest:  # the resting input keeps room for the feedback's largest share
            col_lo[u0 + L * m.m : end] += tm.rest_lo
            col_hi[u0 + L * m.m : end] -= tm.rest_hi
    for t in range(L):  # x_{t+1} = A x_t + B u_t
        for a in range(n):
            C = [x0 + (t + 1) * n + a] + [x0 + t * n + c for c in range(n) if m.A[a, c]]
            C += [u0 + t * m.m + j for j in range(m.m) if m.B[a, j]]
            V = [1.0] + [-m.A[a, c] for c in range(n) if m.A[a, c]] + [-m.B[a, j] for j in range(m.m) if m.B[a, j]]
            rows.add(np.zeros(len(C), int), np.array(C), np.array(V), np.zeros(1), np.zeros(1))
    pos = np.asarray(m.pos)
    b0 = lay.b[r]
    N = g.n_regions
    lo, hi = box
    for t in range(L + 1):
        bs = b0 + t * N + np.arange(N)
        rows.add(np.zeros(N, int), bs, np.ones(N), np.ones(1), np.ones(1))  # exactly one region
        for i in range(N):
            allowed = t >= s.earliest[i] and L - t >= s.to_go[i] and (t > 0 or i in g.start_regions)
            if t == L and s.labels_of is None and i not in g.goal_regions:
                allowed = False
            if not allowed:
                col_hi[b0 + t * N + i] = 0.0
                continue
            H, h = m.regions[i]
            for tt in (t, t + 1) if t < L else (t,):
                for k in range(H.shape[0]):
                    M = max(0.0, _max_over_box(H[k], lo, hi) - h[k])
                    C = np.concatenate([x0 + tt * n + pos, [b0 + t * N + i]])
                    rows.add(
                        np.zeros(len(C), int), C, np.concatenate([H[k], [M]]), np.full(1, -INF), np.array([h[k] + M])
                    )
            if t < L:  # the next region: this one or a neighbour
                nxt = [b0 + (t + 1) * N + j for j in (i, *g.adjacency[i])]
                rows.add(
                    np.zeros(len(nxt) + 1, int),
                    np.array([b0 + t * N + i, *nxt]),
                    np.array([1.0] + [-1.0] * len(nxt)),
                    np.full(1, -INF),
                    np.zeros(1),
                )
    if m.goal is not None:
        if m.goal[0] == "point":
            for a, v in enumerate(m.goal[1]):
                c = x0 + L * n + pos[a]
                col_lo[c] = max(col_lo[c], v)
                col_hi[c] = min(col_hi[c], v)
        else:
            H, h = m.goal[1], m.goal[2]
            if tm is not None and tm.goal is not None:  # the final tube inside the goal
                h = h - tm.goal[L]
            for k in range(H.shape[0]):
                rows.add(np.zeros(len(pos), int), x0 + L * n + pos, H[k], np.full(1, -INF), np.array([h[k]]))
    if m.rest:  # (I - A) x_L = B w
        w0 = u0 + L * m.m
        I_A = np.eye(n) - m.A
        for a in range(n):
            C = [x0 + L * n + c for c in range(n) if I_A[a, c]] + [w0 + j for j in range(m.m) if m.B[a, j]]
            V = [I_A[a, c] for c in range(n) if I_A[a, c]] + [-m.B[a, j] for j in range(m.m) if m.B[a, j]]
            if C:
                rows.add(np.zeros(len(C), int), np.array(C), np.array(V), np.zeros(1), np.zeros(1))


def _read(setup: TeamSetup, L: int, x: np.ndarray) -> tuple[tuple[Trajectory, ...], tuple[tuple[int, ...], ...]]:
    lay = _Layout(setup, L)
    trajs, regions = [], []
    for r, s in enumerate(setup.robots):
        m = s.model
        x0 = lay.base[r]
        X = x[x0 : x0 + (L + 1) * m.n].reshape(L + 1, m.n).copy()
        X[0] = m.start
        U = x[x0 + (L + 1) * m.n : x0 + (L + 1) * m.n + L * m.m].reshape(L, m.m)
        trajs.append(Trajectory(states=X, inputs=U))
        N = s.graph.n_regions
        B = x[lay.b[r] : lay.b[r] + (L + 1) * N].reshape(L + 1, N)
        regions.append(tuple(int(np.argmax(row)) for row in B))
    return tuple(trajs), tuple(regions)
