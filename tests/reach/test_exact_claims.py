"""Every ``infeasible`` and every minimal horizon claimed for the problem is checked
against an independent exact formulation: the big-M MILP of
:func:`reach_oracles.oracle_feasible` over the spec's semantics, which shares no code
with the planner (no decomposition, no regions).

* samples only (``segment_safe=False``): the oracle is exact, and the lazy loop's search
  is too (steps between any two regions one step can connect,
  :func:`~plansynth.reach.lazy.bounds.step_adjacency`): its ``infeasible`` means no
  trajectory at any horizon up to ``max_horizon``, and a horizon claimed minimal for
  the problem (``counters["minimal_relative_to"] == "problem"``) is the oracle's
  smallest feasible horizon;
* segment-safe: the oracle keeps both end points of every segment beyond one face of
  each convex obstacle, which is sufficient for the segment to be safe, so every
  horizon the planner refutes for the problem must be infeasible there too; in a world
  of boxes the planner's own plans (consecutive samples in one free box) are solutions
  of the oracle as well, so a horizon claimed minimal for the problem is its minimum.
  A minimum claimed only through the decomposition (``"decomposition"``) may be larger
  than the oracle's: the public cases below show it, and that the claim says so.

* segment-safe with exact transitions (``exact_segments=True``): the oracle is
  :func:`reach_oracles.oracle_exact`, exact for the spec's segment semantics up to a
  depth of 1e-7 (a MILP keeping points along every segment free, refined where a
  solution's segment still cuts an obstacle, and the face MILP for solutions): the
  planner's ``infeasible`` means no oracle solution at any horizon up to L, a horizon
  claimed minimal for the problem is the oracle's minimum, and every clause the
  planner learns (conflicts naming points along segments too) holds for every
  segment-safe trajectory: each is refuted by an LP written here, and none excludes an
  oracle's witness.

Workspaces: random boxes (:func:`reach_oracles.problems`' generator without the
non-convex polygons), walls thinner than one step (samples jump them: region-skipping
steps) with gaps narrower than one step (thin gaps), a convex triangle among them,
staggered walls whose ends a segment may cut past, and 3-D floors with holes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from reach_oracles import oracle_exact, oracle_feasible, oracle_minimum

from plansynth.reach import ReachStatus, solve
from plansynth.reach.abstraction import abstract
from plansynth.reach.dynamics import integrator_chain
from plansynth.reach.families import random_workspace
from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.geometry import Box, Polygon
from plansynth.reach.problem import ReachProblem

#: Zero-width slits: a position on a face two obstacles share, or on an obstacle's face
#: flush with the workspace's boundary, is outside every obstacle's interior (the
#: spec's words, which the oracle and the validator follow), but the decomposition's
#: regions are full-dimensional and leave such faces out: through a slit the planner's
#: claims hold only for the free space without its zero-width parts. The generated
#: obstacles overlap and reach past the workspace, so that no slit arises.
SLITS = "obstacles overlap by 0.01 and reach 0.1 beyond the workspace"
CLAIMS = Path(__file__).resolve().parents[2] / "examples" / "reach" / "claims"
PROPS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _problem(ws: Box, obstacles: list, goal: Box, start_pos: list[float], order: int) -> ReachProblem:
    dim = ws.dim
    dyn = integrator_chain(order, dim, 1.0 if order == 1 else 0.5)
    start = np.zeros(dyn.n_states)
    start[:dim] = start_pos
    bounds = None
    if order == 2:
        bounds = Box(tuple(ws.lo) + (-2.0,) * dim, tuple(ws.hi) + (2.0,) * dim)
    return ReachProblem(
        workspace=ws,
        obstacles=tuple(obstacles),
        goal=goal,
        dynamics=dyn,
        start=start,
        input_bound=1.0,
        state_bounds=bounds,
    )


@st.composite
def thin_walls(draw) -> ReachProblem:
    """A wall across [0, 10]^2, 0.05..1.5 thick (below one step: samples may jump it),
    with up to two gaps 0.05..1.2 wide (below one step: a segment must pass within the
    gap's width), sometimes a triangle; start below, goal above."""
    y0 = draw(st.floats(3.0, 6.0))
    thick = draw(st.floats(0.05, 1.5))
    cuts = sorted(draw(st.lists(st.floats(0.5, 9.0), min_size=0, max_size=2)))
    widths = [draw(st.floats(0.05, 1.2)) for _ in cuts]
    obstacles: list = []
    x = -0.1  # (0.1 beyond the workspace: no zero-width slit at its boundary, see SLITS)
    for c, w in zip(cuts, widths):
        if c > x + 1e-3:
            obstacles.append(Box((round(x, 3), round(y0, 3)), (round(c, 3), round(y0 + thick, 3))))
        x = max(x, c + w)
    if x < 10.0 - 1e-3:
        obstacles.append(Box((round(x, 3), round(y0, 3)), (10.1, round(y0 + thick, 3))))
    if draw(st.booleans()):
        cx = draw(st.floats(2.0, 8.0))
        obstacles.append(Polygon(((cx - 1.0, 8.0), (cx + 1.0, 8.0), (cx, 9.0))))
    sx, gx = draw(st.floats(0.5, 9.5)), draw(st.floats(0.8, 9.2))
    sy = draw(st.floats(0.5, y0 - 0.5))
    goal = Box((round(gx - 0.4, 3), 9.2), (round(gx + 0.4, 3), 9.9))
    return _problem(Box((0.0, 0.0), (10.0, 10.0)), obstacles, goal, [sx, sy], draw(st.sampled_from([1, 2])))


@st.composite
def floors(draw) -> ReachProblem:
    """[0, 4]^3 with one or two floors (0.1..1.2 thick), each with a box hole; start
    below, goal above (samples may jump a thin floor, a segment must pass its hole)."""
    obstacles: list = []
    levels = sorted(draw(st.lists(st.floats(0.8, 3.0), min_size=1, max_size=2)))
    top = None  # the floor below's top
    for z in levels:
        t = draw(st.floats(0.1, 1.2))
        hx, hy = draw(st.floats(0.2, 3.0)), draw(st.floats(0.2, 3.0))
        w = draw(st.floats(0.1, 0.8))
        z0, z1 = round(z, 3), round(min(z + t, 3.4), 3)
        if top is not None and z0 <= top:  # floors that meet overlap by 0.01 (no seam between them)
            z0 = round(min(z0, top - 0.01), 3)
        top = z1
        a, b, c, d = round(hx, 3), round(min(hx + w, 3.9), 3), round(hy, 3), round(min(hy + w, 3.9), 3)
        # the pieces overlap by 0.01: on a face two obstacles share, a point is outside
        # each one's interior but inside their union's, and the spec (outside every
        # obstacle's interior) would let a trajectory pass through the seam
        # ... and reach 0.1 beyond the workspace: a face flush with the workspace's
        # boundary would leave a zero-width slit between them (see SLITS)
        obstacles += [
            Box((-0.1, -0.1, z0), (a, 4.1, z1)),
            Box((b, -0.1, z0), (4.1, 4.1, z1)),
            Box((a - 0.01, -0.1, z0), (b + 0.01, c, z1)),
            Box((a - 0.01, d, z0), (b + 0.01, 4.1, z1)),
        ]
    obstacles = [o for o in obstacles if all(l < h for l, h in zip(o.lo, o.hi))]
    sx, sy = draw(st.floats(0.2, 3.8)), draw(st.floats(0.2, 3.8))
    gx, gy = draw(st.floats(0.4, 3.6)), draw(st.floats(0.4, 3.6))
    goal = Box((round(gx - 0.3, 3), round(gy - 0.3, 3), 3.6), (round(gx + 0.3, 3), round(gy + 0.3, 3), 3.9))
    return _problem(Box((0.0,) * 3, (4.0,) * 3), obstacles, goal, [sx, sy, 0.3], draw(st.sampled_from([1, 2])))


@st.composite
def box_worlds(draw) -> ReachProblem:
    seed = draw(st.integers(0, 10**6))
    dim = draw(st.sampled_from([2, 2, 3]))
    order = draw(st.sampled_from([1, 2]))
    try:
        return random_workspace(
            seed, draw(st.integers(1, 5)), dim=dim, polygons=False, order=order, dt=1.0 if order == 1 else 0.5
        )
    except RuntimeError:  # no free point for start or goal
        return random_workspace(seed % 97, 2, dim=dim, polygons=False, order=order)


@st.composite
def staggered_walls(draw) -> ReachProblem:
    """Two or three walls (0.05..0.8 thick) from alternate sides of [0, 8]^2, each
    leaving a gap of 0.3..2 at its end: the shortest segment-safe route turns around the
    walls' ends, where a segment may cut past a corner (its ends beyond two different
    faces of the wall), which the face formulation forbids."""
    walls = draw(st.integers(2, 3))
    obstacles: list = []
    for k in range(walls):
        y = 1.5 + k * 6.0 / walls + draw(st.floats(0.0, 0.5))
        thick = draw(st.floats(0.05, 0.8))
        gap = draw(st.floats(0.3, 2.0))
        if k % 2 == 0:
            obstacles.append(Box((-0.1, round(y, 3)), (round(8.0 - gap, 3), round(y + thick, 3))))
        else:
            obstacles.append(Box((round(gap, 3), round(y, 3)), (8.1, round(y + thick, 3))))
    goal = Box((0.5, 7.4), (1.5, 7.9))
    return _problem(
        Box((0.0, 0.0), (8.0, 8.0)), obstacles, goal, [draw(st.floats(0.5, 7.5)), 0.5], draw(st.sampled_from([1, 2]))
    )


worlds = st.one_of(thin_walls(), floors(), box_worlds())
#: Worlds for exact segment transitions (2-D ones: the oracle's corner case is 2-D).
segment_worlds = st.one_of(thin_walls(), staggered_walls(), box_worlds(), floors())


def _solve(p: ReachProblem, L: int, segment_safe: bool, search: str):
    """``search``: the lazy planner's horizon search, or ``"milp"`` (the region MILP)."""
    try:
        if search == "milp":
            return solve(p, "milp", max_horizon=L, segment_safe=segment_safe)
        # (one region per step: the decomposition's claims; the exact ones are
        # test_exact_segment_claims_hold_for_the_problem's)
        return solve(
            p, "lazy-smt", max_horizon=L, segment_safe=segment_safe, horizon_search=search, exact_segments=False
        )
    except Exception as exc:  # pragma: no cover - a planner crash is a failure with its problem
        raise AssertionError(f"the planner failed on {p!r}") from exc


def _check_samples(p: ReachProblem, L: int, search: str) -> None:
    r = _solve(p, L, False, search)
    exact = abstract(p).exact
    event(f"samples: {r.status.value}, minimal for {r.counters.get('minimal_relative_to')}")
    if r.status is ReachStatus.FOUND:
        assert r.validated is True
        if r.counters.get("minimal_relative_to") == "problem":
            for h in range(r.horizon):
                assert oracle_feasible(p, h, segments=False) is False, (h, r.horizon, r.message)
        assert oracle_feasible(p, r.horizon, segments=False) is True
    elif r.status is ReachStatus.INFEASIBLE:
        for h in range(L + 1):
            assert oracle_feasible(p, h, segments=False) is False, (h, r.message)
    else:  # the exact search refutes or finds: never "unknown" on these small instances
        assert not exact, r.message
    if exact and r.status is ReachStatus.FOUND and search in ("linear", "milp", "minimal"):
        assert r.counters["minimal_relative_to"] == "problem"


@PROPS
@given(worlds, st.integers(4, 14), st.sampled_from(["linear", "window", "milp", "minimal"]))
def test_samples_only_claims_hold_for_the_problem(p: ReachProblem, L: int, search: str) -> None:
    """Samples only (the lazy planner's two horizon searches and the region MILP):
    ``infeasible`` means the oracle has no trajectory at any horizon up to L; a horizon
    claimed minimal for the problem is the oracle's minimum; the linear search and the
    MILP always claim it (every shorter horizon refuted by an exact search), and so does
    the minimal search (windows, re-timing, probes)."""
    _check_samples(p, L, search)


def _box_world(p: ReachProblem) -> bool:
    return all(isinstance(o, Box) for o in p.obstacles)


@PROPS
@given(worlds, st.integers(4, 14), st.sampled_from(["linear", "milp", "minimal"]))
def test_segment_safe_claims_hold_for_the_problem(p: ReachProblem, L: int, search: str) -> None:
    """Segment-safe: a refutation for the problem (``infeasible``, or a horizon claimed
    minimal for the problem) is one for the face formulation, which is sufficient for
    segment safety; in a box world the planner's plan is a face-formulation solution."""
    r = _solve(p, L, True, search)
    event(f"segments: {r.status.value}, minimal for {r.counters.get('minimal_relative_to')}")
    if r.status is ReachStatus.FOUND:
        assert r.validated is True and r.segment_safe is True
        if r.counters.get("minimal_relative_to") == "problem":
            for h in range(r.horizon):
                assert oracle_feasible(p, h, segments=True) is False, (h, r.horizon, r.message)
        if _box_world(p):
            assert oracle_feasible(p, r.horizon, segments=True) is True
    elif r.status is ReachStatus.INFEASIBLE:
        for h in range(L + 1):
            assert oracle_feasible(p, h, segments=True) is False, (h, r.message)
    else:
        assert "not a proof" in r.message or "budget" in r.message, r.message


@PROPS
@given(worlds, st.integers(4, 12))
def test_proved_segment_claims_hold_for_the_problem(p: ReachProblem, L: int) -> None:
    """``prove=True`` (the relaxation MILP of lazy/relaxation.py): every claim for the
    problem, now also above the proved bound, is a refutation for the face oracle."""
    r = solve(p, "lazy-smt", max_horizon=L, prove=True, exact_segments=False)
    event(f"prove: {r.status.value}, {r.counters.get('relaxation')}")
    if r.status is ReachStatus.FOUND:
        assert r.validated is True and r.segment_safe is True
        if r.counters.get("minimal_relative_to") == "problem":
            for h in range(r.horizon):
                assert oracle_feasible(p, h, segments=True) is False, (h, r.horizon, r.message)
    elif r.status is ReachStatus.INFEASIBLE:
        for h in range(L + 1):
            assert oracle_feasible(p, h, segments=True) is False, (h, r.message)


@PROPS
@given(worlds, st.integers(1, 12), st.sampled_from([1, 2, 4]))
def test_relaxation_admits_every_face_oracle_solution(p: ReachProblem, h: int, k: int) -> None:
    """The relaxation is necessary for segment safety, so it has a solution whenever the
    face oracle (sufficient for segment safety) has one; with k = 1 it is the samples
    oracle exactly."""
    from plansynth.reach.lazy.relaxation import relaxation_feasible

    relaxed = relaxation_feasible(p, h, subdivisions=k, seconds=60)
    if oracle_feasible(p, h, segments=True):
        assert relaxed is True
    if k == 1:
        assert relaxed is oracle_feasible(p, h, segments=False)
    event(f"relaxation k={k}: {relaxed}")


# -- exact segment transitions -------------------------------------------------------

EXACT_PROPS = settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])


#: seconds per exact-segments solve: a random world may take the search long (the
#: claims are checked when it answers; out of budget it says so)
EXACT_BUDGET = 10.0


def _exact(p: ReachProblem, L: int, search: str):
    from plansynth import Budget

    try:
        return solve(
            p, "lazy-smt", Budget(seconds=EXACT_BUDGET), max_horizon=L, exact_segments=True, horizon_search=search
        )
    except Exception as exc:  # pragma: no cover - a planner crash is a failure with its problem
        raise AssertionError(f"the planner failed on {p!r}") from exc


@EXACT_PROPS
@given(segment_worlds, st.integers(6, 16), st.sampled_from(["linear", "minimal", "window"]))
def test_exact_segment_claims_hold_for_the_problem(p: ReachProblem, L: int, search: str) -> None:
    """Exact segment transitions: ``infeasible`` means the exact oracle has no
    segment-safe trajectory at any horizon up to L; a horizon claimed minimal for the
    problem has none below it; the plan found is one (the validator says so, and the
    oracle does not refute its horizon). The linear search claims its horizon minimal
    for the problem unless it gave a plan up without a proof (``segment_undecided``)."""
    r = _exact(p, L, search)
    undecided = r.counters.get("segment_undecided")
    event(f"exact {search}: {r.status.value}, minimal for {r.counters.get('minimal_relative_to')}")
    if r.status is ReachStatus.FOUND:
        assert r.validated is True and r.segment_safe is True
        assert oracle_exact(p, r.horizon) is not False, (r.horizon, r.message)
        if r.counters.get("minimal_relative_to") == "problem":
            for h in range(r.horizon):
                verdict = oracle_exact(p, h)
                event(f"oracle below a minimal horizon: {verdict}")
                assert verdict is not True, (h, r.horizon, r.message)
        elif search == "linear" and not undecided:
            raise AssertionError(f"linear search without a minimal claim: {r.message}")
    elif r.status is ReachStatus.INFEASIBLE:
        for h in range(L + 1):
            verdict = oracle_exact(p, h)
            event(f"oracle below an infeasible bound: {verdict}")
            assert verdict is not True, (h, r.message)
    else:  # small instances: decided, or given up without a proof (and said so)
        assert undecided or "budget" in r.message or "not a proof" in r.message, r.message


def _conflict_refuted(p: ReachProblem, ab, c) -> bool:
    """The exact oracle, asked for a segment-safe trajectory over the states the
    conflict claims (with the start when anchored there, the goal at its horizon when
    anchored there) that realises its literals (samples and points along segments in
    their closed regions): it must not find one."""
    from plansynth.reach.lazy.segments import DENOM

    lo = 0 if c.anchored_start else c.first_time
    hi = c.horizon if c.anchored_goal else c.last_time
    claims = tuple((t - lo, 0.0, ab.regions[r].H, ab.regions[r].h) for t, r in c.literals)
    claims += tuple((t - lo, f / DENOM, ab.regions[r].H, ab.regions[r].h) for t, f, r in c.vias)
    verdict = oracle_exact(p, hi - lo, start=c.anchored_start, goal=c.anchored_goal, claims=claims)
    event(f"clause oracle: {verdict}")
    return verdict is not True


def _excludes_trajectory(c, ab, P: np.ndarray, waits: bool) -> bool:
    """Does DIS-PLAN's clause of ``c`` (at the shifts it is added at) exclude the
    trajectory with positions ``P`` (horizon len(P) - 1), every literal read as "the
    point lies in the closed region"?"""
    from plansynth.reach.lazy.segments import DENOM

    H = len(P) - 1

    def inside(q, r) -> bool:
        reg = ab.regions[r]
        return bool(np.all(reg.H @ q <= reg.h + 1e-7))

    def matches(shift: int) -> bool:
        if c.first_time + shift < 0 or c.last_time + shift > H:
            return False
        return all(inside(P[t + shift], r) for t, r in c.literals) and all(
            inside(P[t + shift] + f / DENOM * (P[t + shift + 1] - P[t + shift]), r) for t, f, r in c.vias
        )

    times = [t for t, _ in c.literals] + [t for t, _, _ in c.vias]
    earlier = range(-min(times, default=0), 1) if waits else (0,)
    if c.anchored_start and c.anchored_goal:
        return any(H == c.horizon + s and matches(s) for s in earlier)
    if c.anchored_start:
        return any(matches(s) for s in earlier)
    if c.anchored_goal:
        return matches(H - c.horizon)
    return any(matches(s) for s in range(-c.first_time, H - c.last_time + 1))


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(segment_worlds, st.integers(4, 10), st.sampled_from(["linear", "minimal"]))
def test_exact_segment_clauses_hold_for_every_segment_safe_trajectory(p: ReachProblem, L: int, search: str) -> None:
    """Every conflict DIS-PLAN learns with exact segment transitions (CON-PLAN's
    counterexamples over samples and points along segments, and the transit layer's)
    is a true statement about the problem: an LP written here refutes it, and it does
    not exclude the exact oracle's segment-safe witness at the oracle's least horizon
    (up to L), at any time shift DIS-PLAN adds it at. A plan the theory could not
    decide (points exhausted) is blocked, not refuted: the result then claims nothing
    (``segment_undecided``, checked by :func:`_exact`), so its block is left out."""
    from plansynth.reach.lazy.segments import Refinement, SegmentDisPlan
    from plansynth.reach.lazy.segtheory import SegmentTheory

    learned: list = []
    blocked: list = []  # plans the theory could not decide: blocked, not refuted
    original, check = SegmentDisPlan.learn, SegmentTheory.check

    def recording(self, conflict) -> None:
        if not isinstance(conflict, Refinement) and not any(conflict is b for b in blocked):
            learned.append(conflict)
        original(self, conflict)

    def checking(self, plan):
        before = self.undecided
        out = check(self, plan)
        if self.undecided > before:
            blocked.append(out)
        return out

    SegmentDisPlan.learn = recording  # type: ignore[method-assign]
    SegmentTheory.check = checking  # type: ignore[method-assign]
    try:
        _exact(p, L, search)
    finally:
        SegmentDisPlan.learn = original  # type: ignore[method-assign]
        SegmentTheory.check = check  # type: ignore[method-assign]
    ab = abstract(p)
    witness: list = []
    h = next((h for h in range(L + 1) if oracle_exact(p, h, witness=witness) is True), None)
    event(f"clauses: {min(len(learned), 50) // 10 * 10}+; witness {h is not None}; blocked {bool(blocked)}")
    for c in learned[:25]:
        assert _conflict_refuted(p, ab, c), c
    if h is not None:
        P = np.asarray(witness[-1])[:, list(p.dynamics.position)]
        for c in learned:
            assert not _excludes_trajectory(c, ab, P, p.starts_at_rest), (c, P.tolist())


def test_oracle_exact_passes_a_corner() -> None:
    """The corner of :func:`test_oracle_face_formulation_is_only_sufficient`: one step
    cuts past the corner of the unit box; the exact oracle finds it, the face one does
    not; a goal behind the box (its straight step would go through) needs two."""
    p = _problem(
        Box((-2.0, -2.0), (3.0, 3.0)), [Box((0.0, 0.0), (1.0, 1.0))], Box((0.35, 1.55), (0.45, 1.65)), [-0.5, 0.7], 1
    )
    assert oracle_exact(p, 1) is True and oracle_feasible(p, 1, segments=True) is False
    q = _problem(
        Box((-2.0, -2.0), (3.0, 3.0)), [Box((0.0, 0.0), (1.0, 1.0))], Box((1.4, 0.4), (1.6, 0.6)), [-0.5, 0.5], 1
    )
    assert oracle_feasible(q, 1, segments=False) is False  # 2 m in one unit step: too far anyway
    r = _problem(
        Box((-2.0, -2.0), (3.0, 3.0)), [Box((0.0, 0.0), (0.4, 1.0))], Box((0.7, 0.4), (0.9, 0.6)), [-0.3, 0.5], 1
    )
    assert oracle_feasible(r, 1, segments=False) is True  # the samples are free...
    assert oracle_exact(r, 1) is False  # ... the segment goes through the box
    assert oracle_exact(r, 3) is True


# -- the oracle itself ---------------------------------------------------------------


def test_oracle_separates_samples_from_segments() -> None:
    """A wall 0.5 thick, single integrator (1 per axis per step): samples jump it (2
    steps from y = 4.6 to 5.4 + ...), segments must go round its end."""
    p = _problem(
        Box((0.0, 0.0), (10.0, 10.0)), [Box((0.0, 4.8), (9.0, 5.3))], Box((1.0, 9.0), (2.0, 9.5)), [1.5, 4.5], 1
    )
    assert oracle_minimum(p, 20, segments=False) == 5  # 4.5 -> 9.0 in y: 4.5 steps of 1
    assert oracle_minimum(p, 20, segments=True) > 5


def test_oracle_face_formulation_is_only_sufficient() -> None:
    """One step of the single integrator cuts past the corner of the box [0, 1]^2 from
    (-0.5, 0.7) to (0.4, 1.6): the segment misses the box (the line passes above the
    corner (0, 1)), but its end points lie beyond two different faces, so the face
    formulation refuses one step; samples allow it."""
    p = _problem(
        Box((-2.0, -2.0), (3.0, 3.0)), [Box((0.0, 0.0), (1.0, 1.0))], Box((0.35, 1.55), (0.45, 1.65)), [-0.5, 0.7], 1
    )
    assert oracle_feasible(p, 1, segments=False) is True
    assert oracle_feasible(p, 1, segments=True) is False
    assert oracle_feasible(p, 2, segments=True) is True


# -- the public cases (examples/reach/claims/) -------------------------------


PUBLIC = [
    # (file, segment-safe minimum of the face oracle, samples-only minimum)
    ("narrow-passage.yaml", 8, 8),
    ("wall-gap.yaml", 19, 19),
    ("floors-3d.yaml", 22, 10),  # samples only, adjacency through both holes claimed 21 minimal
    ("cross-intersection.yaml", 21, 20),
]


@pytest.mark.parametrize("name, seg_min, samples_min", PUBLIC)
def test_public_cases_minimal_horizons(name: str, seg_min: int, samples_min: int) -> None:
    """On each public case: the samples-only minimum is proved and is the oracle's; the
    segment-safe horizon found is claimed minimal for the problem only if it is the
    face oracle's minimum (the planner's sufficient semantics may need more steps,
    and then the claim says "decomposition")."""
    p = load_reach_problem(CLAIMS / name)
    L = p.max_horizon
    assert oracle_minimum(p, L, segments=False) == samples_min
    assert oracle_minimum(p, L, segments=True) == seg_min
    r = solve(p, "lazy-smt", segment_safe=False, horizon_search="linear")
    assert r.status is ReachStatus.FOUND and r.validated is True
    assert (r.horizon, r.counters["minimal"], r.counters["minimal_relative_to"]) == (samples_min, True, "problem")
    for search in ("linear", "window"):
        r = solve(p, "lazy-smt", horizon_search=search, exact_segments=False)
        assert r.status is ReachStatus.FOUND and r.validated is True and r.segment_safe is True
        assert r.horizon >= seg_min
        if r.counters["minimal_relative_to"] == "problem":
            assert r.horizon == seg_min
        elif r.counters["minimal"]:
            assert r.counters["minimal_relative_to"] == "decomposition" and "not proved for the problem" in r.message
    r = solve(p, "lazy-smt", max_horizon=seg_min, horizon_search="linear", exact_segments=False)  # was "infeasible"
    assert r.status is not ReachStatus.INFEASIBLE


@pytest.mark.parametrize("name, seg_min", [(n, s) for n, s, _ in PUBLIC if n != "floors-3d.yaml"])
def test_public_cases_exact_segments(name: str, seg_min: int) -> None:
    """With exact segment transitions a step may cross several regions: on the public
    cases the planner finds the face oracle's segment-safe minimum and proves it minimal
    for the problem (not only through the decomposition), validated segment-safe."""
    p = load_reach_problem(CLAIMS / name)
    for search in ("linear", "window", "minimal"):
        r = solve(p, "lazy-smt", exact_segments=True, horizon_search=search)
        assert r.status is ReachStatus.FOUND and r.validated is True and r.segment_safe is True, r.message
        assert (r.horizon, r.counters["minimal"], r.counters["minimal_relative_to"]) == (seg_min, True, "problem")
        assert not r.counters["segment_undecided"]


def test_gcs_maze_samples_minimum_and_the_segment_claim() -> None:
    """The GCS paper's maze (10 x 10, seed 4, walls 0.1 thick): samples only, a step
    (up to 0.5 per axis) jumps a wall, and the exact search proves 19 minimal, the
    oracle's minimum (the robot starts at rest, so infeasibility at 18 covers every
    shorter horizon: a shorter trajectory could wait). Segment-safe, the plan's horizon
    is claimed minimal through the decomposition only (the face oracle, 18,800
    binaries at horizon 45, does not finish within minutes here)."""
    p = load_reach_problem(CLAIMS / "gcs-maze-10.yaml")
    assert p.starts_at_rest
    r = solve(p, "lazy-smt", segment_safe=False, horizon_search="linear")
    assert (r.status, r.validated, r.horizon, r.counters["minimal_relative_to"]) == (
        ReachStatus.FOUND,
        True,
        19,
        "problem",
    )
    assert oracle_feasible(p, 18, segments=False) is False and oracle_feasible(p, 19, segments=False) is True
    r = solve(p, "lazy-smt", horizon_search="linear", exact_segments=False)
    assert r.status is ReachStatus.FOUND and r.validated is True and r.segment_safe is True
    assert r.counters["minimal"] is True and r.counters["minimal_relative_to"] == "decomposition"
    assert "not proved for the problem" in r.message


@pytest.mark.slow
def test_gcs_maze_exact_segments_minimum() -> None:
    """The GCS paper's 10 x 10 maze with exact segment transitions (about a minute): the
    timed route's plan through the decomposition (50 steps) is lowered by separating
    half-spaces and the shorter horizons refuted, so 39 is proved minimal for the
    problem, validated segment-safe. The samples-only minimum (19) and the proved
    bound below it (33, the per-axis reachable sets) bracket it."""
    from plansynth import Budget

    p = load_reach_problem(CLAIMS / "gcs-maze-10.yaml")
    r = solve(p, "lazy-smt", Budget(seconds=300), exact_segments=True)
    assert r.status is ReachStatus.FOUND and r.validated is True and r.segment_safe is True, r.message
    assert (r.horizon, r.counters["minimal"], r.counters["minimal_relative_to"]) == (39, True, "problem")
    assert r.counters["reach_sets_bound"] == 33 and r.counters["descent_horizons"] > 0


@pytest.mark.parametrize(
    "target, goal, seg_min, samples_min",
    [
        ("3", ((0, 4), (1.5, 6)), 8, 6),
        ("21", ((4, 0.5), (6, 2.5)), 13, 6),  # samples only, region adjacency claimed 13 minimal
        ("25", ((4, 3), (6, 6)), 13, 6),
    ],
)
def test_smc_ltl_map_targets(target: str, goal: tuple, seg_min: int, samples_min: int) -> None:
    """SMC-LTL's 27-region map, one target region at a time: the samples-only minimum
    is proved and is the oracle's; segment-safe, a claim for the problem is the face
    oracle's minimum and the plan is never shorter than it (a box world)."""
    import dataclasses

    p = dataclasses.replace(load_reach_problem(CLAIMS / "smc-ltl-map.yaml"), goal=Box(*goal))
    assert oracle_minimum(p, 30, segments=False) == samples_min
    assert oracle_minimum(p, 30, segments=True) == seg_min
    r = solve(p, "lazy-smt", segment_safe=False, horizon_search="linear")
    assert (r.status, r.validated, r.horizon, r.counters["minimal_relative_to"]) == (
        ReachStatus.FOUND,
        True,
        samples_min,
        "problem",
    )
    r = solve(p, "lazy-smt", horizon_search="linear", exact_segments=False)
    assert r.status is ReachStatus.FOUND and r.validated is True and r.horizon >= seg_min
    assert r.counters["minimal_relative_to"] != "problem" or r.horizon == seg_min


def _doc(**kw):
    from plansynth.reach.fileformat import reach_problem_from_dict

    return reach_problem_from_dict(kw)


#: found by a review: a goal region next to the start region got "one step to go" from the
#: transit layer's gap (never below 1), so no plan could end in it: "infeasible up to 9" as
#: a proof, where a 5-step trajectory exists (damped double integrator, explicit A, B)
DAMPED = dict(
    workspace={"min": [0, 0], "max": [10, 10]},
    obstacles=[{"min": [5, 0], "max": [8, 2]}],
    goal={"min": [5.4, 8], "max": [6.2, 9]},
    max_horizon=9,
    robot={
        "dynamics": {
            "A": [[1, 0, 0.5, 0], [0, 1, 0, 0.5], [0, 0, 0.8, 0], [0, 0, 0, 0.8]],
            "B": [[0.125, 0], [0, 0.125], [0.5, 0], [0, 0.5]],
            "position": [0, 1],
        },
        "start": [3, 8, 0, 0],
        "input_bound": 1.0,
        "state_bounds": {"min": [0, 0, -2, -2], "max": [10, 10, 2, 2]},
    },
)
#: found by a review: the goal's only free part is a face of a region (the goal's interior
#: beside it is obstacle), which counted as no goal region: "infeasible up to 5" as a proof
GOAL_FACE = dict(
    workspace={"min": [0, 0], "max": [10, 10]},
    obstacles=[{"min": [4, 4], "max": [6, 9]}],
    goal={"min": [4, 4], "max": [6, 9.5]},
    max_horizon=5,
    robot={"dynamics": {"model": "single-integrator", "dt": 1}, "start": [5, 1], "input_bound": 1},
)


@pytest.mark.parametrize("doc,minimum", [(DAMPED, 5), (GOAL_FACE, 3)], ids=["goal-region-to-go", "goal-on-a-face"])
def test_the_goal_regions_end_plans_where_a_trajectory_can_end(doc, minimum):
    p = _doc(**doc)
    assert oracle_minimum(p, doc["max_horizon"], segments=False) == minimum
    r = solve(p, "lazy-smt", max_horizon=doc["max_horizon"], segment_safe=False, horizon_search="linear")
    assert r.status is ReachStatus.FOUND and r.horizon == minimum, r.message


def test_points_too_far_apart_are_a_conflict_without_an_lp() -> None:
    """Two points of a plan whose regions lie farther apart along an axis than the time
    between them allows (at most the largest change per step, times the steps) are a
    two-literal conflict at every shift, found without an LP; the exact oracle confirms
    that no segment-safe trajectory realises it; a plan whose points keep within reach
    gets none."""
    from plansynth.reach.lazy.segments import DENOM
    from plansynth.reach.lazy.segtheory import SegmentTheory

    p = load_reach_problem(CLAIMS / "wall-gap.yaml")  # steps of at most 1 m per axis
    ab = abstract(p)
    th = SegmentTheory(p, ab)
    lo = np.array([np.min(r.vertices, axis=0) for r in ab.regions])
    hi = np.array([np.max(r.vertices, axis=0) for r in ab.regions])
    a = int(np.argmin(hi[:, 1]))  # a region at the bottom, one at the top
    b = int(np.argmax(lo[:, 1]))
    assert lo[b, 1] - hi[a, 1] > 0.5 * th._reach[1][1]  # (the wall's 1 m against half a step)
    c = th._too_far({0: a, 1: a, 2: a}, {(1, DENOM // 2): b}, 2)  # 0.5 steps apart
    assert c is not None and th.lp_calls == 0
    assert not c.anchored_start and not c.anchored_goal
    assert set(c.literals) | {(t, r) for t, _, r in c.vias} <= {(0, a), (1, a), (2, a), (1, b)}
    assert len(c.literals) + len(c.vias) == 2
    lo_t = c.first_time
    claims = tuple((t - lo_t, 0.0, ab.regions[r].H, ab.regions[r].h) for t, r in c.literals)
    claims += tuple((t - lo_t, f / DENOM, ab.regions[r].H, ab.regions[r].h) for t, f, r in c.vias)
    assert oracle_exact(p, c.last_time - lo_t, start=False, goal=False, claims=claims) is False
    assert th._too_far({0: a, 1: a}, {}, 1) is None
