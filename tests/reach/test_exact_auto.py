"""``exact_segments="auto"`` (the default; plansynth.reach.lazy.exactmode): exact segment
transitions where a claim is asked, so that the claim is about the problem, and the
window search that only looks for a plan as fast as before.

* ``prove`` (and the minimal and linear searches) on the public cases of
  ``examples/reach/claims/``: the problem's minimal horizons, proved for the problem
  (the segment-safe decomposition's are one step longer on three of them);
* a too-low ``max_horizon`` (a fixed horizon): the window search refutes it through
  the decomposition and the search continues exactly: ``infeasible`` for the problem,
  or the plan the decomposition misses;
* no claim asked: maze-1 planned by the timed route as before, over the decomposition;
* ``exact_segments=False`` reproduces the claims through the decomposition;
* missions in the segment reading: the same continuation, and with a label that is not
  convex the decomposition's relation, which the result names."""

from __future__ import annotations

from dataclasses import replace

import pytest

from plansynth import Budget
from plansynth.errors import InvalidOption
from plansynth.reach import ReachStatus, load, solve
from plansynth.reach.families import maze
from plansynth.reach.lazy.claims import EXACT_SEGMENTS
from plansynth.reach.lazy.exactmode import AUTO_OFF, REGIONS, SEGMENTS
from plansynth.reach.lazy.options import CONFIGURATIONS, LazyOptions
from plansynth.reach.lazy.planner import plan_lazy
from plansynth.reach.mission.options import MissionOptions

#: public case -> (its minimal horizon for the problem, the decomposition's)
#: (docs/explanation/lazy-smt.md, the table of exact claims)
CASES = {"narrow-passage": (8, 9), "wall-gap": (19, 20), "cross-intersection": (21, 21)}


def _case(name: str):
    return load(f"examples/reach/claims/{name}.yaml")


@pytest.mark.parametrize("name", sorted(CASES))
def test_prove_gives_the_problems_minimal_horizon(name: str) -> None:
    """``prove=True`` under ``auto``: the minimum for the problem, proved for it, the
    plan validated segment-safe; ``exact_segments=False`` keeps the decomposition's
    search (the relaxation MILP then proves nothing on these)."""
    minimum, through = CASES[name]
    p = _case(name)
    r = solve(p, "lazy-smt", Budget(seconds=120), prove=True)
    assert r.status is ReachStatus.FOUND and r.validated and r.segment_safe, r.message
    assert r.horizon == minimum and r.counters["minimal"] is True, r.message
    assert r.counters["minimal_relative_to"] == "problem"
    assert r.counters["transitions"] == SEGMENTS
    assert r.counters["exact_segments"].startswith("on (auto: prove asks")
    assert r.options["exact_segments"] == "auto"
    old = solve(p, "lazy-smt", Budget(seconds=120), prove=True, exact_segments=False)
    assert old.status is ReachStatus.FOUND and old.horizon == through
    assert old.counters["transitions"] == REGIONS
    if through > minimum:  # the relaxation cannot prove the decomposition's horizon minimal
        assert old.counters["minimal_relative_to"] == "decomposition"


@pytest.mark.parametrize("search", ["minimal", "linear"])
def test_the_minimal_and_linear_searches_ask_for_a_claim(search: str) -> None:
    p = _case("narrow-passage")
    r = plan_lazy(p, Budget(seconds=120), LazyOptions(horizon_search=search))
    assert r.status is ReachStatus.FOUND and r.horizon == 8 and r.counters["minimal_relative_to"] == "problem"
    assert r.counters["exact_segments"] == f"on (auto: horizon_search={search} asks for a claim about the problem)"
    old = plan_lazy(p, Budget(seconds=120), LazyOptions(horizon_search=search, exact_segments=False))
    assert old.horizon == 9 and old.counters["minimal_relative_to"] == "decomposition"


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_too_low_fixed_horizon_is_answered_for_the_problem(name: str) -> None:
    """max_horizon one below the minimum: through the decomposition every horizon is
    refuted (not a proof: ``unknown`` with ``exact_segments=False``); under ``auto`` the
    search continues exactly and proves ``infeasible`` for the problem."""
    minimum, _ = CASES[name]
    p = _case(name)
    r = solve(p, "lazy-smt", Budget(seconds=120), max_horizon=minimum - 1)
    assert r.status is ReachStatus.INFEASIBLE and r.horizon == minimum - 1, r.message
    assert EXACT_SEGMENTS in r.message and r.counters["transitions"] == SEGMENTS
    assert r.counters["decomposition_refuted"] == minimum - 1
    assert r.counters["exact_segments"].startswith(f"on (auto: every horizon up to {minimum - 1} refuted")
    assert r.timings["decomposition_search"] > 0 and r.seconds >= r.timings["decomposition_search"]
    old = solve(p, "lazy-smt", Budget(seconds=120), max_horizon=minimum - 1, exact_segments=False)
    assert old.status is ReachStatus.UNKNOWN and "not a proof" in old.message
    assert old.counters["abstraction_refuted"] == minimum - 1 and old.counters["transitions"] == REGIONS


def test_the_plan_the_decomposition_misses_is_found_at_a_fixed_horizon() -> None:
    """narrow-passage at max_horizon 8: no plan through the decomposition (its shortest
    is 9), and the exact continuation finds the 8-step one, proved minimal."""
    p = _case("narrow-passage")
    r = solve(p, "lazy-smt", Budget(seconds=120), max_horizon=8)
    assert r.status is ReachStatus.FOUND and r.horizon == 8 and r.validated and r.segment_safe, r.message
    assert r.counters["minimal_relative_to"] == "problem" and r.counters["decomposition_refuted"] == 8


def test_maze_1s_too_low_horizon_is_infeasible_for_the_problem() -> None:
    """maze-1 at max_horizon 55 (its minimum is 57, for the decomposition and the problem):
    ``unknown`` through the decomposition, ``infeasible`` once continued exactly."""
    r = plan_lazy(maze(1), Budget(seconds=120), LazyOptions(max_horizon=55))
    assert r.status is ReachStatus.INFEASIBLE and EXACT_SEGMENTS in r.message, r.message


def test_no_claim_asked_plans_as_before() -> None:
    """The default window search (no claim asked) on maze-1: the timed route's plan, over
    the decomposition, no SAT call, the same horizon and trajectory as with
    ``exact_segments=False``."""
    r = plan_lazy(maze(1))
    old = plan_lazy(maze(1), options=LazyOptions(exact_segments=False))
    assert r.status is ReachStatus.FOUND and r.horizon == old.horizon == 58
    assert (r.trajectory.states == old.trajectory.states).all()
    assert r.counters["transitions"] == REGIONS and r.counters["exact_segments"] == AUTO_OFF
    assert r.counters["sat_calls"] == 0 and "decomposition_refuted" not in r.counters


def test_the_option_takes_three_values() -> None:
    assert LazyOptions().exact_segments == "auto" and MissionOptions().exact_segments == "auto"
    assert LazyOptions.paper().exact_segments is False  # the paper's abstraction
    assert CONFIGURATIONS["lazy-smt-paper"].exact_segments is False
    with pytest.raises(InvalidOption, match="unknown value 'sometimes' \\(known: auto, true, false\\)"):
        LazyOptions(exact_segments="sometimes")
    with pytest.raises(InvalidOption, match="expected bool or str"):
        MissionOptions(exact_segments=1)


def test_a_mission_refuted_through_the_decomposition_continues_exactly() -> None:
    """avoid-until at max_horizon 24: its shortest plan through the decomposition has 25
    steps, the problem's 24 (tests/reach/test_mission_exact.py): found, proved minimal
    for the problem; ``exact_segments=False`` answers ``unknown``, not a proof."""
    p = load("examples/reach/mission-avoid-until.yaml")
    r = solve(p, "lazy-smt", Budget(seconds=120), max_horizon=24)
    assert r.status is ReachStatus.FOUND and r.horizon == 24 and r.mission["ok"] is True, r.message
    assert r.counters["minimal_relative_to"] == "problem" and r.counters["transitions"] == SEGMENTS
    assert r.counters["decomposition_refuted"] == 24
    old = solve(p, "lazy-smt", Budget(seconds=120), max_horizon=24, exact_segments=False)
    assert old.status is ReachStatus.UNKNOWN and old.counters["abstraction_refuted"] == 24
    plain = solve(p, "lazy-smt", Budget(seconds=120))  # nothing refuted: the decomposition's search
    assert plain.horizon == 25 and plain.counters["minimal_relative_to"] == "decomposition"
    assert plain.counters["exact_segments"] == AUTO_OFF


def test_a_label_that_is_not_convex_keeps_the_decomposition_and_says_so() -> None:
    """Exact transitions read a label along a segment from its ends, which needs convex
    labels: with an L-shaped door, ``auto`` plans through the decomposition, and a
    too-low horizon stays ``unknown`` (not a proof), the result naming why."""
    from plansynth.reach.geometry import Polygon

    p = load("examples/reach/mission-avoid-until.yaml")
    door = Polygon([(17, 8), (20, 8), (20, 12), (19, 12), (19, 9), (17, 9)])
    p = replace(p, labels=(("corridor", dict(p.labels)["corridor"]), ("door", door)))
    r = solve(p, "lazy-smt", Budget(seconds=60), max_horizon=20)
    assert r.counters["exact_segments"] == "off (auto): a label is not convex"
    assert r.counters["transitions"] == REGIONS
    assert r.status is ReachStatus.UNKNOWN and "not a proof" in r.message, r.message


def test_a_continuation_without_a_time_limit_is_capped(monkeypatch: pytest.MonkeyPatch) -> None:
    """Around a circle given as a 400-vertex polygon, its regions left as slivers, the
    decomposition refutes every horizon up to 30 where 3 steps suffice
    (tests/reach/test_proved_bound.py), and the exact relation over the slivers costs
    minutes: without a time budget the continuation gets CONTINUE_SECONDS (here 1 s),
    then answers ``unknown``, still "not a proof", the options recording the budget asked."""
    from test_proved_bound import ring

    from plansynth.reach.abstraction import abstract
    from plansynth.reach.lazy import exactmode

    monkeypatch.setattr(exactmode, "CONTINUE_SECONDS", 1.0)
    p = ring(400)
    ab = abstract(p, coarsen=False)
    r = solve(p, "lazy-smt", abstraction=ab)
    assert r.status is ReachStatus.UNKNOWN and "not a proof" in r.message and "then the exact search" in r.message
    assert r.counters["abstraction_refuted"] == 30 and r.counters["decomposition_refuted"] == 30
    assert r.options["budget"]["seconds"] is None
    assert r.seconds < 30
