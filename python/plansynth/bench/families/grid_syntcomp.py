"""The reactive synthesis competition's robot benchmarks as grid families (SYNTCOMP,
``SYNTCOMP/benchmarks``, CC BY 4.0), written in plansynth's grid format.

- ``moving-obstacle``: Ehlers' "Robot-on-a-grid Moving Obstacle Evasion" family
  (``aiger/moving_obstacle``), one instance per published (m, c): for each grid size m
  the largest realizable glitch count c and c + 1. The document is
  :func:`plansynth.grid.syntcomp.moving_obstacle.grid_document` (its rules, and the
  tests that check it against the benchmark's circuits); the expected answer and the
  published time are Ehlers' Table I (SLUGS, realizability only, on an AMD E-450 at
  1.6 GHz with 4 GB), :data:`~plansynth.grid.syntcomp.moving_obstacle.PUBLISHED`; 128 x 128
  was not decided there within 4 h.
- ``robot-grid`` (realizable) and ``robot-grid-fast`` (unrealizable): after the 8 x 16
  maps of ``tlsf/robot_grid/non_parametric/gr_{1..8}``: the robot serves every pickup and
  drop station pair of the map in turn, forever (a recurrence objective), while one
  obstacle roams the fenced middle corridor, at odd ticks only (``robot-grid``, as the
  ``gr_*`` maps' obstacle) or every step (``robot-grid-fast``). The documents are
  :func:`plansynth.grid.syntcomp.robot_grid_maps.map_document` (what the TLSF files
  have that they leave out is said there); the answers were found by the native engine
  (programs verified; the "no" certified by the obstacles' strategy) and by omega, which
  agree on all sixteen.

>>> [i.name for i in moving_obstacle_family([8])]
['moving-obstacle-8x8-0', 'moving-obstacle-8x8-1']
>>> [i.expected for i in moving_obstacle_family([8, 128])]
['realizable', 'unrealizable', None, None]
>>> [(i.name, i.expected) for i in robot_grid_family([2], fast=True)]
[('robot-grid-fast-2', 'unrealizable')]
"""

from __future__ import annotations

from collections.abc import Sequence

from plansynth.bench.families.grid_problems import SYNTCOMP_PROBLEMS
from plansynth.bench.families.instance import Instance

__all__ = [
    "SYNTCOMP_PROBLEMS",
    "MOVING_OBSTACLE_SIZES",
    "moving_obstacle_family",
    "robot_grid_family",
    "SLUGS_MACHINE",
    "SYNTCOMP_FAMILIES",
]

#: The families of this module (bench solvers: native and the omega peer).
SYNTCOMP_FAMILIES = ("moving-obstacle", "robot-grid", "robot-grid-fast")

#: The grid sizes of Ehlers' Table I.
MOVING_OBSTACLE_SIZES = (8, 16, 24, 32, 48, 64, 96, 128)

#: The machine of the published SLUGS times (Ehlers' description, Sect. IV).
SLUGS_MACHINE = "SLUGS (21 Feb 2014) on an AMD E-450 at 1.6 GHz with 4 GB, x86 Linux; realizability only"


def moving_obstacle_family(values: Sequence[int] | None = None) -> list[Instance]:
    """Both published instances of each grid size m in ``values`` (default: all)."""
    from plansynth.grid.syntcomp.moving_obstacle import PUBLISHED

    out = []
    for m in values if values is not None else MOVING_OBSTACLE_SIZES:
        pairs = sorted(c for (mm, c) in PUBLISHED if mm == int(m))
        if not pairs:
            raise ValueError(f"no published moving-obstacle instance of size {m}")
        for c in pairs:
            answer, seconds = PUBLISHED[(int(m), c)]
            expected = None if answer is None else ("realizable" if answer else "unrealizable")
            out.append(
                Instance(
                    "grid", "moving-obstacle", f"moving-obstacle-{m}x{m}-{c}", {"m": int(m), "c": c}, expected, seconds
                )
            )
    return out


def robot_grid_family(values: Sequence[int] | None = None, *, fast: bool = False) -> list[Instance]:
    """The maps ``gr_<v>`` for v in ``values`` (default 1..8)."""
    family = "robot-grid-fast" if fast else "robot-grid"
    expected = "unrealizable" if fast else "realizable"
    out = []
    for v in values if values is not None else range(1, 9):
        if not 1 <= int(v) <= 8:
            raise ValueError(f"robot_grid has the maps gr_1..gr_8, not gr_{v}")
        out.append(Instance("grid", family, f"{family}-{v}", {"map": int(v)}, expected))
    return out
