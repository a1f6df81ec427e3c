"""Explicit solvers of the moving-obstacle safety game
(:mod:`plansynth.grid.syntcomp.moving_obstacle`), and a checker of their answers.

The robot wins from the greatest fixpoint ``W = nu Z. Safe & CPre(Z)``, where ``Safe``
holds the states without a collision and ``CPre(Z)`` those from which some robot move
leads, whatever the environment replies, into ``Z`` (the classical safety-game
fixpoint; the environment's attractor of the collisions is the complement; e.g. Grädel,
Thomas, Wilke, *Automata, Logics, and Infinite Games*, LNCS 2500, Ch. 2). The game is
realizable iff the initial state is in ``W``.

* :func:`solve` computes ``W`` on dense numpy arrays indexed ``[rx, ry, ox, oy, waits,
  g]``, shifting whole arrays for each of the 9 moves: fine up to 32 x 32 or so. It also
  records each losing state's *rank*, the iteration at which it left ``W``: the number
  of steps within which the environment forces a collision.
* :func:`solve_reference` is the brute-force oracle: the same fixpoint over Python sets,
  driven only by :meth:`MovingObstacle.successors` (the plain successor relation), for
  small grids.
* :func:`check_solution` checks an answer with the plain relation, independently of how
  it was found: ``W`` is safe and closed under a robot move (so the robot wins from it),
  and every ranked state of rank ``k > 0`` lets the environment answer each robot move
  with a state of smaller rank (so the environment forces a collision within ``k``
  steps). One of the two certificates covers the initial state.

>>> from plansynth.grid.syntcomp.moving_obstacle import MovingObstacle
>>> sol = solve(MovingObstacle(8, 0))
>>> sol.status.value, sol.winning_moves(sol.game.initial) != ()
('realizable', True)
>>> solve(MovingObstacle(8, 1)).status.value
'unrealizable'
>>> check_solution(solve(MovingObstacle(5, 1)))
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from plansynth.budget import Budget, BudgetExhausted, checkpoint
from plansynth.grid.result import GridStatus
from plansynth.grid.syntcomp.moving_obstacle import MOVES, Move, MovingObstacle, State

__all__ = ["SafetySolution", "solve", "solve_reference", "check_solution", "SolutionRejected"]


class SolutionRejected(AssertionError):
    """:func:`check_solution` found a state where a certificate does not hold."""


@dataclass(frozen=True)
class SafetySolution:
    """An answer of :func:`solve`: the status, the winning region and the ranks.

    ``winning`` and ``rank`` are indexed ``[rx, ry, ox, oy, waits, g]``; ``rank`` is -1
    on ``winning`` and otherwise the number of steps within which the environment forces
    a collision (0 on collisions). Both are ``None`` when the budget ran out.
    """

    game: MovingObstacle
    status: GridStatus
    winning: np.ndarray | None
    rank: np.ndarray | None
    iterations: int
    seconds: float
    message: str = ""
    counters: dict = field(default_factory=dict)

    def index(self, state: State) -> tuple[int, ...]:
        return (*state.robot, *state.obstacle, int(state.obstacle_waits), state.glitches)

    def is_winning(self, state: State) -> bool:
        if self.winning is None:
            raise ValueError("no winning region: the budget ran out")
        return bool(self.winning[self.index(state)])

    def winning_moves(self, state: State) -> tuple[Move, ...]:
        """The robot's moves from ``state`` that keep it in the winning region (the
        most permissive safety strategy); empty outside it."""
        if not self.is_winning(state):
            return ()
        return tuple(d for d in MOVES if all(self.is_winning(s) for s in self.game.successors(state, d)))


def solve(game: MovingObstacle, budget: Budget | None = None) -> SafetySolution:
    """The greatest fixpoint on numpy arrays (see the module's docstring)."""
    clock = (budget or Budget()).clock()
    m, c = game.size, game.glitches
    rx = np.arange(m).reshape(m, 1, 1, 1)
    ry = np.arange(m).reshape(1, m, 1, 1)
    ox = np.arange(m - 1).reshape(1, 1, m - 1, 1)
    oy = np.arange(m - 1).reshape(1, 1, 1, m - 1)
    collision = (ox <= rx) & (rx <= ox + 1) & (oy <= ry) & (ry <= oy + 1)
    safe = np.broadcast_to(~collision[..., None, None], (m, m, m - 1, m - 1, 2, c + 1))
    win = safe.copy()
    rank = np.where(safe, -1, 0).astype(np.int32)
    iterations = 0
    try:
        with clock.phase("the safety fixpoint"):
            while True:
                checkpoint()
                new = safe & _robot_can_move(_environment_cannot_escape(win, c), m)
                iterations += 1
                lost = win & ~new
                if not lost.any():
                    break
                rank[lost] = iterations
                win = new
    except BudgetExhausted as e:
        return SafetySolution(game, GridStatus.UNKNOWN, None, None, iterations, clock.elapsed(), str(e))
    status = GridStatus.REALIZABLE if win[(0, 0, m - 2, m - 2, 1, 0)] else GridStatus.UNREALIZABLE
    return SafetySolution(
        game,
        status,
        win,
        rank,
        iterations,
        clock.elapsed(),
        counters={"states": int(win.size), "winning_states": int(win.sum())},
    )


def _shift(a: np.ndarray, axis: int, d: int, fill: bool) -> np.ndarray:
    """``out[..., i, ...] = a[..., i + d, ...]``, ``fill`` where ``i + d`` is outside."""
    if d == 0:
        return a
    out = np.full_like(a, fill)
    n = a.shape[axis]
    src = [slice(None)] * a.ndim
    dst = [slice(None)] * a.ndim
    src[axis] = slice(d, n) if d > 0 else slice(0, n + d)
    dst[axis] = slice(0, n - d) if d > 0 else slice(-d, n)
    out[tuple(dst)] = a[tuple(src)]
    return out


def _clamped_shift(a: np.ndarray, axis: int, d: int) -> np.ndarray:
    """``out[i] = a[clamp(i + d)]`` along ``axis`` (the robot stays at the border)."""
    if d == 0:
        return a
    n = a.shape[axis]
    idx = np.clip(np.arange(n) + d, 0, n - 1)
    return np.take(a, idx, axis=axis)


def _environment_cannot_escape(win: np.ndarray, c: int) -> np.ndarray:
    """``E[r, o, waits, g]``: the robot, now at ``r``, stays in ``win`` whatever legal
    ``(o', g')`` the environment picks from ``(o, waits, g)``."""
    out = np.ones_like(win)
    for dx, dy in MOVES:
        moving = (dx, dy) != (0, 0)
        # target[r, o, g'] = win[r, o + d, waits' = moving, g'], True outside the grid
        target = _shift(_shift(win[:, :, :, :, int(moving), :], 2, dx, True), 3, dy, True)
        # the environment may set any counter g' in [g, c] ...
        incl = np.flip(np.logical_and.accumulate(np.flip(target, -1), axis=-1), -1)
        out[:, :, :, :, 0, :] &= incl
        if not moving:
            out[:, :, :, :, 1, :] &= incl
            continue
        # ... and must raise it (g' in (g, c]) for a move right after a move
        excl = np.ones_like(incl)
        excl[..., :c] = incl[..., 1:]
        out[:, :, :, :, 1, :] &= excl
    return out


def _robot_can_move(stay_safe: np.ndarray, m: int) -> np.ndarray:
    """``OR`` over the robot's moves ``d`` of ``stay_safe[clamp(r + d), ...]``."""
    out = np.zeros_like(stay_safe)
    for dx, dy in MOVES:
        out |= _clamped_shift(_clamped_shift(stay_safe, 0, dx), 1, dy)
    return out


def solve_reference(game: MovingObstacle) -> tuple[GridStatus, frozenset[State]]:
    """The same fixpoint over Python sets, from :meth:`MovingObstacle.successors` alone
    (brute force, for small grids): the status and the winning region."""
    states = list(game.states())
    win = {s for s in states if not game.is_collision(s)}
    while True:
        new = {s for s in win if any(all(t in win for t in game.successors(s, d)) for d in MOVES)}
        if new == win:
            break
        win = new
    status = GridStatus.REALIZABLE if game.initial in win else GridStatus.UNREALIZABLE
    return status, frozenset(win)


def check_solution(solution: SafetySolution, *, states: list[State] | None = None) -> None:
    """Check ``solution``'s certificates with the plain successor relation; raise
    :class:`SolutionRejected` at the first state where one fails. ``states`` limits the
    check (default: every state of the game; the initial state always)."""
    game = solution.game
    if solution.winning is None or solution.rank is None:
        raise SolutionRejected("no certificate: the solve ran out of budget")
    initial_wins = solution.is_winning(game.initial)
    if initial_wins != (solution.status is GridStatus.REALIZABLE):
        raise SolutionRejected(
            f"status {solution.status.value} but the initial state is "
            f"{'in' if initial_wins else 'outside'} the winning region"
        )
    todo = list(game.states()) if states is None else [game.initial, *states]
    for s in todo:
        k = int(solution.rank[solution.index(s)])
        if k == -1:
            if game.is_collision(s):
                raise SolutionRejected(f"{s}: a collision in the winning region")
            if not solution.winning_moves(s):
                raise SolutionRejected(f"{s}: no robot move keeps to the winning region")
        elif k == 0:
            if not game.is_collision(s):
                raise SolutionRejected(f"{s}: rank 0 but no collision")
        else:
            for d in MOVES:
                if not any(0 <= solution.rank[solution.index(t)] < k for t in game.successors(s, d)):
                    raise SolutionRejected(
                        f"{s}: rank {k}, but after robot move {d} the environment cannot reach a smaller rank"
                    )
