"""The solver names the bench puts first, in order: the order of the command line's
listings and of the report's columns (any other registered name follows, sorted).

Which names exist is the registries' business (:data:`plansynth.grid.result.BACKENDS`,
:data:`plansynth.reach.planners.PLANNERS`); this is only their order in the bench.

>>> GRID_ORDER[0], REACH_ORDER[0]
('native', 'lazy-smt')
"""

from __future__ import annotations

__all__ = ["GRID_ORDER", "REACH_ORDER", "GRID_PEERS"]

GRID_ORDER = ("native", "omega", "cvc5", "external")
#: Grid solvers of the bench only (not backends of ``plansynth grid solve``): peers run
#: on the games they can be posed (:mod:`plansynth.bench.execute.omega`).
GRID_PEERS = ("omega",)
REACH_ORDER = ("lazy-smt", "milp", "milp-bigm", "rrt", "est", "kpiece", "gcs")
