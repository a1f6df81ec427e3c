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

The modules around this one: :mod:`~plansynth.reach.lazy.regiongraph` (the graph),
:mod:`~plansynth.reach.lazy.satsolver` (the solver, its outcomes, the clause store and
the slices a call runs in), :mod:`~plansynth.reach.lazy.horizons` (one solver instance
for every horizon: activation literals, windows of horizons, the ``before[T]`` guards)
and :mod:`~plansynth.reach.lazy.hints` (decision phases of a reference plan).

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

from collections.abc import Sequence

from pysat.card import CardEnc, EncType
from pysat.formula import IDPool
from pysat.solvers import Solver

from plansynth.budget import Clock, checkpoint
from plansynth.reach.lazy.conflict import Conflict
from plansynth.reach.lazy.hints import PlanHints
from plansynth.reach.lazy.horizons import HorizonGuards
from plansynth.reach.lazy.regiongraph import RegionGraph
from plansynth.reach.lazy.satsolver import (
    CONFLICTS_PER_SLICE,
    MAX_CONFLICTS_PER_SLICE,
    MIN_CONFLICTS_PER_SLICE,
    SAT_SOLVER,
    SLICE_SECONDS,
    LearnedClauses,
    SatOutcome,
    Slices,
)

__all__ = [
    "RegionGraph",
    "Conflict",
    "DisPlan",
    "SatOutcome",
    "LearnedClauses",
    "CARDINALITY_ENCODINGS",
    "PAIRWISE_MAX_REGIONS",
    "PATHS_MIN_REGIONS",
    "SAT_SOLVER",
    "CONFLICTS_PER_SLICE",
    "MIN_CONFLICTS_PER_SLICE",
    "MAX_CONFLICTS_PER_SLICE",
    "SLICE_SECONDS",
]

CARDINALITY_ENCODINGS = {
    "pairwise": EncType.pairwise,
    "seqcounter": EncType.seqcounter,
    "ladder": EncType.ladder,
    "totalizer": EncType.totalizer,
}

#: Up to this many regions "exactly one region per step" is pairwise (k(k-1)/2 binary
#: clauses, no auxiliary variables); beyond, the sequential counter (linear in k).
PAIRWISE_MAX_REGIONS = 8
#: Beyond this many regions ``cardinality="auto"`` is the ``paths`` encoding (see
#: :class:`DisPlan`): no cardinality constraint, variables only where the time windows
#: allow them (the GCS paper's 50 x 50 maze: 1,571 regions over ~600 steps).
PATHS_MIN_REGIONS = 200


class DisPlan(HorizonGuards, PlanHints, LearnedClauses):
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
        self._slices = Slices()
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

    @property
    def sat_slices(self) -> int:
        """The slices of conflicts the SAT calls ran in (:class:`~plansynth.reach.lazy.satsolver.Slices`)."""
        return self._slices.slices

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
        lits = self._literals(c, shift)
        if lits is None:
            return  # a literal that is false in every plan: the clause holds already
        clause = [-v for v in lits]
        if guard is not None:
            clause.append(-guard)
        else:
            short = self.before(c.last_time + shift)
            if short is not None:
                clause.append(short)
        self._learn_clause(clause)

    def _literals(self, c: Conflict, shift: int) -> list[int] | None:
        """The variables of ``c``'s literals shifted by ``shift``, or None when one of
        them is false in every plan. (Points along segments, ``c.vias``, exist only in
        :class:`~plansynth.reach.lazy.segments.SegmentDisPlan`.)"""
        if c.vias:
            raise ValueError("a conflict about points along segments needs a SegmentDisPlan")
        if not all(self.exists(t + shift, i) for t, i in c.literals):
            return None
        return [self.at(t + shift, i) for t, i in c.literals]

    def _rest_shifts(self, c: Conflict) -> range:
        """The shifts at which a start-anchored conflict holds: 0, and with
        ``waits_at_start`` every earlier shift that keeps its literals at times >= 0
        (a trajectory for the shifted claims, preceded by that many steps of waiting at
        the start, would realise the conflict itself; with the goal anchored, the
        horizon moves along, down to the first horizon tried)."""
        if not self.waits_at_start or not (c.literals or c.vias):
            return range(0, -1, -1)
        lowest = min([t for t, _ in c.literals] + [t for t, _, _ in c.vias])
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
        self._open(lo)
        self._extend(horizon)
        for h in range(self.floor, horizon + 1):
            self._ensure_goal(h)
        self.sat_calls += 1
        assumptions = self._window(lo, horizon)
        if assumptions is None:
            return SatOutcome.UNSAT, None
        outcome = self._slices.solve(self.solver, assumptions, clock)
        if outcome is not SatOutcome.SAT:
            return outcome, None
        model = self.solver.get_model()
        true = {v for v in model if v > 0}
        horizon = self._ended(true, horizon)
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
