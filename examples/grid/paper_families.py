"""The grid benchmark families of Chasins & Newcomb (SYNT 2016, Section 4.1), as
problem dictionaries (spec: benchmarks.md). Used by ``measure_native.py``.

>>> sorted(families())[:3]
['depth-1', 'depth-4', 'depth-5']
"""

from __future__ import annotations

from typing import Any

MOVES = ["stay", "up", "right", "down", "left"]
UP_DOWN = ["up", "down"]


def _problem(name: str, w: int, h: int, start, goal, obstacles, steps: int | None) -> dict[str, Any]:
    d: dict[str, Any] = {
        "name": name,
        "grid": [w, h],
        "robot": {"start": list(start), "goal": list(goal), "moves": MOVES},
        "obstacles": [{"start": list(c), "moves": m} for c, m in obstacles],
    }
    if steps is not None:
        d["steps"] = steps
    return d


def families() -> dict[str, dict[str, Any]]:
    """Every instance of the four families plus Figure 1, by name."""
    out: dict[str, dict[str, Any]] = {}
    out["figure1"] = _problem("figure1", 5, 7, (1, 1), (4, 4), [((2, 5), UP_DOWN), ((3, 5), ["stay", "up", "down"])], None)
    static = [((x, 1), ["stay"]) for x in range(4)]
    for name, start, goal in (("depth-1", (0, 0), (5, 0)), ("depth-4", (0, 0), (4, 0)), ("depth-5", (1, 0), (4, 1)), ("depth-6", (3, 0), (3, 2))):
        out[name] = _problem(name, 6, 6, start, goal, static, 5)
    column = [((0, y), UP_DOWN) for y in range(5)]
    for L in (5, 10, 15, 20, 25):
        out[f"steps-{L}"] = _problem(f"steps-{L}", 20, 20, (1, 1), (3, 1), column, L)
    for n in range(5, 55, 5):
        obs = [((i % 20, 19 - i // 20), UP_DOWN) for i in range(n)]
        out[f"obstacles-{n}"] = _problem(f"obstacles-{n}", 20, 20, (0, 0), (2, 3), obs, 5)
    for s in (5, 15, 25, 35, 45, 55):
        out[f"dimensions-{s}"] = _problem(f"dimensions-{s}", s, s, (1, 0), (4, 2), column, 5)
    return out


#: The depth of the paper's programs (Section 4.1): 4 for the steps, obstacles and
#: dimensions families; the depth family is named by it.
PAPER_DEPTH = {"steps": 4, "obstacles": 4, "dimensions": 4, "depth": None}
