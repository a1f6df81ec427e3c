"""The inductive-invariant check of :mod:`.invariant` with its per-state loop in the
compiled core (``crates/plansynth-core/src/inductive.rs``, exposed as
``plansynth._core.check_invariant``); the numpy check of :mod:`.invariant` is its
reference, and a property test checks that the two give the same verdicts.

It stays independent of the native engine. Everything the rule depends on is built
here, in Python, from the rules themselves: the obstacles' replies from
:class:`~.replies.ObstacleReplies` (:mod:`plansynth.grid.semantics`), the robot's end
and swept cells from :func:`~plansynth.grid.semantics.robot_move`, the inputs from
:func:`~plansynth.grid.semantics.controller_inputs`, the program's flat nodes from the
program term (:func:`program_nodes`). The core only walks these tables state by state
(Manna and Pnueli, 1995, rule INV) and evaluates the program; it solves no game and
reads nothing the engine computed.
"""

from __future__ import annotations

import time

from plansynth.budget import Budget, BudgetExhausted
from plansynth.grid.objective import CollisionRule
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Const, Term, Var
from plansynth.grid.semantics import controller_inputs
from plansynth.grid.verify.invariant_tables import key_of, robot_tables, unknown, xy
from plansynth.grid.verify.meter import Meter
from plansynth.grid.verify.replies import ObstacleReplies
from plansynth.grid.verify.verdict import Verdict, VerifyStatus

__all__ = ["available", "check_invariant_compiled", "program_nodes"]

_OPS = {"+": 2, "-": 3, "<=": 4, "=": 5, "not": 6, "and": 7, "or": 8, "ite": 9}


def available() -> bool:
    """Whether the compiled core with the invariant check is built."""
    try:
        from plansynth import _core
    except ImportError:
        return False
    return hasattr(_core, "check_invariant")


def program_nodes(program: Term, variables: tuple[str, ...]) -> list[tuple[int, int, int, int]]:
    """``program`` as flat nodes ``(op, a, b, c)``, children first, root last: op 0 a
    constant a, 1 variable a (its index in ``variables``), 2 ``+``, 3 ``-``, 4 ``<=``,
    5 ``=``, 6 ``not``, 7 ``and``, 8 ``or``, 9 ``ite`` over node indices.

    >>> from plansynth.grid.programs import parse_program
    >>> program_nodes(parse_program("(ite (<= rx 1) 0 1)"), ("rx", "ry"))
    [(1, 0, 0, 0), (0, 1, 0, 0), (4, 0, 1, 0), (0, 0, 0, 0), (0, 1, 0, 0), (9, 2, 3, 4)]
    """
    index = {v: i for i, v in enumerate(variables)}
    out: list[tuple[int, int, int, int]] = []
    memo: dict[int, int] = {}

    def go(t: Term) -> int:
        got = memo.get(id(t))
        if got is not None:
            return got
        if isinstance(t, Const):
            row = (0, int(t.value), 0, 0)
        elif isinstance(t, Var):
            row = (1, index[t.name], 0, 0)
        else:
            kids = [go(a) for a in t.args] + [0, 0]
            row = (_OPS[t.op], kids[0], kids[1], kids[2])
        out.append(row)
        memo[id(t)] = len(out) - 1
        return len(out) - 1

    go(program)
    return out


def check_invariant_compiled(
    problem: GridProblem, program: Term, invariant, keys: list, probes: list, budget: Budget | None
) -> Verdict:
    """The check of :func:`.invariant.check_invariant` (whose caller has checked the
    objective and the initial state, and passes the set's ``keys`` and a state of each
    key, ``probes``) in the core."""
    import numpy as np

    from plansynth import _core

    t0 = time.perf_counter()
    meter = Meter(budget)
    meter.phase = "the obstacles' replies on the invariant"
    w, n = problem.width, problem.width * problem.height
    nw = max(1, (n + 63) // 64)
    n_moves = len(problem.robot.moves)
    key_id = {k: i for i, k in enumerate(keys)}
    try:
        by = ObstacleReplies(problem)
        key = key_of(problem)
        index: dict[tuple, list[int]] = {}  # cells as indices, per tuple of cells
        reply_off, reply_next, danger_off, danger = [0], [], [0], []
        for i, s in enumerate(probes):
            if i % 1024 == 0:
                meter.check()
            for nxt, cells in by.of(s):
                reply_next.append(key_id.get(key(nxt), -1))
                got = index.get(cells)
                if got is None:
                    got = index[cells] = [c[1] * w + c[0] for c in cells]
                danger += got
                danger_off.append(len(danger))
            reply_off.append(len(reply_next))
        fixed = np.array([controller_inputs(problem, s)[2:] for s in probes], np.int64).reshape(len(keys), -1)
        ends, swept, wall_hit = robot_tables(problem)
        table = b"".join(invariant[k].to_bytes(nw * 8, "little") for k in keys)
        meter.phase = "checking the inductive invariant"
        meter.check()
        remaining = None if meter.clock is None else meter.clock.remaining()
        left = None if remaining is None or remaining == float("inf") else max(0.0, remaining)
        checked, failure = _core.check_invariant(
            w,
            n,
            table,
            fixed.shape[1],
            fixed.astype("<i8").tobytes(),
            n_moves,
            ends.astype("<u4").tobytes(),
            wall_hit.astype(np.uint8).tobytes(),
            swept.shape[2],
            swept.astype("<u4").tobytes(),
            np.asarray(reply_off, "<u4").tobytes(),
            np.asarray(reply_next, "<i8").tobytes(),
            np.asarray(danger_off, "<u4").tobytes(),
            np.asarray(danger, "<u4").tobytes(),
            problem.collision is CollisionRule.POSITION,
            program_nodes(program, problem.variables),
            left,
        )
    except (BudgetExhausted, MemoryError) as out:
        return meter.ran_out(out, None, 0, t0)
    if failure is not None:
        kind, key, cell, move, end = failure
        if kind == 0:
            where = probes[key]._replace(robot=xy(cell, w))
            return unknown(t0, 0, f"the program returns no move in state {where}")
        if kind == 1:
            return unknown(t0, 0, f"not inductive: the program's move {move} from {xy(cell, w)} may collide")
        return unknown(
            t0,
            0,
            f"not inductive: state {xy(end, w)} after move {move} from {xy(cell, w)} is outside the invariant",
        )
    return Verdict(
        VerifyStatus.WINS,
        None,
        None,
        checked,
        time.perf_counter() - t0,
        message=f"an inductive invariant of {checked} states",
    )
