"""Regression tests of bad inputs found by generating them: each one is refused at the
door with an error naming file, field and reason (exit 2, one line, no traceback), or,
where the input is legal, handled without a traceback, a hang or a memory blow-up.

The limits are documented in docs/reference/limits.md.
"""

from __future__ import annotations

import json
import math
import shlex
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import yaml

from hostile import FIGURE1, MAZE1, WINNER, check_contract, grid_text, hostile_grid_files, invoke
from plansynth.errors import InvalidProblem
from plansynth.grid.problem import MAX_GRID_SIDE, MAX_STEPS, load_grid_problem
from plansynth.grid.programs import MAX_PROGRAM_NESTING, ProgramSyntaxError, depth, evaluate, parse_program, size
from plansynth.grid.result import load_result
from plansynth.io import MAX_FILE_BYTES, MAX_NODES, load_document, parse_document, read_text
from plansynth.reach.fileformat import load_reach_problem
from plansynth.reach.problem import MAX_COORDINATE, MAX_HORIZON, MAX_ORDER


def _refused(args: list[str], *fragments: str) -> str:
    r = invoke(args)
    check_contract(r, args)
    assert r.exit_code == 2, r.output
    for f in fragments:
        assert f in r.stderr, r.stderr
    return r.stderr


def _reach_text(old: str, new: str) -> str:
    text = MAZE1.read_text(encoding="utf-8")
    assert old in text
    return text.replace(old, new)


# -- hostile files ------------------------------------------------------------------------


def test_hostile_problem_files_are_refused_by_every_reader(tmp_path: Path) -> None:
    for name, (path, expect) in hostile_grid_files(tmp_path).items():
        for args in (
            ["grid", "solve", path],
            ["reach", "solve", path],
            ["grid", "verify", path, WINNER, "--steps", "6"],
            ["grid", "compile", path, "--steps", "2"],
            ["reach", "plot", path, "-o", tmp_path / "x.png"],
        ):
            _refused(args, f"error: {path}: <file>: ", expect)
        # As RESULT_OR_PROGRAM: a regular file is read (same limits), anything else is a term.
        args = ["grid", "verify", FIGURE1, path, "--steps", "6"]
        if name in ("fifo.yaml", "/dev/zero", "directory"):
            _refused(args, "is neither a file nor a controller term")
        else:
            _refused(args, f"error: {path}: ")


def test_recursive_alias_is_an_error_not_a_hang(tmp_path: Path) -> None:
    p = tmp_path / "r.yaml"
    p.write_text("a: &x [1, *x]\n", encoding="utf-8")
    with pytest.raises(InvalidProblem, match="an alias refers to a value that contains it"):
        load_document(p)


def test_billion_laughs_is_refused_before_expansion(tmp_path: Path) -> None:
    from hostile import billion_laughs

    text = billion_laughs()
    assert len(text) < 700
    with pytest.raises(InvalidProblem, match=f"expands to more than {MAX_NODES} values"):
        parse_document(text, "laughs.yaml")
    # Sharing that stays small is fine: aliases are legal YAML.
    doc = parse_document("moves: &m [up, down]\nagain: *m\n", "ok.yaml")
    assert doc == {"moves": ["up", "down"], "again": ["up", "down"]}


def test_nesting_limit_applies_to_yaml_and_json(tmp_path: Path) -> None:
    ok = "[" * 60 + "]" * 60
    assert parse_document(ok, "a.yaml") is not None
    assert parse_document(ok, "a.json", json_syntax=True) is not None
    for n in (65, 5_000, 50_000):
        deep = "[" * n + "]" * n
        with pytest.raises(InvalidProblem, match="nested deeper than 64 levels"):
            parse_document(deep, "d.yaml")
        with pytest.raises(InvalidProblem, match="nested deeper than 64 levels"):
            parse_document(deep, "d.json", json_syntax=True)


def test_size_limit_and_special_files(tmp_path: Path) -> None:
    big = tmp_path / "big.json"
    with open(big, "wb") as fh:
        fh.truncate(MAX_FILE_BYTES + 1)
    with pytest.raises(InvalidProblem, match=rf"big\.json: <file>: too large: {MAX_FILE_BYTES + 1} bytes"):
        read_text(big)
    with pytest.raises(InvalidProblem, match="not a regular file"):
        read_text("/dev/zero")
    with pytest.raises(InvalidProblem, match="cannot read: No such file"):
        read_text(tmp_path / "missing.yaml")
    with pytest.raises(InvalidProblem, match="cannot read"):
        read_text("a\0b.yaml")
    bom = tmp_path / "bom.json"
    bom.write_bytes(b'\xef\xbb\xbf{"a": 1}')
    assert load_document(bom)[0] == {"a": 1}


def test_hostile_files_stay_within_memory_and_time_in_a_real_process(tmp_path: Path) -> None:
    """A real process under a 1.5 GB address-space limit: every hostile file, the huge
    sizes of the issue and an external solver's non-UTF-8 answer, each refused (exit
    2) or answered (exit 3) in seconds, with no traceback."""
    files = {name: str(p) for name, (p, _) in hostile_grid_files(tmp_path).items()}
    huge = tmp_path / "huge.yaml"
    huge.write_text(
        grid_text("steps: 1000000000\n", drop=("max_steps", "grid")) + "grid: [10000, 10000]\n", encoding="utf-8"
    )
    solver = f"{shlex.quote(sys.executable)} -c \"import sys; sys.stdout.buffer.write(b'caf\\xe9 (error)')\""
    cases = [["grid", "solve", f] for f in files.values()] + [
        ["reach", "solve", files["laughs.yaml"]],
        ["grid", "solve", str(huge), "--timeout", "20"],
        ["grid", "solve", str(FIGURE1), "--max-steps", "1000000000", "--timeout", "5"],
        ["grid", "verify", str(FIGURE1), WINNER, "--steps", "1000000000"],
        ["grid", "solve", str(FIGURE1), "--steps", "2", "--solver", "external", "--command", solver + " {file}"],
    ]
    script = textwrap.dedent(
        """
        import json, resource, sys
        resource.setrlimit(resource.RLIMIT_AS, (1536 << 20, 1536 << 20))
        from typer.testing import CliRunner
        from plansynth.cli import app
        out = []
        for args in json.loads(sys.argv[1]):
            r = CliRunner().invoke(app, args)
            out.append([args, r.exit_code, r.stderr, r.output, repr(r.exception)])
        print(json.dumps(out))
        """
    )
    proc = subprocess.run(
        [sys.executable, "-c", script, json.dumps(cases)], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    results = json.loads(proc.stdout.splitlines()[-1])
    assert len(results) == len(cases)
    for args, code, stderr, output, exc in results:
        assert "Traceback" not in output and "MemoryError" not in exc, (args, output[-2000:])
        if args[-1].endswith("{file}"):
            assert code == 3 and "gave no answer" in output, (args, output)
        else:
            lines = [ln for ln in stderr.splitlines() if ln.strip()]
            assert code == 2 and len(lines) == 1 and lines[0].startswith("error: "), (args, stderr)


# -- encodings ------------------------------------------------------------------------------


def test_non_utf8_bytes_are_named_errors_everywhere(tmp_path: Path) -> None:
    grid = tmp_path / "g.yaml"
    grid.write_bytes(("# café\n" + grid_text()).encode("latin-1"))
    _refused(["grid", "solve", grid], "g.yaml: <file>: not UTF-8 text: byte 0xe9 at line 1, column 6")
    reach = tmp_path / "r.yaml"
    reach.write_bytes(("# café\n" + MAZE1.read_text(encoding="utf-8")).encode("latin-1"))
    _refused(["reach", "solve", reach], "r.yaml: <file>: not UTF-8 text")
    result = tmp_path / "res.json"
    result.write_bytes(
        json.dumps({"status": "realizable", "steps": 6, "program": WINNER, "note": "café"}, ensure_ascii=False).encode(
            "latin-1"
        )
    )
    _refused(["grid", "verify", FIGURE1, result], "res.json: <file>: not UTF-8 text")
    _refused(["reach", "validate", MAZE1, result], "res.json: <file>: not UTF-8 text")
    sl = tmp_path / "c.sl"
    sl.write_bytes(("; café\n" + WINNER).encode("latin-1"))
    _refused(["grid", "verify", FIGURE1, sl, "--steps", "6"], "c.sl: <file>: not UTF-8 text")


def test_external_solver_output_that_is_not_utf8_is_an_answer_not_a_crash(tmp_path: Path) -> None:
    answer = tmp_path / "answer.txt"
    answer.write_bytes(
        b"; caf\xe9\n(define-fun move ((rx Int) (ry Int) (o0x Int) (o0y Int) (o1x Int) (o1y Int)) Int (ite (<= rx 3) 2 1))\n"
    )
    command = f"{shlex.quote(sys.executable)} -c \"import sys; sys.stdout.buffer.write(open(sys.argv[1], 'rb').read())\" {shlex.quote(str(answer))}"
    args = ["grid", "solve", FIGURE1, "--steps", "6", "--solver", "external", "--command", command + " {file}"]
    r = invoke(args)
    check_contract(r, args)
    assert r.exit_code == 0 and "realizable" in r.output


# -- sizes --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "extra, drop, fragment",
    [
        ("max_steps: 1000000000\n", ("max_steps",), f"max_steps: must be <= {MAX_STEPS}, got 1000000000"),
        ("max_steps: 1000000000000000000000000000000\n", ("max_steps",), f"max_steps: must be <= {MAX_STEPS}"),
        ("steps: 1000000000\n", ("max_steps",), f"steps: must be <= {MAX_STEPS}"),
        ("grid: [10000, 10000]\n", ("grid",), f"grid[0]: must be <= {MAX_GRID_SIDE}, got 10000"),
        ("grid: [1000000, 1000000]\n", ("grid",), "grid[0]: must be <="),
        ("grid: [1000000000000000000000000000000, 7]\n", ("grid",), "grid[0]: must be <="),
        ("name: " + "x" * 201 + "\n", (), "name: at most 200 characters"),
        ("walls: [[99999999999999999999, 0]]\n", ("walls",), "walls[0][0]: must be <="),
    ],
)
def test_grid_sizes_are_limited_at_the_door(tmp_path: Path, extra: str, drop: tuple[str, ...], fragment: str) -> None:
    p = tmp_path / "p.yaml"
    p.write_text(grid_text(extra, drop=drop), encoding="utf-8")
    _refused(["grid", "solve", p, "--timeout", "5"], f"p.yaml: {fragment}")
    with pytest.raises(InvalidProblem):
        load_grid_problem(p)


@pytest.mark.parametrize(
    "args, option",
    [
        (["grid", "solve", FIGURE1, "--max-steps", "1000000000", "--timeout", "5"], "--max-steps"),
        (["grid", "solve", FIGURE1, "--steps", "1000000000"], "--steps"),
        (["grid", "verify", FIGURE1, WINNER, "--steps", "1000000000"], "--steps"),
        (["grid", "compile", FIGURE1, "--steps", "6", "--depth-bound", "1000000000"], "--depth-bound"),
        (["grid", "explain", FIGURE1, "--steps", "1000000000"], "--steps"),
        (["reach", "solve", MAZE1, "--max-horizon", "1000000000"], "--max-horizon"),
        (["reach", "table", "--order", "3000"], "--order"),
    ],
)
def test_size_options_are_limited_at_the_door(args: list[str], option: str) -> None:
    _refused(args, f"Invalid value for '{option}'")


def test_the_documented_limits_hold_at_the_boundary(tmp_path: Path) -> None:
    p = tmp_path / "p.yaml"
    p.write_text(grid_text(f"steps: {MAX_STEPS}\n", drop=("max_steps",)), encoding="utf-8")
    assert load_grid_problem(p).steps == MAX_STEPS
    p.write_text(grid_text(f"grid: [{MAX_GRID_SIDE}, 7]\n", drop=("grid",)), encoding="utf-8")
    assert load_grid_problem(p).width == MAX_GRID_SIDE
    from plansynth.reach import cli as reach_cli  # its literals (it loads without numpy) match the API's limits

    assert (reach_cli.MAX_HORIZON_OPTION, reach_cli.MAX_ORDER_OPTION) == (MAX_HORIZON, MAX_ORDER)


@pytest.mark.parametrize(
    "old, new, fragment",
    [
        ("dt: 0.5", "dt: 1.0e+308", "robot.dynamics.dt: must lie within"),
        (
            "{model: double-integrator, dt: 0.5}",
            "{model: integrator-chain, order: 3000, dt: 0.5}",
            "robot.dynamics.order: must be <= 50",
        ),
        ("max_horizon: 200", "max_horizon: 1000000000000000000000000000000", f"max_horizon: must be <= {MAX_HORIZON}"),
        (
            "max: [30, 30]\nobstacles",
            "max: [1.0e+200, 1.0e+200]\nobstacles",
            "workspace.max[0]: must lie within -1e+06..1e+06, got 1e+200",
        ),
        ("start: [1, 1, 0, 0]", "start: [1, 1, 0, 1.0e+300]", "robot.start[3]: must lie within"),
        ("input_bound: 1", "input_bound: 1.0e+300", "robot.input_bound: must lie within"),
    ],
)
def test_reach_sizes_and_magnitudes_are_limited_at_the_door(tmp_path: Path, old: str, new: str, fragment: str) -> None:
    p = tmp_path / "r.yaml"
    p.write_text(_reach_text(old, new), encoding="utf-8")
    _refused(["reach", "solve", p, "--timeout", "5"], f"r.yaml: {fragment}")


def test_reach_coordinates_at_the_limit_are_accepted(tmp_path: Path) -> None:
    p = tmp_path / "r.yaml"
    text = _reach_text("max: [30, 30]\nobstacles", f"max: [{MAX_COORDINATE:g}, {MAX_COORDINATE:g}]\nobstacles")
    text = text.replace("max: [30, 30, 2, 2]", f"max: [{MAX_COORDINATE:g}, {MAX_COORDINATE:g}, 2, 2]")
    p.write_text(text, encoding="utf-8")
    problem = load_reach_problem(p)
    assert problem.workspace.hi == (MAX_COORDINATE, MAX_COORDINATE)
    assert math.isfinite(problem.workspace.volume())


# -- programs -----------------------------------------------------------------------------


def _nested_ite(n: int) -> str:
    return "(ite (<= rx 3) " * n + "2" + " 1)" * n


def test_a_long_program_on_the_command_line_is_a_term_not_a_path() -> None:
    program = _nested_ite(20)
    assert len(program) > 300  # longer than a file name may be (ENAMETOOLONG)
    args = ["grid", "verify", FIGURE1, program, "--steps", "6"]
    r = invoke(args)
    check_contract(r, args)
    assert r.exit_code == 0 and "WINS" in r.output
    long_junk = "x" * 5000
    _refused(["grid", "verify", FIGURE1, long_junk, "--steps", "6"], "is neither a file nor a controller term")
    _refused(
        ["grid", "export", long_junk, "--lang", "c", "--problem", FIGURE1], "is neither a file nor a controller term"
    )


def test_deep_programs_are_refused_in_files_results_and_solver_answers(tmp_path: Path) -> None:
    deep = _nested_ite(10_000)
    with pytest.raises(ProgramSyntaxError, match=f"nested deeper than {MAX_PROGRAM_NESTING}"):
        parse_program(deep)
    sl = tmp_path / "deep.sl"
    sl.write_text(deep, encoding="utf-8")
    _refused(["grid", "verify", FIGURE1, sl, "--steps", "6"], "deep.sl: not a controller program: nested deeper than")
    res = tmp_path / "deep.json"
    res.write_text(json.dumps({"status": "realizable", "steps": 6, "program": deep}), encoding="utf-8")
    _refused(["grid", "verify", FIGURE1, res], "deep.json: program: nested deeper than")
    with pytest.raises(InvalidProblem, match="program: nested deeper than"):
        load_result(res)
    answer = tmp_path / "answer.txt"
    answer.write_text(
        f"(define-fun move ((rx Int) (ry Int) (o0x Int) (o0y Int) (o1x Int) (o1y Int)) Int {deep})\n", encoding="utf-8"
    )
    command = (
        f'{shlex.quote(sys.executable)} -c "import sys; print(open(sys.argv[1]).read())" {shlex.quote(str(answer))}'
    )
    args = ["grid", "solve", FIGURE1, "--steps", "6", "--solver", "external", "--command", command + " {file}"]
    r = invoke(args)
    check_contract(r, args)
    assert r.exit_code == 3 and "nested deeper than" in r.output


def test_a_20000_term_and_is_accepted_and_stays_shallow(tmp_path: Path) -> None:
    text = "(ite (and " + " ".join(["(<= rx 3)"] * 20_000) + ") 2 1)"
    t = parse_program(text)
    assert depth(t) < 40 and size(t) == 1 + (2 * 20_000 - 1) + 2 * 20_000 + 2
    assert evaluate(t, {"rx": 1}) == 2 and evaluate(t, {"rx": 4}) == 1
    assert parse_program(str(t)) == t
    res = tmp_path / "and.json"
    res.write_text(json.dumps({"status": "realizable", "steps": 6, "program": text}), encoding="utf-8")
    args = ["grid", "verify", FIGURE1, str(res)]
    r = invoke(args)
    check_contract(r, args)
    assert r.exit_code == 0 and "WINS" in r.output


@pytest.mark.parametrize(
    "text", ["(ite (<= rx ３) 2 1)", "(ite (<= rx ٣) 2 1)", "(ite (<= rx (- ²)) 2 1)", "(ite (<= rx 1234567890) 2 1)"]
)
def test_only_short_ascii_integer_literals(text: str) -> None:
    with pytest.raises(ProgramSyntaxError):
        parse_program(text)
    _refused(["grid", "verify", FIGURE1, text, "--steps", "6"], "is neither a file nor a controller term")


# -- numbers ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "written, value", [("5e-1", 0.5), ("1e-1", 0.1), ("5E-1", 0.5), ("0.5e0", 0.5), ("1.0e-1", 0.1), ("+5e-1", 0.5)]
)
def test_numbers_as_users_write_them(tmp_path: Path, written: str, value: float) -> None:
    p = tmp_path / "r.yaml"
    p.write_text(_reach_text("dt: 0.5", f"dt: {written}"), encoding="utf-8")
    assert load_reach_problem(p).dynamics.dt == value
    assert parse_document(f"a: {written}", "x.yaml") == {"a": value}
    assert parse_document("a: 1e3\nb: 2.5E+2\nc: '5e-1'\nd: 1_000\ne: 0x10", "x.yaml") == {
        "a": 1000.0,
        "b": 250.0,
        "c": "5e-1",
        "d": 1000,
        "e": 16,
    }


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "-1", "0"])
@pytest.mark.parametrize(
    "command",
    [
        ["grid", "solve", FIGURE1],
        ["grid", "explain", FIGURE1, "--steps", "6"],
        ["grid", "minimize", FIGURE1],
        ["reach", "solve", MAZE1],
        ["reach", "table", "--mazes", "1"],
    ],
)
def test_budget_options_must_be_finite_and_positive(command: list[str], value: str) -> None:
    _refused([*command, "--timeout", value], "Invalid value for '--timeout'")


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["grid", "animate", FIGURE1, WINNER, "--steps", "6", "-o", "x.gif", "--fps", "nan"], "Invalid value for"),
        (
            ["reach", "solve", MAZE1, "-O", "window_growth=inf"],
            "lazy-smt: option 'window_growth': must be positive and finite",
        ),
        (["reach", "solve", MAZE1, "-O", "window_growth=nan"], "lazy-smt: option 'window_growth': expected float"),
    ],
)
def test_other_real_options_must_be_finite(args: list[str], fragment: str) -> None:
    _refused(args, fragment)


def test_usage_errors_are_one_line() -> None:
    stderr = _refused(["grid", "solve", FIGURE1, "--no-such-option"], "No such option: --no-such-option")
    assert "plansynth grid solve" in stderr
    _refused(["grid", "solve"], "Missing argument")
    _refused(["reach", "nosuch"], "No such command")


def test_other_malformed_documents_are_named_errors(tmp_path: Path) -> None:
    for text, fragment in [
        (grid_text("x" * 500 + ": 1\n"), ": unknown key (allowed:"),
        (grid_text("a: 1" + "0" * 5000 + "\n"), "<file>: not valid YAML/JSON"),
        (grid_text("name: [1, 2]\n"), "name: expected a string, got list"),
        ("grid: !!python/object:os.system [ls]\n", "<file>: not valid YAML/JSON"),
        ("grid: [5, 7]\ngrid: [5, 7]\n", "grid: duplicated key (line 2)"),
        ("- 1\n- 2\n", "<document>: expected a mapping, got list"),
        (
            grid_text(
                "robot: {start: [1, 1], goal: [4, 4], moves: [up, {name: x, to: [0, 1], via: "
                + str([[0, 0]] * 101)
                + "}]}\n",
                drop=("robot", "  "),
            ),
            "robot.moves[1].via: at most 100 offsets",
        ),
    ]:
        p = tmp_path / "m.yaml"
        p.write_text(text, encoding="utf-8")
        _refused(["grid", "solve", p], "m.yaml: ", fragment)
    j = tmp_path / "m.json"
    j.write_text(
        '{"status": "realizable", "steps": 6, "program": "' + WINNER + '", "x": 1' + "0" * 5000 + "}", encoding="utf-8"
    )
    _refused(["grid", "verify", FIGURE1, j], "m.json: <file>: not valid JSON")
    j.write_text(json.dumps({"status": ["realizable"], "program": WINNER}), encoding="utf-8")
    _refused(["grid", "verify", FIGURE1, j], "m.json: status: expected one of")
    j.write_text(json.dumps({"status": "realizable", "program": {"ite": 1}}), encoding="utf-8")
    _refused(["grid", "verify", FIGURE1, j], "m.json: program: expected the program as a string")
    j.write_text(
        json.dumps({"status": "realizable", "steps": 6, "program": WINNER, "problem": ["x"] * 3}), encoding="utf-8"
    )
    _refused(["grid", "export", j, "--lang", "c"], "not a file from here")


def test_yaml_documents_survive_a_round_trip_within_the_limits(tmp_path: Path) -> None:
    doc = yaml.safe_load(FIGURE1.read_text(encoding="utf-8"))
    p = tmp_path / "figure1.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    assert load_grid_problem(p) == load_grid_problem(FIGURE1)


def test_a_long_unicode_name_still_gives_a_valid_sl_file_name(tmp_path: Path) -> None:
    from dataclasses import replace

    from plansynth.grid.backends._common import keep_file, sl_file_name

    problem = replace(load_grid_problem(FIGURE1), name="é" * 200)
    name = sl_file_name(problem, 7, 3)
    assert len(name.encode("utf-8")) <= 255 and name.endswith("-l7-d3.sl")
    assert Path(keep_file(tmp_path, problem, 7, 3, "(check-synth)")).read_text(encoding="utf-8") == "(check-synth)"


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["reach", "solve", "examples/reach/maze-1.yaml", "-p", "milp-ltl"], "this problem has none"),
        (["reach", "solve", "examples/reach/mission-visit.yaml", "-p", "gcs"], "does not plan LTL missions"),
        (["reach", "solve", "examples/reach/dubins.yaml", "-p", "gcs"], "starts at rest"),
        (
            ["reach", "solve", "examples/reach/maze-1.yaml", "-p", "gcs", "-O", "variant=bogus"],
            "gcs: option 'variant': unknown value 'bogus'",
        ),
    ],
)
def test_a_planner_the_problem_cannot_use_is_a_one_line_error(args: list[str], fragment: str) -> None:
    """A planner's refusal (a mission planner without a mission, gcs on a moving start, an
    unknown gcs variant) is one line and exit 2, not a traceback (found by a review)."""
    _refused(args, fragment)
