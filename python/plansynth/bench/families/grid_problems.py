"""The grid benchmark problems as code: each family's problem document from its parameters.

A builder maps a family's parameters (the depth d, the path length L, the number of
cars ...) to a problem document of the spec (``grid-problem.md``); :data:`GRID_PROBLEMS`
names them by family. The paper's families follow Chasins & Newcomb (SYNT 2016, Section
4.1, the spec's ``benchmarks.md``); the reactive ones are ours, described in
:mod:`plansynth.bench.families.grid`. The shared reactive suite is read from its files
(:func:`reactive_suite_dir`).

>>> GRID_PROBLEMS["steps"](L=5)["steps"], GRID_PROBLEMS["figure1"]()["grid"]
(5, [5, 7])
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

__all__ = ["GRID_PROBLEMS", "REACTIVE_SUITE", "SuiteMissing", "reactive_suite_dir", "UP_DOWN", "ALL_MOVES"]

UP_DOWN = ["up", "down"]
ALL_MOVES = ["stay", "up", "right", "down", "left"]


def _grid_doc(
    width: int,
    height: int,
    start: Sequence[int],
    goal: Sequence[int],
    obstacles: list[dict[str, Any]],
    *,
    steps: int | None = None,
    max_steps: int | None = None,
    walls: Iterable[Sequence[int]] = (),
    robot_moves: list[Any] | None = None,
    name: str = "",
) -> dict[str, Any]:
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
    return _grid_doc(
        5,
        7,
        (1, 1),
        (4, 4),
        [{"start": [2, 5], "moves": UP_DOWN}, {"start": [3, 5], "moves": ["stay", "up", "down"]}],
        max_steps=12,
        name="figure1",
    )


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


_SPRINT = [
    {"name": "sprint-up", "to": [0, 2], "via": [[0, 1]]},
    {"name": "sprint-down", "to": [0, -2], "via": [[0, -1]]},
]


def _patrol(height: int, steps: int = 14, sprint: bool = True) -> dict[str, Any]:
    """Guard in column 2 of a 5 x height grid, starting mid-height; robot (0, mid) -> (4, mid)."""
    mid = height // 2
    moves: list[Any] = list(ALL_MOVES) + (list(_SPRINT) if sprint else [])
    name = f"patrol-{height}" if sprint else f"patrol-walk-{height}"
    return _grid_doc(
        5,
        height,
        (0, mid),
        (4, mid),
        [{"start": [2, mid], "moves": UP_DOWN}],
        steps=steps,
        robot_moves=moves,
        name=name,
    )


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
    return _grid_doc(
        7, height, (1, mid), (6, mid), [{"start": [3, mid + 5], "moves": moves}], steps=steps, walls=walls, name=name
    )


def _scale(size: int) -> dict[str, Any]:
    """Beyond the paper (64 x 64, l = 60): a size x size grid, robot (2,2) ->
    (size/2, size/2), eight [stay, up, down] obstacles on a diagonal that can all reach
    the robot's possible paths in time (examples/grid/scale64.yaml for size 64)."""
    half = size // 2
    obstacles = [{"start": [5 + 3 * i, 10 + 3 * i], "moves": ["stay", "up", "down"]} for i in range(8)]
    return _grid_doc(size, size, (2, 2), (half, half), obstacles, steps=2 * (half - 2), name=f"scale-{size}")


#: The shared reactive suite: 40 problems with certified labels, next to the repository
#: (``../shared/grid-reactive/`` from its root; ``PLANSYNTH_REACTIVE_SUITE`` overrides).
REACTIVE_SUITE = Path(__file__).resolve().parents[4].parent / "shared" / "grid-reactive"


class SuiteMissing(FileNotFoundError):
    """The reactive suite's folder (or one of its files) is not there."""


def reactive_suite_dir() -> Path:
    import os

    d = Path(os.environ.get("PLANSYNTH_REACTIVE_SUITE") or REACTIVE_SUITE)
    if not d.is_dir():
        raise SuiteMissing(
            f"family 'reactive-suite' reads NAME.yaml and NAME.label.json from {d}, which is missing "
            "(expected at ../shared/grid-reactive/ relative to the repository root, or set "
            "PLANSYNTH_REACTIVE_SUITE)"
        )
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
    obstacles = [
        {"start": [0, y] if i % 2 == 0 else [width - 1, y], "moves": right if i % 2 == 0 else left}
        for i, y in enumerate(roads)
    ]
    return _grid_doc(
        width,
        height,
        (5, 0),
        (5, height - 1),
        obstacles,
        steps=steps or height + 5,
        walls=walls,
        name=f"lanes-{lanes}" + (f"-l{steps}" if steps else ""),
    )


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


_SIDESTEP = [
    {"name": "fast-right", "to": [2, 0], "via": [[1, 0]]},
    {"name": "fast-left", "to": [-2, 0], "via": [[-1, 0]]},
]


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
    return _grid_doc(
        width,
        height,
        (mid, 0),
        (mid, height - 1),
        guards,
        steps=4 * roads + 8,
        walls=walls,
        robot_moves=moves,
        name=name,
    )


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
            moves = [
                {"name": f"v{v}", "to": [sgn * v, 0], "via": [[sgn * u, 0] for u in range(1, v)]} for v in (1, 2, 3)
            ]
            obstacles.append({"start": [0 if sgn > 0 else 29, y], "moves": moves})
        elif cars == "stall":
            obstacles.append(
                {"start": [0, y], "moves": ["stay", "right", {"name": "fast-right", "to": [2, 0], "via": [[1, 0]]}]}
            )
        else:
            obstacles.append({"start": [3 + 6 * i, y + 1], "moves": ["left", "right"]})
    if cars == "guard":
        rows = [y + 1 for y in rows]
    walls = [(x, y) for y in range(30) for x in range(30) if y not in rows and not 12 <= x <= 16]
    return _grid_doc(
        30,
        30,
        (14, 0),
        (14, 29),
        obstacles,
        steps=steps,
        walls=walls,
        robot_moves=["stay", "up", "right", "down", "left", "up-right", "up-left"],
        name=f"field30-{cars}-{lanes}-l{steps}",
    )


GRID_PROBLEMS: dict[str, Any] = {
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


def _robot_grid(map: int, period: int) -> dict[str, Any]:  # noqa: A002 - the family's parameter name
    from plansynth.grid.syntcomp.robot_grid_maps import map_document

    return map_document(f"gr_{map}", period=period)


def _moving_obstacle(m: int, c: int) -> dict[str, Any]:
    from plansynth.grid.syntcomp.moving_obstacle import grid_document

    return grid_document(m, c)


#: The SYNTCOMP families (their instances: plansynth.bench.families.grid_syntcomp); the
#: documents are built by plansynth.grid.syntcomp on first use.
SYNTCOMP_PROBLEMS: dict[str, Any] = {
    "moving-obstacle": _moving_obstacle,
    "robot-grid": lambda map: _robot_grid(map, 2),  # noqa: A006
    "robot-grid-fast": lambda map: _robot_grid(map, 1),  # noqa: A006
}
GRID_PROBLEMS.update(SYNTCOMP_PROBLEMS)
