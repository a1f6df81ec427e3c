"""The published sweep behind ``benchmarks/RESULTS.md`` (``plansynth bench publish``).

One command reruns it (resuming whatever is already in the database) and regenerates
the Markdown report with its figures:

    plansynth bench publish                  # run/resume the sweep, then write RESULTS.md
    plansynth bench publish --report-only    # only rewrite RESULTS.md from the database

Beside RESULTS.md it writes RESULTS.html, the same report as one self-contained page
with the figures embedded (unless ``html`` is False: ``--no-html``).

The sweep: every grid family with ``native`` and ``cvc5`` (the reactive suite and the
doors and patrols families once, through the CLI, at :data:`CLI_TIMED_TIMEOUT`; the
SYNTCOMP families with ``native`` and the ``omega`` peer, moving obstacle at
:data:`MOVING_OBSTACLE_TIMEOUT` and :data:`SYNTCOMP_MEMORY_MB`); the mazes with ``lazy-smt``,
``rrt``, ``milp-bigm``, ``milp``, the curve baselines :data:`CURVE_BASELINES` (Drake's Graphs
of Convex Sets over overlapping sets and over our regions, fast path planning: continuous-time
curves, not trajectories of the exact discrete dynamics; RESULTS.md says so beside their
columns) and ``lazy-smt-window`` (the window search alone), and with the counterexample configurations of
:data:`~plansynth.bench.report.CX_VARIANTS`; the integrator-chain scaling (Figure 4) up
to order 25 (n = 50 states) with ``lazy-smt``; random workspaces with every reach planner;
the GCS paper's mazes (the scale family, :data:`~plansynth.bench.families.GCS_MAZE_SIZES`)
with :data:`SCALE_PLANNERS`; the mazes under bounded disturbances (``robust``: :func:`robust_tasks`).
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

from plansynth.bench.families import CLI_TIMED_FAMILIES, GRID_FAMILIES, family
from plansynth.bench.families.grid_syntcomp import SYNTCOMP_FAMILIES
from plansynth.bench.report import CX_VARIANTS
from plansynth.bench.runner import run_sweep
from plansynth.bench.tasks import make_tasks
from plansynth.io import write_output

__all__ = ["published_tasks", "publish", "robust_tasks"]

GRID_SOLVERS = ["native", "cvc5"]
MAZE_PLANNERS = ["lazy-smt", "rrt", "milp-bigm", "milp"]
CHAIN_ORDERS = [1, 2, 3, 5, 10, 25]  # 25: n = 50 states, the paper's largest (Figure 4)
CX_TIMEOUT = 300.0  # the paper's loop on maze-3/4 runs for minutes
N50_TIMEOUT = 300.0  # order-25 chains (n = 50 states)
N50_REPEATS = 3  # the scalability target is on maze-4 at order 25: a median, not one run
RRT_REPEATS = 3
GCS_REPEATS = 3
GCS_MAZE_TIMEOUT = 120.0  # the scale family: lazy-smt's targets are 2 s (50 x 50) and 20 s (100 x 100)
#: FPP on the 100 x 100 maze's 5,951 boxes takes over a minute on a quiet machine: it gets longer
FPP_MAZE_TIMEOUT = 300.0
#: GCS on the scale family gets as long: Drake fixes each solver's share of the budget
#: before it starts (the relaxation 40%, the rounded paths' restrictions 40%), and at
#: 120 s the 20 x 20 maze's IPOPT restriction (a 150-piece path) stopped at its share
#: of 48 s without a curve, where with 300 s the disjoint-region variant finds one in 18 s
GCS_SCALE_TIMEOUT = 300.0
#: lazy-smt-minimal on the scale family: re-timing and probes below the timed route's plan for this long
MINIMAL_MAZE_TIMEOUT = 60.0
#: the baselines that plan continuous-time curves (gcs over overlapping sets and over our regions, fpp)
CURVE_BASELINES = ["gcs", "gcs-decomposition", "fpp"]
#: every planner of the scale family (the GCS paper's mazes), with their limits
SCALE_PLANNERS = {
    "lazy-smt": GCS_MAZE_TIMEOUT,
    "lazy-smt-window": GCS_MAZE_TIMEOUT,
    "lazy-smt-minimal": MINIMAL_MAZE_TIMEOUT,
    "gcs": GCS_SCALE_TIMEOUT,
    "gcs-decomposition": GCS_SCALE_TIMEOUT,
    "fpp": FPP_MAZE_TIMEOUT,
}
RANDOM_DYNAMICS_STATES = (4, 10, 20, 50)
NATIVE_REPEATS = 3
#: ``--timeout`` of the families run through the CLI (reactive suite, doors): the targets
#: ask for answers within 1 s, and with 10 s the 55 instances x 2 solvers finish in about
#: 15 minutes on a shared 2-core machine (cvc5 answers few of them within any limit).
CLI_TIMED_TIMEOUT = 10.0
#: The SYNTCOMP families (plansynth.bench.families.grid_syntcomp): the native engine beside
#: the omega peer. The moving-obstacle targets: 64 x 64 within 60 s, 96 x 96 and 128 x 128
#: within 10 minutes and 16 GiB (else unknown saying which resource ran out).
SYNTCOMP_SOLVERS = ["native", "omega"]
MOVING_OBSTACLE_TIMEOUT = 600.0
SYNTCOMP_MEMORY_MB = 16384
ROBOT_GRID_TIMEOUT = 120.0
#: the missions family: a limit the milp-ltl baseline finishes within (patrol, its
#: slowest, about 13 s on a quiet machine), so that the speed-up is a measured ratio, not a bound
MISSIONS_TIMEOUT = 300.0
#: the robust family (plans under bounded disturbances): the robust MILP on maze-4 needs
#: minutes, and a lazy-smt run at scale 1 also simulates 2,000 runs and bisects the scale
ROBUST_TIMEOUT = 300.0


def published_tasks(grid_timeout: float = 60.0, reach_timeout: float = 60.0, part: str = "all") -> list[dict[str, Any]]:
    """The tasks of the published sweep (``part``: all, grid, reach, or robust: the
    robust family alone, which the reach part includes)."""
    tasks: list[dict[str, Any]] = []
    if part == "robust":
        return robust_tasks(max(reach_timeout, ROBUST_TIMEOUT))
    if part in ("all", "reach"):
        tasks += make_tasks(family("reach", "maze"), MAZE_PLANNERS, timeout=reach_timeout)
        # the sampling planners vary with the seed: more repeats (seed + repeat)
        tasks += [
            t
            for t in make_tasks(family("reach", "maze"), ["rrt", "lazy-smt"], repeat=RRT_REPEATS, timeout=reach_timeout)
            if t["repeat"] > 0
        ]
        # counterexamples compared (Section V): the paper's loop with ZEROPREFIX / trivial, ours with ZEROPREFIX
        tasks += make_tasks(family("reach", "maze"), list(CX_VARIANTS), timeout=max(reach_timeout, CX_TIMEOUT))
        tasks += make_tasks(
            family("reach", "random", [0, 1, 2]), ["lazy-smt", "rrt", "milp-bigm"], timeout=reach_timeout
        )
        # LTL missions: three per maze, lazy-smt and the milp-ltl baselines side by side
        # (horizons upward from the proved bound, and Wolff et al.'s one MILP at the max horizon)
        tasks += make_tasks(
            family("reach", "missions"),
            ["lazy-smt", "milp-ltl", "milp-ltl-oneshot"],
            timeout=max(reach_timeout, MISSIONS_TIMEOUT),
        )
        # the planning literature's scenarios (keys and doors, target groups, dwell, stepping
        # stones, obstacles as labels; the sample reading): lazy-smt and milp-ltl side by side
        tasks += make_tasks(
            family("reach", "missions-literature"),
            ["lazy-smt", "milp-ltl"],
            timeout=max(reach_timeout, MISSIONS_TIMEOUT),
        )
        tasks += make_tasks(
            family("reach", "chain", [1, 2, 3, 4], orders=CHAIN_ORDERS[:-1]), ["lazy-smt"], timeout=reach_timeout
        )
        tasks += robust_tasks(max(reach_timeout, ROBUST_TIMEOUT))
        # the curve baselines (Drake's GCS over overlapping sets and over our regions, fpp) and the
        # window search alone beside lazy-smt on the mazes, interleaved, medians of 3
        tasks += make_tasks(
            family("reach", "maze"), [*CURVE_BASELINES, "lazy-smt-window"], repeat=GCS_REPEATS, timeout=reach_timeout
        )
        # the horizon proved minimal beside the window search, medians of 3
        tasks += make_tasks(family("reach", "maze"), ["lazy-smt-minimal"], repeat=GCS_REPEATS, timeout=reach_timeout)
        # the GCS paper's n x n mazes (the scale family): every planner on the same instances,
        # interleaved (instance by instance)
        for inst in family("reach", "gcs-maze"):
            for planner, limit in SCALE_PLANNERS.items():
                tasks += make_tasks([inst], [planner], timeout=max(reach_timeout, limit))
        # Figure 4 with random dynamics (the paper's setting): seeded random controllable (A, B)
        tasks += make_tasks(
            family("reach", "random-dynamics", [1, 2, 3, 4], states=RANDOM_DYNAMICS_STATES),
            ["lazy-smt"],
            timeout=max(reach_timeout, N50_TIMEOUT),
        )
        # n = 50 states: the scalability target, with a longer limit so that it is measured
        tasks += make_tasks(
            family("reach", "chain", [1, 2, 3, 4], orders=CHAIN_ORDERS[-1:]),
            ["lazy-smt"],
            repeat=N50_REPEATS,
            timeout=max(reach_timeout, N50_TIMEOUT),
        )
    if part in ("all", "grid"):
        # Small instances first, so that an interrupted sweep still covers every figure.
        insts = [
            i for f in GRID_FAMILIES if f != "reactive-suite" and f not in SYNTCOMP_FAMILIES for i in family("grid", f)
        ]
        try:  # the shared suite lives beside the repository; say so when it is not there
            insts += family("grid", "reactive-suite")
        except FileNotFoundError as exc:
            print(f"note: reactive-suite left out of the sweep: {exc}")
        insts.sort(key=lambda i: (i.family not in ("figure1", "depth"), (i.paper_seconds or 0)))
        timed = [i for i in insts if i.family in CLI_TIMED_FAMILIES]
        insts = [i for i in insts if i.family not in CLI_TIMED_FAMILIES]
        tasks += make_tasks(insts, GRID_SOLVERS, timeout=grid_timeout)
        # native answers in milliseconds: repeat it for medians (cvc5 once: its runs take minutes)
        tasks += [
            t for t in make_tasks(insts, ["native"], repeat=NATIVE_REPEATS, timeout=grid_timeout) if t["repeat"] > 0
        ]
        # through the CLI, one sweep with native and cvc5 side by side (the CLI timing targets)
        tasks += make_tasks(timed, GRID_SOLVERS, timeout=CLI_TIMED_TIMEOUT)
        # SYNTCOMP's robot benchmarks: native and the omega peer in one run, side by side
        tasks += make_tasks(
            family("grid", "moving-obstacle"),
            SYNTCOMP_SOLVERS,
            timeout=MOVING_OBSTACLE_TIMEOUT,
            memory_mb=SYNTCOMP_MEMORY_MB,
        )
        tasks += make_tasks(
            family("grid", "robot-grid") + family("grid", "robot-grid-fast"),
            SYNTCOMP_SOLVERS,
            timeout=ROBOT_GRID_TIMEOUT,
        )
    return tasks


def robust_tasks(timeout: float = ROBUST_TIMEOUT) -> list[dict[str, Any]]:
    """The robust family's runs: lazy-smt everywhere; on the mazes at scale 1 also the
    robust MILP (milp-bigm on the tightened problem) and the nominal plan followed by the
    check; on the mission also milp-ltl; on the team lazy-smt-team and milp-team; an
    instance's runs one after the other.

    >>> sorted({t["solver"] for t in robust_tasks()})
    ['lazy-smt', 'lazy-smt-team', 'milp-bigm', 'milp-ltl', 'milp-team', 'nominal-check']
    """
    tasks: list[dict[str, Any]] = []
    from plansynth.bench.families.reach import ROBUST_TEAM

    robust = family("reach", "robust") + family("reach", "robust", [ROBUST_TEAM])
    for inst in robust:  # each instance's planners one after the other (interleaved)
        if "team" in inst.params:  # a team under disturbances: the team planners
            tasks += make_tasks([inst], ["lazy-smt-team", "milp-team"], timeout=timeout)
            continue
        solvers = ["lazy-smt"]
        if "mission" in inst.params:
            solvers.append("milp-ltl")
        elif inst.params.get("scale") == 1.0 and "narrow" not in inst.params:
            solvers += ["milp-bigm", "nominal-check"]
        tasks += make_tasks([inst], solvers, timeout=timeout)
    return tasks


def publish(
    db: str | Path,
    out: str | Path,
    *,
    run: bool = True,
    grid_timeout: float = 60.0,
    reach_timeout: float = 60.0,
    jobs: int = 1,
    cluster: str | None = None,
    part: str = "all",
    html: bool = True,
) -> Path:
    """Run (resume) the published sweep unless ``run`` is False; write ``out/RESULTS.md``
    (and ``out/RESULTS.html`` when ``html``)."""
    from plansynth.bench.report import write_html, write_report

    tasks = published_tasks(grid_timeout, reach_timeout, part)
    if run:
        run_sweep(db, tasks, jobs=jobs, cluster=cluster, progress=True)
    out = Path(out)
    fig_dir = out / "results"
    planned = [(t["experiment"], t["solver"], int(t["repeat"])) for t in published_tasks(grid_timeout, reach_timeout)]
    report = write_report(
        db,
        fig_dir,
        title="plansynth: both papers' evaluations, reproduced side by side with peers",
        planned=planned,
        image_prefix="results/",
        html=False,
    )
    text = report.read_text(encoding="utf-8")
    report.unlink()
    header = "<!-- generated by `plansynth bench publish --report-only` from the results database; do not edit -->\n"
    limits = "\n" + _limits_text(db) + "\n"
    lines = text.splitlines()
    # keep the title first, then our notes
    path = out / "RESULTS.md"
    write_output(path, header + lines[0] + "\n" + limits + "\n".join(lines[1:]) + "\n")
    if html:
        write_html(path)
    return path


def _limits_text(db: str | Path) -> str:
    """Which time limits the recorded runs had, per kind and solver (read from the database)."""
    from collections import defaultdict

    from plansynth.bench.db import ResultsDB

    limits: dict[tuple[str, str], dict[float, int]] = defaultdict(lambda: defaultdict(int))
    with ResultsDB(db) as d:
        for r in d.runs():
            lim = (r["attributes"] or {}).get("timelimit") or r["timelimit"]
            limits[(r["kind"], r["planner"])][float(lim or 0)] += 1
    parts = []
    for (kind, planner), by in sorted(limits.items()):
        parts.append(f"{kind} {planner}: " + ", ".join(f"{n} runs at {lim:g} s" for lim, n in sorted(by.items())))
    return (
        "Time limits of the recorded runs (each cell's own limit is the one shown): " + "; ".join(parts) + ". "
        "One run at a time per sweep process; up to two sweep processes ran side by side on a 2-core machine "
        "shared with other jobs, so times carry noise of tens of percent (counts of LPs, SAT calls and "
        "iterations do not)."
    )


def main() -> None:  # pragma: no cover - used to run one part in the background
    import argparse

    ap = argparse.ArgumentParser(description="run one part of the published sweep")
    ap.add_argument("--db", required=True)
    ap.add_argument("--part", choices=["all", "grid", "reach", "robust"], default="all")
    ap.add_argument("--grid-timeout", type=float, default=60.0)
    ap.add_argument("--reach-timeout", type=float, default=60.0)
    ap.add_argument("--retry", default="", help="comma-separated statuses to rerun, e.g. crash")
    a = ap.parse_args()
    tasks = published_tasks(a.grid_timeout, a.reach_timeout, a.part)
    t0 = time.time()
    counts = run_sweep(
        a.db,
        tasks,
        progress=False,
        retry=[s for s in a.retry.split(",") if s],
        on_result=lambda t, r: print(
            json.dumps(
                {"run": [t["experiment"], t["solver"], t["repeat"]], "status": r.get("status"), "time": r.get("time")}
            ),
            flush=True,
        ),
    )
    print(json.dumps({"counts": counts, "seconds": time.time() - t0}), flush=True)


if __name__ == "__main__":  # pragma: no cover
    main()
