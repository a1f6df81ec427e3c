"""When the lazy planner steps between regions exactly (``exact_segments``; beyond
Shoukry et al., CDC 2016, whose DIS-PLAN moves one region of the abstraction per step).

Segment-safe, DIS-PLAN's transition relation is one of two:

* ``regions``: consecutive samples in one convex region (Section IV's DIS-PLAN over
  Section III's abstraction, with segment safety). Fast, but a refuted horizon is
  refuted only through the decomposition (:mod:`plansynth.reach.lazy.claims`), so ``infeasible`` and a minimal
  horizon are claims about the decomposition, not the problem;
* ``segments``: a step between any two regions one free segment can connect, with
  points along each segment (:mod:`plansynth.reach.lazy.segments`,
  :mod:`plansynth.reach.lazy.segtheory`): refutations hold for the problem.

Samples only (``segment_safe=False``) the relation is ``steps`` (any two regions one
step can connect), exact already. ``exact_segments=True`` and ``False`` pick one;
``"auto"`` (the default) picks ``segments`` exactly where the user asks for a claim and
``regions`` elsewhere, as :func:`exact_mode` says:

* a claim asked up front (``prove``, ``horizon_search`` ``"minimal"`` or ``"linear"``):
  ``segments`` from the start, so the minimal horizon found is one for the problem;
* the window search (no claim asked: a plan is wanted): ``regions``, as fast as without
  the option, and only if it refutes every horizon up to ``max_horizon`` through the
  decomposition (which it would answer with ``unknown``, "not a proof") does the search
  :func:`continue <continued>` with ``segments`` in the budget left (at most
  :data:`CONTINUE_SECONDS` without a time limit), so that a too-low ``max_horizon`` is
  answered about the problem (a plan, or ``infeasible``).

The result says which relation ran (``counters["transitions"]``) and why
(``counters["exact_segments"]``); what each claim is relative to stays in
``counters["minimal_relative_to"]`` and the message.

>>> from plansynth.reach.lazy.options import LazyOptions
>>> [exact_mode(LazyOptions(**o)).first for o in ({}, {"prove": True}, {"horizon_search": "linear"})]
[False, True, True]
>>> exact_mode(LazyOptions()).retry, exact_mode(LazyOptions(exact_segments=False)).retry
(True, False)
>>> exact_mode(LazyOptions(segment_safe=False)).transitions
'steps'
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, TypeVar

from plansynth.budget import Budget, Clock
from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.result import ReachResult, ReachStatus

__all__ = [
    "ExactMode",
    "exact_mode",
    "searched",
    "should_continue",
    "continuation_budget",
    "continued",
    "REGIONS",
    "SEGMENTS",
    "STEPS",
    "AUTO_OFF",
    "CONTINUE_SECONDS",
]

D = TypeVar("D")

#: ``counters["transitions"]``: DIS-PLAN's transition relation (see the module docstring).
REGIONS, SEGMENTS, STEPS = "regions", "segments", "steps"
#: Seconds an exact continuation gets when the budget has no time limit: the window search
#: asked for no claim, and on some decompositions the exact relation alone costs minutes
#: (a circle as a 400-vertex polygon, its regions left as slivers: the segment pairs'
#: step ends take over 2 minutes where the decomposition's search answers in 0.5 s).
CONTINUE_SECONDS = 60.0
#: ``counters["exact_segments"]`` of an ``auto`` run that never needed exact transitions.
AUTO_OFF = "off (auto: no claim asked, and no refutation through the decomposition to continue from)"


@dataclass(frozen=True)
class ExactMode:
    """How a run uses exact segment transitions: the relation its search starts with
    (``transitions``), whether it continues with ``segments`` after a refutation
    through the decomposition (``retry``); ``why`` is what the result records
    (``counters["exact_segments"]``)."""

    transitions: str
    retry: bool
    why: str

    @property
    def first(self) -> bool:
        """Exact segment transitions from the start."""
        return self.transitions == SEGMENTS


def claim_asked(opts: LazyOptions) -> str | None:
    """The option that asks for a claim about the problem (None: the window search,
    which only looks for a plan)."""
    if opts.prove:
        return "prove"
    if opts.horizon_search != "window":
        return f"horizon_search={opts.horizon_search}"
    return None


def exact_mode(opts: LazyOptions) -> ExactMode:
    """What ``opts.exact_segments`` means for this run (see the module docstring)."""
    if not opts.segment_safe:
        return ExactMode(STEPS, False, "off: samples only, steps between any two regions one step can connect")
    if opts.exact_segments is True:
        return ExactMode(SEGMENTS, False, "on")
    if opts.exact_segments is False:
        return ExactMode(REGIONS, False, "off: one region per step, claims through the decomposition")
    asked = claim_asked(opts)
    if asked is not None:
        return ExactMode(SEGMENTS, False, f"on (auto: {asked} asks for a claim about the problem)")
    return ExactMode(REGIONS, True, AUTO_OFF)


def searched(
    mode: ExactMode,
    budget: Budget,
    search: Callable[[Budget, Clock, bool, D | None, bool], tuple[ReachResult, D | None]],
    decomposition: D | None = None,
) -> ReachResult:
    """Run ``search(budget, clock, crossing, decomposition, continuing)`` (a planner's
    search, with exact segment transitions or without, over a decomposition computed
    before or None; it returns its result and the decomposition it planned over) as
    ``mode`` says: once, and under ``auto`` once more with exact transitions when the
    first refuted every horizon through the decomposition (:func:`should_continue`), in
    :func:`continuation_budget`, the two answers :func:`continued`."""
    clock = budget.clock()
    out, decomposition = search(budget, clock, mode.first, decomposition, False)
    if should_continue(mode, out, time_left=not clock.exhausted()):
        more = continuation_budget(budget, clock)
        again, _ = search(more, more.clock(), True, decomposition, True)
        return continued(out, again)
    out.counters["exact_segments"] = mode.why
    return out


def should_continue(mode: ExactMode, first: ReachResult, time_left: bool) -> bool:
    """Whether the search continues with exact transitions after ``first``: under
    ``auto``, when ``first`` refuted every horizon through the decomposition (an
    ``unknown`` that is "not a proof"), over regions that cover the free space (else
    the exact search proves nothing either), with budget left."""
    c = first.counters
    return (
        mode.retry
        and first.status is ReachStatus.UNKNOWN
        and c.get("abstraction_refuted") is not None
        and bool(c.get("exact_abstraction"))
        and time_left
    )


def continuation_budget(budget: Budget, clock: Clock) -> Budget:
    """What an exact continuation may spend: what is left of ``budget`` on ``clock``
    (time and iterations, the same memory), or :data:`CONTINUE_SECONDS` without a time
    limit."""
    left = clock.remaining()
    its = None if budget.iterations is None else max(budget.iterations - clock.iterations, 0)
    return Budget(
        seconds=CONTINUE_SECONDS if math.isinf(left) else max(left, 1e-3),
        iterations=its,
        memory_mb=budget.memory_mb,
    )


def continued(first: ReachResult, second: ReachResult) -> ReachResult:
    """The answer of a search continued exactly: ``second`` (the exact search, on the
    same clock), with the first search's refutation recorded
    (``counters["decomposition_refuted"]``, its seconds in
    ``timings["decomposition_search"]``). When the exact search too ends ``unknown``,
    the first's "not a proof" stays in the message and ``abstraction_refuted``."""
    refuted = first.counters["abstraction_refuted"]
    counters: dict[str, Any] = dict(second.counters)
    counters.update(
        iterations=first.counters.get("iterations", 0) + second.counters.get("iterations", 0),
        decomposition_refuted=refuted,
        exact_segments=f"on (auto: every horizon up to {refuted} refuted through the decomposition; "
        "continued with exact transitions)",
    )
    message = second.message
    if second.status is ReachStatus.UNKNOWN:
        counters.setdefault("abstraction_refuted", refuted)
        message = f"{first.message}; then the exact search: {second.message}"
    timings = dict(second.timings)
    timings["decomposition_search"] = first.seconds
    timings["total"] = first.seconds + second.seconds
    # (the options as asked, with the whole budget: the continuation ran on what was left)
    return replace(
        second, counters=counters, timings=timings, seconds=timings["total"], message=message, options=first.options
    )
