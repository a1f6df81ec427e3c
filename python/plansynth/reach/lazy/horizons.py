"""The horizons of DIS-PLAN (Shoukry et al., CDC 2016, Algorithm 1's loop over L), as
:class:`~plansynth.reach.lazy.displan.DisPlan` drives its one SAT instance: activation
literals, the ``before[T]`` ladder, time windows and tubes from a relaxation.

**Incremental horizons.** One solver instance serves every horizon. The clauses that
hold for every horizon (one region per step, transitions, start, conflicts that talk
about a prefix from time 0) are added unconditionally; the goal at horizon L is guarded
by an activation literal ``act[L]`` that is assumed while L is tried and fixed false
once L is refuted. A conflict that involves the goal is guarded by the same literal, so
every learned clause (and everything CaDiCaL learned from it) survives to the next
horizon. Conflicts that use neither the start state nor the goal hold at every time
shift (the dynamics are time-invariant) and are instantiated at every shift.

**Horizon windows (beyond the paper).** ``solve(hi, lowest=lo)`` asks for a plan that
reaches the goal at *some* horizon h in lo..hi: the activation literals of the window
are assumed as one disjunction, and the plan is cut at the smallest h whose ``act[h]``
is true. The bits after h are padding (staying in the goal region satisfies them), so
a clause whose proof needs the states up to time T, which holds only for plans of
horizon >= T, is guarded by ``before[T]`` ("the plan ends before T"), a literal that a
chain of clauses allows only when some ``act[h]`` with h < T is true. With one horizon
at a time (the paper's loop) every horizon below the one tried is closed and the guards
are never needed. Within a window the solver tries short plans first, unless a plan was
passed to :meth:`DisPlan.prefer`: then its horizon comes first, so that the phases
describe one whole plan (the lazy loop times its reference plan to the window's top).

"""

from __future__ import annotations

import math

from plansynth.budget import checkpoint

__all__ = ["HorizonGuards"]


class HorizonGuards:
    """The horizon literals of a DIS-PLAN (see the module docstring), mixed into
    :class:`~plansynth.reach.lazy.displan.DisPlan`: it provides ``pool``, ``solver``,
    ``graph``, ``at``, ``exists``, ``_add``, ``_extend``, ``_ensure_goal`` and the state
    set in its ``__init__`` (``floor``, ``open_from``, ``closed``, ``preferred``,
    ``to_go``, ``to_go_built``, ``window_clauses``)."""

    def act(self, horizon: int) -> int:
        """The activation literal of horizon L (assumed while L is tried)."""
        return self.pool.id(("horizon", horizon))

    def before(self, time: int) -> int | None:
        """The guard ``before[T]`` for a clause that holds for plans of horizon >= T:
        :meth:`ends_before` (see the module docstring), or None when no open horizon lies
        below T, i.e. no guard is needed."""
        if self.open_from is None or time <= self.open_from:
            return None
        return self.ends_before(time)

    def ends_before(self, time: int) -> int | None:
        """The literal e[T], equivalent to ``OR act[h]`` over floor <= h < T: the plan
        ends before T (None when T <= floor: false)."""
        if self.floor is None or time <= self.floor:
            return None
        top = time
        while top > self.floor + 1 and ("ends-before", top - 1) not in self.pool.obj2id:
            top -= 1
        for T in range(top, time + 1):  # build the ladder upwards from the last rung made
            key = ("ends-before", T)
            if key in self.pool.obj2id:
                continue
            e, a = self.pool.id(key), self.act(T - 1)
            lower = self.pool.id(("ends-before", T - 1)) if T - 1 > self.floor else None
            self._add([-e, a] + ([lower] if lower is not None else []))
            self._add([-a, e])
            if lower is not None:
                self._add([-lower, e])
        return self.pool.id(("ends-before", time))

    def _to_go_windows(self) -> None:
        """Region i at time t only if the plan ends at t + to_go[i] or later:
        ``not b[t, i] or not e[t + to_go[i]]``, one clause per (t, i) for every horizon."""
        if self.floor is None:
            return
        for t in range(self.to_go_built + 1, self.built + 1):
            checkpoint()
            for i in range(self.graph.n_regions):
                if not self.exists(t, i) or self.to_go[i] <= 0:
                    continue  # excluded for good already, or a goal region
                if self.to_go[i] == math.inf:
                    self._add([-self.at(t, i)])
                else:
                    e = self.ends_before(t + int(self.to_go[i]))
                    if e is None:
                        continue
                    self._add([-self.at(t, i), -e])
                self.window_clauses += 1
        self.to_go_built = self.built

    def forbid(self, horizon: int, allowed: set[tuple[int, int]]) -> int:
        """Facts for the plans of exactly ``horizon`` steps (the tube of
        :meth:`plansynth.reach.lazy.axisreach.AxisReach.tube`): such a plan is at time
        t <= horizon only in regions i with (t, i) in ``allowed``. Each other b[t, i]
        gets ``not act[L] or e[L] or not b[t, i]`` ("the plan ends exactly at L" implies
        not region i at t; e[L]: it ends before L), so no plan of another horizon is
        affected. Returns the number of clauses added (also counted in
        ``window_clauses``)."""
        self._extend(horizon)
        self._ensure_goal(horizon)
        guard = [-self.act(horizon)]
        e = self.ends_before(horizon)
        if e is not None:
            guard.append(e)
        added = 0
        for t in range(horizon + 1):
            for i in range(self.graph.n_regions):
                if (t, i) not in allowed and self.exists(t, i):
                    self._add(guard + [-self.at(t, i)])
                    added += 1
        self.window_clauses += added
        return added

    def begin(self, lowest: int) -> None:
        """Make ``lowest`` the first horizon tried (no plan is shorter: the horizons below it
        are refuted by other means) before the first :meth:`solve`, whose first question may
        then be about a higher horizon (a plan found without DIS-PLAN, proved minimal by
        probes below it). No effect once a horizon was tried."""
        if self.floor is None:
            self.floor = self.open_from = int(lowest)

    def close(self, horizon: int) -> None:
        """Horizon L is refuted: fix its activation literal false for good."""
        self.closed.add(horizon)
        self._add([-self.act(horizon)])
        if self.open_from is not None:
            while self.open_from in self.closed:
                self.open_from += 1

    def _open(self, lo: int) -> None:
        """The first question fixes the floor (no plan is shorter); later ones may not
        ask below it."""
        if self.floor is None:
            self.floor = self.open_from = lo
            self._to_go_windows()
            if self.preferred is not None:  # prefer() came first: the plan ends at its horizon, not before
                self.solver.set_phases(
                    [-e for e in (self.ends_before(T) for T in range(lo + 1, self.preferred + 1)) if e is not None]
                )
        elif lo < self.floor:
            raise ValueError(f"horizon {lo} is below the first horizon tried ({self.floor})")

    def _window(self, lo: int, horizon: int) -> list[int] | None:
        """The assumptions that ask for a plan ending at some open horizon in
        lo..horizon, and at none below lo; None when every one of them is closed."""
        window = [h for h in range(lo, horizon + 1) if h not in self.closed]
        if not window:
            return None
        if len(window) == 1:
            assumptions = [self.act(window[0])]
        else:
            select = self.pool.id(("window", lo, horizon))
            self._add([-select] + [self.act(h) for h in window])
            assumptions = [select]
            # the preferred plan's horizon first (its phases describe a plan ending
            # there); without one, short plans: every activation literal false first
            self.solver.set_phases([self.act(h) if h == self.preferred else -self.act(h) for h in window])
        # open horizons below the window are not part of this question
        assumptions += [-self.act(h) for h in range(self.floor, lo) if h not in self.closed]
        return assumptions

    def _ended(self, true: set[int], horizon: int) -> int:
        """The horizon of a model's plan: the smallest one whose activation literal is
        true (every guarded clause then holds for it, see :meth:`before`)."""
        return next(h for h in range(self.floor, horizon + 1) if self.act(h) in true)
