"""The grid benchmark families: which instances each has, their known answers and the
paper's times.

Grid families reproduce Chasins & Newcomb (SYNT 2016, Section 4.1; the spec's
``benchmarks.md``): ``figure1``, ``depth``, ``steps``, ``obstacles``, ``dimensions``.
In those the obstacles rarely come near the robot, so three reactive families of our
own complement them, with answers known by construction:

- ``crossing`` (realizable): the robot must cross a one-lane road at a zebra crossing
  (walls elsewhere) while N cars drive right at speed 1 or 2 (adversarially chosen,
  never stopping). A controller that goes straight is hit; one that waits at the kerb
  until every car has passed the crossing wins, and must read the cars' positions.
- ``crossing-stall`` (unrealizable): the same road, but cars may stop (moves ``stay``
  and ``right``): a car can park just left of the robot's column and shadow it, and the
  road has an end, so no controller crosses safely at any length.
- ``patrol``: a guard walks up and down (it must move every step) in the column the
  robot has to cross; the robot can also sprint two cells vertically. Crossing at row r
  is safe only when the guard is 3 or more rows away, and the guard keeps within 2 rows
  of whichever border row the robot heads for as long as it can cover the distance:
  unrealizable for heights up to 13 (5 and 7 here). At height 15 the robot outruns the
  guard: realizable at l = 24 (found by the native engine, controller independently
  verified; cvc5 finds nothing in minutes), a hard reactive instance.
- ``patrol-walk`` (unrealizable): the same without the sprint.
- ``lanes`` (realizable): a corridor crossed by 1-3 lanes of cars (alternating
  directions, one or two cells per step, never stopping); the controller reads the cars
  and waits for each one. ``lanes-rush`` (unrealizable): the same at the shortest
  length, with no time to wait (both answers found by the native engine; every
  realizable one is checked by the independent verifier in the sweep).
- ``doors`` (realizable), ``doors-rush`` and ``doors-jam`` (unrealizable): doors that
  close, a corridor through 1-3 walls whose doorways panels slide through (see
  :func:`~plansynth.bench.families.grid_problems._doors`); timed through the command line, like the shared suite.
- ``patrols`` (realizable) and ``patrols-walk`` (unrealizable): guards walking back and
  forth along 1-3 roads that the robot crosses at one of two zebras (see
  :func:`~plansynth.bench.families.grid_problems._patrols`); timed through the command line too.
- ``moving-obstacle``, ``robot-grid``, ``robot-grid-fast``: the reactive synthesis
  competition's robot benchmarks in the grid format (safety and recurrence objectives,
  slow and glitching obstacles), run with ``native`` and the ``omega`` peer; see
  :mod:`plansynth.bench.families.grid_syntcomp`.
- ``reactive-suite``: the 40 shared problems with certified labels
  (``../shared/grid-reactive/`` from the repository root, see :func:`reactive_suite`);
  the sweep says clearly when that folder is missing.

The problems themselves are built by :mod:`plansynth.bench.families.grid_problems`.

>>> [i.name for i in grid_family("steps", [5, 10])]
['steps-5', 'steps-10']
>>> grid_family("depth")[0].build().robot.goal
(5, 0)
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import Any

from plansynth.bench.families.grid_problems import SuiteMissing, reactive_suite_dir
from plansynth.bench.families.instance import Instance

__all__ = [
    "GRID_FAMILIES",
    "CLI_TIMED_FAMILIES",
    "PAPER_FAMILIES",
    "PAPER_GRID_SECONDS",
    "grid_family",
    "paper_depth",
    "paper_problems",
    "reactive_suite",
]


def reactive_suite() -> list[Instance]:
    """The suite's instances; ``expected`` and the witness depth come from the labels."""
    d = reactive_suite_dir()
    out = []
    for path in sorted(d.glob("*.label.json")):
        label = json.loads(path.read_text(encoding="utf-8"))
        name = path.name[: -len(".label.json")]
        params = {"name": name, "witness_depth": label.get("witness_depth"), "category": label.get("category")}
        out.append(Instance("grid", "reactive-suite", name, params, label.get("expected")))
    if not out:
        raise SuiteMissing(f"no NAME.label.json files in {d}")
    return out


#: Grid families timed through the command line in a fresh process (start-up included),
#: as their timing targets are stated; see :mod:`plansynth.bench.execute.grid`.
CLI_TIMED_FAMILIES = frozenset({"reactive-suite", "doors", "doors-rush", "doors-jam", "patrols", "patrols-walk"})


#: The paper's times (s) per family and parameter value, Enumerative 2015 (benchmarks.md).
PAPER_GRID_SECONDS = {
    "depth": {1: 0.061, 4: 0.225, 5: 477.0, 6: None},
    "steps": {5: 4.2, 10: 46.6, 15: 218.0, 20: 798.0, 25: 6026.0},
    "obstacles": dict(zip(range(5, 55, 5), [38, 243, 576, 1208, 1816, 3357, 4923, 7379, 8704, 9538])),
    "dimensions": dict(zip([5, 15, 25, 35, 45, 55], [17.1, 27.3, 30.5, 44.9, 65.5, 84.6])),
}

#: The paper's grid families (Chasins & Newcomb, SYNT 2016, Section 4.1), Figure 1 first.
PAPER_FAMILIES = ("figure1", "depth", "steps", "obstacles", "dimensions")


def paper_depth(name: str) -> int:
    """The depth of the paper's program for instance ``name`` (Section 4.1): the depth
    family is named by it (depth-d), every other paper instance has a depth-4 program.

    >>> paper_depth("depth-5"), paper_depth("steps-25")
    (5, 4)
    """
    return int(name.split("-")[1]) if name.startswith("depth-") else 4


def paper_problems() -> dict[str, dict[str, Any]]:
    """Every instance of the paper's families, by name, as problem documents (the one
    definition: the bench, the tests and ``examples/grid/measure_native.py`` use it).

    >>> sorted(paper_problems())[:3]
    ['depth-1', 'depth-4', 'depth-5']
    """
    return {i.name: i.document() for f in PAPER_FAMILIES for i in grid_family(f)}


GRID_FAMILIES: dict[str, tuple[str, list[int], str | None]] = {
    # family: (parameter name, default values, expected answer)
    "figure1": ("", [0], "realizable"),
    "depth": ("d", [1, 4, 5, 6], None),
    "steps": ("L", [5, 10, 15, 20, 25], None),
    "obstacles": ("N", list(range(5, 55, 5)), None),
    "dimensions": ("S", [5, 15, 25, 35, 45, 55], None),
    "crossing": ("cars", [1, 2, 3], "realizable"),
    "crossing-stall": ("cars", [1, 2], "unrealizable"),
    "patrol": ("height", [5, 7, 15], "unrealizable"),
    "patrol-walk": ("height", [5, 7], "unrealizable"),
    "door": ("l", [8, 10, 12], None),
    "door-stall": ("l", [10, 14], "unrealizable"),
    "scale": ("size", [32, 64], "realizable"),
    "lanes": ("lanes", [1, 2, 3], "realizable"),
    "lanes-rush": ("lanes", [1, 2, 3], "unrealizable"),
    "doors": ("doors", [1, 2, 3], "realizable"),
    "doors-rush": ("doors", [1, 2, 3], "unrealizable"),
    "doors-jam": ("doors", [1, 2, 3], "unrealizable"),
    "patrols": ("roads", [1, 2, 3], "realizable"),
    "patrols-walk": ("roads", [1, 2, 3], "unrealizable"),
    "reactive-suite": ("name", [], None),  # the shared suite (see reactive_suite)
    "roads30": ("L", [32, 36], None),  # 30x30, 3 lanes of fast cars (answers per value: _KNOWN)
    "roads30-stall": ("lanes", [2, 3], None),  # 30x30, cars that may stop
    "guards30": ("guards", [3, 4], None),  # 30x30, guards that walk every step
    # SYNTCOMP's robot benchmarks (plansynth.bench.families.grid_syntcomp): values are grid
    # sizes m, each with both published glitch counts
    "moving-obstacle": ("m", [8, 16, 24, 32, 48, 64, 96, 128], None),
    "robot-grid": ("map", [1, 2, 3, 4, 5, 6, 7, 8], "realizable"),
    "robot-grid-fast": ("map", [1, 2, 3, 4, 5, 6, 7, 8], "unrealizable"),
}

#: Answers of the 30x30 families, found by the native engine (the realizable ones'
#: controllers independently verified; the unrealizable ones lose the time-dependent
#: game, decided exactly by backward induction). Instances not listed: not always decided
#: within 60 s and 4 GiB (roads30-stall-3: 25.7 million joint states, a verified program in
#: 52-55 s in two runs of three; guards30-4: more than 1.5 million configurations by step 22).
_KNOWN = {
    ("roads30", 32): "unrealizable",
    ("roads30", 36): "realizable",
    ("roads30-stall", 2): "realizable",
    ("guards30", 3): "unrealizable",
}


def grid_family(name: str, values: Sequence[int] | None = None) -> list[Instance]:
    """Instances of grid family ``name`` (optionally only the given parameter values)."""
    if name not in GRID_FAMILIES:
        raise KeyError(f"unknown grid family {name!r}; choose one of {', '.join(GRID_FAMILIES)}")
    pname, defaults, expected = GRID_FAMILIES[name]
    if name == "reactive-suite":
        suite = reactive_suite()
        return suite if values is None else [i for i in suite if i.name in {str(v) for v in values}]
    if name == "moving-obstacle":
        from plansynth.bench.families.grid_syntcomp import moving_obstacle_family

        return moving_obstacle_family(values)
    if name in ("robot-grid", "robot-grid-fast"):
        from plansynth.bench.families.grid_syntcomp import robot_grid_family

        return robot_grid_family(values, fast=name == "robot-grid-fast")
    out = []
    for v in values if values is not None else defaults:
        if name == "figure1":
            out.append(Instance("grid", "figure1", "figure1", {}, expected))
            continue
        builder_key = {
            "d": "d",
            "L": "L",
            "N": "N",
            "S": "S",
            "cars": "cars",
            "height": "height",
            "size": "size",
            "l": "l",
            "lanes": "lanes",
            "doors": "doors",
            "roads": "roads",
            "guards": "guards",
        }[pname]
        params = {builder_key: int(v)}
        inst_name = f"{name}-{v}"
        paper = PAPER_GRID_SECONDS.get(name, {}).get(int(v))
        known = "realizable" if (name == "patrol" and int(v) > 13) else _KNOWN.get((name, int(v)), expected)
        out.append(Instance("grid", name, inst_name, params, known, paper))
    return out
