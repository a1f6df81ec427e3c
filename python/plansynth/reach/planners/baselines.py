"""The region MILP and the baselines as :class:`~plansynth.reach.planners.Planner`
values: each its name, its options value (:mod:`plansynth.reach.planners.options`,
:mod:`plansynth.reach.mission.options`), the solver packages whose versions it reports
and the ``"module:function"`` that plans (loaded on its first solve, so this module and
``plansynth reach solve --help`` load no solver).

>>> MILP.configure(max_horizon=60)
MilpOptions(max_horizon=60, start_horizon=None, segment_safe=True)
>>> MILP_LTL_ONESHOT.configure().one_shot, MILP_LTL.defaults is None
(True, True)
"""

from __future__ import annotations

from plansynth.reach.lazy.options import LazyOptions
from plansynth.reach.mission.options import MilpLtlOptions
from plansynth.reach.planners import OptionsPlanner
from plansynth.reach.planners.options import BigMOptions, FppOptions, GcsOptions, MilpOptions, OmplOptions

__all__ = [
    "MILP",
    "MILP_BIGM",
    "RRT",
    "EST",
    "KPIECE",
    "GCS",
    "GCS_DECOMPOSITION",
    "FPP",
    "MILP_LTL",
    "MILP_LTL_ONESHOT",
    "NOMINAL_CHECK",
]

_HIGHS = ("highspy",)

#: ``milp``: the region MILP, one per horizon (:func:`plansynth.reach.planners.milp.plan_milp`)
MILP = OptionsPlanner(
    "milp",
    MilpOptions(),
    "plansynth.reach.planners.milp:plan_milp",
    _HIGHS,
    takes_abstraction=True,
    disturbances="tightened",
)
#: ``milp-bigm``: the big-M MILP over the obstacles (:mod:`plansynth.reach.planners.milp_bigm`)
MILP_BIGM = OptionsPlanner(
    "milp-bigm", BigMOptions(), "plansynth.reach.planners.milp_bigm:run", _HIGHS, disturbances="tightened"
)
#: OMPL's kinodynamic planners (:mod:`plansynth.reach.planners.ompl`)
RRT = OptionsPlanner("rrt", OmplOptions(), "plansynth.reach.planners.ompl:run_rrt", ("ompl",))
EST = OptionsPlanner("est", OmplOptions(), "plansynth.reach.planners.ompl:run_est", ("ompl",))
KPIECE = OptionsPlanner("kpiece", OmplOptions(), "plansynth.reach.planners.ompl:run_kpiece", ("ompl",))
#: ``gcs``: Drake's Graphs of Convex Sets (:mod:`plansynth.reach.planners.gcs`)
GCS = OptionsPlanner("gcs", GcsOptions(), "plansynth.reach.planners.gcs:run", ("drake",), takes_abstraction=True)
#: ``gcs-decomposition``: GCS over the lazy planner's disjoint regions (``sets`` fixed)
GCS_DECOMPOSITION = OptionsPlanner(
    "gcs-decomposition",
    GcsOptions(sets="decomposition"),
    "plansynth.reach.planners.gcs:run",
    ("drake",),
    settable=("variant", "order", "time_unit", "max_rounded_paths", "segment_safe", "max_horizon"),
    takes_abstraction=True,
)
#: ``fpp``: fast path planning through the free boxes (:mod:`plansynth.reach.planners.fpp`)
FPP = OptionsPlanner("fpp", FppOptions(), "plansynth.reach.planners.fpp:run", ("fastpathplanning", "cvxpy"))
#: ``milp-ltl``: the bounded mission as one big-M MILP per horizon (missions only;
#: :func:`plansynth.reach.mission.milp.plan_milp_ltl`)
MILP_LTL = OptionsPlanner(
    "milp-ltl",
    None,
    "plansynth.reach.mission.milp:plan_milp_ltl",
    _HIGHS,
    mission_defaults=MilpLtlOptions(),
    disturbances="tightened",
)
#: ``milp-ltl-oneshot``: one MILP at the max horizon (Wolff et al.'s fixed horizon K)
MILP_LTL_ONESHOT = OptionsPlanner(
    "milp-ltl-oneshot",
    None,
    "plansynth.reach.mission.milp:plan_milp_ltl",
    _HIGHS,
    mission_defaults=MilpLtlOptions(one_shot=True),
    disturbances="tightened",
)
#: ``nominal-check``: under a disturbance, the nominal plan (lazy-smt on the problem
#: without it) and then the robust check with the design's gain: the baseline that shows
#: what planning for the tube buys (:mod:`plansynth.reach.robust.baseline`)
NOMINAL_CHECK = OptionsPlanner(
    "nominal-check",
    LazyOptions(),
    "plansynth.reach.robust.baseline:run",
    ("python-sat", "highspy"),
    disturbances="nominal",
)
