"""Random dynamics: the family's horizon rule, and the plan LPs of
dense dynamics, which the interior-point method solves first (a refuted plan whose
window is deferred keeps the whole plan as its conflict)."""

from __future__ import annotations

import numpy as np
from tests.reach.test_separator_chains import SetTheory

from plansynth.budget import Budget
from plansynth.reach.abstraction import abstract
from plansynth.reach.dynamics import displacement_reach
from plansynth.reach.families import RANDOM_DYNAMICS_MAX_HORIZON, random_dynamics
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.displan import DisPlan, RegionGraph
from plansynth.reach.lazy.loop import lazy_loop
from plansynth.reach.lazy.planner import plan_lazy
from plansynth.reach.oracle import oracle_lp
from plansynth.reach.problem import DEFAULT_MAX_HORIZON
from plansynth.reach.result import ReachStatus
from plansynth.reach.solve import solve


def test_every_random_dynamics_instance_gets_the_family_horizon() -> None:
    """The rule: max_horizon 400 for every instance, twice the problem default; maze-4's
    122 m of horizontal travel fits in 400 steps by the long-run displacement bound."""
    assert RANDOM_DYNAMICS_MAX_HORIZON == 2 * DEFAULT_MAX_HORIZON == 400
    for m, n, seed in ((0, 4, 0), (1, 6, 3), (4, 10, 0)):
        assert random_dynamics(m, n, seed).max_horizon == RANDOM_DYNAMICS_MAX_HORIZON
    W = displacement_reach(random_dynamics(4, 4).dynamics, 1.0, RANDOM_DYNAMICS_MAX_HORIZON)
    assert W is not None and W[RANDOM_DYNAMICS_MAX_HORIZON, 0] >= 122.0


def _dense() -> tuple:
    p = random_dynamics(1, 34)  # A has 1,090 nonzeros: CON-PLAN's LPs are dear
    a = abstract(p)
    return p, a


def test_a_dense_plan_lp_is_solved_by_the_interior_point_method_and_validated() -> None:
    p, a = _dense()
    r = solve(p, "lazy-smt", Budget(seconds=60))
    assert r.status is ReachStatus.FOUND and r.regions is not None  # (solve validates)
    cp = ConPlan(p, a, counterexample="trivial", generalize=True)
    assert cp.dear
    out = cp.check(r.regions)
    assert isinstance(out, Feasible)
    assert cp.slot.highs.getInfo().ipm_iteration_count > 0  # the cold plan LP went to the IPM
    assert cp.residual(out.trajectory) <= 1e-6
    assert oracle_lp(p, r.regions, abstraction=a).feasible  # the simplex oracle agrees


def test_an_expendable_refuted_plan_keeps_the_whole_plan_as_its_conflict() -> None:
    """A plan far too fast for the robot: the simplex oracle refutes it; the IPM's
    refutation without a ray gives the whole plan (start- and goal-anchored), the other
    path the Farkas support, smaller."""
    p, a = _dense()
    r = plan_lazy(p)
    assert r.regions is not None
    route = [x for i, x in enumerate(r.regions) if i == 0 or x != r.regions[i - 1]]
    fast = tuple(x for x in route for _ in range(2))  # two steps per region
    assert not oracle_lp(p, fast, abstraction=a).feasible
    cp = ConPlan(p, a, counterexample="trivial", generalize=True)
    cp.expendable = True
    whole = cp.check(fast)
    assert isinstance(whole, Conflict)
    assert whole.literals == tuple(sorted(enumerate(fast))) and whole.anchored_start and whole.anchored_goal
    assert cp.slot.highs.getInfo().ipm_iteration_count > 0
    cp = ConPlan(p, a, counterexample="trivial", generalize=True)
    shrunk = cp.check(fast)
    assert isinstance(shrunk, Conflict) and set(shrunk.literals) < set(whole.literals)


class _Recorder(SetTheory):
    def __init__(self, feasible) -> None:
        super().__init__(feasible)
        self.expendable = False
        self.seen: list[tuple[int, bool]] = []

    def check(self, regions):
        self.seen.append((len(regions) - 1, self.expendable))
        return super().check(regions)


def test_the_loop_marks_the_plans_whose_failure_defers_their_window() -> None:
    """defer_after=1: the first plan of window 2..4 is expendable (its window is deferred
    if it fails), the plans of the last window are not."""
    g = RegionGraph(3, ((1,), (0, 2), (1,)), (0,), (2,))
    target = (0, 0, 0, 0, 1, 1, 2)
    theory = _Recorder({target})
    out = lazy_loop(DisPlan(g), theory, [(2, 4), (5, 6)], Budget().clock(), {"sat": 0.0, "lp": 0.0}, defer_after=1)
    assert out.status is ReachStatus.FOUND and out.regions == target
    assert theory.seen[0][0] <= 4 and theory.seen[0][1] is True
    assert all(not e for N, e in theory.seen[1:] if N >= 5) and any(N >= 5 for N, _ in theory.seen)
    assert np.all([isinstance(e, bool) for _, e in theory.seen])


def test_a_random_robot_in_the_empty_maze_is_solved() -> None:
    """n_passages = 0: one region holds start and goal, and the separator chain is the
    leg start -> goal, which has no leg LP (it crashed the chain refinement)."""
    r = solve(random_dynamics(0, 4), "lazy-smt", Budget(seconds=30))
    assert r.status is ReachStatus.FOUND
