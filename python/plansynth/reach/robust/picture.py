"""Pictures of robust plans: the plan with its tube (the positions every disturbance
sequence can reach, step by step), the obstacles grown by the tube's largest
cross-section (dashed), and disturbed runs of the closed loop; and a nominal plan beside
a robust one under the same disturbance sequences (:func:`plot_comparison`, the
README's picture).

>>> import tempfile, os
>>> from plansynth.reach.families import windy_maze
>>> from plansynth.reach.solve import solve
>>> p = windy_maze(1)
>>> r = solve(p)
>>> with tempfile.TemporaryDirectory() as d:
...     _ = plot_robust(p, r, path=os.path.join(d, "r.png"), runs=5)
...     os.path.getsize(os.path.join(d, "r.png")) > 10_000
True
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Polygon as MplPolygon

from plansynth.io import atomic_output
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robust.check import tube_polygons
from plansynth.reach.robust.simulate import closed_loop, sample_disturbances
from plansynth.reach.trajectory import Trajectory

__all__ = ["plot_robust", "plot_comparison", "robust_abstraction"]

TUBE = "#f4a261"
RUN = "#6c757d"
HIT = "#d62828"


def robust_abstraction(problem: ReachProblem) -> Any:
    """The regions a robust plan of ``problem`` was planned in (its tightened problem's;
    a mission's label-refined ones)."""
    from plansynth.reach.abstraction import abstract
    from plansynth.reach.robust.planning import planned

    tight = planned(problem)
    if tight.problem is None:
        return None
    if tight.problem.mission is not None:
        from plansynth.reach.mission.labels import label_abstraction

        return label_abstraction(tight.problem).abstraction
    return abstract(tight.problem)


def _overlay(
    ax: Axes, problem: ReachProblem, trajectory: Trajectory, K: np.ndarray, runs: int, seed: int
) -> tuple[int, int]:
    """The grown obstacles, the tube along ``trajectory`` and ``runs`` disturbed runs
    (vertex sequences: the hardest); returns (runs drawn, runs that hit something)."""
    from plansynth.reach.robust.planning import planned
    from plansynth.reach.validate import validate

    tight = planned(problem)
    if tight.problem is not None:
        for ob in tight.problem.obstacles:
            v = np.array(ob.vertices) if hasattr(ob, "vertices") else _box_vertices(ob)
            ax.add_patch(
                MplPolygon(v, closed=True, fill=False, edgecolor="black", linestyle="--", linewidth=0.6, zorder=4)
            )
    X = np.asarray(trajectory.states, float)
    P = X[:, list(problem.dynamics.position)]
    for t, E in enumerate(tube_polygons(problem, K, len(X) - 1)):
        if len(E) >= 3:
            ax.add_patch(MplPolygon(P[t] + E, closed=True, facecolor=TUBE, edgecolor="none", alpha=0.35, zorder=6.4))
    hits = 0
    if runs:
        W = sample_disturbances(problem, "vertex", runs, trajectory.horizon, np.random.default_rng(seed))
        XS, US = closed_loop(problem, trajectory, K, W)
        plain = replace(problem, disturbance=None)
        for Xr, Ur in zip(XS, US):
            ok = validate(plain, Trajectory(states=Xr, inputs=Ur), require_segment_safe=True, dynamics="curve").ok
            hits += not ok
            Pr = Xr[:, list(problem.dynamics.position)]
            ax.plot(Pr[:, 0], Pr[:, 1], color=RUN if ok else HIT, linewidth=0.5, alpha=0.6, zorder=6.6)
    return runs, hits


def _box_vertices(b: Any) -> np.ndarray:
    return np.array([[b.lo[0], b.lo[1]], [b.hi[0], b.lo[1]], [b.hi[0], b.hi[1]], [b.lo[0], b.hi[1]]])


def plot_robust(
    problem: ReachProblem,
    result: Any,
    path: str | Path | None = None,
    ax: Axes | None = None,
    *,
    runs: int = 20,
    seed: int = 0,
    title: str | None = None,
) -> Figure:
    """A robust result's plan on ``problem``: regions and sequence (of the tightened
    problem), the tube, the grown obstacles, ``runs`` disturbed runs of the closed loop."""
    from plansynth.reach.plot import plot_problem

    K = np.asarray(result.robust["feedback"]["gain"], float)
    abstraction = robust_abstraction(problem)
    fig = plot_problem(
        problem,
        abstraction,
        result.regions if abstraction is not None else None,
        result.trajectory,
        ax=ax,
        title=title or f"{problem.name}: {result.solver}, horizon {result.horizon}, tube and {runs} disturbed runs",
    )
    target = ax if ax is not None else fig.axes[0]
    _overlay(target, problem, result.trajectory, K, runs, seed)
    if path is not None:
        with atomic_output(path) as tmp:
            fig.savefig(tmp, format="png")
    return fig


def plot_comparison(
    problem: ReachProblem,
    nominal: Trajectory,
    robust: Any,
    path: str | Path,
    *,
    runs: int = 30,
    seed: int = 0,
    zoom: tuple[float, float, float, float] | None = None,
) -> Figure:
    """The nominal plan (the disturbance ignored) and the robust one side by side, each
    with the tube of the same feedback and ``runs`` vertex disturbance sequences (runs
    that break a constraint in red); ``zoom`` (x0, x1, y0, y1): a magnified inset."""
    from plansynth.reach.plot import plot_problem

    K = np.asarray(robust.robust["feedback"]["gain"], float)
    fig = Figure(figsize=(13, 7.2), dpi=100)
    FigureCanvasAgg(fig)
    for k, (traj, what) in enumerate(((nominal, "nominal plan"), (robust.trajectory, "robust plan"))):
        ax = fig.add_subplot(1, 2, k + 1)
        plot_problem(problem, None, None, traj, ax=ax, title="")
        n, bad = _overlay(ax, problem, traj, K, runs, seed)
        ax.set_title(f"{what} (N = {traj.horizon}): {bad} of {n} disturbed runs break a constraint", fontsize=10)
        if zoom is not None:
            inset = ax.inset_axes((0.42, 0.3, 0.38, 0.38))
            plot_problem(problem, None, None, traj, ax=inset, title="")
            _overlay(inset, problem, traj, K, runs, seed)
            inset.set_xlim(zoom[0], zoom[1])
            inset.set_ylim(zoom[2], zoom[3])
            inset.set_xlabel("")
            inset.set_ylabel("")
            inset.set_xticks([])
            inset.set_yticks([])
            legend = inset.get_legend()
            if legend is not None:
                legend.remove()
            ax.indicate_inset_zoom(inset, edgecolor="black")
    w = problem.disturbance
    fig.suptitle(
        f"{problem.name}: |w| <= {list(w.box) if w is not None and w.box is not None else 'W'}, "
        "u = v + K (x - x_nom) (LQR); shaded: the tube, dashed: obstacles grown by it",
        fontsize=10,
    )
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format="png")
    return fig
