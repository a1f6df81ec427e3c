"""A run of the peer ``omega`` (the BDD-based GR(1) solver under TuLiP; the ``baselines``
extra) on a grid instance: a bench-only solver, beside the registered grid backends.

The moving-obstacle family is posed as Ehlers wrote it for SLUGS
(:mod:`plansynth.grid.syntcomp.omega_game`), the other safety and recurrence problems
as TuLiP poses its grid worlds (:mod:`plansynth.grid.syntcomp.omega_grid`); omega
decides realizability and, when realizable, builds its strategy (a BDD transducer,
``make_streett_transducer``), all timed in one child process under the run's budget.
The moving-obstacle strategy is checked with plain BDD operations
(:func:`~plansynth.grid.syntcomp.omega_game.check_strategy`: it keeps the winning set
and the guarantees). An instance omega cannot be posed is recorded ``unavailable`` with
the reason.

>>> GRID_PEERS
('omega',)
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from plansynth.bench.solvers import GRID_PEERS
from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable

__all__ = ["GRID_PEERS", "run_omega"]


def run_omega(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    """The attributes of the omega run of ``task`` on grid instance ``inst``."""
    from plansynth.grid.result import GridStatus

    budget = Budget(seconds=float(task["timeout"]), memory_mb=task.get("memory_mb"))
    if inst.family == "moving-obstacle":
        from plansynth.grid.syntcomp.moving_obstacle import MovingObstacle
        from plansynth.grid.syntcomp.omega_game import solve, versions

        answer = solve(MovingObstacle(int(inst.params["m"]), int(inst.params["c"])), budget, checked=True)
    else:
        from plansynth.grid.syntcomp.omega_game import versions
        from plansynth.grid.syntcomp.omega_grid import solve, supports

        problem = inst.build()
        why = supports(problem)
        if why is not None:
            raise SolverUnavailable("omega", why)
        answer = solve(problem, budget)
    v = versions()
    status = {GridStatus.REALIZABLE: "solved", GridStatus.UNREALIZABLE: "unrealizable"}.get(answer.status, "unknown")
    return {
        "status": status,
        "solved": int(status == "solved"),
        "valid": None if status != "solved" else int(answer.counters.get("strategy_checked", 1)),
        "time": answer.seconds,
        "solver_version": f"omega {v['omega']} (dd {v['dd']}, {v['bdd']})",
        "message": answer.message[:2000],
        "attributes": {"expected": inst.expected, "phases": answer.phases, "counters": answer.counters},
    }
