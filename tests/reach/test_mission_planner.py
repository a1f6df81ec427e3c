"""Mission planning end to end (issue 14): the examples, the checker's verdicts, the
lazy planner against the milp-ltl baseline on random small workspaces and random
formulas, and the soundness of every clause the mission loop learns (checked by an LP
written here from scratch over every lasso or finite plan the clause excludes)."""

from __future__ import annotations

import itertools
import json
from dataclasses import replace

import highspy
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from plansynth import Budget
from plansynth.cli import app
from plansynth.reach import ReachStatus, solve
from plansynth.reach.families import random_workspace
from plansynth.reach.mission.ltl import Lasso, finite_word, holds, parse
from plansynth.reach.mission.bmc import MissionDisPlan
from plansynth.reach.mission.check import check_mission
from plansynth.reach.mission.labels import label_abstraction
from plansynth.reach.mission.planner import plan_mission
from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

from test_ltl import formulas

EXAMPLES = "examples/reach"


@pytest.mark.parametrize("name, semantics", [("mission-visit", "finite"), ("mission-avoid-until", "finite"),
                                             ("mission-patrol", "lasso")])
def test_examples_solve_and_pass_the_checker(name, semantics):
    p = load_reach_problem(f"{EXAMPLES}/{name}.yaml")
    r = solve(p, "lazy-smt", Budget(seconds=120))
    assert r.status is ReachStatus.FOUND, r.message
    assert r.validated is True and r.mission["ok"] is True and r.mission["semantics"] == semantics
    report = check_mission(p, r.trajectory, r.mission["loop_start"])
    assert report.ok
    if semantics == "lasso":
        k = r.mission["loop_start"]
        assert np.allclose(r.trajectory.states[-1], r.trajectory.states[k])


def test_the_maze_example_is_the_benchmark_instance():
    from plansynth.reach.mission.families import mission_problem

    p = load_reach_problem(f"{EXAMPLES}/mission-maze.yaml")
    assert p == replace(mission_problem("maze-2", "avoid-until"), name="mission-maze")


def test_the_unsatisfiable_example_is_infeasible_up_to_its_max_horizon():
    p = load_reach_problem(f"{EXAMPLES}/mission-unsat.yaml")
    r = solve(p, "lazy-smt", Budget(seconds=60))
    assert r.status is ReachStatus.INFEASIBLE and r.horizon == p.max_horizon


def test_reach_validate_rejects_a_violating_trajectory_naming_the_first_failing_step(tmp_path):
    p = load_reach_problem(f"{EXAMPLES}/mission-visit.yaml")
    r = solve(p, "lazy-smt", Budget(seconds=60))
    good = tmp_path / "plan.json"
    r.write_json(good)
    runner = CliRunner()
    ok = runner.invoke(app, ["reach", "validate", f"{EXAMPLES}/mission-visit.yaml", str(good)])
    assert ok.exit_code == 0, ok.output
    assert "mission holds" in ok.output
    # the same trajectory judged against a mission it violates: the kitchen must never be entered
    bad_problem = tmp_path / "bad.yaml"
    text = open(f"{EXAMPLES}/mission-visit.yaml").read().replace('"F (kitchen & F lab) & G !stairs"', '"G !kitchen"')
    bad_problem.write_text(text)
    # the first step whose segment [p_t, p_t+1] enters the kitchen's interior
    from shapely.geometry import LineString
    from shapely.geometry import box as sbox
    P = r.trajectory.states[:, :2]
    kitchen = sbox(2, 2, 6, 6).buffer(-1e-6)
    first = next(t for t in range(len(P) - 1) if LineString([P[t], P[t + 1]]).intersects(kitchen))
    out = runner.invoke(app, ["reach", "validate", str(bad_problem), str(good)])
    assert out.exit_code == 1
    assert f"VIOLATED (finite) at step {first}: in label kitchen" in out.output


def test_the_checker_names_the_step_and_the_reason():
    p = load_reach_problem(f"{EXAMPLES}/mission-patrol.yaml")
    X = np.array([[1, 1, 0, 0], [1.25, 1, 1, 0], [1.75, 1, 1, 0], [2, 1, 0, 0]])
    U = np.array([[2, 0], [0, 0], [-2, 0]], float)
    t = Trajectory(X, U)
    r = check_mission(p, t)
    assert not r.ok and r.step == 3 and "b never holds" in r.reason
    r = check_mission(p, t, loop_start=1)
    assert not r.ok and r.step == 3 and "loop does not close" in r.reason
    # a lasso that closes but never visits b
    X2 = np.array([[1, 1, 0, 0], [1, 1, 0, 0]])
    r = check_mission(p, Trajectory(X2, np.zeros((1, 2))), loop_start=0)
    assert not r.ok and r.semantics == "lasso" and "b never holds" in r.reason


def test_a_segment_that_cuts_through_a_label_is_a_crossing():
    p = load_reach_problem(f"{EXAMPLES}/mission-patrol.yaml")
    # from inside a (x <= 2) to x = 3.5: the labels change between the samples
    X = np.array([[1.5, 0.5, 0, 0], [3.5, 0.5, 0, 0]])
    r = check_mission(replace(p, start=X[0]), Trajectory(X, np.zeros((1, 2))))
    assert not r.ok and r.step == 0 and r.reason == "segment 0 crosses out of label a"
    # from a's edge through the hazard [2, 3] x [0, 0.8] and out of its top: segment 1
    X = np.array([[1.5, 0.5, 0, 0], [2, 0.5, 0, 0], [2.9, 1.5, 0, 0], [3.5, 0.5, 0, 0]])
    r = check_mission(replace(p, start=X[0]), Trajectory(X, np.zeros((3, 2))))
    assert not r.ok and r.step == 1 and r.reason == "segment 1 crosses into label hazard"


# ------------------------------------------------------------ random workspaces and formulas

NAMES = ("a", "b", "c")


@st.composite
def mission_problems(draw):
    seed = draw(st.integers(0, 10**6))
    try:
        base = random_workspace(seed, draw(st.integers(0, 2)), order=1, dt=1.0, input_bound=1.5, polygons=False)
    except RuntimeError:
        base = random_workspace(7, 1, order=1, dt=1.0, input_bound=1.5, polygons=False)
    labels = []
    for name in NAMES:
        x, y = draw(st.floats(0, 7)), draw(st.floats(0, 7))
        w, h = draw(st.floats(1, 3)), draw(st.floats(1, 3))
        labels.append((name, Box((x, y), (x + w, y + h))))
    f = draw(formulas())
    return replace(base, goal=None, labels=tuple(labels), mission=str(f), max_horizon=draw(st.integers(2, 5)))


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(mission_problems())
def test_lazy_and_milp_ltl_agree_and_every_plan_satisfies_the_mission(p):
    lazy = solve(p, "lazy-smt", Budget(seconds=60))
    milp = solve(p, "milp-ltl", Budget(seconds=60))
    for r in (lazy, milp):
        assert r.status is not ReachStatus.UNKNOWN, r.message
        if r.status is ReachStatus.FOUND:
            assert r.validated is True and r.mission["ok"] is True
            assert check_mission(p, r.trajectory, r.mission["loop_start"]).ok
    assert lazy.status is milp.status
    assert lazy.horizon == milp.horizon  # both search horizons upwards from 0


# ------------------------------------------------------------ soundness of learned clauses


def oracle_feasible(p: ReachProblem, ab, walk, loop_start, segment_safe=True) -> bool:
    """A trajectory from the start through ``walk`` (and with x_N = x_loop_start)? A
    direct LP, sharing nothing with the planner's LPs."""
    dyn = p.dynamics
    n, m, N = dyn.n_states, dyn.n_inputs, len(walk) - 1
    A, B = np.asarray(dyn.A), np.asarray(dyn.B)
    lo = np.array(p.state_bounds.lo, float) if p.state_bounds is not None else np.full(n, -highspy.kHighsInf)
    hi = np.array(p.state_bounds.hi, float) if p.state_bounds is not None else np.full(n, highspy.kHighsInf)
    h = highspy.Highs()
    h.silent()
    h.setOptionValue("threads", 1)
    X = [[h.addVariable(lb=float(lo[i]), ub=float(hi[i])) for i in range(n)] for _ in range(N + 1)]
    U = [[h.addVariable(lb=-p.input_bound, ub=p.input_bound) for _ in range(m)] for _ in range(N)]
    for i in range(n):
        h.addConstr(X[0][i] == float(p.start[i]))
    for t in range(N):
        for i in range(n):
            h.addConstr(X[t + 1][i] - sum(float(A[i, k]) * X[t][k] for k in range(n) if A[i, k])
                        - sum(float(B[i, j]) * U[t][j] for j in range(m) if B[i, j]) == 0)
    for t, r in enumerate(walk):
        reg = ab.regions[r]
        for s in ((t, t + 1) if segment_safe and t < N else (t,)):
            for row, b in zip(reg.H, reg.h):
                h.addConstr(sum(float(c) * X[s][k] for c, k in zip(row, dyn.position)) <= float(b))
    for k in range(2):
        lo_k, hi_k = p.workspace.lo[k], p.workspace.hi[k]
        for t in range(N + 1):
            h.addConstr(X[t][dyn.position[k]] >= lo_k)
            h.addConstr(X[t][dyn.position[k]] <= hi_k)
    if loop_start is not None:
        for i in range(n):
            h.addConstr(X[N][i] - X[loop_start][i] == 0)
    h.run()
    return h.getModelStatus() == highspy.HighsModelStatus.kOptimal


def lassos(ab, N):
    def extend(prefix):
        if len(prefix) == N + 1:
            yield prefix
            return
        for nxt in (prefix[-1], *ab.adjacency[prefix[-1]]):
            yield from extend(prefix + (nxt,))

    for s in ab.start_regions:
        yield from extend((s,))


def small_problems() -> list[ReachProblem]:
    patrol = load_reach_problem(f"{EXAMPLES}/mission-patrol.yaml")
    room = ReachProblem(workspace=Box((0, 0), (6, 6)), obstacles=(Box((0, 2), (4, 3)),), goal=None,
                        dynamics=patrol.dynamics, start=[0.5, 0.5, 0, 0], input_bound=1.5,
                        state_bounds=Box((0, 0, -2, -2), (6, 6, 2, 2)),
                        labels=(("a", Box((0, 4), (2, 6))), ("b", Box((4, 0), (6, 2)))), mission="G F a & G F b")
    return [replace(patrol, max_horizon=12), replace(room, max_horizon=7)]


@pytest.mark.parametrize("which", [0])
def test_every_learned_clause_excludes_only_infeasible_plans(which):
    p = small_problems()[which]
    la = label_abstraction(p)
    ab = la.abstraction
    conflicts, loops = [], []
    orig_learn, orig_loop = MissionDisPlan.learn, MissionDisPlan.learn_loop

    def learn(self, c):
        conflicts.append(c)
        orig_learn(self, c)

    def learn_loop(self, lits, k, L, *, shifted):
        loops.append((tuple(lits), k, L, shifted))
        orig_loop(self, lits, k, L, shifted=shifted)

    MissionDisPlan.learn, MissionDisPlan.learn_loop = learn, learn_loop
    try:
        plan_mission(p, Budget(seconds=60, iterations=150), labelled=la, lower_bound=False)
    finally:
        MissionDisPlan.learn, MissionDisPlan.learn_loop = orig_learn, orig_loop
    checked = loops_checked = 0
    for H in range(1, p.max_horizon + 1):
        walks = list(itertools.islice(lassos(ab, H), 1500))
        for c in conflicts:
            def matches(shift, w=None):
                return all(0 <= t + shift <= H and w[t + shift] == r for t, r in c.literals)
            for w in walks:
                if c.anchored_start and c.anchored_goal:
                    hit = H == c.horizon and matches(0, w)
                elif c.anchored_start:  # and shifted earlier: the patrol starts at rest
                    earliest = -min((t for t, _ in c.literals), default=0)
                    hit = any(H >= c.last_time + s and matches(s, w) for s in range(earliest, 1))
                else:
                    shifts = [H - c.horizon] if c.anchored_goal else range(-c.first_time, H - c.last_time + 1)
                    hit = any(c.first_time + s >= 0 and matches(s, w) for s in shifts)
                if hit and checked < 400:
                    assert not oracle_feasible(p, ab, w, None), f"{c} excludes the feasible {w}"
                    checked += 1
        for lits, k, L, shifted in loops:
            period = L - k
            variants = [lits] if not shifted else [tuple((k + (t - k + s) % period, r) for t, r in lits) for s in range(period)]
            shifts = [H - L] if (shifted or H == L) else []
            for s in shifts:
                if not shifted and s != 0:
                    continue
                if k + s < 0:
                    continue
                for v in variants:
                    for w in walks:
                        if all(0 <= t + s <= H and w[t + s] == r for t, r in v) and w[H] == w[k + s] and checked < 800:
                            assert not oracle_feasible(p, ab, w, k + s), f"loop clause {v} (k={k}, L={L}) excludes {w}"
                            checked += 1
                            loops_checked += 1
    assert checked > 0
    if which == 0:  # the patrol learns loop clauses below horizon 12
        assert loops and loops_checked > 0
