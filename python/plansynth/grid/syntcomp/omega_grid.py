"""Grid problems of the safety and recurrence objectives posed to ``omega`` as GR(1)
games, the way TuLiP poses its grid worlds (``tulip/gridworld.py`` with moving
obstacles, through ``tulip.interfaces.omega``): the peer of the native engine on the
robot_grid family (:mod:`plansynth.grid.syntcomp.robot_grid`). The moving-obstacle
family keeps its own encoding, written as Ehlers wrote it for SLUGS
(:mod:`plansynth.grid.syntcomp.omega_game`); the settings are the same.

The game of :mod:`plansynth.grid.semantics`, written in omega's TLA+ fragment:

* ``env`` owns the robot's cell ``rx, ry`` (it must move it as the robot's move ``k``
  says: the move's offset when the end cell is on the grid, else no move), each
  obstacle's cell ``o<i>x, o<i>y`` (when its wait counter ``o<i>p`` is 0, one of its
  listed moves, and no others: a move off the grid or whose start or end cell is a wall
  or kept out leaves it where it is, as a move sweeping one does; while it waits, it
  stays where one of its moves would leave it there, a ``stay`` or a void move), the
  wait counters (by the obstacle's schedule) and, under ``fair``, a flag
  ``o<i>moved`` per obstacle (it changed cell in the last step);
* ``sys`` owns ``k``, the robot's next move;
* ``SysNext``: the robot is on no wall and collides with no obstacle (``position``:
  not on its cell; ``sweep``: not on its cell, and not moving into the cell it leaves
  nor it into the robot's: the swept cells of one-cell agents with moves of one step);
* the objective: safety only (``[]<> TRUE``), or ``[]<> goal_i`` for every goal (each
  goal infinitely often is each goal in turn infinitely often); under ``fair`` the
  assumptions ``[]<> o<i>moved`` (omega's ``<>[] ~o<i>moved`` persistence sets, as
  TuLiP translates environment liveness).

Supported: one-cell obstacles without glitches, and robot and obstacle moves that are
built-in names (one step, no ``via``). :func:`supports` says why a problem is not.
The moving-obstacle games go through :mod:`.omega_game`; everything here is checked
against the brute-force oracle of :mod:`plansynth.grid.oracle` on random small problems
(``tests/grid/syntcomp/test_omega_grid.py``).
"""

from __future__ import annotations

import time
from typing import Any

from plansynth.budget import Budget
from plansynth.grid.objective import CollisionRule, ObjectiveKind, Schedule
from plansynth.grid.problem import BUILTIN_MOVES, GridProblem
from plansynth.grid.result import GridStatus
from plansynth.grid.syntcomp.omega_game import OmegaAnswer, _all, _omega, _quiet, isolated

__all__ = ["supports", "automaton", "solve"]


def supports(problem: GridProblem) -> str | None:
    """None when :func:`automaton` encodes ``problem``, else why not."""
    if problem.objective not in (ObjectiveKind.SAFETY, ObjectiveKind.RECURRENCE):
        return f"the omega peer poses safety and recurrence objectives, not {problem.objective.value}"
    for who, moves in [("the robot", problem.robot.moves)] + [
        (f"obstacle {i}", o.moves) for i, o in enumerate(problem.obstacles)
    ]:
        if any(BUILTIN_MOVES.get(m.name) != m for m in moves):
            return f"{who} has a move that is not a built-in one"
    if any(o.size != (1, 1) or o.glitches for o in problem.obstacles):
        return "the omega peer poses one-cell obstacles without glitches"
    return None


def _cells(x: str, y: str, cells) -> str:
    """``(x, y)`` is one of ``cells``: a disjunction nested as a balanced tree (omega's
    parser recurses once per level, and a flat one of hundreds of cells is too deep)."""
    parts = [f"({x} = {c[0]} /\\ {y} = {c[1]})" for c in sorted(cells)]
    if not parts:
        return "FALSE"
    while len(parts) > 1:
        parts = [
            f"({parts[i]} \\/ {parts[i + 1]})" if i + 1 < len(parts) else parts[i] for i in range(0, len(parts), 2)
        ]
    return parts[0]


def _void_cells(w: int, h: int, d: tuple[int, int], blocked: set) -> set[tuple[int, int]]:
    """The cells from which a one-cell obstacle's move by offset ``d`` is void (it stays):
    its end is off the grid, or its start or end cell (the cells it sweeps) is
    ``blocked`` (:func:`plansynth.grid.semantics.obstacle_move`)."""
    out = set()
    for cx in range(w):
        for cy in range(h):
            ex, ey = cx + d[0], cy + d[1]
            if not (0 <= ex < w and 0 <= ey < h) or (cx, cy) in blocked or (ex, ey) in blocked:
                out.add((cx, cy))
    return out


def _offset(v: str, d: int) -> str:
    return v if d == 0 else f"{v} + {d}" if d > 0 else f"{v} - {-d}"


def automaton(problem: GridProblem) -> Any:
    """The game as an ``omega.symbolic.temporal.Automaton`` (module docstring)."""
    why = supports(problem)
    if why is not None:
        raise ValueError(why)
    _, trl = _omega()
    w, h = problem.width, problem.height
    n_moves = len(problem.robot.moves)
    aut = trl.Automaton()
    decl: dict[str, Any] = {"rx": (0, w - 1), "ry": (0, h - 1), "k": (0, max(n_moves - 1, 1))}
    env = ["rx", "ry"]
    init = [f"rx = {problem.robot.start[0]}", f"ry = {problem.robot.start[1]}"]
    types = [f"rx \\in 0..{w - 1}", f"ry \\in 0..{h - 1}"]
    act: list[str] = []
    for j, m in enumerate(problem.robot.moves):
        dx, dy = m.to
        inside = _all(
            f"{_offset('rx', dx)} >= 0",
            f"{_offset('rx', dx)} <= {w - 1}",
            f"{_offset('ry', dy)} >= 0",
            f"{_offset('ry', dy)} <= {h - 1}",
        )
        act.append(f"(k = {j} /\\ {inside}) => (rx' = {_offset('rx', dx)} /\\ ry' = {_offset('ry', dy)})")
        act.append(f"(k = {j} /\\ ~ ({inside})) => (rx' = rx /\\ ry' = ry)")
    guarantees = [f"~ ({_cells('rx', 'ry', problem.walls)})"] if problem.walls else []
    persist: list[str] = []
    for i, o in enumerate(problem.obstacles):
        x, y, p = f"o{i}x", f"o{i}y", f"o{i}p"
        decl[x], decl[y] = (0, w - 1), (0, h - 1)
        env += [x, y]
        init += [f"{x} = {o.start[0]}", f"{y} = {o.start[1]}"]
        types += [f"{x} \\in 0..{w - 1}", f"{y} \\in 0..{h - 1}"]
        stay = f"({x}' = {x} /\\ {y}' = {y})"
        blocked = set(problem.walls) | set(o.keep_out)
        options: list[str] = []  # one per listed move: its offset, or no move where it is void
        in_place: list[str] = []  # where each move leaves the obstacle on its cell
        for m in o.moves:
            dx, dy = m.to
            if (dx, dy) == (0, 0):
                options.append(stay)
                in_place.append("TRUE")
                continue
            void = _void_cells(w, h, (dx, dy), blocked)
            moved = f"({x}' = {_offset(x, dx)} /\\ {y}' = {_offset(y, dy)})"
            if void:
                options.append(f"((~ ({_cells(x, y, void)}) /\\ {moved}) \\/ (({_cells(x, y, void)}) /\\ {stay}))")
                in_place.append(_cells(x, y, void))
            else:
                options.append(moved)
        may = "TRUE"
        if o.period > 1:
            decl[p] = (0, o.period - 1)
            env.append(p)
            init.append(f"{p} = {o.initial_phase}")
            types.append(f"{p} \\in 0..{o.period - 1}")
            may = f"{p} = 0"
            changed = f"({x}' # {x} \\/ {y}' # {y})"
            top = o.period - 1
            if o.schedule is Schedule.FIXED:
                act.append(f"({p} = 0) => ({p}' = {top})")
                act.append(f"({p} > 0) => ({p}' = {p} - 1)")
            else:
                act.append(f"{changed} => ({p}' = {top})")
                act.append(f"(~ {changed} /\\ {p} > 0) => ({p}' = {p} - 1)")
                act.append(f"(~ {changed} /\\ {p} = 0) => ({p}' = 0)")
        # the listed moves when the obstacle may change its cell; else only those that
        # leave it where it is (semantics.legal_moves)
        any_move = " \\/ ".join(options)
        any_in_place = " \\/ ".join(in_place) or "FALSE"
        act.append(f"(({may}) /\\ ({any_move})) \\/ (~ ({may}) /\\ {stay} /\\ ({any_in_place}))")
        if problem.fair:
            mv = f"o{i}moved"
            decl[mv] = "bool"
            env.append(mv)
            init.append(f"~ {mv}")
            act.append(f"{mv}' <=> ({x}' # {x} \\/ {y}' # {y})")
            persist.append(f"~ {mv}")
        guarantees.append(f"~ (rx = {x} /\\ ry = {y})")
        if problem.collision is CollisionRule.SWEEP:
            guarantees.append(f"~ (rx' = {x} /\\ ry' = {y})")
            guarantees.append(f"~ ({x}' = rx /\\ {y}' = ry)")
    aut.declare_variables(**decl)
    aut.varlist.update(env=env, sys=["k"])
    primed_types = [t.replace(" \\in", "' \\in") for t in types]
    aut.init["env"] = _all(*init)
    aut.init["sys"] = f"k \\in 0..{n_moves - 1}"
    aut.action["env"] = _all(*types, *primed_types, *act)
    aut.action["sys"] = _all(f"k' \\in 0..{n_moves - 1}", *(guarantees or ["TRUE"]))
    if problem.objective is ObjectiveKind.RECURRENCE:
        goals = [f"rx = {g[0]} /\\ ry = {g[1]}" for g in problem.robot.goals]
    else:
        goals = ["TRUE"]
    aut.win["[]<>"] = aut.bdds_from(*goals)
    aut.win["<>[]"] = aut.bdds_from(*(persist or ["FALSE"]))
    aut.qinit = r"\A \E"
    aut.moore = False
    aut.plus_one = False
    return aut


def synthesize(problem: GridProblem, *, strategy: bool = True) -> tuple[GridStatus, dict[str, float], dict[str, int]]:
    """omega's answer in this process: (status, phase seconds, BDD sizes)."""
    gr1, _ = _omega()
    t0 = time.perf_counter()
    aut = automaton(problem)
    aut.build()
    t1 = time.perf_counter()
    z, yij, xijk = gr1.solve_streett_game(aut)
    t2 = time.perf_counter()
    realizable = _quiet(gr1.is_realizable, z, aut)
    t3 = time.perf_counter()
    counters = {"winning_set_nodes": len(z), "bdd_nodes": len(aut.bdd)}
    if realizable and strategy:
        gr1.make_streett_transducer(z, yij, xijk, aut)
        counters["strategy_nodes"] = len(aut.action["impl"])
    t4 = time.perf_counter()
    status = GridStatus.REALIZABLE if realizable else GridStatus.UNREALIZABLE
    return (
        status,
        {"build": t1 - t0, "winning_set": t2 - t1, "realizability": t3 - t2, "strategy": t4 - t3, "total": t4 - t0},
        counters,
    )


def _solve_here(problem: GridProblem, strategy: bool) -> OmegaAnswer:
    status, phases, counters = synthesize(problem, strategy=strategy)
    return OmegaAnswer(status, phases["total"], phases, counters)


def solve(problem: GridProblem, budget: Budget | None = None, *, strategy: bool = True) -> OmegaAnswer:
    """omega's answer in a child process within ``budget``; ``unknown`` past it."""
    return isolated(_solve_here, (problem, strategy), budget or Budget())
