"""A proved lower bound on the horizon of a mission plan through the abstraction: the
horizon search of both mission planners starts there instead of at 0 (beyond the
papers; the product-graph view of LTL planning, Kloetzer and Belta, IEEE TAC 2008, and
of the tableau, Vardi and Wolper, LICS 1986).

DIS-PLAN (:mod:`plansynth.reach.mission.bmc`) plans a region walk r_0..r_L (each step
stays or moves to an adjacent region, region i not before ``earliest[i]``) whose word,
continued by staying in r_L or by a loop back to r_k = r_L, satisfies the mission. Its
word has an accepting run of the mission's tableau (:func:`~plansynth.reach.mission.proof.witness`'s
construction, read with exact letters: the labels region r lies in hold, the others
do not). So in the *product graph* of the region graph and the tableau, a state
(region, tableau node), the run's state at step L is

* reached in exactly L steps from (a start region, {mission}) through states that
  respect the time windows (region i not before step ``earliest[i]``), and
* *live within the regions the frontier has reached*: an accepting path (one that ends
  inside a strongly connected component where each eventuality is, on some edge, not
  carried on) leaves it through regions the frontier held at some step <= L only. The
  plan's word after step L repeats regions of the plan itself (it stays in r_L, or it
  runs the loop r_k..r_L again), each at a step <= L, and walks the region graph, so
  the run's continuation is such a path.

:func:`horizon_lower_bound` is the first step at which the time-expanded breadth-first
frontier holds a live state: no plan of a smaller horizon exists (at the level of
DIS-PLAN, before any CON-PLAN conflict), so refuting those horizons one at a time, SAT
call by SAT call (or MILP by MILP), is work whose answer is known. It uses neither the
dynamics nor the loop closure, so it is a bound, not the answer; the planners still
search upwards from it, and the plan found is still the one of the shortest horizon.

>>> from plansynth.reach.lazy.displan import RegionGraph
>>> from plansynth.reach.mission.ltl import parse
>>> g = RegionGraph(3, ((1,), (0, 2), (1,)), start_regions=(0,), goal_regions=(0, 1, 2))
>>> labels = [frozenset(), frozenset(), frozenset({"a"})]
>>> horizon_lower_bound(g, labels, parse("F a"), None, 10)   # a is two regions away
2
>>> horizon_lower_bound(g, labels, parse("G F a"), None, 10)  # the loop must hold a: after it
2
>>> horizon_lower_bound(g, labels, parse("F a"), [0, 0, 5], 10)  # a's region not before step 5
5
>>> horizon_lower_bound(g, labels, parse("G !a & F a"), None, 10)  # no word at all: past the max
11
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence

from plansynth.budget import BudgetExhausted, Clock
from plansynth.reach.lazy.displan import RegionGraph
from plansynth.reach.mission.ltl import Formula, nnf, props, unroll
from plansynth.reach.mission.proof import MAX_NODES, TooLarge, _components, _expand

__all__ = ["horizon_lower_bound", "timed_horizon_bound", "product_graph", "live_states", "region_letters"]

State = tuple[int, frozenset]  # (region, tableau node)


def region_letters(labels_of, names: frozenset[str]) -> list[tuple[frozenset[str], frozenset[str]]]:
    """Per region, (the labels that hold, those whose negation holds), restricted to
    ``names``: from a :class:`~plansynth.reach.mission.labels.LabelledAbstraction`'s
    letters, from such pairs, or from plain label sets (every other label's negation
    holds)."""
    letters = getattr(labels_of, "letters", labels_of)
    out = []
    for x in letters:
        if isinstance(x, tuple):
            out.append((frozenset(x[0]) & names, frozenset(x[1]) & names))
        else:
            out.append((frozenset(x) & names, names - frozenset(x)))
    return out


def product_graph(
    graph: RegionGraph, labels_of, formula: Formula, *, max_nodes: int = MAX_NODES
) -> tuple[dict[State, list[tuple[State, frozenset]]], set[State]]:
    """The product of the region graph and the mission's tableau, from the start
    regions: ``edges[s]``, the successors of state s as (state, eventualities carried
    on), and the states where a finite word may end (an expansion that carries no
    strong obligation). ``labels_of``: see :func:`region_letters`. Raises
    :class:`~plansynth.reach.mission.proof.TooLarge` past ``max_nodes`` states."""
    f = unroll(nnf(formula))
    names = props(f)
    letters = region_letters(labels_of, names)
    expand_cache: dict[tuple[frozenset, tuple], list[tuple[frozenset, frozenset, bool]]] = {}
    edges: dict[State, list[tuple[State, frozenset]]] = {}
    final: set[State] = set()
    todo = [(r, frozenset({f})) for r in graph.start_regions]
    while todo:
        s = todo.pop()
        if s in edges:
            continue
        if len(edges) >= max_nodes:
            raise TooLarge(f"more than {max_nodes} product states")
        r, node = s
        key = (node, letters[r])  # regions with the same letter expand alike
        if key not in expand_cache:
            expand_cache[key] = _expand(node, letters[r])
        out = [((r2, nxt), pend) for nxt, pend, _ in expand_cache[key] for r2 in (r, *graph.adjacency[r])]
        if any(not strong for _, _, strong in expand_cache[key]):
            final.add(s)
        edges[s] = out
        todo += [v for v, _ in out if v not in edges]
    return edges, final


def live_states(
    edges: dict[State, list[tuple[State, frozenset]]], allowed: frozenset[int], eventualities: frozenset | None = None
) -> set[State]:
    """The states of the product restricted to the regions ``allowed`` from which an
    accepting path (inside ``allowed``) leaves: those that reach a strongly connected
    component with an inner edge that does not carry each eventuality on (the generalized
    Büchi condition of :func:`~plansynth.reach.mission.proof.witness`).
    ``eventualities``: :func:`eventualities` of ``edges``, if the caller has it."""
    sub = {s: [(v, p) for v, p in es if v[0] in allowed] for s, es in edges.items() if s[0] in allowed}
    if eventualities is None:
        eventualities = _eventualities(edges)
    good: set[State] = set()
    for comp in _components({s: [(v, p, 0) for v, p in es] for s, es in sub.items()}):
        inner = [p for s in comp for v, p in sub[s] if v in comp]
        if inner and all(any(g not in p for p in inner) for g in eventualities):
            good |= comp
    back: dict[State, list[State]] = {}
    for s, es in sub.items():
        for v, _ in es:
            back.setdefault(v, []).append(s)
    live = set(good)
    queue = deque(good)
    while queue:
        v = queue.popleft()
        for u in back.get(v, ()):
            if u not in live:
                live.add(u)
                queue.append(u)
    return live


def _eventualities(edges: dict[State, list[tuple[State, frozenset]]]) -> frozenset:
    """Every until (finally) formula some edge of the product carries on (hashing the
    formulas of every edge is most of a :func:`live_states` call: once per graph)."""
    return frozenset(g for pend in {pend for es in edges.values() for _, pend in es} for g in pend)


def horizon_lower_bound(
    graph: RegionGraph,
    labels_of,
    formula: Formula,
    earliest: Sequence[float] | None,
    max_horizon: int,
    *,
    max_nodes: int = MAX_NODES,
    clock: Clock | None = None,
    end: str = "rest",
) -> int:
    """The smallest horizon L <= ``max_horizon`` at which DIS-PLAN may have a plan (see
    the module doc), ``max_horizon + 1`` when none has one, 0 when the product graph
    is past ``max_nodes`` states or the ``clock`` runs out (no bound: 0 is always one).
    ``labels_of``: see :func:`region_letters`; ``end``: with a free end a plan's word
    may also end at L, in a state where no strong obligation is left."""
    try:
        if clock is None:
            edges, final = product_graph(graph, labels_of, formula, max_nodes=max_nodes)
        else:
            with clock.phase("the product graph of the horizon bound"):
                edges, final = product_graph(graph, labels_of, formula, max_nodes=max_nodes)
    except (TooLarge, BudgetExhausted):
        return 0
    early = list(earliest) if earliest is not None else [0] * graph.n_regions
    evs = _eventualities(edges)
    f = unroll(nnf(formula))
    frontier = {(r, frozenset({f})) for r in graph.start_regions if early[r] <= 0}
    live: dict[frozenset[int], set[State]] = {}
    seen: set[int] = set()  # the regions a plan may visit at steps 0..t
    for t in range(max_horizon + 1):
        if clock is not None and clock.exhausted():
            return 0
        if not frontier:
            return max_horizon + 1
        seen |= {r for r, _ in frontier}
        allowed = frozenset(seen)
        if allowed not in live:
            live[allowed] = live_states(edges, allowed, evs)
        if frontier & live[allowed] or (end == "free" and frontier & final):
            return t
        frontier = {v for s in frontier for v, _ in edges[s] if early[v[0]] <= t + 1}
    return max_horizon + 1


def timed_horizon_bound(
    graph: RegionGraph,
    labels_of,
    formula: Formula,
    earliest: Sequence[float] | None,
    max_horizon: int,
    timings: dict,
    counters: dict,
    clock: Clock | None = None,
    *,
    end: str = "rest",
) -> int:
    """:func:`horizon_lower_bound` as both mission planners run it: its time goes to
    ``timings["horizon_bound"]``, the bound to ``counters["horizon_bound"]``."""
    import time

    t0 = time.perf_counter()
    bound = horizon_lower_bound(graph, labels_of, formula, earliest, max_horizon, clock=clock, end=end)
    timings["horizon_bound"] = time.perf_counter() - t0
    counters["horizon_bound"] = bound
    return bound
