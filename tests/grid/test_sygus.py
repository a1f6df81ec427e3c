"""The SyGuS compiler: golden files, what cvc5 makes of the text, the depth-bounded grammar.

Golden files in ``tests/grid/golden/`` pin the compiler's output. After an intended
change of the encoding, regenerate them and review the diff::

    PLANSYNTH_UPDATE_GOLDEN=1 pytest tests/grid/test_sygus.py -k golden
    git diff tests/grid/golden/
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.errors import InvalidProblem
from plansynth.grid.backends.cvc5 import run_smt_text, run_sygus_text
from plansynth.grid.problem import grid_problem_from_dict, load_grid_problem
from plansynth.grid.programs import App, Const, ProgramSyntaxError, Term, Var, depth, parse_program, parse_sexpr
from plansynth.grid.sygus import compile_check, compile_sygus, grammar, read_synth_answer

from .strategies import grid_problems, programs

GOLDEN = Path(__file__).parent / "golden"
EXAMPLES = Path(__file__).parents[2] / "examples" / "grid"
UPDATE = os.environ.get("PLANSYNTH_UPDATE_GOLDEN") == "1"

FIGURE1 = load_grid_problem(EXAMPLES / "figure1.yaml")


# -- golden files ----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("problem_file", "steps", "golden"),
    [
        (EXAMPLES / "figure1.yaml", 6, "figure1-l6.sl"),
        (GOLDEN / "walls-via.yaml", 4, "walls-via-l4.sl"),
        (GOLDEN / "walls-via.yaml", 4, "walls-via-l4-d5.sl"),
    ],
)
def test_golden(problem_file: Path, steps: int, golden: str) -> None:
    problem = load_grid_problem(problem_file)
    bound = re.search(r"-d(\d+)\.sl$", golden)
    text = compile_sygus(problem, steps, int(bound.group(1)) if bound else None)
    path = GOLDEN / golden
    if UPDATE:
        path.write_text(text, encoding="utf-8")
    assert text == path.read_text(encoding="utf-8"), f"{golden} changed; see this module's docstring"


def test_compile_is_pure_and_ignores_where_the_problem_came_from() -> None:
    again = grid_problem_from_dict(FIGURE1.to_dict(), source="elsewhere.yaml", name="figure1")
    assert compile_sygus(FIGURE1, 6) == compile_sygus(again, 6)


def test_the_figure1_text_has_the_papers_structure() -> None:
    text = compile_sygus(FIGURE1, 6)
    assert text.count("(declare-var ") == 2 * 6  # one move choice per obstacle and step
    assert {f"o{i}m{t}" for i in (0, 1) for t in range(6)} <= set(re.findall(r"declare-var (\w+)", text))
    for name in ("obstaclePositionsAllowable", "noIntersection", "correctFinalPosition"):
        assert f"(define-fun {name} " in text
    assert text.count("(move rx") == 6  # the controller is applied once per step
    assert "(synth-fun move ((rx Int) (ry Int) (o0x Int) (o0y Int) (o1x Int) (o1y Int)) Int" in text
    assert "(T Int (rx ry o0x o0y o1x o1y (+ T T) (- T T) (- 1) 0 1 2 3 4 5 6))" in text


# -- cvc5 reads what we write ----------------------------------------------------------


def _parse_only(text: str) -> str:
    """Everything but the final (check-synth): cvc5 parses and declares, solves nothing."""
    assert text.rstrip().endswith("(check-synth)")
    return run_sygus_text(text.rstrip()[: -len("(check-synth)")])


@settings(max_examples=15)
@given(grid_problems(), st.integers(1, 4), st.one_of(st.none(), st.integers(1, 6)))
def test_cvc5_parses_the_compiled_text(problem, steps, depth_bound) -> None:
    assert _parse_only(compile_sygus(problem, steps, depth_bound)) == ""


def test_cvc5_solves_tiny_problems_both_ways() -> None:
    corridor = grid_problem_from_dict(
        {"grid": [3, 1], "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]}}
    )
    assert read_synth_answer(run_sygus_text(compile_sygus(corridor, 1))).kind == "infeasible"
    answer = read_synth_answer(run_sygus_text(compile_sygus(corridor, 2)))
    assert answer.kind == "solution"
    assert parse_program(answer.definition) == Const(1)


# -- the depth-bounded grammar is exact --------------------------------------------------


def _rules(problem, bound) -> dict[str, list[object]]:
    sx = parse_sexpr(grammar(problem, bound).replace("\n", " ").join("()"))
    _decls, body = sx
    return {name: prods for name, _sort, prods in body}


def _derives(rules: dict[str, list[object]], nt: str, term: Term) -> bool:
    for prod in rules[nt]:
        if isinstance(prod, str):
            if isinstance(term, Const) and re.fullmatch(r"-?\d+", prod) and int(prod) == term.value:
                return True
            if isinstance(term, Var) and prod == term.name:
                return True
        elif prod[0] == "-" and len(prod) == 2:  # the constant -1, written (- 1)
            if isinstance(term, Const) and term.value == -int(prod[1]):
                return True
        elif isinstance(term, App) and prod[0] == term.op and len(prod) == len(term.args) + 1:
            if all(_derives(rules, a, t) for a, t in zip(prod[1:], term.args)):
                return True
    return False


def _max_depth(rules: dict[str, list[object]], nt: str) -> int:
    best = 0
    for prod in rules[nt]:
        if isinstance(prod, str):  # a coordinate (depth 2) or a literal (depth 1)
            best = max(best, 2 if re.fullmatch(r"[a-z]\w*", prod) else 1)
        elif prod[0] == "-" and len(prod) == 2 and prod[1].isdigit():
            best = max(best, 1)
        else:
            best = max(best, 1 + max(_max_depth(rules, a) for a in prod[1:]))
    return best


@pytest.mark.parametrize("bound", range(1, 8))
def test_bounded_grammar_derives_nothing_deeper_than_the_bound(bound: int) -> None:
    # Bound 2 adds nothing to bound 1: a move number has depth 1, an ite depth >= 3.
    assert _max_depth(_rules(FIGURE1, bound), "Start") == (1 if bound == 2 else bound)


@settings(max_examples=60)
@given(st.data())
def test_bounded_grammar_derives_every_program_within_the_bound(data) -> None:
    problem = data.draw(grid_problems(max_obstacles=1))
    bound = data.draw(st.integers(1, 6))
    program = data.draw(programs(problem, bound))
    assert depth(program) <= bound
    assert _derives(_rules(problem, bound), "Start", program)
    assert _derives(_rules(problem, None), "Start", program)


def test_bounded_grammar_block() -> None:
    text = grammar(FIGURE1, 4)
    assert text.startswith("((Start Int) (B3 Bool) (B2 Bool) (S3 Int) (S2 Int) (T2 Int) (T1 Int))")
    assert "(Start Int (0 1 2 3 4 (ite B3 S3 S3)))" in text
    assert "(T2 Int (rx ry o0x o0y o1x o1y (+ T1 T1) (- T1 T1) (- 1) 0 1 2 3 4 5 6))" in text


def test_depth_bound_answers_are_relative_to_the_bound() -> None:
    # Right, then up: no constant move does it, and a program of depth <= 3 is in
    # effect a constant; (ite (<= rx 0) 2 1) of depth 4 does it.
    corner = grid_problem_from_dict(
        {"grid": [3, 2], "robot": {"start": [0, 0], "goal": [1, 1], "moves": ["stay", "up", "right"]}}
    )
    assert read_synth_answer(run_sygus_text(compile_sygus(corner, 2, 3))).kind == "infeasible"
    answer = read_synth_answer(run_sygus_text(compile_sygus(corner, 2, 4)))
    assert answer.kind == "solution" and depth(parse_program(answer.definition)) == 4


# -- compile_check ----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("program", "answer"),
    [
        ("(ite (<= rx 3) 2 1)", "unsat"),  # the paper's answer wins
        ("(ite (= rx 4) 1 2)", "unsat"),
        ("(ite (<= rx 2) 2 1)", "sat"),  # turns up one column early: misses the goal
        ("2", "sat"),
    ],
)
def test_compile_check_on_figure1(program: str, answer: str) -> None:
    assert run_smt_text(compile_check(FIGURE1, 6, parse_program(program))).strip() == answer


def test_compile_check_rejects_programs_outside_the_grammar() -> None:
    with pytest.raises(ProgramSyntaxError, match="move number 7"):
        compile_check(FIGURE1, 6, parse_program("(ite (<= rx 3) 7 1)"))
    with pytest.raises(ProgramSyntaxError, match="unknown input 'o2x'"):
        compile_check(FIGURE1, 6, parse_program("(ite (<= o2x 3) 2 1)"))


# -- bad input and solver answers -------------------------------------------------------


def test_bad_path_length_and_depth_bound() -> None:
    with pytest.raises(InvalidProblem, match="steps: must be >= 1, got 0"):
        compile_sygus(FIGURE1, 0)
    with pytest.raises(InvalidProblem, match="depth_bound: must be >= 1, got 0"):
        compile_sygus(FIGURE1, 3, 0)


@pytest.mark.parametrize(
    ("output", "kind"),
    [
        ("(\n(define-fun move ((rx Int)) Int (ite (<= rx 3) 2 1))\n)\n", "solution"),
        ("(define-fun move ((rx Int)) Int 2)", "solution"),
        ("infeasible\n", "infeasible"),
        ("fail\n", "unknown"),
        ("unknown", "unknown"),
        ("", "unknown"),
        ("(define-fun move ((rx Int)) Int (ite", "unknown"),  # cut off
        ('(error "Parse Error: x.sl:3.1: expected")', "unknown"),
    ],
)
def test_read_synth_answer(output: str, kind: str) -> None:
    assert read_synth_answer(output).kind == kind
