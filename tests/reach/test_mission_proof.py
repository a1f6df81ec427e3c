"""Proofs of mission infeasibility (plansynth.reach.mission.proof): the tableau decides
LTL satisfiability over an alphabet; checked against brute force over short lassos, and
every witness it returns satisfies the formula by the fixpoint evaluator."""

from __future__ import annotations

import itertools

from hypothesis import given, settings
from hypothesis import strategies as st
from test_ltl import NAMES, formulas

from plansynth.reach.mission.ltl import Lasso, holds, parse
from plansynth.reach.mission.proof import geometry_letters, satisfiable, witness

ALL = frozenset(NAMES)
alphabets = st.lists(st.frozensets(st.sampled_from(NAMES)), min_size=1, max_size=3, unique=True)


def brute_force(f, alphabet, max_len: int = 4) -> bool:
    """Some lasso over the alphabet with prefix + loop of at most ``max_len`` letters satisfies f?"""
    for n in range(1, max_len + 1):
        for word in itertools.product(alphabet, repeat=n):
            for k in range(n):
                if holds(f, Lasso(word[:k], word[k:])):
                    return True
    return False


@settings(max_examples=300, deadline=None)
@given(formulas(depth=3), alphabets)
def test_the_tableau_agrees_with_brute_force_and_its_witnesses_hold(f, alphabet):
    letters = [(a, ALL - a) for a in alphabet]  # ordinary valuations: a literal holds or its negation does
    w = witness(f, letters)
    if w is not None:
        prefix, loop = w
        assert holds(f, Lasso(tuple(alphabet[i] for i in prefix), tuple(alphabet[i] for i in loop)))
    if brute_force(f, alphabet):
        assert w is not None
    assert satisfiable(f, letters) is (w is not None)


def test_may_hold_letters_are_monotone():
    """A boundary letter (both a and !a may hold) satisfies what either reading does."""
    both = (frozenset({"a"}), frozenset({"a"}))
    assert satisfiable(parse("a & !a"), [both])
    assert not satisfiable(parse("a & !a"), [(frozenset({"a"}), frozenset()), (frozenset(), frozenset({"a"}))])
    assert not satisfiable(parse("F a & G !a"), [(frozenset({"a"}), frozenset()), (frozenset(), frozenset({"a"}))])


def test_the_unsat_example_is_proved_by_its_geometry_and_a_touching_variant_is_not():
    from dataclasses import replace

    from plansynth.reach.fileformat import load_reach_problem
    from plansynth.reach.geometry import Box
    from plansynth.reach.mission.labels import label_abstraction

    p = load_reach_problem("examples/reach/mission-unsat.yaml")
    la = label_abstraction(p)
    letters = geometry_letters(la, p.mission_labels, margin=1e-5)
    assert letters is not None and not satisfiable(parse(p.mission), letters)
    # a vault that reaches the moat's edge: its boundary point is in the vault, not in the moat's interior
    q = replace(p, labels=(("moat", Box((4, 4), (8, 8))), ("vault", Box((5, 5), (8, 7)))))
    lq = label_abstraction(q)
    assert satisfiable(parse(q.mission), geometry_letters(lq, q.mission_labels, margin=1e-5))


@settings(max_examples=40, deadline=None)
@given(
    formulas(depth=3),
    st.integers(0, 10**6),
    st.lists(
        st.tuples(st.integers(0, 7), st.integers(0, 7), st.integers(1, 3), st.integers(1, 3)),
        min_size=len(NAMES),
        max_size=len(NAMES),
    ),
)
def test_label_proof_gives_the_verdict_of_the_whole_letter_set(f, seed, rects):
    """label_proof decides on the regions' interior letters first (a subset of
    geometry_letters: satisfiable there is satisfiable over all of them) and only then
    on the boundary letters: its verdict is the whole letter set's, on random rooms
    whose integer labels often share edges and corners (so boundary letters matter)."""
    from dataclasses import replace

    from plansynth.reach.families import random_workspace
    from plansynth.reach.geometry import Box
    from plansynth.reach.mission.labels import label_abstraction
    from plansynth.reach.mission.proof import label_proof

    try:
        base = random_workspace(seed % 50, seed % 3, order=1, dt=1.0, input_bound=1.5, polygons=False)
    except RuntimeError:
        base = random_workspace(7, 1, order=1, dt=1.0, input_bound=1.5, polygons=False)
    labels = tuple((n, Box((x, y), (x + w, y + h))) for n, (x, y, w, h) in zip(NAMES, rects))
    p = replace(base, goal=None, labels=labels, mission=str(f), max_horizon=3)
    la = label_abstraction(p)
    ws = p.workspace
    letters = geometry_letters(la, p.mission_labels, margin=1e-5 * max(1.0, max(h - l for l, h in zip(ws.lo, ws.hi))))
    verdict, _ = label_proof(p, la)
    assert verdict is (None if letters is None else not satisfiable(f, letters))


def _ringed(thick: float, gap: float, side: int):
    """The ringed-label example with walls ``thick`` m thick around the hole [4, 6]^2 and,
    when ``gap`` > 0, a gap that wide in the middle of wall ``side`` (0..3)."""
    from dataclasses import replace

    from plansynth.reach.fileformat import load_reach_problem
    from plansynth.reach.geometry import Box

    p = load_reach_problem("examples/reach/mission-ringed.yaml")
    lo, hi = 4.0 - thick, 6.0 + thick
    walls = [  # overlapping at the corners (touching walls would leave a seam, a slit no region holds)
        ((lo, lo), (hi, 4.0)),  # south
        ((lo, 6.0), (hi, hi)),  # north
        ((lo, lo), (4.0, hi)),  # west
        ((6.0, lo), (hi, hi)),  # east
    ]
    boxes = []
    for k, (a, b) in enumerate(walls):
        if k == side and gap > 0:
            axis = 0 if k < 2 else 1  # the wall's long axis
            c0, c1 = 5.0 - gap / 2, 5.0 + gap / 2
            first_hi, second_lo = list(b), list(a)
            first_hi[axis], second_lo[axis] = c0, c1
            boxes += [Box(a, tuple(first_hi)), Box(tuple(second_lo), b)]
        else:
            boxes.append(Box(a, b))
    return replace(p, obstacles=tuple(boxes))


@settings(max_examples=12, deadline=None)
@given(
    st.floats(0.3, 2.0),  # (thinner walls: the exact oracle's refinement runs for minutes)
    st.sampled_from([0.0, 0.0, 0.3, 1.0]),
    st.integers(0, 3),
    st.sampled_from(["segment", "sample"]),
)
def test_a_label_no_trajectory_can_reach_is_refuted_only_when_no_trajectory_reaches_it(thick, gap, side, reading):
    """The reachable-letters proof (``steps``: regions whose closures meet in the segment
    reading, the one-step pairs in the sample reading) against an exact oracle: when it
    proves ``F vault`` infeasible, no trajectory of up to 10 steps ends in the vault
    (reach-avoid with the vault as goal: the exact segment-safe oracle, or the exact
    samples MILP), whatever the walls' thickness and gap."""
    from dataclasses import replace

    from reach_oracles import oracle_exact, oracle_feasible

    from plansynth.reach.lazy.bounds import step_adjacency, touching
    from plansynth.reach.mission.labels import label_abstraction, planning_problem
    from plansynth.reach.mission.proof import label_proof

    p = replace(_ringed(thick, gap, side), reading=reading)
    la = label_abstraction(p)
    ab = la.abstraction
    steps = touching(ab) if reading == "segment" else step_adjacency(planning_problem(p), ab)
    proved, why = label_proof(p, la, steps=steps)
    if gap == 0.0 and (reading == "segment" or thick > 1.5):  # closed, and too thick to jump
        assert proved is True and "regions a trajectory can reach" in why, why
    if proved is not True:
        return
    reach = replace(p, mission=None, labels=(), reading="segment", goal=p.mission_labels["vault"])
    for N in range(1, 11):
        if reading == "segment":
            assert oracle_exact(reach, N, seconds=30) is not True, N
        else:
            assert oracle_feasible(reach, N, segments=False, seconds=30) is not True, N
