"""CON-PLAN's HiGHS runs and their retry ladder (see :mod:`plansynth.reach.lazy.conplan`):
a warm start HiGHS refuses is retried from scratch, a stalled simplex run is re-solved
by the interior-point method on a fresh copy, a time limit becomes
:class:`LpBudgetExhausted` and no answer at all :class:`LpFailure`."""

from __future__ import annotations

import os
import time
from collections.abc import Iterator, Mapping
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import highspy
import numpy as np

from plansynth.budget import BudgetExhausted
from plansynth.reach.highs import new_highs
from plansynth.reach.lazy.conplan.lp import LONG_CHAIN_STATES, _Layout, _Part, _Slot

#: Plan LPs with no basis, of dynamics with at least this many states, start interior
#: (``ipm_first`` in :meth:`_HighsRuns._run`). Chains of order 15 and up gain (order 20 on maze-4:
#: 4.2 -> 2.7 s; order 25: the polish of 2-4 s is gone), below they lose a little (order 5:
#: 0.09 -> 0.15 s, the simplex is quick and its residuals small there).
INTERIOR_STATES = 30
#: Threads for the interior-point runs of a split plan LP's cold parts (one per axis), at
#: most the cores there are (1: one after the other).
PART_THREADS = min(2, os.cpu_count() or 1)


class LpBudgetExhausted(BudgetExhausted):
    """HiGHS stopped at the time limit: the budget ran out in the LP solver (a
    :class:`~plansynth.budget.BudgetExhausted`; the planners answer ``unknown``).

    >>> str(LpBudgetExhausted())
    'budget ran out in the LP solver'
    """

    def __init__(self, phase: str = "the LP solver", resource: str = "time", detail: str = "") -> None:
        super().__init__(phase, resource, detail)


class LpFailure(Exception):
    """HiGHS gave no answer on an LP (numerical trouble); the lazy loop answers ``unknown``."""


@dataclass
class LpStats:
    """Counters of one CON-PLAN: LP solves by purpose, certificates, seconds in HiGHS."""

    lp_calls: int = 0
    iis_calls: int = 0
    ray_calls: int = 0
    certified: int = 0
    rejected: int = 0
    retries: int = 0
    ipm_fallbacks: int = 0
    slack_failures: int = 0
    polished: int = 0
    interior: int = 0  # interior-point runs first (ipm_first in _run): one per part of a split plan LP
    uncertified: int = 0  # infeasible answers without a certificate (interior-point method or presolve)
    seconds: float = 0.0
    by_kind: dict[str, int] = field(default_factory=dict)


@contextmanager
def _options(h: highspy.Highs, options: Mapping[str, Any]) -> Iterator[None]:
    """Set HiGHS ``options`` on ``h`` for the duration of the block, then restore them."""
    saved = {k: h.getOptionValue(k)[1] for k in options}
    for k, v in options.items():
        h.setOptionValue(k, v)
    try:
        yield
    finally:
        for k, v in saved.items():
            h.setOptionValue(k, v)


class _HighsRuns:
    """The HiGHS run methods of :class:`~plansynth.reach.lazy.conplan.check.ConPlan`."""

    def _run_slot(self, slot: _Slot, purpose: str, only: int | None = None) -> np.ndarray | None:
        """Solve the LP ``slot`` holds (part by part: infeasible as soon as one part is,
        the part infeasible last time first). ``only``: solve just that part; then
        "feasible" means only that this part is (the column values of the others are 0).
        A plan LP with no basis to start from, from :data:`INTERIOR_STATES` states on,
        goes to the interior-point method first (see :meth:`_run`)."""
        interior = purpose == "plan" and self.n >= INTERIOR_STATES
        if slot.parts is None:
            return self._run(slot.highs, purpose, ipm_first=interior and slot.fresh)
        assert slot.layout is not None
        col = np.zeros(slot.layout.n_col)
        order = sorted(range(len(slot.parts)), key=lambda i: i != slot.infeasible_part)
        if only is not None:
            order = [only]
        # (a part is cold while it has no basis: before its first run, since the first plan
        # LP of a frame may stop at another part's refutation, and after an interior-point
        # run without crossover)
        together = interior and len(order) > 1 and PART_THREADS > 1 and all(slot.parts[i].cold for i in order)
        statuses = self._interior_together([slot.parts[i] for i in order]) if together else None
        for k, i in enumerate(order):
            part = slot.parts[i]
            sub = self._run(
                part.highs,
                purpose,
                count=k == 0,
                ipm_first=interior and part.cold,
                crossover=False,
                first=None if statuses is None else statuses[k],
            )
            # (an interior-point run without crossover leaves no basis: the part stays cold)
            part.cold = not part.highs.getInfo().basis_validity
            if sub is None:
                slot.infeasible_part = i
                return None
            col[part.cols] = sub
        return col

    def _interior_together(self, parts: list[_Part]) -> list[highspy.HighsModelStatus]:
        """The interior-point runs (no crossover) of the cold parts of a split plan LP,
        on up to :data:`PART_THREADS` threads at once: the parts share nothing, and
        HiGHS releases the GIL while it solves (an order-25 chain on maze-4, horizon 191:
        the two axes in 0.87 s where one after the other took 1.62 s). Their statuses,
        in the order of ``parts``, for :meth:`_run` (``first``) to decide on."""
        S = highspy.HighsModelStatus
        if self.clock is not None:
            if self.clock.remaining() <= 0:
                raise LpBudgetExhausted()
            for p in parts:
                p.highs.setOptionValue("time_limit", float(p.highs.getRunTime() + min(self.clock.remaining(), 1e9)))

        def run(p: _Part) -> highspy.HighsModelStatus:
            with _options(p.highs, {"solver": "ipm", "run_crossover": "off"}):
                p.highs.run()
            return p.highs.getModelStatus()

        t0 = time.perf_counter()
        with ThreadPoolExecutor(min(PART_THREADS, len(parts))) as pool:  # (joined here: no idle threads left)
            statuses = list(pool.map(run, parts))
        self.stats.seconds += time.perf_counter() - t0
        if any(st in (S.kTimeLimit, S.kInterrupt, S.kHighsInterrupt) for st in statuses):
            raise LpBudgetExhausted()
        return statuses

    @staticmethod
    def _new_highs() -> highspy.Highs:
        # small LPs: presolve costs more than it saves, and the Farkas ray of an
        # infeasible LP (for shrinking conflicts) is only available without it
        return new_highs(presolve="off")

    def _run(
        self,
        h: highspy.Highs,
        purpose: str,
        count: bool = True,
        ipm_first: bool = False,
        crossover: bool = True,
        first: highspy.HighsModelStatus | None = None,
    ) -> np.ndarray | None:
        """Solve the model ``h`` holds: column values when optimal, None when infeasible.

        ``ipm_first`` (a plan LP with no basis to start from, many states): the
        interior-point method first (with ``crossover`` or without), and the simplex
        method from scratch only when that finds no solution, for the Farkas ray of an
        infeasible LP (the interior-point method has none). On a cold start the simplex
        method takes about as many iterations as the LP has rows: on the n = 50 random
        robots (A with 2,402 nonzeros) a cold plan LP of 135-267 steps took the dual
        simplex 5-32 s (8,000-17,000 iterations) and the interior-point method 1.4-7.6 s
        (11-20 iterations), a feasible one as an optimal basic solution (crossover); on
        an order-25 chain, split per axis, at horizon 146, 0.75 s (4,500 iterations) per
        axis against 0.5 s (20 iterations, without crossover, which costs 15% more
        there), and the simplex answer missed the dynamics by 1e-6 unscaled, which cost a
        polish of 2-4 s, where the interior point's residual is about 1e-10. When the
        plan is ``expendable`` (the lazy loop defers its window if it fails) an
        infeasible answer of the interior-point method is kept as it is (the conflict
        then is the whole plan: sound, only weaker); else a refuted plan costs both methods.
        ``first``: the status of that interior-point run when it has already been made on
        ``h`` (:meth:`_interior_together`); it is decided on here as if just run.

        HiGHS occasionally refuses a warm start after in-place edits (an error before
        any iteration), and the simplex method can stall on badly conditioned LPs (long
        integrator chains: coefficients dt^k/k!). Then the LP is solved again from
        scratch, then on a fresh copy by the interior-point method, then by the simplex
        method after presolve (no Farkas ray then: the conflict is kept unshrunk). If
        every attempt fails, :class:`LpFailure` is raised and the planner answers
        ``unknown``.
        """
        S = highspy.HighsModelStatus
        self._no_ray = False
        answers = (S.kOptimal, S.kInfeasible, S.kUnboundedOrInfeasible, S.kTimeLimit, S.kInterrupt, S.kHighsInterrupt)
        t0 = time.perf_counter()
        status = S.kNotset
        fresh = {
            "ipm": {"solver": "ipm", "presolve": "off", "run_crossover": "on"},
            "presolved": {"solver": "simplex", "presolve": "on", "simplex_iteration_limit": 2**31 - 1},
        }
        methods = {
            "first": {"solver": "ipm", "run_crossover": "on" if crossover else "off"},  # (in h itself)
            **fresh,
        }
        assert first is None or ipm_first, "a status of an interior-point run without ipm_first"
        for attempt in ("first", "warm", "cold", "ipm", "presolved")[0 if ipm_first else 1 :]:
            if attempt == "first" and first is not None:
                status = first
            elif self.clock is not None:
                remaining = self.clock.remaining()
                if remaining <= 0:
                    raise LpBudgetExhausted()
            if attempt == "warm" and ipm_first:
                h.clearSolver()  # (HiGHS would not run a solved model again)
            if attempt == "cold":
                if status == S.kIterationLimit:
                    continue  # a stalled simplex stalls again: straight to the other methods
                self.stats.retries += 1
                h.clearSolver()
            if attempt in fresh:
                # a fresh copy of the LP in the one-off instance, by another method
                self.stats.ipm_fallbacks += 1
                lp = h.getLp()
                h = self.cold
                h.passModel(lp)
            if attempt != "first" or first is None:
                if self.clock is not None:
                    # HiGHS compares time_limit with the instance's run time summed over runs
                    h.setOptionValue("time_limit", float(h.getRunTime() + min(self.clock.remaining(), 1e9)))
                with _options(h, methods.get(attempt, {})):
                    h.run()
                status = h.getModelStatus()
            if attempt == "first":
                self.stats.interior += 1
                if status in (S.kOptimal, S.kTimeLimit, S.kInterrupt, S.kHighsInterrupt):
                    break
                if status == S.kInfeasible and self.expendable:
                    break  # (no ray: the caller's conflict stays unshrunk; counted below)
                continue  # infeasible (no ray) or no answer: the simplex method decides
            if status in answers:
                break
        self.stats.seconds += time.perf_counter() - t0
        if count:
            self.stats.lp_calls += 1
            self.stats.by_kind[purpose] = self.stats.by_kind.get(purpose, 0) + 1
        if status == S.kOptimal:
            return np.asarray(h.getSolution().col_value)
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            # objectives are bounded below (0 or a weighted sum of slacks >= 0)
            # (no Farkas ray: a fallback copy decided it, or the interior-point method)
            self._no_ray = h is self.cold or attempt == "first"
            # a "no" of the interior-point method or of presolve has no certificate, and
            # the loop's claims say so (claims.uncertified); the simplex method's has one
            self.stats.uncertified += attempt in ("first", "ipm", "presolved")
            return None
        if status in (S.kTimeLimit, S.kInterrupt, S.kHighsInterrupt):
            raise LpBudgetExhausted()
        raise LpFailure(f"HiGHS could not solve a CON-PLAN LP ({purpose}): {h.modelStatusToString(status)}")

    def _solve_model(
        self,
        N: int,
        assignment: Mapping[int, int],
        purpose: str,
        *,
        goal: bool = False,
        anchored_start: bool = True,
        slack: bool = False,
        span: tuple[int, int] | None = None,
        part: int | None = None,
        slot: _Slot | None = None,
    ) -> np.ndarray | None:
        """Solve the LP of ``assignment`` over the states 0..N, or only over ``span``
        (first, last) in the span model (for conflicts: a smaller LP that claims no more).
        ``part``: in a split model, solve only that part (an infeasible answer holds for
        the whole LP; a feasible one is only that part's)."""
        if slot is None:
            slot = self.slack_slot if slack else (self.span_slot if span is not None else self.slot)
        lay = self._frame(slot, *((0, N) if span is None else span))
        self._load(
            slot, lay, assignment, self.bounds(lay, assignment, goal=goal, anchored_start=anchored_start, slack=slack)
        )
        col = self._run_slot(slot, purpose, part)
        slot.held = (purpose, max(assignment, default=-1), col is not None)
        return col

    def _cap_cold(self, lay: _Layout) -> None:
        if self.n > LONG_CHAIN_STATES:  # as in _load: a cold run needs ~ a row count of simplex iterations
            self.cold.setOptionValue("simplex_iteration_limit", max(5000, 2 * lay.n_row))
