"""CON-PLAN's check and its dispatch to the counterexample strategies (see
:mod:`plansynth.reach.lazy.conplan`): the feasibility LP of a region sequence, ZEROPREFIX
(Algorithm 2), the trivial and the IIS counterexamples, and the polishing of a found
trajectory."""

from __future__ import annotations

import time
from collections.abc import Sequence
from contextlib import ExitStack

import highspy
import numpy as np

from plansynth.budget import Clock
from plansynth.reach.abstraction import Abstraction
from plansynth.reach.geometry import halfspaces
from plansynth.reach.lazy.conflict import Conflict, Feasible
from plansynth.reach.lazy.conplan.certificates import _Certificates
from plansynth.reach.lazy.conplan.lp import INF, LONG_CHAIN_STATES, _LpEdits, _Slot
from plansynth.reach.lazy.conplan.runs import LpFailure, LpStats, _HighsRuns, _options
from plansynth.reach.problem import ReachProblem
from plansynth.reach.trajectory import Trajectory

COUNTEREXAMPLES = ("zeroprefix", "trivial", "iis")
SLACK_WEIGHTS = ("geometric", "uniform")
ZERO_SLACK = 1e-7  # a slack at most this is zero (HiGHS's primal feasibility tolerance)
#: Dynamics whose A has more nonzeros than this make every LP dear (see ConPlan.dear)
DEAR_NONZEROS = 1000
POLISH_RESIDUAL = 1e-8  # dynamics residual above which a found trajectory is re-solved (validator: 1e-6)
WARM_POLISH_RESIDUAL = 1e-7  # a warm re-solve at tight tolerances is kept at this (10x within the validator's 1e-6)


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


class ConPlan(_Certificates, _HighsRuns, _LpEdits):
    """The theory solver of the lazy loop for one problem and abstraction.

    ``check(regions)`` returns :class:`Feasible` or a sound
    :class:`~plansynth.reach.lazy.conflict.Conflict`. ``slack_lp`` (ZEROPREFIX's slack LP)
    and ``split`` (independent LP blocks) default to what suits the state dimension:
    slack LP up to :data:`LONG_CHAIN_STATES` states, split beyond.
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
            raise ValueError(
                f"unknown counterexample strategy {counterexample!r} (known: {', '.join(COUNTEREXAMPLES)})"
            )
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
        self.slack_lp = problem.dynamics.n_states <= LONG_CHAIN_STATES if slack_lp is None else bool(slack_lp)
        self.clock = clock
        dyn = problem.dynamics
        self.n, self.m = dyn.n_states, dyn.n_inputs
        self.A, self.B = np.asarray(dyn.A, float), np.asarray(dyn.B, float)
        # dense dynamics (n = 50 random dynamics: 2,402 nonzeros in A, 0.1-2 s per LP at
        # horizon 100): a conflict keeps its Farkas support, without the deletion filter
        # (one LP per literal) and the unanchoring LP, which were two thirds of the LP
        # time there (maze-3: 84 of 133 LPs, 95 of 141 s) while the window search defers
        # such windows after a few plans anyway
        # long integrator chains too (an order-25 chain: 0.4-1.5 s per plan LP; maze-2:
        # 55 LPs in 5.0 s -> 37 in 2.9 s, order 10 on maze-4: 108 LPs in 1.5 s -> 79 in 0.7 s)
        self.dear = int(np.count_nonzero(self.A)) > DEAR_NONZEROS or dyn.n_states > LONG_CHAIN_STATES
        # set by the lazy loop (TheoryChecker): a plan whose failure defers its window; a
        # plan LP the interior-point method refutes then keeps that answer, without the
        # simplex run for its Farkas ray (the conflict is the whole plan, unshrunk)
        self.expendable = False
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
        # a tightened problem (plansynth.reach.robust): the step-wise margins of its tube
        self.tube = problem.tube if problem.tube is not None and problem.tube.varies else None
        if self.tube is not None:
            self.tube_state_lo, self.tube_state_hi = self.tube.state_margins()
            self.tube_input_lo, self.tube_input_hi = self.tube.input_margins()
            self.tube_goal = self.tube.position_margins(self.Hgoal, dyn.position)
        self.stats = LpStats()
        # persistent, warm-started models: the slack LPs of Problem 5.2 in one, the
        # feasibility LPs (plan, prefixes, unanchoring) in the other
        self.slack_slot = _Slot(self._new_highs())
        self.slot = _Slot(self._new_highs())
        self.span_slot = _Slot(self._new_highs())  # LPs over a conflict's time span
        self.cold = self._new_highs()  # one-off LPs (re-checks, IIS, fallbacks)
        self.elastic_slot: _Slot | None = None  # violations(): made on first use
        # independent blocks of the feasibility LPs (None: one block); by default split
        # long chains only, where an LP per axis with a fraction of the rows each is
        # cheaper than the whole (the slack LP couples the axes and stays whole)
        self.blocks = self._blocks()
        if split is None:
            split = self.n > LONG_CHAIN_STATES
        self.slot.splits = self.span_slot.splits = bool(split) and self.blocks is not None
        self._no_ray = False  # the last infeasible LP was decided outside the persistent model
        self._ray_part: int | None = None  # the split part of the last Farkas ray
        if self.n > LONG_CHAIN_STATES:
            # long integrator chains (tiny coefficients dt^k/k!): equilibrate harder, cap
            # the simplex iterations (at about twice the row count per model, see _load)
            # and fall back to the interior-point method when stuck
            for h in (self.slot.highs, self.span_slot.highs, self.slack_slot.highs, self.cold):
                h.setOptionValue("simplex_iteration_limit", 5000)
                h.setOptionValue("simplex_scale_strategy", 4)
                # Devex pricing: dual steepest-edge weights are recomputed after every
                # warm start and every rank-deficient basis, both frequent on long chains
                h.setOptionValue("simplex_dual_edge_weight_strategy", 1)

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
        chains), which the validator rejects. Then the plan's LP is solved again from the
        basis it ended at, unscaled and at tolerances of 1e-10 (:meth:`_polished_warm`;
        kept when its residual is at most :data:`WARM_POLISH_RESIDUAL`: order 25, maze-1:
        1.6e-7 -> 4.4e-8 in 0.08 s), else once more
        from scratch with tight tolerances: first by the interior-point method with
        crossover (maze-4 at order 25: residual 4e-10 where the simplex polish below
        left 1.9e-6, in half its time), and when that is not below
        :data:`POLISH_RESIDUAL`, by the simplex method with presolve and without
        scaling. The answer with the smallest residual is kept."""
        if self.residual(found.trajectory) <= POLISH_RESIDUAL:
            return found
        warm = self._polished_warm(regions)
        if warm is not None and self.residual(warm.trajectory) < self.residual(found.trajectory):
            found = warm
            if self.residual(found.trajectory) <= WARM_POLISH_RESIDUAL:
                return found
        lay = self.layout(0, len(regions) - 1)
        methods = (
            {
                "solver": "ipm",
                "presolve": "off",
                "run_crossover": "on",
                "primal_feasibility_tolerance": 1e-10,
                "dual_feasibility_tolerance": 1e-10,
                "ipm_optimality_tolerance": 1e-10,
            },
            {
                "solver": "simplex",
                "presolve": "on",
                "simplex_scale_strategy": 0,
                "primal_feasibility_tolerance": 1e-10,
                "dual_feasibility_tolerance": 1e-10,
                "simplex_iteration_limit": 2**31 - 1,
            },
        )
        best = found
        for tight in methods:
            self._pass_cold(lay, dict(enumerate(int(r) for r in regions)), goal=True, anchored_start=True)
            h = self.cold
            if self.clock is not None:  # within the budget: a polish cut short keeps the best answer so far
                if self.clock.remaining() <= 0:
                    break
                tight = {**tight, "time_limit": float(h.getRunTime() + max(1e-3, min(self.clock.remaining(), 1e9)))}
            with _options(h, tight):
                t0 = time.perf_counter()
                h.run()
                self.stats.seconds += time.perf_counter() - t0
                self.stats.lp_calls += 1
                self.stats.by_kind["polish"] = self.stats.by_kind.get("polish", 0) + 1
                if h.getModelStatus() != highspy.HighsModelStatus.kOptimal:
                    continue
                again = Feasible(self._trajectory(lay, np.asarray(h.getSolution().col_value)))
            self.stats.polished += 1
            if self.residual(again.trajectory) < self.residual(best.trajectory):
                best = again
            if self.residual(best.trajectory) <= POLISH_RESIDUAL:
                break
        return best

    def _polished_warm(self, regions: Sequence[int]) -> Feasible | None:
        """The plan's LP once more in the model that just solved it, from its basis, with
        HiGHS's primal and dual feasibility tolerances at 1e-10 instead of 1e-7: a few
        simplex iterations where the cold polish below solves the LP from scratch (an
        order-25 chain at horizon 98: 2.9 s, 40% of the plan). None when the model does
        not hold the plan's LP or gives no answer."""
        N = len(regions) - 1
        slot = self.slot
        if slot.held != ("plan", N, True) or slot.layout is None or (slot.layout.t0, slot.layout.t1) != (0, N):
            return None
        models = [p.highs for p in slot.parts] if slot.parts is not None else [slot.highs]
        tight = {
            "primal_feasibility_tolerance": 1e-10,
            "dual_feasibility_tolerance": 1e-10,
            "simplex_scale_strategy": 0,
        }
        try:
            with ExitStack() as stack:
                for h in models:
                    stack.enter_context(_options(h, tight))
                    basis = h.getBasis()  # (HiGHS does not re-run a solved model: its basis again,
                    h.clearSolver()  # refactorised at the new tolerances)
                    h.setBasis(basis)
                col = self._run_slot(slot, "polish")
        except LpFailure:
            return None
        finally:
            slot.held = None  # (solved with other tolerances)
        if col is None:
            return None
        self.stats.polished += 1
        return Feasible(self._trajectory(slot.layout, col))

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
            if self.dear:
                return out  # (see __init__)
            if self.minimize:
                out = self._minimize(regions, out)
            out = self._unanchor(regions, out)
        return out

    def feasible(self, regions: Sequence[int]) -> Trajectory | None:
        """The plain feasibility LP of the whole plan (goal included): a trajectory or None."""
        N = len(regions) - 1
        col = self._solve_model(N, dict(enumerate(int(r) for r in regions)), "plan", goal=True)
        return None if col is None else self._trajectory(self._held_layout(), col)

    def violations(self, regions: Sequence[int], tol: float = 0.0) -> tuple[np.ndarray, Feasible | None] | None:
        """Where ``regions`` (r_0..r_N) asks too much (beyond the paper; the timed route of
        :mod:`plansynth.reach.lazy.timed` reads it): the plan's LP with a free slack
        s_t >= 0 on every row on p_t (its region, the segment row of time t - 1 and, at
        N, the goal) and the sum of the slacks minimised, unordered (ZEROPREFIX's slack
        LP orders them). Returns s_0..s_N, zero exactly when the plan is realisable,
        else nonzero around the steps it times too tightly, and when every slack is at
        most ``tol`` the LP's trajectory (polished as :meth:`check` polishes), which then
        realises the plan; None when even the slacks cannot make the LP feasible (the
        dynamics and bounds alone refute it). Not a counterexample: no clause is drawn
        from it."""
        N = len(regions) - 1
        plan = dict(enumerate(int(r) for r in regions))
        if self.elastic_slot is None:
            self.elastic_slot = _Slot(self._new_highs())
        slot = self.elastic_slot
        cur = slot.layout
        if cur is not None and cur.first == 0 and N <= cur.last and 2 * (N + 1) >= cur.T:
            lay = cur.window(0, N)
        else:  # the repair lengthens plans round by round: a frame a quarter longer keeps them warm
            lay = self.layout(0, N + max(4, N // 4)).window(0, N)
        b = self.bounds(lay, plan, goal=True, anchored_start=True, slack=True)
        b.row_hi[lay.ord0 : lay.ord0 + lay.steps] = INF  # (no order among the slacks)
        self._load(slot, lay, plan, b)
        cost = np.zeros(lay.n_col)
        cost[lay.s(lay.t0) : lay.s(lay.t1) + 1] = 1.0
        slot.highs.changeColsCost(lay.n_col, np.arange(lay.n_col, dtype=np.int32), cost)
        col = self._run_slot(slot, "violations")
        slot.held = ("violations", N, col is not None)
        if col is None:
            return None
        slack = np.maximum(col[lay.s(lay.t0) : lay.s(lay.t1) + 1], 0.0)
        if slack.max(initial=0.0) > tol:
            return slack, None
        return slack, self._polished(regions, Feasible(self._trajectory(lay, col)))

    def _whole(self, regions: Sequence[int]) -> Conflict:
        N = len(regions) - 1
        return Conflict(tuple(enumerate(regions)), anchored_start=True, anchored_goal=True, horizon=N)

    def _prefix(self, regions: Sequence[int], k: int) -> Conflict:
        N = len(regions) - 1
        return Conflict(
            tuple((t, regions[t]) for t in range(k + 1)),
            anchored_start=True,
            anchored_goal=False,
            horizon=N,
            last_time=N,
        )

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
        self.cold.setOptionValue(
            "iis_strategy",
            int(highspy.IisStrategy.kIisStrategyFromLp) | int(highspy.IisStrategy.kIisStrategyIrreducible),
        )
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
