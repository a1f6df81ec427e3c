"""The lazy SMT loop (Shoukry et al., CDC 2016, Algorithm 1, lines 3-12).

::

    for each horizon window lo..hi:
        loop:
            plan <- DIS-PLAN(lo..hi)         (SAT; UNSAT -> every horizon of the window refuted)  (Section IV)
            theory(plan) -> trajectory: done                                                  (Section V)
                         -> counterexamples: DIS-PLAN learns them, loop

The loop knows the two halves only through two narrow interfaces (STYLE.md, point 8):
a :class:`PlanSource` (DIS-PLAN: :class:`~plansynth.reach.lazy.displan.DisPlan` for a
goal, :class:`~plansynth.reach.mission.bmc.MissionDisPlan` for an LTL mission) proposes a
plan of a horizon in a window and learns what refutes it; a :class:`TheoryChecker`
(CON-PLAN behind the transit layer, :mod:`plansynth.reach.lazy.conplan` and
:mod:`~plansynth.reach.lazy.transit`, or the mission's theory,
:mod:`plansynth.reach.mission.theory`) answers a plan with a trajectory
(:class:`~plansynth.reach.lazy.conflict.Feasible`) or with counterexamples, which the loop
hands to DIS-PLAN unread. One loop runs reach-avoid problems
(:func:`plansynth.reach.lazy.planner.plan_lazy`) and missions
(:func:`plansynth.reach.mission.planner.plan_mission`).

One iteration (one SAT call and its theory check) is one step of the budget
(:meth:`plansynth.budget.Clock.steps`); the answer is ``unknown`` when the budget runs
out, naming where. Beyond the paper: windows of horizons instead of one horizon at a
time (:func:`horizon_windows`), deferred windows (``defer_after``) and a reference plan
per window for DIS-PLAN's decisions (``guide``).

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.lazy.planner import plan_lazy
>>> r = plan_lazy(maze(1))
>>> r.status.value, r.horizon == len(r.regions) - 1, r.guarantee
('found', True, 'segments')
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from plansynth.budget import BudgetExhausted, Clock
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.conplan.runs import LpFailure
from plansynth.reach.lazy.displan import SatOutcome
from plansynth.reach.result import ReachStatus
from plansynth.reach.trajectory import Trajectory

__all__ = [
    "TheoryChecker",
    "PlanSource",
    "LoopOutcome",
    "lazy_loop",
    "horizon_windows",
    "DEFER_AFTER",
    "DEAR_DEFER_AFTER",
]

ProgressFn = Callable[[int, int], None]  # (horizon, iterations so far)


class TheoryChecker(Protocol):
    """The theory side of the lazy loop (CON-PLAN or any other).

    A theory may also have a boolean attribute ``expendable``, which :func:`lazy_loop`
    sets before each check: True when the window is deferred should the plan fail, so
    that a cheaper, weaker (still sound) counterexample will do (CON-PLAN on dense
    dynamics then skips the Farkas ray of a plan the interior-point method refutes),
    and a counter ``plans_checked`` of the plans that needed its horizon-long LPs (the
    ones ``defer_after`` counts)."""

    def check(self, plan: Any) -> Any:
        """A trajectory following ``plan`` (:class:`~plansynth.reach.lazy.conflict.Feasible`)
        or one or more counterexamples for DIS-PLAN to learn (a
        :class:`~plansynth.reach.lazy.conflict.Conflict`, or a tuple of them)."""
        ...


class PlanSource(Protocol):
    """DIS-PLAN as the lazy loop sees it (Section IV): plans whose length is their
    number of positions (horizon + 1)."""

    closed: set[int]  # the horizons refuted for good

    def solve(self, horizon: int, clock: Clock | None = None, *, lowest: int | None = None) -> tuple[SatOutcome, Any]:
        """A plan ending at a horizon in lowest..horizon, UNSAT, or INTERRUPTED."""
        ...

    def learn(self, conflict: Any) -> None:
        """Block what the theory refuted (Algorithm 1, line 11)."""
        ...

    def close(self, horizon: int) -> None:
        """No plan of this horizon exists."""
        ...


@dataclass(frozen=True)
class LoopOutcome:
    """What :func:`lazy_loop` ends with (the horizon as in
    :class:`~plansynth.reach.result.ReachResult`); ``regions`` is the plan found, as
    DIS-PLAN proposed it (r_0..r_h; a mission's plan with its loop)."""

    status: ReachStatus
    horizon: int | None
    message: str
    trajectory: Trajectory | None = None
    regions: Any = None
    minimal: bool | None = None  # found: is the horizon proved minimal?


#: the window search defers a window after this many of its plans needed CON-PLAN's LPs
DEFER_AFTER = 4
#: ... and after one on dense dynamics (``ConPlan.dear``), where one plan LP over a horizon
#: of 150 takes 5-15 s: the window's reference plan is then the only one asked for
#: before the loop moves on (random dynamics, n = 50, maze-3: 9 plan LPs -> 3)
DEAR_DEFER_AFTER = 1


def lazy_loop(
    displan: PlanSource,
    theory: TheoryChecker,
    windows: Sequence[tuple[int, int]] | range,
    clock: Clock,
    timings: dict[str, float],
    progress: ProgressFn | None = None,
    guide: Callable[[int], Sequence[int] | None] | None = None,
    defer_after: int | None = None,
) -> LoopOutcome:
    """Algorithm 1, the loop: for each horizon window lo..hi (a ``range`` means one
    horizon at a time), ask DIS-PLAN for a plan ending at a horizon in the window, ask
    the theory to realise it, let DIS-PLAN learn its counterexamples, until a trajectory
    is found or DIS-PLAN is UNSAT (then every horizon of the window is refuted: the next
    window). ``progress(hi, iterations)`` is called when a window starts; ``guide(hi)``
    gives the reference plan DIS-PLAN's decision phases follow. Adds the seconds spent
    in the SAT solver and in the theory to ``timings["sat"]`` and ``timings["lp"]``.

    ``defer_after`` (the window search; beyond the paper): a window other than the
    last whose plans have needed that many horizon-long LPs without a trajectory (plans
    that the transit layer refutes alone do not count) is *deferred*: the loop moves on
    to the next window and comes back to the deferred ones, lowest first and without
    the limit, only when no later window yields a trajectory. Refuting the window just
    below the least feasible horizon is the dearest part of the search (long conflicts
    that each rule out a few timings; maze-3 with n = 4 random dynamics: window 92..115,
    over 1,000 iterations, not refuted in 60 s), while a window above it is usually
    realised at once. Nothing learned is lost (the clauses hold for every horizon), a
    deferred window's horizons stay open, and the answer says so: a trajectory is
    ``minimal`` only when every horizon below it is refuted, and ``infeasible`` needs
    every window refuted."""
    if isinstance(windows, range):
        windows = [(L, L) for L in windows]
    first_lo = windows[0][0] if windows else 0
    lo, hi = windows[0] if windows else (0, -1)
    pending = list(windows)
    deferred: list[tuple[int, int]] = []
    try:
        while pending or deferred:
            lo, hi = pending.pop(0) if pending else deferred.pop(0)
            cap = defer_after if pending else None  # the last window, and deferred ones: no limit
            if progress is not None:
                progress(hi, clock.iterations)
            if guide is not None:
                t0 = time.perf_counter()
                ref = guide(hi)
                timings["guide"] = timings.get("guide", 0.0) + time.perf_counter() - t0  # (its first LPs)
                if ref is not None:
                    displan.prefer(ref)  # type: ignore[attr-defined]
            costly = 0  # plans of this window that needed CON-PLAN's LPs
            for _ in clock.steps(itertools.count(clock.iterations + 1), what="the lazy SMT loop's iteration"):
                t0 = time.perf_counter()
                outcome, plan = displan.solve(hi, clock, lowest=lo)
                timings["sat"] += time.perf_counter() - t0
                if outcome is SatOutcome.INTERRUPTED:
                    return LoopOutcome(
                        ReachStatus.UNKNOWN, hi, f"budget ran out in the SAT solver at horizon {_span(lo, hi)}"
                    )
                if outcome is SatOutcome.UNSAT:
                    for L in range(lo, hi + 1):
                        displan.close(L)
                    break
                checked = getattr(theory, "plans_checked", None)
                if hasattr(theory, "expendable"):  # (see TheoryChecker)
                    theory.expendable = cap is not None and costly + 1 >= cap  # type: ignore[attr-defined]
                t0 = time.perf_counter()
                answer = theory.check(plan)
                timings["lp"] += time.perf_counter() - t0
                costly += 1 if checked is None or theory.plans_checked > checked else 0
                if isinstance(answer, Feasible):
                    h = len(plan) - 1
                    below = _lowest_open(displan, first_lo, h)
                    note = "" if h == first_lo else _refuted_note(below, h if below == h else lo)
                    return LoopOutcome(
                        ReachStatus.FOUND, h, f"found at horizon {h}{note}", answer.trajectory, plan, minimal=below == h
                    )
                learn_all(displan, answer)
                if cap is not None and costly >= cap:
                    deferred.append((lo, hi))
                    deferred.sort()
                    break
    except (BudgetExhausted, LpFailure) as exc:  # (the LP solver's time limit is a BudgetExhausted too)
        return LoopOutcome(ReachStatus.UNKNOWN, hi, f"{exc} at horizon {_span(lo, hi)}")
    top = windows[-1][1] if windows else -1
    return LoopOutcome(ReachStatus.INFEASIBLE, top, f"infeasible: every horizon up to {top} refuted")


def horizon_windows(first: int, last: int, growth: float) -> list[tuple[int, int]]:
    """Consecutive windows lo..hi covering first..last, each ``hi = lo + floor(growth * lo)``
    (at least lo; ``growth=0``: one horizon at a time, the paper's loop).

    >>> horizon_windows(10, 30, 0.25)
    [(10, 12), (13, 16), (17, 21), (22, 27), (28, 30)]
    >>> horizon_windows(3, 5, 0.0)
    [(3, 3), (4, 4), (5, 5)]
    """
    out = []
    lo = first
    while lo <= last:
        hi = min(last, lo + int(growth * lo))
        out.append((lo, hi))
        lo = hi + 1
    return out


def _lowest_open(displan: PlanSource, lo: int, h: int) -> int:
    """The lowest horizon in lo..h - 1 that DIS-PLAN has not refuted (h if none)."""
    return next((L for L in range(lo, h) if L not in displan.closed), h)


def _refuted_note(below: int, top: int) -> str:
    """What a found plan's message says of the horizons below it: every one below
    ``below`` refuted, and when ``below < top`` the deferred ones in below..top - 1 not all."""
    if below >= top:
        return f" (horizons below {below} refuted)"
    return f" (horizons below {below} refuted; deferred ones in {below}..{top - 1} not all)"


def _span(lo: int, hi: int) -> str:
    return str(hi) if lo == hi else f"{lo}..{hi}"


def learn_all(displan: PlanSource, answer: Conflict | tuple[Conflict, ...]) -> None:
    """DIS-PLAN learns every counterexample of a theory's answer."""
    for conflict in answer if isinstance(answer, tuple) else (answer,):
        displan.learn(conflict)


#: Names that moved to the modules of one concept each (see :mod:`plansynth.reach.lazy`),
#: still importable from here.
_MOVED = {
    "plan_lazy": "planner",
    "prove_minimal": "minimal",
    "retimed": "minimal",
    "shortened": "minimal",
    "compressed": "minimal",
    "LazyOptions": "options",
    "COUNTEREXAMPLES": "options",
    "HORIZON_SEARCHES": "options",
    "EXACT_SAMPLES": "claims",
    "DECOMPOSITION_ONLY": "claims",
}


def __getattr__(name: str) -> Any:
    if name in _MOVED:
        import importlib

        return getattr(importlib.import_module(f"plansynth.reach.lazy.{_MOVED[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
