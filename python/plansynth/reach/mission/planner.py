"""The lazy SMT planner for LTL missions (Shoukry et al., CDC 2016, Algorithm 1 with
DIS-PLAN replaced by the BMC encoding of the mission): the planner ``lazy-smt`` on a
problem with a mission.

::

    abstraction <- convex decomposition refined by the labels          (labels.py)
    no word over the labels' geometry satisfies the mission -> infeasible (proof.py)
    L0 <- the product graph's lower bound on the horizon                  (horizon.py)
    for L = L0 .. max_horizon:                   (one horizon at a time: L is minimal)
        loop:                                    (the one lazy loop: lazy/loop.py)
            r_0..r_L, loop <- DIS-PLAN(L)          (bmc.py; UNSAT -> next L)
            the mission's theory (theory.py): transit times, the loop alone, CON-PLAN,
                the LP with the loop closure or the rest at x_L -> trajectory: done
                                                            -> counterexamples, loop

The loop is :func:`~plansynth.reach.lazy.loop.lazy_loop`, the one the reach-avoid
planner runs: DIS-PLAN is :class:`~plansynth.reach.mission.bmc.MissionDisPlan` and the
theory :class:`~plansynth.reach.mission.theory.MissionTheory`. Every plan goes through
the validator and the independent mission checker (:mod:`plansynth.reach.mission.check`)
in :func:`plansynth.reach.solve` before it is reported.

**The reading** is the problem's (``problem.reading``): in the **segment** reading
CON-PLAN keeps every segment in its region (segment safety), so a region's letter holds
along the segment, and DIS-PLAN moves to adjacent regions; in the **sample** reading
CON-PLAN constrains the samples only and DIS-PLAN's steps go between any two regions one
step can connect (:func:`~plansynth.reach.lazy.bounds.step_adjacency`, as the reach-avoid
planner's samples mode). A finite plan ends at rest or freely (``problem.end``); the
labels are read at their margins (:mod:`plansynth.reach.mission.labels`), the obstacles
at theirs, a sized robot in its configuration space.

**What ``infeasible`` means** (as in :mod:`plansynth.reach.lazy.claims`). In the segment
reading DIS-PLAN moves one region per step, so refuting every horizon proves only that
no plan *through the label-refined decomposition* exists; a real trajectory may cross
several regions in one step. The answer is then ``infeasible`` only when
:func:`~plansynth.reach.mission.proof.label_proof` holds: no word over the letters the
labels' geometry allows satisfies the mission, so no trajectory does at any horizon
(``counters["label_proof"]``). When the loop refutes every horizon without it, the answer
is ``unknown`` and says "not a proof" (``counters["abstraction_refuted"]``), and the
shortest horizon found is minimal through the decomposition only
(``counters["minimal_relative_to"]``). In the sample reading, over regions that cover the
free space, the search is exact: every trajectory's samples lie in regions one step
apart, each read as the checker reads its sample, so a refuted horizon is refuted for the
problem and the shortest horizon found is minimal (``minimal_relative_to: problem``).
With ``exact_segments`` in the segment reading (convex labels), DIS-PLAN and the theory
are those of :mod:`plansynth.reach.mission.exact` (a step may cross several regions and
labels, its letters read along its segment): refutations are then about the problem in
the segment reading as well, unless a plan was given up without a proof
(``counters["segment_undecided"]``; the claims then say so). ``exact_segments="auto"``
(the default) plans through the decomposition first and continues with exact
transitions, in the budget left, only when that refutes every horizon (an answer that
would be "not a proof"), as the reach-avoid planner's window search does
(:mod:`plansynth.reach.lazy.exactmode`); ``counters["transitions"]`` and
``counters["exact_segments"]`` say which relation ran and why (with a label that is not
convex: the decomposition's, and the claims stay relative to it).

>>> from plansynth.reach.mission.families import mission_problem
>>> r = plan_mission(mission_problem("maze-1", "avoid-until"))
>>> r.status.value, r.horizon, r.mission["semantics"]
('found', 30, 'finite')
"""

from __future__ import annotations

import time
from dataclasses import asdict, replace
from typing import Any

from plansynth.budget import Budget, BudgetExhausted, Clock
from plansynth.errors import InvalidOption
from plansynth.reach.lazy.bounds import segment_adjacency, step_adjacency, time_windows, touching
from plansynth.reach.lazy.claims import EXACT_SAMPLES, EXACT_SEGMENTS, UNDECIDED, uncertified
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.displan import RegionGraph
from plansynth.reach.lazy.exactmode import REGIONS, SEGMENTS, STEPS, searched
from plansynth.reach.lazy.loop import LoopOutcome, ProgressFn, TheoryChecker, lazy_loop
from plansynth.reach.lazy.segtheory import SegmentTheory
from plansynth.reach.mission.bmc import MissionDisPlan
from plansynth.reach.mission.exact import ExactMissionDisPlan, MissionSegmentTheory, avoided_shapes, mission_exact_mode
from plansynth.reach.mission.horizon import timed_horizon_bound
from plansynth.reach.mission.labels import LabelledAbstraction, label_abstraction, planning_problem
from plansynth.reach.mission.looplp import LoopLP
from plansynth.reach.mission.ltl import parse
from plansynth.reach.mission.options import MissionOptions
from plansynth.reach.mission.plans import MissionPlan
from plansynth.reach.mission.proof import NOT_A_PROOF, timed_label_proof
from plansynth.reach.mission.theory import MissionTheory, MissionTransit
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus

__all__ = ["plan_mission", "MissionOptions"]


def plan_mission(
    problem: ReachProblem,
    budget: Budget = Budget(),
    options: MissionOptions | None = None,
    progress: ProgressFn | None = None,
    *,
    labelled: LabelledAbstraction | None = None,
) -> ReachResult:
    """The lazy loop for the problem's mission within ``budget`` (not yet validated:
    :func:`plansynth.reach.solve` does that, with the mission checker). ``options``
    (:class:`~plansynth.reach.mission.options.MissionOptions`, whose fields say what each
    does): ``semantics`` the plans looked for, ``lower_bound`` each region's earliest step
    as unit clauses, ``transit`` the transit layer in front of CON-PLAN (as
    :class:`~plansynth.reach.mission.theory.MissionTransit`), ``wait_shifts``
    start-anchored conflicts shifted earlier, ``loop_first`` a lasso's loop alone
    checked first, ``horizon_bound`` the horizons from the proved lower bound of
    :func:`~plansynth.reach.mission.horizon.horizon_lower_bound` (no DIS-PLAN plan exists
    below it), not from 0. ``labelled``: the label-refined decomposition, computed before."""
    opts = MissionOptions() if options is None else options
    if problem.mission is None:
        raise InvalidOption("lazy-smt", "options", "mission options for a problem without a mission")
    return searched(
        mission_exact_mode(problem, opts),
        budget,
        lambda budget, clock, crossing, la, _: _plan(problem, budget, clock, opts, progress, la, crossing=crossing),
        labelled,
    )


def _plan(
    problem: ReachProblem,
    budget: Budget,
    clock: Clock,
    opts: MissionOptions,
    progress: ProgressFn | None,
    labelled: LabelledAbstraction | None,
    *,
    crossing: bool,
) -> tuple[ReachResult, LabelledAbstraction | None]:
    """One search of :func:`plan_mission` on ``clock``, with exact segment transitions
    (``crossing``, mission/exact.py: a step may cross several regions and labels) or
    without; also the label-refined decomposition (None when the budget ran out first)."""
    t_start = time.perf_counter()
    L_max = problem.max_horizon if opts.max_horizon is None else int(opts.max_horizon)
    timings = {"abstraction": 0.0, "bounds": 0.0, "sat": 0.0, "lp": 0.0}
    counters: dict[str, Any] = {}
    segment = problem.reading == "segment"
    formula = parse(problem.mission)
    counters["transitions"] = SEGMENTS if crossing else REGIONS if segment else STEPS
    try:
        setup = mission_setup(
            problem, clock, timings, L_max, labelled=labelled, lower_bound=opts.lower_bound, crossing=crossing
        )
    except BudgetExhausted as exc:  # in the label refinement or the bounds
        timings["total"] = time.perf_counter() - t_start
        out = LoopOutcome(ReachStatus.UNKNOWN, None, str(exc))
        return _result(problem, opts, L_max, budget, timings, counters, out), labelled
    pp, labelled, graph, earliest = setup
    ab = labelled.abstraction
    encoding = dict(
        semantics=opts.semantics,
        earliest=earliest,
        waits_at_start=opts.wait_shifts and problem.starts_at_rest,
        negs_of=labelled.negs_of,
        end=problem.end,
    )
    conplan = ConPlan(  # (exact transitions: rows of samples only, for the transit layer's legs)
        pp,
        ab,
        segment_safe=segment and not crossing,
        counterexample="trivial",
        generalize=True,
        minimize=True,
        clock=clock,
    )
    loop_lp = LoopLP(pp, ab, segment_safe=segment)
    seg_theory: SegmentTheory | None = None
    theory: TheoryChecker
    if crossing:
        near = touching(ab)
        displan: MissionDisPlan = ExactMissionDisPlan(
            graph,
            labelled.labels_of,
            formula,
            relation=lambda scale: segment_adjacency(pp, ab, scale, near=near),
            near=near,
            **encoding,
        )
        # the transit layer over CON-PLAN without segment rows: its legs hold for every trajectory
        transit = MissionTransit(conplan, ab) if opts.transit else None
        seg_theory = SegmentTheory(pp, ab, transit=transit, clock=clock, labels=avoided_shapes(problem))
        theory = MissionSegmentTheory(seg_theory, end=problem.end)
    else:
        displan = MissionDisPlan(graph, labelled.labels_of, formula, **encoding)
        theory = MissionTheory(
            MissionTransit(conplan, ab) if opts.transit else conplan,
            loop_lp,
            clock,
            loop_first=opts.loop_first,
            end=problem.end,
        )
    counters.update(
        regions=graph.n_regions,
        edges=ab.n_edges,
        step_edges=sum(map(len, graph.adjacency)) // 2,
        exact_abstraction=ab.exact,
    )
    # are the loop's refutations proofs for the problem? samples (steps between any regions
    # one step connects), or segments with exact transitions; regions covering the free space
    exact = (not segment or crossing) and ab.exact

    # what one step can reach: a path through the free space in the segment reading (regions
    # whose closures meet), a step's displacement in the sample reading (the graph's pairs)
    steps = touching(ab) if segment else graph.adjacency
    proved, why = timed_label_proof(problem, labelled, timings, counters, clock, steps=steps)
    if proved:
        out = LoopOutcome(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max} (and beyond): {why}")
    elif not ab.start_regions:
        counters["abstraction_refuted"] = L_max
        out = LoopOutcome(ReachStatus.UNKNOWN, L_max, f"the start lies in no region; {NOT_A_PROOF}")
    else:
        L0 = (
            timed_horizon_bound(graph, labelled, formula, earliest, L_max, timings, counters, clock, end=problem.end)
            if opts.horizon_bound
            else 0
        )
        if L0 > L_max:
            out = LoopOutcome(
                ReachStatus.INFEASIBLE,
                L_max,
                f"no plan through the label-refined abstraction at any horizon up to {L_max} (product graph)",
            )
        else:
            with clock.phase("the lazy SMT loop"):
                out = lazy_loop(displan, theory, range(L0, L_max + 1), clock, timings, progress)
            if out.status is ReachStatus.INFEASIBLE:
                out = replace(
                    out, message=f"every horizon up to {L_max} refuted for plans through the label-refined abstraction"
                )
        if out.status is ReachStatus.FOUND:
            plan = out.regions
            kind = "a finite plan" if plan.loop_start is None else "a lasso"
            loop = "" if plan.loop_start is None else f" (loop from step {plan.loop_start})"
            out = replace(out, message=f"found {kind} at horizon {out.horizon}{loop}", minimal=True)
        elif out.status is ReachStatus.INFEASIBLE and exact:
            why = EXACT_SEGMENTS if crossing else EXACT_SAMPLES
            out = replace(out, message=f"infeasible up to horizon {L_max}: every horizon refuted ({why})")
        elif out.status is ReachStatus.INFEASIBLE:
            # refuted through the label-refined decomposition only (one region per step):
            # a real trajectory may cross several regions in one step, so this is no
            # proof (as in the reach-avoid planner); label_proof above is the proof
            counters["abstraction_refuted"] = L_max
            out = LoopOutcome(ReachStatus.UNKNOWN, L_max, f"{out.message}; {NOT_A_PROOF} ({why})")

    if seg_theory is not None and seg_theory.undecided:  # plans given up without a proof: no claim
        out = uncertified(out, seg_theory.undecided, None, why=UNDECIDED)
        exact = False
    plan = out.regions if out.status is ReachStatus.FOUND else None
    st = conplan.stats
    counters.update(
        iterations=clock.iterations,
        sat_calls=displan.sat_calls,
        clauses=displan.clauses,
        loop_clauses=displan.loop_clauses,
        lp_calls=st.lp_calls + loop_lp.lp_calls,
        loop_lp_calls=loop_lp.lp_calls,
        loop_lp_memo_hits=loop_lp.memo_hits,
        loop_lp_rest_answers=loop_lp.rest_answers,
        horizon=out.horizon,
        minimal=out.status is ReachStatus.FOUND and out.minimal is not False,
        # in the segment reading DIS-PLAN moves one region per step, and a real step may
        # cross several: the shortest horizon is the shortest through the label-refined
        # decomposition only; the sample reading's search is exact
        minimal_relative_to=(
            ("problem" if exact else "decomposition") if out.status is ReachStatus.FOUND and out.minimal else None
        ),
    )
    if isinstance(theory, MissionTheory) and theory.wrap_conflicts:
        counters["wrap_conflicts"] = theory.wrap_conflicts
    if seg_theory is not None:
        assert isinstance(displan, ExactMissionDisPlan)
        counters.update(
            lp_calls=counters["lp_calls"] + seg_theory.lp_calls,
            segment_points=displan.points.most,
            segment_refinements=displan.refinements,
            segment_separated=seg_theory.separated,
            segment_undecided=seg_theory.undecided,
        )
        timings["highs"] = timings.get("highs", 0.0) + seg_theory.lp.seconds
    timings["highs"] = st.seconds + loop_lp.seconds
    timings["encoding"] = displan.encode_seconds  # part of "sat"
    timings["loop_lp_highs"] = loop_lp.seconds  # part of "highs"
    timings["total"] = time.perf_counter() - t_start
    displan.delete()
    return _result(problem, opts, L_max, budget, timings, counters, out, plan), labelled


def mission_setup(
    problem: ReachProblem,
    clock: Clock,
    timings: dict,
    max_horizon: int,
    *,
    labelled: LabelledAbstraction | None = None,
    lower_bound: bool = True,
    steps: bool = False,
    crossing: bool = False,
) -> tuple[ReachProblem, LabelledAbstraction, RegionGraph, list | None]:
    """What both mission planners plan over, each step within the budget (raises
    :class:`~plansynth.budget.BudgetExhausted`): the planning problem, the label-refined
    decomposition, its region graph (in the sample reading, or with ``steps``: every pair
    of regions one step can connect; with ``crossing``: every pair one segment through
    the free space can connect) and each region's earliest step (``lower_bound``)."""
    pp = planning_problem(problem)
    if labelled is None:
        t0 = time.perf_counter()
        try:
            with clock.phase("splitting the regions along the labels"):
                labelled = label_abstraction(problem)
        finally:
            timings["abstraction"] = time.perf_counter() - t0
    ab = labelled.abstraction
    graph = RegionGraph.from_abstraction(ab)
    t0 = time.perf_counter()
    try:
        with clock.phase("the one-step region pairs and time windows"):
            if crossing:  # every pair of regions one segment through the free space can connect
                graph = replace(graph, adjacency=segment_adjacency(pp, ab))
            elif steps or problem.reading == "sample":  # every pair of regions one step can connect
                graph = replace(graph, adjacency=step_adjacency(pp, ab))
            earliest = time_windows(pp, ab, max_horizon, adjacency=graph.adjacency).earliest if lower_bound else None
    finally:
        timings["bounds"] = time.perf_counter() - t0
    return pp, labelled, graph, earliest


def mission_record(problem: ReachProblem, plan: MissionPlan | None) -> dict[str, Any]:
    """The result's ``mission`` record before the checker fills in its verdict."""
    return {
        "formula": problem.mission,
        "semantics": None if plan is None else plan.semantics,
        "loop_start": None if plan is None else plan.loop_start,
        "reading": problem.reading,
        "end": problem.end,
        "margins": {n: problem.label_margin(n) for n in problem.mission_labels},
        "obstacle_margin": problem.obstacle_margin,
    }


def _result(
    problem: ReachProblem,
    opts: MissionOptions,
    L_max: int,
    budget: Budget,
    timings: dict,
    counters: dict,
    out: LoopOutcome,
    plan: MissionPlan | None = None,
) -> ReachResult:
    timings.setdefault("total", sum(v for k, v in timings.items() if k in ("abstraction", "bounds", "sat", "lp")))
    return ReachResult(
        status=out.status,
        solver="lazy-smt",
        seconds=timings["total"],
        trajectory=out.trajectory,
        regions=None if plan is None else plan.regions,
        horizon=out.horizon,
        counters=counters,
        timings=timings,
        options=_record(opts, L_max, budget),
        message=out.message,
        guarantee="segments" if problem.reading == "segment" else "samples",
        mission=mission_record(problem, plan),
    )


def _record(opts: MissionOptions, max_horizon: int, budget: Budget) -> dict[str, Any]:
    """The options as the result records them (``max_horizon`` resolved, the budget)."""
    return {
        **asdict(opts),
        "max_horizon": max_horizon,
        "budget": {"seconds": budget.seconds, "iterations": budget.iterations},
    }
