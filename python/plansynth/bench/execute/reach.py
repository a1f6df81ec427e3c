"""A reach run: a reach-avoid planner on one instance, through :func:`plansynth.reach.solve`.

Every planner of :func:`plansynth.reach.solve` (``lazy-smt`` and its named
configurations, ``milp``, ``milp-bigm``, ``rrt``, ``est``, ``kpiece``, ``gcs``,
``milp-ltl`` ...) runs through it, and it validates every answer (a gcs curve in the
validator's ``dynamics="curve"`` mode; a mission also by the mission checker). For
every solved run whose regions are one per time step, the run also records
``oracle_lp``: the time of one cold LP over its final region sequence
(:func:`plansynth.reach.oracle.oracle_lp`), the limit its total is compared with (not
for a plan lazy-smt shortened, :mod:`plansynth.reach.lazy.shorten`, whose steps may
cross regions' faces between samples: CON-PLAN's LP over its regions is not its LP). A run
of the ``robust`` family also records the closed loop under sampled disturbances and,
for lazy-smt at scale 1, the largest disturbance with a plan
(:mod:`plansynth.bench.execute.robust`).

The run's ``solver_version`` is the one the result reports (its ``solver_version``
key), else the registered planner's own :meth:`~plansynth.reach.planners.Planner.version`
(:func:`reported_version`): never guessed from the planner's name.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from typing import Any

from plansynth.bench.tasks import wall_limit
from plansynth.budget import Budget

__all__ = ["run_reach", "reported_version"]


def reported_version(result: Any, planner: str) -> str | None:
    """The solver version of a reach run: what ``result`` reports as ``solver_version``
    in its record (:meth:`~plansynth.reach.result.ReachResult.to_json_dict`), else the
    ``version()`` of the planner registered as ``planner`` (None for a plugin that has
    none).

    >>> class Result:
    ...     def to_json_dict(self): return {"solver_version": "highspy 9.9"}
    >>> reported_version(Result(), "milp")
    'highspy 9.9'
    >>> class Older:
    ...     def to_json_dict(self): return {"versions": {}}
    >>> reported_version(Older(), "milp-ltl").split()[0]
    'highspy'
    """
    reported = result.to_json_dict().get("solver_version")
    if reported:
        return str(reported)
    from plansynth.reach.planners import get_planner

    version = getattr(get_planner(planner), "version", None)
    return str(version()) if callable(version) else None


def run_reach(inst: Any, task: Mapping[str, Any]) -> dict[str, Any]:
    """The attributes of reach ``task`` on instance ``inst``."""
    from plansynth.reach.solve import get_planner, solve

    started = time.perf_counter()
    problem = inst.build()
    solver = task["solver"]
    budget = Budget(seconds=float(task["timeout"]))
    seed = int(task.get("seed", 0)) + int(task.get("repeat", 0))
    planner = get_planner(solver)
    values = dict(task.get("options") or {})
    if "seed" in getattr(planner, "option_names", lambda: ())():  # the sampling planners (OMPL)
        values["seed"] = seed
    # one path for every planner: solve() plans (a sized robot in its configuration
    # space) and validates (missions also mission-checked); its verdict is the run's
    res = solve(problem, solver, budget, planner.configure(**values))
    valid = None if res.validated is None else int(bool(res.validated))
    dense = getattr(res, "curve_validation", None)
    if dense is not None:  # a continuous-time curve (gcs): its dense sampling says whether segments are safe
        segment_safe = int(bool(dense.segment_safe))
    else:
        segment_safe = None if res.validation is None else int(bool(res.validation.segment_safe))
    if res.status.value == "found":
        status = "solved" if valid == 1 else "invalid"
    elif res.status.value == "infeasible":
        status = "infeasible"
    else:
        status = "invalid" if valid == 0 else "unknown"
    c = dict(res.counters or {})
    timings = {k: float(v) for k, v in (res.timings or {}).items() if isinstance(v, (int, float))}
    oracle = None
    # (not for a mission: its regions index the label-refined abstraction, and a lasso's
    # loop closure is no CON-PLAN row, so the reach-avoid oracle LP does not apply)
    if (
        status == "solved"
        and res.regions is not None
        and res.horizon is not None
        and problem.mission is None
        and getattr(problem, "robots", None) is None  # (a team's regions are one sequence per robot)
        and len(res.regions) == res.horizon + 1
        and getattr(res, "guarantee", None) in ("segments", "samples")
        # (a shortened plan's steps may cross regions' faces between samples and skip a
        # region, lazy/shorten.py: not CON-PLAN's LP over its regions, which the limit is)
        and (res.counters or {}).get("shortened_from") is None
    ):
        from plansynth.reach.oracle import oracle_lp

        # within the child's wall-clock limit (the budget plus its grace), 2 s kept for the rest;
        # with less than a second left the run records no limit
        left = wall_limit(task) - (time.perf_counter() - started) - 2.0
        lim = (
            None
            if left < 1.0
            else oracle_lp(problem, res.regions, segment_safe=res.guarantee == "segments", seconds=left)
        )
        if lim is not None:
            oracle = {
                "seconds": lim.seconds,
                "build": lim.build_seconds,
                "solve": lim.solve_seconds,
                "feasible": lim.feasible,
            }
    extras = {}
    if inst.family == "robust":  # (the closed loop under sampled disturbances, the largest box with a plan)
        from plansynth.bench.execute.robust import robust_attributes

        extras["robust"] = robust_attributes(inst, task, problem, res, started + wall_limit(task) - 5.0)
    return {
        "status": status,
        "solved": int(status == "solved"),
        "valid": valid,
        "segment_safe": segment_safe,
        "time": float(res.seconds),
        "horizon": res.horizon,
        "iterations": c.get("iterations", c.get("milp_calls")),
        "lp_calls": c.get("lp_calls"),
        "sat_calls": c.get("sat_calls"),
        "regions": c.get("regions"),
        "solver_version": reported_version(res, solver),
        "message": (res.message or "")[:2000],
        "attributes": {
            "counters": {k: v for k, v in c.items() if isinstance(v, (int, float, str))},
            "timings": timings,
            "seed": seed,
            "oracle_lp": oracle,
            "guarantee": getattr(res, "guarantee", None),
            # a mission's plan: the reading, the end and the achieved margin the checker reports
            "mission": None
            if not getattr(res, "mission", None)
            else {k: res.mission.get(k) for k in ("semantics", "reading", "end", "robustness", "ok")},
            "duration": None
            if res.trajectory is None or res.horizon is None or not problem.dynamics.dt
            else res.horizon * float(problem.dynamics.dt),
            **extras,
        },
    }
