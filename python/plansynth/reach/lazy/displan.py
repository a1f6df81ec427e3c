"""DIS-PLAN: the Boolean half of the lazy planner (Shoukry et al., CDC 2016, Section IV).

Boolean variables ``b[t, i]`` say "the position at time t lies in region i" (for
t = 0..L, the horizon). The constraints of Section IV:

* exactly one region per time step (a cardinality encoding from :mod:`pysat.card`);
* the start position's regions at t = 0, a goal region at t = L;
* transitions only between equal or adjacent regions (``b[t,i] -> OR_{j in N[i]} b[t+1,j]``).

The SAT solver (CaDiCaL through PySAT) proposes a region sequence; CON-PLAN (Section V)
either realises it or returns a :class:`Conflict`, which becomes a clause here
(Algorithm 1, line 11). Variables come from an :class:`~pysat.formula.IDPool` keyed by
``("at", t, i)``, so no index arithmetic leaks into the encoding (STYLE.md, point 8).

**Incremental horizons.** One solver instance serves every horizon. The clauses that
hold for every horizon (one region per step, transitions, start, conflicts that talk
about a prefix from time 0) are added unconditionally; the goal at horizon L is guarded
by an activation literal ``act[L]`` that is assumed while L is tried and fixed false
once L is refuted. A conflict that involves the goal is guarded by the same literal, so
every learned clause (and everything CaDiCaL learned from it) survives to the next
horizon. Conflicts that use neither the start state nor the goal hold at every time
shift (the dynamics are time-invariant) and are instantiated at every shift.

**Horizon windows (beyond the paper).** ``solve(hi, lowest=lo)`` asks for a plan that
reaches the goal at *some* horizon h in lo..hi: the activation literals of the window
are assumed as one disjunction, and the plan is cut at the smallest h whose ``act[h]``
is true. The bits after h are padding (staying in the goal region satisfies them), so
a clause whose proof needs the states up to time T, which holds only for plans of
horizon >= T, is guarded by ``before[T]`` ("the plan ends before T"), a literal that a
chain of clauses allows only when some ``act[h]`` with h < T is true. With one horizon
at a time (the paper's loop) every horizon below the one tried is closed and the guards
are never needed. Within a window the solver tries short plans first, unless a plan was
passed to :meth:`DisPlan.prefer`: then its horizon comes first, so that the phases
describe one whole plan (the lazy loop times its reference plan to the window's top).

>>> g = RegionGraph(3, ((1,), (0, 2), (1,)), start_regions=(0,), goal_regions=(2,))
>>> d = DisPlan(g)
>>> d.plan(1) is None            # two steps needed: 0 -> 1 -> 2
True
>>> d.plan(2)
(0, 1, 2)
>>> d.learn(Conflict(((1, 1),), anchored_start=True, anchored_goal=False, horizon=2))
>>> d.plan(3)                    # region 1 at time 1 is now excluded
(0, 0, 1, 2)
"""

from __future__ import annotations

import enum
import math
import time
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

from pysat.card import CardEnc, EncType
from pysat.formula import IDPool
from pysat.solvers import Solver

from plansynth.budget import Clock, checkpoint
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.lazy.conflict import Conflict

__all__ = ["RegionGraph", "Conflict", "DisPlan", "SatOutcome", "CARDINALITY_ENCODINGS"]

CARDINALITY_ENCODINGS = {
    "pairwise": EncType.pairwise,
    "seqcounter": EncType.seqcounter,
    "ladder": EncType.ladder,
    "totalizer": EncType.totalizer,
}

SAT_SOLVER = "cadical195"
#: Up to this many regions "exactly one region per step" is pairwise (k(k-1)/2 binary
#: clauses, no auxiliary variables); beyond, the sequential counter (linear in k).
PAIRWISE_MAX_REGIONS = 8
#: Beyond this many regions ``cardinality="auto"`` is the ``paths`` encoding (see
#: :class:`DisPlan`): no cardinality constraint, variables only where the time windows
#: allow them (the GCS paper's 50 x 50 maze: 1,571 regions over ~600 steps).
PATHS_MIN_REGIONS = 200
# python-sat's CaDiCaL 1.9.5 refuses interrupt() and prop_budget() but honours
# conf_budget() with solve_limited(): it runs in slices of conflicts, the clock checked
# between slices. The slice adapts so that one takes about SLICE_SECONDS (conflicts get
# dearer as the formula grows); the learned clauses survive from slice to slice, so the
# answer is exactly the one an unlimited solve() would give.
CONFLICTS_PER_SLICE = 2_000  # the first slice
MIN_CONFLICTS_PER_SLICE = 100
MAX_CONFLICTS_PER_SLICE = 1_000_000
SLICE_SECONDS = 0.1


@dataclass(frozen=True)
class RegionGraph:
    """The discrete abstraction as DIS-PLAN sees it: regions 0..n-1, adjacency lists,
    start and goal regions (paper, Section III)."""

    n_regions: int
    adjacency: tuple[tuple[int, ...], ...]
    start_regions: tuple[int, ...]
    goal_regions: tuple[int, ...]

    def __post_init__(self) -> None:
        if len(self.adjacency) != self.n_regions:
            raise ValueError(f"adjacency has {len(self.adjacency)} lists for {self.n_regions} regions")
        for i, nbrs in enumerate(self.adjacency):
            for j in nbrs:
                if not 0 <= j < self.n_regions or j == i or i not in self.adjacency[j]:
                    raise ValueError(f"adjacency must be symmetric without self-loops: {i} -> {j}")

    @classmethod
    def from_abstraction(cls, abstraction: Abstraction) -> RegionGraph:
        return cls(len(abstraction.regions), abstraction.adjacency, abstraction.start_regions, abstraction.goal_regions)

    def distances(self, sources: Sequence[int]) -> list[float]:
        """Breadth-first number of region transitions from ``sources`` (inf: unreachable)."""
        dist = [math.inf] * self.n_regions
        queue = deque()
        for s in sources:
            dist[s] = 0
            queue.append(s)
        while queue:
            i = queue.popleft()
            for j in self.adjacency[i]:
                if dist[j] == math.inf:
                    dist[j] = dist[i] + 1
                    queue.append(j)
        return dist

    def horizon_lower_bound(self) -> float:
        """The region-graph distance from a start region to a goal region: no region
        sequence of a shorter horizon exists (inf when the goal is disconnected).

        >>> RegionGraph(3, ((1,), (0, 2), (1,)), (0,), (2,)).horizon_lower_bound()
        2
        """
        dist = self.distances(self.start_regions)
        return min((dist[g] for g in self.goal_regions), default=math.inf)


class SatOutcome(str, enum.Enum):
    SAT = "sat"
    UNSAT = "unsat"
    INTERRUPTED = "interrupted"

    def __bool__(self) -> bool:
        raise TypeError("a SatOutcome has no truth value")


class LearnedClauses:
    """Counterexample clauses added once each (a conflict and its shifted copies often
    coincide): the store DIS-PLAN and the mission DIS-PLAN
    (:class:`plansynth.reach.mission.bmc.MissionDisPlan`) share. Needs ``_add(clause)``."""

    _learned: set[tuple[int, ...]]
    clauses: int

    def _add(self, clause: list[int]) -> None:
        raise NotImplementedError

    def _learn_clause(self, clause: list[int]) -> None:
        """Add ``clause`` unless it was added before; count it in ``clauses``."""
        key = tuple(sorted(clause))
        if key in self._learned:
            return
        self._learned.add(key)
        self._add(clause)
        self.clauses += 1


class DisPlan(LearnedClauses):
    """One incremental SAT instance over a growing horizon (paper, Section IV).

    ``cardinality`` names the exactly-one encoding (``pairwise`` or a PySAT encoding
    such as ``seqcounter``; ``"auto"``: pairwise up to 8 regions, ``paths`` beyond
    :data:`PATHS_MIN_REGIONS`). Counters: ``sat_calls``, ``clauses`` (learned conflict
    clauses, counting shifted copies).

    ``cardinality="paths"`` (beyond the paper; for large abstractions) drops the
    exactly-one constraint and the forward transitions. Its variables are only the
    b[t, i] with t >= ``earliest[i]`` (the others are false in the dense encoding too:
    it adds them as unit clauses) and at t = 0 only the start regions; its clauses are
    the *backward* transitions ``b[t,i] -> OR_{j in {i} + N[i]} b[t-1,j]`` over those
    variables, and the goal and every learned clause as in the dense encoding (a clause
    with a literal that cannot be true is not added). A model may set several regions
    true at a step; the plan is read backwards from a true goal region at the horizon,
    one true predecessor per step (the region itself when it is true), down to a start
    region at t = 0. That walk is a region sequence of the dense encoding's semantics,
    and every learned clause (negative literals over the b's, and guards) holds for it
    because it holds for the model's larger true set; conversely a plan's own bits
    satisfy every clause. So the two encodings answer every question alike (a test
    compares them on random workspaces), with about a fifth of the clauses and none of
    the counter's auxiliary variables.
    """

    def __init__(
        self,
        graph: RegionGraph,
        *,
        cardinality: str = "auto",
        earliest: Sequence[float] | None = None,
        to_go: Sequence[float] | None = None,
        waits_at_start: bool = False,
    ) -> None:
        if cardinality == "auto":
            cardinality = (
                "pairwise"
                if graph.n_regions <= PAIRWISE_MAX_REGIONS
                else "paths"
                if graph.n_regions > PATHS_MIN_REGIONS
                else "seqcounter"
            )
        if cardinality not in CARDINALITY_ENCODINGS and cardinality != "paths":
            raise ValueError(
                f"unknown cardinality encoding {cardinality!r} (known: auto, {', '.join(CARDINALITY_ENCODINGS)}, paths)"
            )
        self.paths = cardinality == "paths"
        self._starts = frozenset(graph.start_regions)
        self.graph = graph
        self.cardinality = cardinality
        self.pool = IDPool()
        self.solver = Solver(name=SAT_SOLVER)
        self.built = -1  # largest time step with variables and step constraints
        self.floor: int | None = None  # the first horizon ever tried: no plan is shorter
        self.open_from: int | None = None  # horizons floor..open_from-1 are closed
        self.to_go_built = -1  # time steps with their to-go window clauses
        self.goal_added: set[int] = set()
        self.closed: set[int] = set()
        self.conflicts: list[Conflict] = []
        self.preferred: int | None = None  # the horizon of the plan last passed to prefer()
        self.waits_at_start = bool(waits_at_start)
        self._learned: set[tuple] = set()  # clauses added, against shifted duplicates
        self.sat_calls = 0
        self.sat_slices = 0
        self._slice = CONFLICTS_PER_SLICE
        self.clauses = 0
        self.sat_clauses_encoding = 0
        # time windows (sound facts from a relaxation): region i is impossible before
        # step earliest[i] and fewer than to_go[i] steps before the end
        self.earliest = list(earliest) if earliest is not None else [0] * graph.n_regions
        self.to_go = list(to_go) if to_go is not None else [0] * graph.n_regions
        self.window_clauses = 0

    # -- variables ---------------------------------------------------------------
    def at(self, t: int, i: int) -> int:
        """The variable b[t, i]: the position at time t lies in region i."""
        return self.pool.id(("at", t, i))

    def act(self, horizon: int) -> int:
        """The activation literal of horizon L (assumed while L is tried)."""
        return self.pool.id(("horizon", horizon))

    def before(self, time: int) -> int | None:
        """The guard ``before[T]`` for a clause that holds for plans of horizon >= T:
        :meth:`ends_before` (see the module docstring), or None when no open horizon lies
        below T, i.e. no guard is needed."""
        if self.open_from is None or time <= self.open_from:
            return None
        return self.ends_before(time)

    def ends_before(self, time: int) -> int | None:
        """The literal e[T], equivalent to ``OR act[h]`` over floor <= h < T: the plan
        ends before T (None when T <= floor: false)."""
        if self.floor is None or time <= self.floor:
            return None
        top = time
        while top > self.floor + 1 and ("ends-before", top - 1) not in self.pool.obj2id:
            top -= 1
        for T in range(top, time + 1):  # build the ladder upwards from the last rung made
            key = ("ends-before", T)
            if key in self.pool.obj2id:
                continue
            e, a = self.pool.id(key), self.act(T - 1)
            lower = self.pool.id(("ends-before", T - 1)) if T - 1 > self.floor else None
            self._add([-e, a] + ([lower] if lower is not None else []))
            self._add([-a, e])
            if lower is not None:
                self._add([-lower, e])
        return self.pool.id(("ends-before", time))

    # -- encoding ----------------------------------------------------------------
    def _add(self, clause: list[int]) -> None:
        self.solver.add_clause(clause)

    def exists(self, t: int, i: int) -> bool:
        """Can b[t, i] be true at all? (False before ``earliest[i]``, and at t = 0 outside
        the start regions; the ``paths`` encoding has no variable there.)"""
        return t >= self.earliest[i] and (t > 0 or i in self._starts)

    def _extend_paths(self, horizon: int) -> None:
        """The ``paths`` encoding of steps built+1..horizon (see the class docstring)."""
        g = self.graph
        for t in range(self.built + 1, horizon + 1):
            checkpoint()  # thousands of regions per step: within the budget phase
            if t == 0:
                self._add([self.at(0, i) for i in g.start_regions if self.exists(0, i)])
                self.sat_clauses_encoding += 1
            else:
                for i in range(g.n_regions):
                    if not self.exists(t, i):
                        continue
                    preds = [self.at(t - 1, j) for j in (i, *g.adjacency[i]) if self.exists(t - 1, j)]
                    self._add([-self.at(t, i)] + preds)
                    self.sat_clauses_encoding += 1
            self._built_to(t)
        self._to_go_windows()

    def _extend(self, horizon: int) -> None:
        if self.paths:
            self._extend_paths(horizon)
            return
        g = self.graph
        for t in range(self.built + 1, horizon + 1):
            checkpoint()
            lits = [self.at(t, i) for i in range(g.n_regions)]
            if self.cardinality == "pairwise":
                enc = CardEnc.equals(lits=lits, bound=1, vpool=self.pool, encoding=EncType.pairwise)
            else:
                enc = CardEnc.equals(
                    lits=lits, bound=1, vpool=self.pool, encoding=CARDINALITY_ENCODINGS[self.cardinality]
                )
            for c in enc.clauses:
                self._add(c)
            self.sat_clauses_encoding += len(enc.clauses)
            for i in range(g.n_regions):
                if t < self.earliest[i]:
                    self._add([-self.at(t, i)])
                    self.window_clauses += 1
            if t == 0:
                self._add([self.at(0, i) for i in g.start_regions])
                self.sat_clauses_encoding += 1
            else:
                for i in range(g.n_regions):
                    self._add([-self.at(t - 1, i), self.at(t, i)] + [self.at(t, j) for j in g.adjacency[i]])
                self.sat_clauses_encoding += g.n_regions
            self._built_to(t)
        self._to_go_windows()

    def _built_to(self, t: int) -> None:
        """The encoding now reaches step ``t``: the free (unanchored) conflicts learned so
        far are instantiated at the shifts the new step opens."""
        old = self.built
        self.built = t
        for c in self.conflicts:
            if not c.anchored_start and not c.anchored_goal:
                self._instantiate_free(c, old, t)

    def _to_go_windows(self) -> None:
        """Region i at time t only if the plan ends at t + to_go[i] or later:
        ``not b[t, i] or not e[t + to_go[i]]``, one clause per (t, i) for every horizon."""
        if self.floor is None:
            return
        for t in range(self.to_go_built + 1, self.built + 1):
            checkpoint()
            for i in range(self.graph.n_regions):
                if not self.exists(t, i) or self.to_go[i] <= 0:
                    continue  # excluded for good already, or a goal region
                if self.to_go[i] == math.inf:
                    self._add([-self.at(t, i)])
                else:
                    e = self.ends_before(t + int(self.to_go[i]))
                    if e is None:
                        continue
                    self._add([-self.at(t, i), -e])
                self.window_clauses += 1
        self.to_go_built = self.built

    def _ensure_goal(self, horizon: int) -> None:
        if horizon in self.goal_added:
            return
        self.goal_added.add(horizon)
        act = self.act(horizon)
        self._add([-act] + [self.at(horizon, i) for i in self.graph.goal_regions if self.exists(horizon, i)])
        for c in self.conflicts:
            if c.anchored_goal and not c.anchored_start:
                self._instantiate_goal(c, horizon)

    def _clause(self, c: Conflict, shift: int, guard: int | None) -> None:
        """Add ``c`` shifted by ``shift``: under ``act[guard]`` when goal-anchored, else
        for plans that reach its last time step."""
        if not all(self.exists(t + shift, i) for t, i in c.literals):
            return  # a literal that is false in every plan: the clause holds already
        clause = [-self.at(t + shift, i) for t, i in c.literals]
        if guard is not None:
            clause.append(-guard)
        else:
            short = self.before(c.last_time + shift)
            if short is not None:
                clause.append(short)
        self._learn_clause(clause)

    def _rest_shifts(self, c: Conflict) -> range:
        """The shifts at which a start-anchored conflict holds: 0, and with
        ``waits_at_start`` every earlier shift that keeps its literals at times >= 0
        (a trajectory for the shifted claims, preceded by that many steps of waiting at
        the start, would realise the conflict itself; with the goal anchored, the
        horizon moves along, down to the first horizon tried)."""
        if not self.waits_at_start or not c.literals:
            return range(0, -1, -1)
        lowest = min(t for t, _ in c.literals)
        if c.anchored_goal and self.floor is not None:
            lowest = min(lowest, c.horizon - self.floor)
        return range(0, -lowest - 1, -1)

    def _instantiate_goal(self, c: Conflict, horizon: int) -> None:
        shift = horizon - c.horizon
        if c.first_time + shift >= 0 and horizon <= self.built:
            self._clause(c, shift, self.act(horizon))

    def _instantiate_free(self, c: Conflict, old_built: int, built: int) -> None:
        """Add the shifted copies of a time-invariant conflict whose last step lands in
        (old_built, built]."""
        span = c.last_time - c.first_time
        for end in range(max(old_built + 1, span), built + 1):
            checkpoint()
            self._clause(c, end - c.last_time, None)

    def learn(self, conflict: Conflict) -> None:
        """Add a counterexample from CON-PLAN (Algorithm 1, line 11)."""
        self.conflicts.append(conflict)
        c = conflict
        if c.anchored_start and not c.anchored_goal:
            self._extend(c.last_time)
            for shift in self._rest_shifts(c):
                self._clause(c, shift, None)
        elif c.anchored_start and c.anchored_goal:
            self._extend(c.horizon)
            for shift in self._rest_shifts(c):
                self._clause(c, shift, self.act(c.horizon + shift))
        elif c.anchored_goal:
            for horizon in sorted(self.goal_added):
                if horizon not in self.closed:
                    self._instantiate_goal(c, horizon)
        else:
            self._instantiate_free(c, -1, self.built)

    def forbid(self, horizon: int, allowed: set[tuple[int, int]]) -> int:
        """Facts for the plans of exactly ``horizon`` steps (the tube of
        :meth:`plansynth.reach.lazy.axisreach.AxisReach.tube`): such a plan is at time
        t <= horizon only in regions i with (t, i) in ``allowed``. Each other b[t, i]
        gets ``not act[L] or e[L] or not b[t, i]`` ("the plan ends exactly at L" implies
        not region i at t; e[L]: it ends before L), so no plan of another horizon is
        affected. Returns the number of clauses added (also counted in
        ``window_clauses``)."""
        self._extend(horizon)
        self._ensure_goal(horizon)
        guard = [-self.act(horizon)]
        e = self.ends_before(horizon)
        if e is not None:
            guard.append(e)
        added = 0
        for t in range(horizon + 1):
            for i in range(self.graph.n_regions):
                if (t, i) not in allowed and self.exists(t, i):
                    self._add(guard + [-self.at(t, i)])
                    added += 1
        self.window_clauses += added
        return added

    def begin(self, lowest: int) -> None:
        """Make ``lowest`` the first horizon tried (no plan is shorter: the horizons below it
        are refuted by other means) before the first :meth:`solve`, whose first question may
        then be about a higher horizon (a plan found without DIS-PLAN, proved minimal by
        probes below it). No effect once a horizon was tried."""
        if self.floor is None:
            self.floor = self.open_from = int(lowest)

    def close(self, horizon: int) -> None:
        """Horizon L is refuted: fix its activation literal false for good."""
        self.closed.add(horizon)
        self._add([-self.act(horizon)])
        if self.open_from is not None:
            while self.open_from in self.closed:
                self.open_from += 1

    # -- solving -----------------------------------------------------------------
    def solve(
        self, horizon: int, clock: Clock | None = None, *, lowest: int | None = None
    ) -> tuple[SatOutcome, tuple[int, ...] | None]:
        """A region sequence r_0..r_h satisfying every clause, with h = ``horizon`` or,
        given ``lowest``, some h in lowest..horizon (the smallest one the model allows);
        or UNSAT (no plan of any of these horizons); or INTERRUPTED when ``clock`` runs
        out (checked between slices of CaDiCaL conflicts)."""
        lo = horizon if lowest is None else int(lowest)
        if not 0 <= lo <= horizon:
            raise ValueError(f"empty horizon window {lo}..{horizon}")
        if self.floor is None:
            self.floor = self.open_from = lo
            self._to_go_windows()
            if self.preferred is not None:  # prefer() came first: the plan ends at its horizon, not before
                self.solver.set_phases(
                    [-e for e in (self.ends_before(T) for T in range(lo + 1, self.preferred + 1)) if e is not None]
                )
        elif lo < self.floor:
            raise ValueError(f"horizon {lo} is below the first horizon tried ({self.floor})")
        self._extend(horizon)
        for h in range(self.floor, horizon + 1):
            self._ensure_goal(h)
        self.sat_calls += 1
        window = [h for h in range(lo, horizon + 1) if h not in self.closed]
        if not window:
            return SatOutcome.UNSAT, None
        if len(window) == 1:
            assumptions = [self.act(window[0])]
        else:
            select = self.pool.id(("window", lo, horizon))
            self._add([-select] + [self.act(h) for h in window])
            assumptions = [select]
            # the preferred plan's horizon first (its phases describe a plan ending
            # there); without one, short plans: every activation literal false first
            self.solver.set_phases([self.act(h) if h == self.preferred else -self.act(h) for h in window])
        # open horizons below the window are not part of this question
        assumptions += [-self.act(h) for h in range(self.floor, lo) if h not in self.closed]
        while True:
            if clock is not None and clock.exhausted():
                return SatOutcome.INTERRUPTED, None
            self.solver.conf_budget(self._slice)
            t0 = time.perf_counter()
            answer = self.solver.solve_limited(assumptions=assumptions)
            took = time.perf_counter() - t0
            self.sat_slices += 1
            if answer is None:
                if took < SLICE_SECONDS / 2:
                    self._slice = min(MAX_CONFLICTS_PER_SLICE, self._slice * 2)
                elif took > SLICE_SECONDS:
                    self._slice = max(MIN_CONFLICTS_PER_SLICE, int(self._slice * SLICE_SECONDS / took))
                continue
            if answer is False:
                return SatOutcome.UNSAT, None
            break
        model = self.solver.get_model()
        true = {v for v in model if v > 0}
        # the plan ends at the smallest horizon whose activation literal is true: every
        # guarded clause then holds for it (see before())
        horizon = next(h for h in range(self.floor, horizon + 1) if self.act(h) in true)
        if self.paths:
            return SatOutcome.SAT, self._walk_back(true, horizon)
        plan: list[int | None] = [None] * (horizon + 1)
        for v in model:
            if v > 0:
                key = self.pool.obj(v)
                if key is not None and key[0] == "at" and key[1] <= horizon:
                    if plan[key[1]] is not None:  # pragma: no cover - exactly-one forbids it
                        raise AssertionError(f"SAT model puts time {key[1]} in two regions")
                    plan[key[1]] = key[2]
        if any(r is None for r in plan):  # pragma: no cover - exactly-one forbids it
            raise AssertionError("SAT model leaves a time step without a region")
        return SatOutcome.SAT, tuple(int(r) for r in plan)  # type: ignore[arg-type]

    def _walk_back(self, true: set[int], horizon: int) -> tuple[int, ...]:
        """The ``paths`` encoding's plan: from a true goal region at ``horizon`` back to
        t = 0, each step the region itself when its bit is true, else a true neighbour
        (the backward clauses guarantee one; see the class docstring)."""
        g = self.graph
        obj = self.pool.obj2id

        def on(t: int, i: int) -> bool:
            v = obj.get(("at", t, i))
            return v is not None and v in true

        r = next((i for i in g.goal_regions if on(horizon, i)), None)
        if r is None:  # pragma: no cover - the goal clause forbids it
            raise AssertionError("SAT model has no goal region at the horizon")
        plan = [r]
        for t in range(horizon, 0, -1):
            r = next((j for j in (r, *g.adjacency[r]) if self.exists(t - 1, j) and on(t - 1, j)), None)
            if r is None:  # pragma: no cover - the backward clauses forbid it
                raise AssertionError(f"SAT model has no predecessor at time {t - 1}")
            plan.append(r)
        if plan[-1] not in self._starts:  # pragma: no cover - only start regions exist at t = 0
            raise AssertionError("SAT model's walk does not start in a start region")
        return tuple(plan[::-1])

    def prefer(self, plan: Sequence[int]) -> None:
        """Set the SAT solver's decision phases to ``plan`` (r_0..r_h): b[t, plan[t]]
        true, the other regions false, and the plan ending at h (a window that contains h
        tries h first). Only a hint; no answer depends on it."""
        H = len(plan) - 1
        self.preferred = H
        self._extend(H)
        if self.paths:
            obj = self.pool.obj2id
            phases = [
                v if i == r else -v
                for t, r in enumerate(plan)
                for i in range(self.graph.n_regions)
                if (v := obj.get(("at", t, i))) is not None
            ]
        else:
            phases = [
                self.at(t, i) if i == r else -self.at(t, i)
                for t, r in enumerate(plan)
                for i in range(self.graph.n_regions)
            ]
        if self.floor is not None:  # ... and ending at H, not before
            phases += [-e for e in (self.ends_before(T) for T in range(self.floor + 1, H + 1)) if e is not None]
        if self.paths:  # no auxiliary variables to phase
            self.solver.set_phases(phases)
            return
        # the auxiliary variables of the exactly-one encoding (seqcounter, beyond 8
        # regions) as the plan implies them: unphased, their default phase would steer
        # the search off the plan at once
        ok, implied = self.solver.propagate(assumptions=[self.at(t, r) for t, r in enumerate(plan)])
        if ok:
            phases += [v for v in implied if abs(v) > 0]
        self.solver.set_phases(phases)

    def plan(self, horizon: int) -> tuple[int, ...] | None:
        """Convenience: the region sequence for ``horizon`` or None when UNSAT."""
        outcome, plan = self.solve(horizon)
        return plan if outcome is SatOutcome.SAT else None

    def delete(self) -> None:
        self.solver.delete()

    def __enter__(self) -> DisPlan:
        return self

    def __exit__(self, *exc: object) -> None:
        self.delete()
