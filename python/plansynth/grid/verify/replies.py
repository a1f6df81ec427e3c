"""The obstacles' legal joint replies from one configuration, for the inductive-invariant
check (:mod:`.invariant`): per reply, the configuration after the step and the cells
that collide with the robot (the blocks after the step under ``collision: position``,
else the cells the obstacles sweep).

:func:`replies_by_step` plays every joint move of
:func:`~plansynth.grid.semantics.joint_choices` through
:func:`~plansynth.grid.semantics.step`, the rules themselves: one call per joint move
and configuration, which made it most of the check's time on large games (a 24 x 24
moving-obstacle game has 8464 configurations, each with up to nine replies).
:class:`ObstacleReplies` gives the same replies from the same rules' parts
(:func:`~plansynth.grid.semantics.obstacle_move`, tabulated per obstacle, cell and move
once; :func:`~plansynth.grid.semantics.may_change_cell` and
:func:`~plansynth.grid.semantics.counters_after` per obstacle); a property test checks
that the two agree on random problems and states.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [3, 1], "objective": "safety", "collision": "position",
...     "robot": {"start": [0, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [2, 0], "moves": ["stay", "left"]}]})
>>> from plansynth.grid.semantics import initial_state
>>> ObstacleReplies(p).of(initial_state(p)) == replies_by_step(p, initial_state(p))
True
"""

from __future__ import annotations

import itertools

from plansynth.grid.objective import CollisionRule
from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.semantics import (
    State,
    counters_after,
    joint_choices,
    may_change_cell,
    obstacle_move,
    step,
)

__all__ = ["ObstacleReplies", "Reply", "replies_by_step"]

#: One joint reply: the state after the step (the robot's cell left as it was) and the
#: cells that collide with the robot, sorted.
Reply = tuple[State, tuple[Cell, ...]]


def replies_by_step(problem: GridProblem, probe: State) -> list[Reply]:
    """The distinct joint replies from ``probe``'s configuration, each joint move played
    through :func:`~plansynth.grid.semantics.step` (the reference)."""
    position = problem.collision is CollisionRule.POSITION
    out: dict[Reply, None] = {}
    for joint in joint_choices(problem, probe):
        nxt = step(problem, probe, 0, joint).state._replace(robot=probe.robot)
        cells: set[Cell] = set()
        for i, o in enumerate(problem.obstacles):
            o_end, o_swept = obstacle_move(problem, i, probe.obstacles[i], joint[i])
            cells.update(o.block(o_end) if position else o_swept)
        out[(nxt, tuple(sorted(cells)))] = None
    return list(out)


class ObstacleReplies:
    """:func:`replies_by_step` with each obstacle's moves tabulated per cell (the same
    replies, in another order)."""

    def __init__(self, problem: GridProblem) -> None:
        self.problem = problem
        self.position = problem.collision is CollisionRule.POSITION
        # read once: the problem's properties recompute on every access
        self.stateful = problem.stateful
        self.fair = problem.fair_count > 1
        # the sorted union of the obstacles' colliding cells, per tuple of their cells
        self._union: dict[tuple, tuple[Cell, ...]] = {}
        self._moves: dict[tuple[int, Cell], tuple[tuple[Cell, tuple[Cell, ...]], ...]] = {}

    def _cell_moves(self, i: int, p: Cell) -> tuple[tuple[Cell, tuple[Cell, ...]], ...]:
        got = self._moves.get((i, p))
        if got is None:
            o = self.problem.obstacles[i]
            rows = []
            for k in range(len(o.moves)):
                end, swept = obstacle_move(self.problem, i, p, k)
                rows.append((end, tuple(o.block(end)) if self.position else swept))
            got = self._moves[(i, p)] = tuple(rows)
        return got

    def _local(self, probe: State, i: int) -> list[tuple[Cell, int, int, bool, tuple[Cell, ...]]]:
        """Obstacle ``i``'s legal moves from ``probe``: (end, wait counter, glitches left,
        changed cell, colliding cells), distinct."""
        problem = self.problem
        p = probe.obstacles[i]
        free = may_change_cell(problem, probe, i)
        out: dict[tuple, None] = {}
        for end, cells in self._cell_moves(i, p):
            moved = end != p
            if moved and not free:
                continue
            if self.stateful:
                ph, gl = counters_after(problem, i, probe.phases[i], probe.glitches[i], moved)
            else:
                ph, gl = 0, 0
            out[(end, ph, gl, moved, cells)] = None
        return list(out)

    def of(self, probe: State) -> list[Reply]:
        """The distinct joint replies from ``probe``'s configuration."""
        problem = self.problem
        per = [self._local(probe, i) for i in range(len(problem.obstacles))]
        out: dict[Reply, None] = {}
        if len(per) == 1 and not self.fair:
            # one obstacle (the common case, written out: a third of the check's time)
            robot, mode, fair = probe.robot, probe.mode, probe.fair
            for end, ph, gl, _, cells in per[0]:
                if self.stateful:
                    nxt = State(robot, (end,), (ph,), (gl,), mode, fair)
                else:
                    nxt = State(robot, (end,), (), (), mode, fair)
                single = (cells,)
                got = self._union.get(single)
                if got is None:
                    got = self._union[single] = tuple(sorted(set(cells)))
                out[(nxt, got)] = None
            return list(out)
        for joint in itertools.product(*per):
            fair = probe.fair
            if self.fair and joint[fair][3]:
                fair = (fair + 1) % problem.fair_count
            ends = tuple(j[0] for j in joint)
            if self.stateful:
                nxt = State(probe.robot, ends, tuple(j[1] for j in joint), tuple(j[2] for j in joint), probe.mode, fair)
            else:
                nxt = State(probe.robot, ends, (), (), probe.mode, fair)
            parts = tuple(j[4] for j in joint)
            cells = self._union.get(parts)
            if cells is None:
                cells = self._union[parts] = tuple(sorted({c for part in parts for c in part}))
            out[(nxt, cells)] = None
        return list(out)
