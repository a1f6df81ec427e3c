"""The GCS paper's mazes (Marcucci et al., Science Robotics 2023; gcs-science-robotics
``models/maze.py`` and ``reproduction/maze_example.ipynb``) as
:func:`plansynth.reach.families.gcs_maze` generates them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from plansynth.bench.families import REACH_FAMILIES, reach_family
from plansynth.reach.families import gcs_maze
from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.geometry import Box

CLAIMS = Path(__file__).resolve().parents[2] / "examples" / "reach" / "claims"


def test_gcs_maze_10_is_the_claims_file() -> None:
    """n = 10, seed 4, no knock-downs: the public case committed before, field by field."""
    p, q = gcs_maze(10), load_reach_problem(CLAIMS / "gcs-maze-10.yaml")
    assert p.obstacles == q.obstacles and len(p.obstacles) == 102
    assert (p.workspace, p.goal, p.input_bound, p.state_bounds) == (q.workspace, q.goal, q.input_bound, q.state_bounds)
    assert np.array_equal(p.start, q.start) and p.dynamics.dt == q.dynamics.dt
    assert np.array_equal(p.dynamics.A, q.dynamics.A) and np.array_equal(p.dynamics.B, q.dynamics.B)
    assert p.max_horizon == q.max_horizon == 200 and gcs_maze(50).max_horizon == 2000


def _cells_open(p, n: int) -> int:
    """Unit wall pieces (inner walls of the cell grid) that are not covered by any box."""
    walls = [o for o in p.obstacles if isinstance(o, Box)]
    open_ = 0
    for x in range(n):
        for y in range(1, n):  # the horizontal wall between (x, y-1) and (x, y)
            mid = (x + 0.5, float(y))
            open_ += not any(w.lo[0] <= mid[0] <= w.hi[0] and w.lo[1] <= mid[1] <= w.hi[1] for w in walls)
    for x in range(1, n):
        for y in range(n):
            mid = (float(x), y + 0.5)
            open_ += not any(w.lo[0] <= mid[0] <= w.hi[0] and w.lo[1] <= mid[1] <= w.hi[1] for w in walls)
    return open_


@pytest.mark.parametrize("n", [5, 10, 20])
def test_gcs_maze_is_a_perfect_maze(n: int) -> None:
    """Without knock-downs the backtracker opens exactly n^2 - 1 inner walls (a spanning
    tree of the cells); the knock-downs of the 50 x 50 one open exactly 100 more."""
    assert _cells_open(gcs_maze(n), n) == n * n - 1
    assert _cells_open(gcs_maze(n, knock_downs=7), n) == n * n - 1 + 7


def test_gcs_maze_50_has_the_notebooks_knock_downs() -> None:
    assert _cells_open(gcs_maze(50), 50) == 50 * 50 - 1 + 100
    assert _cells_open(gcs_maze(50, knock_downs=0), 50) == 50 * 50 - 1
    assert gcs_maze(50).obstacles != gcs_maze(50, seed=5).obstacles


def test_gcs_maze_bench_family() -> None:
    assert "gcs-maze" in REACH_FAMILIES
    insts = reach_family("gcs-maze")
    assert [i.name for i in insts] == [f"gcs-maze-{n}" for n in (10, 20, 30, 50, 70, 100)]
    assert insts[0].build().obstacles == gcs_maze(10).obstacles


def test_gcs_maze_rejects_tiny() -> None:
    with pytest.raises(ValueError, match="n must be"):
        gcs_maze(1)
