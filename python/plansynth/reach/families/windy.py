"""The mazes of Shoukry et al. (CDC 2016, Section VI) under a bounded disturbance: the
problems of the robust family (beyond the paper, whose Section VII leaves bounded disturbances as
future work).

``x' = A x + B u + w`` with ``|w| <= scale * WINDY_BOX`` per component: about 2 cm of
position and 5 cm/s of velocity per 0.5 s step at scale 1 (a gust of wind), closed by
the default feedback design (discrete LQR, Q = I, R = I; :mod:`plansynth.reach.robust`).
The tube of that loop is about 0.19 m wide at scale 1 and grows in proportion: the 2 m
gaps of the mazes (and the 2 m goal) close near scale 5.4. :func:`narrow_maze` is maze-1 with a 1 m gap under a disturbance whose
tube fits the goal but not the gap: the disturbance is wider than the passage, and no
robust plan exists (for this feedback design).

>>> p = windy_maze(3)
>>> p.name, p.disturbance.box
('maze-3-windy', (0.02, 0.02, 0.05, 0.05))
>>> windy_maze(1, scale=8).name
'maze-1-windy-x8'
"""

from __future__ import annotations

from dataclasses import replace

from plansynth.reach.disturbance import Disturbance
from plansynth.reach.families.paper_maze import maze
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = ["windy_maze", "windy_box", "windy_name", "narrow_maze", "WINDY_BOX", "STORM_SCALE", "NARROW_GAP"]

#: |w| per state component (x, y, vx, vy) at scale 1
WINDY_BOX = (0.02, 0.02, 0.05, 0.05)
#: the scale of :func:`narrow_maze`'s disturbance: its tube (1.5 m wide) fits the 2 m goal
#: but not the 1 m gap
STORM_SCALE = 4.0
#: the gap of :func:`narrow_maze`
NARROW_GAP = (27.5, 28.5)


def windy_name(base: str, scale: float) -> str:
    """The name of a problem ``base`` under the windy disturbance at ``scale``."""
    return f"{base}-windy" if scale == 1 else f"{base}-windy-x{scale:g}"


def windy_box(scale: float = 1.0) -> Disturbance:
    """``|w| <= scale * WINDY_BOX`` with the default feedback design."""
    return Disturbance(box=tuple(round(scale * v, 12) for v in WINDY_BOX))


def windy_maze(n_passages: int, scale: float = 1.0) -> ReachProblem:
    """The maze with ``n_passages`` walls under ``|w| <= scale * WINDY_BOX``."""
    p = maze(n_passages)
    return replace(p, disturbance=windy_box(scale), name=windy_name(p.name, scale))


def narrow_maze(scale: float = STORM_SCALE) -> ReachProblem:
    """Maze-1 with its gap narrowed to 1 m (:data:`NARROW_GAP`) under ``|w| <= scale *
    WINDY_BOX``: at :data:`STORM_SCALE` the tube is wider than the gap, not than the goal.

    >>> p = narrow_maze()
    >>> p.name, p.obstacles[0].hi[0], p.obstacles[1].lo[0]
    ('maze-1-narrow-windy-x4', 27.5, 28.5)
    """
    p = maze(1)
    wall = p.obstacles
    lo, hi = NARROW_GAP
    narrowed = (Box(wall[0].lo, (lo, wall[0].hi[1])), Box((hi, wall[1].lo[1]), wall[1].hi))
    return replace(p, obstacles=narrowed, disturbance=windy_box(scale), name=windy_name("maze-1-narrow", scale))
