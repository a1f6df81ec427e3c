"""The exact search for a losing run: (time, robot cell, read obstacles' cell sets),
layer by layer, after a short depth-first probe (reductions 1-3 and the shortcuts of
:mod:`plansynth.grid.verify`)."""

from __future__ import annotations

from dataclasses import dataclass
from itertools import product
from types import ModuleType
from typing import Any

from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.programs import Term
from plansynth.grid.semantics import obstacle_move, robot_move
from plansynth.grid.verify import python_tables
from plansynth.grid.verify.controller import read_obstacles
from plansynth.grid.verify.meter import Meter
from plansynth.grid.verify.products import ReadObstacles, merge
from plansynth.grid.verify.tables import Cells, Sets

__all__ = ["Search", "Node", "Loss", "PROBE_NODES"]

#: Expansions the depth-first probe may spend before the exact layered search starts.
PROBE_NODES = 500


class Node:
    """An abstract state at one time: the robot's cell and a product of read-obstacle
    cell sets, every combination of which is reachable with the robot there.

    ``parents`` lists (node, part, robot move) one time earlier whose images make up
    ``sets``; counterexamples are rebuilt through them.
    """

    __slots__ = ("r", "sets", "parents")

    def __init__(self, r: int, sets: Sets, parents: list[tuple[Node, Sets, int]]) -> None:
        self.r = r
        self.sets = sets
        self.parents = parents


@dataclass(frozen=True)
class Loss:
    """Where the search lost: in ``node`` (at time ``t``), on ``part`` with robot move
    ``move``. ``kind`` is "wall", "unread", "read" (read obstacle slot ``obstacle`` can
    collide) or "doomed" (the robot can no longer stand on the goal at time ``steps``;
    ``part`` is the whole node and no move is taken at ``t``)."""

    kind: str
    t: int
    node: Node
    part: Sets
    move: int = -1
    obstacle: int = -1


class ProbeExhausted(Exception):
    """The depth-first probe spent its expansions without finding a loss."""


def representation(use_numpy: bool) -> ModuleType:
    """The module holding ``Table``, ``UnreadReach`` and ``goal_distances``: numpy arrays
    (imported here, only for the grids that use them) or plain Python."""
    if use_numpy:
        from plansynth.grid.verify import numpy_tables

        return numpy_tables
    return python_tables


class Search:
    """Breadth-first exploration of (t, robot cell, read obstacles' cell sets).

    The read obstacles' cells are products split where the program looks
    (:class:`~.products.ReadObstacles`); on each part, a read obstacle can collide iff
    one of its cells has a move sweeping the robot's swept cells, exactly as for unread
    obstacles (whose sweeps are one danger bitmap per step, ``unread_reach``).

    Time is explored layer by layer (so the loss found is a shortest one, unless the
    depth-first probe run first already found one). The robot's future depends only on
    its cell and the obstacles' cells, not on how it got there, so the products reaching
    the same (t, robot cell) are merged where they differ in one factor (S x T and
    S' x T make (S | S') x T) or one contains another.
    """

    def __init__(
        self, problem: GridProblem, program: Term, steps: int, probe_nodes: int, meter: Meter, use_numpy: bool = True
    ) -> None:
        self.probe_nodes = probe_nodes
        self.problem = problem
        self.program = program
        self.steps = steps
        self.meter = meter
        self.width = w = problem.width
        self.n_cells = problem.width * problem.height
        self.walls = frozenset(c[1] * w + c[0] for c in problem.walls)
        rep = representation(use_numpy)
        # Move tables over cell indices, filled lazily. Obstacles with the same moves
        # share a table (a move's effect depends only on the move and walls).
        self.robot = rep.Table(problem, lambda c, k: robot_move(problem, c, k), problem.robot.moves, meter)
        tables: dict[tuple, Any] = {}
        self.obstacle = []
        for i, o in enumerate(problem.obstacles):
            if o.moves not in tables:
                tables[o.moves] = rep.Table(problem, lambda c, k, i=i: obstacle_move(problem, i, c, k), o.moves, meter)
            self.obstacle.append(tables[o.moves])
        self.goal = self.index(problem.robot.goal)
        self.read = read_obstacles(program, len(problem.obstacles))
        self.unread = tuple(i for i in range(len(problem.obstacles)) if i not in self.read)
        self.explored = 0
        meter.phase = "the unread obstacles' reachable cells"
        self.unread_reach = rep.UnreadReach(problem, self.obstacle, self.unread, meter)
        meter.phase = "the robot's distances to the goal"
        self.distance = rep.goal_distances(problem, self.robot, self.goal, steps, meter)
        self.reads = ReadObstacles(program, self.read, self.obstacle, w, meter)

    def index(self, c: Cell) -> int:
        return c[1] * self.width + c[0]

    def danger(self, t: int) -> bytes:
        """Packed bitmap (bit ``c`` of byte ``c >> 3``) of every cell some unread obstacle
        can sweep at step ``t``."""
        return self.unread_reach.danger(t)

    def goal_distance(self, r: int) -> int:
        """Fewest robot moves from cell ``r`` to the goal (obstacles and walls ignored;
        ``steps + 1`` when more than ``steps``)."""
        return int(self.distance[r])

    def run(self) -> Loss | None:
        """None if the controller wins, else a loss (a shortest one unless the probe found one)."""
        r0 = self.index(self.problem.robot.start)
        s0 = tuple(frozenset((self.index(self.problem.obstacles[i].start),)) for i in self.read)
        if self.read and self.probe_nodes > 0:
            self.meter.phase = "the depth-first probe"
            try:
                return self._probe(Node(r0, s0, []), 0, set())
            except ProbeExhausted:
                pass
        return self._layers(Node(r0, s0, []))

    def _step(self, t: int, node: Node, part: Sets, k: int) -> Loss | tuple[int, list[Cells]]:
        """Take move ``k`` on ``part`` at time ``t``: a loss, or (robot end, successor sets)."""
        self.explored += 1
        self.meter.tick(8)
        r_end, r_swept = self.robot[node.r][k]
        if not self.walls.isdisjoint(r_swept):
            return Loss("wall", t, node, part, k)
        danger = self.danger(t)
        if any(danger[c >> 3] >> (c & 7) & 1 for c in r_swept):
            return Loss("unread", t, node, part, k)
        nxt = []
        for j, cells in enumerate(part):
            succ, swept = self.reads.image(j, cells)
            if not swept.isdisjoint(r_swept):
                return Loss("read", t, node, part, k, j)
            nxt.append(succ)
        return r_end, nxt

    def _doomed(self, t: int, node: Node) -> Loss | None:
        # Whatever the obstacles do, the robot can no longer stand on the goal at time
        # `steps` (at t == steps this is the goal check itself).
        if self.goal_distance(node.r) > self.steps - t:
            return Loss("doomed", t, node, node.sets)
        return None

    def _layers(self, root: Node) -> Loss | None:
        """The exact search: time layer by layer, products merged per (t, robot cell)."""
        layer = [root]
        for t in range(self.steps + 1):
            self.meter.phase = f"the layered search (step {t} of {self.steps})"
            self.meter.check()
            successors: dict[int, dict[Sets, list[tuple[Node, Sets, int]]]] = {}
            for node in layer:
                loss = self._doomed(t, node)
                if loss is not None:
                    return loss
                if t == self.steps:
                    continue
                for part, k in self.reads.parts(node.r, node.sets):
                    out = self._step(t, node, part, k)
                    if isinstance(out, Loss):
                        return out
                    r_end, nxt = out
                    successors.setdefault(r_end, {}).setdefault(tuple(nxt), []).append((node, part, k))
            layer = [
                Node(r, sets, parents) for r, boxes in successors.items() for sets, parents in merge(boxes).items()
            ]
        return None

    def _probe(self, node: Node, t: int, safe: set) -> Loss | None:
        """A cheap depth-first hunt for a loss over single combinations, given up after
        ``probe_nodes`` expansions (a losing program is often caught long before the
        exact layered search would reach its last layer). Raises :class:`ProbeExhausted`
        when given up."""
        loss = self._doomed(t, node)
        if loss is not None or t == self.steps:
            return loss
        key = (t, node.r, node.sets)
        if key in safe:
            return None
        if self.explored >= self.probe_nodes or t > 500:
            raise ProbeExhausted
        # Heuristic order: moves that leave the robot farthest from the goal first, and
        # obstacle cells nearest to the robot first.
        robot = self.robot[node.r]
        parts = sorted(self.reads.parts(node.r, node.sets), key=lambda pk: -self.goal_distance(robot[pk[1]][0]))
        for part, k in parts:
            out = self._step(t, node, part, k)
            if isinstance(out, Loss):
                return out
            r_end, nxt = out
            rx, ry = r_end % self.width, r_end // self.width
            near = lambda c: abs(c % self.width - rx) + abs(c // self.width - ry)  # noqa: E731
            for combo in product(*(sorted(c, key=near) for c in nxt)):
                child = Node(r_end, tuple(frozenset((c,)) for c in combo), [(node, part, k)])
                loss = self._probe(child, t + 1, safe)
                if loss is not None:
                    return loss
        safe.add(key)
        return None
