"""The joint DIS-PLAN: one SAT question per horizon over every robot's region sequence
and the pairs' sides (Shoukry et al., CDC 2016, Section IV, for each robot; the SMC
encoding of separation, CDC 2017, Section IV, for each pair).

For a horizon L the formula has, per robot r, the variables ``at[r, t, i]`` of
:class:`~plansynth.reach.lazy.displan.DisPlan` (exactly one region per step, the start
regions at 0, transitions along the robot's region graph, its goal regions at L, and the
time windows of :func:`~plansynth.reach.lazy.bounds.time_windows` as unit clauses), or,
for a robot with a mission, the finite-trace bounded encoding of its LTL formula over the
labels of its regions (:meth:`TeamDisPlan._mission`: the last position repeats forever,
as the mission checker reads a finite plan). Per engaged pair step (i, j, t) the
variables ``side[i, j, t, k]``, at least one true ("the pair keeps side k during step
t"), and two opposite sides never on consecutive steps (the pair cannot switch between
them at one sample). Likewise per engaged robot-obstacle step.

**Horizons.** Each horizon has its own solver (built when it is first tried, dropped
when it is refuted); every clause learned holds where :meth:`TeamConflict.shifts
<plansynth.reach.team.plans.TeamConflict.shifts>` says, and is added to each open
horizon's solver at those shifts. Engaged pair steps hold at every horizon.

**Decision phases** (only hints; no answer depends on them): each robot's reference plan
(:func:`~plansynth.reach.lazy.guide.reference_plan`, its route at constant speed), and
for each engaged side the side the latest trajectories keep best (:attr:`side_hints`).

>>> from plansynth.reach.lazy.displan import RegionGraph
>>> g = RegionGraph(1, ((),), (0,), (0,))
>>> d = TeamDisPlan([g, g], pair_sides={(0, 1): (4, (2, 3, 0, 1))})
>>> out, plan = d.solve(2); out.value, plan.regions, dict(plan.sides)
('sat', ((0, 0, 0), (0, 0, 0)), {})
>>> d.learn(Engage(pairs=((0, 1, 0), (0, 1, 1))))
>>> out, plan = d.solve(2); sorted(plan.sides)
[(0, 1, 0), (0, 1, 1)]
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence

import numpy as np
from pysat.card import CardEnc, EncType
from pysat.formula import IDPool
from pysat.solvers import Solver

from plansynth.budget import Clock, checkpoint
from plansynth.reach.lazy.displan import RegionGraph, SatOutcome
from plansynth.reach.ltl import And, Const, Finally, Formula, Globally, Next, Not, Or, Prop, Release, Until
from plansynth.reach.team.plans import Engage, TeamConflict, TeamPlan

__all__ = ["TeamDisPlan", "RobotMission", "SAT_SOLVER"]

SAT_SOLVER = "cadical195"
PAIRWISE_MAX = 8
SLICE_CONFLICTS = 5_000


class RobotMission:
    """A robot's mission for DIS-PLAN: the formula in negation normal form and, per
    region of its (label-refined) decomposition, the labels the region lies in."""

    def __init__(self, formula: Formula, labels_of: Sequence[frozenset[str]]) -> None:
        self.formula = formula
        self.labels_of = list(labels_of)


class _Frame:
    """The SAT instance of one horizon."""

    def __init__(self, horizon: int) -> None:
        self.horizon = horizon
        self.pool = IDPool()
        self.solver = Solver(name=SAT_SOLVER)
        self.conflicts_added = 0
        self.engaged_added = 0
        self.engaged_added_o = 0
        self.clauses = 0
        #: per robot, the variables at[r, t, i] as an array (t, i)
        self.at_ids: dict[int, np.ndarray] = {}
        #: the reference plans' phases (fixed for the frame), computed at its first question
        self.guide_phases: list[int] | None = None

    def add(self, clause: list[int]) -> None:
        self.solver.add_clause(clause)
        self.clauses += 1


class TeamDisPlan:
    """The joint DIS-PLAN (see the module docstring), a
    :class:`~plansynth.reach.lazy.loop.PlanSource` of :class:`TeamPlan` values.

    ``graphs[r]``: robot r's region graph (its start and goal regions); ``windows[r]``:
    ``(earliest, to_go)`` per region, or None; ``missions[r]``: a :class:`RobotMission`
    (then the goal regions are not asked for) or None. ``pair_sides[(i, j)]`` and
    ``obstacle_sides[(r, o)]``: ``(number of sides, opposite side of each)`` of each
    pair and robot-obstacle couple that can meet (the others never engage).
    ``guide(r, L)``: robot r's reference region sequence for horizon L, or None.
    """

    def __init__(
        self,
        graphs: Sequence[RegionGraph],
        *,
        windows: Sequence[tuple[Sequence[float], Sequence[float]] | None] | None = None,
        missions: Sequence[RobotMission | None] | None = None,
        pair_sides: Mapping[tuple[int, int], tuple[int, tuple[int | None, ...]]] | None = None,
        obstacle_sides: Mapping[tuple[int, int], tuple[int, tuple[int | None, ...]]] | None = None,
        guide: Callable[[int, int], Sequence[int] | None] | None = None,
    ) -> None:
        self.graphs = list(graphs)
        self.n = len(self.graphs)
        self.windows = list(windows) if windows is not None else [None] * self.n
        self.missions = list(missions) if missions is not None else [None] * self.n
        self.pair_sides = dict(pair_sides or {})
        self.obstacle_sides = dict(obstacle_sides or {})
        self.guide = guide
        self.closed: set[int] = set()
        self.frames: dict[int, _Frame] = {}
        self.conflicts: list[TeamConflict] = []
        self.engaged_pairs: list[tuple[int, int, int]] = []
        self.engaged_obstacles: list[tuple[int, int, int]] = []
        self._engaged: set[tuple] = set()
        #: the side each engaged step keeps best in the latest trajectories (phases)
        self.side_hints: dict[tuple, int] = {}
        #: per horizon, sides that take precedence over :attr:`side_hints` (an incumbent's)
        self.horizon_hints: dict[int, dict[tuple, int]] = {}
        self.sat_calls = 0
        self.clauses = 0  # learned clauses, counting shifted copies
        self.sat_seconds = 0.0

    # -- the PlanSource interface -------------------------------------------------
    def solve(
        self, horizon: int, clock: Clock | None = None, *, lowest: int | None = None
    ) -> tuple[SatOutcome, TeamPlan | None]:
        """A plan of horizon ``horizon`` (``lowest`` must be the same: one horizon per
        question), UNSAT, or INTERRUPTED when the clock runs out."""
        if lowest is not None and lowest != horizon:
            raise ValueError("the joint DIS-PLAN answers for one horizon at a time")
        frame = self._frame(horizon)
        self._catch_up(frame)
        frame.solver.set_phases(self._phases(frame))
        self.sat_calls += 1
        while True:
            if clock is not None and clock.out_of_time():
                return SatOutcome.INTERRUPTED, None
            frame.solver.conf_budget(SLICE_CONFLICTS)
            t0 = time.perf_counter()
            answer = frame.solver.solve_limited()
            self.sat_seconds += time.perf_counter() - t0
            if answer is None:
                continue
            if answer is False:
                return SatOutcome.UNSAT, None
            return SatOutcome.SAT, self._read(frame)

    def learn(self, fact: TeamConflict | Engage) -> None:
        """A counterexample (a clause at every shift where it holds) or an engagement."""
        if isinstance(fact, Engage):
            for key in fact.pairs:
                if ("p", *key) not in self._engaged and key[:2] in self.pair_sides:
                    self._engaged.add(("p", *key))
                    self.engaged_pairs.append(key)
            for key in fact.obstacles:
                if ("o", *key) not in self._engaged and key[:2] in self.obstacle_sides:
                    self._engaged.add(("o", *key))
                    self.engaged_obstacles.append(key)
            return
        self.conflicts.append(fact)

    def close(self, horizon: int) -> None:
        """No plan of this horizon exists: drop its solver."""
        self.closed.add(horizon)
        frame = self.frames.pop(horizon, None)
        if frame is not None:
            frame.solver.delete()

    def delete(self) -> None:
        for frame in self.frames.values():
            frame.solver.delete()
        self.frames.clear()

    # -- variables ------------------------------------------------------------------
    @staticmethod
    def at(frame: _Frame, r: int, t: int, i: int) -> int:
        ids = frame.at_ids.get(r)
        if ids is not None and 0 <= t < ids.shape[0] and 0 <= i < ids.shape[1]:
            return int(ids[t, i])
        return frame.pool.id(("at", r, t, i))  # (outside the frame's steps: a fresh variable)

    @staticmethod
    def side(frame: _Frame, i: int, j: int, t: int, k: int) -> int:
        return frame.pool.id(("side", i, j, t, k))

    @staticmethod
    def mside(frame: _Frame, r: int, o: int, t: int, k: int) -> int:
        return frame.pool.id(("mside", r, o, t, k))

    def _var(self, frame: _Frame, lit: tuple) -> int:
        if lit[0] == "at":
            return self.at(frame, *lit[1:])
        return frame.pool.id(lit)

    # -- encoding -------------------------------------------------------------------
    def _frame(self, L: int) -> _Frame:
        frame = self.frames.get(L)
        if frame is not None:
            return frame
        frame = _Frame(L)
        for r, g in enumerate(self.graphs):
            checkpoint()
            self._robot(frame, r, g, L)
        self.frames[L] = frame
        return frame

    def _robot(self, frame: _Frame, r: int, g: RegionGraph, L: int) -> None:
        """Robot r's clauses at horizon L. Its variables ``at[r, t, i]`` are numbered
        as :meth:`at` would number them one by one (t-major, next in the pool), and its
        clauses come in the order of the step-by-step encoding, built from lists of
        numbers rather than one pool look-up per literal (the horizon's frame is made
        anew for every horizon tried)."""
        mission = self.missions[r]
        N = g.n_regions
        pool = frame.pool
        first = pool.top + 1
        pool.top += (L + 1) * N
        ids = np.arange(first, first + (L + 1) * N, dtype=np.int64).reshape(L + 1, N)
        frame.at_ids[r] = ids
        rows = ids.tolist()
        forbidden = self._forbidden(r, N, L)
        pairwise = N <= PAIRWISE_MAX
        pairs = _pairs(N) if pairwise else ()
        nbrs = self._neighbours(r, g)
        clauses: list[list[int]] = []
        add = clauses.append
        for t in range(L + 1):
            lits = rows[t]
            for i in forbidden[t]:
                add([-lits[i]])
            if pairwise:  # exactly one: CardEnc's pairwise clauses, in its order
                add(list(lits))
                clauses.extend([-lits[a], -lits[b]] for a, b in pairs)
            else:
                clauses.extend(CardEnc.equals(lits=lits, bound=1, vpool=pool, encoding=EncType.seqcounter).clauses)
            if t < L:
                nxt = rows[t + 1]
                clauses.extend([-lits[i], *[nxt[j] for j in nb]] for i, nb in enumerate(nbrs))
        add([rows[0][i] for i in g.start_regions])
        if mission is None:
            add([rows[L][i] for i in g.goal_regions])
        solver = frame.solver
        for c in clauses:
            solver.add_clause(c)
        frame.clauses += len(clauses)
        if mission is not None:
            self._mission(frame, r, mission, L)

    def _forbidden(self, r: int, N: int, L: int) -> list[list[int]]:
        """Per step t, the regions robot r's time windows rule out at horizon L."""
        w = self.windows[r]
        if w is None:
            return [[] for _ in range(L + 1)]
        earliest, to_go = (np.asarray(a, float) for a in w)
        t = np.arange(L + 1)[:, None]
        ok = (t >= earliest[None, :]) & (L - t >= to_go[None, :])
        return [np.flatnonzero(~row).tolist() for row in ok]

    def _neighbours(self, r: int, g: RegionGraph) -> list[tuple[int, ...]]:
        """Per region of robot r, itself and its neighbours (the next step's choices)."""
        cache = self.__dict__.setdefault("_nbrs", {})
        if r not in cache:
            cache[r] = [(i, *g.adjacency[i]) for i in range(g.n_regions)]
        return cache[r]

    def _mission(self, frame: _Frame, r: int, mission: RobotMission, L: int) -> None:
        """The finite-trace bounded encoding of robot r's mission (NNF): ``[[f]]_t ->``
        its expansion at t; position L repeats forever, so at L every temporal operator
        reads its argument(s) there (``X a``, ``F a``, ``G a``: a at L; ``a U b``,
        ``a R b``: b at L)."""

        def v(f: Formula, t: int) -> int:
            return frame.pool.id(("ltl", r, f, t))

        def expand(f: Formula, t: int) -> None:
            key = ("ltl-done", r, f, t)
            if key in frame.pool.obj2id:
                return
            frame.pool.id(key)
            x = v(f, t)
            if isinstance(f, Const):
                if not f.value:
                    frame.add([-x])
                return
            if isinstance(f, (Prop, Not)):
                name = f.name if isinstance(f, Prop) else f.arg.name
                want = isinstance(f, Prop)
                regs = [i for i, labels in enumerate(mission.labels_of) if (name in labels) == want]
                frame.add([-x] + [self.at(frame, r, t, i) for i in regs])
                return
            nxt = min(t + 1, L)
            last = t == L
            if isinstance(f, And):
                frame.add([-x, v(f.left, t)])
                frame.add([-x, v(f.right, t)])
                expand(f.left, t)
                expand(f.right, t)
            elif isinstance(f, Or):
                frame.add([-x, v(f.left, t), v(f.right, t)])
                expand(f.left, t)
                expand(f.right, t)
            elif isinstance(f, Next):
                frame.add([-x, v(f.arg, nxt)])
                expand(f.arg, nxt)
            elif isinstance(f, Finally):
                frame.add([-x, v(f.arg, t)] + ([] if last else [v(f, nxt)]))
                expand(f.arg, t)
                if not last:
                    expand(f, nxt)
            elif isinstance(f, Globally):
                frame.add([-x, v(f.arg, t)])
                expand(f.arg, t)
                if not last:
                    frame.add([-x, v(f, nxt)])
                    expand(f, nxt)
            elif isinstance(f, Until):
                frame.add([-x, v(f.right, t)] + ([] if last else [v(f.left, t)]))
                expand(f.right, t)
                if not last:
                    frame.add([-x, v(f.right, t), v(f, nxt)])
                    expand(f.left, t)
                    expand(f, nxt)
            elif isinstance(f, Release):
                frame.add([-x, v(f.right, t)])
                expand(f.right, t)
                if not last:
                    frame.add([-x, v(f.left, t), v(f, nxt)])
                    expand(f.left, t)
                    expand(f, nxt)
            else:  # pragma: no cover - NNF has no other operator
                raise TypeError(f"not in negation normal form: {f}")

        frame.add([v(mission.formula, 0)])
        expand(mission.formula, 0)

    def _catch_up(self, frame: _Frame) -> None:
        """Add the engagements and conflicts learned since the frame last asked."""
        L = frame.horizon
        for key in self.engaged_pairs[frame.engaged_added :]:
            i, j, t = key
            if t < L:
                n_sides, _ = self.pair_sides[(i, j)]
                frame.add([self.side(frame, i, j, t, k) for k in range(n_sides)])
                self._switches(frame, ("side", i, j), t, self.pair_sides[(i, j)][1], L)
        frame.engaged_added = len(self.engaged_pairs)
        for key in self.engaged_obstacles[frame.engaged_added_o :]:
            r, o, t = key
            if t < L:
                n_sides, _ = self.obstacle_sides[(r, o)]
                frame.add([self.mside(frame, r, o, t, k) for k in range(n_sides)])
                self._switches(frame, ("mside", r, o), t, self.obstacle_sides[(r, o)][1], L)
        frame.engaged_added_o = len(self.engaged_obstacles)
        for c in self.conflicts[frame.conflicts_added :]:
            for s in c.shifts(L):
                clause = [-self._var(frame, _shifted(lit, s)) for lit in c.literals]
                frame.add(clause)
                self.clauses += 1
        frame.conflicts_added = len(self.conflicts)

    def _switches(self, frame: _Frame, head: tuple, t: int, opposite: tuple[int | None, ...], L: int) -> None:
        """A pair cannot keep a side in step t and its opposite in step t +- 1 (the two
        would hold together at the sample they share)."""
        for u in (t - 1, t + 1):
            if not 0 <= u < L:
                continue
            for k, ko in enumerate(opposite):
                if ko is not None:
                    frame.add([-frame.pool.id((*head, t, k)), -frame.pool.id((*head, u, ko))])

    def _phases(self, frame: _Frame) -> list[int]:
        L = frame.horizon
        if frame.guide_phases is None:
            frame.guide_phases = []
            for r in range(self.n) if self.guide is not None else ():
                ref = self.guide(r, L)
                if ref is not None:
                    ref = tuple(ref)[: L + 1]
                    ids = frame.at_ids[r]
                    signs = -np.ones(ids.shape, dtype=np.int64)
                    signs[np.arange(len(ref)), np.asarray(ref)] = 1
                    frame.guide_phases.extend((ids[: len(ref)] * signs[: len(ref)]).ravel().tolist())
        out = list(frame.guide_phases)
        hints = {**self.side_hints, **self.horizon_hints.get(L, {})}
        for key, k in hints.items():
            kind, a, b, t = key
            if t >= L:
                continue
            sides = (self.pair_sides if kind == "side" else self.obstacle_sides).get((a, b))
            if sides is None:
                continue
            for kk in range(sides[0]):
                v = frame.pool.id((kind, a, b, t, kk))
                out.append(v if kk == k else -v)
        return out

    def _hint(self, L: int, key: tuple) -> int | None:
        own = self.horizon_hints.get(L, {})
        return own[key] if key in own else self.side_hints.get(key)

    def _read(self, frame: _Frame) -> TeamPlan:
        model = np.asarray(frame.solver.get_model())
        true = set(model[model > 0].tolist())
        value = np.zeros(max(len(model), frame.pool.top) + 1, dtype=bool)
        value[model[model > 0]] = True
        L = frame.horizon
        regions = [tuple(value[frame.at_ids[r]].argmax(axis=1).tolist()) for r in range(self.n)]
        sides = {}
        for i, j, t in self.engaged_pairs:
            if t < L:
                n_sides = self.pair_sides[(i, j)][0]
                sides[(i, j, t)] = _first_true(
                    true, frame, ("side", i, j, t), n_sides, self._hint(L, ("side", i, j, t))
                )
        msides = {}
        for r, o, t in self.engaged_obstacles:
            if t < L:
                n_sides = self.obstacle_sides[(r, o)][0]
                msides[(r, o, t)] = _first_true(
                    true, frame, ("mside", r, o, t), n_sides, self._hint(L, ("mside", r, o, t))
                )
        return TeamPlan(tuple(regions), sides, msides)


def _pairs(n: int) -> list[tuple[int, int]]:
    """The pairs a < b of n items, in lexicographic order (the at-most-one clauses)."""
    return [(a, b) for a in range(n) for b in range(a + 1, n)]


def _first_true(true: set[int], frame: _Frame, head: tuple, n_sides: int, hint: int | None) -> int:
    """The side to ask CON-PLAN for among those the model sets: the hint when it is one."""
    ks = [k for k in range(n_sides) if frame.pool.id((*head, k)) in true]
    return hint if hint in ks else ks[0]


def _shifted(lit: tuple, s: int) -> tuple:
    if s == 0:
        return lit
    if lit[0] == "at":
        return ("at", lit[1], lit[2] + s, lit[3])
    return (lit[0], lit[1], lit[2], lit[3] + s, lit[4])
