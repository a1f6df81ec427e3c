"""A brute-force game solver for every objective, for tiny problems (STYLE.md, point 6).

The oracle the native engine and the verifier are compared with in property tests. It
knows nothing of either: it enumerates the game's states with
:func:`~plansynth.grid.semantics.step` and the legal moves of
:mod:`plansynth.grid.semantics`, and decides each objective of
:mod:`plansynth.grid.objective` by the textbook algorithm least like the engine's
nested fixpoints over bit sets:

* ``reach`` within l: the robot's attractor of the goal, iterated l times;
* ``exact``: whether some positional strategy (a map from states to moves: the paper's
  controllers see no time) wins, by backtracking over the states a partial map reaches;
* ``safety``: the greatest fixpoint of the states with a move that keeps every reply
  safe, over Python sets;
* ``recurrence``: a max-parity game (Emerson and Jutla 1991) over the states extended by
  what the last step did, solved by Zielonka's recursive algorithm ("Infinite games on
  finitely coloured graphs", TCS 200, 1998): priority 2 after a step that ends on the
  awaited goal, 1 after a step in which the fairness assumption progresses (every step
  without ``fair``), 0 otherwise; a collision is a sink of priority 1. The robot wins a
  play iff the largest priority seen infinitely often is even: the goal infinitely
  often, or (under ``fair``) progress of the assumption only finitely often.

Exponential in everything: use it only on grids of a few cells with one or two
obstacles.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [3, 3], "objective": "safety",
...     "robot": {"start": [0, 0], "moves": ["stay", "up", "down", "left", "right"]},
...     "obstacles": [{"start": [2, 2], "moves": ["stay", "up", "down", "left", "right"]}]})
>>> brute_force(p).value            # the obstacle is as fast as the robot
'unrealizable'
>>> brute_force(grid_problem_from_dict({**p.to_dict(), "obstacles": [{"start": [2, 2],
...     "moves": ["stay", "up", "down", "left", "right"], "period": 2}]})).value
'realizable'
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

from plansynth.grid.objective import ObjectiveKind
from plansynth.grid.problem import GridProblem
from plansynth.grid.result import GridStatus
from plansynth.grid.semantics import State, initial_state, joint_choices, step

__all__ = ["brute_force", "game_graph", "zielonka", "stationary_search", "TooLarge"]

#: The collision sink of :func:`game_graph`.
LOST = "lost"


class TooLarge(Exception):
    """The oracle gave up: more states (or partial strategies, or seconds) than its limit."""


def brute_force(
    problem: GridProblem, steps: int | None = None, *, limit: int = 50_000, controller: Controller | None = None
) -> GridStatus:
    """``realizable`` or ``unrealizable``: whether a controller (a map from the states
    the program sees to robot moves) achieves ``problem``'s objective (``steps``: the
    path length l of ``exact`` and ``reach``, default the problem's own).

    With ``controller`` (a map from states to moves) the robot has only that map's move
    in each state: the answer is then whether that controller wins, decided by the same
    algorithms (a check of the verifier independent of it)."""
    kind = problem.objective
    if kind.bounded:
        l = steps if steps is not None else problem.steps
        if l is None:
            raise ValueError("the oracle decides one path length: give steps")
        if kind is ObjectiveKind.EXACT:
            won = _exact(problem, l, limit, controller)
        else:
            won = _reach(problem, l, limit, controller)
    elif kind is ObjectiveKind.SAFETY:
        won = _safety(problem, limit, controller)
    else:
        won = _recurrence(problem, limit, controller)
    return GridStatus.REALIZABLE if won else GridStatus.UNREALIZABLE


Controller = Callable[[State], int]
Rows = list[list[tuple[State, bool]]]


def game_graph(problem: GridProblem, limit: int, controller: Controller | None = None) -> dict[State, Rows]:
    """Every state reachable from the start by any moves, with ``graph[s]`` one row per
    robot move it may take (every move, or the controller's), each row the (next state,
    collided) of every legal obstacle reply."""
    start = initial_state(problem)
    graph: dict[State, Rows] = {}
    todo = [start]
    seen = {start}
    while todo:
        s = todo.pop()
        rows = []
        moves = range(len(problem.robot.moves)) if controller is None else (controller(s),)
        for k in moves:
            row = [tuple(step(problem, s, k, j)) for j in joint_choices(problem, s)]
            rows.append(row)
            for nxt, collided in row:
                if not collided and nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
                    if len(seen) > limit:
                        raise TooLarge(f"more than {limit} states")
        graph[s] = rows
    return graph


def _reach(problem: GridProblem, steps: int, limit: int, controller: Controller | None) -> bool:
    graph = game_graph(problem, limit, controller)
    won = {s for s in graph if s.robot == problem.robot.goal}
    for _ in range(steps):
        won |= {s for s, rows in graph.items() if any(all(not c and n in won for n, c in row) for row in rows)}
    return initial_state(problem) in won


def _safety(problem: GridProblem, limit: int, controller: Controller | None) -> bool:
    graph = game_graph(problem, limit, controller)
    win = set(graph)
    while True:
        keep = {s for s in win if any(all(not c and n in win for n, c in row) for row in graph[s])}
        if keep == win:
            return initial_state(problem) in win
        win = keep


def _exact(problem: GridProblem, steps: int, limit: int, controller: Controller | None) -> bool:
    """Backtracking over positional strategies, each checked on the runs it allows."""
    if controller is not None:
        f = _Fixed(controller)
        return outcome_of(problem, steps, f) is True
    return stationary_search(problem, steps, limit)


def stationary_search(problem: GridProblem, steps: int, limit: int, max_seconds: float | None = None) -> bool:
    """Is there a positional strategy (a map from states to moves) that wins at exactly
    ``steps``? Backtracking over the states the partial map reaches; raises
    :class:`TooLarge` past ``limit`` partial strategies or ``max_seconds``."""
    n = len(problem.robot.moves)
    nodes = [0]
    deadline = None if max_seconds is None else time.perf_counter() + max_seconds

    def search(f: dict[State, int]) -> bool:
        nodes[0] += 1
        if nodes[0] > limit:
            raise TooLarge(f"more than {limit} partial strategies")
        if deadline is not None and nodes[0] % 64 == 0 and time.perf_counter() > deadline:
            raise TooLarge(f"more than {max_seconds} s")
        r = outcome_of(problem, steps, f)
        if r is True or r is False:
            return r
        for k in range(n):
            f[r] = k
            if search(f):
                return True
            del f[r]
        return False

    return search({})


class _Fixed(dict):
    """A controller seen as a total positional strategy."""

    def __init__(self, controller: Controller) -> None:
        super().__init__()
        self.controller = controller

    def __contains__(self, s: object) -> bool:
        return True

    def __missing__(self, s: State) -> int:
        return self.controller(s)


def outcome_of(problem: GridProblem, steps: int, f: dict[State, int]) -> State | bool:
    """The exact-l outcome of a partial positional strategy ``f``: True (it wins),
    False (it loses), or the first state reached where it has no move yet."""
    frontier = {initial_state(problem)}
    for _ in range(steps):
        nxt = set()
        for s in frontier:
            if s not in f:
                return s
            for j in joint_choices(problem, s):
                out = step(problem, s, f[s], j)
                if out.collided:
                    return False
                nxt.add(out.state)
        frontier = nxt
    return all(s.robot == problem.robot.goal for s in frontier)


def _recurrence(problem: GridProblem, limit: int, controller: Controller | None) -> bool:
    """The parity game of the module docstring: robot vertices (state, priority of the
    step that led there), environment vertices (state, move)."""
    graph = game_graph(problem, limit, controller)
    start = initial_state(problem)
    owner: dict[object, int] = {LOST: 1}
    priority: dict[object, int] = {LOST: 1}
    succ: dict[object, list[object]] = {LOST: [LOST]}
    for s, rows in graph.items():
        for p in (0, 1, 2):
            v = ("robot", s, p)
            owner[v], priority[v] = 0, p
            succ[v] = [("env", s, k) for k in range(len(rows))]
        for k, row in enumerate(rows):
            v = ("env", s, k)
            owner[v], priority[v] = 1, 0
            succ[v] = [LOST if c else ("robot", nxt, _priority(problem, s, nxt)) for nxt, c in row]
    won = zielonka(set(owner), owner, priority, succ)[0]
    return ("robot", start, 0) in won


def _priority(problem: GridProblem, s: State, nxt: State) -> int:
    if nxt.robot == problem.robot.goals[s.mode]:
        return 2
    if not problem.fair or not problem.obstacles:
        return 1
    if problem.fair_count > 1:
        return 1 if nxt.fair != s.fair else 0
    return 1 if nxt.obstacles[0] != s.obstacles[0] else 0


def _attractor(vertices: set, owner: dict, succ: dict, player: int, target: Iterable) -> set:
    attr = set(target) & vertices
    changed = True
    while changed:
        changed = False
        for v in vertices - attr:
            out = [w for w in succ[v] if w in vertices]
            if (owner[v] == player and any(w in attr for w in out)) or (
                owner[v] != player and out and all(w in attr for w in out)
            ):
                attr.add(v)
                changed = True
    return attr


def zielonka(vertices: set, owner: dict, priority: dict, succ: dict) -> tuple[set, set]:
    """The winning regions (player 0, player 1) of a max-parity game on ``vertices``
    (player 0 wins a play iff the largest priority seen infinitely often is even)."""
    if not vertices:
        return set(), set()
    top = max(priority[v] for v in vertices)
    player = top % 2
    attr = _attractor(vertices, owner, succ, player, {v for v in vertices if priority[v] == top})
    sub = zielonka(vertices - attr, owner, priority, succ)
    if not sub[1 - player]:
        out = [set(), set()]
        out[player] = set(vertices)
        return out[0], out[1]
    back = _attractor(vertices, owner, succ, 1 - player, sub[1 - player])
    rest = zielonka(vertices - back, owner, priority, succ)
    out = [set(rest[0]), set(rest[1])]
    out[1 - player] |= back
    return out[0], out[1]
