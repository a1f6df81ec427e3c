"""The table ``plansynth reach solve`` prints of a result: status, horizon, counters,
time per phase, guarantee, and the mission's and the disturbance's lines."""

from __future__ import annotations

from typing import Any

from rich.markup import escape
from rich.table import Table

STYLE = {"found": "bold green", "infeasible": "bold red", "unknown": "bold yellow"}


def result_table(result: Any) -> Table:
    c, t = result.counters, result.timings
    table = Table(title=f"{result.solver}: {result.status.value}", show_header=False, title_justify="left")
    table.add_column("item", style="bold")
    table.add_column("value")
    style = STYLE[result.status.value]
    table.add_row("status", f"[{style}]{result.status.value}[/{style}]")
    horizon = "-" if result.horizon is None else str(result.horizon)
    if result.status.value == "infeasible":
        horizon = f"none up to {result.horizon}"
    if result.status.value == "found" and c.get("minimal") is not None:
        relative = c.get("minimal_relative_to", "problem")  # (planners that do not say: as before)
        if c["minimal"] and relative != "problem":
            horizon += f" (minimal through the {relative} only)"
        else:
            horizon += " (proved minimal)" if c["minimal"] else " (not proved minimal)"
    table.add_row("horizon", horizon)
    if c.get("transitions") is not None:  # the lazy planner's transition relation (lazy/exactmode.py)
        table.add_row("transitions", escape(f"{c['transitions']}: exact segments {c.get('exact_segments', '-')}"))
    for key in (
        "regions",
        "first_horizon",
        "iterations",
        "sat_calls",
        "lp_calls",
        "transit_conflicts",
        "clauses",
        "milp_calls",
        "mip_nodes",
    ):
        if key in c and c[key] is not None:
            table.add_row(key.replace("_", " "), str(c[key]))
    if c.get("lp_calls_by_kind"):
        table.add_row("LP calls by kind", ", ".join(f"{k} {v}" for k, v in c["lp_calls_by_kind"].items()))
    phases = [
        k
        for k in (
            "tighten",
            "abstraction",
            "bounds",
            "guide",
            "sat",
            "lp",
            "milp",
            "validate",
            "mission_check",
            "robust_check",
        )
        if k in t
    ]
    table.add_row("time per phase", ", ".join(f"{k} {t[k]:.3f} s" for k in phases))
    table.add_row("total time", f"{result.seconds:.3f} s")
    if result.solver_version:
        table.add_row("solver", escape(f"{result.solver} ({result.solver_version})"))
    if result.validated is not None:
        table.add_row("validated", "[green]yes[/green]" if result.validated else "[red]NO[/red]")
    if result.guarantee is not None:
        held = (
            "" if result.segment_safe is None else (", segments safe" if result.segment_safe else ", segments NOT safe")
        )
        table.add_row("guarantee", f"{result.guarantee}{held}")
    mission = getattr(result, "mission", None)
    if mission and mission.get("semantics"):  # LTL missions
        loop = "" if mission.get("loop_start") is None else f", loop from step {mission['loop_start']} (x_N = x_k)"
        verdict = {True: ", mission checked", False: ", mission check FAILED"}.get(mission.get("ok"), "")
        end = ", free end" if mission.get("semantics") == "finite" and mission.get("end") == "free" else ""
        table.add_row("mission", escape(f"{mission['formula']}: {mission['semantics']} plan{end}{loop}{verdict}"))
        margins = {n: r for n, r in (mission.get("margins") or {}).items() if r}
        asked = ", ".join(f"{n} {r:g}" for n, r in margins.items()) or "none"
        achieved = mission.get("robustness")
        table.add_row(
            "reading",
            escape(
                f"{mission.get('reading', 'segment')}; margins asked: {asked}; achieved margin: "
                + ("-" if achieved is None else f"{achieved:.4g}")
            ),
        )
    robust = getattr(result, "robust", None)
    if robust:  # under a disturbance (plansynth.reach.robust)
        for key, value in _robust_rows(robust, result.status.value == "found"):
            table.add_row(key, escape(value))
    if result.message:
        table.add_row("message", escape(result.message))
    return table


def _robust_rows(robust: dict[str, Any], found: bool) -> list[tuple[str, str]]:
    """The lines of a robust result: what it guarantees (or what a missing plan is
    relative to), the feedback law and gain, the margins, the worst-case check (a team:
    per robot, and how the separation is tightened)."""
    rows = [("robust", robust["guarantee"] if found else robust["relative_to"])]
    if "robots" in robust:  # a team (plansynth.reach.team.robust)
        for name, own in robust["robots"].items():
            rows += _feedback_rows(robust["law"], own, f" {name}")
        rows.append(("separation", robust["separation"]))
    else:
        rows += _feedback_rows(robust["law"], robust, "")
    check = robust.get("check")
    if check is not None:
        verdict = "passed" if check["ok"] else "FAILED"
        room = "" if check.get("clearance") is None else f", worst-case clearance {check['clearance']:.3g}"
        rows.append(("robust check", f"{verdict}: the worst case at every step{room}"))
    return rows


def _feedback_rows(law: str, robust: dict[str, Any], who: str) -> list[tuple[str, str]]:
    """The feedback law and gain and the margins of one robot's design."""
    fb, mg = robust["feedback"], robust["margins"]
    gain = "; ".join(", ".join(f"{v + 0.0:.4g}" for v in row) for row in fb["gain"])
    grown = [max(a, b) for a, b in zip(mg["obstacles_grown_by"]["lo"], mg["obstacles_grown_by"]["hi"])]
    u = max([*mg["input_bound_at_most"]["lo"], *mg["input_bound_at_most"]["hi"]], default=0.0)
    return [
        (f"feedback{who}", f"{law}, K = [{gain}]: {fb['how']}"),
        (
            f"margins{who}",
            "obstacles grown by "
            + ", ".join(f"{v:.4g}" for v in grown)
            + f" (the tube's largest cross-section); state bounds, workspace, input bound (by up to {u:.4g}) "
            f"and goal tightened by E_t at every step (exact for {mg['exact_steps']} steps, then bounded)",
        ),
    ]
