"""The horizon lower bound of the mission planners (plansynth.reach.mission.horizon)
against brute force: on random small region graphs with random labels, start regions,
time windows and formulas, no walk of a smaller horizon (any stay or loop continuation)
has a word that satisfies the formula by the LTL evaluator; and both planners find the
same horizon with and without the bound."""

from __future__ import annotations

import itertools

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_ltl import NAMES, formulas

from plansynth.reach.lazy.displan import RegionGraph
from plansynth.reach.mission.horizon import horizon_lower_bound
from plansynth.reach.mission.ltl import Lasso, finite_word, holds, parse

MAX_L = 4


@st.composite
def region_graphs(draw):
    """A connected region graph of 2..4 regions (a random spanning tree plus some
    edges), labels per region, start regions and earliest steps."""
    n = draw(st.integers(2, 4))
    edges = {(draw(st.integers(0, i - 1)), i) for i in range(1, n)}
    for i, j in itertools.combinations(range(n), 2):
        if draw(st.booleans()) and draw(st.booleans()):
            edges.add((i, j))
    adj = tuple(tuple(sorted({j for a, j in edges if a == i} | {a for a, j in edges if j == i})) for i in range(n))
    starts = tuple(sorted(set(draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=2)))))
    labels = [frozenset(draw(st.sets(st.sampled_from(NAMES)))) for _ in range(n)]
    earliest = [0 if i in starts else draw(st.integers(0, 3)) for i in range(n)]
    return RegionGraph(n, adj, starts, tuple(range(n))), labels, earliest


def brute_force_min_horizon(graph, labels, earliest, f, max_l):
    """The smallest L <= max_l with a walk r_0..r_L (start region, stay or adjacent,
    r_t not before earliest) whose finite word, or lasso word (r_L = r_k), satisfies f."""
    for L in range(max_l + 1):

        def walks(prefix):
            t = len(prefix)
            if t == L + 1:
                yield prefix
                return
            cands = graph.start_regions if t == 0 else (prefix[-1], *graph.adjacency[prefix[-1]])
            for r in cands:
                if earliest[r] <= t:
                    yield from walks(prefix + (r,))

        for w in walks(()):
            ls = [labels[r] for r in w]
            if holds(f, finite_word(ls)):
                return L
            for k in range(L):
                if w[k] == w[L] and holds(f, Lasso(tuple(ls[:k]), tuple(ls[k:L]))):
                    return L
    return None


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(region_graphs(), formulas(depth=3), st.booleans())
def test_no_walk_below_the_bound_satisfies_the_formula(g, f, windows):
    graph, labels, earliest = g
    early = earliest if windows else None
    bound = horizon_lower_bound(graph, labels, f, early, MAX_L)
    best = brute_force_min_horizon(graph, labels, early or [0] * graph.n_regions, f, MAX_L)
    if best is not None:
        assert bound <= best, (bound, best)


def test_the_bound_is_tight_on_simple_missions_and_past_the_max_when_none_exists():
    """Non-vacuous: the bound is the brute-force horizon here, and max + 1 for a
    formula no word satisfies."""
    chain = RegionGraph(4, ((1,), (0, 2), (1, 3), (2,)), (0,), (0, 1, 2, 3))
    labels = [frozenset(), frozenset({"a"}), frozenset(), frozenset({"b"})]
    cases = {"F b": 3, "F (a & F b)": 3, "G F a": 1, "F G b": 3, "X X a": 1, "!a U b": None, "F a & G !a": None}
    for text, expected in cases.items():
        f = parse(text)
        assert brute_force_min_horizon(chain, labels, [0] * 4, f, MAX_L) == expected
        assert horizon_lower_bound(chain, labels, f, None, MAX_L) == (MAX_L + 1 if expected is None else expected), text
    # patrolling a and b needs the loop 1..3..1 (period 4) after the first step: the bound is 3, below it
    both = parse("G F b & G F a")
    assert brute_force_min_horizon(chain, labels, [0] * 4, both, 6) == 5
    assert horizon_lower_bound(chain, labels, both, None, 6) == 3
    assert horizon_lower_bound(chain, labels, parse("F a"), [0, 3, 0, 0], MAX_L) == 3  # a's region from step 3
