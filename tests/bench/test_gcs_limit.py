"""The bench's gcs runs, the limit beside every time (one cold LP over the final region
sequence) and the random-dynamics family."""

from __future__ import annotations

import numpy as np

from plansynth.bench.execute import execute
from plansynth.bench.families import reach_family
from plansynth.bench.tasks import make_tasks
from plansynth.budget import Budget
from plansynth.reach.families import maze, random_dynamics
from plansynth.reach.oracle import oracle_lp
from plansynth.reach.result import ReachStatus
from plansynth.reach.solve import solve


def test_the_oracle_lp_is_feasible_on_the_final_regions_and_not_on_a_wrong_sequence():
    r = solve(maze(1), "lazy-smt", Budget(seconds=60))
    lim = oracle_lp(maze(1), r.regions)
    assert lim.feasible and lim.horizon == r.horizon
    assert 0 < lim.solve_seconds <= lim.seconds and lim.build_seconds > 0
    stuck = [r.regions[0]] * len(r.regions)  # never leaves the start region: cannot reach the goal
    assert not oracle_lp(maze(1), stuck).feasible
    assert oracle_lp(maze(1), r.regions, seconds=1e-9) is None  # out of time: no limit, not a wrong one


def test_an_lp_the_oracle_cannot_solve_records_no_limit_and_keeps_the_run(monkeypatch):
    """HiGHS failing on the oracle's LP is a measurement that did not happen, not a
    crash of the run it measures (which is solved and validated already)."""
    from plansynth.reach.lazy.conplan import ConPlan
    from plansynth.reach.lazy.conplan.runs import LpFailure

    r = solve(maze(1), "lazy-smt", Budget(seconds=60))

    class Failing(ConPlan):  # the oracle's own CON-PLAN only: the planner's is the real one
        def _run_slot(self, *args, **kwargs):
            raise LpFailure("HiGHS could not solve a CON-PLAN LP (plan): Solve error")

    monkeypatch.setattr("plansynth.reach.oracle.ConPlan", Failing)
    assert oracle_lp(maze(1), r.regions) is None
    (task,) = make_tasks(reach_family("maze", [1]), ["lazy-smt"], timeout=60)
    out = execute(task)
    assert out["status"] == "solved" and out["attributes"]["oracle_lp"] is None


def test_the_oracle_lp_of_a_long_chain_is_solved_as_conplan_solves_it():
    """Split per axis and interior-point first (from 30 states), with no iteration cap:
    an answer, not a stopped simplex."""
    p = maze(1, order=15)
    r = solve(p, "lazy-smt", Budget(seconds=60))
    lim = oracle_lp(p, r.regions)
    assert lim.feasible and lim.horizon == r.horizon
    assert not oracle_lp(p, [r.regions[0]] * len(r.regions)).feasible


def test_bench_records_the_limit_and_runs_gcs():
    tasks = make_tasks(reach_family("maze", [1]), ["lazy-smt", "gcs"], timeout=120)
    lazy, gcs = (execute(t) for t in tasks)
    assert lazy["status"] == "solved" and lazy["attributes"]["oracle_lp"]["feasible"] is True
    assert 0 < lazy["attributes"]["oracle_lp"]["seconds"] < lazy["time"]
    assert lazy["attributes"]["duration"] == lazy["horizon"] * 0.5
    assert gcs["status"] == "solved" and gcs["valid"] == 1, gcs["message"]
    assert gcs["attributes"]["guarantee"] == "curve" and gcs["attributes"]["oracle_lp"] is None
    assert gcs["solver_version"].startswith("drake")


def test_random_dynamics_is_seeded_controllable_and_bounded():
    from plansynth.reach.families.random_robots import _controllable

    a, b = random_dynamics(2, 10, seed=5), random_dynamics(2, 10, seed=5)
    assert a == b and a != random_dynamics(2, 10, seed=6)
    A, B = a.dynamics.A, a.dynamics.B
    assert A.shape == (10, 10) and B.shape == (10, 2) and _controllable(A, B)
    rho = np.sort(np.abs(np.linalg.eigvals(A)))
    assert abs(rho[-1] - 1.0) < 1e-9 and abs(rho[-2] - 1.0) < 1e-9 and rho[-3] < 0.91 and rho[0] > 0.6
    assert a.state_bounds is not None and a.starts_at_rest and a.obstacles == maze(2).obstacles
    # an uncontrollable pair is recognised
    assert not _controllable(np.eye(3), np.array([[1.0], [0.0], [0.0]]))


def test_random_dynamics_solves_with_lazy_smt_at_small_n():
    p = random_dynamics(1, 4, seed=0)
    r = solve(p, "lazy-smt", Budget(seconds=120))
    assert r.status is ReachStatus.FOUND and r.validated, r.message


def test_random_dynamics_family_instances():
    insts = reach_family("random-dynamics", [1, 4], states=[4, 50])
    assert [i.name for i in insts] == ["rdyn-1-n4-s0", "rdyn-1-n50-s0", "rdyn-4-n4-s0", "rdyn-4-n50-s0"]
    assert insts[1].build().dynamics.n_states == 50
