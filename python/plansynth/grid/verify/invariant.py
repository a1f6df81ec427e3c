"""Safety by an inductive invariant: where the closed loop has too many states to search
one by one, a set of states the program keeps is checked instead.

An *invariant* is a set of states given as, per obstacle configuration (a key: per
obstacle ((x, y), wait counter, glitches left), then the mode and the fairness
counter), a bit set of robot cells (bit ``y * width + x``). The program wins the safety
objective if the set holds the initial state and, from each of its states, the
program's move collides with no legal obstacle reply and every reply leads back into
the set (the inductive-invariant rule for safety properties: Manna and Pnueli,
*Temporal Verification of Reactive Systems: Safety*, 1995, rule INV). The check is
local, state by state, so it needs no search and no record of visited states; it is
vectorized over the robot cells of each configuration (numpy).

It is independent of whoever proposes the set (the native engine passes the states its
own check of the program reached): the obstacles' replies come from
:func:`~plansynth.grid.semantics.step` and the legal moves of
:mod:`plansynth.grid.semantics`, the robot's moves from
:func:`~plansynth.grid.semantics.robot_move`, the program's choice from its own
vectorized evaluation. A set that is not inductive proves nothing either way: the
verdict is then ``unknown`` (the solve loop falls back to the closed-loop search).

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [3, 1], "objective": "safety",
...     "robot": {"start": [0, 0], "moves": ["stay", "right"]}, "obstacles": []})
>>> check_invariant(p, parse_program("0"), {(): 0b001}).status.value
'wins'
>>> check_invariant(p, parse_program("1"), {(): 0b001}).message
'not inductive: state (1, 0) after move 1 from (0, 0) is outside the invariant'
"""

from __future__ import annotations

import time
from collections.abc import Mapping

from plansynth.budget import Budget, BudgetExhausted
from plansynth.grid.objective import CollisionRule, ObjectiveKind
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import App, Const, Term, Var
from plansynth.grid.semantics import (
    State,
    controller_inputs,
    initial_state,
)
from plansynth.grid.verify.invariant_tables import key_of, state_key
from plansynth.grid.verify.invariant_tables import robot_tables as _robot_tables
from plansynth.grid.verify.invariant_tables import unknown as _unknown
from plansynth.grid.verify.invariant_tables import xy as _xy
from plansynth.grid.verify.meter import Meter
from plansynth.grid.verify.replies import ObstacleReplies
from plansynth.grid.verify.verdict import Verdict, VerifyStatus

__all__ = ["check_invariant", "Invariant", "state_key", "key_of", "CHUNK_STATES"]

Invariant = Mapping[tuple, int]

#: The states checked at once (per chunk of configurations): the check's arrays take
#: about 200 bytes a state, so a chunk stays under a gigabyte whatever the set's size
#: (a 48 x 48 moving-obstacle program keeps some 70 million states).
CHUNK_STATES = 4_000_000


def _state_of(problem: GridProblem, key: tuple, cell: tuple[int, int]) -> State:
    n = len(problem.obstacles)
    obs, rest = key[:n], key[n:]
    mode = rest[0] if problem.mode_count > 1 else 0
    fair = rest[-1] if problem.fair_count > 1 else 0
    cells = tuple(o[0] for o in obs)
    if problem.stateful:
        return State(cell, cells, tuple(o[1] for o in obs), tuple(o[2] for o in obs), mode, fair)
    return State(cell, cells, (), (), mode, fair)


def check_invariant(
    problem: GridProblem,
    program: Term,
    invariant: Invariant,
    *,
    budget: Budget | None = None,
    compiled: bool | None = None,
) -> Verdict:
    """``wins`` if ``invariant`` is an inductive invariant of ``program`` for the safety
    objective holding the initial state; ``unknown`` (with the first failure) if not.

    ``compiled``: walk the states in the compiled core
    (:mod:`.invariant_compiled`; by default when it is built) or with numpy (False, the
    reference). Both build the same tables from the rules and give the same verdicts;
    the failure named when the set is not inductive may differ (the core reports the
    first failing state in order, numpy the first of a chunk's first failing reply).

    The numpy check is vectorized over the states of the set, a chunk of
    configurations at a time (:data:`CHUNK_STATES`): the program is evaluated once per
    state (each state routed down its ``ite`` tree), then for each obstacle reply of
    each configuration the robot's end cell is looked up in the set."""
    import numpy as np

    if problem.objective is not ObjectiveKind.SAFETY:
        raise ValueError("an inductive invariant proves the safety objective only")
    if compiled is not False:
        from plansynth.grid.verify import invariant_compiled

        if compiled and not invariant_compiled.available():
            raise ValueError("the compiled invariant check is not built")
        if invariant_compiled.available():
            start = initial_state(problem)
            t0 = time.perf_counter()
            if not invariant.get(state_key(problem, start), 0) >> (start.robot[1] * problem.width + start.robot[0]) & 1:
                return _unknown(t0, 0, "not inductive: the initial state is outside the invariant")
            keys = list(invariant)
            probes = [_state_of(problem, k, (0, 0)) for k in keys]
            return invariant_compiled.check_invariant_compiled(problem, program, invariant, keys, probes, budget)
    t0 = time.perf_counter()
    meter = Meter(budget)
    meter.phase = "checking the inductive invariant"
    w, n = problem.width, problem.width * problem.height
    n_moves = len(problem.robot.moves)
    start = initial_state(problem)
    keys = list(invariant)
    key_id = {k: i for i, k in enumerate(keys)}
    checked = 0
    try:
        if not invariant.get(state_key(problem, start), 0) >> (start.robot[1] * w + start.robot[0]) & 1:
            return _unknown(t0, 0, "not inductive: the initial state is outside the invariant")
        table = _bit_table(invariant, keys, n)  # (keys, n) bool
        ends, swept, wall_hit = _robot_tables(problem)  # (moves, n), (moves, n, s), (moves, n)
        probes = [_state_of(problem, k, (0, 0)) for k in keys]
        fixed = np.array([controller_inputs(problem, s)[2:] for s in probes], np.int64).reshape(len(keys), -1)
        meter.phase = "the obstacles' replies on the invariant"
        by = ObstacleReplies(problem)
        replies = [_replies(problem, s, key_id, by) for s in probes]
        width = max(len(r) for r in replies)
        depth = max(1, max(len(d) for r in replies for _, d in r))
        # per configuration and reply: the next configuration (-1: none) and the cells
        # that collide with the robot (-1: padding)
        r_next = np.full((len(keys), width), -1, np.int64)
        r_has = np.zeros((len(keys), width), bool)
        r_danger = np.full((len(keys), width, depth), -1, np.int64)
        for i, r in enumerate(replies):
            for j, (nxt, d) in enumerate(r):
                r_next[i, j], r_has[i, j] = nxt, True
                r_danger[i, j, : len(d)] = d
        del replies
        position = problem.collision is CollisionRule.POSITION
        counts = table.sum(axis=1)
        first = 0
        while first < len(keys):
            # a chunk of configurations holding at most CHUNK_STATES states (or one)
            last = first + max(1, int(np.searchsorted(np.cumsum(counts[first:]), CHUNK_STATES, side="right")))
            kid, cells = np.nonzero(table[first:last])
            kid += first
            first = last
            checked += int(kid.size)
            values = {v: fixed[kid, j] for j, v in enumerate(problem.variables[2:])}
            values["rx"], values["ry"] = cells % w, cells // w
            meter.phase = "evaluating the program on the invariant"
            moves = _choose(program, values, kid.size)
            del values
            bad = (moves < 0) | (moves >= n_moves)
            if bad.any():
                i = int(np.argmax(bad))
                return _unknown(
                    t0,
                    checked,
                    f"the program returns no move in state {probes[kid[i]]._replace(robot=_xy(cells[i], w))}",
                )
            end = ends[moves, cells]
            hit = wall_hit[moves, cells]
            meter.phase = "the obstacles' replies on the invariant"
            robot_swept = None if position else swept[moves, cells]  # (states, s)
            for j in range(width):
                meter.check()
                has = r_has[kid, j]
                nxt = r_next[kid, j]
                inside = np.zeros(kid.size, bool)
                known = has & (nxt >= 0)
                inside[known] = table[nxt[known], end[known]]
                mine = r_danger[kid, j]  # (states, depth)
                if position:
                    collide = (mine == end[:, None]).any(axis=1)
                else:
                    collide = (mine[:, :, None] == robot_swept[:, None, :]).any(axis=(1, 2))
                hit |= has & collide
                out = has & ~collide & ~inside
                if out.any():
                    i = int(np.argmax(out))
                    return _unknown(
                        t0,
                        checked,
                        f"not inductive: state {_xy(end[i], w)} after move {int(moves[i])} "
                        f"from {_xy(cells[i], w)} is outside the invariant",
                    )
            if hit.any():
                i = int(np.argmax(hit))
                return _unknown(
                    t0,
                    checked,
                    f"not inductive: the program's move {int(moves[i])} from {_xy(cells[i], w)} may collide",
                )
    except (BudgetExhausted, MemoryError) as out:
        return meter.ran_out(out, None, checked, t0)
    return Verdict(
        VerifyStatus.WINS,
        None,
        None,
        checked,
        time.perf_counter() - t0,
        message=f"an inductive invariant of {checked} states",
    )


def _bit_table(invariant: Invariant, keys: list, n: int):
    import numpy as np

    nbytes = (n + 7) // 8
    raw = np.frombuffer(b"".join(invariant[k].to_bytes(nbytes, "little") for k in keys), np.uint8)
    return np.unpackbits(raw.reshape(len(keys), nbytes), axis=1, bitorder="little")[:, :n].astype(bool)


def _replies(
    problem: GridProblem, probe: State, key_id: dict, by: ObstacleReplies
) -> list[tuple[int, tuple[int, ...]]]:
    """Every legal joint reply from ``probe``'s configuration (:mod:`.replies`): (the
    next configuration's index in the invariant, -1 if absent; the cells that collide
    with the robot: swept cells, or under the position rule the blocks after the step)."""
    w = problem.width
    out = []
    for nxt, cells in by.of(probe):
        out.append((key_id.get(state_key(problem, nxt), -1), tuple(c[1] * w + c[0] for c in cells)))
    return out


def _choose(t: Term, values: dict, n: int):
    """The program's move in each of ``n`` states, each state routed down the ``ite``
    tree (conditions evaluated on the states that reach them only)."""
    import numpy as np

    out = np.full(n, -1, np.int64)
    todo = [(t, np.arange(n))]
    while todo:
        node, idx = todo.pop()
        if idx.size == 0:
            continue
        sub = _Restricted(values, idx)
        if isinstance(node, App) and node.op == "ite":
            c = np.broadcast_to(np.asarray(_evaluate(node.args[0], sub), bool), idx.shape)
            todo.append((node.args[1], idx[c]))
            todo.append((node.args[2], idx[~c]))
        else:
            out[idx] = _evaluate(node, sub)
    return out


class _Restricted:
    """The inputs of the states ``idx`` only, each variable restricted when a condition
    first reads it (a node's condition reads one or two of them)."""

    def __init__(self, values: dict, idx) -> None:
        self.values, self.idx, self.got = values, idx, {}

    def __getitem__(self, name: str):
        v = self.got.get(name)
        if v is None:
            v = self.values[name]
            v = self.got[name] = v[self.idx] if hasattr(v, "shape") else v
        return v


def _evaluate(t: Term, values: dict):
    """The program on arrays of inputs (numpy): integers and Booleans elementwise."""
    import numpy as np

    if isinstance(t, Const):
        return t.value
    if isinstance(t, Var):
        return values[t.name]
    a = [_evaluate(x, values) for x in t.args]
    op = t.op
    if op == "+":
        return a[0] + a[1]
    if op == "-":
        return a[0] - a[1]
    if op == "<=":
        return a[0] <= a[1]
    if op == "=":
        return a[0] == a[1]
    if op == "not":
        return np.logical_not(a[0])
    if op == "and":
        return np.logical_and(a[0], a[1])
    if op == "or":
        return np.logical_or(a[0], a[1])
    if op == "ite":
        return np.where(a[0], a[1], a[2])
    raise ValueError(f"unknown operator {op}")
