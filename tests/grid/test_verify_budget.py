"""The verifier's budget (STYLE.md, point 4): a verification that needs far more time or
memory than it is given answers ``unknown`` (with the phase and the reason) within its
budget plus a second, its memory stays under the cap even in a process with an
address-space limit, and ``grid solve`` never reports a program its verifier could not
finish checking. Also: at the documented limits (grid sides 1000, 1000 steps) the
verifier's memory is what the search touches, not cells x steps."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import textwrap
import time
from dataclasses import dataclass
from pathlib import Path

import pytest
from typer.testing import CliRunner

from plansynth.budget import Budget
from plansynth.cli import app
from plansynth.grid.problem import GridProblem, grid_problem_from_dict
from plansynth.grid.programs import parse_program
from plansynth.grid.result import GridStatus, LengthOutcome
from plansynth.grid.solve import solve
from plansynth.grid.verify import VerdictUnknown, VerifyStatus, verify

MOVES = ["stay", "up", "right", "down", "left"]

#: 256 x 256, 1000 steps, three roaming obstacles the program does not read: exact, but
#: tens of seconds of work (every cell's moves through the semantics).
BIG = {
    "grid": [256, 256],
    "robot": {"start": [0, 0], "goal": [255, 255], "moves": MOVES},
    "obstacles": [{"start": s, "moves": MOVES} for s in ([128, 128], [50, 200], [200, 50])],
    "steps": 1000,
}
BIG_PROGRAM = "(ite (<= rx 254) 2 1)"

#: Two roaming obstacles compared with each other (relational reads): the product sets
#: split towards explicit pairs, and memory grows fast.
RELATIONAL = {
    "grid": [120, 120],
    "robot": {"start": [0, 0], "goal": [119, 119], "moves": MOVES},
    "obstacles": [{"start": [60, 60], "moves": MOVES}, {"start": [30, 90], "moves": MOVES}],
    "steps": 400,
}
RELATIONAL_PROGRAM = "(ite (<= (+ o0x ry) (+ o1y rx)) (ite (<= o0y o1x) 1 2) (ite (= o0x o1y) 0 2))"


def test_a_verification_far_over_its_time_budget_is_unknown_within_budget_plus_one_second() -> None:
    p = grid_problem_from_dict(BIG)
    t0 = time.perf_counter()
    v = verify(p, parse_program(BIG_PROGRAM), 1000, budget=Budget(seconds=1.0))
    wall = time.perf_counter() - t0
    assert v.status is VerifyStatus.UNKNOWN and wall < 2.0, (v.status, wall)
    assert v.counterexample is None and v.phase and "time (1 s)" in v.message and v.phase in v.message
    with pytest.raises(VerdictUnknown, match="budget ran out"):
        v.wins  # noqa: B018 - unknown is never read as "loses"


def test_without_a_budget_the_same_kind_of_problem_is_decided_exactly() -> None:
    # A smaller grid of the same kind: the unread obstacles' sets saturate (period 1),
    # and the loss found replays through the semantics to an unread obstacle's hit.
    doc = {
        **BIG,
        "grid": [40, 40],
        "robot": {**BIG["robot"], "goal": [39, 39]},
        "obstacles": [{"start": [20, 20], "moves": MOVES}, {"start": [5, 30], "moves": ["up", "down"]}],
    }
    p = grid_problem_from_dict(doc)
    v = verify(p, parse_program("(ite (<= rx 38) 2 1)"), 1000, budget=Budget(seconds=120))
    assert v.status is VerifyStatus.LOSES and v.wins is False
    assert "with obstacle" in v.counterexample.reason
    alone = grid_problem_from_dict({**doc, "obstacles": []})
    assert verify(alone, parse_program("(ite (<= rx 38) 2 1)"), 1000).status is VerifyStatus.WINS


def test_grid_verify_cli_times_out_with_unknown_and_exit_3(tmp_path: Path) -> None:
    f = tmp_path / "big.yaml"
    f.write_text(json.dumps(BIG), encoding="utf-8")
    t0 = time.perf_counter()
    r = CliRunner().invoke(app, ["grid", "verify", str(f), BIG_PROGRAM, "--steps", "1000", "--timeout", "1"])
    wall = time.perf_counter() - t0
    assert r.exit_code == 3, r.output
    assert "unknown at l = 1000" in r.output and "budget ran out in" in r.output and "time (1 s)" in r.output
    assert "WINS" not in r.output and "LOSES" not in r.output
    # The verifier's own time (it prints it) is the budget plus under a second; the
    # command's wall time also holds imports and start-up, so it gets a looser bound.
    seconds = float(re.search(r"states explored in ([0-9.]+) s", r.output).group(1))
    assert seconds < 2.0 and wall < 10.0, (seconds, wall)


def test_grid_verify_cli_refuses_a_bad_budget(tmp_path: Path) -> None:
    f = tmp_path / "big.yaml"
    f.write_text(json.dumps(BIG), encoding="utf-8")
    for opt in (["--timeout", "0"], ["--timeout", "nan"], ["--memory-mb", "0"]):
        r = CliRunner().invoke(app, ["grid", "verify", str(f), BIG_PROGRAM, *opt])
        assert r.exit_code == 2, (opt, r.output)


def test_memory_stays_under_the_cap_in_a_process_with_an_address_space_limit() -> None:
    """In a real process whose address space is capped at what it uses after start-up
    plus the verifier's budget plus a margin, a memory-hungry verification answers
    ``unknown`` ("memory") instead of dying, and its resident set grows by little more
    than the budget."""
    script = textwrap.dedent(
        f"""
        import json, resource, time
        from plansynth.budget import Budget
        from plansynth.grid.problem import grid_problem_from_dict
        from plansynth.grid.programs import parse_program
        from plansynth.grid.verify import verify
        page = resource.getpagesize()
        def rss():
            return int(open("/proc/self/statm").read().split()[1]) * page >> 20
        def vm():
            return int(open("/proc/self/statm").read().split()[0]) * page >> 20
        def peak():  # this process's peak resident set since the last reset, in MB (not
            # ru_maxrss: that keeps the parent's peak across fork and exec)
            line = next(l for l in open("/proc/self/status") if l.startswith("VmHWM:"))
            return int(line.split()[1]) >> 10
        p = grid_problem_from_dict(json.loads({json.dumps(json.dumps(RELATIONAL))}))
        program = parse_program({RELATIONAL_PROGRAM!r})
        verify(p, program, 2)   # warm up: imports and first allocations
        cap = vm() + 32 + 96
        resource.setrlimit(resource.RLIMIT_AS, (cap << 20, cap << 20))
        before = rss()
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")  # reset the peak to the resident set now
        t0 = time.perf_counter()
        v = verify(p, program, 400, budget=Budget(seconds=120, memory_mb=32), probe_nodes=0)
        print(json.dumps([v.status.value, v.message, peak() - before, time.perf_counter() - t0]))
        """
    )
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    status, message, grew, seconds = json.loads(proc.stdout.splitlines()[-1])
    assert status == "unknown" and "memory" in message and "32 MB" in message, message
    assert grew <= 32 + 16, (grew, seconds, message)


@dataclass
class _Instant:
    """A backend that answers at once with a fixed program (the verifier does the work)."""

    program: str
    name: str = "instant-for-verify-budget"

    def version(self) -> str:
        return "test"

    def solve_length(
        self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        return LengthOutcome(GridStatus.REALIZABLE, steps, program=parse_program(self.program))


def test_grid_solve_gives_its_verifier_the_budget_left_and_reports_no_unverified_program(monkeypatch) -> None:
    from plansynth.grid import result

    # Registered for this test only (other tests list the registry's names).
    result.BACKENDS.register("instant-for-verify-budget", _Instant)
    try:
        p = grid_problem_from_dict(BIG)
        t0 = time.perf_counter()
        r = solve(p, "instant-for-verify-budget", Budget(seconds=1.5), program=BIG_PROGRAM)
        wall = time.perf_counter() - t0
    finally:
        result.BACKENDS.unregister("instant-for-verify-budget")
    assert r.status is GridStatus.UNKNOWN and r.program is None and wall < 2.5, (r.status, wall)
    (attempt,) = r.attempts
    assert attempt.status is GridStatus.UNKNOWN and attempt.program is None
    assert "not verified" in attempt.message and "budget ran out" in attempt.message
    assert BIG_PROGRAM in attempt.message  # short: quoted


def test_a_long_program_is_named_by_its_measures_in_messages() -> None:
    """The verifier's reason stays in view (the bench keeps a message's first 2,000
    characters): a program too long to read is named by its depth and size."""
    from plansynth.grid.programs import depth, size
    from plansynth.grid.solve import QUOTED_PROGRAM, _shown

    text = "1"
    for k in range(40):
        text = f"(ite (<= rx {k}) {k % 9} {text})"
    program = parse_program(text)
    assert len(text) > QUOTED_PROGRAM
    assert _shown(program) == f"a program of depth {depth(program)} and {size(program)} nodes"
    assert _shown(parse_program(BIG_PROGRAM)) == str(parse_program(BIG_PROGRAM))
