"""The inductive-invariant check's parts that do not depend on how the states are walked
(:mod:`.invariant`'s numpy walk and :mod:`.invariant_compiled`'s compiled one): the
set's keys, the robot's move tables from :func:`~plansynth.grid.semantics.robot_move`,
and the verdict of a set that is not inductive."""

from __future__ import annotations

import time

from plansynth.grid.problem import GridProblem
from plansynth.grid.semantics import State, robot_move
from plansynth.grid.verify.verdict import Verdict, VerifyStatus

__all__ = ["state_key", "key_of", "robot_tables", "xy", "unknown"]


def state_key(problem: GridProblem, s: State) -> tuple:
    """The invariant's key of ``s`` (everything but the robot's cell)."""
    return key_of(problem)(s)


def key_of(problem: GridProblem):
    """:func:`state_key` for ``problem`` as a function of the state (the problem's
    properties read once, for the check's loops over every configuration)."""
    mode, fair = problem.mode_count > 1, problem.fair_count > 1

    def key(s: State) -> tuple:
        if s.phases:
            out: tuple = tuple(zip(s.obstacles, s.phases, s.glitches, strict=True))
        else:
            out = tuple((c, 0, 0) for c in s.obstacles)
        if mode:
            out += (s.mode,)
        if fair:
            out += (s.fair,)
        return out

    return key


def robot_tables(problem: GridProblem):
    """Per robot move and cell: the end cell, the swept cells (padded with the first)
    and whether a wall is swept, from :func:`~plansynth.grid.semantics.robot_move`."""
    import numpy as np

    w, n = problem.width, problem.width * problem.height
    k_n = len(problem.robot.moves)
    rows = [[robot_move(problem, (c % w, c // w), k) for c in range(n)] for k in range(k_n)]
    width = max(len(sw) for row in rows for _, sw in row)
    ends = np.zeros((k_n, n), np.int64)
    swept = np.zeros((k_n, n, width), np.int64)
    walls = np.zeros(n, bool)
    for c in problem.walls:
        walls[c[1] * w + c[0]] = True
    for k, row in enumerate(rows):
        for c, (e, sw) in enumerate(row):
            ends[k, c] = e[1] * w + e[0]
            idx = [x[1] * w + x[0] for x in sw]
            swept[k, c] = idx + [idx[0]] * (width - len(idx))
    return ends, swept, walls[swept].any(axis=2)


def xy(c: int, w: int) -> tuple[int, int]:
    return (int(c) % w, int(c) // w)


def unknown(t0: float, checked: int, why: str) -> Verdict:
    return Verdict(VerifyStatus.UNKNOWN, None, None, checked, time.perf_counter() - t0, "the inductive invariant", why)
