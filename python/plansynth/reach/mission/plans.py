"""What the lazy loop passes between the two halves for a mission: the plan DIS-PLAN
proposes (:class:`MissionPlan`, the region sequence and its loop) and what the
mission's theory answers about the loop (Shoukry et al., CDC 2016, Algorithm 1,
lines 8-11, with the loop selectors of Biere et al.'s BMC encoding, LMCS 2006).

Besides CON-PLAN's :class:`~plansynth.reach.lazy.conflict.Conflict`, the theory
(:mod:`plansynth.reach.mission.theory`) may refute a plan's loop
(:class:`LoopConflict`: no periodic trajectory with x_L = x_k realises these literals)
or its end (:class:`StayConflict`: the finite plan cannot end at rest); the mission's
DIS-PLAN (:meth:`~plansynth.reach.mission.bmc.MissionDisPlan.learn`) blocks each with
its loop or stay selector.

>>> plan = MissionPlan((0, 1, 2, 1), loop_start=1)
>>> plan.horizon, len(plan), plan.semantics
(3, 4, 'lasso')
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["MissionPlan", "LoopConflict", "StayConflict"]


@dataclass(frozen=True)
class MissionPlan:
    """A region sequence r_0..r_L and its loop: ``loop_start`` k with x_L = x_k (a lasso)
    or None (a finite plan: the last position repeats). Its length is that of the
    sequence (L + 1 positions), as for the region tuple of a reach-avoid plan."""

    regions: tuple[int, ...]
    loop_start: int | None

    @property
    def horizon(self) -> int:
        return len(self.regions) - 1

    @property
    def semantics(self) -> str:
        return "finite" if self.loop_start is None else "lasso"

    def __len__(self) -> int:
        return len(self.regions)


@dataclass(frozen=True)
class LoopConflict:
    """No trajectory realises these (time, region) literals together with the loop
    closure x_L = x_k (k = ``loop_start``, L = ``horizon``). ``shifted``: the proof used
    neither the start nor a step before k, so it holds for the same loop at every horizon
    and, the loop being a cycle, at every rotation."""

    literals: tuple[tuple[int, int], ...]
    loop_start: int
    horizon: int
    shifted: bool


@dataclass(frozen=True)
class StayConflict:
    """A finite plan of ``horizon`` steps with these (time, region) literals cannot end
    at rest (no admissible input keeps x_L where it is, which the finite reading needs)."""

    literals: tuple[tuple[int, int], ...]
    horizon: int
