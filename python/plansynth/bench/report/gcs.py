"""The convex-optimisation baselines beside lazy SMT: Graphs of Convex Sets (Marcucci et
al., Science Robotics 2023, through Drake) over overlapping sets and over our regions,
and fast path planning (Marcucci, Nobel, Tedrake and Boyd, IEEE T-RO 2024), on the mazes
and on the GCS paper's own n x n mazes (the scale family).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from plansynth.bench.report.cells import Cell, fmt, instances_of
from plansynth.bench.report.ratios import ratio, ratio_value

__all__ = ["gcs_table", "gcs_maze_table", "CURVE_PLANNERS"]

#: the baselines that return continuous-time curves, in table order, and what they are
CURVE_PLANNERS = {
    "gcs": "gcs (overlapping sets)",
    "gcs-decomposition": "gcs-decomposition (our regions)",
    "fpp": "fpp (boxes)",
}


def _duration(c: Cell | None) -> float | None:
    """The plan's duration in seconds (horizon x dt; a curve re-timed to whole steps)."""
    return (c.extra or {}).get("duration") if c is not None and c.solved else None


def _setups() -> list[str]:
    from plansynth.reach.planners.fpp import GUARANTEE as FPP
    from plansynth.reach.planners.gcs import GUARANTEE as GCS

    return [
        '`gcs`: Marcucci, Petersen, von Wrangel and Tedrake, "Motion planning around obstacles with convex '
        "optimization\", Science Robotics 2023, through Drake's `GcsTrajectoryOptimization`, set up as its users "
        "set it up: over *overlapping* convex sets, the maximal free boxes grown from the obstacle grid (where "
        "obstacles are polygons, Drake's IRIS regions), an edge where two sets overlap; Bezier order 5, velocity "
        "continuity, |v| and |a| bounds of the problem, start at rest, the goal box as the target set, Clarabel "
        "relaxation + IPOPT rounding (5 rounded paths up to 200 sets, 1 beyond), time in units of 10 s. "
        "`gcs-decomposition`: the same over the lazy planner's disjoint regions, which touch only along faces "
        "(the setup this report used before). `fpp`: fast path planning (Marcucci, Nobel, Tedrake and Boyd, IEEE "
        "T-RO 2024, the authors' `fastpathplanning` library) through the same maximal boxes, as its examples set "
        "it up (the jerk's squared norm, the goal's centre as its terminal point), from rest; it plans no "
        "dynamics and no bounds, so its curve is re-timed uniformly to the shortest duration at which |v| and |a| "
        "stay within the problem's bounds (exact: FPP's optimal curve for a longer duration is the same curve, "
        "slower).",
        "",
        "**The guarantees differ**: lazy-smt returns a trajectory of the exact discrete dynamics x' = A x + B u "
        f"(|u| <= 1, every sample and segment free); gcs returns a {GCS}; fpp returns a {FPP}.",
    ]


def gcs_table(cells: Mapping[tuple[str, str], Cell], mazes: Sequence[tuple[str, dict[str, Any]]]) -> list[str]:
    """The curve baselines beside lazy-smt on the mazes, with the difference in guarantee;
    the headline ratios are against the overlapping-set GCS."""
    used = [p for p in CURVE_PLANNERS if any((e, p) in cells for e, _ in mazes)]
    if not used:
        return []
    L = ["### Convex-optimisation baselines beside lazy SMT: Graphs of Convex Sets and fast path planning", ""]
    L += _setups()
    L += [
        "",
        "Times include the validator's checks (for the curves: the samples at dt and the dense curve, several "
        "thousand samples); *planner only* leaves them out. A plan's duration is its horizon x dt (a curve "
        "re-timed to whole steps).",
        "",
    ]
    hdr = ["maze", "lazy-smt", "its plan (s)"]
    for p in used:
        hdr += [CURVE_PLANNERS[p], "its curve (s)", f"{p} / lazy-smt"]
    hdr += [f"planner only: {used[0]} / lazy-smt"]
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))
    for exp, setup in mazes:
        lz = cells.get((exp, "lazy-smt"))
        row = [str(int(setup["params"]["n"])), lz.text() if lz else "-", fmt(_duration(lz))]
        for p in used:
            c = cells.get((exp, p))
            row += [c.text() if c else "-", fmt(_duration(c)), ratio(c, lz)]
        g = cells.get((exp, used[0]))
        gp = (g.extra or {}).get("planner_median") if g and g.solved else None
        lp = (lz.extra or {}).get("planner_median") if lz and lz.solved else None
        row.append(f"{fmt(gp)} / {fmt(lp)} = {gp / lp:.3g}" if gp and lp else "-")
        L.append("| " + " | ".join(row) + " |")
    L.append("")
    if "gcs" in used:
        L.append(
            "**Ratios to the overlapping-set GCS (time gcs / lazy-smt, one run, medians of its repeats):** "
            + "; ".join(
                f"maze-{int(s['params']['n'])}: {ratio(cells.get((e, 'gcs')), cells.get((e, 'lazy-smt')))}"
                for e, s in mazes
            )
            + "."
        )
        L.append("")
    return L


def gcs_maze_table(cells: Mapping[tuple[str, str], Cell]) -> list[str]:
    """The GCS paper's n x n mazes (the scale family): every planner of the sweep on the
    same instances in one run, its time and its plan's duration."""
    insts = sorted(instances_of(cells, "gcs-maze"), key=lambda es: int(es[1]["params"]["n"]))
    if not insts:
        return []
    from plansynth.reach.families import gcs_maze

    planners = [
        p
        for p in ("lazy-smt", "lazy-smt-window", "lazy-smt-minimal", *CURVE_PLANNERS)
        if any((e, p) in cells for e, _ in insts)
    ]
    curves = [p for p in CURVE_PLANNERS if p in planners]
    L = [
        "### The GCS paper's mazes (n x n): the scale family",
        "",
        " ".join((gcs_maze.__doc__ or "").split("\n\n")[0].split()),
        "",
        "Every planner on the same instances (`plansynth bench reach --family gcs-maze`), each with the limit "
        "`bench publish` gives it (gcs and fpp 300 s: Drake fixes each solver's share of the budget before it "
        "starts; an unknown cell shows its own limit). A time is a "
        "solved run: planned and validated (lazy-smt: the exact discrete dynamics, every sample and segment "
        "free; gcs and fpp: their continuous-time curves, see the section above). `lazy-smt` plans with the "
        "timed route (the shortest route timed by an LP and repaired where CON-PLAN finds it too tight), "
        "`lazy-smt-window` with the window search alone (the default before), `lazy-smt-minimal` re-times and "
        "probes below the timed route's plan until its budget (its best plan is reported, minimal when proved).",
        "",
    ]
    hdr = ["n", "regions / boxes", "lazy-smt: horizon, LP / SAT calls"] + planners
    hdr += [f"{p} / lazy-smt" for p in planners if p != "lazy-smt"]
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))
    for exp, setup in insts:
        lz = cells.get((exp, "lazy-smt"))
        regions = next((c.extra or {}).get("regions") for c in [lz] if c is not None) if lz else None
        boxes = next(
            (
                ((cells[(exp, p)].extra or {}).get("counters") or {}).get(k)
                for p, k in (("gcs", "regions"), ("fpp", "boxes"))
                if (exp, p) in cells and ((cells[(exp, p)].extra or {}).get("counters") or {}).get(k)
            ),
            None,
        )
        work = "-"
        if lz is not None and lz.solved:
            x = lz.extra or {}
            work = f"{lz.horizon}, {x.get('lp_calls', '-')} / {x.get('sat_calls') if x.get('sat_calls') is not None else '-'}"
        row = [str(int(setup["params"]["n"])), f"{regions if regions is not None else '-'} / {boxes or '-'}", work]
        row += [cells[(exp, p)].text() if (exp, p) in cells else "-" for p in planners]
        row += [ratio(cells.get((exp, p)), lz) for p in planners if p != "lazy-smt"]
        L.append("| " + " | ".join(row) + " |")
    L += [
        "",
        "Plan durations (seconds of motion: horizon x dt; a curve re-timed to whole steps), and lazy-smt's "
        "over the shortest any planner of the run found:",
        "",
    ]
    hdr = ["n"] + planners + ["shortest", "lazy-smt / shortest"]
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))
    for exp, setup in insts:
        durations = {p: _duration(cells.get((exp, p))) for p in planners}
        row = [str(int(setup["params"]["n"]))]
        for p in planners:
            d = durations[p]
            c = cells.get((exp, p))
            note = ""
            if p == "lazy-smt-minimal" and c is not None and c.solved:
                note = " (proved minimal)" if ((c.extra or {}).get("minimal") or {}).get("minimal") else " (not proved)"
            row.append(f"{fmt(d)}{note}" if d is not None else "-")
        known = {p: d for p, d in durations.items() if d is not None}
        short = min(known.items(), key=lambda kv: kv[1]) if known else None
        own = durations.get("lazy-smt")
        row.append(f"{fmt(short[1])} ({short[0]})" if short else "-")
        row.append(f"{own / short[1]:.3g}" if own and short else "-")
        L.append("| " + " | ".join(row) + " |")
    L.append("")
    if curves:
        big = [(e, s) for e, s in insts if int(s["params"]["n"]) >= 20]
        parts = []
        for e, s in big:
            lz = cells.get((e, "lazy-smt"))
            vals = []
            for p in curves:
                rv = ratio_value(cells.get((e, p)), lz)
                vals.append(f"{p} {ratio(cells.get((e, p)), lz)}" if rv is not None else f"{p} -")
            parts.append(f"{int(s['params']['n'])} x {int(s['params']['n'])}: " + ", ".join(vals))
        if parts:
            L.append(
                "**Speed-up of lazy-smt at 20 x 20 and above (time baseline / lazy-smt):** " + "; ".join(parts) + "."
            )
            L.append("")
    return L
