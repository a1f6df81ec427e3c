"""HiGHS's shared task scheduler (plansynth.reach.highs): whatever ran HiGHS first in a
process, plansynth's LPs still run. Each case is a fresh process, since the scheduler
lives as long as the process (a failure of that kind only shows in a fresh one)."""

from __future__ import annotations

import subprocess
import sys

import pytest

#: An LP run by code outside plansynth, with the given ``threads`` option (None: default).
FOREIGN = """
import highspy, numpy as np
h = highspy.Highs()
h.setOptionValue("output_flag", False)
if {threads!r} is not None:
    h.setOptionValue("threads", {threads!r})
h.addVars(1, np.array([0.0]), np.array([1.0]))
assert h.run() == highspy.HighsStatus.kOk
"""

SOLVE = """
from plansynth.reach.families import maze
from plansynth.reach.solve import solve
for planner in ("lazy-smt", "milp", "milp-bigm"):
    r = solve(maze(1), planner)
    print(planner, r.status.value, r.validated)
"""


def _run(code: str) -> str:
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    return run.stdout


@pytest.mark.parametrize("threads", [None, 2])
def test_plansynth_solves_after_another_highs_user_started_the_scheduler(threads: int | None) -> None:
    out = _run(FOREIGN.format(threads=threads) + SOLVE)
    assert out.split("\n")[-4:] == ["lazy-smt found True", "milp found True", "milp-bigm found True", ""], out


def test_default_instances_still_run_after_plansynth() -> None:
    out = _run(SOLVE + FOREIGN.format(threads=None) + "print('foreign ok')\n")
    assert "lazy-smt found True" in out and out.endswith("foreign ok\n"), out


def test_every_instance_is_single_threaded_and_silent() -> None:
    from plansynth.reach.highs import THREADS, new_highs

    options = new_highs(time_limit=2.5).getOptions()
    assert (options.threads, options.output_flag, options.time_limit) == (THREADS, False, 2.5) == (1, False, 2.5)


def test_no_banner_on_stdout_and_nothing_else_lost() -> None:
    """HiGHS prints its banner when a process's first instance is constructed, before
    any option can be set; plansynth's first instance sends it to the null device, and
    what the process itself printed before and after stays, in order."""
    code = "print('before', flush=False)\n" + SOLVE + "print('after')\n"
    out = _run(code)
    assert "HiGHS" not in out, out
    assert out.split("\n") == ["before", "lazy-smt found True", "milp found True", "milp-bigm found True", "after", ""]


def test_the_cli_prints_no_banner(tmp_path) -> None:
    from pathlib import Path

    maze = Path(__file__).resolve().parents[2] / "examples" / "reach" / "maze-1.yaml"
    run = subprocess.run(
        [
            str(Path(sys.executable).with_name("plansynth")),
            "reach",
            "solve",
            str(maze),
            "--out",
            str(tmp_path / "p.json"),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert run.stdout.startswith("lazy-smt: found"), run.stdout
    assert "Running HiGHS" not in run.stdout + run.stderr
