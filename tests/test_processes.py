"""No process left behind: the ``plansynth`` command is started in a
fresh process, stopped by a signal, and none of its descendants may survive it.
(Linux: PR_SET_PDEATHSIG and /proc, as in CI.)
"""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import psutil
import pytest

ROOT = Path(__file__).resolve().parents[1]
GRID = ROOT / "examples" / "grid"


def start(*args: str) -> subprocess.Popen:
    """``plansynth ARGS`` in its own session (so that a "terminal" signal can go to its group)."""
    return subprocess.Popen(
        [sys.executable, "-m", "plansynth.cli", *args],
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )


def wait_for(predicate, timeout: float = 90.0, what: str = "") -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


def family(proc: subprocess.Popen) -> list[psutil.Process]:
    try:
        return psutil.Process(proc.pid).children(recursive=True)
    except psutil.NoSuchProcess:
        return []


def assert_all_gone(procs: list[psutil.Process], timeout: float = 10.0) -> None:
    _, alive = psutil.wait_procs(procs, timeout=timeout)
    alive = [p for p in alive if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
    for p in alive:  # leave the machine clean for the next test, then fail
        p.kill()
    assert not alive, [" ".join(p.cmdline())[:80] for p in alive]


def cvc5_running(proc: subprocess.Popen) -> list[psutil.Process]:
    """The descendants once the cvc5 worker runs: fork server, worker, resource tracker."""
    found: list[psutil.Process] = []

    def ready() -> bool:
        nonlocal found
        found = family(proc)
        return len(found) >= 3

    wait_for(ready, what="the cvc5 worker")
    time.sleep(0.5)
    return family(proc)


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM, signal.SIGINT])
def test_killing_a_cvc5_solve_leaves_no_worker_fork_server_or_tracker(sig):
    proc = start("grid", "solve", str(GRID / "depth-5.yaml"), "--solver", "cvc5")
    try:
        kids = cvc5_running(proc)
        if sig == signal.SIGINT:
            os.killpg(proc.pid, sig)  # Ctrl-C: to the foreground group (the fork server ignores it)
        else:
            os.kill(proc.pid, sig)
        proc.wait(30)
        assert_all_gone(kids)
        out = proc.stdout.read().decode(errors="replace")
        assert "Traceback" not in out and "BrokenPipeError" not in out, out
        if sig != signal.SIGKILL:
            assert proc.returncode == 130, out  # unwound like Ctrl-C, clean-up ran
    finally:
        proc.kill()
        proc.wait()


def test_ctrl_c_during_a_reach_solve_exits_130(tmp_path):
    import yaml

    from plansynth.reach.families import maze
    from plansynth.reach.fileformat import reach_problem_to_dict

    problem = tmp_path / "slow.yaml"
    problem.write_text(yaml.safe_dump(reach_problem_to_dict(maze(2, order=25))))
    # CPU seconds the command needs to start (imports), measured on this machine
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, "-m", "plansynth.cli", "reach", "solve", "--help"], cwd=ROOT, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    startup = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    # one horizon at a time: about 13 s of LPs (the default window search plans it in ~2 s)
    proc = start("reach", "solve", str(problem), "-O", "horizon_search=linear", "-O", "exact_segments=false")
    try:

        def solving() -> bool:  # started up, then a CPU second into the solve (it needs far more)
            cpu = psutil.Process(proc.pid).cpu_times()
            return cpu.user + cpu.system > startup + 1.0

        wait_for(solving, timeout=240, what="the solve")
        assert proc.poll() is None
        os.killpg(proc.pid, signal.SIGINT)
        out, _ = proc.communicate(timeout=30)
        assert proc.returncode == 130, out
        assert b"Traceback" not in out, out
    finally:
        proc.kill()
        proc.wait()


def _hang(tmp_path: Path) -> str:
    script = tmp_path / "hang.py"
    script.write_text("import time\ntime.sleep(300)\n")
    return f"{sys.executable} {script} {{file}}"


def test_ctrl_c_with_an_external_solver_and_no_timeout_stops_it(tmp_path):
    proc = start("grid", "solve", str(GRID / "figure1.yaml"), "--solver", "external", "--command", _hang(tmp_path))
    try:
        wait_for(lambda: any("hang.py" in " ".join(p.cmdline()) for p in family(proc)), what="the external solver")
        kids = family(proc)
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C: the terminal signals the foreground group
        proc.wait(30)
        assert proc.returncode == 130
        assert_all_gone(kids)
    finally:
        proc.kill()
        proc.wait()


def test_an_escaped_helper_holding_stdout_does_not_make_the_budget_hang(tmp_path):
    """The solver forks a helper that calls setsid (out of the solver's process group)
    and keeps stdout open: the budget still holds, and the helper is killed too."""
    script = tmp_path / "escape.py"
    script.write_text(
        "import os, sys, time\n"
        "if os.fork() == 0:\n"
        "    os.setsid()\n"
        "    time.sleep(300)  # holds the inherited stdout\n"
        "    sys.exit(0)\n"
        "time.sleep(300)\n"
    )
    t0 = time.monotonic()
    proc = start(
        "grid",
        "solve",
        str(GRID / "figure1.yaml"),
        "--solver",
        "external",
        "--timeout",
        "5",
        "--command",
        f"{sys.executable} {script} {{file}}",
    )
    try:
        wait_for(lambda: sum("escape.py" in " ".join(p.cmdline()) for p in family(proc)) >= 2, what="solver and helper")
        kids = family(proc)
        out, _ = proc.communicate(timeout=60)
        elapsed = time.monotonic() - t0
        assert proc.returncode == 3, out  # unknown: the budget ran out
        assert b"ran out of the time budget" in out
        import re

        solve = re.search(rb"unknown \(external .*?, ([0-9.]+) s\)", out)
        assert solve is not None, out
        assert float(solve.group(1)) < 5 + 1.5, out  # the search kept its budget
        assert elapsed < 120, elapsed  # and the command ended (start-up on a loaded machine aside)
        assert_all_gone(kids)
    finally:
        proc.kill()
        proc.wait()


def _rows(db: Path) -> int:
    if not db.exists():
        return 0
    try:
        with sqlite3.connect(db, timeout=5) as conn:
            return conn.execute("SELECT COUNT(*) FROM runs").fetchone()[0]
    except sqlite3.OperationalError:  # the schema is not written yet
        return 0


def test_ctrl_c_stops_a_bench_sweep_at_once_and_keeps_finished_runs(tmp_path):
    db = tmp_path / "b.db"
    # runs in order: native #0, native #1 (quick), then debug-sleep #0 (hangs), #1 (queued)
    proc = start(
        "bench",
        "grid",
        "--family",
        "depth",
        "--values",
        "1",
        "--solvers",
        "native,debug-sleep",
        "--repeat",
        "2",
        "--timeout",
        "60",
        "--db",
        str(db),
    )
    try:
        wait_for(lambda: _rows(db) == 2, what="the two quick runs")
        wait_for(lambda: len(family(proc)) >= 3, what="the hanging run's child")
        time.sleep(0.5)
        kids = family(proc)
        t0 = time.monotonic()
        os.killpg(proc.pid, signal.SIGINT)
        out, _ = proc.communicate(timeout=30)
        stopped = time.monotonic() - t0
        assert proc.returncode == 130, out
        assert stopped < 10, stopped  # promptly (it was 69 s): the queued run is not run
        assert b"interrupted" in out
        assert_all_gone(kids)
        with sqlite3.connect(db) as conn:
            rows = conn.execute(
                'SELECT p.name, r."repeat", r.status FROM runs r JOIN plannerConfigs p ON r.plannerid = p.id'
            ).fetchall()
            assert conn.execute("pragma integrity_check").fetchone()[0] == "ok"
        assert sorted(rows) == [("native", 0, "solved"), ("native", 1, "solved")]
    finally:
        proc.kill()
        proc.wait()
