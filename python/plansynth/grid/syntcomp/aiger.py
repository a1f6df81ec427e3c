"""AIGER circuits as SYNTCOMP's safety games: a reader (ASCII ``aag`` and binary ``aig``)
and a batched simulator.

The format is Biere's AIGER (the 1.9 report "The AIGER And-Inverter Graph (AIG) Format
Version 20071012", extended in 2014 with bad-state, constraint, justice and fairness
sections and latch reset values). SYNTCOMP's safety games (Jacobs et al., "The first
reactive synthesis competition (SYNTCOMP 2014)", STTT 2017, Sect. 3, arXiv 1506.08726;
the benchmark format is arXiv 1405.5793) are AIGER circuits with one convention on top:

* an input whose symbol starts with ``controllable_`` is set by the controller, every
  other input by the environment;
* the single output is the *bad* signal; the controller wins iff it can keep it 0
  forever, choosing its inputs in each step after seeing the latches and the
  environment's inputs of that step.

A literal ``2v + s`` is variable ``v`` negated when ``s = 1``; variable 0 is the
constant (literal 0 is false, 1 true). Latch reset values are 0 (the default), 1, or the
latch's own literal (not initialised; :attr:`Latch.init` is then ``None``).

Why not ``py-aiger`` (PyPI, MIT, reads both formats): its header pattern takes exactly
five numbers, so an AIGER 1.9 header with a B/C/J/F count does not parse; it turns an
uninitialised latch (reset = its own literal) into reset 1; it evaluates a circuit one
Python object per gate and step, where the correspondence checks here simulate hundreds
of thousands of states at once; and it would add five dependencies. The format is small:
this reader is about a hundred lines, and its tests are hand-written circuits in both
forms.

>>> c = parse(b"aag 3 2 0 1 1\\n2\\n4\\n7\\n6 2 4\\ni0 a\\ni1 controllable_b\\no0 err\\n")
>>> [i.name for i in c.inputs], [i.controllable for i in c.inputs], c.bad
(['a', 'controllable_b'], [False, True], 7)
>>> import numpy as np
>>> sim = Simulator(c)
>>> out, _ = sim.step(np.zeros((4, 0), bool), np.array([[0, 0], [0, 1], [1, 0], [1, 1]], bool))
>>> out[:, 0].tolist()                     # err = not (a and b)
[True, True, True, False]
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from plansynth.errors import InvalidProblem

__all__ = ["Circuit", "Input", "Latch", "Output", "Simulator", "parse", "read", "CONTROLLABLE_PREFIX"]

#: SYNTCOMP's mark of an input the controller sets.
CONTROLLABLE_PREFIX = "controllable_"

_HEADER = re.compile(rb"(aag|aig) (\d+) (\d+) (\d+) (\d+) (\d+)((?: \d+){0,4})\n")


@dataclass(frozen=True)
class Input:
    """An input: its (even) literal and its symbol, if the file names it."""

    literal: int
    name: str | None = None

    @property
    def controllable(self) -> bool:
        """Set by the controller (SYNTCOMP: the symbol starts with ``controllable_``)."""
        return self.name is not None and self.name.startswith(CONTROLLABLE_PREFIX)


@dataclass(frozen=True)
class Latch:
    """A latch: its (even) literal, the literal of its next value and its reset value
    (0, 1, or ``None`` for a latch the file leaves uninitialised)."""

    literal: int
    next: int
    init: int | None = 0
    name: str | None = None


@dataclass(frozen=True)
class Output:
    """An output (or a bad-state property): its literal and its symbol."""

    literal: int
    name: str | None = None


@dataclass(frozen=True)
class Circuit:
    """A parsed AIGER file; ``ands`` are ``(lhs, rhs0, rhs1)`` in an order where every
    gate comes after the gates it reads (sorted on reading)."""

    max_var: int
    inputs: tuple[Input, ...]
    latches: tuple[Latch, ...]
    outputs: tuple[Output, ...]
    ands: tuple[tuple[int, int, int], ...]
    bad_properties: tuple[Output, ...] = ()
    constraints: tuple[Output, ...] = ()
    comments: tuple[str, ...] = ()
    file: str | None = None

    @property
    def bad(self) -> int:
        """The literal of SYNTCOMP's bad signal: the single output (or, for a file in
        the 1.9 style with no output, its single bad-state property)."""
        props = self.outputs or self.bad_properties
        if len(props) != 1:
            raise InvalidProblem(
                self.file, "outputs", f"a SYNTCOMP game has one bad output, this file has {len(props)}"
            )
        return props[0].literal

    @property
    def controllable_inputs(self) -> tuple[Input, ...]:
        return tuple(i for i in self.inputs if i.controllable)

    @property
    def uncontrollable_inputs(self) -> tuple[Input, ...]:
        return tuple(i for i in self.inputs if not i.controllable)

    def input_index(self, name: str) -> int:
        """Position of the input named ``name`` in :attr:`inputs`."""
        return _index(self.inputs, name, self.file, "inputs")

    def latch_index(self, name: str) -> int:
        """Position of the latch named ``name`` in :attr:`latches`."""
        return _index(self.latches, name, self.file, "latches")


def _index(items: Sequence[Input | Latch], name: str, file: str | None, field: str) -> int:
    for k, item in enumerate(items):
        if item.name == name:
            return k
    raise InvalidProblem(file, field, f"no symbol {name!r}")


def read(path: str | Path) -> Circuit:
    """Read an ``.aag`` or ``.aig`` file (the header says which)."""
    return parse(Path(path).read_bytes(), file=str(path))


def parse(data: bytes, file: str | None = None) -> Circuit:
    """Parse the bytes of an AIGER file, ASCII or binary.

    Raises :class:`~plansynth.errors.InvalidProblem` naming the part of the file that
    breaks the format.
    """
    reader = _Reader(data, file)
    return reader.circuit()


class _Reader:
    def __init__(self, data: bytes, file: str | None) -> None:
        self.data = data
        self.pos = 0
        self.file = file

    def fail(self, field: str, reason: str) -> InvalidProblem:
        return InvalidProblem(self.file, field, reason)

    def line(self, field: str) -> bytes:
        end = self.data.find(b"\n", self.pos)
        if end < 0:
            if self.pos >= len(self.data):
                raise self.fail(field, "the file ends early")
            end = len(self.data)
        text = self.data[self.pos : end]
        self.pos = end + 1
        return text.rstrip(b"\r")

    def numbers(self, field: str, count: tuple[int, ...]) -> list[int]:
        text = self.line(field)
        parts = text.split()
        if len(parts) not in count or not all(p.isdigit() for p in parts):
            raise self.fail(field, f"expected {' or '.join(map(str, count))} unsigned numbers, got {text[:60]!r}")
        return [int(p) for p in parts]

    def delta(self, field: str) -> int:
        value, shift = 0, 0
        while True:
            if self.pos >= len(self.data):
                raise self.fail(field, "the binary gate section ends early")
            byte = self.data[self.pos]
            self.pos += 1
            value |= (byte & 0x7F) << shift
            if not byte & 0x80:
                return value
            shift += 7
            if shift > 63:
                raise self.fail(field, "a delta longer than 64 bits")

    def circuit(self) -> Circuit:
        header = _HEADER.match(self.data)
        if header is None:
            raise self.fail("header", "not an AIGER header ('aag M I L O A' or 'aig M I L O A', up to 4 more counts)")
        self.pos = header.end()
        binary = header.group(1) == b"aig"
        m, ni, nl, no, na = (int(header.group(k)) for k in range(2, 7))
        extra = [int(x) for x in header.group(7).split()] + [0, 0, 0, 0]
        nb, nc, nj, nf = extra[:4]
        if ni + nl + na > m:
            raise self.fail("header", f"M = {m} is less than I + L + A = {ni + nl + na}")
        if nj or nf:
            raise self.fail("header", "justice and fairness sections are not part of a safety game")

        if binary:
            input_lits = [2 * (k + 1) for k in range(ni)]
        else:
            input_lits = [self.numbers(f"inputs[{k}]", (1,))[0] for k in range(ni)]
        latch_rows = []
        for k in range(nl):
            row = self.numbers(f"latches[{k}]", (1, 2) if binary else (2, 3))
            if binary:
                row = [2 * (ni + k + 1)] + row
            latch_rows.append(row)
        out_lits = [self.numbers(f"outputs[{k}]", (1,))[0] for k in range(no)]
        bad_lits = [self.numbers(f"bad[{k}]", (1,))[0] for k in range(nb)]
        con_lits = [self.numbers(f"constraints[{k}]", (1,))[0] for k in range(nc)]
        if binary:
            ands = []
            for k in range(na):
                lhs = 2 * (ni + nl + k + 1)
                d0 = self.delta(f"ands[{k}]")
                d1 = self.delta(f"ands[{k}]")
                if d0 > lhs or d1 > lhs - d0 or d0 == 0:
                    raise self.fail(f"ands[{k}]", "a delta that does not give 0 <= rhs1 <= rhs0 < lhs")
                ands.append((lhs, lhs - d0, lhs - d0 - d1))
        else:
            ands = [tuple(self.numbers(f"ands[{k}]", (3,))) for k in range(na)]

        names: dict[tuple[str, int], str] = {}
        comments: list[str] = []
        while self.pos < len(self.data):
            text = self.line("symbols").decode("utf-8", "replace")
            if text == "c":
                comments = self.data[self.pos :].decode("utf-8", "replace").splitlines()
                break
            sym = re.fullmatch(r"([ilobc])(\d+) (.+)", text)
            if sym is None:
                if not text.strip():
                    continue
                raise self.fail("symbols", f"not a symbol line: {text[:60]!r}")
            names[(sym.group(1), int(sym.group(2)))] = sym.group(3)

        inputs = tuple(Input(lit, names.get(("i", k))) for k, lit in enumerate(input_lits))
        latches = []
        for k, row in enumerate(latch_rows):
            lit, nxt = row[0], row[1]
            init = row[2] if len(row) > 2 else 0
            if init not in (0, 1, lit):
                raise self.fail(f"latches[{k}]", f"reset {init} is none of 0, 1 or the latch's literal {lit}")
            latches.append(Latch(lit, nxt, None if init == lit and lit > 1 else init, names.get(("l", k))))
        circuit = Circuit(
            max_var=m,
            inputs=inputs,
            latches=tuple(latches),
            outputs=tuple(Output(lit, names.get(("o", k))) for k, lit in enumerate(out_lits)),
            ands=_sorted_ands(ands, self),
            bad_properties=tuple(Output(lit, names.get(("b", k))) for k, lit in enumerate(bad_lits)),
            constraints=tuple(Output(lit, names.get(("c", k))) for k, lit in enumerate(con_lits)),
            comments=tuple(comments),
            file=self.file,
        )
        _check_literals(circuit, self)
        return circuit


def _check_literals(c: Circuit, reader: _Reader) -> None:
    defined = {0}
    for field, lits in (
        ("inputs", [i.literal for i in c.inputs]),
        ("latches", [la.literal for la in c.latches]),
        ("ands", [a[0] for a in c.ands]),
    ):
        for k, lit in enumerate(lits):
            if lit & 1 or lit < 2 or lit >> 1 > c.max_var:
                raise reader.fail(f"{field}[{k}]", f"{lit} is not an even literal in 2..2M")
            if lit >> 1 in defined:
                raise reader.fail(f"{field}[{k}]", f"variable {lit >> 1} is defined twice")
            defined.add(lit >> 1)
    used = (
        [la.next for la in c.latches]
        + [o.literal for o in c.outputs + c.bad_properties + c.constraints]
        + [r for a in c.ands for r in a[1:]]
    )
    for lit in used:
        if lit >> 1 not in defined:
            raise reader.fail("literals", f"literal {lit} reads variable {lit >> 1}, which nothing defines")


def _sorted_ands(ands: list, reader: _Reader) -> tuple[tuple[int, int, int], ...]:
    """The gates in an order where each follows the gates it reads (binary files are
    already so ordered; ASCII files need not be)."""
    gate = {lhs >> 1: (lhs, r0, r1) for lhs, r0, r1 in ands}
    done: set[int] = set()
    on_path: set[int] = set()
    order: list[tuple[int, int, int]] = []
    for root in gate:
        stack = [(root, False)]
        while stack:
            var, expanded = stack.pop()
            if expanded:
                on_path.discard(var)
                done.add(var)
                order.append(gate[var])
                continue
            if var in done:
                continue
            stack.append((var, True))
            on_path.add(var)
            for r in gate[var][1:]:
                if r >> 1 in on_path:
                    raise reader.fail("ands", f"a combinational cycle through variable {r >> 1}")
                if r >> 1 in gate and r >> 1 not in done:
                    stack.append((r >> 1, False))
    return tuple(order)


class Simulator:
    """Steps a circuit on a batch of (latch state, input) pairs at once.

    States are boolean arrays of shape ``(batch, L)`` in the order of
    :attr:`Circuit.latches`; inputs ``(batch, I)`` in the order of
    :attr:`Circuit.inputs`.
    """

    def __init__(self, circuit: Circuit) -> None:
        self.circuit = circuit
        self._ands = np.array(circuit.ands, dtype=np.int64).reshape(-1, 3)
        self._in_vars = np.array([i.literal >> 1 for i in circuit.inputs], dtype=np.int64)
        self._latch_vars = np.array([la.literal >> 1 for la in circuit.latches], dtype=np.int64)
        self._latch_next = np.array([la.next for la in circuit.latches], dtype=np.int64)
        self._outs = np.array([o.literal for o in circuit.outputs], dtype=np.int64)

    def initial_state(self, batch: int = 1, free: np.ndarray | None = None) -> np.ndarray:
        """The reset state, ``batch`` times; ``free`` (shape ``(batch, L)``) gives the
        values of the latches the file leaves uninitialised (default 0)."""
        state = np.zeros((batch, len(self.circuit.latches)), dtype=bool)
        for k, latch in enumerate(self.circuit.latches):
            if latch.init is None:
                if free is not None:
                    state[:, k] = free[:, k]
            else:
                state[:, k] = bool(latch.init)
        return state

    def _packed(self, latches: np.ndarray, inputs: np.ndarray) -> tuple[np.ndarray, int]:
        """Every variable's value, 8 rows of the batch to a byte: ``(M + 1, ceil(batch / 8))``."""
        latches = np.asarray(latches, dtype=bool)
        inputs = np.asarray(inputs, dtype=bool)
        batch = latches.shape[0]
        if (
            latches.ndim != 2
            or inputs.shape != (batch, len(self.circuit.inputs))
            or latches.shape[1] != len(self.circuit.latches)
        ):
            raise ValueError(
                f"expected latches (batch, {len(self.circuit.latches)}) and inputs "
                f"(batch, {len(self.circuit.inputs)}), got {latches.shape} and {inputs.shape}"
            )
        values = np.zeros((self.circuit.max_var + 1, (batch + 7) // 8), dtype=np.uint8)
        if len(self._in_vars):
            values[self._in_vars] = np.packbits(inputs.T, axis=1)
        if len(self._latch_vars):
            values[self._latch_vars] = np.packbits(latches.T, axis=1)
        for lhs, r0, r1 in self._ands:
            a = values[r0 >> 1] ^ np.uint8(255 * (r0 & 1))
            b = values[r1 >> 1] ^ np.uint8(255 * (r1 & 1))
            np.bitwise_and(a, b, out=values[lhs >> 1])
        return values, batch

    def _literals(self, packed: np.ndarray, batch: int, lits: np.ndarray) -> np.ndarray:
        """The values of ``lits``, shape ``(batch, len(lits))``."""
        if lits.size == 0:
            return np.zeros((batch, 0), dtype=bool)
        words = packed[lits >> 1] ^ (255 * (lits & 1)).astype(np.uint8)[:, None]
        return np.unpackbits(words, axis=1, count=batch).astype(bool).T

    def evaluate(self, latches: np.ndarray, inputs: np.ndarray) -> np.ndarray:
        """Every variable's value: an array of shape ``(M + 1, batch)``."""
        packed, batch = self._packed(latches, inputs)
        return np.unpackbits(packed, axis=1, count=batch).astype(bool)

    def step(self, latches: np.ndarray, inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One step: ``(outputs, next_latches)``, shapes ``(batch, O)`` and ``(batch, L)``."""
        packed, batch = self._packed(latches, inputs)
        return self._literals(packed, batch, self._outs), self._literals(packed, batch, self._latch_next)

    def bad(self, latches: np.ndarray, inputs: np.ndarray) -> np.ndarray:
        """SYNTCOMP's bad signal for each pair: shape ``(batch,)``."""
        packed, batch = self._packed(latches, inputs)
        return self._literals(packed, batch, np.array([self.circuit.bad]))[:, 0]
