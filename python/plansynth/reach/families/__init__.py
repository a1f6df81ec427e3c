"""Benchmark families and the example problems (Shoukry et al., CDC 2016, Section VI;
project spec "Benchmark families from the papers"), one module per family.

* :func:`maze` (``paper_maze``) -- the n-passage maze of Section VI (Table I) with the double integrator,
  or with an integrator chain of any order (the scalability study, Figure 4).
* :func:`cluttered` (``rooms``) -- non-convex polygon obstacles (an example beyond the paper).
* :func:`dubins_example` (``rooms``) -- Section VI-A: a unicycle through its feedback-linearised
  form, a double integrator on (x, y) (see :mod:`plansynth.reach.dubins`).
* :func:`random_workspace` (``random_rooms``) -- small random workspaces for property tests.
* :func:`random_dynamics` (``random_robots``) -- the mazes with seeded random controllable (A, B) pairs of
  n states (the paper's Figure 4 setting: random A and B at n = 50).
* :func:`gcs_maze` (``gcs``) -- the n x n mazes of the GCS paper (Marcucci et al., Science
  Robotics 2023), generated as its code does.
* :func:`windy_maze`, :func:`narrow_maze` (``windy``) -- the mazes under a bounded
  disturbance (robust planning, :mod:`plansynth.reach.robust`), and one whose
  disturbance is wider than its gap.

``python -m plansynth.reach.families DIR`` (re)writes the example files of
``examples/reach`` (``example_files``: :func:`examples`, :func:`write_examples`).

>>> p = maze(2)
>>> len(p.obstacles), p.goal, p.start.tolist()
(4, Box(lo=(27.0, 27.0), hi=(29.0, 29.0)), [1.0, 1.0, 0.0, 0.0])
"""

from plansynth.reach.families.example_files import examples, main, write_examples
from plansynth.reach.families.gcs import GCS_MAZE_KNOCK_DOWNS, GCS_MAZE_WALL, gcs_maze
from plansynth.reach.families.paper_maze import DERIVATIVE_BOUND, LEFT_GAP, MAZE_SIZE, RIGHT_GAP, WALL_THICKNESS, maze
from plansynth.reach.families.random_robots import RANDOM_DYNAMICS_MAX_HORIZON, random_dynamics
from plansynth.reach.families.random_rooms import random_workspace
from plansynth.reach.families.rooms import cluttered, dubins_example
from plansynth.reach.families.windy import (
    NARROW_GAP,
    STORM_SCALE,
    WINDY_BOX,
    narrow_maze,
    windy_box,
    windy_maze,
    windy_name,
)

__all__ = [
    "maze",
    "gcs_maze",
    "cluttered",
    "dubins_example",
    "random_workspace",
    "random_dynamics",
    "windy_maze",
    "windy_box",
    "windy_name",
    "narrow_maze",
    "NARROW_GAP",
    "WINDY_BOX",
    "STORM_SCALE",
    "examples",
    "write_examples",
    "main",
    "MAZE_SIZE",
    "WALL_THICKNESS",
    "RIGHT_GAP",
    "LEFT_GAP",
    "DERIVATIVE_BOUND",
    "GCS_MAZE_WALL",
    "GCS_MAZE_KNOCK_DOWNS",
    "RANDOM_DYNAMICS_MAX_HORIZON",
]
