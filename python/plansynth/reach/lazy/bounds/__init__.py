"""Relaxations of CON-PLAN that hold for every region sequence: horizon lower bounds
and time windows for DIS-PLAN (beyond Shoukry et al., CDC 2016; every bound is sound).

* :func:`step_reach` and :func:`physical_lower_bound`: how far the robot can move per
  step along each axis (one small LP per axis and direction), and the distance to the
  goal divided by it;
* :func:`time_windows`: the displacement-box relaxation swept along the region graph,
  the first step at which each region (and the goal) can be reached, and how many
  steps the goal is at least away from each region;
* :func:`proved_horizon_bound`: a lower bound on the horizon of *every* trajectory of
  the problem, whatever the decomposition, which is what may prove ``infeasible``.

* :func:`step_adjacency` and :func:`touching`: which regions one step can connect;
* :func:`separator_bounds` and :func:`chain_gaps`: windows and a horizon bound from
  the regions every plan must pass through.

The lazy loop (:mod:`plansynth.reach.lazy.loop`), the transit layer, the region MILP
and the mission planners use them. One module per bound:

``step``       :func:`step_reach`, :func:`physical_lower_bound`, :func:`box_steps`;
``windows``    :func:`time_windows` (the sweep and its reference beside it);
``adjacency``  :func:`touching`, :func:`step_adjacency`;
``proved``     :func:`proved_horizon_bound`;
``chains``     :func:`separator_bounds`, :func:`chain_gaps`.
"""

from plansynth.reach.lazy.bounds.adjacency import step_adjacency, touching
from plansynth.reach.lazy.bounds.chains import (
    GOAL_NODE,
    SEPARATOR_MAX_REGIONS,
    START_NODE,
    ChainBounds,
    chain_gaps,
    separator_bounds,
)
from plansynth.reach.lazy.bounds.proved import SWEEP_MAX_REGIONS, SWEEP_MAX_WORK, proved_horizon_bound
from plansynth.reach.lazy.bounds.step import MULTISTEP_TABLE, box_steps, physical_lower_bound, shape_box, step_reach
from plansynth.reach.lazy.bounds.windows import TimeWindows, time_windows

__all__ = [
    "step_reach",
    "physical_lower_bound",
    "shape_box",
    "box_steps",
    "TimeWindows",
    "time_windows",
    "touching",
    "step_adjacency",
    "proved_horizon_bound",
    "SWEEP_MAX_REGIONS",
    "SWEEP_MAX_WORK",
    "MULTISTEP_TABLE",
    "SEPARATOR_MAX_REGIONS",
    "START_NODE",
    "GOAL_NODE",
    "ChainBounds",
    "separator_bounds",
    "chain_gaps",
]
