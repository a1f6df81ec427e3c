"""The reach-avoid half of the report (Shoukry et al., CDC 2016): Table I on the mazes
and the tables beside it (Graphs of Convex Sets, proved-minimal horizons,
counterexamples), Figure 4 (integrator chains, random dynamics), the LTL missions, robust
plans under bounded disturbances, the GCS paper's mazes and the random workspaces.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from plansynth.bench.report.cells import Cell, instances_of, planners_of
from plansynth.bench.report.chains import chains_section, random_dynamics_section
from plansynth.bench.report.counterexamples import CX_VARIANTS, counterexample_table
from plansynth.bench.report.gcs import gcs_maze_table, gcs_table
from plansynth.bench.report.horizons import minimal_table
from plansynth.bench.report.mazes import table_one
from plansynth.bench.report.missions import missions_table
from plansynth.bench.report.robust import robust_section
from plansynth.bench.solvers import REACH_ORDER

__all__ = ["reach_section"]


def reach_section(cells: Mapping[tuple[str, str], Cell], out: Path, image_prefix: str) -> list[str]:
    """The reach half's Markdown lines (figures written under ``out``, referred to as
    ``image_prefix + name``); none without a reach run."""
    reach_planners = [
        p
        for p in planners_of(cells, "reach/", REACH_ORDER)
        if p not in CX_VARIANTS and p not in ("milp-ltl", "lazy-smt-minimal", "nominal-check")
    ]  # (their own tables)
    if not reach_planners:
        return []
    L: list[str] = []
    L.append("## Reach-avoid: lazy SMT planning (Shoukry et al., CDC 2016)")
    L.append("")
    mazes = instances_of(cells, "maze")
    if mazes:
        L += table_one(cells, mazes, reach_planners, out, image_prefix)
        L += gcs_table(cells, mazes)
        L += minimal_table(cells, mazes)
        L += counterexample_table(cells, mazes)
    L += chains_section(cells, reach_planners, out, image_prefix)
    L += random_dynamics_section(cells, reach_planners)
    L += missions_table(cells)
    L += robust_section(cells)
    L += gcs_maze_table(cells)
    L += _random_workspaces(cells, reach_planners)
    return L


def _random_workspaces(cells: Mapping[tuple[str, str], Cell], reach_planners: Sequence[str]) -> list[str]:
    rnd = instances_of(cells, "random")
    if not rnd:
        return []
    L: list[str] = []
    L.append("### Random workspaces")
    L.append("")
    used = [p for p in reach_planners if any((e, p) in cells for e, _ in rnd)]
    hdr = ["instance"] + used
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))
    for exp, setup in rnd:
        L.append(
            "| "
            + " | ".join([setup["name"]] + [cells[(exp, p)].text() if (exp, p) in cells else "-" for p in used])
            + " |"
        )
    L.append("")
    return L
