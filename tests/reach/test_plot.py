"""Plot smoke tests: the PNG/GIF files are written and are real pictures.

The trajectories here are built geometrically (a single integrator walking from region
centre to shared-boundary midpoint through a breadth-first region sequence), so these
tests do not depend on the planner.
"""

from __future__ import annotations

from collections import deque
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.abstraction import Abstraction, abstract
from plansynth.reach.dynamics import single_integrator
from plansynth.reach.families import cluttered, maze, random_workspace
from plansynth.reach.plot import animate, plot_problem
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import validate


def region_path(a: Abstraction) -> list[int]:
    prev: dict[int, int | None] = {s: None for s in a.start_regions}
    queue = deque(a.start_regions)
    while queue:
        i = queue.popleft()
        if i in a.goal_regions:
            seq = []
            cur: int | None = i
            while cur is not None:
                seq.append(cur)
                cur = prev[cur]
            return seq[::-1]
        for j in a.adjacency[i]:
            if j not in prev:
                prev[j] = i
                queue.append(j)
    raise AssertionError("goal not reachable in the region graph")


def walk(problem: ReachProblem, a: Abstraction, seq: list[int], step: float) -> Trajectory:
    """Single-integrator samples along centre -> shared-edge midpoint -> centre -> ... -> goal."""
    pts = [problem.start_position]
    for i, j in zip(seq, seq[1:]):
        shared = ShPolygon(a.regions[i].vertices).boundary.intersection(ShPolygon(a.regions[j].vertices).boundary)
        pts.append(np.array(shared.interpolate(0.5, normalized=True).coords[0]))
        pts.append(a.regions[j].center)
    pts.append((np.array(problem.goal.lo) + np.array(problem.goal.hi)) / 2)
    X = [pts[0]]
    for q in pts[1:]:
        d = q - X[-1]
        k = max(1, int(np.ceil(np.max(np.abs(d)) / step)))
        base = X[-1]
        X.extend(base + d * s / k for s in range(1, k + 1))
    X = np.array(X)
    return Trajectory(X, np.diff(X, axis=0) / problem.dynamics.dt)


def single_integrator_version(p: ReachProblem) -> ReachProblem:
    fields = {k: getattr(p, k) for k in p.__dataclass_fields__}
    return ReachProblem(
        **{**fields, "dynamics": single_integrator(p.dim, 0.5), "start": p.start_position, "state_bounds": None}
    )


def assert_real_png(path: Path, min_colors: int = 8) -> None:
    assert path.exists() and path.stat().st_size > 10_000
    with Image.open(path) as im:
        assert im.format == "PNG" and im.width > 300 and im.height > 300
        rgb = np.asarray(im.convert("RGB"))
    colors = np.unique(rgb.reshape(-1, 3), axis=0)
    assert len(colors) >= min_colors
    # not a blank canvas: a good share of pixels is not white
    assert np.mean(np.any(rgb < 240, axis=2)) > 0.05


@pytest.mark.parametrize(
    "problem",
    [single_integrator_version(maze(n)) for n in (1, 4)] + [single_integrator_version(cluttered())],
    ids=["maze-1", "maze-4", "cluttered"],
)
def test_full_picture(problem: ReachProblem, tmp_path: Path) -> None:
    a = abstract(problem)
    seq = region_path(a)
    t = walk(problem, a, seq, step=0.5)
    assert validate(problem, t, require_segment_safe=True).ok  # the picture shows a valid path
    out = tmp_path / f"{problem.name}.png"
    fig = plot_problem(problem, a, seq, t, path=out)
    assert_real_png(out)
    ax = fig.axes[0]
    assert f"{a.n_regions} convex regions" in ax.get_title()
    assert any(f"N = {t.horizon}" in h.get_label() for h in ax.get_lines())


def test_problem_only_and_into_given_axes(tmp_path: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    out = tmp_path / "plain.png"
    plot_problem(maze(2), path=out)
    assert_real_png(out, min_colors=4)
    fig = Figure()
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(1, 2)
    got = plot_problem(maze(1), abstract(maze(1)), ax=ax2, title="right")
    assert got is fig and ax2.get_title() == "right" and ax1.get_title() == ""


def test_3d_is_a_projection(tmp_path: Path) -> None:
    p = random_workspace(4, 5, dim=3)
    out = tmp_path / "p3.png"
    fig = plot_problem(p, abstract(p), path=out)
    assert "projection" in fig.axes[0].get_title()
    assert_real_png(out, min_colors=4)


def test_animation_has_one_frame_per_sample(tmp_path: Path) -> None:
    p = single_integrator_version(maze(1))
    a = abstract(p)
    seq = region_path(a)
    t = walk(p, a, seq, step=10.0)
    out = animate(p, a, t, seq, tmp_path / "run.gif", fps=5)
    with Image.open(out) as im:
        assert im.format == "GIF" and im.n_frames == t.horizon + 1
        im.seek(im.n_frames - 1)
        assert im.width > 200


def test_animation_subsamples_long_trajectories(tmp_path: Path) -> None:
    p = single_integrator_version(maze(1))
    a = abstract(p)
    seq = region_path(a)
    t = walk(p, a, seq, step=1.0)
    assert t.horizon + 1 > 5
    out = animate(p, a, t, seq, tmp_path / "short.gif", max_frames=5, dpi=40)
    with Image.open(out) as im:
        assert im.n_frames == 5


# ------------------------------------------------------------------ a trajectory of another robot

ROOT = Path(__file__).resolve().parents[2]


def _result_file(tmp_path: Path, states: list[list[float]], inputs: list[list[float]]) -> Path:
    import json

    path = tmp_path / "other-robot.json"
    path.write_text(json.dumps({"status": "found", "states": states, "inputs": inputs}), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "states, inputs, field, reason",
    [
        (
            [[1, 1, 0], [1.5, 1, 0], [2, 1, 0]],
            [[0, 0], [0, 0]],
            "states",
            "each state has 3 components, but the problem's robot has 4 states",
        ),
        (
            [[1, 1, 0, 0, 0], [1.5, 1, 0, 0, 0]],
            [[0, 0]],
            "states",
            "each state has 5 components, but the problem's robot has 4 states",
        ),
        (
            [[1, 1, 0, 0], [1.5, 1, 0, 0]],
            [[0, 0, 0]],
            "inputs",
            "each input has 3 components, but the problem's robot has 2 inputs",
        ),
    ],
    ids=["3-of-4-states", "5-of-4-states", "3-of-2-inputs"],
)
def test_plot_refuses_a_trajectory_of_another_robot(
    tmp_path: Path, states: list, inputs: list, field: str, reason: str
) -> None:
    """``plansynth reach plot`` of maze-1 (4 states, 2 inputs) with a result whose states
    or inputs have other dimensions: one line naming the file, the field and the reason,
    exit 2, and no picture (it used to draw the first two components as positions)."""
    import subprocess
    import sys

    from plansynth.errors import InvalidProblem
    from plansynth.reach.fileformat import load_reach_problem
    from plansynth.reach.trajectory import load_trajectory

    result = _result_file(tmp_path, states, inputs)
    out = tmp_path / "picture.png"
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "plansynth.cli",
            "reach",
            "plot",
            str(ROOT / "examples/reach/maze-1.yaml"),
            str(result),
            "-o",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 2, run.stdout + run.stderr
    assert run.stderr.strip() == f"error: {result}: {field}: {reason}", run.stderr
    assert "Traceback" not in run.stderr and not out.exists()
    # the API says the same, for the picture and for the animation
    problem, trajectory = load_reach_problem(ROOT / "examples/reach/maze-1.yaml"), load_trajectory(result)
    with pytest.raises(InvalidProblem, match=f"^{result}: {field}: {reason}$"):
        plot_problem(problem, abstract(problem), None, trajectory, path=out)
    with pytest.raises(InvalidProblem, match=f"^{result}: {field}: "):
        animate(problem, abstract(problem), trajectory, None, tmp_path / "run.gif")
    assert not out.exists() and not (tmp_path / "run.gif").exists()
