"""What the joint DIS-PLAN proposes and what the joint CON-PLAN answers (the lazy loop's
plan and counterexample types for teams; Shoukry et al., CDC 2016, Algorithm 1, lines
8-11, with the pair literals of the SMC encoding, CDC 2017, Section IV).

A :class:`TeamPlan` is a region sequence per robot and, for the pair steps that DIS-PLAN
decides (the *engaged* ones, below), the side each pair keeps during the step, and for a
robot and a moving obstacle likewise. Its literals:

* ``("at", r, t, i)``: robot r's position at step t lies in its region i (and, for t
  below the horizon, the whole segment of step t: segment safety);
* ``("side", i, j, t, k)``: during step t (samples t and t + 1), robots i < j keep side
  k of their forbidden polygon (:mod:`plansynth.reach.team.geometry`);
* ``("mside", r, o, t, k)``: robot r keeps side k of moving obstacle o during step t.

CON-PLAN answers with the team's trajectory, or with :class:`TeamConflict` values (sets
of literals that no trajectory realises together, naming the robots, pairs and steps
involved), or with :class:`Engage` lemmas: the full semantics asks every pair to keep a
side at every step, but DIS-PLAN only decides the pair steps that have been engaged; a
trajectory that breaks the separation at a step not yet engaged engages it (the clause
"some side at step t", true of every plan of the full encoding, so adding it refutes
nothing).

>>> c = TeamConflict((("at", 0, 3, 1), ("side", 0, 1, 3, 2)), start=False, goal=False, timed=False, horizon=9)
>>> c.robots, c.pairs, c.steps, c.first_time, c.last_time
((0, 1), ((0, 1),), (3,), 3, 4)
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

__all__ = ["Lit", "TeamPlan", "TeamConflict", "Engage", "literal_span"]

Lit = tuple  # ("at", r, t, i) | ("side", i, j, t, k) | ("mside", r, o, t, k)


def literal_span(lit: Lit) -> tuple[int, int]:
    """The first and last sample a literal's rows constrain (a side: both ends of its
    step; a region: its sample, and the next one when the segment rows are used)."""
    t = lit[2] if lit[0] == "at" else lit[3]
    return t, t + 1


@dataclass(frozen=True, eq=False)
class TeamPlan:
    """Region sequences ``regions[r]`` (r_0..r_L each) and the sides of the engaged pair
    steps, ``sides[(i, j, t)] = k``, and robot-obstacle steps, ``msides[(r, o, t)] = k``."""

    regions: tuple[tuple[int, ...], ...]
    sides: Mapping[tuple[int, int, int], int] = field(default_factory=dict)
    msides: Mapping[tuple[int, int, int], int] = field(default_factory=dict)

    @property
    def horizon(self) -> int:
        return len(self.regions[0]) - 1

    def __len__(self) -> int:  # the lazy loop reads a plan's horizon as len(plan) - 1
        return self.horizon + 1


@dataclass(frozen=True)
class TeamConflict:
    """Literals no trajectory of the team realises together (the clause "not all of
    them"). The flags say which fixed parts the proof used, and so where the clause holds
    (:meth:`shifts`): ``start`` (the robots' start states: at these absolute times),
    ``goal`` (the goals or the end states at ``horizon``: for plans of that horizon, or
    shifted with the end), ``timed`` (a moving obstacle's position: at these absolute
    times). Without any, the clause holds at every time shift (the dynamics are
    time-invariant). ``first_time``..``last_time``: the samples the proof uses.
    ``later_only``: the constraints tighten with time (a team under disturbances,
    :mod:`plansynth.reach.team.robust`), so the clause holds at non-negative shifts
    only."""

    literals: tuple[Lit, ...]
    start: bool
    goal: bool
    timed: bool
    horizon: int
    first_time: int | None = None
    last_time: int | None = None
    certified: bool = True
    later_only: bool = False

    def __post_init__(self) -> None:
        lits = tuple(sorted(set(self.literals)))
        object.__setattr__(self, "literals", lits)
        spans = [literal_span(lit) for lit in lits]
        first = min([a for a, _ in spans] + ([self.first_time] if self.first_time is not None else []), default=0)
        last = max([b for _, b in spans] + ([self.last_time] if self.last_time is not None else []), default=0)
        if self.start:
            first = 0
        if self.goal:
            last = self.horizon
        last = min(last, self.horizon)
        object.__setattr__(self, "first_time", first)
        object.__setattr__(self, "last_time", last)

    @property
    def robots(self) -> tuple[int, ...]:
        out: set[int] = set()
        for lit in self.literals:
            out.update((lit[1], lit[2]) if lit[0] == "side" else (lit[1],))
        return tuple(sorted(out))

    @property
    def pairs(self) -> tuple[tuple[int, int], ...]:
        return tuple(sorted({(lit[1], lit[2]) for lit in self.literals if lit[0] == "side"}))

    @property
    def steps(self) -> tuple[int, ...]:
        return tuple(sorted({lit[3] for lit in self.literals if lit[0] != "at"}))

    def shifts(self, horizon: int) -> list[int]:
        """The time shifts at which the clause holds for plans of ``horizon``."""
        if self.later_only:
            return [s for s in self._shifts(horizon) if s >= 0]
        return self._shifts(horizon)

    def _shifts(self, horizon: int) -> list[int]:
        if self.goal:
            s = horizon - self.horizon
            if (self.start or self.timed) and s != 0:
                return []
            return [s] if self.first_time + s >= 0 else []
        if self.start or self.timed:
            return [0] if self.last_time <= horizon else []
        return list(range(-self.first_time, horizon - self.last_time + 1))


@dataclass(frozen=True)
class Engage:
    """Pair steps ``(i, j, t)`` and robot-obstacle steps ``(r, o, t)`` that DIS-PLAN must
    decide from now on (a side each)."""

    pairs: tuple[tuple[int, int, int], ...] = ()
    obstacles: tuple[tuple[int, int, int], ...] = ()
