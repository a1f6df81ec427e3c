"""The reach-avoid benchmark families: which instances each has and the paper's Table I.

Reach families reproduce Shoukry et al. (CDC 2016, Section VI): ``maze`` (n passages,
double integrator; Table I), ``chain`` (the same mazes with integrator chains of order
k, i.e. 2k states; Figure 4), ``random-dynamics`` (the same mazes with seeded random
controllable (A, B) pairs of n states, the paper's own Figure 4 setting, from
:func:`plansynth.reach.families.random_dynamics`), and ``random`` workspaces (random
boxes and non-convex polygons, from :func:`plansynth.reach.families.random_workspace`).
``gcs-maze`` is the n x n maze of the GCS paper (Marcucci et al., Science Robotics 2023;
sizes :data:`GCS_MAZE_SIZES`), from :func:`plansynth.reach.families.gcs_maze`: the scale
family.
``missions`` holds three LTL missions per maze (:mod:`plansynth.reach.mission.families`);
``missions-literature`` the temporal-logic planning literature's scenarios (keys and
doors, target groups, dwell, stepping stones, obstacles as labels:
:mod:`plansynth.reach.mission.literature`).
``team`` holds the teams of robots and moving obstacles of
:data:`plansynth.reach.team.families.TEAM_CASES` (SMC-LTL's crossing, the corridor swap,
the room's corners, the mazes with 2 and 4 robots, antipodal crossings, the patrolled
gap, the narrow corridor).
``robust`` holds the mazes under bounded disturbances (:func:`plansynth.reach.families.windy_maze`):
each maze at growing disturbance boxes, a mission under the same disturbance, a
disturbance wider than the mazes' gaps (:mod:`plansynth.reach.robust`), and a team of two
robots under disturbances (:mod:`plansynth.reach.team.robust`).
The problems themselves are built by :mod:`plansynth.bench.families.reach_problems`.

>>> [i.name for i in reach_family("chain", [1], orders=[1, 2])]
['chain-1-k1', 'chain-1-k2']
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from plansynth.bench.families.instance import Instance

__all__ = [
    "REACH_FAMILIES",
    "MISSION_FAMILIES",
    "PAPER_TABLE_I",
    "RANDOM_DYNAMICS_STATES",
    "GCS_MAZE_SIZES",
    "ROBUST_SCALES",
    "ROBUST_TEAM",
    "reach_family",
]


# Table I of the paper (seconds): discrete abstraction, DIS-PLAN, CON-PLAN, RRT, LTL OPT.
PAPER_TABLE_I: dict[int, dict[str, float | str]] = {
    1: {"abstraction": 1.998, "dis-plan": 0.136, "con-plan": 0.254, "rrt": 10.44, "ltl-opt": "> 7200"},
    2: {"abstraction": 7.146, "dis-plan": 1.129, "con-plan": 0.929, "rrt": 122.3, "ltl-opt": "time out"},
    3: {"abstraction": 19.33, "dis-plan": 3.650, "con-plan": 1.005, "rrt": 423.7, "ltl-opt": "time out"},
    4: {"abstraction": 43.10, "dis-plan": 4.091, "con-plan": 1.920, "rrt": 1002, "ltl-opt": "time out"},
}

REACH_FAMILIES = (
    "maze",
    "chain",
    "random",
    "random-dynamics",
    "missions",
    "missions-literature",
    "gcs-maze",
    "robust",
    "team",
)
#: The families whose problems have an LTL mission (planned by the mission planners only).
MISSION_FAMILIES = ("missions", "missions-literature")
#: the robust family's disturbance scales (times WINDY_BOX: 2 cm and 5 cm/s per step at 1)
ROBUST_SCALES = (1.0, 2.0, 4.0)
#: its mission under disturbance
ROBUST_MISSION = (2, "patrol")
#: the value that names its team (planned by the team planners; only when asked for)
ROBUST_TEAM = "windy-swap"
RANDOM_DYNAMICS_STATES = (4, 10, 20, 50)
#: The scale family's maze sides (cells): the GCS paper's 50 x 50 and sizes around it.
GCS_MAZE_SIZES = (10, 20, 30, 50, 70, 100)


def reach_family(
    name: str,
    values: Sequence[Any] | None = None,
    *,
    orders: Sequence[int] = (1, 2, 3, 5),
    states: Sequence[int] = RANDOM_DYNAMICS_STATES,
    seed: int = 0,
) -> list[Instance]:
    """Instances of reach family ``name``.

    ``maze``: values are passage counts (default 1..4). ``chain``: values are passage
    counts, crossed with ``orders`` (the chain order k; 2k states). ``random``: values
    are seeds (default 0..4). ``random-dynamics``: values are passage counts (default
    1..4), crossed with ``states`` (n, default 4, 10, 20, 50), random (A, B) drawn with
    ``seed`` (:func:`plansynth.reach.families.random_dynamics` says how).
    ``missions``: values are passage counts, each with the
    three missions of :mod:`plansynth.reach.mission.families`. ``gcs-maze``: values are
    maze sizes n (default :data:`GCS_MAZE_SIZES`), the n x n mazes of the GCS paper
    (:func:`plansynth.reach.families.gcs_maze`: seed 4, walls 0.1 thick, 100 extra
    knock-downs at n = 50 as in its notebook; the double integrator with dt 0.5 s,
    |u| <= 1, |v| <= 1 per axis, from the centre of cell (0, 0) at rest to a 0.4 box at
    the centre of cell (n-1, n-1)). ``team``: values are case names
    (:data:`plansynth.reach.team.families.TEAM_CASES`, default all). ``robust``: values are passage counts (default
    1..4), each maze at the disturbance scales of :data:`ROBUST_SCALES`, with the mission
    of :data:`ROBUST_MISSION` and maze-1 with a gap narrower than the disturbance's tube
    (:func:`plansynth.reach.families.narrow_maze`: no robust plan, expected infeasible);
    the value :data:`ROBUST_TEAM` adds the team of :func:`plansynth.reach.team.families.windy_swap`
    (two robots under disturbances, for the team planners).
    """
    out = []
    if name == "maze":
        for n in values or [1, 2, 3, 4]:
            tot = sum(
                float(v) for k, v in PAPER_TABLE_I[int(n)].items() if k in ("abstraction", "dis-plan", "con-plan")
            )
            out.append(
                Instance("reach", "maze", f"maze-{n}", {"n": int(n)}, "found", tot if int(n) in PAPER_TABLE_I else None)
            )
    elif name == "chain":
        for n in values or [1, 2, 3, 4]:
            for k in orders:
                out.append(Instance("reach", "chain", f"chain-{n}-k{k}", {"n": int(n), "k": int(k)}, "found"))
    elif name == "random-dynamics":
        for n in values or [1, 2, 3, 4]:
            for k in states:
                out.append(
                    Instance(
                        "reach",
                        "random-dynamics",
                        f"rdyn-{n}-n{k}-s{seed}",
                        {"n": int(n), "states": int(k), "seed": int(seed)},
                        None,
                    )
                )
    elif name == "random":
        for s in values or [0, 1, 2, 3, 4]:
            out.append(Instance("reach", "random", f"random-{s}", {"seed": int(s)}, None))
    elif name == "missions":  # LTL missions: three per maze, values are passage counts
        from plansynth.reach.mission.families import MISSIONS

        for n in values or [1, 2, 3, 4]:
            if isinstance(n, bool) or not isinstance(n, int) or n not in (1, 2, 3, 4):
                raise ValueError(f"the mission mazes are maze-1..4, got {n!r}")
            for m in MISSIONS:
                out.append(Instance("reach", "missions", f"maze-{n}-{m}", {"n": int(n), "mission": m}, "found"))
    elif name == "missions-literature":  # the temporal-logic planning literature's scenarios
        from plansynth.reach.mission.literature import SCENARIOS, scenario_names

        for key in values or list(SCENARIOS):
            if key not in SCENARIOS:
                raise ValueError(f"unknown scenario {key!r} (known: {', '.join(SCENARIOS)})")
            for inst in scenario_names(key):
                out.append(Instance("reach", "missions-literature", inst, {"name": inst}, None))
    elif name == "robust":  # values are passage counts, or ROBUST_TEAM for the team
        from plansynth.reach.families import windy_name

        mazes = None if values is None else [v for v in values if v != ROBUST_TEAM]
        if mazes is None or mazes:
            for scale in ROBUST_SCALES:
                for n in mazes or [1, 2, 3, 4]:
                    out.append(
                        Instance(
                            "reach",
                            "robust",
                            windy_name(f"maze-{n}", scale),
                            {"n": int(n), "scale": float(scale)},
                            "found" if scale == 1 else None,
                        )
                    )
            n, mission = ROBUST_MISSION
            if not mazes or n in mazes:
                out.append(
                    Instance(
                        "reach",
                        "robust",
                        f"maze-{n}-{mission}-windy",
                        {"n": n, "scale": 1.0, "mission": mission},
                        "found",
                    )
                )
            if not mazes or 1 in mazes:  # maze-1 with a 1 m gap: the disturbance is wider than the passage
                out.append(
                    Instance(
                        "reach",
                        "robust",
                        "maze-1-narrow-windy-x4",
                        {"n": 1, "scale": 4.0, "narrow": True},
                        "infeasible",
                    )
                )
        if values is not None and ROBUST_TEAM in values:  # two robots under disturbances: the team planners
            out.append(Instance("reach", "robust", "corridor-swap-windy", {"team": ROBUST_TEAM, "scale": 1.0}, "found"))
    elif name == "gcs-maze":
        for n in values or GCS_MAZE_SIZES:
            out.append(Instance("reach", "gcs-maze", f"gcs-maze-{n}", {"n": int(n)}, "found"))
    elif name == "team":  # teams of robots and moving obstacles: values are case names
        from plansynth.reach.team.families import INFEASIBLE_CASES, TEAM_CASES

        for case in values or list(TEAM_CASES):
            if case not in TEAM_CASES:
                raise KeyError(f"unknown team case {case!r}; choose from {', '.join(TEAM_CASES)}")
            expected = "infeasible" if case in INFEASIBLE_CASES else "found"
            out.append(Instance("reach", "team", case, {"case": case}, expected))
    else:
        raise KeyError(f"unknown reach family {name!r}; choose one of {', '.join(REACH_FAMILIES)}")
    return out
