"""The LTL missions tables: lazy SMT (the BMC encoding in DIS-PLAN) against the
``milp-ltl`` baselines (one MILP per horizon in Wolff et al.'s encoding, and their one
MILP at the max horizon) on the mazes' missions, and on the planning literature's
scenarios (family ``missions-literature``).
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping

from plansynth.bench.report.cells import Cell, fmt, instances_of
from plansynth.bench.report.ratios import ratio, ratio_value

__all__ = ["missions_table", "missions_literature_table"]


def missions_table(cells: Mapping[tuple[str, str], Cell]) -> list[str]:
    """LTL missions on the mazes: lazy-smt against the milp-ltl baseline.
    Beside the baseline's total, the seconds HiGHS spent in its MILP solves
    (``timings["milp_solve"]``): the rest of its total is mostly building the models."""
    insts = instances_of(cells, "missions")
    if not insts:
        return []
    L = [
        "### LTL missions on the mazes: lazy SMT (BMC encoding in DIS-PLAN) vs one big-M MILP per horizon",
        "",
        "Three missions per maze (`plansynth.reach.mission.families`): `visit` = `F (b & F d) & G !h` (finite plan), "
        "`patrol` = `G F a & G F b` (a lasso), `avoid-until` = `!h U door`. Both planners search horizons "
        "upwards from the same proved lower bound (the product graph of `plansynth.reach.mission.horizon`) "
        "and report the shortest; every plan is validated and mission-checked. "
        "`milp-ltl in HiGHS` is the part of the baseline's time spent in HiGHS's MILP solves (the rest "
        "builds one model per horizon in array operations, passed to HiGHS whole, and the abstraction, the "
        "geometry's proof and the exact LP of the plan found); the next column compares lazy-smt with it.",
        "",
        "| instance | lazy-smt | milp-ltl | milp-ltl / lazy-smt | milp-ltl in HiGHS | HiGHS part / lazy-smt |",
        "|---|---|---|---|---|---|",
    ]
    oneshot = any(p == "milp-ltl-oneshot" for _, p in cells)
    if oneshot:
        L[-3] += (
            " `milp-ltl-oneshot` is Wolff et al.'s setting as published: one MILP at the fixed horizon K = "
            "the problem's max horizon (60), whose plan has exactly K steps (not the shortest; lazy-smt's "
            "and milp-ltl's horizons are the shortest)."
        )
        L[-2] += " milp-ltl-oneshot (horizon) | milp-ltl-oneshot / lazy-smt |"
        L[-1] += "---|---|"
    ratios, solve_ratios, oneshot_ratios = [], [], []
    for exp, setup in insts:
        a, b = cells.get((exp, "lazy-smt")), cells.get((exp, "milp-ltl"))
        c = cells.get((exp, "milp-ltl-oneshot"))
        rc = ratio_value(c, a)
        if rc is not None:
            oneshot_ratios.append(rc[0])
        extra = ""
        if oneshot:
            horizon = f" (at {c.horizon})" if c is not None and c.solved and c.horizon is not None else ""
            extra = f" {c.text() if c else '-'}{horizon} | {ratio(c, a)} |"
        rv = ratio_value(b, a)
        if rv is not None:
            ratios.append(rv[0])
        hs = ((b.extra or {}).get("timings") or {}).get("milp_solve") if b is not None and b.solved else None
        ta = a.decided_time() if a is not None else None
        part = "-"
        if hs is not None and ta:
            solve_ratios.append(hs / max(ta, 1e-6))
            part = f"{hs / max(ta, 1e-6):.3g}"
        L.append(
            f"| {setup['name']} | {a.text() if a else '-'} | {b.text() if b else '-'} | {ratio(b, a)} | "
            f"{fmt(hs)} | {part} |{extra}"
        )
    L.append("")
    if ratios:
        L.append(
            f"Median speed-up of lazy-smt over milp-ltl: **{statistics.median(ratios):.3g}x** over {len(ratios)} "
            "instances (a bound where the MILP ran out of time counts at the time limit)."
        )
        if oneshot_ratios:
            L.append(
                f"Over milp-ltl-oneshot (one MILP at the max horizon): **{statistics.median(oneshot_ratios):.3g}x** "
                f"in median over {len(oneshot_ratios)} instances."
            )
        if solve_ratios:
            L.append(
                f"Against the baseline's HiGHS time alone: {statistics.median(solve_ratios):.3g}x in median over "
                f"{len(solve_ratios)} instances."
            )
        L.append("")
    return L


def missions_literature_table(cells: Mapping[tuple[str, str], Cell]) -> list[str]:
    """The literature's scenarios (:mod:`plansynth.reach.mission.literature`): lazy-smt
    against milp-ltl, each plan's horizon and achieved margin."""
    insts = instances_of(cells, "missions-literature")
    if not insts:
        return []
    L = [
        "### LTL missions from the planning literature: lazy SMT vs milp-ltl",
        "",
        "The scenarios of the optimisation-based temporal-logic planners (`plansynth.reach.mission.literature`): "
        "`keys-doors-N` (N doors in series, each closed until its key: `(!d1 U k1) & ... & F goal`), `groups-G` "
        "(one target of each of G groups), `dwell-D` (D steps in a region, then another), `stones-S` (a river on S "
        "stepping stones, every sample on land or a stone) and `avoid-labels-K` (reach-avoid with its K obstacles "
        "as labels); a double integrator, dt = 1, |u| <= 0.5, |v| <= 1, labels read at the samples (the "
        "literature's reading) with a margin of 0.1. In the sample reading both planners search exactly, so "
        "their horizons are the problem's shortest and agree; `milp-ltl` is Wolff, Topcu and Murray's encoding "
        "(labels and obstacles as polytopes on the positions, a binary per label literal and edge). Every plan "
        "is validated and mission-checked; *margin* is the achieved margin the checker reports (the plan's "
        "robustness for its mission: every visit at least that deep, every avoidance that far).",
        "",
        "| instance | lazy-smt | milp-ltl | milp-ltl / lazy-smt | horizon | margin |",
        "|---|---|---|---|---|---|",
    ]
    ratios = []
    for exp, setup in insts:
        a, b = cells.get((exp, "lazy-smt")), cells.get((exp, "milp-ltl"))
        rv = ratio_value(b, a)
        if rv is not None:
            ratios.append(rv[0])
        horizons = sorted({c.horizon for c in (a, b) if c is not None and c.solved and c.horizon is not None})
        margins = [
            ((c.extra or {}).get("mission") or {}).get("robustness") for c in (a, b) if c is not None and c.solved
        ]
        margin = min((m for m in margins if m is not None), default=None)
        L.append(
            f"| {setup['name']} | {a.text() if a else '-'} | {b.text() if b else '-'} | {ratio(b, a)} | "
            f"{', '.join(map(str, horizons)) or '-'} | {'-' if margin is None else f'{margin:.3g}'} |"
        )
    L.append("")
    if ratios:
        L.append(
            f"Median speed-up of lazy-smt over milp-ltl: **{statistics.median(ratios):.3g}x** over {len(ratios)} "
            "instances (a bound where the MILP ran out of time counts at the time limit)."
        )
        L.append("")
    return L
