"""Transit times between regions: a cheap theory layer in front of CON-PLAN (beyond the
paper; it refines the lazy loop's theory check of Shoukry et al., CDC 2016, Section V).

Most region sequences that DIS-PLAN proposes on a maze fail for one reason: the plan
is in region X at time t1 and in region Y at time t2, and no trajectory gets from X to
Y in t2 - t1 steps. CON-PLAN finds such a conflict with several LPs over the whole
horizon, and DIS-PLAN then tries the next gap, one by one. This layer answers those
questions without the horizon-long LPs:

* ``box`` gaps: a position moves by at most ``step_up``/``step_down`` per step along
  each axis (:func:`~plansynth.reach.lazy.bounds.step_reach`), so fewer steps than the
  distance between the bounding boxes of X and Y divided by that are impossible (no LP);
  from a start at rest with a stable internal block, also fewer steps than the table of
  :func:`~plansynth.reach.dynamics.displacement_reach` allows (a bound on the move of
  any k consecutive steps, far below k one-step bounds on random dynamics);
* ``lp`` gaps: just above the box bound, the two-literal LP "p_0 in X, p_k in Y"
  (dynamics, input and state bounds, segment rows as CON-PLAN writes them) decides gap
  k exactly; gaps are scanned upwards until the first feasible one, once per pair.
  Legs out of a start state at rest (``A x_0 = x_0``) are monotone: a robot that can
  reach Y in k steps can wait one step at the start (u = 0) and reach it in k + 1. Their
  first feasible gap is found by galloping and bisection, a handful of LPs where a
  slow chain needs dozens of steps (maze-4, order 25: 58 steps into the first gap,
  box bound 26), and every smaller gap is impossible by that argument.

Every conflict reported is the statement "X at t1 and Y at t2 is impossible", which
uses neither the start nor the goal, so DIS-PLAN adds it at every time shift. All of a
plan's violations are returned at once. Sequences without a violation go to the wrapped
theory (CON-PLAN) unchanged, so this layer only saves work; it never decides feasibility.

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.abstraction import abstract
>>> from plansynth.reach.lazy.conplan import ConPlan
>>> p = maze(1); a = abstract(p)
>>> tc = TransitCheck(ConPlan(p, a), a)
>>> tc.box_gap(0, 2)              # region 0 (y <= 14.5) to region 2 (y >= 15.5): 1 m
1
>>> tc.first_gap(START, 1)         # from (1, 1) at rest into the gap at x >= 27, y >= 14.5
28
>>> rushed = (0,) * 20 + (1,) + (2,) * 10   # the goal (top left) 10 steps after the gap
>>> conflicts = tc.check(rushed)           # refuted without CON-PLAN
>>> sorted({(c.anchored_start, c.anchored_goal) for c in conflicts})
[(False, True), (True, False)]
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from plansynth.reach.abstraction import Abstraction
from plansynth.reach.dynamics import displacement_reach
from plansynth.reach.lazy.bounds import MULTISTEP_TABLE, box_steps, shape_box, step_reach
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.conplan import ConPlan

__all__ = ["TransitCheck", "REFINE_SPAN", "WIDEN_MAX", "START", "GOAL"]

REFINE_SPAN = 48  # gaps up to this far above the box bound are decided by LPs (one each)
WIDEN_MAX = 12  # an LP conflict is widened by at most this many steps each way
START, GOAL = -1, -2  # pseudo-regions: the start state (at time 0) and the goal (at the horizon)


class TransitCheck:
    """A theory checker (see :class:`plansynth.reach.lazy.loop.TheoryChecker`) that reports
    transit-time violations of a region sequence and passes the others on to ``inner``.

    A *leg* (a, b) is a pair of regions, or ``START`` and a region (the start state at
    time 0), or a region and ``GOAL`` (the goal at the plan's horizon). ``first_gap(a, b)``
    is the smallest number of steps the leg may take: every smaller one is proved
    impossible (by the box bound, or by an LP each). When a plan violates a leg, the
    conflicts of *all* impossible gaps of that leg are returned, so DIS-PLAN does not
    try them one by one.

    Counters: ``conflicts`` (transit conflicts reported), ``lp_calls`` (leg LPs),
    ``plans_caught`` (sequences refuted by transit conflicts), ``plans_checked``
    (sequences passed to CON-PLAN's horizon-long LPs).
    """

    def __init__(self, inner: ConPlan, abstraction: Abstraction, *, widen: bool = False) -> None:
        self.inner = inner
        self.widen = widen
        problem = inner.problem
        down, up = step_reach(problem)
        self.step_down, self.step_up = np.asarray(down, float), np.asarray(up, float)
        self.boxes = {
            i: (np.min(r.vertices, axis=0), np.max(r.vertices, axis=0)) for i, r in enumerate(abstraction.regions)
        }
        s = np.asarray(problem.start_position, float)
        self.boxes[START] = (s, s)
        self.boxes[GOAL] = shape_box(problem.goal)
        # from rest, a stable internal block bounds the displacement of k steps by far
        # less than k one-step bounds (random dynamics; None for integrator chains)
        self.reach_table = (
            displacement_reach(problem.dynamics, problem.input_bound, MULTISTEP_TABLE)
            if problem.starts_at_rest
            else None
        )
        # the start is an equilibrium: legs out of it are monotone in the gap
        self.start_at_rest = problem.starts_at_rest
        self._first: dict[tuple[int, int], int] = {}
        self._box: dict[tuple[int, int], int] = {}  # box_gap's answers (re-timing a plan asks a million)
        self._reported: set[tuple[int, int]] = set()
        self.conflicts = 0
        self.lp_calls = 0
        self.plans_caught = 0
        self.plans_checked = 0  # plans whose horizon-long LP CON-PLAN solved
        self.widened = 0

    @property
    def expendable(self) -> bool:
        """The inner theory's (see :class:`~plansynth.reach.lazy.loop.TheoryChecker`)."""
        return self.inner.expendable

    @expendable.setter
    def expendable(self, value: bool) -> None:
        self.inner.expendable = value

    # ---------------------------------------------------------------- gap bounds
    @property
    def reach_table(self) -> np.ndarray | None:
        """The k-step displacement bounds (:func:`~plansynth.reach.dynamics.displacement_reach`)
        the box gaps use, or None (one-step bounds only); setting it forgets the gaps."""
        return self._reach_table

    @reach_table.setter
    def reach_table(self, table: np.ndarray | None) -> None:
        self._reach_table = table
        self._box = {}

    def box_gap(self, a: int, b: int) -> int:
        """The fewest steps of leg (a, b) that the displacement bounds allow."""
        gap = self._box.get((a, b))
        if gap is None:
            gap = self._box[(a, b)] = box_steps(
                self.boxes[a], self.boxes[b], self.step_down, self.step_up, self.reach_table
            )
        return gap

    def first_gap(self, a: int, b: int) -> int:
        """The smallest gap of leg (a, b) not proved impossible: the box bound, then one
        LP per gap upwards until a feasible one (at most ``REFINE_SPAN`` LPs); from a
        start at rest, galloping and bisection over the same range (monotone legs)."""
        key = (a, b)
        if key not in self._first:
            box = max(self.box_gap(a, b), 1)
            if a == START and self.start_at_rest:
                self._first[key] = self._first_monotone(b, box)
            else:
                k = box
                for _ in range(REFINE_SPAN):
                    if not self._impossible_lp(a, b, k):
                        break
                    k += 1
                self._first[key] = k
        return self._first[key]

    def _impossible_lp(self, a: int, b: int, k: int, part: int | None = None) -> bool:
        self.lp_calls += 1
        return self.inner.refutes(self.leg(a, b, k, N=k), part=part)

    def _first_monotone(self, b: int, box: int) -> int:
        """``first_gap(START, b)`` for a start at rest: the gaps box..box+REFINE_SPAN-1
        are infeasible up to some gap and feasible from there on, so the first feasible
        one is found by galloping (box, box+1, box+3, box+7, ...) and bisection.

        When CON-PLAN splits its LPs into independent parts (one per axis: separable
        dynamics, box regions), each part is monotone on its own (the same wait at the
        start) and the leg's LP is feasible exactly when every part is, so the first
        feasible gap is the largest of the parts' own, each searched with LPs of that
        part alone: a part feasible from a small gap is not solved again at every larger
        one (an order-25 chain into maze-4's first gap, 58 steps: 10 LPs of both axes,
        0.85 s, against about 12 one-axis LPs, most of them short)."""
        parts = self.inner.span_parts()
        if parts is None:
            return self._gallop(box, lambda k: self._impossible_lp(START, b, k))
        return max(self._gallop(box, lambda k, p=p: self._impossible_lp(START, b, k, part=p)) for p in range(parts))

    @staticmethod
    def _gallop(box: int, impossible) -> int:
        top = box + REFINE_SPAN  # "not proved impossible" when every gap below is
        low = high = box - 1  # low: the largest gap known impossible; high: feasible
        step = 1
        while high < top:
            high = min(box + step - 1, top)
            if high == top or not impossible(high):
                break
            low, step = high, 2 * step
        while low + 1 < high:
            k = (low + high) // 2
            if impossible(k):
                low = k
            else:
                high = k
        return high

    def impossible(self, a: int, b: int, gap: int) -> bool:
        """Is leg (a, b) in ``gap`` steps impossible? (LPs only for gaps near the box bound.)"""
        box = self.box_gap(a, b)
        if gap < box:
            return True
        if gap >= box + REFINE_SPAN:
            return False
        return gap < self.first_gap(a, b)

    @staticmethod
    def leg(a: int, b: int, gap: int, *, t: int = 0, N: int) -> Conflict:
        """The conflict "leg (a, b) from time t in ``gap`` steps" in a plan of horizon N.

        The later region sits at the last time the conflict uses, so it has no segment
        row (as at the end of a plan): the LP asks no more than any plan does."""
        if a == START:
            return Conflict(((gap, b),), anchored_start=True, anchored_goal=False, horizon=N, last_time=gap)
        if b == GOAL:
            return Conflict(((t, a),), anchored_start=False, anchored_goal=True, horizon=N, first_time=t)
        return Conflict(
            ((t, a), (t + gap, b)),
            anchored_start=False,
            anchored_goal=False,
            horizon=N,
            first_time=t,
            last_time=t + gap,
        )

    # ---------------------------------------------------------------- the theory check
    def legs(self, regions: Sequence[int]) -> list[tuple[int, int, int, int]]:
        """The legs of a plan as (a, b, t, gap): from the start to each region's first
        visit, from the end of each visit to x to the start of each later visit to
        y != x (the latest earlier x-visit counts), and from the end of each region's
        last visit to the goal at the horizon."""
        N = len(regions) - 1
        last_end: dict[int, int] = {}
        out = []
        t = 0
        while t <= N:
            y = regions[t]
            s = t
            while t < N and regions[t + 1] == y:
                t += 1
            if y not in last_end and s > 0:
                out.append((START, y, 0, s))
            for x, e in last_end.items():
                if x != y:
                    out.append((x, y, e, s - e))
            last_end[y] = t
            t += 1
        out += [(x, GOAL, e, N - e) for x, e in last_end.items() if e < N]
        return out

    def violations(
        self, regions: Sequence[int], span: tuple[int, int] | None = None, *, known_only: bool = False
    ) -> list[Conflict]:
        """The conflicts of every leg the plan gets wrong, for all of its impossible gaps
        the first time the leg is seen wrong, for the plan's gap afterwards; with
        ``span`` (lo, hi), only the legs that lie within steps lo..hi; with
        ``known_only``, only the legs decided without a new LP (:meth:`known`)."""
        N = len(regions) - 1
        out: list[Conflict] = []
        for a, b, t, gap in self.legs(regions):
            if span is not None and (t < span[0] or t + gap > span[1]):
                continue
            if known_only and not self.known(a, b, gap):
                continue
            if not self.impossible(a, b, gap):
                continue
            if (a, b) in self._reported:
                out.append(self.leg(a, b, gap, t=t, N=N))
                continue
            self._reported.add((a, b))
            first = self.first_gap(a, b) if gap >= self.box_gap(a, b) else max(self.box_gap(a, b), 1)
            for k in range(1, min(first, N + 1)):  # a pair's conflict holds at every shift
                out.append(self.leg(a, b, k, t=N - k if b == GOAL else 0, N=N))
        return out

    def widened_conflicts(self, c: Conflict) -> list[Conflict]:
        """Variants of an LP conflict with more time between its ends, each proved by an
        LP over its own span: the later end (the last literal, or the goal) moves later
        by 1, 2, ... steps, and the earlier end (the first literal, or the start) earlier,
        until an LP is feasible (at most ``WIDEN_MAX`` each way). A conflict that is
        infeasible because its steps are too tight usually stays so for a few more steps,
        and DIS-PLAN would otherwise propose those plans one at a time."""
        out: list[Conflict] = []
        for end in ("later", "earlier"):
            for j in range(1, WIDEN_MAX + 1):
                v = _moved(c, end, j)
                if v is None:
                    break
                self.lp_calls += 1
                if not self.inner.refutes(v):
                    break
                out.append(v)
        self.widened += len(out)
        return out

    def known(self, a: int, b: int, gap: int) -> bool | None:
        """:meth:`impossible` when it needs no LP (the box bound, or the leg's first gap
        already found), else None."""
        box = self.box_gap(a, b)
        if gap < box:
            return True
        if gap >= box + REFINE_SPAN:
            return False
        first = self._first.get((a, b))
        return None if first is None else gap < first

    def check(self, regions: Sequence[int]) -> Feasible | Conflict | tuple[Conflict, ...]:
        """All transit violations of ``regions``, or the inner theory's answer (an LP
        conflict together with its widened variants).

        When no leg is known to be violated but some legs would need LPs to decide
        (their first gap not yet found), the plan's own LP comes first: a plan that is
        realisable (the guided one usually is) then costs one LP, not one per unknown
        leg gap; when it is not, the legs within the time span of CON-PLAN's conflict are
        decided as usual and their conflicts come with CON-PLAN's. When some leg is known
        to be wrong without an LP, only the legs so known are reported."""
        unknown = False
        known_wrong = False
        for a, b, _, gap in self.legs(regions):
            k = self.known(a, b, gap)
            if k is None:
                unknown = True
            elif k:
                unknown, known_wrong = False, True
                break
        first: Conflict | None = None
        if unknown:
            self.plans_checked += 1
            answer = self.inner.check(regions)
            if isinstance(answer, Feasible):
                return answer
            first = answer
        # after the plan's own LP failed, only the legs within its conflict's span: the
        # others need not be wrong (on the GCS paper's 50 x 50 maze, deciding every leg
        # of a plan took ~8,000 LPs where the plan needed one conflict)
        span = None
        if first is not None:
            span = (
                0 if first.anchored_start else first.first_time,
                len(regions) - 1 if first.anchored_goal else first.last_time,
            )
        # a leg known to be wrong: report the legs known so, without LPs for the others
        # (a plan of a 1,500-region maze has thousands of legs near their box bounds)
        found = self.violations(regions, span, known_only=known_wrong)
        if found:
            self.conflicts += len(found)
            self.plans_caught += 1
            return tuple(found) if first is None else (first, *found)
        if first is None:
            self.plans_checked += 1
        answer = self.inner.check(regions) if first is None else first
        if isinstance(answer, Conflict) and self.widen and answer.literals:
            return (answer, *self.widened_conflicts(answer))
        return answer


def _moved(c: Conflict, end: str, j: int) -> Conflict | None:
    """``c`` with its later end moved ``j`` steps later, or its earlier end ``j`` steps
    earlier (as a shift of everything after it, so no time becomes negative)."""
    lits = sorted(c.literals)
    if end == "later":
        if c.anchored_goal:  # the goal is the later end: the horizon grows
            return Conflict(
                tuple(lits),
                anchored_start=c.anchored_start,
                anchored_goal=True,
                horizon=c.horizon + j,
                first_time=c.first_time,
            )
        if c.anchored_start and len(lits) == 0:
            return None
        *rest, (t, r) = lits
        return Conflict(
            (*rest, (t + j, r)),
            anchored_start=c.anchored_start,
            anchored_goal=False,
            horizon=max(c.horizon, c.last_time + j),
            first_time=c.first_time,
            last_time=c.last_time + j,
        )
    if c.anchored_start:  # the start is the earlier end: every literal moves later
        moved = tuple((t + j, r) for t, r in lits)
        return Conflict(
            moved, anchored_start=True, anchored_goal=c.anchored_goal, horizon=c.horizon + j, last_time=c.last_time + j
        )
    if len(lits) < 2 and not c.anchored_goal:
        return None
    (t0, r0), *rest = lits
    moved = ((t0, r0), *((t + j, r) for t, r in rest))
    return Conflict(
        moved,
        anchored_start=False,
        anchored_goal=c.anchored_goal,
        horizon=c.horizon + j,
        first_time=c.first_time,
        last_time=c.last_time + j,
    )
