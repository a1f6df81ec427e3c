"""The product game's explicit part: the obstacles' joint configurations and their
successors, with the mode m and the fairness counter f as two more dimensions.

The obstacles move independently of the robot (spec, Semantics), so the graph of their
joint configurations, each a tuple of one (cell, wait counter, glitches left) per
obstacle, is explored once from the start, without the robot. A *node* of the game is
a configuration with a mode and a fairness counter; a game state is a node and a robot
cell, and a set of states is one robot-cell bit set per node (the representation of the
time-expanded arena, :mod:`plansynth.grid.native.arena`, without the time). Per
configuration this module keeps what a robot move needs to know about the obstacles'
replies (all of it exact, from :mod:`plansynth.grid.semantics`):

* ``succ[oc]``: the distinct successor configurations (every joint legal move);
* ``changed[oc][j]``: which obstacles change cell on the way to ``succ[oc][j]``;
* ``danger[oc]``: the cells some reply sweeps (collisions of the ``sweep`` rule: a robot
  move is safe against every reply iff it sweeps none of them, since each obstacle
  moves independently);
* ``blocks[oc]``: the cells the obstacles cover in ``oc`` (collisions of the
  ``position`` rule, read at the successor).

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [4, 1], "objective": "safety",
...     "robot": {"start": [0, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [3, 0], "moves": ["stay", "left"], "period": 2}]})
>>> s = ProductSpace.explore(p)
>>> s.configs[:3]          # (cell, wait counter, glitches left) per obstacle
[(((3, 0), 1, 0),), (((3, 0), 0, 0),), (((2, 0), 1, 0),)]
>>> s.succ[:2], s.changed[1]  # it waits, then stays or moves left
([(1,), (1, 2)], (0, 1))
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native.bitgrid import AgentGeometry, cell_mask
from plansynth.grid.native.limits import check_clock
from plansynth.grid.objective import CollisionRule, ObjectiveKind
from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.semantics import State, controller_inputs, counters_after, initial_state, legal_moves, obstacle_move

__all__ = ["ProductSpace", "ObstacleState"]

ObstacleState = tuple[Cell, int, int]  # (cell, wait counter, glitches left)


@dataclass
class ProductSpace:
    """The explored configurations (see the module docstring) and the robot's moves as
    bit-set operations. Node ids: ``(oc * K + m) * F + f``."""

    problem: GridProblem
    robot: AgentGeometry
    configs: list[tuple[ObstacleState, ...]] = field(default_factory=list)
    succ: list[tuple[int, ...]] = field(default_factory=list)
    changed: list[tuple[int, ...]] = field(default_factory=list)
    danger: list[int] = field(default_factory=list)
    blocks: list[int] = field(default_factory=list)
    K: int = 1  # noqa: N815 - the number of modes, as in the docs
    F: int = 1  # noqa: N815 - the values of the fairness counter
    _after: dict = field(default_factory=dict, repr=False)

    @property
    def n_configs(self) -> int:
        return len(self.configs)

    @property
    def n_nodes(self) -> int:
        return self.n_configs * self.K * self.F

    @property
    def position(self) -> bool:
        return self.problem.collision is CollisionRule.POSITION

    def node(self, oc: int, m: int = 0, f: int = 0) -> int:
        return (oc * self.K + m) * self.F + f

    def split(self, node: int) -> tuple[int, int, int]:
        """(configuration, mode, fairness counter) of a node id."""
        f = node % self.F
        rest = node // self.F
        return rest // self.K, rest % self.K, f

    @classmethod
    def explore(cls, problem: GridProblem, clock: Clock | None = None, max_configs: int | None = None) -> ProductSpace:
        """Every configuration reachable from the start (breadth first)."""
        space = cls(problem, AgentGeometry.robot(problem), K=problem.mode_count, F=problem.fair_count)
        start = initial_state(problem)
        first = tuple(space._obstacle_state(start, i) for i in range(len(problem.obstacles)))
        index = {first: 0}
        space.configs.append(first)
        head = 0
        while head < len(space.configs):
            oc = space.configs[head]
            head += 1
            replies = [space._replies(i, s) for i, s in enumerate(oc)]
            succ, changed = [], []
            danger = 0
            for row in replies:
                for _, _, swept in row:
                    danger |= swept
            for combo in itertools.product(*replies):
                nxt = tuple(c[0] for c in combo)
                j = index.get(nxt)
                if j is None:
                    j = index[nxt] = len(space.configs)
                    space.configs.append(nxt)
                    if max_configs is not None and len(space.configs) > max_configs:
                        raise BudgetExhausted(
                            "exploring the obstacles' configurations",
                            "configurations",
                            f"more than {max_configs} obstacle configurations",
                        )
                if j not in succ:
                    succ.append(j)
                    changed.append(sum(1 << i for i, c in enumerate(combo) if c[1]))
            space.succ.append(tuple(succ))
            space.changed.append(tuple(changed))
            space.danger.append(danger)
            space.blocks.append(space._blocks(oc))
            if head % 256 == 0:
                check_clock(clock, "exploring the obstacles' configurations", f" ({len(space.configs)} so far)")
        return space

    def _obstacle_state(self, state: State, i: int) -> ObstacleState:
        if not state.phases:
            return (state.obstacles[i], 0, 0)
        return (state.obstacles[i], state.phases[i], state.glitches[i])

    def _replies(self, i: int, s: ObstacleState) -> list[tuple[ObstacleState, bool, int]]:
        """Obstacle i's distinct replies from ``s``: (next state, changed cell, swept mask)."""
        p = self.problem
        cell, phase, glitches = s
        probe = State(
            p.robot.start,
            tuple(cell if j == i else o.start for j, o in enumerate(p.obstacles)),
            *(
                (
                    tuple(phase if j == i else 0 for j in range(len(p.obstacles))),
                    tuple(glitches if j == i else 0 for j in range(len(p.obstacles))),
                )
                if p.stateful
                else ((), ())
            ),
        )
        out: dict[ObstacleState, list] = {}
        for k in legal_moves(p, probe, i):
            end, swept = obstacle_move(p, i, cell, k)
            moved = end != cell
            ph, gl = counters_after(p, i, phase, glitches, moved) if p.stateful else (0, 0)
            mask = 0
            for c in swept:
                mask |= cell_mask(p, c)
            key = (end, ph, gl)
            if key in out:
                out[key][2] |= mask
            else:
                out[key] = [key, moved, mask]
        return [tuple(v) for v in out.values()]

    def _blocks(self, oc: tuple[ObstacleState, ...]) -> int:
        m = 0
        for i, (cell, _, _) in enumerate(oc):
            for c in self.problem.obstacles[i].block(cell):
                m |= cell_mask(self.problem, c)
        return m

    # -- reading states -------------------------------------------------------------
    def cells_of(self, oc: int) -> tuple[Cell, ...]:
        return tuple(s[0] for s in self.configs[oc])

    def state(self, r: int, node: int) -> State:
        """The :class:`~plansynth.grid.semantics.State` of robot cell index ``r`` at ``node``."""
        oc, m, f = self.split(node)
        conf = self.configs[oc]
        w = self.problem.width
        cells = tuple(s[0] for s in conf)
        if self.problem.stateful:
            return State((r % w, r // w), cells, tuple(s[1] for s in conf), tuple(s[2] for s in conf), m, f)
        return State((r % w, r // w), cells, (), (), m, f)

    def inputs(self, r: int, node: int) -> tuple[int, ...]:
        return controller_inputs(self.problem, self.state(r, node))

    def goal_mask(self, m: int) -> int:
        """The cell whose arrival counts: ``goals[m]`` (recurrence) or the goal."""
        p = self.problem
        if p.objective is ObjectiveKind.RECURRENCE:
            return cell_mask(p, p.robot.goals[m])
        if p.robot.goal is None:
            return 0
        return cell_mask(p, p.robot.goal)

    def robot_end(self, r: int, k: int) -> int:
        """The robot's cell index after move ``k`` from cell index ``r``."""
        robot = self.robot
        if robot.valid[k] >> r & 1:
            to = robot.moves[k].to
            return r + to[1] * robot.width + to[0]
        return r

    def collides(self, r: int, node: int, k: int) -> bool:
        """Whether some obstacle reply collides with robot move ``k`` from cell ``r``
        (or the move sweeps a wall)."""
        robot = self.robot
        oc, _, _ = self.split(node)
        if not robot.free[k] >> r & 1:
            return True
        if not self.position:
            return bool(robot.hit_sources(self.danger[oc], k) >> r & 1)
        end = self.robot_end(r, k)
        return any(self.blocks[oc2] >> end & 1 for oc2 in self.succ[oc])

    def successors(self, r: int, node: int, k: int) -> tuple[tuple[int, int], ...]:
        """:meth:`after` for every reply (memoized: programs are checked again and again)."""
        key = (r, node, k)
        got = self._after.get(key)
        if got is None:
            oc = node // (self.K * self.F)
            got = self._after[key] = tuple(self.after(r, node, k, j) for j in range(len(self.succ[oc])))
        return got

    def after(self, r: int, node: int, k: int, j: int) -> tuple[int, int]:
        """The state after robot move ``k`` from (r, node) and obstacle reply ``j`` (an
        index into ``succ``): the mode advances on the awaited goal (recurrence), the
        fairness counter when its obstacle changed cell."""
        oc, m, f = self.split(node)
        end = self.robot_end(r, k)
        if self.K > 1 and self.goal_mask(m) >> end & 1:
            m = (m + 1) % self.K
        ch = self.changed[oc][j]
        if self.F > 1 and ch >> f & 1:
            f = (f + 1) % self.F
        return end, self.node(self.succ[oc][j], m, f)

    def start(self) -> tuple[int, int]:
        """(robot cell index, node) of the initial state."""
        s = self.problem.robot.start
        return s[1] * self.problem.width + s[0], self.node(0)
