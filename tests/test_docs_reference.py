"""The reference pages agree with the code and with the shared format specification.

* docs/reference/cli.md and options.md are what docs/_tools/reference.py generates from
  the code now (rerun the script after changing a command or an option), every option
  of every command appears in its command's section, and every command states its exit
  statuses;
* the format pages (docs/reference/*-format.md) hold every field plansynth's loaders
  accept and every name the benchmark families and registries know;
* against the shared specification (``../shared/spec/`` beside the checkout, as in CI):
  every YAML/JSON example there loads with plansynth's loaders, and every field or value
  it names appears in the repository's page.
"""

from __future__ import annotations

import importlib.util
import json
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "docs" / "reference"
SPEC = ROOT.parent / "shared" / "spec"
#: The shared specification's pages and the repository's page each one became.
#: An elided array's tail in an example, ``[[1, 1, 0, 0], ...]``.
ELISION = r",\s*\.\.\.(?=\s*[\]}])"
PAGES = {
    "grid-problem.md": "grid-format.md",
    "reach-problem.md": "reach-format.md",
    "benchmarks.md": "benchmarks-format.md",
}


def _generator() -> Any:
    spec = importlib.util.spec_from_file_location("docs_reference", ROOT / "docs" / "_tools" / "reference.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def generator() -> Any:
    return _generator()


def test_the_generated_reference_is_current() -> None:
    """docs/reference/cli.md and options.md are what the generator writes now (run in a
    fresh interpreter: other tests register stand-in solvers in this one)."""
    run = subprocess.run(
        [sys.executable, str(ROOT / "docs" / "_tools" / "reference.py"), "--check"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stdout + run.stderr


def _sections(text: str) -> dict[str, str]:
    """``## `plansynth ...` `` heading -> the section's text."""
    parts = re.split(r"^## `(plansynth[^`]*)`\n", text, flags=re.M)
    return dict(zip(parts[1::2], parts[2::2]))


def test_every_option_of_every_command_is_in_the_cli_reference(generator: Any) -> None:
    sections = _sections((REFERENCE / "cli.md").read_text(encoding="utf-8"))
    commands = generator.commands()
    assert len(commands) >= 15 and {line for line, _, _ in commands} == set(sections)
    missing = []
    for line, command, _ in commands:
        table = [row for row in sections[line].splitlines() if row.startswith("| `")]
        for param in command.params:
            is_argument = param.param_type_name == "argument"
            names = [param.name.upper()] if is_argument else generator.option_names(param)
            for name in names:
                if not any(f"`{name}`" in row.split(" | ")[0] for row in table):
                    missing.append(f"{line}: {name}")
    assert not missing, f"options missing from docs/reference/cli.md: {missing}"


def test_every_command_states_its_exit_statuses() -> None:
    sections = _sections((REFERENCE / "cli.md").read_text(encoding="utf-8"))
    for line, text in sections.items():
        status = re.search(r"^\*\*Exit status:\*\* (.*)$", text, re.M)
        assert status and re.search(r"\b0\b", status.group(1)), f"{line}: no exit statuses"
        assert "not documented" not in status.group(1), f"{line}: exit statuses not documented"


def _code_spans(text: str) -> set[str]:
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return {m.group(1) for m in re.finditer(r"`([^`\n]+)`", text)}


def _field_names(text: str) -> set[str]:
    """The field names and values a page names in code: identifiers such as ``max_steps``,
    ``via``, ``double-integrator`` (not expressions or paths)."""
    return {s for s in _code_spans(text) if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_-]*", s)}


def _blocks(text: str, *languages: str) -> list[tuple[str, str]]:
    return [
        (m.group(1), m.group(2))
        for m in re.finditer(r"^```(\w+)\n(.*?)^```", text, re.S | re.M)
        if m.group(1) in languages
    ]


def _load_example(page: str, language: str, code: str, folder: Path) -> None:
    """Load one example of a format page with plansynth's loader for it; an example whose
    arrays are elided (``...``) is parsed as JSON and its keys checked against the page."""
    from plansynth.grid.problem import load_grid_problem
    from plansynth.grid.result import load_result
    from plansynth.io import parse_document
    from plansynth.reach.team.fileformat import load_problem as load_reach_problem  # one robot or a team

    path = folder / f"example.{'yaml' if language == 'yaml' else 'json'}"
    if language == "json" and re.search(ELISION, code):
        doc = parse_document(re.sub(ELISION, "", code), str(path), json_syntax=True)
        documented = _code_spans((REFERENCE / PAGES.get(page, page)).read_text(encoding="utf-8"))
        assert set(doc) <= documented, f"{page}: keys {set(doc) - documented} not documented"
        return
    path.write_text(code, encoding="utf-8")
    loader = {
        ("grid", "yaml"): load_grid_problem,
        ("grid", "json"): load_result,
        ("reach", "yaml"): load_reach_problem,
    }[(page.split("-")[0], language)]
    loader(path)


def _format_pages() -> list[str]:
    return sorted(p.name for p in REFERENCE.glob("*-format.md"))


@pytest.mark.parametrize("page", ["grid-format.md", "reach-format.md"])
def test_every_example_of_the_format_pages_loads(page: str, tmp_path: Path) -> None:
    blocks = _blocks((REFERENCE / page).read_text(encoding="utf-8"), "yaml", "json")
    assert len(blocks) >= 2
    for language, code in blocks:
        _load_example(page, language, code, tmp_path)


def test_the_format_pages_name_every_field_the_loaders_accept() -> None:
    from plansynth.grid import problem as grid_problem
    from plansynth.reach import fileformat

    grid = _code_spans((REFERENCE / "grid-format.md").read_text(encoding="utf-8"))
    reach = _code_spans((REFERENCE / "reach-format.md").read_text(encoding="utf-8"))
    grid_keys = set(grid_problem._TOP_KEYS) | {"start", "goal", "moves", "name", "to", "via"}
    assert grid_keys <= grid, f"grid fields not documented: {grid_keys - grid}"
    reach_keys = set(fileformat._TOP_KEYS) | set(fileformat._ROBOT_KEYS)
    assert reach_keys <= reach, f"reach fields not documented: {reach_keys - reach}"
    from plansynth.reach.team import fileformat as team

    team_keys = set(team._TOP_KEYS) | set(team._ROBOT_KEYS) | {"distance", "norm", "shape", "path", "point"}
    assert team_keys <= reach, f"team fields not documented: {team_keys - reach}"


def _builtin_names() -> dict[str, list[str]]:
    """The grid backends and reach planners a fresh interpreter knows (other tests
    register stand-ins in this one)."""
    code = (
        "import json; from plansynth.grid.result import backend_names; "
        "from plansynth.reach.planners import planners; "
        "print(json.dumps({'backends': list(backend_names()), 'planners': list(planners())}))"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120)
    return json.loads(run.stdout)


def test_the_pages_name_every_family_planner_and_backend() -> None:
    from plansynth.bench.families import GRID_FAMILIES, REACH_FAMILIES

    text = (REFERENCE / "benchmarks-format.md").read_text(encoding="utf-8")
    every = {*GRID_FAMILIES, *REACH_FAMILIES}
    named = {name for name in every if f"`{name}`" in text or re.search(rf"\b{re.escape(name)}\b", text)}
    assert named == every, f"families not documented: {every - named}"
    builtin = _builtin_names()
    trajectories = _code_spans((ROOT / "docs" / "how-to" / "plan-trajectories.md").read_text(encoding="utf-8"))
    trajectories |= {w.strip() for s in trajectories for w in s.split(",")}
    assert set(builtin["planners"]) <= trajectories, (
        f"planners not in plan-trajectories.md: {set(builtin['planners']) - trajectories}"
    )
    solvers = _code_spans((ROOT / "docs" / "how-to" / "sygus-and-external-solvers.md").read_text(encoding="utf-8"))
    assert set(builtin["backends"]) <= solvers, f"backends not documented: {set(builtin['backends']) - solvers}"


needs_spec = pytest.mark.skipif(
    not SPEC.is_dir(), reason="the shared specification (../shared/spec) is not beside the checkout"
)


@needs_spec
@pytest.mark.parametrize("page", sorted(PAGES))
def test_every_example_of_the_shared_spec_loads(page: str, tmp_path: Path) -> None:
    for language, code in _blocks((SPEC / page).read_text(encoding="utf-8"), "yaml", "json"):
        _load_example(page, language, code, tmp_path)


@needs_spec
@pytest.mark.parametrize("page", sorted(PAGES))
def test_every_field_of_the_shared_spec_is_in_the_repository_page(page: str) -> None:
    spec = (SPEC / page).read_text(encoding="utf-8")
    ours = (REFERENCE / PAGES[page]).read_text(encoding="utf-8")
    named = _field_names(spec)
    for _, code in _blocks(spec, "yaml", "json"):  # and every key of its examples
        named |= set(re.findall(r"^\s*-?\s*([a-z_]+):", code, re.M))
        if code.lstrip().startswith("{"):
            named |= set(json.loads(re.sub(ELISION, "", code)))
    assert named, page
    missing = {name for name in named if f"`{name}`" not in ours and not re.search(rf"^\s*-?\s*{name}:", ours, re.M)}
    assert not missing, f"{PAGES[page]} does not name {sorted(missing)} (from the shared {page})"
