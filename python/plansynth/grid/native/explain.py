"""Why no controller exists: the obstacles' winning strategy, played out.

When the native engine refutes a path length through the game (Arena.solve_game), the
backward induction also gives the obstacles a strategy: in every state where the robot
cannot win, for every move of the robot, a joint obstacle move after which the robot
still cannot win (or collides now). That strategy defeats every controller, with or
without access to the time, so it is a certificate of unrealizability; it can be
checked independently by replaying it (:func:`check_witness_play`).

:func:`explain` plays the strategy against the robot's most stubborn choices (a safe
move that keeps the goal reachable when there is one) and returns the play, ready to be
printed or animated.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [3, 1],
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [2, 0], "moves": ["stay", "left"]}], "steps": 2})
>>> e = explain(p, 2)
>>> e.kind, e.play[-1].reason
('game', 'collision at step 1 in cell (1, 0) with obstacle 0')
>>> check_witness_play(p, e.play, 2)
True
"""

from __future__ import annotations

from dataclasses import dataclass, field

from plansynth.budget import Budget
from plansynth.grid.native.arena import Arena
from plansynth.grid.native.cone import influence_cone
from plansynth.grid.native.engine import Engine
from plansynth.grid.native.turn import Turn, collision_text
from plansynth.grid.problem import GridProblem
from plansynth.grid.result import GridStatus
from plansynth.grid.semantics import State, initial_state, obstacle_move, robot_move, step


@dataclass(frozen=True)
class Explanation:
    """``kind``: ``realizable`` (nothing to explain), ``goal``, ``game``,
    ``stationary`` or ``unknown``; ``summary`` is one sentence; ``play`` the witness
    strategy against the robot's best try (for ``game``); ``final`` the last state;
    ``strategy`` the obstacles' strategy itself (for ``game``), to play against any move."""

    kind: str
    steps: int
    summary: str
    play: tuple[Turn, ...] = ()
    final: State | None = None
    counters: dict = field(default_factory=dict)
    strategy: ObstacleStrategy | None = field(default=None, compare=False, repr=False)
    #: the infinite objectives: the play's last state is that of step ``loop``, and the
    #: steps from there repeat forever
    loop: int | None = None


def explain(problem: GridProblem, steps: int | None, budget: Budget = Budget(seconds=60)) -> Explanation:
    """Decide ``steps`` (None for safety and recurrence) with the native engine and
    explain an unrealizable answer."""
    out = Engine().solve_length(problem, steps, budget)
    where = f"at l = {steps}" if steps is not None else f"for the {problem.objective.value} objective"
    if out.status is GridStatus.REALIZABLE:
        return Explanation("realizable", steps, f"a controller exists {where}: {out.program}", counters=out.counters)
    if out.status is GridStatus.UNKNOWN:
        return Explanation("unknown", steps, out.message, counters=out.counters)
    ref = out.witness
    if not problem.paper_model:
        from plansynth.grid.native.product.witness import product_play

        play, final, loop = product_play(problem, ref.strategy, steps)
        summary = f"{ref.detail} (the obstacles' strategy is certified: {ref.certificate.reason})"
        return Explanation("game", steps, summary, tuple(play), final, out.counters, loop=loop)
    if ref.kind == "goal":
        return Explanation("goal", steps, ref.detail, counters=out.counters)
    if ref.kind == "stationary":
        return Explanation(
            "stationary",
            steps,
            "time-dependent strategies would win, but no stationary one does: every controller that sees "
            "only positions must, in some state it reaches twice, make a move that loses one of the times",
            counters=out.counters,
        )
    strategy = ObstacleStrategy(problem, ref.arena)
    play, final = witness_play(problem, ref.arena, strategy)
    return Explanation("game", steps, ref.detail, tuple(play), final, out.counters, strategy)


def _joint_to(problem: GridProblem, arena: Arena, state: State, oc2) -> tuple[int, ...]:
    """Obstacle moves that take the read obstacles from ``state`` to configuration ``oc2``."""
    joint = [0] * len(problem.obstacles)
    for j, i in enumerate(arena.read):
        for m in range(len(problem.obstacles[i].moves)):
            end, _ = obstacle_move(problem, i, state.obstacles[i], m)
            if arena.sem.index(end) == oc2[j]:
                joint[i] = m
                break
    return tuple(joint)


def _collision_reply(problem: GridProblem, state: State, k: int) -> tuple[int, ...] | None:
    """A joint obstacle move that hits the robot playing ``k`` (None if none can)."""
    _, r_swept = robot_move(problem, state.robot, k)
    if any(c in problem.walls for c in r_swept):
        return tuple(0 for _ in problem.obstacles)
    for i in range(len(problem.obstacles)):
        for j in range(len(problem.obstacles[i].moves)):
            _, swept = obstacle_move(problem, i, state.obstacles[i], j)
            if set(swept) & set(r_swept):
                joint = [0] * len(problem.obstacles)
                joint[i] = j
                return tuple(joint)
    return None


class ObstacleStrategy:
    """The obstacles' winning strategy of a refuted game, as a reply to any robot move.

    The backward induction of the game (minimax over the explored arena): the robot
    maximises the step at which it loses, the obstacles minimise it; a win would count
    as infinitely late. :meth:`reply` answers a robot move in any state of the game, so
    the strategy can be played against a person choosing the robot's moves, not only
    against the robot's best try (:func:`witness_play`).
    """

    def __init__(self, problem: GridProblem, arena: Arena) -> None:
        self.problem = problem
        self.arena = arena
        self.steps = arena.steps
        self._memo: dict = {}

    def value(self, t: int, r: int, oc) -> int:
        """The step at which the robot at cell index ``r`` loses from step ``t`` against
        this strategy, however it plays (``steps + 1``: it cannot be made to lose)."""
        arena, problem, steps = self.arena, self.problem, self.steps
        key = (t, r, oc)
        memo = self._memo
        if key in memo:
            return memo[key]
        if t == steps:
            v = steps + 1 if r == arena.sem.index(problem.robot.goal) else steps
        else:
            v = -1
            safe = arena.safe_sources(t, oc)
            for k in range(len(problem.robot.moves)):
                if not safe[k] >> r & 1:
                    val = t
                else:
                    e = arena.robot_end(r, k)
                    val = min(self.value(t + 1, e, oc2) for oc2 in arena.successors(oc))
                v = max(v, val)
        memo[key] = v
        return v

    def reply(self, t: int, state: State, k: int) -> tuple[tuple[int, ...], int]:
        """The obstacles' joint move against robot move ``k`` in ``state`` at step ``t``,
        and the step at which the robot then loses at the latest."""
        arena, problem = self.arena, self.problem
        r = arena.sem.index(state.robot)
        oc = tuple(arena.sem.index(state.obstacles[i]) for i in arena.read)
        if not arena.safe_sources(t, oc)[k] >> r & 1:
            joint, val = _collision_reply(problem, state, k), t
        else:
            e = arena.robot_end(r, k)
            val, oc2 = min((self.value(t + 1, e, oc2), oc2) for oc2 in arena.successors(oc))
            joint = _joint_to(problem, arena, state, oc2)
        if joint is None:  # unsafe only through an obstacle outside the arena: cannot happen
            raise AssertionError("unsafe move without a colliding obstacle")
        return joint, val


def witness_play(
    problem: GridProblem, arena: Arena, strategy: ObstacleStrategy | None = None
) -> tuple[list[Turn], State]:
    """Play the obstacles' strategy (:class:`ObstacleStrategy`) against a robot that
    postpones its loss for as long as it can."""
    strategy = strategy or ObstacleStrategy(problem, arena)
    steps = arena.steps
    state = initial_state(problem)
    play: list[Turn] = []
    for t in range(steps):
        best = None
        for k in range(len(problem.robot.moves)):
            joint, val = strategy.reply(t, state, k)
            end, _ = robot_move(problem, state.robot, k)
            closer = -abs(end[0] - problem.robot.goal[0]) - abs(end[1] - problem.robot.goal[1])
            if best is None or (val, closer) > best[0]:
                best = ((val, closer), k, joint)
        _, k, joint = best
        out = step(problem, state, k, joint)
        if out.collided:
            play.append(Turn(t, state, k, joint, collision_text(problem, state, k, joint, t)))
            return play, out.state
        play.append(Turn(t, state, k, joint))
        state = out.state
    last = play[-1]
    play[-1] = Turn(
        last.t,
        last.state,
        last.robot_move,
        last.obstacle_moves,
        f"not on the goal after step {steps - 1}: the robot is at {state.robot}",
    )
    return play, state


def check_witness_play(problem: GridProblem, play: tuple[Turn, ...], steps: int) -> bool:
    """Replay a play with the spec's semantics: True iff it ends in a loss for the robot."""
    state = initial_state(problem)
    for turn in play:
        if turn.state != state:
            return False
        out = step(problem, state, turn.robot_move, turn.obstacle_moves)
        if out.collided:
            return True
        state = out.state
    return len(play) == steps and state.robot != problem.robot.goal


def relevant_summary(problem: GridProblem, steps: int) -> str:
    cone = influence_cone(problem, steps)
    return f"{len(cone.relevant)} of {len(problem.obstacles)} obstacles can meet the robot in {steps} steps"
