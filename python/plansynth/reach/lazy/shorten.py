"""Shortening a found plan: fewer samples in its regions, steps crossing box faces
anywhere, thin boxes skipped (beyond Shoukry et al., CDC 2016: a pass after the lazy
loop of Algorithm 1 has its plan, each candidate checked by an LP as CON-PLAN's of
Section V).

The timed route (:mod:`plansynth.reach.lazy.timed`) lengthens the stays around every
place CON-PLAN finds too tight by a fraction of its span and stops at the first timing
CON-PLAN realises, so its plan is long: the GCS paper's 50 x 50 maze, 423 steps of
0.5 s, 1.33 times the 159 s of gcs-decomposition's curve. Two things keep it there:
the stays, and CON-PLAN's rule that a step changing region ends on the regions' common
face with a sample in every region on the way (each of the maze's doorways is a box
0.1 m deep). Even re-timed to the last step, plans under that rule stay long (10 x 10:
46 steps proved minimal through the decomposition, where gcs's curve takes 39).

This pass keeps the plan's regions and their order, its runs r_0^{n_0} .. r_K^{n_K}
(n_k samples in region r_k), and checks each candidate with the prism LP
(:class:`~plansynth.reach.lazy.prismlp.PrismLP`), where a step between box regions
that follow each other across one axis may have both ends anywhere in their prism
instead: it crosses the faces anywhere and may skip a run whole (a doorway). First the
pairs' prisms are switched on wherever the plan stays realised (a few LPs, those near
slack switched off again); then, in turn for j = 0, 1, 2, every run k = j mod
:data:`STRIDE` gives up steps at once (one, twice as many after each success; a run
of one sample in a box between two boxes across one axis gives itself up):

* no slack left: its trajectory realises the shorter plan, which is kept;
* slack left: for each run with slack the cut run nearest it is struck (it proposes
  nothing until a plan is kept; a cut of several steps drops to one instead); a run
  struck :data:`STRIKES` times proposes no cut again.

Every LP shortens the plan, halves a cut or strikes a run, so the pass ends: when no
run can give a step, or when its time is up (``shorten`` times the seconds the plan
took, at least :data:`MIN_SECONDS`; no LP is started that would end after it), or the
budget's. The plan kept is solved once more with no slack (its trajectory holds every
row to HiGHS's tolerance) and validated as every answer is; nothing shorter is refuted,
so a shortened plan is never claimed minimal. Its samples are one region each, but
consecutive regions may be a skipped box apart and a step need not end on a face, so it
is no plan of CON-PLAN's (the bench records no oracle LP for it). The GCS paper's
50 x 50 maze: 423 -> 347 steps (173.5 s, 1.09 times gcs-decomposition's) in about 25
LPs, 1 s.

>>> from plansynth.reach.families import gcs_maze
>>> from plansynth.reach.lazy.planner import plan_lazy
>>> from plansynth.reach.lazy.options import LazyOptions
>>> from plansynth.budget import Budget
>>> p = gcs_maze(20)
>>> long = plan_lazy(p, options=LazyOptions(shorten=0))
>>> short = plan_lazy(p, Budget(seconds=60))
>>> long.horizon, short.horizon < long.horizon, short.counters["shortened_from"], short.counters["minimal"]
(398, True, 398, False)
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np

from plansynth.budget import BudgetExhausted, Clock
from plansynth.reach.lazy.conplan.runs import LpFailure
from plansynth.reach.lazy.loop import LoopOutcome
from plansynth.reach.lazy.prismlp import SLACK_TOL, PrismLP
from plansynth.reach.result import ReachStatus

__all__ = ["shorten_plan", "runs_of", "plan_of", "STRIKES", "STRIDE", "MIN_SECONDS"]

#: A run whose one-step cut was struck this many times proposes none again.
STRIKES = 2
#: One step is cut from every STRIDE-th run at once.
STRIDE = 3
#: The pass's time is ``shorten`` times the seconds the plan took, or this, whichever is more.
MIN_SECONDS = 1.0
#: Sweeps over the runs (each ending when every run is struck out; the next forgets the strikes).
SWEEPS = 2
#: Rounds of turning pairs' prisms on before the cuts (those within WIDEN_MARGIN runs
#: of slack off again).
WIDEN_ROUNDS = 2
WIDEN_MARGIN = 1


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
    lp: PrismLP,
    found: LoopOutcome,
    clock: Clock,
    seconds: float,
    *,
    counters: dict | None = None,
) -> LoopOutcome:
    """``found`` with its stays shortened as the module doc says, within ``seconds``
    (and ``clock``; one iteration per LP): the shortest plan realised, with its
    trajectory, or ``found`` itself when no run could lose a step. Never claims
    minimality. ``counters`` gets ``shorten_lps``, and when the plan is shortened
    ``shortened_from`` (its horizon before) and ``skipped_regions``."""
    if (
        found.status is not ReachStatus.FOUND
        or found.regions is None
        or found.horizon is None
        or found.trajectory is None
        or seconds <= 0
    ):
        return found
    reg, n = runs_of(found.regions)
    K = len(n)
    deadline = time.perf_counter() + seconds
    lps0 = lp.lp_calls
    nan = np.full(lp.d, np.nan)
    pair = [lp.prism(reg[i : i + 2]) for i in range(K - 1)]  # the prism of runs i, i + 1
    pair_lo = np.array([nan if a is None else a for a, _ in pair]).reshape(K - 1, lp.d)
    pair_hi = np.array([nan if b is None else b for _, b in pair]).reshape(K - 1, lp.d)
    skip = [
        lp.prism(reg[k - 1 : k + 2]) if 0 < k < K - 1 and reg[k - 1] != reg[k + 1] else (None, None) for k in range(K)
    ]
    skip_lo = np.array([nan if a is None else a for a, _ in skip]).reshape(K, lp.d)
    skip_hi = np.array([nan if b is None else b for _, b in skip]).reshape(K, lp.d)
    skippable = np.isfinite(skip_lo).all(axis=1)

    def prisms(lengths: np.ndarray, wide: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The prism rows of the plan of ``lengths``: a skipped run's prism, else the
        pair's where ``wide``, else none (CON-PLAN's row)."""
        full = np.flatnonzero(lengths > 0)
        a, b = full[:-1], full[1:]
        lo = np.where(
            ((b - a) == 2)[:, None], skip_lo[np.minimum(a + 1, K - 1)], np.where(wide[a][:, None], pair_lo[a], nan)
        )
        hi = np.where(
            ((b - a) == 2)[:, None], skip_hi[np.minimum(a + 1, K - 1)], np.where(wide[a][:, None], pair_hi[a], nan)
        )
        return lo, hi

    def holding(plan: tuple[int, ...], lengths: np.ndarray, states: np.ndarray) -> np.ndarray:
        """The pairs of runs (both kept) whose prism holds both ends of their step."""
        P = np.asarray(states)[:, lp.pos]
        full = np.flatnonzero(lengths > 0)
        a = full[:-1][(full[1:] - full[:-1]) == 1]
        t = np.cumsum(lengths)[a] - 1  # the last sample of run a
        ok = np.isfinite(pair_lo[a]).all(axis=1)
        for dt in (0, 1):
            ok &= np.all((P[t + dt] >= pair_lo[a] - 1e-9) & (P[t + dt] <= pair_hi[a] + 1e-9), axis=1)
        out = np.zeros(K - 1, dtype=bool)
        out[a[ok]] = True
        return out

    wide = holding(tuple(found.regions), n, np.asarray(found.trajectory.states))
    index = np.arange(K)
    best_n, best_wide = None, wide
    strikes = np.zeros(K, dtype=np.int64)
    paused = np.zeros(K, dtype=bool)  # (struck since the last plan kept)
    size = np.ones(K, dtype=np.int64)  # the steps each run proposes to give
    k, idle, lp_seconds = 0, 0, 0.0
    result = found
    try:
        # every pair's prism where it has one, but those around slack (a few rounds)
        every = np.isfinite(pair_lo).all(axis=1) | wide
        for _ in range(WIDEN_ROUNDS):
            if not (every & ~wide).any():
                break
            clock.tick()
            out = lp.solve(found.regions, *prisms(n, every))
            if out is None:
                break
            if out[1] is not None:
                wide = every
                break
            bad = np.unique(np.repeat(index, n)[out[0] > SLACK_TOL])
            off = np.zeros(K - 1, dtype=bool)
            off[np.clip((bad[:, None] + np.arange(-WIDEN_MARGIN - 1, WIDEN_MARGIN + 1)[None, :]).ravel(), 0, K - 2)] = (
                True
            )
            every &= ~off | wide
        sweeps = 1
        while time.perf_counter() + lp_seconds < deadline and not clock.exhausted():
            if idle >= STRIDE:  # no run can give a step: once more with the strikes forgotten
                if sweeps >= SWEEPS or best_n is None:
                    break
                sweeps, idle = sweeps + 1, 0
                strikes[:], paused[:], size[:] = 0, False, 1
            kept = n > 0
            can_skip = skippable & (n == 1) & np.r_[False, kept[:-1]] & np.r_[kept[1:], False]
            mine = (strikes < STRIKES) & ~paused & ((n > 1) | can_skip) & (index % STRIDE == k)
            one = np.where(mine, np.where(n > 1, np.minimum(size, n - 1), 1), 0)
            if not one.any():
                k, idle = (k + 1) % STRIDE, idle + 1
                continue
            trial = n - one
            plan = plan_of(reg, trial)
            clock.tick()
            t0 = time.perf_counter()
            out = lp.solve(plan, *prisms(trial, wide))
            lp_seconds = time.perf_counter() - t0  # (no LP is started that would end past the deadline)
            if out is not None and out[1] is not None:  # realised
                n, k, idle, best_n = trial, (k + 1) % STRIDE, 0, trial
                paused[:] = False
                size[one > 0] *= 2  # (a run that gave a step may give two next time)
                wide = wide | holding(plan, n, np.asarray(out[1].states))
                best_wide = wide
                continue
            cuts = np.flatnonzero(one)
            if out is None:  # (the dynamics and bounds alone refute it)
                struck = cuts
            else:  # the cut nearest each run with slack
                bad = np.unique(np.repeat(index, trial)[out[0] > SLACK_TOL])
                struck = np.unique(cuts[np.abs(bad[:, None] - cuts[None, :]).argmin(axis=1)])
            big = struck[one[struck] > 1]  # (a cut of several steps: one step next)
            size[big] = 1
            struck = struck[one[struck] == 1]
            strikes[struck] += 1
            paused[struck] = True
        if best_n is not None:
            plan = plan_of(reg, best_n)
            out = lp.solve(plan, *prisms(best_n, best_wide), strict=True)
            if out is not None and out[1] is not None:
                h = len(plan) - 1
                result = LoopOutcome(
                    ReachStatus.FOUND,
                    h,
                    f"{found.message}; shortened from {found.horizon} by {lp.lp_calls - lps0} LPs over its stays "
                    f"(steps crossing box faces anywhere, {int((best_n == 0).sum())} regions skipped)",
                    out[1],
                    plan,
                    minimal=False,
                )
    except (BudgetExhausted, LpFailure):
        pass  # the plan found stands
    if counters is not None:
        counters["shorten_lps"] = lp.lp_calls - lps0
        if result is not found:
            counters.update(shortened_from=found.horizon, skipped_regions=int((best_n == 0).sum()))
    return result
