"""The independent mission checker.

It knows the problem (labels, margins, mission, its reading and end) and the trajectory,
and nothing of the planner: no regions, no encoding. It recomputes the labels from the
geometry (half-planes and shapely) and evaluates the mission with
:mod:`plansynth.reach.mission.ltl`'s direct semantics (not the BMC encoding).

**A literal's margin at a step** (the quantitative reading of a label, in the units of
the workspace). For a convex label {H p <= h} (unit rows) and a point p, the margin of
``a`` is the depth ``min_i (h_i - H_i p)`` (the distance to the label's boundary inside
it, negative outside) and the margin of ``!a`` is ``max_i (H_i p - h_i)``, the distance
beyond the farthest edge line (for a box: the larger of the gaps along the axes), so
the margins of ``a`` and ``!a`` are each other's negatives; for a non-convex label (no
margin allowed) both are the Euclidean signed distance to its boundary. The **reading**
says what a step is: the **sample** reading (the discrete-time literature's) reads step t
at p_t; the **segment** reading reads it along the whole segment [p_t, p_t+1]: the margin
of ``a`` is its least margin along the segment, and so is that of ``!a`` (a segment that
crosses the label's edge has neither), and the last step of a finite plan is its last
position. Literal a of label a with margin r *holds* at step t when its margin there is
>= r (within ``tol``).

**The word** of a trajectory (finite plan x_0..x_N, or a lasso with loop start k and
x_N = x_k within tol, else a ``loop`` violation) is its steps' letters: a lasso's word
has N letters (position N is position k again, the successor of N - 1); a finite plan
**at rest** (``end: rest``) repeats its last letter forever, so the robot must be able
to hold x_N: some admissible input keeps x_N where it is (:func:`can_rest`); a finite
plan with a **free end** is the finite word of its N + 1 letters, read as LTL on finite
traces (:mod:`plansynth.reach.ltl.semantics`).

**Touches.** With margin 0 a robot that only touches a label's boundary (as touching an
obstacle is no collision) may be read as in or as out of it, but one way per step for the
whole formula: the mission holds when some *consistent reading* of the touches satisfies
it (the planner's word fixes each touch one way, so it is such a reading). "May hold" for
every literal at once is the quick upper bound: a mission that fails under it fails under
every reading; otherwise :func:`consistent_reading` decides whether a reading exists, by
a SAT encoding of the semantics (CaDiCaL). So ``F a & G !a`` fails on a trajectory that
only touches ``a``. With a margin r > 0, ``a`` and ``!a`` never hold at one step.

**The achieved margin** (``robustness``): the robustness of the mission on the word of
the literals' margins (:func:`plansynth.reach.ltl.robustness`, max for "or", min for
"and"), the largest margin at which the plan satisfies the mission; every label the
plan must visit is reached that deep. It is reported beside the verdict.

**The first failing step.** When the mission fails, :func:`check_mission` descends the
formula from position 0 (a conjunction into a failing conjunct, ``G f`` into the first
step where f fails, ``a U b`` into the first step where a fails before b, a label
literal to its step, with what the geometry says there) and names the step where the
descent ends; ``F f`` that never holds fails at the first position of the loop, after
which no future remains unseen.

>>> from plansynth.reach.fileformat import reach_problem_from_dict
>>> from plansynth.reach.trajectory import Trajectory
>>> p = reach_problem_from_dict({"workspace": {"min": [0, 0], "max": [4, 4]},
...     "labels": {"s": {"min": [1, 0], "max": [2, 4]}}, "mission": "G !s",
...     "robot": {"dynamics": {"model": "single-integrator", "dt": 1}, "start": [0.5, 0.5],
...               "input_bound": 2}})
>>> r = check_mission(p, Trajectory([[0.5, 0.5], [0.5, 2], [3, 2]], [[0, 1.5], [2.5, 0]]))
>>> r.ok, r.step, r.reason
(False, 1, 'segment 1 crosses into label s')
>>> r = check_mission(p, Trajectory([[0.5, 0.5], [0.5, 2], [3, 2]], [[0, 1.5], [2.5, 0]]), reading="sample")
>>> r.ok, round(r.robustness, 3)
(True, 0.5)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from plansynth.reach.mission.failure import failure_reason, first_failure
from plansynth.reach.mission.ltl import FiniteWord, Lasso, holds, nnf, parse, robustness
from plansynth.reach.mission.touches import consistent_reading
from plansynth.reach.mission.word import NEG, Label, trajectory_word
from plansynth.reach.mission.word import literal_form as _literal_form
from plansynth.reach.problem import MISSION_ENDS, MISSION_READINGS, ReachProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import component_tolerance, row_tolerance

__all__ = ["MissionReport", "can_rest", "check_mission", "consistent_reading", "trajectory_word", "NEG"]


@dataclass(frozen=True)
class MissionReport:
    """``ok``: the mission holds on the trajectory's word; ``step``/``reason``: where
    and why it fails (None when ok); ``semantics``: finite or lasso; ``reading``:
    segment or sample; ``end``: rest or free (of a finite plan); ``letters``: the labels
    that hold at each step 0..N in the reading used (boundary touches as the satisfying
    reading reads them; for a violated mission, every label that may hold);
    ``robustness``: the achieved margin (None when it is infinite: a mission without
    labels); ``margins``: each label's required margin."""

    ok: bool
    semantics: str
    loop_start: int | None
    step: int | None
    reason: str | None
    letters: tuple[tuple[str, ...], ...]
    reading: str = "segment"
    end: str = "rest"
    robustness: float | None = None
    margins: dict[str, float] = field(default_factory=dict)

    def __bool__(self) -> bool:
        raise TypeError("a MissionReport has no truth value; read .ok")

    def summary(self) -> str:
        kind = self.semantics if self.loop_start is None else f"lasso (loop from step {self.loop_start})"
        if self.semantics == "finite" and self.end == "free":
            kind = "finite, free end"
        how = "" if self.reading == "segment" else ", sample reading"
        if self.ok:
            margin = "" if self.robustness is None else f", achieved margin {self.robustness:.4g}"
            return f"mission holds ({kind}{how}{margin})"
        return f"mission VIOLATED ({kind}{how}) at step {self.step}: {self.reason}"

    def to_json_dict(self) -> dict:
        return {
            "ok": self.ok,
            "semantics": self.semantics,
            "loop_start": self.loop_start,
            "step": self.step,
            "reason": self.reason,
            "letters": [list(a) for a in self.letters],
            "reading": self.reading,
            "end": self.end,
            "robustness": self.robustness,
            "margins": dict(self.margins),
        }


def check_mission(
    problem: ReachProblem,
    trajectory: Trajectory,
    loop_start: int | None = None,
    *,
    tol: float = 1e-6,
    reading: str | None = None,
    end: str | None = None,
) -> MissionReport:
    """Evaluate the problem's mission on ``trajectory`` (finite, or a lasso with
    ``x_N = x_loop_start``) in the problem's reading and end (or those given); see the
    module doc."""
    if problem.mission is None:
        raise ValueError("the problem has no mission")
    reading = problem.reading if reading is None else reading
    end = problem.end if end is None else end
    if reading not in MISSION_READINGS or end not in MISSION_ENDS:
        raise ValueError(f"unknown reading {reading!r} or end {end!r}")
    X = trajectory.states
    P = problem.position_of(X)
    N = len(X) - 1
    semantics = "finite" if loop_start is None else "lasso"
    labels = {n: Label(s) for n, s in problem.mission_labels.items()}  # each label's geometry once
    margins = {n: problem.label_margin(n) for n in labels}
    shown: tuple[tuple[str, ...], ...] = ()

    def fail(step: int | None, reason: str, rho: float | None = None) -> MissionReport:
        return MissionReport(False, semantics, loop_start, step, reason, shown, reading, end, rho, margins)

    if loop_start is not None:
        if isinstance(loop_start, bool) or not isinstance(loop_start, (int, np.integer)) or not 0 <= loop_start < N:
            return fail(None, f"loop start {loop_start!r} is not a step in 0..{N - 1}")
        gap = np.abs(X[N] - X[loop_start])
        err = float(np.max(gap))
        if np.any(gap > component_tolerance(X[loop_start], tol)):
            return fail(N, f"the loop does not close: |x_{N} - x_{loop_start}|_inf = {err:.3g}")
    elif end == "rest" and not can_rest(problem, X[N], tol):
        return fail(
            N,
            f"the plan cannot end at x_{N}: no admissible input keeps the robot there, and a finite "
            "plan ending at rest stays at its last state",
        )
    letters, values = trajectory_word(problem, P, loop_start, tol, reading=reading, labels=labels)
    shown = _shown(letters, labels, loop_start, N)
    word, valued = _words(letters, values, loop_start, end)
    formula = nnf(parse(problem.mission))
    rho = _finite(robustness(formula, valued))
    f = _literal_form(formula)
    if not holds(f, word):  # fails even with every boundary touch read both ways
        step, lit = first_failure(f, word, 0)
        return fail(step, failure_reason(lit, step, reading, P, N, values, margins, labels, loop_start), rho)
    reading_found = consistent_reading(f, word)
    if reading_found is None:
        touched = sorted({t for t, a in enumerate(word.letters) for n in labels if n in a and NEG + n in a})
        return fail(
            touched[0],
            "no consistent reading of the boundary touches satisfies the mission "
            f"(the robot touches a label's boundary at steps {', '.join(map(str, touched))})",
            rho,
        )
    shown = _shown(list(reading_found.letters), labels, loop_start, N)
    return MissionReport(True, semantics, loop_start, None, None, shown, reading, end, rho, margins)


def _finite(x: float) -> float | None:
    """A margin as reported: None when infinite (no label read), 0 within rounding."""
    if not math.isfinite(x):
        return None
    return 0.0 if abs(x) < 1e-9 else float(x)


def _words(letters, values, loop_start: int | None, end: str):
    """The word of the letters, and that of the margins, for the plan's shape."""
    if loop_start is not None:
        k = loop_start
        return Lasso(tuple(letters[:k]), tuple(letters[k:])), Lasso(tuple(values[:k]), tuple(values[k:]))
    if end == "free":
        return FiniteWord(tuple(letters)), FiniteWord(tuple(values))
    return Lasso(tuple(letters[:-1]), (letters[-1],)), Lasso(tuple(values[:-1]), (values[-1],))


def _shown(letters, labels, loop_start: int | None, N: int) -> tuple[tuple[str, ...], ...]:
    """The labels that hold at each step 0..N (step N of a lasso is step k)."""
    out = [tuple(sorted(n for n in labels if n in a)) for a in letters]
    if loop_start is not None:
        out.append(out[loop_start])
    return tuple(out[: N + 1])


def can_rest(problem: ReachProblem, x: np.ndarray, tol: float = 1e-6) -> bool:
    """Some input u with |u|_inf <= the bound keeps the state x where it is:
    each row of x - (A x + B u) within tol max(1, sum_j |A_ij x_j| + sum_j |B_ij u_j|)
    (the validator's dynamics tolerance).
    A finite plan ending at rest needs it: the robot stays at its last state forever. The
    input tried is the least-squares one, B^+ (x - A x): exact when B has full column rank
    (every named model, and the random robots), where it is the only one that fits;
    with a rank-deficient B another input might fit within the bound where this one
    does not, and the answer is then a conservative no (a valid plan may be rejected,
    an invalid one never accepted).

    >>> from plansynth.reach.families import maze
    >>> can_rest(maze(1), [3.0, 4.0, 0.0, 0.0]), can_rest(maze(1), [3.0, 4.0, 0.5, 0.0])
    (True, False)
    """
    A, B = np.asarray(problem.dynamics.A, float), np.asarray(problem.dynamics.B, float)
    x = np.asarray(x, float)
    r = x - A @ x  # B u must equal r
    u = np.linalg.lstsq(B, r, rcond=None)[0] if B.shape[1] else np.zeros(0)
    fits = bool(np.all(np.abs(B @ u - r) <= row_tolerance(A, B, x, u, tol)))
    return fits and (not u.size or float(np.max(np.abs(u))) <= problem.input_bound + tol)


def validate_mission_file(
    problem: ReachProblem,
    trajectory: Trajectory,
    result: dict,
    *,
    segment_safe: bool = False,
    tol: float = 1e-6,
) -> tuple[bool, list[str]]:
    """``plansynth reach validate`` for a mission: the validator on the problem with its
    obstacle margin (the problem's goal is no constraint then; segments are checked in the
    segment reading, and when ``segment_safe``) and :func:`check_mission`, with the loop
    start read from the result file's ``mission.loop_start`` (absent: a finite plan).
    (ok, lines to print). The result file's fields must have passed
    :func:`check_result_mission` (the CLI's door)."""
    from rich.markup import escape

    from plansynth.reach.validate import validate

    loop_start = (result.get("mission") or {}).get("loop_start")
    report = validate(
        _margin_problem(problem).reach_view(),
        trajectory,
        require_segment_safe=segment_safe or problem.reading == "segment",
        tol=tol,
    )
    shape_ok = not any(v.kind == "shape" for v in report.violations)
    if shape_ok:
        mission = check_mission(problem, trajectory, loop_start, tol=tol)
        ok = report.ok and mission.ok
        said = mission.summary()
    else:
        ok, said = False, "mission not checked (the trajectory does not fit the robot)"
    style = "bold green" if ok else "bold red"
    lines = [f"[{style}]{'valid' if ok else 'INVALID'}[/{style}]: {escape(report.summary())}; {escape(said)}"]
    lines += [f"  {escape(str(v))}" for v in report.violations[:50]]
    return ok, lines


def check_result_mission(result: dict, horizon: int, source: str | None) -> None:
    """The ``mission`` record of a result file at the door of ``reach validate``: a
    mapping whose ``loop_start``, if given, is a step 0..N-1 (an integer, not a
    boolean); raises :class:`~plansynth.errors.InvalidProblem` naming the field."""
    from plansynth.errors import InvalidProblem
    from plansynth.io import show

    raw = result.get("mission")
    if raw is None:
        return
    if not isinstance(raw, dict):
        raise InvalidProblem(source, "mission", f"expected a mapping (formula, loop_start, ...), got {show(raw)}")
    k = raw.get("loop_start")
    if k is not None and (isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < max(horizon, 0)):
        steps = f"0..{horizon - 1}" if horizon > 0 else "none (a plan of one state has no loop)"
        raise InvalidProblem(source, "mission.loop_start", f"expected a step in {steps} or null, got {show(k)}")


def _margin_problem(problem: ReachProblem) -> ReachProblem:
    """The obstacles grown by the obstacle margin (each edge pushed out, corners mitred:
    :mod:`plansynth.reach.offsets`, the definition the format documents)."""
    if problem.obstacle_margin <= 0:
        return problem
    from dataclasses import replace

    from plansynth.reach.offsets import grown

    return replace(problem, obstacles=tuple(grown(o, problem.obstacle_margin) for o in problem.obstacles))
