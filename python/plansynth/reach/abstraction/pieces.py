"""Greedy merging of convex pieces with exact contacts (Shoukry et al., CDC 2016,
Section III: few regions make the Boolean search small). Both 2-D constructions
(Hertel-Mehlhorn and the slabs) start from elementary convex pieces whose contacts are
known combinatorially and merge neighbours while their union stays convex, decided by
the exact orientation predicate; piece contacts are lifted to the merged regions, so no
adjacency is computed by floating-point geometry.

>>> square = Pieces([[(0, 0), (1, 0), (1, 1)], [(0, 0), (1, 1), (0, 1)]], [(0, 1)])
>>> square.merge_all()
>>> square.result()
([[(1, 1), (0, 1), (0, 0), (1, 0)]], set())
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from plansynth.budget import checkpoint
from plansynth.reach.abstraction.predicates import Pt, orient

__all__ = ["Pieces"]


def _longest_first(e: tuple[Pt, Pt]) -> float:
    return -math.hypot(e[1][0] - e[0][0], e[1][1] - e[0][1])


class Pieces:
    """Convex pieces (CCW vertex cycles) with exact piece contacts; greedy convex merging.

    Two pieces can merge only along an edge that is a full edge of both (the shared
    chord of a convex union always is); the union is convex iff the turns at the two
    ends of the edge are not right turns.

    ``straight``: points known by construction to lie inside a straight edge of the free
    space's boundary (slab corners interpolated on an obstacle edge). The turn there is
    0 whatever the rounded coordinates say: asking the orientation predicate would keep
    a vertex of angle 180 degrees +- 1e-16, convex or reflex by a rounding error.
    """

    def __init__(
        self, cycles: list[list[Pt]], contacts: Iterable[tuple[int, int]], order=None, straight: Iterable[Pt] = ()
    ) -> None:
        self.order = order or _longest_first
        self.straight = frozenset(straight)
        self.cycles: dict[int, list[Pt]] = {i: c for i, c in enumerate(cycles)}
        self.parent = list(range(len(cycles)))
        self.contacts = {(min(a, b), max(a, b)) for a, b in contacts if a != b}

    def find(self, i: int) -> int:
        while self.parent[i] != i:
            self.parent[i] = self.parent[self.parent[i]]
            i = self.parent[i]
        return i

    def merge_all(self) -> None:
        while self._merge_pass():
            pass

    def _merge_pass(self) -> bool:
        owner: dict[tuple[Pt, Pt], int] = {}
        for pid, cyc in self.cycles.items():
            for i in range(len(cyc)):
                owner[(cyc[i], cyc[(i + 1) % len(cyc)])] = pid
        diagonals = [(u, v) for (u, v), pid in owner.items() if (v, u) in owner and owner[(v, u)] != pid and u < v]
        diagonals.sort(key=self.order)
        merged_any = False
        for u, v in diagonals:
            checkpoint()  # within a budget (plansynth.budget): many thousand diagonals
            p, q = owner.get((u, v)), owner.get((v, u))
            if p is None or q is None or p == q or p not in self.cycles or q not in self.cycles:
                continue
            new = self._try_merge(self.cycles[p], self.cycles[q], u, v)
            if new is None:
                continue
            del self.cycles[q]
            self.cycles[p] = new
            self.parent[q] = p
            for i in range(len(new)):
                owner[(new[i], new[(i + 1) % len(new)])] = p
            merged_any = True
        return merged_any

    def _try_merge(self, P: list[Pt], Q: list[Pt], u: Pt, v: Pt) -> list[Pt] | None:
        """Union of P (with edge u->v) and Q (with edge v->u) if convex, else None."""
        # the owner map may hold edges that collinear-vertex removal has since dissolved
        if v not in P or u not in Q:
            return None
        i = P.index(v)
        Pr = P[i:] + P[:i]  # v ... u
        j = Q.index(u)
        Qr = Q[j:] + Q[:j]  # u ... v
        if Pr[-1] != u or Qr[-1] != v:
            return None
        # turn at u: Pr[-2] -> u -> Qr[1]; at v: Qr[-2] -> v -> Pr[1]
        tu = 0 if u in self.straight else orient(Pr[-2], u, Qr[1])
        tv = 0 if v in self.straight else orient(Qr[-2], v, Pr[1])
        if tu < 0 or tv < 0:
            return None
        cyc = Pr[:-1] + [u] + Qr[1:-1]
        if tu == 0:
            cyc.remove(u)
        if tv == 0:
            cyc.remove(v)
        return cyc

    def result(self) -> tuple[list[list[Pt]], set[tuple[int, int]]]:
        ids = sorted(self.cycles)
        pos = {pid: k for k, pid in enumerate(ids)}
        adj = set()
        for a, b in self.contacts:
            ra, rb = pos[self.find(a)], pos[self.find(b)]
            if ra != rb:
                adj.add((min(ra, rb), max(ra, rb)))
        return [self.cycles[i] for i in ids], adj
