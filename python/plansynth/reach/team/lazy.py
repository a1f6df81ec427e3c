"""The joint lazy SMT planner for teams: the lazy loop of Shoukry et al. (CDC 2016,
Algorithm 1; :func:`~plansynth.reach.lazy.loop.lazy_loop`) over the joint DIS-PLAN
(:mod:`plansynth.reach.team.displan`: a region sequence per robot, a side per engaged
pair step, the SMC encoding of CDC 2017, Section IV) and the joint CON-PLAN
(:mod:`plansynth.reach.team.conplan`: one LP per component of interacting robots, its
counterexamples naming the robots, pairs and steps involved, and the engagement of
pair steps a trajectory found breaks).

::

    setup <- per robot: decomposition, region graph, time windows, LP data     (setup)
    for L = max of the robots' horizon bounds .. max_horizon:
        loop:
            plan <- DIS-PLAN(L)          (SAT; UNSAT -> L refuted)
            CON-PLAN(plan) -> team trajectory: done
                           -> counterexamples / engagements: learned, loop

**Horizons.** ``horizon_search="linear"`` refutes every horizon before trying the next,
so the horizon found is the smallest of the encoding. ``"defer"`` (the default) sets a
horizon aside after ``defer_after`` refuted plans and comes back to it only when no
later horizon yields a plan (the lazy loop's deferred windows); the answer then says
whether its horizon is minimal.

**What an answer claims.** ``found``: a team trajectory, which the independent team
validator checks (:func:`~plansynth.reach.team.solve.solve_team`). ``infeasible``: every
horizon up to ``max_horizon`` refuted *relative to the encoding*: each robot's plans are
segment-safe plans through its decomposition (one region per step), each pair keeps one
side of its forbidden polygon during each step (switching sides only at a sample both
allow), a disc robot's zone is its circumscribed 16-gon; every clause behind it comes
from a checked Farkas certificate. Some trajectories of the problem are not plans of the
encoding (a step that crosses two regions, a pair that cuts a corner of its zone
within a step), so ``infeasible`` is a claim about the encoding, and the result says so
(``counters["infeasible_relative_to"] = "encoding"``); the joint MILP
(:mod:`plansynth.reach.team.milp`) decides the same encoding, and the property tests
compare the two. Without a certificate for some clause the answer is ``unknown``.

**Under disturbances** (a robot with ``disturbance``) the loop plans the team tightened by
the robots' tubes (:mod:`plansynth.reach.team.robust`): the same DIS-PLAN, the
CON-PLAN's bounds and sides tightened step by step, every counterexample learned at
later placements only (the margins grow with time), and ``infeasible`` relative to the
feedback designs as well as the encoding.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict
from typing import Any

import numpy as np

from plansynth.budget import Budget, BudgetExhausted
from plansynth.reach.lazy.loop import LoopOutcome, lazy_loop
from plansynth.reach.result import ReachStatus
from plansynth.reach.team.conplan import TeamConPlan
from plansynth.reach.team.displan import RobotMission, TeamDisPlan
from plansynth.reach.team.options import TeamLazyOptions
from plansynth.reach.team.plans import Engage
from plansynth.reach.team.problem import TeamProblem
from plansynth.reach.team.result import TeamResult
from plansynth.reach.team.robust import is_disturbed, tightened_team
from plansynth.reach.team.setup import TeamSetup, prepare
from plansynth.reach.trajectory import Trajectory

__all__ = ["plan_team_lazy", "split_trajectory", "ENCODING", "SEEDED_DEFER_AFTER"]

#: with an incumbent, a horizon below it is set aside after this many refuted plans
SEEDED_DEFER_AFTER = 3

#: what an ``infeasible`` of the team planners is relative to
ENCODING = (
    "segment-safe plans through each robot's decomposition, each pair and robot-obstacle couple keeping one "
    "side of its forbidden polygon during each step"
)


def split_trajectory(problem: TeamProblem, joint: Trajectory) -> tuple[Trajectory, ...]:
    """Each robot's trajectory out of the joint one (states and inputs side by side)."""
    out = []
    xs = us = 0
    for r in problem.robots:
        n, m = r.dynamics.n_states, r.dynamics.n_inputs
        out.append(Trajectory(states=joint.states[:, xs : xs + n], inputs=joint.inputs[:, us : us + m]))
        xs, us = xs + n, us + m
    return tuple(out)


def _missions(setup: TeamSetup) -> list[RobotMission | None]:
    from plansynth.reach.ltl import nnf, parse

    out: list[RobotMission | None] = []
    for r, s in enumerate(setup.robots):
        mission = setup.problem.robots[r].mission
        out.append(None if mission is None else RobotMission(nnf(parse(mission)), s.labels_of))
    return out


def _transit_layers(setup: TeamSetup, clock: Any) -> list[Any]:
    """Each robot's single-robot transit layer over its own CON-PLAN
    (:class:`~plansynth.reach.lazy.transit.TransitCheck`, segment-safe)."""
    from plansynth.reach.lazy.conplan import ConPlan
    from plansynth.reach.lazy.transit import TransitCheck

    return [TransitCheck(ConPlan(s.planning, s.abstraction, clock=clock), s.abstraction) for s in setup.robots]


def _engage_seed(setup: TeamSetup, displan: TeamDisPlan, seed: TeamResult) -> None:
    """At the seed's horizon, DIS-PLAN's phases are the seed's sides (every pair step) and
    region sequences, and the pair steps where the seed's robots come within the size
    of their forbidden polygon are engaged: the seed is a plan of the encoding, so
    DIS-PLAN proposes it first there."""
    problem = setup.problem
    H = seed.horizon
    pos = [problem.robot_problems[r].position_of(t.states) for r, t in enumerate(seed.trajectories)]
    pairs = []
    hints = displan.horizon_hints.setdefault(H, {})
    for (i, j), f in setup.pair_facets.items():
        M = f.margins(pos[i] - pos[j])
        S = np.minimum(M[:-1], M[1:])
        reach = float(np.max(f.b))
        for t in range(H):
            k = int(S[t].argmax())
            hints[("side", i, j, t)] = k
            if S[t, k] < reach:
                pairs.append((i, j, t))
    displan.learn(Engage(pairs=tuple(pairs)))
    guide = displan.guide
    regions = seed.regions

    def seeded_guide(r: int, L: int) -> Any:
        if L == H:
            return regions[r]
        return None if guide is None else guide(r, L)

    displan.guide = seeded_guide


def plan_team_lazy(
    problem: TeamProblem,
    budget: Budget = Budget(),
    options: TeamLazyOptions | None = None,
    progress: Any = None,
    *,
    horizons: range | None = None,
    seed: TeamResult | None = None,
    setup: TeamSetup | None = None,
) -> TeamResult:
    """Plan the team (see the module docstring); the answer is not validated here
    (:func:`plansynth.reach.solve` validates). ``horizons``: try only these (tests; an
    ``infeasible`` then covers only them). ``seed``: an incumbent plan of the encoding
    (:mod:`plansynth.reach.team.seeding`): the horizons below it are tried first, each
    set aside after :data:`SEEDED_DEFER_AFTER` refuted plans, then its own, where
    DIS-PLAN proposes it first. ``setup``: the problem's :func:`~plansynth.reach.team.setup.prepare`
    for this ``max_horizon`` when the caller has it already (the seed's: the same robots,
    decompositions and bounds); another is not used."""
    options = TeamLazyOptions() if options is None else options
    clock = budget.clock()
    t_start = time.perf_counter()
    L_max = problem.max_horizon if options.max_horizon is None else options.max_horizon
    timings: dict[str, float] = {"sat": 0.0, "lp": 0.0}
    counters: dict[str, Any] = {"robots": problem.n_robots}
    record = {**asdict(options), "max_horizon": L_max, "budget_seconds": budget.seconds}

    def result(out: LoopOutcome, trajectories: tuple[Trajectory, ...] | None = None) -> TeamResult:
        timings["total"] = time.perf_counter() - t_start
        return TeamResult(
            status=out.status,
            solver="lazy-smt-team",
            seconds=timings["total"],
            trajectories=trajectories,
            regions=None if out.regions is None else tuple(out.regions.regions),
            horizon=out.horizon,
            counters=counters,
            timings=timings,
            options=record,
            message=out.message,
            guarantee="segments",
            names=tuple(r.name for r in problem.robots),
        )

    if is_disturbed(problem):  # plan the team tightened by its robots' tubes (plansynth.reach.team.robust)
        tight = tightened_team(problem)
        if tight.status is not None:
            status = ReachStatus.INFEASIBLE if tight.status == "infeasible" else ReachStatus.UNKNOWN
            return result(LoopOutcome(status, None, tight.reason))
        L_max = min(L_max, tight.max_horizon)
        record["max_horizon"] = L_max
    if setup is None or not setup.serves(problem, L_max):
        try:
            with clock.phase("the robots' decompositions and bounds"):
                setup = prepare(problem, L_max, clock)
        except BudgetExhausted as exc:
            return result(LoopOutcome(ReachStatus.UNKNOWN, None, str(exc)))
    timings["abstraction"] = setup.seconds
    counters.update(setup.counters)
    first = setup.first
    counters["first_horizon"] = None if math.isinf(first) else int(first)
    if horizons is None:
        if first > L_max:
            counters["infeasible_relative_to"] = "encoding"
            why = (
                "a robot's goal is not reachable through its regions"
                if math.isinf(first)
                else (f"a robot alone needs at least {int(first)} steps (its time windows through its regions)")
            )
            return result(LoopOutcome(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: {why}"))
        horizons = range(int(first), L_max + 1)
    displan = TeamDisPlan(
        [s.graph for s in setup.robots],
        windows=[(s.earliest, s.to_go) for s in setup.robots],
        missions=_missions(setup),
        pair_sides={k: (f.n_sides, f.opposite) for k, f in setup.pair_facets.items()},
        obstacle_sides={k: (f.n_sides, f.opposite) for k, f in setup.obstacle_facets.items()},
        guide=setup.guide if options.guided else None,
    )
    conplan = TeamConPlan(
        problem,
        [s.model for s in setup.robots],
        setup.pair_facets,
        setup.obstacle_facets,
        clock,
        hints=displan.side_hints,
        objective=options.objective,
        transit=_transit_layers(setup, clock) if options.transit else None,
        pair_margins=setup.pair_margins,
        obstacle_margins=setup.obstacle_margins,
    )
    if seed is not None and seed.horizon is not None and first <= seed.horizon <= L_max and not setup.tightened:
        # an incumbent: the horizons below it first, then its own
        horizons = [L for L in horizons if L < seed.horizon] + [seed.horizon]
        _engage_seed(setup, displan, seed)
    windows = [(L, L) for L in horizons]
    defer = options.defer_after if options.horizon_search == "defer" else None
    if seed is not None and seed.horizon in horizons and defer is not None:  # the horizons below it get less
        defer = min(defer, SEEDED_DEFER_AFTER)
    with clock.phase("the joint lazy SMT loop"):
        out = lazy_loop(displan, conplan, windows, clock, timings, progress, None, defer)
    st = conplan.stats
    counters.update(
        iterations=clock.iterations,
        sat_calls=displan.sat_calls,
        clauses=displan.clauses,
        conflicts=len(displan.conflicts),
        engaged_pair_steps=len(displan.engaged_pairs),
        engaged_obstacle_steps=len(displan.engaged_obstacles),
        lp_calls=st.lp_calls,
        lp_infeasible=st.infeasible,
        lp_cached=st.cached,
        certified=st.certified,
        uncertified=st.uncertified,
        engagements=st.engagements,
        transit_conflicts=st.transit,
        largest_component=st.largest_component,
        conflict_literals_max=max(st.conflict_sizes, default=0),
        conflict_literals_mean=(sum(st.conflict_sizes) / len(st.conflict_sizes)) if st.conflict_sizes else 0.0,
        minimal=out.minimal,
    )
    timings["highs"] = st.seconds
    displan.delete()
    if out.status is ReachStatus.FOUND:
        counters["minimal_relative_to"] = "encoding"
        return result(out, split_trajectory(problem, out.trajectory))
    if out.status is ReachStatus.INFEASIBLE:
        if st.uncertified:
            return result(
                LoopOutcome(
                    ReachStatus.UNKNOWN,
                    out.horizon,
                    f"every horizon up to {out.horizon} refuted, but {st.uncertified} conflicts had no checked "
                    "certificate: not a proof",
                )
            )
        counters["infeasible_relative_to"] = "encoding"
        return result(
            LoopOutcome(
                ReachStatus.INFEASIBLE,
                out.horizon,
                f"infeasible up to horizon {out.horizon} relative to the encoding ({ENCODING})",
            )
        )
    return result(out)
