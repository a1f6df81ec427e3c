"""``bench report``: Markdown tables and log-scale PNG plots from a results database.

For every figure and table of the two papers the report puts the paper's number beside
ours and beside the peers' from the same run:

- grid (Chasins & Newcomb, SYNT 2016): Figure 2 (time vs program depth: ``depth``),
  Figure 3 (time vs path length: ``steps``), Figure 4 (time vs number of obstacles:
  ``obstacles``), Figure 5 (time vs grid size: ``dimensions``), Figure 6 (solver
  comparison on steps-20), plus ``figure1`` and our reactive families;
- reach (Shoukry et al., CDC 2016): Table I (mazes: lazy SMT vs RRT vs MILP) and
  Figure 4 (time vs number of states, integrator chains).

Times are medians over the repeats that solved; a cell is ``> T`` when no repeat solved
within the limit T (then the status counts say why), and ratio columns compare two
backends on the same instance (``a/b`` > 1 means ``b`` was faster). Ratios with an
unsolved side are bounds, marked ``>`` or ``<``.
"""

from __future__ import annotations

import json
import statistics
import time
from collections import defaultdict
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from plansynth.bench.db import ResultsDB
from plansynth.bench.families import PAPER_TABLE_I
from plansynth.io import atomic_output, write_output

__all__ = ["Cell", "summarise", "write_report", "headline"]

GRID_FIGURES = [
    ("depth", "Figure 2: time vs program depth", "program depth d of the paper's instance depth-d"),
    ("steps", "Figure 3: time vs number of steps", "number of steps L"),
    ("obstacles", "Figure 4: time vs number of obstacles", "number of obstacles N"),
    ("dimensions", "Figure 5: time vs grid size", "grid size S (S x S)"),
]
REACTIVE = ["figure1", "crossing", "crossing-stall", "patrol", "patrol-walk", "door", "door-stall", "scale", "lanes",
            "lanes-rush", "roads30", "roads30-stall", "guards30"]
CLI_TIMED_NOTE = ("Each run is `plansynth grid solve FILE --solver S --timeout T` in a fresh process, as a user "
                  "runs it: *wall* is that process's wall clock from spawn to exit (start-up included), *solve* the "
                  "time the result file reports; *budget kept*: wall <= T + 1 s (issue 11's Targets). *depth - "
                  "witness*: the program's depth minus the depth of the label's witness program.")
PAPER_FIG6 = {"Stochastic 2014": "> 1800 (time out)", "Enumerative 2014": 1003.0, "Enumerative 2015": 805.0}


@dataclass(frozen=True)
class Cell:
    """Aggregate of the repeats of one (instance, solver)."""

    runs: int
    solved: int
    median: float | None  # median time of the solved repeats
    worst: float | None
    limit: float | None
    statuses: dict[str, int]
    depth: int | None = None
    steps: int | None = None
    horizon: int | None = None
    extra: dict[str, Any] | None = None

    @property
    def all_solved(self) -> bool:
        return self.runs > 0 and self.solved == self.runs

    def text(self) -> str:
        if self.solved == 0:
            if set(self.statuses) <= {"unrealizable", "infeasible"}:
                return f"{_fmt(self.median_any)} ({next(iter(self.statuses))})"
            if self.out_of_time:
                lim = f"> {_fmt(self.limit)}" if self.limit else "-"
                t = self.median_any
                if t is not None and self.limit and not self.used_its_limit:
                    return f"no answer ({_status_summary(self.statuses)} after {_fmt(t)} s of {_fmt(self.limit)})"
                return f"{lim} ({_status_summary(self.statuses)})"
            return _status_summary(self.statuses)
        s = _fmt(self.median)
        if (self.extra or {}).get("samples_only"):
            s += " (samples only: a segment crosses an obstacle)"
        if self.solved < self.runs:
            s += f" ({self.solved}/{self.runs} solved; {_status_summary(self.statuses)})"
        return s

    @property
    def out_of_time(self) -> bool:
        """No answer because time ran out (not a crash or an invalid plan)."""
        return self.solved == 0 and set(self.statuses) <= {"unknown", "timeout"}

    @property
    def used_its_limit(self) -> bool:
        """No answer within (nearly) the whole limit: the limit is then a lower bound of
        the time it would need. A run that gave up well before it (an iteration limit of
        the solver, say) bounds nothing."""
        t = self.median_any
        return self.out_of_time and bool(self.limit) and (t is None or t >= 0.9 * self.limit)

    @property
    def median_any(self) -> float | None:
        return (self.extra or {}).get("median_any")

    def decided_time(self) -> float | None:
        """Median time when every repeat gave a definite answer (solved or proved)."""
        if self.runs and set(self.statuses) <= {"solved", "unrealizable", "infeasible"}:
            return self.median if self.solved else self.median_any
        return None


def _fmt(x: float | None) -> str:
    if x is None:
        return "-"
    if isinstance(x, str):
        return x
    if x >= 1000:
        return f"{x:.0f}"
    if x >= 0.01:
        return f"{x:.3g}"
    return f"{x:.1e}"


def _status_summary(statuses: Mapping[str, int]) -> str:
    return ", ".join(f"{n} {s}" for s, n in sorted(statuses.items()))


def summarise(runs: Sequence[Mapping[str, Any]]) -> dict[tuple[str, str], Cell]:
    """(experiment, planner) -> :class:`Cell`."""
    groups: dict[tuple[str, str], list[Mapping[str, Any]]] = defaultdict(list)
    for r in runs:
        groups[(r["experiment"], r["planner"])].append(r)
    out = {}
    for key, rs in groups.items():
        solved = [r for r in rs if r["solved"]]
        times = [float(r["time"]) for r in solved if r["time"] is not None]
        all_times = [float(r["time"]) for r in rs if r["time"] is not None]
        statuses: dict[str, int] = defaultdict(int)
        for r in rs:
            statuses[r["status"]] += 1
        first = solved[0] if solved else rs[0]
        out[key] = Cell(
            runs=len(rs), solved=len(solved),
            median=statistics.median(times) if times else None,
            worst=max(times) if times else None,
            limit=max(((r.get("attributes") or {}).get("timelimit") or r["timelimit"] or 0) for r in rs) or None,
            statuses=dict(statuses),
            depth=first.get("depth"), steps=first.get("steps"), horizon=first.get("horizon"),
            extra={"median_any": statistics.median(all_times) if all_times else None,
                   "family": rs[0]["family"], "instance": rs[0]["instance"], "setup": rs[0]["setup"],
                   "lp_calls": first.get("lp_calls"), "sat_calls": first.get("sat_calls"),
                   "timings": (first.get("attributes") or {}).get("timings", {}),
                   "expected": (rs[0]["setup"] or {}).get("expected"),
                   "samples_only": any(r.get("segment_safe") == 0 for r in solved),
                   "program": (first.get("attributes") or {}).get("program"),
                   # the limit beside the time: one cold LP over the final region sequence (median)
                   "oracle_lp": _median_attr(solved, "oracle_lp", "seconds"),
                   "duration": _median_attr(solved, "duration"),
                   "guarantee": (first.get("attributes") or {}).get("guarantee"),
                   # the planner's own time: the run's time less the validator's (median)
                   "planner_median": _median_planner(solved),
                   # runs through the CLI (bench.execute._grid_cli): wall clock of the whole process
                   "cli_wall": _median_attr(rs, "cli_wall"),
                   "budget_kept": [bool((r.get("attributes") or {}).get("budget_kept")) for r in rs
                                   if "budget_kept" in (r.get("attributes") or {})],
                   "depth_minimal": (first.get("attributes") or {}).get("depth_minimal"),
                   # the lazy planner's minimality claim (issue 13): proved? for what? how many probes?
                   "minimal": {k: ((first.get("attributes") or {}).get("counters") or {}).get(k)
                               for k in ("minimal", "minimal_relative_to", "minimal_probes")},
                   "regions": first.get("regions"),
                   "counters": (first.get("attributes") or {}).get("counters") or {}},
        )
    return out


def _median_attr(runs: Sequence[Mapping[str, Any]], key: str, sub: str | None = None) -> float | None:
    """Median of ``attributes[key]`` (or ``attributes[key][sub]``) over ``runs``, when recorded."""
    vals = []
    for r in runs:
        v = (r.get("attributes") or {}).get(key)
        if sub is not None:
            v = v.get(sub) if isinstance(v, Mapping) else None
        if isinstance(v, (int, float)):
            vals.append(float(v))
    return statistics.median(vals) if vals else None


def _median_planner(runs: Sequence[Mapping[str, Any]]) -> float | None:
    vals = []
    for r in runs:
        v = ((r.get("attributes") or {}).get("timings") or {}).get("validate")
        if r.get("time") is not None and isinstance(v, (int, float)):
            vals.append(float(r["time"]) - float(v))
    return statistics.median(vals) if vals else None


def _over_limit(c: Cell | None) -> str:
    """``total / limit``: the median time over the median one-cold-LP time."""
    if c is None or not c.solved or c.median is None:
        return "-"
    lim = (c.extra or {}).get("oracle_lp")
    if not lim:
        return "-"
    return f"{_fmt(c.median)} / {_fmt(lim)} = {c.median / lim:.3g}x"


def _ratio(a: Cell | None, b: Cell | None) -> str:
    """time(a) / time(b) on one instance, with bounds when one side did not finish."""
    if a is None or b is None:
        return "-"
    rv = _ratio_value(a, b)
    if rv is None:
        return "-"
    return f"{'' if rv[1] == '=' else rv[1] + ' '}{rv[0]:.3g}"


def _ratio_value(a: Cell | None, b: Cell | None) -> tuple[float, str] | None:
    if a is None or b is None:
        return None
    ta, tb = a.decided_time(), b.decided_time()
    if ta is not None and tb is not None:
        return ta / max(tb, 1e-6), "="
    if ta is None and tb is not None and a.used_its_limit:
        return a.limit / max(tb, 1e-6), ">"
    if tb is None and ta is not None and b.used_its_limit:
        return ta / b.limit, "<"
    return None


def _param(cell_or_setup: Mapping[str, Any]) -> float:
    params = cell_or_setup.get("params") or {}
    for k in ("d", "L", "N", "S", "cars", "height", "n", "seed"):
        if k in params:
            return float(params[k])
    return 0.0


def _instances(cells: Mapping[tuple[str, str], Cell], family: str) -> list[tuple[str, dict[str, Any]]]:
    seen: dict[str, dict[str, Any]] = {}
    for (exp, _), c in cells.items():
        if c.extra and c.extra["family"] == family:
            seen.setdefault(exp, c.extra["setup"])
    return sorted(seen.items(), key=lambda kv: (_param(kv[1]), kv[1].get("params", {}).get("k", 0)))


def _planners(cells: Mapping[tuple[str, str], Cell], kind_prefix: str, order: Sequence[str]) -> list[str]:
    ps = {p for (exp, p) in cells if exp.startswith(kind_prefix)}
    return [p for p in order if p in ps] + sorted(ps - set(order))


def headline(cells: Mapping[tuple[str, str], Cell], a: str, b: str, prefix: str) -> dict[str, Any]:
    """Median and worst of time(a)/time(b) over instances of ``prefix`` both decided."""
    vals = []
    bounds = []
    for (exp, p), c in cells.items():
        if p != a or not exp.startswith(prefix):
            continue
        rv = _ratio_value(c, cells.get((exp, b)))
        if rv is None:
            continue
        (vals if rv[1] == "=" else bounds).append((rv[0], exp, rv[1]))
    if not vals and not bounds:
        return {"n": 0}
    exact = sorted(v for v, _, _ in vals)
    return {
        "n": len(vals),
        "median": statistics.median(exact) if exact else None,
        "worst_for_b": max(vals)[0:2] if vals else None,  # largest a/b
        "best_for_b": min(vals)[0:2] if vals else None,
        "bounds": [(float(f"{v:.3g}"), e, s) for v, e, s in bounds],
    }


# ------------------------------------------------------------------------------ plots


def _plot_family(cells: Mapping[tuple[str, str], Cell], family: str, planners: Sequence[str], title: str,
                 xlabel: str, path: Path, paper: Mapping[float, float] | None = None,
                 xkey: Any = None) -> bool:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    insts = _instances(cells, family)
    if not insts:
        return False
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    markers = "osD^v<>p*"
    for i, p in enumerate(planners):
        xs, ys, xu, yu = [], [], [], []
        for exp, setup in insts:
            c = cells.get((exp, p))
            if c is None:
                continue
            x = xkey(setup) if xkey else _param(setup)
            t = c.decided_time()
            if t is not None:
                xs.append(x)
                ys.append(max(t, 1e-3))
            elif c.limit and c.out_of_time:
                xu.append(x)
                yu.append(c.limit)
        if xs or xu:
            line = ax.plot(xs, ys, marker=markers[i % len(markers)], label=p)[0]
            if xu:
                ax.plot(xu, yu, linestyle="none", marker=markers[i % len(markers)], mfc="none",
                        color=line.get_color(), label=f"{p}: no answer within limit")
    if paper:
        px = sorted(k for k, v in paper.items() if v is not None)
        ax.plot(px, [paper[k] for k in px], "k--", marker="x", label="paper (Enumerative 2015, 2016 machine)")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("time (s, log scale)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
    return True


def _plot_bars(groups: Sequence[str], series: Mapping[str, Sequence[float | None]], title: str, path: Path,
               limits: Mapping[str, Sequence[bool]] | None = None) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    k = len(series)
    width = 0.8 / max(1, k)
    x = np.arange(len(groups))
    for i, (name, vals) in enumerate(series.items()):
        v = [np.nan if t is None else max(t, 1e-3) for t in vals]
        bars = ax.bar(x + (i - (k - 1) / 2) * width, v, width, label=name)
        if limits and name in limits:
            for b, lim in zip(bars, limits[name]):
                if lim:
                    b.set_hatch("//")
                    b.set_alpha(0.5)
    ax.set_xticks(x, groups)
    ax.set_yscale("log")
    ax.set_ylabel("time (s, log); hatched: no answer in limit")
    ax.set_title(title, fontsize=10)
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


# ------------------------------------------------------------------------------ report


def write_report(db_path: str | Path, out_dir: str | Path, *, title: str = "plansynth benchmark report",
                 planned: Sequence[tuple[str, str, int]] | None = None, image_prefix: str = "") -> Path:
    """Write ``out_dir/REPORT.md`` and its PNG figures from the database; returns the path.

    ``planned`` (resume keys) lets the report list the runs that are missing. Images
    are referred to as ``image_prefix + name`` (for a report that lives elsewhere).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with ResultsDB(db_path) as db:
        runs = db.runs()
        info = db.info()
        if planned is None and "planned" in info:
            planned = [tuple(k) for k in json.loads(info["planned"])]  # type: ignore[misc]
        done = db.done_keys()
    cells = summarise(runs)
    machine = json.loads(info.get("machine", "{}"))
    L: list[str] = [f"# {title}", ""]
    L.append(f"Generated {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} from `{Path(db_path).name}` "
             f"({len(runs)} runs). Machine: {machine.get('cpuinfo', '?')}; Python {machine.get('python', '?')}; "
             + ", ".join(f"{k} {v}" for k, v in (machine.get("versions") or {}).items() if v) + ".")
    L.append("")
    L.append("Times are medians over repeats, in seconds, measured by each solver around its own solve "
             "(problem construction and process start excluded). `> T` means no repeat answered within the "
             "limit T; the statuses say what happened (`unknown`: the solver's budget ran out; `timeout`: "
             "killed by the runner; `crash`/`memout`: the child died). A result counts as solved only if the "
             "independent checker accepted it (grid: `plansynth.grid.verify`; reach: `plansynth.reach.validate`). "
             "Paper numbers were measured in 2016 on the authors' machines; they are context, not a comparison.")
    L.append("")
    if planned:
        missing = [k for k in planned if tuple(k) not in done]
        L.append(f"Runs planned: {len(planned)}; finished: {len(planned) - len(missing)}; missing: {len(missing)}.")
        if missing:
            L.append("")
            L.append("<details><summary>Missing runs</summary>")
            L.append("")
            for e, p, r in missing[:400]:
                L.append(f"- {e} {p} #{r}")
            L.append("")
            L.append("</details>")
        L.append("")

    figs: list[str] = []
    # ---------------------------------------------------------------- grid
    grid_planners = _planners(cells, "grid/", ["native", "cvc5", "external"])
    if grid_planners:
        L.append("## Grid: reactive controllers (Chasins & Newcomb, SYNT 2016)")
        L.append("")
        if "native" in grid_planners and "cvc5" in grid_planners:
            h = headline(cells, "cvc5", "native", "grid/")
            if h["n"]:
                L.append(f"**Headline: native vs cvc5** (time ratio cvc5 / native on the same instance, {h['n']} "
                         f"instances both decided): median {h['median']:.3g}x; worst case for native (smallest ratio) "
                         f"{h['best_for_b'][0]:.3g}x on {h['best_for_b'][1]}; largest {h['worst_for_b'][0]:.3g}x on "
                         f"{h['worst_for_b'][1]}.")
            if h.get("bounds"):
                L.append("")
                L.append(f"Decided by one side only ({len(h['bounds'])} instances; ratio bounds from the time limit): "
                         + "; ".join(f"{e.split('/')[-1]} {s} {v:.3g}x" for v, e, s in h["bounds"]) + ".")
            L.append("")
        from plansynth.bench.families import PAPER_GRID_SECONDS

        for fam, caption, pname in GRID_FIGURES:
            insts = _instances(cells, fam)
            if not insts:
                continue
            L.append(f"### {caption} (family `{fam}`)")
            L.append("")
            L.extend(_grid_table(cells, insts, grid_planners, paper=True))
            L.append("")
            png = f"grid-{fam}.png"
            paper = {float(k): v for k, v in PAPER_GRID_SECONDS[fam].items() if v is not None}
            if _plot_family(cells, fam, grid_planners, f"Grid, {caption} ({fam})", pname, out / png, paper):
                L.append(f"![{caption}]({image_prefix}{png})")
                figs.append(png)
                L.append("")
        check = _paper_regression(cells)
        if check:
            L.append(check)
            L.append("")
        # Figure 6
        exp6 = "grid/steps/steps-20"
        if any(e == exp6 for e, _ in cells):
            L.append("### Figure 6: solvers on steps-20")
            L.append("")
            L.append("| solver | time (s) | source |")
            L.append("|---|---|---|")
            for k, v in PAPER_FIG6.items():
                L.append(f"| {k} | {_fmt(v) if not isinstance(v, str) else v} | paper |")
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
            _plot_bars(["steps-20"], series, "Grid, Figure 6: solver comparison on steps-20", out / "grid-figure6.png", lim)
            L.append(f"![Figure 6]({image_prefix}grid-figure6.png)")
            figs.append("grid-figure6.png")
            L.append("")
        react = [f for f in REACTIVE if _instances(cells, f)]
        if react:
            L.append("### Figure 1 and reactive families (ours: obstacles cross the robot's way)")
            L.append("")
            for fam in react:
                L.append(f"Family `{fam}`:")
                L.append("")
                L.extend(_grid_table(cells, _instances(cells, fam), grid_planners, paper=False, expected=True))
                L.append("")

        suite = _instances(cells, "reactive-suite")
        if suite:
            L.append("### The shared reactive suite (family `reactive-suite`: 40 problems with certified labels)")
            L.append("")
            L.append(CLI_TIMED_NOTE)
            L.append("")
            L.extend(_suite_table(cells, suite, grid_planners))
            L.append("")
        doors = [i for f in ("doors", "doors-rush", "doors-jam", "patrols", "patrols-walk") for i in _instances(cells, f)]
        if doors:
            L.append("### Doors that close and guards that patrol (families `doors`, `doors-rush`, `doors-jam`, "
                     "`patrols`, `patrols-walk`; labels certified by brute force)")
            L.append("")
            L.append(CLI_TIMED_NOTE)
            L.append("")
            L.extend(_suite_table(cells, doors, grid_planners))
            L.append("")

    # ---------------------------------------------------------------- reach
    reach_planners = [p for p in _planners(cells, "reach/", ["lazy-smt", "milp", "milp-bigm", "rrt", "est", "kpiece", "gcs"])
                      if p not in CX_VARIANTS and p not in ("milp-ltl", "lazy-smt-minimal")]  # (their own tables)
    if reach_planners:
        L.append("## Reach-avoid: lazy SMT planning (Shoukry et al., CDC 2016)")
        L.append("")
        mazes = _instances(cells, "maze")
        if mazes:
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
                row = [str(n), _fmt(tot), _fmt(pap.get("rrt")), str(pap.get("ltl-opt", "-"))]
                for p in reach_planners:
                    c = cells.get((exp, p))
                    row.append(c.text() if c else "-")
                if base:
                    for p in others:
                        row.append(_ratio(cells.get((exp, p)), cells.get((exp, base))))
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
            L.append("`milp` is the region-graph MILP planner; `milp-bigm` the one-shot big-M MILP over the horizon "
                     "(the paper's LTL OPT stand-in); `rrt`, `est`, `kpiece` are OMPL's kinodynamic planners with the "
                     "exact discrete dynamics. All keep whole segments off the obstacles unless marked `samples only`.")
            L.append("")
            if base:
                L.append("**Headline ratios (per maze):** " + "; ".join(
                    f"maze-{int(s['params']['n'])}: " + ", ".join(
                        f"{p}/lazy-smt {_ratio(cells.get((e, p)), cells.get((e, base)))}" for p in others)
                    for e, s in mazes) + ".")
                L.append("")
            # lazy-smt breakdown
            if base:
                L.append("Lazy SMT phases (median run): abstraction / SAT / LP seconds, SAT and LP calls, horizon:")
                L.append("")
                L.append("| maze | paper abstraction | paper DIS-PLAN | paper CON-PLAN | abstraction | sat | lp | SAT calls | LP calls | horizon | total / limit (one cold LP) |")
                L.append("|---|---|---|---|---|---|---|---|---|---|---|")
                for exp, setup in mazes:
                    c = cells.get((exp, base))
                    n = int(setup["params"]["n"])
                    pap = PAPER_TABLE_I.get(n, {})
                    tm = (c.extra or {}).get("timings", {}) if c else {}
                    L.append(f"| {n} | {_fmt(pap.get('abstraction'))} | {_fmt(pap.get('dis-plan'))} | {_fmt(pap.get('con-plan'))} | "
                             f"{_fmt(tm.get('abstraction'))} | {_fmt(tm.get('sat'))} | {_fmt(tm.get('lp'))} | "
                             f"{(c.extra or {}).get('sat_calls') if c else '-'} | {(c.extra or {}).get('lp_calls') if c else '-'} | "
                             f"{c.horizon if c else '-'} | {_over_limit(c)} |")
                L.append("")
                L.append("The limit is one cold LP over the final region sequence: what the plan would cost if an oracle "
                         "handed the planner its regions (CON-PLAN's feasibility LP built and solved from scratch in a "
                         "fresh CON-PLAN, as it solves a plan LP with no basis: beyond 8 states split per axis where "
                         "the dynamics and regions separate (the axes then on two threads), by the interior-point "
                         "method first from 30 states on, no iteration cap; median "
                         "over the solved runs); "
                         "total / limit is the search's overhead.")
                L.append("")
            _plot_bars(groups, dict(series), "Reach, Table I: mazes (log scale)", out / "reach-table1.png", dict(lims))
            L.append(f"![Table I]({image_prefix}reach-table1.png)")
            figs.append("reach-table1.png")
            L.append("")
        if mazes:
            L += _gcs_table(cells, mazes)
            L += _minimal_table(cells, mazes)
            L += _counterexample_table(cells, mazes)
        chains = _instances(cells, "chain")
        if chains:
            L.append("### Figure 4: scalability with the number of states (integrator chains)")
            L.append("")
            L.append("The paper reports 1.64 s (1 passage) to 152 s (4 passages) at n = 50 states, with random A, B; "
                     "we use integrator chains of order k (n = 2k states).")
            L.append("")
            used = [p for p in reach_planners if any((e, p) in cells for e, _ in chains)]
            hdr = ["passages", "k", "states n"] + used + ["lazy-smt horizon", "lazy-smt total / limit"]
            L.append("| " + " | ".join(hdr) + " |")
            L.append("|" + "---|" * len(hdr))
            for exp, setup in chains:
                n, k = int(setup["params"]["n"]), int(setup["params"]["k"])
                row = [str(n), str(k), str(2 * k)] + [cells[(exp, p)].text() if (exp, p) in cells else "-" for p in used]
                lz = cells.get((exp, "lazy-smt"))
                row += [str(lz.horizon) if lz and lz.solved else "-", _over_limit(lz)]
                L.append("| " + " | ".join(row) + " |")
            L.append("")
            _plot_chain(cells, chains, used, out / "reach-figure4.png")
            L.append(f"![Figure 4]({image_prefix}reach-figure4.png)")
            figs.append("reach-figure4.png")
            L.append("")
        rdyn = _instances(cells, "random-dynamics")
        if rdyn:
            from plansynth.reach.families import random_dynamics

            L.append("### Figure 4 with random dynamics (the paper's setting: random A, B)")
            L.append("")
            import re

            text = " ".join((random_dynamics.__doc__ or "").split("\n\n")[1].split())
            L.append(re.sub(r":\w+:`~?(?:[\w.]+\.)?(\w+)`", r"`\1`", text).replace("``", "`"))
            L.append("")
            used = [p for p in reach_planners if any((e, p) in cells for e, _ in rdyn)]
            hdr = ["passages", "states n", "seed"] + used + ["lazy-smt horizon", "lazy-smt total / limit"]
            L.append("| " + " | ".join(hdr) + " |")
            L.append("|" + "---|" * len(hdr))
            for exp, setup in sorted(rdyn, key=lambda es: (int(es[1]["params"]["n"]), int(es[1]["params"]["states"]))):
                pr = setup["params"]
                row = [str(pr["n"]), str(pr["states"]), str(pr.get("seed", 0))]
                row += [cells[(exp, p)].text() if (exp, p) in cells else "-" for p in used]
                lz = cells.get((exp, "lazy-smt"))
                row += [str(lz.horizon) if lz and lz.solved else "-", _over_limit(lz)]
                L.append("| " + " | ".join(row) + " |")
            L.append("")
        L += _missions_table(cells)
        L += _gcs_maze_table(cells)
        rnd = _instances(cells, "random")
        if rnd:
            L.append("### Random workspaces")
            L.append("")
            used = [p for p in reach_planners if any((e, p) in cells for e, _ in rnd)]
            hdr = ["instance"] + used
            L.append("| " + " | ".join(hdr) + " |")
            L.append("|" + "---|" * len(hdr))
            for exp, setup in rnd:
                L.append("| " + " | ".join([setup["name"]] + [cells[(exp, p)].text() if (exp, p) in cells else "-" for p in used]) + " |")
            L.append("")
    report = out / "REPORT.md"
    write_output(report, "\n".join(L) + "\n")
    return report


def _gcs_table(cells: Mapping[tuple[str, str], Cell], mazes: Sequence[tuple[str, dict[str, Any]]]) -> list[str]:
    """GCS (Drake) beside lazy-smt on the mazes, with the difference in guarantee."""
    if not any((e, "gcs") in cells for e, _ in mazes):
        return []
    from plansynth.reach.planners.gcs import GUARANTEE

    L = ["### Graphs of Convex Sets (Drake) beside lazy SMT", "",
         "`gcs`: Marcucci, Petersen, von Wrangel and Tedrake, \"Motion planning around obstacles with convex "
         "optimization\", Science Robotics 2023, through Drake's `GcsTrajectoryOptimization`, over *our* convex "
         "regions (the lazy planner's decomposition and adjacency); like-for-like variant: Bezier order 5, velocity "
         "continuity, |v| and |a| bounds of the problem, start at rest, the goal box as the target set, Clarabel "
         "relaxation + IPOPT rounding, time in units of 10 s. **The guarantees differ**: lazy-smt returns a "
         "trajectory of the exact discrete dynamics x' = A x + B u (|u| <= 1, every sample and segment free); "
         f"gcs returns a {GUARANTEE}.", "",
         "Times include the validator's checks (for gcs: the samples at dt and the dense curve, several thousand "
         "samples); the planner-only columns leave them out.", "",
         "| maze | gcs | gcs curve duration (s) | lazy-smt | lazy-smt horizon x dt (s) | gcs / lazy-smt | "
         "planner only: gcs / lazy-smt |",
         "|---|---|---|---|---|---|---|"]
    for exp, setup in mazes:
        g, lz = cells.get((exp, "gcs")), cells.get((exp, "lazy-smt"))
        gd = (g.extra or {}).get("duration") if g and g.solved else None
        ld = (lz.extra or {}).get("duration") if lz and lz.solved else None
        gp = (g.extra or {}).get("planner_median") if g and g.solved else None
        lp = (lz.extra or {}).get("planner_median") if lz and lz.solved else None
        only = f"{_fmt(gp)} / {_fmt(lp)} = {gp / lp:.3g}" if gp and lp else "-"
        L.append(f"| {int(setup['params']['n'])} | {g.text() if g else '-'} | {_fmt(gd)} | {lz.text() if lz else '-'} | "
                 f"{_fmt(ld)} | {_ratio(g, lz)} | {only} |")
    L.append("")
    return L


def _minimal_table(cells: Mapping[tuple[str, str], Cell], mazes: Sequence[tuple[str, dict[str, Any]]]) -> list[str]:
    """The proved-minimal horizon (issue 13, item 3): ``lazy-smt-minimal`` (the window
    search, then the re-timing and probes of ``horizon_search="minimal"``) beside the
    default window search, with what the minimality holds for."""
    if not any((e, "lazy-smt-minimal") in cells for e, _ in mazes):
        return []
    L = ["### Proved-minimal horizons", "",
         "`lazy-smt-minimal`: the default window search, then its horizon proved minimal (the plan re-timed by LPs "
         "alone, then single-horizon probes, every shorter horizon refuted; from a start at rest a refuted horizon "
         "refutes every shorter one). *decomposition*: minimal among plans whose consecutive samples share a convex "
         "region (segment-safe mode; see the README on claims); *problem*: for the problem as the spec defines it.", "",
         "| maze | lazy-smt (window) | its horizon | lazy-smt-minimal | proved minimal horizon | minimal for | probes | "
         "LP calls | proof (s, first run) | minimal / window |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    for exp, setup in mazes:
        w, m = cells.get((exp, "lazy-smt")), cells.get((exp, "lazy-smt-minimal"))
        claim = (m.extra or {}).get("minimal", {}) if m else {}
        proved = m.horizon if m and m.solved and claim.get("minimal") else None
        proof = ((m.extra or {}).get("timings") or {}).get("minimal") if m and m.solved else None
        L.append(f"| {int(setup['params']['n'])} | {w.text() if w else '-'} | {w.horizon if w and w.solved else '-'} | "
                 f"{m.text() if m else '-'} | {proved if proved is not None else 'not proved'} | "
                 f"{claim.get('minimal_relative_to') or '-'} | {claim.get('minimal_probes') if claim.get('minimal_probes') is not None else '-'} | "
                 f"{(m.extra or {}).get('lp_calls') if m else '-'} | {_fmt(proof)} | {_ratio(m, w)} |")
    L.append("")
    return L


def _gcs_maze_table(cells: Mapping[tuple[str, str], Cell]) -> list[str]:
    """The GCS paper's n x n mazes (issue 13, item 8): lazy-smt and gcs on the same
    instances in the same run."""
    insts = sorted(_instances(cells, "gcs-maze"), key=lambda es: int(es[1]["params"]["n"]))
    if not insts:
        return []
    from plansynth.reach.families import gcs_maze

    L = ["### The GCS paper's mazes (n x n)", "",
         " ".join((gcs_maze.__doc__ or "").split("\n\n")[0].split()), "",
         "A time is a solved run: planned and validated (lazy-smt: the exact discrete dynamics, every sample and "
         "segment free; gcs: its continuous-time curve, see the Graphs of Convex Sets section). lazy-smt's horizon is not proved minimal here "
         "(a window search: horizons below the window's bottom refuted).", "",
         "| n | regions | lazy-smt | lazy-smt horizon x dt (s) | lazy-smt LP calls / learned clauses | gcs | "
         "gcs curve duration (s) | gcs / lazy-smt |",
         "|---|---|---|---|---|---|---|---|"]
    for exp, setup in insts:
        g, lz = cells.get((exp, "gcs")), cells.get((exp, "lazy-smt"))
        regions = next((c.extra or {}).get("regions") for c in (lz, g) if c is not None)
        ld = (lz.extra or {}).get("duration") if lz and lz.solved else None
        gd = (g.extra or {}).get("duration") if g and g.solved else None
        cnt = (lz.extra or {}).get("counters", {}) if lz else {}
        work = f"{cnt.get('lp_calls', '-')} / {cnt.get('clauses', '-')}" if lz else "-"
        hor = f"{lz.horizon} x dt = {_fmt(ld)}" if lz and lz.solved and lz.horizon is not None else "-"
        L.append(f"| {int(setup['params']['n'])} | {regions if regions is not None else '-'} | "
                 f"{lz.text() if lz else '-'} | {hor} | {work} | {g.text() if g else '-'} | {_fmt(gd)} | "
                 f"{_ratio(g, lz)} |")
    L.append("")
    return L


def _missions_table(cells: Mapping[tuple[str, str], Cell]) -> list[str]:
    """LTL missions on the mazes (issue 14): lazy-smt against the milp-ltl baseline.
    Beside the baseline's total, the seconds HiGHS spent in its MILP solves
    (``timings["milp_solve"]``): the rest of its total is mostly building the models."""
    insts = _instances(cells, "missions")
    if not insts:
        return []
    L = ["### LTL missions on the mazes: lazy SMT (BMC encoding in DIS-PLAN) vs one big-M MILP per horizon", "",
         "Three missions per maze (`plansynth.reach.mission.families`): `visit` = `F (b & F d) & G !h` (finite plan), "
         "`patrol` = `G F a & G F b` (a lasso), `avoid-until` = `!h U door`. Both planners search horizons "
         "upwards from the same proved lower bound (the product graph of `plansynth.reach.mission.horizon`) "
         "and report the shortest; every plan is validated and mission-checked. "
         "`milp-ltl in HiGHS` is the part of the baseline's time spent in HiGHS's MILP solves (the rest "
         "builds one model per horizon in array operations, passed to HiGHS whole, and the abstraction, the "
         "geometry's proof and the exact LP of the plan found); the next column compares lazy-smt with it.", "",
         "| instance | lazy-smt | milp-ltl | milp-ltl / lazy-smt | milp-ltl in HiGHS | HiGHS part / lazy-smt |",
         "|---|---|---|---|---|---|"]
    oneshot = any(p == "milp-ltl-oneshot" for _, p in cells)
    if oneshot:
        L[-3] += (" `milp-ltl-oneshot` is Wolff et al.'s setting as published: one MILP at the fixed horizon K = "
                  "the problem's max horizon (60), whose plan has exactly K steps (not the shortest; lazy-smt's "
                  "and milp-ltl's horizons are the shortest).")
        L[-2] += " milp-ltl-oneshot (horizon) | milp-ltl-oneshot / lazy-smt |"
        L[-1] += "---|---|"
    ratios, solve_ratios, oneshot_ratios = [], [], []
    for exp, setup in insts:
        a, b = cells.get((exp, "lazy-smt")), cells.get((exp, "milp-ltl"))
        c = cells.get((exp, "milp-ltl-oneshot"))
        rc = _ratio_value(c, a)
        if rc is not None:
            oneshot_ratios.append(rc[0])
        extra = ""
        if oneshot:
            horizon = f" (at {c.horizon})" if c is not None and c.solved and c.horizon is not None else ""
            extra = f" {c.text() if c else '-'}{horizon} | {_ratio(c, a)} |"
        rv = _ratio_value(b, a)
        if rv is not None:
            ratios.append(rv[0])
        hs = ((b.extra or {}).get("timings") or {}).get("milp_solve") if b is not None and b.solved else None
        ta = a.decided_time() if a is not None else None
        part = "-"
        if hs is not None and ta:
            solve_ratios.append(hs / max(ta, 1e-6))
            part = f"{hs / max(ta, 1e-6):.3g}"
        L.append(f"| {setup['name']} | {a.text() if a else '-'} | {b.text() if b else '-'} | {_ratio(b, a)} | "
                 f"{_fmt(hs)} | {part} |{extra}")
    L.append("")
    if ratios:
        L.append(f"Median speed-up of lazy-smt over milp-ltl: **{statistics.median(ratios):.3g}x** over {len(ratios)} "
                 "instances (a bound where the MILP ran out of time counts at the time limit).")
        if oneshot_ratios:
            L.append(f"Over milp-ltl-oneshot (one MILP at the max horizon): **{statistics.median(oneshot_ratios):.3g}x** "
                     f"in median over {len(oneshot_ratios)} instances.")
        if solve_ratios:
            L.append(f"Against the baseline's HiGHS time alone: {statistics.median(solve_ratios):.3g}x in median over "
                     f"{len(solve_ratios)} instances.")
        L.append("")
    return L


# lazy-smt configurations compared by their counterexamples (Section V), in table order
CX_VARIANTS = {
    "lazy-smt-paper": "paper's loop, ZEROPREFIX",
    "lazy-smt-paper-trivial": "paper's loop, trivial",
    "lazy-smt-zeroprefix": "our loop, ZEROPREFIX (Farkas-shrunk)",
}


def _counterexample_table(cells: Mapping[tuple[str, str], Cell], mazes: Sequence[tuple[str, dict[str, Any]]]) -> list[str]:
    """LP calls and time per maze for each counterexample configuration (median run)."""
    used = [p for p in ("lazy-smt", *CX_VARIANTS) if any((e, p) in cells for e, _ in mazes)]
    if len(used) < 2:
        return []
    names = {"lazy-smt": "our loop, Farkas (default)", **CX_VARIANTS}
    L = ["### Counterexamples (Section V): LP calls per maze", "",
         "The paper's loop (one horizon at a time, counterexamples as published, no refinement beyond the paper "
         "except the shared abstraction, segment safety and horizon lower bound) with ZEROPREFIX and with the "
         "trivial counterexample (block the whole sequence), and our loop (horizon windows, transit layer, guided "
         "DIS-PLAN) with ZEROPREFIX and with the default Farkas counterexample. Each cell: LP calls, then time "
         "(an unfinished run shows the LP calls made until its limit and the horizon it had reached: every "
         "shorter one was refuted).", ""]
    hdr = ["maze"] + [f"{names[p]}: LP calls" for p in used] + [f"{names[p]}: time" for p in used]
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))
    for exp, setup in mazes:
        row = [str(int(setup["params"]["n"]))]
        for p in used:
            c = cells.get((exp, p))
            lp = (c.extra or {}).get("lp_calls") if c else None
            mark = "" if c is None or c.all_solved else f" (unfinished, at horizon {c.horizon})"
            row.append("-" if lp is None else f"{lp}{mark}")
        row += [cells[(exp, p)].text() if (exp, p) in cells else "-" for p in used]
        L.append("| " + " | ".join(row) + " |")
    L.append("")
    return L


def _grid_table(cells: Mapping[tuple[str, str], Cell], insts: Sequence[tuple[str, dict[str, Any]]],
                planners: Sequence[str], *, paper: bool, expected: bool = False) -> list[str]:
    hdr = ["instance"] + (["paper (s)"] if paper else []) + (["expected"] if expected else [])
    for p in planners:
        hdr += [f"{p} (s)", f"{p} depth / l"]
    pairs = [(a, b) for a in planners for b in planners if a != b and b == "native"]
    hdr += [f"{a} / {b}" for a, b in pairs]
    out = ["| " + " | ".join(hdr) + " |", "|" + "---|" * len(hdr)]
    for exp, setup in insts:
        row = [setup["name"]]
        if paper:
            row.append(_fmt(setup.get("paper_seconds")))
        if expected:
            row.append(str(setup.get("expected") or "-"))
        for p in planners:
            c = cells.get((exp, p))
            row.append(c.text() if c else "-")
            row.append(f"{c.depth if c and c.depth is not None else '-'} / {c.steps if c and c.steps is not None else '-'}")
        for a, b in pairs:
            row.append(_ratio(cells.get((exp, a)), cells.get((exp, b))))
        out.append("| " + " | ".join(row) + " |")
    return out


def _plot_chain(cells: Mapping[tuple[str, str], Cell], chains: Sequence[tuple[str, dict[str, Any]]],
                planners: Sequence[str], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    by: dict[tuple[str, int], list[tuple[int, float, bool]]] = defaultdict(list)
    for exp, setup in chains:
        n, k = int(setup["params"]["n"]), int(setup["params"]["k"])
        for p in planners:
            c = cells.get((exp, p))
            if c is None:
                continue
            t = c.decided_time()
            if t is not None:
                by[(p, n)].append((2 * k, t, False))
            elif c.out_of_time and c.limit:
                by[(p, n)].append((2 * k, c.limit, True))
    styles = ["-", "--", ":", "-."]
    for (p, n), pts in sorted(by.items()):
        pts.sort()
        done = [(x, y) for x, y, u in pts if not u]
        line = ax.plot([x for x, _ in done], [max(y, 1e-3) for _, y in done], linestyle=styles[planners.index(p) % 4],
                       marker="o", label=f"{p}, {n} passage{'s' if n > 1 else ''}")[0]
        unl = [(x, y) for x, y, u in pts if u]
        if unl:
            ax.plot([x for x, _ in unl], [y for _, y in unl], "x", markersize=9, mew=2, color=line.get_color())
    ax.plot([50, 50], [1.64, 152], "k|", markersize=12, label="paper at n = 50: 1.64 s .. 152 s")
    ax.set_yscale("log")
    ax.set_xlabel("number of states n (= 2k)")
    ax.set_ylabel("time (s, log scale); x: no answer within the limit")
    ax.set_title("Reach, Figure 4: scalability with the number of states", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


def _answer(c: Cell | None) -> str:
    if c is None:
        return "-"
    if c.solved:
        return "realizable" if c.all_solved else f"realizable ({c.solved}/{c.runs})"
    return "/".join(sorted(c.statuses))


def _paper_regression(cells: Mapping[tuple[str, str], Cell], planner: str = "native") -> str:
    """Issue 11's "no regression on the paper's families": every instance solved in under
    1 s (median solve time) with a program no deeper than the paper's; one line."""
    from plansynth.bench.families import PAPER_FAMILIES, paper_depth

    got = [(setup["name"], cells[(exp, planner)]) for f in PAPER_FAMILIES for exp, setup in _instances(cells, f)
           if (exp, planner) in cells]
    if not got:
        return ""
    solved = [(n, c) for n, c in got if c.all_solved and c.median is not None]
    under = [n for n, c in solved if c.median < 1.0]
    shallow = [n for n, c in solved if c.depth is not None and c.depth <= paper_depth(n)]
    slowest = max(solved, key=lambda nc: nc[1].median, default=None)
    verdict = "holds" if len(under) == len(shallow) == len(got) else "FAILS"
    return (f"**No regression on the paper's families** ({planner}, {len(got)} instances): solved {len(solved)}/"
            f"{len(got)}, under 1 s {len(under)}/{len(got)}"
            + (f" (slowest {slowest[0]}, {_fmt(slowest[1].median)} s)" if slowest else "")
            + f", depth at most the paper's {len(shallow)}/{len(got)}: {verdict}. "
            "`--minimize` proving the depth family's minimal depths is a test "
            "(`tests/grid/test_native.py::test_minimize_proves_the_depth_family`).")


def _suite_table(cells: Mapping[tuple[str, str], Cell], insts: Sequence[tuple[str, dict[str, Any]]],
                 planners: Sequence[str]) -> list[str]:
    """Per instance and solver (issue 11, Targets): the wall time of the run through the
    CLI in a fresh process (start-up included), the solve time the result reports, the
    answer and whether it matches the certified label, the program depth, depth minus
    the label's witness depth, ``depth_minimal``, and whether ``--timeout T`` was kept
    (the process ended within T + 1 s). A summary line per solver comes first."""
    hdr = ["instance", "label", "witness depth"]
    for p in planners:
        hdr += [f"{p} wall (s)", f"{p} solve (s)", f"{p} answer", f"{p} matches", f"{p} depth", f"{p} depth - witness",
                f"{p} depth_minimal", f"{p} budget kept"]
    rows = ["| " + " | ".join(hdr) + " |", "|" + "---|" * len(hdr)]
    summary: dict[str, dict[str, list[Any]]] = {p: {"ok": [], "wrong": [], "wall": [], "dd": [], "kept": [], "proved": []}
                                               for p in planners}
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
            ok = (expected == "realizable" and c.all_solved) or (expected == "unrealizable"
                                                                 and set(c.statuses) == {"unrealizable"})
            # a wrong answer contradicts the label; unknown or timeout is no answer
            wrong = (expected == "realizable" and "unrealizable" in c.statuses) or (expected == "unrealizable"
                                                                                   and c.solved > 0)
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
            row += [_fmt(wall), _fmt(t), _answer(c), "yes" if ok else "WRONG" if wrong else "no answer",
                    str(c.depth) if c.solved and c.depth is not None else "-", dd,
                    str(ex.get("depth_minimal") or "-") if c.solved else "-",
                    ("yes" if all(kept) else "NO") if kept else "-"]
        rows.append("| " + " | ".join(row) + " |")
    lines = [_suite_summary(p, summary[p]) for p in planners if summary[p]["ok"]]
    return lines + [""] + rows


def _suite_summary(planner: str, sm: Mapping[str, list[Any]]) -> str:
    """One line: correct answers, median and max CLI wall, depth against the witnesses,
    budgets kept (issue 11's Targets, in the order it states them)."""
    wall = (f"wall through the CLI median {_fmt(statistics.median(sm['wall']))} s, max {_fmt(max(sm['wall']))} s"
            if sm["wall"] else "no CLI wall recorded")
    dd = (f"depth - witness depth median {statistics.median(sm['dd']):+g}, max {max(sm['dd']):+d} "
          f"({len(sm['dd'])} programs)" if sm["dd"] else "no depth against a witness")
    kept = f"budget kept {sum(sm['kept'])}/{len(sm['kept'])}" if sm["kept"] else "budget not recorded"
    proved = f"; depth_minimal proved on {sum(sm['proved'])}/{len(sm['proved'])}" if sm["proved"] else ""
    return (f"- **{planner}**: correct {sum(sm['ok'])}/{len(sm['ok'])} ({sum(sm['wrong'])} contradict the label); "
            f"{wall}; {dd}; {kept}{proved}.")
