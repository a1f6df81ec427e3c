"""Strategies read off the fixpoints: the moves each winning state may play (any choice
among them wins: the robot's side), and a winning reply to every robot move in each
losing state (the obstacles' side, a positional strategy; the certificate of a "no").

The robot's *allowed* moves of a state of rank r (:class:`~.fixpoints.Solution`):

* safety: the moves that keep it in the winning set;
* reach: the moves into rank < r (or onto the goal);
* recurrence: the moves that reach the awaited goal into the winning set, or rank < r,
  or (under ``fair``) rank r on a step without the fairness progress J. A play that
  keeps its rank forever takes J finitely often, so the assumption fails.

The obstacles' reply to a robot move in a losing state: a reply that collides with the
move if there is one; else, for safety, a reply into a state of smaller rank (the
obstacles force a collision within the rank); for reach, a reply into a state of
largest rank (the goal stays out of reach); for recurrence, a reply following the ranks
of :func:`~.fixpoints.recurrence_dual`: into a lower level, or off the goal into a lower
X' round, or off the goal on a step with J into the same level.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.native.product.space import ProductSpace
>>> from plansynth.grid.native.product.fixpoints import safety
>>> king = ["stay", "up", "down", "left", "right"]
>>> p = grid_problem_from_dict({"grid": [3, 3], "objective": "safety",
...     "robot": {"start": [1, 1], "moves": king},
...     "obstacles": [{"start": [2, 2], "moves": king, "period": 2}]})
>>> space = ProductSpace.explore(p)
>>> RobotMoves(safety(space)).allowed(*space.start())   # not towards the obstacle
(0, 2, 3)
"""

from __future__ import annotations

from plansynth.grid.native.product.fixpoints import (
    Solution,
    _next_f,
    _progress,
    _recurrence_target,
    _standing,
    controllable,
)
from plansynth.grid.objective import ObjectiveKind

__all__ = ["RobotMoves", "ObstacleReplies", "COLLIDE"]

#: The obstacles' reply "collide with the robot's move".
COLLIDE = -1


class RobotMoves:
    """The allowed moves of every winning state (see the module docstring)."""

    def __init__(self, sol: Solution) -> None:
        self.sol = sol
        self.space = sol.space
        self.kind = sol.space.problem.objective
        self._cache: dict[tuple[int, int], list[int]] = {}
        self._rank: dict[tuple[int, int], int | None] = {}

    def terminal(self, r: int, node: int) -> bool:
        """Whether the play is over in this state (reach: the robot stands on the goal)."""
        return self.kind is ObjectiveKind.REACH and bool(self.space.goal_mask(0) >> r & 1)

    def rank(self, r: int, node: int) -> int | None:
        key = (r, node)
        if key not in self._rank:
            self._rank[key] = self.sol.rank(r, node)
        return self._rank[key]

    def allowed(self, r: int, node: int) -> tuple[int, ...]:
        """The moves state (r, node) may play: empty when it is not winning."""
        if not self.sol.wins(r, node):
            return ()
        if self.kind is ObjectiveKind.SAFETY:
            masks = self._masks(node, -1)
        else:
            rank = self.rank(r, node)
            if rank is None or (self.kind is ObjectiveKind.REACH and rank == 0):
                return ()
            masks = self._masks(node, rank)
        return tuple(k for k, mk in enumerate(masks) if mk >> r & 1)

    def _masks(self, node: int, rank: int) -> list[int]:
        key = (node, rank)
        got = self._cache.get(key)
        if got is not None:
            return got
        space, sol = self.space, self.sol
        oc, m, f = space.split(node)
        if self.kind is ObjectiveKind.SAFETY:
            win = sol.win
            got = controllable(
                space, node, lambda j, oc2: win[space.node(oc2, m, _next_f(space, f, space.changed[oc][j]))]
            )
        elif self.kind is ObjectiveKind.REACH:
            below, goal = sol.layers[rank - 1], space.goal_mask(0)
            got = controllable(space, node, lambda j, oc2: below[space.node(oc2)] | goal)
        else:
            below = sol.layers[rank - 1] if rank > 0 else [0] * space.n_nodes
            same = sol.layers[rank] if space.problem.fair else None
            got = controllable(space, node, _recurrence_target(space, node, sol.win, below, same))
        self._cache[key] = got
        return got


class ObstacleReplies:
    """The obstacles' positional winning strategy on the losing states (see the module
    docstring): :meth:`reply` gives, for a state and a robot move, :data:`COLLIDE` or
    the index of a successor configuration in ``space.succ[oc]``."""

    def __init__(self, sol: Solution, dual: tuple | None = None) -> None:
        self.sol, self.space = sol, sol.space
        self.kind = sol.space.problem.objective
        self.dual = dual
        self._level: dict[tuple[int, int], tuple[int, int]] = {}

    def end(self, r: int, k: int) -> int:
        return self.space.robot_end(r, k)

    def successor(self, r: int, node: int, k: int, j: int) -> tuple[int, int]:
        """The state after robot move k and reply j."""
        return self.space.after(r, node, k, j)

    def reply(self, r: int, node: int, k: int, t: int | None = None) -> int:
        """The reply to robot move k in losing state (r, node) (``t``: unused, the
        strategy is positional)."""
        if self.space.collides(r, node, k):
            return COLLIDE
        oc, _, _ = self.space.split(node)
        options = range(len(self.space.succ[oc]))
        if self.kind is ObjectiveKind.SAFETY:
            return min(options, key=lambda j: self._safety_rank(*self.successor(r, node, k, j)))
        if self.kind is ObjectiveKind.REACH:
            return max(options, key=lambda j: _inf(self.sol.rank(*self.successor(r, node, k, j))))
        return self._recurrence_reply(r, node, k, options)

    def _safety_rank(self, r: int, node: int) -> float:
        rank = self.sol.rank(r, node)  # layers: the cells removed within rounds <= i
        return float("inf") if rank is None else rank

    def _recurrence_reply(self, r: int, node: int, k: int, options) -> int:
        space = self.space
        oc, m, f = space.split(node)
        level, xr = self.level(r, node)
        best = None
        for j in options:
            r2, n2 = self.successor(r, node, k, j)
            arrive = bool(space.goal_mask(m) >> r2 & 1)
            l2, x2 = self.level(r2, n2)
            if l2 < level:
                key = (0, l2, x2)
            elif arrive or l2 > level:
                continue
            elif x2 < xr:
                key = (1, x2, 0)
            elif _progress(space, f, space.changed[oc][j]):
                key = (2, x2, 0)
            else:
                continue
            if best is None or key < best[0]:
                best = (key, j)
        if best is None:
            raise AssertionError(f"no winning reply of the obstacles in state ({r}, {node}) to move {k}")
        return best[1]

    def level(self, r: int, node: int) -> tuple[int, int]:
        """(Z' level, X' round) of a losing state; (inf, inf) for a winning one."""
        key = (r, node)
        got = self._level.get(key)
        if got is None:
            got = (10**9, 10**9)
            for i, (_, xrounds) in enumerate(self.dual[1]):
                for x, layer in enumerate(xrounds):
                    if layer[node] >> r & 1:
                        got = (i, x)
                        break
                if got[0] == i:
                    break
            self._level[key] = got
        return got

    def standing(self) -> int:
        return _standing(self.space)


def _inf(rank: int | None) -> float:
    return float("inf") if rank is None else rank
