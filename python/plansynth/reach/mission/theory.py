"""The theory side of the lazy loop for a mission (Shoukry et al., CDC 2016,
Algorithm 1, lines 8-11; the loop of a lasso as in Biere et al.'s BMC encoding).

:class:`MissionTheory` is the :class:`~plansynth.reach.lazy.loop.TheoryChecker` the
one lazy loop (:func:`~plansynth.reach.lazy.loop.lazy_loop`) asks about a
:class:`~plansynth.reach.mission.plans.MissionPlan`:

::

    lasso, loop start k: transit-time violations of the plan, then of the loop's
        wrap-around legs; the loop alone (any x_k, x_L = x_k) -> LoopConflict
    CON-PLAN(r_0..r_L) (with the goal the whole workspace) -> Conflict
    lasso: the LP with x_L = x_k (LoopLP)       -> trajectory, or LoopConflict
    finite plan ending at rest: the LP that also keeps x_L at rest -> trajectory, or StayConflict
    finite plan with a free end: CON-PLAN's trajectory as it is

CON-PLAN runs unchanged on the problem with the whole workspace as its goal
(:func:`~plansynth.reach.mission.labels.planning_problem`); its conflicts are sound
for the mission because the mission adds constraints only through the region sequence
and the loop. The loop closure is the one constraint missions add to CON-PLAN's; it is
checked by :class:`~plansynth.reach.mission.looplp.LoopLP`: the loop alone before
CON-PLAN (``loop_first``: a refuted loop holds at every horizon and rotation), the
whole lasso for sequences CON-PLAN realised. :class:`MissionTransit` is the transit
layer as the mission's plans need it.
"""

from __future__ import annotations

from plansynth.budget import Clock
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.transit import GOAL, TransitCheck
from plansynth.reach.mission.looplp import LoopLP
from plansynth.reach.mission.plans import LoopConflict, MissionPlan, StayConflict

__all__ = ["MissionTheory", "MissionTransit", "wrap_violation"]

Answer = Feasible | Conflict | LoopConflict | StayConflict | tuple[Conflict, ...]


class MissionTheory:
    """The mission's theory behind the lazy loop's narrow interface: ``check(plan)``
    answers a :class:`~plansynth.reach.mission.plans.MissionPlan` with a trajectory
    (:class:`~plansynth.reach.lazy.conflict.Feasible`: a lasso closes, a finite plan
    ends at rest) or with what the mission's DIS-PLAN learns (CON-PLAN's conflicts, a
    :class:`~plansynth.reach.mission.plans.LoopConflict` or a
    :class:`~plansynth.reach.mission.plans.StayConflict`).

    ``inner`` is CON-PLAN, or the transit layer in front of it; ``loop_lp`` the LP with
    the loop closure; every LP gets what is left of ``clock``; ``end``: how a finite
    plan ends (``rest``: its last state must be one the robot can hold). Counters:
    ``wrap_conflicts`` (loops refuted by their wrap-around legs' transit times)."""

    def __init__(
        self, inner: TransitCheck | object, loop_lp: LoopLP, clock: Clock, *, loop_first: bool = True, end: str = "rest"
    ) -> None:
        self.inner = inner
        self.end = end
        self.loop_lp = loop_lp
        self.clock = clock
        self.loop_first = loop_first
        self.wrap_conflicts = 0

    def check(self, plan: MissionPlan) -> Answer:
        regions, k, L = plan.regions, plan.loop_start, plan.horizon
        lp = self.loop_lp
        if self.loop_first and k is not None:
            refuted = self._loop_alone(regions, k, L)
            if refuted is not None:
                return refuted
        answer = self.inner.check(regions)  # type: ignore[attr-defined]
        if not isinstance(answer, Feasible):
            return answer
        if k is not None:
            traj = lp.solve(regions, k, self.clock.remaining())
            if traj is None:
                lits, shifted = lp.conflict(regions, k, self.clock.remaining())
                return LoopConflict(lits, k, L, shifted)
            return Feasible(traj)
        if self.end == "free":  # a finite plan with a free end: CON-PLAN's trajectory
            return answer
        # a finite plan ending at rest: its last state must be one the robot can hold
        traj = (
            answer.trajectory
            if lp.ends_at_rest(answer.trajectory)
            else lp.solve_finite(regions, self.clock.remaining())
        )
        if traj is None:
            return StayConflict(lp.rest_conflict(regions, self.clock.remaining()), L)
        return Feasible(traj)

    def _loop_alone(self, regions: tuple[int, ...], k: int, L: int) -> LoopConflict | tuple[Conflict, ...] | None:
        """The cheap checks of a lasso before CON-PLAN: transit-time violations of the
        sequence, then of the loop's wrap-around legs (cached gaps, no horizon-long LP),
        then the loop alone (states k..L with x_L = x_k, any x_k)."""
        if isinstance(self.inner, TransitCheck):
            found = self.inner.violations(regions)
            if found:
                return tuple(found)
            wrap = wrap_violation(self.inner, regions, k)
            if wrap is not None:
                self.wrap_conflicts += 1
                return LoopConflict(wrap, k, L, shifted=True)
        if self.loop_lp.loop_infeasible({t: regions[t] for t in range(k, L + 1)}, k, L, self.clock.remaining()):
            lits, shifted = self.loop_lp.conflict(regions, k, self.clock.remaining(), loop_refuted=True)
            return LoopConflict(lits, k, L, shifted)
        return None


def wrap_violation(
    transit: TransitCheck, regions: tuple[int, ...], loop_start: int
) -> tuple[tuple[int, int], tuple[int, int]] | None:
    """Two loop positions i >= j whose wrap-around leg is too short: with x_L = x_k
    the robot repeats the loop, so it is in r_i at step i and in r_j at step
    L + (j - k), and if the transit layer proves r_i -> r_j impossible in that many
    steps, no periodic trajectory realises the two literals (at any horizon or
    rotation: :meth:`~plansynth.reach.mission.bmc.MissionDisPlan.learn_loop` with ``shifted``)."""
    k, L = loop_start, len(regions) - 1
    for i in range(L - 1, k - 1, -1):
        for j in range(k, i):
            if regions[i] != regions[j] and transit.impossible(regions[i], regions[j], (L - i) + (j - k)):
                return ((j, regions[j]), (i, regions[i]))
    return None


class MissionTransit(TransitCheck):
    """The transit-time layer (:class:`~plansynth.reach.lazy.transit.TransitCheck`) as the
    mission planner uses it: a leg's gaps are decided by LPs only when the plan's gap
    is the leg's box bound (the fewest steps the displacement bounds allow), and legs
    to the goal are never checked (a mission's goal is the whole workspace).

    On the mazes most legs a plan's infeasibility brings up have their first feasible
    gap at or just above the box bound, and a plan's gap far above it is almost never
    the reason: scanning every leg (one LP per gap from the box bound up) cost the visit
    missions twice the LPs of CON-PLAN and the mission loop together. A leg whose plan
    gap lies above its box bound is decided as soon as another plan puts it at the
    bound, or by CON-PLAN. This only drops conflicts: every one reported is still proved
    (by the box bound or an LP), so the loop's clauses stay sound."""

    def box_gap(self, a: int, b: int) -> int:
        """:meth:`TransitCheck.box_gap`, once per leg (a pure function of the two boxes
        and the step bounds; the mission loop asks for every leg of every plan, ~10,000
        times on a patrol)."""
        memo = self.__dict__.setdefault("_box_gaps", {})
        g = memo.get((a, b))
        if g is None:
            g = memo[(a, b)] = super().box_gap(a, b)
        return g

    def _skip(self, a: int, b: int, gap: int) -> bool:
        return b == GOAL or ((a, b) not in self._first and gap > self.box_gap(a, b))

    def impossible(self, a: int, b: int, gap: int) -> bool:
        return False if self._skip(a, b, gap) else super().impossible(a, b, gap)

    def violations(self, regions, span=None, *, known_only: bool = False):
        """:meth:`TransitCheck.violations` over every leg of the plan, also when CON-PLAN's
        conflict covers only part of it (``span`` is ignored). The reach-avoid planner
        restricts the legs to the conflict's span because deciding every leg of a plan
        through a 1,500-region maze took thousands of LPs; here a leg above its box bound
        is never decided by an LP (:meth:`_skip`), and the legs outside the span, reported
        together with CON-PLAN's conflict, spare DIS-PLAN the plans it would otherwise
        propose one by one: visit 21 -> 10 SAT calls and 84 -> 58 LPs, avoid-until 8 -> 6
        SAT calls, patrol unchanged. Sound as before: every reported leg is proved
        impossible (box bound or LP)."""
        return super().violations(regions, None, known_only=known_only)

    def known(self, a: int, b: int, gap: int) -> bool | None:
        return False if self._skip(a, b, gap) else super().known(a, b, gap)
