"""Strongly connected components of an explicit graph (Tarjan, "Depth-first search and
linear graph algorithms", SIAM J. Comput. 1(2), 1972), without recursion.

The checkers of infinite plays use it: the verifier's search for a cycle that avoids
the next goal (:mod:`plansynth.grid.verify.closed_loop`) and the check of the
obstacles' strategy (:mod:`plansynth.grid.native.product.certify`): a component with an
internal edge holds a cycle through all its internal edges.

>>> sorted(map(sorted, strongly_connected({1: [2], 2: [1, 3], 3: []})))
[[1, 2], [3]]
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Mapping

__all__ = ["strongly_connected"]


def strongly_connected(
    edges: Mapping[Hashable, Iterable],
    tick: Callable[[], None] | None = None,
    target: Callable[[object], Hashable] = lambda e: e,
) -> list[list]:
    """The components of the graph ``edges[v]`` (every vertex a key; ``target`` reads a
    successor off an edge), in reverse topological order; ``tick`` runs once per step
    of the search (a budget's check)."""
    index: dict = {}
    low: dict = {}
    on: set = set()
    stack: list = []
    out: list[list] = []
    counter = 0
    for root in edges:
        if root in index:
            continue
        work = [(root, iter(edges[root]))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on.add(root)
        while work:
            if tick is not None:
                tick()
            v, it = work[-1]
            advanced = False
            for e in it:
                w = target(e)
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(edges[w])))
                    advanced = True
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                out.append(comp)
    return out
