"""The verifier's entry point: decide whether a controller wins at exactly l steps,
within an optional budget (see :mod:`plansynth.grid.verify`)."""

from __future__ import annotations

import time

from plansynth.budget import Budget, BudgetExhausted
from plansynth.grid.objective import ObjectiveKind
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import Term
from plansynth.grid.verify.closed_loop import verify_closed_loop
from plansynth.grid.verify.controller import check_controller
from plansynth.grid.verify.counterexample import counterexample
from plansynth.grid.verify.invariant import Invariant, check_invariant
from plansynth.grid.verify.meter import Meter
from plansynth.grid.verify.search import PROBE_NODES, Search
from plansynth.grid.verify.verdict import Verdict, VerifyStatus

__all__ = ["verify", "PYTHON_CELLS", "PYTHON_OBSTACLES"]

#: Grids of at most this many cells, with at most :data:`PYTHON_OBSTACLES` obstacles,
#: keep their move tables and reachable sets in plain Python (dicts, integer bitsets):
#: on them the search itself takes milliseconds and numpy's import (0.1-0.15 s) would
#: dominate a ``plansynth grid solve``. Larger ones use numpy arrays (see ``tables`` of
#: :func:`verify`); the two representations give the same verdicts and counterexamples.
PYTHON_CELLS = 4096
PYTHON_OBSTACLES = 8


def verify(
    problem: GridProblem,
    program: Term,
    steps: int | None,
    *,
    probe_nodes: int | None = None,
    budget: Budget | None = None,
    tables: str | None = None,
    invariant: Invariant | None = None,
) -> Verdict:
    """Decide exactly whether ``program`` wins ``problem`` at path length ``steps``.

    ``probe_nodes`` bounds the depth-first probe for a quick counterexample that runs
    before the exhaustive search (default :data:`~.search.PROBE_NODES`; 0 disables it).
    It changes only the time taken and which counterexample is found, never the answer.

    ``budget`` bounds the time (``seconds``) and the memory (``memory_mb``, default
    :data:`plansynth.budget.DEFAULT_MEMORY_MB`) the verification may use; once either is
    used up the verdict is ``unknown`` naming the phase (see :mod:`plansynth.grid.verify`).
    Without a budget the search runs to its exact answer.

    ``tables`` chooses how move tables and the unread obstacles' reachable sets are
    stored: ``"python"`` (dicts and integer bitsets, no numpy import) or ``"numpy"``
    (lazily filled arrays, for large grids); by default ``"python"`` on grids of at most
    :data:`PYTHON_CELLS` cells with at most :data:`PYTHON_OBSTACLES` obstacles. It changes
    only the time and memory taken, never the verdict or the counterexample.

    Raises :class:`~plansynth.grid.programs.ProgramSyntaxError` when the program is not
    a controller of the problem's grammar (for example a move number with no move).

    A problem outside the paper's model (another objective, obstacles with a block, a
    period or glitches, position collisions: :attr:`GridProblem.paper_model`) is decided
    by the closed-loop search of :mod:`.closed_loop` instead, for its objective;
    ``steps`` is then the path length of ``exact`` and ``reach`` and None for
    ``safety`` and ``recurrence``.

    ``invariant`` (safety only): a set of states the program is claimed to keep
    (:mod:`.invariant`); when it is inductive the program wins without a search of its
    closed loop (what makes a 64 x 64 moving-obstacle game checkable); when it is not,
    the closed-loop search decides within what is left of the budget.
    """
    check_controller(problem, program)
    if invariant is not None and problem.objective is ObjectiveKind.SAFETY:
        clock = None if budget is None else budget.clock()
        verdict = check_invariant(problem, program, invariant, budget=budget)
        if verdict.status is VerifyStatus.WINS or clock is not None and clock.exhausted():
            return verdict
        budget = None if clock is None else clock.left()
    if not problem.paper_model:
        return verify_closed_loop(problem, program, steps, budget=budget)
    if steps is None or steps < 1:
        raise ValueError(f"steps must be >= 1, got {steps}")
    if tables is None:
        small = problem.width * problem.height <= PYTHON_CELLS and len(problem.obstacles) <= PYTHON_OBSTACLES
        tables = "python" if small else "numpy"
    elif tables not in ("python", "numpy"):
        raise ValueError(f"tables must be 'python' or 'numpy', got {tables!r}")
    t0 = time.perf_counter()
    meter = Meter(budget)
    search = None
    try:
        search = Search(
            problem, program, steps, PROBE_NODES if probe_nodes is None else probe_nodes, meter, tables == "numpy"
        )
        loss = search.run()
        meter.phase = "building the counterexample"
        cex = None if loss is None else counterexample(search, loss)
    except (BudgetExhausted, MemoryError) as out:
        explored = 0 if search is None else search.explored
        return meter.ran_out(out, steps, explored, t0)
    status = VerifyStatus.WINS if loss is None else VerifyStatus.LOSES
    return Verdict(status, steps, cex, search.explored, time.perf_counter() - t0)
