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

from collections.abc import Callable
from dataclasses import dataclass, field, replace

from plansynth.grid.native.bitgrid import AgentGeometry, bits, cell_mask
from plansynth.grid.native.limits import check_clock
from plansynth.grid.problem import GridProblem


@dataclass(frozen=True)
class Cone:
    """Reachability facts for one path length (all masks over cell indices).

    ``live[t]`` (t = 0..l): robot cells on some obstacle-free path to the goal.
    ``zone[t]`` (t = 0..l-1): cells the robot may sweep in step t on such a path.
    ``positions[i][t]``: cells obstacle i may occupy at time t (t = 0..l).
    ``danger[i][t]``: cells obstacle i may sweep in step t.
    ``blind_danger[t]``: the union of ``danger[i][t]`` over the relevant obstacles
    (what a controller that reads no obstacle must avoid).
    ``relevant``: obstacles whose danger meets the robot's zone at some step.
    ``parkable[i]``: obstacle i has a move that leaves it on its start cell, so the
    adversary can keep it still forever (its coordinates then carry no information).

    ``positions`` and ``danger`` are computed per obstacle when first read (and kept):
    on a 1000 x 1000 grid with l = 1000 each is a thousand masks of a million bits, so
    the cone keeps only ``blind_danger`` of its own.
    """

    steps: int
    live: tuple[int, ...]
    zone: tuple[int, ...]
    relevant: tuple[int, ...]
    parkable: tuple[bool, ...]
    blind_danger: tuple[int, ...]
    problem: GridProblem = field(repr=False, compare=False, default=None)  # type: ignore[assignment]
    _facts: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def goal_reachable(self) -> bool:
        """False when no obstacle-free path of exactly l steps reaches the goal."""
        return self.live[0] != 0

    def obstacle_facts(self, i: int, clock=None) -> tuple[tuple[int, ...], tuple[int, ...]]:
        """``(positions[i], danger[i])``, computed once."""
        got = self._facts.get(i)
        if got is None:
            got = self._facts[i] = obstacle_reach(self.problem, i, self.steps, clock)
        return got

    @property
    def positions(self) -> _PerObstacle:
        return _PerObstacle(self, 0)

    @property
    def danger(self) -> _PerObstacle:
        return _PerObstacle(self, 1)


class _PerObstacle:
    """``cone.positions[i]`` / ``cone.danger[i]``, through :meth:`Cone.obstacle_facts`."""

    def __init__(self, cone: Cone, which: int) -> None:
        self.cone, self.which = cone, which

    def __getitem__(self, i: int) -> tuple[int, ...]:
        return self.cone.obstacle_facts(i)[self.which]

    def __len__(self) -> int:
        return len(self.cone.problem.obstacles)


def obstacle_reach(problem: GridProblem, i: int, steps: int, clock=None) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """Cells obstacle i may occupy at each time t = 0..l, and sweep in each step."""
    g = AgentGeometry.obstacle(problem, i)
    pos = [cell_mask(problem, problem.obstacles[i].start)]
    dng = []
    for t in range(steps):
        _tick(clock, f"computing the cells obstacle {i} may reach (cone of influence)", t)
        dng.append(g.sweep_all(pos[-1]))
        pos.append(g.post(pos[-1]))
    return tuple(pos), tuple(dng)


#: Grids up to this many cells keep every obstacle's reachable sets (cheap there, and
#: read again by the clock label and tests); larger ones recompute them when read.
SMALL_GRID_CELLS = 10_000


def _tick(clock, what: str, t: int) -> None:
    """Stop with :class:`~plansynth.budget.BudgetExhausted` when ``clock`` has run out (on
    a 1000 x 1000 grid one step of these loops is a few big-integer operations of a
    million bits, and there are up to 1000 steps: the clock is read every step)."""
    check_clock(clock, what, f" at step {t}")


def robot_live(
    robot: AgentGeometry, start: int, goal: int, steps: int, danger: tuple[int, ...] | None = None, clock=None
) -> tuple[int, ...]:
    """Robot cells at each time t on a path start -> goal of exactly ``steps`` steps.

    With ``danger`` (a mask per step), a move that sweeps ``danger[t]`` in step t is
    forbidden; this is the obstacle-blind robot's reachable graph. Raises
    :class:`~plansynth.budget.BudgetExhausted` when ``clock`` runs out.
    """
    n = len(robot.moves)

    def safe(t: int, k: int) -> int:
        return robot.full if danger is None else ~robot.hit_sources(danger[t], k) & robot.full

    fwd = [start]
    for t in range(steps):
        _tick(clock, "computing the robot's reachable cells", t)
        nxt = 0
        for k in range(n):
            nxt |= robot.image(fwd[-1] & safe(t, k), k)
        fwd.append(nxt)
    back = [0] * (steps + 1)
    back[steps] = goal & fwd[steps]
    for t in range(steps - 1, -1, -1):
        _tick(clock, "computing the cells from which the robot reaches the goal", t)
        m = 0
        for k in range(n):
            m |= robot.pre(back[t + 1], k) & safe(t, k)
        back[t] = m & fwd[t]
    return tuple(back)


def influence_cone(problem: GridProblem, steps: int, clock=None) -> Cone:
    """Compute :class:`Cone` for ``problem`` at exactly ``steps`` steps (the engine's
    ``BudgetExhausted`` when ``clock`` runs out)."""
    robot = AgentGeometry.robot(problem)
    start = cell_mask(problem, problem.robot.start)
    goal = cell_mask(problem, problem.robot.goal)
    live = robot_live(robot, start, goal, steps, clock=clock)
    zone = []
    for t in range(steps):
        _tick(clock, "computing the robot's zone (cone of influence)", t)
        z = 0
        for k in range(len(robot.moves)):
            z |= robot.sweep(live[t] & robot.pre(live[t + 1], k), k)
        zone.append(z)
    relevant, parkable = [], []
    blind = [0] * steps
    small = problem.width * problem.height <= SMALL_GRID_CELLS
    facts = {}
    for i in range(len(problem.obstacles)):
        g = AgentGeometry.obstacle(problem, i)
        pos, dng = obstacle_reach(problem, i, steps, clock)
        if small:
            facts[i] = (pos, dng)
        if any(dng[t] & zone[t] for t in range(steps)):
            relevant.append(i)
            for t in range(steps):
                blind[t] |= dng[t]
        s = pos[0]
        parkable.append(any(g.image(s, k) == s for k in range(len(g.moves))))
    return Cone(steps, live, tuple(zone), tuple(relevant), tuple(parkable), tuple(blind), problem, facts)


def with_relevant(cone: Cone, read: tuple[int, ...]) -> Cone:
    """The cone with the obstacles ``read`` counted relevant too (a program reads them)."""
    return replace(cone, relevant=tuple(sorted(set(cone.relevant) | set(read))))


def clock_label(problem: GridProblem, cone: Cone) -> Callable[[int], int] | None:
    """The time label that accounts for dropped obstacles that cannot stay put.

    Returns None when every dropped obstacle can be kept on its start cell; otherwise
    ``t -> min(t, K)`` where by time K the adversary can have parked all of them.
    """
    k_all = 0
    for i in range(len(problem.obstacles)):
        if i in cone.relevant or cone.parkable[i]:
            continue
        g = AgentGeometry.obstacle(problem, i)
        park_cells = 0
        for c in bits(g.full):
            m = 1 << c
            if any(g.image(m, k) == m for k in range(len(g.moves))):
                park_cells |= m
        k_i = next((t for t, pos in enumerate(cone.positions[i]) if pos & park_cells), cone.steps)
        k_all = max(k_all, k_i)
    if k_all == 0:
        return None
    return lambda t, K=k_all: min(t, K)
