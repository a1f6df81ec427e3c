"""The descent by separating half-spaces (plansynth.reach.lazy.descent): every plan it
lowers to is segment-safe by the validator (an independent check), it never goes below
the exact oracle's minimum (tests/reach/reach_oracles.py), and on the public cases it
takes the timed route's plan through the decomposition down to the minimum that the
lazy loop proves for the problem."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from reach_oracles import oracle_exact
from test_exact_claims import segment_worlds

from plansynth.budget import Budget
from plansynth.reach import ReachStatus, solve
from plansynth.reach.abstraction import abstract
from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.lazy.descent import Descent, _resampled
from plansynth.reach.lazy.loop import LoopOutcome
from plansynth.reach.lazy.segtheory import SegmentTheory
from plansynth.reach.problem import ReachProblem
from plansynth.reach.validate import validate

CLAIMS = Path(__file__).resolve().parents[2] / "examples" / "reach" / "claims"


def _descent(p: ReachProblem) -> Descent:
    ab = abstract(p)
    return Descent(SegmentTheory(p, ab), ab, Budget(seconds=30).clock())


def _start(p: ReachProblem, L: int) -> LoopOutcome | None:
    """A segment-safe plan through the decomposition (the timed route or the loop)."""
    r = solve(p, "lazy-smt", Budget(seconds=10), max_horizon=L, exact_segments=False)
    if r.status is not ReachStatus.FOUND:
        return None
    return LoopOutcome(ReachStatus.FOUND, r.horizon, r.message, r.trajectory, tuple(r.regions), minimal=False)


def test_resampled_keeps_the_ends() -> None:
    P = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 2.0]])
    R = _resampled(P, 4)
    assert R.shape == (5, 2) and np.allclose(R[0], P[0]) and np.allclose(R[-1], P[-1])
    assert np.allclose(_resampled(P, 2), P)


@pytest.mark.parametrize("name, minimum", [("narrow-passage.yaml", 8), ("cross-intersection.yaml", 21)])
def test_descent_reaches_the_public_minimum(name: str, minimum: int) -> None:
    """From the plan through the decomposition (several steps longer) down to the
    minimum for the problem, each plan on the way segment-safe by the validator."""
    p = load_reach_problem(CLAIMS / name)
    start = _start(p, p.max_horizon)
    assert start is not None and start.horizon > minimum
    d = _descent(p)
    out = d.lowered(start, minimum)
    assert out.horizon == minimum and d.horizons == start.horizon - minimum
    rep = validate(p, out.trajectory, require_segment_safe=True)
    assert rep.ok and rep.segment_safe, rep.violations
    assert len(out.regions) == minimum + 1
    assert all(
        np.all(np.asarray(d.abstraction.regions[r].H) @ q <= np.asarray(d.abstraction.regions[r].h) + 1e-6)
        for r, q in zip(out.regions, np.asarray(out.trajectory.states)[:, list(p.dynamics.position)])
    )


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(segment_worlds, st.integers(8, 24))
def test_descent_plans_are_segment_safe_and_never_below_the_minimum(p: ReachProblem, L: int) -> None:
    """On random small worlds (thin walls, narrow gaps, staggered walls, floors): every
    plan the descent returns passes the validator's segment check, and the exact
    oracle does not refute its horizon (no plan below the problem's minimum)."""
    start = _start(p, L)
    if start is None:
        event("no plan through the decomposition")
        return
    d = _descent(p)
    out = d.lowered(start, 0)
    event(f"lowered by {min(start.horizon - out.horizon, 3)}+")
    assert out.horizon <= start.horizon
    rep = validate(p, out.trajectory, require_segment_safe=True)
    assert rep.ok and rep.segment_safe, (rep.violations, out.horizon)
    if out.horizon < start.horizon:
        assert oracle_exact(p, out.horizon) is not False, out.horizon
