"""The grid half of the report (Chasins & Newcomb, SYNT 2016): the paper's Figures 2-5
(time against program depth, path length, number of obstacles and grid size) as tables
beside the paper's times and as plots, the no-regression line on the paper's families,
Figure 6 (solvers on steps-20), Figure 1 and our reactive families, then the runs timed
through the CLI (:mod:`plansynth.bench.report.suite`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from plansynth.bench.families import PAPER_FAMILIES, PAPER_GRID_SECONDS, paper_depth
from plansynth.bench.report.cells import Cell, fmt, instances_of, planners_of
from plansynth.bench.report.plots import plot_bars, plot_family
from plansynth.bench.report.ratios import headline, ratio
from plansynth.bench.report.suite import cli_timed_sections
from plansynth.bench.report.syntcomp import syntcomp_sections
from plansynth.bench.solvers import GRID_ORDER, GRID_PEERS

__all__ = ["grid_section", "grid_table", "paper_regression", "GRID_FIGURES", "REACTIVE", "PAPER_FIG6"]

GRID_FIGURES = [
    ("depth", "Figure 2: time vs program depth", "program depth d of the paper's instance depth-d"),
    ("steps", "Figure 3: time vs number of steps", "number of steps L"),
    ("obstacles", "Figure 4: time vs number of obstacles", "number of obstacles N"),
    ("dimensions", "Figure 5: time vs grid size", "grid size S (S x S)"),
]
REACTIVE = [
    "figure1",
    "crossing",
    "crossing-stall",
    "patrol",
    "patrol-walk",
    "door",
    "door-stall",
    "scale",
    "lanes",
    "lanes-rush",
    "roads30",
    "roads30-stall",
    "guards30",
]
PAPER_FIG6 = {"Stochastic 2014": "> 1800 (time out)", "Enumerative 2014": 1003.0, "Enumerative 2015": 805.0}


def grid_section(cells: Mapping[tuple[str, str], Cell], out: Path, image_prefix: str) -> list[str]:
    """The grid half's Markdown lines (figures written under ``out``, referred to as
    ``image_prefix + name``); none without a grid run."""
    every = planners_of(cells, "grid/", GRID_ORDER)
    if not every:
        return []
    grid_planners = [p for p in every if p not in GRID_PEERS]  # the peers have their own tables
    L: list[str] = []
    L.append("## Grid: reactive controllers (Chasins & Newcomb, SYNT 2016)")
    L.append("")
    if "native" in grid_planners and "cvc5" in grid_planners:
        h = headline(cells, "cvc5", "native", "grid/")  # (cvc5 refuses the SYNTCOMP families: never both decided)
        if h["n"]:
            L.append(
                f"**Headline: native vs cvc5** (time ratio cvc5 / native on the same instance, {h['n']} "
                f"instances both decided): median {h['median']:.3g}x; worst case for native (smallest ratio) "
                f"{h['best_for_b'][0]:.3g}x on {h['best_for_b'][1]}; largest {h['worst_for_b'][0]:.3g}x on "
                f"{h['worst_for_b'][1]}."
            )
        if h.get("bounds"):
            L.append("")
            L.append(
                f"Decided by one side only ({len(h['bounds'])} instances; ratio bounds from the time limit): "
                + "; ".join(f"{e.split('/')[-1]} {s} {v:.3g}x" for v, e, s in h["bounds"])
                + "."
            )
        L.append("")
    for fam, caption, pname in GRID_FIGURES:
        insts = instances_of(cells, fam)
        if not insts:
            continue
        L.append(f"### {caption} (family `{fam}`)")
        L.append("")
        L.extend(grid_table(cells, insts, grid_planners, paper=True))
        L.append("")
        png = f"grid-{fam}.png"
        paper = {float(k): v for k, v in PAPER_GRID_SECONDS[fam].items() if v is not None}
        if plot_family(cells, fam, grid_planners, f"Grid, {caption} ({fam})", pname, out / png, paper):
            L.append(f"![{caption}]({image_prefix}{png})")
            L.append("")
    check = paper_regression(cells)
    if check:
        L.append(check)
        L.append("")
    L += _figure6(cells, grid_planners, out, image_prefix)
    react = [f for f in REACTIVE if instances_of(cells, f)]
    if react:
        L.append("### Figure 1 and reactive families (ours: obstacles cross the robot's way)")
        L.append("")
        for fam in react:
            L.append(f"Family `{fam}`:")
            L.append("")
            L.extend(grid_table(cells, instances_of(cells, fam), grid_planners, paper=False, expected=True))
            L.append("")
    L += cli_timed_sections(cells, grid_planners)
    L += syntcomp_sections(cells, every)
    return L


def _figure6(
    cells: Mapping[tuple[str, str], Cell], grid_planners: Sequence[str], out: Path, image_prefix: str
) -> list[str]:
    """Figure 6: every solver on steps-20 beside the paper's three (table and bars)."""
    exp6 = "grid/steps/steps-20"
    if not any(e == exp6 for e, _ in cells):
        return []
    L: list[str] = []
    L.append("### Figure 6: solvers on steps-20")
    L.append("")
    L.append("| solver | time (s) | source |")
    L.append("|---|---|---|")
    for k, v in PAPER_FIG6.items():
        L.append(f"| {k} | {fmt(v) if not isinstance(v, str) else v} | paper |")
    for p in grid_planners:
        c = cells.get((exp6, p))
        if c:
            L.append(f"| {p} | {c.text()} | this run |")
    L.append("")
    series = {p: [cells[(exp6, p)].decided_time() if (exp6, p) in cells else None] for p in grid_planners}
    lim = {p: [cells[(exp6, p)].decided_time() is None] if (exp6, p) in cells else [False] for p in grid_planners}
    for p in grid_planners:
        if series[p][0] is None and (exp6, p) in cells:
            series[p] = [cells[(exp6, p)].limit]
    series["Enumerative 2014 (paper)"] = [1003.0]
    series["Enumerative 2015 (paper)"] = [805.0]
    series["Stochastic 2014 (paper, time out)"] = [1800.0]
    lim["Stochastic 2014 (paper, time out)"] = [True]
    plot_bars(["steps-20"], series, "Grid, Figure 6: solver comparison on steps-20", out / "grid-figure6.png", lim)
    L.append(f"![Figure 6]({image_prefix}grid-figure6.png)")
    L.append("")
    return L


def grid_table(
    cells: Mapping[tuple[str, str], Cell],
    insts: Sequence[tuple[str, dict[str, Any]]],
    planners: Sequence[str],
    *,
    paper: bool,
    expected: bool = False,
) -> list[str]:
    hdr = ["instance"] + (["paper (s)"] if paper else []) + (["expected"] if expected else [])
    for p in planners:
        hdr += [f"{p} (s)", f"{p} depth / l"]
    pairs = [(a, b) for a in planners for b in planners if a != b and b == "native"]
    hdr += [f"{a} / {b}" for a, b in pairs]
    out = ["| " + " | ".join(hdr) + " |", "|" + "---|" * len(hdr)]
    for exp, setup in insts:
        row = [setup["name"]]
        if paper:
            row.append(fmt(setup.get("paper_seconds")))
        if expected:
            row.append(str(setup.get("expected") or "-"))
        for p in planners:
            c = cells.get((exp, p))
            row.append(c.text() if c else "-")
            row.append(
                f"{c.depth if c and c.depth is not None else '-'} / {c.steps if c and c.steps is not None else '-'}"
            )
        for a, b in pairs:
            row.append(ratio(cells.get((exp, a)), cells.get((exp, b))))
        out.append("| " + " | ".join(row) + " |")
    return out


def paper_regression(cells: Mapping[tuple[str, str], Cell], planner: str = "native") -> str:
    """The target "no regression on the paper's families": every instance solved in under
    1 s (median solve time) with a program no deeper than the paper's; one line."""
    got = [
        (setup["name"], cells[(exp, planner)])
        for f in PAPER_FAMILIES
        for exp, setup in instances_of(cells, f)
        if (exp, planner) in cells
    ]
    if not got:
        return ""
    solved = [(n, c) for n, c in got if c.all_solved and c.median is not None]
    under = [n for n, c in solved if c.median < 1.0]
    shallow = [n for n, c in solved if c.depth is not None and c.depth <= paper_depth(n)]
    slowest = max(solved, key=lambda nc: nc[1].median, default=None)
    verdict = "holds" if len(under) == len(shallow) == len(got) else "FAILS"
    return (
        f"**No regression on the paper's families** ({planner}, {len(got)} instances): solved {len(solved)}/"
        f"{len(got)}, under 1 s {len(under)}/{len(got)}"
        + (f" (slowest {slowest[0]}, {fmt(slowest[1].median)} s)" if slowest else "")
        + f", depth at most the paper's {len(shallow)}/{len(got)}: {verdict}. "
        "`--minimize` proving the depth family's minimal depths is a test "
        "(`tests/grid/test_native.py::test_minimize_proves_the_depth_family`)."
    )
