"""The native grid engine: exact, fast answers for the reactive grid problems of
Chasins & Newcomb (SYNT 2016) without a SyGuS solver.

Modules, bottom up: :mod:`bitgrid` (cell sets as integers), :mod:`limits` (stopping
with :class:`plansynth.budget.BudgetExhausted`), :mod:`cone` (cone of influence),
:mod:`arena` (the bounded game), :mod:`sat` (budgeted SAT calls), :mod:`stationary`
(position-only strategies by SAT), :mod:`conditions` (bottom-up condition enumeration),
:mod:`synth` (decision trees: greedy and by SAT), :mod:`check` (program checks on the
game, simplification), :mod:`run` (the state of one run: options, budget, counters),
:mod:`exact_depth` (the smallest depth over every strategy), :mod:`answer` (a program
from a strategy, answer first), :mod:`engine` (the stages together), :mod:`explain`
(why no controller exists), :mod:`animation` (GIFs of plays), :mod:`reference`
(brute-force oracles for tests), :mod:`fast` (the compiled core behind the same
signatures as the references) and :mod:`options`.

Typical use goes through the backend registry::

    from plansynth.grid.solve import solve
    result = solve(problem, "native", Budget(seconds=60))            # smallest l, verified
    result = solve(problem, "native", Budget(seconds=60), minimize=True)  # proved minimal depth
"""

from typing import Any

__all__ = ["Engine", "Refutation", "program_wins"]


def __getattr__(name: str) -> Any:
    """The engine's names, imported on first use: importing a submodule (the options
    the CLI parses, say) does not load the engine and its SAT solver."""
    if name in __all__:
        from plansynth.grid.native import engine

        return getattr(engine, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
