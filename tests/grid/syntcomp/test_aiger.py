"""The AIGER reader and simulator (:mod:`plansynth.grid.syntcomp.aiger`) on hand-written
circuits in both forms, on random circuits against a gate-by-gate reference, and on a
benchmark circuit rewritten in binary form."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.errors import InvalidProblem
from plansynth.grid.syntcomp.aiger import Circuit, Simulator, parse, read

DATA = Path(__file__).parent / "data"

# A 2-bit counter that counts while the environment's input `en` is 1 and the controller
# does not `hold` it; bad when it is 3. Latch l0 (lit 6) is bit 0, l1 (lit 8) bit 1:
#   step = en & !hold (10); next0 = l0 xor step = !16; next1 = l1 xor (l0 & step) = !24
COUNTER_AAG = b"""aag 13 2 2 1 9
2
4
6 17
8 25
26
10 2 5
12 6 11
14 7 10
16 13 15
18 6 10
20 8 19
22 9 18
24 21 23
26 6 8
i0 en
i1 controllable_hold
l0 bit0
l1 bit1
o0 bad
c
a hand-written counter
"""


def test_ascii_counter():
    c = parse(COUNTER_AAG)
    assert [i.name for i in c.inputs] == ["en", "controllable_hold"]
    assert [i.name for i in c.controllable_inputs] == ["controllable_hold"]
    assert [i.name for i in c.uncontrollable_inputs] == ["en"]
    assert [la.name for la in c.latches] == ["bit0", "bit1"] and all(la.init == 0 for la in c.latches)
    assert c.bad == 26 and c.comments == ("a hand-written counter",)
    sim = Simulator(c)
    state = sim.initial_state(1)
    seen = []
    for en, hold in [(1, 0), (1, 1), (0, 0), (1, 0), (1, 0)]:
        out, state = sim.step(state, np.array([[en, hold]], bool))
        seen.append((int(out[0, 0]), int(state[0, 0]) + 2 * int(state[0, 1])))
    assert seen == [(0, 1), (0, 1), (0, 1), (0, 2), (0, 3)]
    assert sim.bad(state, np.array([[0, 0]], bool)).tolist() == [True]


def test_gates_in_any_order_in_ascii():
    lines = COUNTER_AAG.split(b"\n")
    shuffled = b"\n".join(lines[:6] + lines[6:15][::-1] + lines[15:])
    a, b = parse(COUNTER_AAG), parse(shuffled)
    rng = np.random.default_rng(0)
    s, i = rng.integers(0, 2, (64, 2)).astype(bool), rng.integers(0, 2, (64, 2)).astype(bool)
    for x, y in zip(Simulator(a).step(s, i), Simulator(b).step(s, i)):
        np.testing.assert_array_equal(x, y)


def to_binary(c: Circuit) -> bytes:
    """The circuit in AIGER's binary form (inputs, latches and gates renumbered in order)."""
    ni, nl = len(c.inputs), len(c.latches)
    rename = {0: 0}
    for k, i in enumerate(c.inputs):
        rename[i.literal >> 1] = k + 1
    for k, la in enumerate(c.latches):
        rename[la.literal >> 1] = ni + k + 1
    for k, (lhs, _, _) in enumerate(c.ands):
        rename[lhs >> 1] = ni + nl + k + 1

    def lit(x: int) -> int:
        return 2 * rename[x >> 1] + (x & 1)

    out = [f"aig {ni + nl + len(c.ands)} {ni} {nl} {len(c.outputs)} {len(c.ands)}\n".encode()]
    for la in c.latches:
        init = "" if la.init == 0 else f" {1 if la.init == 1 else lit(la.literal)}"
        out.append(f"{lit(la.next)}{init}\n".encode())
    out += [f"{lit(o.literal)}\n".encode() for o in c.outputs]
    for lhs, r0, r1 in c.ands:
        a, b, d = lit(lhs), *sorted((lit(r0), lit(r1)), reverse=True)
        for delta in (a - b, b - d):
            while delta >= 0x80:
                out.append(bytes([(delta & 0x7F) | 0x80]))
                delta >>= 7
            out.append(bytes([delta]))
    for k, i in enumerate(c.inputs):
        if i.name:
            out.append(f"i{k} {i.name}\n".encode())
    for k, la in enumerate(c.latches):
        if la.name:
            out.append(f"l{k} {la.name}\n".encode())
    for k, o in enumerate(c.outputs):
        if o.name:
            out.append(f"o{k} {o.name}\n".encode())
    return b"".join(out)


def same_behaviour(a: Circuit, b: Circuit, rng: np.random.Generator, n: int = 256) -> None:
    s = rng.integers(0, 2, (n, len(a.latches))).astype(bool)
    i = rng.integers(0, 2, (n, len(a.inputs))).astype(bool)
    for x, y in zip(Simulator(a).step(s, i), Simulator(b).step(s, i)):
        np.testing.assert_array_equal(x, y)


def test_binary_counter():
    a = parse(COUNTER_AAG)
    b = parse(to_binary(a))
    assert [i.name for i in b.inputs] == ["en", "controllable_hold"] and b.bad == 26
    same_behaviour(a, b, np.random.default_rng(1))


def test_binary_form_of_a_benchmark_circuit():
    a = read(DATA / "moving_obstacle_8x8_1glitches.aag")
    data = to_binary(a)
    assert data.startswith(b"aig ") and len(data) < len((DATA / "moving_obstacle_8x8_1glitches.aag").read_bytes())
    b = parse(data)
    assert [i.name for i in b.inputs] == [i.name for i in a.inputs]
    same_behaviour(a, b, np.random.default_rng(2), n=4096)


@st.composite
def random_circuits(draw):
    ni, nl, na = draw(st.integers(0, 4)), draw(st.integers(0, 3)), draw(st.integers(0, 12))
    lits = list(range(2, 2 * (ni + nl) + 2, 2))
    ands = []
    for k in range(na):
        lhs = 2 * (ni + nl + k + 1)
        pool = [0, 1] + lits + [x ^ 1 for x in lits]
        ands.append((lhs, draw(st.sampled_from(pool)), draw(st.sampled_from(pool))))
        lits.append(lhs)
    pool = [0, 1] + lits + [x ^ 1 for x in lits]
    latches = [(2 * (ni + k + 1), draw(st.sampled_from(pool)), draw(st.sampled_from([0, 1, None]))) for k in range(nl)]
    outputs = draw(st.lists(st.sampled_from(pool), min_size=1, max_size=3))
    text = [f"aag {ni + nl + na} {ni} {nl} {len(outputs)} {na}"]
    text += [str(2 * (k + 1)) for k in range(ni)]
    text += [f"{lit} {nxt}" + ("" if init == 0 else f" {lit if init is None else 1}") for lit, nxt, init in latches]
    text += [str(o) for o in outputs]
    text += [f"{a} {b} {c}" for a, b, c in ands]
    return "\n".join(text) + "\n", ni, latches, ands, outputs


def reference_step(ni, latches, ands, outputs, state, inputs):
    """Gate by gate, with Python ints."""
    val = {0: 0}
    for k in range(ni):
        val[k + 1] = inputs[k]
    for k, (lit, _, _) in enumerate(latches):
        val[lit >> 1] = state[k]

    def lit_value(x):
        return val[x >> 1] ^ (x & 1)

    for lhs, r0, r1 in ands:
        val[lhs >> 1] = lit_value(r0) & lit_value(r1)
    return [lit_value(o) for o in outputs], [lit_value(nxt) for _, nxt, _ in latches]


@settings(max_examples=60)
@given(random_circuits(), st.integers(0, 2**32 - 1))
def test_random_circuits_against_a_reference(circ, seed):
    text, ni, latches, ands, outputs = circ
    c = parse(text.encode())
    assert [la.init for la in c.latches] == [init for _, _, init in latches]
    rng = np.random.default_rng(seed)
    n = 64
    state = rng.integers(0, 2, (n, len(latches))).astype(bool)
    inputs = rng.integers(0, 2, (n, ni)).astype(bool)
    out, nxt = Simulator(c).step(state, inputs)
    for row in range(n):
        ro, rn = reference_step(
            ni, latches, ands, outputs, state[row].astype(int).tolist(), inputs[row].astype(int).tolist()
        )
        assert out[row].astype(int).tolist() == ro and nxt[row].astype(int).tolist() == rn
    same_behaviour(c, parse(to_binary(c)), rng)
    # reset values: 0, 1, or free (given by the caller)
    free = rng.integers(0, 2, (n, len(latches))).astype(bool)
    init = Simulator(c).initial_state(n, free)
    for k, (_, _, v) in enumerate(latches):
        np.testing.assert_array_equal(init[:, k], free[:, k] if v is None else bool(v))


def test_aiger_1_9_header_and_bad_section():
    c = parse(b"aag 3 1 1 0 1 1\n2\n4 3 4\n6\n6 2 4\nb0 both\n")
    assert c.outputs == () and c.bad == 6 and c.bad_properties[0].name == "both"
    assert c.latches[0].init is None  # reset = its own literal: not initialised


@pytest.mark.parametrize(
    "data,field",
    [
        (b"aig 1 1\n", "header"),
        (b"aag 1 2 0 0 0\n2\n4\n", "header"),
        (b"aag 2 1 0 1 1\n2\n4\n4 2 6\n", "literals"),
        (b"aag 3 1 0 1 2\n2\n4\n4 2 6\n6 4 2\n", "ands"),
        (b"aag 2 1 0 1 1\n2\n2\n2 2 2\n", "ands"),
        (b"aag 1 1 0 1 0\n2\n", "outputs"),
        (b"aag 2 0 1 0 0\n4 2 7\n", "latches"),
        (b"aag 1 0 0 0 0 0 0 1 0\n", "header"),
    ],
)
def test_malformed_files_are_named_errors(data, field):
    with pytest.raises(InvalidProblem, match=field):
        parse(data)


def test_a_game_needs_one_bad_output():
    with pytest.raises(InvalidProblem, match="one bad output"):
        _ = parse(b"aag 1 1 0 2 0\n2\n2\n3\n").bad
