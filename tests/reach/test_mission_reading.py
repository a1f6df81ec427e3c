"""The mission checker's consistent reading of boundary touches
(plansynth.reach.mission.check.consistent_reading): a SAT search, checked against
brute force over every reading, and on trajectories that only touch a label."""

from __future__ import annotations

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from test_ltl import NAMES, formulas

from plansynth.reach.fileformat import reach_problem_from_dict
from plansynth.reach.mission.check import NEG, _literal_form, check_mission, consistent_reading
from plansynth.reach.mission.ltl import Lasso, holds, nnf
from plansynth.reach.trajectory import Trajectory

#: a "may hold" letter per label: in only, out only, or touched (both)
_choice = st.sampled_from(["in", "out", "both"])
may_letters = st.tuples(*[_choice] * len(NAMES)).map(
    lambda cs: frozenset(
        x for n, c in zip(NAMES, cs) for x in ({"in": (n,), "out": (NEG + n,), "both": (n, NEG + n)}[c])
    )
)


def brute_force(f, word: Lasso) -> bool:
    """Some reading (each touched label at each position in or out) satisfies f?"""
    letters = word.letters
    amb = [(i, n) for i, a in enumerate(letters) for n in NAMES if n in a and NEG + n in a]
    for bits in itertools.product((True, False), repeat=len(amb)):
        out = [set(a) for a in letters]
        for (i, n), inside in zip(amb, bits):
            out[i].discard(NEG + n if inside else n)
        k = len(word.prefix)
        if holds(f, Lasso(tuple(out[:k]), tuple(out[k:]))):
            return True
    return False


@settings(max_examples=400, deadline=None)
@given(formulas(depth=3), st.lists(may_letters, min_size=0, max_size=3), st.lists(may_letters, min_size=1, max_size=3))
def test_the_reading_exists_exactly_when_brute_force_finds_one(f, prefix, loop):
    word = Lasso(tuple(prefix), tuple(loop))
    g = _literal_form(nnf(f))
    r = consistent_reading(g, word)
    assert (r is not None) is brute_force(g, word)
    if r is not None:  # a reading: one literal of each touched label per position, and f holds on it
        assert holds(g, r)
        for a, b in zip(word.letters, r.letters):
            assert b <= a and all((n in b) != (NEG + n in b) for n in NAMES)


def _room(mission: str):
    return reach_problem_from_dict(
        {
            "workspace": {"min": [0, 0], "max": [4, 4]},
            "labels": {"a": {"min": [2, 0], "max": [4, 4]}},
            "mission": mission,
            "robot": {"dynamics": {"model": "single-integrator", "dt": 1}, "start": [0.5, 0.5], "input_bound": 2},
        }
    )


def test_a_trajectory_that_only_touches_a_label_is_read_one_way_per_step():
    # to a's edge (x = 2) and back: every step touches a at most
    X = np.array([[0.5, 0.5], [2.0, 0.5], [2.0, 2.0], [0.5, 2.0]])
    t = Trajectory(X, np.diff(X, axis=0))
    assert check_mission(_room("F a"), t).ok  # the touch read as in
    assert check_mission(_room("G !a"), t).ok  # read as out
    r = check_mission(_room("F a & G !a"), t)  # no reading does both: "may hold" alone accepted it
    assert not r.ok and r.step == 1 and "no consistent reading" in r.reason
    # in at step 1, out at step 2: two touches, two readings
    assert check_mission(_room("X a & X X !a"), t).ok
    assert not check_mission(_room("X (a & !a)"), t).ok
    # a real visit still satisfies F a & F !a without any boundary reading
    Y = np.array([[0.5, 0.5], [2.0, 0.5], [3.0, 0.5], [2.0, 0.5], [0.5, 0.5]])
    assert check_mission(_room("F a & F !a"), Trajectory(Y, np.diff(Y, axis=0))).ok


def test_a_lasso_on_a_boundary_keeps_one_reading_per_position():
    # resting on a's edge forever: G F a & G F !a needs two readings of one position
    X = np.array([[0.5, 0.5], [2.0, 0.5], [2.0, 0.5]])
    t = Trajectory(X, np.diff(X, axis=0))
    assert check_mission(_room("G F a"), t, loop_start=1).ok
    assert not check_mission(_room("G F a & G F !a"), t, loop_start=1).ok
    # walking along the edge between two points gives two positions in the loop
    Z = np.array([[0.5, 0.5], [2.0, 0.5], [2.0, 2.0], [2.0, 0.5]])
    assert check_mission(_room("G F a & G F !a"), Trajectory(Z, np.diff(Z, axis=0)), loop_start=1).ok
