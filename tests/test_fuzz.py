"""Fuzz test of plansynth's door: random mutations of the example
problem files (wrong types, missing and extra fields, huge, negative and NaN numbers,
strings, deep nesting, bad bytes), random result files, random program strings and
random command lines with output paths, all through the CLI's entry.

Every run must keep the CLI's contract (:func:`hostile.check_contract`): exit status in
{0, 1, 2, 3}, no traceback, one ``error:`` line on status 2, and a bounded time. Most
runs are in-process (typer's CliRunner, for speed); one batch runs in a real process
under an address-space limit, so memory is bounded too, and a few through the console
entry ``python -m plansynth.cli``.
"""

from __future__ import annotations

import copy
import json
import math
import os
import random
import subprocess
import sys
import textwrap
import time
from pathlib import Path
from typing import Any

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hostile import FIGURE1, MAZE1, ROOT, WINNER, billion_laughs, check_contract, invoke
from plansynth.grid.programs import (
    ProgramSyntaxError,
    compile_program,
    depth,
    evaluate,
    parse_program,
    size,
    to_c,
    variables_of,
)

GRID_EXAMPLES = [FIGURE1] + [ROOT / "examples" / "grid" / f for f in ("traffic.yaml", "door.yaml")]
REACH_EXAMPLES = [MAZE1] + [
    ROOT / "examples" / "reach" / f for f in ("cluttered.yaml", "dubins.yaml", "chain-maze-2.yaml")
]
GRID_DOCS = [yaml.safe_load(p.read_text(encoding="utf-8")) for p in GRID_EXAMPLES]
REACH_DOCS = [yaml.safe_load(p.read_text(encoding="utf-8")) for p in REACH_EXAMPLES]

#: Wall-clock bound of one in-process run: every run has a budget of at most 2 s, or is
#: refused at the door.
SECONDS = 30.0

#: Examples per fuzz test; PLANSYNTH_FUZZ_SCALE=10 runs ten times as many (a longer hunt).
SCALE = max(1, int(os.environ.get("PLANSYNTH_FUZZ_SCALE", "1")))
FUZZ = settings(max_examples=40 * SCALE, deadline=None, suppress_health_check=list(HealthCheck))

WEIRD: list[Any] = [
    None,
    True,
    False,
    0,
    -1,
    1,
    2,
    3,
    7,
    1001,
    10**9,
    10**30,
    -(10**30),
    0.5,
    -0.0,
    1e-320,
    1e308,
    math.nan,
    math.inf,
    -math.inf,
    "",
    "x",
    "5e-1",
    "up",
    "café",
    "\u202e",
    "１",
    "a" * 300,
    [],
    {},
    [[]],
    [1, 2],
    [1, 2, 3],
    [0.5, 0.5],
    [-1, -1],
    [10**30, 0],
    {"min": [0, 0], "max": [1, 1]},
    {"name": "n", "to": [0, 1]},
    list(range(40)),
    [[1, 1]] * 30,
]


def _deep(n: int) -> Any:
    v: Any = []
    for _ in range(n):
        v = [v]
    return v


def _paths(doc: Any, prefix: tuple = ()) -> list[tuple]:
    out = [prefix]
    if isinstance(doc, dict):
        for k, v in doc.items():
            out += _paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc[:12]):
            out += _paths(v, prefix + (i,))
    return out


def _set(doc: Any, path: tuple, value: Any, op: str) -> Any:
    if not path:
        return value if op == "replace" else doc
    parent = doc
    for k in path[:-1]:
        parent = parent[k]
    key = path[-1]
    if op == "delete":
        del parent[key]
    elif op == "replace":
        parent[key] = value
    elif op == "wrap":
        parent[key] = [parent[key]]
    elif op == "extra" and isinstance(parent, dict):
        parent[f"extra_{key}"] = value
    elif op == "extra" and isinstance(parent, list):
        parent.append(value)
    elif op == "scale" and isinstance(parent[key], (int, float)) and not isinstance(parent[key], bool):
        parent[key] = -parent[key] * 10**30
    elif op == "nudge" and isinstance(parent[key], (int, float)) and not isinstance(parent[key], bool):
        parent[key] = parent[key] + (
            value if isinstance(value, int) and not isinstance(value, bool) and abs(value) <= 3 else 1
        )
    return doc


@st.composite
def mutated_documents(draw: st.DrawFn, docs: list[Any]) -> Any:
    doc = copy.deepcopy(draw(st.sampled_from(docs)))
    for _ in range(draw(st.integers(1, 3))):
        paths = _paths(doc)
        path = draw(st.sampled_from(paths))
        op = draw(st.sampled_from(["replace", "replace", "delete", "wrap", "extra", "scale", "nudge", "nudge"]))
        value = draw(
            st.sampled_from(WEIRD)
            | st.integers(65, 90).map(_deep)
            | st.floats(allow_nan=True, allow_infinity=True)
            | st.integers(-3, 3)
        )
        doc = _set(doc, path, copy.deepcopy(value), op)
    return doc


@st.composite
def problem_bytes(draw: st.DrawFn, docs: list[Any]) -> tuple[bytes, str]:
    """A mutated document, as YAML or JSON, with byte-level damage at times."""
    doc = draw(mutated_documents(docs))
    suffix = draw(st.sampled_from([".yaml", ".json"]))
    text = json.dumps(doc) if suffix == ".json" else yaml.safe_dump(doc, allow_unicode=True)
    data = text.encode("utf-8")
    damage = draw(
        st.sampled_from(["none", "none", "none", "latin1", "nul", "bom", "truncate", "laughs", "complex-key", "tab"])
    )
    if damage == "latin1":
        data = b"# caf\xe9\n" + data if suffix == ".yaml" else data.replace(b"{", b'{"caf\xe9": 1, ', 1)
    elif damage == "nul":
        data = data[: len(data) // 2] + b"\0" + data[len(data) // 2 :]
    elif damage == "bom":
        data = b"\xef\xbb\xbf" + data
    elif damage == "truncate":
        data = data[: draw(st.integers(0, max(0, len(data) - 1)))]
    elif damage == "laughs" and suffix == ".yaml":
        data += ("\n" + billion_laughs(draw(st.integers(2, 9)))).encode()
    elif damage == "complex-key" and suffix == ".yaml":
        data += b"\n? [1, 2]\n: 3\n"
    elif damage == "tab":
        data = data.replace(b"  ", b"\t", 1)
    return data, suffix


@pytest.fixture(scope="module")
def work(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("fuzz")
    os.mkfifo(d / "fifo.yaml")
    (d / "result.json").write_text(
        json.dumps({"status": "realizable", "steps": 6, "program": WINNER}), encoding="utf-8"
    )
    (d / "traj.json").write_text(
        json.dumps({"states": [[1, 1, 0, 0], [1.1, 1.1, 0.2, 0.2]], "inputs": [[0.4, 0.4]]}), encoding="utf-8"
    )
    (d / "out").mkdir()
    return d


def _run(args: list[Any]) -> Any:
    args = [str(a) for a in args]
    t0 = time.perf_counter()
    r = invoke(args)
    seconds = time.perf_counter() - t0
    check_contract(r, args)
    assert seconds < SECONDS, f"plansynth {' '.join(args)[:300]}: {seconds:.1f} s"
    return r


def _write(work: Path, data: bytes, suffix: str) -> Path:
    p = work / f"case{suffix}"
    p.write_bytes(data)
    return p


# -- problem files ------------------------------------------------------------------------


@FUZZ
@given(case=problem_bytes(GRID_DOCS), command=st.sampled_from(["solve", "compile", "verify", "solve-cvc5"]))
def test_mutated_grid_problems_keep_the_contract(work: Path, case: tuple[bytes, str], command: str) -> None:
    p = _write(work, *case)
    if command == "solve":
        _run(["grid", "solve", p, "--max-steps", "3", "--timeout", "2"])
    elif command == "solve-cvc5":
        _run(["grid", "solve", p, "--steps", "2", "--solver", "cvc5", "--timeout", "2"])
    elif command == "compile":
        _run(["grid", "compile", p, "--steps", "2"])
    else:
        _run(["grid", "verify", p, WINNER, "--steps", "3"])


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
def test_the_unmutated_documents_pass_the_same_path(work: Path, suffix: str) -> None:
    """Controls: the examples, serialized as the fuzzer serializes, are accepted."""
    for kind, docs in (("grid", GRID_DOCS), ("reach", REACH_DOCS)):
        for doc in docs:
            text = json.dumps(doc) if suffix == ".json" else yaml.safe_dump(doc, allow_unicode=True)
            p = _write(work, text.encode("utf-8"), suffix)
            if kind == "grid":
                r = _run(["grid", "compile", p, "--steps", "2"])
            else:
                r = _run(["reach", "solve", p, "--max-horizon", "4", "--timeout", "2"])
            assert r.exit_code != 2, r.output


@FUZZ
@given(case=problem_bytes(REACH_DOCS), command=st.sampled_from(["solve", "solve", "validate"]))
def test_mutated_reach_problems_keep_the_contract(work: Path, case: tuple[bytes, str], command: str) -> None:
    p = _write(work, *case)
    if command == "solve":
        _run(["reach", "solve", p, "--max-horizon", "4", "--timeout", "2"])
    else:
        _run(["reach", "validate", p, work / "traj.json"])


@FUZZ
@given(
    doc=mutated_documents(
        [
            {"status": "realizable", "steps": 6, "program": WINNER, "problem": str(FIGURE1)},
            {"states": [[1, 1, 0, 0], [1.1, 1.1, 0.2, 0.2]], "inputs": [[0.4, 0.4]], "regions": [0, 0]},
        ]
    )
)
def test_mutated_result_files_keep_the_contract(work: Path, doc: Any) -> None:
    p = work / "mutated-result.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    _run(["grid", "verify", FIGURE1, p])
    _run(["grid", "export", p, "--lang", "python"])
    _run(["reach", "validate", MAZE1, p])


# -- programs -----------------------------------------------------------------------------

_TOKENS = [
    "(",
    "(",
    ")",
    ")",
    "ite",
    "and",
    "or",
    "not",
    "<=",
    "=",
    "+",
    "-",
    "rx",
    "ry",
    "o0x",
    "o0y",
    "o1x",
    "o1y",
    "0",
    "1",
    "2",
    "3",
    "-1",
    "4",
    "99",
    "1234567890",
    "１",
    "²",
    "٣",
    "define-fun",
    "move",
    "Int",
    "((rx Int))",
    ";c\n",
    "\u3000",
    "x" * 70,
    "\0",
    "é",
]


def _valid_terms() -> st.SearchStrategy[str]:
    leaf = st.sampled_from(["rx", "ry", "o0x", "o1y", "0", "1", "3", "(- 1)"])
    cond = st.recursive(
        st.tuples(st.sampled_from(["<=", "="]), leaf, leaf).map(lambda t: f"({t[0]} {t[1]} {t[2]})"),
        lambda c: st.one_of(
            st.lists(c, min_size=2, max_size=5).map(lambda cs: "(and " + " ".join(cs) + ")"),
            st.lists(c, min_size=2, max_size=5).map(lambda cs: "(or " + " ".join(cs) + ")"),
            c.map(lambda x: f"(not {x})"),
        ),
        max_leaves=8,
    )
    return st.recursive(
        st.sampled_from(["0", "1", "2", "3", "4"]),
        lambda s: st.tuples(cond, s, s).map(lambda t: f"(ite {t[0]} {t[1]} {t[2]})"),
        max_leaves=12,
    )


PROGRAMS = st.one_of(
    st.lists(st.sampled_from(_TOKENS), max_size=60).map(" ".join),
    st.text(max_size=80),
    _valid_terms(),
    st.sampled_from([2, 50, 99, 100, 101, 3_000]).map(lambda n: "(ite (<= rx 3) " * n + "2" + " 1)" * n),
    st.sampled_from([3, 4, 5, 17, 1_000]).map(lambda n: "(ite (and " + " ".join(["(<= rx 3)"] * n) + ") 2 1)"),
    _valid_terms().map(lambda t: f"((define-fun move ((rx Int) (ry Int)) Int {t}))"),
)


@settings(max_examples=200 * SCALE, deadline=None, suppress_health_check=list(HealthCheck))
@given(text=PROGRAMS)
def test_random_programs_parse_or_fail_with_a_named_error(text: str) -> None:
    try:
        t = parse_program(text)
    except ProgramSyntaxError:
        return
    names = sorted(variables_of(t))
    assert parse_program(str(t)) == t
    assert depth(t) >= 1 and size(t) >= 1
    env = {v: 1 for v in names}
    value = evaluate(t, env)
    assert compile_program(t, names)(*[1] * len(names)) == value
    if "move" in names:  # the default function name would shadow an input: refused, by name
        with pytest.raises(ValueError, match="'move' is an input of the controller"):
            to_c(t, names)
        to_c(t, names, name="_".join(["controller", *names]))  # not an input
    else:
        to_c(t, names)


@FUZZ
@given(text=PROGRAMS)
def test_random_programs_through_the_cli(text: str) -> None:
    _run(["grid", "verify", FIGURE1, text, "--steps", "3"])


# -- command lines ------------------------------------------------------------------------

_COMMANDS = {
    ("grid", "solve"): ["{grid}"],
    ("grid", "compile"): ["{grid}"],
    ("grid", "verify"): ["{grid}", "{program}"],
    ("grid", "export"): ["{program}"],
    ("grid", "explain"): ["{grid}"],
    ("grid", "minimize"): ["{grid}"],
    ("grid", "animate"): ["{grid}", "{program}"],
    ("reach", "solve"): ["{reach}"],
    ("reach", "validate"): ["{reach}", "{traj}"],
    ("reach", "plot"): ["{reach}"],
}
_VALUES = [
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "1",
    "2",
    "3",
    "6",
    "1001",
    "1000000000000",
    "1e400",
    "abc",
    "",
    "0.5",
    "{out}",
    "{grid}",
    "{reach}",
]
_OPTIONS = {
    "--steps": _VALUES,
    "--max-steps": _VALUES,
    "--depth-bound": _VALUES,
    "--memory-mb": _VALUES,
    "--timeout": ["nan", "inf", "-1", "0", "abc", "", "1e400", "0.5", "2"],
    "--solver": ["native", "cvc5", "external", "nosuch", ""],
    "--command": ["true", "echo infeasible", "nosuch-command", "", "'"],
    "--option": ["sygus-enum=fast", "x", "=", "minimize=true", "nosuch=1"],
    "--out": ["{out}"],
    "-o": ["{out}"],
    "--keep-sl": ["{outdir}"],
    "--minimize": None,
    "--lang": ["python", "c", "sygus", "rust", ""],
    "--problem": ["{grid}", "{missing}", "{fifo}"],
    "--planner": ["lazy-smt", "milp", "lazy-smt-paper", "nosuch", ""],
    "--max-horizon": _VALUES,
    "-O": [
        "counterexample=farkas",
        "counterexample=trivial",
        "counterexample=x",
        "horizon_search=linear",
        "horizon_search=x",
        "window_growth=nan",
        "window_growth=inf",
        "window_growth=0",
        "window_growth=0.25",
        "window_growth=1e9",
        "window_growth=x",
        "generalize=false",
        "semantics=lasso",
        "max_horizon=1e400",
        "x",
        "=",
    ],
    "--fps": ["nan", "inf", "0", "3", "1e9"],
    "--seed": ["0", "-1", "1e3", "99999999999999999999"],
    "--obstacles": ["adversarial", "random", "x"],
    "--paper": None,
    "--bogus": None,
    "--segment-safe": None,
}


@st.composite
def command_lines(draw: st.DrawFn) -> list[str]:
    group, name = draw(st.sampled_from(sorted(_COMMANDS)))
    args = [group, name]
    for slot in _COMMANDS[(group, name)]:
        args.append(
            draw(st.sampled_from([slot, slot, slot, "{missing}", "{fifo}", "{dir}", "/dev/null", "x" * 400, "", "-"]))
        )
    for _ in range(draw(st.integers(0, 4))):
        opt = draw(st.sampled_from(sorted(_OPTIONS)))
        values = _OPTIONS[opt]
        args.append(opt)
        if values is not None:
            args.append(draw(st.sampled_from(values)))
    needs_budget = (group, name) in {("grid", "solve"), ("grid", "explain"), ("grid", "minimize"), ("reach", "solve")}
    if needs_budget and "--timeout" not in args:
        args += ["--timeout", "2"]
    if (group, name) == ("reach", "solve") and "--max-horizon" not in args:
        args += ["--max-horizon", "6"]
    if (group, name) in {("grid", "animate"), ("reach", "plot")} and "-o" not in args and "--out" not in args:
        args += ["-o", "{out}"]
    return args


def _fill(args: list[str], work: Path, n: int) -> list[str]:
    names = {
        "{grid}": str(FIGURE1),
        "{reach}": str(MAZE1),
        "{program}": WINNER,
        "{traj}": str(work / "traj.json"),
        "{out}": str(work / "out" / f"o{n}.png"),
        "{outdir}": str(work / "out" / f"sl{n}"),
        "{missing}": str(work / "missing.yaml"),
        "{fifo}": str(work / "fifo.yaml"),
        "{dir}": str(work),
    }
    return [names.get(a, a) for a in args]


@settings(max_examples=60 * SCALE, deadline=None, suppress_health_check=list(HealthCheck))
@given(args=command_lines(), n=st.integers(0, 3))
def test_random_command_lines_keep_the_contract(work: Path, args: list[str], n: int) -> None:
    _run(_fill(args, work, n))


# -- real processes -----------------------------------------------------------------------


def test_random_command_lines_in_a_real_process_under_a_memory_limit(work: Path) -> None:
    """Twenty random command lines and mutated files in one real process, under a
    1.5 GB address-space limit; and three through the console entry."""
    rng = random.Random(20261201)
    cases = []
    for n in range(20):
        group, name = rng.choice(sorted(_COMMANDS))
        args = [group, name] + [rng.choice([slot, slot, "{fifo}", "x" * 400]) for slot in _COMMANDS[(group, name)]]
        for _ in range(rng.randint(0, 3)):
            opt = rng.choice(sorted(_OPTIONS))
            args += [opt] if _OPTIONS[opt] is None else [opt, rng.choice(_OPTIONS[opt])]
        if group == "grid" and name in ("solve", "explain", "minimize") or (group, name) == ("reach", "solve"):
            args += ["--timeout", "2", "--max-horizon", "6"] if group == "reach" else ["--timeout", "2"]
        if (group, name) in {("grid", "animate"), ("reach", "plot")}:
            args += ["-o", "{out}"]
        cases.append(_fill(args, work, n))
    hostile = work / "hostile.yaml"
    hostile.write_text(billion_laughs() + FIGURE1.read_text(encoding="utf-8"), encoding="utf-8")
    cases += [["grid", "solve", str(hostile)], ["reach", "solve", str(hostile)], ["grid", "solve", "/dev/zero"]]
    script = textwrap.dedent(
        """
        import json, resource, sys, time
        resource.setrlimit(resource.RLIMIT_AS, (1536 << 20, 1536 << 20))
        from typer.testing import CliRunner
        from plansynth.cli import app
        out = []
        for args in json.loads(sys.argv[1]):
            t0 = time.perf_counter()
            r = CliRunner().invoke(app, args)
            out.append([args, r.exit_code, r.stderr, r.output[-3000:], repr(r.exception), time.perf_counter() - t0])
        print(json.dumps(out))
        """
    )
    proc = subprocess.run(
        [sys.executable, "-c", script, json.dumps(cases)], capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    for args, code, stderr, output, exc, seconds in json.loads(proc.stdout.splitlines()[-1]):
        where = " ".join(args)[:300]
        assert code in (0, 1, 2, 3) and "Traceback" not in output and "MemoryError" not in exc, (where, code, output)
        assert exc == "None" or exc.startswith("SystemExit"), (where, exc)
        assert seconds < SECONDS, (where, seconds)
        if code == 2:
            lines = [ln for ln in stderr.splitlines() if ln.strip()]
            assert len(lines) == 1 and lines[0].startswith("error: "), (where, stderr)
    for args in (
        ["grid", "solve", str(FIGURE1), "--timeout", "nan"],
        ["grid", "verify", str(FIGURE1), "x" * 400],
        ["reach", "solve", str(hostile)],
    ):
        p = subprocess.run([sys.executable, "-m", "plansynth.cli", *args], capture_output=True, text=True, timeout=120)
        lines = [ln for ln in p.stderr.splitlines() if ln.strip()]
        assert p.returncode == 2 and len(lines) == 1 and lines[0].startswith("error: "), (args, p.stderr)
