"""The bounded game between the robot and the obstacles, explored as sets of cells.

A joint state is the robot's cell and the cells of the obstacles the controller
*reads*. Obstacles that matter but are not read are folded into a per-step danger mask
(the cells they may sweep in that step): a controller that does not look at an
obstacle must avoid everything that obstacle can do, and this is exact because every
obstacle moves independently of everything else (spec, Semantics).

The game is explored per obstacle configuration: for each time t and tuple of read
obstacle cells, the set of robot cells is one integer mask, so a step of the robot is a
few shifts (:mod:`plansynth.grid.native.bitgrid`). The obstacles' successor
configurations are the product of each read obstacle's end cells.

Backward induction over this graph (:meth:`Arena.solve_game`) decides the game in which
the controller may also see the time: a necessary condition for a controller program to
exist (the paper's controllers see positions only, Section 3.1).

The exploration, backward induction and the winning-forward layers run in the compiled
core when it is built (``crates/plansynth-core/src/arena/``, same numbering, same
order); the pure-Python methods here are its reference (``use_rust=False``), and a
property test compares the two on random problems. The compiled game's memory limit is
checked against the bytes its data structures hold (their capacities).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

from plansynth.budget import BudgetExhausted, Clock
from plansynth.grid.native.bitgrid import AgentGeometry, bits, cell_mask
from plansynth.grid.native.cone import Cone, robot_live
from plansynth.grid.native.limits import check_clock
from plansynth.grid.problem import GridProblem
from plansynth.grid.semantics import CompiledSemantics, obstacle_move, robot_move

Config = tuple[int, ...]  # cell indices of the read obstacles


#: Seconds kept back, beyond the per-object estimate, for leaving a compiled game.
COMPILED_FREE_SECONDS = 0.1


@dataclass
class Arena:
    """The explored game for one path length and one set of read obstacles.

    ``layers[t]`` maps each obstacle configuration reachable at time t to the mask of
    robot cells reachable with it (pruned to cells that can still reach the goal).
    After :meth:`solve_game`, ``win[t]`` holds the states from which the robot wins the
    time-dependent game.
    """

    problem: GridProblem
    steps: int
    read: tuple[int, ...]
    abstract_danger: tuple[int, ...]
    sem: CompiledSemantics
    robot: AgentGeometry
    live: tuple[int, ...]
    layers: list[dict[Config, int]] = field(default_factory=list)
    win: list[dict[Config, int]] = field(default_factory=list)
    _succ: dict[Config, tuple[Config, ...]] = field(default_factory=dict)
    _danger: dict[Config, int] = field(default_factory=dict)
    _hits: dict[tuple[Config, int], tuple[int, ...]] = field(default_factory=dict)
    _ends: list[list[tuple[int, ...]]] = field(default_factory=list)
    _obs_danger: list[list[int]] = field(default_factory=list)
    _robot_end: dict[tuple[int, int], int] = field(default_factory=dict)
    _succ_tuples: int = 0
    _wm: dict[tuple[int, Config], tuple[int, ...]] = field(default_factory=dict)
    memory_bytes: int | None = None
    _core: object = None
    _fwd: list | None = None  # the compiled game's winning-forward layers, once read
    _fwd_rows: list | None = None  # the same as the core returned them, until read

    # -- construction --------------------------------------------------------------
    @classmethod
    def build(
        cls,
        problem: GridProblem,
        steps: int,
        cone: Cone,
        read: tuple[int, ...],
        clock: Clock | None = None,
        max_states: int | None = None,
        explore: bool = True,
        memory_mb: int | None = None,
        use_rust: bool | None = None,
    ) -> Arena:
        """Explore the states reachable from the start that can still reach the goal.

        Stops with :class:`~plansynth.budget.BudgetExhausted` when the clock runs out (keeping the time that
        freeing the explored game will take), when more than ``max_states``
        configurations are met, or when the game's memory passes ``memory_mb`` (measured
        in the compiled core, estimated in the reference). ``use_rust``: None uses the
        compiled core when built, False the pure-Python reference.
        """
        sem = CompiledSemantics(problem)
        robot = AgentGeometry.robot(problem)
        if not read:
            abstract = list(cone.blind_danger)
        else:
            abstract = [0] * steps
            for i in cone.relevant:
                if i not in read:
                    dng = cone.obstacle_facts(i, clock)[1]
                    for t in range(steps):
                        abstract[t] |= dng[t]
        start = cell_mask(problem, problem.robot.start)
        goal = cell_mask(problem, problem.robot.goal)
        live = robot_live(robot, start, goal, steps, tuple(abstract), clock=clock)
        a = cls(problem, steps, tuple(read), tuple(abstract), sem, robot, live)
        a.memory_bytes = None if memory_mb is None else int(memory_mb) << 20
        a._ends = [_LazyCells(problem, i, ends=True) for i in read]
        a._obs_danger = [_LazyCells(problem, i, ends=False) for i in read]
        if explore and use_rust is not False and _compiled() is not None:
            a._core = a._compiled_game(_compiled())
            a._explore_compiled(clock, max_states)
        elif explore:
            a._explore(clock, max_states)
        return a

    def _compiled_game(self, core):
        """The game's fixed data handed to the core's ``arena``: masks as bytes, moves as
        cell-index deltas (``y * width + x``)."""
        p, w = self.problem, self.problem.width
        n = w * p.height
        nbytes = (n + 7) // 8

        def b(m: int) -> bytes:
            return m.to_bytes(nbytes, "little")

        def delta(o) -> int:
            return o[1] * w + o[0]

        robot = [
            (b(self.robot.valid[k]), b(self.robot.free[k]), delta(m.to), [delta(o) for o in m.offsets()])
            for k, m in enumerate(self.robot.moves)
        ]
        obstacles = []
        for i in self.read:
            g = AgentGeometry.obstacle(p, i)
            obstacles.append(
                [(b(g.valid[k]), delta(m.to), [delta(o) for o in m.offsets()]) for k, m in enumerate(g.moves)]
            )
        oc0 = [self.sem.index(p.obstacles[i].start) for i in self.read]
        return core.Arena(
            n,
            self.steps,
            robot,
            obstacles,
            [b(d) for d in self.abstract_danger],
            [b(x) for x in self.live],
            self.sem.index(p.robot.start),
            self.sem.index(p.robot.goal),
            oc0,
        )

    def core_seconds(self, clock: Clock | None) -> float | None:
        """Seconds a call of the compiled core may use (None: no limit): what is left,
        less the time that freeing the game (and the layers read from it) will take
        once the answer is unknown."""
        if clock is None:
            return None
        left = clock.remaining()
        return None if left == float("inf") else max(0.0, left - self.free_reserve())

    def free_reserve(self) -> float:
        """Seconds kept back at the end of a budget for releasing the game."""
        if self._core is None:
            return 0.0
        fwd = self._fwd if self._fwd is not None else self._fwd_rows
        held = sum(self._core.layer_sizes()) + (sum(len(x) for x in fwd) if fwd is not None else 0)
        return COMPILED_FREE_SECONDS + 2 * self.FREE_SECONDS_PER_OBJECT * held

    def _explore_compiled(self, clock: Clock | None, max_states: int | None) -> None:
        self._core.explore(self.core_seconds(clock), self.memory_bytes, max_states)  # BudgetExhausted past them
        self.layers = _CompiledLayers(self._core, False)

    def config_count(self) -> int:
        """Obstacle configurations explored, summed over times."""
        if self._core is not None:
            return sum(self._core.layer_sizes())
        return sum(len(x) for x in self.layers)

    def start_alive(self) -> bool:
        """Whether the start state is in the explored game (it can reach the goal)."""
        if self._core is not None:
            return self._core.layer_sizes()[0] > 0
        return bool(self.layers[0])

    #: Rough bytes per explored configuration and per cached successor tuple (CPython),
    #: and seconds to free one of them: the memory limit and the time reserved at the end
    #: of a budget for releasing the game are derived from these.
    BYTES_PER_CONFIG = 400
    BYTES_PER_SUCCESSOR = 120
    FREE_SECONDS_PER_OBJECT = 3e-7

    def _footprint(self) -> tuple[int, int]:
        """(configurations, cached successor tuples) held now."""
        return sum(len(x) for x in self.layers), self._succ_tuples

    def _over_budget(self, clock: Clock | None, memory_bytes: int | None) -> str | None:
        """Why exploration must stop now (time, keeping what freeing the game will
        cost, or memory), or None."""
        configs, tuples = self._footprint()
        if clock is not None and clock.remaining() <= self.FREE_SECONDS_PER_OBJECT * (configs + tuples):
            return "time"
        if (
            memory_bytes is not None
            and configs * self.BYTES_PER_CONFIG + tuples * self.BYTES_PER_SUCCESSOR > memory_bytes
        ):
            return "memory"
        return None

    def _explore(self, clock: Clock | None, max_states: int | None) -> None:
        oc0: Config = tuple(self.sem.index(self.problem.obstacles[i].start) for i in self.read)
        first = cell_mask(self.problem, self.problem.robot.start) & self.live[0]
        self.layers = [{oc0: first} if first else {}]
        count = 1
        for t in range(self.steps):
            nxt: dict[Config, int] = {}
            for oc, r in self.layers[t].items():
                img = 0
                for k, safe in enumerate(self.safe_sources(t, oc)):
                    img |= self.robot.image(r & safe, k)
                img &= self.live[t + 1]
                if not img:
                    continue
                for oc2 in self.successors(oc):
                    nxt[oc2] = nxt.get(oc2, 0) | img
                why = self._over_budget(clock, self.memory_bytes) if len(nxt) % 64 == 0 else None
                if why is not None or (clock is not None and clock.exhausted()):
                    self._explore_stopped(why, clock, t, count + len(nxt))
            self.layers.append(nxt)
            count += len(nxt)
            if max_states is not None and count > max_states:
                raise BudgetExhausted(
                    "exploring the game", "configurations", f"more than {max_states} obstacle configurations"
                )

    def _explore_stopped(self, why: str | None, clock: Clock | None, t: int, configs: int) -> None:
        """Raise why the reference exploration stops at step ``t``."""
        where = f" at step {t} ({configs} obstacle configurations)"
        if why == "time":  # what is left would not free the game
            raise BudgetExhausted("exploring the game", "time", f"exploring the game{where}: out of time")
        check_clock(clock, "exploring the game", where)
        raise BudgetExhausted(
            "exploring the game",
            "memory",
            f"exploring the game at step {t}: the game outgrows the memory budget of "
            f"{(self.memory_bytes or 0) >> 20} MB ({configs} obstacle configurations, "
            f"{self._succ_tuples} joint obstacle moves)",
        )

    # -- local facts ---------------------------------------------------------------
    def successors(self, oc: Config) -> tuple[Config, ...]:
        """Obstacle configurations one step after ``oc`` (every joint obstacle move)."""
        s = self._succ.get(oc)
        if s is None and self._core is not None:
            s = tuple(map(tuple, self._core.successors(list(oc))))
            self._succ[oc] = s
        elif s is None:
            s = tuple(itertools.product(*(self._ends[j][c] for j, c in enumerate(oc))))
            self._succ[oc] = s
            self._succ_tuples += len(s)
        return s

    def config_danger(self, oc: Config) -> int:
        """Cells the read obstacles may sweep in one step from ``oc``."""
        d = self._danger.get(oc)
        if d is None:
            d = _or(self._obs_danger[j][c] for j, c in enumerate(oc))
            self._danger[oc] = d
        return d

    def safe_sources(self, t: int, oc: Config) -> tuple[int, ...]:
        """Per robot move k: cells from which k collides with nothing in step t."""
        h = self._hits.get((oc, t))
        if h is None:
            danger = self.config_danger(oc) | self.abstract_danger[t]
            h = tuple(
                self.robot.free[k] & ~self.robot.hit_sources(danger, k) & self.robot.full
                for k in range(len(self.robot.moves))
            )
            if len(self._hits) > 200_000:
                self._hits.clear()
            self._hits[(oc, t)] = h
        return h

    def robot_end(self, r: int, k: int) -> int:
        key = (r, k)
        e = self._robot_end.get(key)
        if e is None:
            end, _ = robot_move(self.problem, self.sem.cell(r), k)
            e = self._robot_end[key] = self.sem.index(end)
        return e

    def winning_moves(self, t: int, oc: Config) -> tuple[int, ...]:
        """Per robot move k: robot cells (of ``layers[t][oc]``) from which k wins at t.

        Needs :meth:`solve_game` first. A move wins if it is safe and every successor
        state is winning at t + 1 (exactly the goal at t + 1 = l).
        """
        key = (t, oc)
        got = self._wm.get(key)
        if got is not None:
            return got
        if self._core is not None:
            got = tuple(int.from_bytes(m, "little") for m in self._core.winning_moves(t, list(oc)))
            self._wm[key] = got
            return got
        target = self._target(t, oc)
        safe = self.safe_sources(t, oc)
        r = self.layers[t].get(oc, 0)
        got = tuple(self.robot.pre(target, k) & safe[k] & r for k in range(len(self.robot.moves)))
        self._wm[key] = got  # final once win[t + 1] is (backward induction fills it first)
        return got

    def _target(self, t: int, oc: Config) -> int:
        nxt = self.win[t + 1]
        m = -1
        for oc2 in self.successors(oc):
            m &= nxt.get(oc2, 0)
            if not m:
                return 0
        return m

    # -- the time-dependent game ---------------------------------------------------
    def solve_game(self, clock: Clock | None = None) -> bool:
        """Backward induction; True iff the robot wins when it may also see the time."""
        if self._core is not None:
            self._wm, self._fwd, self._fwd_rows = {}, None, None
            won = self._core.solve_game(self.core_seconds(clock), self.memory_bytes)
            self.win = _CompiledLayers(self._core, True)
            return won
        goal = cell_mask(self.problem, self.problem.robot.goal)
        self._wm = {}
        self.win = [dict() for _ in range(self.steps + 1)]
        self.win[self.steps] = {oc: r & goal for oc, r in self.layers[self.steps].items() if r & goal}
        for t in range(self.steps - 1, -1, -1):
            layer = {}
            for oc in self.layers[t]:
                w = 0
                for m in self.winning_moves(t, oc):
                    w |= m
                if w:
                    layer[oc] = w
                check_clock(clock, "solving the game", f" at step {t}")
            self.win[t] = layer
        oc0 = next(iter(self.layers[0]), None)
        return oc0 is not None and bool(self.win[0].get(oc0, 0) & cell_mask(self.problem, self.problem.robot.start))

    def state_count(self) -> int:
        if self._core is not None:
            return self._core.state_count()
        return sum(bin(r).count("1") for layer in self.layers for r in layer.values())

    def inputs(self, r: int, oc: Config) -> tuple[int, ...]:
        """Controller inputs of a state, over :meth:`variables`."""
        out = list(self.sem.cell(r))
        for c in oc:
            out.extend(self.sem.cell(c))
        return tuple(out)

    def variables(self) -> tuple[str, ...]:
        names = ["rx", "ry"]
        for i in self.read:
            names += [f"o{i}x", f"o{i}y"]
        return tuple(names)

    def cells_of(self, mask: int) -> list[int]:
        return bits(mask)


def _compiled():
    """The compiled core's module when it has the arena, else None."""
    from plansynth.grid.native import fast

    core = fast._core
    return core if fast.available() and hasattr(core, "Arena") else None


class _CompiledLayers:
    """The layers (or winning sets) of a compiled game, read as the reference's list of
    dicts ``{configuration: robot-cell mask}``; each layer is fetched on first use."""

    def __init__(self, core, win: bool) -> None:
        self.core, self.is_win = core, win
        self.n = len(core.layer_sizes())
        self.cache: dict[int, dict[Config, int]] = {}

    def __len__(self) -> int:
        return self.n

    def __getitem__(self, t: int) -> dict[Config, int]:
        if t < 0:
            t += self.n
        if not 0 <= t < self.n:
            raise IndexError(t)
        got = self.cache.get(t)
        if got is None:
            got = self.cache[t] = {tuple(oc): int.from_bytes(m, "little") for oc, m in self.core.layer(t, self.is_win)}
        return got

    def __iter__(self):
        return (self[t] for t in range(self.n))


def _or(masks) -> int:
    out = 0
    for m in masks:
        out |= m
    return out


class _LazyCells:
    """Per-cell facts of one obstacle, computed on first use (grids can be large and
    an obstacle visits few cells): its distinct end cells, or the mask it may sweep."""

    def __init__(self, problem: GridProblem, i: int, ends: bool) -> None:
        self.problem, self.i, self.ends = problem, i, ends
        self.cache: dict[int, object] = {}

    def __getitem__(self, c: int):
        v = self.cache.get(c)
        if v is None:
            p, w = self.problem, self.problem.width
            cell = (c % w, c // w)
            outs = [obstacle_move(p, self.i, cell, k) for k in range(len(p.obstacles[self.i].moves))]
            if self.ends:
                v = tuple(dict.fromkeys(e[1] * w + e[0] for e, _ in outs))
            else:
                v = 0
                for _, swept in outs:
                    for x, y in swept:
                        v |= 1 << (y * w + x)
            self.cache[c] = v
        return v
