"""The lazy SMT planner for reach-avoid problems (Shoukry et al., CDC 2016, Algorithm 1):
the abstraction, the horizon bounds, DIS-PLAN and CON-PLAN set up around the one lazy
loop (:func:`~plansynth.reach.lazy.loop.lazy_loop`), and the claims of its answer.

::

    abstraction <- convex decomposition of the free space             (Section III)
    first horizon <- the horizon lower bounds (time windows per region)
    for L = first horizon .. max_horizon (in windows):
        loop:
            r_0..r_L <- DIS-PLAN(L)        (SAT; UNSAT -> next L)         (Section IV)
            CON-PLAN(r_0..r_L) -> trajectory: done                     (Section V)
                               -> counterexample: add its clause, loop

**The timed route** (``timed_route=True``, the default with the window and minimal
searches; beyond the paper): before DIS-PLAN is built, the shortest route through the
region graph, timed by an LP and repaired where CON-PLAN's slack LP finds it too tight
(:mod:`~plansynth.reach.lazy.timed`), is the first plan checked; realised, it is the
answer (the window search), or the plan the minimal search proves minimal from the
horizon bounds up. Only no horizon below it is refuted, so it is not claimed minimal.
When it gives up, the loop below runs as before. With the window search on an
abstraction of more than 200 regions its plan is then shortened (``shorten``;
:mod:`~plansynth.reach.lazy.shorten`, checked by the prism LP of
:mod:`~plansynth.reach.lazy.prismlp`), never claimed minimal either.

**Horizon search.** ``horizon_search="linear"`` is the paper's loop above: one horizon
at a time, so the trajectory found has the smallest horizon any region sequence
allows, and every shorter horizon is refuted on the way. That refutation is most of
the work (maze-4: horizons 122..140 cost ~1,700 LPs before 141 succeeds). The default,
``"window"`` (beyond the paper), asks DIS-PLAN for a plan that reaches the goal at
*some* horizon in a window lo..hi (windows grow geometrically by ``window_growth``
from the lower bound), which is monotone in hi: a window that admits a trajectory
usually yields one after a few counterexamples, and only windows without any are
refuted whole (``window_growth=None``, the default: 0.25, and 1.0 on an abstraction of
more than 200 regions, see :func:`~plansynth.reach.lazy.options.window_growth_for`).
The result's ``counters["minimal"]`` says whether the horizon found is proved minimal
(it is when it equals the window's lower end, and always under ``"linear"``); a plan
above a deferred window is :func:`~plansynth.reach.lazy.minimal.shortened`.
``"minimal"`` runs the windows and then
:func:`~plansynth.reach.lazy.minimal.prove_minimal`.

**Cheaper iterations** (beyond the paper, both on by default): the theory is CON-PLAN
behind :class:`~plansynth.reach.lazy.transit.TransitCheck`, which refutes plans with
impossible transit times between regions without a horizon-long LP; and DIS-PLAN's
decision phases follow :func:`~plansynth.reach.lazy.guide.reference_plan`, an evenly
timed route ending at the window's top (its first leg no faster than the transit layer
allows), so that the first plans proposed are plausible ones. When the robot starts at
rest, a start-anchored conflict also holds shifted earlier (``wait_shifts``): a
trajectory for the earlier claims, after waiting at the start, would realise the
conflict itself. On maze-4 with an order-25 chain these three make the loop find its
trajectory in the first feasible window with 4 iterations, not 46.

**Lower bound on the horizon** where the search starts (segment-safe: a bound for plans
through the abstraction, not for the problem; samples only, over the step relation: a
bound for the problem): the largest of the region-graph distance from a start region to
a goal region (BFS), the distance to the goal along each axis divided by the largest
displacement per step (one small LP per axis and direction), the first step at which
the displacement-box relaxation reaches the goal along the region graph
(:func:`~plansynth.reach.lazy.bounds.time_windows`, beyond the paper; it also gives
DIS-PLAN a time window per region), and the separator chains of
:func:`~plansynth.reach.lazy.bounds.separator_bounds` where they apply.

What the answer claims (``infeasible``, "minimal") and relative to what is
:mod:`plansynth.reach.lazy.claims`'s. The answer is ``unknown`` when the budget (time
or iterations, one iteration = one SAT call and its theory check) runs out.

>>> from plansynth.reach.families import maze
>>> r = plan_lazy(maze(1))
>>> r.status.value, r.horizon == len(r.regions) - 1, r.guarantee
('found', True, 'segments')
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import replace

from plansynth.budget import Budget, BudgetExhausted, Clock
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.lazy.axisreach import AxisReach
from plansynth.reach.lazy.bounds import physical_lower_bound, segment_adjacency, step_adjacency, touching
from plansynth.reach.lazy.bounds.segpairs import pair_boxes
from plansynth.reach.lazy.claims import (
    DECOMPOSITION_ONLY,
    EXACT_SAMPLES,
    EXACT_SEGMENTS,
    UNDECIDED,
    minimal_claim,
    not_a_proof,
    prove_claims,
    uncertified,
)
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.descent import Descent
from plansynth.reach.lazy.displan import DisPlan, RegionGraph
from plansynth.reach.lazy.exactmode import REGIONS, SEGMENTS, STEPS, exact_mode, searched
from plansynth.reach.lazy.guide import reference_plans, route
from plansynth.reach.lazy.horizon_bounds import (
    chain_bounds,
    count_bound,
    horizon_bounds,
    refuted_by_bounds,
    with_chains,
)
from plansynth.reach.lazy.loop import (
    DEAR_DEFER_AFTER,
    DEFER_AFTER,
    LoopOutcome,
    ProgressFn,
    TheoryChecker,
    horizon_windows,
    lazy_loop,
)
from plansynth.reach.lazy.minimal import prove_minimal, shortened
from plansynth.reach.lazy.options import LARGE_REGIONS, LazyOptions, window_growth_for
from plansynth.reach.lazy.prismlp import PrismLP
from plansynth.reach.lazy.segments import SegmentDisPlan
from plansynth.reach.lazy.segtheory import SegmentTheory
from plansynth.reach.lazy.shorten import MIN_SECONDS, shorten_plan
from plansynth.reach.lazy.timed import timed_route
from plansynth.reach.lazy.transit import START, TransitCheck
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus

__all__ = ["plan_lazy", "LazyOptions"]


@contextmanager
def _timed(clock: Clock, timings: dict[str, float], key: str, phase: str) -> Iterator[None]:
    """Run a block as the budget phase ``phase``, adding its seconds to ``timings[key]``
    (also when the budget runs out in it)."""
    t0 = time.perf_counter()
    try:
        with clock.phase(phase):
            yield
    finally:
        timings[key] = timings.get(key, 0.0) + time.perf_counter() - t0


def plan_lazy(
    problem: ReachProblem,
    budget: Budget = Budget(),
    options: LazyOptions | None = None,
    progress: ProgressFn | None = None,
    *,
    abstraction: Abstraction | None = None,
) -> ReachResult:
    """Algorithm 1 on ``problem`` within ``budget``; the trajectory is *not* yet
    validated here (:func:`plansynth.reach.solve` does that).

    ``options`` (:class:`~plansynth.reach.lazy.options.LazyOptions`, whose fields say
    what each option does; default: ours; ``LazyOptions.paper()``: the paper's loop).
    ``max_horizon`` overrides the problem's. ``counterexample`` ``"farkas"`` (the
    default, beyond the paper) is one feasibility LP over the whole plan whose Farkas
    certificate shrinks the trivial counterexample to the literals the proof needs
    (``trivial`` with ``generalize``; see :mod:`plansynth.reach.lazy.conplan`).
    ``progress(L, iterations)`` is called when a horizon (window: its top) starts.
    ``abstraction``: a decomposition computed before (else it is computed here, within
    the budget). ``prove`` (segment-safe; it turns the window search into ``minimal``):
    after the loop, try to prove its claims for the problem with the MILP relaxation of
    :mod:`plansynth.reach.lazy.relaxation` (:func:`~plansynth.reach.lazy.claims.prove_claims`).
    ``exact_segments`` (segment-safe): a step may cross several regions, always (True),
    never (False) or where a claim is asked (``"auto"``, the default: ``prove`` or a
    minimal or linear search from the start, the window search after it refuted every
    horizon through the decomposition; :mod:`plansynth.reach.lazy.exactmode`).
    """
    opts = LazyOptions() if options is None else options
    # (continuing after a refutation through the decomposition: the timed route, a plan
    # through the decomposition, cannot be one)
    return searched(
        exact_mode(opts),
        budget,
        lambda budget, clock, crossing, ab, continuing: _plan(
            problem, budget, clock, opts, progress, ab, crossing=crossing, timed=not continuing
        ),
        abstraction,
    )


def _plan(
    problem: ReachProblem,
    budget: Budget,
    clock: Clock,
    opts: LazyOptions,
    progress: ProgressFn | None,
    abstraction: Abstraction | None,
    *,
    crossing: bool,
    timed: bool = True,
) -> tuple[ReachResult, Abstraction | None]:
    """One search of :func:`plan_lazy` on ``clock``, with exact segment transitions
    (``crossing``: a step may cross several regions, lazy/segments.py) or without,
    with the timed route (``timed`` and ``opts.timed_route``) or without; also the
    abstraction it planned over (None when the budget ran out before it)."""
    # the relaxation can only prove a horizon that is minimal through the decomposition
    # (it refutes h - 1): the window search's plan sits at its window's top; with exact
    # transitions, a window whose plans need points along their segments is deferred
    # and the plan found lies far above the minimum (the GCS paper's 10 x 10 maze: 200):
    # the minimal search, from the timed route's plan lowered by separating half-spaces
    # (lazy/descent.py)
    search = "minimal" if (opts.prove or crossing) and opts.horizon_search == "window" else opts.horizon_search
    t_start = time.perf_counter()
    L_max = problem.max_horizon if opts.max_horizon is None else int(opts.max_horizon)
    record = opts.record(L_max, budget)
    timings = {"abstraction": 0.0, "bounds": 0.0, "guide": 0.0, "sat": 0.0, "lp": 0.0}
    counters: dict = {}
    guarantee = "segments" if opts.segment_safe else "samples"

    def result(out: LoopOutcome) -> tuple[ReachResult, Abstraction | None]:
        timings["total"] = time.perf_counter() - t_start
        counters.update(transitions=SEGMENTS if crossing else REGIONS if opts.segment_safe else STEPS)
        return ReachResult(
            status=out.status,
            solver="lazy-smt",
            seconds=timings["total"],
            trajectory=out.trajectory,
            regions=out.regions,
            horizon=out.horizon,
            counters=counters,
            timings=timings,
            options=record,
            message=out.message,
            guarantee=guarantee,
        ), abstraction

    try:
        if abstraction is None:
            with _timed(clock, timings, "abstraction", "the convex decomposition (abstraction)"):
                abstraction = abstract(problem)
        graph = RegionGraph.from_abstraction(abstraction)
        if not opts.segment_safe:  # samples only: every pair of regions one step can connect (exact search)
            with _timed(clock, timings, "bounds", "the one-step region pairs"):
                graph = replace(graph, adjacency=step_adjacency(problem, abstraction))
        counters.update(regions=graph.n_regions, edges=sum(map(len, graph.adjacency)) // 2)
        # (with exact segments: first CON-PLAN with segment rows, which checks the timed
        # route, a plan through the decomposition, as without them; the loop's below)
        conplan = _conplan(problem, abstraction, opts, search, clock, segment_rows=opts.segment_safe)
        transit = TransitCheck(conplan, abstraction, widen=opts.widen) if opts.transit else None
        theory: TheoryChecker = conplan if transit is None else transit
        path = route(problem, abstraction) if (opts.guided or opts.timed_route) else None
        quick = None
        if timed and opts.timed_route and search != "linear" and not conplan.dear:
            with clock.phase("the timed route"):
                first_leg = (  # (exact and a few LPs from rest; else a scan of up to REFINE_SPAN LPs)
                    transit.first_gap(START, path[1])
                    if transit is not None and problem.starts_at_rest and path is not None and len(path) > 1
                    else None
                )
                quick = timed_route(
                    problem,
                    abstraction,
                    path,
                    conplan,
                    clock,
                    timings,
                    max_horizon=L_max,
                    first_leg=first_leg,
                    counters=counters,
                )
        if quick is not None and search == "window":  # no bounds needed: nothing below it is claimed
            physical = physical_lower_bound(problem)
            counters.update(
                bfs_bound=count_bound(graph.horizon_lower_bound()),
                physical_bound=physical,
                exact_abstraction=abstraction.exact,
            )
            if opts.shorten > 0 and graph.n_regions > LARGE_REGIONS:
                with clock.phase("shortening the timed route's plan"):
                    t0 = time.perf_counter()
                    quick = shorten_plan(
                        PrismLP(problem, abstraction, clock),
                        quick,
                        clock,
                        opts.shorten * max(time.perf_counter() - t_start, MIN_SECONDS),
                        counters=counters,
                    )
                    timings["shorten"] = time.perf_counter() - t0
            out = _claims(quick, conplan, physical, False, counters, theory)
            _count_run(counters, clock, None, conplan, theory, out)
            timings["highs"] = conplan.stats.seconds
            return result(out)
        if crossing:
            # every pair of regions one segment through the free space can connect
            with _timed(clock, timings, "bounds", "the one-segment region pairs"):
                graph = replace(graph, adjacency=segment_adjacency(problem, abstraction))
            counters.update(edges=sum(map(len, graph.adjacency)) // 2)
            # CON-PLAN without segment rows: its transit legs hold for every segment-safe step
            conplan = _conplan(problem, abstraction, opts, search, clock, segment_rows=False)
            transit = TransitCheck(conplan, abstraction, widen=opts.widen) if opts.transit else None
            with _timed(clock, timings, "bounds", "the ends of steps between regions that do not touch"):
                boxes = pair_boxes(problem, abstraction, graph.adjacency)
            theory = SegmentTheory(problem, abstraction, transit=transit, clock=clock, boxes=boxes)
        with _timed(clock, timings, "bounds", "the horizon bounds (time windows)"):
            bounds = horizon_bounds(problem, abstraction, graph, opts, L_max)
        counters.update(
            proved_bound=count_bound(bounds.proved),
            exact_abstraction=abstraction.exact,
            bfs_bound=count_bound(bounds.bfs),
            physical_bound=bounds.physical,
            box_bound=count_bound(bounds.box),
            first_horizon=bounds.first,
        )
        if bounds.earliest is not None and bounds.first <= L_max:
            with _timed(clock, timings, "bounds", "the separator chains (time windows)"):
                bounds = with_chains(bounds, chain_bounds(problem, abstraction, graph, transit, path), L_max, counters)
    except BudgetExhausted as exc:  # before the loop: in the abstraction or the bounds
        return result(LoopOutcome(ReachStatus.UNKNOWN, None, str(exc)))

    # are the loop's refutations proofs for the problem? (samples only, or segments with
    # exact transitions; regions that cover the free space)
    exact = (not opts.segment_safe or crossing) and abstraction.exact
    proved = bounds.proved
    windows_kw = dict(
        cardinality=opts.cardinality,
        earliest=bounds.earliest,
        to_go=bounds.to_go,
        waits_at_start=opts.wait_shifts and problem.starts_at_rest,
    )
    if crossing:
        near = touching(abstraction)
        displan: DisPlan = SegmentDisPlan(
            graph, lambda scale: segment_adjacency(problem, abstraction, scale, near=near), **windows_kw
        )
    else:
        displan = DisPlan(graph, **windows_kw)
    if proved > L_max or bounds.first > L_max:
        out = refuted_by_bounds(problem, bounds, L_max, exact, opts, counters)
        if out.status is ReachStatus.UNKNOWN and opts.prove and opts.segment_safe:
            out = prove_claims(problem, out, proved, clock, counters)
    else:
        growth = window_growth_for(opts.window_growth, graph.n_regions)
        record["window_growth"] = growth  # (None: resolved)
        windows = horizon_windows(bounds.first, L_max, growth if search != "linear" else 0.0)
        first_leg = (lambda region: transit.first_gap(START, region)) if transit is not None else None
        guide = reference_plans(problem, abstraction, path, first_leg) if opts.guided else None
        with clock.phase("the lazy SMT loop"):
            defer = (DEAR_DEFER_AFTER if conplan.dear else DEFER_AFTER) if search == "window" else None
            if quick is not None and quick.horizon is not None and quick.horizon >= bounds.first:
                out, bottom = quick, bounds.first  # (nothing between the bounds and it refuted)
                displan.begin(bottom)
            else:
                out, bottom = lazy_loop(displan, theory, windows, clock, timings, progress, guide, defer), None
            if search == "window" and out.status is ReachStatus.FOUND and not out.minimal and not conplan.dear:
                out = shortened(displan, theory, out, windows, clock, timings, counters)
            if search == "minimal" and out.status is ReachStatus.FOUND and not out.minimal:
                out = _prove_minimal(
                    problem, abstraction, graph, displan, theory, out, windows, clock, timings, counters, opts, bottom
                )
        if out.status is ReachStatus.INFEASIBLE and exact:
            why = EXACT_SEGMENTS if crossing else EXACT_SAMPLES
            out = replace(out, message=f"infeasible up to horizon {out.horizon}: every horizon refuted ({why})")
        elif out.status is ReachStatus.INFEASIBLE:  # refuted through the abstraction only: not a proof
            counters["abstraction_refuted"] = out.horizon
            out = LoopOutcome(
                ReachStatus.UNKNOWN,
                out.horizon,
                f"every horizon up to {out.horizon} refuted for plans through the abstraction; {not_a_proof(proved)}",
            )
        if opts.prove and opts.segment_safe and not exact:
            out = prove_claims(problem, out, proved, clock, counters)
    out = _claims(out, conplan, proved, exact, counters, theory)
    _count_run(counters, clock, displan, conplan, theory, out)
    timings["highs"] = conplan.stats.seconds + (theory.lp.seconds if isinstance(theory, SegmentTheory) else 0.0)
    displan.delete()
    return result(out)


def _conplan(
    problem: ReachProblem,
    abstraction: Abstraction,
    opts: LazyOptions,
    search: str,
    clock: Clock,
    *,
    segment_rows: bool,
) -> ConPlan:
    """CON-PLAN as the options ask: ``farkas`` is ``trivial`` generalised. ``segment_rows``:
    keep each segment in one region (segment-safe without exact transitions)."""
    counterexample, generalize = opts.counterexample, opts.generalize
    if counterexample == "farkas":
        counterexample, generalize = "trivial", True
    # a proof of the minimal horizon (minimal, linear) is hundreds of LPs over the longest
    # horizons: split them into independent blocks where they separate (box regions, one
    # block per axis; maze-4: HiGHS's time 2-3x less); the window search needs a handful,
    # and the paper's loop (no generalisation) keeps the LPs it was measured with
    proof = search == "minimal" or (search == "linear" and opts.generalize)
    return ConPlan(
        problem,
        abstraction,
        segment_safe=segment_rows,
        counterexample=counterexample,
        generalize=generalize,
        minimize=opts.minimize,
        slack_weights=opts.slack_weights,
        clock=clock,
        split=True if proof else None,
    )


def _prove_minimal(
    problem: ReachProblem,
    abstraction: Abstraction,
    graph: RegionGraph,
    displan: DisPlan,
    theory: TheoryChecker,
    out: LoopOutcome,
    windows: list[tuple[int, int]],
    clock: Clock,
    timings: dict[str, float],
    counters: dict,
    opts: LazyOptions,
    bottom: int | None = None,
) -> LoopOutcome:
    """``horizon_search="minimal"``: :func:`~plansynth.reach.lazy.minimal.prove_minimal`
    from ``bottom`` (default: the bottom of the window of the plan found, every horizon
    below it refuted; the timed route's plan gives the first horizon, nothing above it
    refuted), with the per-axis reachable sets when ``reach_sets``."""
    t0 = time.perf_counter()
    if bottom is None:
        bottom = next(lo for lo, hi in windows if lo <= out.horizon <= hi)
    reach = (
        AxisReach.build(
            problem,
            abstraction,
            graph.adjacency,
            graph.start_regions,
            graph.goal_regions,
            segment_safe=opts.segment_safe and not isinstance(theory, SegmentTheory),
        )
        if opts.reach_sets
        else None
    )
    descent = Descent(theory, abstraction, clock) if isinstance(theory, SegmentTheory) else None
    out, counters["minimal_probes"] = prove_minimal(
        displan,
        theory,
        out,
        bottom,
        clock,
        timings,
        monotone=problem.starts_at_rest,
        reach=reach,
        counters=counters,
        lower=None if descent is None else descent.lowered,
    )
    if descent is not None:
        counters.update(descent_lp_calls=descent.lp_calls, descent_horizons=descent.horizons)
        timings["descent"] = descent.seconds
    timings["minimal"] = time.perf_counter() - t0
    return out


def _claims(
    out: LoopOutcome, conplan: ConPlan, proved: float, exact: bool, counters: dict, theory: TheoryChecker
) -> LoopOutcome:
    """The answer's claims as :mod:`~plansynth.reach.lazy.claims` words them."""
    st = conplan.stats
    if st.uncertified:
        out = uncertified(out, st.uncertified, counters.get("relaxation"))
    if isinstance(theory, SegmentTheory) and theory.undecided:
        out = uncertified(out, theory.undecided, counters.get("relaxation"), why=UNDECIDED)
    counters.update(horizon=out.horizon, minimal=out.minimal)
    if out.status is ReachStatus.FOUND:
        counters.update(minimal_claim(out, proved, exact or counters.get("relaxation") == "minimal"))
        if counters["minimal_relative_to"] == "decomposition":
            out = replace(
                out,
                message=f"{out.message}; minimal only among plans through the decomposition "
                f"({DECOMPOSITION_ONLY}), not proved for the problem (proved lower bound: "
                f"{int(proved)})",
            )
    return out


def _count_run(
    counters: dict, clock: Clock, displan: DisPlan | None, conplan: ConPlan, theory: TheoryChecker, out: LoopOutcome
) -> None:
    """What the run did, in ``counters`` (``displan`` None: DIS-PLAN was never built)."""
    st = conplan.stats
    counters.update(
        iterations=clock.iterations,
        sat_calls=0 if displan is None else displan.sat_calls,
        sat_slices=0 if displan is None else displan.sat_slices,
        clauses=0 if displan is None else displan.clauses,
        window_clauses=0 if displan is None else displan.window_clauses,
        conflicts=0 if displan is None else len(displan.conflicts),
        lp_calls=st.lp_calls,
        lp_calls_by_kind=dict(st.by_kind),
        iis_calls=st.iis_calls,
        ray_calls=st.ray_calls,
        certified=st.certified,
        rejected=st.rejected,
        lp_retries=st.retries,
        ipm_fallbacks=st.ipm_fallbacks,
        polished=st.polished,
        slack_failures=st.slack_failures,
    )
    transit = theory.transit if isinstance(theory, SegmentTheory) else theory
    if isinstance(transit, TransitCheck):
        counters.update(
            transit_conflicts=transit.conflicts,
            transit_lp_calls=transit.lp_calls,
            transit_plans=transit.plans_caught,
            widened_conflicts=transit.widened,
        )
    if isinstance(theory, SegmentTheory):
        assert isinstance(displan, SegmentDisPlan)
        counters.update(
            segment_lp_calls=theory.lp_calls,
            segment_points=displan.most_points,
            segment_refinements=displan.refinements,
            segment_separated=theory.separated,
            segment_undecided=theory.undecided,
        )
        counters["lp_calls"] += theory.lp_calls
