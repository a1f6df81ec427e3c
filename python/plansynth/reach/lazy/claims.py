"""What the lazy planner's ``infeasible`` and "minimal" mean, and the steps that make
them hold (Shoukry et al., CDC 2016, Algorithm 1 refutes horizons through the
abstraction of Section III; this module says when such a refutation is a proof).

The claims are about the problem as ``shared/spec/reach-problem.md`` defines it, or they
say what they are relative to:

* *Samples only* (``segment_safe=False``): DIS-PLAN steps between any two regions one
  step can connect (:func:`~plansynth.reach.lazy.bounds.step_adjacency`, an
  over-approximation from the displacement bounds; CON-PLAN's LP refutes the pairs no
  step realises, and its counterexamples are sound), and the lower bounds and time
  windows follow the same relation. With regions that cover the free space (an
  ``exact`` abstraction) every trajectory's region sequence is then a DIS-PLAN plan,
  so a refuted horizon is refuted for the problem: ``infeasible up to L`` is a proof,
  and a horizon found at the bottom of its window is minimal for the problem
  (``counters["minimal_relative_to"] == "problem"``). Without the step relation a
  thin wall that one step jumps, or a region that one step skips, made the loop claim
  minimal horizons that were not (``tests/reach/test_exact_claims.py``).
* *Segment-safe* (the default): CON-PLAN keeps each segment inside one convex region,
  which is sufficient for safety but not necessary (a segment may cross several
  regions; stlpy's narrow passage has an 8-step segment-safe plan where this search
  needs 9). So a horizon the loop refutes is refuted only for plans whose consecutive
  samples share a region, and: ``infeasible`` only when
  :func:`~plansynth.reach.lazy.bounds.proved_horizon_bound`, which holds for every
  trajectory of the problem, exceeds ``max_horizon`` (else ``unknown``,
  ``counters["abstraction_refuted"]``: not a proof; around a circle given as a
  400-vertex polygon the sliver regions made the loop refute horizon 30 where 3 steps
  suffice, ``tests/reach/test_proved_bound.py``); and a found horizon is minimal for
  the problem only when it is at most that proved bound, else
  ``counters["minimal_relative_to"] == "decomposition"`` and the message says so
  (the CLI prints "minimal through the decomposition only"). With ``prove=True`` the
  MILP relaxation of :mod:`~plansynth.reach.lazy.relaxation` (samples and points along
  each segment kept free: necessary for segment safety) may prove such a horizon
  minimal, or every horizon up to ``max_horizon`` infeasible, for the problem
  (``counters["relaxation"]``).
* An abstraction that is not ``exact`` (obstacles replaced by outer polygons) makes
  every refutation relative to the decomposition, in both modes.

Both modes read the free space as the union of full-dimensional regions: a zero-width
slit (a face two obstacles share, or an obstacle face flush with the workspace's
boundary) lies outside every obstacle's interior as the spec words it, but no region
holds it, so no claim counts paths through such slits.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

from plansynth.budget import Clock
from plansynth.reach.lazy.loop import LoopOutcome
from plansynth.reach.problem import ReachProblem
from plansynth.reach.result import ReachStatus

__all__ = ["uncertified", "minimal_claim", "prove_claims", "not_a_proof", "EXACT_SAMPLES", "DECOMPOSITION_ONLY"]


def uncertified(out: LoopOutcome, n: int, relaxation: str | None) -> LoopOutcome:
    """The claims of a loop that kept ``n`` LP refutations without a Farkas certificate
    (the interior-point method's, on expendable plans (see :class:`~plansynth.reach.lazy.loop.TheoryChecker`) or
    as a fallback when the simplex method stalls, and presolve's): an ``infeasible``
    from the loop alone becomes ``unknown`` and a minimal horizon is no longer claimed,
    unless the independent relaxation MILP proved it (``prove=True``). The refutations
    stay sound as far as HiGHS's verdict goes, but a "no" is certified before it is
    reported, and these are not."""
    why = f"{n} LP refutation{'s' * (n != 1)} without a Farkas certificate (interior-point method or presolve)"
    if out.status is ReachStatus.INFEASIBLE and relaxation != "infeasible":  # (bounds refute before any LP)
        return LoopOutcome(ReachStatus.UNKNOWN, out.horizon, f"{out.message}; not a proof: {why}")
    if out.status is ReachStatus.FOUND and out.minimal and relaxation != "minimal":
        return replace(out, minimal=False, message=f"{out.message}; not proved minimal: {why}")
    return out


#: What makes a samples-only refutation a proof (see the module docstring).
EXACT_SAMPLES = (
    "samples only, steps between any two regions one step can connect, regions covering the free "
    "space: a proof for the problem"
)

#: What a segment-safe search's refutations are relative to (see the module docstring).
DECOMPOSITION_ONLY = "consecutive samples in one convex region"


def minimal_claim(out: LoopOutcome, proved: float, exact: bool) -> dict[str, Any]:
    """What a found horizon's minimality claim is relative to:
    ``minimal_relative_to`` is ``"problem"`` when no trajectory of the problem (the
    spec's semantics) has a shorter horizon (an exact samples-only search, or a horizon
    no larger than :func:`~plansynth.reach.lazy.bounds.proved_horizon_bound`), else
    ``"decomposition"``: no shorter plan whose consecutive samples share a region of the
    decomposition (segment-safe mode), or through an inexact decomposition."""
    h = out.horizon
    if h is not None and h <= proved:  # every trajectory needs at least `proved` steps
        return {"minimal": True, "minimal_relative_to": "problem"}
    if not out.minimal:
        return {"minimal_relative_to": None}
    return {"minimal_relative_to": "problem" if exact else "decomposition"}


def prove_claims(problem: ReachProblem, out: LoopOutcome, proved: float, clock: Clock, counters: dict) -> LoopOutcome:
    """``prove=True``, segment-safe: try to make the loop's claims hold for the problem
    with :func:`~plansynth.reach.lazy.relaxation.refute_below` (a MILP relaxation of
    segment safety; one MILP at h - 1 when the robot starts at rest), within the
    budget left: a found horizon becomes proved minimal, every horizon refuted through
    the abstraction becomes ``infeasible``. ``counters["relaxation"]`` says what it
    proved (``minimal``, ``infeasible``, or ``not proved``)."""
    from plansynth.reach.lazy.relaxation import SUBDIVISIONS, refute_below

    lowest = 0 if math.isinf(proved) else int(proved)
    if out.status is ReachStatus.FOUND and out.horizon is not None and out.horizon > lowest:
        ok = refute_below(problem, out.horizon, lowest=lowest, seconds=clock.remaining())
        counters["relaxation"] = "minimal" if ok else "not proved"
        if ok:
            return replace(
                out,
                minimal=True,
                message=f"{out.message}; proved minimal for the problem: no shorter "
                f"trajectory keeps its samples and {SUBDIVISIONS - 1} points per segment free",
            )
    elif out.status is ReachStatus.UNKNOWN and counters.get("abstraction_refuted") is not None:
        L = int(counters["abstraction_refuted"])
        ok = refute_below(problem, L + 1, lowest=lowest, seconds=clock.remaining())
        counters["relaxation"] = "infeasible" if ok else "not proved"
        if ok:
            return LoopOutcome(
                ReachStatus.INFEASIBLE,
                L,
                f"infeasible up to horizon {L}: no trajectory keeps its "
                f"samples and {SUBDIVISIONS - 1} points per segment free (a MILP relaxation of "
                f"segment safety: a proof for the problem)",
            )
    if counters.get("relaxation") == "not proved":
        return replace(out, message=f"{out.message}; prove: the relaxation MILP has a solution or ran out of time")
    return out


def not_a_proof(proved: float) -> str:
    """What a refutation through the abstraction is not (segment-safe; see the module docstring)."""
    return (
        f"not a proof of infeasibility (a step may cross several regions; proved lower bound on the "
        f"horizon: {int(proved)})"
    )
