"""The tables of the runs timed through the CLI: the shared reactive suite and the doors
and patrols families, each run a ``plansynth grid solve FILE --timeout T`` process.

Per instance and solver: the process's wall clock, the solve time, the answer against
the certified label, the program depth against the label's witness, ``depth_minimal``
and whether the budget was kept; a summary line per solver first.
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence
from typing import Any

from plansynth.bench.report.cells import Cell, fmt, instances_of

__all__ = ["CLI_TIMED_NOTE", "cli_timed_sections", "suite_table"]

CLI_TIMED_NOTE = (
    "Each run is `plansynth grid solve FILE --solver S --timeout T` in a fresh process, as a user "
    "runs it: *wall* is that process's wall clock from spawn to exit (start-up included), *solve* the "
    "time the result file reports; *budget kept*: wall <= T + 1 s (the CLI's budget promise). *depth - "
    "witness*: the program's depth minus the depth of the label's witness program."
)


def cli_timed_sections(cells: Mapping[tuple[str, str], Cell], planners: Sequence[str]) -> list[str]:
    """The shared reactive suite's section, then the doors and patrols families'."""
    L: list[str] = []
    suite = instances_of(cells, "reactive-suite")
    if suite:
        L.append("### The shared reactive suite (family `reactive-suite`: 40 problems with certified labels)")
        L.append("")
        L.append(CLI_TIMED_NOTE)
        L.append("")
        L.extend(suite_table(cells, suite, planners))
        L.append("")
    doors = [i for f in ("doors", "doors-rush", "doors-jam", "patrols", "patrols-walk") for i in instances_of(cells, f)]
    if doors:
        L.append(
            "### Doors that close and guards that patrol (families `doors`, `doors-rush`, `doors-jam`, "
            "`patrols`, `patrols-walk`; labels certified by brute force)"
        )
        L.append("")
        L.append(CLI_TIMED_NOTE)
        L.append("")
        L.extend(suite_table(cells, doors, planners))
        L.append("")
    return L


def _answer(c: Cell | None) -> str:
    if c is None:
        return "-"
    if c.solved:
        return "realizable" if c.all_solved else f"realizable ({c.solved}/{c.runs})"
    return "/".join(sorted(c.statuses))


def suite_table(
    cells: Mapping[tuple[str, str], Cell], insts: Sequence[tuple[str, dict[str, Any]]], planners: Sequence[str]
) -> list[str]:
    """Per instance and solver (the CLI timing targets): the wall time of the run through the
    CLI in a fresh process (start-up included), the solve time the result reports, the
    answer and whether it matches the certified label, the program depth, depth minus
    the label's witness depth, ``depth_minimal``, and whether ``--timeout T`` was kept
    (the process ended within T + 1 s). A summary line per solver comes first."""
    hdr = ["instance", "label", "witness depth"]
    for p in planners:
        hdr += [
            f"{p} wall (s)",
            f"{p} solve (s)",
            f"{p} answer",
            f"{p} matches",
            f"{p} depth",
            f"{p} depth - witness",
            f"{p} depth_minimal",
            f"{p} budget kept",
        ]
    rows = ["| " + " | ".join(hdr) + " |", "|" + "---|" * len(hdr)]
    summary: dict[str, dict[str, list[Any]]] = {
        p: {"ok": [], "wrong": [], "wall": [], "dd": [], "kept": [], "proved": []} for p in planners
    }
    for exp, setup in insts:
        wd = (setup.get("params") or {}).get("witness_depth")
        expected = setup.get("expected")
        row = [setup["name"], str(expected or "-"), str(wd if wd is not None else "-")]
        for p in planners:
            c = cells.get((exp, p))
            if c is None:
                row += ["-"] * 8
                continue
            ex = c.extra or {}
            ok = (expected == "realizable" and c.all_solved) or (
                expected == "unrealizable" and set(c.statuses) == {"unrealizable"}
            )
            # a wrong answer contradicts the label; unknown or timeout is no answer
            wrong = (expected == "realizable" and "unrealizable" in c.statuses) or (
                expected == "unrealizable" and c.solved > 0
            )
            t = c.median if c.solved else c.median_any
            wall = ex.get("cli_wall")
            kept = ex.get("budget_kept") or []
            dd = "-"
            if c.solved and c.depth is not None and wd is not None:
                dd = f"{c.depth - int(wd):+d}"
                summary[p]["dd"].append(c.depth - int(wd))
            if c.solved and ex.get("depth_minimal"):
                summary[p]["proved"].append(ex.get("depth_minimal") == "proved")
            summary[p]["ok"].append(ok)
            summary[p]["wrong"].append(wrong)
            if wall is not None:
                summary[p]["wall"].append(float(wall))
            summary[p]["kept"] += kept
            row += [
                fmt(wall),
                fmt(t),
                _answer(c),
                "yes" if ok else "WRONG" if wrong else "no answer",
                str(c.depth) if c.solved and c.depth is not None else "-",
                dd,
                str(ex.get("depth_minimal") or "-") if c.solved else "-",
                ("yes" if all(kept) else "NO") if kept else "-",
            ]
        rows.append("| " + " | ".join(row) + " |")
    lines = [_suite_summary(p, summary[p]) for p in planners if summary[p]["ok"]]
    return lines + [""] + rows


def _suite_summary(planner: str, sm: Mapping[str, list[Any]]) -> str:
    """One line: correct answers, median and max CLI wall, depth against the witnesses,
    budgets kept (the CLI timing targets, in the order they are stated)."""
    wall = (
        f"wall through the CLI median {fmt(statistics.median(sm['wall']))} s, max {fmt(max(sm['wall']))} s"
        if sm["wall"]
        else "no CLI wall recorded"
    )
    dd = (
        f"depth - witness depth median {statistics.median(sm['dd']):+g}, max {max(sm['dd']):+d} "
        f"({len(sm['dd'])} programs)"
        if sm["dd"]
        else "no depth against a witness"
    )
    kept = f"budget kept {sum(sm['kept'])}/{len(sm['kept'])}" if sm["kept"] else "budget not recorded"
    proved = f"; depth_minimal proved on {sum(sm['proved'])}/{len(sm['proved'])}" if sm["proved"] else ""
    return (
        f"- **{planner}**: correct {sum(sm['ok'])}/{len(sm['ok'])} ({sum(sm['wrong'])} contradict the label); "
        f"{wall}; {dd}; {kept}{proved}."
    )
