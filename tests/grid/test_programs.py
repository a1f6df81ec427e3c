"""Controller programs: parsing, printing, depth, evaluation and export (spec: Controller programs)."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import (
    App,
    Const,
    ProgramSyntaxError,
    Term,
    Var,
    check_program,
    compile_program,
    depth,
    evaluate,
    parse_program,
    parse_sexpr,
    reads_obstacles,
    size,
    subterms,
    to_c,
    to_define_fun,
    to_python,
    variables_of,
)

from .strategies import grid_problems, problems_and_programs, programs

VARS = ("rx", "ry", "o0x", "o0y", "o1x", "o1y")


def inputs_for(variables: tuple[str, ...]) -> st.SearchStrategy[tuple[int, ...]]:
    return st.tuples(*(st.integers(-3, 12) for _ in variables))


# -- parsing and printing -----------------------------------------------------------------


@given(problems_and_programs(max_depth=6))
def test_print_parse_round_trip(pp: tuple[GridProblem, Term]) -> None:
    p, t = pp
    assert parse_program(str(t)) == t
    assert parse_program(to_define_fun(t, p.variables)) == t
    assert parse_program(f"({to_define_fun(t, p.variables)})") == t  # as cvc5 prints it
    check_program(parse_program(str(t)), p.variables, len(p.robot.moves), p.max_constant)


def test_minus_one_is_a_constant() -> None:
    assert parse_program("(- 1)") == Const(-1)
    assert str(Const(-1)) == "(- 1)"
    assert parse_program("-1") == Const(-1)
    assert parse_program("(= ry (- 1))") == App("=", (Var("ry"), Const(-1)))
    assert parse_program("(- rx 1)") == App("-", (Var("rx"), Const(1)))
    assert parse_program("(- 1 rx)") == App("-", (Const(1), Var("rx")))
    assert depth(parse_program("(- 1)")) == 1
    assert depth(parse_program("(<= rx (- 1))")) == 3
    assert evaluate(parse_program("(+ rx (- 1))"), {"rx": 4}) == 3


@pytest.mark.parametrize(
    ("text", "d", "n"),
    [
        ("2", 1, 1),  # a move number
        ("rx", 2, 1),  # a coordinate is (get-x p) in the paper
        ("(+ rx 1)", 3, 3),
        ("(<= rx 3)", 3, 3),
        ("(ite (<= rx 3) 2 1)", 4, 6),  # the spec's example, the paper's Figure 1 program
        ("(ite (<= 1 2) 0 1)", 3, 6),
        ("(ite (not (= o0y (+ ry 1))) 0 (ite (and (<= rx 2) (<= 0 ry)) 1 2))", 6, 18),
    ],
)
def test_depth_and_size_match_the_spec_examples(text: str, d: int, n: int) -> None:
    t = parse_program(text)
    assert (depth(t), size(t)) == (d, n)
    assert len(list(subterms(t))) == n


def test_nary_operators_fold_to_binary() -> None:
    t = parse_program("(ite (and (<= rx 1) (<= ry 1) (= rx ry)) 0 1)")
    assert t.args[0] == App(
        "and", (App("and", (parse_program("(<= rx 1)"), parse_program("(<= ry 1)"))), parse_program("(= rx ry)"))
    )
    assert parse_program("(+ rx ry 1)") == App("+", (App("+", (Var("rx"), Var("ry"))), Const(1)))


def test_define_fun_and_comments() -> None:
    text = """
    ; a solver's answer
    ((define-fun move ((rx Int) (ry Int)) Int
        (ite (<= rx 3) 2 1)))  ; trailing comment
    """
    assert parse_program(text) == parse_program("(ite (<= rx 3) 2 1)")
    assert parse_sexpr("(a (b c) d)") == ["a", ["b", "c"], "d"]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("(ite (<= rx 3) 2)", "ite takes 3 arguments, got 2"),
        ("(not (<= rx 1) (<= ry 1))", "not takes 1 arguments, got 2"),
        ("(* rx 2)", "unknown operator '\\*'"),
        ("(ite (<= rx 3) 2 1", "missing '\\)'"),
        (")", "unexpected '\\)'"),
        ("(ite (<= rx 3) 2 1) 0", "trailing text"),
        ("", "unexpected end of text"),
        ("(define-fun move Int 2)", "define-fun needs a name, parameters, a sort and a body"),
        ("r-x", "unexpected token 'r-x'"),
        ("((<= rx 1) 0 1)", "unexpected term"),
        ("(- 1 2 3)", "- takes 2 arguments, got 3"),
        # found by tests/test_fuzz.py: an input named like a keyword parsed, then broke export
        ("(ite (<= if 1) 0 1)", "'if' cannot name an input: it is a keyword of Python or C"),
        ("(ite (<= rx while) 0 1)", "'while' cannot name an input"),
        # found by tests/test_fuzz.py: the trailing text was quoted raw, so a control
        # character in it (\x1e splits lines) broke the CLI's one-line error
        ("0\r\x1e0", r"trailing text after the term: '\\x1e0'"),
    ],
)
def test_syntax_errors(text: str, message: str) -> None:
    with pytest.raises(ProgramSyntaxError, match=message) as caught:
        parse_program(text)
    assert len(str(caught.value).splitlines()) == 1


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("5", "move number 5 is not in 0..4"),
        ("(- 1)", "move number -1 is not in 0..4"),
        ("(ite (<= rx 7) 0 1)", "constant 7 is not in -1..6"),
        ("(ite (<= rx -2) 0 1)", "constant -2 is not in -1..6"),
        ("(ite (<= o2x 1) 0 1)", "unknown input 'o2x'"),
        ("rx", "coordinate rx where a move is expected"),
        ("(ite rx 0 1)", "coordinate rx where a condition is expected"),
        ("(ite 1 0 1)", "integer 1 where a condition is expected"),
        ("(ite (<= (<= rx 1) 1) 0 1)", "where a T term is expected"),
        ("(<= rx 1)", "where a move term is expected"),
        ("(ite (<= rx 1) (+ 1 1) 0)", "where a move term is expected"),
    ],
)
def test_grammar_check(text: str, message: str) -> None:
    with pytest.raises(ProgramSyntaxError, match=message):
        check_program(parse_program(text), VARS, 5, 6)


def test_reads_obstacles_and_variables_of() -> None:
    t = parse_program("(ite (<= o1y (+ rx 1)) 0 1)")
    assert variables_of(t) == {"o1y", "rx"}
    assert reads_obstacles(t)
    assert not reads_obstacles(parse_program("(ite (<= ry 1) 0 1)"))
    assert variables_of(Const(1)) == frozenset()


@given(problems_and_programs(max_depth=5))
def test_random_programs_respect_the_depth_bound(pp: tuple[GridProblem, Term]) -> None:
    p, t = pp
    assert 1 <= depth(t) <= 5
    assert variables_of(t) <= set(p.variables)


# -- evaluation and export ---------------------------------------------------------------


@given(grid_problems(), st.data())
def test_evaluate_equals_compile_program_and_python_export(p: GridProblem, data: st.DataObject) -> None:
    t = data.draw(programs(p, 6))
    f = compile_program(t, p.variables)
    namespace: dict[str, object] = {}
    exec(to_python(t, p.variables, "controller"), namespace)  # noqa: S102 - the exported source
    g = namespace["controller"]
    for _ in range(5):
        xs = data.draw(inputs_for(p.variables))
        expected = evaluate(t, dict(zip(p.variables, xs)))
        assert isinstance(expected, int) and not isinstance(expected, bool)
        assert 0 <= expected < len(p.robot.moves)
        assert f(*xs) == expected
        assert g(*xs) == expected  # type: ignore[operator]


@given(st.data())
def test_evaluate_conditions_and_terms(data: st.DataObject) -> None:
    x, y = data.draw(st.integers(-5, 5)), data.draw(st.integers(-5, 5))
    env = {"rx": x, "ry": y}
    assert evaluate(parse_program("(+ rx ry)"), env) == x + y
    assert evaluate(parse_program("(- rx ry)"), env) == x - y
    assert evaluate(parse_program("(<= rx ry)"), env) is (x <= y)
    assert evaluate(parse_program("(= rx ry)"), env) is (x == y)
    assert evaluate(parse_program("(not (= rx ry))"), env) is (x != y)
    assert evaluate(parse_program("(and (<= rx ry) (<= ry rx))"), env) is (x == y)
    assert evaluate(parse_program("(or (<= rx ry) (<= ry rx))"), env) is True


def test_python_export_reads_like_the_docstring() -> None:
    src = to_python(parse_program("(ite (not (= o0y (- 1))) 2 1)"), ["rx", "ry", "o0x", "o0y"])
    assert src.splitlines()[0] == "def move(rx: int, ry: int, o0x: int, o0y: int) -> int:"
    assert "return (2 if (not (o0y == (-1))) else 1)" in src


C_DRIVER = """
#include <stdio.h>
{functions}
int main(void) {{
    int v[{n}];
    for (;;) {{
        for (int i = 0; i < {n}; i++) if (scanf("%d", &v[i]) != 1) return 0;
        {calls}
        printf("\\n");
    }}
}}
"""


@settings(max_examples=4, suppress_health_check=[HealthCheck.large_base_example, HealthCheck.data_too_large])
@given(p=grid_problems(), data=st.data())
def test_c_export_compiles_with_gcc_and_agrees(tmp_path_factory, p: GridProblem, data: st.DataObject) -> None:
    """Many programs per gcc run: each example compiles one C file with 16 controllers."""
    terms = [data.draw(programs(p, 6)) for _ in range(16)]
    inputs = [data.draw(inputs_for(p.variables)) for _ in range(12)]
    n = len(p.variables)
    functions = "\n".join(to_c(t, p.variables, f"move_{i}") for i, t in enumerate(terms))
    args = ", ".join(f"v[{i}]" for i in range(n))
    calls = " ".join(f'printf("%d ", move_{i}({args}));' for i in range(len(terms)))
    d: Path = tmp_path_factory.mktemp("c")
    (d / "controllers.c").write_text(C_DRIVER.format(functions=functions, n=n, calls=calls), encoding="utf-8")
    # Random programs hold tautologies such as (<= rx rx) that gcc rightly warns about;
    # the export must be standard C, which -pedantic-errors enforces.
    cc = subprocess.run(
        ["gcc", "-std=c99", "-pedantic-errors", "-o", str(d / "run"), str(d / "controllers.c")],
        capture_output=True,
        text=True,
    )
    assert cc.returncode == 0, cc.stderr
    stdin = "\n".join(" ".join(map(str, xs)) for xs in inputs) + "\n"
    out = subprocess.run([str(d / "run")], input=stdin, check=True, capture_output=True, text=True).stdout
    got = [[int(v) for v in line.split()] for line in out.strip().splitlines()]
    expected = [[evaluate(t, dict(zip(p.variables, xs))) for t in terms] for xs in inputs]
    assert got == expected


def test_c_export_of_a_program_without_inputs_is_a_void_function() -> None:
    assert "int move(void)" in to_c(Const(0), [])
