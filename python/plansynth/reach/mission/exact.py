"""Exact segment transitions for a mission in the segment reading (beyond Shoukry et al.,
CDC 2016, whose DIS-PLAN puts one region per time step; the reach-avoid case is
:mod:`plansynth.reach.lazy.segments` and :mod:`plansynth.reach.lazy.segtheory`).

In the segment reading step t is the whole segment [p_t, p_{t+1}]: ``a`` holds when the
segment lies in label a (at depth >= its margin), ``!a`` when it stays out (at distance
>= the margin), and a segment that crosses a's edge holds neither. A real step may cross
several regions and labels, so a search that keeps each segment in one region of the
label-refined decomposition refutes horizons for its own plans only. Here:

* **DIS-PLAN** (:class:`ExactMissionDisPlan`, the BMC encoding of
  :class:`~plansynth.reach.mission.bmc.MissionDisPlan`) steps between the regions one
  segment through the free space can connect
  (:func:`~plansynth.reach.lazy.bounds.segment_adjacency`) and has, per segment, points
  with regions of their own (:class:`~plansynth.reach.lazy.segments.SegmentPoints`): the
  segment's end p_{t+1} (a point apart from the sample t + 1, in a region equal or
  touching r_{t+1}'s, so that two segments meeting on a label's edge each read it their
  way) and the points the theory asks for. Every label literal of step t asks every
  point of segment t (the sample p_t, the end, the others) to lie in a region that holds
  it. A segment reads a literal only if all its points do, and each point lies in some
  closed region that holds what the point holds, so every trajectory's word is a
  DIS-PLAN plan's (up to the caveat below).
* **The theory** (:class:`MissionSegmentTheory`) is the exact segment theory
  (:class:`~plansynth.reach.lazy.segtheory.SegmentTheory`) with the plan's closure (a
  lasso's x_L = x_k, a finite plan's rest at x_L) in its point LP, and with the labels
  each segment reads ``!a`` for (the model's literals; a lasso's last position reads as
  segment k) kept out of the segment as it keeps the obstacles out: the exact depth check
  and the separating LP accept, and a segment that enters such a label gets a point there
  (which cuts the solution off). ``a`` needs nothing more: both ends of the segment lie
  in regions inside the label shrunk by its margin, a convex set (the exact mode needs
  convex labels, as margins do). The point LP is a necessary condition, so its conflicts
  hold for the problem; a conflict that needs the closure blocks the plan with its loop
  or stay selector (:class:`~plansynth.reach.lazy.segtheory.ClosedConflict`).

So a horizon refuted here is refuted for every trajectory of the problem in the segment
reading, and ``infeasible`` and a minimal horizon are claims about the problem, unless
the theory gave a plan up without a proof (``segment_undecided``; the claims then say
so). The caveat (as the sample reading's, :mod:`plansynth.reach.mission.planner`): a
point is read as the closed region it is put in, so a segment that runs *along* a label's
edge reads that label the way a region beside it does; a segment along the common edge of
two labels that lie on the same side, read as inside one and outside the other, is
outside the model (a set of trajectories of measure zero).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.displan import PAIRWISE_MAX_REGIONS
from plansynth.reach.lazy.exactmode import AUTO_OFF, REGIONS, SEGMENTS, STEPS, ExactMode
from plansynth.reach.lazy.regiongraph import RegionGraph
from plansynth.reach.lazy.segments import Adjacency, Refinement, SegmentPoints
from plansynth.reach.lazy.segtheory import ClosedConflict, SegmentTheory
from plansynth.reach.mission.bmc import MissionDisPlan
from plansynth.reach.mission.ltl import Formula, Not, Prop
from plansynth.reach.mission.plans import LoopConflict, MissionPlan, StayConflict

__all__ = [
    "ExactMissionDisPlan",
    "MissionSegmentTheory",
    "SegmentMissionPlan",
    "convex_labels",
    "avoided_shapes",
    "mission_exact_mode",
]


@dataclass(frozen=True)
class SegmentMissionPlan(MissionPlan):
    """A :class:`~plansynth.reach.mission.plans.MissionPlan` with the regions of the
    points along its segments (``vias[(t, f)]``, f over DENOM; f = DENOM is the segment's
    end) and, per segment t, the labels it must stay out of (``avoid[t]``: the model's
    ``!a`` at step t, and for a lasso's segment k those of position L too)."""

    vias: Mapping[tuple[int, int], int] = field(default_factory=dict, compare=False, repr=False)
    avoid: Mapping[int, frozenset[str]] = field(default_factory=dict, compare=False, repr=False)


class ExactMissionDisPlan(MissionDisPlan):
    """The mission's DIS-PLAN with points along the segments (see the module docstring).
    ``graph``'s adjacency: the regions one segment can connect; ``relation(scale)``: those
    a piece of that share of a step can connect; ``near``: regions whose closures meet.
    Counters besides the BMC encoding's: ``refinements`` (points added)."""

    def __init__(
        self,
        graph: RegionGraph,
        labels_of: Sequence[frozenset[str]],
        formula: Formula,
        *,
        relation,
        near: Adjacency,
        **kw,
    ) -> None:
        super().__init__(graph, labels_of, formula, **kw)
        self._literal_subs = [f for f in self.subs if isinstance(f, (Prop, Not))]
        self._holding = {id(g): self._regions_of(g) for g in self._literal_subs}
        self.points = SegmentPoints(
            self,
            graph.n_regions,
            relation,
            pairwise=graph.n_regions <= PAIRWISE_MAX_REGIONS,
            ends=True,
            near=near,
            on_point=self._letters_at,
        )

    @property
    def refinements(self) -> int:
        return self.points.refinements

    def _regions_of(self, f: Prop | Not) -> list[int]:
        """The regions that hold the literal ``f``."""
        n = self.graph.n_regions
        if isinstance(f, Prop):
            return [r for r in range(n) if f.name in self.labels_of[r]]
        assert isinstance(f.arg, Prop), "negation normal form"
        return [r for r in range(n) if f.arg.name in self.negs_of[r]]

    def _letters_at(self, t: int, f: int) -> None:
        """Step t's label literals at the point at fraction f of its segment: each one
        that holds at step t holds there (segment t exists once position t + 1 does, so
        position t is not the last one of any horizon asked from now on)."""
        for g in self._literal_subs:
            self._add([-self.v(g, t)] + [self.points.via(t, f, r) for r in self._holding[id(g)]])

    def _position(self, t: int) -> None:
        super()._position(t)
        while self.points.segments < t:  # position t completes segment t - 1
            self.points.encode_segment()

    def _boundary(self, horizon: int) -> None:
        new = horizon not in self.bounded
        super()._boundary(horizon)
        if not new:
            return
        # a lasso's position L is position k again (x_L = x_k): its letter is segment k's,
        # so the literals that hold at L hold at k, where segment k's points read them
        for s, j in self.selectors(horizon):
            if s != self.stay(horizon):
                for g in self._literal_subs:
                    self._add([-s, -self.v(g, horizon), self.v(g, j - 1)])

    def _shift(self, c: Conflict, shift: int, horizon: int | None) -> None:
        if c.first_time + shift < 0 or c.last_time + shift > self.built:
            return
        vias = self.points.literals(c.vias, shift)
        if vias is None:
            return  # (a point missing there: not added, sound, only weaker)
        clause = [-self.at(t + shift, i) for t, i in c.literals] + [-v for v in vias]
        if horizon is not None:
            clause.append(-self.act(horizon))
        self._learn_clause(clause)

    def learn(self, c: Conflict | LoopConflict | StayConflict | Refinement | ClosedConflict) -> None:  # type: ignore[override]
        """What the segment theory answers: more points (a
        :class:`~plansynth.reach.lazy.segments.Refinement`), a conflict that needs the
        plan's closure (blocked with its loop or stay selector, at its horizon), or a
        conflict over samples and points (:meth:`MissionDisPlan.learn`)."""
        if isinstance(c, Refinement):
            self.points.refine(c.points)
            return
        if isinstance(c, ClosedConflict):
            inner, L = c.conflict, c.conflict.horizon
            vias = self.points.literals(inner.vias, 0)
            assert vias is not None, "a conflict about the plan just proposed names its points"
            sel = self.loop(L, int(c.closure[1]) + 1) if c.closure[0] == "loop" else self.stay(L)
            self._learn_clause([-self.at(t, i) for t, i in inner.literals] + [-v for v in vias] + [-sel])
            self.loop_clauses += 1
            return
        super().learn(c)

    def solve(self, horizon: int, clock=None, *, lowest: int | None = None):
        outcome, plan = super().solve(horizon, clock, lowest=lowest)
        if plan is None:
            return outcome, plan
        true = {v for v in self.solver.get_model() if v > 0}
        L, k = plan.horizon, plan.loop_start
        avoid: dict[int, set[str]] = {}
        for g in self._literal_subs:
            if isinstance(g, Not):
                for t in range(L + 1):
                    if self.v(g, t) in true:
                        seg = k if (t == L and k is not None) else t  # a lasso's position L is segment k
                        if seg < L:
                            avoid.setdefault(seg, set()).add(g.arg.name)
        vias = self.points.read(true, L)
        return outcome, SegmentMissionPlan(
            plan.regions, k, vias=vias, avoid={t: frozenset(s) for t, s in avoid.items()}
        )


class MissionSegmentTheory:
    """The mission's theory with exact segment transitions (see the module docstring):
    ``check(plan)`` asks the exact segment theory ``segments`` about a
    :class:`SegmentMissionPlan` with its closure (``("loop", k)``, ``("rest",)`` for a
    finite plan ending at rest, none with a free end) and the labels its segments must
    stay out of."""

    def __init__(self, segments: SegmentTheory, *, end: str = "rest") -> None:
        self.segments = segments
        self.end = end
        self.expendable = False

    @property
    def plans_checked(self) -> int:
        return self.segments.plans_checked

    def check(self, plan: SegmentMissionPlan) -> Feasible | Conflict | ClosedConflict | Refinement | tuple:
        k = plan.loop_start
        closure = ("loop", k) if k is not None else (("rest",) if self.end == "rest" else None)
        return self.segments.check_closed(plan.regions, closure, plan.avoid, dict(plan.vias))


def convex_labels(problem) -> bool:
    """Is every label of the problem convex (one convex piece)? The exact mode reads
    ``a`` along a segment from its two ends, which needs it."""
    from plansynth.reach.geometry import convex_pieces

    return all(len(convex_pieces(s)) == 1 for s in problem.mission_labels.values())


def mission_exact_mode(problem, opts) -> ExactMode:
    """What ``opts.exact_segments`` means for this mission (as
    :func:`~plansynth.reach.lazy.exactmode.exact_mode` for a reach-avoid problem): the
    sample reading's steps are exact already; in the segment reading ``True`` and
    ``"auto"`` need convex labels (else the decomposition's relation, and the result says
    why); ``"auto"`` starts through the decomposition (a mission asks for no claim up
    front) and continues exactly after a refutation through it."""
    if problem.reading != "segment":
        return ExactMode(STEPS, False, "off: the sample reading, steps between any two regions one step can connect")
    if opts.exact_segments is False:
        return ExactMode(REGIONS, False, "off: one region per step, claims through the decomposition")
    auto = " (auto)" if opts.exact_segments == "auto" else ""
    if not convex_labels(problem):
        return ExactMode(REGIONS, False, f"off{auto}: a label is not convex")
    if auto:
        return ExactMode(REGIONS, True, AUTO_OFF)
    return ExactMode(SEGMENTS, False, "on")


def avoided_shapes(problem) -> dict[str, object]:
    """Per label, what a segment reading ``!a`` must stay out of: the label grown by its
    margin (``{H p <= h + r}``)."""
    from plansynth.reach.offsets import grown

    return {n: grown(s, problem.label_margin(n)) for n, s in problem.mission_labels.items()}
