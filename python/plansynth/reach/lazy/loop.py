"""The lazy SMT planner (Shoukry et al., CDC 2016, Algorithm 1).

::

    abstraction <- convex decomposition of the free space             (Section III)
    for L = lower bound .. max_horizon:
        loop:
            r_0..r_L <- DIS-PLAN(L)        (SAT; UNSAT -> next L)         (Section IV)
            CON-PLAN(r_0..r_L) -> trajectory: done                     (Section V)
                               -> counterexample: add its clause, loop

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
The result's ``counters["minimal"]`` says whether the horizon found is
proved minimal (it is when it equals the window's lower end, and always under
``"linear"``). ``"minimal"`` runs the windows and then :func:`prove_minimal`, which
refutes the horizons below the one found, with every learned clause kept: for dynamics
that separate by axis, first the per-axis reachable sets of
:mod:`~plansynth.reach.lazy.axisreach` (every horizon below their first goal step
refuted without an LP, then one probe there under their tube), else (or when that probe
is refuted) the plan :func:`retimed` by LPs alone, then single-horizon probes galloping
down and bisecting when the start is at rest, where feasibility is monotone in the
horizon.

**Cheaper iterations** (beyond the paper, both on by default): the theory is
CON-PLAN behind :class:`~plansynth.reach.lazy.transit.TransitCheck`, which refutes plans
with impossible transit times between regions without a horizon-long LP; and DIS-PLAN's
decision phases follow :func:`~plansynth.reach.lazy.guide.reference_plan`, an evenly timed
route ending at the window's top (its first leg no faster than the transit layer allows),
so that the first plans proposed are plausible ones. When the robot starts at rest, a
start-anchored conflict also holds shifted earlier (``wait_shifts``): a trajectory for
the earlier claims, after waiting at the start, would realise the conflict itself. On
maze-4 with an order-25 chain these three make the loop find its trajectory in the first
feasible window with 4 iterations, not 46.

The loop talks to the continuous side only through :class:`TheoryChecker`: ``check``
maps a region sequence to :class:`~plansynth.reach.lazy.conflict.Feasible` or to one or more
:class:`~plansynth.reach.lazy.conflict.Conflict` (STYLE.md, point 8). The answer is
``unknown`` when the budget (time or iterations, one iteration = one SAT call and its
theory check) runs out.

**What ``infeasible`` and "minimal" mean** (issue 13, item 7). The claims are about
the problem as ``shared/spec/reach-problem.md`` defines it, or they say what they are
relative to:

* *Samples only* (``segment_safe=False``): DIS-PLAN steps between any two regions one
  step can connect (:func:`~plansynth.reach.lazy.bounds.step_adjacency`, an
  over-approximation from the displacement bounds; CON-PLAN's LP refutes the pairs no
  step realises, and its counterexamples are sound), and the lower bounds and time
  windows follow the same relation. With regions that cover the free space (an
  ``exact`` abstraction) every trajectory's region sequence is then a DIS-PLAN plan,
  so a refuted horizon is refuted for the problem: ``infeasible up to L`` is a proof,
  and a horizon found at the bottom of its window is minimal for the problem
  (``counters["minimal_relative_to"] == "problem"``). Without the step relation a
  thin wall that one step jumps, or a region that one step skips, made the loop claim
  minimal horizons that were not (``tests/reach/test_exact_claims.py``).
* *Segment-safe* (the default): CON-PLAN keeps each segment inside one convex region,
  which is sufficient for safety but not necessary (a segment may cross several
  regions; stlpy's narrow passage has an 8-step segment-safe plan where this search
  needs 9). So a horizon the loop refutes is refuted only for plans whose consecutive
  samples share a region, and: ``infeasible`` only when
  :func:`~plansynth.reach.lazy.bounds.proved_horizon_bound`, which holds for every
  trajectory of the problem, exceeds ``max_horizon`` (else ``unknown``,
  ``counters["abstraction_refuted"]``: not a proof; around a circle given as a
  400-vertex polygon the sliver regions made the loop refute horizon 30 where 3 steps
  suffice, ``tests/reach/test_proved_bound.py``); and a found horizon is minimal for
  the problem only when it is at most that proved bound, else
  ``counters["minimal_relative_to"] == "decomposition"`` and the message says so
  (the CLI prints "minimal through the decomposition only"). With ``prove=True`` the
  MILP relaxation of :mod:`~plansynth.reach.lazy.relaxation` (samples and points along
  each segment kept free: necessary for segment safety) may prove such a horizon
  minimal, or every horizon up to ``max_horizon`` infeasible, for the problem
  (``counters["relaxation"]``).
* An abstraction that is not ``exact`` (obstacles replaced by outer polygons) makes
  every refutation relative to the decomposition, in both modes.

Both modes read the free space as the union of full-dimensional regions: a zero-width
slit (a face two obstacles share, or an obstacle face flush with the workspace's
boundary) lies outside every obstacle's interior as the spec words it, but no region
holds it, so no claim counts paths through such slits.

Lower bound on the horizon where the search starts (segment-safe: a bound for plans
through the abstraction, not for the problem; samples only, over the step relation: a
bound for the problem): the largest of the region-graph distance from a
start region to a goal region (BFS), the distance to the goal along each axis divided
by the largest displacement per step (one small LP per axis and direction), and the
first step at which the displacement-box relaxation reaches the goal along the region
graph (:func:`~plansynth.reach.lazy.bounds.time_windows`, beyond the paper; it also gives
DIS-PLAN a time window per region).

>>> from plansynth.reach.families import maze
>>> r = plan_lazy(maze(1))
>>> r.status.value, r.horizon == len(r.regions) - 1, r.guarantee
('found', True, 'segments')
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any, Protocol

from plansynth.budget import Budget, BudgetExhausted, Clock
from plansynth.errors import InvalidOption
from plansynth.reach.lazy.axisreach import AxisReach
from plansynth.reach.lazy.bounds import (SEPARATOR_MAX_REGIONS, ChainBounds, chain_gaps, physical_lower_bound,
                                         proved_horizon_bound, separator_bounds, step_adjacency, time_windows)
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.conplan import ConPlan, LpBudgetExhausted, LpFailure
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.lazy.displan import DisPlan, RegionGraph, SatOutcome
from plansynth.reach.lazy.options import COUNTEREXAMPLES, HORIZON_SEARCHES, LazyOptions, window_growth_for
from plansynth.reach.lazy.guide import departure, reference_plan, route
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.lazy.transit import GOAL, START, TransitCheck

__all__ = ["TheoryChecker", "LoopOutcome", "lazy_loop", "plan_lazy", "horizon_windows", "HORIZON_SEARCHES",
           "COUNTEREXAMPLES", "LazyOptions"]

ProgressFn = Callable[[int, int], None]  # (horizon, iterations so far)


class TheoryChecker(Protocol):
    """The theory side of the lazy loop (CON-PLAN or any other).

    A theory may also have a boolean attribute ``expendable``, which :func:`lazy_loop`
    sets before each check: True when the window is deferred should the plan fail, so
    that a cheaper, weaker (still sound) counterexample will do (CON-PLAN on dense
    dynamics then skips the Farkas ray of a plan the interior-point method refutes)."""

    def check(self, regions: Sequence[int]) -> Feasible | Conflict | tuple[Conflict, ...]:
        """A trajectory following ``regions`` or one or more counterexample clauses."""
        ...


def plan_lazy(
    problem: ReachProblem,
    budget: Budget = Budget(),
    options: LazyOptions | None = None,
    *,
    abstraction: Abstraction | None = None,
    progress: ProgressFn | None = None,
    **values: Any,
) -> ReachResult:
    """Algorithm 1 on ``problem`` within ``budget``; the trajectory is *not* yet
    validated here (:func:`plansynth.reach.solve` does that).

    ``options`` (:class:`~plansynth.reach.lazy.options.LazyOptions`, default: ours;
    ``LazyOptions.paper()``: the paper's loop) with ``values`` replacing some of its
    fields (``plan_lazy(p, counterexample="trivial")``). ``max_horizon`` overrides the
    problem's. ``counterexample``, ``generalize`` and ``slack_weights`` choose how CON-PLAN
    explains an infeasible sequence (see :mod:`plansynth.reach.lazy.conplan`):
    ``"farkas"`` (the default, beyond the paper) is one feasibility LP over the whole plan
    whose Farkas certificate shrinks the trivial counterexample to the literals the proof
    needs (``trivial`` with ``generalize``); ``"zeroprefix"`` is the paper's
    (``generalize=False, slack_weights="uniform"``: as published). ``segment_safe``
    constrains whole segments, not only samples. ``lower_bound=False`` starts at horizon 0
    without time windows. ``horizon_search`` (``window``, ``linear`` or ``minimal``:
    windows, then :func:`prove_minimal`) and
    ``window_growth`` choose the horizons tried (see the module docstring). ``transit``
    puts :class:`~plansynth.reach.lazy.transit.TransitCheck` in front of CON-PLAN
    (transit-time conflicts without horizon-long LPs; ``widen`` also widens LP conflicts
    in time); ``guided`` sets DIS-PLAN's phases to
    :func:`~plansynth.reach.lazy.guide.reference_plan`. ``wait_shifts``: when the robot
    starts at rest, DIS-PLAN also adds every start-anchored conflict shifted earlier (it
    could have waited at the start). ``progress(L, iterations)`` is called when a horizon
    (window: its top) starts. ``abstraction``: a decomposition computed before (else it
    is computed here, within the budget). ``prove`` (segment-safe; it turns the window
    search into ``minimal``): after the loop, try
    to prove its claims for the problem with the MILP relaxation of
    :mod:`plansynth.reach.lazy.relaxation` (see "What infeasible and minimal mean").
    """
    opts = options if options is not None else LazyOptions()
    if values:
        unknown = sorted(set(values) - set(LazyOptions.names()))
        if unknown:
            raise InvalidOption("lazy-smt", unknown[0], f"not an option of the lazy planner "
                                                        f"(its options: {', '.join(LazyOptions.names())})")
        opts = replace(opts, **values)
    counterexample, segment_safe, generalize = opts.counterexample, opts.segment_safe, opts.generalize
    minimize, slack_weights, cardinality, lower_bound = opts.minimize, opts.slack_weights, opts.cardinality, opts.lower_bound
    horizon_search, window_growth, transit, guided = opts.horizon_search, opts.window_growth, opts.transit, opts.guided
    widen, wait_shifts = opts.widen, opts.wait_shifts
    if opts.prove and horizon_search == "window":
        # the relaxation can only prove a horizon that is minimal through the decomposition
        # (it refutes h - 1): the window search's plan sits at its window's top
        horizon_search = "minimal"
    t_start = time.perf_counter()
    clock = budget.clock()
    L_max = problem.max_horizon if opts.max_horizon is None else int(opts.max_horizon)
    options_record = opts.record(L_max, budget)
    timings = {"abstraction": 0.0, "bounds": 0.0, "guide": 0.0, "sat": 0.0, "lp": 0.0}
    counters: dict = {}
    guarantee = "segments" if segment_safe else "samples"

    def ran_out(exc: BudgetExhausted) -> ReachResult:
        """The budget ran out before the loop started (in the abstraction or the bounds)."""
        timings["total"] = time.perf_counter() - t_start
        return ReachResult(status=ReachStatus.UNKNOWN, planner="lazy-smt", seconds=timings["total"], counters=counters,
                           timings=timings, options=options_record, message=str(exc), guarantee=guarantee)

    if abstraction is None:
        t0 = time.perf_counter()
        try:
            with clock.phase("the convex decomposition (abstraction)"):
                abstraction = abstract(problem)
        except BudgetExhausted as exc:
            timings["abstraction"] = time.perf_counter() - t0
            return ran_out(exc)
        timings["abstraction"] = time.perf_counter() - t0
    step_graph = None  # samples only: every pair of regions one step can connect (exact search)
    if not segment_safe:
        t0 = time.perf_counter()
        try:
            with clock.phase("the one-step region pairs"):
                step_graph = step_adjacency(problem, abstraction)
        except BudgetExhausted as exc:
            timings["bounds"] = time.perf_counter() - t0
            return ran_out(exc)
        timings["bounds"] = time.perf_counter() - t0
    graph = RegionGraph.from_abstraction(abstraction)
    if step_graph is not None:
        graph = RegionGraph(graph.n_regions, step_graph, graph.start_regions, graph.goal_regions)
    exact = step_graph is not None and abstraction.exact  # are the loop's refutations proofs for the problem?
    counters.update(regions=graph.n_regions, edges=sum(map(len, graph.adjacency)) // 2)

    t0 = time.perf_counter()
    bfs = graph.horizon_lower_bound()
    try:
        with clock.phase("the horizon bounds (time windows)"):
            phys = physical_lower_bound(problem) if lower_bound else 0
            windows = (time_windows(problem, abstraction, L_max, adjacency=graph.adjacency)
                       if (lower_bound and math.isfinite(bfs)) else None)
            proved = proved_horizon_bound(problem, abstraction, L_max, segment_safe=segment_safe)
    except BudgetExhausted as exc:
        timings["bounds"] = time.perf_counter() - t0
        return ran_out(exc)
    timings["bounds"] += time.perf_counter() - t0
    counters["proved_bound"] = None if math.isinf(proved) else int(proved)
    counters["exact_abstraction"] = abstraction.exact
    counters["bfs_bound"] = None if math.isinf(bfs) else int(bfs)
    counters["physical_bound"] = phys
    box = windows.horizon if windows is not None else 0
    counters["box_bound"] = None if math.isinf(box) else int(box)
    if not math.isfinite(bfs) or not math.isfinite(box):
        first = L_max + 1
    else:
        first = int(max(bfs, phys, box)) if lower_bound else 0
    counters["first_horizon"] = first

    if counterexample == "farkas":
        counterexample, generalize = "trivial", True
    # a proof of the minimal horizon (minimal, linear) is hundreds of LPs over the longest
    # horizons: split them into independent blocks where they separate (box regions, one
    # block per axis; maze-4: HiGHS's time 2-3x less); the window search needs a handful,
    # and the paper's loop (no generalisation) keeps the LPs it was measured with
    proof = horizon_search == "minimal" or (horizon_search == "linear" and opts.generalize)
    conplan = ConPlan(problem, abstraction, segment_safe=segment_safe, counterexample=counterexample,
                      generalize=generalize, minimize=minimize, slack_weights=slack_weights, clock=clock,
                      split=True if proof else None)

    theory: TheoryChecker = TransitCheck(conplan, abstraction, widen=widen) if transit else conplan
    path = route(problem, abstraction) if guided else None

    earliest = windows.earliest if windows is not None else None
    to_go = windows.to_go if windows is not None else None
    if windows is not None and first <= L_max:
        t0 = time.perf_counter()
        try:
            with clock.phase("the separator chains (time windows)"):
                chain = _chain_bounds(problem, abstraction, graph, theory, path)
        except (BudgetExhausted, LpBudgetExhausted) as exc:
            timings["bounds"] += time.perf_counter() - t0
            return ran_out(exc if isinstance(exc, BudgetExhausted) else BudgetExhausted("the separator chains"))
        timings["bounds"] += time.perf_counter() - t0
        if chain is not None:
            counters["chain_bound"] = None if math.isinf(chain.horizon) else int(chain.horizon)
            earliest = tuple(max(a, b) for a, b in zip(earliest, chain.earliest))
            to_go = tuple(max(a, b) for a, b in zip(to_go, chain.to_go))
            first = L_max + 1 if math.isinf(chain.horizon) else max(first, int(chain.horizon))
            counters["first_horizon"] = first

    displan = DisPlan(
        graph,
        cardinality=cardinality,
        earliest=earliest,
        to_go=to_go,
        waits_at_start=wait_shifts and problem.starts_at_rest,
    )

    def finish(out: LoopOutcome) -> ReachResult:
        st = conplan.stats
        if st.uncertified:
            out = _uncertified(out, st.uncertified, counters.get("relaxation"))
        counters.update(
            iterations=clock.iterations,
            sat_calls=displan.sat_calls,
            sat_slices=displan.sat_slices,
            clauses=displan.clauses,
            window_clauses=displan.window_clauses,
            conflicts=len(displan.conflicts),
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
            horizon=out.horizon,
            minimal=out.minimal,
        )
        if out.status is ReachStatus.FOUND:
            counters.update(_minimal_claim(out, proved, exact or counters.get("relaxation") == "minimal"))
            if counters["minimal_relative_to"] == "decomposition":
                out = replace(out, message=f"{out.message}; minimal only among plans through the decomposition "
                              f"({DECOMPOSITION_ONLY}), not proved for the problem (proved lower bound: {int(proved)})")
        if isinstance(theory, TransitCheck):
            counters.update(transit_conflicts=theory.conflicts, transit_lp_calls=theory.lp_calls,
                            transit_plans=theory.plans_caught, widened_conflicts=theory.widened)
        timings["highs"] = st.seconds
        timings["total"] = time.perf_counter() - t_start
        displan.delete()
        return ReachResult(
            status=out.status, planner="lazy-smt", seconds=timings["total"], trajectory=out.trajectory,
            regions=out.regions, segment_safe=None, horizon=out.horizon, counters=counters, timings=timings,
            options=options_record, message=out.message, guarantee=guarantee,
        )

    if proved > L_max:
        if (phys if lower_bound else physical_lower_bound(problem)) >= 1 << 30:
            why = "the dynamics and bounds allow no displacement toward the goal"
        elif math.isinf(proved):
            why = ("the goal is not connected to the start in the free space" if math.isinf(bfs)
                   else "no position reaches the goal by bounded displacements through the free space")
        else:
            why = f"every trajectory needs at least {int(proved)} steps (bounded displacement through the free space)"
        return finish(LoopOutcome(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: {why}"))
    if first > L_max:
        if math.isinf(bfs):
            why = "the goal regions are not connected to the start regions"
        elif math.isinf(box):
            why = f"no position in the regions reaches the goal within {L_max} steps of bounded displacement"
        else:
            why = f"the region-hop lower bound on the horizon ({first}) exceeds max_horizon"
        if exact:
            return finish(LoopOutcome(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: {why} "
                                      f"({EXACT_SAMPLES})"))
        counters["abstraction_refuted"] = L_max
        out = LoopOutcome(ReachStatus.UNKNOWN, L_max, f"no plan through the abstraction up to horizon {L_max}: "
                          f"{why}; {_not_a_proof(proved)}")
        return finish(_prove(problem, out, proved, clock, counters) if opts.prove and segment_safe else out)
    growth = window_growth_for(window_growth, graph.n_regions) if horizon_search != "linear" else 0.0
    options_record["window_growth"] = window_growth_for(window_growth, graph.n_regions)  # (None: resolved)
    windows = horizon_windows(first, L_max, growth)
    guide = _guide(problem, abstraction, theory if isinstance(theory, TransitCheck) else None, path) if guided else None
    with clock.phase("the lazy SMT loop"):
        defer = (DEAR_DEFER_AFTER if conplan.dear else DEFER_AFTER) if horizon_search == "window" else None
        out = lazy_loop(displan, theory, windows, clock, timings, progress, guide, defer)
        if (horizon_search == "window" and out.status is ReachStatus.FOUND and not out.minimal and windows
                and not conplan.dear):
            out = shortened(displan, theory, out, windows, clock, timings, counters)
        if horizon_search == "minimal" and out.status is ReachStatus.FOUND and not out.minimal:
            t0 = time.perf_counter()
            bottom = next(lo for lo, hi in windows if lo <= out.horizon <= hi)  # (horizons below refuted)
            reach = (AxisReach.build(problem, abstraction, graph.adjacency, graph.start_regions, graph.goal_regions,
                                     segment_safe=segment_safe) if opts.reach_sets else None)
            out, counters["minimal_probes"] = prove_minimal(displan, theory, out, bottom, clock, timings,
                                                            monotone=problem.starts_at_rest, reach=reach,
                                                            counters=counters)
            timings["minimal"] = time.perf_counter() - t0
    if out.status is ReachStatus.INFEASIBLE and exact:
        out = replace(out, message=f"infeasible up to horizon {out.horizon}: every horizon refuted ({EXACT_SAMPLES})")
    elif out.status is ReachStatus.INFEASIBLE:  # refuted through the abstraction only: not a proof
        counters["abstraction_refuted"] = out.horizon
        out = LoopOutcome(ReachStatus.UNKNOWN, out.horizon, f"every horizon up to {out.horizon} refuted for plans "
                          f"through the abstraction; {_not_a_proof(proved)}")
    if opts.prove and segment_safe and not exact:
        out = _prove(problem, out, proved, clock, counters)
    return finish(out)


def _uncertified(out: LoopOutcome, n: int, relaxation: str | None) -> LoopOutcome:
    """The claims of a loop that kept ``n`` LP refutations without a Farkas certificate
    (the interior-point method's, on expendable plans (see :class:`TheoryChecker`) or
    as a fallback when the simplex method stalls, and presolve's): an ``infeasible``
    from the loop alone becomes ``unknown`` and a minimal horizon is no longer claimed,
    unless the independent relaxation MILP proved it (``--prove``). The refutations
    stay sound as far as HiGHS's verdict goes, but a "no" is certified before it is
    reported, and these are not."""
    why = f"{n} LP refutation{'s' * (n != 1)} without a Farkas certificate (interior-point method or presolve)"
    if out.status is ReachStatus.INFEASIBLE and relaxation != "infeasible":  # (bounds refute before any LP)
        return LoopOutcome(ReachStatus.UNKNOWN, out.horizon, f"{out.message}; not a proof: {why}")
    if out.status is ReachStatus.FOUND and out.minimal and relaxation != "minimal":
        return replace(out, minimal=False, message=f"{out.message}; not proved minimal: {why}")
    return out


#: What makes a samples-only refutation a proof (see the module docstring).
EXACT_SAMPLES = ("samples only, steps between any two regions one step can connect, regions covering the free "
                 "space: a proof for the problem")


DECOMPOSITION_ONLY = "consecutive samples in one convex region"


def _minimal_claim(out: LoopOutcome, proved: float, exact: bool) -> dict[str, Any]:
    """What a found horizon's minimality claim is relative to (issue 13, item 7):
    ``minimal_relative_to`` is ``"problem"`` when no trajectory of the problem (the
    spec's semantics) has a shorter horizon (an exact samples-only search, or a horizon
    no larger than :func:`~plansynth.reach.lazy.bounds.proved_horizon_bound`), else
    ``"decomposition"``: no shorter plan whose consecutive samples share a region of the
    decomposition (segment-safe mode), or through an inexact decomposition."""
    h = out.horizon
    if h is not None and h <= proved:  # every trajectory needs at least `proved` steps
        return {"minimal": True, "minimal_relative_to": "problem"}
    if not out.minimal:
        return {"minimal_relative_to": None}
    return {"minimal_relative_to": "problem" if exact else "decomposition"}


def _prove(problem: ReachProblem, out: LoopOutcome, proved: float, clock: Clock, counters: dict) -> LoopOutcome:
    """``prove=True``, segment-safe: try to make the loop's claims hold for the problem
    with :func:`~plansynth.reach.lazy.relaxation.refute_below` (a MILP relaxation of
    segment safety; one MILP at h - 1 when the robot starts at rest), within the
    budget left: a found horizon becomes proved minimal, every horizon refuted through
    the abstraction becomes ``infeasible``. ``counters["relaxation"]`` says what it
    proved (``minimal``, ``infeasible``, or ``not proved``)."""
    from plansynth.reach.lazy.relaxation import SUBDIVISIONS, refute_below

    lowest = 0 if math.isinf(proved) else int(proved)
    if out.status is ReachStatus.FOUND and out.horizon is not None and out.horizon > lowest:
        ok = refute_below(problem, out.horizon, lowest=lowest, seconds=clock.remaining())
        counters["relaxation"] = "minimal" if ok else "not proved"
        if ok:
            return replace(out, minimal=True, message=f"{out.message}; proved minimal for the problem: no shorter "
                           f"trajectory keeps its samples and {SUBDIVISIONS - 1} points per segment free")
    elif out.status is ReachStatus.UNKNOWN and counters.get("abstraction_refuted") is not None:
        L = int(counters["abstraction_refuted"])
        ok = refute_below(problem, L + 1, lowest=lowest, seconds=clock.remaining())
        counters["relaxation"] = "infeasible" if ok else "not proved"
        if ok:
            return LoopOutcome(ReachStatus.INFEASIBLE, L, f"infeasible up to horizon {L}: no trajectory keeps its "
                               f"samples and {SUBDIVISIONS - 1} points per segment free (a MILP relaxation of "
                               f"segment safety: a proof for the problem)")
    if counters.get("relaxation") == "not proved":
        return replace(out, message=f"{out.message}; --prove: the relaxation MILP has a solution or ran out of time")
    return out


#: How the per-axis reachable sets refute the shorter horizons (prove_minimal).
REACH_SETS = "refuted by the per-axis reachable sets over the region graph, which do not reach the goal"


def _not_a_proof(proved: float) -> str:
    return (f"not a proof of infeasibility (a step may cross several regions; proved lower bound on the "
            f"horizon: {int(proved)})")


def _chain_bounds(problem: ReachProblem, abstraction: Abstraction, graph: RegionGraph, theory: TheoryChecker,
                  path: Sequence[int] | None) -> ChainBounds | None:
    """The separator chains of :func:`~plansynth.reach.lazy.bounds.separator_bounds` over
    DIS-PLAN's region graph (beyond the paper; issue 13, item 4), or None when they do
    not apply: no multi-step displacement table (integrator chains, whose one-step
    bounds the sweep of :func:`~plansynth.reach.lazy.bounds.time_windows` already
    uses), or more than :data:`~plansynth.reach.lazy.bounds.SEPARATOR_MAX_REGIONS`
    regions. The gaps are those of :func:`~plansynth.reach.lazy.bounds.chain_gaps`,
    raised by the transit layer's LP bound
    (:meth:`~plansynth.reach.lazy.transit.TransitCheck.first_gap`: every smaller gap
    refuted by an LP; exact for a leg out of the start at rest) from the start into the
    guide's first region (``path[1]``; the guide asks for it anyway) and on the legs of
    the chain that gives the horizon bound, for up to :data:`CHAIN_ROUNDS` rounds
    (the chain may move to other legs once these are raised). Each is a lower bound on
    the steps between two samples of a plan through the region graph, as the chains
    need; the transit layer reuses the LPs. Maze-3 with n = 4 random dynamics: horizon
    bound 86 where the sweep gives 17 (no plan below 108); with n = 50, 93 (sweep: 22)."""
    if graph.n_regions > SEPARATOR_MAX_REGIONS:
        return None
    base = chain_gaps(problem, abstraction)
    if base is None:
        return None
    transit = theory if isinstance(theory, TransitCheck) else None
    refined: dict[tuple[int, int], int] = {}

    def gap(a: int, b: int) -> int:
        return max(base(a, b), refined.get((a, b), 0))

    if transit is not None and path is not None and len(path) > 1:
        refined[(START, path[1])] = transit.first_gap(START, path[1])
    out = separator_bounds(graph.adjacency, graph.start_regions, graph.goal_regions, gap)
    for _ in range(CHAIN_ROUNDS if transit is not None else 0):
        # (start straight to goal, one region holding both: no leg LP, the box gap stands)
        legs = [(a, b) for a, b in zip(out.critical, out.critical[1:])
                if (a, b) not in refined and (a, b) != (START, GOAL)]
        if not legs:
            break
        for a, b in legs:
            refined[(a, b)] = transit.first_gap(a, b)
        out = separator_bounds(graph.adjacency, graph.start_regions, graph.goal_regions, gap)
    return out


#: rounds of LP refinement of the critical separator chain (see _chain_bounds)
CHAIN_ROUNDS = 4


def _guide(
    problem: ReachProblem, abstraction: Abstraction, transit: TransitCheck | None, path: Sequence[int] | None = None,
) -> Callable[[int], Sequence[int] | None] | None:
    """DIS-PLAN's reference plan per horizon (:mod:`plansynth.reach.lazy.guide`): the route
    at constant speed, its first leg held back to the fewest steps the transit layer
    proves for it (plus :data:`~plansynth.reach.lazy.guide.DEPART_SLACK`; LPs, so computed on
    the first call, inside the loop and its budget)."""
    path = route(problem, abstraction) if path is None else list(path)
    if path is None:
        return None
    held = transit is not None and len(path) > 1
    depart: int | None = None

    def plan(L: int) -> Sequence[int] | None:
        nonlocal depart
        if held and depart is None:
            depart = departure(transit.first_gap(START, path[1]))
        return reference_plan(problem, abstraction, L, depart=depart, path=path)

    return plan


def horizon_windows(first: int, last: int, growth: float) -> list[tuple[int, int]]:
    """Consecutive windows lo..hi covering first..last, each ``hi = lo + floor(growth * lo)``
    (at least lo; ``growth=0``: one horizon at a time, the paper's loop).

    >>> horizon_windows(10, 30, 0.25)
    [(10, 12), (13, 16), (17, 21), (22, 27), (28, 30)]
    >>> horizon_windows(3, 5, 0.0)
    [(3, 3), (4, 4), (5, 5)]
    """
    out = []
    lo = first
    while lo <= last:
        hi = min(last, lo + int(growth * lo))
        out.append((lo, hi))
        lo = hi + 1
    return out


@dataclass(frozen=True)
class LoopOutcome:
    """What :func:`lazy_loop` ends with (the horizon as in :class:`ReachResult`)."""

    status: ReachStatus
    horizon: int | None
    message: str
    trajectory: Trajectory | None = None
    regions: tuple[int, ...] | None = None
    minimal: bool | None = None  # found: is the horizon proved minimal?


def lazy_loop(
    displan: DisPlan,
    theory: TheoryChecker,
    windows: Sequence[tuple[int, int]] | range,
    clock: Clock,
    timings: dict[str, float],
    progress: ProgressFn | None = None,
    guide: Callable[[int], Sequence[int] | None] | None = None,
    defer_after: int | None = None,
) -> LoopOutcome:
    """Algorithm 1, the loop: for each horizon window lo..hi (a ``range`` means one
    horizon at a time), ask DIS-PLAN for a region sequence ending at a horizon in the
    window, ask the theory to realise it, learn its counterexample, until a trajectory
    is found or DIS-PLAN is UNSAT (then every horizon of the window is refuted: the
    next window). Adds the seconds spent in the SAT solver and in the theory to
    ``timings["sat"]`` and ``timings["lp"]``.

    ``defer_after`` (the window search; beyond the paper): a window other than the
    last whose plans have needed that many horizon-long LPs without a trajectory (plans
    that the transit layer refutes alone do not count) is *deferred*: the loop moves on
    to the next window and comes back to the deferred ones, lowest first and without
    the limit, only when no later window yields a trajectory. Refuting the window just
    below the least feasible horizon is the dearest part of the search (long conflicts
    that each rule out a few timings; maze-3 with n = 4 random dynamics: window 92..115,
    over 1,000 iterations, not refuted in 60 s), while a window above it is usually
    realised at once. Nothing learned is lost (the clauses hold for every horizon), a
    deferred window's horizons stay open, and the answer says so: a trajectory is
    ``minimal`` only when every horizon below it is refuted, and ``infeasible`` needs
    every window refuted."""
    if isinstance(windows, range):
        windows = [(L, L) for L in windows]
    first_lo = windows[0][0] if windows else 0
    lo, hi = windows[0] if windows else (0, -1)
    pending = list(windows)
    deferred: list[tuple[int, int]] = []
    try:
        while pending or deferred:
            lo, hi = pending.pop(0) if pending else deferred.pop(0)
            cap = defer_after if pending else None  # the last window, and deferred ones: no limit
            if progress is not None:
                progress(hi, clock.iterations)
            if guide is not None:
                t0 = time.perf_counter()
                ref = guide(hi)
                timings["guide"] = timings.get("guide", 0.0) + time.perf_counter() - t0  # (its first LPs)
                if ref is not None:
                    displan.prefer(ref)
            costly = 0  # plans of this window that needed CON-PLAN's LPs
            while True:
                if cap is not None and costly >= cap:
                    deferred.append((lo, hi))
                    deferred.sort()
                    break
                if clock.exhausted():
                    return LoopOutcome(ReachStatus.UNKNOWN, hi, f"budget ran out in the lazy SMT loop (between SAT and LP calls) at horizon {_span(lo, hi)} after {clock.iterations} iterations")
                clock.tick()
                t0 = time.perf_counter()
                outcome, plan = displan.solve(hi, clock, lowest=lo)
                timings["sat"] += time.perf_counter() - t0
                if outcome is SatOutcome.INTERRUPTED:
                    return LoopOutcome(ReachStatus.UNKNOWN, hi, f"budget ran out in the SAT solver at horizon {_span(lo, hi)}")
                if outcome is SatOutcome.UNSAT:
                    for L in range(lo, hi + 1):
                        displan.close(L)
                    break
                assert plan is not None
                checked = getattr(theory, "plans_checked", None)
                if hasattr(theory, "expendable"):  # (see TheoryChecker)
                    theory.expendable = cap is not None and costly + 1 >= cap
                t0 = time.perf_counter()
                answer = theory.check(plan)
                timings["lp"] += time.perf_counter() - t0
                costly += 1 if checked is None or getattr(theory, "plans_checked") > checked else 0
                if isinstance(answer, Feasible):
                    h = len(plan) - 1
                    below = _lowest_open(displan, first_lo, h)
                    note = "" if h == first_lo else _refuted_note(below, h if below == h else lo)
                    return LoopOutcome(ReachStatus.FOUND, h, f"found at horizon {h}{note}", answer.trajectory, plan,
                                       minimal=below == h)
                for conflict in answer if isinstance(answer, tuple) else (answer,):
                    displan.learn(conflict)
    except LpBudgetExhausted:
        return LoopOutcome(ReachStatus.UNKNOWN, hi, f"budget ran out in the LP solver at horizon {_span(lo, hi)}")
    except BudgetExhausted as exc:
        return LoopOutcome(ReachStatus.UNKNOWN, hi, f"{exc} at horizon {_span(lo, hi)}")
    except LpFailure as exc:
        return LoopOutcome(ReachStatus.UNKNOWN, hi, f"{exc} at horizon {_span(lo, hi)}")
    top = windows[-1][1] if windows else -1
    return LoopOutcome(ReachStatus.INFEASIBLE, top, f"infeasible: every horizon up to {top} refuted")


#: the window search defers a window after this many of its plans needed CON-PLAN's LPs
DEFER_AFTER = 4
#: ... and after one on dense dynamics (``ConPlan.dear``), where one plan LP over a horizon
#: of 150 takes 5-15 s: the window's reference plan is then the only one asked for
#: before the loop moves on (random dynamics, n = 50, maze-3: 9 plan LPs -> 3)
DEAR_DEFER_AFTER = 1


def prove_minimal(
    displan: DisPlan,
    theory: TheoryChecker,
    found: LoopOutcome,
    bottom: int,
    clock: Clock,
    timings: dict[str, float],
    *,
    monotone: bool,
    reach: AxisReach | None = None,
    counters: dict | None = None,
) -> tuple[LoopOutcome, int]:
    """Prove the horizon of ``found`` minimal (``horizon_search="minimal"``, beyond the
    paper), given that every horizon below ``bottom`` is refuted and DIS-PLAN holds every
    clause learned so far.

    With ``monotone`` (the robot starts at rest, ``A x_0 = x_0``) feasibility is monotone
    in the horizon: a plan of horizon L, preceded by one step of waiting at the start
    (u = 0, in the start's region), is a plan of horizon L + 1, through the same regions
    plus one. So refuting a single horizon L refutes every horizon <= L, and the least
    feasible horizon is found by probes of one horizon each (a refuted probe closes
    every horizon below it; a realised one is the new best plan): first the best plan
    is :func:`retimed` (LPs only, no SAT call), then the probes gallop down from it
    (h - 1, then 2, 4, ... steps below the best plan while they are realised, each new
    plan re-timed too), and once a probe is refuted they bisect between it and the best
    plan. DIS-PLAN's phases follow the best plan so far, :func:`compressed` to the
    probe's horizon.

    Why this order (issue 13, item 3): every probe above the minimum is a SAT search
    for a near-tight timing, and on the mazes those cost as much as the refutation
    below the minimum (maze-4, from the window's 152 and its start 122: the plain
    bisection probed 136, 144, 140, 142, 141, 182 iterations; re-timing takes the plan
    to 145 in ~25 LPs and the gallop probes 144, 142, 141, 140). The refutation of
    h - 1 is what remains, about 40 iterations on maze-4.
    Without it, the window bottom..h-1 is asked as a whole until it is refuted, each
    plan found lowering its top. Either way the answer is minimal relative to the
    transition relation DIS-PLAN uses (as under ``horizon_search="linear"``); when the
    budget runs out the best plan so far is returned with ``minimal=False``. Returns the
    outcome and the number of probes (single horizons, or windows) asked.

    With ``reach`` (:class:`~plansynth.reach.lazy.axisreach.AxisReach`, for dynamics that
    separate by axis; ``reach_sets=True``) the per-axis reachable sets come first, with
    no LP: every horizon below their first goal step b has no plan (the module's
    soundness argument, relative to the same transition relation as DIS-PLAN's), so
    those are closed; if b is the plan's own horizon or above, the plan is minimal.
    Otherwise one probe at b, under the tube of horizon b (the regions a trajectory of
    that horizon can visit at each step, added as clauses for that horizon only); a
    plan found there is minimal. On maze-1..4 b is the minimum and the tube leaves 1-2
    steps per gap, so that probe costs a few iterations where the probes above took
    ~100 (``counters["reach_sets_bound"]``: b, or None when no horizon below the
    plan's is reached). If b is refuted, the probes above continue from b + 1."""
    best, probes = found, 0
    assert best.horizon is not None
    if reach is not None and best.horizon > bottom:
        t0 = time.perf_counter()
        try:
            bound = reach.first_horizon(best.horizon - 1, displan.earliest, displan.to_go)
            tube = reach.tube(bound) if bound is not None and bound >= bottom and reach.reached else None
        except BudgetExhausted as exc:
            return replace(best, minimal=False, message=f"{best.message}; not proved minimal: {exc}"), probes
        finally:
            timings["reach_sets"] = timings.get("reach_sets", 0.0) + time.perf_counter() - t0
        if counters is not None:
            counters["reach_sets_bound"] = bound
            counters["reach_sets_reached"] = reach.reached
        if bound is None:
            return replace(best, minimal=True, message=f"found at horizon {best.horizon} (proved minimal: every "
                                                       f"shorter horizon {REACH_SETS})"), probes
        bound = max(bound, bottom)
        for L in range(bottom, bound):
            if L not in displan.closed:
                displan.close(L)  # no plan of these horizons: the sets do not reach the goal
        bottom = bound
        if reach.reached and best.horizon > bound:  # (else the sweep stopped at its work cap: no probe there)
            if tube is not None:
                displan.forbid(bound, tube)
            # under the tube the plans proposed keep to feasible crossing times, and the
            # transit layer's leg LPs (maze-4: 80 to decide the legs of one refuted plan)
            # would only repeat what CON-PLAN's conflict says: CON-PLAN alone
            plain = theory.inner if isinstance(theory, TransitCheck) and tube is not None else theory
            out = lazy_loop(displan, plain, [(bound, bound)], clock, timings, None,
                            lambda H, plan=best.regions: compressed(plan, H))
            probes += 1
            if out.status is ReachStatus.FOUND:
                return replace(out, minimal=True, message=f"found at horizon {out.horizon} (proved minimal: every "
                                                          f"shorter horizon {REACH_SETS})"), probes
            if out.status is not ReachStatus.INFEASIBLE:
                return (replace(best, minimal=False, message=f"{best.message}; not proved minimal: {out.message}"),
                        probes)
            if bound not in displan.closed:
                displan.close(bound)
            bottom = bound + 1
    best = retimed(displan, theory, best, bottom, clock, timings)
    step, refuted = 1, False  # downward gallop from the best plan until a probe is refuted
    while best.horizon > bottom:
        top = best.horizon - 1
        if refuted:
            probe = (bottom + top) // 2
        else:
            probe = max(bottom, top + 1 - step)
        window = [(probe, probe)] if monotone else [(bottom, top)]
        out = lazy_loop(displan, theory, window, clock, timings, None,
                        lambda H, plan=best.regions: compressed(plan, H))
        probes += 1
        if out.status is ReachStatus.FOUND:
            best = retimed(displan, theory, out, bottom, clock, timings)
            step *= 2
        elif out.status is ReachStatus.INFEASIBLE:
            refuted = True
            for L in range(bottom, probe + 1 if monotone else top + 1):
                if L not in displan.closed:
                    displan.close(L)  # (by monotonicity, when below the probe)
            bottom = probe + 1 if monotone else top + 1
        else:
            return replace(best, minimal=False, message=f"{best.message}; not proved minimal: {out.message}"), probes
    assert best.horizon is not None
    how = ", by monotonicity from the start at rest" if monotone else ""
    return replace(best, minimal=True, message=f"found at horizon {best.horizon} (proved minimal: every shorter "
                                               f"horizon refuted{how})"), probes


def retimed(
    displan: DisPlan,
    theory: TheoryChecker,
    found: LoopOutcome,
    bottom: int,
    clock: Clock,
    timings: dict[str, float],
) -> LoopOutcome:
    """``found`` with its horizon lowered by re-timing alone (beyond the paper): while
    some stay of the plan, shortened by one step (the longest stays first), is still
    realised by the theory, keep the shorter plan. One theory check per candidate, no
    SAT call; the conflicts of the candidates refuted are learned by DIS-PLAN (they hold
    for every plan, as in the loop). Only an upper bound for :func:`prove_minimal`: its
    probes, not this, prove the horizon minimal. Stops at ``bottom`` (no shorter plan
    exists), when the budget runs out, or when no stay can lose a step.

    On the mazes a plan at the first window's top (maze-4: 152) comes down to a few
    steps above the minimum (145 of 141) in about 25 LPs, so the bisection's probes
    above the minimum, each a SAT search for a near-tight timing, mostly go."""
    best = found
    try:
        while best.horizon is not None and best.horizon > bottom and best.regions is not None:
            stays: list[list[int]] = []
            for r in best.regions:
                if stays and stays[-1][0] == r:
                    stays[-1][1] += 1
                else:
                    stays.append([r, 1])
            shorter = None
            for i in sorted(range(len(stays)), key=lambda i: -stays[i][1]):
                if stays[i][1] <= 1 or clock.exhausted():
                    continue
                plan = tuple(r for j, (r, n) in enumerate(stays) for _ in range(n - (j == i)))
                t0 = time.perf_counter()
                answer = theory.check(plan)
                timings["lp"] += time.perf_counter() - t0
                if isinstance(answer, Feasible):
                    h = len(plan) - 1
                    shorter = LoopOutcome(ReachStatus.FOUND, h, f"found at horizon {h} (re-timed)", answer.trajectory,
                                          plan, minimal=False)
                    break
                for conflict in answer if isinstance(answer, tuple) else (answer,):
                    displan.learn(conflict)
            if shorter is None:
                break
            best = shorter
    except (LpBudgetExhausted, LpFailure, BudgetExhausted):
        pass  # the best plan so far stands; the probes report the budget
    return best


def shortened(
    displan: DisPlan,
    theory: TheoryChecker,
    found: LoopOutcome,
    windows: Sequence[tuple[int, int]],
    clock: Clock,
    timings: dict[str, float],
    counters: dict | None = None,
) -> LoopOutcome:
    """``found`` at a shorter horizon when a deferred window lies below it (the window
    search; beyond the paper): the plan's stays :func:`compressed` in proportion to a
    horizon between the lowest horizon not refuted and the plan's, by bisection, one
    theory check each and no SAT call (a compressed plan that fails only moves the
    bisection; its conflicts are learned as in the loop). A window deferred after a few
    plans leaves the answer to the next window, often at its top: the GCS paper's 50 x 50
    maze was found at 1,146 (window 573..1,146 above the deferred 286..572) and comes down
    to 668 in 10 LPs (1.7 s). Not used on dear dynamics, where each check costs a
    horizon-long LP of seconds. The result is minimal only if it reaches the lowest
    horizon not refuted (every horizon below that is)."""
    h = found.horizon
    if h is None or found.regions is None:
        return found
    below = _lowest_open(displan, windows[0][0], h)
    own = next((lo for lo, hi in windows if lo <= h <= hi), h)  # the bottom of the plan's window
    if below >= own:
        return found  # no deferred window below: the plan's own window is the lowest open one
    best, lo, hi, checks = found, below - 1, h, 0
    try:
        while lo + 1 < hi and not clock.exhausted():
            H = (lo + hi) // 2
            plan = compressed(best.regions, H)
            checks += 1
            t0 = time.perf_counter()
            answer = theory.check(plan)
            timings["lp"] += time.perf_counter() - t0
            if isinstance(answer, Feasible):
                best = LoopOutcome(ReachStatus.FOUND, H, "", answer.trajectory, plan)
                hi = H
                continue
            lo = H
            for conflict in answer if isinstance(answer, tuple) else (answer,):
                displan.learn(conflict)
    except (LpBudgetExhausted, LpFailure, BudgetExhausted):
        pass  # the best plan so far stands
    if counters is not None:
        counters["shortened_checks"] = checks
    if best is found:
        return found
    minimal = hi == below
    note = _refuted_note(below, hi)
    return replace(best, message=f"found at horizon {hi}{note}; shortened from {h} by compressing its stays",
                   minimal=minimal)


def _lowest_open(displan: DisPlan, lo: int, h: int) -> int:
    """The lowest horizon in lo..h - 1 that DIS-PLAN has not refuted (h if none)."""
    return next((L for L in range(lo, h) if L not in displan.closed), h)


def _refuted_note(below: int, top: int) -> str:
    """What a found plan's message says of the horizons below it: every one below
    ``below`` refuted, and when ``below < top`` the deferred ones in below..top - 1 not all."""
    if below >= top:
        return f" (horizons below {below} refuted)"
    return f" (horizons below {below} refuted; deferred ones in {below}..{top - 1} not all)"


def compressed(plan: Sequence[int], horizon: int) -> tuple[int, ...]:
    """``plan`` (r_0..r_h) shortened to ``horizon``: the same regions in the same order,
    each stay shortened in proportion to its length (largest remainders first; every stay
    keeps one step). Only a hint for DIS-PLAN's phases: when the stays have fewer spare
    steps than must go, the plan is cut off at ``horizon``.

    >>> compressed((0, 0, 0, 0, 1, 2, 2, 2, 2), 6)
    (0, 0, 0, 1, 2, 2, 2)
    """
    runs: list[list[int]] = []
    for r in plan:
        if runs and runs[-1][0] == r:
            runs[-1][1] += 1
        else:
            runs.append([r, 1])
    drop = len(plan) - 1 - horizon
    spare = [n - 1 for _, n in runs]
    total = sum(spare)
    if drop <= 0 or total < drop:
        return tuple(plan) if drop <= 0 else tuple(plan[: horizon + 1])
    share = [drop * s / total for s in spare]
    cut = [int(x) for x in share]
    for i in sorted(range(len(runs)), key=lambda i: share[i] - cut[i], reverse=True)[: drop - sum(cut)]:
        cut[i] += 1
    out: list[int] = []
    for (r, n), c in zip(runs, cut):
        out += [r] * (n - c)
    return tuple(out)


def _span(lo: int, hi: int) -> str:
    return str(hi) if lo == hi else f"{lo}..{hi}"
