"""The documentation's commands and Python blocks are tests.

Every ``plansynth ...`` line in a code block of README.md, CONTRIBUTING.md or any page
of docs/ (:data:`DOCS`) is run here as a user would run it: the installed ``plansynth`` command in a fresh process,
in a temporary folder holding a copy of the checkout's ``examples/`` (and
``benchmarks/``), with its outcome asserted (exit status, what it prints, the files it
writes, the status and validation recorded in them).

:data:`CASES` maps each documented command (as :func:`documented_commands` spells it:
comments dropped, re-quoted by ``shlex.join``) to what it must do. A documented command
without an entry FAILS :func:`test_every_documented_command_has_a_case`, which prints the
line to add; an entry for a command no document shows fails too. Adding one is a
one-liner, e.g.::

    "plansynth grid solve examples/grid/figure1.yaml": Case(out=("realizable",)),

A command too slow for every CI run gets a ``fast`` variant (a smaller ``--timeout``,
fewer values, an easier example), which always runs; the command as written then runs
with ``--runslow`` (``slow=False``: never, for benchmark sweeps and synopses such as
``[--report-only]``). The first README line's ``bash scripts/setup.sh`` and the
``bash scripts/test.sh`` line are what CI itself runs; here the first line's
``plansynth`` part runs with the installed package.

Every ``python`` block of those documents runs too, in a fresh interpreter from such a
folder, and prints what its ``print(...)  # OUTPUT`` comments promise. A block that is
only an illustration (a sketch that cannot run on its own) is marked by the line
``<!-- not-a-test -->`` just before it; few are (:data:`MAX_UNTESTED_BLOCKS`).

``p.yaml``, the placeholder problem of some lines, is a small grid problem written into
the folder, and ``cvc5`` on the PATH is a stand-in for the cvc5 binary (the cvc5 wheel
ships none): ``python -m plansynth.grid.backends.cvc5_cli``, cvc5 through its Python API.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: Every document whose code blocks are tests: the README, the contributors' guide and
#: every page of the documentation site.
DOCS = ("README.md", "CONTRIBUTING.md", *sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md")))
#: The mark of a code block that is only an illustration, on the line before it.
NOT_A_TEST = "<!-- not-a-test -->"
#: At most this many blocks may be marked so (illustrations are the exception).
MAX_UNTESTED_BLOCKS = 3
BIN = Path(sys.executable).parent
PLANSYNTH = shutil.which("plansynth", path=str(BIN)) or shutil.which("plansynth")

#: The placeholder problem ``p.yaml``: a 3x1 corridor, realizable at l = 2.
P_YAML = """\
grid: [3, 1]
robot: {start: [0, 0], goal: [2, 0], moves: [stay, right]}
max_steps: 3
"""

#: ``small.yaml``: an open 10 x 10 workspace, double integrator (a short trajectory).
SMALL_YAML = """\
name: small
workspace: {min: [0, 0], max: [10, 10]}
goal: {min: [6, 6], max: [8, 8]}
robot:
  dynamics: {model: double-integrator, dt: 0.5}
  start: [1, 1, 0, 0]
  input_bound: 1
  state_bounds: {min: [0, 0, -2, -2], max: [10, 10, 2, 2]}
max_horizon: 40
"""

CVC5_SHIM = f"""#!/bin/sh
# stands in for the cvc5 binary: cvc5 through its Python API
exec {shlex.quote(sys.executable)} -m plansynth.grid.backends.cvc5_cli "$@"
"""


@dataclass(frozen=True)
class Case:
    """What a documented command must do.

    ``exit``: the allowed exit statuses; ``out``: texts its output contains; ``files``:
    files it writes (relative to the folder; a trailing ``/`` means a non-empty folder);
    ``json``: (file, key, value) triples its JSON files hold; ``before``: commands run
    first to make its inputs (asserted to exit 0); ``fast``: the variant run in every
    CI run when the command as written is slow (a command, or a tuple whose last
    command is the variant and the others its own ``before``), held to the same
    assertions; ``slow``: whether the command as written also runs with ``--runslow``
    when there is a ``fast`` variant.
    """

    exit: tuple[int, ...] = (0,)
    out: tuple[str, ...] = ()
    files: tuple[str, ...] = ()
    json: tuple[tuple[str, str, Any], ...] = ()
    before: tuple[str, ...] = ()
    fast: str | tuple[str, ...] | None = None
    slow: bool = True
    timeout: float = 300.0
    #: a command that runs until stopped (a server) is run by this test file instead
    runs_in: str = ""


FIGURE1_CVC5 = Case(
    out=("realizable",),
    files=("figure1-result.json",),
    json=(("figure1-result.json", "status", "realizable"), ("figure1-result.json", "verified", True)),
    fast="plansynth grid solve p.yaml --solver cvc5 --out figure1-result.json",
)
SOLVED_P = "plansynth grid solve p.yaml -o door.json"
SOLVED_FIGURE1 = "plansynth grid solve examples/grid/figure1.yaml --out result.json"
SOLVED_DOOR = "plansynth grid solve examples/grid/door.yaml -o door.json"
SOLVED_WINDY = "plansynth reach solve examples/reach/maze-3-windy.yaml --out plan.json --plot plan.png"
SOLVED_WINDY_TEAM = "plansynth reach solve examples/reach/team-swap-windy.yaml --out team.json --plot team.png"
SOLVED_CROSSING = "plansynth grid solve examples/grid/crossing.yaml -o crossing.json"
SOLVED_MAZE3 = "plansynth reach solve examples/reach/maze-3.yaml --out traj.json"
SOLVED_PATROL = "plansynth reach solve examples/reach/mission-patrol.yaml --out plan.json"
SOLVED_CLUTTERED = "plansynth reach solve examples/reach/cluttered.yaml --out traj.json"
SOLVED_TEAM = "plansynth reach solve examples/reach/team-swap.yaml --out plan.json --plot plan.png --animate plan.gif"
TINY_BENCH = "plansynth bench grid --family figure1 --solvers native --timeout 60 --db bench-results.db"
FOUND = ("found",)

CASES: dict[str, Case] = {
    # README.md: the two commands, then the tour; each documented command once, wherever it is shown
    "plansynth grid solve examples/grid/figure1.yaml --solver cvc5 --out figure1-result.json": FIGURE1_CVC5,
    # README: see it in the browser (plansynth view; tests/view/ drives the pages in Chromium)
    "plansynth grid solve examples/grid/traffic.yaml -o traffic.json": Case(
        out=("realizable",), json=(("traffic.json", "status", "realizable"),)
    ),
    "plansynth view examples/grid/traffic.yaml --result traffic.json -o traffic.html": Case(
        out=("page written to traffic.html",),
        files=("traffic.html",),
        before=("plansynth grid solve examples/grid/traffic.yaml -o traffic.json",),
    ),
    "plansynth reach solve examples/reach/mission-patrol.yaml -o patrol.json": Case(
        out=FOUND, json=(("patrol.json", "status", "found"),)
    ),
    "plansynth view examples/reach/mission-patrol.yaml --result patrol.json -o patrol.html": Case(
        out=("page written to patrol.html",),
        files=("patrol.html",),
        before=("plansynth reach solve examples/reach/mission-patrol.yaml -o patrol.json",),
    ),
    # docs/how-to/view.md (the page's behaviour is tested in a browser by tests/view/)
    "plansynth grid solve examples/grid/traffic.yaml --steps 8 -o traffic-8.json": Case(
        exit=(1,), out=("unrealizable",), files=("traffic-8.json",)
    ),
    "plansynth view examples/grid/traffic.yaml --result traffic-8.json -o why.html": Case(
        out=("page written to why.html",),
        files=("why.html",),
        before=("plansynth grid solve examples/grid/traffic.yaml --steps 8 -o traffic-8.json",),
    ),
    "plansynth reach solve examples/reach/team-crossing.yaml -o crossing.json": Case(
        out=FOUND, json=(("crossing.json", "status", "found"), ("crossing.json", "validated", True))
    ),
    "plansynth view examples/reach/team-crossing.yaml --result crossing.json -o crossing.html": Case(
        out=("page written to crossing.html",),
        files=("crossing.html",),
        before=("plansynth reach solve examples/reach/team-crossing.yaml -o crossing.json",),
    ),
    # serves until stopped: tests/view/test_commands.py starts it, asks for the page and stops it
    "plansynth view examples/reach/maze-3.yaml --serve": Case(runs_in="tests/view/test_commands.py"),
    # grid commands (README, how-to guides)
    "plansynth grid solve examples/grid/figure1.yaml": Case(out=("realizable", "l =   6")),
    "plansynth grid solve examples/grid/figure1.yaml --solver cvc5 --out result.json": Case(
        out=("realizable",),
        json=(("result.json", "status", "realizable"), ("result.json", "verified", True)),
        fast="plansynth grid solve p.yaml --solver cvc5 --out result.json",
    ),
    "plansynth grid solve examples/grid/depth-5.yaml --minimize": Case(out=("realizable", "minimal")),
    "plansynth grid solve p.yaml --solver external --command 'cvc5 --lang=sygus2 {file}'": Case(out=("realizable",)),
    "plansynth grid solve p.yaml --solver cvc5 --depth-bound 4 --max-steps 8 --timeout 600 -O sygus-enum=fast": Case(
        out=("realizable",)
    ),
    "plansynth grid compile examples/grid/figure1.yaml --steps 6 -o figure1-l6.sl": Case(files=("figure1-l6.sl",)),
    "plansynth grid compile examples/grid/figure1.yaml --steps 6 --depth-bound 4": Case(
        out=("(synth-fun", "(check-synth)")
    ),
    "plansynth grid solve examples/grid/shuttle.yaml": Case(out=("realizable (recurrence objective)", "verified")),
    "plansynth grid solve examples/grid/moving-obstacle-8x8.yaml --out mo.json": Case(
        out=("realizable (safety objective)",),
        json=(("mo.json", "status", "realizable"), ("mo.json", "verified", True), ("mo.json", "objective", "safety")),
    ),
    "plansynth grid verify examples/grid/moving-obstacle-8x8.yaml mo.json": Case(
        out=("WINS at the safety objective",),
        before=("plansynth grid solve examples/grid/moving-obstacle-8x8.yaml --out mo.json",),
    ),
    "plansynth grid explain examples/grid/robot-grid-2-fast.yaml": Case(
        exit=(1,), out=("unrealizable", "the play repeats", "the robot loses")
    ),
    "plansynth bench grid --family moving-obstacle --values 8,16 --solvers native,omega --timeout 120 --db syntcomp.db": Case(
        out=("finished",),
        files=("syntcomp.db",),
        fast="plansynth bench grid --family moving-obstacle --values 8 --solvers native,omega --timeout 60 --db syntcomp.db",
    ),
    "plansynth grid verify examples/grid/figure1.yaml result.json": Case(out=("WINS",), before=(SOLVED_FIGURE1,)),
    "plansynth grid verify examples/grid/figure1.yaml '(ite (<= rx 3) 2 1)' --steps 6": Case(out=("WINS",)),
    "plansynth grid animate examples/grid/door.yaml door.json -o door.gif --obstacles adversarial": Case(
        files=("door.gif",),
        before=(SOLVED_DOOR,),
        fast=(SOLVED_P, "plansynth grid animate p.yaml door.json -o door.gif --obstacles adversarial"),
    ),
    "plansynth grid animate examples/grid/door.yaml door.json -o run.gif --obstacles random --seed 3 --png step5.png --step 5": Case(
        files=("run.gif", "step5.png"),
        before=(SOLVED_DOOR,),
        fast=(
            SOLVED_P,
            "plansynth grid animate p.yaml door.json -o run.gif --obstacles random --seed 3 --png step5.png --step 1",
        ),
    ),
    "plansynth grid export result.json --lang c --problem examples/grid/figure1.yaml": Case(
        out=("return",), before=(SOLVED_FIGURE1,)
    ),
    "plansynth grid solve examples/grid/door.yaml -o door.json": Case(
        out=("realizable", "o0y"), json=(("door.json", "status", "realizable"),)
    ),
    "plansynth grid minimize examples/grid/crossing.yaml": Case(out=("minimal",)),
    "plansynth grid explain examples/grid/crossing.yaml --steps 8 --gif why.gif": Case(
        exit=(1,), out=("unrealizable",), files=("why.gif",)
    ),
    # reach commands (README, how-to guides, explanations)
    "plansynth reach solve examples/reach/maze-3.yaml --out traj.json --plot traj.png": Case(
        out=FOUND, files=("traj.png",), json=(("traj.json", "status", "found"), ("traj.json", "validated", True))
    ),
    "plansynth reach validate examples/reach/maze-3.yaml traj.json": Case(out=("valid",), before=(SOLVED_MAZE3,)),
    "plansynth reach solve examples/reach/maze-1.yaml --animate run.gif": Case(
        out=FOUND, files=("run.gif",), fast="plansynth reach solve small.yaml --animate run.gif"
    ),
    "plansynth reach solve examples/reach/claims/narrow-passage.yaml --prove": Case(
        out=("found", "8 (proved minimal)", "segments")
    ),
    "plansynth reach solve examples/reach/claims/narrow-passage.yaml --planner lazy-smt-minimal": Case(
        out=("found", "9 (minimal through the decomposition only)", "regions")
    ),
    "plansynth reach solve examples/reach/claims/narrow-passage.yaml --prove -O exact_segments=false": Case(
        out=("found", "9 (minimal through the decomposition only)", "regions")
    ),
    "plansynth reach solve examples/reach/claims/narrow-passage.yaml --max-horizon 7": Case(
        exit=(1,), out=("infeasible", "a proof for the problem")
    ),
    "plansynth reach solve examples/reach/maze-1.yaml --planner lazy-smt-paper": Case(
        out=("found", "57 (minimal through the decomposition only)")
    ),
    "plansynth reach solve examples/reach/cluttered.yaml --planner milp --max-horizon 60": Case(out=FOUND),
    "plansynth reach plot examples/reach/cluttered.yaml traj.json -o cluttered.png": Case(
        files=("cluttered.png",), before=(SOLVED_CLUTTERED,)
    ),
    "plansynth grid solve examples/grid/corridor.yaml --timeout 30": Case(out=("realizable",)),
    "plansynth grid solve examples/grid/corridor.yaml --effort 0": Case(out=("realizable", "not proved")),
    "plansynth reach solve examples/reach/maze-1.yaml --planner gcs --timeout 120": Case(out=FOUND),
    "plansynth reach solve examples/reach/maze-1.yaml --planner fpp --timeout 120": Case(out=FOUND),
    "plansynth reach solve examples/reach/mission-patrol.yaml --out plan.json --plot plan.png --animate plan.gif": Case(
        out=FOUND,
        files=("plan.png", "plan.gif"),
        json=(("plan.json", "status", "found"), ("plan.json", "validated", True)),
    ),
    "plansynth reach validate examples/reach/mission-patrol.yaml plan.json": Case(before=(SOLVED_PATROL,)),
    SOLVED_TEAM: Case(
        out=FOUND,
        files=("plan.json", "plan.png", "plan.gif"),
        json=(("plan.json", "status", "found"), ("plan.json", "validated", True)),
    ),
    "plansynth reach validate examples/reach/team-swap.yaml plan.json": Case(out=("valid",), before=(SOLVED_TEAM,)),
    "plansynth reach solve examples/reach/team-swap.yaml --planner milp-team": Case(out=FOUND),
    "plansynth reach solve examples/reach/team-swap.yaml --planner prioritized": Case(exit=(3,), out=("unknown",)),
    # bench commands (docs/how-to/benchmarks.md; the sweeps as written are the published benchmark: fast variants only)
    "plansynth bench grid --family steps --solvers native,cvc5 --timeout 300 --repeat 3": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench grid --family steps --values 1 --solvers native,cvc5 --timeout 60 --db b.db",
    ),
    "plansynth bench grid --family all --solvers native,external -O 'external:command=cvc5 --lang=sygus2 {file}'": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench grid --family steps --values 1 --solvers native,external -O 'external:command=cvc5 --lang=sygus2 {file}' --timeout 60 --db b.db",
    ),
    "plansynth bench reach --family maze --planners lazy-smt,rrt,milp-bigm,milp --repeat 5": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench reach --family maze --values 1 --planners lazy-smt,milp-bigm,milp --timeout 20 --db b.db",
    ),
    "plansynth bench reach --family chain --values 1,2 --orders 1,2,5,10 --planners lazy-smt": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench reach --family chain --values 1 --orders 1 --planners lazy-smt --timeout 20 --db b.db",
    ),
    "plansynth bench grid --family reactive-suite --solvers native,cvc5 --timeout 60": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench grid --family reactive-suite --values r03_traffic --solvers native --timeout 60 --db b.db",
    ),
    "plansynth bench grid --family reactive-suite,doors,doors-rush,doors-jam,patrols,patrols-walk --solvers native,cvc5 --timeout 10": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench grid --family doors --values 1 --solvers native --timeout 10 --db b.db",
    ),
    "plansynth bench reach --family maze --planners lazy-smt,gcs,gcs-decomposition,fpp --repeat 3": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench reach --family maze --values 1 --planners lazy-smt,gcs,fpp --timeout 120 --db b.db",
    ),
    "plansynth bench reach --family random-dynamics --values 1,2,3,4 --states 4,10,20,50 --planners lazy-smt": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench reach --family random-dynamics --values 1 --states 4 --planners lazy-smt --timeout 30 --db b.db",
    ),
    "plansynth bench reach --family gcs-maze --planners lazy-smt,lazy-smt-window,lazy-smt-minimal,gcs,gcs-decomposition,fpp --timeout 120": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench reach --family gcs-maze --values 10 --planners lazy-smt,lazy-smt-window --timeout 60 --db b.db",
    ),
    "plansynth bench reach --family team --planners lazy-smt-team,milp-team,prioritized": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench reach --family team --values smc-crossing --planners lazy-smt-team,milp-team,prioritized --timeout 60 --db b.db",
    ),
    "plansynth bench report --db bench-results.db --out bench-report/": Case(
        files=("bench-report/",), before=(TINY_BENCH,)
    ),
    "plansynth bench merge other-results.db --db benchmarks/results.db": Case(
        out=("runs merged into",),
        files=("benchmarks/results.db",),
        before=(TINY_BENCH.replace("bench-results.db", "other-results.db"),),
    ),
    "plansynth bench publish '[--report-only]'": Case(
        files=("published/RESULTS.md",), slow=False, fast="plansynth bench publish --report-only --out published"
    ),
    "plansynth reach solve examples/reach/mission-visit.yaml -p milp-ltl": Case(out=("found", "milp-ltl")),
    # under a bounded disturbance (README, docs/how-to/robust.md)
    "plansynth reach solve examples/reach/maze-3-windy.yaml --out plan.json --plot plan.png": Case(
        out=FOUND + ("keeps the closed loop safe and reaching", "K = ["),
        files=("plan.json", "plan.png"),
        json=(("plan.json", "status", "found"), ("plan.json", "validated", True)),
    ),
    "plansynth reach validate examples/reach/maze-3-windy.yaml plan.json --disturbances 1000": Case(
        out=("valid", "robust: worst case at every step", "0 of 1", " random, 0 of 1", " vertex runs violated"),
        before=(SOLVED_WINDY,),
        fast=(SOLVED_WINDY, "plansynth reach validate examples/reach/maze-3-windy.yaml plan.json --disturbances 100"),
    ),
    # a team under disturbances (docs/how-to/robust.md)
    SOLVED_WINDY_TEAM: Case(
        out=FOUND + ("each robot's W keeps every closed loop safe, separated and reaching", "feedback B"),
        files=("team.json", "team.png"),
        json=(("team.json", "status", "found"), ("team.json", "validated", True)),
    ),
    "plansynth reach validate examples/reach/team-swap-windy.yaml team.json --disturbances 200 --nominal": Case(
        out=("valid", "worst case: robust", "0 of 200 random, 0 of 200 vertex runs violated", "nominal plan (horizon"),
        before=(SOLVED_WINDY_TEAM,),
    ),
    "plansynth bench reach --family robust --values windy-swap --planners lazy-smt-team,milp-team": Case(
        files=("bench-results.db",), out=("solved",)
    ),
    "plansynth reach solve examples/reach/maze-3-windy.yaml --planner nominal-check": Case(
        exit=(3,), out=("unknown", "fails the robust check")
    ),
    "plansynth bench reach --family robust --planners lazy-smt --timeout 300": Case(
        files=("b.db",),
        slow=False,
        fast="plansynth bench reach --family robust --values 1 --planners lazy-smt --timeout 60 --db b.db",
    ),
    "plansynth reach solve examples/reach/mission-unsat.yaml": Case(exit=(1,), out=("infeasible",)),
    "plansynth reach solve examples/reach/mission-ringed.yaml --plot ringed.png": Case(
        exit=(1,), out=("infeasible", "picture of the problem written to ringed.png"), files=("ringed.png",)
    ),
    "plansynth reach solve examples/reach/mission-avoid-until.yaml -O exact_segments=true": Case(
        out=("found", "24", "proved minimal")
    ),
    # docs/how-to/missions.md: margins, readings
    "plansynth reach solve examples/reach/mission-visit.yaml --reading sample --margin 0.3": Case(
        out=("found", "achieved margin: 0.3")
    ),
    "plansynth reach solve examples/reach/mission-readings.yaml": Case(out=("found", "horizon", "18")),
    "plansynth reach solve examples/reach/mission-readings.yaml --reading sample": Case(
        out=("found", "9 (proved minimal)")
    ),
    "plansynth --version": Case(out=("plansynth 0.", "core")),
    SOLVED_FIGURE1: Case(
        out=("realizable",), json=(("result.json", "status", "realizable"), ("result.json", "verified", True))
    ),
    # docs/tutorial.md
    "plansynth grid solve examples/grid/crossing.yaml -o crossing.json": Case(
        out=("realizable",), json=(("crossing.json", "status", "realizable"),)
    ),
    "plansynth grid animate examples/grid/crossing.yaml crossing.json -o crossing.gif": Case(
        files=("crossing.gif",),
        before=(SOLVED_CROSSING,),
        fast=(SOLVED_P, "plansynth grid animate p.yaml door.json -o crossing.gif"),
    ),
    "plansynth grid animate examples/grid/crossing.yaml crossing.json -o random.gif --obstacles random --seed 1": Case(
        files=("random.gif",),
        before=(SOLVED_CROSSING,),
        fast=(SOLVED_P, "plansynth grid animate p.yaml door.json -o random.gif --obstacles random --seed 1"),
    ),
    "plansynth grid solve examples/grid/crossing.yaml --steps 8": Case(exit=(1,), out=("unrealizable",)),
    "plansynth grid compile examples/grid/crossing.yaml --steps 9 -o crossing.sl": Case(files=("crossing.sl",)),
    "plansynth grid solve examples/grid/crossing.yaml --solver cvc5 --timeout 120": Case(
        exit=(0, 3), out=("cvc5",), fast="plansynth grid solve examples/grid/crossing.yaml --solver cvc5 --timeout 5"
    ),
    "plansynth grid solve examples/grid/crossing.yaml --solver external --command 'python -m plansynth.grid.backends.cvc5_cli {file}'": Case(
        exit=(0, 3),
        out=("external",),
        fast="plansynth grid solve examples/grid/crossing.yaml --solver external --command 'python -m plansynth.grid.backends.cvc5_cli {file}' --timeout 5",
    ),
    "plansynth grid verify examples/grid/crossing.yaml '(ite (<= rx 3) 2 0)' --steps 9": Case(
        exit=(1,), out=("LOSES", "counterexample")
    ),
}


def code_blocks(doc: str) -> list[tuple[str, int, str, bool]]:
    """Every fenced code block of ``doc``: (language, line of the fence, code, whether it
    is marked :data:`NOT_A_TEST`)."""
    text = (ROOT / doc).read_text(encoding="utf-8")
    blocks = []
    for m in re.finditer(r"^```([^\n]*)\n(.*?)^```", text, re.S | re.M):
        before = text[: m.start()].rstrip().rsplit("\n", 1)[-1].strip()
        blocks.append((m.group(1).strip(), text.count("\n", 0, m.start()) + 1, m.group(2), before == NOT_A_TEST))
    return blocks


def documented_commands() -> dict[str, str]:
    """Every ``plansynth`` command line in a code block of :data:`DOCS` (but the blocks
    marked :data:`NOT_A_TEST`), canonical form -> where it is shown. Continuation lines
    are joined; ``cmd && plansynth ...`` and ``.venv/bin/plansynth`` count as
    ``plansynth ...``."""
    found: dict[str, str] = {}
    for doc in DOCS:
        for _, _, block, untested in code_blocks(doc):
            if untested:
                continue
            for line in block.replace("\\\n", " ").splitlines():
                for part in line.split("&&"):
                    try:
                        words = shlex.split(part, comments=True)
                    except ValueError:
                        continue
                    if words and (words[0] == "plansynth" or words[0].endswith("/bin/plansynth")):
                        found.setdefault(shlex.join(["plansynth", *words[1:]]), doc)
    return found


def test_every_documented_command_has_a_case() -> None:
    documented = documented_commands()
    assert len(documented) >= 30, "the parser found too few commands"
    missing = [f"    {c!r}: Case(...),  # {doc}" for c, doc in documented.items() if c not in CASES]
    assert not missing, (
        "documented commands without a test; add to CASES in tests/test_readme_commands.py:\n" + "\n".join(missing)
    )
    stale = [c for c in CASES if c not in documented]
    assert not stale, f"CASES for commands no document shows any more: {stale}"


def test_the_parser_reads_continuations_comments_and_prefixes() -> None:
    documented = documented_commands()
    assert "plansynth grid solve examples/grid/figure1.yaml" in documented  # its comment dropped
    assert any(
        c.startswith("plansynth grid solve examples/grid/crossing.yaml --solver external --command") for c in documented
    )  # joined from two lines
    assert "plansynth grid solve examples/grid/figure1.yaml --solver cvc5 --out figure1-result.json" in documented


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    """A temporary folder holding a copy of the checkout's example files."""
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    shutil.copytree(ROOT / "benchmarks", tmp_path / "benchmarks")
    (tmp_path / "p.yaml").write_text(P_YAML, encoding="utf-8")
    (tmp_path / "small.yaml").write_text(SMALL_YAML, encoding="utf-8")
    shim = tmp_path / "bin" / "cvc5"
    shim.parent.mkdir()
    shim.write_text(CVC5_SHIM, encoding="utf-8")
    shim.chmod(0o755)
    return tmp_path


def _run(command: str, folder: Path, timeout: float) -> subprocess.CompletedProcess[str]:
    words = shlex.split(command)
    assert words[0] == "plansynth" and PLANSYNTH is not None
    env = {
        **os.environ,
        "PATH": os.pathsep.join([str(folder / "bin"), str(BIN), os.environ.get("PATH", "")]),
        "COLUMNS": "200",
        "NO_COLOR": "1",
        "TERM": "dumb",
        "MPLBACKEND": "Agg",
    }
    return subprocess.run(
        [PLANSYNTH, *words[1:]],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
        stdin=subprocess.DEVNULL,
    )


def _params() -> list[Any]:
    params = []
    for command, case in CASES.items():
        if case.runs_in:
            assert (ROOT / case.runs_in).is_file() and command in (ROOT / case.runs_in).read_text(), case.runs_in
            continue
        if case.fast is None:
            params.append(pytest.param(command, (*case.before, command), id=command))
        else:
            fast = (*case.before, case.fast) if isinstance(case.fast, str) else case.fast
            params.append(pytest.param(command, fast, id=f"fast: {fast[-1]}"))
            if case.slow:
                params.append(pytest.param(command, (*case.before, command), id=command, marks=pytest.mark.slow))
    return params


@pytest.mark.commands
@pytest.mark.parametrize(("documented", "commands"), _params())
def test_documented_command(documented: str, commands: tuple[str, ...], folder: Path) -> None:
    case = CASES[documented]
    *before, command = commands
    for step in before:
        pre = _run(step, folder, case.timeout)
        allowed = CASES[step].exit if step in CASES else (0,)  # a documented step exits as documented
        assert pre.returncode in allowed, f"{step}: exit {pre.returncode}\n{pre.stdout}\n{pre.stderr}"
    run = _run(command, folder, case.timeout)
    said = f"{command}: exit {run.returncode}\n--- stdout\n{run.stdout}\n--- stderr\n{run.stderr}"
    assert run.returncode in case.exit, said
    assert "Traceback" not in run.stdout + run.stderr, said
    output = run.stdout + run.stderr
    for text in case.out:
        assert text in output, f"{text!r} not printed by {said}"
    for name in case.files:
        path = folder / name
        if name.endswith("/"):
            assert path.is_dir() and any(path.iterdir()), f"{command} wrote nothing into {name}"
        else:
            assert path.is_file() and path.stat().st_size > 0, f"{command} did not write {name}"
    for name, key, value in case.json:
        doc = json.loads((folder / name).read_text(encoding="utf-8"))
        assert doc.get(key) == value, f"{name}: {key} is {doc.get(key)!r}, expected {value!r}"


def documented_python() -> list[tuple[str, int, str]]:
    """Every ``python`` code block of :data:`DOCS` but those marked :data:`NOT_A_TEST`:
    (document, line, code)."""
    return [
        (doc, line, code)
        for doc in DOCS
        for lang, line, code, untested in code_blocks(doc)
        if lang == "python" and not untested
    ]


def _expected_prints(code: str) -> list[str]:
    """The output a block promises: ``print(...)  # OUTPUT`` comments, in order."""
    return [
        line.split("#", 1)[1].strip()
        for line in code.splitlines()
        if line.lstrip().startswith("print(") and "#" in line
    ]


def test_the_documents_show_python() -> None:
    blocks = documented_python()
    shown = {doc for doc, _, _ in blocks}
    assert {"README.md", "docs/tutorial.md", "docs/how-to/add-a-backend-or-planner.md"} <= shown, shown
    assert len(blocks) >= 8


def test_few_blocks_are_only_illustrations() -> None:
    """Marking a block :data:`NOT_A_TEST` is the exception: a sketch, not a way out."""
    marked = [f"{doc}:{line}" for doc in DOCS for _, line, _, untested in code_blocks(doc) if untested]
    assert len(marked) <= MAX_UNTESTED_BLOCKS, f"too many blocks marked {NOT_A_TEST}: {marked}"


def test_every_code_block_names_its_language() -> None:
    """``sh``, ``python``, ``yaml``, ``json``, ``text``...: what a block is decides how it
    is tested (and highlighted)."""
    bare = [f"{doc}:{line}" for doc in DOCS for lang, line, _, _ in code_blocks(doc) if not lang]
    assert not bare, f"code blocks without a language: {bare}"


@pytest.mark.parametrize("doc,line,code", documented_python(), ids=lambda v: str(v) if isinstance(v, int) else None)
def test_every_documented_python_block_runs(doc: str, line: int, code: str, folder: Path) -> None:
    """A documented Python block runs as a user pastes it, in a folder with the examples,
    and prints what its ``# ...`` comments say it prints (a block whose prints carry no
    comment has to run without error)."""
    env = {**os.environ, "MPLBACKEND": "Agg"}
    run = subprocess.run(
        [sys.executable, "-c", code],
        cwd=folder,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
        stdin=subprocess.DEVNULL,
    )
    assert run.returncode == 0, f"{doc}:{line}\n{run.stdout}{run.stderr}"
    printed = run.stdout.splitlines()
    for expected in _expected_prints(code):
        assert expected in printed, f"{doc}:{line}: expected a line {expected!r}, got {printed}"
