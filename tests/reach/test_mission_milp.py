"""The milp-ltl baseline's array build (the baseline's wall time is HiGHS's
solve plus a small build) is the same model as the expression-API build it replaced
(tests/reach/mission_milp_reference.py): the same columns with the same bounds,
integrality and objective, and the same rows with the same bounds, on the examples at
several horizons and semantics and on random small missions."""

from __future__ import annotations

import highspy
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mission_milp_reference import reference_model
from test_mission_planner import mission_problems

from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.lazy.bounds import time_windows
from plansynth.reach.mission.labels import label_abstraction, planning_problem
from plansynth.reach.mission.ltl import Const, nnf, parse
from plansynth.reach.mission.milp import mission_milp, solve_mission_horizon


def rows_of(lp: highspy.HighsLp) -> list[tuple[tuple[tuple[int, float], ...], float, float]]:
    """Every row as (sorted nonzero (column, coefficient) pairs, lower, upper), sorted:
    the rows as a multiset, whatever order or matrix format the build used."""
    a = lp.a_matrix_
    starts, index, value = np.asarray(a.start_), np.asarray(a.index_), np.asarray(a.value_)
    colwise = a.format_ == highspy.MatrixFormat.kColwise
    rows: list[dict[int, float]] = [{} for _ in range(lp.num_row_)]
    for outer in range(len(starts) - 1):
        for k in range(starts[outer], starts[outer + 1]):
            r, c = (int(index[k]), outer) if colwise else (outer, int(index[k]))
            rows[r][c] = rows[r].get(c, 0.0) + float(value[k])
    lo, hi = np.asarray(lp.row_lower_), np.asarray(lp.row_upper_)
    return sorted(
        (tuple(sorted((c, v) for c, v in r.items() if v != 0.0)), float(l), float(u)) for r, l, u in zip(rows, lo, hi)
    )


def assert_same_lp(new: highspy.HighsLp, old: highspy.HighsLp) -> None:
    assert (new.num_col_, new.num_row_) == (old.num_col_, old.num_row_)
    for field in ("col_lower_", "col_upper_", "col_cost_"):
        assert np.array_equal(np.asarray(getattr(new, field)), np.asarray(getattr(old, field))), field
    assert list(new.integrality_) == list(old.integrality_)
    assert new.offset_ == old.offset_ and new.sense_ == old.sense_
    assert rows_of(new) == rows_of(old)


def both(p, L, **kw):
    la, pp = label_abstraction(p), planning_problem(p)
    f = parse(p.mission)
    new = mission_milp(pp, la, f, L, **kw)
    old = reference_model(pp, la, f, L, **kw)
    return new, old


EXAMPLES = ["mission-patrol", "mission-visit", "mission-avoid-until", "mission-maze"]


@pytest.mark.parametrize("name", EXAMPLES)
@pytest.mark.parametrize(
    "L, semantics, segment_safe",
    [
        (0, "any", True),
        (1, "any", True),
        (4, "any", True),
        (0, "finite", True),
        (4, "finite", True),
        (1, "lasso", False),
        (4, "lasso", False),
        (4, "lasso", True),
    ],
)
def test_the_array_build_is_the_expression_build(name, L, semantics, segment_safe):
    new, old = both(
        load_reach_problem(f"examples/reach/{name}.yaml"), L, semantics=semantics, segment_safe=segment_safe
    )
    assert new.lp.num_row_ > 0
    assert_same_lp(new.lp, old.getLp())


@pytest.mark.parametrize("name", EXAMPLES)
def test_a_lasso_at_horizon_0_has_no_successor_and_is_infeasible(name):
    """No loop_j for j in 1..0: the selectors' row "sum = 1" is empty, so the model is
    infeasible (the expression build raised there: ``sum([]) == 1.0`` is a bool)."""
    p = load_reach_problem(f"examples/reach/{name}.yaml")
    la = label_abstraction(p)
    status, regions, loop_start, _ = solve_mission_horizon(
        planning_problem(p), la, parse(p.mission), 0, semantics="lasso"
    )
    assert (status, regions, loop_start) == ("infeasible", None, None)
    with pytest.raises(AttributeError):
        reference_model(planning_problem(p), la, parse(p.mission), 0, semantics="lasso")


def test_the_array_build_keeps_the_time_windows():
    """With the lower bound (the planner's default), regions not reachable by step t are
    switched off by rows, in both builds."""
    p = load_reach_problem("examples/reach/mission-maze.yaml")
    la, pp = label_abstraction(p), planning_problem(p)
    earliest = time_windows(pp, la.abstraction, 6).earliest
    assert max(earliest) > 1  # the windows do switch regions off
    new = mission_milp(pp, la, parse(p.mission), 6, earliest=earliest)
    old = reference_model(pp, la, parse(p.mission), 6, earliest=earliest)
    assert_same_lp(new.lp, old.getLp())


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(mission_problems(), st.integers(0, 4), st.sampled_from(["any", "finite", "lasso"]))
def test_the_array_build_is_the_expression_build_on_random_missions(p, L, semantics):
    L = max(L, 1) if semantics == "lasso" else L  # a lasso at horizon 0: the test above
    new, old = both(p, L, semantics=semantics)
    if new is None:  # only a mission false in negation normal form has no model (the old one was never run)
        assert nnf(parse(p.mission)) == Const(False)
        return
    assert_same_lp(new.lp, old.getLp())
