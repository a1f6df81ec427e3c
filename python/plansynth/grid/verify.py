"""The independent verifier: does a controller win a grid problem at exactly l steps?

A controller wins for path length l if, for every behaviour of the obstacles, the robot
never collides in steps 0..l-1 and stands on the goal after step l-1 (spec:
grid-problem.md, Semantics; Chasins & Newcomb, SYNT 2016, Section 3.1). This module
decides that exactly, using only :mod:`plansynth.grid.semantics` (the single definition
of a step) and :mod:`plansynth.grid.programs` (evaluation). Every program a solver
reports is checked here before it is called realizable.

Enumerating the obstacles' joint choices is hopeless on the paper's families (2^50 per
step for obstacles-50), so the verifier uses three reductions that preserve exactness.
There is no alternation to preserve: the program is fixed, so the question is whether
*some* obstacle behaviour makes the robot lose.

1. **Only read obstacles steer the robot.** The robot's next move is a function of the
   inputs the program reads (:func:`~plansynth.grid.programs.variables_of`). The robot
   and the obstacles the program reads are explored jointly, depth first, with every
   abstract state already shown safe remembered.
2. **Unread obstacles are independent of everything.** An obstacle the program never
   reads cannot influence the robot, nor can the other obstacles influence it. So it
   can collide at step t iff some cell it can occupy at time t (its t-step reachable
   set) has a move whose swept cells meet the robot's swept cells at step t. Those sets
   are computed once per obstacle, and their swept cells are merged into one "danger"
   bitmask per step.
3. **Read obstacles are tracked as sets, split only where the program looks.** Given
   the robot's moves so far, the read obstacles' possible cells form a product of one
   set per obstacle (they move independently, and the image of a product under their
   moves is a product). The program's choice is evaluated on the sets with interval
   arithmetic; where a comparison is undecided, the sets are split on it until the
   choice is constant on each part. On a part, a read obstacle can collide iff one of
   its cells has a move meeting the robot's swept cells, as in 2. A program that
   compares against a threshold (``(<= o0y 3)``) splits a set in two; only relational
   comparisons between obstacles (``(<= o0y o1y)``) approach explicit enumeration.

Two shortcuts only make losses cheaper to find: a robot farther from the goal (in robot
moves, obstacles ignored) than the steps left has lost whatever the obstacles do, and a
short depth-first probe (:data:`PROBE_NODES` expansions, obstacles nearest the robot
first) runs before the exhaustive layered search. Move tables are filled lazily from
:func:`~plansynth.grid.semantics.robot_move` and
:func:`~plansynth.grid.semantics.obstacle_move`, so a 64 x 64 grid costs only the cells
visited.

When the controller loses, the verdict carries a concrete :class:`Counterexample`: the
obstacles' joint moves, the states visited and the program's choices, which replay
through :func:`~plansynth.grid.semantics.step` to the loss it describes.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [4, 1],
...     "robot": {"start": [0, 0], "goal": [3, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [3, 0], "moves": ["stay", "left"]}]})
>>> verify(p, parse_program("1"), 3).wins
False
>>> print(verify(p, parse_program("1"), 3).counterexample.reason)
collision at step 1 in cell (2, 0) with obstacle 0
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import product

from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.programs import (
    App,
    Const,
    ProgramSyntaxError,
    Term,
    Var,
    check_program,
    compile_program,
    evaluate,
    variables_of,
)
from plansynth.grid.semantics import CompiledSemantics, State, initial_state, obstacle_move, robot_move, step


@dataclass(frozen=True)
class Counterexample:
    """A run on which the controller loses.

    ``states[t]`` is the state at the start of step t (``states[0]`` the initial one,
    the last one the state after the losing step); ``robot_moves[t]`` and
    ``obstacle_moves[t]`` are the moves taken at step t. ``reason`` says why it loses.
    """

    obstacle_moves: tuple[tuple[int, ...], ...]
    states: tuple[State, ...]
    robot_moves: tuple[int, ...]
    reason: str


@dataclass(frozen=True)
class Verdict:
    """The verifier's answer for one program and one path length.

    ``wins`` is exact (there is no "unknown": the verifier is complete). When it is
    False, ``counterexample`` shows a losing run. ``states_explored`` counts the
    (t, robot, read obstacles) nodes expanded.
    """

    wins: bool
    steps: int
    counterexample: Counterexample | None
    states_explored: int
    seconds: float


def read_obstacles(program: Term, n_obstacles: int) -> tuple[int, ...]:
    """Indices of the obstacles whose coordinates ``program`` reads, in order.

    >>> from plansynth.grid.programs import parse_program
    >>> read_obstacles(parse_program("(ite (<= o2y rx) 0 1)"), 3)
    (2,)
    """
    names = variables_of(program)
    return tuple(i for i in range(n_obstacles) if f"o{i}x" in names or f"o{i}y" in names)


def check_controller(problem: GridProblem, program: Term) -> None:
    """Raise :class:`ProgramSyntaxError` unless ``program`` is a controller of ``problem``'s
    grammar: a Start term over its inputs whose move numbers name robot moves."""
    check_program(program, problem.variables, len(problem.robot.moves), problem.max_constant)


def verify(problem: GridProblem, program: Term, steps: int, *, probe_nodes: int | None = None) -> Verdict:
    """Decide exactly whether ``program`` wins ``problem`` at path length ``steps``.

    ``probe_nodes`` bounds the depth-first probe for a quick counterexample that runs
    before the exhaustive search (default :data:`PROBE_NODES`; 0 disables it). It
    changes only the time taken and which counterexample is found, never the answer.

    Raises :class:`~plansynth.grid.programs.ProgramSyntaxError` when the program is not
    a controller of the problem's grammar (for example a move number with no move).
    """
    if steps < 1:
        raise ValueError(f"steps must be >= 1, got {steps}")
    check_controller(problem, program)
    t0 = time.perf_counter()
    search = _Search(problem, program, steps, PROBE_NODES if probe_nodes is None else probe_nodes)
    loss = search.run()
    cex = None if loss is None else search.counterexample(loss)
    return Verdict(loss is None, steps, cex, search.explored, time.perf_counter() - t0)


# -- the search ------------------------------------------------------------------------

#: A set of cells (indices ``y * width + x``) one read obstacle may occupy.
Cells = frozenset[int]
Sets = tuple[Cells, ...]


class _Node:
    """An abstract state at one time: the robot's cell and a product of read-obstacle
    cell sets, every combination of which is reachable with the robot there.

    ``parents`` lists (node, part, robot move) one time earlier whose images make up
    ``sets``; counterexamples are rebuilt through them.
    """

    __slots__ = ("r", "sets", "parents")

    def __init__(self, r: int, sets: Sets, parents: list[tuple["_Node", Sets, int]]) -> None:
        self.r = r
        self.sets = sets
        self.parents = parents


@dataclass(frozen=True)
class _Loss:
    """Where the search lost: in ``node`` (at time ``t``), on ``part`` with robot move
    ``move``. ``kind`` is "wall", "unread", "read" (read obstacle slot ``obstacle`` can
    collide) or "doomed" (the robot can no longer stand on the goal at time ``steps``;
    ``part`` is the whole node and no move is taken at ``t``)."""

    kind: str
    t: int
    node: _Node
    part: Sets
    move: int = -1
    obstacle: int = -1


_UNDECIDED = None

#: Expansions the depth-first probe may spend before the exact layered search starts.
PROBE_NODES = 500


class _ProbeExhausted(Exception):
    pass


class _Search:
    """Breadth-first exploration of (t, robot cell, read obstacles' cell sets).

    Given the robot's history, the read obstacles' possible positions form a product
    set: the obstacles move independently, and the image of a product set under their
    moves is again one. The only thing that breaks products is the program's choice,
    which depends on the read coordinates; so each set is evaluated with intervals and
    split on an undecided comparison until the choice is constant on every part
    (reduction 3 of the module docstring; all-singleton sets are plain enumeration).
    On each part, a read obstacle can collide iff one of its cells has a move sweeping
    the robot's swept cells, exactly as for unread obstacles.

    Time is explored layer by layer (so the loss found is a shortest one, unless the
    depth-first probe run first already found one). The robot's future depends only on its cell and the obstacles' cells, not on how it got
    there, so the products reaching the same (t, robot cell) are merged where they
    differ in one factor (S x T and S' x T make (S | S') x T) or one contains another.
    """

    def __init__(self, problem: GridProblem, program: Term, steps: int, probe_nodes: int) -> None:
        self.probe_nodes = probe_nodes
        self.problem = problem
        self.program = program
        self.steps = steps
        self.sem = CompiledSemantics(problem)  # cell indices and the wall mask
        # Move tables over cell indices, filled lazily: a 64 x 64 grid has 4096 cells
        # and the robot and obstacles visit few of them.
        self.robot = _Rows(problem, lambda c, k: robot_move(problem, c, k), len(problem.robot.moves))
        self.obstacle = [
            _Rows(problem, lambda c, k, i=i: obstacle_move(problem, i, c, k), len(o.moves))
            for i, o in enumerate(problem.obstacles)
        ]
        self.width = problem.width
        self.goal = self.sem.index(problem.robot.goal)
        self.read = read_obstacles(program, len(problem.obstacles))
        self.unread = tuple(i for i in range(len(problem.obstacles)) if i not in self.read)
        self.explored = 0
        self.reach, self.danger = self._unread_reach()
        self.distance = self._goal_distances()
        # Per read obstacle: cell set -> (successor set, every cell it can sweep).
        self._image: list[dict[Cells, tuple[Cells, int]]] = [{} for _ in self.read]
        self._bounds: dict[Cells, tuple[int, int, int, int]] = {}
        # (robot, sets) -> parts on which the program's choice is constant, with it.
        self._parts: dict[tuple[int, tuple[Cells, ...]], tuple[tuple[tuple[Cells, ...], int], ...]] = {}

    # -- unread obstacles ------------------------------------------------------------

    def _unread_reach(self) -> tuple[list[list[Cells]], list[int]]:
        """Per unread obstacle, the cells it can occupy at each time 0..steps-1, and per
        step the union of every cell some unread obstacle can sweep then."""
        danger = [0] * self.steps
        reach: list[list[Cells]] = []
        for i in self.unread:
            succ = self.obstacle[i].successors
            # A set of cells determines its successor set and its swept cells, and the
            # sequence of sets is often periodic (an up/down obstacle alternates), so
            # each distinct set is expanded once.
            expanded: dict[Cells, tuple[Cells, int]] = {}
            cur = frozenset((self.sem.index(self.problem.obstacles[i].start),))
            sets = []
            for t in range(self.steps):
                sets.append(cur)
                if cur not in expanded:
                    expanded[cur] = _image(succ, cur)
                cur, mask = expanded[cur]
                danger[t] |= mask
            reach.append(sets)
        return reach, danger

    def goal_distance(self, r: int) -> int:
        """Fewest robot moves from cell ``r`` to the goal (obstacles and walls ignored;
        ``steps + 1`` when more than ``steps``)."""
        return self.distance.get(r, self.steps + 1)

    def _goal_distances(self) -> dict[int, int]:
        """Breadth-first search back from the goal over the robot's moves, to depth ``steps``."""
        p = self.problem
        w = self.width
        dist = {self.goal: 0}
        frontier = [self.goal]
        for d in range(1, self.steps + 1):
            nxt = []
            for e in frontier:
                ex, ey = e % w, e // w
                for m in p.robot.moves:
                    c = (ex - m.to[0], ey - m.to[1])
                    if p.in_grid(c):
                        ci = c[1] * w + c[0]
                        if ci not in dist and any(end == e for end, _ in self.robot[ci]):
                            dist[ci] = d
                            nxt.append(ci)
            frontier = nxt
        return dist

    # -- read obstacles: images, bounds, and the program's choice on a product set ----

    def image(self, j: int, cells: Cells) -> tuple[Cells, int]:
        """Successor set and swept-cells mask of read obstacle number ``j`` (slot) on ``cells``."""
        cache = self._image[j]
        if cells not in cache:
            cache[cells] = _image(self.obstacle[self.read[j]].successors, cells)
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

    def intervals(self, r: int, sets: tuple[Cells, ...]) -> dict[str, tuple[int, int]]:
        w = self.width
        env = {"rx": (r % w, r % w), "ry": (r // w, r // w)}
        for j, i in enumerate(self.read):
            x0, x1, y0, y1 = self.bounds(sets[j])
            env[f"o{i}x"] = (x0, x1)
            env[f"o{i}y"] = (y0, y1)
        return env

    def parts(self, r: int, sets: tuple[Cells, ...]) -> tuple[tuple[tuple[Cells, ...], int], ...]:
        """Split ``sets`` into parts on which the program's move is constant: (part, move)."""
        key = (r, sets)
        cached = self._parts.get(key)
        if cached is not None:
            return cached
        out: list[tuple[tuple[Cells, ...], int]] = []
        stack: list[tuple[tuple[Cells, ...], dict[int, bool]]] = [(sets, {})]
        while stack:
            part, known = stack.pop()
            env = self.intervals(r, part)
            found = _choose(self.program, env, known)
            if isinstance(found, int):
                out.append((part, found))
            else:
                stack.extend(self._split(found, r, part, env, known))
        # Splits are hierarchical, so the parts with one move usually reassemble into
        # fewer products (often the whole set, when both branches of an undecided ite
        # choose alike); fewer, larger parts keep the next layer small.
        by_move: dict[int, dict[Sets, list]] = {}
        for part, k in out:
            by_move.setdefault(k, {})[part] = []
        result = tuple((part, k) for k, group in by_move.items() for part in _merge(group))
        self._parts[key] = result
        return result

    def _split(
        self, atom: App, r: int, part: tuple[Cells, ...], env: dict[str, tuple[int, int]], known: dict[int, bool]
    ) -> list[tuple[tuple[Cells, ...], dict[int, bool]]]:
        """Split ``part`` so that ``atom`` (undecided on its intervals) is decided on each piece."""
        names = variables_of(atom)
        # Read obstacles whose coordinates in the atom are not yet single values.
        loose = []
        for j, i in enumerate(self.read):
            coords = [c for c in "xy" if f"o{i}{c}" in names]
            if any(env[f"o{i}{c}"][0] != env[f"o{i}{c}"][1] for c in coords):
                loose.append((j, i, coords))
        if len(loose) == 1:
            # The atom reads one undetermined obstacle: evaluate it on each of its cells.
            j, i, _ = loose[0]
            w = self.width
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
        w = self.width

        def key_of(c: int, coords: list[str]) -> tuple[int, ...]:
            return tuple(c % w if k == "x" else c // w for k in coords)

        j, i, coords = min(loose, key=lambda l: len({key_of(c, l[2]) for c in part[l[0]]}))
        groups: dict[tuple[int, ...], set[int]] = {}
        for c in part[j]:
            groups.setdefault(key_of(c, coords), set()).add(c)
        return [(part[:j] + (frozenset(g),) + part[j + 1 :], known) for g in groups.values()]

    # -- exploration -----------------------------------------------------------------

    def run(self) -> _Loss | None:
        """None if the controller wins, else a loss (a shortest one unless the probe found one)."""
        r0 = self.sem.index(self.problem.robot.start)
        s0 = tuple(frozenset((self.sem.index(self.problem.obstacles[i].start),)) for i in self.read)
        if self.read and self.probe_nodes > 0:
            try:
                return self._probe(_Node(r0, s0, []), 0, set())
            except _ProbeExhausted:
                pass
        return self._layers(_Node(r0, s0, []))

    def _step(self, t: int, node: _Node, part: Sets, k: int) -> _Loss | tuple[int, list[Cells]]:
        """Take move ``k`` on ``part`` at time ``t``: a loss, or (robot end, successor sets)."""
        self.explored += 1
        r_end, r_mask = self.robot[node.r][k]
        if r_mask & self.sem.walls:
            return _Loss("wall", t, node, part, k)
        if r_mask & self.danger[t]:
            return _Loss("unread", t, node, part, k)
        nxt = []
        for j, cells in enumerate(part):
            succ, swept = self.image(j, cells)
            if swept & r_mask:
                return _Loss("read", t, node, part, k, j)
            nxt.append(succ)
        return r_end, nxt

    def _doomed(self, t: int, node: _Node) -> _Loss | None:
        # Whatever the obstacles do, the robot can no longer stand on the goal at time
        # `steps` (at t == steps this is the goal check itself).
        if self.goal_distance(node.r) > self.steps - t:
            return _Loss("doomed", t, node, node.sets)
        return None

    def _layers(self, root: _Node) -> _Loss | None:
        """The exact search: time layer by layer, products merged per (t, robot cell)."""
        layer = [root]
        for t in range(self.steps + 1):
            successors: dict[int, dict[Sets, list[tuple[_Node, Sets, int]]]] = {}
            for node in layer:
                loss = self._doomed(t, node)
                if loss is not None:
                    return loss
                if t == self.steps:
                    continue
                for part, k in self.parts(node.r, node.sets):
                    out = self._step(t, node, part, k)
                    if isinstance(out, _Loss):
                        return out
                    r_end, nxt = out
                    successors.setdefault(r_end, {}).setdefault(tuple(nxt), []).append((node, part, k))
            layer = [
                _Node(r, sets, parents) for r, boxes in successors.items() for sets, parents in _merge(boxes).items()
            ]
        return None

    def _probe(self, node: _Node, t: int, safe: set) -> _Loss | None:
        """A cheap depth-first hunt for a loss over single combinations, given up after
        PROBE_NODES expansions (a losing program is often caught long before the exact
        layered search would reach its last layer). Raises _ProbeExhausted when given up."""
        loss = self._doomed(t, node)
        if loss is not None or t == self.steps:
            return loss
        key = (t, node.r, node.sets)
        if key in safe:
            return None
        if self.explored >= self.probe_nodes or t > 500:
            raise _ProbeExhausted
        # Heuristic order: moves that leave the robot farthest from the goal first, and
        # obstacle cells nearest to the robot first.
        robot = self.robot[node.r]
        parts = sorted(self.parts(node.r, node.sets), key=lambda pk: -self.goal_distance(robot[pk[1]][0]))
        for part, k in parts:
            out = self._step(t, node, part, k)
            if isinstance(out, _Loss):
                return out
            r_end, nxt = out
            rx, ry = r_end % self.width, r_end // self.width
            near = lambda c: abs(c % self.width - rx) + abs(c // self.width - ry)  # noqa: E731
            for combo in product(*(sorted(c, key=near) for c in nxt)):
                child = _Node(r_end, tuple(frozenset((c,)) for c in combo), [(node, part, k)])
                loss = self._probe(child, t + 1, safe)
                if loss is not None:
                    return loss
        safe.add(key)
        return None

    # -- counterexamples -------------------------------------------------------------

    def counterexample(self, loss: _Loss) -> Counterexample:
        """Turn a loss into a concrete run of all obstacles, and replay it with step()."""
        p = self.problem
        steps_taken = loss.t if loss.kind == "doomed" else loss.t + 1
        joint: list[list[int]] = [[0] * len(p.obstacles) for _ in range(steps_taken)]
        robot_moves = [0] * steps_taken
        # Cells of the read obstacles at time loss.t (and their moves then, if a step is taken).
        cells = [min(s) for s in loss.part]
        if loss.kind != "doomed":
            robot_moves[loss.t] = loss.move
            r_mask = self.robot[loss.node.r][loss.move][1]
            if loss.kind == "read":
                j = loss.obstacle
                table = self.obstacle[self.read[j]]
                cells[j], joint[loss.t][self.read[j]] = next(
                    (c, k) for c in sorted(loss.part[j]) for k, (_, m) in enumerate(table[c]) if m & r_mask
                )
        # Walk back through the parents: a parent part whose image holds the cells, and
        # for each obstacle a cell there with a move into its current cell.
        node, t = loss.node, loss.t
        while t > 0:
            for parent, part, k in node.parents:
                back = self._preimage(part, cells)
                if back is not None:
                    break
            else:  # pragma: no cover - the parents' images make up the node's sets
                raise AssertionError("verifier bug: no parent leads to the losing state")
            t -= 1
            robot_moves[t] = k
            cells = []
            for j, (c, m) in enumerate(back):
                cells.append(c)
                joint[t][self.read[j]] = m
            node = parent
        if loss.kind == "unread":
            # Steer one unread obstacle into the robot's swept cells at the last step.
            for u, i in enumerate(self.unread):
                hit = self._unread_hit(u, i, loss.t, r_mask)
                if hit is not None:
                    for s, k in enumerate(hit):
                        joint[s][i] = k
                    break
            else:  # pragma: no cover - the danger mask promised a hit
                raise AssertionError("verifier bug: no unread obstacle realises the danger mask")
        if loss.kind == "doomed":
            # Any continuation loses: run the program on, every obstacle taking move 0.
            state = _replay(p, robot_moves, joint, self.steps)[0][-1]
            controller = compile_program(self.program, p.variables)
            for _ in range(loss.t, self.steps):
                k = controller(*state.inputs())
                zero = (0,) * len(p.obstacles)
                robot_moves.append(k)
                joint.append(list(zero))
                state, collided = step(p, state, k, zero)
                if collided:
                    break
        moves = tuple(robot_moves)
        obstacle_moves = tuple(tuple(j) for j in joint)
        states, reason = _replay(p, moves, obstacle_moves, self.steps)
        if reason is None:  # pragma: no cover - would mean the search and step() disagree
            raise AssertionError("verifier bug: the counterexample does not lose when replayed")
        return Counterexample(obstacle_moves, states, moves, reason)

    def _preimage(self, part: Sets, cells: list[int]) -> list[tuple[int, int]] | None:
        """Per read obstacle, a (cell in ``part``, move) ending in ``cells``; None if some
        obstacle cannot get there from ``part``."""
        out = []
        for j, target in enumerate(cells):
            table = self.obstacle[self.read[j]]
            found = next(
                ((c, k) for c in sorted(part[j]) for k, (e, _) in enumerate(table[c]) if e == target), None
            )
            if found is None:
                return None
            out.append(found)
        return out

    def _unread_hit(self, u: int, i: int, t: int, r_mask: int) -> list[int] | None:
        """Moves of unread obstacle ``i`` for steps 0..t that sweep ``r_mask`` at step t."""
        table = self.obstacle[i]
        sets = self.reach[u]
        for c in sorted(sets[t]):
            for k, (_, mask) in enumerate(table[c]):
                if mask & r_mask:
                    return _walk_back(table, sets[:t], c) + [k]
        return None


def _merge(boxes: dict[Sets, list]) -> dict[Sets, list]:
    """Merge products that differ in one factor, and drop products inside another.

    The result covers exactly the same combinations; each product keeps the parents
    of the products merged into it.
    """
    if len(boxes) < 2:
        return boxes
    n = len(next(iter(boxes)))
    if len(boxes) > 256 and sum(_volume(b) for b in boxes) <= 4 * len(boxes):
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


class _Rows:
    """``rows[c][k]``: (end index, swept-cells mask) of move k from cell index c, computed
    on first use from :mod:`plansynth.grid.semantics` (the same numbers as
    :class:`~plansynth.grid.semantics.CompiledSemantics`, without building every row)."""

    def __init__(self, problem: GridProblem, move, n_moves: int) -> None:
        self.width = problem.width
        self.move = move
        self.n_moves = n_moves
        self.rows: dict[int, tuple[tuple[int, int], ...]] = {}
        self.successors = _Distinct(self)

    def __getitem__(self, ci: int) -> tuple[tuple[int, int], ...]:
        row = self.rows.get(ci)
        if row is None:
            w = self.width
            out = []
            for k in range(self.n_moves):
                end, swept = self.move((ci % w, ci // w), k)
                mask = 0
                for x, y in swept:
                    mask |= 1 << (y * w + x)
                out.append((end[1] * w + end[0], mask))
            row = self.rows[ci] = tuple(out)
        return row


class _Distinct:
    """``successors[c]``: the distinct (end, mask) pairs of a :class:`_Rows` row."""

    def __init__(self, rows: _Rows) -> None:
        self.of = rows
        self.cache: dict[int, tuple[tuple[int, int], ...]] = {}

    def __getitem__(self, ci: int) -> tuple[tuple[int, int], ...]:
        row = self.cache.get(ci)
        if row is None:
            row = self.cache[ci] = tuple(dict.fromkeys(self.of[ci]))
        return row


def _volume(sets: Sets) -> int:
    v = 1
    for c in sets:
        v *= len(c)
    return v


def _image(succ: Sequence[Sequence[tuple[int, int]]], cells: Cells) -> tuple[Cells, int]:
    """The cells reachable in one move from ``cells`` and every cell swept on the way."""
    nxt: set[int] = set()
    mask = 0
    for c in cells:
        for end, swept in succ[c]:
            nxt.add(end)
            mask |= swept
    return frozenset(nxt), mask


def _walk_back(table: Sequence[Sequence[tuple[int, int]]], sets: Sequence[Cells], cell: int) -> list[int]:
    """Moves m_0..m_{T-1} of one obstacle with cell_s in ``sets[s]`` ending in ``cell`` at T.

    Each ``sets[s + 1]`` must lie in the image of ``sets[s]`` (true of the search's sets).
    """
    moves: list[int] = []
    cur = cell
    for s in range(len(sets) - 1, -1, -1):
        prev, k = next((q, k) for q in sorted(sets[s]) for k, (e, _) in enumerate(table[q]) if e == cur)
        moves.append(k)
        cur = prev
    return moves[::-1]


def _choose(program: Term, env: dict[str, tuple[int, int]], known: dict[int, bool]) -> int | App:
    """The program's move if it is the same for every input in the intervals ``env``,
    else an undecided comparison to split on. ``known`` fixes atoms decided by splits."""
    t = program
    while isinstance(t, App):  # (ite B S S)
        cond = t.args[0]
        v = _truth(cond, env, known)
        if v is _UNDECIDED:
            return _undecided_atom(cond, env, known)
        t = t.args[1] if v else t.args[2]
    assert isinstance(t, Const)
    return t.value


def _truth(b: Term, env: dict[str, tuple[int, int]], known: dict[int, bool]) -> bool | None:
    """Kleene three-valued truth of a condition over intervals."""
    assert isinstance(b, App)
    op = b.op
    if op == "not":
        v = _truth(b.args[0], env, known)
        return None if v is None else not v
    if op == "and":
        a = _truth(b.args[0], env, known)
        if a is False:
            return False
        c = _truth(b.args[1], env, known)
        if c is False:
            return False
        return True if (a and c) else None
    if op == "or":
        a = _truth(b.args[0], env, known)
        if a is True:
            return True
        c = _truth(b.args[1], env, known)
        if c is True:
            return True
        return False if (a is False and c is False) else None
    if id(b) in known:
        return known[id(b)]
    lo1, hi1 = _interval(b.args[0], env)
    lo2, hi2 = _interval(b.args[1], env)
    if op == "<=":
        if hi1 <= lo2:
            return True
        if lo1 > hi2:
            return False
        return None
    # "="
    if lo1 == hi1 == lo2 == hi2:
        return True
    if hi1 < lo2 or hi2 < lo1:
        return False
    return None


def _undecided_atom(b: Term, env: dict[str, tuple[int, int]], known: dict[int, bool]) -> App:
    """A comparison inside the undecided condition ``b`` that is itself undecided."""
    assert isinstance(b, App)
    if b.op in ("not", "and", "or"):
        for a in b.args:
            if _truth(a, env, known) is _UNDECIDED:
                return _undecided_atom(a, env, known)
        raise AssertionError("an undecided condition has an undecided part")  # pragma: no cover
    return b


def _interval(t: Term, env: dict[str, tuple[int, int]]) -> tuple[int, int]:
    if isinstance(t, Const):
        return t.value, t.value
    if isinstance(t, Var):
        return env[t.name]
    a0, a1 = _interval(t.args[0], env)
    b0, b1 = _interval(t.args[1], env)
    if t.op == "+":
        return a0 + b0, a1 + b1
    return a0 - b1, a1 - b0  # "-"


def _replay(
    problem: GridProblem,
    robot_moves: Sequence[int],
    obstacle_moves: Sequence[Sequence[int]],
    steps: int,
) -> tuple[tuple[State, ...], str | None]:
    """Run the moves through :func:`step`; the states and why the run loses (None: it wins)."""
    state = initial_state(problem)
    states = [state]
    for t, (k, joint) in enumerate(zip(robot_moves, obstacle_moves, strict=True)):
        nxt, collided = step(problem, state, k, joint)
        states.append(nxt)
        if collided:
            return tuple(states), collision_reason(problem, state, k, joint, t)
        state = nxt
    if len(robot_moves) == steps and state.robot != problem.robot.goal:
        return tuple(states), (
            f"not on the goal {_fmt(problem.robot.goal)} after step {steps - 1}: "
            f"the robot is at {_fmt(state.robot)}"
        )
    return tuple(states), None


def collision_reason(problem: GridProblem, state: State, k: int, joint: Sequence[int], t: int) -> str:
    """Why the robot collides at step ``t`` from ``state`` (a wall, or the first obstacle)."""
    _, swept = robot_move(problem, state.robot, k)
    for c in swept:
        if c in problem.walls:
            return f"collision at step {t} with the wall at {_fmt(c)}"
    for i, (p, j) in enumerate(zip(state.obstacles, joint)):
        _, o_swept = obstacle_move(problem, i, p, j)
        common = [c for c in swept if c in o_swept]
        if common:
            return f"collision at step {t} in cell {_fmt(common[0])} with obstacle {i}"
    raise ValueError(f"no collision at step {t}")


def _fmt(c: Cell) -> str:
    return f"({c[0]}, {c[1]})"


__all__ = [
    "Counterexample",
    "ProgramSyntaxError",
    "Verdict",
    "check_controller",
    "collision_reason",
    "read_obstacles",
    "verify",
]
