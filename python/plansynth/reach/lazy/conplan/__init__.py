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

**Long integrator chains** (more than :data:`LONG_CHAIN_STATES` states; maze-4 with order 25 has 50): the
coefficients dt^k/k! span many decades and bases are often near-singular, so the
simplex method uses a stronger scaling and Devex pricing (dual steepest-edge weights
were recomputed after every warm start); ZEROPREFIX skips the slack LP (``slack_lp``:
several seconds per call there, without a usable warm start) and finds the earliest
infeasible prefix by binary search, cut short by checked Farkas certificates; and when
the dynamics and every region and goal row are separable (chains in box regions: one
block per axis) the feasibility LPs are split into independent HiGHS models
(``split``), each half the size, whose rays are mapped back to the whole LP.

The package, by concern: :mod:`~plansynth.reach.lazy.conplan.check` (the check and its
dispatch to the strategies), :mod:`~plansynth.reach.lazy.conplan.layout` (the LP layout),
:mod:`~plansynth.reach.lazy.conplan.lp` (its edits in place),
:mod:`~plansynth.reach.lazy.conplan.runs` (HiGHS runs and the retry ladder),
:mod:`~plansynth.reach.lazy.conplan.certificates` (rays, shrinking, the deletion filter).
"""

from plansynth.reach.lazy.conplan.check import (
    COUNTEREXAMPLES,
    POLISH_RESIDUAL,
    SLACK_WEIGHTS,
    ZERO_SLACK,
    ConPlan,
    zero_prefix,
)
from plansynth.reach.lazy.conplan.lp import LONG_CHAIN_STATES
from plansynth.reach.lazy.conplan.runs import LpBudgetExhausted, LpFailure, LpStats

__all__ = [
    "ConPlan",
    "LpBudgetExhausted",
    "LpFailure",
    "LpStats",
    "zero_prefix",
    "COUNTEREXAMPLES",
    "SLACK_WEIGHTS",
    "ZERO_SLACK",
    "POLISH_RESIDUAL",
    "LONG_CHAIN_STATES",
]
