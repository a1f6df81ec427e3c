"""The controller under verification: is it one of the problem's grammar, and which
obstacles does it read (Chasins & Newcomb, SYNT 2016, Section 3.1: a program over the
robot's and the obstacles' coordinates choosing a robot move)."""

from __future__ import annotations

from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Term, check_program, variables_of

__all__ = ["read_obstacles", "check_controller"]


def read_obstacles(program: Term, n_obstacles: int) -> tuple[int, ...]:
    """Indices of the obstacles whose coordinates ``program`` reads, in order.

    >>> from plansynth.grid.programs import parse_program
    >>> read_obstacles(parse_program("(ite (<= o2y rx) 0 1)"), 3)
    (2,)
    """
    names = variables_of(program)
    return tuple(i for i in range(n_obstacles) if f"o{i}x" in names or f"o{i}y" in names)


def check_controller(problem: GridProblem, program: Term) -> None:
    """Raise :class:`~plansynth.grid.programs.ProgramSyntaxError` unless ``program`` is a
    controller of ``problem``'s grammar: a Start term over its inputs whose move numbers
    name robot moves."""
    check_program(program, problem.variables, len(problem.robot.moves), problem.max_constant)
