"""What the theory answers the lazy loop (Shoukry et al., CDC 2016, Algorithm 1, lines 8-11):
a trajectory that realises a region sequence (:class:`Feasible`), or a counterexample
(:class:`Conflict`, the clause of Theorem 5.3) that DIS-PLAN learns.

CON-PLAN (:mod:`plansynth.reach.lazy.conplan`), the transit layer
(:mod:`plansynth.reach.lazy.transit`), DIS-PLAN (:mod:`plansynth.reach.lazy.displan`)
and the mission planner all speak in these two types; they live here so that none of
those modules has to import another to name them.
"""

from __future__ import annotations

from dataclasses import dataclass

from plansynth.reach.trajectory import Trajectory

__all__ = ["Conflict", "Feasible"]


@dataclass(frozen=True)
class Conflict:
    """A set of (time, region) pairs that no trajectory realises together: the clause
    ``OR_{(t, i)} not b[t, i]`` (the counterexample of Theorem 5.3).

    The flags say which fixed ends the proof used, and therefore where the clause holds:

    * ``anchored_start`` (the proof uses x_0 = start): at the given absolute times, and
      earlier when the robot can wait at its start (``DisPlan(waits_at_start=True)``);
      otherwise at every time shift (the dynamics are time-invariant).
    * ``anchored_goal`` (the proof uses "p_L in the goal"): only for plans whose horizon
      is ``horizon`` (shifted along with the goal when not start-anchored).

    ``first_time``/``last_time``: the first and last time steps whose states the proof
    uses (they enclose the literal times); a shifted copy is only added where all of
    them exist. An empty literal set means that no plan of the given kind exists.

    ``vias`` (exact segment transitions, :mod:`plansynth.reach.lazy.segments`): literals
    (t, f, i) "the point at fraction f / :data:`~plansynth.reach.lazy.segments.DENOM`
    of the segment from p_t to p_{t+1} lies in region i"; they use the states t and
    t + 1. Only a DIS-PLAN that has such points learns a conflict with vias.
    """

    literals: tuple[tuple[int, int], ...]
    anchored_start: bool
    anchored_goal: bool
    horizon: int
    first_time: int | None = None
    last_time: int | None = None
    vias: tuple[tuple[int, int, int], ...] = ()

    def __post_init__(self) -> None:
        lits = tuple(sorted({(int(t), int(i)) for t, i in self.literals}))
        object.__setattr__(self, "literals", lits)
        vias = tuple(sorted({(int(t), int(f), int(i)) for t, f, i in self.vias}))
        object.__setattr__(self, "vias", vias)
        times = [t for t, _ in lits] + [t for t, _, _ in vias] + [t + 1 for t, _, _ in vias]
        first = min(times + ([self.first_time] if self.first_time is not None else []), default=0)
        last = max(times + ([self.last_time] if self.last_time is not None else []), default=0)
        if self.anchored_start:
            first = 0
        if self.anchored_goal:
            last = self.horizon
        object.__setattr__(self, "first_time", first)
        object.__setattr__(self, "last_time", last)
        if first < 0 or last > self.horizon:
            raise ValueError(f"conflict uses times {first}..{last} outside 0..{self.horizon}")


@dataclass(frozen=True)
class Feasible:
    """CON-PLAN realised the sequence; ``trajectory`` follows it."""

    trajectory: Trajectory
