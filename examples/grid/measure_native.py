"""Measure the native grid engine against its speed targets, with cvc5 side by side.

Usage (from the repository root)::

    python examples/grid/measure_native.py                 # native only
    python examples/grid/measure_native.py --cvc5 300      # plus cvc5, 300 s per instance
    python examples/grid/measure_native.py --json out.json

Every number comes from this run: the paper's four families (Chasins & Newcomb, SYNT
2016, Section 4.1) at their path length, every shorter (unrealizable) length, the
``minimize`` option on the depth family, the reactive examples and the 64 x 64 instance.
Every program is checked by the independent verifier (``plansynth.grid.verify``).
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import time
from pathlib import Path

from plansynth.bench.families import paper_depth
from plansynth.bench.families import paper_problems as families
from plansynth.budget import Budget
from plansynth.grid.native.engine import Engine
from plansynth.grid.problem import grid_problem_from_dict, load_grid_problem
from plansynth.grid.programs import depth, reads_obstacles
from plansynth.grid.result import GridStatus
from plansynth.grid.verify import verify

HERE = Path(__file__).resolve().parent


def native(problem, steps, **options):
    t0 = time.perf_counter()
    out = Engine(**options).solve_length(problem, steps, Budget(seconds=120))
    seconds = time.perf_counter() - t0
    verified = None
    if out.status is GridStatus.REALIZABLE:
        verified = verify(problem, out.program, steps).wins
    return out, seconds, verified


def cvc5(problem, steps, timeout):
    from plansynth.grid.result import get_backend

    t0 = time.perf_counter()
    out = get_backend("cvc5").solve_length(problem, steps, Budget(seconds=timeout))
    return out, time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cvc5", type=float, default=None, help="also run cvc5 with this many seconds per instance")
    ap.add_argument("--cvc5-only", default="", help="comma-separated instance names for cvc5 (default: all)")
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    rows = []
    print(
        f"{'instance':<16} {'l':>3} {'status':<12} {'native s':>9} {'depth':>5} {'paper':>5} {'verified':>8} {'cvc5':>14}"
    )
    for name, doc in families().items():
        if name == "figure1":
            continue
        problem = grid_problem_from_dict(doc)
        l = problem.steps
        out, secs, ok = native(problem, l)
        paper = paper_depth(name)
        row = {
            "instance": name,
            "steps": l,
            "status": out.status.value,
            "native_seconds": secs,
            "depth": depth(out.program) if out.program else None,
            "paper_depth": paper,
            "verified": ok,
            "program": str(out.program),
        }
        cv = "-"
        if args.cvc5 is not None and (not args.cvc5_only or name in args.cvc5_only.split(",")):
            c_out, c_secs = cvc5(problem, l, args.cvc5)
            row["cvc5_status"] = c_out.status.value
            row["cvc5_seconds"] = c_secs
            cv = f"{c_out.status.value[:5]} {c_secs:7.2f}"
        rows.append(row)
        print(
            f"{name:<16} {l:>3} {out.status.value:<12} {secs:9.3f} {row['depth']!s:>5} {paper:>5} {ok!s:>8} {cv:>14}",
            flush=True,
        )

    # shorter lengths: every one must be refuted quickly
    unreal = []
    for name, doc in families().items():
        problem = grid_problem_from_dict(doc)
        top = problem.steps or 6
        for l in range(1, top):
            out, secs, _ = native(problem, l)
            unreal.append(
                {
                    "instance": name,
                    "steps": l,
                    "status": out.status.value,
                    "seconds": secs,
                    "why": out.witness.kind if out.witness else out.message,
                }
            )
    worst = max((r for r in unreal if r["status"] == "unrealizable"), key=lambda r: r["seconds"])
    kinds = {}
    for r in unreal:
        kinds[r["status"]] = kinds.get(r["status"], 0) + 1
    print(
        f"\nshorter lengths: {len(unreal)} decided {kinds}; slowest unrealizable {worst['instance']} l={worst['steps']} {worst['seconds']:.3f} s; "
        f"slowest of all {max(r['seconds'] for r in unreal):.3f} s"
    )

    print("\nminimize (proved minimal depth):")
    mins = []
    for name in ("depth-1", "depth-4", "depth-5", "depth-6", "figure1"):
        problem = grid_problem_from_dict(families()[name])
        l = problem.steps or 6
        out, secs, ok = native(problem, l, minimize=True)
        proved = out.counters.get("minimal_depth_proved")
        mins.append(
            {
                "instance": name,
                "depth": depth(out.program) if out.program else None,
                "proved": proved,
                "seconds": secs,
                "verified": ok,
            }
        )
        print(f"  {name:<10} depth {mins[-1]['depth']} proved {proved} {secs:.3f} s verified {ok}  {out.program}")

    print("\nreactive examples (controllers must read obstacles):")
    reactive = []
    for name, l in (("crossing", 9), ("traffic", 9), ("patrol", 7), ("door", 10)):
        problem = load_grid_problem(HERE / f"{name}.yaml")
        out, secs, ok = native(problem, l)
        reactive.append(
            {
                "instance": name,
                "steps": l,
                "status": out.status.value,
                "seconds": secs,
                "verified": ok,
                "reads_obstacles": reads_obstacles(out.program) if out.program else None,
                "program": str(out.program),
            }
        )
        print(
            f"  {name:<10} l={l} {out.status.value} {secs:.2f} s verified {ok} reads obstacles {reactive[-1]['reads_obstacles']}  {out.program}"
        )

    problem = load_grid_problem(HERE / "scale64.yaml")
    out, secs, ok = native(problem, 60)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(
        f"\nscale64: {out.status.value} in {secs:.2f} s, relevant obstacles {out.counters.get('relevant_obstacles')}, "
        f"verified {ok}, peak RSS of this process {rss:.0f} MB, program {out.program}"
    )

    if args.cvc5 is not None:
        solved = [r for r in rows if r.get("cvc5_status") == "realizable"]
        if solved:
            ratios = [r["cvc5_seconds"] / r["native_seconds"] for r in solved]
            print(
                f"\ncvc5 solved {len(solved)} of {sum('cvc5_status' in r for r in rows)} within {args.cvc5} s; "
                f"median speed-up of native over cvc5 on those: {statistics.median(ratios):.0f}x"
            )
    native_times = [r["native_seconds"] for r in rows]
    print(
        f"\nfamilies: {len(rows)} instances, all verified: {all(r['verified'] for r in rows)}, "
        f"slowest {max(native_times):.3f} s, depth <= paper: {all(r['depth'] <= r['paper_depth'] for r in rows)}"
    )
    if args.json:
        args.json.write_text(
            json.dumps({"families": rows, "shorter": unreal, "minimize": mins, "reactive": reactive}, indent=1)
        )


if __name__ == "__main__":
    main()
