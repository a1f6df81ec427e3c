"""Robust planning under bounded disturbances (beyond Shoukry et al., CDC 2016, whose
Section VII leaves "bounded disturbances" as future work).

A problem with ``robot.disturbance`` (a set W, :mod:`plansynth.reach.disturbance`) is
planned as a nominal trajectory with a feedback law ``u = v + K (x - x_nom)`` whose
error stays in the tube of :mod:`plansynth.reach.tube`; the nominal plan satisfies the
problem tightened by that tube, so the closed loop satisfies the problem under every
disturbance sequence within W. One module per part:

``feedback``   the design of K (discrete LQR by a DARE solved with numpy, deadbeat, or given);
``tighten``    the tightened problem the planners plan, and what it guarantees;
``missions``   the same for LTL missions: labels tightened (visit: the whole tube
               inside; avoid: the tube outside);
``check``      the independent robust validator: the worst case at every step by
               support functions and exact polygons, sharing no code with the planner;
``simulate``   the closed loop under random and vertex disturbance sequences;
``baseline``   the nominal planner followed by the robust check.

Nothing is imported until a name is used.
"""

from importlib import import_module
from typing import Any

_DEFINED_IN = {
    "design_feedback": "plansynth.reach.robust.feedback",
    "Feedback": "plansynth.reach.robust.feedback",
    "RobustDesign": "plansynth.reach.robust.tighten",
    "robust_design": "plansynth.reach.robust.tighten",
    "tightened": "plansynth.reach.robust.tighten",
    "GUARANTEE": "plansynth.reach.robust.tighten",
    "check_robust": "plansynth.reach.robust.check",
    "RobustReport": "plansynth.reach.robust.check",
    "simulate": "plansynth.reach.robust.simulate",
}

__all__ = sorted(_DEFINED_IN)


def __getattr__(name: str) -> Any:
    if name not in _DEFINED_IN:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(_DEFINED_IN[name]), name)
    globals()[name] = value
    return value
