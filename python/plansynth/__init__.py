"""plansynth: correct-by-construction robot motion planning with off-the-shelf solvers.

Two halves, each in its own subpackage:

* :mod:`plansynth.grid` -- reactive grid controllers (Chasins & Newcomb, "Using SyGuS to
  Synthesize Reactive Motion Plans", SYNT 2016): a SyGuS compiler with cvc5 and external
  solver backends, and a native engine.
* :mod:`plansynth.reach` -- reach-avoid planning with linear dynamics (Shoukry et al.,
  "Scalable Motion Planning Using Lazy SMT-Based Solving", CDC 2016).

Shared pieces live beside them: :mod:`plansynth.errors` (the named errors),
:mod:`plansynth.budget` (explicit solver budgets) and :mod:`plansynth.io` (loading
problem files with errors that name the file and the field).
"""

from plansynth.budget import Budget
from plansynth.errors import InvalidProblem, PlansynthError, SolverUnavailable

__version__ = "0.1.0"

__all__ = ["Budget", "InvalidProblem", "PlansynthError", "SolverUnavailable", "__version__"]
