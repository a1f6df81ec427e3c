"""CON-PLAN: the continuous half of the lazy planner (Shoukry et al., CDC 2016, Section V).

Given a region sequence r_0..r_N from DIS-PLAN, CON-PLAN looks for a trajectory that
follows it, with HiGHS linear programs over x_0..x_N, u_0..u_{N-1}:

* ``x_0 = start``, ``x_{t+1} = A x_t + B u_t``, ``|u_t|_inf <= input_bound``, state
  bounds, positions in the workspace;
* ``H_{r_t} p_t <= h_{r_t}`` (the position at time t lies in region r_t) and, with
  segment safety (the default), ``H_{r_t} p_{t+1} <= h_{r_t}`` too, so the whole
  segment [p_t, p_{t+1}] lies in the convex region r_t: the trajectory is safe between
  samples, not only at them (the paper guarantees samples only);
* ``H_goal p_N <= h_goal`` (and p_N in r_N).

When the sequence is infeasible, CON-PLAN returns a counterexample (Theorem 5.3), a
:class:`~plansynth.reach.lazy.conflict.Conflict`. Three strategies (``counterexample=``):

``zeroprefix`` (default, the paper's): Problem 5.2, the LP with a slack s_t >= 0 on
    every constraint on p_t, ordered ``s_0 <= s_1 <= ... <= s_N`` and minimised
    (``slack_weights="uniform"``: the paper's plain sum; ``"geometric"``, the default:
    weights decaying from 1 to 1e-4 along the horizon, which pushes violations later);
    ZEROPREFIX (Algorithm 2) finds the longest zero-slack prefix 0..k-1 by binary
    search, and the counterexample blocks r_0..r_k at times 0..k. The slack optimum
    only *suggests* that k is the earliest infeasible step (another trajectory might
    realise the prefix 0..k at the price of more slack later), so the prefix is
    confirmed by a feasibility LP, and when it is feasible the earliest infeasible
    prefix is found by binary search (prefix feasibility is monotone). Every clause is
    therefore backed by an infeasible LP: sound.
``trivial``: one feasibility LP; block the whole sequence (at this horizon only).
``iis``: one feasibility LP; on infeasibility, HiGHS's irreducible infeasible subsystem
    (``getIis``); its rows map back to time steps, and only the regions at those steps
    are blocked. The IIS is re-checked by an LP over exactly the constraints the clause
    claims (the whole sequence is blocked if that LP were feasible).

With ``generalize=True`` (beyond the paper), a conflict is shrunk to the support of the
Farkas certificate (dual ray) of its infeasible LP, re-checked in floating point (or by
an LP); with ``minimize=True`` a deletion filter then drops every region literal whose
rows the infeasibility does not need (one warm LP per literal); finally HiGHS tries to
drop the start state: a conflict whose proof uses neither x_0 = start nor the goal
holds at every time shift, and DIS-PLAN adds every shifted copy.

Robustness: a warm start HiGHS refuses is retried from scratch; a simplex run that
stalls (long integrator chains, whose coefficients dt^k/k! span many decades) is
re-solved by the interior-point method on a fresh copy (without a Farkas ray, so that
conflict stays unshrunk); if HiGHS still has no answer the planner says ``unknown``.

**One LP per horizon, edited in place.** All LPs for a horizon N share one layout
(:class:`_Layout`): per time step a block of region rows and a block of segment rows
(padded to the largest region), the goal rows and the slack columns. Which regions
apply, whether the goal, the start and the slacks count, is set through row and
column bounds (a row that does not apply is free), so HiGHS re-solves from the previous
basis (dual simplex warm start); coefficients change only where a time step moves to a
region with a different H. A "prefix" LP is the plan LP with the rows after the prefix
freed: it also asks that the trajectory can continue within the bounds up to N, which
every plan of horizon >= N must do, so its clause holds for every horizon >= N.

**One frame for all horizons.** A HiGHS model holds a *frame* a little longer than the
horizon it was built for; an LP over the states lo..hi of the frame frees the rows on
the other states and moves the goal rows to p_hi, which changes no answer (those
columns are left in no constraining row) but lets the LPs of other horizons and of
conflict spans warm-start instead of solving cold.

**Long integrator chains** (more than 8 states; maze-4 with order 25 has 50): the
coefficients dt^k/k! span many decades and bases are often near-singular, so the
simplex method uses a stronger scaling and Devex pricing (dual steepest-edge weights
were recomputed after every warm start); ZEROPREFIX skips the slack LP (``slack_lp``:
several seconds per call there, without a usable warm start) and finds the earliest
infeasible prefix by binary search, cut short by checked Farkas certificates; and when
the dynamics and every region and goal row are separable (chains in box regions: one
block per axis) the feasibility LPs are split into independent HiGHS models
(``split``), each half the size, whose rays are mapped back to the whole LP.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import highspy
import numpy as np

from plansynth.budget import Clock
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.highs import new_highs
from plansynth.reach.geometry import halfspaces
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

__all__ = [
    "ConPlan",
    "LpBudgetExhausted",
    "LpFailure",
    "LpStats",
    "zero_prefix",
    "COUNTEREXAMPLES",
    "ZERO_SLACK",
]

COUNTEREXAMPLES = ("zeroprefix", "trivial", "iis")
SLACK_WEIGHTS = ("geometric", "uniform")
ZERO_SLACK = 1e-7  # a slack at most this is zero (HiGHS's primal feasibility tolerance)
MINIMIZE_MAX_LITERALS = 16
POLISH_RESIDUAL = 1e-8  # dynamics residual above which a found trajectory is re-solved (validator: 1e-6)
INF = highspy.kHighsInf

# row kinds of the LPs
DYN, REGION, SEGMENT, GOAL, ORDER = range(5)


def zero_prefix(slacks: Sequence[float], tol: float = ZERO_SLACK) -> int:
    """ZEROPREFIX (Algorithm 2): the length k of the longest all-zero prefix of a
    nondecreasing slack vector, by binary search; ``slacks[k]`` is the first nonzero
    slack (k = len(slacks) when all are zero).

    >>> zero_prefix([0, 0, 0, 0.5, 2])
    3
    >>> zero_prefix([0, 0]), zero_prefix([1, 1]), zero_prefix([])
    (2, 0, 0)
    """
    lo, hi = 0, len(slacks)  # slacks[:lo] are zero, slacks[hi:] are nonzero
    while lo < hi:
        mid = (lo + hi) // 2
        if slacks[mid] <= tol:
            lo = mid + 1
        else:
            hi = mid
    return lo


class LpBudgetExhausted(Exception):
    """HiGHS stopped at the time limit; the lazy loop turns this into ``unknown``."""


class LpFailure(Exception):
    """HiGHS gave no answer on an LP (numerical trouble); the lazy loop answers ``unknown``."""


@dataclass
class LpStats:
    """Counters of one CON-PLAN: LP solves by purpose, certificates, seconds in HiGHS."""

    lp_calls: int = 0
    iis_calls: int = 0
    ray_calls: int = 0
    certified: int = 0
    rejected: int = 0
    retries: int = 0
    ipm_fallbacks: int = 0
    slack_failures: int = 0
    polished: int = 0
    seconds: float = 0.0
    by_kind: dict[str, int] = field(default_factory=dict)


@dataclass(frozen=True)
class _Layout:
    """Columns and rows of the CON-PLAN LP over the states x_first..x_last.

    Columns: x_t (n each), u_t (m each, t < last), s_t (one per state). Rows: the
    dynamics (n per step); per time t a block of K rows "p_t in region r_t"; per t <
    last a block of K rows "p_{t+1} in region r_t" (segment safety); the goal block
    "p_last in the goal"; the T-1 slack-order rows ``s_t - s_{t+1} <= 0``.

    The LP may use only a window ``lo..hi`` of this frame (default: all of it): rows on
    states outside the window are free, the goal rows sit on p_hi and the start on x_lo.
    The columns outside the window then appear in no constraining row, so the LP is the
    one of the window's layout exactly, but an LP of another window (another horizon)
    can be loaded into the same HiGHS model in place and warm-started from its basis.
    """

    first: int
    last: int
    n: int
    m: int
    d: int
    K: int
    Kg: int
    lo: int = -1  # the window (-1: the frame's ends)
    hi: int = -1

    @property
    def t0(self) -> int:
        return self.first if self.lo < 0 else self.lo

    @property
    def t1(self) -> int:
        return self.last if self.hi < 0 else self.hi

    @property
    def frame(self) -> tuple[int, ...]:
        return (self.first, self.last, self.n, self.m, self.d, self.K, self.Kg)

    def window(self, lo: int, hi: int) -> "_Layout":
        assert self.first <= lo <= hi <= self.last
        return _Layout(*self.frame, lo, hi)

    @property
    def T(self) -> int:
        return self.last - self.first + 1

    @property
    def steps(self) -> int:
        return self.T - 1

    @property
    def n_x(self) -> int:
        return self.T * self.n

    @property
    def n_u(self) -> int:
        return self.steps * self.m

    @property
    def n_col(self) -> int:
        return self.n_x + self.n_u + self.T

    @property
    def reg0(self) -> int:
        return self.steps * self.n

    @property
    def seg0(self) -> int:
        return self.reg0 + self.T * self.K

    @property
    def goal0(self) -> int:
        return self.seg0 + self.steps * self.K

    @property
    def ord0(self) -> int:
        return self.goal0 + self.Kg

    @property
    def n_row(self) -> int:
        return self.ord0 + self.steps

    def x(self, t: int) -> int:
        return (t - self.first) * self.n

    def s(self, t: int) -> int:
        return self.n_x + self.n_u + (t - self.first)

    @cached_property
    def meta(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per row: its kind, the time of the region literal it belongs to (-1: none),
        and the latest state time it constrains (-1: none)."""
        T, steps, K, n = self.T, self.steps, self.K, self.n
        ts = np.arange(self.first, self.last + 1)
        kind = np.concatenate([np.full(steps * n, DYN), np.full(T * K, REGION), np.full(steps * K, SEGMENT),
                               np.full(self.Kg, GOAL), np.full(steps, ORDER)])
        lit = np.concatenate([np.full(steps * n, -1), np.repeat(ts, K), np.repeat(ts[:-1], K),
                              np.full(self.Kg, -1), np.full(steps, -1)])
        state = np.concatenate([np.repeat(ts[1:], n), np.repeat(ts, K), np.repeat(ts[1:], K),
                                np.full(self.Kg, self.t1), np.full(steps, -1)])
        return kind, lit, state


@dataclass
class _Part:
    """One independent block of a split LP: its rows and columns in the whole LP."""

    highs: highspy.Highs
    rows: np.ndarray
    cols: np.ndarray


@dataclass
class _Slot:
    """A HiGHS instance holding one LP of a layout, edited in place (warm starts).

    With ``parts``, the LP falls apart into independent blocks (for example one per
    axis when the dynamics and every region are separable), each held by a HiGHS
    instance of its own; ``highs`` then only carries the options the parts copy.
    """

    highs: highspy.Highs
    layout: _Layout | None = None
    coef: np.ndarray | None = None  # the region whose H fills each time's blocks
    coo: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    bounds: "_Bounds | None" = None
    held: tuple | None = None  # a description of the LP last solved
    splits: bool = False  # may this slot's LPs be split into parts?
    parts: list[_Part] | None = None
    row_part: np.ndarray | None = None  # per row of the whole LP: its part (-1: in none)
    row_local: np.ndarray | None = None  # and its index there
    col_part: np.ndarray | None = None
    col_local: np.ndarray | None = None
    infeasible_part: int = 0  # the part that was infeasible last (tried first)


@dataclass
class _Bounds:
    row_lo: np.ndarray
    row_hi: np.ndarray
    col_lo: np.ndarray
    col_hi: np.ndarray
    anchored_start: bool


def _csc_lp(n_col: int, n_row: int, R: np.ndarray, C: np.ndarray, V: np.ndarray, cost: np.ndarray,
            col_lo: np.ndarray, col_hi: np.ndarray, row_lo: np.ndarray, row_hi: np.ndarray) -> highspy.HighsLp:
    """A HiGHS LP with the column-wise matrix of the COO entries (R, C, V)."""
    order = np.lexsort((R, C))
    starts = np.zeros(n_col + 1, dtype=np.int32)
    np.cumsum(np.bincount(C, minlength=n_col), out=starts[1:])
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = n_col, n_row
    lp.col_cost_ = cost
    lp.col_lower_, lp.col_upper_ = col_lo, col_hi
    lp.row_lower_, lp.row_upper_ = row_lo, row_hi
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_ = starts
    lp.a_matrix_.index_ = R[order].astype(np.int32)
    lp.a_matrix_.value_ = V[order]
    return lp


@contextmanager
def _options(h: highspy.Highs, options: Mapping[str, Any]) -> Iterator[None]:
    """Set HiGHS ``options`` on ``h`` for the duration of the block, then restore them."""
    saved = {k: h.getOptionValue(k)[1] for k in options}
    for k, v in options.items():
        h.setOptionValue(k, v)
    try:
        yield
    finally:
        for k, v in saved.items():
            h.setOptionValue(k, v)


class ConPlan:
    """The theory solver of the lazy loop for one problem and abstraction.

    ``check(regions)`` returns :class:`Feasible` or a sound
    :class:`~plansynth.reach.lazy.conflict.Conflict`. ``slack_lp`` (ZEROPREFIX's slack LP)
    and ``split`` (independent LP blocks) default to what suits the state dimension:
    slack LP up to 8 states, split beyond.
    """

    def __init__(
        self,
        problem: ReachProblem,
        abstraction: Abstraction,
        *,
        segment_safe: bool = True,
        counterexample: str = "zeroprefix",
        generalize: bool = False,
        minimize: bool = False,
        slack_weights: str = "geometric",
        slack_lp: bool | None = None,
        split: bool | None = None,
        clock: Clock | None = None,
    ) -> None:
        if counterexample not in COUNTEREXAMPLES:
            raise ValueError(f"unknown counterexample strategy {counterexample!r} (known: {', '.join(COUNTEREXAMPLES)})")
        if slack_weights not in SLACK_WEIGHTS:
            raise ValueError(f"unknown slack weights {slack_weights!r} (known: {', '.join(SLACK_WEIGHTS)})")
        self.problem = problem
        self.segment_safe = segment_safe
        self.counterexample = counterexample
        self.generalize = generalize
        self.minimize = minimize
        self.slack_weights = slack_weights
        # None: the slack LP only for short state vectors; on long chains it costs
        # several times a warm feasibility LP (it cannot reuse a basis well), more than
        # the binary search it saves
        self.slack_lp = problem.dynamics.n_states <= 8 if slack_lp is None else bool(slack_lp)
        self.clock = clock
        dyn = problem.dynamics
        self.n, self.m = dyn.n_states, dyn.n_inputs
        self.A, self.B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
        self.pos = np.array(dyn.position, dtype=np.int64)
        self.d = len(self.pos)
        self.start = np.asarray(problem.start, dtype=float)
        # regions padded to K rows (padding rows are 0 <= inf, i.e. free)
        Hs = [np.asarray(r.H, float) for r in abstraction.regions]
        hs = [np.asarray(r.h, float) for r in abstraction.regions]
        self.K = max(H.shape[0] for H in Hs)
        self.Hpad = np.zeros((len(Hs), self.K, self.d))
        self.hpad = np.full((len(Hs), self.K), INF)
        for i, (H, h) in enumerate(zip(Hs, hs)):
            self.Hpad[i, : H.shape[0]] = H
            self.hpad[i, : H.shape[0]] = h
        # regions with equal H share their coefficients (all boxes do)
        keys: dict[bytes, int] = {}
        self.hkey = np.array([keys.setdefault(self.Hpad[i].tobytes(), len(keys)) for i in range(len(Hs))])
        self.Hgoal, self.hgoal = (np.asarray(a, float) for a in halfspaces(problem.goal))
        self.state_lo, self.state_hi = problem.state_box
        self.stats = LpStats()
        # persistent, warm-started models: the slack LPs of Problem 5.2 in one, the
        # feasibility LPs (plan, prefixes, unanchoring) in the other
        self.slack_slot = _Slot(self._new_highs())
        self.slot = _Slot(self._new_highs())
        self.span_slot = _Slot(self._new_highs())  # LPs over a conflict's time span
        self.cold = self._new_highs()  # one-off LPs (re-checks, IIS, fallbacks)
        # independent blocks of the feasibility LPs (None: one block); by default split
        # long chains only (maze-4, order 25: one LP per axis, half the rows each, ~2x
        # the loop iterations per second; the slack LP couples the axes and stays whole)
        self.blocks = self._blocks()
        if split is None:
            split = self.n > 8
        self.slot.splits = self.span_slot.splits = bool(split) and self.blocks is not None
        self._no_ray = False  # the last infeasible LP was decided outside the persistent model
        self._ray_part: int | None = None  # the split part of the last Farkas ray
        if self.n > 8:
            # long integrator chains (tiny coefficients dt^k/k!): equilibrate harder, cap
            # the simplex iterations (at about twice the row count per model, see _load)
            # and fall back to the interior-point method when stuck
            for h in (self.slot.highs, self.span_slot.highs, self.slack_slot.highs, self.cold):
                h.setOptionValue("simplex_iteration_limit", 5000)
                h.setOptionValue("simplex_scale_strategy", 4)
                # Devex pricing: dual steepest-edge weights are recomputed after every
                # warm start and every rank-deficient basis (frequent on long chains);
                # maze-4, order 25: warm re-solves 5.6x faster, cold ones 1.7x
                h.setOptionValue("simplex_dual_edge_weight_strategy", 1)

    def _blocks(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
        """Independent blocks of the feasibility LPs: states and inputs coupled by A or
        B, or by a region or goal row, are in one block. Per state, input, padded
        region row and goal row its block (-1: a row that is zero in every region);
        None when there is only one block."""
        n, m = self.n, self.m
        parent = list(range(n + m))

        def find(i: int) -> int:
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        def union(i: int, j: int) -> None:
            parent[find(i)] = find(j)

        for i, j in zip(*np.nonzero(self.A)):
            union(int(i), int(j))
        for i, j in zip(*np.nonzero(self.B)):
            union(int(i), n + int(j))
        reg_rows = [np.nonzero(np.any(self.Hpad[:, k, :] != 0, axis=0))[0] for k in range(self.K)]
        goal_rows = [np.nonzero(self.Hgoal[k] != 0)[0] for k in range(len(self.hgoal))]
        for touched in reg_rows + goal_rows:
            for a in touched[1:]:
                union(int(self.pos[touched[0]]), int(self.pos[a]))
        root = np.array([find(i) for i in range(n + m)])
        if len(set(root[:n].tolist())) < 2:
            return None
        ids = {r: i for i, r in enumerate(sorted(set(root[:n].tolist())))}
        label = np.array([ids.get(int(r), -1) for r in root])

        def row_label(touched: np.ndarray) -> int:
            return int(label[self.pos[touched[0]]]) if touched.size else -1

        return (label[:n], label[n:], np.array([row_label(t) for t in reg_rows], dtype=np.int64),
                np.array([row_label(t) for t in goal_rows], dtype=np.int64))

    def _split(self, slot: _Slot, lay: _Layout, b: "_Bounds") -> None:
        """Load the LP of ``lay`` (matrix ``slot.coo``, bounds ``b``) into ``slot`` as
        independent parts. Rows and columns in no part (slack-order rows, slack
        columns, inputs that drive nothing) must be free and fixable at 0."""
        assert self.blocks is not None and slot.coo is not None
        state_b, input_b, reg_b, goal_b = self.blocks
        T, steps = lay.T, lay.steps
        col_part = np.concatenate([np.tile(state_b, T), np.tile(input_b, steps), np.full(T, -1)])
        row_part = np.concatenate([np.tile(state_b, steps), np.tile(reg_b, T), np.tile(reg_b, steps), goal_b,
                                   np.full(steps, -1)])
        slot.col_part, slot.row_part = col_part, row_part
        slot.col_local = np.zeros(lay.n_col, dtype=np.int64)
        slot.row_local = np.zeros(lay.n_row, dtype=np.int64)
        R, C, V = slot.coo
        keep = (row_part[R] >= 0) & (row_part[R] == col_part[C])
        # (explicit zeros: the H entries of a region row on the other axes)
        assert not np.any((row_part[R] >= 0) & (col_part[C] >= 0) & ~keep & (V != 0)), "blocks are not independent"
        R, C, V = R[keep], C[keep], V[keep]
        options = slot.highs.getOptions()
        slot.parts = []
        for p in range(int(state_b.max()) + 1):
            rows = np.nonzero(row_part == p)[0]
            cols = np.nonzero(col_part == p)[0]
            slot.row_local[rows] = np.arange(rows.size)
            slot.col_local[cols] = np.arange(cols.size)
            mine = row_part[R] == p
            r, c, v = slot.row_local[R[mine]], slot.col_local[C[mine]], V[mine]
            lp = _csc_lp(int(cols.size), int(rows.size), r, c, v, np.zeros(cols.size), b.col_lo[cols],
                         b.col_hi[cols], b.row_lo[rows], b.row_hi[rows])
            h = self._new_highs()
            h.passOptions(options)
            h.passModel(lp)
            h.setOptionValue("simplex_iteration_limit", max(5000, 2 * int(rows.size)))
            slot.parts.append(_Part(h, rows, cols))
        slot.infeasible_part = 0
        self._change_bounds(slot, b)  # (checks the rows and columns left out)

    def _change_coeff(self, slot: _Slot, row: int, col: int, value: float) -> None:
        if slot.parts is None:
            slot.highs.changeCoeff(row, col, value)
            return
        assert slot.row_part is not None and slot.col_part is not None
        p = int(slot.row_part[row])
        if p >= 0 and p == slot.col_part[col]:
            slot.parts[p].highs.changeCoeff(int(slot.row_local[row]), int(slot.col_local[col]), value)
        else:  # a slack column, or another part's column: only ever a zero
            assert value == 0.0 or slot.col_part[col] < 0, "a coefficient across split parts"

    def _change_bounds(self, slot: _Slot, b: "_Bounds") -> None:
        if slot.parts is None:
            h, lay = slot.highs, slot.layout
            h.changeRowsBounds(lay.n_row, np.arange(lay.n_row, dtype=np.int32), b.row_lo, b.row_hi)
            h.changeColsBounds(lay.n_col, np.arange(lay.n_col, dtype=np.int32), b.col_lo, b.col_hi)
            return
        assert slot.row_part is not None and slot.col_part is not None
        out_r, out_c = slot.row_part < 0, slot.col_part < 0
        assert np.all(b.row_lo[out_r] <= -INF) and np.all(b.row_hi[out_r] >= INF), "a split LP's extra row applies"
        assert np.all(b.col_lo[out_c] <= 0) and np.all(b.col_hi[out_c] >= 0), "a split LP's extra column is not 0"
        for part in slot.parts:
            r, c = part.rows, part.cols
            part.highs.changeRowsBounds(r.size, np.arange(r.size, dtype=np.int32), b.row_lo[r], b.row_hi[r])
            part.highs.changeColsBounds(c.size, np.arange(c.size, dtype=np.int32), b.col_lo[c], b.col_hi[c])

    def _run_slot(self, slot: _Slot, purpose: str, only: int | None = None) -> np.ndarray | None:
        """Solve the LP ``slot`` holds (part by part: infeasible as soon as one part is,
        the part infeasible last time first). ``only``: solve just that part; then
        "feasible" means only that this part is (the column values of the others are 0)."""
        if slot.parts is None:
            return self._run(slot.highs, purpose)
        assert slot.layout is not None
        col = np.zeros(slot.layout.n_col)
        order = sorted(range(len(slot.parts)), key=lambda i: i != slot.infeasible_part)
        if only is not None:
            order = [only]
        for k, i in enumerate(order):
            part = slot.parts[i]
            sub = self._run(part.highs, purpose, count=k == 0)
            if sub is None:
                slot.infeasible_part = i
                return None
            col[part.cols] = sub
        return col

    @staticmethod
    def _new_highs() -> highspy.Highs:
        # small LPs: presolve costs more than it saves, and the Farkas ray of an
        # infeasible LP (for shrinking conflicts) is only available without it
        return new_highs(presolve="off")

    # ------------------------------------------------------------------ assembly
    def layout(self, first: int, last: int) -> _Layout:
        return _Layout(first, last, self.n, self.m, self.d, self.K, len(self.hgoal))

    def _matrix(self, lay: _Layout, coef: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """COO entries of the LP matrix; ``coef[t - first]`` is the region whose H fills
        the region block of time t and the segment block of time t."""
        n, m, d, K, T, steps = lay.n, lay.m, lay.d, lay.K, lay.T, lay.steps
        # dynamics x_{t+1} - A x_t - B u_t = 0
        ai, aj = np.nonzero(self.A)
        bi, bj = np.nonzero(self.B)
        r1 = np.concatenate([np.arange(n), ai, bi])
        tt = np.arange(steps)[:, None]
        rows = [(tt * n + r1[None, :]).ravel()]
        cols = [np.concatenate([tt * n + np.concatenate([n + np.arange(n), aj])[None, :],
                                lay.n_x + tt * m + bj[None, :]], axis=1).ravel()]
        vals = [np.tile(np.concatenate([np.ones(n), -self.A[ai, aj], -self.B[bi, bj]]), steps)]
        # region blocks (time b) and segment blocks (rows on p_{b+1}, H of time b)
        kk = np.repeat(np.arange(K), d)
        jj = np.tile(self.pos, K)
        for row0, nblocks, shift in ((lay.reg0, T, 0), (lay.seg0, steps, 1)):
            b = np.arange(nblocks)[:, None]
            rows.append((row0 + b * K + kk[None, :]).ravel())
            cols.append(((b + shift) * n + jj[None, :]).ravel())
            vals.append(self.Hpad[coef[:nblocks]].reshape(nblocks, K * d).ravel())
        Kg = lay.Kg
        rows.append(np.repeat(lay.goal0 + np.arange(Kg), d))
        cols.append(np.tile((lay.t1 - lay.first) * n + self.pos, Kg))
        vals.append(self.Hgoal.ravel())
        # slacks: -s_t in every row on p_t; order rows s_t - s_{t+1} <= 0
        s0 = lay.n_x + lay.n_u
        rows += [lay.reg0 + np.arange(T * K), lay.seg0 + np.arange(steps * K), lay.goal0 + np.arange(Kg),
                 lay.ord0 + np.arange(steps), lay.ord0 + np.arange(steps)]
        cols += [s0 + np.repeat(np.arange(T), K), s0 + 1 + np.repeat(np.arange(steps), K), np.full(Kg, s0 + lay.t1 - lay.first),
                 s0 + np.arange(steps), s0 + 1 + np.arange(steps)]
        vals += [-np.ones(T * K), -np.ones(steps * K), -np.ones(Kg), np.ones(steps), -np.ones(steps)]
        return (np.concatenate(rows).astype(np.int64), np.concatenate(cols).astype(np.int64),
                np.concatenate(vals).astype(float))

    def _lp(self, lay: _Layout, coo: tuple[np.ndarray, np.ndarray, np.ndarray], b: _Bounds, cost: np.ndarray) -> highspy.HighsLp:
        return _csc_lp(lay.n_col, lay.n_row, *coo, cost, b.col_lo, b.col_hi, b.row_lo, b.row_hi)

    def _pass_cold(self, lay: _Layout, assignment: Mapping[int, int], *, goal: bool, anchored_start: bool) -> _Bounds:
        """Put the feasibility LP of ``assignment`` over ``lay`` into the one-off model."""
        b = self.bounds(lay, assignment, goal=goal, anchored_start=anchored_start, slack=False)
        coo = self._matrix(lay, self._coef_for(lay, assignment))
        self.cold.passModel(self._lp(lay, coo, b, np.zeros(lay.n_col)))
        return b

    def _cost(self, lay: _Layout) -> np.ndarray:
        cost = np.zeros(lay.n_col)
        W = lay.t1 - lay.t0 + 1
        s0 = lay.s(lay.t0)
        if self.slack_weights == "uniform":
            cost[s0 : s0 + W] = 1.0
        else:
            cost[s0 : s0 + W] = (1e-4 ** (1.0 / max(1, W - 1))) ** np.arange(W)
        return cost

    def bounds(
        self, lay: _Layout, assignment: Mapping[int, int], *, goal: bool, anchored_start: bool, slack: bool
    ) -> _Bounds:
        """Row and column bounds: region rows of the assigned times (segment rows too,
        unless the next time has the same region), goal rows, x_first = start, slacks;
        within the layout's window only."""
        reg0, seg0, first, K, n = lay.reg0, lay.seg0, lay.first, lay.K, lay.n
        w0, w1 = lay.t0 - first, lay.t1 - first  # the window's steps are w0..w1-1
        row_lo = np.full(lay.n_row, -INF)
        row_hi = np.full(lay.n_row, INF)
        row_lo[w0 * n : w1 * n] = 0.0
        row_hi[w0 * n : w1 * n] = 0.0
        if assignment:
            ts = np.fromiter(assignment.keys(), dtype=np.int64, count=len(assignment))
            rs = np.fromiter(assignment.values(), dtype=np.int64, count=len(assignment))
            blocks = row_hi[reg0:seg0].reshape(lay.T, K)
            blocks[ts - first] = self.hpad[rs]
            if self.segment_safe:
                nxt = np.array([assignment.get(int(t) + 1, -1) for t in ts])
                seg = (ts < lay.t1) & (nxt != rs)
                row_hi[seg0 : lay.goal0].reshape(lay.steps, K)[ts[seg] - first] = self.hpad[rs[seg]]
        if goal:
            row_hi[lay.goal0 : lay.ord0] = self.hgoal
        slack_hi = np.zeros(lay.T)
        if slack:
            row_hi[lay.ord0 + w0 : lay.ord0 + w1] = 0.0
            slack_hi[w0 : w1 + 1] = INF
        col_lo = np.concatenate([np.tile(self.state_lo, lay.T), np.full(lay.n_u, -self.problem.input_bound),
                                 np.zeros(lay.T)])
        col_hi = np.concatenate([np.tile(self.state_hi, lay.T), np.full(lay.n_u, self.problem.input_bound), slack_hi])
        if anchored_start:
            col_lo[w0 * n : (w0 + 1) * n] = self.start
            col_hi[w0 * n : (w0 + 1) * n] = self.start
        return _Bounds(row_lo, row_hi, col_lo, col_hi, anchored_start)

    def _coef_for(self, lay: _Layout, assignment: Mapping[int, int], base: np.ndarray | None = None) -> np.ndarray:
        coef = np.zeros(lay.T, dtype=np.int64) if base is None else base.copy()
        for t, r in assignment.items():
            coef[t - lay.first] = r
        return coef

    def _load(self, slot: _Slot, lay: _Layout, assignment: Mapping[int, int], b: _Bounds) -> None:
        """Make ``slot`` hold the LP of ``lay`` with the H of ``assignment`` and bounds
        ``b``: in place when the layout is unchanged (warm start)."""
        h = slot.highs
        old = slot.layout
        if old is None or old.frame != lay.frame or slot.coef is None or slot.coo is None:
            slot.layout = lay
            slot.coef = self._coef_for(lay, assignment)
            slot.coo = self._matrix(lay, slot.coef)
            if slot.splits:
                self._split(slot, lay, b)
            else:
                h.passModel(self._lp(lay, slot.coo, b, self._cost(lay)))
                if self.n > 8:  # a cold simplex run on a long chain needs ~ a row count of iterations
                    h.setOptionValue("simplex_iteration_limit", max(5000, 2 * lay.n_row))
        else:
            coef = self._coef_for(lay, assignment, slot.coef)
            changed = np.nonzero(self.hkey[coef] != self.hkey[slot.coef])[0]
            slot.layout = lay
            if changed.size:
                self._recoefficient(slot, coef, changed)
            if (old.t0, old.t1) != (lay.t0, lay.t1):
                if old.t1 != lay.t1:  # move the goal rows (and their slack) to p_t1
                    for i in range(lay.Kg):
                        r = lay.goal0 + i
                        for j in range(lay.d):
                            self._change_coeff(slot, r, lay.x(old.t1) + int(self.pos[j]), 0.0)
                        self._change_coeff(slot, r, lay.s(old.t1), 0.0)
                        for j in range(lay.d):
                            if self.Hgoal[i, j] != 0.0:
                                self._change_coeff(slot, r, lay.x(lay.t1) + int(self.pos[j]), float(self.Hgoal[i, j]))
                        self._change_coeff(slot, r, lay.s(lay.t1), -1.0)
                if slot.parts is None:  # (split LPs are feasibility LPs: no cost)
                    h.changeColsCost(lay.n_col, np.arange(lay.n_col, dtype=np.int32), self._cost(lay))
                slot.coo = self._matrix(lay, slot.coef)
            self._change_bounds(slot, b)
        slot.bounds = b

    def _recoefficient(self, slot: _Slot, coef: np.ndarray, changed: np.ndarray) -> None:
        """Put region H's into the blocks of the ``changed`` times (coefficient edits)."""
        lay = slot.layout
        assert lay is not None
        K, d, n = lay.K, lay.d, lay.n
        for b in changed:
            H = self.Hpad[coef[b]]
            for row0, state_b, ok in ((lay.reg0, b, True), (lay.seg0, b + 1, b < lay.steps)):
                if not ok:
                    continue
                for i in range(K):
                    for j in range(d):
                        self._change_coeff(slot, int(row0 + b * K + i), int(state_b * n + self.pos[j]), float(H[i, j]))
        slot.coef = coef
        slot.coo = self._matrix(lay, coef)

    def _run(self, h: highspy.Highs, purpose: str, count: bool = True) -> np.ndarray | None:
        """Solve the model ``h`` holds: column values when optimal, None when infeasible.

        HiGHS occasionally refuses a warm start after in-place edits (an error before
        any iteration), and the simplex method can stall on badly conditioned LPs (long
        integrator chains: coefficients dt^k/k!). Then the LP is solved again from
        scratch, then on a fresh copy by the interior-point method, then by the simplex
        method after presolve (no Farkas ray then: the conflict is kept unshrunk). If
        every attempt fails, :class:`LpFailure` is raised and the planner answers
        ``unknown``.
        """
        S = highspy.HighsModelStatus
        self._no_ray = False
        answers = (S.kOptimal, S.kInfeasible, S.kUnboundedOrInfeasible, S.kTimeLimit, S.kInterrupt, S.kHighsInterrupt)
        t0 = time.perf_counter()
        status = S.kNotset
        fresh = {"ipm": {"solver": "ipm", "presolve": "off", "run_crossover": "on"},
                 "presolved": {"solver": "simplex", "presolve": "on", "simplex_iteration_limit": 2**31 - 1}}
        for attempt in ("warm", "cold", "ipm", "presolved"):
            if self.clock is not None:
                remaining = self.clock.remaining()
                if remaining <= 0:
                    raise LpBudgetExhausted()
            if attempt == "cold":
                if status == S.kIterationLimit:
                    continue  # a stalled simplex stalls again: straight to the other methods
                self.stats.retries += 1
                h.clearSolver()
            if attempt in fresh:
                # a fresh copy of the LP in the one-off instance, by another method
                self.stats.ipm_fallbacks += 1
                lp = h.getLp()
                h = self.cold
                h.passModel(lp)
            if self.clock is not None:
                # HiGHS compares time_limit with the instance's run time summed over runs
                h.setOptionValue("time_limit", float(h.getRunTime() + min(self.clock.remaining(), 1e9)))
            with _options(h, fresh.get(attempt, {})):
                h.run()
            status = h.getModelStatus()
            if status in answers:
                break
        self.stats.seconds += time.perf_counter() - t0
        if count:
            self.stats.lp_calls += 1
            self.stats.by_kind[purpose] = self.stats.by_kind.get(purpose, 0) + 1
        if status == S.kOptimal:
            return np.asarray(h.getSolution().col_value)
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            # objectives are bounded below (0 or a weighted sum of slacks >= 0)
            self._no_ray = h is self.cold  # the persistent model holds no Farkas ray
            return None
        if status in (S.kTimeLimit, S.kInterrupt, S.kHighsInterrupt):
            raise LpBudgetExhausted()
        raise LpFailure(f"HiGHS could not solve a CON-PLAN LP ({purpose}): {h.modelStatusToString(status)}")

    def _solve_model(self, N: int, assignment: Mapping[int, int], purpose: str, *, goal: bool = False,
                     anchored_start: bool = True, slack: bool = False,
                     span: tuple[int, int] | None = None, part: int | None = None,
                     slot: _Slot | None = None) -> np.ndarray | None:
        """Solve the LP of ``assignment`` over the states 0..N, or only over ``span``
        (first, last) in the span model (for conflicts: a smaller LP that claims no more).
        ``part``: in a split model, solve only that part (an infeasible answer holds for
        the whole LP; a feasible one is only that part's)."""
        if slot is None:
            slot = self.slack_slot if slack else (self.span_slot if span is not None else self.slot)
        lay = self._frame(slot, *((0, N) if span is None else span))
        self._load(slot, lay, assignment, self.bounds(lay, assignment, goal=goal, anchored_start=anchored_start, slack=slack))
        col = self._run_slot(slot, purpose, part)
        slot.held = (purpose, max(assignment, default=-1), col is not None)
        return col

    def _held_layout(self) -> _Layout:
        assert self.slot.layout is not None
        return self.slot.layout

    def _frame(self, slot: _Slot, lo: int, hi: int) -> _Layout:
        """The layout for the states lo..hi in ``slot``: a window of the frame the slot
        holds when it fits (and is not much longer: free rows cost too), else a new
        frame a little longer than needed, so that the next horizons fit as well."""
        cur = slot.layout
        if cur is not None and cur.first <= lo and hi <= cur.last and 2 * (hi - lo + 1) >= cur.T:
            return cur.window(lo, hi)
        return self.layout(lo, hi + (hi - lo) // 16).window(lo, hi)

    def _trajectory(self, lay: _Layout, col: np.ndarray) -> Trajectory:
        a, z = lay.t0 - lay.first, lay.t1 - lay.first
        X = col[: lay.n_x].reshape(lay.T, lay.n)[a : z + 1]
        U = col[lay.n_x : lay.n_x + lay.n_u].reshape(lay.steps, lay.m)[a:z]
        U = np.clip(U, -self.problem.input_bound, self.problem.input_bound)
        return Trajectory(states=X, inputs=U)

    # ------------------------------------------------------------------ the theory check
    def check(self, regions: Sequence[int]) -> Feasible | Conflict:
        """Realise ``regions`` (r_0..r_N) or return a sound counterexample."""
        out = self._check(regions)
        if isinstance(out, Feasible):
            out = self._polished(regions, out)
        return out

    def residual(self, traj: Trajectory) -> float:
        """The largest violation of ``x_{t+1} = A x_t + B u_t`` along ``traj``."""
        X, U = np.asarray(traj.states, float), np.asarray(traj.inputs, float)
        if len(U) == 0:
            return 0.0
        return float(np.max(np.abs(X[1:] - X[:-1] @ self.A.T - U @ self.B.T)))

    def _polished(self, regions: Sequence[int], found: Feasible) -> Feasible:
        """A warm-started, scaled simplex answer can meet HiGHS's tolerances on the
        scaled rows and still miss the dynamics by 1e-5 unscaled (long integrator
        chains), which the validator rejects. Then the plan's LP is solved once more,
        from scratch, with presolve, without scaling and with tight tolerances; the
        answer with the smaller residual is kept."""
        if self.residual(found.trajectory) <= POLISH_RESIDUAL:
            return found
        lay = self.layout(0, len(regions) - 1)
        self._pass_cold(lay, dict(enumerate(int(r) for r in regions)), goal=True, anchored_start=True)
        h = self.cold
        tight = {"presolve": "on", "simplex_scale_strategy": 0, "primal_feasibility_tolerance": 1e-10,
                 "dual_feasibility_tolerance": 1e-10, "simplex_iteration_limit": 2**31 - 1}
        if self.clock is not None:  # within the budget: a polish cut short keeps the first answer
            tight["time_limit"] = float(h.getRunTime() + max(1e-3, min(self.clock.remaining(), 1e9)))
        with _options(h, tight):
            t0 = time.perf_counter()
            h.run()
            self.stats.seconds += time.perf_counter() - t0
            self.stats.lp_calls += 1
            self.stats.by_kind["polish"] = self.stats.by_kind.get("polish", 0) + 1
            if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
                return found
            again = self._trajectory(lay, np.asarray(h.getSolution().col_value))
        self.stats.polished += 1
        return Feasible(again) if self.residual(again) < self.residual(found.trajectory) else found

    def _check(self, regions: Sequence[int]) -> Feasible | Conflict:
        regions = tuple(int(r) for r in regions)
        N = len(regions) - 1
        plan = dict(enumerate(regions))
        if self.counterexample == "iis":
            return self._check_iis(regions)
        if self.counterexample == "zeroprefix":
            out = self._check_zeroprefix(regions)
        else:
            col = self._solve_model(N, plan, "plan", goal=True)
            if col is not None:
                return Feasible(self._trajectory(self._held_layout(), col))
            out = self._whole(regions)
        if isinstance(out, Conflict) and self.generalize:
            out = self._from_ray(regions, out)  # HiGHS holds out's LP
            if self.minimize:
                out = self._minimize(regions, out)
            out = self._unanchor(regions, out)
        return out

    def feasible(self, regions: Sequence[int]) -> Trajectory | None:
        """The plain feasibility LP of the whole plan (goal included): a trajectory or None."""
        N = len(regions) - 1
        col = self._solve_model(N, dict(enumerate(int(r) for r in regions)), "plan", goal=True)
        return None if col is None else self._trajectory(self._held_layout(), col)

    def _whole(self, regions: Sequence[int]) -> Conflict:
        N = len(regions) - 1
        return Conflict(tuple(enumerate(regions)), anchored_start=True, anchored_goal=True, horizon=N)

    def _prefix(self, regions: Sequence[int], k: int) -> Conflict:
        N = len(regions) - 1
        return Conflict(tuple((t, regions[t]) for t in range(k + 1)), anchored_start=True, anchored_goal=False,
                        horizon=N, last_time=N)

    def prefix_feasible(self, regions: Sequence[int], k: int) -> bool:
        """Is the prefix r_0..r_k (at times 0..k) realisable, continuing within the
        bounds up to N? (Monotone: a longer prefix is harder.)"""
        N = len(regions) - 1
        return self._solve_model(N, {t: regions[t] for t in range(k + 1)}, "prefix") is not None

    def _check_zeroprefix(self, regions: tuple[int, ...]) -> Feasible | Conflict:
        N = len(regions) - 1
        plan = dict(enumerate(regions))
        lo, bound = 0, None
        if not self.slack_lp:
            # no slack LP: the plan LP, then the earliest infeasible prefix by binary
            # search, cut short by the plan LP's certificate when it needs no goal row
            col = self._solve_model(N, plan, "plan", goal=True)
            if col is not None:
                return Feasible(self._trajectory(self._held_layout(), col))
            bound = self._certified_prefix()
        else:
            try:
                col = self._solve_model(N, plan, "slack", goal=True, slack=True)
            except LpFailure:  # no ZEROPREFIX candidate this time; the search below still decides
                self.stats.slack_failures += 1
                col = None
            if col is not None:
                lay = self.slack_slot.layout
                assert lay is not None
                k = zero_prefix(col[lay.s(lay.t0) : lay.s(lay.t1) + 1])
                if k == N + 1:
                    return Feasible(self._trajectory(lay, col))
                # the paper's counterexample r_0..r_k; prefix 0..k-1 has a zero-slack witness
                if not self.prefix_feasible(regions, k):
                    return self._prefix(regions, k)
                lo = k + 1
            # else: infeasible even with slacks (dynamics and bounds alone), or no answer
        hi = self._earliest_infeasible_prefix(regions, lo, bound)
        if hi <= N:
            return self._prefix(regions, hi)
        col = self._solve_model(N, plan, "plan", goal=True)
        if col is not None:
            return Feasible(self._trajectory(self._held_layout(), col))
        return self._whole(regions)

    def _earliest_infeasible_prefix(self, regions: Sequence[int], lo: int, bound: int | None) -> int:
        """The earliest infeasible prefix in lo..N by binary search (feasibility is
        monotone), N + 1 if prefix N is feasible; then the plan model holds its LP.
        ``bound``: a prefix known to be infeasible. A checked certificate of an
        infeasible prefix LP that needs only the literals up to time t proves prefix t
        infeasible too, and cuts the search there."""
        N = len(regions) - 1
        hi = N + 1  # sentinel: "prefix N is feasible"
        a, b = lo, N
        if bound is not None and lo <= bound <= N:
            hi, b = bound, bound - 1
        while a <= b:
            mid = (a + b) // 2
            if self.prefix_feasible(regions, mid):
                a = mid + 1
            else:
                hi, b = mid, mid - 1
                t = self._certified_prefix()
                if t is not None and a <= t < mid:
                    hi, b = t, t - 1
        if hi <= N and self.slot.held != ("prefix", hi, False):
            # HiGHS must hold the conflict's LP
            if self.prefix_feasible(regions, hi):  # pragma: no cover (a certificate that did not hold)
                return self._earliest_infeasible_prefix(regions, hi + 1, None)
        return hi

    # ------------------------------------------------------------------ IIS
    def _check_iis(self, regions: tuple[int, ...]) -> Feasible | Conflict:
        N = len(regions) - 1
        plan = dict(enumerate(regions))
        lay = self.layout(0, N)
        b = self._pass_cold(lay, plan, goal=True, anchored_start=True)
        self._cap_cold(lay)
        col = self._run(self.cold, "plan")
        if col is not None:
            return Feasible(self._trajectory(lay, col))
        whole = self._whole(regions)
        self.cold.setOptionValue("iis_strategy", int(highspy.IisStrategy.kIisStrategyFromLp) | int(highspy.IisStrategy.kIisStrategyIrreducible))
        t0 = time.perf_counter()
        status, iis = self.cold.getIis()
        self.stats.seconds += time.perf_counter() - t0
        self.stats.iis_calls += 1
        if status != highspy.HighsStatus.kOk or not iis.valid_ or len(iis.row_index_) == 0:
            self.stats.rejected += 1
            return whole
        rows = np.asarray(list(iis.row_index_), dtype=np.int64)
        cols = np.asarray(list(iis.col_index_), dtype=np.int64)
        out = self._shrunk(lay, b, regions, rows, cols, whole, certified=False)
        if self.generalize:
            out = self._unanchor(regions, out)
        return out

    # ------------------------------------------------------------------ shrinking
    def _from_ray(self, regions: Sequence[int], fallback: Conflict, slot: _Slot | None = None) -> Conflict:
        """Shrink ``fallback``, whose infeasible LP ``slot`` (default: the plan model)
        holds, to the support of its Farkas certificate (dual ray): the rows with nonzero
        multipliers and the bounds of the columns whose combined coefficient is nonzero
        are infeasible on their own."""
        slot = self.slot if slot is None else slot
        lay, b = slot.layout, slot.bounds
        assert lay is not None and b is not None
        support = self._ray_support(slot)
        if support is None:
            self.stats.rejected += 1
            return fallback
        rows, cols, certified = support
        return self._shrunk(lay, b, regions, rows, cols, fallback, certified=certified)

    def _ray_support(self, slot: _Slot) -> tuple[np.ndarray, np.ndarray, bool] | None:
        """The rows and columns of the Farkas certificate (dual ray) of the infeasible
        LP ``slot`` holds, and whether it checks (:func:`_farkas_certifies`); None when
        HiGHS has no ray."""
        lay, b, coo = slot.layout, slot.bounds, slot.coo
        assert lay is not None and b is not None and coo is not None
        self._ray_part = None
        if self._no_ray:  # the LP was decided by the fallback method
            return None
        if slot.parts is None:
            status, has_ray, ray = slot.highs.getDualRay()
            y = np.asarray(ray, dtype=float)
        else:  # the ray of the infeasible part, zero on the other parts' rows
            self._ray_part = slot.infeasible_part
            part = slot.parts[slot.infeasible_part]
            status, has_ray, ray = part.highs.getDualRay()
            y = np.zeros(lay.n_row)
            if has_ray:
                y[part.rows] = np.asarray(ray, dtype=float)
        self.stats.ray_calls += 1
        scale = float(np.max(np.abs(y))) if (has_ray and y.size) else 0.0
        if status != highspy.HighsStatus.kOk or not scale > 0:
            return None
        y = y / scale
        # free rows (outside the LP's window, or not applying) take no part in a
        # certificate; HiGHS may leave round-off on them: drop it (the check below decides)
        y[(b.row_lo <= -INF) & (b.row_hi >= INF)] = 0.0
        rows = np.nonzero(np.abs(y) > 1e-9)[0]
        R, C, V = coo
        dcol = np.bincount(C, weights=V * y[R], minlength=lay.n_col)
        cols = np.nonzero(np.abs(dcol) > 1e-9)[0]
        return rows, cols, _farkas_certifies(b, y, dcol, rows, cols)

    def _certified_prefix(self) -> int | None:
        """For the infeasible LP the plan model holds: the latest region literal its
        checked Farkas certificate needs, when that certificate uses no goal row (so
        the prefix up to that time is infeasible as well), else None."""
        support = self._ray_support(self.slot)
        if support is None or not support[2]:
            return None
        kind, lit, _ = self.slot.layout.meta  # type: ignore[union-attr]
        rows = support[0]
        if np.any(kind[rows] == GOAL):
            return None
        times = lit[rows]
        return int(times.max()) if times.size and times.max() >= 0 else None

    def _minimize(self, regions: Sequence[int], c: Conflict) -> Conflict:
        """Deletion filter: drop each literal whose region rows the conflict does not
        need (the LP without them is still infeasible), so that no literal can be
        dropped from the result; then shrink by the last infeasible LP's certificate.
        The LPs span only the conflict's time steps (``c.first_time..c.last_time``)."""
        if not 1 < len(c.literals) <= MINIMIZE_MAX_LITERALS:
            return c  # long ones (no Farkas ray to shrink them first) would cost an LP each
        N = len(regions) - 1
        span = (c.first_time, c.last_time)
        # in a split model only the part of c's certificate: a literal it does not need
        # leaves that part infeasible (another part's infeasibility is not looked for)
        part = self._ray_part
        keep = list(c.literals)
        last_infeasible = False
        for lit in list(keep):
            trial = [x for x in keep if x != lit]
            col = self._solve_model(N, dict(trial), "minimize", goal=c.anchored_goal,
                                    anchored_start=c.anchored_start, span=span, part=part)
            last_infeasible = col is None
            if last_infeasible:
                keep = trial
        if len(keep) == len(c.literals):
            return c
        if not last_infeasible:  # HiGHS must hold the kept set's (infeasible) LP
            if self._solve_model(N, dict(keep), "minimize", goal=c.anchored_goal,
                                 anchored_start=c.anchored_start, span=span, part=part) is not None:  # pragma: no cover
                return c
        smaller = Conflict(tuple(keep), anchored_start=c.anchored_start, anchored_goal=c.anchored_goal,
                           horizon=c.horizon, first_time=span[0], last_time=span[1])
        return self._from_ray(regions, smaller, self.span_slot)

    def _unanchor(self, regions: Sequence[int], c: Conflict) -> Conflict:
        """Try to drop the start from a start-anchored conflict: if the LP of its claims
        with x_0 free (within the state bounds) is infeasible too, shrink that one; a
        conflict that uses neither the start nor the goal holds at every time shift."""
        if not c.anchored_start or not c.literals:
            return c
        N = len(regions) - 1
        span = (c.first_time, c.last_time)
        col = self._solve_model(N, dict(c.literals), "unanchor", goal=c.anchored_goal, anchored_start=False, span=span,
                                part=self._ray_part)
        if col is not None:
            return c
        free = Conflict(c.literals, anchored_start=False, anchored_goal=c.anchored_goal, horizon=c.horizon,
                        first_time=span[0], last_time=span[1])
        return self._from_ray(regions, free, self.span_slot)

    def _shrunk(
        self, lay: _Layout, b: _Bounds, regions: Sequence[int], rows: np.ndarray, cols: np.ndarray,
        fallback: Conflict, *, certified: bool,
    ) -> Conflict:
        """The conflict of an infeasible subsystem (``rows`` and the bounds of ``cols``):
        the regions at the times of its region rows, anchored at the start when it uses
        x_0's fixed bounds, at the goal when it uses a goal row, spanning the states it
        touches. Returned when ``certified`` (a checked Farkas certificate of exactly
        these rows and bounds) or when an LP over exactly these claims is infeasible."""
        kind, lit, state = lay.meta
        n, m = lay.n, lay.m
        kinds = kind[rows]
        lit_times = sorted({int(t) for t in lit[rows] if t >= 0})
        uses_goal = bool(np.any(kinds == GOAL))
        x_cols = cols[cols < lay.n_x]
        u_cols = cols[(cols >= lay.n_x) & (cols < lay.n_x + lay.n_u)]
        x_start = lay.x(lay.t0)
        uses_start = b.anchored_start and bool(np.any((x_cols >= x_start) & (x_cols < x_start + n)))
        touched = [int(t) for t in state[rows] if t >= 0] + lit_times
        touched += [int(t) - 1 for t in state[rows[kinds == DYN]]]
        touched += [int(c) // n + lay.first for c in x_cols]
        touched += [(int(c) - lay.n_x) // m + lay.first for c in u_cols]
        conflict = Conflict(
            tuple((t, regions[t]) for t in lit_times),
            anchored_start=uses_start,
            anchored_goal=uses_goal,
            horizon=len(regions) - 1,
            first_time=0 if uses_start else min(touched, default=0),
            last_time=lay.t1 if uses_goal else max(touched, default=0),
        )
        if conflict == fallback:
            return conflict
        if certified:
            self.stats.certified += 1
            return conflict
        if self.refutes(conflict):
            return conflict
        self.stats.rejected += 1
        return fallback

    def refutes(self, c: Conflict, *, cold: bool = False) -> bool:
        """Is the LP of exactly what ``c`` claims infeasible? (states c.first_time ..
        c.last_time, the literals' region and segment rows, the goal and the start as
        anchored). By default in a persistent model (a window of its frame, split when
        the LPs split, warm-started); ``cold``: a fresh LP of exactly that layout."""
        assign = dict(c.literals)
        if not cold:
            # the span model (shared with the deletion filter), not a model of its own:
            # on maze-4 with an order-25 chain the loop then needs 46 iterations, not 104
            col = self._solve_model(c.last_time, assign, "verify", goal=c.anchored_goal,
                                    anchored_start=c.anchored_start, span=(c.first_time, c.last_time))
            return col is None
        lay = self.layout(c.first_time, c.last_time)
        self._pass_cold(lay, assign, goal=c.anchored_goal, anchored_start=c.anchored_start)
        self._cap_cold(lay)
        return self._run(self.cold, "verify") is None

    def _cap_cold(self, lay: _Layout) -> None:
        if self.n > 8:  # as in _load: a cold run needs ~ a row count of simplex iterations
            self.cold.setOptionValue("simplex_iteration_limit", max(5000, 2 * lay.n_row))


def _farkas_certifies(b: _Bounds, y: np.ndarray, d: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> bool:
    """Does ``y`` (zero outside ``rows``) prove that those rows, with the bounds of the
    columns ``cols`` (the other columns free), have no solution?

    With ``d = A^T y``, every solution has ``y^T (A x) = d^T x``; the row bounds confine
    the left side to an interval, the column bounds the right side to another, and
    disjoint intervals (by a safety margin) prove infeasibility. The tiny coefficients
    of ``d`` outside ``cols`` are charged to the margin with their columns' bounds.
    """
    yr = y[rows]
    lo_r, hi_r = b.row_lo[rows], b.row_hi[rows]
    with np.errstate(invalid="ignore"):
        row_min = float(np.where(yr > 0, yr * lo_r, yr * hi_r).sum())
        row_max = float(np.where(yr > 0, yr * hi_r, yr * lo_r).sum())
        dc = d[cols]
        col_min = float(np.where(dc > 0, dc * b.col_lo[cols], dc * b.col_hi[cols]).sum())
        col_max = float(np.where(dc > 0, dc * b.col_hi[cols], dc * b.col_lo[cols]).sum())
    if any(math.isnan(v) for v in (row_min, row_max, col_min, col_max)):
        return False
    rest = np.setdiff1d(np.nonzero(d)[0], cols)
    bound = np.maximum(np.abs(b.col_lo[rest]), np.abs(b.col_hi[rest]))
    if np.any(~np.isfinite(bound)):
        return False
    slop = float(np.sum(np.abs(d[rest]) * bound))
    finite = [abs(v) for v in (row_min, row_max, col_min, col_max) if math.isfinite(v)]
    margin = 1e-7 * (1.0 + max(finite, default=0.0)) + slop
    return col_max + margin < row_min or row_max + margin < col_min
