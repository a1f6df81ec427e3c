"""The multi-step displacement bound of random dynamics
(plansynth.reach.dynamics.displacement_reach) against an independent computation: the
largest move of k steps from time t is the l1 norm of the inputs' coefficients in
p_{t+k} - p_t, read off by simulating unit impulses with A and B themselves."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.reach.dynamics import displacement_reach, integrator_chain, reach_steps
from plansynth.reach.families import random_dynamics
from plansynth.reach.lazy.bounds import box_steps, physical_lower_bound, step_reach


def _exact_move(A: np.ndarray, B: np.ndarray, pos: list[int], t: int, k: int, ubar: float) -> np.ndarray:
    """max over |u| <= ubar of |p_{t+k} - p_t| per axis, from rest, by impulse simulation."""
    n, m = B.shape
    total = np.zeros(len(pos))
    for s in range(t + k):
        for j in range(m):
            x = B[:, j].copy()  # the state one step after a unit impulse at time s
            traj = {s + 1: x}
            for tt in range(s + 1, t + k):
                x = A @ x
                traj[tt + 1] = x
            at = lambda time: traj[time][pos] if time in traj else np.zeros(len(pos))  # noqa: E731
            total += np.abs(at(t + k) - at(t))
    return ubar * total


@settings(max_examples=12, deadline=None)
@given(states=st.integers(4, 9), seed=st.integers(0, 50), k=st.integers(1, 12), t=st.integers(0, 40))
def test_bound_holds_and_is_tight_far_from_the_start(states: int, seed: int, k: int, t: int) -> None:
    p = random_dynamics(1, states, seed)
    A, B = np.asarray(p.dynamics.A), np.asarray(p.dynamics.B)
    W = displacement_reach(p.dynamics, p.input_bound, 20)
    assert W is not None
    exact = _exact_move(A, B, list(p.dynamics.position), t, k, p.input_bound)
    assert np.all(exact <= W[k] + 1e-9)
    # W is the supremum over t: the move at a late time comes within a small margin
    late = _exact_move(A, B, list(p.dynamics.position), 150, k, p.input_bound)
    assert np.all(late >= W[k] - 1e-4 * (1 + W[k]))


def test_bound_at_fifty_states_beats_one_step_bounds() -> None:
    p = random_dynamics(1, 50, 0)
    W = displacement_reach(p.dynamics, p.input_bound, 300)
    down, up = step_reach(p)
    assert W[1, 0] <= up[0] * 1.01 + 5.0  # one step: of the same order as the LP bound
    assert W[300, 0] < 300 * up[0] / 10  # 300 steps: far below 300 one-step bounds
    # and it raises the horizon lower bound from rest (the maze's goal is 26 m up)
    assert physical_lower_bound(p) == box_steps(
        (np.array([1.0, 1.0]),) * 2, (np.array([1.0, 27.0]), np.array([3.0, 29.0])), down, up, W
    )
    assert physical_lower_bound(p) > box_steps(
        (np.array([1.0, 1.0]),) * 2, (np.array([1.0, 27.0]), np.array([3.0, 29.0])), down, up
    )


def test_no_table_for_chains_and_steps_read_off_it() -> None:
    assert displacement_reach(integrator_chain(3, 2, 0.5), 1.0, 10) is None
    W = np.array([[0.0], [1.0], [1.5], [3.0]])
    assert [reach_steps(W, d, 0) for d in (0.0, 0.5, 1.0, 1.2, 3.0, 3.5)] == [0, 1, 1, 2, 3, 4]


@pytest.mark.parametrize("states", [10, 50])
def test_random_trajectories_stay_within_the_bound(states: int) -> None:
    p = random_dynamics(2, states, 1)
    A, B = np.asarray(p.dynamics.A), np.asarray(p.dynamics.B)
    W = displacement_reach(p.dynamics, p.input_bound, 60)
    rng = np.random.default_rng(0)
    for _ in range(20):
        x = np.asarray(p.start, float).copy()
        P = [x[:2].copy()]
        for _t in range(120):
            x = A @ x + B @ rng.choice([-1.0, 1.0], size=2)
            P.append(x[:2].copy())
        P = np.array(P)
        for k in (1, 5, 20, 60):
            assert np.all(np.abs(P[k:] - P[:-k]).max(axis=0) <= W[k] + 1e-9)


def test_transit_box_gaps_from_the_start_are_refuted_by_the_exact_lp() -> None:
    """Every gap out of the start that the table calls impossible is infeasible for
    CON-PLAN's exact LP (dynamics, input and state bounds, anchored at the start)."""
    from plansynth.reach.abstraction import abstract
    from plansynth.reach.lazy.conplan import ConPlan
    from plansynth.reach.lazy.transit import START, TransitCheck

    p = random_dynamics(1, 6, 2)
    a = abstract(p)
    tc = TransitCheck(ConPlan(p, a), a)
    assert tc.reach_table is not None
    for b in range(len(a.regions)):
        box = tc.box_gap(START, b)
        for k in range(1, box):
            assert tc.inner.refutes(tc.leg(START, b, k, N=k), cold=True), (b, k)
    # the table raises some box gap above the one-step bound's
    plain = [tc.box_gap(START, b) for b in range(len(a.regions))]
    tc.reach_table = None
    assert any(x > tc.box_gap(START, b) for b, x in enumerate(plain))
