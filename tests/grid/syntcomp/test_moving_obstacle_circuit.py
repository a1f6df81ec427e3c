"""The benchmark's own circuits are the explicit game of
:mod:`plansynth.grid.syntcomp.moving_obstacle` (SYNTCOMP ``aiger/moving_obstacle``, the
circuits copied into ``data/``).

8 x 8 (c = 0, 1): exhaustive. Every state of the game and every robot move fix the
circuit's latches; then every environment reply (all 9 obstacle displacements, every
counter value, both ``obsmove`` values; the illegal ones included), every controller
move code (0..3 in x and y), every robot position and every obstacle position the input
bits can encode, and every input of the first step. On each row the circuit's ``err``,
its "assumption violated" flag and its next latches must be what the game says.
16 x 16 (c = 3, 4): the same comparison on random rows, plus random runs of the circuit
and the game side by side.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.grid.syntcomp.aiger import Simulator, read
from plansynth.grid.syntcomp.moving_obstacle import MOVES, MovingObstacle, State, circuit_name
from plansynth.grid.syntcomp.moving_obstacle_circuit import (
    FIRST_ROUND,
    VIOLATED,
    StepBatch,
    compare_step,
    expected_step,
    input_layout,
    latch_layout,
)

DATA = Path(__file__).parent / "data"


def circuit(m: int, c: int):
    return read(DATA / circuit_name(m, c))


def state_move_grid(game: MovingObstacle, moves=MOVES, rx: int | None = None) -> dict[str, np.ndarray]:
    """Every (state, robot move) pair as columns (those with the robot in column ``rx``
    if given: the exhaustive checks go column by column to keep their memory small)."""
    m, c = game.size, game.glitches
    axes = np.meshgrid(
        np.arange(m) if rx is None else np.array([rx]),
        np.arange(m),
        np.arange(m - 1),
        np.arange(m - 1),
        np.arange(2),
        np.arange(c + 1),
        np.arange(len(moves)),
        indexing="ij",
    )
    rx, ry, ox, oy, waits, g, k = (a.ravel() for a in axes)
    d = np.array(moves)[k]
    return dict(rx=rx, ry=ry, ox=ox, oy=oy, waits=waits, g=g, dx=d[:, 0], dy=d[:, 1])


def each_state_and_move(game: MovingObstacle, times: int, moves=MOVES):
    """Every (state, robot move) pair ``times`` times over, and the copy number 0..times-1
    of each row (to vary the next step's inputs over), one robot column at a time."""
    for rx in range(game.size):
        cols = {k: np.repeat(v, times) for k, v in state_move_grid(game, moves, rx).items()}
        yield cols, np.tile(np.arange(times), len(cols["rx"]) // times)


def assert_same(game, circ, q: StepBatch) -> dict:
    report = compare_step(game, circ, q)
    assert report["err_mismatches"] == 0, report
    assert report["violated_mismatches"] == 0, report
    assert report["latches_mismatches"] == 0, report
    return report


def test_the_circuits_name_the_fields_the_game_reads():
    c = circuit(8, 1)
    inputs, latches = input_layout(c), latch_layout(c)
    assert inputs.names() == ["obsx", "obsy", "robx", "roby", "glitches", "movx", "movy", "obsmove"]
    assert inputs.ranges["robx"] == (0, 7) and inputs.ranges["obsx"] == (0, 6)
    assert inputs.ranges["glitches"] == (0, 1) and inputs.ranges["movx"] == (0, 2)
    assert [i.name.split("@")[0] for i in c.controllable_inputs] == [
        "controllable_movx",
        "controllable_movx",
        "controllable_movy",
        "controllable_movy",
        "controllable_obsmove",
    ]
    assert set(latches.names()) == {FIRST_ROUND, VIOLATED} | {"prev_" + n for n in inputs.names()}
    assert all(la.init == 0 for la in c.latches)
    assert [o.name for o in c.outputs] == ["err"]
    assert "STATUS : unrealizable" in c.comments


@pytest.mark.parametrize("c", [0, 1])
def test_8x8_every_environment_reply(c):
    game, circ = MovingObstacle(8, c), circuit(8, c)
    rng = np.random.default_rng(c)
    kinds = np.zeros(3, int)
    # every obstacle displacement (9), counter value (c + 1) and obsmove value (2)
    for cols, j in each_state_and_move(game, 9 * (c + 1) * 2):
        kinds += _check_env_replies(game, circ, c, cols, j, rng)
    # the batches held winning, losing and illegal rows alike
    assert (kinds > 1000).all(), kinds


def _check_env_replies(game, circ, c, cols, j, rng) -> np.ndarray:
    delta = np.array(MOVES)[j % 9]
    g_next = (j // 9) % (c + 1)
    obsmove = j // (9 * (c + 1))
    obsx, obsy = cols["ox"] + delta[:, 0], cols["oy"] + delta[:, 1]
    keep = (obsx >= 0) & (obsy >= 0)  # negative positions have no encoding; the top edge is 7 > 6, kept
    q = StepBatch.of(
        int(keep.sum()),
        **{k: v[keep] for k, v in cols.items()},
        robx=np.clip(cols["rx"] + cols["dx"], 0, 7)[keep],
        roby=np.clip(cols["ry"] + cols["dy"], 0, 7)[keep],
        obsx=obsx[keep],
        obsy=obsy[keep],
        glitches=g_next[keep],
        obsmove=obsmove[keep],
        movx=rng.integers(0, 3, int(keep.sum())),
        movy=rng.integers(0, 3, int(keep.sum())),
    )
    err, violated = expected_step(game, q)
    assert_same(game, circ, q)
    return np.array([err.sum(), (~err & ~violated).sum(), violated.sum()])


@pytest.mark.parametrize("c", [0, 1])
def test_8x8_every_controller_move_code(c):
    game, circ = MovingObstacle(8, c), circuit(8, c)
    for cols, code in each_state_and_move(game, 16):
        q = StepBatch.of(
            len(code),
            **cols,
            robx=np.clip(cols["rx"] + cols["dx"], 0, 7),
            roby=np.clip(cols["ry"] + cols["dy"], 0, 7),
            obsx=cols["ox"],
            obsy=cols["oy"],
            glitches=cols["g"],
            obsmove=1,
            movx=code % 4,
            movy=code // 4,
        )
        assert_same(game, circ, q)


@pytest.mark.parametrize("c", [0, 1])
def test_8x8_every_robot_position_the_bits_encode(c):
    game, circ = MovingObstacle(8, c), circuit(8, c)
    for cols, cell in each_state_and_move(game, 64):
        n = len(cell)
        q = StepBatch.of(
            n,
            **cols,
            robx=cell % 8,
            roby=cell // 8,
            obsx=cols["ox"],
            obsy=cols["oy"],
            glitches=cols["g"],
            obsmove=1,
            movx=1,
            movy=1,
        )
        _, violated = expected_step(game, q)
        assert violated.sum() == n * 63 // 64  # one position per row is where the move leads
        assert_same(game, circ, q)


@pytest.mark.parametrize("c", [0, 1])
def test_8x8_every_obstacle_position_and_counter_the_bits_encode(c):
    game, circ = MovingObstacle(8, c), circuit(8, c)
    gbits = 1 if c else 0
    for cols, j in each_state_and_move(game, 64 << gbits, moves=((0, 0),)):
        q = StepBatch.of(
            len(j),
            **cols,
            robx=cols["rx"],
            roby=cols["ry"],
            obsx=j % 8,
            obsy=(j // 8) % 8,
            glitches=j // 64,
            obsmove=1,
            movx=1,
            movy=1,
        )
        assert_same(game, circ, q)


@pytest.mark.parametrize("c", [0, 1])
def test_8x8_every_first_step(c):
    game, circ = MovingObstacle(8, c), circuit(8, c)
    gvals = 2 if c else 1
    j = np.arange(64 * 64 * gvals * 2 * 16)
    q = StepBatch.of(
        len(j),
        first=1,
        robx=j % 8,
        roby=(j // 8) % 8,
        obsx=(j // 64) % 8,
        obsy=(j // 512) % 8,
        glitches=(j // 4096) % gvals,
        obsmove=(j // (4096 * gvals)) % 2,
        movx=(j // (8192 * gvals)) % 4,
        movy=(j // (32768 * gvals)) % 4,
    )
    err, violated = expected_step(game, q)
    assert (~violated).sum() == 2 * 16 and err.sum() == 2 * 16 - 9
    assert_same(game, circ, q)


def random_rows(game: MovingObstacle, n: int, seed: int) -> StepBatch:
    """Random states, moves and replies: mostly legal, some with one field off."""
    m, c = game.size, game.glitches
    rng = np.random.default_rng(seed)
    rx, ry = rng.integers(0, m, n), rng.integers(0, m, n)
    ox, oy = rng.integers(0, m - 1, n), rng.integers(0, m - 1, n)
    d = np.array(MOVES)[rng.integers(0, 9, n)]
    e = np.array(MOVES)[rng.integers(0, 9, n)]
    g = rng.integers(0, c + 1, n)
    robx, roby = np.clip(rx + d[:, 0], 0, m - 1), np.clip(ry + d[:, 1], 0, m - 1)
    off = rng.integers(0, 6, n)  # 0..2: legal-looking; 3: robot elsewhere; 4: obstacle anywhere; 5: counter anywhere
    robx = np.where(off == 3, rng.integers(0, m, n), robx)
    obsx = np.where(off == 4, rng.integers(0, m, n), np.clip(ox + e[:, 0], 0, m - 2))
    obsy = np.where(off == 4, rng.integers(0, m, n), np.clip(oy + e[:, 1], 0, m - 2))
    gbits = max(c, 1).bit_length() if c else 0
    glitches = np.where(
        off == 5, rng.integers(0, 1 << gbits, n) if gbits else 0, np.minimum(g + rng.integers(0, 2, n), c)
    )
    return StepBatch.of(
        n,
        rx=rx,
        ry=ry,
        ox=ox,
        oy=oy,
        waits=rng.integers(0, 2, n),
        g=g,
        dx=d[:, 0],
        dy=d[:, 1],
        robx=robx,
        roby=roby,
        obsx=obsx,
        obsy=obsy,
        glitches=glitches,
        movx=rng.choice([0, 1, 2, 1, 0, 2, 3], n),
        movy=rng.choice([0, 1, 2, 1, 0, 2, 3], n),
        obsmove=rng.integers(0, 2, n),
        first=rng.random(n) < 0.02,
        violated=rng.random(n) < 0.02,
    )


@pytest.mark.parametrize("c", [3, 4])
def test_16x16_random_rows(c):
    game, circ = MovingObstacle(16, c), circuit(16, c)
    q = random_rows(game, 200_000, seed=c)
    err, violated = expected_step(game, q)
    assert err.sum() > 1000 and (~err & ~violated).sum() > 1000 and violated.sum() > 1000
    assert_same(game, circ, q)


@settings(max_examples=300)
@given(
    c=st.sampled_from([3, 4]),
    rx=st.integers(0, 15),
    ry=st.integers(0, 15),
    ox=st.integers(0, 14),
    oy=st.integers(0, 14),
    waits=st.booleans(),
    g=st.integers(0, 4),
    move=st.sampled_from(MOVES),
    reply=st.integers(0, 10**6),
    obsmove=st.booleans(),
)
def test_16x16_each_legal_reply_of_the_game_is_a_legal_input_of_the_circuit(
    c, rx, ry, ox, oy, waits, g, move, reply, obsmove
):
    game, circ = MovingObstacle(16, c), CIRCUITS_16[c]
    state = State((rx, ry), (ox, oy), waits, min(g, c))
    replies = list(game.successors(state, move))
    nxt = replies[reply % len(replies)]
    q = StepBatch.of(
        1,
        rx=rx,
        ry=ry,
        ox=ox,
        oy=oy,
        waits=int(waits),
        g=state.glitches,
        dx=move[0],
        dy=move[1],
        robx=nxt.robot[0],
        roby=nxt.robot[1],
        obsx=nxt.obstacle[0],
        obsy=nxt.obstacle[1],
        glitches=nxt.glitches,
        movx=1,
        movy=1,
        obsmove=int(obsmove),
    )
    err, violated = expected_step(game, q)
    assert not violated[0]
    assert err[0] == (game.is_collision(state) or obsmove == nxt.obstacle_waits)
    assert_same(game, circ, q)


CIRCUITS_16 = {c: circuit(16, c) for c in (3, 4)}


@pytest.mark.parametrize("m,c", [(8, 1), (16, 3), (16, 4)])
def test_random_runs_of_the_circuit_follow_the_game(m, c):
    """Play the circuit and the game side by side: the environment picks legal replies
    of the game at random, the robot random moves, mostly towards the obstacle (so that
    runs end in collisions); the circuit never flags a broken
    assumption, and flags ``err`` exactly at the step after the game's first collision."""
    game, circ = MovingObstacle(m, c), circuit(m, c)
    sim, lat, inp = Simulator(circ), latch_layout(circ), input_layout(circ)
    rng = np.random.default_rng(m + c)
    collisions = 0
    for _run in range(60):
        latches = sim.initial_state(1)
        state, previous = game.initial, None
        for _step in range(4 * m):
            if rng.random() < 0.6:
                move = tuple(int(v) for v in np.sign(np.array(state.obstacle) - np.array(state.robot)))
            else:
                move = MOVES[rng.integers(9)]
            inputs = np.zeros((1, inp.width), bool)
            for name, v in {
                "robx": state.robot[0],
                "roby": state.robot[1],
                "obsx": state.obstacle[0],
                "obsy": state.obstacle[1],
                "glitches": state.glitches,
                "movx": move[0] + 1,
                "movy": move[1] + 1,
                "obsmove": int(not state.obstacle_waits),
            }.items():
                if inp.has(name):
                    inp.encode(inputs, name, v)
            out, latches = sim.step(latches, inputs)
            assert not lat.decode(latches, VIOLATED)[0]
            # the circuit reads the collision guarantee from the latched (previous) positions
            collided = previous is not None and game.is_collision(previous)
            assert bool(out[0, 0]) == collided, (previous, state)
            if collided:
                collisions += 1
                break
            replies = list(game.successors(state, move))
            previous, state = state, replies[rng.integers(len(replies))]
    assert collisions > 20
