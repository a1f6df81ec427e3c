"""GIF animations of plays: the obstacles' witness strategy (``explain``) or a
controller's run against obstacles.

Frames show the grid, walls (dark), the goal (green), the robot (blue disc, with its
path so far), obstacles (numbered red squares, the cells they may move to shaded) and
a title with the step and the moves taken.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from PIL import Image, ImageDraw

from plansynth.grid.problem import GridProblem
from plansynth.grid.semantics import State, obstacle_move

CELL = 36
MARGIN = 8
TITLE = 34


def draw_frame(problem: GridProblem, state: State, path: Sequence[tuple[int, int]], title: str) -> Image.Image:
    w, h = problem.width, problem.height
    img = Image.new("RGB", (2 * MARGIN + w * CELL, TITLE + 2 * MARGIN + h * CELL), "white")
    d = ImageDraw.Draw(img)

    def box(c: tuple[int, int], inset: int = 0):
        x0 = MARGIN + c[0] * CELL + inset
        y0 = TITLE + MARGIN + (h - 1 - c[1]) * CELL + inset
        return (x0, y0, x0 + CELL - 2 * inset, y0 + CELL - 2 * inset)

    for x in range(w):
        for y in range(h):
            d.rectangle(box((x, y)), outline=(200, 200, 200))
    for c in problem.walls:
        d.rectangle(box(c), fill=(60, 60, 60))
    d.rectangle(box(problem.robot.goal, 2), fill=(150, 230, 150))
    for i, p in enumerate(state.obstacles):
        for k in range(len(problem.obstacles[i].moves)):
            end, _ = obstacle_move(problem, i, p, k)
            if end != p:
                d.rectangle(box(end, 6), fill=(255, 220, 220))
    for a, b in zip(path, path[1:]):
        ca, cb = box(a), box(b)
        d.line([((ca[0] + ca[2]) / 2, (ca[1] + ca[3]) / 2), ((cb[0] + cb[2]) / 2, (cb[1] + cb[3]) / 2)], fill=(90, 120, 230), width=3)
    for i, p in enumerate(state.obstacles):
        d.rectangle(box(p, 5), fill=(220, 60, 60))
        bx = box(p, 5)
        d.text((bx[0] + 8, bx[1] + 6), str(i), fill="white")
    d.ellipse(box(state.robot, 7), fill=(40, 80, 220))
    d.text((MARGIN, 6), title, fill="black")
    return img


def animate_states(problem: GridProblem, states: Sequence[State], titles: Sequence[str], path_gif: str | Path, fps: int = 2) -> None:
    frames = []
    for t, (s, title) in enumerate(zip(states, titles)):
        frames.append(draw_frame(problem, s, [x.robot for x in states[: t + 1]], title))
    frames += [frames[-1]] * 2  # linger on the end
    frames[0].save(path_gif, save_all=True, append_images=frames[1:], duration=int(1000 / fps), loop=0)


def animate_play(problem: GridProblem, explanation, path_gif: str | Path, fps: int = 2) -> None:
    """Animate :class:`~plansynth.grid.native.explain.Explanation.play`."""
    names = [m.name for m in problem.robot.moves]
    states = [turn.state for turn in explanation.play] + [explanation.final]
    titles = []
    for turn in explanation.play:
        omv = ", ".join(problem.obstacles[i].moves[j].name for i, j in enumerate(turn.obstacle_moves))
        titles.append(f"t={turn.t}: robot {names[turn.robot_move]}; obstacles {omv}")
    titles.append(explanation.play[-1].reason[:60])
    animate_states(problem, states, titles, path_gif, fps)


def animate_program(problem: GridProblem, program, steps: int, path_gif: str | Path, seed: int = 0, fps: int = 2) -> None:
    """Run ``program`` against obstacles that stay as close to the robot as they can
    (random ties, seeded) and animate it."""
    import random

    from plansynth.grid.programs import compile_program
    from plansynth.grid.semantics import initial_state, step

    rng = random.Random(seed)
    f = compile_program(program, problem.variables)
    names = [m.name for m in problem.robot.moves]
    state = initial_state(problem)
    states, titles = [state], []
    for t in range(steps):
        k = f(*state.inputs())
        joint = []
        for i, p in enumerate(state.obstacles):
            options = list(range(len(problem.obstacles[i].moves)))
            rng.shuffle(options)
            best = min(options, key=lambda j: _dist(obstacle_move(problem, i, p, j)[0], state.robot))
            joint.append(best)
        out = step(problem, state, k, tuple(joint))
        titles.append(f"t={t}: robot {names[k]}")
        state = out.state
        states.append(state)
        if out.collided:
            titles.append("collision")
            break
    else:
        titles.append("on the goal" if state.robot == problem.robot.goal else "not on the goal")
    animate_states(problem, states, titles, path_gif, fps)


def _dist(a, b) -> int:
    return abs(a[0] - b[0]) + abs(a[1] - b[1])
