"""The native engine's options: one frozen value, validated at the door; the counters
of a run are in its outcome, not on the engine; an option that does not apply to the
chosen backend is an error (exit 2), in ``grid solve`` and in ``bench grid``."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from typer.testing import CliRunner

from plansynth.budget import Budget
from plansynth.cli import app
from plansynth.grid.native.engine import Engine
from plansynth.grid.native.options import OPTION_DOCS, InvalidOption, NativeOptions
from plansynth.grid.problem import load_grid_problem
from plansynth.grid.result import GridStatus, get_backend

ROOT = Path(__file__).resolve().parents[2]
FIGURE1 = str(ROOT / "examples" / "grid" / "figure1.yaml")


def test_the_options_are_frozen_and_every_one_is_documented():
    o = NativeOptions(effort=0.5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.effort = 1.0  # type: ignore[misc]
    assert [f.name for f in dataclasses.fields(NativeOptions)] == list(OPTION_DOCS)
    reference = (ROOT / "docs" / "reference" / "options.md").read_text()
    for name in OPTION_DOCS:
        assert f"`{name}`" in reference, f"native option {name} is not in docs/reference/options.md"


@pytest.mark.parametrize(
    "items, match",
    [
        (["minimise=true"], "option 'minimise': not an option of this solver"),
        (["minimize"], "not KEY=VALUE"),
        (["minimize=3"], "expected bool"),
        (["effort=-1"], "below its minimum 0"),
        (["effort=fast"], "expected float"),
        (["max_configs=0"], "below its minimum 1"),
        (["attempt_seconds=2"], "not an option of this solver"),  # an option that never did anything
    ],
)
def test_bad_options_are_named_errors(items, match):
    with pytest.raises(InvalidOption, match=match):
        NativeOptions.parse(items)


def test_strings_and_keywords_give_the_same_value():
    assert NativeOptions.parse(["minimize=true", "max-configs=100"]) == NativeOptions(minimize=True, max_configs=100)
    assert get_backend("native", options=["effort=0"]).options == get_backend("native", effort=0).options


def test_the_counters_are_in_the_outcome_not_on_the_engine():
    engine = Engine(NativeOptions(effort=0))
    problem = load_grid_problem(FIGURE1)
    a = engine.solve_length(problem, 6, Budget(seconds=30))
    b = engine.solve_length(problem, 5, Budget(seconds=30))
    assert a.status is GridStatus.REALIZABLE and b.status is GridStatus.UNREALIZABLE
    assert "phase_seconds" in a.counters and a.counters is not b.counters
    assert not hasattr(engine, "counters") and engine.options == NativeOptions(effort=0)


@pytest.mark.parametrize(
    "args, hint",
    [
        (["--solver", "cvc5", "--effort", "1"], "--effort"),
        (["--solver", "cvc5", "--minimize"], "--minimize"),
        (["-O", "minimise=true"], "not an option of this solver"),
        (["-O", "effort=-2"], "below its minimum 0"),
    ],
)
def test_an_option_that_does_not_apply_exits_2(args, hint):
    res = CliRunner().invoke(app, ["grid", "solve", FIGURE1, "--timeout", "30", *args])
    assert res.exit_code == 2, res.output
    assert hint in res.output


def test_bench_refuses_options_for_no_solver_of_the_sweep_and_bad_native_options(tmp_path):
    db = str(tmp_path / "b.db")
    base = ["bench", "grid", "--family", "figure1", "--solvers", "native", "--timeout", "30", "--db", db]
    res = CliRunner().invoke(app, [*base, "-O", "cvc5:sygus-enum=fast"])
    assert res.exit_code == 2 and "is not one of --solvers" in res.output
    res = CliRunner().invoke(app, [*base, "-O", "native:minimise=true"])
    assert res.exit_code == 2 and "not an option of this solver" in res.output
    assert not (tmp_path / "b.db").exists()


def test_a_program_deeper_than_the_depth_bound_is_no_answer_to_it(monkeypatch) -> None:
    """A path that builds its program without the bound (the clock-obstacle reading)
    must not report it as the answer to "a program of depth <= D" (found by a review)."""
    from plansynth.budget import Budget
    from plansynth.grid.native import engine as eng
    from plansynth.grid.problem import load_grid_problem
    from plansynth.grid.programs import parse_program
    from plansynth.grid.result import GridStatus

    p = load_grid_problem(ROOT / "examples" / "grid" / "figure1.yaml")
    deep = parse_program("(ite (<= rx 3) (ite (<= ry 3) 2 1) (ite (<= ry 2) 2 1))")
    monkeypatch.setattr(
        eng._Run, "_solve", lambda self, problem, steps, clock, bound: (GridStatus.REALIZABLE, deep, "", None)
    )
    out = eng.Engine().solve_length(p, 6, Budget(seconds=10), depth_bound=4)
    assert out.status is GridStatus.UNKNOWN and out.program is None and "none of depth <= 4" in out.message
    assert eng.Engine().solve_length(p, 6, Budget(seconds=10)).status is GridStatus.REALIZABLE
