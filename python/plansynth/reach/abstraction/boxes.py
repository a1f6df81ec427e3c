"""The ``boxes`` construction (2-D and 3-D, every obstacle a box; Shoukry et al., CDC
2016, Section III): the grid of all obstacle coordinates, free cells grown greedily
into maximal boxes (the best of all axis orders). Grid cells sharing a face are the
contacts the boxes inherit.
"""

from __future__ import annotations

import itertools

import numpy as np

from plansynth.budget import checkpoint
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = ["grid_boxes", "obstacle_grid"]


def obstacle_grid(problem: ReachProblem) -> tuple[list[np.ndarray], np.ndarray]:
    """The grid of all obstacle coordinates inside the workspace (every obstacle a box):
    the cut coordinates per axis and the boolean array of free cells."""
    ws = problem.workspace
    d = ws.dim
    cuts = []
    for k in range(d):
        vals = {ws.lo[k], ws.hi[k]}
        for ob in problem.obstacles:
            if not isinstance(ob, Box):
                raise ValueError("the obstacle grid needs every obstacle to be a box")
            vals.update(v for v in (ob.lo[k], ob.hi[k]) if ws.lo[k] < v < ws.hi[k])
        cuts.append(np.array(sorted(vals)))
    free = np.ones(tuple(len(c) - 1 for c in cuts), dtype=bool)
    for ob in problem.obstacles:
        assert isinstance(ob, Box)
        sl = []
        for k in range(d):
            i0 = int(np.searchsorted(cuts[k], max(ob.lo[k], ws.lo[k]), side="left"))
            i1 = int(np.searchsorted(cuts[k], min(ob.hi[k], ws.hi[k]), side="left"))
            sl.append(slice(i0, max(i0, i1)))
        free[tuple(sl)] = False
    return cuts, free


def grid_boxes(problem: ReachProblem) -> tuple[list[tuple[np.ndarray, np.ndarray]], set[tuple[int, int]]]:
    """Free grid cells of all obstacle coordinates, grown greedily into maximal boxes.

    Every axis order is tried; the one giving fewest boxes wins.
    """
    cuts, free = obstacle_grid(problem)
    d = free.ndim

    best = None
    for order in itertools.permutations(range(d)):
        label = _grow_boxes(free, order)
        count = int(label.max()) + 1
        if best is None or count < best[0]:
            best = (count, label)
    assert best is not None
    count, label = best
    boxes = []
    for b in range(count):
        idx = np.argwhere(label == b)
        lo_i, hi_i = idx.min(axis=0), idx.max(axis=0) + 1
        boxes.append((np.array([cuts[k][lo_i[k]] for k in range(d)]), np.array([cuts[k][hi_i[k]] for k in range(d)])))
    adj = set()
    for k in range(d):
        a = np.moveaxis(label, k, 0)
        x, y = a[:-1].ravel(), a[1:].ravel()
        mask = (x >= 0) & (y >= 0) & (x != y)
        for i, j in zip(x[mask].tolist(), y[mask].tolist()):
            adj.add((min(i, j), max(i, j)))
    return boxes, adj


def _grow_boxes(free: np.ndarray, order: tuple[int, ...]) -> np.ndarray:
    """Label free cells with box ids: from each unassigned free cell (in scan order),
    grow along ``order[0]``, then ``order[1]``, ... while the slab stays free+unassigned."""
    label = np.full(free.shape, -1, dtype=np.int64)
    avail = free.copy()  # free and not yet in a box
    flat = avail.reshape(-1)  # a view: updated with avail
    d = free.ndim
    nb = 0
    ptr = 0
    while True:
        checkpoint()
        rest = flat[ptr:]
        k0 = int(np.argmax(rest))
        if not rest[k0]:
            break
        ptr += k0
        cell = np.unravel_index(ptr, free.shape)
        lo = [int(c) for c in cell]
        hi = [c + 1 for c in lo]
        for k in order:
            while hi[k] < free.shape[k]:
                sl = tuple(slice(lo[j], hi[j]) if j != k else slice(hi[k], hi[k] + 1) for j in range(d))
                if np.all(avail[sl]):
                    hi[k] += 1
                else:
                    break
        box = tuple(slice(lo[j], hi[j]) for j in range(d))
        label[box] = nb
        avail[box] = False
        nb += 1
    return label
