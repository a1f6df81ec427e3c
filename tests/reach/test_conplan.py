"""CON-PLAN (Section V): ZEROPREFIX, the LPs on hand-made regions, counterexamples."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from plansynth.reach.abstraction import Abstraction, Region, abstract
from plansynth.reach.dynamics import double_integrator, single_integrator
from plansynth.reach.families import maze
from plansynth.reach.geometry import Box
from plansynth.reach.lazy.bounds import physical_lower_bound, step_reach, time_windows
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.conplan import COUNTEREXAMPLES, ConPlan, zero_prefix
from plansynth.reach.problem import ReachProblem
from plansynth.reach.validate import validate

# ------------------------------------------------------------------ ZEROPREFIX


@pytest.mark.parametrize(
    ("slacks", "k"),
    [
        ([], 0),
        ([0.0], 1),
        ([3.0], 0),
        ([0, 0, 0, 0.5, 2], 3),
        ([0, 1e-9, 5e-8, 1e-3], 3),  # below the zero tolerance counts as zero
        ([0, 0, 0, 0], 4),
        ([2, 2, 2], 0),
    ],
)
def test_zero_prefix_on_hand_made_slacks(slacks: list[float], k: int) -> None:
    assert zero_prefix(slacks) == k


@given(st.integers(0, 30), st.lists(st.floats(1e-6, 10), max_size=30))
def test_zero_prefix_is_the_linear_scan_on_monotone_slacks(zeros: int, rest: list[float]) -> None:
    slacks = [0.0] * zeros + sorted(rest)
    linear = next((i for i, s in enumerate(slacks) if s > 1e-7), len(slacks))
    assert zero_prefix(slacks) == linear


# ------------------------------------------------------------------ hand-made regions


def box_region(index: int, lo: tuple[float, float], hi: tuple[float, float]) -> Region:
    H = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
    h = np.array([hi[0], hi[1], -lo[0], -lo[1]])
    v = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    return Region(index, H, h, v)


def one_region() -> tuple[ReachProblem, Abstraction]:
    """An empty 4 x 2 room, a single integrator with |u| <= 1 per step."""
    p = ReachProblem(
        workspace=Box((0, 0), (4, 2)),
        obstacles=(),
        goal=Box((3, 0.5), (4, 1.5)),
        dynamics=single_integrator(2, 1.0),
        start=[0.5, 1.0],
        input_bound=1.0,
    )
    a = Abstraction((box_region(0, (0, 0), (4, 2)),), ((),), (0,), (0,), 0.0)
    return p, a


def l_shape() -> tuple[ReachProblem, Abstraction]:
    """A 3 x 3 room whose lower right 2 x 2 is an obstacle; region 0 the left column
    below y = 2, region 1 the top strip. Their union is not convex: a segment from
    region 0 to region 1 can cut the obstacle's corner."""
    p = ReachProblem(
        workspace=Box((0, 0), (3, 3)),
        obstacles=(Box((1, 0), (3, 2)),),
        goal=Box((2.5, 2), (3, 2.5)),
        dynamics=single_integrator(2, 1.0),
        start=[0.5, 0.5],
        input_bound=3.0,
    )
    a = Abstraction((box_region(0, (0, 0), (1, 2)), box_region(1, (0, 2), (3, 3))), ((1,), (0,)), (0,), (1,), 0.0)
    return p, a


def test_one_region_lp_feasible_and_infeasible() -> None:
    p, a = one_region()
    c = ConPlan(p, a)
    # 2.5 m to go at most 1 m per step: horizon 2 is too short, 3 is enough
    assert c.feasible((0, 0, 0)) is None
    traj = c.feasible((0, 0, 0, 0))
    assert traj is not None and validate(p, traj, require_segment_safe=True).ok
    out = c.check((0, 0, 0))
    assert isinstance(out, Conflict) and out.anchored_goal
    assert isinstance(c.check((0, 0, 0, 0)), Feasible)
    assert c.stats.lp_calls >= 3


@pytest.mark.parametrize("strategy", COUNTEREXAMPLES)
@pytest.mark.parametrize("generalize", [False, True])
def test_counterexamples_are_refuted_by_their_own_lp(strategy: str, generalize: bool) -> None:
    p, a = one_region()
    c = ConPlan(p, a, counterexample=strategy, generalize=generalize)
    out = c.check((0, 0, 0))
    assert isinstance(out, Conflict)
    assert c.refutes(out)  # the LP of exactly what the clause claims has no solution


def test_segment_safety_forbids_cutting_the_corner() -> None:
    p, a = l_shape()
    samples = ConPlan(p, a, segment_safe=False)
    segments = ConPlan(p, a, segment_safe=True)
    # horizon 1: jump from region 0 straight into the goal -- through the obstacle
    traj = samples.feasible((0, 1))
    assert traj is not None
    report = validate(p, traj)
    assert report.ok and not report.segment_safe
    assert segments.feasible((0, 1)) is None
    # horizon 2 with a stop on the common edge y = 2, x <= 1
    traj = segments.feasible((0, 1, 1))
    assert traj is not None
    assert validate(p, traj, require_segment_safe=True).ok
    assert traj.states[1][1] == pytest.approx(2.0, abs=1e-7) and traj.states[1][0] <= 1 + 1e-7


def test_two_regions_counterexample_blocks_the_early_switch() -> None:
    p, a = l_shape()
    c = ConPlan(p, a, segment_safe=True)
    out = c.check((0, 1))
    assert isinstance(out, Conflict)
    # the plan (0, 1) dies at time 1 (p_1 must lie on the common edge and in the goal)
    assert c.refutes(out)
    assert all(t <= 1 for t, _ in out.literals)


def test_zeroprefix_counterexample_is_the_earliest_infeasible_prefix() -> None:
    """A plan that dives into region 1 too early dies at that step, not at the goal."""
    p = maze(1)
    ab = abstract(p)
    c = ConPlan(p, ab, generalize=False)
    plan = (0,) * 5 + (1,) * 3 + (2,) * 52  # the gap (region 1) at t = 5: 26 m away
    out = c.check(plan)
    assert isinstance(out, Conflict) and out.anchored_start and not out.anchored_goal
    k = max(t for t, _ in out.literals)
    assert k == 5 and out.literals == tuple(enumerate(plan[: k + 1]))
    assert not c.prefix_feasible(plan, k) and c.prefix_feasible(plan, k - 1)


def test_generalized_counterexample_is_shift_invariant_when_the_start_does_not_matter() -> None:
    """Gap to gap in 5 steps is impossible from any state: no start, no goal, any time."""
    p = maze(2)
    ab = abstract(p)
    c = ConPlan(p, ab, generalize=True)
    plan = (0,) * 30 + (1,) * 2 + (2,) * 5 + (3,) * 2 + (4,) * 61
    out = c.check(plan)
    assert isinstance(out, Conflict)
    assert not out.anchored_start and not out.anchored_goal
    assert c.refutes(out)
    assert out.last_time - out.first_time < 20


def test_time_windows_and_bounds_on_the_maze() -> None:
    p = maze(1)
    down, up = step_reach(p)
    assert np.allclose(down, 1.0) and np.allclose(up, 1.0)  # |v| <= 2 m/s for 0.5 s
    assert physical_lower_bound(p) == 26
    w = time_windows(p, abstract(p), 200)
    assert w.horizon >= 26 and w.earliest[0] == 0 and w.to_go[2] == 0
    assert all(e + g <= 57 for e, g in zip(w.earliest, w.to_go))  # 57: a validated plan exists


def test_time_windows_without_state_bounds_are_unbounded() -> None:
    p = ReachProblem(
        workspace=Box((0, 0), (4, 2)),
        obstacles=(),
        goal=Box((3, 0.5), (4, 1.5)),
        dynamics=double_integrator(2, 1.0),
        start=[0.5, 1.0, 0, 0],
        input_bound=1.0,
    )
    down, up = step_reach(p)
    assert np.all(up <= 4.0)  # the workspace still bounds one step's displacement
    assert physical_lower_bound(p) >= 1


def test_unknown_options_are_rejected() -> None:
    p, a = one_region()
    with pytest.raises(ValueError, match="counterexample"):
        ConPlan(p, a, counterexample="oracle")
    with pytest.raises(ValueError, match="slack weights"):
        ConPlan(p, a, slack_weights="random")


def test_start_outside_every_region_horizon_zero() -> None:
    p, a = one_region()
    c = ConPlan(p, a)
    assert isinstance(c.check((0,)), Conflict)  # the start is not in the goal
    assert math.isfinite(c.stats.seconds)


def test_stalled_simplex_falls_back_to_the_interior_point_method() -> None:
    p, a = one_region()
    c = ConPlan(p, a, generalize=True)
    c.slot.highs.setOptionValue("simplex_iteration_limit", 0)  # every warm simplex "stalls"
    c.slack_slot.highs.setOptionValue("simplex_iteration_limit", 0)
    out = c.check((0, 0, 0))
    assert isinstance(out, Conflict) and c.refutes(out)
    assert c.stats.ipm_fallbacks > 0
    found = c.check((0, 0, 0, 0))
    assert isinstance(found, Feasible) and validate(p, found.trajectory, require_segment_safe=True).ok


def test_a_trajectory_that_misses_the_dynamics_is_polished() -> None:
    """Long chains can leave unscaled dynamics residuals of 1e-5 after a scaled simplex
    run; CON-PLAN then re-solves the plan's LP tightly instead of reporting it."""
    from plansynth.reach.lazy.conplan import POLISH_RESIDUAL
    from plansynth.reach.lazy.planner import plan_lazy
    from plansynth.reach.trajectory import Trajectory
    from plansynth.reach.validate import validate

    p = maze(1)
    ab = abstract(p)
    regions = plan_lazy(p).regions
    cp = ConPlan(p, ab)
    good = cp.feasible(regions)
    assert good is not None and cp.residual(good) <= POLISH_RESIDUAL
    X = np.array(good.states, float)
    X[1:, 2] += 3e-5  # velocities off the dynamics, as a sloppy LP answer would be
    sloppy = Trajectory(states=X, inputs=np.array(good.inputs, float))
    assert cp.residual(sloppy) > 1e-5 and not validate(p, sloppy).ok
    fixed = cp._polished(regions, Feasible(sloppy)).trajectory
    assert cp.residual(fixed) <= 1e-8 and validate(p, fixed, require_segment_safe=True).ok
    assert cp.stats.polished == 1 and cp.stats.by_kind["polish"] == 1


def test_the_warm_polish_needs_the_plan_in_the_model() -> None:
    """The polish first re-solves the plan's LP from its own basis at tight tolerances,
    but only while the model holds exactly that LP; otherwise it gives None and the cold
    polish runs."""
    from plansynth.reach.lazy.planner import plan_lazy

    p = maze(1, order=4)
    ab = abstract(p)
    regions = plan_lazy(p).regions
    cp = ConPlan(p, ab)
    assert cp.feasible(regions) is not None
    warm = cp._polished_warm(regions)
    assert warm is not None and cp.residual(warm.trajectory) <= 1e-8
    assert validate(p, warm.trajectory, require_segment_safe=True).ok
    assert cp._polished_warm(regions) is None  # (the model's answer was at other tolerances)
    assert cp.prefix_feasible(regions, 3)
    assert cp._polished_warm(regions) is None  # the model holds a prefix LP now
    assert cp._polished_warm(regions[:-1]) is None


@pytest.mark.parametrize("threads", [1, 2])
def test_long_chain_plan_lps_start_interior_and_fall_back_to_the_simplex(threads: int, monkeypatch) -> None:
    """On a long chain a plan LP with no basis is first solved by the interior-point
    method (no polish needed: its residual is far below the validator's), the axes one
    after the other or on two threads at once; when that finds no solution, the simplex
    method decides and the conflict comes from its Farkas ray."""
    import plansynth.reach.lazy.conplan.runs as runs

    monkeypatch.setattr(runs, "PART_THREADS", threads)
    from plansynth.reach.lazy.conplan import POLISH_RESIDUAL
    from plansynth.reach.lazy.conplan.runs import INTERIOR_STATES
    from plansynth.reach.lazy.planner import plan_lazy

    p = maze(1, order=15)
    assert p.dynamics.n_states >= INTERIOR_STATES
    ab = abstract(p)
    regions = plan_lazy(p).regions
    cp = ConPlan(p, ab)
    found = cp.feasible(regions)
    assert found is not None and cp.residual(found) <= POLISH_RESIDUAL
    assert validate(p, found, require_segment_safe=True).ok
    assert cp.stats.interior == 2 and cp.stats.by_kind == {"plan": 1}  # one run per axis, one LP call
    # too short by half: no trajectory; the interior-point run is counted, the simplex decides
    short = regions[: len(regions) // 2]
    cp = ConPlan(p, ab, counterexample="trivial", generalize=True)  # (lazy-smt's default)
    out = cp.check(short)
    assert isinstance(out, Conflict) and cp.refutes(out, cold=True)
    assert cp.stats.interior >= 1 and cp.stats.ray_calls >= 1  # (the simplex after the interior-point run)
    assert cp.stats.uncertified == 0  # (the simplex method's "no" has its ray)
    # the simplex method stalls (as on a badly conditioned chain): the fallback's
    # interior-point run decides, and its "no" is counted as uncertified too
    cp = ConPlan(p, ab, counterexample="trivial", generalize=True)
    split = cp._split

    def stalling(slot, lay, b):
        split(slot, lay, b)
        for part in slot.parts:
            part.highs.setOptionValue("simplex_iteration_limit", 1)

    cp._split = stalling
    out = cp.check(short)
    assert isinstance(out, Conflict) and cp.refutes(out, cold=True)
    assert cp.stats.ipm_fallbacks >= 1 and cp.stats.uncertified >= 1
    # a plan whose window is deferred if it fails keeps the interior-point refutation: no ray
    cp = ConPlan(p, ab, counterexample="trivial", generalize=True)
    cp.expendable = True
    whole = cp.check(short)
    assert isinstance(whole, Conflict) and cp.refutes(whole, cold=True)
    assert cp.stats.ray_calls == 0 and len(whole.literals) == len(short)  # the whole plan
    assert cp.stats.uncertified == 1  # (and the loop's claims say so: see the next test)


def test_claims_resting_on_uncertified_refutations_are_withdrawn() -> None:
    """An expendable plan refuted by the interior-point method has no Farkas certificate:
    a loop that kept such refutations reports no unproved `infeasible` and no minimal
    horizon (unless the relaxation MILP proved it)."""
    from dataclasses import replace as _replace

    from plansynth.reach.lazy.claims import uncertified
    from plansynth.reach.lazy.loop import LoopOutcome
    from plansynth.reach.result import ReachStatus

    inf = LoopOutcome(ReachStatus.INFEASIBLE, 40, "infeasible up to horizon 40: every horizon refuted")
    out = uncertified(inf, 2, None)
    assert out.status is ReachStatus.UNKNOWN and "2 LP refutations without a Farkas certificate" in out.message
    assert uncertified(inf, 2, "infeasible") is inf  # proved by the relaxation MILP
    found = LoopOutcome(ReachStatus.FOUND, 30, "found at horizon 30", minimal=True)
    out = uncertified(found, 1, None)
    assert out.status is ReachStatus.FOUND and out.minimal is False and "not proved minimal" in out.message
    assert uncertified(found, 1, "minimal") is found
    plain = _replace(found, minimal=False)
    assert uncertified(plain, 1, None) is plain
