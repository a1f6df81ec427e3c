"""The certificate of a "no" of the compiled safety game as the refutation the engine
reports: what ``explain`` prints and plays.

The core has checked the obstacles' rank strategy from the start (every robot move meets
a colliding reply or a reply of smaller rank, so every play collides within the start's
rank). :class:`CompiledRefutation` offers it as a strategy on concrete states
(:meth:`strategy`), for :func:`~plansynth.grid.native.product.witness.product_play`.
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.grid.native.product.compiled import CompiledSafety
from plansynth.grid.semantics import State, joint_choices, step

__all__ = ["CompiledRefutation"]


@dataclass
class CompiledRefutation:
    game: CompiledSafety
    states: int
    kind: str = "game"
    steps: None = None

    @property
    def detail(self) -> str:
        return "the obstacles force a collision"

    @property
    def reason(self) -> str:
        return f"every play collides within {self.game.core.rank(*self.game.start)} steps, {self.states} states checked"

    @property
    def certificate(self):
        from plansynth.grid.native.product.certify import Certificate

        return Certificate(True, self.states, self.reason)

    @property
    def strategy(self):
        return _RankStrategy(self.game)


class _RankStrategy:
    """The rank strategy on concrete states: a colliding reply, else a reply into the
    state of smallest rank."""

    def __init__(self, game: CompiledSafety) -> None:
        self.game = game
        self.index = {game.config_key(oc): oc for oc in range(game.n_configs)}

    def __call__(self, state: State, k: int, t: int | None = None) -> tuple[int, ...]:
        p = self.game.problem
        best = None
        for joint in joint_choices(p, state):
            nxt, collided = step(p, state, k, joint)
            if collided:
                return tuple(joint)
            key = tuple(
                zip(
                    nxt.obstacles,
                    nxt.phases or (0,) * len(nxt.obstacles),
                    nxt.glitches or (0,) * len(nxt.obstacles),
                    strict=True,
                )
            )
            oc = self.index[key]
            r = nxt.robot[1] * p.width + nxt.robot[0]
            rank = self.game.core.rank(oc, r) or 10**9
            if best is None or rank < best[0]:
                best = (rank, tuple(joint))
        return best[1]
