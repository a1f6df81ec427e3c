"""Property tests of robust planning on small random problems (plansynth.reach.robust):

* the tightened LP agrees with the robust MILP: the lazy planner (one horizon at a time)
  and the region MILP, both on the problem tightened by the tube, give the same status
  and the same shortest horizon, and every plan passes the worst-case check;
* the worst-case check agrees with a dense simulation: on tiny horizons every sequence
  of vertices of W is run through the closed loop, and (a) the positions they reach at
  step t span exactly the tube polygon the check draws, (b) a linear bound (input,
  state bound, workspace, goal) is broken in the worst case at step t exactly when some
  vertex sequence breaks it there, (c) a vertex sequence that ends inside an obstacle is
  flagged by the check.
"""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st
from reach_oracles import disturbed

from plansynth.reach import ReachStatus, solve
from plansynth.reach.disturbance import Disturbance
from plansynth.reach.families import random_workspace
from plansynth.reach.geometry import convex_hull, halfspaces
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robust.check import check_robust, tube_polygons
from plansynth.reach.robust.tighten import robust_design
from plansynth.reach.trajectory import Trajectory

PROPS = settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@PROPS
@given(disturbed(), st.integers(3, 9))
def test_the_tightened_lp_agrees_with_the_robust_milp(p: ReachProblem, max_horizon: int) -> None:
    lazy = solve(p, "lazy-smt", max_horizon=max_horizon, horizon_search="linear", exact_segments=False)
    milp = solve(p, "milp", max_horizon=max_horizon)
    event(f"status {lazy.status.value}")
    assert lazy.status is milp.status, (lazy.message, milp.message)
    assert lazy.horizon == milp.horizon
    for r in (lazy, milp):
        if r.status is ReachStatus.FOUND:
            assert r.validated is True and r.robust["check"]["ok"] is True


def vertex_runs(p: ReachProblem, traj: Trajectory, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every sequence of vertices of W through the closed loop: states (runs, N+1, n), inputs (runs, N, m)."""
    V = p.disturbance.corners()
    N = traj.horizon
    A, B = np.asarray(p.dynamics.A), np.asarray(p.dynamics.B)
    seqs = np.array(list(itertools.product(range(len(V)), repeat=N)), dtype=int).reshape(-1, N)
    X = np.empty((len(seqs), N + 1, A.shape[0]))
    U = np.empty((len(seqs), N, B.shape[1]))
    X[:, 0] = traj.states[0]
    for t in range(N):
        U[:, t] = traj.inputs[t] + (X[:, t] - traj.states[t]) @ K.T
        X[:, t + 1] = X[:, t] @ A.T + U[:, t] @ B.T + V[seqs[:, t]]
    return X, U


def worst_per_step(p: ReachProblem, X: np.ndarray, U: np.ndarray) -> dict[tuple[str, int], float]:
    """The largest violation of each linear bound at each step over the runs (> 0: broken)."""
    out: dict[tuple[str, int], float] = {}
    N = U.shape[1]
    for t in range(N):
        out[("input", t)] = float(np.max(np.abs(U[:, t]))) - p.input_bound
    lo, hi = (np.array(p.state_bounds.lo), np.array(p.state_bounds.hi)) if p.state_bounds else (None, None)
    pos = list(p.dynamics.position)
    ws_lo, ws_hi = np.array(p.workspace.lo), np.array(p.workspace.hi)
    for t in range(N + 1):
        if lo is not None:
            out[("state-bound", t)] = float(max(np.max(X[:, t] - hi), np.max(lo - X[:, t])))
        P = X[:, t][:, pos]
        out[("workspace", t)] = float(max(np.max(P - ws_hi), np.max(ws_lo - P)))
    H, h = halfspaces(p.goal)
    out[("goal", N)] = float(np.max(X[:, N][:, pos] @ H.T - h))
    return out


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(disturbed(max_obstacles=5), st.integers(1, 3), st.integers(0, 10**6))
def test_the_worst_case_check_agrees_with_every_vertex_sequence(p: ReachProblem, N: int, seed: int) -> None:
    w = p.disturbance
    assume(len(w.corners()) ** N <= 5000)
    K = robust_design(p).K
    rng = np.random.default_rng(seed)
    # a random nominal plan from the start (anywhere: the check must say what breaks)
    A, B = np.asarray(p.dynamics.A), np.asarray(p.dynamics.B)
    Vn = rng.uniform(-p.input_bound, p.input_bound, size=(N, B.shape[1]))
    Xn = [np.array(p.start, float)]
    for t in range(N):
        Xn.append(A @ Xn[-1] + B @ Vn[t])
    traj = Trajectory(states=np.array(Xn), inputs=Vn)
    X, U = vertex_runs(p, traj, K)
    tol = 1e-6
    report = check_robust(p, traj, K, tol=tol)
    assert all(n <= 20 for n in report.counts.values())  # every violation listed
    flagged = {(v.kind, v.step) for v in report.violations}
    event("worst case broken" if flagged else "worst case holds")
    # (a) the tube polygons are the hulls of the positions the vertex sequences reach
    pos = list(p.dynamics.position)
    polys = tube_polygons(p, K, N)
    for t in range(N + 1):
        reached = convex_hull(X[:, t][:, pos])  # (GEOS's own hull of repeated points can be wrong)
        drawn = convex_hull(traj.states[t][pos] + polys[t])
        assert shapely.hausdorff_distance(reached, drawn) < 1e-9
    # (b) the linear bounds: broken in the worst case exactly when by some vertex sequence
    for (kind, t), amount in worst_per_step(p, X, U).items():
        if abs(amount - tol) < 1e-8:
            continue  # a tie at the tolerance: either answer is right
        assert ((kind, t) in flagged) == (amount > tol), (kind, t, amount)
    # (c) a vertex sequence inside an obstacle is an obstacle of the worst case
    for t in range(N + 1):
        for o in p.obstacles:
            inner = shapely.buffer(
                shapely.Polygon(np.array(o.vertices)) if hasattr(o, "vertices") else shapely.box(*o.lo, *o.hi),
                -2 * tol,
                join_style="mitre",
            )
            if np.any(shapely.contains_xy(inner, X[:, t, pos[0]], X[:, t, pos[1]])):
                assert ("obstacle", t) in flagged


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_robust_plan_on_a_random_room_survives_its_vertex_sequences(seed: int) -> None:
    """End to end on a short plan: found robustly, then every vertex sequence (a dense
    simulation of the worst case) keeps the run valid."""
    from plansynth.reach.validate import validate

    for s in range(seed * 50, seed * 50 + 50):
        try:
            p = random_workspace(s, 2, order=1)
        except RuntimeError:
            continue
        p = replace(p, disturbance=Disturbance(box=(0.05, 0.05)), max_horizon=6)
        r = solve(p, "lazy-smt", horizon_search="linear", exact_segments=False)
        if r.status is ReachStatus.FOUND and 1 <= r.horizon <= 6:
            break
    else:
        pytest.skip("no short robust plan among the seeds")  # pragma: no cover
    K = np.array(r.robust["feedback"]["gain"])
    X, U = vertex_runs(p, r.trajectory, K)
    plain = replace(p, disturbance=None)
    for Xr, Ur in zip(X, U):
        assert validate(plain, Trajectory(states=Xr, inputs=Ur), require_segment_safe=True, dynamics="curve").ok
