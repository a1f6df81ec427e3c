"""CON-PLAN's LP layout (see :mod:`plansynth.reach.lazy.conplan`; Shoukry et al., CDC
2016, Section V): the columns and rows of the LP over one horizon frame
(:class:`_Layout`), the persistent HiGHS models that hold it (:class:`_Slot`), the
independent blocks a separable LP splits into (:class:`_Part`) and the bounds loaded
into a model (:class:`_Bounds`). The edits in place are :mod:`plansynth.reach.lazy.conplan.lp`."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import highspy
import numpy as np

INF = highspy.kHighsInf

# row kinds of the LPs
DYN, REGION, SEGMENT, GOAL, ORDER = range(5)

#: More states than this make a "long integrator chain" (an order-25 chain in 2-D has 50):
#: its coefficients dt^k/k! span many decades, so CON-PLAN scales harder, caps and
#: prices the simplex differently, skips the slack LP and splits the LPs.
LONG_CHAIN_STATES = 8


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

    def window(self, lo: int, hi: int) -> _Layout:
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
        kind = np.concatenate(
            [
                np.full(steps * n, DYN),
                np.full(T * K, REGION),
                np.full(steps * K, SEGMENT),
                np.full(self.Kg, GOAL),
                np.full(steps, ORDER),
            ]
        )
        lit = np.concatenate(
            [np.full(steps * n, -1), np.repeat(ts, K), np.repeat(ts[:-1], K), np.full(self.Kg, -1), np.full(steps, -1)]
        )
        state = np.concatenate(
            [
                np.repeat(ts[1:], n),
                np.repeat(ts, K),
                np.repeat(ts[1:], K),
                np.full(self.Kg, self.t1),
                np.full(steps, -1),
            ]
        )
        return kind, lit, state


@dataclass
class _Part:
    """One independent block of a split LP: its rows and columns in the whole LP."""

    highs: highspy.Highs
    rows: np.ndarray
    cols: np.ndarray
    cold: bool = True  # no basis to warm-start from (not solved yet, or by the interior-point method alone)


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
    bounds: _Bounds | None = None
    held: tuple | None = None  # a description of the LP last solved
    splits: bool = False  # may this slot's LPs be split into parts?
    parts: list[_Part] | None = None
    row_part: np.ndarray | None = None  # per row of the whole LP: its part (-1: in none)
    row_local: np.ndarray | None = None  # and its index there
    col_part: np.ndarray | None = None
    col_local: np.ndarray | None = None
    infeasible_part: int = 0  # the part that was infeasible last (tried first)
    fresh: bool = False  # was the model passed whole for this LP (no basis to warm-start from)?


@dataclass
class _Bounds:
    row_lo: np.ndarray
    row_hi: np.ndarray
    col_lo: np.ndarray
    col_hi: np.ndarray
    anchored_start: bool
    origin: int = 0  # the state time whose tube is E_0 (a problem with a tube: see _LpEdits._tightened)
