"""Pictures of teams: the workspace and static obstacles as :mod:`plansynth.reach.plot`
draws them, one colour per robot (its start, its goal hatched in its colour, its
trajectory, its footprint at the start and the end), and the moving obstacles (their
path dotted, their shape where they are at time 0). :func:`animate_team` writes a GIF
with the robots' footprints and every moving obstacle where it is at each frame.

>>> import tempfile, os
>>> from plansynth.reach.team.families import smc_crossing
>>> with tempfile.TemporaryDirectory() as d:
...     fig = plot_team(smc_crossing(), path=os.path.join(d, "t.png"))
...     os.path.getsize(os.path.join(d, "t.png")) > 10_000
True
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.animation import FuncAnimation, PillowWriter
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Rectangle

from plansynth.io import atomic_output
from plansynth.reach.geometry import Box, Shape
from plansynth.reach.plot import OBSTACLE, _new_figure, _shape_patch
from plansynth.reach.team.problem import GoalPoint, TeamProblem, TeamRobot
from plansynth.reach.trajectory import Trajectory, check_dimensions

__all__ = ["plot_team", "animate_team", "robot_colour"]

#: one colour per robot (matplotlib's tab20 order, the dark ones first), cycled
COLOURS = (
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
    "#bcbd22", "#7f7f7f", "#393b79", "#637939", "#843c39", "#7b4173", "#3182bd", "#e6550d",
)  # fmt: skip
MOVING = "#6d597a"


def robot_colour(r: int) -> str:
    """The colour of robot r."""
    return COLOURS[r % len(COLOURS)]


def _footprint(robot: TeamRobot, p: np.ndarray, colour: str, **kw) -> Circle | Rectangle:
    rs = robot.robot_shape
    if rs is not None and not rs.is_point and rs.radius is not None:
        return Circle((p[0], p[1]), rs.radius, facecolor=colour, edgecolor="black", **kw)
    h = (0.0, 0.0) if rs is None or rs.is_point else rs.margins(2)
    if h[0] == 0.0 and h[1] == 0.0:  # a point robot: a dot of the workspace's scale
        return Circle((p[0], p[1]), 0.0, facecolor=colour, edgecolor="black", **kw)
    return Rectangle((p[0] - h[0], p[1] - h[1]), 2 * h[0], 2 * h[1], facecolor=colour, edgecolor="black", **kw)


def _placed(shape: Shape, c: np.ndarray) -> Shape:
    """A moving obstacle's shape with its reference point at c."""
    from plansynth.reach.geometry import Polygon

    if isinstance(shape, Box):
        return Box(tuple(l + v for l, v in zip(shape.lo, c)), tuple(h + v for h, v in zip(shape.hi, c)))
    return Polygon(tuple((x + c[0], y + c[1]) for x, y in shape.vertices))


def _check(problem: TeamProblem, trajectories: Sequence[Trajectory]) -> None:
    from plansynth.errors import InvalidProblem

    if len(trajectories) != problem.n_robots:
        raise InvalidProblem(None, "robots", f"{len(trajectories)} trajectories for {problem.n_robots} robots")
    for r, t in zip(problem.robots, trajectories):
        check_dimensions(t, r.dynamics.n_states, r.dynamics.n_inputs)


def plot_team(
    problem: TeamProblem,
    trajectories: Sequence[Trajectory] | None = None,
    path: str | Path | None = None,
    ax: Axes | None = None,
    *,
    title: str | None = None,
    moving_at_start: bool = True,
) -> Figure:
    """Draw the team problem and, when given, each robot's trajectory (see the module
    docstring); a PNG at ``path`` when given. 3-D problems are drawn projected.
    ``moving_at_start``: draw each moving obstacle where it is at time 0."""
    if trajectories is not None:
        _check(problem, trajectories)
    fig, ax = _new_figure(problem) if ax is None else (ax.figure, ax)  # type: ignore[assignment]
    _static(problem, ax)
    for k, o in enumerate(problem.moving_obstacles):
        P = np.asarray(o.positions, float)
        ax.plot(
            P[:, 0],
            P[:, 1],
            linestyle=":",
            color=MOVING,
            linewidth=1.2,
            zorder=3,
            label="moving obstacle path" if k == 0 else None,
        )
        if moving_at_start:
            placed = _placed(o.shape, o.position(0.0))
            ax.add_patch(_shape_patch(placed, facecolor=MOVING, edgecolor="black", alpha=0.5, zorder=4))
    for r, robot in enumerate(problem.robots):
        colour = robot_colour(r)
        P = None if trajectories is None else problem.robot_problems[r].position_of(trajectories[r].states)
        if P is not None:
            ax.plot(P[:, 0], P[:, 1], color=colour, linewidth=1.4, zorder=7, label=robot.name)
            ax.plot(P[:, 0], P[:, 1], "o", color=colour, markersize=2.2, zorder=8)
            ax.add_patch(_footprint(robot, P[-1], colour, alpha=0.35, linewidth=0.6, zorder=8))
        s = robot.start_position
        ax.add_patch(_footprint(robot, s, colour, alpha=0.7, linewidth=0.6, zorder=9))
        ax.plot(
            [s[0]],
            [s[1]],
            marker="o",
            color=colour,
            markeredgecolor="black",
            markersize=6,
            zorder=9.5,
            linestyle="none",
            label=None if P is not None else robot.name,
        )
    ws = problem.workspace
    margin = 0.02 * max(ws.hi[0] - ws.lo[0], ws.hi[1] - ws.lo[1])
    ax.set_xlim(ws.lo[0] - margin, ws.hi[0] + margin)
    ax.set_ylim(ws.lo[1] - margin, ws.hi[1] + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if title is None:
        title = f"{problem.name}: {problem.n_robots} robots, separation {problem.separation.distance:g}"
        if trajectories is not None:
            title += f", horizon {trajectories[0].horizon}"
        if problem.dim == 3:
            title += "\n(3-D problem: projection onto the x-y plane)"
    ax.set_title(title, fontsize=10)
    handles, _ = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    fig.tight_layout()
    if path is not None:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, format="png")
    return fig


def _static(problem: TeamProblem, ax: Axes) -> None:
    ws = problem.workspace
    ax.add_patch(
        Rectangle(
            (ws.lo[0], ws.lo[1]),
            ws.hi[0] - ws.lo[0],
            ws.hi[1] - ws.lo[1],
            facecolor="white",
            edgecolor="black",
            linewidth=1.5,
            zorder=0,
        )
    )
    for ob in problem.obstacles:
        ax.add_patch(_shape_patch(ob, facecolor=OBSTACLE, edgecolor="black", linewidth=0.6, zorder=4))
    for r, robot in enumerate(problem.robots):
        colour = robot_colour(r)
        g = robot.goal
        if isinstance(g, GoalPoint):
            ax.plot(
                [g.point[0]], [g.point[1]], marker="x", color=colour, markersize=9, mew=2, zorder=6, linestyle="none"
            )
        elif g is not None:
            ax.add_patch(_shape_patch(g, facecolor=colour, edgecolor=colour, alpha=0.25, hatch="//", zorder=5))
    for name, shape in problem.labels:
        ax.add_patch(_shape_patch(shape, facecolor="none", edgecolor="#e07a1f", linewidth=1.2, zorder=5))
        lv = np.array(shape.vertices) if not isinstance(shape, Box) else np.array([shape.lo, shape.hi])
        ax.annotate(
            name,
            (lv[:, 0].min(), lv[:, 1].max()),
            xytext=(2, -2),
            textcoords="offset points",
            fontsize=8,
            color="#e07a1f",
            ha="left",
            va="top",
            zorder=9.5,
        )


def animate_team(
    problem: TeamProblem,
    trajectories: Sequence[Trajectory],
    path_gif: str | Path,
    fps: int = 10,
    *,
    max_frames: int = 300,
    dpi: int = 80,
) -> Path:
    """An animated GIF: at each frame every robot's footprint and trail, and every
    moving obstacle where it is at that time."""
    _check(problem, trajectories)
    fig, ax = _new_figure(problem)
    plot_team(problem, None, ax=ax, moving_at_start=False)
    pos = [problem.robot_problems[r].position_of(t.states) for r, t in enumerate(trajectories)]
    N = len(pos[0]) - 1
    frames = np.unique(np.linspace(0, N, min(N + 1, max_frames)).round().astype(int))
    trails = [ax.plot([], [], color=robot_colour(r), linewidth=1.3, zorder=7)[0] for r in range(problem.n_robots)]
    bodies = []
    for r, robot in enumerate(problem.robots):
        body = _footprint(robot, pos[r][0], robot_colour(r), alpha=0.85, linewidth=0.8, zorder=10)
        ax.add_patch(body)
        dot = ax.plot([], [], "o", color=robot_colour(r), markeredgecolor="black", markersize=6, zorder=11)[0]
        bodies.append((body, dot))
    movers = []
    for o in problem.moving_obstacles:
        patch = _shape_patch(
            _placed(o.shape, o.position(0.0)), facecolor=MOVING, edgecolor="black", alpha=0.8, zorder=9
        )
        ax.add_patch(patch)
        movers.append(patch)
    label = ax.text(
        0.02,
        0.97,
        "",
        transform=ax.transAxes,
        fontsize=8,
        va="top",
        zorder=12,
        bbox={"facecolor": "white", "alpha": 0.8, "edgecolor": "none"},
    )
    dt = problem.dt

    def update(k: int):
        for r, robot in enumerate(problem.robots):
            P = pos[r]
            trails[r].set_data(P[: k + 1, 0], P[: k + 1, 1])
            body, dot = bodies[r]
            _move(body, robot, P[k])
            dot.set_data([P[k, 0]], [P[k, 1]])
        for o, patch in zip(problem.moving_obstacles, movers):
            placed = _placed(o.shape, o.position(problem.time_of(k)))
            if isinstance(placed, Box):
                patch.set_xy((placed.lo[0], placed.lo[1]))
            else:
                patch.set_xy(np.array(placed.vertices))
        label.set_text(f"t = {k}" + (f" ({k * dt:.1f} s)" if dt else ""))
        return [*trails, *movers, label]

    anim = FuncAnimation(fig, update, frames=frames, blit=False)
    out = Path(path_gif)
    with atomic_output(out) as tmp:
        anim.save(str(tmp), writer=PillowWriter(fps=fps), dpi=dpi)
    return out


def _move(body: Circle | Rectangle, robot: TeamRobot, p: np.ndarray) -> None:
    if isinstance(body, Circle):
        body.set_center((p[0], p[1]))
    else:
        body.set_xy((p[0] - body.get_width() / 2, p[1] - body.get_height() / 2))
