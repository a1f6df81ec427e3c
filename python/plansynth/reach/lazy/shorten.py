"""Shortening a found plan by re-timing its stays, many at once (beyond Shoukry et al.,
CDC 2016: a pass after Algorithm 1's loop returns, checked by CON-PLAN, Section V).

The timed route (:mod:`plansynth.reach.lazy.timed`) lengthens the stays around every
place CON-PLAN's slack LP finds too tight by a fraction of its span, and stops at the
first timing it realises: the plan is long (the GCS paper's 50 x 50 maze: 423 steps of
0.5 s, 1.33 times the 159 s of gcs-decomposition's curve). Most of its stays could lose
steps; which ones, only CON-PLAN can say. Lowering them one step and one LP at a time
(:func:`~plansynth.reach.lazy.minimal.retimed`) costs an LP per step removed, hundreds
at that scale. This pass keeps the plan's regions and their order (its runs
r_0^{n_0} .. r_K^{n_K}, a run of n_k samples in region r_k) and removes steps from
every run at once:

1. every run k proposes a cut c_k (at first half its spare steps, n_k - 1);
2. the plan with n_k - c_k samples in every run goes through CON-PLAN's slack LP
   (:meth:`~plansynth.reach.lazy.conplan.ConPlan.violations`, warm-started from the
   last one: the plans shrink inside its frame);
3. no slack left: the LP's trajectory realises the shorter plan, which is kept, and
   every run proposes its cut again (bounded by its spare steps);
   slack left: the runs around each step with slack (:data:`MARGIN` runs either side)
   halve their cuts (those with none left drop out), and the others propose theirs
   again; when none of those runs has a cut left, every run halves its own.

Every round halves a positive cut or shortens the plan, so the pass ends (when no run
has a cut left, or when its time, ``shorten`` times the timed route's seconds, or the
budget runs out). Each kept plan is one CON-PLAN realised, consecutive regions
equal or adjacent as before, so it is a DIS-PLAN plan with CON-PLAN's trajectory, and
it is validated as every answer is; nothing shorter is refuted, so a shortened plan is
never claimed minimal. On the GCS paper's mazes (lazy-smt, the timed route then this):
10 x 10 43 -> 39 steps, 50 x 50 423 -> about 340 (1.07 times gcs-decomposition's curve).

>>> from plansynth.reach.families import maze
>>> from plansynth.reach.lazy.planner import plan_lazy
>>> from plansynth.reach.lazy.options import LazyOptions
>>> long = plan_lazy(maze(1), options=LazyOptions(shorten=0))
>>> short = plan_lazy(maze(1))
>>> short.horizon <= long.horizon, short.counters["minimal"]
(True, False)
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from plansynth.budget import BudgetExhausted, Clock
from plansynth.reach.lazy.conplan import ConPlan
from plansynth.reach.lazy.conplan.runs import LpFailure
from plansynth.reach.lazy.loop import LoopOutcome
from plansynth.reach.lazy.timed import SLACK_TOL
from plansynth.reach.result import ReachStatus

__all__ = ["shorten_plan", "runs_of", "plan_of", "MARGIN", "STRIKES", "STRIDE"]

#: Runs on either side of a run with slack whose cuts are halved with its own.
MARGIN = 1
#: A run whose one-step cut failed this many times proposes none again.
STRIKES = 2
#: The last phase cuts one step from every STRIDE-th run at once.
STRIDE = 3


def runs_of(plan: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
    """The runs of ``plan``: its regions (consecutive ones differ) and their lengths.

    >>> [a.tolist() for a in runs_of((3, 3, 4, 5, 5, 5))]
    [[3, 4, 5], [2, 1, 3]]
    """
    p = np.asarray(plan, dtype=np.int64)
    if not len(p):
        return p, p
    starts = np.flatnonzero(np.r_[True, p[1:] != p[:-1]])
    return p[starts], np.diff(np.r_[starts, len(p)])


def plan_of(regions: np.ndarray, lengths: np.ndarray) -> tuple[int, ...]:
    """The plan of the runs ``regions`` of ``lengths`` samples (the inverse of :func:`runs_of`).

    >>> plan_of(np.array([3, 4, 5]), np.array([2, 1, 3]))
    (3, 3, 4, 5, 5, 5)
    """
    return tuple(np.repeat(regions, lengths).tolist())


def shorten_plan(
    conplan: ConPlan,
    found: LoopOutcome,
    clock: Clock,
    seconds: float,
    *,
    lower: Sequence[float] | None = None,
    scale: float = 1.0,
    counters: dict | None = None,
) -> LoopOutcome:
    """``found`` with its stays shortened as the module doc says, within ``seconds``
    (and ``clock``; one iteration per LP): the shortest plan realised, with its
    trajectory, or ``found`` itself when no run could lose a step. ``lower``: a stay per
    run (real numbers) too short to realise (the timed route's before its repair), for
    the first phase's bisection; ``scale``: the workspace's size (the slack tolerance is
    relative to it). Never claims minimality. ``counters`` gets ``shorten_lps`` and
    ``shortened_from``."""
    if found.status is not ReachStatus.FOUND or found.regions is None or found.horizon is None or seconds <= 0:
        return found
    regions, n = runs_of(found.regions)
    deadline = time.perf_counter() + seconds
    tol = SLACK_TOL * max(1.0, scale)
    best, lps = found, 0

    def realised(lengths: np.ndarray) -> LoopOutcome | np.ndarray | None:
        """The plan of ``lengths`` realised, or its slacks (None: refuted outright)."""
        nonlocal lps
        plan = plan_of(regions, lengths)
        lps += 1
        clock.tick()
        elastic = conplan.violations(plan, tol)
        if elastic is None:
            return None
        if elastic[1] is None:
            return elastic[0]
        return LoopOutcome(ReachStatus.FOUND, len(plan) - 1, "", elastic[1].trajectory, plan, minimal=False)

    def going() -> bool:
        return time.perf_counter() < deadline and not clock.exhausted()

    try:
        if lower is not None and len(lower) == len(n):
            # phase 1: the stays between the lower ones and the plan's, by bisection
            low = np.minimum(np.maximum(np.asarray(lower, float), 1.0), n)
            low[-1] = min(low[-1] + 1.0, n[-1])  # (the plan's last sample, one more in the last region)
            lo, hi = 0.0, 1.0
            while going() and (hi - lo) * float((n - low).sum()) >= 1.0:
                mid = (lo + hi) / 2
                trial = _rounded(low + mid * (n - low))
                if trial.sum() >= n.sum():
                    break  # (no shorter plan between them at this resolution)
                out = realised(trial)
                if isinstance(out, LoopOutcome):
                    best, n, hi = out, trial, mid
                else:
                    lo = mid
        # phase 2: every run's cut at once, halved around the slack
        cut = (n - 1) // 2
        strikes = np.zeros(len(n), dtype=np.int64)
        while cut.any() and going():
            trial = n - cut
            out = realised(trial)
            if isinstance(out, LoopOutcome):
                best, n = out, trial
                # the same cuts again, and one step from every run not yet struck out
                cut = np.minimum(np.where((cut == 0) & (strikes < STRIKES), 1, cut), n - 1)
                continue
            near = _near(out, trial, tol) & (cut > 0) if out is not None else np.zeros(len(n), dtype=bool)
            if not near.any():  # (refuted by the dynamics and bounds alone, or slack far from every cut)
                near = cut > 0
            strikes[near & (cut == 1)] += 1
            cut[near] //= 2
        # phase 3: one step from every STRIDE-th run not struck out, in turn
        strikes[:] = 0
        k, idle, index = 0, 0, np.arange(len(n))
        while idle < STRIDE and going():
            one = ((strikes < STRIKES) & (n > 1) & (index % STRIDE == k)).astype(np.int64)
            if not one.any():
                k, idle = (k + 1) % STRIDE, idle + 1
                continue
            out = realised(n - one)
            if isinstance(out, LoopOutcome):
                best, n = out, n - one
                k, idle = (k + 1) % STRIDE, 0
                continue
            near = _near(out, n - one, tol) & (one > 0) if out is not None else one > 0
            strikes[near if near.any() else one > 0] += 1
    except (BudgetExhausted, LpFailure):
        pass  # the shortest plan realised so far stands
    if counters is not None:
        counters.update(shorten_lps=lps, shortened_from=found.horizon)
    if best is found:
        return found
    return replace(best, message=f"{found.message}; shortened from {found.horizon} by {lps} LPs over its stays")


def _near(slack: np.ndarray, lengths: np.ndarray, tol: float) -> np.ndarray:
    """The runs (of ``lengths`` samples) within :data:`MARGIN` runs of a sample whose
    slack exceeds ``tol``."""
    run = np.repeat(np.arange(len(lengths)), lengths)  # the run of each sample
    bad = np.unique(run[np.flatnonzero(slack > tol)])
    near = np.zeros(len(lengths), dtype=bool)
    for d in range(-MARGIN, MARGIN + 1):
        near[np.clip(bad + d, 0, len(lengths) - 1)] = True
    return near


def _rounded(stays: np.ndarray) -> np.ndarray:
    """Real stays as whole runs of samples (rounded cumulatively, at least one each).

    >>> _rounded(np.array([1.4, 1.4, 2.2])).tolist()
    [1, 2, 2]
    """
    ends = np.round(np.cumsum(stays)).astype(np.int64)
    out = np.diff(np.r_[0, ends])
    return np.maximum(out, 1)
