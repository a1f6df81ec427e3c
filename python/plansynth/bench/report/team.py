"""The teams table: the joint lazy SMT planner against the joint big-M MILP over the same
encoding and prioritized planning, on the ``team`` family (SMC-LTL's crossing, Shoukry
et al., CDC 2017; the lazy paper's mazes with several robots; antipodal crossings; a
patrolled gap; a narrow corridor with no plan).
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping

from plansynth.bench.report.cells import Cell, fmt, instances_of
from plansynth.bench.report.ratios import ratio, ratio_value

__all__ = ["team_table", "TEAM_COLUMNS"]

#: the planners of the table, in its order (they have no column in the other tables)
TEAM_COLUMNS = ("lazy-smt-team", "milp-team", "prioritized")
#: the issue's time targets, by case: (seconds, what)
TARGETS = {"smc-crossing": 0.5, "antipodal-8": 10.0, "antipodal-16": 60.0}


def _horizon(c: Cell | None) -> str:
    if c is None:
        return "-"
    if c.solved and c.horizon is not None:
        minimal = (c.extra or {}).get("minimal", {}).get("minimal")
        return f"{c.horizon}{'' if minimal else '*'}"
    return "-"


def team_table(cells: Mapping[tuple[str, str], Cell]) -> list[str]:
    """The team family's Markdown lines (none without a run)."""
    insts = instances_of(cells, "team")
    if not insts:
        return []
    order = list(_case_order())
    insts.sort(key=lambda kv: order.index(kv[1]["name"]) if kv[1]["name"] in order else len(order))
    L = [
        "### Teams of robots and moving obstacles: joint lazy SMT vs the joint big-M MILP and prioritized planning",
        "",
        "The `team` family (`plansynth.reach.team.families`): SMC-LTL's two-robot crossing with its numbers, "
        "a corridor swap with one passing bay, four robots exchanging a room's corners around a pillar, the "
        "lazy paper's maze-n with 2 and 4 robots entering from both ends, 8 and 16 robots crossing a 10 x 10 "
        "room to antipodal points, a vehicle patrolling a maze's gap, and a corridor too narrow to pass "
        "(infeasible). `lazy-smt-team` and `milp-team` decide the same encoding (per-robot regions with "
        "segment safety, one side of each pair's forbidden polygon per step); their `infeasible` is relative "
        "to it. `milp-team` tries every horizon upwards from the same bound, so its horizon is the least of "
        "the encoding; `lazy-smt-team` sets a horizon aside after some refuted plans (horizons marked `*` "
        "are not proved minimal). `prioritized` plans the robots in the order given, each among the earlier "
        "ones as moving obstacles; its failure is `unknown`. Every plan is checked by the independent team "
        "validator.",
        "",
        "| instance | robots | lazy-smt-team | horizon | milp-team | horizon | milp-team / lazy-smt-team | prioritized |",
        "|---|---|---|---|---|---|---|---|",
    ]
    ratios, bounds = [], []
    prioritized_failed = []
    for exp, setup in insts:
        a, b, c = (cells.get((exp, p)) for p in TEAM_COLUMNS)
        rv = ratio_value(b, a)
        if rv is not None:
            (ratios if rv[1] == "=" else bounds).append(rv[0])
        robots = ((a or b or c).extra or {}).get("counters", {}).get("robots", "-") if (a or b or c) else "-"
        if c is not None and not c.solved and (a is not None and a.solved):
            prioritized_failed.append(setup["name"])
        L.append(
            f"| {setup['name']} | {robots} | {a.text() if a else '-'} | {_horizon(a)} | {b.text() if b else '-'} | "
            f"{_horizon(b)} | {ratio(b, a)} | {c.text() if c else '-'} |"
        )
    L.append("")
    both = ratios + bounds
    if both:
        L.append(
            f"Median speed-up of lazy-smt-team over milp-team: **{statistics.median(both):.3g}x** over {len(both)} "
            f"instances both decided or one ran out of time ({len(bounds)} of them bounds: the MILP's time limit "
            "counts as its time)"
            + (f"; over the {len(ratios)} both decided: {statistics.median(ratios):.3g}x." if ratios else ".")
        )
    if prioritized_failed:
        L.append(f"Solved by lazy-smt-team where prioritized planning fails: {', '.join(prioritized_failed)}.")
    met = []
    for case, limit in TARGETS.items():
        exp = f"reach/team/{case}"
        a = cells.get((exp, "lazy-smt-team"))
        if a is not None:
            t = a.median if a.solved else None
            met.append(f"{case} {fmt(t)} s (target < {limit:g} s{'' if t is not None and t < limit else ': missed'})")
    if met:
        L.append("Time targets of lazy-smt-team: " + "; ".join(met) + ".")
    L.append("")
    return L


def _case_order() -> tuple[str, ...]:
    from plansynth.reach.team.families import TEAM_CASES

    return tuple(TEAM_CASES)
