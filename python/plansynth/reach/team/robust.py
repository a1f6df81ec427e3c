"""Teams under bounded disturbances: the tightened team problem the team planners plan
(robust planning, :mod:`plansynth.reach.robust`, for several robots; beyond Shoukry et
al., CDC 2016, whose Section VII leaves bounded disturbances as future work).

Each robot r with a ``disturbance`` (its own W_r and feedback design) follows its
nominal plan with ``u = v + K_r (x - x_nom)``; its error stays in the tube E_{r,t}
(:mod:`plansynth.reach.tube`), and the disturbances of different robots are
independent. The team is tightened robot by robot and pair by pair:

* **each robot's own constraints** exactly as for one robot, by the single-robot
  tightening (:func:`plansynth.reach.robust.tighten.tightened` on the robot's own
  problem): static obstacles grown by the tube's largest cross-section, state bounds,
  workspace, input bound and goal tightened by E_{r,t} at every step, the horizon
  lowered where a bound runs out of room; a robot that must end where it can stay
  (``stop``) keeps its resting input within the bound less the feedback's largest
  share (the cap of ``h_{E_r}(+-K_j)``);
* **the separation between robots i and j**: their relative position is
  ``z + e_i - e_j`` with ``e_i in E_{i,t}`` and ``e_j in E_{j,t}`` independent, i.e.
  ``z + D_t`` with ``D_t = E_{i,t} + (-E_{j,t})`` (position parts, Minkowski sum). A side
  ``a_k z >= b_k`` of the pair's forbidden polygon (:mod:`plansynth.reach.team.geometry`:
  ``d P + K_i + (-K_j)``, the separation d in the norm with unit ball P and the robots'
  shapes) holds for every error pair exactly when

      ``a_k z >= b_k + h_{E_{i,t}}(-a_k) + h_{E_{j,t}}(a_k)``    (= b_k + h_{D_t}(-a_k)),

  so each side is moved out by the support of both tubes in its direction, at each
  sample t (the margins of the sample's own time); the forbidden polygon grows to
  ``F + (-D_t)``'s outer polygon with F's facet normals. A side held at both samples of
  a step by every error pair holds along the disturbed step (the disturbed relative
  motion is a straight segment between the disturbed samples);
* **a moving obstacle** against robot r: a side ``a_k (p - c(t)) >= b_k`` by
  ``h_{E_{r,t}}(-a_k)``; at a waypoint time inside a step (a fraction lam of it) by
  ``(1 - lam) h_{E_{r,t}}(-a_k) + lam h_{E_{r,t+1}}(-a_k)`` (the disturbed position
  there interpolates the disturbed samples).

Robots without a disturbance have no tube (margins 0). Every margin is non-decreasing in
t, so a counterexample proved at some steps also holds at every later placement, but not
at earlier ones: the team planners learn the clauses of a tightened team only at
non-negative time shifts (:attr:`~plansynth.reach.team.plans.TeamConflict.later_only`).

What a plan guarantees (:data:`GUARANTEE`) and what ``infeasible`` is relative to
(:data:`~plansynth.reach.robust.tighten.RELATIVE`, for every robot's design) are
recorded with the result (:func:`record`). A robot under a disturbance has a goal
region (not a point) and no mission (checked when the problem is made).

>>> from plansynth.reach.team.families import windy_swap
>>> t = tightened_team(windy_swap())
>>> t.status is None, [d is not None for d in t.designs], t.max_horizon <= windy_swap().max_horizon
(True, [True, True], True)
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robust.tighten import LAW, RELATIVE, RobustDesign, robust_design, tightened
from plansynth.reach.team.geometry import Facets
from plansynth.reach.team.problem import TeamProblem
from plansynth.reach.tube import Tube

__all__ = [
    "GUARANTEE",
    "SEPARATION",
    "RobotMargins",
    "TightenedTeam",
    "tightened_team",
    "is_disturbed",
    "robot_margins",
    "pair_margins",
    "obstacle_margins",
    "record",
    "without_disturbances",
]

GUARANTEE = (
    "every disturbance sequence within each robot's W keeps every closed loop safe, separated and reaching "
    "(for the tightened sets as computed)"
)
SEPARATION = (
    "each side a.z >= b of a pair's forbidden polygon moved out by h_E_i,t(-a) + h_E_j,t(a) (the support of both "
    "robots' error sets, E_i,t + (-E_j,t)) at every sample; against a moving obstacle by h_E_r,t(-a)"
)


def is_disturbed(problem: Any) -> bool:
    """Does some robot of the team carry a disturbance?"""
    return any(getattr(r, "disturbance", None) is not None for r in getattr(problem, "robots", ()))


@dataclass(frozen=True, eq=False)
class TightenedTeam:
    """Per robot its design (None: no disturbance) and the problem its planners plan
    (the single-robot tightening's, or its configuration space's when undisturbed: see
    :func:`tightened_team`); ``max_horizon``: the team's, lowered to the smallest of the
    tightened robots'; ``status``/``reason``: why there is nothing to plan ("infeasible"
    or "unknown"; None when there is); ``note``: what was limited."""

    designs: tuple[RobustDesign | None, ...]
    planning: tuple[ReachProblem | None, ...]
    max_horizon: int
    status: str | None = None
    reason: str = ""
    note: str = ""


@lru_cache(maxsize=16)
def tightened_team(problem: TeamProblem) -> TightenedTeam:
    """Every disturbed robot's own problem tightened by the single-robot code (module
    doc); ``planning[r]`` None for a robot without a disturbance (its planners use its
    configuration space as before). The team has nothing to plan when a robot's
    tightening leaves it none: ``infeasible`` when one robot's is infeasible (its tube
    outgrows a bound at the first step), else ``unknown``; both relative to the
    designs."""
    designs: list[RobustDesign | None] = []
    planning: list[ReachProblem | None] = []
    horizon, notes = problem.max_horizon, []
    status, reasons = None, []
    for i, robot in enumerate(problem.robots):
        if robot.disturbance is None:
            designs.append(None)
            planning.append(None)
            continue
        own = problem.robot_problems[i]
        try:
            design = robust_design(own)
        except InvalidProblem as exc:
            raise InvalidProblem(problem.source, exc.field.replace("robot.", f"robots[{i}].", 1), exc.reason) from None
        tight = tightened(own, design)
        designs.append(design)
        planning.append(tight.problem)
        if tight.problem is None:
            status = "infeasible" if tight.status == "infeasible" or status == "infeasible" else "unknown"
            reasons.append(f"robot {robot.name}: {tight.reason}")
            continue
        horizon = min(horizon, tight.problem.max_horizon)
        if tight.note:
            notes.append(f"robot {robot.name}: {tight.note}")
    return TightenedTeam(tuple(designs), tuple(planning), horizon, status, "; ".join(reasons), "; ".join(notes))


@dataclass(frozen=True, eq=False)
class RobotMargins:
    """How much one robot's constraints tighten at t = 0..H (rows): ``state_lo/hi``
    (n columns: the lower bounds rise, the upper fall), ``input_lo/hi`` (m columns),
    ``rest_lo/hi`` (the resting input's, at the cap), ``goal`` (per goal half-space,
    or None)."""

    state_lo: np.ndarray
    state_hi: np.ndarray
    input_lo: np.ndarray
    input_hi: np.ndarray
    rest_lo: np.ndarray
    rest_hi: np.ndarray
    goal: np.ndarray | None

    @property
    def horizon(self) -> int:
        return len(self.state_lo) - 1


def robot_margins(tube: Tube, position: tuple[int, ...], goal_H: np.ndarray | None, horizon: int) -> RobotMargins:
    """The tube's margins of one robot up to ``horizon`` (the tube's own accessors)."""
    s_lo, s_hi = tube.state_margins(horizon)
    u_lo, u_hi = tube.input_margins(horizon)
    cap_lo, cap_hi = tube.input_margins()
    goal = None if goal_H is None else tube.position_margins(goal_H, position, horizon)
    return RobotMargins(s_lo, s_hi, u_lo, u_hi, cap_lo[-1], cap_hi[-1], goal)


def _position_support(tube: Tube | None, position: tuple[int, ...], A: np.ndarray, horizon: int) -> np.ndarray:
    """``h_{E_t}(row of A)`` on the positions for t = 0..horizon (zeros without a tube)."""
    if tube is None:
        return np.zeros((horizon + 1, len(A)))
    return tube.position_margins(A, position, horizon)


def pair_margins(
    facets: Facets,
    tube_i: Tube | None,
    pos_i: tuple[int, ...],
    tube_j: Tube | None,
    pos_j: tuple[int, ...],
    horizon: int,
) -> np.ndarray | None:
    """``h_{E_i,t}(-a_k) + h_{E_j,t}(a_k)`` per sample t = 0..horizon (rows) and side k
    (columns) of the pair's facets (module doc); None when neither robot has a tube."""
    if tube_i is None and tube_j is None:
        return None
    A = np.asarray(facets.A, float)
    return _position_support(tube_i, pos_i, -A, horizon) + _position_support(tube_j, pos_j, A, horizon)


def obstacle_margins(facets: Facets, tube: Tube | None, pos: tuple[int, ...], horizon: int) -> np.ndarray | None:
    """``h_{E_r,t}(-a_k)`` per sample and side of a robot-obstacle couple (None without a tube)."""
    if tube is None:
        return None
    return _position_support(tube, pos, -np.asarray(facets.A, float), horizon)


def record(problem: TeamProblem, tight: TightenedTeam) -> dict[str, Any]:
    """What a team result records of the robust planning (``robust`` in its file): the
    law, the guarantee, what a missing plan is relative to, the separation's tightening,
    and per disturbed robot its gain K and margins (the single-robot record's)."""
    robots = {}
    for robot, design in zip(problem.robots, tight.designs):
        if design is None:
            continue
        own = design.record()
        robots[robot.name] = {"feedback": own["feedback"], "margins": own["margins"]}
    return {
        "law": LAW,
        "guarantee": GUARANTEE,
        "relative_to": RELATIVE.replace("for this gain K", "for these gains K"),
        "separation": SEPARATION,
        "robots": robots,
    }


def without_disturbances(problem: TeamProblem) -> TeamProblem:
    """The nominal team: every robot's disturbance dropped."""
    return replace(problem, robots=tuple(replace(r, disturbance=None) for r in problem.robots))
