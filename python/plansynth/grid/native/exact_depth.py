"""The exact depth search: the smallest program depth over every stationary winning
strategy of the game, by tree SAT over the stationary encoding (Chasins & Newcomb,
SYNT 2016, Section 3.1: a program's depth as the paper counts it; depths 2 and 3 add
nothing over 1). Exact when the conditions are enumerated completely to the depths
that matter."""

from __future__ import annotations

import time

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.bitgrid import bits
from plansynth.grid.native.conditions import Enumeration
from plansynth.grid.native.run import RunState
from plansynth.grid.native.sat import ConflictLimit, solve_clauses
from plansynth.grid.native.stationary import encode_stationary, winning_forward
from plansynth.grid.native.synth import TreeEncoding, conditions_by_level, program_depths, tree_levels
from plansynth.grid.problem import GridProblem

__all__ = ["minimal_program"]


def minimal_program(
    arena: Arena,
    clock: Clock,
    depth_bound: int | None,
    run: RunState,
    problem: GridProblem,
    cond_depth: int | None = None,
    max_clauses: int | None = None,
    max_conflicts: int | None = None,
    max_seconds: float | None = None,
    total_seconds: float | None = None,
    skip_hard: bool = False,
):
    """Search program depths 1, 4, 5, ... for a winning program over the whole game.

    Returns ``(program or None, proved, last depth tried)``; ``proved`` is True when
    every smaller depth was refuted with a complete condition enumeration.
    """
    fwd = winning_forward(arena)
    states = sorted({(r, oc) for layer in fwd[:-1] for oc, m in layer.items() for r in bits(m)})
    top_ = depth_bound if depth_bound is not None else run.o.max_tree_depth
    if max_clauses is not None and (
        len(states) > run.o.improve_states or len(states) * 2 ** tree_levels(min(top_, 5)) > max_clauses // 50
    ):
        raise BudgetExhausted(
            "the exact depth search", "states", f"{len(states)} states are too many for the exact depth search"
        )
    clauses, ids, fwd = encode_stationary(arena, clock, fwd=fwd)
    inputs = [arena.inputs(r, oc) for r, oc in states]
    run.counters["universe_states"] = len(states)
    top = depth_bound if depth_bound is not None else run.o.max_tree_depth
    cap = min(5, run.o.condition_depth + 1) if cond_depth is None else cond_depth
    if max_clauses is not None and len(states) * 2 ** tree_levels(min(top, 5)) > max_clauses // 50:
        raise BudgetExhausted(
            "the exact depth search", "states", f"{len(states)} states are too many for the exact depth search"
        )
    n_moves = len(arena.robot.moves)
    proved = True
    last = 0
    enums: dict[int, Enumeration] = {}
    started = time.perf_counter()
    for d in program_depths(top):
        if total_seconds is not None and time.perf_counter() - started > total_seconds:
            raise BudgetExhausted("the exact depth search", "time", f"exact depth search beyond {total_seconds} s")
        last = d
        need = max(2, min(d - 1, cap))  # the root's conditions have depth <= d - 1
        if need not in enums:
            enums[need] = run.conditions(inputs, arena.variables(), problem, need, clock)
        enum = enums[need]
        by_level = conditions_by_level(enum.conditions, d, len(states))
        est = len(clauses) + sum(len(by_level[(n + 1).bit_length() - 1]) for n in range(2 ** tree_levels(d) - 1)) * len(
            states
        )
        run.counters["exact_search_clauses"] = est
        if max_clauses is not None and est > max_clauses:
            raise BudgetExhausted("the exact depth search", "clauses", f"depth-{d} search of about {est} clauses")
        enc = TreeEncoding(tree_levels(d), by_level, len(states), n_moves, len(ids), list(clauses))

        def out_lit(s: int, k: int, states=states):
            r, oc = states[s]
            v = ids.get(("m", r, oc, 0, k))
            return False if v is None else v

        enc.build(out_lit, clock)
        try:
            model = solve_clauses(enc.clauses, clock, max_conflicts=max_conflicts, max_seconds=max_seconds)
        except ConflictLimit:
            if not skip_hard:
                raise
            proved = False  # this depth is left undecided; try the next one
            continue
        if model is not None:
            return enc.program(model), proved, d
        if d >= 4 and enum.complete_to < d - 1:
            proved = False
    return None, proved, last
