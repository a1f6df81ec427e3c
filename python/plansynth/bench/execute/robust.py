"""What a run of the ``robust`` family records beyond its time (robust planning,
:mod:`plansynth.reach.robust`): after the solve, inside the same child, within what is
left of its wall-clock limit.

* ``runs``: the plan's closed loop (the result's gain K) under 1,000 random and 1,000
  vertex disturbance sequences (:func:`plansynth.reach.robust.simulate.simulate`), each
  run checked by the validator: how many broke a constraint, and the first violation.
  For a robust plan this shows nothing breaks; for the ``nominal-check`` baseline's
  nominal plan it shows what does (shown, not assumed).
* a team's runs: every robot's closed loop under the same numbers of sequences, each team
  run checked by the team validator (:mod:`plansynth.reach.team.robust_simulate`).
* ``largest``: for ``lazy-smt`` on a maze at scale 1, the largest disturbance scale
  (times :data:`~plansynth.reach.families.WINDY_BOX`) that still has a robust plan,
  found by bisection between scale 1 (a plan) and :data:`TOP_SCALE` (none): the margins
  grow linearly with the scale, so the tightened problem only gets harder.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from typing import Any

import numpy as np

from plansynth.budget import Budget

__all__ = ["robust_attributes", "largest_scale", "SEQUENCES", "TOP_SCALE", "BISECTIONS"]

#: disturbance sequences of each kind (random, vertex) a run's plan is simulated under
SEQUENCES = 1000
#: the bisection's upper end (the 2 m gaps close near 5.4) and its steps
TOP_SCALE = 8.0
BISECTIONS = 8
#: seconds each bisection probe may take
PROBE_SECONDS = 10.0


def largest_scale(n: int, deadline: float) -> dict[str, Any]:
    """The largest scale s in [1, TOP_SCALE] with a robust plan of maze-n (lazy-smt,
    default design), to within (TOP_SCALE - 1) / 2^BISECTIONS, and the box there."""
    from plansynth.reach.families import WINDY_BOX, windy_maze
    from plansynth.reach.solve import solve

    lo, hi = 1.0, TOP_SCALE
    probes: list[dict[str, Any]] = []
    for _ in range(BISECTIONS):
        left = deadline - time.perf_counter()
        if left < 2.0:
            break
        mid = (lo + hi) / 2
        r = solve(windy_maze(n, mid), "lazy-smt", Budget(seconds=min(PROBE_SECONDS, left - 1.0)))
        probes.append({"scale": mid, "status": r.status.value, "horizon": r.horizon})
        if r.status.value == "found":
            lo = mid
        else:
            hi = mid
    return {
        "scale": lo,
        "box": [lo * v for v in WINDY_BOX],
        "none_at": hi,
        "probes": probes,
        "complete": len(probes) == BISECTIONS,
    }


def robust_attributes(inst: Any, task: Mapping[str, Any], problem: Any, result: Any, deadline: float) -> dict[str, Any]:
    """The robust family's extras of one run (module doc)."""
    from plansynth.reach.robust.simulate import simulate

    out: dict[str, Any] = {"scale": float(inst.params.get("scale", 1.0))}
    record = getattr(result, "robust", None) or {}
    if record.get("margins"):
        out["grown"] = [
            max(a, b)
            for a, b in zip(
                record["margins"]["obstacles_grown_by"]["lo"], record["margins"]["obstacles_grown_by"]["hi"]
            )
        ]
    if "check" in record:
        out["worst_case"] = {"ok": record["check"]["ok"], "clearance": record["check"].get("clearance")}
    if getattr(problem, "robots", None) is not None:  # a team (plansynth.reach.team.robust)
        return _team_attributes(task, problem, result, record, out, deadline)
    if result.trajectory is not None and record.get("feedback") and deadline - time.perf_counter() > 10.0:
        K = np.asarray(record["feedback"]["gain"], float)
        mission = result.mission or {}
        loop = mission.get("loop_start")
        if loop is None and mission.get("semantics") == "finite":
            loop = result.trajectory.horizon
        t0 = time.perf_counter()
        runs = simulate(
            problem, result.trajectory, K, sequences=SEQUENCES, seed=int(task.get("seed", 0)), loop_start=loop
        )
        out["runs"] = {**runs.to_json_dict(), "seconds": time.perf_counter() - t0}
    if (
        task["solver"] == "lazy-smt"
        and "mission" not in inst.params
        and "narrow" not in inst.params
        and float(inst.params.get("scale", 1.0)) == 1.0
        and result.status.value == "found"
    ):
        out["largest"] = largest_scale(int(inst.params["n"]), deadline)
    return out


def _team_attributes(
    task: Mapping[str, Any], problem: Any, result: Any, record: dict[str, Any], out: dict[str, Any], deadline: float
) -> dict[str, Any]:
    """A team's extras: the worst-case team check and every robot's closed loop under the
    same numbers of sampled sequences (:func:`plansynth.reach.team.robust_simulate.simulate_team`)."""
    from plansynth.reach.team.robust_check import team_gains
    from plansynth.reach.team.robust_simulate import simulate_team

    if "check" in record:
        out["worst_case"] = {"ok": record["check"]["ok"], "clearance": record["check"].get("clearance")}
    if result.trajectories is not None and record.get("robots") and deadline - time.perf_counter() > 10.0:
        t0 = time.perf_counter()
        runs = simulate_team(
            problem,
            result.trajectories,
            team_gains(problem, record),
            sequences=SEQUENCES,
            seed=int(task.get("seed", 0)),
        )
        out["runs"] = {**runs.to_json_dict(), "seconds": time.perf_counter() - t0}
    return out
