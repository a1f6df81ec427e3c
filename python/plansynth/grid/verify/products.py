"""The read obstacles' possible cells as a product of one set per obstacle (reduction 3
of :mod:`plansynth.grid.verify`).

Given the robot's history, the read obstacles' possible positions form a product set:
the obstacles move independently, and the image of a product set under their moves is
again one. The only thing that breaks products is the program's choice, which depends
on the read coordinates; so each product is evaluated with intervals
(:mod:`.intervals`) and split on an undecided comparison until the choice is constant
on every part (all-singleton sets are plain enumeration). Products that reach the same
(t, robot cell) are merged again where they differ in one factor (:func:`merge`).
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import product

from plansynth.grid.programs import App, Term, evaluate, variables_of
from plansynth.grid.verify.intervals import Env, choose
from plansynth.grid.verify.meter import Meter
from plansynth.grid.verify.tables import Cells, MoveTable, Sets

__all__ = ["ReadObstacles", "merge", "volume", "image"]

#: A part of a product with the program's move on it.
Part = tuple[Sets, int]


class ReadObstacles:
    """The obstacles a program reads (``read``, in slot order) and the program's choice
    on products of their cell sets, with what has been computed kept for reuse."""

    def __init__(
        self, program: Term, read: tuple[int, ...], tables: Sequence[MoveTable], width: int, meter: Meter
    ) -> None:
        self.program = program
        self.read = read
        self.tables = [tables[i] for i in read]
        self.width = width
        self.meter = meter
        # Per read obstacle: cell set -> (successor set, every cell it can sweep).
        self._image: list[dict[Cells, tuple[Cells, Cells]]] = [{} for _ in read]
        self._bounds: dict[Cells, tuple[int, int, int, int]] = {}
        # (robot, sets) -> parts on which the program's choice is constant, with it.
        self._parts: dict[tuple[int, Sets], tuple[Part, ...]] = {}

    def image(self, j: int, cells: Cells) -> tuple[Cells, Cells]:
        """Successor set and swept cells of read obstacle number ``j`` (slot) on ``cells``."""
        cache = self._image[j]
        if cells not in cache:
            self.meter.tick(len(cells))
            cache[cells] = image(self.tables[j], cells)
        return cache[cells]

    def bounds(self, cells: Cells) -> tuple[int, int, int, int]:
        """(min x, max x, min y, max y) over ``cells``."""
        b = self._bounds.get(cells)
        if b is None:
            w = self.width
            xs = [c % w for c in cells]
            ys = [c // w for c in cells]
            b = self._bounds[cells] = (min(xs), max(xs), min(ys), max(ys))
        return b

    def intervals(self, r: int, sets: Sets) -> Env:
        """The program's inputs as intervals: the robot on cell ``r``, the read obstacles
        anywhere in ``sets``."""
        w = self.width
        env = {"rx": (r % w, r % w), "ry": (r // w, r // w)}
        for j, i in enumerate(self.read):
            x0, x1, y0, y1 = self.bounds(sets[j])
            env[f"o{i}x"] = (x0, x1)
            env[f"o{i}y"] = (y0, y1)
        return env

    def parts(self, r: int, sets: Sets) -> tuple[Part, ...]:
        """Split ``sets`` into parts on which the program's move is constant: (part, move)."""
        key = (r, sets)
        cached = self._parts.get(key)
        if cached is not None:
            return cached
        out: list[Part] = []
        stack: list[tuple[Sets, dict[int, bool]]] = [(sets, {})]
        while stack:
            part, known = stack.pop()
            env = self.intervals(r, part)
            found = choose(self.program, env, known)
            if isinstance(found, int):
                out.append((part, found))
            else:
                stack.extend(self._split(found, part, env, known))
        # Splits are hierarchical, so the parts with one move usually reassemble into
        # fewer products (often the whole set, when both branches of an undecided ite
        # choose alike); fewer, larger parts keep the next layer small.
        by_move: dict[int, dict[Sets, list]] = {}
        for part, k in out:
            by_move.setdefault(k, {})[part] = []
        result = tuple((part, k) for k, group in by_move.items() for part in merge(group))
        self._parts[key] = result
        return result

    def _split(self, atom: App, part: Sets, env: Env, known: dict[int, bool]) -> list[tuple[Sets, dict[int, bool]]]:
        """Split ``part`` so that ``atom`` (undecided on its intervals) is decided on each piece."""
        self.meter.tick(sum(map(len, part)))
        names = variables_of(atom)
        # Read obstacles whose coordinates in the atom are not yet single values.
        loose = []
        for j, i in enumerate(self.read):
            coords = [c for c in "xy" if f"o{i}{c}" in names]
            if any(env[f"o{i}{c}"][0] != env[f"o{i}{c}"][1] for c in coords):
                loose.append((j, i, coords))
        w = self.width
        if len(loose) == 1:
            # The atom reads one undetermined obstacle: evaluate it on each of its cells.
            j, i, _ = loose[0]
            point = {v: lo for v, (lo, hi) in env.items() if lo == hi}
            by_value: dict[bool, set[int]] = {True: set(), False: set()}
            for c in part[j]:
                point[f"o{i}x"], point[f"o{i}y"] = c % w, c // w
                by_value[bool(evaluate(atom, point))].add(c)
            return [
                (part[:j] + (frozenset(cells),) + part[j + 1 :], {**known, id(atom): value})
                for value, cells in by_value.items()
                if cells
            ]
        # Several undetermined obstacles: fix the read coordinates of the one with the
        # fewest distinct values; the atom then reads one fewer undetermined obstacle.

        def key_of(c: int, coords: list[str]) -> tuple[int, ...]:
            return tuple(c % w if k == "x" else c // w for k in coords)

        j, i, coords = min(loose, key=lambda l: len({key_of(c, l[2]) for c in part[l[0]]}))
        groups: dict[tuple[int, ...], set[int]] = {}
        for c in part[j]:
            groups.setdefault(key_of(c, coords), set()).add(c)
        return [(part[:j] + (frozenset(g),) + part[j + 1 :], known) for g in groups.values()]


def image(table: MoveTable, cells: Cells) -> tuple[Cells, Cells]:
    """The cells reachable in one move from ``cells`` and every cell swept on the way."""
    succ = table.successors
    nxt: set[int] = set()
    swept: set[int] = set()
    for c in cells:
        for end, sw in succ[c]:
            nxt.add(end)
            swept |= sw
    return frozenset(nxt), frozenset(swept)


def volume(sets: Sets) -> int:
    """The number of combinations in a product."""
    v = 1
    for c in sets:
        v *= len(c)
    return v


def merge(boxes: dict[Sets, list]) -> dict[Sets, list]:
    """Merge products that differ in one factor, and drop products inside another.

    The result covers exactly the same combinations; each product keeps the parents
    of the products merged into it.

    >>> a, b, c = frozenset({1}), frozenset({2}), frozenset({3})
    >>> sorted(map(sorted, merge({(a, c): ["p"], (b, c): ["q"]})))
    [[frozenset({1, 2}), frozenset({3})]]
    """
    if len(boxes) < 2:
        return boxes
    n = len(next(iter(boxes)))
    if len(boxes) > 256 and sum(volume(b) for b in boxes) <= 4 * len(boxes):
        # Many small overlapping products: fall back to the combinations themselves,
        # so there are never many more products than reachable states.
        single: dict[Sets, list] = {}
        for sets, parents in boxes.items():
            for combo in product(*sets):
                single.setdefault(tuple(frozenset((c,)) for c in combo), []).extend(parents)
        boxes = single
    changed = True
    while changed and len(boxes) > 1:
        changed = False
        for j in range(n):
            groups: dict[Sets, list[Sets]] = {}
            for sets in boxes:
                groups.setdefault(sets[:j] + sets[j + 1 :], []).append(sets)
            if len(groups) == len(boxes):
                continue
            merged: dict[Sets, list] = {}
            for rest, members in groups.items():
                union = frozenset().union(*(m[j] for m in members))
                key = rest[:j] + (union,) + rest[j:]
                parents = merged.setdefault(key, [])
                for m in members:
                    parents.extend(boxes[m])
            boxes = merged
            changed = True
    if 1 < len(boxes) <= 64:
        keys = sorted(boxes, key=lambda s: -sum(len(c) for c in s))
        kept: dict[Sets, list] = {}
        for sets in keys:
            if not any(all(a <= b for a, b in zip(sets, big)) for big in kept):
                kept[sets] = boxes[sets]
        boxes = kept
    return boxes
