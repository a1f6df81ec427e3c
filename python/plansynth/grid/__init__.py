"""Reactive grid controllers (Chasins & Newcomb, SYNT 2016).

>>> from plansynth.grid import load, solve
>>> r = solve(load("examples/grid/figure1.yaml"))
>>> r.status.value, r.steps, r.verified
('realizable', 6, True)

The same kinds of names as :mod:`plansynth.reach`:

* problems: :class:`GridProblem` (:func:`load`, spec grid-problem.md);
* solvers: :func:`solve` with a backend chosen by name (``native``, ``cvc5``,
  ``external``; :func:`backend_names`);
* answers: :class:`GridResult` with :class:`GridStatus` (``write()`` writes the spec's
  result JSON), every program checked by the independent :func:`verify`.

These modules import no solver (cvc5 loads with its backend), so this stays a cheap
import.
"""

from plansynth.grid.problem import GridProblem, load_grid_problem
from plansynth.grid.result import GridResult, GridStatus, backend_names
from plansynth.grid.solve import solve
from plansynth.grid.verify import Verdict, verify

load = load_grid_problem

__all__ = [
    "GridProblem",
    "GridResult",
    "GridStatus",
    "Verdict",
    "backend_names",
    "load",
    "load_grid_problem",
    "solve",
    "verify",
]
