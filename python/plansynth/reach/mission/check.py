"""The independent mission checker.

It knows the problem (labels, mission) and the trajectory, and nothing of the planner:
no regions, no encoding. It recomputes the labels from the geometry (shapely) and
evaluates the mission with :func:`plansynth.reach.mission.ltl.holds` (the direct semantics,
not the BMC encoding).

**The word of a trajectory.** Labels are closed sets, and a robot that touches a
label's boundary may be read as in or as out of it (as touching an obstacle is no
collision): at step t, ``a`` may hold when the position lies in the label (within
``tol``), ``!a`` may hold when it is not in the label's interior deeper than ``tol``;
which of the two a touch is, is fixed once per step (below).
Along a segment the labels are those of its first sample: for t < N, letter t is read
off the whole segment [p_t, p_{t+1}] (``a`` may hold when the segment lies in the label,
``!a`` when it avoids the interior), and a segment that goes from outside a label into
its interior or back is a violation (``crossing``), since its labels change between
samples. The last letter of a finite plan is its last position, held forever, so the
robot must be able to hold it: some admissible input keeps x_N where it is
(:func:`can_rest`; for the integrator models, every derivative is 0 there); a lasso
with loop start k (x_N = x_k within tol, else a ``loop`` violation) is the word of
positions 0..N-1 whose successor of N-1 is k.

The mission, in negation normal form, holds when some *consistent reading* of the
boundary touches satisfies it: at each step, each label the robot only touches is read
as in or as out, once for every literal of that step (the planner's word fixes each
touch one way, so it is such a reading). "May hold" for every literal at once is the
quick upper bound: a mission that fails under it fails under every reading, and when
no letter is ambiguous the two coincide; otherwise :func:`consistent_reading` decides
whether a reading exists, by a SAT encoding of the lasso semantics (CaDiCaL). So
``F a & G !a`` fails on a trajectory that only touches ``a``, which the "may hold"
reading alone would accept.

**The first failing step.** When the mission fails, :func:`check_mission` descends the
formula from position 0 (a conjunction into a failing conjunct, ``G f`` into the first
step where f fails, ``a U b`` into the first step where a fails before b, a label
literal to its step) and names the step where the descent ends; ``F f`` that never
holds fails at the first position of the loop, after which no future remains unseen.

>>> from plansynth.reach.fileformat import reach_problem_from_dict
>>> from plansynth.reach.trajectory import Trajectory
>>> p = reach_problem_from_dict({"workspace": {"min": [0, 0], "max": [4, 4]},
...     "labels": {"s": {"min": [1, 0], "max": [2, 4]}}, "mission": "G !s",
...     "robot": {"dynamics": {"model": "single-integrator", "dt": 1}, "start": [0.5, 0.5],
...               "input_bound": 2}})
>>> r = check_mission(p, Trajectory([[0.5, 0.5], [0.5, 2], [3, 2]], [[0, 1.5], [2.5, 0]]))
>>> r.ok, r.step, r.reason
(False, 1, 'segment 1 crosses into label s')
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Point
from shapely.geometry import Polygon as ShPolygon

from plansynth.reach.geometry import Box
from plansynth.reach.mission.ltl import (
    And,
    Const,
    Finally,
    Formula,
    Globally,
    Lasso,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
    holds,
    holds_at,
    nnf,
    parse,
)
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory
from plansynth.reach.validate import component_tolerance, row_tolerance

__all__ = ["MissionReport", "can_rest", "check_mission", "consistent_reading", "trajectory_word"]

NEG = "!"  # letters hold "a" (a may hold) and "!a" (not a may hold)


@dataclass(frozen=True)
class MissionReport:
    """``ok``: the mission holds on the trajectory's word; ``step``/``reason``: where
    and why it fails (None when ok); ``semantics``: finite or lasso; ``letters``: the
    labels inside which the robot is at each step (for reports and pictures)."""

    ok: bool
    semantics: str
    loop_start: int | None
    step: int | None
    reason: str | None
    letters: tuple[tuple[str, ...], ...]

    def __bool__(self) -> bool:
        raise TypeError("a MissionReport has no truth value; read .ok")

    def summary(self) -> str:
        kind = self.semantics if self.loop_start is None else f"lasso (loop from step {self.loop_start})"
        if self.ok:
            return f"mission holds ({kind})"
        return f"mission VIOLATED ({kind}) at step {self.step}: {self.reason}"

    def to_json_dict(self) -> dict:
        return {
            "ok": self.ok,
            "semantics": self.semantics,
            "loop_start": self.loop_start,
            "step": self.step,
            "reason": self.reason,
            "letters": [list(a) for a in self.letters],
        }


class _Label:
    def __init__(self, shape, tol: float) -> None:
        if isinstance(shape, Box):
            g = shapely.box(shape.lo[0], shape.lo[1], shape.hi[0], shape.hi[1])
        else:
            g = ShPolygon(shape.vertices)
        self.closed = g.buffer(tol, join_style="mitre")
        inner = g.buffer(-tol, join_style="mitre")
        self.inner = inner
        shapely.prepare(self.closed)
        if not inner.is_empty:
            shapely.prepare(inner)

    def covers(self, geom) -> bool:
        return bool(self.closed.covers(geom))

    def enters(self, geom) -> bool:
        return (not self.inner.is_empty) and bool(shapely.relate_pattern(self.inner, geom, "T********"))


def trajectory_word(
    problem: ReachProblem,
    positions: np.ndarray,
    loop_start: int | None,
    tol: float = 1e-6,
    *,
    labels: dict | None = None,
):
    """The letters (sets of "may hold" literals) of the trajectory's word, and the first
    segment crossing, as ``(letters, crossing)`` with ``crossing = (step, label, into)``
    or None. A lasso's word has N letters (position N is position k again). ``labels``:
    the labels' geometry (name -> ``_Label``), if the caller has built it."""
    if labels is None:
        labels = {n: _Label(s, tol) for n, s in problem.mission_labels.items()}
    N = len(positions) - 1
    last = N - 1 if loop_start is not None else N
    geoms = []
    for t in range(last + 1):
        p = positions[t]
        geom = Point(p[0], p[1]) if t == N else LineString([tuple(p[:2]), tuple(positions[t + 1][:2])])
        if t < N and np.allclose(positions[t], positions[t + 1], rtol=0, atol=0):
            geom = Point(p[0], p[1])
        geoms.append(geom)
    # each label's predicates over all the samples and segments at once (shapely's
    # vectorised predicates: the same answers as one call per geometry)
    garr = np.array(geoms, dtype=object)
    covers = {n: np.asarray(shapely.covers(lab.closed, garr), dtype=bool) for n, lab in labels.items()}
    enter = {
        n: (
            np.zeros(len(geoms), dtype=bool)
            if lab.inner.is_empty
            else np.asarray(shapely.relate_pattern(lab.inner, garr, "T********"), dtype=bool)
        )
        for n, lab in labels.items()
    }
    letters, crossing = [], None
    for t in range(last + 1):
        p = positions[t]
        letter = set()
        for n, lab in labels.items():
            inside, enters = bool(covers[n][t]), bool(enter[n][t])
            if inside:
                letter.add(n)
            if not enters:
                letter.add(NEG + n)
            if not inside and enters and crossing is None:
                pt = Point(p[0], p[1])
                into = not lab.enters(pt)
                crossing = (t, n, into)
                letter.add(n)
                letter.add(NEG + n)
        letters.append(frozenset(letter))
    return letters, crossing


def _literal_form(f: Formula) -> Formula:
    """NNF with ``!a`` turned into the proposition "!a" (read off the letters)."""
    if isinstance(f, Not):
        return Prop(NEG + f.arg.name)
    if isinstance(f, (Const, Prop)):
        return f
    if isinstance(f, (Next, Finally, Globally)):
        return type(f)(_literal_form(f.arg))
    return type(f)(_literal_form(f.left), _literal_form(f.right))


def check_mission(
    problem: ReachProblem, trajectory: Trajectory, loop_start: int | None = None, *, tol: float = 1e-6
) -> MissionReport:
    """Evaluate the problem's mission on ``trajectory`` (finite, or a lasso with
    ``x_N = x_loop_start``); see the module doc for the reading."""
    if problem.mission is None:
        raise ValueError("the problem has no mission")
    X = trajectory.states
    P = problem.position_of(X)
    N = len(X) - 1
    semantics = "finite" if loop_start is None else "lasso"
    labels = {n: _Label(s, tol) for n, s in problem.mission_labels.items()}  # each label's geometry once
    points = np.array([Point(p[0], p[1]) for p in P], dtype=object)
    inside = {
        n: (
            np.zeros(len(P), dtype=bool)
            if lab.inner.is_empty
            else np.asarray(shapely.relate_pattern(lab.inner, points, "T********"), dtype=bool)
        )
        for n, lab in labels.items()
    }
    shown = tuple(tuple(sorted(n for n in labels if inside[n][t])) for t in range(len(P)))

    def fail(step: int | None, reason: str) -> MissionReport:
        return MissionReport(False, semantics, loop_start, step, reason, shown)

    if loop_start is not None:
        if not 0 <= loop_start < N:
            return fail(None, f"loop start {loop_start} outside 0..{N - 1}")
        gap = np.abs(X[N] - X[loop_start])
        err = float(np.max(gap))
        if np.any(gap > component_tolerance(X[loop_start], tol)):
            return fail(N, f"the loop does not close: |x_{N} - x_{loop_start}|_inf = {err:.3g}")
    elif not can_rest(problem, X[N], tol):
        return fail(
            N,
            f"the plan cannot end at x_{N}: no admissible input keeps the robot there, and a finite "
            "plan's robot stays at its last state",
        )
    letters, crossing = trajectory_word(problem, P, loop_start, tol, labels=labels)
    if crossing is not None:
        t, name, into = crossing
        return fail(t, f"segment {t} crosses {'into' if into else 'out of'} label {name}")
    if loop_start is None:
        word = Lasso(tuple(letters[:-1]), (letters[-1],))
    else:
        word = Lasso(tuple(letters[:loop_start]), tuple(letters[loop_start:]))
    f = _literal_form(nnf(parse(problem.mission)))
    if not holds(f, word):  # fails even with every boundary touch read both ways
        step, reason = _first_failure(f, word, 0)
        return fail(step, reason)
    if consistent_reading(f, word) is None:
        touched = sorted({t for t, a in enumerate(word.letters) for n in labels if n in a and NEG + n in a})
        return fail(
            touched[0],
            "no consistent reading of the boundary touches satisfies the mission "
            f"(the robot touches a label's boundary at steps {', '.join(map(str, touched))})",
        )
    return MissionReport(True, semantics, loop_start, None, None, shown)


def can_rest(problem: ReachProblem, x: np.ndarray, tol: float = 1e-6) -> bool:
    """Some input u with |u|_inf <= the bound keeps the state x where it is:
    each row of x - (A x + B u) within tol max(1, sum_j |A_ij x_j| + sum_j |B_ij u_j|)
    (the validator's dynamics tolerance).
    The finite reading needs it: the robot stays at its last state forever. The input
    tried is the least-squares one, B^+ (x - A x): exact when B has full column rank
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


def consistent_reading(f: Formula, word: Lasso) -> Lasso | None:
    """A consistent reading of the "may hold" word that satisfies ``f`` (NNF, with
    ``!a`` as the proposition "!a", as :func:`_literal_form` writes it), or None when
    there is none. A reading keeps, at each position, exactly one of ``a`` and ``!a``
    for every label the letter has both of (and the letter's other literals); the
    result's letters are those readings, so :func:`holds` can confirm it.

    No ambiguous letter: the word itself (when f holds on it). Otherwise the two uniform
    readings (every touch in, every touch out), then SAT over one variable per
    ambiguous (position, label): each subformula gets one literal per lasso position,
    defined by exact (two-sided) Tseitin gates; ``a U b`` on a loop position i is
    ``OR_j (b_{i+j} & a_i & ... & a_{i+j-1})`` over one turn of the loop (a witness
    that exists lies within one turn), on a prefix position ``b_i | (a_i & (a U b)_{i+1})``;
    ``a R b`` is ``!(!a U !b)``, ``F`` and ``G`` are ``U`` and ``R`` with a constant.

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

    def reading(value) -> Lasso:
        out = [set(a) for a in letters]
        for i, n in ambiguous:
            out[i].discard(NEG + n if value(i, n) else n)
        k = len(word.prefix)
        return Lasso(tuple(out[:k]), tuple(out[k:]))

    for uniform in (True, False):
        w = reading(lambda i, n, u=uniform: u)
        if holds(f, w):
            return w
    from pysat.solvers import Solver

    n_pos, k = len(letters), len(word.prefix)
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
            out[i] = gate([b[i], gate([a[i], out[i + 1]], True)], False)
        return out

    memo: dict[Formula, list[int]] = {}

    def enc(g: Formula) -> list[int]:
        if g in memo:
            return memo[g]
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
            v = [gate([x, y], isinstance(g, And)) for x, y in zip(enc(g.left), enc(g.right))]
        elif isinstance(g, Next):
            a = enc(g.arg)
            v = [a[word.successor(i)] for i in range(n_pos)]
        elif isinstance(g, (Finally, Until)):
            a = [TRUE] * n_pos if isinstance(g, Finally) else enc(g.left)
            v = until(a, enc(g.arg if isinstance(g, Finally) else g.right))
        elif isinstance(g, (Globally, Release)):
            a = [-TRUE] * n_pos if isinstance(g, Globally) else enc(g.left)
            b = enc(g.arg if isinstance(g, Globally) else g.right)
            v = [-x for x in until([-x for x in a], [-x for x in b])]
        else:
            raise TypeError(f"not in negation normal form: {g!r}")
        memo[g] = v
        return v

    clauses.append([enc(f)[0]])
    with Solver(name="cadical195", bootstrap_with=clauses) as solver:
        if not solver.solve():
            return None
        model = set(solver.get_model())
    return reading(lambda i, n: var[(i, n)] in model)


def _first_failure(f: Formula, word: Lasso, i: int) -> tuple[int, str]:
    n = len(word.letters)

    def val(g: Formula) -> list[bool]:
        return holds_at(g, word)

    if isinstance(f, Const):
        return i, "false"
    if isinstance(f, Prop):
        if f.name.startswith(NEG):
            return i, f"in label {f.name[1:]}"
        return i, f"not in label {f.name}"
    if isinstance(f, And):
        sub = f.left if not val(f.left)[i] else f.right
        return _first_failure(sub, word, i)
    if isinstance(f, Or):
        a, b = _first_failure(f.left, word, i), _first_failure(f.right, word, i)
        return max(a, b, key=lambda x: x[0])
    if isinstance(f, Next):
        return _first_failure(f.arg, word, word.successor(i))
    if isinstance(f, (Globally, Release)):
        b = f.arg if isinstance(f, Globally) else f.right
        vb = val(b)
        j, seen = i, set()
        while j not in seen:
            seen.add(j)
            if not vb[j]:
                return _first_failure(b, word, j)
            j = word.successor(j)
        return i, f"{f} fails"  # pragma: no cover - R fails only where b fails
    if isinstance(f, (Finally, Until)):
        b = f.arg if isinstance(f, Finally) else f.right
        va = [True] * n if isinstance(f, Finally) else val(f.left)
        j, seen = i, set()
        while j not in seen:
            seen.add(j)
            if not va[j]:
                return _first_failure(f.left, word, j)
            j = word.successor(j)
        return len(word.prefix), f"{b} never holds (checked through the loop from step {len(word.prefix)})"
    raise TypeError(f"not in negation normal form: {f!r}")  # pragma: no cover


def validate_mission_file(
    problem: ReachProblem, trajectory: Trajectory, result: dict, *, segment_safe: bool = False, tol: float = 1e-6
) -> tuple[bool, list[str]]:
    """``plansynth reach validate`` for a mission: the validator (the problem's goal
    is no constraint then) and :func:`check_mission`, with the loop start read from the
    result file's ``mission.loop_start`` (absent: a finite plan). (ok, lines to print)."""
    from dataclasses import replace

    from rich.markup import escape

    from plansynth.reach.validate import validate

    loop_start = (result.get("mission") or {}).get("loop_start")
    report = validate(replace(problem, goal=problem.workspace), trajectory, require_segment_safe=segment_safe, tol=tol)
    mission = check_mission(problem, trajectory, loop_start, tol=tol)
    ok = report.ok and mission.ok
    style = "bold green" if ok else "bold red"
    lines = [
        f"[{style}]{'valid' if ok else 'INVALID'}[/{style}]: {escape(report.summary())}; {escape(mission.summary())}"
    ]
    lines += [f"  {escape(str(v))}" for v in report.violations[:50]]
    return ok, lines
