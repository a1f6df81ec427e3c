"""The baseline: the bounded mission as one mixed-integer program per horizon in HiGHS,
encoded as Wolff, Topcu and Murray do ("Optimization-based trajectory generation with
linear temporal logic specifications", ICRA 2014), planner ``milp-ltl``.

No abstraction: the labels and the obstacles are polytopes stated directly on the
continuous positions, as Wolff et al. encode their atomic propositions (Section IV,
"mixed-integer encoding of polyhedra"), and the mission is the linear encoding of Biere
et al. over continuous [0, 1] variables (their Section V). For a horizon L:

* the trajectory: states x_0..x_L, inputs u_0..u_{L-1}, the start, the dynamics, the
  input and state bounds, and each position within the box the robot can reach from the
  start in t steps (:class:`ReachBoxes`, an LP per axis and step: it makes every big-M
  tight and drops the constraints that cannot bind);
* **obstacles** (each convex piece {H p <= h}): at each sample (the sample reading) or
  for each segment (the segment reading: both ends on the outer side of one edge, the
  classical sufficient condition of Richards and How, ACC 2002), a binary per edge that
  can separate within the reachable box, at least one of them set, with
  ``H_i p >= h_i - M_i (1 - d_i)``; an edge that separates the whole box drops the
  obstacle there;
* **labels** at their margins (:mod:`plansynth.reach.offsets`): ``a`` at step t is one
  binary z with ``H p <= h - r + M (1 - z)`` (the shrunk label, at both ends of the
  segment in the segment reading); ``!a`` is a binary per edge of the grown label, as for
  obstacles; a non-convex label (margin 0) is the union of its convex pieces (``a``) and
  of those of its complement in the workspace (``!a``), a binary per piece;
* the **successor of the last position** (Wolff et al.'s loop variables): binaries
  ``stay`` (a finite plan: at rest, ``(A - I) x_L + B u = 0`` for an admissible u; or a
  free end, the word ending at L) and ``loop_j`` with ``x_L = x_{j-1}`` (big-M);
* the **mission** (negation normal form, bounded operators unrolled) as continuous
  variables P[f, t] in [0, 1], t = 0..L + 1 (``P[a, t] + P[!a, t] <= 1``: a position on
  a label's edge is read as in or as out, as the checker reads it), with the one-sided rows of its recursive
  definition (``P[a & b, t] <= P[a, t]``, ``P[a U b, t] <= P[b, t] + P[a, t]``, ...; in
  negation normal form one direction suffices), position L + 1 taking the values of the
  loop's target, and the eventuality rows of the linear encoding; ``P[mission, 0] = 1``.

The binaries are those of the propositions, the obstacles and the loop only (Wolff et
al.'s count: linear in the horizon, independent of any decomposition). Horizons are
tried upwards from the proved lower bound of
:func:`~plansynth.reach.mission.horizon.horizon_lower_bound` over the regions one step
can connect (a bound for every trajectory, so for this model's plans too), as in the lazy
planner; the first with a solution is the shortest. ``milp-ltl-oneshot`` (``one_shot``) is
Wolff et al.'s setting as published: one MILP at the fixed horizon K = ``max_horizon``
(a plan of exactly K steps, not the shortest; no solution there proves nothing about
shorter horizons, so it is ``unknown`` unless the label proof decides).

**What its answers mean.** In the sample reading the model is exact: every trajectory
whose samples satisfy the mission is a solution, so no solution at L refutes L for the
problem, and the first horizon with one is the minimum. In the segment reading the
edge condition is sufficient, not necessary (a segment that passes an obstacle's corner
diagonally is excluded): the plans are valid, the refutations no proof. ``infeasible``
needs the labels' geometry's proof (:func:`~plansynth.reach.mission.proof.label_proof`)
or, in the sample reading, every horizon refuted. The trajectory is not taken from the
MILP (big-M rows slip by the integrality tolerance): with every binary fixed at its
rounded value the model is an LP, solved again.

The polytopes are :mod:`plansynth.reach.mission.milp_geometry`, the model of one horizon
:mod:`plansynth.reach.mission.milp_model`; this module solves one horizon and runs the
horizons.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import asdict
from typing import Any

import highspy
import numpy as np

from plansynth.budget import Budget, BudgetExhausted
from plansynth.errors import InvalidOption
from plansynth.reach.highs import new_highs
from plansynth.reach.lazy.claims import EXACT_SAMPLES
from plansynth.reach.mission.horizon import timed_horizon_bound
from plansynth.reach.mission.labels import LabelledAbstraction
from plansynth.reach.mission.ltl import Formula, parse
from plansynth.reach.mission.milp_geometry import MilpGeometry, ReachBoxes
from plansynth.reach.mission.milp_model import MissionMilp, mission_milp
from plansynth.reach.mission.options import MilpLtlOptions
from plansynth.reach.mission.proof import NOT_A_PROOF, timed_label_proof
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachResult, ReachStatus
from plansynth.reach.trajectory import Trajectory

__all__ = [
    "MissionMilp",
    "MilpGeometry",
    "ReachBoxes",
    "mission_milp",
    "plan_milp_ltl",
    "solve_mission_horizon",
    "MilpLtlOptions",
]


def solve_mission_horizon(
    problem: ReachProblem,
    planning: ReachProblem,
    geometry: MilpGeometry,
    formula: Formula,
    L: int,
    boxes: ReachBoxes,
    *,
    semantics: str = "any",
    seconds: float = math.inf,
) -> tuple[str, Trajectory | None, int | None, dict]:
    """One MILP at horizon L (:func:`mission_milp`), then the LP with its binaries fixed:
    ``(status, trajectory, loop_start, stats)`` with status ``found`` / ``infeasible`` /
    ``unknown`` (time limit, or a solution the LP does not confirm)."""
    t0 = time.perf_counter()
    model = mission_milp(problem, planning, geometry, formula, L, boxes, semantics=semantics)
    if model is None:
        return "infeasible", None, None, {"binaries": 0, "mip_nodes": 0, "build_seconds": time.perf_counter() - t0}
    h = new_highs()
    if math.isfinite(seconds):
        h.setOptionValue("time_limit", max(1e-3, float(seconds)))
    h.passModel(model.lp)
    build = time.perf_counter() - t0
    t0 = time.perf_counter()
    h.run()
    status = h.getModelStatus()
    S = highspy.HighsModelStatus
    stats = {
        "binaries": int(len(model.binaries)),
        "mip_nodes": int(h.getInfo().mip_node_count),
        "solve_seconds": time.perf_counter() - t0,
        "build_seconds": build,
    }
    if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
        return "infeasible", None, None, stats
    if status != S.kOptimal:
        return "unknown", None, None, stats
    col = np.asarray(h.getSolution().col_value)
    chosen = max(model.sels, key=lambda sj: col[sj[0]])
    loop_start = chosen[1] - 1 if chosen[2] else None
    traj = _polish(model, col, seconds - (time.perf_counter() - t0), loop_start)
    if traj is None:
        stats["unconfirmed"] = True
        return "unknown", None, loop_start, stats
    return "found", traj, loop_start, stats


def _polish(model: MissionMilp, col: np.ndarray, seconds: float, loop_start: int | None) -> Trajectory | None:
    """The LP of the model with every binary fixed at its rounded value: its solution
    keeps each constraint the binaries switch on exactly (up to the LP's tolerance), not
    up to the integrality tolerance times a big-M."""
    lp = model.lp
    lo, hi = np.array(lp.col_lower_, float), np.array(lp.col_upper_, float)
    fixed = np.round(col[model.binaries])
    lo[model.binaries] = hi[model.binaries] = fixed
    lp.col_lower_, lp.col_upper_ = lo, hi
    lp.integrality_ = []
    h = new_highs()
    if math.isfinite(seconds):
        h.setOptionValue("time_limit", max(1e-3, float(seconds)))
    h.passModel(lp)
    h.run()
    if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
        return None
    x = np.asarray(h.getSolution().col_value)
    L, n, m = model.horizon, model.n, model.m
    states = x[: (L + 1) * n].reshape(L + 1, n).copy()
    inputs = x[(L + 1) * n : (L + 1) * n + L * m].reshape(L, m).copy()
    if loop_start is not None:
        states[L] = states[loop_start]  # the closure holds to tolerance; make it exact
    return Trajectory(states=states, inputs=inputs)


# --------------------------------------------------------------------------- the planner


def plan_milp_ltl(
    problem: ReachProblem,
    budget: Budget = Budget(),
    options: MilpLtlOptions | None = None,
    progress: Callable[[int, int], None] | None = None,
    *,
    labelled: LabelledAbstraction | None = None,
) -> ReachResult:
    """MILPs at horizons up to max_horizon within ``budget`` (not yet validated:
    :func:`plansynth.reach.solve` does that, with the mission checker); ``options``
    (:class:`~plansynth.reach.mission.options.MilpLtlOptions`): ``horizon_bound``: from
    the proved lower bound of :func:`~plansynth.reach.mission.horizon.horizon_lower_bound`
    on, as the lazy planner; ``one_shot``: one MILP at ``max_horizon`` only (Wolff et
    al.'s fixed horizon; see the module doc), planner ``milp-ltl-oneshot``."""
    from plansynth.reach.mission.planner import mission_record, mission_setup

    opts = MilpLtlOptions() if options is None else options
    one_shot = opts.one_shot
    name = "milp-ltl-oneshot" if one_shot else "milp-ltl"
    if problem.mission is None:
        raise InvalidOption(
            name, "planner", "plans LTL missions, and this problem has none (plan it with a reach-avoid planner)"
        )
    t_start = time.perf_counter()
    clock = budget.clock()
    L_max = problem.max_horizon if opts.max_horizon is None else int(opts.max_horizon)
    timings = {"abstraction": 0.0, "bounds": 0.0, "milp": 0.0, "lp": 0.0}
    formula = parse(problem.mission)
    segment = problem.reading == "segment"
    record = {
        **asdict(opts),
        "max_horizon": L_max,
        "budget": {"seconds": budget.seconds, "iterations": budget.iterations},
    }
    counters: dict[str, Any] = {"milp_calls": 0, "mip_nodes": 0, "binaries": 0}

    def finish(status, horizon, message, traj=None, loop_start=None, minimal=None) -> ReachResult:
        timings["total"] = time.perf_counter() - t_start
        counters["iterations"] = clock.iterations
        if minimal is not None:
            counters["minimal"] = minimal
            counters["minimal_relative_to"] = "problem" if not segment else "model"
        rec = mission_record(problem, None)
        if traj is not None:
            rec.update(semantics="finite" if loop_start is None else "lasso", loop_start=loop_start)
        return ReachResult(
            status=status,
            solver=name,
            seconds=timings["total"],
            trajectory=traj,
            regions=None,
            horizon=horizon,
            counters=counters,
            timings=timings,
            options=record,
            message=message,
            guarantee="segments" if segment else "samples",
            mission=rec,
        )

    try:
        # the label refinement serves the geometry's proof and the horizon bound (over the
        # regions one step can connect: a bound for every trajectory), not the model
        planning, labelled, graph, earliest = mission_setup(
            problem, clock, timings, L_max, labelled=labelled, lower_bound=opts.lower_bound, steps=True
        )
        counters["regions"] = labelled.n_regions
        with clock.phase("the model's polytopes"):
            geometry = MilpGeometry.of(problem, planning)
        boxes = ReachBoxes(planning)
    except BudgetExhausted as exc:
        return finish(ReachStatus.UNKNOWN, None, str(exc))
    # (graph: the regions one step can connect, in either reading)
    proved, why = timed_label_proof(problem, labelled, timings, counters, clock, steps=graph.adjacency)
    if proved:
        return finish(ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max} (and beyond): {why}")
    L0 = 0
    if one_shot:
        L0 = L_max
    elif opts.horizon_bound:
        L0 = timed_horizon_bound(graph, labelled, formula, earliest, L_max, timings, counters, clock, end=problem.end)
    L = L0
    exact = not segment and labelled.abstraction.exact
    try:
        for L in clock.steps(range(L0, L_max + 1), progress=progress, what="the MILP at horizon"):
            t0 = time.perf_counter()
            with clock.phase(f"the MILP at horizon {L}"):
                status, traj, loop_start, stats = solve_mission_horizon(
                    problem, planning, geometry, formula, L, boxes, semantics=opts.semantics, seconds=clock.remaining()
                )
            timings["milp"] += time.perf_counter() - t0
            timings["milp_solve"] = timings.get("milp_solve", 0.0) + stats.get("solve_seconds", 0.0)
            counters["milp_calls"] += 1
            counters["mip_nodes"] += stats.get("mip_nodes", 0)
            counters["binaries"] = stats.get("binaries", 0)
            counters["reach_box_lps"] = boxes.lp_calls
            if status == "unknown":
                why_unknown = (
                    "its binaries fixed, the LP has no solution (numerically borderline)"
                    if stats.get("unconfirmed")
                    else "HiGHS stopped without an answer (time limit)"
                )
                return finish(ReachStatus.UNKNOWN, L, f"the MILP at horizon {L}: {why_unknown}")
            if status == "found":
                if one_shot:
                    return finish(
                        ReachStatus.FOUND,
                        L,
                        f"found at horizon {L} (one MILP at the max horizon: a plan of exactly that many "
                        "steps, not the shortest)",
                        traj,
                        loop_start,
                        minimal=False,
                    )
                return finish(ReachStatus.FOUND, L, f"found at horizon {L}", traj, loop_start, minimal=exact)
    except BudgetExhausted as exc:
        said = str(exc) if exc.phase.startswith("before") or "horizon" in exc.phase else f"{exc} at horizon {L}"
        return finish(ReachStatus.UNKNOWN, L, said)
    if one_shot:
        return finish(
            ReachStatus.UNKNOWN,
            L_max,
            f"no MILP solution at horizon {L_max} (one MILP at the max horizon: shorter horizons not "
            f"tried, no proof); {NOT_A_PROOF} ({why})",
        )
    if exact:
        return finish(
            ReachStatus.INFEASIBLE, L_max, f"infeasible up to horizon {L_max}: every horizon refuted ({EXACT_SAMPLES})"
        )
    counters["abstraction_refuted"] = L_max
    return finish(
        ReachStatus.UNKNOWN,
        L_max,
        f"no MILP solution at any horizon up to {L_max} (segments: each kept beyond one edge of each "
        f"obstacle, a sufficient condition); {NOT_A_PROOF} ({why})",
    )
