"""The reactive synthesis competition's robot benchmarks in the report: the
moving-obstacle family beside omega (the peer, in the same run) and the published SLUGS
times (their machine), and the robot-grid families beside omega.

The native engine's time is the whole answer: the game decided, a program learnt and
verified by the independent verifier (an inductive invariant for the safety games), or
the "no" certified by the obstacles' strategy. Beside it, ``decided`` is the time at
which its answer was known (the game solved, and for a "no" certified), the part that
compares with a realizability check. omega's time is its realizability and, when
realizable, its strategy (a BDD transducer).
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping, Sequence

from plansynth.bench.report.cells import Cell, fmt, instances_of

__all__ = ["syntcomp_sections", "SLUGS_NOTE"]

SLUGS_NOTE = (
    "*slugs*: the times Ehlers' description publishes (Table I; SLUGS of 21 Feb 2014, realizability only, "
    "on an AMD E-450 at 1.6 GHz with 4 GB, x86 Linux), not rerun here."
)


def _decided(c: Cell | None) -> float | None:
    if c is None or c.decided_time() is None:
        return None
    d = (c.extra or {}).get("counters", {}).get("decided_seconds")
    return float(d) if isinstance(d, (int, float)) else c.decided_time()


def _answer(c: Cell | None) -> str:
    if c is None:
        return "-"
    if c.all_solved:
        return "realizable"
    return "/".join(sorted(c.statuses))


def _ratio(a: float | None, b: float | None) -> float | None:
    return None if a is None or b is None else a / max(b, 1e-6)


def syntcomp_sections(cells: Mapping[tuple[str, str], Cell], planners: Sequence[str]) -> list[str]:
    """The SYNTCOMP families' tables and the ratios quoted in the closing note; none
    without a run of them."""
    L: list[str] = []
    mo = instances_of(cells, "moving-obstacle")
    if mo:
        L += _moving_obstacle(cells, mo)
    rg = instances_of(cells, "robot-grid") + instances_of(cells, "robot-grid-fast")
    if rg:
        L += _robot_grid(cells, rg)
    return L


def _moving_obstacle(cells, insts) -> list[str]:
    L = [
        "### SYNTCOMP: robot-on-a-grid moving obstacle evasion (family `moving-obstacle`, Ehlers)",
        "",
        "Safety games: a 2 x 2 obstacle that moves at most every second step except for c glitches; the robot must "
        "never be in its block. *native*: decided, a program learnt and verified (an inductive invariant checked by "
        'the independent verifier), or the "no" certified by the obstacles\' rank strategy; *decided*: when its '
        "answer was known. *omega*: realizability and, if realizable, its BDD strategy (checked), in the same run. Neither time counts module imports (omega's clock starts after omega and dd are imported, native's after its engine and verifier are). "
        + SLUGS_NOTE,
        "",
        "| instance | published | slugs (s) | native (s) | native decided (s) | native depth | omega (s) | "
        "omega / native | omega / native decided |",
        "|" + "---|" * 9,
    ]
    full, decided = [], []
    for exp, setup in insts:
        n, o = cells.get((exp, "native")), cells.get((exp, "omega"))
        tn, to, td = (n.decided_time() if n else None), (o.decided_time() if o else None), _decided(n)
        r_full, r_dec = _ratio(to, tn), _ratio(to, td)
        if r_full is not None:
            full.append(r_full)
        if r_dec is not None:
            decided.append(r_dec)
        L.append(
            "| "
            + " | ".join(
                [
                    setup["name"],
                    str(setup.get("expected") or "unknown"),
                    fmt(setup.get("paper_seconds")),
                    n.text() if n else "-",
                    fmt(td),
                    str(n.depth) if n and n.depth else "-",
                    o.text() if o else "-",
                    f"{r_full:.3g}" if r_full else "-",
                    f"{r_dec:.3g}" if r_dec else "-",
                ]
            )
            + " |"
        )
    L.append("")
    if full:
        L.append(
            f"**Ratios, one run** (omega / native on the {len(full)} instances both decided): median "
            f"{statistics.median(full):.3g}x on the whole answer, {statistics.median(decided):.3g}x on the "
            f"decision (range {min(full):.3g}x-{max(full):.3g}x and {min(decided):.3g}x-{max(decided):.3g}x)."
        )
        L.append("")
    return L


def _robot_grid(cells, insts) -> list[str]:
    L = [
        "### SYNTCOMP: after robot_grid (families `robot-grid`, `robot-grid-fast`)",
        "",
        "Recurrence games on the 8 x 16 maps of `tlsf/robot_grid`: every pickup and drop station in turn, forever, "
        "past one obstacle in the fenced corridor, moving at odd ticks (`robot-grid`) or every step "
        '(`robot-grid-fast`). *native*: a program that reads the mode, verified, or the "no" certified by the '
        "obstacles' strategy (`plansynth grid explain` plays it). *omega*: TuLiP's GR(1) encoding, each goal a "
        "`[]<>` guarantee.",
        "",
        "| instance | expected | native (s) | native depth | reads the mode | omega (s) | omega / native |",
        "|" + "---|" * 7,
    ]
    ratios = []
    for exp, setup in insts:
        n, o = cells.get((exp, "native")), cells.get((exp, "omega"))
        r = _ratio(o.decided_time() if o else None, n.decided_time() if n else None)
        if r is not None:
            ratios.append(r)
        program = (n.extra or {}).get("program") if n else None
        reads = "-" if not program else ("yes" if " m)" in program or " m " in program else "no")
        L.append(
            "| "
            + " | ".join(
                [
                    setup["name"],
                    str(setup.get("expected") or "-"),
                    n.text() if n else "-",
                    str(n.depth) if n and n.depth else "-",
                    reads,
                    o.text() if o else "-",
                    f"{r:.3g}" if r else "-",
                ]
            )
            + " |"
        )
    L.append("")
    if ratios:
        L.append(
            f"**Ratios, one run** (omega / native on the {len(ratios)} instances both decided): median "
            f"{statistics.median(ratios):.3g}x (range {min(ratios):.3g}x-{max(ratios):.3g}x)."
        )
        L.append("")
    return L
