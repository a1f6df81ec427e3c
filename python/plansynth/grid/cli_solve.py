"""``plansynth grid solve`` and ``plansynth grid compile``: thin shells over
:func:`plansynth.grid.solve.solve` and :func:`plansynth.grid.sygus.compile_sygus`
(STYLE.md, point 12). Registered on the ``plansynth grid`` app by :mod:`plansynth.grid.cli`.

``solve`` is the command run most (by users and by ``plansynth bench grid``, which times
it through the CLI), so its module imports only what every solve needs: the answer is
printed with click's styles (no rich console), rich's spinner is loaded only when
standard error is a terminal, and the backend's modules load with the backend.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import typer

from plansynth.budget import Budget
from plansynth.cli_support import EXIT_BAD_INPUT, EXIT_NO, EXIT_UNKNOWN, EXIT_YES, positive_seconds, seconds_since_start
from plansynth.errors import OutputUnwritable, PlansynthError
from plansynth.grid.problem import MAX_STEPS, GridProblem, load_grid_problem
from plansynth.grid.programs import MAX_PROGRAM_NESTING, size, to_python
from plansynth.grid.result import GridResult, GridStatus, LengthOutcome
from plansynth.io import check_output_folder, check_output_path, write_output


def _native_help() -> str:
    from plansynth.grid.native.options import help_text

    return help_text()


_NATIVE_HELP = _native_help()

#: Seconds of ``--timeout`` kept back for printing the answer and the interpreter's
#: exit (0.4 s measured on a loaded 2-core machine).
EXIT_RESERVE = 0.5

#: Exit statuses of ``solve``.
EXIT_REALIZABLE, EXIT_UNREALIZABLE = EXIT_YES, EXIT_NO

_STATUS_COLOUR = {
    GridStatus.REALIZABLE: "green",
    GridStatus.UNREALIZABLE: "red",
    GridStatus.UNKNOWN: "yellow",
}


def _status(status: GridStatus, width: int = 0) -> str:
    """The status word in bold colour (click drops the styles when not on a terminal)."""
    return typer.style(f"{status.value:<{width}}", fg=_STATUS_COLOUR[status], bold=True)


def _error(exc: Exception) -> None:
    typer.echo(f"{typer.style('error:', fg='red', bold=True)} {exc}", err=True)


SOLVE_EPILOG = """\
Examples:

  plansynth grid solve examples/grid/figure1.yaml                      # native engine (default)

  plansynth grid solve examples/grid/depth-5.yaml --minimize           # smallest depth, proved minimal

  plansynth grid solve examples/grid/corridor.yaml --effort 0 --timeout 30   # the first verified program

  plansynth grid solve examples/grid/figure1.yaml --solver cvc5 --out result.json

  plansynth grid solve examples/grid/figure1.yaml --solver cvc5 --steps 6 -O sygus-enum=fast --keep-sl sl/

  plansynth grid solve p.yaml --solver external --command "cvc5 --lang=sygus2 {file}" --timeout 600

  plansynth grid solve p.yaml --solver cvc5 --depth-bound 4 --max-steps 8

Exit status: 0 realizable (verified controller), 1 unrealizable, 2 bad input or solver unavailable, 3 unknown (budget ran out or a solver gave no answer).
"""

COMPILE_EPILOG = """\
Examples:

  plansynth grid compile examples/grid/figure1.yaml --steps 6 -o figure1-l6.sl

  plansynth grid compile examples/grid/figure1.yaml --steps 6 --depth-bound 4

  python -m plansynth.grid.backends.cvc5_cli figure1-l6.sl    # solve it by hand
"""


def _load(file: Path, steps: int | None, max_steps: int | None) -> GridProblem:
    problem = load_grid_problem(file)
    if max_steps is not None:
        problem = replace(problem, steps=None, max_steps=max_steps)
    if steps is not None:
        problem = replace(problem, steps=steps)
    return problem


def _solver_options(
    solver: str,
    command: str | None,
    option: list[str],
    keep_sl: Path | None,
    minimize: bool = False,
    effort: float | None = None,
) -> dict[str, Any]:
    """The backend's options, built once; an option that does not apply to ``solver``
    is an error (exit 2), never dropped."""
    sygus = solver in ("cvc5", "external")
    if minimize and solver != "native":
        raise typer.BadParameter(
            "--minimize needs --solver native (the only backend that proves minimal depth)", param_hint="--minimize"
        )
    if effort is not None and solver != "native":
        raise typer.BadParameter("--effort needs --solver native", param_hint="--effort")
    if command is not None and solver != "external":
        raise typer.BadParameter("--command is for --solver external", param_hint="--command")
    if keep_sl is not None and not sygus:
        raise typer.BadParameter("--keep-sl is for the SyGuS solvers (cvc5, external)", param_hint="--keep-sl")
    if option and solver == "external":
        raise typer.BadParameter("put the external solver's options in --command", param_hint="--option")
    kwargs: dict[str, Any] = {}
    if solver == "native":
        from plansynth.grid.native.options import NativeOptions

        given: dict[str, Any] = {"minimize": True} if minimize else {}
        if effort is not None:
            given["effort"] = effort
        kwargs["options"] = NativeOptions.parse(option, **given)  # InvalidOption: exit 2
        return kwargs
    if solver == "external":
        kwargs["command"] = command
    if option:
        kwargs["options"] = list(option)
    if keep_sl is not None:
        kwargs["keep_sl"] = str(keep_sl)
    return kwargs


def _print_result(problem: GridProblem, r: GridResult) -> None:
    echo = typer.echo
    if r.status is not GridStatus.REALIZABLE:
        where = ""
    elif r.steps is None:
        where = f" ({problem.objective.value} objective)"
    else:
        where = f" at l = {r.steps}" + (" (within)" if problem.objective.value == "reach" else "")
    echo(f"{_status(r.status)}{where} ({r.solver} {r.solver_version}, {r.seconds:.2f} s)")
    if r.status is GridStatus.REALIZABLE and r.program is not None:
        echo(f"controller (depth {r.depth}, size {size(r.program)}):")
        echo(f"  {r.program}")
        echo(to_python(r.program, problem.variables).rstrip())
        if r.verified:
            echo(typer.style(r.message, fg="green"))
        if r.depth_minimal is not None:
            echo(f"depth_minimal: {r.depth_minimal}")
    elif r.message:
        echo(r.message)
    if r.status is GridStatus.UNREALIZABLE and r.certified_by:
        echo(f"certified by the {r.certified_by} engine (it decides realizability exactly)")
        why = [a.message for a in r.attempts if a.message and not problem.paper_model]
        if why and len(r.attempts) == 1:
            echo(why[0])


class _Lines:
    """One line per path length tried, on standard error; on a terminal, above rich's
    transient spinner (rich is imported only then)."""

    def __init__(self, solver: str, lengths: list[int]) -> None:
        self.solver, self.lengths = solver, lengths
        self.bar = None
        if sys.stderr.isatty():
            from rich.console import Console
            from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

            self.bar = Progress(
                SpinnerColumn(),
                TextColumn("[progress.description]{task.description}"),
                TimeElapsedColumn(),
                console=Console(stderr=True, soft_wrap=True),
                transient=True,
            )

    def __enter__(self) -> _Lines:
        if self.bar is not None:
            self.bar.__enter__()
            self.task = self.bar.add_task(self._description(0), total=len(self.lengths))
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.bar is not None:
            self.bar.__exit__(*exc)

    def _description(self, i: int) -> str:
        from rich.markup import escape

        if self.lengths == [None]:
            nxt = "the objective" if i == 0 else "done"
        else:
            nxt = f"l = {self.lengths[i]} ({i + 1}/{len(self.lengths)})" if i < len(self.lengths) else "done"
        return escape(f"{self.solver}: {nxt}")

    def __call__(self, l: int | None, o: LengthOutcome) -> None:
        note = f"  {o.message}" if o.message and o.status is not GridStatus.UNREALIZABLE else ""
        cpu = o.counters.get("solver_cpu_seconds")
        cpu_note = f" (solver cpu {cpu:.2f} s)" if isinstance(cpu, (int, float)) else ""
        head = "objective" if l is None else f"l = {l:>3}"
        line = f"{head}  {_status(o.status, 12)} {o.seconds:8.2f} s{cpu_note}{note}"
        if self.bar is None:
            typer.echo(line, err=True)
            return
        from rich.text import Text

        self.bar.console.print(Text.from_ansi(line))
        self.bar.update(self.task, advance=1, description=self._description(self.lengths.index(l) + 1))


def solve_command(
    file: Path = typer.Argument(..., help="Grid problem file (YAML or JSON, spec: grid-problem.md)."),
    solver: str = typer.Option("native", "--solver", "-s", help="Backend: native, cvc5 or external."),
    command: str | None = typer.Option(
        None,
        "--command",
        help='External SyGuS-IF v2 solver command; {file} is the .sl path, e.g. "cvc5 --lang=sygus2 {file}".',
    ),
    option: list[str] = typer.Option(
        [],
        "--option",
        "-O",
        help="Solver option KEY=VALUE, repeatable (cvc5: its option names, e.g. sygus-enum=fast; native: "
        + _NATIVE_HELP
        + ").",
    ),
    steps: int | None = typer.Option(
        None, "--steps", min=1, max=MAX_STEPS, help="Solve for exactly this path length (overrides the file)."
    ),
    max_steps: int | None = typer.Option(
        None, "--max-steps", min=1, max=MAX_STEPS, help="Search l = 1..N (overrides the file's steps/max_steps)."
    ),
    depth_bound: int | None = typer.Option(
        None,
        "--depth-bound",
        min=1,
        max=MAX_PROGRAM_NESTING,
        help="Only programs of depth <= D (the paper's depth); unrealizable is then relative to D.",
    ),
    timeout: float | None = typer.Option(
        None, "--timeout", callback=positive_seconds, help="Wall-clock budget in seconds for the whole search."
    ),
    memory_mb: int | None = typer.Option(
        None,
        "--memory-mb",
        min=1,
        max=1_000_000,
        help="Memory limit of a solver process, in MB (native: of the joint game, default 4096).",
    ),
    out: Path | None = typer.Option(None, "--out", "-o", help="Write the result JSON (spec: Result file) here."),
    keep_sl: Path | None = typer.Option(
        None, "--keep-sl", help="Keep the .sl file of every attempt in this directory."
    ),
    minimize: bool = typer.Option(
        False, "--minimize", help="Native only: return a program of smallest depth, proved minimal."
    ),
    effort: float | None = typer.Option(
        None,
        "--effort",
        min=0.0,
        help="Native only: seconds spent making the first verified program smaller (default 0.05 s or 10% of --timeout, whichever is smaller; 0: the first program).",
    ),
) -> None:
    """Synthesize a controller: try path lengths l in order, report the first verified one."""
    from plansynth.grid.solve import solve

    try:
        if timeout is not None and timeout <= 0:
            raise typer.BadParameter("must be positive", param_hint="--timeout")
        problem = _load(file, steps, max_steps)
        kwargs = _solver_options(solver, command, option, keep_sl, minimize, effort)
        if out is not None:
            check_output_path(out)  # before solving: a result is never computed and then lost
        if keep_sl is not None:
            check_output_folder(keep_sl)
        # the budget counts from the process's start: the answer comes within --timeout
        # of running the command, start-up and loading included
        left = None if timeout is None else max(timeout - seconds_since_start() - EXIT_RESERVE, 0.01)
        budget = Budget(seconds=left, memory_mb=memory_mb)
        with _Lines(solver, list(problem.path_lengths()) or [None]) as progress:
            result = solve(problem, solver, budget, depth_bound=depth_bound, progress=progress, **kwargs)
    except typer.BadParameter:
        raise
    except PlansynthError as exc:
        _error(exc)
        raise typer.Exit(EXIT_BAD_INPUT) from None
    _print_result(problem, result)
    if out is not None:
        try:
            result.write(out)
        except OutputUnwritable as exc:
            _error(exc)
            raise typer.Exit(EXIT_BAD_INPUT) from None
        typer.echo(f"result written to {out}")
    code = {GridStatus.REALIZABLE: EXIT_REALIZABLE, GridStatus.UNREALIZABLE: EXIT_UNREALIZABLE}
    raise typer.Exit(code.get(result.status, EXIT_UNKNOWN))


def compile_command(
    file: Path = typer.Argument(..., help="Grid problem file (YAML or JSON)."),
    steps: int | None = typer.Option(
        None, "--steps", min=1, max=MAX_STEPS, help="Path length l (default: the file's steps)."
    ),
    depth_bound: int | None = typer.Option(
        None, "--depth-bound", min=1, max=MAX_PROGRAM_NESTING, help="Unroll the grammar to programs of depth <= D."
    ),
    output: Path | None = typer.Option(None, "--output", "-o", help="Write the .sl here (default: stdout)."),
) -> None:
    """Write the SyGuS-IF v2 specification of a problem at one path length (paper §3.2)."""
    from plansynth.grid.sygus import compile_sygus

    try:
        problem = load_grid_problem(file)
        l = steps if steps is not None else problem.steps
        if l is None:
            raise typer.BadParameter("the file fixes no path length; give --steps N", param_hint="--steps")
        if output is not None:
            check_output_path(output)
        text = compile_sygus(problem, l, depth_bound)
        if output is not None:
            write_output(output, text)
    except PlansynthError as exc:
        _error(exc)
        raise typer.Exit(EXIT_BAD_INPUT) from None
    if output is None:
        typer.echo(text, nl=False)
    else:
        typer.echo(f"wrote {output} ({len(text)} characters)", err=True)


def register(app: typer.Typer) -> None:
    """Add ``solve`` and ``compile`` to the ``plansynth grid`` app."""
    app.command("solve", epilog=SOLVE_EPILOG)(solve_command)
    app.command("compile", epilog=COMPILE_EPILOG)(compile_command)
