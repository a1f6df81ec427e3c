"""The tightened problem: what the nominal plan must satisfy so that the closed loop
``u = v + K (x - x_nom)`` satisfies the problem under every disturbance sequence in W
(constraint tightening by the error sets of :mod:`plansynth.reach.tube`).

With the error ``e_t in E_t`` (the tube, E_0 = {0}, growing with t), a constraint
``c . x <= b`` holds for every disturbance exactly when the nominal state satisfies
``c . x_nom <= b - h_{E_t}(c)``; the input ``v + K e`` stays within ``|u| <= ubar``
exactly when ``v_t`` is within the bound less ``h_{E_t}(+-K_j)``. The tightened problem
applies this

* **at every step, with E_t itself** (time-varying) to the state bounds, the workspace
  (on the positions), the input bound and the goal (at the final step N, by E_N): the
  problem carries the :class:`~plansynth.reach.tube.Tube` (``problem.tube``) and the
  planners that plan under disturbances tighten their LP bounds by it, step by step;
* **to the obstacles, by the tube's largest cross-section**: every obstacle grows by
  the box B of the position error's extremes ``[-h(-e_i), h(e_i)]`` over all steps (the
  cap of the support functions: exact up to the truncation, bounded after), exactly as
  for a box-shaped robot (:func:`~plansynth.reach.robot.grown_by_box`). Why not by E_t
  at each step: the planners walk a fixed convex decomposition of the free space, and a
  region shrunk by E_t cannot meet its neighbour (their common face moves apart on both
  sides), so a plan could never change region. Growing the obstacles before the
  decomposition keeps every region's tube clear of the obstacles at every step (B
  contains every E_t's positions), at the price of the early steps' smaller tube;

A nominal state in region r (of the decomposition of the tightened free space) has its
whole tube outside the obstacles, and so does the straight segment between two samples
in r: a point of the disturbed segment is ``(1 - s)(p_t + e_t) + s (p_{t+1} + e_{t+1})``,
inside ``r + B`` because both samples' tubes are and r + B is convex. A constraint
tightened at both ends of a segment holds along it (it is linear in s).

What it guarantees (:data:`GUARANTEE`): every disturbance sequence within W keeps the
closed loop safe and reaching, for the tightened sets as computed, with the gain K of the
chosen design. What it does not: ``infeasible`` and ``unknown`` are relative to that
design (:data:`RELATIVE`).

>>> from dataclasses import replace
>>> from plansynth.reach.families import maze
>>> from plansynth.reach.disturbance import Disturbance
>>> p = replace(maze(1), disturbance=Disturbance(box=(0.02, 0.02, 0.05, 0.05)))
>>> t = tightened(p)
>>> [round(v, 3) for v in t.design.position_hi]
[0.186, 0.186]
>>> [[round(v, 3) for v in c] for c in (t.problem.obstacles[0].lo, t.problem.obstacles[0].hi)]
[[0.0, 14.314], [27.186, 15.686]]
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.reach.geometry import halfspaces
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robot import clipped, configuration_space, grown_by_box
from plansynth.reach.robust.feedback import Feedback, design_feedback
from plansynth.reach.tube import Tube, UnstableFeedback

__all__ = ["RobustDesign", "Tightened", "tightened", "robust_design", "unplannable", "GUARANTEE", "RELATIVE", "LAW"]

GUARANTEE = (
    "every disturbance sequence within W keeps the closed loop safe and reaching (for the tightened sets as computed)"
)
RELATIVE = (
    "relative to the feedback design: no robust plan for this gain K and this tightening, "
    "not a proof that no controller can do it"
)
LAW = "u_t = v_t + K (x_t - x_nom_t)"


@dataclass(frozen=True, eq=False)
class RobustDesign:
    """The feedback and its tube, with the margins at the cap (the largest, every step's
    being at most these): ``position_lo/hi`` (how far the position error reaches below
    and above along each workspace axis: the obstacles grow by them), ``state_lo/hi``
    and ``input_lo/hi`` (how much each bound tightens)."""

    feedback: Feedback
    tube: Tube
    position_lo: tuple[float, ...]
    position_hi: tuple[float, ...]
    state_lo: np.ndarray
    state_hi: np.ndarray
    input_lo: np.ndarray
    input_hi: np.ndarray

    @property
    def K(self) -> np.ndarray:
        return self.feedback.K

    def record(self) -> dict[str, Any]:
        """What a result records of the design (``robust`` in the result file)."""
        return {
            "law": LAW,
            "guarantee": GUARANTEE,
            "relative_to": RELATIVE,
            "feedback": {
                "design": self.feedback.design,
                "how": self.feedback.how,
                "gain": np.asarray(self.K).tolist(),
                "spectral_radius": self.feedback.spectral_radius,
            },
            "margins": {
                "obstacles_grown_by": {"lo": list(self.position_lo), "hi": list(self.position_hi)},
                "state_bounds_at_most": {"lo": self.state_lo.tolist(), "hi": self.state_hi.tolist()},
                "input_bound_at_most": {"lo": self.input_lo.tolist(), "hi": self.input_hi.tolist()},
                "exact_steps": self.tube.exact_steps,
                "tail": self.tube.tail,
            },
        }


def robust_design(problem: ReachProblem) -> RobustDesign:
    """The feedback of ``problem.disturbance`` and its tube's margins (InvalidProblem,
    field ``robot.disturbance.feedback``, when the design fails)."""
    w = problem.disturbance
    if w is None:
        raise ValueError("the problem has no disturbance")
    fb = design_feedback(problem.dynamics, w, problem.source)
    tube = Tube(fb.A_K, fb.K, w)
    try:
        s_lo, s_hi = tube.state_margins()
    except UnstableFeedback as exc:
        raise InvalidProblem(problem.source, "robot.disturbance.feedback", str(exc)) from None
    u_lo, u_hi = tube.input_margins()
    pos = list(problem.dynamics.position)
    return RobustDesign(
        feedback=fb,
        tube=tube,
        position_lo=tuple(float(v) for v in s_lo[-1, pos]),
        position_hi=tuple(float(v) for v in s_hi[-1, pos]),
        state_lo=s_lo[-1],
        state_hi=s_hi[-1],
        input_lo=u_lo[-1],
        input_hi=u_hi[-1],
    )


@dataclass(frozen=True, eq=False)
class Tightened:
    """The tightened problem (``problem``; None when there is none to plan) with its
    ``design``; ``status`` ("infeasible" or "unknown") and ``reason`` say why there is
    none; ``note`` says what was limited (the horizon, when the tube outgrows a bound)."""

    design: RobustDesign
    problem: ReachProblem | None
    status: str | None = None
    reason: str = ""
    note: str = ""


def _first_empty_step(problem: ReachProblem, design: RobustDesign, steps: int) -> tuple[int | None, str]:
    """The first step t <= ``steps`` at which a tightened bound is empty (the state box,
    the workspace on the positions, the input interval, the goal), and which; None when
    every step has room. The margins never decrease, so every later step is empty too."""
    tube = design.tube
    I = min(steps, tube.exact_steps + 1)
    lo, hi = problem.state_box
    m_lo, m_hi = tube.state_margins(I)
    room = (hi - m_hi) - (lo + m_lo)
    bad_state = np.nonzero(np.any(room < 0, axis=1))[0]
    u_lo, u_hi = tube.input_margins(I)
    ub = problem.input_bound
    bad_input = np.nonzero(np.any((ub - u_hi) - (-ub + u_lo) < 0, axis=1))[0]
    bad_goal = np.zeros(0, dtype=int)
    if problem.goal is not None:
        H, h = halfspaces(problem.goal)
        g = tube.position_margins(H, problem.dynamics.position, I)
        empty = np.array([_polytope_empty(H, h - g[t]) for t in range(I + 1)])
        bad_goal = np.nonzero(empty)[0]
    found = [
        (int(a[0]), what) for a, what in ((bad_state, "state"), (bad_input, "input"), (bad_goal, "goal")) if a.size
    ]
    if not found:
        return None, ""
    t, what = min(found)
    why = {
        "state": "the tube is wider than the state bounds (or the workspace)",
        "input": "the feedback's share of the input exceeds the input bound",
        "goal": "the tube no longer fits in the goal",
    }[what]
    return t, f"after {t - 1} steps {why}"


def _polytope_empty(H: np.ndarray, h: np.ndarray) -> bool:
    """Is ``{p : H p <= h}`` (2-D) empty? (An LP.)"""
    import highspy

    from plansynth.reach.highs import csc_lp, new_highs

    k, d = H.shape
    r, c = np.nonzero(np.ones((k, d)))
    lp = csc_lp(
        d,
        k,
        r,
        c,
        H[r, c],
        np.zeros(d),
        np.full(d, -highspy.kHighsInf),
        np.full(d, highspy.kHighsInf),
        np.full(k, -highspy.kHighsInf),
        h,
    )
    hs = new_highs()
    hs.passModel(lp)
    hs.run()
    return hs.getModelStatus() != highspy.HighsModelStatus.kOptimal


def tightened(problem: ReachProblem, design: RobustDesign | None = None) -> Tightened:
    """The tightened problem of a problem with a disturbance (module doc): obstacles grown
    by the tube's largest cross-section, clipped to the workspace (a sized robot's
    configuration space first), the tube attached for the step-wise tightening of the
    state bounds, the workspace, the input bound and the goal, and ``max_horizon``
    lowered to the last step at which every tightened bound has room."""
    design = robust_design(problem) if design is None else design
    t_empty, why = _first_empty_step(problem, design, problem.max_horizon)
    horizon, note = problem.max_horizon, ""
    if t_empty is not None:
        if t_empty <= 1:
            return Tightened(
                design,
                None,
                "infeasible",
                f"no robust plan: {why.replace('after 0 steps ', 'after one step ')} ({RELATIVE})",
            )
        horizon = t_empty - 1
        note = f"horizons up to {horizon} only: {why}, so no longer plan is robust"
    base = configuration_space(problem)
    lo = tuple(-v for v in design.position_hi)  # q + E meets O iff q is in O + (-E)
    hi = tuple(design.position_lo)
    ws = base.workspace
    obstacles = tuple(c for o in base.obstacles for c in clipped(grown_by_box(o, lo, hi), ws))
    try:
        planned = replace(
            base,
            obstacles=obstacles,
            disturbance=None,
            tube=design.tube,
            max_horizon=horizon,
            name=f"{problem.name} (tightened)",
        )
    except InvalidProblem as exc:
        return unplannable(design, exc, "the obstacles grown by the tube's largest cross-section")
    return Tightened(design, planned, note=note)


def unplannable(design: RobustDesign, exc: InvalidProblem, how: str) -> Tightened:
    """No tightened problem: the tightening refused it (a start inside a grown obstacle,
    a goal with no room left, ...): ``unknown``, relative to the design."""
    return Tightened(
        design, None, "unknown", f"no plan through the tightened problem ({exc.field}: {exc.reason}; {how}); {RELATIVE}"
    )
