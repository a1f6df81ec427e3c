"""The runner: isolation (hang -> timeout, crash -> crash), results kept, resume."""

from __future__ import annotations

import pytest

from plansynth.bench.db import ResultsDB
from plansynth.bench.families import grid_family
from plansynth.bench.runner import run_sweep
from plansynth.bench.tasks import make_tasks


def _tasks(solvers, repeat=1):
    tasks = make_tasks(grid_family("depth", [1]), solvers, repeat=repeat, timeout=0.5, memory_mb=2048)
    for t in tasks:
        t["grace"] = 1.0  # keep the hung child's kill quick
    return tasks


@pytest.fixture(scope="module", autouse=True)
def _fork_server_started(tmp_path_factory):
    """Start the fork server (and its preloaded solver modules) before the timed runs:
    its first start counts against a child's deadline, and these tests give children
    0.5 s plus 1 s of grace. In the whole suite another test has usually started it."""
    db = tmp_path_factory.mktemp("warm") / "w.db"
    tasks = make_tasks(grid_family("depth", [1]), ["debug-ok"], repeat=1, timeout=120, memory_mb=2048)
    assert run_sweep(db, tasks, jobs=1, progress=False)["done"] == 1


def _by_solver(db_path):
    with ResultsDB(db_path) as db:
        return {(r["planner"], r["repeat"]): r for r in db.runs()}


def test_hang_and_crash_are_recorded_and_others_survive(tmp_path):
    db = tmp_path / "r.db"
    counts = run_sweep(db, _tasks(["debug-sleep", "debug-crash", "debug-raise", "debug-ok"]), jobs=2, progress=False)
    runs = _by_solver(db)
    assert counts["done"] == 4
    assert runs[("debug-sleep", 0)]["status"] == "timeout"
    assert runs[("debug-sleep", 0)]["solved"] == 0
    assert runs[("debug-crash", 0)]["status"] == "crash"
    assert "SIGSEGV" in runs[("debug-crash", 0)]["message"]
    assert runs[("debug-raise", 0)]["status"] == "crash"
    assert "debug-raise: a solver bug" in runs[("debug-raise", 0)]["message"]
    ok = runs[("debug-ok", 0)]
    assert (ok["status"], ok["solved"], ok["valid"]) == ("solved", 1, 1)
    assert ok["memory"] > 0 and ok["wall"] > 0


def test_interrupted_sweep_resumes_and_skips_done_runs(tmp_path):
    db = tmp_path / "r.db"
    tasks = _tasks(["debug-ok"], repeat=4)
    seen = []

    def interrupt_after_two(task, attrs):
        seen.append(task["repeat"])
        if len(seen) == 2:
            raise KeyboardInterrupt  # as if the user pressed Ctrl-C mid-sweep

    with pytest.raises(KeyboardInterrupt):
        run_sweep(db, tasks, progress=False, on_result=interrupt_after_two)
    with ResultsDB(db) as d:
        done_before = d.done_keys()
    # the two recorded runs, and the third if it finished before its child could be
    # killed (every finished run is kept); the fourth never started
    assert len(done_before) in (2, 3)
    counts = run_sweep(db, tasks, progress=False)
    assert counts["skipped"] == len(done_before) and counts["done"] == 4 - len(done_before)
    with ResultsDB(db) as d:
        assert {k[2] for k in d.done_keys()} == {0, 1, 2, 3}
        assert len(d.runs()) == 4
    # a third invocation has nothing left to do
    assert run_sweep(db, tasks, progress=False) == {"skipped": 4, "done": 0}


def test_real_grid_solver_run_is_verified(tmp_path):
    db = tmp_path / "r.db"
    tasks = make_tasks(grid_family("depth", [4]), ["native"], timeout=20)
    run_sweep(db, tasks, progress=False)
    (run,) = _by_solver(db).values()
    assert run["status"] == "solved" and run["valid"] == 1
    assert run["depth"] == 4 and run["steps"] == 5
    assert run["attributes"]["program"]


def test_retry_reruns_only_runs_with_the_given_statuses(tmp_path):
    db = tmp_path / "r.db"
    tasks = _tasks(["debug-raise", "debug-ok"])
    run_sweep(db, tasks, progress=False)
    counts = run_sweep(db, tasks, progress=False, retry=["crash"])
    assert counts["skipped"] == 1 and counts["done"] == 1 and counts["crash"] == 1
    with ResultsDB(db) as d:
        assert len(d.runs()) == 2  # the rerun replaced the crashed row


def test_a_program_the_verifier_refutes_is_recorded_invalid(tmp_path):
    """A backend that answers with a losing program gave status unknown (the message said
    "refutes", the runner looked for "verif" and "fail"): a wrong answer hid among the
    timeouts (found by a review). It is recorded invalid."""
    import stat

    from plansynth.bench.execute import execute

    fake = tmp_path / "fake.sh"  # a SyGuS "solver" that always answers "stay"
    fake.write_text(
        "#!/bin/sh\necho '(define-fun move ((rx Int) (ry Int) (o0x Int) (o0y Int) (o1x Int) (o1y Int)) Int 0)'\n"
    )
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    (task,) = make_tasks(
        grid_family("figure1"), ["external"], timeout=30, options={"external": {"command": f"{fake} {{file}}"}}
    )
    out = execute(task)
    assert out["status"] == "invalid", out


def test_a_run_under_other_solver_options_is_not_taken_as_done(tmp_path):
    """Resuming compared only the time and memory limits: a sweep with -O
    native:minimize=true skipped the runs made without it (found by a review)."""
    db = tmp_path / "r.db"
    plain = make_tasks(grid_family("depth", [4]), ["native"], timeout=20)
    counts = run_sweep(db, plain, progress=False)
    assert counts["done"] == 1
    assert run_sweep(db, plain, progress=False)["skipped"] == 1  # the same options: resumed
    minimize = make_tasks(grid_family("depth", [4]), ["native"], timeout=20, options={"native": {"minimize": True}})
    counts = run_sweep(db, minimize, progress=False)
    assert counts["skipped"] == 0 and counts["done"] == 1
    (run,) = _by_solver(db).values()
    assert run["attributes"]["options"] == {"minimize": True}
