"""A loss found by the search turned into a concrete run of every obstacle, replayed
through the semantics to the loss it describes."""

from __future__ import annotations

from plansynth.grid.programs import compile_program
from plansynth.grid.semantics import step
from plansynth.grid.verify.replay import replay
from plansynth.grid.verify.search import Loss, Search
from plansynth.grid.verify.tables import Sets
from plansynth.grid.verify.verdict import Counterexample

__all__ = ["counterexample"]


def counterexample(search: Search, loss: Loss) -> Counterexample:
    """Turn a loss into a concrete run of all obstacles, and replay it with step()."""
    p = search.problem
    steps_taken = loss.t if loss.kind == "doomed" else loss.t + 1
    joint: list[list[int]] = [[0] * len(p.obstacles) for _ in range(steps_taken)]
    robot_moves = [0] * steps_taken
    # Cells of the read obstacles at time loss.t (and their moves then, if a step is taken).
    cells = [min(s) for s in loss.part]
    if loss.kind != "doomed":
        robot_moves[loss.t] = loss.move
        r_swept = search.robot[loss.node.r][loss.move][1]
        if loss.kind == "read":
            j = loss.obstacle
            table = search.obstacle[search.read[j]]
            cells[j], joint[loss.t][search.read[j]] = next(
                (c, k) for c in sorted(loss.part[j]) for k, (_, m) in enumerate(table[c]) if not m.isdisjoint(r_swept)
            )
    # Walk back through the parents: a parent part whose image holds the cells, and
    # for each obstacle a cell there with a move into its current cell.
    node, t = loss.node, loss.t
    while t > 0:
        for parent, part, k in node.parents:  # noqa: B007 - the parent found and its move are read after the loop
            back = _preimage(search, part, cells)
            if back is not None:
                break
        else:  # pragma: no cover - the parents' images make up the node's sets
            raise AssertionError("verifier bug: no parent leads to the losing state")
        t -= 1
        robot_moves[t] = k
        cells = []
        for j, (c, m) in enumerate(back):
            cells.append(c)
            joint[t][search.read[j]] = m
        node = parent
    if loss.kind == "unread":
        # Steer one unread obstacle into the robot's swept cells at the last step.
        for i in search.unread:
            hit = search.unread_reach.hit(i, loss.t, r_swept)
            if hit is not None:
                for s, k in enumerate(hit):
                    joint[s][i] = k
                break
        else:  # pragma: no cover - the danger mask promised a hit
            raise AssertionError("verifier bug: no unread obstacle realises the danger mask")
    if loss.kind == "doomed":
        # Any continuation loses: run the program on, every obstacle taking move 0.
        state = replay(p, robot_moves, joint, search.steps)[0][-1]
        controller = compile_program(search.program, p.variables)
        for _ in range(loss.t, search.steps):
            k = controller(*state.inputs())
            zero = (0,) * len(p.obstacles)
            robot_moves.append(k)
            joint.append(list(zero))
            state, collided = step(p, state, k, zero)
            if collided:
                break
    moves = tuple(robot_moves)
    obstacle_moves = tuple(tuple(j) for j in joint)
    states, reason = replay(p, moves, obstacle_moves, search.steps)
    if reason is None:  # pragma: no cover - would mean the search and step() disagree
        raise AssertionError("verifier bug: the counterexample does not lose when replayed")
    return Counterexample(obstacle_moves, states, moves, reason)


def _preimage(search: Search, part: Sets, cells: list[int]) -> list[tuple[int, int]] | None:
    """Per read obstacle, a (cell in ``part``, move) ending in ``cells``; None if some
    obstacle cannot get there from ``part``."""
    out = []
    for j, target in enumerate(cells):
        table = search.obstacle[search.read[j]]
        found = next(((c, k) for c in sorted(part[j]) for k, (e, _) in enumerate(table[c]) if e == target), None)
        if found is None:
            return None
        out.append(found)
    return out
