"""Mission planning end to end: the examples, the checker's verdicts, the
lazy planner against the milp-ltl baseline on random small workspaces and random
formulas, and the soundness of every clause the mission loop learns (checked by an LP
written here from scratch over every lasso or finite plan the clause excludes)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import highspy
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from reach_oracles import feasible
from test_ltl import formulas
from typer.testing import CliRunner

from plansynth import Budget
from plansynth.cli import app
from plansynth.reach import ReachStatus, solve
from plansynth.reach.families import random_workspace
from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.geometry import Box
from plansynth.reach.lazy.claims import EXACT_SEGMENTS
from plansynth.reach.lazy.conflict import Conflict
from plansynth.reach.mission.bmc import MissionDisPlan
from plansynth.reach.mission.check import check_mission
from plansynth.reach.mission.labels import label_abstraction
from plansynth.reach.mission.options import MissionOptions
from plansynth.reach.mission.planner import plan_mission
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

EXAMPLES = "examples/reach"


@pytest.mark.parametrize(
    "name, semantics", [("mission-visit", "finite"), ("mission-avoid-until", "finite"), ("mission-patrol", "lasso")]
)
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


@pytest.mark.parametrize("planner", ["lazy-smt", "milp-ltl"])
def test_the_unsatisfiable_example_is_infeasible_up_to_its_max_horizon(planner):
    """The vault lies inside the moat: no word over the labels' geometry satisfies
    ``F vault & G !moat``, a proof for every trajectory (plansynth.reach.mission.proof)."""
    p = load_reach_problem(f"{EXAMPLES}/mission-unsat.yaml")
    r = solve(p, planner, Budget(seconds=60))
    assert r.status is ReachStatus.INFEASIBLE and r.horizon == p.max_horizon
    assert r.counters["label_proof"] is True and "labels' geometry" in r.message


@pytest.mark.parametrize("reading", ["segment", "sample"])
@pytest.mark.parametrize("planner", ["lazy-smt", "milp-ltl"])
def test_a_label_ringed_by_walls_no_step_crosses_is_infeasible_for_the_problem(planner, reading):
    """The vault lies behind walls 2 m thick, and a step covers at most 1 m: no region a
    trajectory can reach from the start (in the segment reading: regions whose closures
    meet; in the sample reading: the one-step pairs) holds it, so ``F vault`` is refuted
    at every horizon, a proof for the problem in either reading (through the
    decomposition alone it was ``unknown``)."""
    p = replace(load_reach_problem(f"{EXAMPLES}/mission-ringed.yaml"), reading=reading)
    r = solve(p, planner, Budget(seconds=60))
    assert r.status is ReachStatus.INFEASIBLE and r.horizon == p.max_horizon, r.message
    assert r.counters["label_proof"] is True and "regions a trajectory can reach" in r.message


def test_a_label_behind_a_single_contact_point_is_not_refuted_by_reachability():
    """Two obstacles meet at one corner, cutting the room into two halves that touch at
    that point only: a segment through the point avoids both interiors, so the vault in
    the other half is reachable in the segment reading and the proof claims nothing (the
    regions' facet adjacency alone would have cut it off)."""
    p = replace(
        load_reach_problem(f"{EXAMPLES}/mission-ringed.yaml"),
        obstacles=(Box((0, 5), (5, 10)), Box((5, 0), (10, 5))),
        labels=(("vault", Box((7, 7), (8, 8))),),
        max_horizon=4,
    )
    r = solve(p, "lazy-smt", Budget(seconds=60), exact_segments=False)
    assert r.status is not ReachStatus.INFEASIBLE and r.counters["label_proof"] is False, r.message
    # exact transitions (auto: after the decomposition's refutation) take the corner: the
    # vault is out of reach in 4 steps (from rest at (1, 1): a proof for the problem) and
    # reached in 10, the trajectory through the contact point
    r = solve(p, "lazy-smt", Budget(seconds=60))
    assert r.status is ReachStatus.INFEASIBLE and r.counters["label_proof"] is False, r.message
    assert r.counters["transitions"] == "segments" and r.counters["decomposition_refuted"] == 4
    r = solve(replace(p, max_horizon=12), "lazy-smt", Budget(seconds=60))
    assert r.status is ReachStatus.FOUND and r.horizon == 10 and r.mission["ok"] and r.segment_safe, r.message


@pytest.mark.parametrize("planner", ["lazy-smt", "milp-ltl"])
def test_a_mission_out_of_reach_in_time_is_unknown_not_infeasible(planner):
    """Every horizon up to 10 refuted through the abstraction is no proof (a step may
    cross several regions): ``unknown``, saying so, with the counter."""
    p = replace(load_reach_problem(f"{EXAMPLES}/mission-visit.yaml"), max_horizon=10)
    r = solve(p, planner, Budget(seconds=60), **({"exact_segments": False} if planner == "lazy-smt" else {}))
    assert r.status is ReachStatus.UNKNOWN and r.counters["abstraction_refuted"] == 10
    assert r.counters["label_proof"] is False and "not a proof" in r.message
    if planner == "lazy-smt":  # auto (the default): continued exactly, a proof for the problem
        r = solve(p, planner, Budget(seconds=60))
        assert r.status is ReachStatus.INFEASIBLE and EXACT_SEGMENTS in r.message, r.message


@pytest.mark.parametrize("name, semantics", [("mission-visit", {"finite", "lasso"}), ("mission-patrol", {"lasso"})])
def test_the_one_shot_baseline_plans_exactly_the_max_horizon_and_is_checked(name, semantics):
    """``milp-ltl-oneshot`` (Wolff et al.'s fixed horizon K): one MILP, a plan of exactly
    K steps, validated and mission-checked like every plan (the visit mission may end in a
    finite plan or in a loop resting in the lab); the per-horizon search finds a shorter
    one."""
    p = replace(load_reach_problem(f"{EXAMPLES}/{name}.yaml"), max_horizon=34)  # shortest: 28 and 13
    r = solve(p, "milp-ltl-oneshot", Budget(seconds=60))
    assert r.status is ReachStatus.FOUND and r.planner == "milp-ltl-oneshot", r.message
    assert r.horizon == 34 and len(r.trajectory.states) == 35 and r.counters["milp_calls"] == 1
    assert r.validated is True and r.mission["ok"] is True and r.mission["semantics"] in semantics
    assert check_mission(p, r.trajectory, r.mission["loop_start"]).ok
    shortest = solve(p, "milp-ltl", Budget(seconds=60))
    assert shortest.status is ReachStatus.FOUND and shortest.horizon < 34


def test_the_one_shot_baseline_without_a_solution_at_its_horizon_proves_nothing():
    """No plan of exactly K steps is no proof for shorter horizons: ``unknown``, and the
    unsatisfiable example is still proved infeasible by the labels' geometry."""
    p = replace(load_reach_problem(f"{EXAMPLES}/mission-visit.yaml"), max_horizon=10)
    r = solve(p, "milp-ltl-oneshot", Budget(seconds=60))
    assert r.status is ReachStatus.UNKNOWN and r.counters["milp_calls"] == 1
    assert "shorter horizons not tried" in r.message and "not a proof" in r.message
    unsat = solve(load_reach_problem(f"{EXAMPLES}/mission-unsat.yaml"), "milp-ltl-oneshot", Budget(seconds=60))
    assert unsat.status is ReachStatus.INFEASIBLE and unsat.counters["label_proof"] is True


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
    text = (
        Path(f"{EXAMPLES}/mission-visit.yaml").read_text().replace('"F (kitchen & F lab) & G !stairs"', '"G !kitchen"')
    )
    bad_problem.write_text(text)
    # the first step whose segment [p_t, p_t+1] enters the kitchen's interior
    from shapely.geometry import LineString
    from shapely.geometry import box as sbox

    P = r.trajectory.states[:, :2]
    kitchen = sbox(2, 2, 6, 6).buffer(-1e-6)
    first = next(t for t in range(len(P) - 1) if LineString([P[t], P[t + 1]]).intersects(kitchen))
    out = runner.invoke(app, ["reach", "validate", str(bad_problem), str(good)])
    assert out.exit_code == 1
    assert f"VIOLATED (finite) at step {first}: segment {first} crosses into label kitchen" in out.output


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


def test_a_segment_that_cuts_through_a_label_holds_neither_literal_in_the_segment_reading():
    """The segment reading reads a step along its whole segment: a segment that crosses
    a label's edge is neither in it nor out of it (the reason names the crossing); the
    sample reading reads the step at its sample."""
    p = load_reach_problem(f"{EXAMPLES}/mission-patrol.yaml")
    # from inside a (x <= 2) to x = 3.5: the labels change between the samples
    X = np.array([[1.5, 0.5, 0, 0], [3.5, 0.5, 0, 0]])
    q = replace(p, start=X[0], mission="a")
    r = check_mission(q, Trajectory(X, np.zeros((1, 2))), end="free")
    assert not r.ok and r.step == 0 and r.reason == "segment 0 crosses out of label a"
    assert not check_mission(replace(q, mission="!a"), Trajectory(X, np.zeros((1, 2))), end="free").ok
    assert check_mission(q, Trajectory(X, np.zeros((1, 2))), end="free", reading="sample").ok
    # from a's edge through the hazard [2, 3] x [0, 0.8] and out of its top: segment 1
    X = np.array([[1.5, 0.5, 0, 0], [2, 0.5, 0, 0], [2.9, 1.5, 0, 0], [3.5, 0.5, 0, 0]])
    q = replace(p, start=X[0], mission="G !hazard")
    r = check_mission(q, Trajectory(X, np.zeros((3, 2))), end="free")
    assert not r.ok and r.step == 1 and r.reason == "segment 1 crosses into label hazard"
    assert check_mission(q, Trajectory(X, np.zeros((3, 2))), end="free", reading="sample").ok  # no sample in it


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
@given(mission_problems(), st.sampled_from(["segment", "sample"]), st.sampled_from(["rest", "free"]))
def test_lazy_and_milp_ltl_are_sound_and_agree_where_both_are_exact(p, reading, end):
    """Random formulas on random rooms, in both readings and with both ends: every plan
    either planner reports passes the validator and the checker; ``infeasible`` only with
    a proof (the geometry's, or the sample reading's exact search); in the sample reading
    both searches are exact, so they agree on the answer and the horizon. (In the segment
    reading each is sound and conservative in its own way: lazy-smt keeps a segment in one
    region, milp-ltl beyond one edge of each obstacle.)"""
    p = replace(p, reading=reading, end=end)
    lazy = solve(p, "lazy-smt", Budget(seconds=60))
    milp = solve(p, "milp-ltl", Budget(seconds=60))
    for r in (lazy, milp):
        # unknown only as "every horizon refuted" without a proof, never out of budget
        assert r.status is not ReachStatus.UNKNOWN or r.counters.get("abstraction_refuted") == p.max_horizon, r.message
        if r.status is ReachStatus.FOUND:
            assert r.validated is True and r.mission["ok"] is True
            assert check_mission(p, r.trajectory, r.mission["loop_start"]).ok
        if r.status is ReachStatus.INFEASIBLE:  # claimed only with a proof
            exact = r.counters.get("transitions") == "segments"  # lazy-smt continued exactly
            assert r.counters["label_proof"] is True or reading == "sample" or exact
    if reading == "sample":
        assert lazy.status is milp.status and lazy.horizon == milp.horizon
    elif milp.status is ReachStatus.INFEASIBLE or lazy.counters["label_proof"]:  # the geometry's proof is shared
        assert lazy.status is milp.status
    elif lazy.status is ReachStatus.INFEASIBLE:  # exact: no plan of the problem, so none of the MILP's
        assert milp.status is not ReachStatus.FOUND, (milp.horizon, lazy.message)
    # the horizon bound prunes nothing the search from 0 would find: the MILP from 0 agrees
    unbounded = solve(p, "milp-ltl", Budget(seconds=60), horizon_bound=False)
    assert unbounded.status is milp.status and unbounded.horizon == milp.horizon
    assert milp.counters.get("horizon_bound", 0) <= (
        milp.horizon if milp.status is ReachStatus.FOUND else p.max_horizon + 1
    )


# ------------------------------------------------------------ soundness of learned clauses


def oracle_feasible(p: ReachProblem, ab, walk, loop_start, segment_safe=True) -> bool:
    """A trajectory from the start through ``walk`` (and with x_N = x_loop_start)? A
    direct LP, sharing nothing with the planner's LPs (built row by row as sparse
    arrays: HiGHS's expression API costs more than the solve here)."""
    dyn = p.dynamics
    n, m, N = dyn.n_states, dyn.n_inputs, len(walk) - 1
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    inf = highspy.kHighsInf
    lo = np.array(p.state_bounds.lo, float) if p.state_bounds is not None else np.full(n, -inf)
    hi = np.array(p.state_bounds.hi, float) if p.state_bounds is not None else np.full(n, inf)
    x = lambda t, i: t * n + i  # noqa: E731 - column of state i at time t
    u = lambda t, j: (N + 1) * n + t * m + j  # noqa: E731 - column of input j at time t
    col_lo = np.concatenate([np.tile(lo, N + 1), np.full(N * m, -p.input_bound)])
    col_hi = np.concatenate([np.tile(hi, N + 1), np.full(N * m, p.input_bound)])
    rows: list[tuple[dict[int, float], float, float]] = []  # (coefficients, lower, upper)
    for i in range(n):
        rows.append(({x(0, i): 1.0}, float(p.start[i]), float(p.start[i])))
    for t in range(N):
        for i in range(n):
            coef = {x(t + 1, i): 1.0}
            for k in range(n):
                if A[i, k]:
                    coef[x(t, k)] = coef.get(x(t, k), 0.0) - float(A[i, k])
            for j in range(m):
                if B[i, j]:
                    coef[u(t, j)] = -float(B[i, j])
            rows.append((coef, 0.0, 0.0))
    for t, r in enumerate(walk):
        reg = ab.regions[r]
        for s in (t, t + 1) if segment_safe and t < N else (t,):
            for row, b in zip(reg.H, reg.h):
                coef: dict[int, float] = {}
                for c, k in zip(row, dyn.position):
                    if c:
                        coef[x(s, k)] = coef.get(x(s, k), 0.0) + float(c)
                rows.append((coef, -inf, float(b)))
    for k in range(2):
        for t in range(N + 1):
            rows.append(({x(t, dyn.position[k]): 1.0}, float(p.workspace.lo[k]), float(p.workspace.hi[k])))
    if loop_start is not None:
        for i in range(n):
            coef = {x(N, i): 1.0}
            coef[x(loop_start, i)] = coef.get(x(loop_start, i), 0.0) - 1.0
            rows.append((coef, 0.0, 0.0))
    h = highspy.Highs()
    h.silent()
    h.setOptionValue("threads", 1)
    h.addVars(len(col_lo), col_lo, col_hi)
    return feasible(h, rows)


def walks_through(ab, N, fixed: dict[int, int], close: int | None = None, limit: int = 3, seed: int = 0):
    """Up to ``limit`` region walks of horizon N from a start region, each step staying
    or moving to an adjacent region, with walk[t] == r for every (t, r) in ``fixed`` (and
    walk[N] == walk[close]); found by a depth-first search pruned by the distances
    between regions (waiting is a step, so "within d steps" is "in exactly d"), in an
    order shuffled by ``seed`` so that the walks differ off the fixed times; every
    region a step takes has a completion (:func:`ok` decides it exactly), so the search
    never backtracks out of a dead end."""
    R = ab.n_regions
    dist = np.full((R, R), np.inf)
    for r in range(R):  # breadth-first from r
        dist[r, r], frontier, d = 0, [r], 0
        while frontier:
            d += 1
            frontier = [q for x in frontier for q in ab.adjacency[x] if dist[r, q] == np.inf]
            for q in frontier:
                dist[r, q] = d
    times = sorted(fixed)
    rng = np.random.default_rng(seed)
    out: list[tuple[int, ...]] = []

    def chain(points: list[tuple[int, int]]) -> bool:
        """Can one walk pass through every (time, region) of ``points`` (sorted by time)?
        Exactly when each consecutive pair is within reach (waiting is a step)."""
        return all(a == b if u == v else dist[a, b] <= v - u for (u, a), (v, b) in zip(points, points[1:]))

    def ok(t: int, r: int, walk: tuple[int, ...]) -> bool:
        """Does some completion of walk + (r,) meet every constraint? (Exact, so the
        search never enters a subtree without a walk: the pruning by the next fixed
        time alone left it to enumerate millions of dead ends, most of the clause
        soundness test's time.)"""
        if t in fixed and fixed[t] != r:
            return False
        later = [(u, fixed[u]) for u in times if u > t]
        if close is None:
            return chain([(t, r)] + later)
        if t >= close:
            target = r if t == close else walk[close]
            return chain(sorted([(t, r)] + later + [(N, target)]))
        # walk[close] is still open: some region q for it (and for walk[N])
        return any(
            chain(sorted([(t, r)] + later + [(close, q), (N, q)]))
            for q in ([fixed[close]] if close in fixed else range(R))
        )

    def extend(walk: tuple[int, ...]) -> None:
        if len(out) >= limit:
            return
        t = len(walk)
        if t == N + 1:
            out.append(walk)
            return
        cands = list(ab.start_regions) if t == 0 else [walk[-1], *ab.adjacency[walk[-1]]]
        for r in rng.permutation(cands):
            if ok(t, int(r), walk):
                extend(walk + (int(r),))

    extend(())
    return out


def small_problems() -> list[ReachProblem]:
    """The patrol example and a room whose wall makes the patrol between a and b long
    (both learn CON-PLAN conflicts and refuted loops below their max horizons)."""
    patrol = load_reach_problem(f"{EXAMPLES}/mission-patrol.yaml")
    room = ReachProblem(
        workspace=Box((0, 0), (6, 6)),
        obstacles=(Box((0, 2), (4, 3)),),
        goal=None,
        dynamics=patrol.dynamics,
        start=[0.5, 0.5, 0, 0],
        input_bound=1.5,
        state_bounds=Box((0, 0, -2, -2), (6, 6, 2, 2)),
        labels=(("a", Box((0, 4), (2, 6))), ("b", Box((4, 0), (6, 2)))),
        mission="G F a & G F b",
    )
    return [replace(patrol, max_horizon=12), replace(room, max_horizon=14)]


def test_the_mission_transit_layer_reports_only_proved_legs_and_never_the_goal():
    """MissionTransit on random walks of the visit maze: no LP for a leg to the goal
    (the workspace) or above its box bound before the leg is decided; every conflict
    it reports is infeasible by a fresh LP of exactly its claim (cold, its own model);
    it reports a subset of the full layer's conflicts, with fewer LPs; and it decides every
    leg of the plan, whatever span CON-PLAN's conflict covers (the same conflicts with a
    span as without)."""
    from plansynth.reach.lazy.conplan import ConPlan
    from plansynth.reach.lazy.transit import GOAL, TransitCheck
    from plansynth.reach.mission.families import mission_problem
    from plansynth.reach.mission.labels import planning_problem
    from plansynth.reach.mission.theory import MissionTransit

    p = mission_problem("maze-1", "visit")
    ab = label_abstraction(p).abstraction
    pp = planning_problem(p)
    mine, full = MissionTransit(ConPlan(pp, ab), ab), TransitCheck(ConPlan(pp, ab), ab)
    spanned = MissionTransit(ConPlan(pp, ab), ab)
    judge = ConPlan(pp, ab)
    walks = [w for j in range(30) for w in walks_through(ab, 8 + j % 14, {}, limit=1, seed=j)]
    reported = 0
    key = lambda c: (c.literals, c.anchored_start, c.anchored_goal)  # noqa: E731
    for j, w in enumerate(walks):
        ours = mine.violations(w)
        assert [key(c) for c in spanned.violations(w, (j % 3, j % 3 + 1))] == [key(c) for c in ours]
        theirs = {(c.literals, c.anchored_start, c.anchored_goal) for c in full.violations(w)}
        for c in ours:
            assert not c.anchored_goal
            assert judge.refutes(c, cold=True), c
            assert (c.literals, c.anchored_start, c.anchored_goal) in theirs
        reported += len(ours)
    assert all(b != GOAL for _, b in mine._first)
    assert reported > 0 and mine.lp_calls < full.lp_calls


@pytest.mark.parametrize("which", [0, 1])
def test_the_loop_lp_agrees_with_an_lp_written_from_scratch(which):
    """LoopLP (its rows gathered from per-region templates) on random walks, finite and
    lassos back to a random step, against ``oracle_feasible``: the same verdict, and a
    trajectory through the walk when feasible."""
    from plansynth.reach.mission.labels import planning_problem
    from plansynth.reach.mission.looplp import LoopLP

    p = small_problems()[which]
    ab = label_abstraction(p).abstraction
    rng = np.random.default_rng(which)
    verdicts = []
    for seg in (True, False):
        lp = LoopLP(planning_problem(p), ab, segment_safe=seg)
        for j in range(40):
            H = int(rng.integers(1, 13))
            close = None if j % 3 == 0 else int(rng.integers(0, H))
            for w in walks_through(ab, H, {}, close=close, limit=1, seed=j):
                traj = lp.solve(w, close)
                expected = oracle_feasible(p, ab, w, close, segment_safe=seg)
                assert (traj is not None) == expected, (w, close, seg)
                verdicts.append(expected)
                if traj is not None:
                    assert len(traj.states) == H + 1
                    for t, r in enumerate(w):  # p_t in r_t (and p_t+1, segments)
                        reg = ab.regions[r]
                        for s_ in (t, t + 1) if seg and t < H else (t,):
                            pos = traj.states[s_][list(p.dynamics.position)]
                            assert np.all(np.asarray(reg.H) @ pos <= np.asarray(reg.h) + 1e-6), (w, t, s_)
                    if close is not None:
                        assert np.allclose(traj.states[H], traj.states[close])
    assert any(verdicts) and not all(verdicts)  # both verdicts are exercised


@pytest.mark.parametrize("which", [0, 1])
def test_every_learned_clause_excludes_only_infeasible_plans(which):
    """Every learned clause is checked at a few of the placements (horizon, shift,
    rotation) where the planner applies it, spread over all of them, on a walk built to
    match it: none has a trajectory (``oracle_feasible``), for CON-PLAN conflicts
    (finite walks) and loop clauses (lassos back to the loop start)."""
    p = small_problems()[which]
    la = label_abstraction(p)
    ab = la.abstraction
    conflicts, loops = [], []
    orig_learn, orig_loop = MissionDisPlan.learn, MissionDisPlan.learn_loop

    def learn(self, c):
        if isinstance(c, Conflict):  # (the loop's refuted loops and stays come through learn_loop, learn_stay)
            conflicts.append(c)
        orig_learn(self, c)

    def learn_loop(self, lits, k, L, *, shifted):
        loops.append((tuple(lits), k, L, shifted))
        orig_loop(self, lits, k, L, shifted=shifted)

    MissionDisPlan.learn, MissionDisPlan.learn_loop = learn, learn_loop
    try:
        plan_mission(
            p, Budget(seconds=60, iterations=150), MissionOptions(lower_bound=False, exact_segments=False), labelled=la
        )
    finally:
        MissionDisPlan.learn, MissionDisPlan.learn_loop = orig_learn, orig_loop
    assert conflicts and loops  # both kinds are learned, so both are checked below

    def placed(lits, shift, H):
        """The literals at time + shift, as a map time -> region (None: off 0..H or contradictory)."""
        fixed: dict[int, int] = {}
        for t, r in lits:
            if not 0 <= t + shift <= H or fixed.setdefault(t + shift, r) != r:
                return None
        return fixed

    # every placement (horizon, shift, rotation) where the planner applies each clause
    placements: list[list[tuple[int, dict[int, int], int | None, str]]] = []
    for c in conflicts:
        mine = []
        for H in range(1, p.max_horizon + 1):
            if c.anchored_start and c.anchored_goal:
                shifts = [0] if H == c.horizon else []
            elif c.anchored_start:  # and shifted earlier: the patrol starts at rest
                shifts = [s for s in range(-min((t for t, _ in c.literals), default=0), 1) if H >= c.last_time + s]
            else:
                shifts = [H - c.horizon] if c.anchored_goal else range(-c.first_time, H - c.last_time + 1)
            for s in shifts:
                fixed = placed(c.literals, s, H)
                if fixed is not None and c.first_time + s >= 0:
                    mine.append((H, fixed, None, f"{c} (shift {s})"))
        placements.append(mine)
    n_conflicts = len(placements)
    for lits, k, L, shifted in loops:
        period = L - k
        variants = (
            [lits] if not shifted else [tuple((k + (t - k + s) % period, r) for t, r in lits) for s in range(period)]
        )
        mine = []
        for H in range(L if not shifted else 1, (L if not shifted else p.max_horizon) + 1):
            s = H - L
            for v in variants:
                fixed = placed(v, s, H)
                if fixed is not None and k + s >= 0:
                    mine.append((H, fixed, k + s, f"loop clause {v} (k={k}, L={L}) at horizon {H}"))
        placements.append(mine)
    # a few placements of each clause, spread over all of them; at each, one walk built to match it
    checked = [0, 0]
    for n, mine in enumerate(placements):
        per = 5 if n < n_conflicts else 2
        for j in sorted(set(np.linspace(0, len(mine) - 1, min(per, len(mine))).astype(int))) if mine else []:
            H, fixed, close, what = mine[j]
            for w in walks_through(ab, H, fixed, close=close, limit=1, seed=n * 100 + j):
                assert not oracle_feasible(p, ab, w, close), f"{what} excludes the feasible {w}"
                checked[close is not None] += 1
    print(
        f"problem {which}: {len(conflicts)} conflicts, {len(loops)} loop clauses; "
        f"{checked[0]} finite and {checked[1]} lasso walks refuted"
    )
    assert checked[0] > 0 and checked[1] > 0


def test_the_checker_shares_no_code_with_the_planner():
    """The independent mission checker imports neither the encoding,
    the planners, the label refinement, the decomposition nor the lazy loop: it is run
    on the problem and the trajectory alone (LTL evaluation by ltl.holds, geometry by shapely)."""
    import ast
    import inspect

    import plansynth.reach.mission.check as check
    import plansynth.reach.mission.failure as failure
    import plansynth.reach.mission.touches as touches
    import plansynth.reach.mission.word as word

    imported: set[str] = set()
    for module in (check, word, touches, failure):  # the checker and the modules it is made of
        tree = ast.parse(inspect.getsource(module))
        imported |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
        imported |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    planner_side = (
        "plansynth.reach.mission.bmc",
        "plansynth.reach.mission.planner",
        "plansynth.reach.mission.milp",
        "plansynth.reach.mission.theory",
        "plansynth.reach.mission.looplp",
        "plansynth.reach.mission.plans",
        "plansynth.reach.mission.labels",
        "plansynth.reach.mission.proof",
        "plansynth.reach.abstraction",
        "plansynth.reach.lazy",
        "plansynth.reach.planners",
        "plansynth.reach.highs",
    )
    assert not [m for m in imported if m.startswith(planner_side)], imported
    assert "plansynth.reach.mission.ltl" in imported


@pytest.mark.parametrize("which", [0, 1])
def test_loop_alone_verdicts_from_the_memo_and_at_rest_are_the_lps(which):
    """LoopLP.loop_infeasible answers from its memo (period and times relative to the
    loop start) and from rest witnesses (:meth:`LoopLP.rests`); on random partial loops
    of random walks, at random loop starts and shifted to others, its verdict is the
    LP's own (``_lp`` of a LoopLP without memo, the LP checked against the oracle
    above), and a rest witness, anchored at the start or not, is never claimed for an
    infeasible LP."""
    import math

    from plansynth.reach.mission.labels import planning_problem
    from plansynth.reach.mission.looplp import LoopLP

    p = small_problems()[which]
    ab = label_abstraction(p).abstraction
    pp = planning_problem(p)
    mine, plain = LoopLP(pp, ab), LoopLP(pp, ab)
    rng = np.random.default_rng(which)
    verdicts = []
    for j in range(80):
        k, period = int(rng.integers(0, 4)), int(rng.integers(1, 9))
        L = k + period
        for w in walks_through(ab, L, {}, close=k, limit=1, seed=j):
            times = [t for t in range(k, L + 1) if rng.random() < 0.6]
            assign = {t: w[t] for t in times}
            expected = plain._lp(assign, k, L, False, k, math.inf) is None
            verdicts.append(expected)
            assert mine.loop_infeasible(assign, k, L) is expected, (assign, k, L)
            if mine.rests(assign, False):
                assert not expected
            s = int(rng.integers(1, 4))  # the same loop later: the memo's (or the witness's) answer
            assert mine.loop_infeasible({t + s: r for t, r in assign.items()}, k + s, L + s) is expected
            if mine.rests(assign, True):  # resting at the start, through the literals' regions
                assert plain._lp(assign, 0, L, True, k, math.inf) is not None
    assert mine.memo_hits > 0 and mine.rest_answers > 0
    assert any(verdicts) and not all(verdicts)  # both verdicts are exercised


def test_the_shortest_mission_horizon_is_claimed_through_the_decomposition_only():
    """DIS-PLAN moves one region per step; a real step may cross several, so a shorter
    plan can exist (found by a review: the CLI said "proved minimal" at horizon 2 while
    a valid 1-step plan exists)."""
    from plansynth.reach.fileformat import reach_problem_from_dict
    from plansynth.reach.mission.labels import planning_problem
    from plansynth.reach.trajectory import Trajectory
    from plansynth.reach.validate import validate

    obs = [{"min": [x, 0], "max": [x + 0.2, 1]} for x in (2, 4, 6)] + [
        {"min": [x, 9], "max": [x + 0.2, 10]} for x in (3, 5, 7)
    ]
    p = reach_problem_from_dict(
        {
            "workspace": {"min": [0, 0], "max": [10, 10]},
            "obstacles": obs,
            "labels": {"a": {"min": [9, 4], "max": [10, 6]}},
            "mission": "F a",
            "robot": {"dynamics": {"model": "single-integrator", "dt": 1}, "start": [0.5, 5], "input_bound": 20},
        }
    )
    r = solve(p)
    assert r.status is ReachStatus.FOUND and r.horizon == 2
    assert r.counters["minimal"] and r.counters["minimal_relative_to"] == "decomposition"
    one = Trajectory(np.array([[0.5, 5], [9.0, 5]]), np.array([[8.5, 0]]))  # a shorter plan to a's edge, valid
    assert validate(planning_problem(p), one, require_segment_safe=True).ok and check_mission(p, one).ok


def _edge_of_b(mission: str = "F a & G !b"):
    from plansynth.reach.fileformat import reach_problem_from_dict

    return reach_problem_from_dict(
        {
            "workspace": {"min": [0, 0], "max": [10, 10]},
            "labels": {"a": {"min": [4, 0], "max": [5, 10]}, "b": {"min": [5, 0], "max": [10, 10]}},
            "mission": mission,
            "robot": {"dynamics": {"model": "double-integrator", "dt": 1}, "start": [0.4, 5, 0, 0], "input_bound": 1},
        }
    )


def test_a_finite_plan_must_end_where_the_robot_can_stay():
    """The finite reading holds the last state forever, so the robot must be able to
    rest there (found by a review: a plan ending at 0.7 m/s towards b passed G !b,
    although every input takes it into b at the next step)."""
    from plansynth.reach.mission.check import can_rest

    p = _edge_of_b()
    X, U = [[0.4, 5, 0, 0]], []
    for u in (1, 1, -0.8, -0.5):
        x, y, vx, vy = X[-1]
        X.append([x + vx + 0.5 * u, y, vx + u, vy])
        U.append([u, 0])
    moving = Trajectory(np.array(X), np.array(U, float))
    r = check_mission(p, moving)
    assert not r.ok and r.step == 4 and "cannot end" in r.reason
    # both planners end their finite plans at rest, and the checker accepts them
    for planned in (solve(p, "lazy-smt", Budget(seconds=60)), solve(p, "milp-ltl", Budget(seconds=60))):
        assert planned.status is ReachStatus.FOUND and planned.mission["semantics"] == "finite", planned.message
        assert can_rest(p, planned.trajectory.states[-1]) and planned.mission["ok"]
        assert np.allclose(planned.trajectory.states[-1][2:], 0.0, atol=1e-6)
