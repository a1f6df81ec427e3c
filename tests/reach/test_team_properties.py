"""Property tests of the joint planners on random small teams (2-3 robots, few regions):

* the joint lazy planner and the joint big-M MILP decide the same encoding: same status,
  and (one horizon at a time) the same least horizon; every plan passes the team
  validator; ``infeasible`` never comes from prioritized planning;
* clause soundness, extended to pairs and moving obstacles: every counterexample the
  joint CON-PLAN hands to DIS-PLAN (region, side and moving-obstacle literals, with its
  start, goal and time anchors) is refuted by an LP written here from scratch, at the
  shifts where DIS-PLAN adds it;
* the teams include pairs that must wait and swap: two robots exchanging the ends of a
  corridor they cannot pass each other in, with or without a bay to wait in;
* clause soundness for teams under disturbances, every row of the oracle tightened by
  the error sets of its step (the lazy and MILP agreement under disturbances is
  tests/reach/test_team_robust.py).
"""

from __future__ import annotations

import math
from dataclasses import replace

import highspy
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from reach_oracles import feasible

from plansynth.budget import Budget
from plansynth.reach import ReachStatus, solve
from plansynth.reach.disturbance import Disturbance
from plansynth.reach.dynamics import double_integrator, single_integrator
from plansynth.reach.geometry import Box, halfspaces
from plansynth.reach.highs import new_highs
from plansynth.reach.robot import RobotShape
from plansynth.reach.robust.error_sets import error_supports
from plansynth.reach.robust.feedback import design_feedback
from plansynth.reach.team.displan import TeamDisPlan
from plansynth.reach.team.plans import TeamConflict
from plansynth.reach.team.problem import GoalPoint, MovingObstacle, Separation, TeamProblem, TeamRobot
from plansynth.reach.team.setup import TeamSetup, prepare

PROPS = settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def random_team(seed: int) -> TeamProblem:
    """A random small team: a workspace with up to two box obstacles, 2-3 robots (points
    or small boxes), single or double integrators, maybe a moving obstacle."""
    rng = np.random.default_rng(seed)
    W, H = float(rng.integers(4, 8)), float(rng.integers(3, 6))
    ws = Box((0.0, 0.0), (W, H))
    obstacles = []
    for _ in range(int(rng.integers(0, 3))):
        lo = (float(rng.uniform(1, W - 2)), float(rng.uniform(0.5, H - 1.5)))
        obstacles.append(Box(lo, (lo[0] + float(rng.uniform(0.5, 1.5)), lo[1] + float(rng.uniform(0.5, 1.5)))))
    order = int(rng.integers(1, 3))
    dyn = single_integrator(2, 1.0) if order == 1 else double_integrator(2, 1.0)
    n = 2 + int(rng.integers(0, 2))
    sep = float(rng.uniform(0.3, 0.8))
    sized = bool(rng.integers(0, 2))
    shape = RobotShape(half_extent=(0.2, 0.2)) if sized else None
    margin = 0.2 if sized else 0.0
    robots: list[TeamRobot] = []
    tries = 0
    while len(robots) < n and tries < 400:
        tries += 1
        s = (float(rng.uniform(margin, W - margin)), float(rng.uniform(margin, H - margin)))
        g = (float(rng.uniform(0.5, W - 0.5)), float(rng.uniform(0.5, H - 0.5)))
        start = np.zeros(dyn.n_states)
        start[:2] = s
        goal = Box((g[0] - 0.5, g[1] - 0.5), (g[0] + 0.5, g[1] + 0.5))
        bounds = Box((0, 0, -1.5, -1.5), (W, H, 1.5, 1.5)) if order == 2 else None
        cand = TeamRobot(f"r{len(robots)}", dyn, start, 1.0, goal=goal, state_bounds=bounds, robot_shape=shape)
        try:
            TeamProblem(ws, tuple(obstacles), (*robots, cand), Separation(sep))
        except Exception:  # noqa: BLE001 - a start in an obstacle or too close: draw again
            continue
        robots.append(cand)
    moving = ()
    if rng.integers(0, 3) == 0:
        y = float(rng.uniform(0.5, H - 0.5))
        moving = (MovingObstacle(Box((-0.3, -0.3), (0.3, 0.3)), (0.0, 3.0, 6.0), ((0.0, y), (W, y), (0.0, y)), "cart"),)
    for _ in range(2):
        try:
            return TeamProblem(
                ws, tuple(obstacles), tuple(robots), Separation(sep), moving, max_horizon=7, name=f"team-{seed}"
            )
        except Exception:  # noqa: BLE001 - a start under the cart at time 0: no cart
            moving = ()
    raise AssertionError("unreachable")


def swap_corridor(seed: int) -> TeamProblem:
    """Two robots swap the ends of a corridor too narrow to pass in (1 m wide, 1.2 m
    apart), with a bay to wait in or not: they must wait and swap, or cannot."""
    rng = np.random.default_rng(seed)
    length = float(rng.integers(4, 7))
    bay = bool(rng.integers(0, 2))
    x0 = float(rng.integers(1, int(length) - 2))
    obstacles = (Box((0, 1), (x0, 2.5)), Box((x0 + 1.5, 1), (length, 2.5))) if bay else (Box((0, 1), (length, 2.5)),)
    dyn = single_integrator(2, 1.0)
    a = TeamRobot("a", dyn, [0.5, 0.5], 1.0, goal=GoalPoint((length - 0.5, 0.5)))
    b = TeamRobot("b", dyn, [length - 0.5, 0.5], 1.0, goal=GoalPoint((0.5, 0.5)))
    return TeamProblem(
        Box((0, 0), (length, 2.5)), obstacles, (a, b), Separation(1.2), max_horizon=int(length) + 6, name=f"swap-{seed}"
    )


# ------------------------------------------------------------------ lazy and MILP agree


def _agree(p: TeamProblem) -> None:
    lazy = solve(p, "lazy-smt-team", Budget(seconds=120), horizon_search="linear", incumbent="none")
    milp = solve(p, "milp-team", Budget(seconds=120))
    for r in (lazy, milp):
        assert r.status is not ReachStatus.UNKNOWN, (p.name, r.solver, r.message)
        if r.status is ReachStatus.FOUND:
            assert r.validated is True and r.validation.ok, (p.name, r.solver, r.message)
    assert lazy.status is milp.status, (p.name, lazy.message, milp.message)
    assert lazy.horizon == milp.horizon, (p.name, lazy.message, milp.message)
    if lazy.status is ReachStatus.INFEASIBLE:
        assert lazy.counters["infeasible_relative_to"] == "encoding"
    prio = solve(p, "prioritized", Budget(seconds=120))
    assert prio.status is not ReachStatus.INFEASIBLE
    if prio.status is ReachStatus.FOUND:
        assert prio.validated is True and lazy.status is ReachStatus.FOUND and prio.horizon >= lazy.horizon


@PROPS
@given(st.integers(0, 10**6))
def test_lazy_and_milp_agree_on_random_teams(seed: int) -> None:
    _agree(random_team(seed))


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 10**6))
def test_lazy_and_milp_agree_on_pairs_that_must_wait_and_swap(seed: int) -> None:
    _agree(swap_corridor(seed))


def test_a_swap_with_a_bay_waits_and_one_without_has_no_plan() -> None:
    found = [p for p in map(swap_corridor, range(40)) if len(p.obstacles) == 2][:1]
    stuck = [p for p in map(swap_corridor, range(40)) if len(p.obstacles) == 1][:1]
    r = solve(found[0], "lazy-smt-team", Budget(seconds=120))
    assert r.status is ReachStatus.FOUND and max(t.states[:, 1].max() for t in r.trajectories) > 1.0
    assert solve(stuck[0], "lazy-smt-team", Budget(seconds=120)).status is ReachStatus.INFEASIBLE


# ------------------------------------------------------------------ clause soundness


def _supports(p: TeamProblem, L: int):  # noqa: ANN202 - a closure
    """``grow(r, D, t)``: the support of robot r's error set E_t at the rows of D (its
    states), from the independent validator's exact sums with the robot's designed gain
    (zeros for a robot without a disturbance): the tightened team's margins, written
    without the planner's tube."""
    gains = [None if r.disturbance is None else design_feedback(r.dynamics, r.disturbance).K for r in p.robots]

    def grow(r: int, D: np.ndarray, t: int) -> np.ndarray:
        D = np.atleast_2d(np.asarray(D, float))
        if gains[r] is None:
            return np.zeros(len(D))
        return error_supports(p.robot_problems[r], gains[r], D, max(t, 0))[t]

    return grow


def _on_positions(p: TeamProblem, r: int, a: np.ndarray) -> np.ndarray:
    D = np.zeros(p.robots[r].dynamics.n_states)
    D[list(p.robots[r].dynamics.position)] = a
    return D


def _oracle_refutes(p: TeamProblem, setup: TeamSetup, c: TeamConflict, L: int, s: int) -> bool:
    """Is ``c`` shifted by ``s`` infeasible in plans of horizon L? An LP over every robot
    (dynamics, input and state bounds, the robot's workspace), the starts when ``c`` uses
    them, the goals and end states when it does, and the rows of its literals; built
    here from the problem, the robots' regions and the sides' facets only. Under
    disturbances every bound, goal and side tightened by the error sets of its step
    (:func:`_supports`)."""
    inf = highspy.kHighsInf
    grow = _supports(p, L)
    cols: list[tuple[float, float]] = []
    x: dict[tuple[int, int], int] = {}
    u: dict[tuple[int, int], int] = {}
    w: dict[int, int] = {}
    for r, robot in enumerate(p.robots):
        lo, hi = setup.robots[r].planning.state_box
        n = robot.dynamics.n_states
        K = None if robot.disturbance is None else design_feedback(robot.dynamics, robot.disturbance).K
        for t in range(L + 1):
            x[(r, t)] = len(cols)
            up, down = grow(r, np.eye(n), t), grow(r, -np.eye(n), t)
            for i in range(n):
                fixed = c.start and t == 0
                v = robot.start[i]
                cols.append((v, v) if fixed else (max(lo[i] + down[i], -1e9), min(hi[i] - up[i], 1e9)))
        for t in range(L):
            u[(r, t)] = len(cols)
            if K is None:
                cols += [(-robot.input_bound, robot.input_bound)] * robot.dynamics.n_inputs
            else:
                up, down = grow(r, K, t), grow(r, -K, t)
                cols += [(-robot.input_bound + down[j], robot.input_bound - up[j]) for j in range(len(K))]
        w[r] = len(cols)
        cols += [(-robot.input_bound, robot.input_bound)] * robot.dynamics.n_inputs
    rows = []

    def pos(r: int, t: int) -> list[int]:
        return [x[(r, t)] + i for i in p.robots[r].dynamics.position]

    for r, robot in enumerate(p.robots):
        A, B = np.asarray(robot.dynamics.A), np.asarray(robot.dynamics.B)
        n, m = B.shape
        for t in range(L):
            for i in range(n):
                coef = {x[(r, t + 1)] + i: 1.0}
                for j in range(n):
                    if A[i, j]:
                        coef[x[(r, t)] + j] = coef.get(x[(r, t)] + j, 0.0) - A[i, j]
                for j in range(m):
                    if B[i, j]:
                        coef[u[(r, t)] + j] = -B[i, j]
                rows.append((coef, 0.0, 0.0))
        if c.goal:
            g = robot.goal
            if isinstance(g, GoalPoint):
                for k, v in zip(pos(r, L), g.point):
                    rows.append(({k: 1.0}, v, v))
            elif g is not None:
                Hg, hg = halfspaces(g)
                for row, b in zip(Hg, hg):
                    room = float(grow(r, _on_positions(p, r, row), L)[0])
                    rows.append(({k: a for k, a in zip(pos(r, L), row)}, -inf, float(b) - room))
            if robot.stop or robot.mission is not None:
                for i in range(n):
                    coef = {x[(r, L)] + j: (1.0 if i == j else 0.0) - A[i, j] for j in range(n)}
                    for j in range(m):
                        coef[w[r] + j] = -B[i, j]
                    rows.append(({k: v for k, v in coef.items() if v}, 0.0, 0.0))
    dt = p.dt or 1.0
    for lit in c.literals:
        if lit[0] == "at":
            _, r, t, i = lit
            t += s
            reg = setup.robots[r].abstraction.regions[i]
            for tt in (t, t + 1) if t < L else (t,):
                for row, b in zip(reg.H, reg.h):
                    rows.append(({k: a for k, a in zip(pos(r, tt), row)}, -inf, float(b)))
        elif lit[0] == "side":
            _, i, j, t, k = lit
            f = setup.pair_facets[(i, j)]
            for tt in (t + s, t + s + 1):
                coef = {q: a for q, a in zip(pos(i, tt), f.A[k])}
                for q, a in zip(pos(j, tt), f.A[k]):
                    coef[q] = coef.get(q, 0.0) - a
                both = grow(i, _on_positions(p, i, -f.A[k]), tt)[0] + grow(j, _on_positions(p, j, f.A[k]), tt)[0]
                rows.append((coef, float(f.b[k] + both), inf))
        else:
            _, r, o, t, k = lit
            t += s
            f = setup.obstacle_facets[(r, o)]
            ob = p.moving_obstacles[o]
            fr = [0.0] + [(b - t * dt) / dt for b in ob.times if t * dt < b < (t + 1) * dt] + [1.0]
            for lam in fr:
                cpos = np.array([np.interp((t + lam) * dt, ob.times, np.asarray(ob.positions)[:, a]) for a in range(2)])
                coef: dict[int, float] = {}
                for q0, q1, a in zip(pos(r, t), pos(r, t + 1), f.A[k]):
                    coef[q0] = coef.get(q0, 0.0) + (1 - lam) * a
                    coef[q1] = coef.get(q1, 0.0) + lam * a
                room = (1 - lam) * grow(r, _on_positions(p, r, -f.A[k]), t)[0] + lam * grow(
                    r, _on_positions(p, r, -f.A[k]), t + 1
                )[0]
                rows.append((coef, float(f.b[k] + f.A[k] @ cpos + room), inf))
    h = new_highs(presolve="off")
    h.addVars(len(cols), np.array([a for a, _ in cols]), np.array([b for _, b in cols]))
    return not feasible(h, rows)


def _checked(p: TeamProblem) -> tuple[int, int]:
    """Plan ``p`` with every learned clause recorded; refute each at up to two shifts in
    its own horizon and two steps longer. Returns (instances refuted, of them with pair
    or obstacle literals)."""
    learned: list[TeamConflict] = []
    original = TeamDisPlan.learn

    def recording(self: TeamDisPlan, fact) -> None:  # noqa: ANN001
        if isinstance(fact, TeamConflict):
            learned.append(fact)
        original(self, fact)

    TeamDisPlan.learn = recording  # type: ignore[method-assign]
    try:
        solve(p, "lazy-smt-team", Budget(seconds=120), horizon_search="linear", incumbent="none")
    finally:
        TeamDisPlan.learn = original  # type: ignore[method-assign]
    setup = prepare(p, p.max_horizon)
    refuted = with_pairs = 0
    for c in learned:
        if not c.certified:
            continue
        for L in (c.horizon, c.horizon + 2):
            shifts = c.shifts(L)
            for s in sorted({shifts[0], shifts[-1]}) if shifts else []:
                assert _oracle_refutes(p, setup, c, L, s), (p.name, c, L, s)
                refuted += 1
                with_pairs += any(lit[0] != "at" for lit in c.literals)
    return refuted, with_pairs


def test_every_clause_of_the_joint_conplan_is_sound() -> None:
    """Clause soundness over random teams and swaps; it must check many clauses, pair
    clauses among them (it would pass vacuously otherwise)."""
    refuted = with_pairs = 0
    for p in [*(random_team(s) for s in range(12)), *(swap_corridor(s) for s in range(6))]:
        a, b = _checked(p)
        refuted, with_pairs = refuted + a, with_pairs + b
    assert refuted >= 100 and with_pairs >= 20, (refuted, with_pairs)


def windy_team(seed: int) -> TeamProblem:
    """A random small team of two robots (:func:`random_team`) under a small disturbance
    each (0.5 to 3 cm on the positions, 2 to 5 cm/s on the velocities, LQR feedback)."""
    p = random_team(seed)
    rng = np.random.default_rng(seed + 1)
    robots = []
    for r in p.robots[:2]:
        pos_w, vel_w = float(rng.uniform(0.005, 0.03)), float(rng.uniform(0.02, 0.05))
        box = (pos_w, pos_w) + ((vel_w, vel_w) if r.dynamics.n_states == 4 else ())
        robots.append(replace(r, disturbance=Disturbance(box=box)))
    moving = p.moving_obstacles
    return replace(p, robots=tuple(robots), moving_obstacles=moving, name=f"windy-{seed}")


def test_every_clause_of_a_tightened_team_is_sound() -> None:
    """Clause soundness under disturbances: the oracle tightens every row by the error
    sets of its own step (computed here from the validator's exact sums), and refutes
    every clause at the (non-negative) shifts where DIS-PLAN adds it."""
    refuted = with_pairs = 0
    for p in (windy_team(s) for s in range(14)):
        a, b = _checked(p)
        refuted, with_pairs = refuted + a, with_pairs + b
    assert refuted >= 60 and with_pairs >= 10, (refuted, with_pairs)


def test_an_earlier_shift_of_a_tightened_clause_is_not_added() -> None:
    """Under growing margins a clause holds at later placements only: ``later_only``
    drops the negative shifts (a clause learned at steps 3-4 is not added at 0-1)."""
    c = TeamConflict((("at", 0, 3, 1), ("side", 0, 1, 3, 2)), start=False, goal=False, timed=False, horizon=9)
    assert min(c.shifts(9)) == -3
    assert replace(c, later_only=True).shifts(9) == [0, 1, 2, 3, 4, 5]


@pytest.mark.parametrize("seed", [3, 11])
def test_a_deliberately_unsound_clause_is_caught(seed: int) -> None:
    """The oracle can fail: a conflict claiming the robots' starts are enough to refute
    any plan (no literals, anchored at the start) is refuted only when it is true."""
    p = random_team(seed)
    setup = prepare(p, p.max_horizon)
    bogus = TeamConflict((), start=True, goal=False, timed=False, horizon=p.max_horizon)
    assert not _oracle_refutes(p, setup, bogus, p.max_horizon, 0)
    assert math.isfinite(setup.first)
