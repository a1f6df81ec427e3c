"""Exact segment transitions for missions (plansynth.reach.mission.exact, the option
``exact_segments`` in the segment reading): its claims about the problem against an
independent MILP over the same segment reading (tests/reach/mission_exact_milp.py, whose
plans are plans of the problem: sufficient conditions), and every clause its loop learns
against an LP written here from scratch; the examples' proved minima."""

from __future__ import annotations

from dataclasses import replace

import highspy
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, event, given, settings
from mission_exact_milp import shortest_horizon
from test_mission_milp import _touching_labels, sample_missions

from plansynth import Budget
from plansynth.reach import ReachStatus, load, solve
from plansynth.reach.lazy.conflict import Conflict
from plansynth.reach.lazy.segments import DENOM
from plansynth.reach.lazy.segtheory import ClosedConflict, SegmentTheory
from plansynth.reach.mission.check import check_mission
from plansynth.reach.mission.exact import ExactMissionDisPlan
from plansynth.reach.mission.labels import label_abstraction, planning_problem
from plansynth.reach.mission.options import MissionOptions
from plansynth.reach.mission.planner import plan_mission

EXACT = MissionOptions(exact_segments=True)


@settings(max_examples=12, deadline=None, suppress_health_check=list(HealthCheck))
@given(sample_missions())
def test_exact_segment_claims_hold_for_the_problem(p):
    """A horizon the exact search refutes "for the problem" has no plan of the oracle
    MILP (each of whose plans is a plan of the problem), so a proved minimum is at most
    the oracle's least horizon and ``infeasible`` means the oracle has no plan at any
    horizon up to the maximum; every plan found passes the validator and the checker."""
    p = replace(p, reading="segment")
    assume(not _touching_labels(p))
    r = solve(p, "lazy-smt", Budget(seconds=90), exact_segments=True)
    upper = shortest_horizon(p, p.max_horizon, segments=True)
    event(f"{r.status.value}, oracle {'none' if upper is None else 'found'}")
    if r.status is ReachStatus.FOUND:
        assert r.validated is True and r.mission["ok"] is True, r.message
        assert check_mission(p, r.trajectory, r.mission["loop_start"]).ok
        if r.counters.get("minimal_relative_to") == "problem":
            assert upper is None or r.horizon <= upper, (r.horizon, upper)
    elif r.status is ReachStatus.INFEASIBLE:
        assert upper is None, (upper, r.message)
    else:  # unknown: a budget or plans given up without a proof, which it says
        assert r.counters.get("segment_undecided") or "budget" in r.message or "ran out" in r.message, r.message
    if upper is not None and r.counters.get("segment_undecided", 0) == 0 and r.status is not ReachStatus.UNKNOWN:
        assert r.status is ReachStatus.FOUND and r.horizon <= upper, (r.status, r.horizon, upper)


def _refuted(pp, regions, c: Conflict, closure: tuple | None) -> bool:
    """Is the conflict's claim an LP infeasibility? States over its span (from 0 with the
    start), dynamics, input and state bounds, each sample (t, r) in region r, each point
    (t, f, r) at fraction f / DENOM of segment t in region r, and the closure (x_N = x_k,
    or some admissible input keeping x_N). Written apart from the point LP."""
    dyn = pp.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = list(dyn.position)
    times = [t for t, _ in c.literals] + [t for t, _, _ in c.vias] + [t + 1 for t, _, _ in c.vias]
    lo = 0 if c.anchored_start or not times else min(times)
    hi = max(times, default=0)
    if closure is not None:
        hi = c.horizon
        if closure[0] == "loop":
            lo = min(lo, int(closure[1]))
    T = hi - lo + 1
    h = highspy.Highs()
    h.silent()

    def row(terms, lower: float, upper: float) -> None:
        """sum of coefficient * column over ``terms`` (zero coefficients left out) within bounds."""
        idx: dict[int, float] = {}
        for coef, var in terms:
            if coef != 0.0:
                idx[var.index] = idx.get(var.index, 0.0) + float(coef)
        cols = np.array(list(idx), dtype=np.int32)
        h.addRow(lower, upper, len(cols), cols, np.array([idx[i] for i in cols.tolist()], float))

    slo, shi = pp.state_box
    slo = np.where(np.isfinite(slo), slo, -1e6)
    shi = np.where(np.isfinite(shi), shi, 1e6)
    x = [[h.addVariable(float(slo[i]), float(shi[i])) for i in range(n)] for _ in range(T)]
    u = [[h.addVariable(-pp.input_bound, pp.input_bound) for _ in range(m)] for _ in range(T)]
    if c.anchored_start:
        for i in range(n):
            row([(1.0, x[0][i])], float(pp.start[i]), float(pp.start[i]))

    def step(now, after, inp) -> None:  # after = A now + B inp
        for i in range(n):
            terms = [(1.0, after[i])] + [(-A[i, j], now[j]) for j in range(n)] + [(-B[i, j], inp[j]) for j in range(m)]
            row(terms, 0.0, 0.0)

    for k in range(T - 1):
        step(x[k], x[k + 1], u[k])

    def inside(t: int, lam: float, r: int) -> None:
        """The point (1 - lam) p_t + lam p_{t+1} in region r."""
        reg = regions[r]
        for H, b in zip(np.asarray(reg.H, float), np.asarray(reg.h, float)):
            terms = [((1 - lam) * H[a], x[t - lo][i]) for a, i in enumerate(pos)]
            if lam:
                terms += [(lam * H[a], x[t + 1 - lo][i]) for a, i in enumerate(pos)]
            row(terms, -highspy.kHighsInf, float(b))

    for t, r in c.literals:
        inside(t, 0.0, r)
    for t, f, r in c.vias:
        inside(t, f / DENOM, r)
    if closure is not None and closure[0] == "loop":
        for i in range(n):
            row([(1.0, x[hi - lo][i]), (-1.0, x[int(closure[1]) - lo][i])], 0.0, 0.0)
    elif closure is not None:  # at rest: x_N = A x_N + B u
        step(x[hi - lo], x[hi - lo], u[T - 1])
    h.run()
    return h.getModelStatus() == highspy.HighsModelStatus.kInfeasible


@settings(max_examples=10, deadline=None, suppress_health_check=list(HealthCheck))
@given(sample_missions())
def test_every_clause_the_exact_mission_loop_learns_is_refuted_by_an_lp(p):
    """Every conflict the exact loop learns (over samples and points along segments, with
    the loop or rest closure when it needs one) is an LP infeasibility, checked here from
    scratch: no trajectory realises its literals, so the clause excludes no plan of the
    problem. Plans given up without a proof are left out (no refutation; the result then
    claims nothing)."""
    p = replace(p, reading="segment")
    la = label_abstraction(p)
    regions = la.abstraction.regions
    pp = planning_problem(p)
    learned: list[tuple[Conflict, tuple | None]] = []
    given_up: set[int] = set()
    learn, check = ExactMissionDisPlan.learn, SegmentTheory.check_closed

    def recording_learn(self, c):
        if isinstance(c, ClosedConflict) and id(c) not in given_up:
            learned.append((c.conflict, c.closure))
        elif isinstance(c, Conflict) and id(c) not in given_up:
            learned.append((c, None))
        return learn(self, c)

    def recording_check(self, plan, *a, **kw):
        before = self.undecided
        answer = check(self, plan, *a, **kw)
        if self.undecided > before:
            given_up.add(id(answer))
        return answer

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(ExactMissionDisPlan, "learn", recording_learn)
        mp.setattr(SegmentTheory, "check_closed", recording_check)
        plan_mission(p, Budget(seconds=60), EXACT, labelled=la)
    event(f"{len(learned) > 0} clauses learned")
    for c, closure in learned:
        assert _refuted(pp, regions, c, closure), (c, closure)


@pytest.mark.parametrize(
    "name, decomposition, exact",
    [("mission-readings", 18, 18), ("mission-avoid-until", 25, 24), ("mission-patrol", 13, 12)],
)
def test_the_examples_minima_are_proved_for_the_problem(name, decomposition, exact):
    """Through the label-refined decomposition (one region per step) the shortest plans
    are claimed minimal for the decomposition only; with exact segment transitions the
    search finds the shorter ones where they exist and proves them minimal for the
    problem."""
    p = load(f"examples/reach/{name}.yaml")
    plain = solve(p, "lazy-smt", Budget(seconds=120))
    assert plain.horizon == decomposition and plain.counters["minimal_relative_to"] == "decomposition"
    r = solve(p, "lazy-smt", Budget(seconds=120), exact_segments=True)
    assert r.status is ReachStatus.FOUND and r.horizon == exact and r.validated is True, r.message
    assert r.mission["ok"] is True and r.counters["minimal_relative_to"] == "problem"
    assert r.counters["exact_segments"] == "on"


def test_stepping_stones_read_along_segments_are_infeasible_for_the_problem():
    """Read along segments, ``G (bank | far | s1 | ..)`` asks every step's segment to lie
    in one label, and a step from the bank to a stone crosses water: no trajectory
    satisfies it. Through the decomposition that is ``unknown`` (not a proof); with exact
    transitions the same refutation is about the problem, and under ``auto`` (the
    default) the decomposition's refutation is continued exactly to reach it."""
    from plansynth.reach.lazy.claims import EXACT_SEGMENTS
    from plansynth.reach.mission.literature import literature_problem

    p = replace(literature_problem("stones-4"), reading="segment")
    plain = solve(p, "lazy-smt", Budget(seconds=60), exact_segments=False)
    assert plain.status is ReachStatus.UNKNOWN and "not a proof" in plain.message
    assert plain.counters["transitions"] == "regions"
    for mode in (True, "auto"):
        r = solve(p, "lazy-smt", Budget(seconds=60), exact_segments=mode)
        assert r.status is ReachStatus.INFEASIBLE and EXACT_SEGMENTS in r.message, r.message
        assert r.counters["transitions"] == "segments"
    assert r.counters["decomposition_refuted"] == p.max_horizon
