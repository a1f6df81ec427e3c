"""The path-length search: order, statuses, the shared budget, and the verifier's veto."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable
from plansynth.grid.problem import GridProblem, grid_problem_from_dict, load_grid_problem
from plansynth.grid.programs import Term, parse_program
from plansynth.grid.result import GridStatus, LengthOutcome, load_result, register_backend
from plansynth.grid.solve import solve
from plansynth.grid.verify import verify

FIGURE1 = Path(__file__).parents[2] / "examples" / "grid" / "figure1.yaml"

#: 3x1 corridor, goal two cells right: the robot needs exactly 2 "right"s, then waits.
CORRIDOR = grid_problem_from_dict(
    {"grid": [3, 1], "max_steps": 4, "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]}}
)


@dataclass
class ScriptedBackend:
    """A backend that answers from a script {l: (status, program text)} and records calls."""

    script: dict[int, tuple[GridStatus, str | None]]
    name: str = "scripted"
    calls: list[tuple[int, float | None, int | None]] = field(default_factory=list)
    delay: float = 0.0

    def version(self) -> str:
        return "test"

    def solve_length(
        self, problem: GridProblem, steps: int, budget: Budget, *, depth_bound: int | None = None
    ) -> LengthOutcome:
        self.calls.append((steps, budget.seconds, depth_bound))
        time.sleep(self.delay)
        status, text = self.script.get(steps, (GridStatus.UNREALIZABLE, None))
        program: Term | None = None if text is None else parse_program(text)
        return LengthOutcome(status, steps, program=program, message="scripted", counters={"calls": len(self.calls)})


_LAST: dict[str, ScriptedBackend] = {}


def _scripted(**options) -> ScriptedBackend:
    backend = ScriptedBackend(**options)
    _LAST["backend"] = backend
    return backend


register_backend("scripted", _scripted)

U, R, K = GridStatus.UNREALIZABLE, GridStatus.REALIZABLE, GridStatus.UNKNOWN

#: The goal is 5 cells away: no controller wins at any l <= 4 (the native engine proves it).
FAR = grid_problem_from_dict(
    {"grid": [6, 1], "max_steps": 4, "robot": {"start": [0, 0], "goal": [5, 0], "moves": ["stay", "right"]}}
)


def test_first_realizable_length_wins_and_the_program_is_verified() -> None:
    r = solve(CORRIDOR, "scripted", script={2: (R, "1")})
    assert r.status is R and r.steps == 2 and r.verified is True and str(r.program) == "1"
    assert [a.status for a in r.attempts] == [U, R]
    assert "verify_states" in r.attempts[-1].counters
    assert r.solver == "scripted" and r.solver_version == "test"


def test_search_does_not_stop_at_unknown_or_unrealizable() -> None:
    r = solve(CORRIDOR, "scripted", script={1: (K, None), 2: (U, None), 3: (R, "(ite (<= rx 1) 1 0)")})
    assert r.status is R and r.steps == 3
    assert [a.steps for a in r.attempts] == [1, 2, 3]


def test_unrealizable_only_if_every_length_is() -> None:
    r = solve(FAR, "scripted", script={})
    assert r.status is U and r.program is None and r.verified is None
    assert [a.steps for a in r.attempts] == [1, 2, 3, 4]
    assert r.message == "no controller wins at every l in 1..4"
    assert r.certified_by == "native" and r.to_json_dict()["certified_by"] == "native"
    assert all(a.counters["certified_by"] == "native" for a in r.attempts)
    r = solve(FAR, "scripted", script={3: (K, None)})
    assert r.status is K and "l = 3: scripted" in r.message


def test_unrealizable_relative_to_the_depth_bound() -> None:
    r = solve(FAR.with_steps(3), "scripted", depth_bound=4, script={})
    assert r.status is U and r.depth_bound == 4
    assert r.message == "no controller (programs of depth <= 4) wins at l = 3"
    assert _LAST["backend"].calls == [(3, None, 4)]
    assert r.to_json_dict()["depth_bound"] == 4


def test_a_program_the_verifier_refutes_is_never_reported() -> None:
    # "0" (stay) does not reach the goal; a backend claiming it wins is buggy.
    r = solve(CORRIDOR, "scripted", script={2: (R, "0")})
    assert r.status is K and r.program is None and r.verified is None
    bad = r.attempts[1]
    assert bad.status is K and bad.message.startswith("BACKEND BUG: scripted returned 0 for l = 2")
    assert "not on the goal (2, 0) after step 1" in bad.message
    assert bad.witness is not None  # the counterexample
    # ... and a later verified answer is still found.
    r = solve(CORRIDOR, "scripted", script={2: (R, "0"), 3: (R, "(ite (<= rx 1) 1 0)")})
    assert r.status is R and r.steps == 3


def test_budget_is_shared_over_the_search() -> None:
    r = solve(CORRIDOR, "scripted", Budget(seconds=0.25), script={}, delay=0.1)
    assert r.status is K and "the budget ran out before l =" in r.message
    calls = _LAST["backend"].calls
    assert 1 <= len(calls) < 4
    assert all(b is not None and b <= 0.25 for _, b, _ in calls)
    assert [b for _, b, _ in calls] == sorted((b for _, b, _ in calls), reverse=True)


def test_iterations_budget_counts_path_lengths() -> None:
    r = solve(CORRIDOR, "scripted", Budget(iterations=2), script={})
    assert r.status is K and [a.steps for a in r.attempts] == [1, 2]


def test_progress_callback_sees_every_length() -> None:
    seen: list[tuple[int, GridStatus]] = []
    far6 = grid_problem_from_dict(
        {"grid": [6, 1], "max_steps": 6, "robot": {"start": [0, 0], "goal": [5, 0], "moves": ["stay", "right"]}}
    )
    solve(far6, "scripted", script={5: (R, "1")}, progress=lambda l, o: seen.append((l, o.status)))
    assert seen == [(1, U), (2, U), (3, U), (4, U), (5, R)]


def test_a_false_unrealizable_claim_is_a_backend_error() -> None:
    """The native engine certifies every unrealizable: a backend that says
    "unrealizable" where a controller exists is caught, and the length is unknown."""
    r = solve(CORRIDOR.with_steps(2), "scripted", script={})
    assert r.status is K and r.certified_by is None
    bad = r.attempts[0]
    assert bad.status is K and bad.message.startswith("BACKEND ERROR: scripted claims unrealizable at l = 2")
    assert "verified by the independent verifier" in bad.message


def test_an_uncertified_claim_is_unknown() -> None:
    """Certification runs within the budget: without time left the claim stays unproved."""
    r = solve(FAR.with_steps(3), "scripted", Budget(seconds=0.2), script={}, delay=0.25)
    assert r.status is K and "not certified" in r.message


def test_unknown_solver() -> None:
    with pytest.raises(SolverUnavailable, match="unknown grid solver; choose one of: .*cvc5"):
        solve(CORRIDOR, "no-such-solver")


def test_result_file_round_trip(tmp_path: Path) -> None:
    r = solve(CORRIDOR, "scripted", script={2: (R, "1")})
    r.write(tmp_path / "r.json")
    stored = load_result(tmp_path / "r.json")
    assert stored.status is R and stored.steps == 2 and stored.program == r.program
    assert stored.raw["verified"] is True and stored.raw["solver"] == "scripted"
    assert stored.raw["options"] == {"script": {"2": ["realizable", "1"]}}


def test_cvc5_corridor_search() -> None:
    r = solve(CORRIDOR, "cvc5", Budget(seconds=120))
    assert r.status is R and r.steps == 2 and r.verified is True
    assert verify(CORRIDOR, r.program, 2).wins
    assert [a.status for a in r.attempts] == [U, R]


@pytest.mark.slow
def test_figure1_full_search_with_cvc5_defaults() -> None:
    # The command: l = 1..5 infeasible, l = 6 realizable (cvc5 defaults, ~10-20 s).
    r = solve(load_grid_problem(FIGURE1), "cvc5", Budget(seconds=600))
    assert r.status is R and r.steps == 6 and r.verified is True
    assert [a.status for a in r.attempts] == [U] * 5 + [R]


def test_certification_respects_the_depth_bound() -> None:
    """depth-5.yaml has a program of depth 5 and none of depth <= 4: a claim of
    "unrealizable with depth <= 4" is certified, the same claim at depth <= 5 is not."""
    p = load_grid_problem(FIGURE1.parent / "depth-5.yaml")
    r = solve(p, "scripted", Budget(seconds=120), depth_bound=4, script={})
    assert r.status is U and r.certified_by == "native"
    assert r.message == "no controller (programs of depth <= 4) wins at l = 5"
    r = solve(p, "scripted", Budget(seconds=120), depth_bound=5, script={})
    assert r.status is K and r.attempts[0].message.startswith("BACKEND ERROR: scripted claims unrealizable at l = 5")
