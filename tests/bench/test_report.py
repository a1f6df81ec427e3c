"""Report generation on a small hand-made database: tables, ratios, plots."""

from __future__ import annotations

from plansynth.bench.db import ResultsDB
from plansynth.bench.families import grid_family, reach_family
from plansynth.bench.report import headline, summarise, write_report


def _fill(path):
    with ResultsDB(path) as db:
        for inst, t_native, t_cvc5 in zip(grid_family("steps", [5, 10, 15]), [0.1, 0.2, 0.4], [1.0, 4.0, None]):
            e = db.experiment(
                inst.key, kind="grid", family="steps", instance=inst.name, setup=inst.to_dict(), timelimit=60
            )
            pn, pc = db.planner("native", {}), db.planner("cvc5", {})
            db.add_run(
                e, pn, 0, {"time": t_native, "status": "solved", "solved": 1, "valid": 1, "depth": 4, "steps": 5}
            )
            if t_cvc5 is None:
                db.add_run(e, pc, 0, {"time": 60.0, "status": "timeout", "solved": 0})
            else:
                db.add_run(
                    e, pc, 0, {"time": t_cvc5, "status": "solved", "solved": 1, "valid": 1, "depth": 4, "steps": 5}
                )
        (maze,) = reach_family("maze", [1])
        e = db.experiment(maze.key, kind="reach", family="maze", instance=maze.name, setup=maze.to_dict(), timelimit=60)
        for name, t in [("lazy-smt", 0.5), ("rrt", 5.0), ("milp-bigm", 50.0)]:
            db.add_run(
                e,
                db.planner(name, {}),
                0,
                {
                    "time": t,
                    "status": "solved",
                    "solved": 1,
                    "valid": 1,
                    "horizon": 40,
                    "lp_calls": 3,
                    "sat_calls": 4,
                    "attributes": {"timings": {"abstraction": 0.01, "sat": 0.2, "lp": 0.3}},
                },
            )
        for name, lp, status in [
            ("lazy-smt-paper", 299, "solved"),
            ("lazy-smt-paper-trivial", 618, "solved"),
            ("lazy-smt-zeroprefix", 54, "unknown"),
        ]:
            db.add_run(
                e,
                db.planner(name, {}),
                0,
                {
                    "time": 0.3,
                    "status": status,
                    "solved": int(status == "solved"),
                    "valid": 1,
                    "horizon": 57,
                    "lp_calls": lp,
                },
            )
        for k in (1, 2):
            (ch,) = [i for i in reach_family("chain", [1], orders=[k])]
            e = db.experiment(ch.key, kind="reach", family="chain", instance=ch.name, setup=ch.to_dict(), timelimit=60)
            db.add_run(e, db.planner("lazy-smt", {}), 0, {"time": 0.5 * k, "status": "solved", "solved": 1, "valid": 1})


def test_summary_and_headline_ratios(tmp_path):
    _fill(tmp_path / "r.db")
    with ResultsDB(tmp_path / "r.db") as db:
        cells = summarise(db.runs())
    h = headline(cells, "cvc5", "native", "grid/")
    assert h["n"] == 2
    assert h["median"] == 15.0  # ratios 10 and 20
    assert h["worst_for_b"] == (20.0, "grid/steps/steps-10")
    assert h["bounds"] == [(150.0, "grid/steps/steps-15", ">")]  # 60 s limit / 0.4 s


def test_report_tables_and_plots(tmp_path):
    _fill(tmp_path / "r.db")
    out = tmp_path / "rep"
    path = write_report(tmp_path / "r.db", out, planned=[("grid/steps/steps-20", "native", 0)])
    text = path.read_text()
    assert "Figure 3: time vs number of steps" in text
    assert "| steps-5 | 4.2 |" in text  # the paper's number beside ours
    assert "> 60 (1 timeout)" in text
    assert "| 10 |" in text or "10 |" in text  # cvc5 / native ratio column
    assert "Table I" in text and "| 1 | 2.39 | 10.4 | > 7200 |" in text
    assert "rrt/lazy-smt 10" in text
    assert "missing: 1" in text and "grid/steps/steps-20 native #0" in text
    # the counterexample configurations get their own table, not Table I columns
    assert "Counterexamples (Section V): LP calls per maze" in text
    assert "| 1 | 3 | 299 | 618 | 54 (unfinished, at horizon 57) |" in text
    assert "lazy-smt-paper |" not in text.split("Counterexamples")[0]
    for png in ("grid-steps.png", "reach-table1.png", "reach-figure4.png"):
        assert (out / png).stat().st_size > 5000


def test_the_proved_minimal_table_beside_the_window_search():
    from plansynth.bench.report import Cell
    from plansynth.bench.report.horizons import minimal_table

    mazes = [("reach/maze/maze-1", {"params": {"n": 1}}), ("reach/maze/maze-2", {"params": {"n": 2}})]
    claim = {"minimal": True, "minimal_relative_to": "decomposition", "minimal_probes": 1}
    cells = {
        ("reach/maze/maze-1", "lazy-smt"): Cell(1, 1, 0.1, 0.1, 60.0, {"solved": 1}, horizon=62, extra={}),
        ("reach/maze/maze-1", "lazy-smt-minimal"): Cell(
            1,
            1,
            0.3,
            0.3,
            60.0,
            {"solved": 1},
            horizon=57,
            extra={"minimal": claim, "lp_calls": 36, "timings": {"minimal": 0.2}},
        ),
        ("reach/maze/maze-2", "lazy-smt"): Cell(1, 1, 0.2, 0.2, 60.0, {"solved": 1}, horizon=92, extra={}),
        ("reach/maze/maze-2", "lazy-smt-minimal"): Cell(
            1, 1, 60.0, 60.0, 60.0, {"solved": 1}, horizon=90, extra={"minimal": {"minimal": False}, "lp_calls": 900}
        ),
    }
    text = "\n".join(minimal_table(cells, mazes))
    assert "| 1 | 0.1 | 62 | 0.3 | 57 | decomposition | 1 | 36 | 0.2 | 3 |" in text
    assert "| 2 | 0.2 | 92 | 60 | not proved | - | - | 900 | - | 300 |" in text
    assert minimal_table({k: v for k, v in cells.items() if k[1] == "lazy-smt"}, mazes) == []


def test_the_reactive_suite_table_tells_wrong_answers_from_no_answer():
    from plansynth.bench.report import Cell
    from plansynth.bench.report.suite import suite_table

    insts = [
        ("grid/reactive-suite/a", {"name": "a", "expected": "realizable", "params": {"witness_depth": 7}}),
        ("grid/reactive-suite/b", {"name": "b", "expected": "unrealizable", "params": {}}),
        ("grid/reactive-suite/c", {"name": "c", "expected": "realizable", "params": {"witness_depth": 5}}),
        ("grid/reactive-suite/d", {"name": "d", "expected": "realizable", "params": {"witness_depth": 4}}),
    ]
    run = {"budget_kept": [True], "depth_minimal": "not proved"}
    cells = {
        ("grid/reactive-suite/a", "native"): Cell(
            1, 1, 0.1, 0.1, 60.0, {"solved": 1}, depth=8, extra={"median_any": 0.1, "cli_wall": 0.9, **run}
        ),
        ("grid/reactive-suite/b", "native"): Cell(
            1,
            0,
            None,
            None,
            60.0,
            {"unrealizable": 1},
            extra={"median_any": 0.2, "cli_wall": 1.2, "budget_kept": [True]},
        ),
        ("grid/reactive-suite/c", "native"): Cell(
            1,
            0,
            None,
            None,
            60.0,
            {"unrealizable": 1},
            extra={"median_any": 0.3, "cli_wall": 1.5, "budget_kept": [True]},
        ),
        ("grid/reactive-suite/d", "native"): Cell(
            1, 0, None, None, 60.0, {"unknown": 1}, extra={"median_any": 60.0, "cli_wall": 61.7, "budget_kept": [False]}
        ),
    }
    text = "\n".join(suite_table(cells, insts, ["native"]))
    assert (
        "- **native**: correct 2/4 (1 contradict the label); wall through the CLI median 1.35 s, max 61.7 s; "
        "depth - witness depth median +1, max +1 (1 programs); budget kept 3/4; depth_minimal proved on 0/1."
    ) in text
    assert "| a | realizable | 7 | 0.9 | 0.1 | realizable | yes | 8 | +1 | not proved | yes |" in text
    assert "| c | realizable | 5 | 1.5 | 0.3 | unrealizable | WRONG | - | - | - | yes |" in text
    assert "| d | realizable | 4 | 61.7 | 60 | unknown | no answer | - | - | - | NO |" in text


def test_the_paper_regression_line_fails_on_a_slow_or_deep_instance():
    from plansynth.bench.report import Cell
    from plansynth.bench.report.grid import paper_regression

    def cell(name, t, d):
        fam = name.rsplit("-", 1)[0]
        return Cell(
            1,
            1,
            t,
            t,
            120.0,
            {"solved": 1},
            depth=d,
            extra={"family": fam, "instance": name, "setup": {"name": name, "params": {}}},
        )

    good = {
        ("grid/depth/depth-4", "native"): cell("depth-4", 0.01, 4),
        ("grid/steps/steps-25", "native"): cell("steps-25", 0.3, 4),
    }
    assert (
        "solved 2/2, under 1 s 2/2 (slowest steps-25, 0.3 s), depth at most the paper's 2/2: holds"
        in paper_regression(good)
    )
    slow = {**good, ("grid/steps/steps-20", "native"): cell("steps-20", 1.5, 4)}
    assert "under 1 s 2/3 (slowest steps-20, 1.5 s), depth at most the paper's 3/3: FAILS" in paper_regression(slow)
    deep = {**good, ("grid/depth/depth-1", "native"): cell("depth-1", 0.01, 2)}
    assert "depth at most the paper's 2/3: FAILS" in paper_regression(deep)


def test_the_missions_table_shows_the_baselines_highs_time_beside_its_total(tmp_path):
    from plansynth.bench.report.missions import missions_table

    with ResultsDB(tmp_path / "m.db") as db:
        for inst, (t_lazy, t_milp, t_highs) in zip(
            reach_family("missions", [1]), [(0.5, 5.0, 1.0), (2.0, 10.0, 9.0), (0.25, 5.0, 0.5)]
        ):
            e = db.experiment(
                inst.key, kind="reach", family="missions", instance=inst.name, setup=inst.to_dict(), timelimit=300
            )
            db.add_run(e, db.planner("lazy-smt", {}), 0, {"time": t_lazy, "status": "solved", "solved": 1, "valid": 1})
            db.add_run(
                e,
                db.planner("milp-ltl", {}),
                0,
                {
                    "time": t_milp,
                    "status": "solved",
                    "solved": 1,
                    "valid": 1,
                    "attributes": {"timings": {"milp_solve": t_highs}},
                },
            )
        cells = summarise(db.runs())
    text = "\n".join(missions_table(cells))
    assert "| maze-1-visit | 0.5 | 5 | 10 | 1 | 2 |" in text
    assert "**10x** over 3 instances" in text  # ratios 10, 5, 20
    assert "HiGHS time alone: 2x in median over 3 instances" in text  # 2, 4.5, 2
    assert "milp-ltl-oneshot" not in text  # no such runs: no such columns


def test_the_missions_table_adds_the_one_shot_baseline_with_its_horizon(tmp_path):
    from plansynth.bench.report.missions import missions_table

    with ResultsDB(tmp_path / "m.db") as db:
        for inst, (t_lazy, t_one) in zip(reach_family("missions", [1]), [(0.5, 6.0), (2.0, 4.0), (0.25, 5.0)]):
            e = db.experiment(
                inst.key, kind="reach", family="missions", instance=inst.name, setup=inst.to_dict(), timelimit=300
            )
            db.add_run(e, db.planner("lazy-smt", {}), 0, {"time": t_lazy, "status": "solved", "solved": 1, "valid": 1})
            db.add_run(e, db.planner("milp-ltl", {}), 0, {"time": 1.0, "status": "solved", "solved": 1, "valid": 1})
            db.add_run(
                e,
                db.planner("milp-ltl-oneshot", {}),
                0,
                {"time": t_one, "status": "solved", "solved": 1, "valid": 1, "horizon": 60},
            )
        cells = summarise(db.runs())
    text = "\n".join(missions_table(cells))
    assert "| milp-ltl-oneshot (horizon) | milp-ltl-oneshot / lazy-smt |" in text
    assert "| maze-1-visit | 0.5 | 1 | 2 | - | - | 6 (at 60) | 12 |" in text
    assert (
        "Over milp-ltl-oneshot (one MILP at the max horizon): **12x** in median over 3 instances" in text
    )  # 12, 2, 20


def test_the_published_missions_run_gives_the_baseline_time_to_finish():
    """A measured milp-ltl time, not a timeout bound, makes the speed-up honest."""
    from plansynth.bench.publish import MISSIONS_TIMEOUT, published_tasks

    tasks = [t for t in published_tasks(part="reach") if "/missions/" in t["experiment"]]
    assert len(tasks) == 36 and {t["solver"] for t in tasks} == {"lazy-smt", "milp-ltl", "milp-ltl-oneshot"}
    assert {t["timeout"] for t in tasks} == {MISSIONS_TIMEOUT} and MISSIONS_TIMEOUT >= 300


def test_the_gcs_maze_table_puts_both_planners_side_by_side(tmp_path):
    """The GCS paper's mazes: regions, lazy-smt's horizon, work and time, gcs's time and
    curve duration, gcs with no answer shown as such, and the shortest plan of the run."""
    from plansynth.bench.report.gcs import gcs_maze_table

    with ResultsDB(tmp_path / "g.db") as db:
        for inst, (t_lazy, t_gcs) in zip(reach_family("gcs-maze", [10, 50]), [(0.5, 4.0), (50.0, None)]):
            e = db.experiment(
                inst.key, kind="reach", family="gcs-maze", instance=inst.name, setup=inst.to_dict(), timelimit=120
            )
            regions = 55 if inst.params["n"] == 10 else 1571
            db.add_run(
                e,
                db.planner("lazy-smt", {}),
                0,
                {
                    "time": t_lazy,
                    "status": "solved",
                    "solved": 1,
                    "valid": 1,
                    "horizon": 60,
                    "regions": regions,
                    "lp_calls": 12,
                    "sat_calls": 3,
                    "attributes": {"duration": 30.0, "counters": {"lp_calls": 12, "clauses": 3400}},
                },
            )
            if t_gcs is None:
                db.add_run(
                    e, db.planner("gcs", {}), 0, {"time": 130.0, "status": "unknown", "solved": 0, "regions": regions}
                )
            else:
                db.add_run(
                    e,
                    db.planner("gcs", {}),
                    0,
                    {
                        "time": t_gcs,
                        "status": "solved",
                        "solved": 1,
                        "valid": 1,
                        "regions": regions,
                        "attributes": {"duration": 20.0, "counters": {"regions": 52}},
                    },
                )
        cells = summarise(db.runs())
    text = "\n".join(gcs_maze_table(cells))
    assert "| 10 | 55 / 52 | 60, 12 / 3 | 0.5 | 4 | 8 |" in text
    assert "| 50 | 1571 / - | 60, 12 / 3 | 50 | > 120 (1 unknown) | > 2.4 |" in text
    # the plans' durations: gcs's curve is the shortest at n = 10, lazy-smt's the only one at 50
    assert "| 10 | 30 | 20 | 20 (gcs) | 1.5 |" in text
    assert "| 50 | 30 | - | 30 (lazy-smt) | 1 |" in text


def test_a_run_that_gave_up_early_bounds_no_ratio(tmp_path):
    """gcs ending `unknown` after 13 s of a 120 s limit (an iteration limit, not the
    clock) says nothing about how long it would take: no "> 120 / t" ratio, and its cell
    says when it gave up."""
    from plansynth.bench.report.gcs import gcs_maze_table

    with ResultsDB(tmp_path / "g.db") as db:
        inst = reach_family("gcs-maze", [20])[0]
        e = db.experiment(
            inst.key, kind="reach", family="gcs-maze", instance=inst.name, setup=inst.to_dict(), timelimit=120
        )
        db.add_run(
            e,
            db.planner("lazy-smt", {}),
            0,
            {
                "time": 3.5,
                "status": "solved",
                "solved": 1,
                "valid": 1,
                "horizon": 532,
                "regions": 249,
                "attributes": {"duration": 266.0, "counters": {"lp_calls": 18, "clauses": 3807}},
            },
        )
        db.add_run(e, db.planner("gcs", {}), 0, {"time": 13.1, "status": "unknown", "solved": 0, "regions": 249})
        cells = summarise(db.runs())
    row = next(line for line in gcs_maze_table(cells) if line.startswith("| 20 |"))
    assert "no answer (1 unknown after 13.1 s of 120)" in row
    assert row.endswith("| - |"), row  # no gcs / lazy-smt ratio


def test_every_published_grid_family_has_a_table(tmp_path):
    """A family the published sweep runs but no table shows is work thrown away: the
    30 x 30 families (roads30, roads30-stall, guards30) were swept and shown nowhere."""
    from plansynth.bench.families import GRID_FAMILIES

    names = {}
    with ResultsDB(tmp_path / "r.db") as db:
        pn = db.planner("native", {})
        for fam in GRID_FAMILIES:
            if fam == "reactive-suite":  # its own table, tested above (its instances live outside the repository)
                continue
            inst = grid_family(fam)[0]
            e = db.experiment(inst.key, kind="grid", family=fam, instance=inst.name, setup=inst.to_dict(), timelimit=60)
            db.add_run(e, pn, 0, {"time": 0.123, "status": "solved", "solved": 1, "valid": 1, "depth": 3, "steps": 9})
            names[fam] = inst.name
    text = write_report(tmp_path / "r.db", tmp_path / "rep").read_text()
    shown = {fam for fam, name in names.items() if f"| {name} |" in text}
    assert shown == set(names), f"families without a table: {sorted(set(names) - shown)}"
