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
import shapely
from shapely.geometry import LineString
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.geometry import Box, halfspaces, is_convex
from plansynth.reach.mission.ltl import (
    And,
    Const,
    Finally,
    FiniteWord,
    Formula,
    Globally,
    Lasso,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
    WeakNext,
    children,
    holds,
    holds_at,
    nnf,
    parse,
    robustness,
    subformulas,
    unroll,
)
from plansynth.reach.problem import MISSION_ENDS, MISSION_READINGS, ReachProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import component_tolerance, row_tolerance

__all__ = ["MissionReport", "can_rest", "check_mission", "consistent_reading", "trajectory_word", "NEG"]

NEG = "!"  # letters hold "a" (a may hold) and "!a" (not a may hold)


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


# --------------------------------------------------------------------------- the labels' margins


class _Label:
    """One label's geometry: its half-planes when convex, shapely's polygon otherwise."""

    def __init__(self, shape) -> None:
        self.convex = is_convex(shape)
        if self.convex:
            self.H, self.h = halfspaces(shape)
        if isinstance(shape, Box):
            self.geom = shapely.box(shape.lo[0], shape.lo[1], shape.hi[0], shape.hi[1])
        else:
            self.geom = ShPolygon(shape.vertices)
        shapely.prepare(self.geom)

    def at_points(self, P: np.ndarray) -> np.ndarray:
        """The margin of ``a`` at each point (that of ``!a`` is its negative)."""
        if self.convex:
            return np.min(self.h[None, :] - P @ self.H.T, axis=1)
        pts = shapely.points(P)
        d = shapely.distance(self.geom.boundary, pts)
        inside = shapely.contains(self.geom, pts)
        return np.where(inside, d, -d)

    def along(self, p: np.ndarray, q: np.ndarray) -> tuple[float, float]:
        """(the least margin of ``a``, the least margin of ``!a``) along [p, q]."""
        if np.array_equal(p, q):
            v = float(self.at_points(p[None, :])[0])
            return v, -v
        if self.convex:
            a = float(min(np.min(self.h - self.H @ p), np.min(self.h - self.H @ q)))
            return a, _min_of_max(self.H @ p - self.h, self.H @ (q - p))
        seg = LineString([tuple(p), tuple(q)])
        P = np.array([p, q])
        ends = self.at_points(P)
        inside, boundary = self.geom.covers(seg), self.geom.boundary
        if inside:
            a = float(shapely.distance(boundary, seg))
        else:  # leaves the label: the farthest of the endpoints and of the parts outside
            out = seg.difference(self.geom)
            pts = np.array([c for part in shapely.get_parts(out) for c in part.coords] or [p])
            a = -max(float(np.max(-self.at_points(pts))), 1e-300)
        if not shapely.relate_pattern(self.geom, seg, "T********"):
            na = float(shapely.distance(self.geom, seg))
        else:  # enters its interior: the deepest of the endpoints and of the parts inside
            part_in = seg.intersection(self.geom)
            pts = np.array([c for part in shapely.get_parts(part_in) for c in getattr(part, "coords", [])] or [p])
            mids = (pts[:-1] + pts[1:]) / 2 if len(pts) > 1 else pts
            na = -max(float(np.max(self.at_points(np.vstack([pts, mids])))), float(np.max(ends)), 1e-300)
        return a, na


def _min_of_max(c: np.ndarray, d: np.ndarray) -> float:
    """min over s in [0, 1] of max_i (c_i + d_i s): a convex piecewise-linear function,
    least at an end or where two of its lines cross."""
    cand = [0.0, 1.0]
    for i in range(len(c)):
        for j in range(i + 1, len(c)):
            if d[i] != d[j]:
                s = (c[j] - c[i]) / (d[i] - d[j])
                if 0.0 < s < 1.0:
                    cand.append(float(s))
    S = np.array(cand)
    return float(np.min(np.max(c[None, :] + d[None, :] * S[:, None], axis=1)))


def _step_margins(
    problem: ReachProblem, P: np.ndarray, loop_start: int | None, reading: str, labels: dict[str, _Label]
) -> list[dict[str, float]]:
    """Per step of the word, each literal's margin (``"a"`` and ``"!a"``)."""
    N = len(P) - 1
    last = N - 1 if loop_start is not None else N
    out: list[dict[str, float]] = [{} for _ in range(last + 1)]
    for n, lab in labels.items():
        if reading == "sample":
            depth = lab.at_points(P[: last + 1])
            for t in range(last + 1):
                out[t][n], out[t][NEG + n] = float(depth[t]), float(-depth[t])
            continue
        for t in range(last + 1):
            if t < N:
                a, na = lab.along(P[t], P[t + 1])
            else:
                d = float(lab.at_points(P[t][None, :])[0])
                a, na = d, -d
            out[t][n], out[t][NEG + n] = a, na
    return out


def trajectory_word(
    problem: ReachProblem,
    positions: np.ndarray,
    loop_start: int | None,
    tol: float = 1e-6,
    *,
    reading: str | None = None,
    labels: dict | None = None,
) -> tuple[list[frozenset[str]], list[dict[str, float]]]:
    """The letters (sets of "may hold" literals: ``a`` when its margin is >= the label's
    margin - tol, ``!a`` likewise) of the trajectory's word in the reading (default: the
    problem's), and each step's margins. A lasso's word has N letters (position N is
    position k again). ``labels``: the labels' geometry (name -> ``_Label``), if the
    caller has built it."""
    reading = problem.reading if reading is None else reading
    if labels is None:
        labels = {n: _Label(s) for n, s in problem.mission_labels.items()}
    P = np.asarray(positions, float)[:, :2]
    values = _step_margins(problem, P, loop_start, reading, labels)
    letters = []
    for v in values:
        letter = set()
        for n in labels:
            r = problem.label_margin(n)
            if v[n] >= r - tol:
                letter.add(n)
            if v[NEG + n] >= r - tol:
                letter.add(NEG + n)
        letters.append(frozenset(letter))
    return letters, values


def _literal_form(f: Formula) -> Formula:
    """NNF with ``!a`` turned into the proposition "!a" (read off the letters); iterative."""
    done: dict[Formula, Formula] = {}
    for g in subformulas(f):
        if isinstance(g, Not):
            done[g] = Prop(NEG + g.arg.name)
        elif not children(g):
            done[g] = g
        else:
            kids = [done[c] for c in children(g)]
            fields = [getattr(g, k) for k in ("lo", "hi") if hasattr(g, k)]
            done[g] = type(g)(*fields, *kids)
    return done[f]


# --------------------------------------------------------------------------- the check


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
    labels = {n: _Label(s) for n, s in problem.mission_labels.items()}  # each label's geometry once
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
        step, lit = _first_failure(f, word, 0)
        return fail(step, _why(lit, step, reading, P, N, values, margins, labels, loop_start), rho)
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


def _why(lit: str | None, step: int, reading: str, P, N: int, values, margins, labels, loop_start) -> str:
    """The reason a literal fails at a step, from the geometry there."""
    if lit is None:
        return "false"
    if lit.startswith(("never:", "text:")):
        return lit.split(":", 1)[1]
    neg = lit.startswith(NEG)
    name = lit[len(NEG) :] if neg else lit
    v = values[step]
    r = margins[name]
    here = v[lit]
    start_depth = float(labels[name].at_points(np.asarray(P[step : step + 1], float)[:, :2])[0])
    segment = reading == "segment" and step < N
    if neg:
        if here > -1e-9 and r > 0:
            return f"within the margin {r:g} of label {name} (distance {here:.3g})"
        if segment and start_depth <= 0:
            return f"segment {step} crosses into label {name}"
        return f"in label {name}"
    if here > -1e-9 and r > 0:
        return f"in label {name} at depth {here:.3g}, below its margin {r:g}"
    if segment and start_depth >= 0:
        return f"segment {step} crosses out of label {name}"
    return f"not in label {name}"


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


def consistent_reading(f: Formula, word: Lasso | FiniteWord) -> Lasso | FiniteWord | None:
    """A consistent reading of the "may hold" word that satisfies ``f`` (NNF, with
    ``!a`` as the proposition "!a", as :func:`_literal_form` writes it), or None when
    there is none. A reading keeps, at each position, exactly one of ``a`` and ``!a``
    for every label the letter has both of (and the letter's other literals); the
    result's letters are those readings, so :func:`holds` can confirm it.

    No ambiguous letter: the word itself (when f holds on it). Otherwise the two uniform
    readings (every touch in, every touch out), then SAT over one variable per
    ambiguous (position, label), on the formula with its bounded operators unrolled:
    each subformula gets one literal per position, defined by exact (two-sided) Tseitin
    gates; ``a U b`` on a loop position i is ``OR_j (b_{i+j} & a_i & ... & a_{i+j-1})``
    over one turn of the loop (a witness that exists lies within one turn), on a prefix
    position ``b_i | (a_i & (a U b)_{i+1})``, past the end of a finite word false;
    ``a R b`` is ``!(!a U !b)``, ``F`` and ``G`` are ``U`` and ``R`` with a constant; ``X``
    is false past the end of a finite word, its weak dual true.

    >>> w = Lasso((), (frozenset({"a", "!a"}),))   # the robot rests on a's boundary
    >>> consistent_reading(_literal_form(nnf(parse("F a & G !a"))), w) is None
    True
    >>> consistent_reading(_literal_form(nnf(parse("F a"))), w).loop
    (frozenset({'a'}),)
    """
    letters = word.letters
    ambiguous = sorted(
        {(i, n[len(NEG) :]) for i, a in enumerate(letters) for n in a if n.startswith(NEG) and n[len(NEG) :] in a}
    )
    if not ambiguous:
        return word if holds(f, word) else None
    finite = isinstance(word, FiniteWord)

    def reading(value) -> Lasso | FiniteWord:
        out = [set(a) for a in letters]
        for i, n in ambiguous:
            out[i].discard(NEG + n if value(i, n) else n)
        if finite:
            return FiniteWord(tuple(out))
        k = len(word.prefix)
        return Lasso(tuple(out[:k]), tuple(out[k:]))

    for uniform in (True, False):
        w = reading(lambda i, n, u=uniform: u)
        if holds(f, w):
            return w
    from pysat.solvers import Solver

    n_pos = len(letters)
    k = n_pos if finite else len(word.prefix)
    m = n_pos - k
    TRUE = 1
    clauses: list[list[int]] = [[TRUE]]
    top = [TRUE]

    def new() -> int:
        top[0] += 1
        return top[0]

    var = {key: new() for key in ambiguous}

    def gate(xs: list[int], conj: bool) -> int:
        xs = [x for x in xs if x != (TRUE if conj else -TRUE)]
        if (-TRUE if conj else TRUE) in xs:
            return -TRUE if conj else TRUE
        if not xs:
            return TRUE if conj else -TRUE
        if len(xs) == 1:
            return xs[0]
        v = new()
        s = 1 if conj else -1  # conj: v -> x for all x, (all x) -> v; disj: the dual
        clauses.extend([-s * v, s * x] for x in xs)
        clauses.append([s * v] + [-s * x for x in xs])
        return v

    def until(a: list[int], b: list[int]) -> list[int]:
        out = [0] * n_pos
        for i in range(k, n_pos):
            terms, chain = [], TRUE
            for j in range(m):
                p = k + (i - k + j) % m
                terms.append(gate([chain, b[p]], True))
                chain = gate([chain, a[p]], True)
            out[i] = gate(terms, False)
        for i in range(k - 1, -1, -1):
            later = out[i + 1] if i + 1 < n_pos else -TRUE  # past a finite word's end: no witness
            out[i] = gate([b[i], gate([a[i], later], True)], False)
        return out

    enc: dict[Formula, list[int]] = {}
    for g in subformulas(unroll(f)):
        if isinstance(g, Const):
            v = [TRUE if g.value else -TRUE] * n_pos
        elif isinstance(g, Prop):
            neg = g.name.startswith(NEG)
            name = g.name[len(NEG) :] if neg else g.name
            v = []
            for i, a in enumerate(letters):
                lit = var[(i, name)] if (i, name) in var else (TRUE if g.name in a else -TRUE)
                v.append(-lit if neg and (i, name) in var else lit)
        elif isinstance(g, (And, Or)):
            v = [gate([x, y], isinstance(g, And)) for x, y in zip(enc[g.left], enc[g.right])]
        elif isinstance(g, (Next, WeakNext)):
            a = enc[g.arg]
            past = -TRUE if isinstance(g, Next) else TRUE
            v = [past if word.successor(i) is None else a[word.successor(i)] for i in range(n_pos)]
        elif isinstance(g, (Finally, Until)):
            a = [TRUE] * n_pos if isinstance(g, Finally) else enc[g.left]
            v = until(a, enc[g.arg if isinstance(g, Finally) else g.right])
        elif isinstance(g, (Globally, Release)):
            a = [-TRUE] * n_pos if isinstance(g, Globally) else enc[g.left]
            b = enc[g.arg if isinstance(g, Globally) else g.right]
            v = [-x for x in until([-x for x in a], [-x for x in b])]
        else:
            raise TypeError(f"not in negation normal form: {type(g).__name__}")
        enc[g] = v
    clauses.append([enc[unroll(f)][0]])
    with Solver(name="cadical195", bootstrap_with=clauses) as solver:
        if not solver.solve():
            return None
        model = set(solver.get_model())
    return reading(lambda i, n: var[(i, n)] in model)


def _first_failure(f: Formula, word: Lasso | FiniteWord, i: int) -> tuple[int, str | None]:
    """(the step where the descent from f at position i ends, the failing literal there,
    or ``"never:<text>"`` / ``"text:<text>"`` for a reason that is no literal). A
    disjunction fails where the last of its disjuncts fails. Iterative (explicit frames
    for the disjunctions)."""
    n = len(word.letters)
    memo: dict[Formula, list[bool]] = {}

    def val(g: Formula) -> list[bool]:
        if g not in memo:
            memo[g] = holds_at(g, word)
        return memo[g]

    def descend(g: Formula, i: int) -> tuple[int, str | None] | tuple[Formula, int, None]:
        """Down to a result, or to a disjunction (returned as (g, i, None))."""
        while True:
            if isinstance(g, Const):
                return i, None
            if isinstance(g, Prop):
                return i, g.name
            if isinstance(g, Or):
                return g, i, None
            if isinstance(g, And):
                g = g.left if not val(g.left)[i] else g.right
                continue
            if isinstance(g, (Next, WeakNext)):
                j = word.successor(i)
                if j is None:
                    return i, f"text:{g} needs a step after the last"
                g, i = g.arg, j
                continue
            if isinstance(g, (Globally, Release)):
                b = g.arg if isinstance(g, Globally) else g.right
                vb = val(b)
                j, seen = i, set()
                while j is not None and j not in seen and vb[j]:
                    seen.add(j)
                    j = word.successor(j)
                if j is None or vb[j]:  # pragma: no cover - R fails only where b fails
                    return i, f"text:{g} fails"
                g, i = b, j
                continue
            if isinstance(g, (Finally, Until)):
                b = g.arg if isinstance(g, Finally) else g.right
                va = [True] * n if isinstance(g, Finally) else val(g.left)
                j, seen = i, set()
                while j is not None and j not in seen and va[j]:
                    seen.add(j)
                    j = word.successor(j)
                if j is not None and not va[j]:
                    g, i = g.left, j
                    continue
                if j is None:
                    return n - 1, f"never:{b} never holds (the plan ends at step {n - 1})"
                return len(
                    word.prefix
                ), f"never:{b} never holds (checked through the loop from step {len(word.prefix)})"
            u = unroll(g)  # a bounded operator: its unrolling names the step
            if u is g:  # pragma: no cover - only bounded operators are left
                raise TypeError(f"not in negation normal form: {type(g).__name__}")
            g = u

    frames: list[list] = []  # [pending (disjunct, position) pairs, best result so far]
    todo: tuple[Formula, int] = (f, i)
    while True:
        got = descend(*todo)
        if got[-1] is None and isinstance(got[0], Or):
            g, at, _ = got
            parts, stack = [], [g]
            while stack:  # the disjuncts of a chain of | (iteratively)
                h = stack.pop()
                if isinstance(h, Or):
                    stack += [h.right, h.left]
                else:
                    parts.append(h)
            frames.append([[(d, at) for d in reversed(parts[1:])], None])
            todo = (parts[0], at)
            continue
        result = got
        while frames:
            frame = frames[-1]
            frame[1] = result if frame[1] is None else max(frame[1], result, key=lambda x: x[0])
            if frame[0]:
                todo = frame[0].pop()
                break
            frames.pop()
            result = frame[1]
        else:
            return result  # type: ignore[return-value]


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
