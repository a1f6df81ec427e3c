"""The certificate of a "no": the obstacles' strategy, played against every robot move.

An unrealizable answer of the product engine comes with a positional strategy of the
obstacles (:class:`~.strategy.ObstacleReplies`, turned into joint obstacle moves by
:class:`ObstacleStrategy`). :func:`check_refutation` checks it with nothing but
:func:`~plansynth.grid.semantics.step` and the legal moves of
:mod:`plansynth.grid.semantics`: it explores every play in which the robot moves as it
likes and the obstacles answer by the strategy, and shows that the robot loses each:

* safety: the plays that avoid a collision form no cycle (so every play collides);
* reach within l, exact l: no play stands on the goal within l steps (at step l for
  ``exact``) without a collision before;
* recurrence: in the graph of the plays' collision-free steps no cycle takes a step
  onto the awaited goal, and (under ``fair``) no cycle avoiding the goal lets some
  obstacle keep its cell (the robot would win by the failed assumption). Checked on the
  strongly connected components (Tarjan 1972) of the right subgraphs.

A strategy that breaks a rule (an illegal obstacle move) or lets some play win is
rejected, with the reason; the engine then answers ``unknown``, never ``unrealizable``.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.native.product.space import ProductSpace
>>> from plansynth.grid.native.product.fixpoints import safety
>>> from plansynth.grid.native.product.strategy import ObstacleReplies
>>> p = grid_problem_from_dict({"grid": [4, 1], "objective": "safety",
...     "robot": {"start": [0, 0], "moves": ["stay", "right", "left"]},
...     "obstacles": [{"start": [3, 0], "moves": ["stay", "left", "right"], "period": 2}]})
>>> space = ProductSpace.explore(p)
>>> s = ObstacleStrategy(ObstacleReplies(safety(space)))
>>> check_refutation(p, s, None)
Certificate(valid=True, states=9, reason='every play collides')
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from plansynth.budget import Clock
from plansynth.grid.cycles import strongly_connected
from plansynth.grid.native.limits import check_clock
from plansynth.grid.native.product.exact import ExactGame
from plansynth.grid.native.product.strategy import COLLIDE, ObstacleReplies
from plansynth.grid.objective import ObjectiveKind
from plansynth.grid.problem import GridProblem
from plansynth.grid.semantics import State, initial_state, joint_choices, step

__all__ = ["ObstacleStrategy", "Certificate", "check_refutation"]

Strategy = Callable[[State, int, "int | None"], tuple[int, ...]]  # (state, robot move, step t)


@dataclass(frozen=True)
class Certificate:
    valid: bool
    states: int
    reason: str


class ObstacleStrategy:
    """The obstacles' replies as joint obstacle moves on concrete states."""

    def __init__(self, replies: ObstacleReplies | ExactGame) -> None:
        self.replies = replies
        self.space = replies.space
        self.index = {c: i for i, c in enumerate(self.space.configs)}

    def locate(self, state: State) -> tuple[int, int]:
        """(robot cell index, node) of a concrete state."""
        p = self.space.problem
        if state.phases:
            conf = tuple(zip(state.obstacles, state.phases, state.glitches, strict=True))
        else:
            conf = tuple((c, 0, 0) for c in state.obstacles)
        r = state.robot[1] * p.width + state.robot[0]
        return r, self.space.node(self.index[conf], state.mode, state.fair)

    def __call__(self, state: State, k: int, t: int | None = None) -> tuple[int, ...]:
        p = self.space.problem
        r, node = self.locate(state)
        j = self.replies.reply(r, node, k, t)
        oc, _, _ = self.space.split(node)
        want = None if j == COLLIDE else self.space.configs[self.space.succ[oc][j]]
        for joint in joint_choices(p, state):
            nxt, collided = step(p, state, k, joint)
            if want is None and collided:
                return tuple(joint)
            if want is not None and self.locate(nxt)[1] // (self.space.K * self.space.F) == self.space.succ[oc][j]:
                return tuple(joint)
        raise AssertionError(f"no joint obstacle move realizes the reply {j} in {state}")


def check_refutation(
    problem: GridProblem, strategy: Strategy, steps: int | None, clock: Clock | None = None
) -> Certificate:
    """Check that ``strategy`` defeats every robot (see the module docstring)."""
    kind = problem.objective
    if kind.bounded:
        assert steps is not None
        return _bounded(problem, strategy, steps, kind is ObjectiveKind.EXACT, clock)
    graph, bad = _plays(problem, strategy, clock)
    if bad is not None:
        return Certificate(False, len(graph), bad)
    if kind is ObjectiveKind.SAFETY:
        for comp in strongly_connected({s: [t for t, _ in out] for s, out in graph.items()}):
            if _has_inner(comp, graph):
                return Certificate(False, len(graph), "a cycle of plays without a collision")
        return Certificate(True, len(graph), "every play collides")
    goals = problem.robot.goals
    full = {s: [t for t, _ in out] for s, out in graph.items()}
    for comp in strongly_connected(full):
        members = set(comp)
        for s in comp:
            for t, _ in graph[s]:
                if t in members and t.robot == goals[s.mode]:
                    return Certificate(False, len(graph), f"a cycle of plays reaches goal {s.mode} again and again")
    if problem.fair:
        for i in range(len(problem.obstacles)):
            sub = {
                s: [t for t, moved in out if t.robot != goals[s.mode] and not moved >> i & 1]
                for s, out in graph.items()
            }
            for comp in strongly_connected(sub):
                members = set(comp)
                if any(t in members for s in comp for t in sub[s]):
                    return Certificate(
                        False,
                        len(graph),
                        f"a cycle of plays in which obstacle {i} never moves (the fairness assumption fails there)",
                    )
    return Certificate(
        True,
        len(graph),
        "no play visits the goals in turn forever" + (" while the obstacles keep moving" if problem.fair else ""),
    )


def _plays(problem: GridProblem, strategy: Strategy, clock: Clock | None):
    """Every state the plays reach, with its collision-free steps (next state, mask of
    the obstacles that changed cell); or the first illegal reply."""
    start = initial_state(problem)
    graph: dict[State, list[tuple[State, int]]] = {}
    todo = [start]
    graph[start] = []
    while todo:
        s = todo.pop()
        legal = set(joint_choices(problem, s))
        out = []
        for k in range(len(problem.robot.moves)):
            joint = strategy(s, k, None)
            if joint not in legal:
                return graph, f"the strategy's reply {joint} to move {k} in {s} is not a legal obstacle move"
            nxt, collided = step(problem, s, k, joint)
            if collided:
                continue
            moved = sum(1 << i for i, (a, b) in enumerate(zip(s.obstacles, nxt.obstacles)) if a != b)
            out.append((nxt, moved))
            if nxt not in graph:
                graph[nxt] = []
                todo.append(nxt)
        graph[s] = out
        if len(graph) % 1024 == 0:
            check_clock(clock, "checking the obstacles' strategy", f" ({len(graph)} states)")
    return graph, None


def _bounded(problem: GridProblem, strategy: Strategy, steps: int, exact: bool, clock: Clock | None) -> Certificate:
    goal = problem.robot.goal
    layer = {initial_state(problem)}
    seen = 0
    for t in range(steps + 1):
        seen += len(layer)
        for s in layer:
            if s.robot == goal and (not exact or t == steps):
                return Certificate(False, seen, f"a play stands on the goal at step {t}")
        if t == steps:
            break
        nxt_layer = set()
        for s in layer:
            legal = set(joint_choices(problem, s))
            for k in range(len(problem.robot.moves)):
                joint = strategy(s, k, t)
                if joint not in legal:
                    return Certificate(False, seen, f"the strategy's reply {joint} in {s} is not a legal move")
                nxt, collided = step(problem, s, k, joint)
                if not collided:
                    nxt_layer.add(nxt)
        layer = nxt_layer
        check_clock(clock, "checking the obstacles' strategy", f" at step {t}")
    what = "at step" if exact else "within"
    return Certificate(True, seen, f"no play stands on the goal {what} {steps} without a collision")


def _has_inner(comp: list[State], graph) -> bool:
    members = set(comp)
    return any(t in members for s in comp for t, _ in graph[s])
