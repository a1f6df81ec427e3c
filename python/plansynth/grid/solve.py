"""Search the path length and report only verified controllers.

A grid problem fixes the path length l exactly (``steps``) or bounds it (``max_steps``);
a controller must bring the robot to the goal at exactly l steps (Chasins & Newcomb,
SYNT 2016, Section 3.1). Success is not monotone in l (an obstacle may block the goal at
one time and not at the next), so :func:`solve` tries every l of
``problem.path_lengths()`` in order until one is realizable, and calls the whole search
unrealizable only when every l was proved unrealizable.

Every program a backend returns is checked by the independent verifier
(:func:`plansynth.grid.verify.verify`) before it is reported. A program that fails the
check is a backend bug: that l becomes ``unknown`` with a loud message and the
counterexample, and the program is never reported as a controller. The verifier runs
within the search's budget (the time left, and its memory); when that runs out first,
the l is ``unknown`` ("not verified"), never realizable.

Every ``unrealizable`` is certified the same way: a SyGuS solver's "infeasible" (or
whatever an external command prints) is not taken on trust; the native engine, which
decides realizability exactly (:mod:`plansynth.grid.native.engine`; with a depth bound D
it decides "no program of depth <= D wins" when its condition enumeration is complete),
re-decides that length within the budget that is left. If it agrees, the length counts
as unrealizable (``counters["certified_by"] = "native"``); if it finds a controller
(checked by the verifier) the claim was a backend error and the length is ``unknown``
with the reason; if it cannot decide in time, the length is ``unknown``
("not certified"). The native engine's own answers are exact and need no second run.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [3, 1], "max_steps": 3,
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]}})
>>> r = solve(p, "cvc5", Budget(seconds=60))
>>> r.status.value, r.steps, r.verified, [a.status.value for a in r.attempts]
('realizable', 2, True, ['unrealizable', 'realizable'])
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

from plansynth.budget import Budget
from plansynth.grid.problem import GridProblem
from plansynth.grid.programs import depth, size
from plansynth.grid.result import GridResult, GridStatus, LengthOutcome, get_backend
from plansynth.jsonable import jsonable as _jsonable

__all__ = ["solve", "Progress", "CERTIFIER"]

#: The backend that certifies every ``unrealizable`` (it decides realizability exactly).
CERTIFIER = "native"

#: Called after each path length with (l, what the backend said, after verification).
Progress = Callable[[int, LengthOutcome], None]


#: Longest program text a message quotes; a longer one is named by its depth and size
#: (a message is read, and the bench keeps its first 2,000 characters).
QUOTED_PROGRAM = 240


def _shown(program: Any) -> str:
    """``program`` as a message quotes it: its text when short, else its measures."""
    text = str(program)
    if len(text) <= QUOTED_PROGRAM:
        return text
    return f"a program of depth {depth(program)} and {size(program)} nodes"


def solve(
    problem: GridProblem,
    solver: str = "native",
    budget: Budget = Budget(),
    *,
    depth_bound: int | None = None,
    progress: Progress | None = None,
    **solver_options: Any,
) -> GridResult:
    """Find the smallest path length with a winning controller, and a verified controller.

    ``solver`` names a registered backend (``native``, ``cvc5``, ``external``);
    ``solver_options`` go to its constructor (for example ``options=[...]`` and
    ``keep_sl=DIR`` for cvc5, ``command=...`` for external). The ``budget`` is shared by
    the whole search: each backend call gets the time that is left, and
    ``budget.iterations`` caps the number of path lengths tried. With ``depth_bound``
    the backends search programs of depth <= D only, and ``unrealizable`` is relative
    to that bound.

    The result is ``realizable`` with a verified program for the first l that has one;
    ``unrealizable`` if every l tried was proved unrealizable (and the budget allowed
    every l); ``unknown`` otherwise.
    """
    from plansynth.grid.verify import VerifyStatus, verify

    clock = budget.clock()  # the budget covers starting the backend too
    backend = get_backend(solver, **solver_options)
    # safety and recurrence have no path length: one attempt, with steps None
    lengths: list[int | None] = list(problem.path_lengths()) or [None]
    attempts: list[LengthOutcome] = []
    notes: list[str] = []

    def result(status: GridStatus, **kw: Any) -> GridResult:
        return GridResult(
            status=status,
            steps=kw.pop("steps", problem.steps),
            program=kw.pop("program", None),
            solver=backend.name,
            seconds=clock.elapsed(),
            verified=kw.pop("verified", None),
            depth_bound=depth_bound,
            attempts=tuple(attempts),
            solver_version=backend.version(),
            options=_jsonable(solver_options),
            problem=problem.source or problem.name,
            objective=problem.objective.value,
            **kw,
        )

    for l in lengths:
        if clock.exhausted():
            notes.append(f"the budget ran out before l = {l}")
            break
        outcome = backend.solve_length(problem, l, clock.left(), depth_bound=depth_bound)
        clock.tick()
        if outcome.status is GridStatus.UNREALIZABLE:
            outcome = _certified(problem, backend.name, outcome, clock, budget, depth_bound)
        if outcome.status is GridStatus.REALIZABLE:
            assert outcome.program is not None, f"backend {backend.name} said realizable without a program"
            started = time.perf_counter()
            # an engine may hand over the states its program keeps (a safety invariant)
            invariant = outcome.witness if isinstance(outcome.witness, dict) else None
            verdict = verify(problem, outcome.program, l, budget=clock.left(), invariant=invariant)
            counters = {
                **outcome.counters,
                "verify_seconds": round(time.perf_counter() - started, 6),
                "verify_states": verdict.states_explored,
            }
            if verdict.status is VerifyStatus.UNKNOWN:
                outcome = replace(
                    outcome,
                    status=GridStatus.UNKNOWN,
                    program=None,
                    counters=counters,
                    message=(
                        f"{backend.name} returned {_shown(outcome.program)} for {_at(l)}, not verified: "
                        f"{verdict.message}"
                    ),
                )
                attempts.append(outcome)
                if progress is not None:
                    progress(l, outcome)
                continue
            if verdict.wins:
                outcome = replace(outcome, counters=counters)
                attempts.append(outcome)
                if progress is not None:
                    progress(l, outcome)
                return result(
                    GridStatus.REALIZABLE,
                    steps=l,
                    program=outcome.program,
                    verified=True,
                    message=(
                        f"verified by the independent verifier "
                        f"({verdict.message or f'{verdict.states_explored} states explored'})"
                    ),
                )
            cex = verdict.counterexample
            reason = cex.reason if cex is not None else "no counterexample given"
            moves = "" if cex is None else f"; obstacle moves {[list(m) for m in cex.obstacle_moves]}"
            outcome = replace(
                outcome,
                status=GridStatus.UNKNOWN,
                counters={**counters, "refuted_by_verifier": 1},  # (bench records the run invalid)
                message=(
                    f"BACKEND BUG: {backend.name} returned {_shown(outcome.program)} for {_at(l)}, but the "
                    f"independent verifier refutes it: {reason}{moves}. The program is not reported"
                    + ("." if len(str(outcome.program)) <= QUOTED_PROGRAM else f": {outcome.program}")
                ),
                witness=cex,
            )
        attempts.append(outcome)
        if progress is not None:
            progress(l, outcome)

    bound = "" if depth_bound is None else f" (programs of depth <= {depth_bound})"
    if lengths == [None]:
        searched = f"the {problem.objective.value} objective"
    else:
        searched = f"l = {lengths[0]}" if len(lengths) == 1 else f"every l in {lengths[0]}..{lengths[-1]}"
    if len(attempts) == len(lengths) and all(a.status is GridStatus.UNREALIZABLE for a in attempts):
        return result(
            GridStatus.UNREALIZABLE, message=f"no controller{bound} wins at {searched}", certified_by=CERTIFIER
        )
    unknown = [f"{_at(a.steps)}: {a.message or 'no answer'}" for a in attempts if a.status is GridStatus.UNKNOWN]
    return result(GridStatus.UNKNOWN, message="; ".join(unknown + notes) or "no answer")


def _at(l: int | None) -> str:
    """A path length in a message ("l = 3"), or "the objective" for those without one."""
    return "the objective" if l is None else f"l = {l}"


def _certified(
    problem: GridProblem, claimant: str, outcome: LengthOutcome, clock: Any, budget: Budget, depth_bound: int | None
) -> LengthOutcome:
    """``outcome`` (an unrealizable claim by ``claimant``) re-decided by the native
    engine within the budget left: kept and marked ``certified_by``, or ``unknown``
    with the reason (see the module docstring)."""
    from plansynth.grid.verify import VerifyStatus, verify

    l = outcome.steps
    if claimant == CERTIFIER:
        return replace(outcome, counters={**outcome.counters, "certified_by": CERTIFIER})
    remaining = clock.remaining()
    if remaining <= 0:
        return replace(
            outcome,
            status=GridStatus.UNKNOWN,
            message=f"{claimant} claims unrealizable at {_at(l)}, not certified: the budget ran out",
        )
    started = time.perf_counter()
    check = get_backend(CERTIFIER).solve_length(problem, l, clock.left(), depth_bound=depth_bound)
    counters = {**outcome.counters, "certify_seconds": round(time.perf_counter() - started, 6)}
    if check.status is GridStatus.UNREALIZABLE:
        return replace(outcome, counters={**counters, "certified_by": CERTIFIER})
    fits = check.program is not None and (depth_bound is None or depth(check.program) <= depth_bound)
    if check.status is GridStatus.REALIZABLE and fits:
        verdict = verify(problem, check.program, l, budget=clock.left())
        if verdict.status is VerifyStatus.WINS:
            return replace(
                outcome,
                status=GridStatus.UNKNOWN,
                counters=counters,
                message=(
                    f"BACKEND ERROR: {claimant} claims unrealizable at {_at(l)}, but the native engine finds the "
                    f"controller {check.program}, verified by the independent verifier. The claim is not reported."
                ),
            )
    why = check.message or "no answer"
    return replace(
        outcome,
        status=GridStatus.UNKNOWN,
        counters=counters,
        message=f"{claimant} claims unrealizable at {_at(l)}, not certified by the native engine: {why}",
    )
