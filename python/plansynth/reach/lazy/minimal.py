"""Proving a found horizon minimal, and lowering it (beyond Shoukry et al., CDC 2016).

The paper's loop (Algorithm 1) tries one horizon at a time, so the first trajectory it
finds has the smallest horizon any region sequence allows. The window search
(:func:`~plansynth.reach.lazy.loop.horizon_windows`) finds one sooner, at some horizon of
its window; this module turns such a plan into a proved minimal one
(``horizon_search="minimal"``: :func:`prove_minimal`) or a shorter one
(:func:`shortened`), with every clause DIS-PLAN learned kept:

* :func:`retimed`: the plan's stays shortened one step at a time while the theory still
  realises it (LPs only, no SAT call);
* :func:`compressed`: a plan's stays shortened in proportion to a shorter horizon (the
  phases DIS-PLAN's probes follow, and the candidates :func:`shortened` checks);
* :func:`prove_minimal`: the per-axis reachable sets of
  :mod:`~plansynth.reach.lazy.axisreach` first, then single-horizon probes of the lazy
  loop galloping down and bisecting (monotone when the robot starts at rest).

Minimal is relative to the transition relation DIS-PLAN uses; what that means for the
problem is :mod:`plansynth.reach.lazy.claims`'s.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import replace

from plansynth.budget import BudgetExhausted, Clock
from plansynth.reach.lazy.axisreach import AxisReach
from plansynth.reach.lazy.conflict import Feasible
from plansynth.reach.lazy.conplan.runs import LpFailure
from plansynth.reach.lazy.displan import DisPlan
from plansynth.reach.lazy.loop import LoopOutcome, TheoryChecker, _lowest_open, _refuted_note, lazy_loop, learn_all
from plansynth.reach.lazy.transit import TransitCheck
from plansynth.reach.result import ReachStatus

__all__ = ["prove_minimal", "retimed", "shortened", "compressed", "REACH_SETS"]

#: How the per-axis reachable sets refute the shorter horizons (prove_minimal).
REACH_SETS = "refuted by the per-axis reachable sets over the region graph, which do not reach the goal"


def prove_minimal(
    displan: DisPlan,
    theory: TheoryChecker,
    found: LoopOutcome,
    bottom: int,
    clock: Clock,
    timings: dict[str, float],
    *,
    monotone: bool,
    reach: AxisReach | None = None,
    counters: dict | None = None,
    lower: Callable[[LoopOutcome, int], LoopOutcome] | None = None,
) -> tuple[LoopOutcome, int]:
    """Prove the horizon of ``found`` minimal (``horizon_search="minimal"``, beyond the
    paper), given that every horizon below ``bottom`` is refuted and DIS-PLAN holds every
    clause learned so far.

    With ``monotone`` (the robot starts at rest, ``A x_0 = x_0``) feasibility is monotone
    in the horizon: a plan of horizon L, preceded by one step of waiting at the start
    (u = 0, in the start's region), is a plan of horizon L + 1, through the same regions
    plus one. So refuting a single horizon L refutes every horizon <= L, and the least
    feasible horizon is found by probes of one horizon each (a refuted probe closes
    every horizon below it; a realised one is the new best plan): first the best plan
    is :func:`retimed` (LPs only, no SAT call), then the probes gallop down from it
    (h - 1, then 2, 4, ... steps below the best plan while they are realised, each new
    plan re-timed too), and once a probe is refuted they bisect between it and the best
    plan. DIS-PLAN's phases follow the best plan so far, :func:`compressed` to the
    probe's horizon.

    Why this order: every probe above the minimum is a SAT search
    for a near-tight timing, and on the mazes those cost as much as the refutation
    below the minimum (maze-4, from the window's 152 and its start 122: the plain
    bisection probed 136, 144, 140, 142, 141, 182 iterations; re-timing takes the plan
    to 145 in ~25 LPs and the gallop probes 144, 142, 141, 140). The refutation of
    h - 1 is what remains, about 40 iterations on maze-4.
    Without it, the window bottom..h-1 is asked as a whole until it is refuted, each
    plan found lowering its top. Either way the answer is minimal relative to the
    transition relation DIS-PLAN uses (as under ``horizon_search="linear"``); when the
    budget runs out the best plan so far is returned with ``minimal=False``. Returns the
    outcome and the number of probes (single horizons, or windows) asked.

    With ``reach`` (:class:`~plansynth.reach.lazy.axisreach.AxisReach`, for dynamics that
    separate by axis; ``reach_sets=True``) the per-axis reachable sets come first, with
    no LP: every horizon below their first goal step b has no plan (the module's
    soundness argument, relative to the same transition relation as DIS-PLAN's), so
    those are closed; if b is the plan's own horizon or above, the plan is minimal.
    Otherwise one probe at b, under the tube of horizon b (the regions a trajectory of
    that horizon can visit at each step, added as clauses for that horizon only); a
    plan found there is minimal. On maze-1..4 b is the minimum and the tube leaves 1-2
    steps per gap, so that probe costs a few iterations where the probes above took
    ~100 (``counters["reach_sets_bound"]``: b, or None when no horizon below the
    plan's is reached). If b is refuted, the probes above continue from b + 1.

    ``lower(best, bottom)`` (optional; exact segment transitions:
    :meth:`~plansynth.reach.lazy.descent.Descent.lowered`) returns a plan at a horizon
    down to ``bottom`` or ``best``; it runs wherever :func:`retimed` does, and before
    the probe at b (a plan it finds at b needs no probe). It refutes nothing."""
    best, probes = found, 0
    assert best.horizon is not None
    if reach is not None and best.horizon > bottom:
        t0 = time.perf_counter()
        try:
            bound = reach.first_horizon(best.horizon - 1, displan.earliest, displan.to_go)
            tube = reach.tube(bound) if bound is not None and bound >= bottom and reach.reached else None
        except BudgetExhausted as exc:
            return replace(best, minimal=False, message=f"{best.message}; not proved minimal: {exc}"), probes
        finally:
            timings["reach_sets"] = timings.get("reach_sets", 0.0) + time.perf_counter() - t0
        if counters is not None:
            counters["reach_sets_bound"] = bound
            counters["reach_sets_reached"] = reach.reached
        if bound is None:
            return replace(
                best,
                minimal=True,
                message=f"found at horizon {best.horizon} (proved minimal: every shorter horizon {REACH_SETS})",
            ), probes
        bound = max(bound, bottom)
        for L in range(bottom, bound):
            if L not in displan.closed:
                displan.close(L)  # no plan of these horizons: the sets do not reach the goal
        bottom = bound
        if lower is not None:
            best = lower(best, bound)
            if best.horizon == bound:
                return replace(
                    best,
                    minimal=True,
                    message=f"found at horizon {bound} (proved minimal: every shorter horizon {REACH_SETS})",
                ), probes
        if reach.reached and best.horizon > bound:  # (else the sweep stopped at its work cap: no probe there)
            if tube is not None:
                displan.forbid(bound, tube)
            # under the tube the plans proposed keep to feasible crossing times, and the
            # transit layer's leg LPs (maze-4: 80 to decide the legs of one refuted plan)
            # would only repeat what CON-PLAN's conflict says: CON-PLAN alone
            plain = theory.inner if isinstance(theory, TransitCheck) and tube is not None else theory
            out = lazy_loop(
                displan, plain, [(bound, bound)], clock, timings, None, lambda H, plan=best.regions: compressed(plan, H)
            )
            probes += 1
            if out.status is ReachStatus.FOUND:
                return replace(
                    out,
                    minimal=True,
                    message=f"found at horizon {out.horizon} (proved minimal: every shorter horizon {REACH_SETS})",
                ), probes
            if out.status is not ReachStatus.INFEASIBLE:
                return (
                    replace(best, minimal=False, message=f"{best.message}; not proved minimal: {out.message}"),
                    probes,
                )
            if bound not in displan.closed:
                displan.close(bound)
            bottom = bound + 1
    best = _lowered(retimed(displan, theory, best, bottom, clock, timings), bottom, lower)
    step, refuted = 1, False  # downward gallop from the best plan until a probe is refuted
    while best.horizon > bottom:
        top = best.horizon - 1
        if refuted:
            probe = (bottom + top) // 2
        else:
            probe = max(bottom, top + 1 - step)
        window = [(probe, probe)] if monotone else [(bottom, top)]
        if monotone and reach is not None and reach.reached:
            _forbid_outside_tube(displan, reach, probe, timings)
        out = lazy_loop(displan, theory, window, clock, timings, None, lambda H, plan=best.regions: compressed(plan, H))
        probes += 1
        if out.status is ReachStatus.FOUND:
            best = _lowered(retimed(displan, theory, out, bottom, clock, timings), bottom, lower)
            step *= 2
        elif out.status is ReachStatus.INFEASIBLE:
            refuted = True
            for L in range(bottom, probe + 1 if monotone else top + 1):
                if L not in displan.closed:
                    displan.close(L)  # (by monotonicity, when below the probe)
            bottom = probe + 1 if monotone else top + 1
        else:
            return replace(best, minimal=False, message=f"{best.message}; not proved minimal: {out.message}"), probes
    assert best.horizon is not None
    how = ", by monotonicity from the start at rest" if monotone else ""
    return replace(
        best,
        minimal=True,
        message=f"found at horizon {best.horizon} (proved minimal: every shorter horizon refuted{how})",
    ), probes


def _forbid_outside_tube(displan: DisPlan, reach: AxisReach, horizon: int, timings: dict[str, float]) -> None:
    """The per-axis reachable sets' tube of ``horizon`` as clauses for that horizon only
    (a single-horizon probe's plans keep to it; no plan of another horizon is affected)."""
    t0 = time.perf_counter()
    try:
        tube = reach.tube(horizon)
    finally:
        timings["reach_sets"] = timings.get("reach_sets", 0.0) + time.perf_counter() - t0
    if tube is not None:
        displan.forbid(horizon, tube)


def _lowered(best: LoopOutcome, bottom: int, lower: Callable[[LoopOutcome, int], LoopOutcome] | None) -> LoopOutcome:
    """``best`` lowered by ``lower`` (prove_minimal's), if any."""
    return best if lower is None else lower(best, bottom)


def retimed(
    displan: DisPlan,
    theory: TheoryChecker,
    found: LoopOutcome,
    bottom: int,
    clock: Clock,
    timings: dict[str, float],
) -> LoopOutcome:
    """``found`` with its horizon lowered by re-timing alone (beyond the paper): while
    some stay of the plan, shortened by one step (the longest stays first), is still
    realised by the theory, keep the shorter plan. One theory check per candidate, no
    SAT call; the conflicts of the candidates refuted are learned by DIS-PLAN (they hold
    for every plan, as in the loop). Only an upper bound for :func:`prove_minimal`: its
    probes, not this, prove the horizon minimal. Stops at ``bottom`` (no shorter plan
    exists), when the budget runs out, or when no stay can lose a step.

    On the mazes a plan at the first window's top (maze-4: 152) comes down to a few
    steps above the minimum (145 of 141) in about 25 LPs, so the bisection's probes
    above the minimum, each a SAT search for a near-tight timing, mostly go."""
    best = found
    try:
        while best.horizon is not None and best.horizon > bottom and best.regions is not None:
            stays: list[list[int]] = []
            for r in best.regions:
                if stays and stays[-1][0] == r:
                    stays[-1][1] += 1
                else:
                    stays.append([r, 1])
            shorter = None
            for i in sorted(range(len(stays)), key=lambda i: -stays[i][1]):
                if stays[i][1] <= 1 or clock.exhausted():
                    continue
                plan = tuple(r for j, (r, n) in enumerate(stays) for _ in range(n - (j == i)))
                t0 = time.perf_counter()
                answer = theory.check(plan)
                timings["lp"] += time.perf_counter() - t0
                if isinstance(answer, Feasible):
                    h = len(plan) - 1
                    shorter = LoopOutcome(
                        ReachStatus.FOUND, h, f"found at horizon {h} (re-timed)", answer.trajectory, plan, minimal=False
                    )
                    break
                learn_all(displan, answer)
            if shorter is None:
                break
            best = shorter
    except (BudgetExhausted, LpFailure):
        pass  # the best plan so far stands; the probes report the budget
    return best


def shortened(
    displan: DisPlan,
    theory: TheoryChecker,
    found: LoopOutcome,
    windows: Sequence[tuple[int, int]],
    clock: Clock,
    timings: dict[str, float],
    counters: dict | None = None,
) -> LoopOutcome:
    """``found`` at a shorter horizon when a deferred window lies below it (the window
    search; beyond the paper): the plan's stays :func:`compressed` in proportion to a
    horizon between the lowest horizon not refuted and the plan's, by bisection, one
    theory check each and no SAT call (a compressed plan that fails only moves the
    bisection; its conflicts are learned as in the loop). A window deferred after a few
    plans leaves the answer to the next window, often at its top: the GCS paper's 50 x 50
    maze was found at 1,146 (window 573..1,146 above the deferred 286..572) and comes down
    to 668 in 10 LPs (1.7 s). Not used on dear dynamics, where each check costs a
    horizon-long LP of seconds. The result is minimal only if it reaches the lowest
    horizon not refuted (every horizon below that is)."""
    h = found.horizon
    if h is None or found.regions is None:
        return found
    below = _lowest_open(displan, windows[0][0], h)
    own = next((lo for lo, hi in windows if lo <= h <= hi), h)  # the bottom of the plan's window
    if below >= own:
        return found  # no deferred window below: the plan's own window is the lowest open one
    best, lo, hi, checks = found, below - 1, h, 0
    try:
        while lo + 1 < hi and not clock.exhausted():
            H = (lo + hi) // 2
            plan = compressed(best.regions, H)
            checks += 1
            t0 = time.perf_counter()
            answer = theory.check(plan)
            timings["lp"] += time.perf_counter() - t0
            if isinstance(answer, Feasible):
                best = LoopOutcome(ReachStatus.FOUND, H, "", answer.trajectory, plan)
                hi = H
                continue
            lo = H
            learn_all(displan, answer)
    except (BudgetExhausted, LpFailure):
        pass  # the best plan so far stands
    if counters is not None:
        counters["shortened_checks"] = checks
    if best is found:
        return found
    minimal = hi == below
    note = _refuted_note(below, hi)
    return replace(
        best, message=f"found at horizon {hi}{note}; shortened from {h} by compressing its stays", minimal=minimal
    )


def compressed(plan: Sequence[int], horizon: int) -> tuple[int, ...]:
    """``plan`` (r_0..r_h) shortened to ``horizon``: the same regions in the same order,
    each stay shortened in proportion to its length (largest remainders first; every stay
    keeps one step). Only a hint for DIS-PLAN's phases: when the stays have fewer spare
    steps than must go, the plan is cut off at ``horizon``.

    >>> compressed((0, 0, 0, 0, 1, 2, 2, 2, 2), 6)
    (0, 0, 0, 1, 2, 2, 2)
    """
    runs: list[list[int]] = []
    for r in plan:
        if runs and runs[-1][0] == r:
            runs[-1][1] += 1
        else:
            runs.append([r, 1])
    drop = len(plan) - 1 - horizon
    spare = [n - 1 for _, n in runs]
    total = sum(spare)
    if drop <= 0 or total < drop:
        return tuple(plan) if drop <= 0 else tuple(plan[: horizon + 1])
    share = [drop * s / total for s in spare]
    cut = [int(x) for x in share]
    for i in sorted(range(len(runs)), key=lambda i: share[i] - cut[i], reverse=True)[: drop - sum(cut)]:
        cut[i] += 1
    out: list[int] = []
    for (r, n), c in zip(runs, cut):
        out += [r] * (n - c)
    return tuple(out)
