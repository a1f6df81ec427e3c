"""The closed loop of a program and the obstacles, explored state by state, and the
verdict for each objective (:mod:`plansynth.grid.objective`).

With the program fixed there is no alternation left: the controller loses iff *some*
obstacle behaviour makes it lose, and each objective's losing runs have a shape that
a search of the closed loop's reachable states finds exactly:

* ``safety``: a reachable step with a collision;
* ``reach`` within l: a run of at most l steps that collides before first standing on
  the goal, or that has not stood on it by time l;
* ``exact``: a collision in steps 0..l-1, or a run not on the goal after step l-1;
* ``recurrence``: a reachable collision, or a reachable cycle of steps none of which
  ends on the goal g_m the mode waits for (then the mode never changes again), in which,
  under ``fair``, every obstacle changes its cell at least once (a fair cycle: the
  obstacles keep their promise and the robot still never gets there). Cycles are found
  through the strongly connected components (Tarjan, "Depth-first search and linear
  graph algorithms", SIAM J. Comput. 1(2), 1972) of the steps that do not end on the
  goal: a component with an internal step contains a cycle through all its internal
  steps, so it holds a fair cycle iff every obstacle changes cell on one of them.

This is the verifier of every problem outside the paper's model
(:attr:`~plansynth.grid.problem.GridProblem.paper_model`): it uses only
:func:`~plansynth.grid.semantics.step` and the legal moves of
:mod:`plansynth.grid.semantics`, and :func:`~plansynth.grid.programs.compile_program`
to evaluate the program; it shares no code with the native engine. The number of
states it visits is that of the closed loop (for a 16 x 16 moving-obstacle game a few
hundred thousand); beyond what a budget allows, the verdict is ``unknown``.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [3, 1], "objective": "recurrence",
...     "robot": {"start": [0, 0], "goals": [[2, 0], [0, 0]], "moves": ["stay", "right", "left"]}})
>>> verify_closed_loop(p, parse_program("(ite (= m 0) 1 2)"), None).status.value
'wins'
>>> v = verify_closed_loop(p, parse_program("1"), None)
>>> v.status.value, v.counterexample.reason
('loses', 'the robot never reaches goal 1 at (0, 0) again: the run repeats from step 2')
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Iterator

from plansynth.budget import Budget, BudgetExhausted
from plansynth.grid.cycles import strongly_connected
from plansynth.grid.objective import ObjectiveKind
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Term, compile_program
from plansynth.grid.semantics import State, controller_inputs, initial_state, joint_choices, step
from plansynth.grid.verify.meter import Meter
from plansynth.grid.verify.replay import collision_reason
from plansynth.grid.verify.verdict import Counterexample, Verdict, VerifyStatus

__all__ = ["verify_closed_loop", "ClosedLoop"]

Edge = tuple[State, int, tuple[int, ...]]  # (predecessor, robot move, joint obstacle move)


class ClosedLoop:
    """The program's moves and the obstacles' replies, one state at a time."""

    def __init__(self, problem: GridProblem, program: Term, meter: Meter) -> None:
        self.problem = problem
        self.meter = meter
        self.f = compile_program(program, problem.variables)
        self.n_moves = len(problem.robot.moves)

    def move(self, state: State) -> int:
        k = self.f(*controller_inputs(self.problem, state))
        if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < self.n_moves:
            raise ValueError(f"the program returned {k!r} in {state}, not a move number of the robot")
        return k

    def successors(self, state: State, k: int) -> Iterator[tuple[tuple[int, ...], State, bool]]:
        """(joint obstacle move, next state, collided) for every legal reply, each
        outcome once."""
        seen: set[tuple[State, bool]] = set()
        for joint in joint_choices(self.problem, state):
            self.meter.tick(self.meter.SEMANTICS_CALL)
            nxt, collided = step(self.problem, state, k, joint)
            if (nxt, collided) not in seen:
                seen.add((nxt, collided))
                yield joint, nxt, collided


def verify_closed_loop(
    problem: GridProblem, program: Term, steps: int | None, *, budget: Budget | None = None
) -> Verdict:
    """Decide exactly whether ``program`` achieves ``problem``'s objective (``steps``:
    the path length l of ``exact`` and ``reach``; None otherwise), within ``budget``."""
    t0 = time.perf_counter()
    meter = Meter(budget)
    loop = ClosedLoop(problem, program, meter)
    search = _Search(problem, loop, meter)
    try:
        if problem.objective.bounded:
            if steps is None or steps < 1:
                raise ValueError(f"objective {problem.objective.value} needs a path length >= 1, got {steps}")
            cex = search.bounded(steps, exact=problem.objective is ObjectiveKind.EXACT)
        elif problem.objective is ObjectiveKind.SAFETY:
            cex = search.stationary(cycles=False)
        else:
            cex = search.stationary(cycles=True)
    except (BudgetExhausted, MemoryError) as out:
        return meter.ran_out(out, steps, search.explored, t0)
    status = VerifyStatus.WINS if cex is None else VerifyStatus.LOSES
    return Verdict(status, steps, cex, search.explored, time.perf_counter() - t0)


class _Search:
    def __init__(self, problem: GridProblem, loop: ClosedLoop, meter: Meter) -> None:
        self.problem, self.loop, self.meter = problem, loop, meter
        self.explored = 0

    # -- runs ----------------------------------------------------------------------
    def _run(
        self, parent: dict[State, Edge | None], last: State
    ) -> tuple[list[State], list[int], list[tuple[int, ...]]]:
        states, moves, joints = [last], [], []
        while parent[states[-1]] is not None:
            prev, k, joint = parent[states[-1]]
            states.append(prev)
            moves.append(k)
            joints.append(joint)
        return states[::-1], moves[::-1], joints[::-1]

    def _collision(self, parent, state: State, k: int, joint, nxt: State, t: int) -> Counterexample:
        states, moves, joints = self._run(parent, state)
        reason = collision_reason(self.problem, state, k, joint, t)
        return Counterexample(tuple(joints) + (tuple(joint),), tuple(states) + (nxt,), tuple(moves) + (k,), reason)

    # -- exact and reach: layer by layer -------------------------------------------
    def bounded(self, steps: int, *, exact: bool) -> Counterexample | None:
        goal = self.problem.robot.goal
        start = initial_state(self.problem)
        layer: dict[State, Edge | None] = {start: None}
        history: list[dict[State, Edge | None]] = []
        for t in range(steps + 1):
            self.meter.phase = f"the closed loop (step {t} of {steps})"
            self.meter.check()
            history.append(layer)
            nxt_layer: dict[State, Edge | None] = {}
            for state in layer:
                self.explored += 1
                if not exact and state.robot == goal:
                    continue  # reached: this run is won
                if t == steps:
                    if exact and state.robot == goal:
                        continue
                    states, moves, joints = self._runs(history, state)
                    where = "after step" if exact else "within"
                    reason = (
                        f"not on the goal ({goal[0]}, {goal[1]}) {where} {steps - 1 if exact else steps}"
                        f"{'' if exact else ' steps'}: the robot is at ({state.robot[0]}, {state.robot[1]})"
                    )
                    return Counterexample(tuple(joints), tuple(states), tuple(moves), reason)
                k = self.loop.move(state)
                for joint, nxt, collided in self.loop.successors(state, k):
                    if collided:
                        states, moves, joints = self._runs(history, state)
                        reason = collision_reason(self.problem, state, k, joint, t)
                        return Counterexample(
                            tuple(joints) + (tuple(joint),), tuple(states) + (nxt,), tuple(moves) + (k,), reason
                        )
                    if nxt not in nxt_layer:
                        nxt_layer[nxt] = (state, k, joint)
            layer = nxt_layer
        return None

    @staticmethod
    def _runs(history: list[dict[State, Edge | None]], last: State):
        states, moves, joints = [last], [], []
        for t in range(len(history) - 1, 0, -1):
            prev, k, joint = history[t][states[-1]]
            states.append(prev)
            moves.append(k)
            joints.append(joint)
        return states[::-1], moves[::-1], joints[::-1]

    # -- safety and recurrence: the reachable graph ----------------------------------
    def stationary(self, *, cycles: bool) -> Counterexample | None:
        problem = self.problem
        start = initial_state(problem)
        parent: dict[State, Edge | None] = {start: None}
        depth = {start: 0}
        # for recurrence: the steps that do not end on the awaited goal, with the
        # obstacles that change cell in them (a bit mask)
        edges: dict[State, list[tuple[State, int, tuple[int, ...], int]]] = {}
        queue = deque([start])
        self.meter.phase = "the closed loop's reachable states"
        self.meter.check()
        while queue:
            state = queue.popleft()
            self.explored += 1
            k = self.loop.move(state)
            out = []
            for joint, nxt, collided in self.loop.successors(state, k):
                if collided:
                    return self._collision(parent, state, k, joint, nxt, depth[state])
                if nxt not in parent:
                    parent[nxt] = (state, k, joint)
                    depth[nxt] = depth[state] + 1
                    queue.append(nxt)
                if cycles and nxt.robot != problem.robot.goals[state.mode]:
                    moved = sum(1 << i for i, (a, b) in enumerate(zip(state.obstacles, nxt.obstacles)) if a != b)
                    out.append((nxt, k, tuple(joint), moved))
            if cycles:
                edges[state] = out
        if not cycles:
            return None
        self.meter.phase = "the cycles that avoid the next goal"
        return self._bad_cycle(parent, edges)

    def _bad_cycle(self, parent, edges) -> Counterexample | None:
        problem = self.problem
        everyone = (1 << len(problem.obstacles)) - 1 if problem.fair else 0
        for component in strongly_connected(edges, self.meter.tick, target=lambda e: e[0]):
            members = set(component)
            inner = [(u, e) for u in component for e in edges[u] if e[0] in members]
            if not inner:
                continue
            moved = 0
            for _, e in inner:
                moved |= e[3]
            if moved & everyone != everyone:
                continue  # an obstacle never changes cell here: the assumption fails
            return self._lasso(parent, edges, members, inner, everyone)
        return None

    def _lasso(self, parent, edges, members: set[State], inner, everyone: int) -> Counterexample:
        """A run to the component and a cycle in it through a step in which each
        obstacle changes cell (under ``fair``), as a lasso."""
        problem = self.problem
        entry = min(members, key=lambda s: self._depth(parent, s))
        states, moves, joints = self._run(parent, entry)
        loop_at = len(states) - 1
        wanted = []
        need = everyone
        for u, e in inner:
            if e[3] & need:
                wanted.append((u, e))
                need &= ~e[3]
        if not wanted:
            wanted = [inner[0]]
        cur = entry
        for u, e in wanted:
            for v, k, joint in _path(edges, members, cur, u):
                moves.append(k)
                joints.append(joint)
                states.append(v)
            moves.append(e[1])
            joints.append(e[2])
            states.append(e[0])
            cur = e[0]
        for v, k, joint in _path(edges, members, cur, entry):
            moves.append(k)
            joints.append(joint)
            states.append(v)
        m = entry.mode
        g = problem.robot.goals[m]
        reason = f"the robot never reaches goal {m} at ({g[0]}, {g[1]}) again: the run repeats from step {loop_at}" + (
            " while every obstacle keeps moving" if problem.fair else ""
        )
        return Counterexample(tuple(joints), tuple(states), tuple(moves), reason, loop=loop_at)

    @staticmethod
    def _depth(parent, s: State) -> int:
        n = 0
        while parent[s] is not None:
            s = parent[s][0]
            n += 1
        return n


def _path(edges, members: set[State], src: State, dst: State) -> list[tuple[State, int, tuple[int, ...]]]:
    """The steps of a shortest path from ``src`` to ``dst`` inside ``members``."""
    if src == dst:
        return []
    back: dict[State, tuple[State, int, tuple[int, ...]]] = {}
    queue = deque([src])
    seen = {src}
    while queue:
        u = queue.popleft()
        for v, k, joint, _ in edges[u]:
            if v in members and v not in seen:
                seen.add(v)
                back[v] = (u, k, joint)
                if v == dst:
                    out = []
                    while v != src:
                        u2, k2, j2 = back[v]
                        out.append((v, k2, j2))
                        v = u2
                    return out[::-1]
                queue.append(v)
    raise AssertionError("no path inside a strongly connected component")
