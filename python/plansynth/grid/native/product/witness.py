"""Why no controller exists, for the product engine's objectives: the obstacles'
certified strategy (:mod:`.certify`) played against the robot's most stubborn try.

The robot tries, at every step, the move that postpones its defeat the longest: a move
no reply collides with, then (reach, exact) one towards the goal, (recurrence) one onto
the awaited goal or towards it, (safety) one whose reply leaves it the most room. The
obstacles answer by their strategy. The play ends at a collision, after l steps
(``exact``, ``reach``), or, for the infinite objectives, when a state repeats: the steps
from its first visit then repeat forever (a lasso). Since the strategy wins against
every robot, the loop never reaches the awaited goal and, under ``fair``, every
obstacle changes cell in it; :func:`check_product_play` replays the play through
:func:`~plansynth.grid.semantics.step` and checks exactly that.
"""

from __future__ import annotations

from plansynth.grid.native.product.certify import ObstacleStrategy
from plansynth.grid.native.turn import Turn, collision_text
from plansynth.grid.objective import ObjectiveKind
from plansynth.grid.problem import GridProblem
from plansynth.grid.semantics import State, initial_state, robot_move, step

__all__ = ["product_play", "check_product_play"]


def _distance(a: tuple[int, int], b: tuple[int, int]) -> int:
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def product_play(problem: GridProblem, strategy: ObstacleStrategy, steps: int | None):
    """(turns, final state, loop start or None): the play described above, as the
    :class:`~plansynth.grid.native.turn.Turn` values of the paper engine's witness."""
    kind = problem.objective
    state = initial_state(problem)
    turns: list[Turn] = []
    seen: dict[State, int] = {}
    horizon = steps if kind.bounded else 10_000
    for t in range(horizon):
        if kind is ObjectiveKind.REACH and state.robot == problem.robot.goal:
            break
        if not kind.bounded:
            if state in seen:
                loop = seen[state]
                goal = problem.robot.goals[state.mode] if kind is ObjectiveKind.RECURRENCE else None
                why = (
                    f"the play repeats from step {loop} forever"
                    if goal is None
                    else f"the play repeats from step {loop} forever without reaching goal {state.mode} at {goal}"
                    + (" while every obstacle keeps moving" if problem.fair else "")
                )
                last = turns[-1]
                turns[-1] = Turn(last.t, last.state, last.robot_move, last.obstacle_moves, why)
                return turns, state, loop
            seen[state] = t
        best = None
        for k in range(len(problem.robot.moves)):
            joint = strategy(state, k, t)
            nxt, collided = step(problem, state, k, joint)
            score = _score(problem, state, k, nxt, collided)
            if best is None or score > best[0]:
                best = (score, k, joint, nxt, collided)
        _, k, joint, nxt, collided = best
        if collided:
            turns.append(Turn(t, state, k, joint, collision_text(problem, state, k, joint, t)))
            return turns, nxt, None
        turns.append(Turn(t, state, k, joint))
        state = nxt
    if turns and kind.bounded:
        last = turns[-1]
        turns[-1] = Turn(
            last.t,
            last.state,
            last.robot_move,
            last.obstacle_moves,
            f"not on the goal {'after step' if kind is ObjectiveKind.EXACT else 'within'} "
            f"{steps - 1 if kind is ObjectiveKind.EXACT else steps}: the robot is at {state.robot}",
        )
    return turns, state, None


def _score(problem: GridProblem, state: State, k: int, nxt: State, collided: bool) -> tuple:
    kind = problem.objective
    if collided:
        return (0, 0)
    if kind is ObjectiveKind.RECURRENCE:
        goal = problem.robot.goals[state.mode]
        return (1, -_distance(nxt.robot, goal))
    if kind.bounded:
        return (1, -_distance(nxt.robot, problem.robot.goal))
    end, _ = robot_move(problem, state.robot, k)
    return (1, min(_distance(end, o) for o in nxt.obstacles) if nxt.obstacles else 0)


def check_product_play(problem: GridProblem, turns, loop: int | None, steps: int | None) -> bool:
    """Replay ``turns`` with the spec's semantics: True iff the play is a loss for the
    robot as its last turn says (a collision; not on the goal in time; a repeated
    state whose loop avoids the awaited goal and, under ``fair``, moves every obstacle)."""
    state = initial_state(problem)
    states = [state]
    for turn in turns:
        if turn.state != state:
            return False
        state, collided = step(problem, state, turn.robot_move, turn.obstacle_moves)
        states.append(state)
        if collided:
            return turn is turns[-1]
    kind = problem.objective
    if kind.bounded:
        return (
            len(turns) == steps
            and state.robot != problem.robot.goal
            and (kind is ObjectiveKind.EXACT or all(s.robot != problem.robot.goal for s in states))
        )
    if loop is None or states[loop] != state:
        return False
    if kind is ObjectiveKind.SAFETY:
        return False  # a safety play is lost only by a collision
    cyc = states[loop:]
    if any(b.robot == problem.robot.goals[a.mode] for a, b in zip(cyc, cyc[1:])):
        return False
    if problem.fair:
        return all(
            any(a.obstacles[i] != b.obstacles[i] for a, b in zip(cyc, cyc[1:])) for i in range(len(problem.obstacles))
        )
    return True
