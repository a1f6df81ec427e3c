"""The documented limits of a reach-avoid problem (README, "Formats and extensions";
docs/reference/limits.md), checked at the door by :mod:`plansynth.reach.problem_checks`,
and the readings and ends a mission may name. :mod:`plansynth.reach.problem` exports them
all, as it always has.
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_MAX_HORIZON",
    "MAX_COORDINATE",
    "MAX_DT",
    "MAX_ORDER",
    "MAX_STATES",
    "MAX_HORIZON",
    "MAX_OBSTACLES",
    "MAX_VERTICES",
    "MAX_LABELS",
    "MAX_LABEL_VERTICES",
    "MISSION_READINGS",
    "MISSION_ENDS",
]

DEFAULT_MAX_HORIZON = 200

#: Documented limits (README, "Formats and extensions"), checked at the door. Every
#: coordinate (workspace, obstacles, goal, start state, state bounds) and the input bound
#: lie within +-MAX_COORDINATE, so areas, volumes and LP data stay far from overflow
#: (a workspace of 1e200 would have an infinite area); so do the entries of explicit
#: A and B matrices.
MAX_COORDINATE = 1.0e6
#: Largest time step ``dt`` of a named model.
MAX_DT = 1.0e3
#: Largest integrator-chain order (and so at most 3 * MAX_ORDER states).
MAX_ORDER = 50
#: Largest number of states (and of inputs) of explicit dynamics.
MAX_STATES = 3 * MAX_ORDER
#: Largest ``max_horizon``.
MAX_HORIZON = 10_000
#: Most obstacles, and most vertices of one polygon.
MAX_OBSTACLES = 10_000
MAX_VERTICES = 100_000
#: Most labels of a mission, and most vertices of one polygon label (the labels cut
#: the decomposition: every label edge may split every region it crosses).
MAX_LABELS = 1_000
MAX_LABEL_VERTICES = 1_000

#: How a mission reads labels and obstacles: along whole segments [p_t, p_t+1]
#: (``segment``) or at the samples p_t only (``sample``, the discrete-time literature's).
MISSION_READINGS = ("segment", "sample")
#: How a finite plan ends: at rest, its last letter held forever (``rest``), or ``free``
#: (the formula read on the finite word, as LTL on finite traces).
MISSION_ENDS = ("rest", "free")
