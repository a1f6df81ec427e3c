"""Start-up: ``import plansynth.reach``, ``plansynth --version`` and ``plansynth reach
--help`` load none of the numeric and solver libraries, and a reach solve loads only
the planner it runs. Guarded by what a fresh process imports, not by timing it (a
loaded machine would make a timed test flaky; the timings belong in benchmarks):
numpy alone is 0.04-0.1 s of imports, shapely, python-sat and highspy add more, and
``plansynth.reach`` used to import all of them and every planner whatever the command.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Libraries no command needs before it plans, with why each one is heavy.
NUMERIC = {
    "numpy": "arrays: 0.04-0.1 s of imports on its own",
    "shapely": "the geometry of the abstraction and the validator (and numpy)",
    "pysat": "DIS-PLAN's SAT solver",
    "highspy": "CON-PLAN's LP solver",
    "matplotlib": "pictures only",
    "PIL": "animations only",
    "cvc5": "the grid half's SyGuS backend",
}

#: Modules a lazy-smt solve of a reach-avoid problem without a mission does not need.
NOT_ON_A_LAZY_SOLVE = {
    "matplotlib": "pictures only (--plot, --animate)",
    "PIL": "animations only",
    "cvc5": "the grid half's SyGuS backend",
    "plansynth.grid": "the other half",
    "plansynth.bench": "benchmarks",
    "plansynth.reach.families": "the benchmark families",
    "plansynth.reach.mission.planner": "LTL missions (their options, a light module, are listed)",
    "plansynth.reach.mission.bmc": "the mission encoding",
    "plansynth.reach.mission.labels": "the label-refined abstraction",
    "plansynth.reach.mission.proof": "the mission's geometric proof",
    "plansynth.reach.mission.milp": "the mission MILP baseline",
    "plansynth.reach.mission.milp_model": "the mission MILP's model",
    "plansynth.reach.mission.milp_geometry": "the mission MILP's polytopes",
    "plansynth.reach.ltl": "the mission language (a problem without a mission has no formula)",
    "plansynth.reach.planners.milp": "the MILP planner",
    "plansynth.reach.planners.milp_bigm": "the big-M MILP baseline",
    "plansynth.reach.planners.gcs": "the GCS baseline",
    "plansynth.reach.planners.ompl": "the sampling baselines",
    "plansynth.reach.plot": "pictures only",
}


#: Prepended to the code a process runs: at exit it lists every module it imported
#: (``sys.modules``, which also holds what ``importlib.import_module`` loaded, as the
#: CLI loads its sub-command groups; ``-X importtime`` does not trace those).
_LIST_MODULES_AT_EXIT = (
    "import atexit, sys\n"
    "atexit.register(lambda: sys.stderr.write('\\nMODULES ' + ' '.join(sorted(sys.modules)) + '\\n'))\n"
)


def _imported(code: str, *args: str) -> tuple[subprocess.CompletedProcess, set[str]]:
    """The finished process and every module it imported (full dotted names)."""
    run = subprocess.run(
        [sys.executable, "-c", _LIST_MODULES_AT_EXIT + code, *args],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    listed = re.findall(r"^MODULES (.*)$", run.stderr, re.M)
    assert listed, "no module list: " + run.stderr[-2000:]
    return run, set(listed[-1].split())


def _cli(*args: str) -> tuple[subprocess.CompletedProcess, set[str]]:
    return _imported("from plansynth.cli import main; main()", *args)


def _loaded(names: set[str], modules: dict[str, str]) -> dict[str, str]:
    return {m: why for m, why in modules.items() if any(n == m or n.startswith(m + ".") for n in names)}


def test_importing_plansynth_reach_loads_no_numeric_library() -> None:
    run, names = _imported("import plansynth.reach")
    assert run.returncode == 0, run.stderr[-2000:]
    assert "plansynth.reach" in names
    assert not _loaded(names, NUMERIC), _loaded(names, NUMERIC)
    # nor any module of the package: each public name is imported on first use
    assert not [n for n in names if n.startswith("plansynth.reach.")], sorted(names)


def test_plansynth_version_loads_neither_half() -> None:
    run, names = _cli("--version")
    assert run.returncode == 0 and run.stdout.startswith("plansynth "), run.stdout + run.stderr[-2000:]
    heavy = {
        **NUMERIC,
        "plansynth.reach": "the reach half",
        "plansynth.grid": "the grid half",
        "plansynth.bench": "benchmarks",
        "yaml": "no file is read",
        "rich": "nothing is laid out",
    }
    assert not _loaded(names, heavy), _loaded(names, heavy)


def test_reach_help_loads_no_numeric_library() -> None:
    run, names = _cli("reach", "--help")
    assert run.returncode == 0 and "solve" in run.stdout, run.stdout + run.stderr[-2000:]
    assert "plansynth.reach.cli" in names
    assert not _loaded(names, NUMERIC), _loaded(names, NUMERIC)


def test_a_lazy_solve_loads_only_what_it_runs() -> None:
    run, names = _cli("reach", "solve", str(ROOT / "examples/reach/maze-1.yaml"), "--timeout", "60")
    assert run.returncode == 0 and "found" in run.stdout, run.stdout + run.stderr[-2000:]
    assert {"plansynth.reach.lazy.loop", "plansynth.reach.validate", "pysat", "highspy"} <= names
    assert not _loaded(names, NOT_ON_A_LAZY_SOLVE), _loaded(names, NOT_ON_A_LAZY_SOLVE)


def test_a_mission_still_loads_the_mission_language() -> None:
    """The guard above is not vacuous: a problem with a mission does load the parser
    (the problem checks the formula at the door) and the mission planner."""
    run, names = _imported(
        "from plansynth.reach.fileformat import load_reach_problem; import sys; load_reach_problem(sys.argv[1])",
        str(ROOT / "examples/reach/mission-patrol.yaml"),
    )
    assert run.returncode == 0, run.stderr[-2000:]
    assert "plansynth.reach.ltl.syntax" in names


def test_every_public_name_of_plansynth_reach_resolves() -> None:
    """The lazy names are the ones ``__all__`` promises, and ``solve``, ``validate`` and
    ``planners`` stay the functions after their modules (of the same names) are imported."""
    code = (
        "import importlib, plansynth.reach as r\n"
        "for m in ('solve', 'validate', 'planners'): importlib.import_module('plansynth.reach.' + m)\n"
        "missing = [n for n in r.__all__ if getattr(r, n, None) is None]\n"
        "assert not missing, missing\n"
        "assert callable(r.solve) and callable(r.validate) and callable(r.planners)\n"
        "assert r.solve.__module__ == 'plansynth.reach.solve' and r.load is r.load_reach_problem\n"
        "from plansynth.reach import ReachStatus, load, solve\n"
        "print(solve(load('examples/reach/maze-1.yaml')).status is ReachStatus.FOUND)\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert run.returncode == 0 and run.stdout.strip() == "True", run.stdout + run.stderr[-2000:]


@pytest.mark.parametrize("name", ["nonexistent", "_DEFINED_IN_typo"])
def test_an_unknown_name_is_an_attribute_error(name: str) -> None:
    import plansynth.reach

    with pytest.raises(AttributeError, match=name):
        getattr(plansynth.reach, name)
