"""What the verifier answers: a status, and on a loss a run that shows it.

``wins`` and ``loses`` are exact; ``unknown`` means the budget ran out (STYLE.md,
points 3 and 4), and is never read as ``loses``.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from plansynth.grid.semantics import State

__all__ = ["VerifyStatus", "VerdictUnknown", "Counterexample", "Verdict"]


class VerifyStatus(str, Enum):
    """The verifier's answer. ``unknown`` (the budget ran out) is never ``loses``.

    There is deliberately no truthiness.
    """

    WINS = "wins"
    LOSES = "loses"
    UNKNOWN = "unknown"

    def __bool__(self) -> bool:
        raise TypeError("VerifyStatus has no truth value; compare with VerifyStatus.WINS etc.")


class VerdictUnknown(Exception):
    """Raised by :attr:`Verdict.wins` on an ``unknown`` verdict: it neither wins nor loses."""


@dataclass(frozen=True)
class Counterexample:
    """A run on which the controller loses.

    ``states[t]`` is the state at the start of step t (``states[0]`` the initial one,
    the last one the state after the losing step); ``robot_moves[t]`` and
    ``obstacle_moves[t]`` are the moves taken at step t. ``reason`` says why it loses.
    ``loop`` (recurrence objectives): the run is a lasso, the last state equals
    ``states[loop]`` and the steps from there repeat forever.
    """

    obstacle_moves: tuple[tuple[int, ...], ...]
    states: tuple[State, ...]
    robot_moves: tuple[int, ...]
    reason: str
    loop: int | None = None


@dataclass(frozen=True)
class Verdict:
    """The verifier's answer for one program and one path length.

    ``status`` is exact when it is ``wins`` or ``loses``; ``unknown`` only when a budget
    ran out, with ``phase`` (where) and ``reason`` ("time" or "memory", with figures) in
    ``message``. When it loses, ``counterexample`` shows a losing run. A win proved by an
    inductive invariant instead of a search says so in ``message``.
    ``states_explored`` counts the (t, robot, read obstacles) nodes expanded.
    """

    status: VerifyStatus
    steps: int | None
    counterexample: Counterexample | None
    states_explored: int
    seconds: float
    phase: str | None = None
    message: str | None = None

    @property
    def wins(self) -> bool:
        """True if the controller wins, False if it loses; :class:`VerdictUnknown` if the
        budget ran out (check ``status`` first when a budget was given)."""
        if self.status is VerifyStatus.UNKNOWN:
            raise VerdictUnknown(self.message or "the verifier gave no answer")
        return self.status is VerifyStatus.WINS
