"""Pictures of grid runs: one step as a PNG, a whole run as a GIF (matplotlib, Agg).

Each picture shows the grid lines, walls (dark), the goal (green), the robot (blue) with
its path so far, the obstacles (red, numbered) with the cells their possible moves
could sweep next drawn faintly, and a title with the step counter and the moves taken.
The last frame of a run marks a collision with a cross and states the outcome.

No pyplot: figures are built on :class:`matplotlib.figure.Figure` with the Agg canvas,
so rendering works headless and leaves no global state behind.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

from matplotlib.animation import FuncAnimation, PillowWriter
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PatchCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle, FancyArrowPatch, Rectangle

from plansynth.grid.problem import Cell, GridProblem
from plansynth.grid.semantics import obstacle_move, robot_move
from plansynth.grid.simulate import Run
from plansynth.io import atomic_output

WALL = "#3a3a3a"
GOAL = "#7bc67b"
ROBOT = "#1f5fbf"
OBSTACLE = "#c8312b"
GRID = "#c8c8c8"

#: Extra copies of the last frame in a GIF, so the outcome stays on screen.
HOLD_FRAMES = 3


def _cell_inches(problem: GridProblem) -> float:
    return min(0.6, 7.5 / max(problem.width, problem.height))


def new_figure(problem: GridProblem) -> Figure:
    """An empty Agg figure sized for ``problem``'s grid (about 8 inches at most)."""
    cs = _cell_inches(problem)
    width = max(5.5, problem.width * cs + 1.2)
    height = problem.height * cs + 1.6
    fig = Figure(figsize=(width, height), dpi=100)
    FigureCanvasAgg(fig)
    # Room for a three-line title above the grid.
    top = 1 - 1.0 / height
    fig.add_axes((0.08, 0.4 / height, 0.84, top - 0.45 / height))
    return fig


def _center(c: Cell) -> tuple[float, float]:
    return c[0] + 0.5, c[1] + 0.5


def _move_names(problem: GridProblem, run: Run, t: int) -> str:
    k = run.robot_moves[t]
    text = f"robot {problem.robot.moves[k].name}"
    if problem.obstacles:
        shown = [f"o{i} {problem.obstacles[i].moves[j].name}" for i, j in enumerate(run.obstacle_moves[t][:6])]
        if len(problem.obstacles) > 6:
            shown.append(f"... ({len(problem.obstacles)} obstacles)")
        text += " | " + ", ".join(shown)
    return text


def draw_on(ax: Axes, problem: GridProblem, run: Run, t: int) -> None:
    """Draw the state at the start of step ``t`` of ``run`` (``t = len(run.states) - 1``
    is the state after the last step taken) on ``ax``, replacing what was there."""
    last = len(run.states) - 1
    if not 0 <= t <= last:
        raise ValueError(f"step {t} is not in 0..{last}")
    ax.clear()
    w, h = problem.width, problem.height
    cs = _cell_inches(problem)
    font = max(4.0, min(11.0, cs * 72 * 0.45))
    ax.set_xlim(0, w)
    ax.set_ylim(0, h)
    ax.set_aspect("equal")
    ax.tick_params(length=0, labelsize=max(5.0, font * 0.8))
    every = 1 if max(w, h) <= 20 else (5 if max(w, h) <= 80 else 10)
    ax.set_xticks([x + 0.5 for x in range(0, w, every)], [str(x) for x in range(0, w, every)])
    ax.set_yticks([y + 0.5 for y in range(0, h, every)], [str(y) for y in range(0, h, every)])
    for side in ax.spines.values():
        side.set_color(GRID)

    lines = [[(x, 0), (x, h)] for x in range(w + 1)] + [[(0, y), (w, y)] for y in range(h + 1)]
    ax.add_collection(LineCollection(lines, colors=GRID, linewidths=0.6, zorder=1))
    if problem.walls:
        walls = [Rectangle(c, 1, 1) for c in sorted(problem.walls)]
        ax.add_collection(PatchCollection(walls, facecolor=WALL, edgecolor=WALL, zorder=2))
    gx, gy = problem.robot.goal
    ax.add_patch(Rectangle((gx, gy), 1, 1, facecolor=GOAL, edgecolor="#2e7d32", linewidth=1.5, zorder=2))
    ax.text(gx + 0.5, gy + 0.5, "goal", ha="center", va="center", fontsize=font * 0.7, color="#1b5e20", zorder=3)

    state = run.states[t]
    # The obstacles' possible next moves, faintly: swept cells and arrows to the ends.
    if t < last or run.collision is None:
        faint = []
        for i, (o, p) in enumerate(zip(problem.obstacles, state.obstacles)):
            for j in range(len(o.moves)):
                end, swept = obstacle_move(problem, i, p, j)
                faint.extend(Rectangle(c, 1, 1) for c in swept if c != p)
                if end != p:
                    ax.add_patch(
                        FancyArrowPatch(
                            _center(p),
                            _center(end),
                            arrowstyle="->",
                            mutation_scale=font,
                            color=OBSTACLE,
                            alpha=0.35,
                            linewidth=0.8,
                            zorder=3,
                        )
                    )
        if faint:
            ax.add_collection(PatchCollection(faint, facecolor=OBSTACLE, edgecolor="none", alpha=0.10, zorder=2))

    path = [_center(s.robot) for s in run.states[: t + 1]]
    if len(path) > 1:
        ax.plot(*zip(*path), color=ROBOT, linewidth=1.6, alpha=0.6, marker="o", markersize=font * 0.3, zorder=4)
    for i, p in enumerate(state.obstacles):
        ax.add_patch(Rectangle((p[0] + 0.12, p[1] + 0.12), 0.76, 0.76, facecolor=OBSTACLE, edgecolor="none", zorder=5))
        ax.text(
            p[0] + 0.5,
            p[1] + 0.5,
            str(i),
            ha="center",
            va="center",
            color="white",
            fontsize=font * 0.8,
            fontweight="bold",
            zorder=6,
        )
    ax.add_patch(Circle(_center(state.robot), 0.36, facecolor=ROBOT, edgecolor="white", linewidth=1.0, zorder=7))

    verdict = "controller wins" if run.wins else "controller loses"
    header = f"{problem.name}: l = {run.steps}, {verdict} ({run.mode} obstacles)"
    if t < len(run.robot_moves):
        detail = f"step {t} of {run.steps}: {_move_names(problem, run, t)}"
    else:
        detail = f"after step {t - 1}: {run.outcome}" if t > 0 else run.outcome
    if t == last and run.collision is not None:
        # The cells swept in the losing step: the robot's and the colliding obstacle's.
        prev, k = run.states[t - 1], run.robot_moves[t - 1]
        swept = [robot_move(problem, prev.robot, k)[1]]
        if run.collision.obstacle is not None:
            i = run.collision.obstacle
            swept.append(obstacle_move(problem, i, prev.obstacles[i], run.obstacle_moves[t - 1][i])[1])
        for cells, color in zip(swept, (ROBOT, OBSTACLE)):
            ax.add_collection(
                PatchCollection(
                    [Rectangle(c, 1, 1) for c in cells],
                    facecolor="none",
                    edgecolor=color,
                    hatch="///",
                    linewidth=1.2,
                    alpha=0.7,
                    zorder=4,
                )
            )
        cx, cy = _center(run.collision.cell)
        ax.plot([cx - 0.45, cx + 0.45], [cy - 0.45, cy + 0.45], color="black", linewidth=2.5, zorder=8)
        ax.plot([cx - 0.45, cx + 0.45], [cy + 0.45, cy - 0.45], color="black", linewidth=2.5, zorder=8)
    chars = int(ax.figure.get_figwidth() * 13)
    ax.set_title("\n".join([header, *textwrap.wrap(detail, chars)][:3]), fontsize=9, loc="left")


def draw_state(problem: GridProblem, run: Run, t: int, path: str | Path | None = None) -> Figure:
    """A picture of step ``t`` of ``run``; also written as a PNG when ``path`` is given."""
    fig = new_figure(problem)
    draw_on(fig.axes[0], problem, run, t)
    if path is not None:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, format="png")
    return fig


def animate(problem: GridProblem, run: Run, path_gif: str | Path, fps: float = 3) -> Path:
    """Write ``run`` as a GIF: one frame per state, the last one held a little longer."""
    if fps <= 0:
        raise ValueError(f"fps must be positive, got {fps}")
    fig = new_figure(problem)
    ax = fig.axes[0]
    last = len(run.states) - 1
    frames = list(range(last + 1)) + [last] * HOLD_FRAMES
    anim = FuncAnimation(fig, lambda t: draw_on(ax, problem, run, t), frames=frames, blit=False, repeat=False)
    out = Path(path_gif)
    with atomic_output(out) as tmp:
        anim.save(str(tmp), writer=PillowWriter(fps=fps))
    return out
