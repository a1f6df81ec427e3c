"""Table I of Shoukry et al. (CDC 2016, Section VI): the mazes, every reach planner
beside the paper's lazy SMT, RRT and LTL OPT, with the ratios to lazy SMT, the lazy SMT
phases beside the paper's (abstraction, DIS-PLAN, CON-PLAN), and the bars figure.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from plansynth.bench.families import PAPER_TABLE_I
from plansynth.bench.report.cells import Cell, fmt
from plansynth.bench.report.plots import plot_bars
from plansynth.bench.report.ratios import over_limit, ratio

__all__ = ["table_one"]


def table_one(
    cells: Mapping[tuple[str, str], Cell],
    mazes: Sequence[tuple[str, dict[str, Any]]],
    reach_planners: Sequence[str],
    out: Path,
    image_prefix: str,
) -> list[str]:
    """Table I's section for the ``mazes`` (instances of family ``maze``); its figure is
    written under ``out``."""
    L: list[str] = []
    L.append("### Table I: mazes (double integrator)")
    L.append("")
    hdr = ["passages", "paper: abstraction + DIS-PLAN + CON-PLAN", "paper: RRT", "paper: LTL OPT"]
    hdr += [f"{p}" for p in reach_planners]
    base = "lazy-smt" if "lazy-smt" in reach_planners else None
    others = [p for p in reach_planners if p != base]
    if base:
        hdr += [f"{p} / {base}" for p in others]
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))
    groups, series, lims = [], defaultdict(list), defaultdict(list)
    for exp, setup in mazes:
        n = int(setup["params"]["n"])
        pap = PAPER_TABLE_I.get(n, {})
        tot = sum(float(pap[k]) for k in ("abstraction", "dis-plan", "con-plan")) if pap else None
        row = [str(n), fmt(tot), fmt(pap.get("rrt")), str(pap.get("ltl-opt", "-"))]
        for p in reach_planners:
            c = cells.get((exp, p))
            row.append(c.text() if c else "-")
        if base:
            for p in others:
                row.append(ratio(cells.get((exp, p)), cells.get((exp, base))))
        L.append("| " + " | ".join(row) + " |")
        groups.append(f"maze-{n}")
        for p in reach_planners:
            c = cells.get((exp, p))
            t = None if c is None else c.decided_time()
            timed_out = c is not None and t is None and c.out_of_time
            series[p].append(t if t is not None else (c.limit if timed_out else None))
            lims[p].append(timed_out)
        series["paper lazy SMT (total)"].append(tot)
        lims["paper lazy SMT (total)"].append(False)
        series["paper RRT"].append(float(pap["rrt"]) if pap else None)
        lims["paper RRT"].append(False)
    L.append("")
    L.append(
        "`milp` is the region-graph MILP planner; `milp-bigm` the one-shot big-M MILP over the horizon "
        "(the paper's LTL OPT stand-in); `rrt`, `est`, `kpiece` are OMPL's kinodynamic planners with the "
        "exact discrete dynamics. All keep whole segments off the obstacles unless marked `samples only`."
    )
    L.append("")
    if base:
        L.append(
            "**Headline ratios (per maze):** "
            + "; ".join(
                f"maze-{int(s['params']['n'])}: "
                + ", ".join(f"{p}/lazy-smt {ratio(cells.get((e, p)), cells.get((e, base)))}" for p in others)
                for e, s in mazes
            )
            + "."
        )
        L.append("")
    # lazy-smt breakdown
    if base:
        L.append("Lazy SMT phases (median run): abstraction / SAT / LP seconds, SAT and LP calls, horizon:")
        L.append("")
        L.append(
            "| maze | paper abstraction | paper DIS-PLAN | paper CON-PLAN | abstraction | sat | lp | SAT calls | LP calls | horizon | total / limit (one cold LP) |"
        )
        L.append("|---|---|---|---|---|---|---|---|---|---|---|")
        for exp, setup in mazes:
            c = cells.get((exp, base))
            n = int(setup["params"]["n"])
            pap = PAPER_TABLE_I.get(n, {})
            tm = (c.extra or {}).get("timings", {}) if c else {}
            L.append(
                f"| {n} | {fmt(pap.get('abstraction'))} | {fmt(pap.get('dis-plan'))} | {fmt(pap.get('con-plan'))} | "
                f"{fmt(tm.get('abstraction'))} | {fmt(tm.get('sat'))} | {fmt(tm.get('lp'))} | "
                f"{(c.extra or {}).get('sat_calls') if c else '-'} | {(c.extra or {}).get('lp_calls') if c else '-'} | "
                f"{c.horizon if c else '-'} | {over_limit(c)} |"
            )
        L.append("")
        L.append(
            "The limit is one cold LP over the final region sequence: what the plan would cost if an oracle "
            "handed the planner its regions (CON-PLAN's feasibility LP built and solved from scratch in a "
            "fresh CON-PLAN, as it solves a plan LP with no basis: beyond 8 states split per axis where "
            "the dynamics and regions separate (the axes then on two threads), by the interior-point "
            "method first from 30 states on, no iteration cap; median "
            "over the solved runs); "
            "total / limit is the search's overhead."
        )
        L.append("")
    plot_bars(groups, dict(series), "Reach, Table I: mazes (log scale)", out / "reach-table1.png", dict(lims))
    L.append(f"![Table I]({image_prefix}reach-table1.png)")
    L.append("")
    return L
