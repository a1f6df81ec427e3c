"""Reach-avoid problems: the immutable problem value (Shoukry et al., CDC 2016,
Section II, Definition 2.3).

A :class:`ReachProblem` is a box workspace, obstacles (boxes, or simple polygons in
2-D, possibly non-convex), a convex goal, and a discrete-time linear robot
``x' = A x + B u`` with ``||u||_inf <= input_bound``; it is checked when it is made.
The shapes live in :mod:`plansynth.reach.geometry`, the dynamics in
:mod:`plansynth.reach.dynamics`, the robot's extent in :mod:`plansynth.reach.robot` and
the mission language in :mod:`plansynth.reach.ltl`, all below this module; the file
format (:mod:`plansynth.reach.fileformat`: ``load_reach_problem``,
``reach_problem_from_dict``, ``reach_problem_to_dict``) sits above it and reads files
into problems, so a problem value knows nothing of files.

Equality: problems, dynamics and shapes compare by value (arrays element-wise) and are
hashable, so a problem round-trips through the file format.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from plansynth.io import MAX_NAME_LENGTH, type_name  # noqa: F401 - MAX_NAME_LENGTH: a documented limit, with the others
from plansynth.reach.disturbance import Disturbance
from plansynth.reach.dynamics import NAMED_MODELS, LinearDynamics
from plansynth.reach.geometry import (
    Box,
    Polygon,
    Shape,
    _array_key,
    _frozen_array,
    halfspaces,
    is_convex,
    shape_to_shapely,
)
from plansynth.reach.limits import (  # noqa: F401 - the documented limits, exported here as they always were
    DEFAULT_MAX_HORIZON,
    MAX_COORDINATE,
    MAX_DT,
    MAX_HORIZON,
    MAX_LABEL_VERTICES,
    MAX_LABELS,
    MAX_OBSTACLES,
    MAX_ORDER,
    MAX_STATES,
    MAX_VERTICES,
    MISSION_ENDS,
    MISSION_READINGS,
)
from plansynth.reach.problem_checks import check_problem
from plansynth.reach.robot import RobotShape
from plansynth.reach.tube import Tube

__all__ = [
    "Box",
    "Polygon",
    "Shape",
    "LinearDynamics",
    "RobotShape",
    "ReachProblem",
    "halfspaces",
    "is_convex",
    "shape_to_shapely",
    "DEFAULT_MAX_HORIZON",
    "NAMED_MODELS",
    "MISSION_READINGS",
    "MISSION_ENDS",
]

# --------------------------------------------------------------------------- problem


@dataclass(frozen=True, eq=False)
class ReachProblem:
    """A reach-avoid problem (paper, Definition 2.3), checked on construction.

    Construction validates the semantics (shapes of matrices, start free and inside the
    workspace, goal with free area, positive bounds); a violation raises InvalidProblem
    naming ``source`` and the file field that would hold the bad value.
    """

    workspace: Box
    obstacles: tuple[Shape, ...]
    goal: Shape | None
    dynamics: LinearDynamics
    start: np.ndarray
    input_bound: float
    state_bounds: Box | None = None
    max_horizon: int = DEFAULT_MAX_HORIZON
    name: str = "reach"
    source: str | None = field(default=None)
    robot_shape: RobotShape | None = None
    # LTL missions (plansynth.reach.mission): named label shapes and the
    # mission text over their names. With a mission the goal is optional: it is then
    # only the label "goal", and the mission alone says what a plan must do.
    labels: tuple[tuple[str, Shape], ...] = ()
    mission: str | None = None
    # how a mission reads its plan (MISSION_READINGS, MISSION_ENDS; the margins in the
    # same units as the workspace): labels along whole segments or at the samples only;
    # a finite plan ending at rest or free; each label's margin (``margin`` for those
    # not in ``label_margins``) and the obstacles' (0: none)
    reading: str = "segment"
    end: str = "rest"
    margin: float = 0.0
    label_margins: tuple[tuple[str, float], ...] = ()
    obstacle_margin: float = 0.0
    # Bounded disturbances (plansynth.reach.robust): the set W of x' = A x + B u + w and
    # the feedback design of the file's robot.disturbance. A problem with one is planned
    # robustly: solve() plans its tightened problem, which carries the tube instead.
    disturbance: Disturbance | None = None
    # The tube of a tightened problem (set by plansynth.reach.robust.tighten, never read
    # from a file): the planners that plan under disturbances tighten the state bounds,
    # the workspace, the input bound and the goal by its error sets at every step.
    tube: Tube | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "obstacles", tuple(self.obstacles))
        object.__setattr__(
            self,
            "labels",
            tuple((str(k), v) for k, v in (self.labels.items() if isinstance(self.labels, Mapping) else self.labels)),
        )
        object.__setattr__(
            self,
            "label_margins",
            tuple(
                (str(k), v)
                for k, v in (
                    self.label_margins.items() if isinstance(self.label_margins, Mapping) else self.label_margins
                )
            ),
        )
        object.__setattr__(self, "start", _frozen_array(np.asarray(self.start, dtype=float).reshape(-1)))
        object.__setattr__(self, "input_bound", float(self.input_bound))
        check_problem(self)

    @property
    def dim(self) -> int:
        """Workspace dimension (2 or 3)."""
        return self.workspace.dim

    @property
    def mission_labels(self) -> dict[str, Shape]:
        """The labels the mission may name: ``labels`` and, when there is a goal, ``goal``."""
        out = dict(self.labels)
        if self.goal is not None:
            out.setdefault("goal", self.goal)
        return out

    def reach_view(self) -> ReachProblem:
        """The reach-avoid problem under a mission: the goal the whole workspace (so "p_N
        in the goal" holds for every position) and no mission (its labels and readings are
        the mission planners' and checker's business): what the validator and the
        reach-avoid machinery see of a mission problem."""
        from dataclasses import replace

        return replace(
            self,
            goal=self.workspace,
            labels=(),
            mission=None,
            reading="segment",
            end="rest",
            margin=0.0,
            label_margins=(),
            obstacle_margin=0.0,
        )

    def label_margin(self, name: str) -> float:
        """The margin of label ``name``: its own, else the mission's ``margin``."""
        return float(dict(self.label_margins).get(name, self.margin))

    @property
    def start_position(self) -> np.ndarray:
        return self.start[list(self.dynamics.position)]

    @property
    def starts_at_rest(self) -> bool:
        """Is the start an equilibrium (``A x_0 = x_0``, so that u = 0 keeps the robot
        there)? Then whatever the robot can do from the start it can also do later, after
        waiting: start-anchored facts hold shifted earlier."""
        if self.tube is not None and self.tube.varies:
            # the constraints tighten as the tube grows: what the robot can do from the
            # start it need not be able to do later, after waiting
            return False
        A = np.asarray(self.dynamics.A, float)
        return bool(np.allclose(A @ self.start, self.start, rtol=0.0, atol=1e-12))

    @cached_property
    def state_box(self) -> tuple[np.ndarray, np.ndarray]:
        """(lo, hi): the bounds of every state, the state bounds met with the workspace
        on the position components (+-inf where nothing bounds a state). Computed once;
        the arrays are read-only.

        >>> from plansynth.reach.families import maze
        >>> [a.tolist() for a in maze(1).state_box]
        [[0.0, 0.0, -2.0, -2.0], [30.0, 30.0, 2.0, 2.0]]
        """
        pos = list(self.dynamics.position)
        lo = np.full(self.dynamics.n_states, -np.inf)
        hi = np.full(self.dynamics.n_states, np.inf)
        if self.state_bounds is not None:
            lo = np.maximum(lo, self.state_bounds.lo)
            hi = np.minimum(hi, self.state_bounds.hi)
        lo[pos] = np.maximum(lo[pos], self.workspace.lo)
        hi[pos] = np.minimum(hi[pos], self.workspace.hi)
        return _frozen_array(lo), _frozen_array(hi)

    def position_of(self, states: np.ndarray) -> np.ndarray:
        """Workspace coordinates of one state or of a (T x n) array of states."""
        return np.asarray(states)[..., list(self.dynamics.position)]

    def _key(self) -> tuple:
        return (
            self.workspace,
            self.obstacles,
            self.goal,
            self.dynamics,
            _array_key(self.start),
            self.input_bound,
            self.state_bounds,
            self.max_horizon,
            self.name,
            None if self.robot_shape is None or self.robot_shape.is_point else self.robot_shape,
            self.labels,
            self.mission,
            self.reading,
            self.end,
            self.margin,
            self.label_margins,
            self.obstacle_margin,
            self.disturbance,
            self.tube,
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ReachProblem):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())
