"""The moving-obstacle circuits read as the explicit game: which bits are which, and one
step of a circuit compared with one step of :class:`MovingObstacle`.

Ehlers compiled each instance with SLUGS's structured front end and ABC (description,
Sect. III), and the circuits keep SLUGS's names: an integer variable ``v`` with range
``lo..hi`` has bits ``v@0.lo.hi`` (bit 0, which carries the range), ``v@1``, ... (least
significant first); controller inputs start with ``controllable_``. The monitor's
latches hold the previous step's inputs (``prev_*``) and two flags:

* inputs (environment): ``robx``, ``roby`` (0..m-1), ``obsx``, ``obsy`` (0..m-2), and
  ``glitches`` (0..c) when ``c > 0``;
* inputs (controller): ``movx``, ``movy`` (0..2 for ``d = v - 1``; 3 is invalid) and
  ``obsmove`` (one bit);
* latches: ``prev_<input>`` for each of them, ``IsNotFirstRound`` and
  ``AssumptionsAlreadyViolated`` (all reset to 0);
* output: ``err``, SYNTCOMP's bad signal.

The circuit's state after the robot has chosen move ``d`` in state ``s`` of the game is
:func:`latch_values` ``(s, d)``: ``prev_rob = s.robot``, ``prev_obs = s.obstacle``,
``prev_mov = d + 1``, ``prev_obsmove = not s.obstacle_waits``, ``prev_glitches =
s.glitches``, both flags as in a run where no assumption was broken yet.
:func:`expected_step` is what one step of the circuit must do from there under given
inputs, if the circuit is the game of :mod:`plansynth.grid.syntcomp.moving_obstacle`;
:func:`compare_step` runs the circuit and reports every difference. The tests in
``tests/grid/syntcomp`` run it on every state of the 8 x 8 instances and on random ones
of 16 x 16.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from plansynth.grid.syntcomp.aiger import CONTROLLABLE_PREFIX, Circuit, Input, Latch, Simulator
from plansynth.grid.syntcomp.moving_obstacle import MovingObstacle

__all__ = [
    "FieldLayout",
    "StepBatch",
    "expected_step",
    "compare_step",
    "latch_layout",
    "input_layout",
    "FIRST_ROUND",
    "VIOLATED",
]

FIRST_ROUND = "IsNotFirstRound"
VIOLATED = "AssumptionsAlreadyViolated"
_BIT = re.compile(r"(.+?)@(\d+)(?:\.(\d+)\.(\d+))?")


class FieldLayout:
    """SLUGS's integer fields over a circuit's inputs or latches: name -> bit columns.

    >>> from plansynth.grid.syntcomp.aiger import Input
    >>> lay = FieldLayout([Input(2, "robx@0.0.5"), Input(4, "robx@1"), Input(6, "robx@2"), Input(8, "controllable_obsmove")])
    >>> lay.names(), lay.ranges["robx"]
    (['robx', 'obsmove'], (0, 5))
    >>> a = np.zeros((2, 4), bool); lay.encode(a, "robx", np.array([5, 2])); lay.decode(a, "robx").tolist()
    [5, 2]
    """

    def __init__(self, items: list[Input] | list[Latch] | tuple) -> None:
        self.width = len(items)
        self.columns: dict[str, list[int]] = {}
        self.ranges: dict[str, tuple[int, int]] = {}
        bits: dict[str, dict[int, int]] = {}
        for col, item in enumerate(items):
            name = (item.name or f"#{col}").removeprefix(CONTROLLABLE_PREFIX)
            m = _BIT.fullmatch(name)
            if m is None:
                bits.setdefault(name, {})[0] = col
                self.ranges[name] = (0, 1)
                continue
            bits.setdefault(m.group(1), {})[int(m.group(2))] = col
            if m.group(3) is not None:
                self.ranges[m.group(1)] = (int(m.group(3)), int(m.group(4)))
        for name, by_bit in bits.items():
            if sorted(by_bit) != list(range(len(by_bit))):
                raise ValueError(f"field {name!r} has bits {sorted(by_bit)}, not 0..{len(by_bit) - 1}")
            self.columns[name] = [by_bit[b] for b in range(len(by_bit))]

    def names(self) -> list[str]:
        return list(self.columns)

    def has(self, name: str) -> bool:
        return name in self.columns

    def bits(self, name: str) -> int:
        return len(self.columns[name])

    def encode(self, array: np.ndarray, name: str, values: np.ndarray | int) -> None:
        """Write ``values`` (one per row) into ``name``'s bit columns of ``array``."""
        values = np.asarray(values, dtype=np.int64)
        for b, col in enumerate(self.columns[name]):
            array[:, col] = (values >> b) & 1

    def decode(self, array: np.ndarray, name: str) -> np.ndarray:
        out = np.zeros(array.shape[0], dtype=np.int64)
        for b, col in enumerate(self.columns[name]):
            out |= array[:, col].astype(np.int64) << b
        return out


def latch_layout(circuit: Circuit) -> FieldLayout:
    return FieldLayout(circuit.latches)


def input_layout(circuit: Circuit) -> FieldLayout:
    return FieldLayout(circuit.inputs)


@dataclass(frozen=True)
class StepBatch:
    """A batch of one-step questions, one row each: the game state (``rx, ry, ox, oy,
    waits, g``) and the robot's move (``dx, dy``) that fix the circuit's latches, and the
    inputs of the next step (environment: ``robx, roby, obsx, obsy, glitches``;
    controller: ``movx, movy`` as raw codes 0..3, ``obsmove``). ``first`` marks rows
    that ask about the circuit's first step instead (reset latches; the state columns
    are then ignored), ``violated`` rows whose latches say an assumption was already
    broken."""

    rx: np.ndarray
    ry: np.ndarray
    ox: np.ndarray
    oy: np.ndarray
    waits: np.ndarray
    g: np.ndarray
    dx: np.ndarray
    dy: np.ndarray
    robx: np.ndarray
    roby: np.ndarray
    obsx: np.ndarray
    obsy: np.ndarray
    glitches: np.ndarray
    movx: np.ndarray
    movy: np.ndarray
    obsmove: np.ndarray
    first: np.ndarray
    violated: np.ndarray

    @staticmethod
    def of(n: int, **columns: np.ndarray | int) -> StepBatch:
        """A batch of ``n`` rows; columns not given are 0 (``first``/``violated`` false)."""
        names = StepBatch.__dataclass_fields__
        unknown = set(columns) - set(names)
        if unknown:
            raise TypeError(f"unknown columns {sorted(unknown)}")
        full = {k: np.broadcast_to(np.asarray(columns.get(k, 0), dtype=np.int32), (n,)).copy() for k in names}
        return StepBatch(**full)

    def __len__(self) -> int:
        return len(self.rx)


def expected_step(game: MovingObstacle, q: StepBatch) -> tuple[np.ndarray, np.ndarray]:
    """What the circuit must answer if it is ``game``: ``(err, violated_next)`` per row.

    * first step: the environment's inputs are legal iff they are the start (robot at
      (0, 0), obstacle at (m-2, m-2), counter 0); ``err`` iff they are and the
      controller's move is invalid or ``obsmove`` is true (the obstacle waits);
    * a row already violated: ``err`` false, violated stays;
    * otherwise the inputs are legal iff the robot is where move ``d`` takes it and
      ``(obs, glitches)`` is one of :meth:`MovingObstacle.obstacle_moves`; ``err`` iff
      they are legal and (the state was a collision, or ``obsmove`` is not "the
      obstacle stayed", or a move code is 3). A move of the obstacle from a state where
      it waits is a glitch.
    """
    m, c = game.size, game.glitches
    in_grid = (q.obsx <= m - 2) & (q.obsy <= m - 2) & (q.robx <= m - 1) & (q.roby <= m - 1) & (q.glitches <= c)
    bad_move = (q.movx == 3) | (q.movy == 3)
    # first step
    start = (q.robx == 0) & (q.roby == 0) & (q.obsx == m - 2) & (q.obsy == m - 2) & (q.glitches == 0)
    err_first = start & (bad_move | (q.obsmove == 1))
    # a later step
    robot_ok = (q.robx == np.clip(q.rx + q.dx, 0, m - 1)) & (q.roby == np.clip(q.ry + q.dy, 0, m - 1))
    step_x, step_y = q.obsx - q.ox, q.obsy - q.oy
    stayed = (step_x == 0) & (step_y == 0)
    small = (np.abs(step_x) <= 1) & (np.abs(step_y) <= 1)
    glitch = ~stayed & (q.waits == 1)
    counter_ok = (q.glitches >= q.g + glitch.astype(np.int64)) & (q.glitches <= c)
    legal = in_grid & robot_ok & small & counter_ok
    collision = (q.ox <= q.rx) & (q.rx <= q.ox + 1) & (q.oy <= q.ry) & (q.ry <= q.oy + 1)
    obsmove_wrong = (q.obsmove == 1) != stayed
    err_later = legal & (collision | obsmove_wrong | bad_move)
    first = q.first.astype(bool)
    violated = q.violated.astype(bool)
    err = np.where(violated, False, np.where(first, err_first, err_later))
    violated_next = violated | np.where(first, ~start, ~legal)
    return err, violated_next


def _encode(game: MovingObstacle, circuit: Circuit, q: StepBatch) -> tuple[np.ndarray, np.ndarray]:
    lat, inp = latch_layout(circuit), input_layout(circuit)
    n = len(q)
    latches = np.zeros((n, lat.width), dtype=bool)
    inputs = np.zeros((n, inp.width), dtype=bool)
    first = q.first.astype(bool)

    def later(v: np.ndarray) -> np.ndarray:
        return np.where(first, 0, v)

    lat.encode(latches, FIRST_ROUND, (~first).astype(np.int64))
    lat.encode(latches, VIOLATED, later(q.violated))
    for name, v in (
        ("prev_robx", q.rx),
        ("prev_roby", q.ry),
        ("prev_obsx", q.ox),
        ("prev_obsy", q.oy),
        ("prev_movx", q.dx + 1),
        ("prev_movy", q.dy + 1),
        ("prev_obsmove", 1 - q.waits),
    ):
        lat.encode(latches, name, later(v))
    if game.glitches:
        lat.encode(latches, "prev_glitches", later(q.g))
        inp.encode(inputs, "glitches", q.glitches)
    for name in ("robx", "roby", "obsx", "obsy", "movx", "movy", "obsmove"):
        inp.encode(inputs, name, getattr(q, name))
    return latches, inputs


def compare_step(game: MovingObstacle, circuit: Circuit, q: StepBatch, *, chunk: int = 1 << 16) -> dict:
    """Run one circuit step on every row of ``q`` and compare with
    :func:`expected_step`: ``err`` and the violation flag, and (on rows where no
    assumption is broken) that the next latches hold this step's inputs with
    ``IsNotFirstRound`` set. Returns counts and the first differing rows."""
    sim = Simulator(circuit)
    lat, inp = latch_layout(circuit), input_layout(circuit)
    expect_err, expect_violated = expected_step(game, q)
    rows = {"err": [], "violated": [], "latches": []}
    for lo in range(0, len(q), chunk):
        part = StepBatch(**{k: getattr(q, k)[lo : lo + chunk] for k in StepBatch.__dataclass_fields__})
        latches, inputs = _encode(game, circuit, part)
        out, nxt = sim.step(latches, inputs)
        err = out[:, 0]
        violated = lat.decode(nxt, VIOLATED).astype(bool)
        ok_rows = ~violated
        copied = np.ones(len(part), dtype=bool)
        for name in inp.names():
            copied &= lat.decode(nxt, "prev_" + name) == inp.decode(inputs, name)
        copied &= lat.decode(nxt, FIRST_ROUND) == 1
        sl = slice(lo, lo + len(part))
        for key, bad in (
            ("err", err != expect_err[sl]),
            ("violated", violated != expect_violated[sl]),
            ("latches", ok_rows & ~copied),
        ):
            rows[key].extend((np.nonzero(bad)[0] + lo).tolist())
    return {
        "rows": len(q),
        **{f"{k}_mismatches": len(v) for k, v in rows.items()},
        "first_mismatches": {k: v[:5] for k, v in rows.items() if v},
    }
