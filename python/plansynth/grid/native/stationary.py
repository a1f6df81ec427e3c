"""Does a *stationary* winning strategy exist? An exact SAT encoding.

The paper's controller (Chasins & Newcomb, SYNT 2016, Section 3.1) sees positions, not
the time: the same joint state met at two different times must get the same move. So a
win of the time-dependent game (:meth:`Arena.solve_game`) is necessary but not
sufficient. This module decides the stationary question exactly over the states the
game leaves winning, with CaDiCaL through PySAT:

* ``reach[t, s]``: state s is reached at time t under the strategy,
* ``move[s, k]``: the strategy may play move k in state s (several may hold; every
  move that holds must be winning, so any choice among them is a winning strategy),
* ``reach[0, s0]``; ``reach[t, s] -> OR_k move[s, k]`` over moves winning at (t, s);
  ``reach[t, s] -> not move[s, k]`` for moves not winning at (t, s);
  ``reach[t, s] & move[s, k] -> reach[t+1, s']`` for every obstacle reply s'.

The controller only has to be defined on states it reaches itself, which the reach
variables capture. A model gives reach sets R(t) closed under the allowed moves; the
*allowed* moves of a state are all moves that stay inside R and win at every time the
state is in R, which leaves the program synthesiser as much freedom as possible.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

from plansynth.budget import Clock
from plansynth.grid.native.arena import Arena, Config
from plansynth.grid.native.bitgrid import bits, cell_mask
from plansynth.grid.native.limits import check_clock
from plansynth.grid.native.sat import solve_clauses

State = tuple[int, Config]  # (robot cell index, read obstacle cells)


@dataclass(frozen=True)
class Strategy:
    """A stationary winning strategy: allowed moves per state, and where it goes.

    ``reach[t]`` maps configurations to robot-cell masks of the states it may visit at
    time t; ``allowed[s]`` is never empty and every choice among it wins.
    """

    allowed: dict[State, tuple[int, ...]]
    reach: tuple[dict[Config, int], ...]
    counters: dict[str, int]


def winning_forward(arena: Arena, clock: Clock | None = None) -> list[dict[Config, int]]:
    """States reachable from the start using only moves that win the game (in the
    compiled core when the arena was explored there; this loop is its reference)."""
    if arena._core is not None:
        if arena._fwd is None:
            core_forward(arena, clock)
            arena._fwd = [{tuple(oc): int.from_bytes(m, "little") for oc, m in layer} for layer in arena._fwd_rows]
            arena._fwd_rows = None
        return arena._fwd
    return winning_forward_reference(arena, clock)


def core_forward(arena: Arena, clock: Clock | None = None) -> None:
    """Have the compiled game compute its winning-forward layers (kept in the core, as
    its strategy read-off and program check need them) without reading them into
    Python dicts: on a 30x30 game with three cars that may stall (roads30-stall-3) the
    dicts alone took 2 s, and only the SAT encoding and the references read them."""
    if arena._fwd is not None or arena._fwd_rows is not None:
        return
    arena._fwd_rows = arena._core.winning_forward(arena.core_seconds(clock), arena.memory_bytes)


def winning_forward_reference(arena: Arena, clock: Clock | None = None) -> list[dict[Config, int]]:
    """:func:`winning_forward` in pure Python."""
    oc0 = next(iter(arena.layers[0]))
    start = cell_mask(arena.problem, arena.problem.robot.start)
    out: list[dict[Config, int]] = [{oc0: start}]
    for t in range(arena.steps):
        nxt: dict[Config, int] = {}
        for oc, r in out[t].items():
            img = 0
            for k, wm in enumerate(arena.winning_moves(t, oc)):
                img |= arena.robot.image(r & wm, k)
            if img:
                for oc2 in arena.successors(oc):
                    nxt[oc2] = nxt.get(oc2, 0) | img
        out.append(nxt)
        check_clock(clock, "following winning moves", f" at step {t}")
    return out


def encode_stationary(arena: Arena, clock: Clock | None = None, label: Callable[[int], int] | None = None, fwd=None):
    """The clauses of the stationary question and the variable map.

    Returns ``(clauses, ids, fwd)``: keys of ``ids`` are ``("r", t, r, oc)`` (reach)
    and ``("m", r, oc, label, k)`` (move); ``fwd`` are the winning-forward layers.
    """
    lab = label or (lambda t: 0)
    fwd = winning_forward(arena, clock) if fwd is None else fwd
    steps = arena.steps
    n_moves = len(arena.robot.moves)
    ids: dict[tuple, int] = {}

    def var(key: tuple) -> int:
        v = ids.get(key)
        if v is None:
            v = len(ids) + 1
            ids[key] = v
        return v

    clauses: list[list[int]] = []
    # Large games share each configuration's replies per end cell (fewer clauses); small
    # ones keep the direct clauses, which make the exact depth searches easier for SAT.
    size = sum(m.bit_count() * len(arena.successors(oc)) for layer in fwd[:-1] for oc, m in layer.items())
    share = size * n_moves > 300_000
    oc0 = next(iter(fwd[0]))
    r0 = arena.sem.index(arena.problem.robot.start)
    clauses.append([var(("r", 0, r0, oc0))])
    for t in range(steps):
        label_t = lab(t)
        for oc, rmask in fwd[t].items():
            wm = arena.winning_moves(t, oc)
            succ = arena.successors(oc)
            goes: dict[int, int] = {}  # end cell -> "every obstacle reply from oc is reached"
            for r in bits(rmask):
                rv = var(("r", t, r, oc))
                mv = [var(("m", r, oc, label_t, k)) for k in range(n_moves)]
                clauses.append([-rv] + [mv[k] for k in range(n_moves) if wm[k] >> r & 1])
                for k in range(n_moves):
                    if not wm[k] >> r & 1:
                        clauses.append([-rv, -mv[k]])
                    elif t + 1 < steps:
                        e = arena.robot_end(r, k)
                        if not share:
                            for oc2 in succ:
                                clauses.append([-rv, -mv[k], var(("r", t + 1, e, oc2))])
                            continue
                        g = goes.get(e)
                        if g is None:
                            # shared by every (r, k) of this configuration that ends in e
                            g = goes[e] = var(("g", t, e, oc))
                            for oc2 in succ:
                                clauses.append([-g, var(("r", t + 1, e, oc2))])
                        clauses.append([-rv, -mv[k], g])
            check_clock(clock, "encoding the stationary strategy", f" at step {t}")
    return clauses, ids, fwd


def stationary_strategy(
    arena: Arena, clock: Clock | None = None, label: Callable[[int], int] | None = None, quick: bool = True
) -> Strategy | None:
    """A stationary winning strategy, or None when none exists (exact).

    Requires :meth:`Arena.solve_game` to have returned True. ``label`` optionally adds
    a time label to the states the strategy must be stationary on (used to account for
    obstacles outside the cone of influence that work as a clock). With ``quick``, a
    strategy that can be read off the game (:func:`consistent_strategy`) is returned
    without SAT.
    Raises :class:`~plansynth.budget.BudgetExhausted` when the clock runs out.
    """
    if label is None and quick:
        if arena._core is not None:
            core_forward(arena, clock)  # what the compiled read-off needs
            found = consistent_strategy(arena, None, clock)
        else:
            found = consistent_strategy(arena, winning_forward(arena, clock), clock)
        if found is not None:
            return found
    clauses, ids, fwd = encode_stationary(arena, clock, label, fwd=winning_forward(arena, clock))
    steps = arena.steps
    counters = {"sat_vars": len(ids), "sat_clauses": len(clauses)}
    model = solve_clauses(clauses, clock, phases=_phases(arena, ids))
    if model is None:
        return None
    truth = set(v for v in model if v > 0)
    reach: list[dict[Config, int]] = [dict() for _ in range(steps + 1)]
    for key, v in ids.items():
        if key[0] == "r" and v in truth:
            _, t, r, oc = key
            reach[t][oc] = reach[t].get(oc, 0) | (1 << r)
    allowed = _allowed(arena, reach, clock)
    if label is None:
        # Keep only what the allowed moves actually reach (the solver may set reach
        # variables it did not need), which leaves more freedom per state.
        reach = _closure(arena, allowed, clock)
        allowed = _allowed(arena, reach, clock)
        assert all(allowed.values()), "a SAT model must leave every reached state a move"
    final = {s: tuple(sorted(a)) for s, a in allowed.items()}
    return Strategy(final, tuple(reach), counters)


def consistent_strategy(
    arena: Arena, fwd: list[dict[Config, int]] | None, clock: Clock | None = None
) -> Strategy | None:
    """A stationary strategy read off the game without SAT, when one is there to read.

    A move that wins at *every* time a state can be met on the winning-forward graph
    may be played in that state whatever the time. Following one such move per state
    (preferring moves towards the goal, then staying) from the start either reaches
    only states that have one -- a stationary winning strategy, found in linear time --
    or meets a state without one, and then the SAT encoding decides. In the compiled
    core when the arena is compiled (``arena/strategy.rs``, ``Arena::consistent``); the loops
    below are its reference. ``fwd`` (the winning-forward layers) is read by the
    reference only: the compiled core keeps its own (:func:`core_forward`).
    """
    if arena._core is not None:
        core_forward(arena, clock)
        got = arena._core.consistent(arena.problem.width, arena.core_seconds(clock))
        if got is None:
            return None
        reach_rows, rows = got
        reach = tuple(_layers_in(reach_rows))
        final = {(r, tuple(oc)): _moves_of(m) for r, oc, m in rows}
        assert all(final.values()), "a consistent choice must leave every reached state a move"
        return Strategy(final, reach, {"sat_vars": 0, "sat_clauses": 0, "consistent": 1})
    if fwd is None:
        fwd = winning_forward(arena, clock)
    steps = arena.steps
    n_moves = len(arena.robot.moves)
    bad: dict[Config, list[int]] = {}
    for t in range(steps):
        for oc, rmask in fwd[t].items():
            wm = arena.winning_moves(t, oc)
            b = bad.setdefault(oc, [0] * n_moves)
            for k in range(n_moves):
                b[k] |= rmask & ~wm[k]
        check_clock(clock, "reading a strategy off the game", f" at step {t}")
    gx, gy = arena.problem.robot.goal
    choice: dict[State, int] = {}

    def pick(r: int, oc: Config) -> int | None:
        key = (r, oc)
        if key in choice:
            return choice[key]
        b = bad[oc]
        x, y = arena.sem.cell(r)
        best = None
        for k in range(n_moves):
            if b[k] >> r & 1:
                continue
            ex, ey = arena.sem.cell(arena.robot_end(r, k))
            rank = (abs(ex - gx) + abs(ey - gy) - abs(x - gx) - abs(y - gy), k)
            if best is None or rank < best[0]:
                best = (rank, k)
        k = None if best is None else best[1]
        choice[key] = k
        return k

    oc0 = next(iter(fwd[0]))
    reach: list[dict[Config, int]] = [{oc0: cell_mask(arena.problem, arena.problem.robot.start)}]
    for t in range(steps):
        nxt: dict[Config, int] = {}
        for oc, rmask in reach[t].items():
            ends = 0
            for r in bits(rmask):
                k = pick(r, oc)
                if k is None:
                    return None
                ends |= 1 << arena.robot_end(r, k)
            for oc2 in arena.successors(oc):
                nxt[oc2] = nxt.get(oc2, 0) | ends
        reach.append(nxt)
    allowed = _allowed(arena, reach)
    assert all(allowed.values()), "a consistent choice must leave every reached state a move"
    final = {s_: tuple(sorted(a)) for s_, a in allowed.items()}
    return Strategy(final, tuple(reach), {"sat_vars": 0, "sat_clauses": 0, "consistent": 1})


def _phases(arena: Arena, ids: dict[tuple, int]) -> list[int]:
    """Preferred polarities that steer the solver towards simple strategies: reach as
    few states as possible, and in each state head for the goal (or stay there)."""
    gx, gy = arena.problem.robot.goal
    out = []
    for key, v in ids.items():
        if key[0] != "m":
            out.append(-v)
            continue
        _, r, _, _, k = key
        x, y = arena.sem.cell(r)
        e = arena.sem.cell(arena.robot_end(r, k))
        before, after = abs(x - gx) + abs(y - gy), abs(e[0] - gx) + abs(e[1] - gy)
        out.append(v if after < before or (before == 0 and after == 0) else -v)
    return out


def _layers_in(rows) -> list[dict[Config, int]]:
    return [{tuple(oc): int.from_bytes(m, "little") for oc, m in layer} for layer in rows]


def _layers_out(arena: Arena, layers) -> list[list[tuple[list[int], bytes]]]:
    nbytes = (arena.problem.width * arena.problem.height + 7) // 8
    return [[(list(oc), m.to_bytes(nbytes, "little")) for oc, m in layer.items()] for layer in layers]


@lru_cache(maxsize=4096)
def _moves_of(mask: int) -> tuple[int, ...]:
    """The move numbers of a move bitmask (few distinct masks, met for every state)."""
    return tuple(k for k in range(mask.bit_length()) if mask >> k & 1)


def _allowed(arena: Arena, reach: list[dict[Config, int]], clock: Clock | None = None) -> dict[State, set[int]]:
    """Moves of each reached state that win and stay inside ``reach`` at every time
    (compiled when the arena is; the loops below are the reference)."""
    if arena._core is not None:
        rows = arena._core.allowed(_layers_out(arena, reach), arena.core_seconds(clock))
        return {(r, tuple(oc)): set(_moves_of(m)) for r, oc, m in rows}
    steps = arena.steps
    n_moves = len(arena.robot.moves)
    allowed: dict[State, set[int]] = {}
    for t in range(steps):
        for oc, rmask in reach[t].items():
            wm = arena.winning_moves(t, oc)
            succ = arena.successors(oc)
            for r in bits(rmask):
                ok = set()
                for k in range(n_moves):
                    if not wm[k] >> r & 1:
                        continue
                    if t + 1 < steps:
                        e = arena.robot_end(r, k)
                        if not all(reach[t + 1].get(oc2, 0) >> e & 1 for oc2 in succ):
                            continue
                    ok.add(k)
                prev = allowed.get((r, oc))
                allowed[(r, oc)] = ok if prev is None else prev & ok
    return allowed


def _closure(arena: Arena, allowed: dict[State, set[int]], clock: Clock | None = None) -> list[dict[Config, int]]:
    """States reached from the start when every state may play any of its allowed moves."""
    if arena._core is not None:
        rows = [(r, list(oc), sum(1 << k for k in ks)) for (r, oc), ks in allowed.items()]
        return _layers_in(arena._core.closure(rows, arena.core_seconds(clock)))
    oc0 = next(iter(arena.layers[0]))
    out: list[dict[Config, int]] = [{oc0: cell_mask(arena.problem, arena.problem.robot.start)}]
    for t in range(arena.steps):
        nxt: dict[Config, int] = {}
        for oc, rmask in out[t].items():
            ends = 0
            for r in bits(rmask):
                for k in allowed[(r, oc)]:
                    ends |= 1 << arena.robot_end(r, k)
            for oc2 in arena.successors(oc):
                nxt[oc2] = nxt.get(oc2, 0) | ends
        out.append(nxt)
    return out
