"""The eight 8 x 16 maps of SYNTCOMP's ``tlsf/robot_grid/non_parametric/gr_{1..8}``, as
text, for the ``robot-grid`` bench family (no TLSF file is needed to run it).

Each map is :meth:`~plansynth.grid.syntcomp.robot_grid.RobotGridMap.render` of the map
read from the benchmark's TLSF file (``#`` wall, ``|`` a cell the moving obstacle never
enters, ``D`` door, ``S`` pickup, ``T`` drop, ``o`` the obstacle's start, ``.`` free);
``tests/grid/syntcomp/test_robot_grid_family.py`` checks that the text and the documents
built from it are those of the files (SYNTCOMP/benchmarks, CC BY 4.0; the maps were
generated with the SLUGS map generator of R. Ehlers, modified by A. Khalimov).

>>> d = map_document("gr_2")
>>> d["robot"]["goals"], d["obstacles"][0]["start"], d["obstacles"][0]["period"]
([[0, 0], [7, 0], [0, 2], [7, 2]], [3, 3], 2)
"""

from __future__ import annotations

__all__ = ["MAPS", "map_document"]

#: The maps by name, one row of text per y (y = 0 first).
MAPS: dict[str, str] = {
    "gr_1": "\n".join(
        [
            "SD|..|DT",
            "DD|..|DD",
            "..|..|..",
            "..|o.|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
        ]
    ),
    "gr_2": "\n".join(
        [
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|o.|##",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
        ]
    ),
    "gr_3": "\n".join(
        [
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|o.|##",
            "SD|..|DT",
            "##|..|##",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
        ]
    ),
    "gr_4": "\n".join(
        [
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|o.|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
        ]
    ),
    "gr_5": "\n".join(
        [
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|o.|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
        ]
    ),
    "gr_6": "\n".join(
        [
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|o.|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "..|..|..",
            "..|..|..",
            "..|..|..",
            "..|..|..",
        ]
    ),
    "gr_7": "\n".join(
        [
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|o.|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "..|..|..",
            "..|..|..",
        ]
    ),
    "gr_8": "\n".join(
        [
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|o.|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
            "SD|..|DT",
            "##|..|##",
        ]
    ),
}


def map_document(name: str, *, period: int = 2, fair: bool = False) -> dict:
    """The recurrence problem after map ``name`` (the rules of
    :func:`plansynth.grid.syntcomp.robot_grid.grid_document`, built from the text):
    goals the pickup and the drop of each row in turn, the obstacle kept out of the
    ``|`` cells, ``period: 2`` on the ``fixed`` schedule by default."""
    rows = MAPS[name].split("\n")
    cells = {(x, y): ch for y, row in enumerate(rows) for x, ch in enumerate(row)}
    goals: list[list[int]] = []
    for y, row in enumerate(rows):
        for x, ch in enumerate(row):
            if ch == "S":
                goals.append([x, y])
                goals.append([row.index("T"), y])
    start = next(c for c, ch in cells.items() if ch == "o")
    moves = ["stay", "up", "down", "left", "right"]
    obstacle: dict = {
        "start": list(start),
        "moves": moves,
        "keep_out": [list(c) for c in sorted(c for c, ch in cells.items() if ch == "|")],
    }
    if period > 1:
        obstacle.update(period=period, schedule="fixed")
    doc: dict = {
        "name": f"robot-grid-{name}" + ("" if period == 2 else f"-p{period}") + ("-fair" if fair else ""),
        "grid": [len(rows[0]), len(rows)],
        "objective": "recurrence",
        "collision": "position",
        "robot": {"start": [0, 0], "goals": goals, "moves": moves},
        "obstacles": [obstacle],
        "walls": [list(c) for c in sorted(c for c, ch in cells.items() if ch == "#")],
    }
    if fair:
        doc["fair"] = True
    return doc
