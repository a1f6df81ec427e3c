"""The closed loop under sampled disturbance sequences: the robot runs
``u_t = v_t + K (x_t - x_nom_t)`` on ``x_{t+1} = A x_t + B u_t + w_t`` from the start,
and every run is checked by the independent validator
(:func:`plansynth.reach.validate.validate` in ``curve`` mode: the disturbed run does
not satisfy ``x' = A x + B u``, everything else is required, segments included).

Two kinds of sequences (``--disturbances N`` runs N of each):

``random``  every w_t drawn independently and uniformly from W (a box: each component
            uniform; a polytope: a point of the simplex of its vertices, uniform);
``vertex``  every w_t a vertex of W drawn uniformly (a box: a corner), the sequences
            that push hardest (the worst case of a linear system is reached at vertices).

A simulation can only show a violation, never prove there is none; the worst case of
:mod:`plansynth.reach.robust.check` proves it. Simulating a *nominal* plan under the
same sequences shows what the robust one buys.

>>> from dataclasses import replace
>>> from plansynth.reach.families import maze
>>> from plansynth.reach.disturbance import Disturbance
>>> from plansynth.reach.lazy.planner import plan_lazy
>>> from plansynth.reach.robust.tighten import tightened
>>> p = replace(maze(1), disturbance=Disturbance(box=(0.02, 0.02, 0.05, 0.05)))
>>> t = tightened(p)
>>> simulate(p, plan_lazy(t.problem).trajectory, t.design.K, sequences=20).violated
0
>>> bad = simulate(p, plan_lazy(maze(1)).trajectory, t.design.K, sequences=20)
>>> bad.violated, sorted(bad.kinds_violated)
(40, ['goal', 'input', 'obstacle', 'segment', 'state-bound', 'workspace'])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import validate

__all__ = ["SimulationReport", "Failure", "simulate", "sample_disturbances", "closed_loop", "unrolled", "KINDS"]

KINDS = ("random", "vertex")


@dataclass(frozen=True)
class Failure:
    """The first violated run: its kind of sequence, its index, the validator's first violation."""

    kind: str
    index: int
    violation: str

    def to_json_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "index": self.index, "violation": self.violation}


@dataclass(frozen=True)
class SimulationReport:
    """How many runs of each kind were simulated and how many the validator rejected."""

    runs: dict[str, int]
    violations: dict[str, int]
    seed: int
    first: Failure | None
    kinds_violated: dict[str, int]  # violation kind -> runs with one

    @property
    def total(self) -> int:
        return sum(self.runs.values())

    @property
    def violated(self) -> int:
        return sum(self.violations.values())

    def summary(self) -> str:
        parts = ", ".join(f"{self.violations[k]} of {n} {k}" for k, n in self.runs.items())
        head = f"closed loop under sampled disturbances (seed {self.seed}): {parts} runs violated"
        if self.first is not None:
            head += f"; first: {self.first.kind} run {self.first.index}, {self.first.violation}"
        return head

    def to_json_dict(self) -> dict[str, Any]:
        return {
            "runs": dict(self.runs),
            "violated": dict(self.violations),
            "seed": self.seed,
            "first": None if self.first is None else self.first.to_json_dict(),
            "violation_kinds": dict(self.kinds_violated),
        }


def sample_disturbances(
    problem: ReachProblem, kind: str, runs: int, steps: int, rng: np.random.Generator
) -> np.ndarray:
    """``runs`` sequences of ``steps`` disturbances of the given kind: (runs, steps, n)."""
    w = problem.disturbance
    assert w is not None
    n = w.dim
    if kind == "random":
        if w.box is not None:
            b = np.asarray(w.box, float)
            return rng.uniform(-1.0, 1.0, size=(runs, steps, n)) * b
        V = np.asarray(w.vertices, float)
        weights = rng.dirichlet(np.ones(len(V)), size=(runs, steps))
        return weights @ V
    if kind == "vertex":
        if w.box is not None:
            b = np.asarray(w.box, float)
            return rng.choice((-1.0, 1.0), size=(runs, steps, n)) * b
        V = np.asarray(w.vertices, float)
        return V[rng.integers(0, len(V), size=(runs, steps))]
    raise ValueError(f"unknown kind of disturbance sequence {kind!r} (known: {', '.join(KINDS)})")


def closed_loop(
    problem: ReachProblem, trajectory: Trajectory, K: np.ndarray, W: np.ndarray, *, feedback: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """The disturbed runs (states (runs, N+1, n), inputs (runs, N, m)) of the nominal
    plan with the feedback ``K`` (``feedback=False``: the nominal inputs open loop)
    under the disturbances ``W`` (runs, N, n)."""
    A, B = np.asarray(problem.dynamics.A, float), np.asarray(problem.dynamics.B, float)
    Xn, Vn = np.asarray(trajectory.states, float), np.asarray(trajectory.inputs, float)
    K = np.asarray(K, float) if feedback else np.zeros((B.shape[1], A.shape[0]))
    runs, N = W.shape[0], len(Vn)
    X = np.empty((runs, N + 1, A.shape[0]))
    U = np.empty((runs, N, B.shape[1]))
    X[:, 0] = Xn[0]
    for t in range(N):
        U[:, t] = Vn[t] + (X[:, t] - Xn[t]) @ K.T
        X[:, t + 1] = X[:, t] @ A.T + U[:, t] @ B.T + W[:, t]
    return X, U


def unrolled(problem: ReachProblem, trajectory: Trajectory, loop_start: int | None, repeats: int) -> Trajectory:
    """A plan that goes on forever, as far as a simulation follows it: a lasso (``x_N =
    x_k``, ``loop_start`` k < N) with its loop ``repeats`` more times; a plan that rests
    at its end (``loop_start`` N) with ``repeats`` more steps at rest (the input that
    holds x_N: zero for the named models, else the least-squares solution of
    ``B v = x_N - A x_N``)."""
    X, U = np.asarray(trajectory.states, float), np.asarray(trajectory.inputs, float)
    N = len(X) - 1
    if loop_start is None or repeats <= 0:
        return trajectory
    if loop_start < N:
        X = np.vstack([X] + [X[loop_start + 1 :]] * repeats)
        U = np.vstack([U] + [U[loop_start:]] * repeats)
        return Trajectory(states=X, inputs=U)
    A, B = np.asarray(problem.dynamics.A, float), np.asarray(problem.dynamics.B, float)
    v = np.linalg.lstsq(B, X[-1] - A @ X[-1], rcond=None)[0]
    return Trajectory(states=np.vstack([X] + [X[-1:]] * repeats), inputs=np.vstack([U] + [v[None, :]] * repeats))


#: a lasso's loop (or a finite plan's rest) is simulated this many more times
REPEATS = 3


def simulate(
    problem: ReachProblem,
    trajectory: Trajectory,
    K: np.ndarray,
    *,
    sequences: int = 1000,
    seed: int = 0,
    kinds: tuple[str, ...] = KINDS,
    feedback: bool = True,
    tol: float = 1e-6,
    validator: Any = None,
    loop_start: int | None = None,
) -> SimulationReport:
    """Run ``sequences`` disturbance sequences of each kind (the same for the same
    ``seed``) and check every run. ``validator(states, inputs) -> (ok, first violation,
    kinds of violation)`` replaces the reach-avoid validator (a mission's, from
    :func:`plansynth.reach.robust.mission_check.run_checker`, checks its labels too, and is
    the default for a problem with a mission). ``loop_start``: the plan goes on forever
    (:func:`unrolled`, :data:`REPEATS` more times)."""
    rng = np.random.default_rng(seed)
    if problem.mission is not None and validator is None:
        from plansynth.reach.robust.mission_check import run_checker

        validator = run_checker(problem, trajectory, K, loop_start, tol)
    trajectory = unrolled(problem, trajectory, loop_start, REPEATS)
    N = trajectory.horizon
    runs: dict[str, int] = {}
    bad: dict[str, int] = {}
    kinds_seen: dict[str, int] = {}
    first: Failure | None = None
    check = validator if validator is not None else _validator(problem, tol)
    for kind in kinds:
        W = sample_disturbances(problem, kind, sequences, N, rng)
        X, U = closed_loop(problem, trajectory, K, W, feedback=feedback)
        runs[kind], bad[kind] = sequences, 0
        for i in range(sequences):
            ok, why, which = check(X[i], U[i])
            if ok:
                continue
            bad[kind] += 1
            for k in which:
                kinds_seen[k] = kinds_seen.get(k, 0) + 1
            if first is None:
                first = Failure(kind, i, why)
    return SimulationReport(runs, bad, seed, first, kinds_seen)


def _validator(problem: ReachProblem, tol: float):
    def check(X: np.ndarray, U: np.ndarray) -> tuple[bool, str, tuple[str, ...]]:
        report = validate(problem, Trajectory(states=X, inputs=U), require_segment_safe=True, tol=tol, dynamics="curve")
        if report.ok:
            return True, "", ()
        return False, str(report.violations[0]), tuple(report.counts)

    return check
