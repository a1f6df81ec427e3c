"""Proofs that a mission is infeasible for every trajectory, whatever the horizon.

The lazy loop (and the MILP baseline) refute horizons for plans *through the
label-refined decomposition*, one region per step; a real trajectory may cross several
regions in one step, so "every horizon up to L refuted" is no proof (the reach-avoid
planner's treatment, :mod:`plansynth.reach.lazy.loop`). What is proved here holds for
every trajectory of the problem: **no infinite word over the letters the labels'
geometry allows satisfies the mission.**

*Letters* (:func:`geometry_letters`). The independent checker
(:mod:`plansynth.reach.mission.check`) reads, at each step, the literals that hold
there: ``a`` when the sample (segment) lies in label a at depth >= a's margin, ``!a`` when
it lies outside at distance >= the margin; with margin 0, a point on a's boundary may be
read as in or as out, one of the two per step. Every free position lies in the closure
of a region of an exact decomposition, and a region lies inside, outside or in the band
of each label; so the letter of any sample or segment is contained in one of the letters
of the points of its region's closure: the region's own (``a`` for the labels it holds,
``!a`` for those whose negation it holds) and, where the cuts of a set B of labels meet,
the region's letter with each label of B read the way that point allows (either way on a
label's own edge, ``a`` added on the edge of its shrunk shape, ``!a`` on that of its grown
shape). The mission in negation normal form is monotone in the letters, so if no word over
these letters satisfies it, no trajectory's word does (finite plans ending at rest are
read as words that repeat their last letter, lassos as lassos: both are infinite words;
with a free end, finite words are tried too).

*Reachable letters* (``steps``, beyond the papers). A trajectory moves between regions
one step can connect: in the segment reading along a path through the free space, so
between regions whose closures meet (:func:`~plansynth.reach.lazy.bounds.touching`); in
the sample reading between regions one step's displacement can connect
(:func:`~plansynth.reach.lazy.bounds.step_adjacency`); both over-approximations. So
every position of a trajectory lies in a region reachable from a start region over that
relation, and only those regions' letters (with their boundaries') need be read: a label
behind walls no step can cross gives no letter, and ``F label`` is refuted at every
horizon.

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

from collections.abc import Iterable, Sequence

from plansynth.budget import checkpoint
from plansynth.reach.lazy.regiongraph import reachable
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
    WeakNext,
    nnf,
    unroll,
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
    "MAX_LETTERS",
]

#: What a refutation through the label-refined decomposition is not (DIS-PLAN moves one
#: region per step, a real step may cross several): only :func:`label_proof` is a proof.
NOT_A_PROOF = "not a proof of infeasibility (a step may cross several regions)"

Letter = tuple[frozenset[str], frozenset[str]]  # (labels that may hold, labels whose negation may hold)

MAX_NODES = 20_000  # tableau nodes explored before giving up (no proof)


class TooLarge(Exception):
    """The tableau outgrew :data:`MAX_NODES`: satisfiability is not decided."""


def _expand(
    obligations: frozenset[Formula], letter: Letter
) -> list[tuple[frozenset[Formula], frozenset[Formula], bool]]:
    """Every way to meet ``obligations`` (negation normal form, bounded operators
    unrolled) at a position reading ``letter``: triples (formulas carried to the next
    position, until/finally formulas carried on, whether a *strong* obligation is
    carried: an ``X``, ``F`` or ``U`` that a finite word's last position cannot meet).
    Iterative: the deterministic parts in one loop, a branch copied only at ``|``, ``F``,
    ``U``, ``R``."""
    pos, neg = letter
    out: dict[tuple[frozenset[Formula], frozenset[Formula]], bool] = {}
    work: list[tuple[list[Formula], set, set, set, bool]] = [(list(obligations), set(), set(), set(), False)]
    steps = 0
    while work:
        todo, done, nxt, pending, strong = work.pop()
        ok = True
        while todo:
            steps += 1
            if steps % 256 == 0:
                checkpoint()  # one node of a deep formula may expand in many ways
            f = todo.pop()
            if f in done:  # each is met once: a second copy could only carry what the first meets
                continue
            done.add(f)
            if isinstance(f, Const):
                ok = f.value
            elif isinstance(f, Prop):
                ok = f.name in pos
            elif isinstance(f, Not):
                ok = f.arg.name in neg  # negation normal form: the argument is a label
            elif isinstance(f, And):
                todo += [f.right, f.left]
            elif isinstance(f, Or):
                work.append((todo + [f.right], set(done), set(nxt), set(pending), strong))
                todo.append(f.left)
            elif isinstance(f, Next):
                nxt.add(f.arg)
                strong = True
            elif isinstance(f, WeakNext):
                nxt.add(f.arg)
            elif isinstance(f, Finally):
                work.append((list(todo), set(done), nxt | {f}, pending | {f}, True))
                todo.append(f.arg)
            elif isinstance(f, Until):
                work.append((todo + [f.left], set(done), nxt | {f}, pending | {f}, True))
                todo.append(f.right)
            elif isinstance(f, Globally):
                todo.append(f.arg)
                nxt.add(f)
            elif isinstance(f, Release):
                work.append((todo + [f.right], set(done), nxt | {f}, set(pending), strong))
                todo += [f.left, f.right]
            else:  # pragma: no cover - nnf() and unroll() leave no other node
                raise TypeError(f"not in negation normal form: {type(f).__name__}")
            if not ok:
                break
        if ok:
            key = (frozenset(nxt), frozenset(pending))
            out[key] = out.get(key, True) and strong
    return [(v, p, st) for (v, p), st in out.items()]


def satisfiable(
    formula: Formula, letters: Iterable[Letter], *, max_nodes: int = MAX_NODES, finite: bool = False
) -> bool:
    """Is there an infinite word over ``letters`` (pairs: the labels that may hold, the
    labels whose negation may hold) satisfying ``formula`` (read with every literal as
    "may hold"), or, with ``finite``, a finite one (LTL on finite traces)? Raises
    :class:`TooLarge` past ``max_nodes`` tableau nodes."""
    return witness(formula, letters, max_nodes=max_nodes, finite=finite) is not None


def witness(
    formula: Formula, letters: Iterable[Letter], *, max_nodes: int = MAX_NODES, finite: bool = False
) -> tuple[list[int], list[int]] | None:
    """A lasso satisfying ``formula`` as (prefix, loop) of indices into ``letters``, or
    None when no infinite word over them does (see :func:`satisfiable`); with ``finite``
    also a finite word, returned as (the word, []), when no lasso satisfies it."""
    f = unroll(nnf(formula))
    alphabet = [(frozenset(p), frozenset(n)) for p, n in letters]
    distinct = list(dict.fromkeys((frozenset(p), frozenset(n)) for p, n in alphabet))
    first = {a: alphabet.index(a) for a in distinct}
    start = frozenset({f})
    Edge = tuple[frozenset[Formula], frozenset[Formula], int]
    edges: dict[frozenset[Formula], list[Edge]] = {}
    final: dict[frozenset[Formula], int] = {}  # nodes a finite word may end in, with the last letter
    stack = [start]
    while stack:
        node = stack.pop()
        if node in edges:
            continue
        if len(edges) >= max_nodes:
            raise TooLarge(f"more than {max_nodes} tableau nodes")
        checkpoint()
        succ: dict[tuple[frozenset[Formula], frozenset[Formula]], int] = {}
        for a in distinct:
            for nxt, pend, strong in _expand(node, a):
                succ.setdefault((nxt, pend), first.get(a, 0))
                if not strong:
                    final.setdefault(node, first.get(a, 0))
        edges[node] = [(v, pend, k) for (v, pend), k in succ.items()]
        stack += [v for v, _, _ in edges[node] if v not in edges]
    eventualities = {g for node in edges for _, pend, _ in edges[node] for g in pend}
    for comp in _components(edges):
        inner = [(u, e) for u in comp for e in edges[u] if e[0] in comp]
        if not inner:
            continue  # a single node without a self-loop: no cycle
        accepting = []
        for g in sorted(eventualities, key=lambda x: x.order):
            hit = next((ue for ue in inner if g not in ue[1][1]), None)
            if hit is None:
                break
            accepting.append(hit)
        else:
            entry = min(comp, key=lambda n: sorted(x.order for x in n))
            prefix = _path(edges, start, entry, None)
            loop: list[int] = []
            here = entry
            for u, (v, _, k) in accepting or [inner[0]]:
                loop += _path(edges, here, u, comp) + [k]
                here = v
            loop += _path(edges, here, entry, comp)
            assert prefix is not None and loop
            return prefix, loop
    if finite and final:
        node = min(final, key=lambda n: len(_path(edges, start, n, None)))
        return _path(edges, start, node, None) + [final[node]], []
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


#: Most letters :func:`geometry_letters` builds before it gives up (no proof).
MAX_LETTERS = 20_000


def geometry_letters(
    labelled,
    shapes: dict,
    *,
    margin: float,
    margins: dict[str, float] | None = None,
    within: Sequence[bool] | None = None,
) -> list[Letter] | None:
    """Every letter a point of the free space may read (see the module doc), from the
    label-refined decomposition ``labelled``
    (:class:`~plansynth.reach.mission.labels.LabelledAbstraction`): in region r, away
    from the cuts, its letter (``labels_of``, ``negs_of``); where the cuts of a set B of
    labels meet (within ``margin``) in r's closure, the letters a point there reads: a
    label's own edge (margin 0) is read as in or as out, one of the two (a touch, as
    the checker reads it); the edge of its shrunk shape (margin > 0) adds ``a``, that of
    its grown shape ``!a`` (closed sets). ``margins``: each label's margin (default 0).
    None when the decomposition does not cover the free space exactly (then the letters
    prove nothing) or past :data:`MAX_LETTERS`. ``within``: only the regions marked
    (the reachable ones, see the module docstring)."""
    import shapely

    from plansynth.reach.geometry import shape_to_shapely
    from plansynth.reach.offsets import grown, shrunk

    ab = labelled.abstraction
    if not ab.exact or not ab.regions:
        return None
    margins = margins or {}
    cuts: list[tuple[str, str, object]] = []  # (label, kind, the cut's edges grown by margin)
    for name in labelled.names:
        r = margins.get(name, 0.0)
        kinds = (
            [("edge", shapes[name])] if r <= 0 else [("in", shrunk(shapes[name], r)), ("out", grown(shapes[name], r))]
        )
        for kind, shape in kinds:
            if shape is not None:
                cuts.append((name, kind, shape_to_shapely(shape).boundary.buffer(margin)))
    out: list[Letter] = []
    for k, (reg, pos, neg) in enumerate(zip(ab.regions, labelled.labels_of, labelled.negs_of)):
        checkpoint()
        if within is not None and not within[k]:
            continue
        area = shapely.Polygon(reg.vertices).buffer(margin)
        out.append((frozenset(pos), frozenset(neg)))
        close = [k for k, c in enumerate(cuts) if c[2].intersects(area)]
        # the sets of cuts that meet at one point near the region (grown one cut at a
        # time: a set meets only if its subsets do)
        level = [((), area)]
        while level:
            nxt = []
            for B, where in level:
                for k in close:
                    if B and k <= B[-1]:
                        continue
                    meet = where.intersection(cuts[k][2])
                    if not meet.is_empty:
                        nxt.append((B + (k,), meet))
                        out += _boundary_letters(pos, neg, [cuts[j][:2] for j in B + (k,)])
                if len(out) > MAX_LETTERS:
                    return None
            level = nxt
    return list(dict.fromkeys(out))


def _boundary_letters(pos, neg, cuts: list[tuple[str, str]]) -> list[Letter]:
    """The letters of a point on these cuts in the closure of a region (pos, neg)."""
    p, n = set(pos), set(neg)
    edges = []
    for name, kind in cuts:
        if kind == "in":
            p.add(name)
        elif kind == "out":
            n.add(name)
        else:
            edges.append(name)
    out = []
    for bits in range(1 << len(edges)):
        pp, nn = set(p), set(n)
        for k, name in enumerate(edges):
            if bits >> k & 1:
                pp.add(name)
                nn.discard(name)
            else:
                nn.add(name)
                pp.discard(name)
        out.append((frozenset(pp), frozenset(nn)))
    return out


def label_proof(problem, labelled, *, steps: Sequence[Sequence[int]] | None = None) -> tuple[bool | None, str]:
    """``(True, why)`` when no trajectory of ``problem`` satisfies its mission, at any
    horizon (no word over :func:`geometry_letters` satisfies it: no infinite word, nor,
    with a free end, a finite one); ``(False, why)`` when some word over the letters does
    (the geometry alone proves nothing); ``(None, why)`` when undecided (a decomposition
    that does not cover the free space, or a tableau past :data:`MAX_NODES`). ``steps``
    (region -> the regions one step of a trajectory can reach, an over-approximation):
    only the letters of the regions reachable from the start over it are read (the
    module docstring); without it, every region's."""
    from plansynth.reach.mission.ltl import parse

    ws = problem.workspace
    margin = 1e-5 * max(1.0, max(h - l for l, h in zip(ws.lo, ws.hi)))
    ab = labelled.abstraction
    if not ab.exact or not ab.regions:
        return None, "the decomposition does not cover the free space exactly"
    mission = parse(problem.mission)
    finite = problem.end == "free"
    # the regions' own letters first, without the boundary letters (the shapely
    # buffers and intersections of geometry_letters, most of its time): they are a
    # subset of the letters, so a word over them is a word over the letters, and the
    # mission, satisfiable over the subset, is over the whole set (the same verdict)
    within = None if steps is None or not ab.start_regions else reachable(ab.start_regions, steps)
    interior = list(dict.fromkeys(x for k, x in enumerate(labelled.letters) if within is None or within[k]))
    try:
        if satisfiable(mission, interior, finite=finite):
            return False, (
                f"some word over the {len(interior)} letters of the regions' interiors (a subset of the "
                "labels' geometry's letters) satisfies the mission"
            )
    except TooLarge:
        pass  # decided on the whole set below
    margins = {n: problem.label_margin(n) for n in labelled.names}
    letters = geometry_letters(labelled, problem.mission_labels, margin=margin, margins=margins, within=within)
    if letters is None:
        return None, "the decomposition does not cover the free space exactly, or its letters are too many"
    try:
        if satisfiable(mission, letters, finite=finite):
            return False, f"some word over the {len(letters)} letters of the labels' geometry satisfies the mission"
    except TooLarge as exc:
        return None, f"the LTL tableau is too large ({exc})"
    reach = "" if within is None or all(within) else f" in the {sum(within)} regions a trajectory can reach"
    return True, (
        f"no word over the {len(letters)} letters the labels' geometry allows{reach} satisfies the mission "
        "(LTL tableau), so no trajectory does, at any horizon"
    )


def timed_label_proof(
    problem, labelled, timings: dict, counters: dict, clock=None, *, steps: Sequence[Sequence[int]] | None = None
) -> tuple[bool | None, str]:
    """:func:`label_proof` as both mission planners run it first: its time goes to
    ``timings["proof"]``, its verdict to ``counters["label_proof"]``; within ``clock``'s
    budget (run out: undecided)."""
    import time

    from plansynth.budget import BudgetExhausted

    t0 = time.perf_counter()
    try:
        if clock is None:
            proved, why = label_proof(problem, labelled, steps=steps)
        else:
            with clock.phase("the labels' geometry's proof"):
                proved, why = label_proof(problem, labelled, steps=steps)
    except BudgetExhausted as exc:
        proved, why = None, f"the labels' geometry's proof ran out of budget ({exc})"
    timings["proof"] = time.perf_counter() - t0
    counters["label_proof"] = proved
    return proved, why
