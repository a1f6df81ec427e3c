"""DIS-PLAN for an LTL mission: the linear bounded model checking encoding.

Biere, Heljanko, Junttila, Latvala and Schuppan, "Linear encoding of bounded LTL model
checking" (LMCS 2006, Section 4, the encoding with loop selectors), over the region
variables ``b[t, i]`` of DIS-PLAN (Shoukry et al., CDC 2016, Section IV), incremental
in the horizon L in one CaDiCaL solver.

A plan of horizon L is a region sequence r_0..r_L and a *successor of the last
position* s in 1..L, chosen by exactly one loop selector:

* ``loop[L, j]`` (a lasso, j = k + 1): x_L = x_k, so the robot repeats x_k..x_L
  forever; DIS-PLAN asks r_L = r_k, CON-PLAN asks x_L = x_k;
* ``stay[L]`` (a finite plan): with the end at rest, s = L, the last position repeats
  (the robot stays in its last region: the reading of :mod:`plansynth.reach.mission.ltl`);
  with a free end the word ends at L (LTL on finite traces): ``X f`` is false at L,
  ``F``/``U`` must be met by L, ``G``/``R`` and the weak next ask nothing past L (the
  virtual position L + 1 is left free, and the eventualities need no loop).

For every subformula psi of the mission in negation normal form and every position
i there is a variable [[psi]]_i, with the one-sided (polarity) clauses
``[[psi]]_i -> <psi's expansion at i>`` (``a U b`` at i: b_i, or a_i and [[a U b]]_{i+1};
``X a``: [[a]]_{i+1}; labels: the region at i lies in the label, or outside it, at the
label's margin: ``labels_of`` and ``negs_of`` of the label reading). Bounded operators are
encoded as their unrolling (:func:`~plansynth.reach.ltl.syntax.unroll`: chains of ``X``
whose copies share their subformula, about 2 (b + 1) nodes for ``F[a,b] f``). These
clauses never change with L: position i's clauses mention position i + 1, which at
horizon L is the virtual position L + 1 whose values are those of position s
(``selector -> ([[psi]]_{L+1} -> [[psi]]_s)``, guarded by the horizon's activation
literal ``act[L]``), and a real position once the horizon grows past L. So moving from
L to L + 1 adds clauses and never retracts one, and every clause learned from CON-PLAN
stays (Heljanko, Junttila and Latvala, CAV 2005, make the same observation).

Eventualities: the circular loop admits the unwanted fixpoint for ``U``/``F`` (an
eventuality "postponed forever"). As in Biere et al.'s linear encoding, per horizon a
chain ``in[L, i]`` (position i lies in the loop) and per until-formula a chain
``<<F b>>[L, i]`` (b holds at a loop position <= i) give the constraint
``act[L] & [[a U b]]_L -> <<F b>>[L, L]``. ``R``/``G`` need none (their circular
reading is the greatest fixpoint, which is the right one).

Conflicts from CON-PLAN (:class:`~plansynth.reach.lazy.conflict.Conflict`) become clauses as
in :class:`~plansynth.reach.lazy.displan.DisPlan`: start-anchored ones at their absolute
times, the others at every time shift; goal-anchored ones only for their horizon
(CON-PLAN plans a mission with the whole workspace as the goal). A lasso whose loop
CON-PLAN refutes is blocked together with its loop selector (:meth:`learn_loop`); a loop
refuted without the start holds for the same loop at every later horizon as well.

>>> from plansynth.reach.lazy.displan import RegionGraph
>>> from plansynth.reach.mission.ltl import parse
>>> g = RegionGraph(3, ((1,), (0, 2), (1,)), start_regions=(0,), goal_regions=(0, 1, 2))
>>> d = MissionDisPlan(g, [frozenset(), frozenset(), frozenset({"a"})], parse("G F a"))
>>> d.solve(1)[0].value              # a is two steps away
'unsat'
>>> d.close(1); out, plan = d.solve(2); plan
MissionPlan(regions=(0, 1, 2), loop_start=None)
>>> d.close(2); d.solve(3)[1]        # G F a with stay: the plan ends in a; or a loop
MissionPlan(regions=(0, 1, 2, 2), loop_start=None)
"""

from __future__ import annotations

import time
from collections.abc import Sequence

from pysat.card import CardEnc, EncType
from pysat.formula import IDPool
from pysat.solvers import Solver

from plansynth.budget import Clock, checkpoint
from plansynth.reach.lazy.conflict import Conflict
from plansynth.reach.lazy.displan import PAIRWISE_MAX_REGIONS
from plansynth.reach.lazy.regiongraph import RegionGraph
from plansynth.reach.lazy.satsolver import CONFLICTS_PER_SLICE, SAT_SOLVER, LearnedClauses, SatOutcome
from plansynth.reach.mission.ltl import (
    And,
    Const,
    Finally,
    Formula,
    Globally,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
    WeakNext,
    children,
    nnf,
    subformulas,
    unroll,
)
from plansynth.reach.mission.options import SEMANTICS
from plansynth.reach.mission.plans import LoopConflict, MissionPlan, StayConflict

__all__ = ["MissionDisPlan", "MissionPlan", "SEMANTICS"]


class MissionDisPlan(LearnedClauses):
    """One incremental SAT instance for the mission over growing horizons.

    ``labels_of[i]``: the labels that hold in region i; ``negs_of[i]``: those whose
    negation holds there (default: every other label; with margins a region in a label's
    band holds neither). ``end``: how a finite plan ends, ``rest`` or ``free`` (the
    problem's; see the module doc).
    ``semantics``: which plans to look for: ``finite`` (stay selectors only),
    ``lasso`` (loop selectors only) or ``any`` (both; finite plans are tried first by
    the decision phases). ``earliest[i]``: region i is impossible before that step (a
    sound relaxation, :func:`~plansynth.reach.lazy.bounds.time_windows`). ``waits_at_start``:
    the robot starts at rest (``A x_0 = x_0``), so start-anchored conflicts also hold
    shifted earlier (as in :class:`~plansynth.reach.lazy.displan.DisPlan`).
    Counters: ``sat_calls``, ``clauses`` (learned), ``loop_clauses``.
    """

    def __init__(
        self,
        graph: RegionGraph,
        labels_of: Sequence[frozenset[str]],
        formula: Formula,
        *,
        semantics: str = "any",
        earliest: Sequence[float] | None = None,
        waits_at_start: bool = False,
        negs_of: Sequence[frozenset[str]] | None = None,
        end: str = "rest",
    ) -> None:
        if end not in ("rest", "free"):
            raise ValueError(f"unknown end {end!r} (known: rest, free)")
        if semantics not in SEMANTICS:
            raise ValueError(f"unknown semantics {semantics!r} (known: {', '.join(SEMANTICS)})")
        if len(labels_of) != graph.n_regions:
            raise ValueError(f"labels for {len(labels_of)} regions, the graph has {graph.n_regions}")
        self.graph = graph
        self.labels_of = [frozenset(s) for s in labels_of]
        if negs_of is None:
            names = frozenset().union(*self.labels_of) if self.labels_of else frozenset()
            names |= {g.name for g in subformulas(formula) if isinstance(g, Prop)}
            negs_of = [names - s for s in self.labels_of]
        self.negs_of = [frozenset(s) for s in negs_of]
        self.end = end
        self.formula = unroll(nnf(formula))
        self.semantics = semantics
        self.subs = [s for s in subformulas(self.formula) if not isinstance(s, Const)]
        self.index = {s: k for k, s in enumerate(self.subs)}
        # the index of every node of the formula's tree by identity: v() is asked for
        # [[f]]_i for each subformula and position, and a formula's own hash walks its
        # whole subtree (frozen dataclasses); the tree is held by self.formula, so no
        # other live object shares an id with one of its nodes
        self._ids: dict[int, int] = {}
        todo = [self.formula]
        while todo:
            g = todo.pop()
            if id(g) in self._ids or isinstance(g, Const):
                continue
            self._ids[id(g)] = self.index[g]
            todo.extend(children(g))
        # the subformulas whose value at position i + 1 the clauses of position i use
        nxt: list[Formula] = []
        for s in self.subs:
            if isinstance(s, (Next, WeakNext)) and not isinstance(s.arg, Const):
                nxt.append(s.arg)
            if isinstance(s, (Finally, Globally, Until, Release)):
                nxt.append(s)
        self.next_subs = list(dict.fromkeys(nxt))
        self.pool = IDPool()
        self._rows: list[list[int]] = []
        self.solver = Solver(name=SAT_SOLVER)
        self.true = self.pool.id(("true",))
        self.solver.add_clause([self.true])
        self.earliest = list(earliest) if earliest is not None else [0] * graph.n_regions
        self.waits_at_start = bool(waits_at_start)
        self.built = -1
        self.bounded: set[int] = set()
        self.closed: set[int] = set()
        self.conflicts: list[Conflict] = []
        self.loop_conflicts: list[tuple[tuple[tuple[int, int], ...], int, int, bool]] = []
        self._learned: set[tuple[int, ...]] = set()
        self.sat_calls = 0
        self.encode_seconds = 0.0  # building positions and horizon boundaries (in solve)
        self.clauses = 0
        self.loop_clauses = 0
        self.stay_clauses = 0  # finite plans refuted for not ending at rest (learn_stay)
        self._add([self.v(self.formula, 0)])

    # -- variables ---------------------------------------------------------------
    def at(self, t: int, i: int) -> int:
        """b[t, i]: the position at time t lies in region i."""
        return self.row(t)[i]

    def row(self, t: int) -> list[int]:
        """[b[t, 0], ..., b[t, n-1]] (cached: the encoding asks for them very often)."""
        while len(self._rows) <= t:
            u = len(self._rows)
            self._rows.append([self.pool.id(("at", u, i)) for i in range(self.graph.n_regions)])
        return self._rows[t]

    def act(self, horizon: int) -> int:
        return self.pool.id(("horizon", horizon))

    def v(self, f: Formula, i: int) -> int:
        """The literal [[f]]_i (constants are the fixed literal ``true`` or its negation)."""
        k = self._ids.get(id(f))
        if k is None:
            if isinstance(f, Const):
                return self.true if f.value else -self.true
            k = self.index[f]
        return self.pool.id(("f", k, i))

    def loop(self, horizon: int, j: int) -> int:
        """The selector "the successor of position L is j" with x_L = x_{j-1} (lasso)."""
        return self.pool.id(("loop", horizon, j))

    def stay(self, horizon: int) -> int:
        """The selector "the successor of position L is L" (finite plan)."""
        return self.pool.id(("stay", horizon))

    # -- encoding ----------------------------------------------------------------
    def _add(self, clause: list[int]) -> None:
        self.solver.add_clause(clause)

    def _position(self, t: int) -> None:
        g = self.graph
        lits = list(self.row(t))
        enc = CardEnc.equals(
            lits=lits,
            bound=1,
            vpool=self.pool,
            encoding=EncType.pairwise if g.n_regions <= PAIRWISE_MAX_REGIONS else EncType.seqcounter,
        )
        for c in enc.clauses:
            self._add(c)
        for i in range(g.n_regions):
            if t < self.earliest[i]:
                self._add([-self.at(t, i)])
        if t == 0:
            self._add([self.at(0, i) for i in g.start_regions])
        else:
            before, now = self.row(t - 1), self.row(t)
            for i in range(g.n_regions):
                self._add([-before[i], now[i]] + [now[j] for j in g.adjacency[i]])
        for k, f in enumerate(self.subs):
            if k % 1024 == 0:
                checkpoint()  # a long mission: its encoding keeps the budget too
            self._expand(f, t)

    def _expand(self, f: Formula, i: int) -> None:
        """The clauses ``[[f]]_i -> expansion of f at i`` (negation normal form)."""
        v = self.v(f, i)
        n = self.graph.n_regions
        if isinstance(f, Prop):
            row = self.row(i)
            self._add([-v] + [row[r] for r in range(n) if f.name in self.labels_of[r]])
        elif isinstance(f, Not):
            assert isinstance(f.arg, Prop), "negation normal form"
            row = self.row(i)
            self._add([-v] + [row[r] for r in range(n) if f.arg.name in self.negs_of[r]])
        elif isinstance(f, And):
            self._add([-v, self.v(f.left, i)])
            self._add([-v, self.v(f.right, i)])
        elif isinstance(f, Or):
            self._add([-v, self.v(f.left, i), self.v(f.right, i)])
        elif isinstance(f, (Next, WeakNext)):
            self._add([-v, self.v(f.arg, i + 1)])
        elif isinstance(f, Finally):
            self._add([-v, self.v(f.arg, i), self.v(f, i + 1)])
        elif isinstance(f, Globally):
            self._add([-v, self.v(f.arg, i)])
            self._add([-v, self.v(f, i + 1)])
        elif isinstance(f, Until):
            self._add([-v, self.v(f.right, i), self.v(f.left, i)])
            self._add([-v, self.v(f.right, i), self.v(f, i + 1)])
        elif isinstance(f, Release):
            self._add([-v, self.v(f.right, i)])
            self._add([-v, self.v(f.left, i), self.v(f, i + 1)])
        else:  # pragma: no cover - nnf() leaves no other node
            raise TypeError(f"not in negation normal form: {f!r}")

    def _extend(self, horizon: int) -> None:
        for t in range(self.built + 1, horizon + 1):
            self._position(t)
            self.built = t
            for c in self.conflicts:
                if not c.anchored_start and not c.anchored_goal:
                    self._shift(c, t - c.last_time, None)

    def selectors(self, horizon: int) -> list[tuple[int, int]]:
        """(selector literal, successor position) of the loops allowed at ``horizon``."""
        L = horizon
        out = []
        if self.semantics in ("any", "finite"):
            out.append((self.stay(L), L))
        if self.semantics in ("any", "lasso"):
            out += [(self.loop(L, j), j) for j in range(1, L + 1)]
        return out

    def _boundary(self, horizon: int) -> None:
        """The loop of horizon L, all under ``act[L]``: exactly one selector, the lasso's
        region equality, the virtual position L + 1, the eventuality chains."""
        if horizon in self.bounded:
            return
        self.bounded.add(horizon)
        L, act = horizon, self.act(horizon)
        sels = self.selectors(L)
        self._add([-act] + [s for s, _ in sels])
        for s, _ in sels:
            self._add([-s, act])
        if len(sels) > 1:
            for c in CardEnc.atmost(
                lits=[s for s, _ in sels], bound=1, vpool=self.pool, encoding=EncType.seqcounter
            ).clauses:
                self._add(c)
        free = self.end == "free"
        for s, j in sels:
            if s != self.stay(L):  # x_L = x_{j-1}: the same region
                last, back = self.row(L), self.row(j - 1)
                for i in range(self.graph.n_regions):
                    self._add([-s, -last[i], back[i]])
            elif free:  # the word ends at L: no position L + 1 to map
                self._end_at(s, L)
                continue
            for f in self.next_subs:
                self._add([-s, -self.v(f, L + 1), self.v(f, j)])
        # in[L, i]: position i is in the loop (the successor of L is at or before i)
        inl = [self.pool.id(("in", L, i)) for i in range(L + 1)]
        for i in range(L + 1):
            here = [s for s, j in sels if j == i and not (free and s == self.stay(L))]
            self._add([-inl[i]] + ([inl[i - 1]] if i > 0 else []) + here)
        for f in self.subs:
            if not isinstance(f, (Finally, Until)):
                continue
            b = f.arg if isinstance(f, Finally) else f.right
            fi = self.index[f]
            ev = [self.pool.id(("ev", fi, L, i)) for i in range(L + 1)]
            for i in range(L + 1):
                c = self.pool.id(("evat", fi, L, i))
                self._add([-ev[i]] + ([ev[i - 1]] if i > 0 else []) + [c])
                self._add([-c, inl[i]])
                self._add([-c, self.v(b, i)])
            # a word that ends at L (free end) meets its eventualities by L (_end_at)
            self._add([-act, -self.v(f, L), ev[L]] + ([self.stay(L)] if free else []))
        for c in self.conflicts:
            if c.anchored_goal and not c.anchored_start:
                self._shift(c, L - c.horizon, L)
        for lits, k, h, shifted in self.loop_conflicts:
            if shifted and h != L:
                self._loop_clause(lits, k, h, L - h)

    def _end_at(self, s: int, L: int) -> None:
        """The word ends at L (selector ``s``, free end): the strong next fails there and
        every eventuality at L is met at L; the virtual position L + 1 stays free, so the
        weak next, ``G`` and ``R`` ask nothing past L."""
        for f in self.subs:
            if isinstance(f, Next):
                self._add([-s, -self.v(f, L)])
            elif isinstance(f, (Finally, Until)):
                b = f.arg if isinstance(f, Finally) else f.right
                self._add([-s, -self.v(f, L), self.v(b, L)])

    def _shift(self, c: Conflict, shift: int, horizon: int | None) -> None:
        if c.first_time + shift < 0 or c.last_time + shift > self.built:
            return
        clause = [-self.at(t + shift, i) for t, i in c.literals]
        if horizon is not None:
            clause.append(-self.act(horizon))
        self._learn_clause(clause)

    def learn(self, c: Conflict | LoopConflict | StayConflict) -> None:
        """A counterexample from the mission's theory (Algorithm 1, line 11), for the plan
        of horizon ``c.horizon`` just proposed: CON-PLAN's conflict, a refuted loop
        (:meth:`learn_loop`) or a finite plan that cannot end at rest (:meth:`learn_stay`)."""
        if isinstance(c, LoopConflict):
            self.learn_loop(c.literals, c.loop_start, c.horizon, shifted=c.shifted)
            return
        if isinstance(c, StayConflict):
            self.learn_stay(c.literals, c.horizon)
            return
        self.conflicts.append(c)
        if c.anchored_start and not c.anchored_goal:
            self._shift(c, 0, None)
            if self.waits_at_start and c.literals:
                # the robot can wait at its start: the claims shifted earlier are refuted too
                # (a trajectory for them, after waiting, would realise the conflict itself)
                for shift in range(-1, -min(t for t, _ in c.literals) - 1, -1):
                    self._shift(c, shift, None)
        elif c.anchored_start:
            self._shift(c, 0, c.horizon)
        elif c.anchored_goal:
            for h in sorted(self.bounded - self.closed):
                self._shift(c, h - c.horizon, h)
        else:
            for end in range(c.last_time - c.first_time, self.built + 1):
                self._shift(c, end - c.last_time, None)

    def learn_loop(self, literals: Sequence[tuple[int, int]], loop_start: int, horizon: int, *, shifted: bool) -> None:
        """CON-PLAN refuted the loop x_L = x_k (L = ``horizon``, k = ``loop_start``)
        together with these (time, region) literals: block them with the loop selector.
        ``shifted``: the proof used neither the start nor any step before k, so it holds
        for the same loop ending at every horizon (time-invariant dynamics): the clause
        is added, shifted, at every horizon built later too."""
        k, L = int(loop_start), int(horizon)
        base = tuple(sorted({(int(t), int(r)) for t, r in literals}))
        variants = [base]
        if shifted:
            # a loop is a cycle: a periodic trajectory of period L - k realises the claims
            # rotated by any number of steps iff it realises them unrotated, so every
            # rotation (times k + (t - k + s) mod (L - k)) is refuted by the same LP
            period = L - k
            variants = [tuple(sorted({(k + (t - k + s) % period, r) for t, r in base})) for s in range(period)]
        for lits in dict.fromkeys(variants):
            self.loop_conflicts.append((lits, k, L, bool(shifted)))
            self._loop_clause(lits, k, L, 0)

    def learn_stay(self, literals: Sequence[tuple[int, int]], horizon: int) -> None:
        """A finite plan of horizon L with these (time, region) literals cannot end at
        rest (no admissible input keeps x_L where it is, which the finite reading needs):
        block them with the stay selector, at this horizon only."""
        if self.semantics == "lasso" or self.end == "free":
            return
        L = int(horizon)
        lits = sorted({(int(t), int(r)) for t, r in literals})
        self._learn_clause([-self.at(t, r) for t, r in lits] + [-self.stay(L)])
        self.stay_clauses += 1

    def _loop_clause(self, lits: tuple[tuple[int, int], ...], k: int, L: int, shift: int) -> None:
        if k + shift < 0 or L + shift > self.built + 1 and L + shift not in self.bounded:
            return
        if self.semantics == "finite":
            return
        self._learn_clause([-self.at(t + shift, r) for t, r in lits] + [-self.loop(L + shift, k + shift + 1)])
        self.loop_clauses += 1

    def close(self, horizon: int) -> None:
        """Every plan of horizon L is refuted: ``act[L]`` false for good."""
        self.closed.add(horizon)
        self._add([-self.act(horizon)])

    # -- solving -----------------------------------------------------------------
    def solve(
        self, horizon: int, clock: Clock | None = None, *, lowest: int | None = None
    ) -> tuple[SatOutcome, MissionPlan | None]:
        """A plan of exactly this horizon satisfying the mission and every learned
        clause, UNSAT, or INTERRUPTED when ``clock`` runs out. (One horizon at a time:
        ``lowest``, the lazy loop's window, must be the horizon itself.)"""
        if lowest is not None and lowest != horizon:
            raise ValueError(f"the mission's DIS-PLAN asks one horizon at a time, not {lowest}..{horizon}")
        if horizon < self.built:
            raise ValueError(f"horizons must not decrease: {horizon} after {self.built}")
        t0 = time.perf_counter()
        self._extend(horizon)
        self._boundary(horizon)
        self.encode_seconds += time.perf_counter() - t0
        self.sat_calls += 1
        if horizon in self.closed:
            return SatOutcome.UNSAT, None
        # decision phases (hints only): a finite plan first; else a loop back to the start
        # state (the natural lasso of a robot that starts at rest)
        hints = [s for s, j in self.selectors(horizon) if s == self.stay(horizon) or j == 1]
        self.solver.set_phases(hints)
        while True:
            if clock is not None and clock.exhausted():
                return SatOutcome.INTERRUPTED, None
            self.solver.conf_budget(CONFLICTS_PER_SLICE)
            answer = self.solver.solve_limited(assumptions=[self.act(horizon)])
            if answer is None:
                continue
            if answer is False:
                return SatOutcome.UNSAT, None
            break
        true = {v for v in self.solver.get_model() if v > 0}
        regions = []
        for t in range(horizon + 1):
            row = self.row(t)
            rs = [i for i in range(self.graph.n_regions) if row[i] in true]
            if len(rs) != 1:  # pragma: no cover - exactly-one forbids it
                raise AssertionError(f"SAT model puts time {t} in regions {rs}")
            regions.append(rs[0])
        loop_start = None
        for s, j in self.selectors(horizon):
            if s in true and s != self.stay(horizon):
                loop_start = j - 1
        return SatOutcome.SAT, MissionPlan(tuple(regions), loop_start)

    def delete(self) -> None:
        self.solver.delete()
