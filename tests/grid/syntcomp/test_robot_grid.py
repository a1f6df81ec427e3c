"""The ``robot_grid`` TLSF maps read by :mod:`plansynth.grid.syntcomp.robot_grid`,
checked against their pictures (``maps/*.png`` with ``*.colorcoding``: the generator's
own input, one pixel a cell, one palette index a feature) and against the clauses the
module's docstring says the files hold."""

from __future__ import annotations

import gzip
import re
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from plansynth.errors import InvalidProblem
from plansynth.grid.syntcomp.robot_grid import parse, read

DATA = Path(__file__).parent / "data" / "robot_grid"
NAMES = [f"{k}_{i}" for k in ("gr", "ltl") for i in range(1, 9)]
STEPS = {"left": (-1, 0), "right": (1, 0), "up": (0, -1), "down": (0, 1)}


def picture(name: str) -> tuple[np.ndarray, dict[int, str]]:
    pixels = np.array(Image.open(DATA / f"{name}.png"))  # palette indices, rows = y
    coding = {}
    for line in (DATA / f"{name}.colorcoding").read_text().splitlines():
        if line.strip():
            colour, meaning = line.split(" ", 1)
            coding[int(colour)] = meaning.strip()
    return pixels, coding


def cells_of(pixels: np.ndarray, colours) -> frozenset:
    ys, xs = np.nonzero(np.isin(pixels, list(colours)))
    return frozenset(zip(xs.tolist(), ys.tolist()))


def text(name: str) -> str:
    return gzip.decompress((DATA / f"{name}.tlsf.gz").read_bytes()).decode()


def cell_of(conj: str, xname="x", yname="y") -> tuple[int, int]:
    x = sum((0 if neg else 1) << int(b) for neg, b in re.findall(rf"(!\s*)?(?:X\s+)?\b{xname}(\d+)\b", conj))
    y = sum((0 if neg else 1) << int(b) for neg, b in re.findall(rf"(!\s*)?(?:X\s+)?\b{yname}(\d+)\b", conj))
    return (x, y)


@pytest.mark.parametrize("name", NAMES)
def test_map_is_the_picture(name):
    m = read(DATA / f"{name}.tlsf.gz")
    pixels, coding = picture(name)
    assert m.size == (pixels.shape[1], pixels.shape[0]) == (8, 16)
    assert m.walls == cells_of(pixels, [1])
    doors = {f"door{c}": cells_of(pixels, [c]) for c, what in coding.items() if what == "Door"}
    assert {d.name: d.cells for d in m.doors} == doors
    stations = {
        f"deliveryrequest{c}": (cells_of(pixels, [c]), cells_of(pixels, [c + 1]))
        for c, what in coding.items()
        if what == "Delivery"
    }
    assert {s.name: (s.pickup, s.drop) for s in m.deliveries} == stations
    ((colour, spec),) = [(c, w) for c, w in coding.items() if w.startswith("MovingObstacle:")]
    speed, w, h, blockades = spec.split(":")[1:]
    assert (w, h) == ("1", "1")
    assert {m.obstacle.start} == cells_of(pixels, [colour])
    assert m.obstacle.even_ticks_only == (speed == "0") == name.startswith("gr")
    assert m.obstacle.blocked == cells_of(pixels, [int(b) for b in blockades.split(",")])
    if name.startswith("ltl"):
        fav = [c for c, what in coding.items() if what == "RobotFav"]
        stations_cells = set().union(*(a | b for a, b in stations.values()))
        assert m.robot_favourite == cells_of(pixels, fav) | set().union(*doors.values()) | stations_cells
        ob_fav = [c for c, what in coding.items() if what == f"MovingObstacleFav:{colour}"]
        assert m.obstacle_favourite == cells_of(pixels, ob_fav)
    else:
        assert m.robot_favourite is None and m.obstacle_favourite is None


@pytest.mark.parametrize("name", NAMES)
def test_the_robot_moves_as_the_docstring_says(name):
    """One clause per (command or none, coordinate value); none for a command off the grid."""
    t = text(name)
    m = read(DATA / f"{name}.tlsf.gz")
    body = t[t.index("coordinates are updated") : t.index("}", t.index("coordinates are updated"))]
    found = set()
    for line in body.splitlines()[1:]:
        if "->" not in line:
            continue
        lhs, rhs = line.rstrip(";").split("->")
        axis = "x" if "x0" in lhs else "y"
        cmd = "stay" if lhs.startswith("!") else lhs.split("&&")[0].strip()
        pos = lambda s: cell_of(s)[0 if axis == "x" else 1]  # noqa: E731
        found.add((axis, cmd, pos(lhs), pos(rhs)))
    expected = set()
    for axis, n, cmds in (("x", m.width, ("left", "right")), ("y", m.height, ("up", "down"))):
        for v in range(n):
            expected.add((axis, "stay", v, v))
            for cmd in cmds:
                to = v + STEPS[cmd][0 if axis == "x" else 1]
                if 0 <= to < n:
                    expected.add((axis, cmd, v, to))
    assert found == expected


@pytest.mark.parametrize("name", NAMES)
def test_door_clauses_are_the_moves_into_closed_doors(name):
    t = text(name)
    m = read(DATA / f"{name}.tlsf.gz")
    found = {
        (d, cmd, cell_of(rest))
        for d, cmd, rest in re.findall(r"^! \(X (door\d+) && X (left|right|up|down) && (.*)\);$", t, re.M)
    }
    expected = set()
    for door in m.doors:
        for x, y in m.cells():
            for cmd, (dx, dy) in STEPS.items():
                if (x, y) not in door.cells and (x + dx, y + dy) in door.cells:
                    expected.add((door.name, cmd, (x, y)))
    assert found == expected
    assert set(re.findall(r"^G F ! (door\d+);$", t, re.M)) == {d.name for d in m.doors}
    assert set(re.findall(r"^G F ! pending(delivery\d+);$", t, re.M)) == {
        s.name.replace("deliveryrequest", "delivery") for s in m.deliveries
    }


@pytest.mark.parametrize("name", NAMES)
def test_obstacle_clauses(name):
    t = text(name)
    m = read(DATA / f"{name}.tlsf.gz")
    ob = m.obstacle
    k = ob.name.removeprefix("mo")
    # it stays or takes a 4-neighbour step, never into a blocked cell
    for x, y in m.cells():
        expected = {
            (x + dx, y + dy)
            for dx, dy in ((0, 0), *STEPS.values())
            if 0 <= x + dx < m.width and 0 <= y + dy < m.height and (x + dx, y + dy) not in ob.blocked
        }
        assert ob.moves[(x, y)] == expected, (x, y)
    # no collision: robot and obstacle never on the same cell, for every cell
    pairs = re.findall(rf"^! \(((?:! )?X mox{k}_0.*?)  &&  (.*)\);$", t, re.M)
    assert len(pairs) == m.width * m.height
    assert all(cell_of(a, f"mox{k}_", f"moy{k}_") == cell_of(b) for a, b in pairs)
    # the speed monitor of gr_*: false at 0, toggling, and the obstacle stays while it is false
    if ob.even_ticks_only:
        assert f"! MOSpeederMonitor{k};" in t and f"MOSpeederMonitor{k} <-> ! X MOSpeederMonitor{k};" in t
        assert f"! MOSpeederMonitor{k} -> (mox{k}_0 <-> X mox{k}_0);" in t
    else:
        assert "MOSpeederMonitor" not in t


def test_gr_maps_grow_as_the_readme_says():
    """README: the number of assumptions and guarantees grows with the index."""
    counts = [
        (len(read(DATA / f"gr_{i}.tlsf.gz").doors), len(read(DATA / f"gr_{i}.tlsf.gz").deliveries)) for i in range(1, 9)
    ]
    assert counts == [(i, i) for i in range(1, 9)]


def test_a_file_that_is_not_a_robot_grid_is_a_named_error():
    with pytest.raises(InvalidProblem, match="MAIN"):
        parse("INFO { }")
    with pytest.raises(InvalidProblem, match="robot motion"):
        parse("MAIN {\nINPUTS {\nx0;\n}\n}\n")
