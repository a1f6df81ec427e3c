"""Runs timed through the CLI (their timing targets): a fresh ``plansynth grid solve``
process per run, its wall clock beside the solve time, the budget check T + 1 s."""

from __future__ import annotations

import json
import sys

import yaml

from plansynth.bench import execute as execute_module
from plansynth.bench.db import ResultsDB
from plansynth.bench.execute import grid as grid_run
from plansynth.bench.families import CLI_TIMED_FAMILIES, grid_family
from plansynth.bench.runner import run_sweep
from plansynth.bench.tasks import make_tasks


def _suite(tmp_path, monkeypatch):
    """A one-problem reactive suite: lanes-1 with a label, in a folder of its own."""
    (inst,) = grid_family("lanes", [1])
    suite = tmp_path / "suite"
    suite.mkdir()
    (suite / "r99_lanes.yaml").write_text(yaml.safe_dump(inst.document()), encoding="utf-8")
    (suite / "r99_lanes.label.json").write_text(
        json.dumps({"expected": "realizable", "witness_depth": 6}), encoding="utf-8"
    )
    monkeypatch.setenv("PLANSYNTH_REACTIVE_SUITE", str(suite))
    return grid_family("reactive-suite")


def test_a_suite_run_is_a_cli_process_whose_wall_includes_start_up(tmp_path, monkeypatch):
    # in this process (execute, as the runner's child calls it): the runner's children come
    # from a fork server that may have started before monkeypatch set the suite's folder
    insts = _suite(tmp_path, monkeypatch) + grid_family("doors-rush", [1])
    assert {i.family for i in insts} <= CLI_TIMED_FAMILIES
    suite, rush = (execute_module.execute(t) for t in make_tasks(insts, ["native"], timeout=20))
    a = suite["attributes"]
    assert suite["status"] == "solved", suite["message"]
    assert suite["valid"] == 1 and suite["depth"] >= 1
    assert a["exit_status"] == 0 and a["budget_kept"] is True
    assert a["depth_minimal"] in ("proved", "not proved")
    # the process's wall clock holds the solve time the result file reports, and start-up
    assert 0 < suite["time"] < a["cli_wall"] <= suite["wall"]
    # the command as a user types it, naming no folder of this machine
    assert a["command"] == "plansynth grid solve r99_lanes.yaml --solver native --timeout 20 --out result.json"
    assert rush["status"] == "unrealizable" and rush["attributes"]["exit_status"] == 1
    assert str(tmp_path) not in json.dumps(rush["attributes"])


def test_a_cli_run_that_overruns_is_killed_and_counted_as_a_broken_budget(monkeypatch):
    """A command that ignores its budget (here: a sleep in place of the solver) is killed
    4 s past T and recorded as a timeout with the budget not kept; no result is read."""
    (inst,) = grid_family("doors", [1])
    monkeypatch.setattr(
        grid_run,
        "_cli_command",
        lambda *a, **k: [sys.executable, "-c", "import time, sys; print('grid'); time.sleep(60)", "grid"],
    )
    (task,) = make_tasks([inst], ["native"], timeout=0.5)
    attrs = execute_module.execute(task)
    assert attrs["status"] == "timeout" and attrs["solved"] == 0
    assert attrs["attributes"]["budget_kept"] is False
    assert 4.5 <= attrs["attributes"]["cli_wall"] < 30


def test_a_cli_run_that_the_cli_refuses_is_a_crash_with_its_message():
    (inst,) = grid_family("doors", [1])
    (task,) = make_tasks([inst], ["native"], timeout=5, options={"native": {"no_such_option": "1"}})
    attrs = execute_module.execute(task)
    assert attrs["status"] == "crash" and attrs["attributes"]["exit_status"] == 2
    assert "no_such_option" in attrs["message"]


def test_the_runner_records_a_cli_run_with_its_attributes(tmp_path):
    insts = grid_family("doors", [1])
    run_sweep(tmp_path / "r.db", make_tasks(insts, ["native"], timeout=20), progress=False)
    with ResultsDB(tmp_path / "r.db") as db:
        (run,) = db.runs()
    assert run["status"] == "solved", run["message"]
    assert run["time"] < run["attributes"]["cli_wall"] <= run["wall"]
    assert run["attributes"]["budget_kept"] is True and run["attributes"]["timelimit"] == 20
