"""Property tests on small random workspaces (``families.random_workspace``):

* every trajectory the planners return passes the independent validator;
* the lazy planner and the region MILP agree: same status, same (shortest) horizon;
* counterexample soundness: every clause CON-PLAN hands to DIS-PLAN excludes only
  region sequences that have no trajectory, checked by brute force -- all excluded
  walks are enumerated and each is refuted by an LP written here from scratch; also on
  problems tightened by a disturbance's tube, whose bounds tighten at every step (a
  clause that holds at one time need not hold earlier), by the same LP with the tube's
  margins at every step.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator

import highspy
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from reach_oracles import disturbed, feasible, problems, tube_margins

from plansynth.reach import ReachStatus, solve
from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.dynamics import double_integrator
from plansynth.reach.geometry import Box, halfspaces
from plansynth.reach.highs import new_highs
from plansynth.reach.lazy.conflict import Conflict
from plansynth.reach.lazy.displan import DisPlan
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.lazy.planner import plan_lazy
from plansynth.reach.problem import ReachProblem

PROPS = settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@PROPS
@given(problems(), st.integers(3, 9), st.booleans())
def test_lazy_and_milp_agree_and_every_trajectory_validates(
    p: ReachProblem, max_horizon: int, segment_safe: bool
) -> None:
    lazy = solve(
        p, "lazy-smt", max_horizon=max_horizon, segment_safe=segment_safe, horizon_search="linear", exact_segments=False
    )
    window = solve(
        p,
        "lazy-smt",
        max_horizon=max_horizon,
        segment_safe=segment_safe,
        horizon_search="window",
        window_growth=1.0,
        exact_segments=False,
    )
    milp = solve(p, "milp", max_horizon=max_horizon, segment_safe=segment_safe)
    # (through the decomposition, as the region MILP: exact transitions are
    # tests/reach/test_exact_claims.py's and tests/reach/test_exact_auto.py's)
    for r in (lazy, window, milp):
        # unknown only when every horizon was refuted through the abstraction, which
        # does not prove infeasibility (a step may cross several regions)
        assert r.status is not ReachStatus.UNKNOWN or r.counters.get("abstraction_refuted") == max_horizon, r.message
        if r.status is ReachStatus.FOUND:
            assert r.validated is True and r.validation.ok
            if segment_safe:
                assert r.segment_safe is True
    assert lazy.status is milp.status is window.status
    assert lazy.horizon == milp.horizon  # the paper's loop finds the smallest horizon
    if lazy.status is ReachStatus.FOUND:
        assert lazy.counters["minimal"] is True
        # a window may end later; "minimal" is claimed only when it is the smallest
        assert lazy.horizon <= window.horizon <= max_horizon
        if window.counters["minimal"]:
            assert window.horizon == lazy.horizon
    else:
        assert window.horizon == lazy.horizon == max_horizon


# ------------------------------------------------------------------ soundness by brute force


def oracle_feasible(p: ReachProblem, ab: Abstraction, walk: tuple[int, ...], segment_safe: bool) -> bool:
    """Is there a trajectory through ``walk``? A direct LP, independent of conplan (built
    as sparse rows: HiGHS's expression API costs more than the solve here)."""
    dyn = p.dynamics
    n, m, N = dyn.n_states, dyn.n_inputs, len(walk) - 1
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    inf = highspy.kHighsInf
    lo = np.full(n, -inf) if p.state_bounds is None else np.array(p.state_bounds.lo, float)
    hi = np.full(n, inf) if p.state_bounds is None else np.array(p.state_bounds.hi, float)
    x = lambda t, i: t * n + i  # noqa: E731 - column of state i at time t
    u = lambda t, j: (N + 1) * n + t * m + j  # noqa: E731 - column of input j at time t
    rows: list[tuple[dict[int, float], float, float]] = []  # (coefficients, lower, upper)
    for i in range(n):
        rows.append(({x(0, i): 1.0}, float(p.start[i]), float(p.start[i])))
    for t in range(N):
        for i in range(n):
            coef = {x(t + 1, i): 1.0}
            for k in range(n):
                if A[i, k] != 0:
                    coef[x(t, k)] = -float(A[i, k])
            for j in range(m):
                if B[i, j] != 0:
                    coef[u(t, j)] = -float(B[i, j])
            rows.append((coef, 0.0, 0.0))

    col_lo = np.concatenate([np.tile(lo, N + 1), np.full(N * m, -p.input_bound)])
    col_hi = np.concatenate([np.tile(hi, N + 1), np.full(N * m, p.input_bound)])
    goal_margin = np.zeros(len(halfspaces(p.goal)[0]))
    if p.tube is not None:  # a tightened problem: every bound tightened by the tube at its step
        ws_lo, ws_hi = np.array(p.workspace.lo, float), np.array(p.workspace.hi, float)
        pos = list(dyn.position)
        lo, hi = lo.copy(), hi.copy()
        lo[pos], hi[pos] = np.maximum(lo[pos], ws_lo), np.minimum(hi[pos], ws_hi)
        S = tube_margins(p, np.vstack([np.eye(n), -np.eye(n)]), N)
        col_lo[: (N + 1) * n] = (lo[None, :] + S[:, n:]).ravel()
        col_hi[: (N + 1) * n] = (hi[None, :] - S[:, :n]).ravel()
        K = np.asarray(p.tube.K, float)
        Su = tube_margins(p, np.vstack([K, -K]), N)
        col_lo[(N + 1) * n :] = (-p.input_bound + Su[:N, m:]).ravel()
        col_hi[(N + 1) * n :] = (p.input_bound - Su[:N, :m]).ravel()
        Hg = halfspaces(p.goal)[0]
        Dg = np.zeros((len(Hg), n))
        Dg[:, pos] = Hg
        goal_margin = tube_margins(p, Dg, N)[N]

    def inside(H: np.ndarray, hh: np.ndarray, t: int) -> None:
        for row, b in zip(H, hh):
            coef: dict[int, float] = {}
            for c, k in zip(row, dyn.position):
                if c:
                    coef[x(t, k)] = coef.get(x(t, k), 0.0) + float(c)
            rows.append((coef, -inf, float(b)))

    for t, r in enumerate(walk):
        reg = ab.regions[r]
        inside(reg.H, reg.h, t)
        if segment_safe and t < N:
            inside(reg.H, reg.h, t + 1)
    Hg, hg = halfspaces(p.goal)
    inside(Hg, hg - goal_margin, N)
    h = new_highs()  # the package's constructor: one HiGHS scheduler setting per process
    if np.any(col_lo > col_hi):  # a bound the tube leaves empty
        return False
    h.addVars((N + 1) * n + N * m, col_lo, col_hi)
    return feasible(h, rows)


def oracle_refutes(p: ReachProblem, ab: Abstraction, c: Conflict, segment_safe: bool) -> bool:
    """Is what ``c`` claims impossible wherever DIS-PLAN may use it? An LP over the
    states ``c.first_time..c.last_time`` with its literals' region rows (and segment
    rows within the span), x_0 = start when it is anchored at the start (absolute
    times), the goal at its last state when anchored at the goal; a tube's margins (the
    problem's, at each step) put E_0 at the start, or, without the start, at the span's
    first state: the earliest placement, the loosest (a conflict without the start is
    reused at every time shift)."""
    dyn = p.dynamics
    n, m = dyn.n_states, dyn.n_inputs
    first = 0 if c.anchored_start else c.first_time
    T = c.last_time - first  # the span's steps
    A, B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
    pos = list(dyn.position)
    inf = highspy.kHighsInf
    lo = np.full(n, -inf) if p.state_bounds is None else np.array(p.state_bounds.lo, float)
    hi = np.full(n, inf) if p.state_bounds is None else np.array(p.state_bounds.hi, float)
    lo[pos] = np.maximum(lo[pos], p.workspace.lo)
    hi[pos] = np.minimum(hi[pos], p.workspace.hi)
    col_lo = np.concatenate([np.tile(lo, T + 1), np.full(T * m, -p.input_bound)])
    col_hi = np.concatenate([np.tile(hi, T + 1), np.full(T * m, p.input_bound)])
    Hg, hg = halfspaces(p.goal)
    if p.tube is not None:
        S = tube_margins(p, np.vstack([np.eye(n), -np.eye(n)]), T)
        col_lo[: (T + 1) * n] += S[:, n:].ravel()
        col_hi[: (T + 1) * n] -= S[:, :n].ravel()
        K = np.asarray(p.tube.K, float)
        Su = tube_margins(p, np.vstack([K, -K]), T)
        col_lo[(T + 1) * n :] += Su[:T, m:].ravel()
        col_hi[(T + 1) * n :] -= Su[:T, :m].ravel()
        Dg = np.zeros((len(Hg), n))
        Dg[:, pos] = Hg
        hg = hg - tube_margins(p, Dg, T)[T]
    if np.any(col_lo > col_hi):
        return True
    x = lambda t, i: (t - first) * n + i  # noqa: E731
    u = lambda t, j: (T + 1) * n + (t - first) * m + j  # noqa: E731
    rows: list[tuple[dict[int, float], float, float]] = []
    if c.anchored_start:
        for i in range(n):
            rows.append(({x(0, i): 1.0}, float(p.start[i]), float(p.start[i])))
    for t in range(first, c.last_time):
        for i in range(n):
            coef = {x(t + 1, i): 1.0}
            for k in range(n):
                if A[i, k] != 0:
                    coef[x(t, k)] = coef.get(x(t, k), 0.0) - float(A[i, k])
            for j in range(m):
                if B[i, j] != 0:
                    coef[u(t, j)] = -float(B[i, j])
            rows.append((coef, 0.0, 0.0))

    def inside(H: np.ndarray, hh: np.ndarray, t: int) -> None:
        for row, b in zip(H, hh):
            rows.append(({x(t, k): float(v) for v, k in zip(row, pos) if v}, -inf, float(b)))

    for t, r in c.literals:
        reg = ab.regions[r]
        inside(reg.H, reg.h, t)
        if segment_safe and t < c.last_time:
            inside(reg.H, reg.h, t + 1)
    if c.anchored_goal:
        inside(Hg, hg, c.last_time)
    h = new_highs()
    h.addVars((T + 1) * n + T * m, col_lo, col_hi)
    return not feasible(h, rows)


def walks(ab: Abstraction, N: int) -> Iterator[tuple[int, ...]]:
    def extend(prefix: tuple[int, ...]) -> Iterator[tuple[int, ...]]:
        if len(prefix) == N + 1:
            if prefix[-1] in ab.goal_regions:
                yield prefix
            return
        last = prefix[-1]
        for nxt in (last, *ab.adjacency[last]):
            yield from extend(prefix + (nxt,))

    for s in ab.start_regions:
        yield from extend((s,))


def excludes(c: Conflict, walk: tuple[int, ...], waits: bool = False) -> bool:
    """Does the clause of ``c``, as DIS-PLAN instantiates it, exclude ``walk``? (``waits``:
    DIS-PLAN also adds start-anchored conflicts shifted earlier.)"""
    H = len(walk) - 1

    def matches(shift: int) -> bool:
        return all(0 <= t + shift <= H and walk[t + shift] == r for t, r in c.literals)

    earlier = range(-min((t for t, _ in c.literals), default=0), 1) if waits else (0,)
    if c.anchored_start and c.anchored_goal:
        return any(H == c.horizon + s and matches(s) for s in earlier)
    if c.anchored_start:
        return any(H >= c.last_time + s and matches(s) for s in earlier)
    if c.anchored_goal:
        shift = H - c.horizon
        return c.first_time + shift >= 0 and matches(shift)
    return any(matches(s) for s in range(-c.first_time, H - c.last_time + 1))


def soundness_checked(
    p: ReachProblem,
    strategy: str,
    generalize: bool,
    segment_safe: bool,
    top: int = 4,
    search: str = "linear",
    claims: list[Conflict] | None = None,
) -> int:
    """Run the lazy planner up to horizon ``top`` from horizon 0, record every clause it
    learns, and refute every walk (up to ``top``) a clause excludes by the oracle LP
    (at most 12 per clause and horizon). Returns the number of excluded walks refuted:
    0 when no clause was learned or none excluded a walk, so that nothing was checked.
    ``claims``: the learned clauses are appended to it."""
    ab = abstract(p)
    learned: list[Conflict] = []
    original = DisPlan.learn

    def recording(self: DisPlan, conflict: Conflict) -> None:  # every clause, from CON-PLAN or the transit layer
        learned.append(conflict)
        original(self, conflict)

    DisPlan.learn = recording  # type: ignore[method-assign]
    try:
        plan_lazy(
            p,
            options=LazyOptions(
                max_horizon=top,
                counterexample=strategy,
                generalize=generalize,
                segment_safe=segment_safe,
                lower_bound=False,
                horizon_search=search,
                window_growth=2.0,
                exact_segments=False,
            ),
            abstraction=ab,
        )
    finally:
        DisPlan.learn = original  # type: ignore[method-assign]
    if claims is not None:
        claims.extend(learned)
    checked = 0
    walks_of = {H: list(itertools.islice(walks(ab, H), 3000)) for H in range(0, top + 1)}
    feasible: dict[tuple[int, ...], bool] = {}  # the oracle's answer per walk (clauses share walks)
    for c in learned:
        for H in range(0, top + 1):
            excluded = [w for w in walks_of[H] if excludes(c, w, p.starts_at_rest)]
            for w in excluded[:12]:
                if w not in feasible:
                    feasible[w] = oracle_feasible(p, ab, w, segment_safe)
                assert not feasible[w], f"clause {c} excludes the feasible {w}"
                checked += 1
    return checked


#: Examples of the soundness property with a clause that excluded some walk (examples
#: without one check nothing and are drawn again), and the fewest excluded walks the
#: oracle must refute over all of them (random rooms give about 50 per example).
SOUNDNESS_EXAMPLES = 30
SOUNDNESS_FLOOR = 200
#: the loop's configurations the soundness properties draw: counterexample strategy,
#: generalisation, segment safety, horizon search
LOOP_CONFIGURATIONS = (
    st.sampled_from(["zeroprefix", "trivial", "iis"]),
    st.booleans(),
    st.booleans(),
    st.sampled_from(["linear", "window"]),
)


def soundness_examples(n: int):
    """The settings of a soundness property: ``n`` examples, slow and filtered ones allowed."""
    return settings(
        max_examples=n, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much]
    )


def test_every_learned_clause_excludes_only_infeasible_sequences() -> None:
    """Every clause learned on random rooms excludes only walks the oracle refutes. An
    example whose clauses exclude no walk (no clause learned: a start in the goal, say)
    proves nothing, so it is rejected (``assume``) and another one drawn; the test as a
    whole must refute at least :data:`SOUNDNESS_FLOOR` excluded walks."""
    checked: list[int] = []

    @soundness_examples(SOUNDNESS_EXAMPLES)
    @given(problems(max_obstacles=4), *LOOP_CONFIGURATIONS)
    def every_clause_is_sound(
        p: ReachProblem, strategy: str, generalize: bool, segment_safe: bool, search: str
    ) -> None:
        n = soundness_checked(p, strategy, generalize, segment_safe, search=search)
        assume(n > 0)
        checked.append(n)

    every_clause_is_sound()
    assert len(checked) >= SOUNDNESS_EXAMPLES and sum(checked) >= SOUNDNESS_FLOOR, checked


#: examples of the soundness property under a tube (each with some excluded walk)
TUBE_SOUNDNESS_EXAMPLES = 15


def test_every_learned_clause_is_sound_under_a_tube() -> None:
    """The same property on random rooms tightened by a disturbance's tube
    (plansynth.reach.robust): the state bounds, the workspace, the input bound and the
    goal tighten at every step, so a conflict without the start may be reused only
    where it was proved at its earliest placement; every clause learned there excludes
    only walks the oracle, with the tube's margins at each step, refutes."""
    from plansynth.reach.robust.tighten import tightened

    checked: list[int] = []

    # tubes that grow by tenths of a metre in the first steps
    @soundness_examples(TUBE_SOUNDNESS_EXAMPLES)
    @given(disturbed(scales=(0.05, 0.3)), *LOOP_CONFIGURATIONS)
    def every_clause_is_sound(
        p: ReachProblem, strategy: str, generalize: bool, segment_safe: bool, search: str
    ) -> None:
        q = tightened(p).problem
        assume(q is not None and q.tube.varies)
        assert not q.starts_at_rest  # no clause is shifted earlier by waiting at the start
        claims: list[Conflict] = []
        n = soundness_checked(q, strategy, generalize, segment_safe, search=search, claims=claims)
        ab = abstract(q)
        for c in claims:  # each claim refuted where DIS-PLAN may use it first
            assert oracle_refutes(q, ab, c, segment_safe), f"clause {c} is not refuted at its earliest placement"
        shifted[0] += sum(1 for c in claims if not c.anchored_start and c.first_time > 0)
        assume(n > 0)
        checked.append(n)

    shifted = [0]
    every_clause_is_sound()
    assert len(checked) >= TUBE_SOUNDNESS_EXAMPLES and sum(checked) >= 50, checked
    assert shifted[0] > 0  # clauses without the start, found after step 0: the case the tube makes delicate


@pytest.mark.parametrize(
    ("seed", "order", "scale", "strategy"),
    [
        (10, 1, 0.3, "trivial"),
        (10, 1, 0.3, "zeroprefix"),
        (10, 1, 0.3, "iis"),
        (3, 2, 0.15, "iis"),
        (12, 2, 0.15, "iis"),
    ],
)
def test_clauses_under_a_tube_are_refuted_where_they_are_reused(
    seed: int, order: int, scale: float, strategy: str
) -> None:
    """Rooms where a conflict, shrunk by its certificate to a later first step, is not
    refuted at its earliest placement (each failed here when such a certificate was
    trusted): every clause learned must be refuted by the oracle where DIS-PLAN may use
    it, and every walk it excludes must be infeasible."""
    from dataclasses import replace

    from plansynth.reach.disturbance import Disturbance
    from plansynth.reach.families import random_workspace
    from plansynth.reach.robust.tighten import tightened

    p = random_workspace(seed, 3, order=order, dt=1.0 if order == 1 else 0.5)
    q = tightened(replace(p, disturbance=Disturbance(box=(scale,) * p.dynamics.n_states))).problem
    claims: list[Conflict] = []
    assert soundness_checked(q, strategy, True, True, claims=claims) > 0
    ab = abstract(q)
    for c in claims:
        assert oracle_refutes(q, ab, c, True), f"clause {c} is not refuted at its earliest placement"


def detour() -> ReachProblem:
    """A room with two offset walls: the shortest plans need several region changes, so
    short horizons produce many counterexamples."""
    return ReachProblem(
        workspace=Box((0, 0), (6, 6)),
        obstacles=(Box((0, 2), (4, 3)), Box((2, 4), (6, 5))),
        goal=Box((0.5, 5.2), (1.5, 5.8)),
        dynamics=double_integrator(2, 1.0),
        start=[0.5, 0.5, 0, 0],
        input_bound=1.5,
        state_bounds=Box((0, 0, -2, -2), (6, 6, 2, 2)),
    )


@pytest.mark.parametrize("strategy", ["zeroprefix", "trivial", "iis"])
@pytest.mark.parametrize("generalize", [False, True])
@pytest.mark.parametrize("segment_safe", [False, True])
@pytest.mark.parametrize("search", ["linear", "window"])
def test_learned_clauses_are_sound_on_a_detour(
    strategy: str, generalize: bool, segment_safe: bool, search: str
) -> None:
    assert soundness_checked(detour(), strategy, generalize, segment_safe, top=5, search=search) > 0


def small_random_robot(seed: int) -> ReachProblem:
    """A 3 x 3 m room with a wall and a random robot of 6 states (the random-dynamics
    family's draw): the multi-step displacement bound of the transit layer applies."""
    from plansynth.reach.families import random_dynamics

    r = random_dynamics(0, 6, seed)
    lo, hi = r.state_bounds.lo, r.state_bounds.hi
    start = np.zeros(6)
    start[:2] = (0.3, 0.3)
    return ReachProblem(
        workspace=Box((0, 0), (3, 3)),
        obstacles=(Box((0, 1.2), (2, 1.5)),),
        goal=Box((0.2, 2.3), (0.9, 2.9)),
        dynamics=r.dynamics,
        start=start,
        input_bound=1.0,
        state_bounds=Box((0, 0, *lo[2:]), (3, 3, *hi[2:])),
    )


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("segment_safe", [False, True])
def test_learned_clauses_are_sound_with_random_dynamics(seed: int, segment_safe: bool) -> None:
    p = small_random_robot(seed)
    from plansynth.reach.lazy.conplan import ConPlan
    from plansynth.reach.lazy.transit import TransitCheck

    ab = abstract(p)
    assert TransitCheck(ConPlan(p, ab), ab).reach_table is not None
    assert soundness_checked(p, "trivial", True, segment_safe, top=9, search="linear") > 0
    # some walk up to the top is feasible, so a clause that cut it would be caught
    assert any(oracle_feasible(p, ab, w, segment_safe) for w in itertools.islice(walks(ab, 9), 400))
