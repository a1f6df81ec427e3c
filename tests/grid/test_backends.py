"""Process isolation and the SyGuS backends (cvc5 in a child process, external commands)."""

from __future__ import annotations

import os
import sys
import textwrap
import time
from pathlib import Path

import pytest

from plansynth.budget import Budget
from plansynth.errors import InvalidProblem, SolverUnavailable
from plansynth.grid.backends.cvc5 import Cvc5Backend, parse_options
from plansynth.grid.backends.external import ExternalBackend
from plansynth.grid.problem import grid_problem_from_dict
from plansynth.grid.programs import Const, parse_program
from plansynth.grid.result import GridStatus, get_backend
from plansynth.grid.sygus import compile_sygus
from plansynth.isolate import Crash, Finished, Timeout, run_isolated

#: Robot in a 3x1 corridor, goal two cells right: realizable at l = 2 (and not at l = 1).
CORRIDOR = grid_problem_from_dict(
    {"grid": [3, 1], "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]}}
)


# -- isolate ----------------------------------------------------------------------------
# Module-level functions: the child process must be able to import them.


def _sleep(seconds: float) -> float:
    time.sleep(seconds)
    return seconds


def _raise() -> None:
    raise ValueError("the solver fell over")


def _abort() -> None:
    os.abort()


def _allocate(mb: int) -> int:
    return len(bytearray(mb * 1024 * 1024))


def _unpicklable():
    return lambda: None


def _spawn_grandchild_and_hang(path: str) -> None:
    import subprocess

    proc = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    Path(path).write_text(str(proc.pid))
    time.sleep(60)


def _nested_process() -> int:
    import multiprocessing

    child = multiprocessing.get_context("fork").Process(target=time.sleep, args=(0,))
    child.start()
    child.join()
    return child.exitcode


def test_isolate_returns_the_value() -> None:
    out = run_isolated(_sleep, 0.01, timeout=30)
    assert isinstance(out, Finished) and out.value == 0.01 and out.seconds > 0


def test_isolate_kills_on_timeout() -> None:
    start = time.perf_counter()
    out = run_isolated(_sleep, 30, timeout=0.5)
    assert isinstance(out, Timeout) and out.limit == 0.5
    assert time.perf_counter() - start < 5


def test_isolate_kills_the_whole_process_group(tmp_path: Path) -> None:
    pid_file = tmp_path / "pid"
    out = run_isolated(_spawn_grandchild_and_hang, str(pid_file), timeout=3)
    assert isinstance(out, Timeout)
    pid = int(pid_file.read_text())
    for _ in range(50):  # the grandchild is gone (or a zombie reaped by init) shortly
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            break
        if Path(f"/proc/{pid}/stat").exists() and Path(f"/proc/{pid}/stat").read_text().split()[2] == "Z":
            break
        time.sleep(0.1)
    else:
        pytest.fail(f"grandchild {pid} survived the timeout")


def test_isolate_reports_exceptions_with_their_traceback() -> None:
    out = run_isolated(_raise, timeout=30)
    assert isinstance(out, Crash)
    assert "ValueError: the solver fell over" in out.error
    assert out.describe() == "ValueError: the solver fell over"


def test_isolate_reports_a_dying_child() -> None:
    out = run_isolated(_abort, timeout=30)
    assert isinstance(out, Crash) and out.exitcode == -6
    assert out.describe() == "killed by SIGABRT"


def test_isolate_memory_limit() -> None:
    out = run_isolated(_allocate, 2048, timeout=30, memory_mb=512)
    assert isinstance(out, Crash) and out.memory_out and out.describe() == "ran out of memory"
    small = run_isolated(_allocate, 8, timeout=30, memory_mb=512)
    assert isinstance(small, Finished) and small.value == 8 * 1024 * 1024


def test_isolate_unpicklable_result_is_a_crash() -> None:
    out = run_isolated(_unpicklable, timeout=30)
    assert isinstance(out, Crash) and "pickle" in out.error.lower()


def test_isolated_function_may_use_multiprocessing() -> None:
    out = run_isolated(_nested_process, timeout=30)
    assert isinstance(out, Finished) and out.value == 0


def test_isolate_spawn_and_zero_timeout() -> None:
    assert isinstance(run_isolated(_sleep, 0, timeout=30, method="spawn"), Finished)
    assert isinstance(run_isolated(_sleep, 0, timeout=0), Timeout)


# -- cvc5 -------------------------------------------------------------------------------


def test_cvc5_backend_both_answers(tmp_path: Path) -> None:
    backend = get_backend("cvc5", keep_sl=tmp_path)
    assert backend.name == "cvc5" and backend.version().startswith("1.")
    no = backend.solve_length(CORRIDOR, 1, Budget(seconds=60))
    assert no.status is GridStatus.UNREALIZABLE and no.program is None
    yes = backend.solve_length(CORRIDOR, 2, Budget(seconds=60))
    assert yes.status is GridStatus.REALIZABLE and yes.program == Const(1)
    # The kept file is exactly the text the solver saw.
    assert Path(yes.artefact).read_text() == compile_sygus(CORRIDOR, 2)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["problem-l1.sl", "problem-l2.sl"]


def test_cvc5_backend_timeout_gives_unknown() -> None:
    from plansynth.grid.problem import load_grid_problem

    figure1 = load_grid_problem(Path(__file__).parents[2] / "examples" / "grid" / "figure1.yaml")
    start = time.perf_counter()
    out = Cvc5Backend().solve_length(figure1, 6, Budget(seconds=0.5))
    assert out.status is GridStatus.UNKNOWN and "time budget" in out.message
    assert time.perf_counter() - start < 5


def test_cvc5_backend_crash_gives_unknown() -> None:
    out = Cvc5Backend().solve_length(CORRIDOR, 2, Budget(seconds=30, memory_mb=20))
    assert out.status is GridStatus.UNKNOWN and out.message.startswith("cvc5 crashed")


def test_cvc5_options() -> None:
    assert parse_options({"sygus-enum": "fast", "stats": True}) == {"sygus-enum": "fast", "stats": "true"}
    out = Cvc5Backend(options=["sygus-enum=fast"]).solve_length(CORRIDOR, 2, Budget(seconds=60))
    assert out.status is GridStatus.REALIZABLE
    with pytest.raises(InvalidProblem, match="cvc5 options: no-such-option: .*unrecognized option"):
        Cvc5Backend(options=["no-such-option=1"])
    with pytest.raises(InvalidProblem, match="cvc5 options: sygus-enum"):
        Cvc5Backend(options={"sygus-enum": "sideways"})


# -- external ---------------------------------------------------------------------------


def _fake_solver(tmp_path: Path, body: str) -> str:
    """A python script standing in for a SyGuS solver; returns the command line."""
    script = tmp_path / "fake_solver.py"
    script.write_text(textwrap.dedent(body))
    return f"{sys.executable} {script} {{file}}"


ECHO_IF_SL = """
    import sys
    text = open(sys.argv[1]).read()
    assert "(check-synth)" in text and "(synth-fun move" in text
    print({answer!r})
"""


@pytest.mark.parametrize(
    ("answer", "status", "program"),
    [
        (
            "(\n(define-fun move ((rx Int) (ry Int)) Int (ite (<= rx 1) 1 0))\n)",
            GridStatus.REALIZABLE,
            "(ite (<= rx 1) 1 0)",
        ),
        ("infeasible", GridStatus.UNREALIZABLE, None),
        ("fail", GridStatus.UNKNOWN, None),
        ("(define-fun move ((rx Int) (ry Int)) Int 9)", GridStatus.UNKNOWN, None),  # not a move number
    ],
)
def test_external_reads_the_solver_answer(tmp_path: Path, answer: str, status: GridStatus, program: str | None) -> None:
    backend = ExternalBackend(_fake_solver(tmp_path, ECHO_IF_SL.format(answer=answer)))
    out = backend.solve_length(CORRIDOR, 2, Budget(seconds=30))
    assert out.status is status, out.message
    assert out.program == (None if program is None else parse_program(program))
    if answer.endswith("9)"):
        assert "outside the grammar" in out.message


def test_external_reports_errors_and_exit_status(tmp_path: Path) -> None:
    cmd = _fake_solver(tmp_path, "import sys\nprint('boom', file=sys.stderr)\nsys.exit(3)\n")
    out = ExternalBackend(cmd).solve_length(CORRIDOR, 2, Budget(seconds=30))
    assert out.status is GridStatus.UNKNOWN and "exit status 3" in out.message and "boom" in out.message


def test_external_timeout_kills_the_solver(tmp_path: Path) -> None:
    cmd = _fake_solver(tmp_path, "import time\ntime.sleep(60)\n")
    start = time.perf_counter()
    out = ExternalBackend(cmd).solve_length(CORRIDOR, 2, Budget(seconds=0.5))
    assert out.status is GridStatus.UNKNOWN and "time budget" in out.message
    assert time.perf_counter() - start < 5


def test_external_keeps_the_sl_file_and_appends_it_without_placeholder(tmp_path: Path) -> None:
    script = tmp_path / "s.py"
    script.write_text(
        "import sys\nprint(open(sys.argv[-1]).read().count('declare-var'), file=sys.stderr)\nprint('infeasible')\n"
    )
    out = ExternalBackend(f"{sys.executable} {script}", keep_sl=tmp_path / "kept").solve_length(
        CORRIDOR, 1, Budget(seconds=30)
    )
    assert out.status is GridStatus.UNREALIZABLE
    assert Path(out.artefact) == tmp_path / "kept" / "problem-l1.sl"
    assert Path(out.artefact).read_text() == compile_sygus(CORRIDOR, 1)


def test_external_needs_a_runnable_command() -> None:
    with pytest.raises(SolverUnavailable, match="give the solver's command line"):
        get_backend("external")
    with pytest.raises(SolverUnavailable, match="'no-such-solver-xyz' not found on PATH"):
        ExternalBackend("no-such-solver-xyz --lang=sygus2 {file}")


def test_external_with_a_real_solver(tmp_path: Path) -> None:
    # The cvc5 wheel has no binary; the shim runs cvc5's Python API as a command.
    backend = ExternalBackend(f"{sys.executable} -m plansynth.grid.backends.cvc5_cli {{file}}")
    assert backend.solve_length(CORRIDOR, 1, Budget(seconds=60)).status is GridStatus.UNREALIZABLE
    yes = backend.solve_length(CORRIDOR, 2, Budget(seconds=60))
    assert yes.status is GridStatus.REALIZABLE and yes.program == Const(1)


def test_cvc5_cli_shim(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from plansynth.grid.backends.cvc5_cli import main

    sl = tmp_path / "c.sl"
    sl.write_text(compile_sygus(CORRIDOR, 2))
    assert main([str(sl)]) == 0
    assert "(define-fun move ((rx Int) (ry Int)) Int 1)" in capsys.readouterr().out
    assert main(["--sygus-enum=fast", str(sl)]) == 0
    assert main(["--no-such-option=1", str(sl)]) == 1
    assert "unrecognized option" in capsys.readouterr().err
    assert main([]) == 2
