"""Shorter segment-safe trajectories by separating half-spaces (beyond Shoukry et al.,
CDC 2016): the upper side of the minimal-horizon search with exact segment
transitions (:mod:`plansynth.reach.lazy.segments`).

With exact transitions a segment may cross several regions, and the shortest plans
cut corners the decomposition's regions do not (the GCS paper's 10 x 10 maze: 46 steps
through the decomposition, 33 for the problem). DIS-PLAN finds such plans only after
many points along the segments; this module finds them from a plan already found,
one horizon shorter at a time, by sequential linear programming (the idea of the
convex feasible set algorithm, Liu, Lin and Tomizuka, 2018):

1. the reference positions: the plan's, resampled in time to one step fewer;
2. per segment of the reference and per obstacle piece near it, the half-space
   beyond that piece with the widest margin for both ends
   (:meth:`~plansynth.reach.lazy.segtheory.ObstaclePiece.separators`: a face, or in
   2-D the line through a vertex along the segment); a segment whose two ends lie
   beyond one such half-space misses the piece (a half-space is convex);
3. one LP (:class:`~plansynth.reach.lazy.pointlp.PointLP` without regions): the
   states with the start, dynamics, input and state bounds, both ends of each segment
   beyond its half-spaces and the last position in the goal, each of those rows with
   a slack, the slacks' weighted sum minimised;
4. its trajectory is checked exactly (every segment against every piece,
   :func:`~plansynth.reach.lazy.bounds.depth.segment_depth`); accepted when no slack
   is left and no segment cuts a piece deeper than
   :data:`~plansynth.reach.lazy.segtheory.ACCEPT_DEPTH`; otherwise it becomes the
   reference (pieces a segment cut join that segment's rows) and the LP is solved
   again, up to :data:`ROUNDS` times.

Only a plan is ever produced here, never a refutation: every trajectory returned has
passed the exact check (and the planner's validator checks it again), and the
horizons below it are left to the lazy loop's probes
(:func:`~plansynth.reach.lazy.minimal.prove_minimal`), so the claims stay sound. The
samples' regions of a trajectory found are the first region of the decomposition
holding each sample (the phases DIS-PLAN's later probes follow).
"""

from __future__ import annotations

import time

import numpy as np

from plansynth.budget import BudgetExhausted, Clock
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import halfspaces
from plansynth.reach.lazy.conplan.runs import LpFailure
from plansynth.reach.lazy.loop import LoopOutcome
from plansynth.reach.lazy.pointlp import PointLP
from plansynth.reach.lazy.segments import DENOM
from plansynth.reach.lazy.segtheory import SegmentTheory
from plansynth.reach.result import ReachStatus
from plansynth.reach.trajectory import Trajectory

__all__ = ["Descent", "ROUNDS", "SOFT_WEIGHT"]

#: LPs per horizon before the descent gives that horizon up.
ROUNDS = 6
#: The weight of a separating row's slack against the goal's.
SOFT_WEIGHT = 10.0
#: Slack left below this (relative to the workspace's size) counts as none.
SLACK_TOL = 1e-7


class Descent:
    """Lower a segment-safe plan's horizon by the separating-half-space LP (see the
    module docstring). ``theory``: the exact segment theory (its obstacle pieces and its
    exact check). Counters: ``lp_calls``, ``seconds``, ``horizons`` (horizons it
    lowered a plan to)."""

    def __init__(self, theory: SegmentTheory, abstraction: Abstraction, clock: Clock | None = None) -> None:
        self.theory = theory
        self.abstraction = abstraction
        self.problem = theory.problem
        self.lp = PointLP(self.problem, abstraction, clock)
        self.clock = clock
        self.pos = np.asarray(theory.pos)
        ws_lo, ws_hi = (np.asarray(a, float) for a in (self.problem.workspace.lo, self.problem.workspace.hi))
        self.scale = float(np.max(ws_hi - ws_lo))
        self.Hg, self.hg = (np.asarray(a, float) for a in halfspaces(self.problem.goal))
        self.seconds = 0.0
        self.horizons = 0

    @property
    def lp_calls(self) -> int:
        return self.lp.lp_calls

    def lowered(self, best: LoopOutcome, bottom: int) -> LoopOutcome:
        """``best`` (found, with a trajectory) at the lowest horizon down to ``bottom``
        that the descent reaches one step at a time; ``best`` itself when it reaches none.
        Not minimal (nothing is refuted here)."""
        t0 = time.perf_counter()
        try:
            while best.horizon is not None and best.horizon > bottom and best.trajectory is not None:
                if self.clock is not None and self.clock.exhausted():
                    break
                H = best.horizon - 1
                traj = self.at_horizon(np.asarray(best.trajectory.states)[:, self.pos], H)
                if traj is None:
                    break
                self.horizons += 1
                best = LoopOutcome(
                    ReachStatus.FOUND,
                    H,
                    f"found at horizon {H} (lowered by separating half-spaces)",
                    traj,
                    self.regions_of(traj),
                    minimal=False,
                )
        except (BudgetExhausted, LpFailure):
            pass  # the best plan so far stands; the probes report the budget
        finally:
            self.seconds += time.perf_counter() - t0
        return best

    def at_horizon(self, P: np.ndarray, H: int) -> Trajectory | None:
        """A segment-safe trajectory of horizon H near the positions P (any length),
        resampled in time to H + 1 positions, or None after :data:`ROUNDS` LPs."""
        R = _resampled(P, H)
        rows: set[tuple[int, int]] = set()  # (segment, piece): its separating rows
        pieces = self.theory.pieces
        lo_b = np.array([pc.lo for pc in pieces]) if pieces else np.zeros((0, len(self.pos)))
        hi_b = np.array([pc.hi for pc in pieces]) if pieces else np.zeros((0, len(self.pos)))
        for _ in range(ROUNDS):
            a, b = R[:-1], R[1:]
            reach = float(np.max(np.abs(b - a))) if H > 0 else 0.0  # (a neighbourhood of each segment)
            lo, hi = np.minimum(a, b) - reach, np.maximum(a, b) + reach
            for t in range(H):
                near = np.nonzero(np.all(lo[t] < hi_b, axis=1) & np.all(hi[t] > lo_b, axis=1))[0]
                rows.update((t, int(k)) for k in near if len(pieces[k].h))
            extra = []
            for t, k in sorted(rows):
                n, c = pieces[k].separators(R[t], R[t + 1])
                extra += [(t, 0, n, c), (t, DENOM, n, c)]
            sol = self.lp.solve({}, {}, 0, H, start=True, goal=True, extra=extra, soft=SOFT_WEIGHT)
            if sol is None:  # (a slack LP is feasible unless the dynamics cannot hold at all)
                return None
            X, U = sol
            P_new = X[:, self.pos]
            cuts = self.theory.cuts(X)
            goal_gap = float(np.max(self.Hg @ P_new[-1] - self.hg, initial=0.0))
            if not cuts and goal_gap <= SLACK_TOL * max(1.0, self.scale):
                return Trajectory(states=X, inputs=U)
            rows.update((t, k) for t, _, k, _ in cuts)
            if np.allclose(P_new, R, atol=SLACK_TOL * max(1.0, self.scale)):
                return None  # (a fixed point with slack left)
            R = P_new
        return None

    def regions_of(self, traj: Trajectory) -> tuple[int, ...]:
        """A region of the decomposition holding each sample (the nearest when rounding
        leaves a sample just outside every region)."""
        out = []
        regions = self.abstraction.regions
        for p in np.asarray(traj.states)[:, self.pos]:
            slack = [float(np.max(np.asarray(r.H) @ p - np.asarray(r.h))) for r in regions]
            out.append(int(np.argmin(slack)))
        return tuple(out)


def _resampled(P: np.ndarray, H: int) -> np.ndarray:
    """The positions P (h + 1 of them) resampled at H + 1 evenly spaced times, linearly
    between the samples.

    >>> _resampled(np.array([[0.0], [1.0], [2.0], [3.0]]), 2).ravel().tolist()
    [0.0, 1.5, 3.0]
    """
    h = len(P) - 1
    if H <= 0 or h <= 0:
        return np.repeat(P[-1:], H + 1, axis=0)
    s = np.arange(H + 1) * (h / H)
    i = np.minimum(np.floor(s).astype(int), h - 1)
    w = (s - i)[:, None]
    return (1 - w) * P[i] + w * P[i + 1]
