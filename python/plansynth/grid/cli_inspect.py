"""``plansynth grid verify``, ``animate`` and ``export``: thin shells over
:func:`plansynth.grid.verify.verify`, :func:`plansynth.grid.simulate.simulate` with
:mod:`plansynth.grid.render`, and the exports of :mod:`plansynth.grid.programs`
(STYLE.md, point 12). Registered on the ``plansynth grid`` app by :mod:`plansynth.grid.cli`.

A controller may be given as a result JSON (spec: Result file), as a file holding a
term or a ``define-fun`` (``.sl``, ``.txt``, ...), or as a literal term.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import typer
from rich.console import Console
from rich.markup import escape
from rich.table import Table

from plansynth.cli_support import EXIT_NO, EXIT_UNKNOWN, EXIT_YES, fail, finite_positive, positive_seconds
from plansynth.errors import PlansynthError
from plansynth.grid.problem import MAX_STEPS, GridProblem, load_grid_problem
from plansynth.grid.programs import (
    ProgramSyntaxError,
    Term,
    depth,
    function_name_problem,
    parse_program,
    to_c,
    to_define_fun,
    to_python,
)
from plansynth.grid.result import load_result
from plansynth.io import check_output_path, read_text, write_output

#: Exit statuses of ``verify`` (``animate`` and ``export`` use 0 and 2).
EXIT_WINS, EXIT_LOSES = EXIT_YES, EXIT_NO

VERIFY_EPILOG = """\
Examples:

  plansynth grid verify examples/grid/figure1.yaml "(ite (<= rx 3) 2 1)" --steps 6

  plansynth grid verify examples/grid/figure1.yaml result.json

  plansynth grid verify examples/grid/figure1.yaml controller.sl --steps 6

  plansynth grid verify examples/grid/figure1.yaml "(ite (<= rx 3) 2 1)" --steps 6 --timeout 30 --memory-mb 1024

A result.json comes from `plansynth grid solve -o`; a .sl or .txt file holds a term or a define-fun.
The verifier is exact; --timeout and --memory-mb (default 4096 MB) bound it, and a budget
that runs out gives `unknown` with the phase it was in, never a guessed answer.

Exit status: 0 the controller wins, 1 it loses (a counterexample is printed), 2 bad input,
3 unknown (the budget ran out).
"""

ANIMATE_EPILOG = """\
Examples:

  plansynth grid animate examples/grid/figure1.yaml result.json -o run.gif

  plansynth grid animate examples/grid/figure1.yaml "(ite (<= rx 1) 2 1)" --steps 6 -o lose.gif

  plansynth grid animate examples/grid/traffic.yaml result.json -o t.gif --obstacles random --seed 3

  plansynth grid animate examples/grid/figure1.yaml result.json -o run.gif --png step2.png --step 2

Adversarial obstacles replay the verifier's counterexample when the controller loses,
and otherwise stay as close to the robot as they can. Exit status: 0 written, 2 bad input.
"""

EXPORT_EPILOG = """\
Examples:

  plansynth grid export result.json --lang python --problem examples/grid/figure1.yaml

  plansynth grid export result.json --lang c -o controller.c --problem examples/grid/figure1.yaml

  plansynth grid export "(ite (<= rx 3) 2 1)" --lang sygus --problem examples/grid/figure1.yaml

Without --problem the result's own "problem" field is used (the path given to solve).
Exit status: 0 written, 2 bad input.
"""


@dataclass(frozen=True)
class Controller:
    """A controller read from the command line, with the path length its result gave."""

    program: Term
    steps: int | None
    origin: str
    problem_path: str | None = None


def read_controller(spec: str) -> Controller:
    """Read RESULT_OR_PROGRAM: a result JSON, a file holding a term, or a literal term.

    A name that is a regular file is read as one; anything else (including text too
    long to be a path, or holding a NUL byte) is parsed as a term.
    """
    path = Path(spec)
    if _is_file(path):
        if path.suffix.lower() == ".json":
            stored = load_result(path)
            if stored.program is None:
                raise _BadInput(f"{spec}: the result has no program (status {stored.status.value})")
            where = stored.raw.get("problem") or None
            if where is not None:
                where = str(where)
                if not _is_file(Path(where)) and _is_file(path.parent / where):
                    where = str(path.parent / where)
            return Controller(stored.program, stored.steps, spec, where)
        text, _ = read_text(path)
        try:
            return Controller(parse_program(text), None, spec)
        except ProgramSyntaxError as exc:
            raise _BadInput(f"{spec}: not a controller program: {exc}") from exc
    try:
        return Controller(parse_program(spec), None, "the command line")
    except ProgramSyntaxError as exc:
        hint = "" if "(" in spec or " " not in spec else " (and no such file)"
        shown = spec if len(spec) <= 80 else spec[:77] + "..."
        raise _BadInput(f"{shown!r} is neither a file nor a controller term{hint}: {exc}") from exc


def _is_file(path: Path) -> bool:
    """``path.is_file()``, False instead of an error for names no file can have."""
    try:
        return path.is_file()
    except (OSError, ValueError):
        return False


class _BadInput(Exception):
    """Bad command-line input: reported and exit status 2."""


def _steps(controller: Controller, problem: GridProblem, steps: int | None) -> int | None:
    if not problem.objective.bounded:
        if steps is not None:
            raise _BadInput(f"--steps: objective {problem.objective.value} has no path length")
        return None
    if steps is not None:
        return steps
    if controller.steps is not None:
        return controller.steps
    if problem.steps is not None:
        return problem.steps
    raise _BadInput("no path length: give --steps N (the problem file has no `steps` and no result gave one)")


_fail = fail  # cli_support.fail: one line, exit 2


def _cell(c: tuple[int, int]) -> str:
    return f"({c[0]}, {c[1]})"


def verify_command(
    file: Path = typer.Argument(..., help="Grid problem file (YAML or JSON, spec: grid-problem.md)."),
    result_or_program: str = typer.Argument(
        ..., metavar="RESULT_OR_PROGRAM", help="A result JSON, a file with a term or define-fun, or a literal term."
    ),
    steps: int | None = typer.Option(
        None, "--steps", min=1, max=MAX_STEPS, help="Path length l (default: the result's, else the problem's)."
    ),
    timeout: float | None = typer.Option(
        None, "--timeout", callback=positive_seconds, help="Wall-clock budget in seconds (past it: unknown, exit 3)."
    ),
    memory_mb: int | None = typer.Option(
        None,
        "--memory-mb",
        min=1,
        max=1_000_000,
        help="Memory the verifier may add, in MB (default 4096; past it: unknown, exit 3).",
    ),
) -> None:
    """Check exactly whether a controller wins against every obstacle behaviour."""
    from plansynth.budget import Budget
    from plansynth.grid.verify import VerifyStatus, verify

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    try:
        problem = load_grid_problem(file)
        controller = read_controller(result_or_program)
        l = _steps(controller, problem, steps)
        verdict = verify(problem, controller.program, l, budget=Budget(seconds=timeout, memory_mb=memory_mb))
    except (PlansynthError, _BadInput) as exc:
        raise _fail(err, str(exc)) from None
    stats = f"{verdict.states_explored} states explored in {verdict.seconds:.3f} s"
    program = escape(str(controller.program))
    at = f"l = {l}" if l is not None else f"the {problem.objective.value} objective"
    if verdict.status is VerifyStatus.UNKNOWN:
        console.print(f"[bold yellow]unknown[/bold yellow] at {at}: {program}  ({stats})", highlight=False)
        console.print(escape(verdict.message or "no answer"), highlight=False)
        raise typer.Exit(EXIT_UNKNOWN)
    if verdict.wins:
        console.print(f"[bold green]WINS[/bold green] at {at}: {program}  ({stats})", highlight=False)
        raise typer.Exit(EXIT_WINS)
    cex = verdict.counterexample
    assert cex is not None
    console.print(f"[bold red]LOSES[/bold red] at {at}: {program}  ({stats})", highlight=False)
    console.print(f"counterexample: {escape(cex.reason)}", highlight=False)
    if cex.loop is not None:
        console.print(
            f"the run ends in the state of step {cex.loop}: the steps from there repeat forever", highlight=False
        )
    table = Table(show_edge=False, header_style="bold")
    table.add_column("step", justify="right")
    table.add_column("robot")
    table.add_column("robot move")
    for i in range(len(problem.obstacles)):
        table.add_column(f"o{i}")
    for t, state in enumerate(cex.states):
        if t < len(cex.robot_moves):
            k = cex.robot_moves[t]
            moves = [problem.obstacles[i].moves[j].name for i, j in enumerate(cex.obstacle_moves[t])]
            row = [str(t), _cell(state.robot), f"{k} {problem.robot.moves[k].name}"]
            row += [f"{_cell(o)} {m}" for o, m in zip(state.obstacles, moves)]
        else:
            row = ["end", _cell(state.robot), ""] + [_cell(o) for o in state.obstacles]
        table.add_row(*row)
    console.print(table)
    raise typer.Exit(EXIT_LOSES)


def animate_command(
    file: Path = typer.Argument(..., help="Grid problem file (YAML or JSON)."),
    result_or_program: str = typer.Argument(
        ..., metavar="RESULT", help="A result JSON, a file with a term or define-fun, or a literal term."
    ),
    out: Path = typer.Option(..., "--out", "-o", help="The GIF to write."),
    obstacles: str = typer.Option(
        "adversarial", "--obstacles", help="adversarial (counterexample, else greedy pursuit) or random."
    ),
    seed: int = typer.Option(0, "--seed", help="Seed of the random obstacles."),
    steps: int | None = typer.Option(
        None, "--steps", min=1, max=MAX_STEPS, help="Path length l (default: the result's, else the problem's)."
    ),
    fps: float = typer.Option(
        3.0, "--fps", min=0.1, max=1000.0, callback=finite_positive, help="Frames per second of the GIF."
    ),
    png: Path | None = typer.Option(None, "--png", help="Also write one step as a PNG."),
    step: int | None = typer.Option(None, "--step", min=0, help="The step for --png (default: the last state)."),
) -> None:
    """Animate one run of a controller as a GIF (and optionally one step as a PNG)."""
    from plansynth.grid.render import animate, draw_state
    from plansynth.grid.simulate import MODES, simulate

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    try:
        if obstacles not in MODES:
            raise _BadInput(f"--obstacles must be one of {', '.join(MODES)}, got {obstacles!r}")
        if step is not None and png is None:
            raise _BadInput("--step needs --png")
        problem = load_grid_problem(file)
        controller = read_controller(result_or_program)
        l = _steps(controller, problem, steps)
        if l is None:
            raise _BadInput(f"animate shows runs of a path length; objective {problem.objective.value} has none")
        run = simulate(problem, controller.program, l, obstacles=obstacles, seed=seed)
        last = len(run.states) - 1
        if step is not None and step > last:
            raise _BadInput(f"--step {step}: the run has states 0..{last}")
        for path in (out, png):
            if path is not None:
                check_output_path(path)
        animate(problem, run, out, fps=fps)
    except (PlansynthError, _BadInput) as exc:
        raise _fail(err, str(exc)) from None
    verdict = "[green]wins[/green]" if run.wins else "[red]loses[/red]"
    console.print(
        f"controller {verdict} at l = {l}; this run ({obstacles} obstacles): {escape(run.outcome)}", highlight=False
    )
    console.print(f"wrote {escape(str(out))} ({last + 1} states)", highlight=False)
    if png is not None:
        t = last if step is None else step
        try:
            draw_state(problem, run, t, png)
        except PlansynthError as exc:
            raise _fail(err, str(exc)) from None
        console.print(f"wrote {escape(str(png))} (state {t})", highlight=False)


def export_command(
    result_or_program: str = typer.Argument(
        ..., metavar="RESULT", help="A result JSON, a file with a term or define-fun, or a literal term."
    ),
    lang: str = typer.Option(..., "--lang", help="python, c or sygus."),
    out: Path | None = typer.Option(None, "--out", "-o", help="Write here (default: standard output)."),
    problem_file: Path | None = typer.Option(
        None, "--problem", help="The problem (its obstacle count fixes the inputs); default: the result's."
    ),
    name: str = typer.Option("move", "--name", help="Function name."),
) -> None:
    """Export a controller as Python, C or a SyGuS-IF define-fun."""
    err = Console(stderr=True, soft_wrap=True)
    try:
        if lang not in ("python", "c", "sygus"):
            raise _BadInput(f"--lang must be python, c or sygus, got {lang!r}")
        bad_name = function_name_problem(name, lang)
        if bad_name is not None:
            raise _BadInput(f"--name: {bad_name}")
        if out is not None:
            check_output_path(out)
        controller = read_controller(result_or_program)
        where = str(problem_file) if problem_file is not None else controller.problem_path
        if where is None:
            raise _BadInput("give --problem FILE: the inputs rx ry o0x o0y ... depend on its obstacles")
        if problem_file is None and not _is_file(Path(where)):
            raise _BadInput(
                f"the result names the problem {where!r}, which is not a file from here: give --problem FILE"
            )
        problem = load_grid_problem(where)
        from plansynth.grid.verify import check_controller

        check_controller(problem, controller.program)
        bad_name = function_name_problem(name, lang, problem.variables)
        if bad_name is not None:
            raise _BadInput(f"--name: {bad_name}")
        variables = problem.variables
        if lang == "python":
            text = to_python(controller.program, variables, name)
        elif lang == "c":
            text = to_c(controller.program, variables, name)
        else:
            text = (
                f"; controller for {problem.name} (depth {depth(controller.program)}), SyGuS-IF v2\n"
                + to_define_fun(controller.program, variables, name)
                + "\n"
            )
        if out is not None:
            write_output(out, text)
    except (PlansynthError, _BadInput) as exc:
        raise _fail(err, str(exc)) from None
    if out is None:
        typer.echo(text, nl=False)
    else:
        Console(soft_wrap=True).print(f"wrote {escape(str(out))}", highlight=False)


def register(app: typer.Typer) -> None:
    """Add this module's commands to ``app``."""
    app.command("verify", epilog=VERIFY_EPILOG)(verify_command)
    app.command("animate", epilog=ANIMATE_EPILOG)(animate_command)
    app.command("export", epilog=EXPORT_EPILOG)(export_command)
