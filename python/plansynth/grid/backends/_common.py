"""Pieces the SyGuS backends (``cvc5``, ``external``) share: naming and keeping the .sl
file of each attempt, and turning a solver's printed answer into a :class:`LengthOutcome`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import ProgramSyntaxError, check_program, parse_program
from plansynth.grid.result import GridStatus, LengthOutcome
from plansynth.grid.sygus import read_synth_answer
from plansynth.io import check_output_folder, write_output


def sl_file_name(problem: GridProblem, steps: int, depth_bound: int | None) -> str:
    """File name for the .sl of one attempt: ``<problem>-l<steps>[-d<D>].sl``."""
    bound = "" if depth_bound is None else f"-d{depth_bound}"
    # ASCII and at most 100 characters: a file name has at most 255 bytes.
    safe = (
        "".join(ch if (ch.isascii() and ch.isalnum()) or ch in "-_." else "_" for ch in problem.name[:100]) or "problem"
    )
    return f"{safe}-l{steps}{bound}.sl"


def keep_file(
    directory: str | Path | None, problem: GridProblem, steps: int, depth_bound: int | None, text: str
) -> str | None:
    """Write ``text`` into ``directory`` (created if needed) and return the path, or None."""
    if directory is None:
        return None
    d = check_output_folder(directory)
    path = d / sl_file_name(problem, steps, depth_bound)
    write_output(path, text)  # atomic; OutputUnwritable
    return str(path)


def outcome_from_answer(
    problem: GridProblem,
    steps: int,
    output: str,
    solver: str,
    seconds: float,
    counters: dict[str, Any],
    artefact: str | None,
) -> LengthOutcome:
    """Turn a solver's printed answer into a :class:`LengthOutcome` (shared with ``external``).

    A ``define-fun`` that is not a program of the problem's grammar is reported as
    unknown with the reason: a solver bug is never passed on as a controller.
    """
    answer = read_synth_answer(output)
    if answer.kind == "infeasible":
        return LengthOutcome(
            GridStatus.UNREALIZABLE,
            steps,
            seconds=seconds,
            counters=counters,
            message=f"{solver}: infeasible",
            artefact=artefact,
        )
    if answer.kind == "solution":
        assert answer.definition is not None
        try:
            program = parse_program(answer.definition)
            check_program(program, problem.variables, len(problem.robot.moves), problem.max_constant)
        except ProgramSyntaxError as exc:
            return LengthOutcome(
                GridStatus.UNKNOWN,
                steps,
                seconds=seconds,
                counters=counters,
                message=f"{solver} answered a term outside the grammar ({exc}): {answer.definition}",
                artefact=artefact,
            )
        return LengthOutcome(
            GridStatus.REALIZABLE, steps, program=program, seconds=seconds, counters=counters, artefact=artefact
        )
    tail = " ".join(output.strip().split())[-300:] or "no answer"
    return LengthOutcome(
        GridStatus.UNKNOWN,
        steps,
        seconds=seconds,
        counters=counters,
        message=f"{solver} gave no answer: {tail}",
        artefact=artefact,
    )
