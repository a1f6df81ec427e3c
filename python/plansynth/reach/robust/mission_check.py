"""The robust reading of a mission, for the independent robust validator: does the
mission hold under every disturbance sequence?

It knows the problem (its labels and mission, W) and the plan (nominal states, the gain
K, the loop), and nothing of the planner's tightened labels: it draws the error sets
itself (:func:`plansynth.reach.robust.check.tube_polygons`, exact at every step of the
plan; the loop's and the rest's steps, which repeat forever, with the box of the limit
supports) and reads each label three ways per letter: *surely in* (the tube, or along a
segment the hull of both ends' tubes, lies in the label within tol), *surely out* (it
stays out of the label's interior deeper than tol), or neither (the disturbance decides).
The mission in negation normal form is evaluated with ``a`` true only when surely in and
``!a`` true only when surely out (:func:`plansynth.reach.ltl.semantics.holds` over the
plan's lasso): a formula in negation normal form is monotone in its literals, so if it
holds with every undecided literal false it holds for every disturbed run.

:func:`run_checker` checks a simulated run against the same reading: each letter the
robust word asserts must hold on the run (and the run must satisfy the validator).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
import shapely

from plansynth.reach.geometry import convex_hull, shape_to_shapely
from plansynth.reach.ltl.semantics import Lasso, finite_word, holds
from plansynth.reach.ltl.syntax import Formula, Not, Prop, children, nnf, parse
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robust.check import _limit_polygon, tube_polygons
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import validate

__all__ = ["robust_letters", "mission_holds", "run_checker"]

SURE, NOT = "+", "-"  # letters hold "a+" (a surely holds) and "a-" (a surely fails)


def _sure_formula(f: Formula) -> Formula:
    """NNF with ``a`` -> ``a+`` and ``!a`` -> ``a-`` (positive labels only)."""
    f = nnf(f)

    def walk(g: Formula) -> Formula:
        if isinstance(g, Prop):
            return Prop(g.name + SURE)
        if isinstance(g, Not):
            return Prop(g.arg.name + NOT)  # type: ignore[union-attr]
        kids = children(g)
        return g if not kids else type(g)(*(walk(k) for k in kids))  # type: ignore[call-arg]

    return walk(f)


def robust_letters(
    problem: ReachProblem, trajectory: Trajectory, K: np.ndarray, loop_start: int | None, tol: float = 1e-6
) -> list[frozenset[str]]:
    """Letters 0..N: letter t < N read off segment t (the hull of the tubes at its two
    ends), letter N off the last tube; a step at or after ``loop_start`` uses the limit
    box (a finite plan that rests at its end: ``loop_start`` N)."""
    X = np.asarray(trajectory.states, float)
    N = len(X) - 1
    P = X[:, list(problem.dynamics.position)]
    polys = tube_polygons(problem, K, N)
    limit = _limit_polygon(problem, K)
    if loop_start is not None:
        if not np.all(np.isfinite(limit)):
            return [frozenset() for _ in range(N + 1)]
        polys = [limit if t >= loop_start else E for t, E in enumerate(polys)]
    labels = problem.mission_labels
    geoms = {a: shape_to_shapely(s) for a, s in labels.items()}
    outer = {a: g.buffer(tol, join_style="mitre") for a, g in geoms.items()}
    inner = {a: g.buffer(-tol, join_style="mitre") for a, g in geoms.items()}
    bodies = []
    for t in range(N + 1):
        pts = P[t][None, :] + polys[t]
        if t < N:
            pts = np.vstack([pts, P[t + 1][None, :] + polys[t + 1]])
        bodies.append(convex_hull(pts))
    letters: list[set[str]] = [set() for _ in range(N + 1)]
    for a in labels:
        ins = shapely.covers(outer[a], np.array(bodies, dtype=object))
        outs = (
            np.ones(N + 1, dtype=bool)
            if inner[a].is_empty
            else ~shapely.relate_pattern(inner[a], np.array(bodies, dtype=object), "T********")
        )
        for t in range(N + 1):
            if ins[t]:
                letters[t].add(a + SURE)
            if outs[t]:
                letters[t].add(a + NOT)
    return [frozenset(s) for s in letters]


def mission_holds(
    problem: ReachProblem, trajectory: Trajectory, K: np.ndarray, loop_start: int | None, tol: float = 1e-6
) -> tuple[bool, str]:
    """Does the mission hold on the robust word (module doc)? A lasso (``loop_start`` <
    N) is the word of letters 0..N-1 returning to ``loop_start``; a finite plan
    (``loop_start`` None or N) rests at its last letter."""
    N = trajectory.horizon
    rests = loop_start is None or loop_start >= N
    letters = robust_letters(problem, trajectory, K, N if rests else loop_start, tol)
    word = finite_word(letters) if rests else Lasso(tuple(letters[:loop_start]), tuple(letters[loop_start:N]))
    f = _sure_formula(parse(problem.mission or "true"))
    if holds(f, word):
        return True, "the mission holds with every label read surely (the whole tube in, or out)"
    return False, "the mission fails when each label holds only where the whole tube is surely in (or out of) it"


def run_checker(
    problem: ReachProblem, trajectory: Trajectory, K: np.ndarray, loop_start: int | None, tol: float
) -> Any:
    """A checker of simulated runs of a mission's plan (for
    :func:`plansynth.reach.robust.simulate.simulate`): the validator on the problem
    with the workspace as its goal, and every letter the robust word asserts at the
    matching step of the plan (a run's step j beyond the plan maps into the loop, or to
    the rest)."""
    from plansynth.reach.mission.labels import planning_problem

    N = trajectory.horizon
    rest = loop_start is None or loop_start >= N
    letters = robust_letters(problem, trajectory, K, N if rest else loop_start, tol)
    plain = replace(planning_problem(problem), disturbance=None)
    geoms = {a: shape_to_shapely(s) for a, s in problem.mission_labels.items()}
    pos = list(problem.dynamics.position)

    def step_of(j: int) -> int:
        """The plan's letter that holds at step j of a run (a lasso's step N is its k)."""
        if rest:
            return min(j, N)
        if j < N:
            return j
        return loop_start + (j - loop_start) % (N - loop_start)  # type: ignore[operator]

    steps = None
    sure_in = {a: np.array([a + SURE in s for s in letters]) for a in geoms}
    sure_out = {a: np.array([a + NOT in s for s in letters]) for a in geoms}
    outer = {a: g.buffer(tol, join_style="mitre") for a, g in geoms.items()}
    inner = {a: g.buffer(-tol, join_style="mitre") for a, g in geoms.items()}

    def check(X: np.ndarray, U: np.ndarray) -> tuple[bool, str, tuple[str, ...]]:
        nonlocal steps
        report = validate(plain, Trajectory(states=X, inputs=U), require_segment_safe=True, tol=tol, dynamics="curve")
        kinds = list(report.counts)
        first = "" if report.ok else str(report.violations[0])
        P = X[:, pos]
        M = len(P) - 1
        if steps is None or len(steps) != M + 1:
            steps = np.array([step_of(j) for j in range(M + 1)])
        pieces = np.array([shapely.linestrings(P[j : j + 2]) for j in range(M)] + [shapely.points(P[M])], dtype=object)
        for a in geoms:
            left = sure_in[a][steps] & ~shapely.covers(outer[a], pieces)
            entered = (
                sure_out[a][steps] & shapely.relate_pattern(inner[a], pieces, "T********")
                if not inner[a].is_empty
                else np.zeros(M + 1, dtype=bool)
            )
            for j, what in ((np.nonzero(left)[0], "leaves"), (np.nonzero(entered)[0], "enters")):
                if len(j):
                    kinds.append("label")
                    side = "in" if what == "leaves" else "out"
                    first = (
                        first
                        or f"label at step {int(j[0])}: the run {what} {a}, which the robust plan has surely {side}"
                    )
        return not kinds, first, tuple(dict.fromkeys(kinds))

    return check
