"""The mission family of ``plansynth bench reach --family missions``: three missions on
each of the mazes 1..4 of Shoukry et al. (CDC 2016, Table I; benchmarks spec), all in
the first corridor (below the first wall, height 30/(n+1) - 0.5), double integrator:

``visit``         ``F (b & F d) & G !h``: visit b, then d, never entering the hazard h
                  between them (finite plan);
``patrol``        ``G F a & G F b``: patrol between the start area a and b forever
                  (a lasso: the robot returns to the same state);
``avoid-until``   ``!h U door``: stay out of the hall h until the door (the gap of the
                  first wall) is reached.

>>> p = mission_problem("maze-2", "patrol")
>>> p.mission, sorted(dict(p.labels))
('G F a & G F b', ['a', 'b'])
"""

from __future__ import annotations

from dataclasses import replace

from plansynth.reach.families import maze
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = ["MISSIONS", "mission_problem", "mission_instances"]

MISSIONS = ("visit", "patrol", "avoid-until")


def mission_problem(instance: str, mission: str) -> ReachProblem:
    """The maze ``maze-N`` with one of :data:`MISSIONS` (and without its goal)."""
    if not instance.startswith("maze-"):
        raise ValueError(f"mission instances are maze-1..4, got {instance!r}")
    n = int(instance.split("-")[1])
    base = maze(n)
    top = 30.0 / (n + 1) - 0.5  # the first wall's lower face
    if mission == "visit":
        labels = {"b": Box((9, 1), (11, 3)), "d": Box((20, 1), (22, 3)), "h": Box((14, 0), (16, 2.5))}
        text = "F (b & F d) & G !h"
    elif mission == "patrol":
        labels = {"a": Box((0, 0), (3, 3)), "b": Box((4, 0), (6, 3))}
        text = "G F a & G F b"
    elif mission == "avoid-until":
        labels = {"h": Box((8, 0), (22, 2.5)), "door": Box((27, top), (29, top + 1))}
        text = "!h U door"
    else:
        raise ValueError(f"unknown mission {mission!r} (known: {', '.join(MISSIONS)})")
    return replace(
        base, goal=None, labels=tuple(labels.items()), mission=text, max_horizon=60, name=f"{instance}-{mission}"
    )


def mission_instances() -> list[ReachProblem]:
    """Every (maze, mission) pair, maze-1..4 times :data:`MISSIONS`."""
    return [mission_problem(f"maze-{n}", m) for n in range(1, 5) for m in MISSIONS]
