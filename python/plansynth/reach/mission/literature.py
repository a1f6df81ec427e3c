"""The temporal-logic planning literature's scenarios as missions: the family
``missions-literature`` of ``plansynth bench reach``.

Each is the kind of task the optimisation-based planners of the literature benchmark
(Wolff, Topcu and Murray, ICRA 2014; Kurtz and Lin's stlpy scenarios, "Mixed-integer
programming for signal temporal logic with fewer binary variables", IEEE L-CSS 2022),
with their robot: a double integrator, dt = 1, |u| <= 0.5 per axis, |v| <= 1, starting at
rest, labels read at the samples (the sample reading those scenarios use) with a margin
of 0.1 (every visit 0.1 deep, every avoidance 0.1 away):

``keys-doors-N``    N = 1..4 doors in series along the one corridor through a thick wall,
                    each closed until its key is collected: ``!d1 U k1 & ... & F goal``
                    (the doors are as long as a step can reach, so no sample skips one);
``groups-G``        G = 2, 3 target groups, one target of each to visit:
                    ``(F a1 | F a2) & (F b1 | F b2) & ...``, among obstacles;
``dwell-D``         stay D steps in a region, then reach another:
                    ``F (G[0,D-1] t1 & F[D-1,D-1] true) & F t2`` (the window must fit the plan);
``stones-S``        cross a river S m wide on S stepping stones, every sample on land or a stone:
                    ``G (bank | s1 | ... | sS) & F far``;
``avoid-labels-K``  reach-avoid with its K obstacles written as labels: ``F goal & G !o1 & ...``.

>>> p = literature_problem("keys-doors-2")
>>> p.mission, p.reading, p.dynamics.model
('(!d1 U k1) & (!d2 U k2) & F goal', 'sample', 'double-integrator')
>>> [n for n in SCENARIOS], scenario_names("dwell")
(['keys-doors', 'groups', 'dwell', 'stones', 'avoid-labels'], ['dwell-3', 'dwell-5'])
"""

from __future__ import annotations

from plansynth.reach.dynamics import double_integrator
from plansynth.reach.geometry import Box
from plansynth.reach.problem import ReachProblem

__all__ = ["SCENARIOS", "scenario_names", "literature_problem", "literature_instances"]

#: scenario -> its instances' parameter values
SCENARIOS: dict[str, tuple[int, ...]] = {
    "keys-doors": (1, 2, 3, 4),
    "groups": (2, 3),
    "dwell": (3, 5),
    "stones": (4, 6),
    "avoid-labels": (4, 8),
}

#: the robot of every scenario: dt = 1, |u| <= 0.5, |v| <= 1
DT, INPUT_BOUND, SPEED = 1.0, 0.5, 1.0
MAX_HORIZON = 60
MARGIN = 0.1


def scenario_names(key: str) -> list[str]:
    """The instance names of a scenario (``keys-doors`` -> keys-doors-1..4)."""
    return [f"{key}-{v}" for v in SCENARIOS[key]]


def _problem(name: str, size: tuple[float, float], start, obstacles, labels, mission: str) -> ReachProblem:
    w, h = size
    return ReachProblem(
        workspace=Box((0, 0), (w, h)),
        obstacles=tuple(obstacles),
        goal=None,
        dynamics=double_integrator(2, DT),
        start=[start[0], start[1], 0.0, 0.0],
        input_bound=INPUT_BOUND,
        state_bounds=Box((0, 0, -SPEED, -SPEED), (w, h, SPEED, SPEED)),
        labels=tuple(labels),
        mission=mission,
        reading="sample",
        margin=MARGIN,
        max_horizon=MAX_HORIZON,
        name=name,
    )


def _keys_doors(n: int) -> ReachProblem:
    # a 12 x 10 world; the wall x in [5, 10] has one corridor y in [4.4, 5.6], split into n
    # doors (each at least 1.25 long: a step moves at most 1); the goal beyond the wall
    obstacles = [Box((5, 0), (10, 4.4)), Box((5, 5.6), (10, 10))]
    length = 5.0 / n
    labels = [(f"d{i + 1}", Box((5 + i * length, 4.4), (5 + (i + 1) * length, 5.6))) for i in range(n)]
    keys = [((0.5, 8.5), (1.5, 9.5)), ((0.5, 0.5), (1.5, 1.5)), ((3.2, 8.5), (4.2, 9.5)), ((3.2, 0.5), (4.2, 1.5))]
    labels += [(f"k{i + 1}", Box(*keys[i])) for i in range(n)]
    labels.append(("goal", Box((10.5, 4.2), (12, 5.8))))
    mission = " & ".join(f"(!d{i + 1} U k{i + 1})" for i in range(n)) + " & F goal"
    return _problem(f"keys-doors-{n}", (12, 10), (2.5, 5.0), obstacles, labels, mission)


def _groups(g: int) -> ReachProblem:
    obstacles = [Box((3, 3), (4, 7)), Box((6, 3), (7, 7))]
    spots = {
        "a": [((0.5, 8), (1.5, 9)), ((8.5, 0.5), (9.5, 1.5))],
        "b": [((8.5, 8.5), (9.5, 9.5)), ((4.5, 0.5), (5.5, 1.5))],
        "c": [((4.5, 8.5), (5.5, 9.5)), ((0.5, 0.5), (1.5, 1.5))],
    }
    names = "abc"[:g]
    labels = [(f"{k}{i + 1}", Box(*spots[k][i])) for k in names for i in range(2)]
    mission = " & ".join(f"(F {k}1 | F {k}2)" for k in names)
    return _problem(f"groups-{g}", (10, 10), (5.0, 5.0), obstacles, labels, mission)


def _dwell(d: int) -> ReachProblem:
    obstacles = [Box((4, 0), (5, 6))]
    labels = [("t1", Box((1, 6), (3, 8))), ("t2", Box((7.5, 1), (9, 2.5)))]
    mission = f"F (G[0,{d - 1}] t1 & F[{d - 1},{d - 1}] true) & F t2"
    return _problem(f"dwell-{d}", (10, 10), (1.0, 1.0), obstacles, labels, mission)


def _stones(s: int) -> ReachProblem:
    # a river x in [2, 2 + s] between two banks; stones of 0.5 m every metre (a step
    # moves at most 1.25 m: every sample must land on land or a stone)
    stones = [(f"s{i + 1}", Box((2.25 + i, 4), (2.75 + i, 6))) for i in range(s)]
    labels = [("bank", Box((0, 0), (2, 10))), ("far", Box((2 + s, 0), (10, 10)))] + stones
    mission = "G (bank | far | " + " | ".join(n for n, _ in stones) + ") & F far"
    return _problem(f"stones-{s}", (10, 10), (1.0, 5.0), [], labels, mission)


def _avoid_labels(k: int) -> ReachProblem:
    cells = [
        ((2, 1), (3, 7)),
        ((5, 3), (6, 10)),
        ((7.5, 0), (8.5, 6)),
        ((3.5, 8), (5, 9)),
        ((2, 8.5), (3, 10)),
        ((6.5, 7), (7.5, 8)),
        ((0, 4), (1.2, 5)),
        ((8.5, 7.5), (10, 8.5)),
    ][:k]
    labels = [(f"o{i + 1}", Box(*c)) for i, c in enumerate(cells)] + [("goal", Box((9, 1), (10, 2)))]
    mission = "F goal & " + " & ".join(f"G !o{i + 1}" for i in range(k))
    return _problem(f"avoid-labels-{k}", (10, 10), (0.5, 0.5), [], labels, mission)


_BUILD = {
    "keys-doors": _keys_doors,
    "groups": _groups,
    "dwell": _dwell,
    "stones": _stones,
    "avoid-labels": _avoid_labels,
}


def literature_problem(name: str) -> ReachProblem:
    """The instance ``name`` (``keys-doors-3``, ``groups-2``, ...)."""
    key, _, value = name.rpartition("-")
    if key not in SCENARIOS or not value.isdigit() or int(value) not in SCENARIOS[key]:
        known = ", ".join(n for k in SCENARIOS for n in scenario_names(k))
        raise ValueError(f"unknown instance {name!r} (known: {known})")
    return _BUILD[key](int(value))


def literature_instances() -> list[ReachProblem]:
    """Every instance of every scenario."""
    return [literature_problem(n) for k in SCENARIOS for n in scenario_names(k)]
