"""The native grid engine: exact, fast answers for the reactive grid problems of
Chasins & Newcomb (SYNT 2016) without a SyGuS solver.

Modules: :mod:`bitgrid` (cell sets as integers), :mod:`cone` (cone of influence),
:mod:`arena` (the bounded game), :mod:`stationary` (position-only strategies by SAT),
:mod:`conditions` (bottom-up condition enumeration), :mod:`synth` (smallest decision
tree programs), :mod:`engine` (the stages together), :mod:`explain` (why no controller
exists), :mod:`animation` (GIFs of plays), :mod:`reference` (brute-force oracles for
tests), :mod:`fast` (the compiled core behind the same signatures as the references).

Typical use goes through the backend registry::

    from plansynth.grid.solve import solve
    result = solve(problem, "native", Budget(seconds=60))            # smallest l, verified
    result = solve(problem, "native", Budget(seconds=60), minimize=True)  # proved minimal depth
"""

from plansynth.grid.native.engine import Engine, Refutation, program_wins

__all__ = ["Engine", "Refutation", "program_wins"]
