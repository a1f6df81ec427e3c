"""Hints to DIS-PLAN's SAT solver (beyond Shoukry et al., CDC 2016): the decision phases
of a reference plan, so that CaDiCaL tries it (or its neighbourhood) first. Only hints:
no answer depends on them.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["PlanHints"]


class PlanHints:
    """:meth:`prefer`, mixed into :class:`~plansynth.reach.lazy.displan.DisPlan` (it
    provides ``pool``, ``solver``, ``graph``, ``paths``, ``floor``, ``at``, ``_extend``
    and ``ends_before``)."""

    preferred: int | None

    def prefer(self, plan: Sequence[int]) -> None:
        """Set the SAT solver's decision phases to ``plan`` (r_0..r_h): b[t, plan[t]]
        true, the other regions false, and the plan ending at h (a window that contains h
        tries h first). Only a hint; no answer depends on it."""
        H = len(plan) - 1
        self.preferred = H
        self._extend(H)
        if self.paths:
            obj = self.pool.obj2id
            phases = [
                v if i == r else -v
                for t, r in enumerate(plan)
                for i in range(self.graph.n_regions)
                if (v := obj.get(("at", t, i))) is not None
            ]
        else:
            phases = [
                self.at(t, i) if i == r else -self.at(t, i)
                for t, r in enumerate(plan)
                for i in range(self.graph.n_regions)
            ]
        if self.floor is not None:  # ... and ending at H, not before
            phases += [-e for e in (self.ends_before(T) for T in range(self.floor + 1, H + 1)) if e is not None]
        if self.paths:  # no auxiliary variables to phase
            self.solver.set_phases(phases)
            return
        # the auxiliary variables of the exactly-one encoding (seqcounter, beyond 8
        # regions) as the plan implies them: unphased, their default phase would steer
        # the search off the plan at once
        ok, implied = self.solver.propagate(assumptions=[self.at(t, r) for t, r in enumerate(plan)])
        if ok:
            phases += [v for v in implied if abs(v) > 0]
        self.solver.set_phases(phases)
