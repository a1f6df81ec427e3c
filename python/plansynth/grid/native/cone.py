"""Cone of influence: which obstacles can matter for a path length l at all.

An obstacle whose reachable cells can never meet the cells the robot may sweep on its
way to the goal in exactly l steps cannot influence any controller: it never collides
with the robot, whatever either does. Such obstacles are dropped before search. (The
paper's obstacle-count family, Chasins & Newcomb SYNT 2016 Section 4.1, puts up to 50
obstacles far from the robot; this is why that family costs a SyGuS solver hours.)

The robot's side is over-approximated by its *live* cells: reachable from the start in
t steps and able to reach the goal in the remaining l - t steps, ignoring obstacles
(walls included). An obstacle's side is its t-step reachable set, which is exact
because obstacles are independent of everything else.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [20, 20],
...     "robot": {"start": [0, 0], "goal": [2, 3], "moves": ["stay", "up", "right", "down", "left"]},
...     "obstacles": [{"start": [5, 19], "moves": ["up", "down"]}, {"start": [1, 2], "moves": ["up", "down"]}]})
>>> influence_cone(p, 5).relevant
(1,)
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.grid.native.bitgrid import AgentGeometry, cell_mask
from plansynth.grid.problem import GridProblem


@dataclass(frozen=True)
class Cone:
    """Reachability facts for one path length (all masks over cell indices).

    ``live[t]`` (t = 0..l): robot cells on some obstacle-free path to the goal.
    ``zone[t]`` (t = 0..l-1): cells the robot may sweep in step t on such a path.
    ``positions[i][t]``: cells obstacle i may occupy at time t (t = 0..l).
    ``danger[i][t]``: cells obstacle i may sweep in step t.
    ``relevant``: obstacles whose danger meets the robot's zone at some step.
    ``parkable[i]``: obstacle i has a move that leaves it on its start cell, so the
    adversary can keep it still forever (its coordinates then carry no information).
    """

    steps: int
    live: tuple[int, ...]
    zone: tuple[int, ...]
    positions: tuple[tuple[int, ...], ...]
    danger: tuple[tuple[int, ...], ...]
    relevant: tuple[int, ...]
    parkable: tuple[bool, ...]

    @property
    def goal_reachable(self) -> bool:
        """False when no obstacle-free path of exactly l steps reaches the goal."""
        return self.live[0] != 0


def robot_live(robot: AgentGeometry, start: int, goal: int, steps: int, danger: tuple[int, ...] | None = None) -> tuple[int, ...]:
    """Robot cells at each time t on a path start -> goal of exactly ``steps`` steps.

    With ``danger`` (a mask per step), a move that sweeps ``danger[t]`` in step t is
    forbidden; this is the obstacle-blind robot's reachable graph.
    """
    n = len(robot.moves)

    def safe(t: int, k: int) -> int:
        return robot.full if danger is None else ~robot.hit_sources(danger[t], k) & robot.full

    fwd = [start]
    for t in range(steps):
        nxt = 0
        for k in range(n):
            nxt |= robot.image(fwd[-1] & safe(t, k), k)
        fwd.append(nxt)
    back = [0] * (steps + 1)
    back[steps] = goal & fwd[steps]
    for t in range(steps - 1, -1, -1):
        m = 0
        for k in range(n):
            m |= robot.pre(back[t + 1], k) & safe(t, k)
        back[t] = m & fwd[t]
    return tuple(back)


def influence_cone(problem: GridProblem, steps: int) -> Cone:
    """Compute :class:`Cone` for ``problem`` at exactly ``steps`` steps."""
    robot = AgentGeometry.robot(problem)
    start = cell_mask(problem, problem.robot.start)
    goal = cell_mask(problem, problem.robot.goal)
    live = robot_live(robot, start, goal, steps)
    zone = []
    for t in range(steps):
        z = 0
        for k in range(len(robot.moves)):
            z |= robot.sweep(live[t] & robot.pre(live[t + 1], k), k)
        zone.append(z)
    positions, danger, relevant, parkable = [], [], [], []
    for i, o in enumerate(problem.obstacles):
        g = AgentGeometry.obstacle(problem, i)
        pos = [cell_mask(problem, o.start)]
        dng = []
        for t in range(steps):
            dng.append(g.sweep_all(pos[-1]))
            pos.append(g.post(pos[-1]))
        positions.append(tuple(pos))
        danger.append(tuple(dng))
        if any(dng[t] & zone[t] for t in range(steps)):
            relevant.append(i)
        s = pos[0]
        parkable.append(any(g.image(s, k) == s for k in range(len(g.moves))))
    return Cone(steps, live, tuple(zone), tuple(positions), tuple(danger), tuple(relevant), tuple(parkable))
