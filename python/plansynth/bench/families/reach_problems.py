"""The reach-avoid benchmark problems as code: each family's problem from its parameters.

Thin builders over :mod:`plansynth.reach.families` (the mazes of Shoukry et al., CDC 2016,
Section VI, their integrator chains and random dynamics, random workspaces, the GCS
paper's mazes, the mazes under disturbances) and :mod:`plansynth.reach.mission.families`
(LTL missions on the mazes);
:data:`REACH_PROBLEMS` names them by family. Which instances a family has is
:mod:`plansynth.bench.families.reach`.

>>> REACH_PROBLEMS["chain"](n=1, k=3).dynamics.n_states
6
"""

from __future__ import annotations

from typing import Any

__all__ = ["REACH_PROBLEMS"]


def _maze(n: int) -> Any:
    from plansynth.reach.families import maze

    return maze(n, 2)


def _chain(n: int, k: int) -> Any:
    from plansynth.reach.families import maze

    return maze(n, k)


def _random(seed: int, obstacles: int = 6) -> Any:
    from plansynth.reach.families import random_workspace

    return random_workspace(seed, obstacles)


def _random_dynamics(n: int, states: int, seed: int = 0) -> Any:
    from plansynth.reach.families import random_dynamics

    return random_dynamics(n, states, seed)


def _gcs_maze(n: int) -> Any:
    from plansynth.reach.families import gcs_maze

    return gcs_maze(n)


def _missions(n: int, mission: str) -> Any:
    from plansynth.reach.mission.families import mission_problem

    return mission_problem(f"maze-{n}", mission)


def _team(case: str) -> Any:
    from plansynth.reach.team.families import team_case

    return team_case(case)


def _missions_literature(name: str) -> Any:
    from plansynth.reach.mission.literature import literature_problem

    return literature_problem(name)


def _robust(
    n: int | None = None, scale: float = 1.0, mission: str | None = None, narrow: bool = False, team: str | None = None
) -> Any:
    from dataclasses import replace

    from plansynth.reach.families import narrow_maze, windy_box, windy_maze, windy_name

    if team is not None:  # a team under disturbances (the only one: the windy corridor swap)
        from plansynth.reach.team.families import windy_swap

        if team != "windy-swap":
            raise ValueError(f"unknown robust team {team!r} (known: windy-swap)")
        return windy_swap(scale)
    assert n is not None
    if narrow:
        return narrow_maze(scale)
    if mission is None:
        return windy_maze(n, scale)
    from plansynth.reach.mission.families import mission_problem

    p = mission_problem(f"maze-{n}", mission)
    return replace(p, disturbance=windy_box(scale), name=windy_name(p.name, scale))


REACH_PROBLEMS: dict[str, Any] = {
    "missions-literature": _missions_literature,
    "maze": _maze,
    "chain": _chain,
    "random": _random,
    "random-dynamics": _random_dynamics,
    "missions": _missions,
    "gcs-maze": _gcs_maze,
    "team": _team,
    "robust": _robust,
}
