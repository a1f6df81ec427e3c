"""SYNTCOMP's ``tlsf/robot_grid`` maps (stations, doors, walls, one moving obstacle) read
from their TLSF files into plain data.

Source: ``tlsf/robot_grid/non_parametric/{gr,ltl}_{1..8}.tlsf`` of SYNTCOMP's benchmark
repository (``SYNTCOMP/benchmarks``, CC BY 4.0), with their maps ``maps/*.png`` and
``maps/*.colorcoding``. The benchmarks' README: "created using the generator script
written by Ruediger [Ehlers] and modified by Ayrat [Khalimov], taken from slugs
synthesizer"; the generator turns an 8 x 16 picture (one pixel a cell, one colour a
feature) into a specification. :func:`parse` reads the TLSF text (no TLSF tool needed:
these files are flat lists of Boolean conjunctions over bit-encoded cells); the tests
check every map against its picture and every derived clause below against the file.

The semantics (read from the files; ``X`` is LTL's next; ``SEMANTICS: Mealy,Strict``:
the system reacts to each input in the same step, and the guarantees must hold for as
long as the assumptions have held, TLSF's strict implication)
===============================================================================

* **Grid.** ``width x height = 8 x 16`` cells ``(x, y)``, ``x`` rightwards 0..7, ``y``
  downwards 0..15 (the picture's rows); inputs ``x0..x2``, ``y0..y3`` (least significant
  bit first) give the robot's cell. The robot starts at ``(0, 0)`` (INITIALLY).
* **Robot.** Outputs ``left, right, up, down, pickup, drop``, all false at time 0
  (PRESET); from time 1 at most one of the four motion commands (ASSERT ``X (left ->
  !right && !up && !down)`` ...): 4-neighbour moves or staying. The environment moves
  the robot as commanded (REQUIRE): ``left``: ``x - 1``, ``right``: ``x + 1``, ``up``:
  ``y - 1``, ``down``: ``y + 1``, no command in an axis: that coordinate stays. A command
  off the grid (``left`` at ``x = 0`` ...) has no clause: the environment may then put
  that coordinate anywhere, so a winning robot never gives one. (The PNG generator of
  SLUGS clamps instead; these files do not.)
* **Walls** (black pixels, :attr:`RobotGridMap.walls`): ``!(X cell)`` for each, the robot
  is never on one from time 1.
* **Doors** (one input ``door<k>`` per door colour ``k``; true = closed;
  :attr:`RobotGridMap.doors`): the robot never commands a move from a cell outside the
  door into one of its cells while the door is closed (``! (X door<k> && X right && X
  cell)``, for each 4-neighbour of the door, from time 1); assumption ``G F ! door<k>``
  (the door opens infinitely often); guarantee ``G F`` (the robot is on none of the
  door's cells) (it does not block the door forever).
* **Deliveries** (outputs ``pendingdelivery<k>``, ``deliverypickedup<k>``, input
  ``deliveryrequest<k>``; pickup cells of colour ``k``, drop cells of colour ``k + 1``;
  :attr:`RobotGridMap.deliveries`): a request makes the delivery pending (``X pending ->
  pending || request``, ``request -> pending || X pending``); it stays pending until the
  robot, having picked it up (``pickup`` while on a pickup cell sets ``pickedup``, and
  only there), issues ``drop`` on a drop cell (``pending && !X pending`` only so;
  ``pickedup && X drop`` must be on a drop cell and clears ``pickedup``; no ``pickup``
  while carrying); guarantee ``G F ! pending<k>`` (every request is served).
* **The moving obstacle** (inputs ``mox<k>_i``, ``moy<k>_i``; one cell, colour ``k``;
  :attr:`RobotGridMap.obstacle`): starts at its pixel (INITIALLY); each step it stays or
  moves to a 4-neighbour that is not a blocked cell (REQUIRE ``(cell) -> (X target) ||
  ...``, :attr:`MovingObstacle.moves`); it may change cell only at even ticks when the
  map says so (``gr_*``: output ``MOSpeederMonitor<k>``, false at 0 and toggling every
  step, ``! MOSpeederMonitor<k> -> (mo <-> X mo)``: it may move from ``t`` to ``t + 1``
  only for odd ``t``; ``ltl_*``: every step). It is blocked by the gray fence (both
  families: it stays in the middle corridor) and, in ``ltl_*``, by the top door too.
  **Collision:** ``! (X mo = c && X robot = c)`` for every cell ``c``: robot and obstacle
  never on the same cell from time 1 (positions only; they may swap cells).
* **Objectives.** ``gr_k``: ``(AND_doors G F ! door) -> (AND_doors G F robot off the
  door && AND_deliveries G F ! pending)`` under the safety parts above: GR(1), realizable
  (README). ``ltl_k`` adds the assumption ``F G`` (obstacle on its favourite cells) and
  the guarantee ``F G`` (robot on its favourite cells, doors or stations):
  :attr:`RobotGridMap.obstacle_favourite`, :attr:`RobotGridMap.robot_favourite`.

>>> m = parse(EXAMPLE)
>>> m.size, m.robot_start, sorted(m.doors[0].cells)
((3, 2), (0, 0), [(1, 0)])
>>> print(m.render())
SDT
.o#
>>> sorted(m.obstacle.moves[(1, 1)])
[(0, 1), (1, 1)]
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from plansynth.errors import InvalidProblem

__all__ = ["RobotGridMap", "Door", "Delivery", "MovingObstacle", "parse", "read", "Cell", "grid_document"]

Cell = tuple[int, int]


@dataclass(frozen=True)
class Door:
    """A door (one colour of the map): its input name and its cells."""

    name: str
    cells: frozenset[Cell]


@dataclass(frozen=True)
class Delivery:
    """A pickup-delivery station pair: the request input's name, pickup and drop cells."""

    name: str
    pickup: frozenset[Cell]
    drop: frozenset[Cell]


@dataclass(frozen=True)
class MovingObstacle:
    """The moving obstacle (one cell): start, whether it moves only at even ticks, and
    the cells it may go to from each cell (staying included where allowed)."""

    name: str
    start: Cell
    even_ticks_only: bool
    moves: dict[Cell, frozenset[Cell]] = field(hash=False)

    @property
    def blocked(self) -> frozenset[Cell]:
        """Cells the obstacle may never enter (the fence, and in ``ltl_*`` the top door)."""
        reachable = {c for targets in self.moves.values() for c in targets}
        return frozenset(c for c in self.moves if c not in reachable)


@dataclass(frozen=True)
class RobotGridMap:
    """One map (see the module's docstring for the semantics of each part)."""

    name: str
    width: int
    height: int
    robot_start: Cell
    walls: frozenset[Cell]
    doors: tuple[Door, ...]
    deliveries: tuple[Delivery, ...]
    obstacle: MovingObstacle | None
    robot_favourite: frozenset[Cell] | None = None
    obstacle_favourite: frozenset[Cell] | None = None

    @property
    def size(self) -> tuple[int, int]:
        return (self.width, self.height)

    def cells(self) -> Iterator[Cell]:
        for y in range(self.height):
            for x in range(self.width):
                yield (x, y)

    def render(self) -> str:
        """The map as text, one row per ``y``: ``#`` wall, ``|`` blocked for the obstacle
        only, ``D`` door, ``S`` pickup, ``T`` drop, ``o`` the obstacle's start, ``.``
        free."""
        mark: dict[Cell, str] = {}
        if self.obstacle is not None:
            for c in self.obstacle.blocked:
                mark[c] = "|"
            mark[self.obstacle.start] = "o"
        for c in self.walls:
            mark[c] = "#"
        for d in self.doors:
            for c in d.cells:
                mark[c] = "D"
        for s in self.deliveries:
            for c in s.pickup:
                mark[c] = "S"
            for c in s.drop:
                mark[c] = "T"
        return "\n".join("".join(mark.get((x, y), ".") for x in range(self.width)) for y in range(self.height))


# --------------------------------------------------------------------------- parsing

_BLOCK = re.compile(r"^([A-Z]+)\s*\{(.*?)^\}", re.S | re.M)


def read(path: str | Path) -> RobotGridMap:
    """Read a ``.tlsf`` file (``.tlsf.gz`` too)."""
    p = Path(path)
    data = p.read_bytes()
    if p.suffix == ".gz":
        import gzip

        data = gzip.decompress(data)
    name = p.name.split(".")[0]
    return parse(data.decode("utf-8"), name=name, file=str(path))


def _blocks(text: str) -> list[tuple[str, str, list[str]]]:
    """``(section, comment, lines)`` for each top-level section inside ``MAIN``."""
    main = text.find("MAIN")
    if main < 0:
        raise InvalidProblem(None, "MAIN", "no MAIN section")
    out = []
    for m in _BLOCK.finditer(text, main + 4):
        body = [ln.strip() for ln in m.group(2).splitlines() if ln.strip()]
        comment = " ".join(ln[2:].strip() for ln in body if ln.startswith("//"))
        out.append((m.group(1), comment, [ln for ln in body if not ln.startswith("//")]))
    return out


class _Cells:
    """Decode conjunctions of bit literals into cells for one pair of bit prefixes."""

    def __init__(self, xbits: str, ybits: str) -> None:
        self.x, self.y = xbits, ybits

    def decode(self, conj: str, *, primed: bool | None = None) -> Cell | None:
        """The cell a conjunction ``[!] [X] x0 && ...`` names, or None if it is not one."""
        vals = {self.x: {}, self.y: {}}
        for part in conj.split("&&"):
            m = re.fullmatch(r"\s*(!\s*)?(X\s+)?(\w+?)_?(\d+)\s*", part)
            if m is None:
                return None
            base = m.group(3)
            if base not in vals or (primed is not None and bool(m.group(2)) != primed):
                return None
            vals[base][int(m.group(4))] = 0 if m.group(1) else 1
        if not vals[self.x] or not vals[self.y]:
            return None
        return (sum(v << b for b, v in vals[self.x].items()), sum(v << b for b, v in vals[self.y].items()))

    def all_in(self, text: str, *, primed: bool | None = None) -> list[Cell]:
        """Every parenthesised cell conjunction in ``text``."""
        cells = []
        for group in re.findall(r"\(([^()]*)\)", text):
            c = self.decode(group, primed=primed)
            if c is not None:
                cells.append(c)
        return cells


def parse(text: str, *, name: str = "", file: str | None = None) -> RobotGridMap:
    """The map of a ``robot_grid`` TLSF file (see the module's docstring)."""
    blocks = _blocks(text)
    robot = _Cells("x", "y")

    def fail(field_: str, reason: str) -> InvalidProblem:
        return InvalidProblem(file, field_, reason)

    # the grid: the cells the "no command: stay" clauses of the robot's motion mention
    xs, ys = set(), set()
    for sec, comment, lines in blocks:
        if sec == "REQUIRE" and "coordinates are updated" in comment:
            for ln in lines:
                lhs = ln.split("->")[0]
                if lhs.startswith("!left && !right"):
                    xs.add(_axis(lhs, "x"))
                if lhs.startswith("!up && !down"):
                    ys.add(_axis(lhs, "y"))
    xs.discard(None)
    ys.discard(None)
    if not xs or not ys:
        raise fail("REQUIRE", "no robot motion clauses")
    width, height = max(xs) + 1, max(ys) + 1

    walls: set[Cell] = set()
    doors: list[Door] = []
    deliveries: list[Delivery] = []
    obstacle: MovingObstacle | None = None
    robot_fav = obstacle_fav = None
    pending_door: str | None = None
    ob_name = ob_start = None
    ob_moves: dict[Cell, frozenset[Cell]] = {}
    ob_monitor = False
    for k, (sec, comment, lines) in enumerate(blocks):
        joined = " ".join(lines)
        if sec == "ASSERT" and "forbidden zones" in comment:
            for ln in lines:
                m = re.fullmatch(r"!\s*\((.*)\);?", ln)
                walls.add(robot.decode(m.group(1), primed=True) if m else None)
        elif sec == "INPUTS" and re.fullmatch(r"door\d+;", joined):
            pending_door = joined[:-1]
        elif sec == "GUARANTEE" and pending_door is not None and joined.startswith("G F"):
            doors.append(Door(pending_door, frozenset(robot.all_in(joined))))
            pending_door = None
        elif sec == "INPUTS" and re.fullmatch(r"deliveryrequest\d+;", joined):
            deliveries.append(_delivery(joined[:-1], blocks[k + 1 :], robot, fail))
        elif sec == "INPUTS" and joined.startswith("mox"):
            ob_name = re.match(r"mox(\d+)_0;", joined).group(1)
            mo = _Cells(f"mox{ob_name}", f"moy{ob_name}")
        elif sec == "INITIALLY" and ob_name is not None and ob_start is None and "mox" in joined:
            ob_start = mo.decode(joined.rstrip(";"), primed=False)
        elif sec == "OUTPUTS" and joined.startswith("MOSpeederMonitor"):
            ob_monitor = True
        elif sec == "REQUIRE" and "correct motion by the moving obstacle" in comment:
            for ln in lines:
                lhs, rhs = ln.rstrip(";").split("->")
                ob_moves[mo.decode(lhs.strip().strip("()"), primed=False)] = frozenset(mo.all_in(rhs, primed=True))
        elif sec == "ASSUME" and "moving object visits fav cells" in comment:
            obstacle_fav = frozenset(mo.all_in(joined))
        elif sec == "GUARANTEE" and "robot moves along fav cells" in comment:
            robot_fav = frozenset(robot.all_in(joined))
    if ob_name is not None:
        if ob_start is None or not ob_moves:
            raise fail("moving obstacle", "no start or no motion clauses")
        obstacle = MovingObstacle(f"mo{ob_name}", ob_start, ob_monitor, ob_moves)
    if None in walls:
        raise fail("forbidden zones", "a clause that is not one cell")
    return RobotGridMap(
        name,
        width,
        height,
        (0, 0),
        frozenset(walls),
        tuple(doors),
        tuple(deliveries),
        obstacle,
        robot_fav,
        obstacle_fav,
    )


def grid_document(m: RobotGridMap, *, period: int = 2, fair: bool = False) -> dict:
    """A recurrence problem of plansynth's grid format after the map ``m``
    (docs/reference/grid-format.md): the robot, from (0, 0), with the moves ``stay, up,
    down, left, right``, must serve every delivery forever: visit its pickup cell, then
    its drop cell, delivery after delivery in the order of the map's rows, infinitely
    often (the goals of a ``recurrence`` objective); it must never stand on a wall or
    on the moving obstacle's cell (``collision: position``: the TLSF guarantee
    ``! (X mo = c && X robot = c)`` reads positions only). The obstacle starts on its
    pixel, moves like the robot, never enters the cells the map blocks for it
    (``keep_out``: the fence) and, with the default ``period: 2`` on the ``fixed``
    schedule, may change cell only at odd ticks (the ``gr_*`` maps'
    ``MOSpeederMonitor``); ``period: 1`` makes it move every step. ``fair``: the GR(1)
    assumption that it changes cell infinitely often.

    What the TLSF files have and this family leaves out: the doors (door cells are free
    here), the delivery requests (every delivery is always pending), the ``pickup`` and
    ``drop`` outputs (standing on the cell is the visit) and the robot's off-grid
    commands (the format keeps the robot in place). So the family is *after*
    robot_grid, not robot_grid itself.

    >>> d = grid_document(parse(EXAMPLE))
    >>> d["objective"], d["robot"]["goals"], d["obstacles"][0]["keep_out"]
    ('recurrence', [[0, 0], [2, 0]], [])
    """
    if m.obstacle is None:
        raise InvalidProblem(None, "moving obstacle", f"map {m.name!r} has no moving obstacle")
    moves = ["stay", "up", "down", "left", "right"]
    goals: list[list[int]] = []
    for d in sorted(m.deliveries, key=lambda d: min(d.pickup)[::-1]):
        goals += [list(min(d.pickup)), list(min(d.drop))]
    obstacle: dict = {
        "start": list(m.obstacle.start),
        "moves": moves,
        "keep_out": [list(c) for c in sorted(m.obstacle.blocked)],
    }
    if period > 1:
        obstacle.update(period=period, schedule="fixed")
    doc: dict = {
        "name": f"robot-grid-{m.name}" + ("" if period == 2 else f"-p{period}") + ("-fair" if fair else ""),
        "grid": [m.width, m.height],
        "objective": "recurrence",
        "collision": "position",
        "robot": {"start": list(m.robot_start), "goals": goals, "moves": moves},
        "obstacles": [obstacle],
        "walls": [list(c) for c in sorted(m.walls)],
    }
    if fair:
        doc["fair"] = True
    return doc


def _axis(conj: str, axis: str) -> int | None:
    bits = re.findall(rf"(!\s*)?\b{axis}(\d+)\b", conj)
    if not bits:
        return None
    return sum((0 if neg else 1) << int(b) for neg, b in bits)


def _delivery(request: str, rest: list, robot: _Cells, fail) -> Delivery:
    k = request.removeprefix("deliveryrequest")
    pickup = drop = None
    for sec, _comment, lines in rest:
        if sec != "ASSERT":
            continue
        for ln in lines:
            if ln.startswith(f"! deliverypickedup{k} && X deliverypickedup{k} ->"):
                pickup = frozenset(robot.all_in(ln.split("->")[1], primed=True))
            if ln.startswith(f"deliverypickedup{k} && X drop ->"):
                drop = frozenset(robot.all_in(ln.split("->")[1], primed=True))
        if pickup is not None and drop is not None:
            return Delivery(request, pickup, drop)
    raise fail(request, "no pickup or drop clause")


#: A tiny hand-written file of the same form (3 x 2 cells, a wall, a door, a station,
#: the obstacle), for the doctests.
EXAMPLE = """\
MAIN {
INPUTS {
x0; x1; y0;
}
REQUIRE {
// robots' coordinates are updated according to the move commands
!left && !right && ! x0 && ! x1 -> ! X x0 && ! X x1;
!left && !right && x0 && ! x1 -> X x0 && ! X x1;
!left && !right && ! x0 && x1 -> ! X x0 && X x1;
!up && !down && ! y0 -> ! X y0;
!up && !down && y0 -> X y0;
}
ASSERT {
// forbidden zones:
!(! X x0 && X x1 && X y0);
}
INPUTS {
door4;
}
GUARANTEE {
G F (!(x0 && ! x1 && ! y0) );
}
INPUTS {
deliveryrequest2;
}
ASSERT {
! deliverypickedup2 && X deliverypickedup2 -> ((! X x0 && ! X x1 && ! X y0)) && X pickup;
deliverypickedup2 && X drop -> ((! X x0 && X x1 && ! X y0));
}
INPUTS {
mox6_0;
mox6_1;
moy6_0;
}
INITIALLY {
mox6_0 && ! mox6_1 && moy6_0;
}
REQUIRE {
// correct motion by the moving obstacle
(mox6_0 && ! mox6_1 && moy6_0) -> (X mox6_0 && ! X mox6_1 && X moy6_0) || (! X mox6_0 && ! X mox6_1 && X moy6_0);
}
}
"""
