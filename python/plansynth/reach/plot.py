"""Pictures of reach-avoid problems, abstractions and trajectories (cf. Figure 3 of
Shoukry et al., CDC 2016): the workspace, the obstacles (dark), the convex regions (thin
outlines, numbered when few), the region sequence found by the planner (shaded, with a
dashed line through the region centres), the trajectory (a line with a dot at every
sample), the start and the goal.

Drawing uses matplotlib's object API with the Agg canvas (no pyplot, no display), so it
is safe in servers and tests. 3-D problems are drawn as their projection onto the first
two axes, and the title says so.

>>> import tempfile, os
>>> from plansynth.reach.families import maze
>>> with tempfile.TemporaryDirectory() as d:
...     fig = plot_problem(maze(1), path=os.path.join(d, "m.png"))
...     os.path.getsize(os.path.join(d, "m.png")) > 10_000
True
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.animation import FuncAnimation, PillowWriter
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Rectangle
from matplotlib.patches import Polygon as MplPolygon

from plansynth.io import atomic_output
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import Box, Shape
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory, check_dimensions

__all__ = ["plot_problem", "animate"]

OBSTACLE = "#3b3b3b"
REGION_EDGE = "#5b8fd6"
SEQUENCE = "#ffd166"
TRAJ = "#d62828"
GOAL = "#2a9d8f"
START = "#1d3557"
MAX_LABELS = 60


def _shape_patch(shape: Shape, **kw) -> MplPolygon | Rectangle:
    if isinstance(shape, Box):
        return Rectangle((shape.lo[0], shape.lo[1]), shape.hi[0] - shape.lo[0], shape.hi[1] - shape.lo[1], **kw)
    return MplPolygon(np.array(shape.vertices), closed=True, **kw)


def _region_outline(vertices: np.ndarray) -> np.ndarray:
    """2-D outline of a region: its polygon, or the projected box of a 3-D region."""
    if vertices.shape[1] == 2:
        return vertices
    lo, hi = vertices[:, :2].min(axis=0), vertices[:, :2].max(axis=0)
    return np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])


LABEL_COLOURS = ("#e07a1f", "#7b2cbf", "#2a9d8f", "#d62828", "#3a86ff", "#8d6e63")


def _new_figure(problem: ReachProblem) -> tuple[Figure, Axes]:
    ws = problem.workspace
    w, h = ws.hi[0] - ws.lo[0], ws.hi[1] - ws.lo[1]
    side = 7.0
    fig = Figure(
        figsize=(side, max(3.0, side * h / w) + 0.8) if w >= h else (max(3.0, side * w / h), side + 0.8), dpi=100
    )
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    return fig, ax


def plot_problem(
    problem: ReachProblem,
    abstraction: Abstraction | None = None,
    result_regions: Sequence[int] | None = None,
    trajectory: Trajectory | None = None,
    path: str | Path | None = None,
    ax: Axes | None = None,
    *,
    title: str | None = None,
    labels: bool | None = None,
) -> Figure:
    """Draw ``problem`` (with optional abstraction, region sequence and trajectory).

    Writes a PNG to ``path`` when given; draws into ``ax`` when given (else a new
    figure). ``labels`` forces region numbers on/off (default: on when at most 60
    regions). Returns the figure. A trajectory whose states or inputs do not have the
    problem's dimensions raises :class:`~plansynth.errors.InvalidProblem` before
    anything is drawn.
    """
    if trajectory is not None:
        check_dimensions(trajectory, problem.dynamics.n_states, problem.dynamics.n_inputs)
    if ax is None:
        fig, ax = _new_figure(problem)
    else:
        fig = ax.figure  # type: ignore[assignment]
    ws = problem.workspace
    projected = problem.dim == 3

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

    if abstraction is not None and result_regions:
        for i in dict.fromkeys(result_regions):
            v = _region_outline(abstraction.regions[i].vertices)
            ax.add_patch(MplPolygon(v, closed=True, facecolor=SEQUENCE, edgecolor="none", alpha=0.55, zorder=1))
        centres = np.array([abstraction.regions[i].center[:2] for i in result_regions])
        ax.plot(
            centres[:, 0],
            centres[:, 1],
            linestyle="--",
            color="#b5838d",
            linewidth=1.2,
            zorder=2,
            label="region sequence",
        )

    if abstraction is not None:
        show_labels = labels if labels is not None else abstraction.n_regions <= MAX_LABELS
        for r in abstraction.regions:
            v = _region_outline(r.vertices)
            ax.add_patch(
                MplPolygon(v, closed=True, facecolor="none", edgecolor=REGION_EDGE, linewidth=0.6, alpha=0.9, zorder=2)
            )
            if show_labels:
                c = r.center
                ax.text(
                    c[0],
                    c[1],
                    str(r.index),
                    fontsize=7,
                    color="#1f4e99",
                    ha="center",
                    va="center",
                    zorder=8.5,
                    bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "alpha": 0.7, "edgecolor": "none"},
                )

    for ob in problem.obstacles:
        ax.add_patch(
            _shape_patch(
                ob, facecolor=OBSTACLE, edgecolor="black", linewidth=0.6, alpha=0.55 if projected else 1.0, zorder=4
            )
        )
    if problem.goal is not None:
        ax.add_patch(_shape_patch(problem.goal, facecolor=GOAL, edgecolor=GOAL, alpha=0.45, hatch="//", zorder=5))
        g = (
            np.array(problem.goal.vertices)
            if not isinstance(problem.goal, Box)
            else np.array([problem.goal.lo, problem.goal.hi])
        )
        gc = g.mean(axis=0)
        ax.annotate("goal", (gc[0], gc[1]), fontsize=8, color="black", ha="center", va="center", zorder=6)
    # mission labels: outlined in colour, named at their centre
    for k, (name, shape) in enumerate(problem.labels):
        colour = LABEL_COLOURS[k % len(LABEL_COLOURS)]
        ax.add_patch(_shape_patch(shape, facecolor=colour, edgecolor=colour, alpha=0.25, linewidth=1.4, zorder=5))
        lv = np.array(shape.vertices) if not isinstance(shape, Box) else np.array([shape.lo, shape.hi])
        # the name in the label's top left corner (the centre is where plans and region numbers go)
        ax.annotate(
            name,
            (lv[:, 0].min(), lv[:, 1].max()),
            xytext=(2, -2),
            textcoords="offset points",
            fontsize=8,
            color=colour,
            ha="left",
            va="top",
            zorder=9.5,
            fontweight="bold",
        )
    if problem.mission is not None and title is None:
        title = f"{problem.name}: {problem.mission}"

    robot = problem.robot_shape
    if robot is not None and not robot.is_point:
        # a sized robot: the grown obstacles its reference point avoids (dashed), and its
        # footprint along the trajectory (plansynth.reach.robot)
        from plansynth.reach.robot import configuration_space

        for ob in configuration_space(problem).obstacles:
            ax.add_patch(_shape_patch(ob, facecolor="none", edgecolor="black", linestyle="--", linewidth=0.6, zorder=4))
        if trajectory is not None:
            P = trajectory.positions(problem.dynamics.position)
            every = max(1, len(P) // 40)
            for q in P[::every]:
                if robot.radius is not None:
                    patch = Circle(
                        (q[0], q[1]), robot.radius, facecolor=TRAJ, alpha=0.12, edgecolor=TRAJ, linewidth=0.4
                    )
                else:
                    hx, hy = robot.half_extent[:2]  # type: ignore[index]
                    patch = Rectangle(
                        (q[0] - hx, q[1] - hy),
                        2 * hx,
                        2 * hy,
                        facecolor=TRAJ,
                        alpha=0.12,
                        edgecolor=TRAJ,
                        linewidth=0.4,
                    )
                patch.set_zorder(6.5)
                ax.add_patch(patch)

    if trajectory is not None:
        P = trajectory.positions(problem.dynamics.position)
        ax.plot(P[:, 0], P[:, 1], color=TRAJ, linewidth=1.3, zorder=7, label=f"trajectory (N = {trajectory.horizon})")
        ax.plot(P[:, 0], P[:, 1], "o", color=TRAJ, markersize=2.5, zorder=8)

    s = problem.start_position
    ax.plot([s[0]], [s[1]], marker="o", color=START, markersize=7, zorder=9, label="start", linestyle="none")

    margin = 0.02 * max(ws.hi[0] - ws.lo[0], ws.hi[1] - ws.lo[1])
    ax.set_xlim(ws.lo[0] - margin, ws.hi[0] + margin)
    ax.set_ylim(ws.lo[1] - margin, ws.hi[1] + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if title is None:
        title = problem.name
        if abstraction is not None:
            title += f": {abstraction.n_regions} convex regions ({abstraction.method})"
        if projected:
            title += "\n(3-D problem: projection onto the x-y plane)"
    ax.set_title(title, fontsize=10)
    handles, _ = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09), ncol=len(handles), fontsize=8, frameon=False)
    fig.tight_layout()
    if path is not None:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, format="png")
    return fig


def animate(
    problem: ReachProblem,
    abstraction: Abstraction | None,
    trajectory: Trajectory,
    result_regions: Sequence[int] | None,
    path_gif: str | Path,
    fps: int = 10,
    *,
    max_frames: int = 300,
    dpi: int = 80,
) -> Path:
    """Write an animated GIF of the robot following ``trajectory`` over the static picture.

    One frame per sample (subsampled to at most ``max_frames``); the region the robot
    is in is not re-computed, the planner's sequence is shown as in :func:`plot_problem`.
    """
    check_dimensions(trajectory, problem.dynamics.n_states, problem.dynamics.n_inputs)
    fig = plot_problem(problem, abstraction, result_regions, None)
    ax = fig.axes[0]
    P = trajectory.positions(problem.dynamics.position)
    frames = np.unique(np.linspace(0, len(P) - 1, min(len(P), max_frames)).round().astype(int))
    (trail,) = ax.plot([], [], color=TRAJ, linewidth=1.3, zorder=7)
    (dots,) = ax.plot([], [], "o", color=TRAJ, markersize=2.5, zorder=8)
    (robot,) = ax.plot([], [], "o", color=TRAJ, markersize=9, markeredgecolor="black", zorder=11)
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
    dt = problem.dynamics.dt

    def update(k: int):
        trail.set_data(P[: k + 1, 0], P[: k + 1, 1])
        dots.set_data(P[: k + 1, 0], P[: k + 1, 1])
        robot.set_data([P[k, 0]], [P[k, 1]])
        label.set_text(f"t = {k}" + (f" ({k * dt:.1f} s)" if dt else ""))
        return trail, dots, robot, label

    anim = FuncAnimation(fig, update, frames=frames, blit=False)
    out = Path(path_gif)
    with atomic_output(out) as tmp:
        anim.save(str(tmp), writer=PillowWriter(fps=fps), dpi=dpi)
    return out
