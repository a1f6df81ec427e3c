"""The discrete abstraction as DIS-PLAN sees it (Shoukry et al., CDC 2016, Section III):
regions 0..n-1, their adjacency, the start and goal regions, and the breadth-first
distances that bound the horizon from below.

>>> g = RegionGraph(3, ((1,), (0, 2), (1,)), start_regions=(0,), goal_regions=(2,))
>>> g.distances([0])
[0, 1, 2]
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

from plansynth.reach.abstraction import Abstraction

__all__ = ["RegionGraph", "reachable"]


def reachable(starts: Sequence[int], adjacency: Sequence[Sequence[int]], blocked: int | None = None) -> list[bool]:
    """Per region: does a walk over ``adjacency`` from ``starts`` reach it (never through
    ``blocked``, which counts as reached)?

    >>> reachable([0], [(1,), (0,), ()]), reachable([0], [(1,), (0, 2), (1,)], blocked=1)
    ([True, True, False], [True, True, False])
    """
    seen = [False] * len(adjacency)
    if blocked is not None:
        seen[blocked] = True
    stack = [s for s in starts if s != blocked]
    for s in stack:
        seen[s] = True
    while stack:
        i = stack.pop()
        for j in adjacency[i]:
            if not seen[j]:
                seen[j] = True
                stack.append(j)
    return seen


@dataclass(frozen=True)
class RegionGraph:
    """The discrete abstraction as DIS-PLAN sees it: regions 0..n-1, adjacency lists,
    start and goal regions (paper, Section III)."""

    n_regions: int
    adjacency: tuple[tuple[int, ...], ...]
    start_regions: tuple[int, ...]
    goal_regions: tuple[int, ...]

    def __post_init__(self) -> None:
        if len(self.adjacency) != self.n_regions:
            raise ValueError(f"adjacency has {len(self.adjacency)} lists for {self.n_regions} regions")
        for i, nbrs in enumerate(self.adjacency):
            for j in nbrs:
                if not 0 <= j < self.n_regions or j == i or i not in self.adjacency[j]:
                    raise ValueError(f"adjacency must be symmetric without self-loops: {i} -> {j}")

    @classmethod
    def from_abstraction(cls, abstraction: Abstraction) -> RegionGraph:
        return cls(len(abstraction.regions), abstraction.adjacency, abstraction.start_regions, abstraction.goal_regions)

    def distances(self, sources: Sequence[int]) -> list[float]:
        """Breadth-first number of region transitions from ``sources`` (inf: unreachable)."""
        dist = [math.inf] * self.n_regions
        queue = deque()
        for s in sources:
            dist[s] = 0
            queue.append(s)
        while queue:
            i = queue.popleft()
            for j in self.adjacency[i]:
                if dist[j] == math.inf:
                    dist[j] = dist[i] + 1
                    queue.append(j)
        return dist

    def horizon_lower_bound(self) -> float:
        """The region-graph distance from a start region to a goal region: no region
        sequence of a shorter horizon exists (inf when the goal is disconnected).

        >>> RegionGraph(3, ((1,), (0, 2), (1,)), (0,), (2,)).horizon_lower_bound()
        2
        """
        dist = self.distances(self.start_regions)
        return min((dist[g] for g in self.goal_regions), default=math.inf)
