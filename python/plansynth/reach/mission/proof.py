"""Proofs that a mission is infeasible for every trajectory, whatever the horizon.

The lazy loop (and the MILP baseline) refute horizons for plans *through the
label-refined decomposition*, one region per step; a real trajectory may cross several
regions in one step, so "every horizon up to L refuted" is no proof (the reach-avoid
planner's treatment, :mod:`plansynth.reach.lazy.loop`). What is proved here holds for
every trajectory of the problem: **no infinite word over the letters the labels'
geometry allows satisfies the mission.**

*Letters* (:func:`geometry_letters`). The independent checker
(:mod:`plansynth.reach.mission.check`) reads, at each step, the literals that *may*
hold there: ``a`` when the sample (segment) lies in the closed label a, ``!a`` when it
avoids a's interior. Every free position lies in the closure of a region of an exact
decomposition, and a region lies inside or outside each label; so the letter of any
sample or segment is contained in the letter of its first point, which is one of its
region's letters: ``a`` for the labels the region lies in, ``!a`` for the others, and,
at a point where the boundaries of a set B of labels meet, both literals of each label
of B (a point on a boundary may read either way). The mission in negation
normal form is monotone in the letters, so if no word over these letters satisfies it,
no trajectory's word does (finite plans are read as words that repeat their last letter,
lassos as lassos: both are infinite words).

*Satisfiability over an alphabet* (:func:`satisfiable`): the tableau construction of
LTL (Wolper, "Temporal logic can be more expressive", 1983; Vardi and Wolper, LICS
1986) with one-sided obligations: a node is the set of formulas a position must
satisfy; reading a letter, each obligation is expanded (``a U b``: b now, or a now and
``a U b`` next; ``a R b``: b now, and a now or ``a R b`` next; ``X a``: a next) and the
formulas carried to the next position form the successor node. An infinite word
satisfies the mission iff a run from ``{mission}`` reaches a cycle in which every
until (``F``) formula is, on some edge, not carried on (its eventuality met): a
generalized Büchi condition, checked per strongly connected component. Exponential in
the number of temporal subformulas; :data:`MAX_NODES` bounds the work (beyond it: no
proof, never a wrong one).

>>> from plansynth.reach.mission.ltl import parse
>>> inside = (frozenset({"moat", "vault"}), frozenset())  # letters: (may hold, negation may hold)
>>> moat = (frozenset({"moat"}), frozenset({"vault"}))
>>> out = (frozenset(), frozenset({"moat", "vault"}))
>>> satisfiable(parse("F vault & G !moat"), [inside, moat, out])
False
>>> satisfiable(parse("G F moat & G F !moat"), [moat, out])
True
"""

from __future__ import annotations

from collections.abc import Iterable

from plansynth.reach.mission.ltl import (
    And,
    Const,
    Finally,
    Formula,
    Globally,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
    nnf,
)

__all__ = [
    "satisfiable",
    "witness",
    "geometry_letters",
    "TooLarge",
    "MAX_NODES",
    "label_proof",
    "timed_label_proof",
    "NOT_A_PROOF",
]

#: What a refutation through the label-refined decomposition is not (DIS-PLAN moves one
#: region per step, a real step may cross several): only :func:`label_proof` is a proof.
NOT_A_PROOF = "not a proof of infeasibility (a step may cross several regions)"

Letter = tuple[frozenset[str], frozenset[str]]  # (labels that may hold, labels whose negation may hold)

MAX_NODES = 20_000  # tableau nodes explored before giving up (no proof)


class TooLarge(Exception):
    """The tableau outgrew :data:`MAX_NODES`: satisfiability is not decided."""


def _expand(obligations: frozenset[Formula], letter: Letter) -> list[tuple[frozenset[Formula], frozenset[Formula]]]:
    """Every way to meet ``obligations`` at a position reading ``letter``: pairs
    (formulas carried to the next position, until/finally formulas carried on)."""
    pos, neg = letter
    out: list[tuple[frozenset[Formula], frozenset[Formula]]] = []

    def go(todo: list[Formula], done: frozenset[Formula], nxt: frozenset[Formula], pending: frozenset[Formula]) -> None:
        # ``done``: formulas already met at this position (each is expanded once: a second
        # copy could only carry an eventuality the first one meets)
        while todo and todo[0] in done:
            todo = todo[1:]
        if not todo:
            out.append((nxt, pending))
            return
        f, rest = todo[0], todo[1:]
        done = done | {f}
        if isinstance(f, Const):
            if f.value:
                go(rest, done, nxt, pending)
        elif isinstance(f, Prop):
            if f.name in pos:
                go(rest, done, nxt, pending)
        elif isinstance(f, Not):
            if f.arg.name in neg:  # negation normal form: the argument is a label
                go(rest, done, nxt, pending)
        elif isinstance(f, And):
            go([f.left, f.right] + rest, done, nxt, pending)
        elif isinstance(f, Or):
            go([f.left] + rest, done, nxt, pending)
            go([f.right] + rest, done, nxt, pending)
        elif isinstance(f, Next):
            go(rest, done, nxt | {f.arg}, pending)
        elif isinstance(f, Finally):
            go([f.arg] + rest, done, nxt, pending)
            go(rest, done, nxt | {f}, pending | {f})
        elif isinstance(f, Until):
            go([f.right] + rest, done, nxt, pending)
            go([f.left] + rest, done, nxt | {f}, pending | {f})
        elif isinstance(f, Globally):
            go([f.arg] + rest, done, nxt | {f}, pending)
        elif isinstance(f, Release):
            go([f.right, f.left] + rest, done, nxt, pending)
            go([f.right] + rest, done, nxt | {f}, pending)
        else:  # pragma: no cover - nnf() leaves no other node
            raise TypeError(f"not in negation normal form: {f!r}")

    go(sorted(obligations, key=repr), frozenset(), frozenset(), frozenset())
    return out


def satisfiable(formula: Formula, letters: Iterable[Letter], *, max_nodes: int = MAX_NODES) -> bool:
    """Is there an infinite word over ``letters`` (pairs: the labels that may hold, the
    labels whose negation may hold) satisfying ``formula`` (read with every literal as
    "may hold")? Raises :class:`TooLarge` past ``max_nodes`` tableau nodes."""
    return witness(formula, letters, max_nodes=max_nodes) is not None


def witness(
    formula: Formula, letters: Iterable[Letter], *, max_nodes: int = MAX_NODES
) -> tuple[list[int], list[int]] | None:
    """A lasso satisfying ``formula`` as (prefix, loop) of indices into ``letters``, or
    None when no infinite word over them does (see :func:`satisfiable`)."""
    f = nnf(formula)
    alphabet = [(frozenset(p), frozenset(n)) for p, n in letters]
    distinct = list(dict.fromkeys((frozenset(p), frozenset(n)) for p, n in alphabet))
    first = {a: alphabet.index(a) for a in distinct}
    start = frozenset({f})
    Edge = tuple[frozenset[Formula], frozenset[Formula], int]
    edges: dict[frozenset[Formula], list[Edge]] = {}
    stack = [start]
    while stack:
        node = stack.pop()
        if node in edges:
            continue
        if len(edges) >= max_nodes:
            raise TooLarge(f"more than {max_nodes} tableau nodes")
        succ: dict[tuple[frozenset[Formula], frozenset[Formula]], int] = {}
        for a in distinct:
            for e in _expand(node, a):
                succ.setdefault(e, first.get(a, 0))
        edges[node] = [(v, pend, k) for (v, pend), k in succ.items()]
        stack += [v for v, _, _ in edges[node] if v not in edges]
    eventualities = {g for node in edges for _, pend, _ in edges[node] for g in pend}
    for comp in _components(edges):
        inner = [(u, e) for u in comp for e in edges[u] if e[0] in comp]
        if not inner:
            continue  # a single node without a self-loop: no cycle
        accepting = []
        for g in sorted(eventualities, key=repr):
            hit = next((ue for ue in inner if g not in ue[1][1]), None)
            if hit is None:
                break
            accepting.append(hit)
        else:
            entry = next(iter(sorted(comp, key=lambda n: sorted(map(repr, n)))))
            prefix = _path(edges, start, entry, None)
            loop: list[int] = []
            here = entry
            for u, (v, _, k) in accepting or [inner[0]]:
                loop += _path(edges, here, u, comp) + [k]
                here = v
            loop += _path(edges, here, entry, comp)
            assert prefix is not None and loop
            return prefix, loop
    return None


def _path(edges, src, dst, within) -> list[int]:
    """The letters of a shortest path src -> dst (inside ``within`` when given)."""
    from collections import deque

    back = {src: None}
    todo = deque([src])
    while todo:
        u = todo.popleft()
        if u == dst:
            break
        for v, _, k in edges[u]:
            if v not in back and (within is None or v in within):
                back[v] = (u, k)
                todo.append(v)
    out: list[int] = []
    u = dst
    while back[u] is not None:
        u, k = back[u]
        out.append(k)
    return out[::-1]


def _components(edges: dict) -> list[set[frozenset[Formula]]]:
    """Strongly connected components (Tarjan's algorithm, iterative)."""
    index: dict = {}
    low: dict = {}
    on: set = set()
    st: list = []
    comps: list[set] = []
    counter = 0
    for root in edges:
        if root in index:
            continue
        work = [(root, iter([e[0] for e in edges[root]]))]
        index[root] = low[root] = counter
        counter += 1
        st.append(root)
        on.add(root)
        while work:
            u, it = work[-1]
            advanced = False
            for v in it:
                if v not in index:
                    index[v] = low[v] = counter
                    counter += 1
                    st.append(v)
                    on.add(v)
                    work.append((v, iter([e[0] for e in edges[v]])))
                    advanced = True
                    break
                if v in on:
                    low[u] = min(low[u], index[v])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[u])
            if low[u] == index[u]:
                comp = set()
                while True:
                    w = st.pop()
                    on.discard(w)
                    comp.add(w)
                    if w == u:
                        break
                comps.append(comp)
    return comps


def geometry_letters(labelled, shapes: dict, *, margin: float) -> list[Letter] | None:
    """Every letter a point of the free space may read (see the module doc), from the
    label-refined decomposition ``labelled``
    (:class:`~plansynth.reach.mission.labels.LabelledAbstraction`): in region r, away
    from label boundaries, ``a`` for the labels r lies in and ``!a`` for the others;
    where the boundaries of a set B of labels meet (within ``margin``) in r's closure,
    both literals of each label of B. None when the decomposition does not cover the
    free space exactly (then the letters prove nothing)."""
    import shapely
    from shapely.geometry import Polygon as ShPolygon

    from plansynth.reach.geometry import Box

    ab = labelled.abstraction
    if not ab.exact or not ab.regions:
        return None
    near_boundary = {}
    for name in labelled.names:
        s = shapes[name]
        g = shapely.box(s.lo[0], s.lo[1], s.hi[0], s.hi[1]) if isinstance(s, Box) else ShPolygon(s.vertices)
        near_boundary[name] = g.boundary.buffer(margin)
    out: list[Letter] = []
    for reg, inside in zip(ab.regions, labelled.labels_of):
        area = ShPolygon(reg.vertices).buffer(margin)
        pos, neg = frozenset(inside), frozenset(labelled.names) - frozenset(inside)
        out.append((pos, neg))
        close = [n for n in labelled.names if near_boundary[n].intersects(area)]
        # the sets of labels whose boundaries meet at one point near the region (grown one
        # label at a time: a set meets only if its subsets do)
        level = [(frozenset(), area)]
        while level:
            nxt = []
            for B, where in level:
                for n in close:
                    if B and n <= max(B):
                        continue
                    meet = where.intersection(near_boundary[n])
                    if not meet.is_empty:
                        nxt.append((B | {n}, meet))
                        out.append((pos | B | {n}, neg | B | {n}))
            level = nxt
    return list(dict.fromkeys(out))


def label_proof(problem, labelled) -> tuple[bool | None, str]:
    """``(True, why)`` when no trajectory of ``problem`` satisfies its mission, at any
    horizon (no word over :func:`geometry_letters` satisfies it); ``(False, why)`` when
    some word over the letters does (the geometry alone proves nothing); ``(None, why)``
    when undecided (a decomposition that does not cover the free space, or a tableau
    past :data:`MAX_NODES`)."""
    from plansynth.reach.mission.ltl import parse

    ws = problem.workspace
    margin = 1e-5 * max(1.0, max(h - l for l, h in zip(ws.lo, ws.hi)))
    ab = labelled.abstraction
    if not ab.exact or not ab.regions:
        return None, "the decomposition does not cover the free space exactly"
    mission = parse(problem.mission)
    # the regions' own letters first, without the boundary letters (the shapely
    # buffers and intersections of geometry_letters, most of its time): they are a
    # subset of the letters, so a word over them is a word over the letters, and the
    # mission, satisfiable over the subset, is over the whole set (the same verdict)
    names = frozenset(labelled.names)
    interior = list(dict.fromkeys((frozenset(s), names - frozenset(s)) for s in labelled.labels_of))
    try:
        if satisfiable(mission, interior):
            return False, (
                f"some word over the {len(interior)} letters of the regions' interiors (a subset of the "
                "labels' geometry's letters) satisfies the mission"
            )
    except TooLarge:
        pass  # decided on the whole set below
    letters = geometry_letters(labelled, problem.mission_labels, margin=margin)
    if letters is None:
        return None, "the decomposition does not cover the free space exactly"
    try:
        if satisfiable(mission, letters):
            return False, f"some word over the {len(letters)} letters of the labels' geometry satisfies the mission"
    except TooLarge as exc:
        return None, f"the LTL tableau is too large ({exc})"
    return True, (
        f"no word over the {len(letters)} letters the labels' geometry allows satisfies the mission "
        "(LTL tableau), so no trajectory does, at any horizon"
    )


def timed_label_proof(problem, labelled, timings: dict, counters: dict) -> tuple[bool | None, str]:
    """:func:`label_proof` as both mission planners run it first: its time goes to
    ``timings["proof"]``, its verdict to ``counters["label_proof"]``."""
    import time

    t0 = time.perf_counter()
    proved, why = label_proof(problem, labelled)
    timings["proof"] = time.perf_counter() - t0
    counters["label_proof"] = proved
    return proved, why
