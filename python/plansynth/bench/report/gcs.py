"""Graphs of Convex Sets (Marcucci et al., Science Robotics 2023, through Drake) beside
lazy SMT: on the mazes, and on the GCS paper's own n x n mazes.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from plansynth.bench.report.cells import Cell, fmt, instances_of
from plansynth.bench.report.ratios import ratio

__all__ = ["gcs_table", "gcs_maze_table"]


def gcs_table(cells: Mapping[tuple[str, str], Cell], mazes: Sequence[tuple[str, dict[str, Any]]]) -> list[str]:
    """GCS (Drake) beside lazy-smt on the mazes, with the difference in guarantee."""
    if not any((e, "gcs") in cells for e, _ in mazes):
        return []
    from plansynth.reach.planners.gcs import GUARANTEE

    L = [
        "### Graphs of Convex Sets (Drake) beside lazy SMT",
        "",
        '`gcs`: Marcucci, Petersen, von Wrangel and Tedrake, "Motion planning around obstacles with convex '
        "optimization\", Science Robotics 2023, through Drake's `GcsTrajectoryOptimization`, over *our* convex "
        "regions (the lazy planner's decomposition and adjacency); like-for-like variant: Bezier order 5, velocity "
        "continuity, |v| and |a| bounds of the problem, start at rest, the goal box as the target set, Clarabel "
        "relaxation + IPOPT rounding, time in units of 10 s. **The guarantees differ**: lazy-smt returns a "
        "trajectory of the exact discrete dynamics x' = A x + B u (|u| <= 1, every sample and segment free); "
        f"gcs returns a {GUARANTEE}.",
        "",
        "Times include the validator's checks (for gcs: the samples at dt and the dense curve, several thousand "
        "samples); the planner-only columns leave them out.",
        "",
        "| maze | gcs | gcs curve duration (s) | lazy-smt | lazy-smt horizon x dt (s) | gcs / lazy-smt | "
        "planner only: gcs / lazy-smt |",
        "|---|---|---|---|---|---|---|",
    ]
    for exp, setup in mazes:
        g, lz = cells.get((exp, "gcs")), cells.get((exp, "lazy-smt"))
        gd = (g.extra or {}).get("duration") if g and g.solved else None
        ld = (lz.extra or {}).get("duration") if lz and lz.solved else None
        gp = (g.extra or {}).get("planner_median") if g and g.solved else None
        lp = (lz.extra or {}).get("planner_median") if lz and lz.solved else None
        only = f"{fmt(gp)} / {fmt(lp)} = {gp / lp:.3g}" if gp and lp else "-"
        L.append(
            f"| {int(setup['params']['n'])} | {g.text() if g else '-'} | {fmt(gd)} | {lz.text() if lz else '-'} | "
            f"{fmt(ld)} | {ratio(g, lz)} | {only} |"
        )
    L.append("")
    return L


def gcs_maze_table(cells: Mapping[tuple[str, str], Cell]) -> list[str]:
    """The GCS paper's n x n mazes: lazy-smt and gcs on the same
    instances in the same run."""
    insts = sorted(instances_of(cells, "gcs-maze"), key=lambda es: int(es[1]["params"]["n"]))
    if not insts:
        return []
    from plansynth.reach.families import gcs_maze

    L = [
        "### The GCS paper's mazes (n x n)",
        "",
        " ".join((gcs_maze.__doc__ or "").split("\n\n")[0].split()),
        "",
        "A time is a solved run: planned and validated (lazy-smt: the exact discrete dynamics, every sample and "
        "segment free; gcs: its continuous-time curve, see the Graphs of Convex Sets section). lazy-smt's horizon is not proved minimal here "
        "(a window search: horizons below the window's bottom refuted).",
        "",
        "| n | regions | lazy-smt | lazy-smt horizon x dt (s) | lazy-smt LP calls / learned clauses | gcs | "
        "gcs curve duration (s) | gcs / lazy-smt |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for exp, setup in insts:
        g, lz = cells.get((exp, "gcs")), cells.get((exp, "lazy-smt"))
        regions = next((c.extra or {}).get("regions") for c in (lz, g) if c is not None)
        ld = (lz.extra or {}).get("duration") if lz and lz.solved else None
        gd = (g.extra or {}).get("duration") if g and g.solved else None
        cnt = (lz.extra or {}).get("counters", {}) if lz else {}
        work = f"{cnt.get('lp_calls', '-')} / {cnt.get('clauses', '-')}" if lz else "-"
        hor = f"{lz.horizon} x dt = {fmt(ld)}" if lz and lz.solved and lz.horizon is not None else "-"
        L.append(
            f"| {int(setup['params']['n'])} | {regions if regions is not None else '-'} | "
            f"{lz.text() if lz else '-'} | {hor} | {work} | {g.text() if g else '-'} | {fmt(gd)} | "
            f"{ratio(g, lz)} |"
        )
    L.append("")
    return L
