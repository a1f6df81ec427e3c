"""What a grid controller must achieve (the problem file's ``objective``), how collisions
are counted (``collision``) and when a slow obstacle may move (``schedule``).

The paper's problems (Chasins & Newcomb, SYNT 2016, Section 3.1) have one objective:
stand on the goal after exactly l steps without a collision before. A file without the
keys below means exactly that. plansynth adds three objectives, each defined on the
plays of the game of :mod:`plansynth.grid.semantics` (the robot picks a move seeing the
state, then every obstacle picks one of its legal moves):

``exact`` (the default)
    no collision in steps 0..l-1 and the robot on the goal after step l-1.
``reach``
    the robot *first* stands on the goal at some time t <= l (time 0 included) without
    a collision before; the play ends there. Monotone in l, so a search over l gives the
    smallest bound.
``safety``
    no collision in any step, forever (no goal; the safety games of Thomas, "On the
    synthesis of strategies in infinite games", STACS 1995).
``recurrence``
    no collision in any step, and the goals g0, g1, ..., g(k-1) visited in this order
    infinitely often. The game carries a *mode* m, the index of the next goal: m = 0 at
    the start, and m becomes (m + 1) mod k after each step that ends on g_m (its update
    is fixed, not chosen by the controller). The robot wins iff the mode changes
    infinitely often (a Büchi condition on the product with the mode, Thomas 1995). With
    ``fair: true`` the objective is the GR(1) implication of Bloem, Jobstmann, Piterman,
    Pnueli and Sa'ar ("Synthesis of Reactive(1) designs", JCSS 78(3), 2012): the robot
    must never collide, and must change the mode infinitely often *if* every obstacle
    changes its cell infinitely often. A play on which some obstacle eventually stays
    put forever is then won by the robot as long as it never collides (GR(1)'s strict
    reading: safety is never excused, liveness is). With two or more obstacles the game
    also carries a fairness counter f (the obstacle waited for): f becomes
    (f + 1) mod n after a step in which obstacle f changed its cell; every obstacle
    changes cell infinitely often iff f advances infinitely often, so one assumption
    suffices and positional strategies win (the counter is the usual reduction of a
    conjunction of Büchi assumptions to one).

The controller reads the mode as the input ``m`` (when there are two or more goals)
and the fairness counter as ``f`` (with two or more obstacles under ``fair``); with
them the state it sees is the whole state of the game, so positional strategies suffice
for safety, recurrence and reach (the games are positionally determined), while for
``exact`` a program that does not see the time may still lose a won game (Section 3.1:
the paper's controllers see positions only).

>>> ObjectiveKind("recurrence").bounded, ObjectiveKind.EXACT.bounded
(False, True)
>>> CollisionRule("position").value
'position'
"""

from __future__ import annotations

from enum import Enum

__all__ = ["ObjectiveKind", "CollisionRule", "Schedule"]


class ObjectiveKind(str, Enum):
    """The problem file's ``objective`` (see the module docstring)."""

    EXACT = "exact"
    REACH = "reach"
    SAFETY = "safety"
    RECURRENCE = "recurrence"

    @property
    def bounded(self) -> bool:
        """Whether the objective is about a path length l (``exact``, ``reach``)."""
        return self in (ObjectiveKind.EXACT, ObjectiveKind.REACH)

    @property
    def has_goal(self) -> bool:
        """Whether the robot has one ``goal`` (``exact``, ``reach``)."""
        return self.bounded

    def __bool__(self) -> bool:
        raise TypeError("ObjectiveKind has no truth value; compare with ObjectiveKind.EXACT etc.")


class CollisionRule(str, Enum):
    """The problem file's ``collision``.

    ``sweep`` (the default, the shared format's rule): the robot collides in a step if a
    cell it sweeps is swept by an obstacle in the same step. ``position``: only the
    cells after the step count: the robot collides if its cell lies in an obstacle's
    block after the step (SYNTCOMP's moving-obstacle family, Ehlers' guarantee 1).
    Walls collide the same way under both: a robot move that sweeps a wall.
    """

    SWEEP = "sweep"
    POSITION = "position"

    def __bool__(self) -> bool:
        raise TypeError("CollisionRule has no truth value")


class Schedule(str, Enum):
    """When an obstacle of ``period`` k > 1 may change its cell without a glitch.

    Each such obstacle has a counter p in 0..k-1, the steps it must still wait (the
    controller reads it as ``o<i>p``), starting at ``phase`` (default k - 1: the robot
    moves first). In a step it may change cell if p = 0, or if p > 0 by spending one of
    its ``glitches`` (the controller reads the glitches left as ``o<i>g``).

    ``rest``: after a step in which it changed cell p becomes k - 1, else max(p - 1, 0):
    at most one change every k steps, with no fixed phase (Ehlers' moving obstacle: "at
    most every second step"). ``fixed``: p becomes k - 1 after a step that began with
    p = 0, else p - 1, whether or not it moved: it may change cell only at the steps t
    with t = phase (mod k) (SYNTCOMP's robot_grid obstacle, which moves at odd ticks).
    A glitch leaves p as the schedule says for a step without a change (``fixed``) or
    sets it to k - 1 (``rest``).
    """

    REST = "rest"
    FIXED = "fixed"

    def __bool__(self) -> bool:
        raise TypeError("Schedule has no truth value")
