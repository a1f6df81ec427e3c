"""Benchmark families as code (and, through :func:`write_family_files`, as files).

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
  :func:`_doors`); timed through the command line, like the shared suite.
- ``patrols`` (realizable) and ``patrols-walk`` (unrealizable): guards walking back and
  forth along 1-3 roads that the robot crosses at one of two zebras (see
  :func:`_patrols`); timed through the command line too.
- ``reactive-suite``: the 40 shared problems with certified labels
  (``../shared/grid-reactive/`` from the repository root, see :func:`reactive_suite`);
  the sweep says clearly when that folder is missing.

Reach families reproduce Shoukry et al. (CDC 2016, Section VI): ``maze`` (n passages,
double integrator; Table I), ``chain`` (the same mazes with integrator chains of order
k, i.e. 2k states; Figure 4), ``random-dynamics`` (the same mazes with seeded random
controllable (A, B) pairs of n states, the paper's own Figure 4 setting, from
:func:`plansynth.reach.families.random_dynamics`), and ``random`` workspaces (random
boxes and non-convex polygons, from :func:`plansynth.reach.families.random_workspace`).
``gcs-maze`` is the n x n maze of the GCS paper (Marcucci et al., Science Robotics 2023;
sizes 10, 20, 50), from :func:`plansynth.reach.families.gcs_maze`.

>>> [i.name for i in grid_family("steps", [5, 10])]
['steps-5', 'steps-10']
>>> grid_family("depth")[0].build().robot.goal
(5, 0)
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = [
    "Instance",
    "GRID_FAMILIES",
    "REACH_FAMILIES",
    "grid_family",
    "paper_problems",
    "paper_depth",
    "PAPER_FAMILIES",
    "CLI_TIMED_FAMILIES",
    "reach_family",
    "family",
    "instance_from_task",
    "write_family_files",
]

UP_DOWN = ["up", "down"]
ALL_MOVES = ["stay", "up", "right", "down", "left"]


@dataclass(frozen=True)
class Instance:
    """One benchmark problem: ``kind`` is "grid" or "reach"; ``params`` rebuild it.

    ``expected`` is the answer known by construction (``realizable``/``unrealizable``
    for grid, ``found`` for reach problems with a known solution), else None.
    ``paper_seconds`` is the time the paper reports for it, when it does.
    """

    kind: str
    family: str
    name: str
    params: Mapping[str, Any] = field(default_factory=dict)
    expected: str | None = None
    paper_seconds: float | None = None

    @property
    def key(self) -> str:
        return f"{self.kind}/{self.family}/{self.name}"

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "family": self.family, "name": self.name, "params": dict(self.params),
                "expected": self.expected, "paper_seconds": self.paper_seconds}

    def document(self) -> dict[str, Any]:
        """The problem as a spec document (grid-problem.md / reach-problem.md)."""
        if self.kind == "grid":
            return _GRID_BUILDERS[self.family](**self.params)
        from plansynth.reach.problem import reach_problem_to_dict

        return reach_problem_to_dict(self.build())

    def build(self) -> Any:
        """The problem object (GridProblem or ReachProblem)."""
        if self.kind == "grid":
            from plansynth.grid.problem import grid_problem_from_dict

            return grid_problem_from_dict(self.document(), source=f"<bench {self.key}>", name=self.name)
        return _REACH_BUILDERS[self.family](**self.params)


# ---------------------------------------------------------------------------- grid


def _grid_doc(width: int, height: int, start: Sequence[int], goal: Sequence[int], obstacles: list[dict[str, Any]],
              *, steps: int | None = None, max_steps: int | None = None, walls: Iterable[Sequence[int]] = (),
              robot_moves: list[Any] | None = None, name: str = "") -> dict[str, Any]:
    doc: dict[str, Any] = {
        "name": name,
        "grid": [width, height],
        "robot": {"start": list(start), "goal": list(goal), "moves": robot_moves or list(ALL_MOVES)},
        "obstacles": obstacles,
    }
    walls = [list(w) for w in walls]
    if walls:
        doc["walls"] = walls
    if steps is not None:
        doc["steps"] = steps
    if max_steps is not None:
        doc["max_steps"] = max_steps
    return doc


def _figure1() -> dict[str, Any]:
    return _grid_doc(5, 7, (1, 1), (4, 4), [{"start": [2, 5], "moves": UP_DOWN},
                                            {"start": [3, 5], "moves": ["stay", "up", "down"]}],
                     max_steps=12, name="figure1")


_DEPTH = {1: ((0, 0), (5, 0)), 4: ((0, 0), (4, 0)), 5: ((1, 0), (4, 1)), 6: ((3, 0), (3, 2))}


def _depth(d: int) -> dict[str, Any]:
    start, goal = _DEPTH[d]
    obstacles = [{"start": [x, 1], "moves": ["stay"]} for x in range(4)]
    return _grid_doc(6, 6, start, goal, obstacles, steps=5, name=f"depth-{d}")


def _five_up_down() -> list[dict[str, Any]]:
    return [{"start": [0, y], "moves": UP_DOWN} for y in range(5)]


def _steps(L: int) -> dict[str, Any]:
    return _grid_doc(20, 20, (1, 1), (3, 1), _five_up_down(), steps=L, name=f"steps-{L}")


def _obstacles(N: int) -> dict[str, Any]:
    obstacles = [{"start": [i % 20, 19 - i // 20], "moves": UP_DOWN} for i in range(N)]
    return _grid_doc(20, 20, (0, 0), (2, 3), obstacles, steps=5, name=f"obstacles-{N}")


def _dimensions(S: int) -> dict[str, Any]:
    return _grid_doc(S, S, (1, 0), (4, 2), _five_up_down(), steps=5, name=f"dimensions-{S}")


_FAST = {"name": "fast", "to": [2, 0], "via": [[1, 0]]}


def _crossing(cars: int, width: int = 7, steps: int = 12, stall: bool = False) -> dict[str, Any]:
    """Road in row 2 of a width x 5 grid; robot (3,0) -> (3,4) along the zebra crossing
    (column 3; every other cell of rows 0-1 and 3-4 is a wall); cars start at 0..cars-1."""
    moves = ["stay", "right"] if stall else ["right", _FAST]
    obstacles = [{"start": [i, 2], "moves": moves} for i in range(cars)]
    walls = [(x, y) for x in range(width) for y in (0, 1, 3, 4) if x != 3]
    name = f"crossing-stall-{cars}" if stall else f"crossing-{cars}"
    return _grid_doc(width, 5, (3, 0), (3, 4), obstacles, steps=steps, walls=walls, name=name)


_SPRINT = [{"name": "sprint-up", "to": [0, 2], "via": [[0, 1]]}, {"name": "sprint-down", "to": [0, -2], "via": [[0, -1]]}]


def _patrol(height: int, steps: int = 14, sprint: bool = True) -> dict[str, Any]:
    """Guard in column 2 of a 5 x height grid, starting mid-height; robot (0, mid) -> (4, mid)."""
    mid = height // 2
    moves: list[Any] = list(ALL_MOVES) + (list(_SPRINT) if sprint else [])
    name = f"patrol-{height}" if sprint else f"patrol-walk-{height}"
    return _grid_doc(5, height, (0, mid), (4, mid), [{"start": [2, mid], "moves": UP_DOWN}], steps=steps,
                     robot_moves=moves, name=name)


def _door(steps: int, stall: bool = False, height: int = 11) -> dict[str, Any]:
    """A sliding panel runs down the slot (column 3) of a wall with one doorway (3, mid),
    one or two cells per step (adversarial; with ``stall`` it may also stop). Robot
    (1, mid) -> (6, mid) in exactly ``steps`` steps (examples/grid/door.yaml is door-10).
    Realizable controllers must read the panel (o0y); at 8 steps there is no time to
    wait for it, and a panel that may stop can block the doorway forever."""
    mid = height // 2
    walls = [(x, y) for x in (2, 4) for y in range(height) if y != mid]
    moves: list[Any] = (["stay"] if stall else []) + ["down", {"name": "down2", "to": [0, -2], "via": [[0, -1]]}]
    name = f"door-stall-{steps}" if stall else f"door-{steps}"
    return _grid_doc(7, height, (1, mid), (6, mid), [{"start": [3, mid + 5], "moves": moves}], steps=steps,
                     walls=walls, name=name)


def _scale(size: int) -> dict[str, Any]:
    """Beyond the paper (issue: 64 x 64, l = 60): a size x size grid, robot (2,2) ->
    (size/2, size/2), eight [stay, up, down] obstacles on a diagonal that can all reach
    the robot's possible paths in time (examples/grid/scale64.yaml for size 64)."""
    half = size // 2
    obstacles = [{"start": [5 + 3 * i, 10 + 3 * i], "moves": ["stay", "up", "down"]} for i in range(8)]
    return _grid_doc(size, size, (2, 2), (half, half), obstacles, steps=2 * (half - 2), name=f"scale-{size}")


#: The shared reactive suite: 40 problems with certified labels, next to the repository
#: (``../shared/grid-reactive/`` from its root; ``PLANSYNTH_REACTIVE_SUITE`` overrides).
REACTIVE_SUITE = Path(__file__).resolve().parents[3].parent / "shared" / "grid-reactive"


class SuiteMissing(FileNotFoundError):
    """The reactive suite's folder (or one of its files) is not there."""


def reactive_suite_dir() -> Path:
    import os

    d = Path(os.environ.get("PLANSYNTH_REACTIVE_SUITE") or REACTIVE_SUITE)
    if not d.is_dir():
        raise SuiteMissing(f"family 'reactive-suite' reads NAME.yaml and NAME.label.json from {d}, which is missing "
                           "(expected at ../shared/grid-reactive/ relative to the repository root, or set "
                           "PLANSYNTH_REACTIVE_SUITE)")
    return d


def _reactive_suite(name: str, **_: Any) -> dict[str, Any]:
    """One problem of the shared reactive suite, as its file gives it."""
    import yaml

    path = reactive_suite_dir() / f"{name}.yaml"
    if not path.is_file():
        raise SuiteMissing(f"reactive-suite problem {path} is missing")
    doc = yaml.safe_load(path.read_text(encoding="utf-8"))
    doc.setdefault("name", name)
    return doc


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


def _lanes(lanes: int, steps: int | None = None) -> dict[str, Any]:
    """Several lanes of cars to cross: a 9-wide corridor going up through ``lanes`` roads
    (rows 2, 4, ...), each with one car driving right or left at one or two cells per step
    (never stopping), alternating directions. Realizable at the default length (the robot
    waits for each car to pass), unrealizable when ``steps`` leaves no time to wait."""
    width, height = 11, 2 * lanes + 3
    roads = [2 + 2 * i for i in range(lanes)]
    walls = [(x, y) for y in range(height) for x in range(width) if y not in roads and x not in (4, 5, 6)]
    right = ["right", {"name": "fast-right", "to": [2, 0], "via": [[1, 0]]}]
    left = ["left", {"name": "fast-left", "to": [-2, 0], "via": [[-1, 0]]}]
    obstacles = [{"start": [0, y] if i % 2 == 0 else [width - 1, y], "moves": right if i % 2 == 0 else left}
                 for i, y in enumerate(roads)]
    return _grid_doc(width, height, (5, 0), (5, height - 1), obstacles, steps=steps or height + 5, walls=walls,
                     name=f"lanes-{lanes}" + (f"-l{steps}" if steps else ""))


def _doors(doors: int, steps: int | None = None, jam: bool = False) -> dict[str, Any]:
    """Doors that close: the robot walks along the middle row of a corridor through
    ``doors`` walls, each with one doorway, and a panel slides down each wall's slot
    (its columns between the wall's two faces), through the doorway, at one or two
    cells per step (adversarially chosen); with ``jam`` it may also stop, so it can
    stay in the doorway: the door is shut for good. Panel i starts 2 + 4 i rows above
    the doorway, so the robot must wait at each door in turn, reading the panels.
    Realizable at the default length (the corridor's length plus 6); at the
    corridor's length plus 1 there is no time to wait (``doors-rush``), and a panel
    that may jam makes every length unrealizable (``doors-jam``). The answers are
    certified by brute force (:func:`plansynth.grid.reference.reference_wins` on the
    engine's program; :func:`plansynth.grid.native.reference.game_won` for a lost
    game) in ``tests/bench/test_families.py``."""
    height = 9 + 4 * doors
    mid = height // 2
    slots = [2 + 3 * i for i in range(doors)]
    width = slots[-1] + 3
    walls = [(x, mid + dy) for c in slots for x in (c - 1, c + 1) for dy in range(-mid, height - mid) if dy != 0]
    moves: list[Any] = (["stay"] if jam else []) + ["down", {"name": "down2", "to": [0, -2], "via": [[0, -1]]}]
    panels = [{"start": [c, mid + 2 + 4 * i], "moves": moves} for i, c in enumerate(slots)]
    length = steps or width + 5
    name = f"doors-jam-{doors}" if jam else f"doors-{doors}" + (f"-l{steps}" if steps else "")
    return _grid_doc(width, height, (0, mid), (width - 1, mid), panels, steps=length, walls=walls, name=name)


_SIDESTEP = [{"name": "fast-right", "to": [2, 0], "via": [[1, 0]]}, {"name": "fast-left", "to": [-2, 0], "via": [[-1, 0]]}]


def _patrols(roads: int, run: bool = True, width: int = 11) -> dict[str, Any]:
    """Obstacles that patrol: ``roads`` roads (rows 2, 6, ...) between walls, each crossed
    only at two zebra cells near its ends (columns 1 and width - 2); on each road a guard
    walks back and forth (left or right every step, adversarially chosen; the road's ends
    turn it). The robot starts and ends in the middle of the sidewalks, runs two cells a
    step along them (with ``run``) and crosses a road in one sprint of two cells (its
    middle cell is the road's). A guard can hover at one zebra, never at both: the
    controller reads where it is and runs to the other. Realizable at length
    4 roads + 8; without the run (``patrols-walk``) the guard covers both zebras in time
    and no controller wins. Labels certified by brute force in
    ``tests/bench/test_families.py``, as for :func:`_doors`."""
    height = 4 * roads + 1
    mid = width // 2
    zebras = (1, width - 2)
    rows = [2 + 4 * i for i in range(roads)]
    walls = [(x, y) for r in rows for y in (r - 1, r + 1) for x in range(width) if x not in zebras]
    guards = [{"start": [mid, r], "moves": ["left", "right"]} for r in rows]
    moves = list(ALL_MOVES) + (list(_SIDESTEP) if run else []) + list(_SPRINT)
    name = f"patrols-{roads}" if run else f"patrols-walk-{roads}"
    return _grid_doc(width, height, (mid, 0), (mid, height - 1), guards, steps=4 * roads + 8, walls=walls,
                     robot_moves=moves, name=name)


#: Grid families timed through the command line in a fresh process (start-up included),
#: as issue 11's targets are stated; see :mod:`plansynth.bench.execute`.
CLI_TIMED_FAMILIES = frozenset({"reactive-suite", "doors", "doors-rush", "doors-jam", "patrols", "patrols-walk"})


def _field30(lanes: int, steps: int, *, cars: str) -> dict[str, Any]:
    """30x30: a 5-wide corridor (columns 12-16) going up through ``lanes`` open rows
    (5, 10, 15, ...), each with one obstacle. ``cars="fast"``: a car entering from the
    left or right border (alternately) at 1, 2 or 3 cells per step, never stopping;
    ``cars="stall"``: a car from the left that may also stop (stay, right, fast-right),
    which the robot dodges by crossing on the side it cannot reach in time;
    ``cars="guard"``: a guard that walks left or right every step. Hundreds of
    thousands of obstacle configurations and millions of joint states."""
    rows = [5, 10, 15, 20, 25][:lanes]
    obstacles = []
    for i, y in enumerate(rows):
        if cars == "fast":
            sgn = 1 if i % 2 == 0 else -1
            moves = [{"name": f"v{v}", "to": [sgn * v, 0], "via": [[sgn * u, 0] for u in range(1, v)]} for v in (1, 2, 3)]
            obstacles.append({"start": [0 if sgn > 0 else 29, y], "moves": moves})
        elif cars == "stall":
            obstacles.append({"start": [0, y], "moves": ["stay", "right", {"name": "fast-right", "to": [2, 0], "via": [[1, 0]]}]})
        else:
            obstacles.append({"start": [3 + 6 * i, y + 1], "moves": ["left", "right"]})
    if cars == "guard":
        rows = [y + 1 for y in rows]
    walls = [(x, y) for y in range(30) for x in range(30) if y not in rows and not 12 <= x <= 16]
    return _grid_doc(30, 30, (14, 0), (14, 29), obstacles, steps=steps, walls=walls,
                     robot_moves=["stay", "up", "right", "down", "left", "up-right", "up-left"],
                     name=f"field30-{cars}-{lanes}-l{steps}")


_GRID_BUILDERS: dict[str, Any] = {
    "reactive-suite": lambda name, **kw: _reactive_suite(name),
    "lanes": lambda lanes, steps=None: _lanes(lanes, steps),
    "lanes-rush": lambda lanes: _lanes(lanes, 2 * lanes + 2),
    "doors": lambda doors: _doors(doors),
    "doors-rush": lambda doors: _doors(doors, 3 * doors + 2),
    "doors-jam": lambda doors: _doors(doors, jam=True),
    "patrols": lambda roads: _patrols(roads),
    "patrols-walk": lambda roads: _patrols(roads, run=False),
    "roads30": lambda L: _field30(3, L, cars="fast"),
    "roads30-stall": lambda lanes: _field30(lanes, 36, cars="stall"),
    "guards30": lambda guards: _field30(guards, 36 if guards <= 3 else 40, cars="guard"),
    "figure1": lambda: _figure1(),
    "depth": lambda d: _depth(d),
    "steps": lambda L: _steps(L),
    "obstacles": lambda N: _obstacles(N),
    "dimensions": lambda S: _dimensions(S),
    "crossing": lambda cars, steps=12: _crossing(cars, steps=steps),
    "crossing-stall": lambda cars, steps=12: _crossing(cars, steps=steps, stall=True),
    "patrol": lambda height, steps=None: _patrol(height, steps=steps or (24 if height > 13 else 14)),
    "patrol-walk": lambda height, steps=14: _patrol(height, steps=steps, sprint=False),
    "door": lambda l: _door(l),
    "door-stall": lambda l: _door(l, stall=True),
    "scale": lambda size: _scale(size),
}

# Paper's times (s), Enumerative 2015 (benchmarks.md).
_PAPER_GRID = {
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
}

#: Answers of the 30x30 families, found by the native engine (the realizable ones'
#: controllers independently verified; the unrealizable ones lose the time-dependent
#: game, decided exactly by backward induction). Instances not listed: not always decided
#: within 60 s and 4 GiB (roads30-stall-3: 25.7 million joint states, a verified program in
#: 52-55 s in two runs of three; guards30-4: more than 1.5 million configurations by step 22).
_KNOWN = {("roads30", 32): "unrealizable", ("roads30", 36): "realizable", ("roads30-stall", 2): "realizable",
          ("guards30", 3): "unrealizable"}


def grid_family(name: str, values: Sequence[int] | None = None) -> list[Instance]:
    """Instances of grid family ``name`` (optionally only the given parameter values)."""
    if name not in GRID_FAMILIES:
        raise KeyError(f"unknown grid family {name!r}; choose one of {', '.join(GRID_FAMILIES)}")
    pname, defaults, expected = GRID_FAMILIES[name]
    if name == "reactive-suite":
        suite = reactive_suite()
        return suite if values is None else [i for i in suite if i.name in {str(v) for v in values}]
    out = []
    for v in (values if values is not None else defaults):
        if name == "figure1":
            out.append(Instance("grid", "figure1", "figure1", {}, expected))
            continue
        builder_key = {"d": "d", "L": "L", "N": "N", "S": "S", "cars": "cars", "height": "height", "size": "size", "l": "l",
                       "lanes": "lanes", "doors": "doors", "roads": "roads", "guards": "guards"}[pname]
        params = {builder_key: int(v)}
        inst_name = f"{name}-{v}"
        paper = _PAPER_GRID.get(name, {}).get(int(v))
        known = "realizable" if (name == "patrol" and int(v) > 13) else _KNOWN.get((name, int(v)), expected)
        out.append(Instance("grid", name, inst_name, params, known, paper))
    return out


# ---------------------------------------------------------------------------- reach


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


_REACH_BUILDERS: dict[str, Any] = {"maze": _maze, "chain": _chain, "random": _random, "random-dynamics": _random_dynamics,
                                   "missions": _missions, "gcs-maze": _gcs_maze}

# Table I of the paper (seconds): discrete abstraction, DIS-PLAN, CON-PLAN, RRT, LTL OPT.
PAPER_TABLE_I: dict[int, dict[str, float | str]] = {
    1: {"abstraction": 1.998, "dis-plan": 0.136, "con-plan": 0.254, "rrt": 10.44, "ltl-opt": "> 7200"},
    2: {"abstraction": 7.146, "dis-plan": 1.129, "con-plan": 0.929, "rrt": 122.3, "ltl-opt": "time out"},
    3: {"abstraction": 19.33, "dis-plan": 3.650, "con-plan": 1.005, "rrt": 423.7, "ltl-opt": "time out"},
    4: {"abstraction": 43.10, "dis-plan": 4.091, "con-plan": 1.920, "rrt": 1002, "ltl-opt": "time out"},
}

REACH_FAMILIES = ("maze", "chain", "random", "random-dynamics", "missions", "gcs-maze")
RANDOM_DYNAMICS_STATES = (4, 10, 20, 50)


def reach_family(name: str, values: Sequence[Any] | None = None, *, orders: Sequence[int] = (1, 2, 3, 5),
                 states: Sequence[int] = RANDOM_DYNAMICS_STATES, seed: int = 0) -> list[Instance]:
    """Instances of reach family ``name``.

    ``maze``: values are passage counts (default 1..4). ``chain``: values are passage
    counts, crossed with ``orders`` (the chain order k; 2k states). ``random``: values
    are seeds (default 0..4). ``random-dynamics``: values are passage counts (default
    1..4), crossed with ``states`` (n, default 4, 10, 20, 50), random (A, B) drawn with
    ``seed`` (:func:`plansynth.reach.families.random_dynamics` says how).
    ``missions``: values are passage counts, each with the
    three missions of :mod:`plansynth.reach.mission.families`. ``gcs-maze``: values are
    maze sizes n (default 10, 20, 50), the n x n mazes of the GCS paper
    (:func:`plansynth.reach.families.gcs_maze`: seed 4, walls 0.1 thick, 100 extra
    knock-downs at n = 50 as in its notebook; the double integrator with dt 0.5 s,
    |u| <= 1, |v| <= 1 per axis, from the centre of cell (0, 0) at rest to a 0.4 box at
    the centre of cell (n-1, n-1)).
    """
    out = []
    if name == "maze":
        for n in values or [1, 2, 3, 4]:
            tot = sum(float(v) for k, v in PAPER_TABLE_I[int(n)].items() if k in ("abstraction", "dis-plan", "con-plan"))
            out.append(Instance("reach", "maze", f"maze-{n}", {"n": int(n)}, "found", tot if int(n) in PAPER_TABLE_I else None))
    elif name == "chain":
        for n in values or [1, 2, 3, 4]:
            for k in orders:
                out.append(Instance("reach", "chain", f"chain-{n}-k{k}", {"n": int(n), "k": int(k)}, "found"))
    elif name == "random-dynamics":
        for n in values or [1, 2, 3, 4]:
            for k in states:
                out.append(Instance("reach", "random-dynamics", f"rdyn-{n}-n{k}-s{seed}",
                                    {"n": int(n), "states": int(k), "seed": int(seed)}, None))
    elif name == "random":
        for s in values or [0, 1, 2, 3, 4]:
            out.append(Instance("reach", "random", f"random-{s}", {"seed": int(s)}, None))
    elif name == "missions":  # LTL missions (issue 14): three per maze, values are passage counts
        from plansynth.reach.mission.families import MISSIONS

        for n in values or [1, 2, 3, 4]:
            for m in MISSIONS:
                out.append(Instance("reach", "missions", f"maze-{n}-{m}", {"n": int(n), "mission": m}, "found"))
    elif name == "gcs-maze":
        for n in values or [10, 20, 50]:
            out.append(Instance("reach", "gcs-maze", f"gcs-maze-{n}", {"n": int(n)}, "found"))
    else:
        raise KeyError(f"unknown reach family {name!r}; choose one of {', '.join(REACH_FAMILIES)}")
    return out


def family(kind: str, name: str, values: Sequence[Any] | None = None, **kw: Any) -> list[Instance]:
    return grid_family(name, values) if kind == "grid" else reach_family(name, values, **kw)


def instance_from_task(task: Mapping[str, Any]) -> Instance:
    """Rebuild an :class:`Instance` from the dict a task carries (``Instance.to_dict``)."""
    d = task["instance"]
    return Instance(d["kind"], d["family"], d["name"], dict(d["params"]), d.get("expected"), d.get("paper_seconds"))


def write_family_files(directory: str | Path, instances: Iterable[Instance]) -> list[Path]:
    """Write each instance as a problem file (YAML) under ``directory/<kind>/<family>/``."""
    import yaml

    written = []
    for inst in instances:
        path = Path(directory) / inst.kind / inst.family / f"{inst.name}.yaml"
        path.parent.mkdir(parents=True, exist_ok=True)
        doc = inst.document()
        header = f"# plansynth bench family {inst.family!r}, instance {inst.name!r} (generated by `plansynth bench families`)\n"
        if inst.expected:
            header += f"# expected answer: {inst.expected}\n"
        from plansynth.io import write_output

        write_output(path, header + yaml.safe_dump(json.loads(json.dumps(doc)), sort_keys=False, default_flow_style=None))
        written.append(path)
    return written
