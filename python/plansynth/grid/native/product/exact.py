"""The paper's objective (the goal at exactly l steps) on the product game, for problems
outside the paper's model (obstacles with a block, a period or glitches; position
collisions), where the time-expanded arena of :mod:`plansynth.grid.native.arena` does
not apply.

Backward induction over the time-expanded product decides the game in which the robot
may also see the time: losing it proves that no controller exists (the obstacles'
strategy, :meth:`ExactGame.reply`, is the certificate). Winning it is necessary, not
sufficient, for a program, which sees positions only (Chasins & Newcomb, SYNT 2016,
Section 3.1): a strategy that plays, in every state, a move winning at *every* time the
state is met on the winning-forward graph is positional and wins (the read-off of
:func:`plansynth.grid.native.stationary.consistent_strategy`). When following such moves
from the start meets a state without one, the engine answers ``unknown``: the exact
question over positional strategies (the SAT encoding of
:mod:`plansynth.grid.native.stationary`) is implemented for the paper's model only.
"""

from __future__ import annotations

from plansynth.budget import Clock
from plansynth.grid.native.bitgrid import bits
from plansynth.grid.native.limits import check_clock
from plansynth.grid.native.product.fixpoints import _standing, controllable
from plansynth.grid.native.product.space import ProductSpace
from plansynth.grid.native.product.strategy import COLLIDE

__all__ = ["ExactGame"]


class ExactGame:
    """The time-expanded product game of one path length, solved."""

    def __init__(self, space: ProductSpace, steps: int, clock: Clock | None = None) -> None:
        self.space, self.steps = space, steps
        # configurations reachable at each time
        at = [{0}]
        for t in range(steps):
            at.append({oc2 for oc in at[t] for oc2 in space.succ[oc]})
        goal, standing = space.goal_mask(0), _standing(space)
        self.win: list[dict[int, int]] = [dict() for _ in range(steps + 1)]
        self.win[steps] = {oc: goal & standing for oc in at[steps]}
        self.moves: list[dict[int, list[int]]] = [dict() for _ in range(steps)]
        for t in range(steps - 1, -1, -1):
            nxt = self.win[t + 1]
            for oc in at[t]:
                mv = controllable(space, space.node(oc), lambda j, oc2, nxt=nxt: nxt.get(oc2, 0))
                self.moves[t][oc] = mv
                w = 0
                for m in mv:
                    w |= m
                self.win[t][oc] = w & standing
            check_clock(clock, "the exact game", f" at step {t}")
        r0, _ = space.start()
        self.won = bool(self.win[0].get(0, 0) >> r0 & 1)
        self.choice: dict[tuple[int, int], int] | None = self._read_off() if self.won else None

    def _read_off(self) -> dict[tuple[int, int], int] | None:
        """One move per state, winning at every time the state is met on the
        winning-forward graph, followed from the start; None if a state has none."""
        space, steps = self.space, self.steps
        fwd: list[dict[int, int]] = [{0: 1 << space.start()[0]}]
        for t in range(steps):
            nxt: dict[int, int] = {}
            for oc, rmask in fwd[t].items():
                img = 0
                for k, mk in enumerate(self.moves[t][oc]):
                    img |= space.robot.image(rmask & mk, k)
                for oc2 in space.succ[oc]:
                    nxt[oc2] = nxt.get(oc2, 0) | img
            fwd.append(nxt)
        n_moves = len(space.robot.moves)
        bad: dict[int, list[int]] = {}
        for t in range(steps):
            for oc, rmask in fwd[t].items():
                b = bad.setdefault(oc, [0] * n_moves)
                for k in range(n_moves):
                    b[k] |= rmask & ~self.moves[t][oc][k]
        choice: dict[tuple[int, int], int] = {}
        frontier = {space.start()}
        for _ in range(steps):
            nxt_states = set()
            for r, node in frontier:
                k = choice.get((r, node))
                if k is None:
                    ok = [k2 for k2 in range(n_moves) if not bad[node][k2] >> r & 1]
                    if not ok:
                        return None
                    k = choice[(r, node)] = ok[0]
                for j in range(len(space.succ[node])):
                    nxt_states.add(space.after(r, node, k, j))
            frontier = nxt_states
        return choice

    # the RobotMoves interface of the program learner
    def allowed(self, r: int, node: int) -> tuple[int, ...]:
        k = None if self.choice is None else self.choice.get((r, node))
        return () if k is None else (k,)

    def terminal(self, r: int, node: int) -> bool:
        return False

    def reply(self, r: int, node: int, k: int, t: int) -> int:
        """The obstacles' reply to robot move k in a state not winning at time t: a
        collision, or a successor configuration where the robot does not win at t + 1."""
        if self.space.collides(r, node, k):
            return COLLIDE
        end = self.space.robot_end(r, k)
        nxt = self.win[t + 1] if t + 1 <= self.steps else {}
        for j, oc2 in enumerate(self.space.succ[node]):
            if not nxt.get(oc2, 0) >> end & 1:
                return j
        raise AssertionError(f"no winning reply of the obstacles at step {t}")

    def end(self, r: int, k: int) -> int:
        return self.space.robot_end(r, k)

    def cells(self, mask: int) -> list[int]:
        return bits(mask)
