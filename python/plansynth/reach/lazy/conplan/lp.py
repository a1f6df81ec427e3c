"""CON-PLAN's LP edits in place (see :mod:`plansynth.reach.lazy.conplan`): the models of
a layout (:mod:`plansynth.reach.lazy.conplan.layout`: one per horizon frame, held by
persistent HiGHS models) built, their bounds and coefficients edited between LPs, and
the independent blocks a separable LP splits into."""

from __future__ import annotations

from collections.abc import Mapping

import highspy
import numpy as np

from plansynth.reach.highs import pass_csc
from plansynth.reach.lazy.conplan.layout import (  # noqa: F401 - the layout's names, imported from here too
    DYN,
    GOAL,
    INF,
    LONG_CHAIN_STATES,
    ORDER,
    REGION,
    SEGMENT,
    _Bounds,
    _Layout,
    _Part,
    _Slot,
)
from plansynth.reach.trajectory import Trajectory


class _LpEdits:
    """The layout and edit methods of :class:`~plansynth.reach.lazy.conplan.check.ConPlan`."""

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

        return (
            label[:n],
            label[n:],
            np.array([row_label(t) for t in reg_rows], dtype=np.int64),
            np.array([row_label(t) for t in goal_rows], dtype=np.int64),
        )

    def _split(self, slot: _Slot, lay: _Layout, b: _Bounds) -> None:
        """Load the LP of ``lay`` (matrix ``slot.coo``, bounds ``b``) into ``slot`` as
        independent parts. Rows and columns in no part (slack-order rows, slack
        columns, inputs that drive nothing) must be free and fixable at 0."""
        assert self.blocks is not None and slot.coo is not None
        state_b, input_b, reg_b, goal_b = self.blocks
        T, steps = lay.T, lay.steps
        col_part = np.concatenate([np.tile(state_b, T), np.tile(input_b, steps), np.full(T, -1)])
        row_part = np.concatenate(
            [np.tile(state_b, steps), np.tile(reg_b, T), np.tile(reg_b, steps), goal_b, np.full(steps, -1)]
        )
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
            h = self._new_highs()
            h.passOptions(options)
            pass_csc(
                h,
                int(cols.size),
                int(rows.size),
                r,
                c,
                v,
                np.zeros(cols.size),
                b.col_lo[cols],
                b.col_hi[cols],
                b.row_lo[rows],
                b.row_hi[rows],
            )
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

    def _change_bounds(self, slot: _Slot, b: _Bounds) -> None:
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

    def span_parts(self) -> int | None:
        """The number of independent parts the span model's LPs split into (one per axis
        when the dynamics and every region separate), or None when they are not split."""
        if not self.span_slot.splits or self.blocks is None:
            return None
        return int(self.blocks[0].max()) + 1

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
        cols = [
            np.concatenate(
                [tt * n + np.concatenate([n + np.arange(n), aj])[None, :], lay.n_x + tt * m + bj[None, :]], axis=1
            ).ravel()
        ]
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
        rows += [
            lay.reg0 + np.arange(T * K),
            lay.seg0 + np.arange(steps * K),
            lay.goal0 + np.arange(Kg),
            lay.ord0 + np.arange(steps),
            lay.ord0 + np.arange(steps),
        ]
        cols += [
            s0 + np.repeat(np.arange(T), K),
            s0 + 1 + np.repeat(np.arange(steps), K),
            np.full(Kg, s0 + lay.t1 - lay.first),
            s0 + np.arange(steps),
            s0 + 1 + np.arange(steps),
        ]
        vals += [-np.ones(T * K), -np.ones(steps * K), -np.ones(Kg), np.ones(steps), -np.ones(steps)]
        return (
            np.concatenate(rows).astype(np.int64),
            np.concatenate(cols).astype(np.int64),
            np.concatenate(vals).astype(float),
        )

    def _pass(
        self,
        h: highspy.Highs,
        lay: _Layout,
        coo: tuple[np.ndarray, np.ndarray, np.ndarray],
        b: _Bounds,
        cost: np.ndarray,
    ) -> None:
        """Load the LP into ``h`` (:func:`~plansynth.reach.highs.pass_csc`: the arrays by pointer)."""
        pass_csc(h, lay.n_col, lay.n_row, *coo, cost, b.col_lo, b.col_hi, b.row_lo, b.row_hi)

    def _pass_cold(self, lay: _Layout, assignment: Mapping[int, int], *, goal: bool, anchored_start: bool) -> _Bounds:
        """Put the feasibility LP of ``assignment`` over ``lay`` into the one-off model."""
        b = self.bounds(lay, assignment, goal=goal, anchored_start=anchored_start, slack=False)
        coo = self._matrix(lay, self._coef_for(lay, assignment))
        self._pass(self.cold, lay, coo, b, np.zeros(lay.n_col))
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
        col_lo = np.concatenate(
            [np.tile(self.state_lo, lay.T), np.full(lay.n_u, -self.problem.input_bound), np.zeros(lay.T)]
        )
        col_hi = np.concatenate([np.tile(self.state_hi, lay.T), np.full(lay.n_u, self.problem.input_bound), slack_hi])
        origin = 0 if anchored_start else lay.t0
        if self.tube is not None:
            self._tightened(lay, origin, goal, row_hi, col_lo, col_hi)
        if anchored_start:
            col_lo[w0 * n : (w0 + 1) * n] = self.start
            col_hi[w0 * n : (w0 + 1) * n] = self.start
        return _Bounds(row_lo, row_hi, col_lo, col_hi, anchored_start, origin)

    def _tightened(
        self, lay: _Layout, origin: int, goal: bool, row_hi: np.ndarray, col_lo: np.ndarray, col_hi: np.ndarray
    ) -> None:
        """A problem with a tube (plansynth.reach.robust): tighten the bounds of the
        window's states and inputs, and the goal rows, by the error sets E_t of the tube
        at t = (state time - ``origin``) (the margins of :class:`~plansynth.reach.tube.Tube`,
        constant from their cap on). An LP anchored at the start has ``origin`` 0 (its
        times are absolute); one that is not puts E_0 at the window's first state: the
        earliest placement, where every margin is smallest. The margins never decrease
        in t, so a conflict proved there holds at every time shift DIS-PLAN adds it at
        (later placements only tighten), and none is claimed where it was not proved
        (:meth:`~plansynth.reach.lazy.conplan.certificates._Certificates._shrunk`)."""
        n, m, first = lay.n, lay.m, lay.first
        w0, w1 = lay.t0 - first, lay.t1 - first
        cap = len(self.tube_state_lo) - 1
        steps = np.minimum(np.arange(lay.t0, lay.t1 + 1) - origin, cap)
        xs = slice(w0 * n, (w1 + 1) * n)
        col_lo[xs] += self.tube_state_lo[steps].ravel()
        col_hi[xs] -= self.tube_state_hi[steps].ravel()
        us = slice(lay.n_x + w0 * m, lay.n_x + w1 * m)
        col_lo[us] += self.tube_input_lo[steps[:-1]].ravel()
        col_hi[us] -= self.tube_input_hi[steps[:-1]].ravel()
        if goal:
            row_hi[lay.goal0 : lay.ord0] -= self.tube_goal[steps[-1]]

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
        slot.fresh = old is None or old.frame != lay.frame or slot.coef is None
        if slot.fresh:
            slot.layout = lay
            slot.coef = self._coef_for(lay, assignment)
            slot.coo = self._matrix(lay, slot.coef)
            if slot.splits:
                self._split(slot, lay, b)
            else:
                self._pass(h, lay, slot.coo, b, self._cost(lay))
                if self.n > LONG_CHAIN_STATES:  # a cold simplex run on a long chain needs ~ a row count of iterations
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
                slot.coo = None  # (the goal rows moved: rebuilt when a certificate needs it)
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
        slot.coo = None  # (rebuilt from coef and the layout when a certificate needs it)

    def _slot_coo(self, slot: _Slot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The COO entries of the LP ``slot`` holds, built from its layout and
        coefficients on first use after an edit (only Farkas certificates need them,
        not every LP)."""
        if slot.coo is None:
            assert slot.layout is not None and slot.coef is not None
            slot.coo = self._matrix(slot.layout, slot.coef)
        return slot.coo

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
