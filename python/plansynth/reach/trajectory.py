"""Trajectories x_0 .. x_N with inputs u_0 .. u_{N-1} (paper, Definition 2.3).

A trajectory is plain data; whether it solves a problem is the validator's business
(:mod:`plansynth.reach.validate`). Result files carry it under the keys ``states`` and
``inputs`` (spec, "Result file").

>>> t = Trajectory(states=[[0, 0], [1, 0]], inputs=[[1, 0]])
>>> t.horizon, t.n_states, t.n_inputs
(1, 2, 2)
>>> trajectory_to_lists(t)
([[0.0, 0.0], [1.0, 0.0]], [[1.0, 0.0]])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.io import Fields, as_float_vector, load_document, show

__all__ = ["Trajectory", "load_trajectory", "trajectory_from_dict", "trajectory_to_lists", "check_dimensions"]


@dataclass(frozen=True, eq=False)
class Trajectory:
    """``states`` is (N+1) x n, ``inputs`` is N x m; arrays are read-only copies.

    A trajectory of horizon 0 (start already in the goal) has ``inputs`` of shape
    (0, m), with m = 0 when unknown. Equality compares the arrays element-wise.
    ``source``: the file it was read from, for error messages (not compared).
    """

    states: np.ndarray
    inputs: np.ndarray
    source: str | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        s = np.array(self.states, dtype=float)
        u = np.array(self.inputs, dtype=float)
        if s.ndim != 2 or s.shape[0] < 1:
            raise ValueError(f"states must be a non-empty (N+1) x n array, got shape {s.shape}")
        if u.size == 0:
            u = u.reshape(0, u.shape[1] if u.ndim == 2 else 0)
        if u.ndim != 2 or u.shape[0] != s.shape[0] - 1:
            raise ValueError(
                f"inputs must be N x m with N = {s.shape[0] - 1} (one fewer than states), got shape {u.shape}"
            )
        s.flags.writeable = False
        u.flags.writeable = False
        object.__setattr__(self, "states", s)
        object.__setattr__(self, "inputs", u)

    @property
    def horizon(self) -> int:
        """N, the number of steps."""
        return int(self.states.shape[0] - 1)

    @property
    def n_states(self) -> int:
        return int(self.states.shape[1])

    @property
    def n_inputs(self) -> int:
        return int(self.inputs.shape[1])

    def positions(self, position: Sequence[int]) -> np.ndarray:
        """The (N+1) x d workspace coordinates for the given state indices."""
        return self.states[:, list(position)]

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Trajectory):
            return NotImplemented
        return bool(np.array_equal(self.states, other.states) and np.array_equal(self.inputs, other.inputs))

    def __hash__(self) -> int:
        return hash((self.states.shape, self.states.tobytes(), self.inputs.shape, self.inputs.tobytes()))


def trajectory_to_lists(trajectory: Trajectory) -> tuple[list[list[float]], list[list[float]]]:
    """``(states, inputs)`` as nested lists of floats, ready for JSON."""
    return trajectory.states.tolist(), trajectory.inputs.tolist()


def trajectory_from_dict(doc: Any, source: str | None = None) -> Trajectory:
    """Read ``states`` and ``inputs`` from a result document; other keys are ignored.

    >>> trajectory_from_dict({"states": [[0, 0], [1, 0]], "inputs": [[]]}, "r.json")
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidProblem: r.json: inputs[0]: empty input
    """
    f = Fields(doc, source, "")
    states_raw = f.require("states")
    if states_raw is None:
        status = doc.get("status", "?")
        raise InvalidProblem(source, "states", f"no trajectory in this result (status {show(status)})")
    inputs_raw = f.require("inputs")
    if not isinstance(states_raw, Sequence) or isinstance(states_raw, (str, bytes)) or len(states_raw) == 0:
        raise InvalidProblem(source, "states", f"expected a non-empty list of states, got {show(states_raw)}")
    if not isinstance(inputs_raw, Sequence) or isinstance(inputs_raw, (str, bytes)):
        raise InvalidProblem(source, "inputs", f"expected a list of inputs, got {show(inputs_raw)}")
    states = [as_float_vector(s, source, f"states[{i}]") for i, s in enumerate(states_raw)]
    n = len(states[0])
    if n == 0:
        raise InvalidProblem(source, "states[0]", "empty state")
    for i, s in enumerate(states):
        if len(s) != n:
            raise InvalidProblem(source, f"states[{i}]", f"has {len(s)} components, states[0] has {n}")
    inputs = [as_float_vector(u, source, f"inputs[{i}]") for i, u in enumerate(inputs_raw)]
    if len(inputs) != len(states) - 1:
        raise InvalidProblem(
            source,
            "inputs",
            f"expected {len(states) - 1} inputs (one per step between {len(states)} states), got {len(inputs)}",
        )
    m = len(inputs[0]) if inputs else 0
    if inputs and m == 0:  # (else the arrays' shapes disagree, and Trajectory's ValueError names no field)
        raise InvalidProblem(source, "inputs[0]", "empty input")
    for i, u in enumerate(inputs):
        if len(u) != m:
            raise InvalidProblem(source, f"inputs[{i}]", f"has {len(u)} components, inputs[0] has {m}")
    return Trajectory(states=np.array(states), inputs=np.array(inputs).reshape(len(inputs), m), source=source)


def check_dimensions(trajectory: Trajectory, n_states: int, n_inputs: int) -> None:
    """Raise :class:`InvalidProblem` (naming the trajectory's file) unless its states have
    ``n_states`` components and its inputs ``n_inputs`` (the problem's robot): a
    trajectory of another robot is a bad input, not a picture or a plan.

    >>> check_dimensions(Trajectory(states=[[0, 0, 0], [1, 0, 0]], inputs=[[1, 0]], source="r.json"), 4, 2)
    Traceback (most recent call last):
    ...
    plansynth.errors.InvalidProblem: r.json: states: each state has 3 components, but the problem's robot has 4 states
    """
    if trajectory.n_states != n_states:
        raise InvalidProblem(
            trajectory.source,
            "states",
            f"each state has {trajectory.n_states} components, but the problem's robot has {n_states} states",
        )
    if trajectory.horizon > 0 and trajectory.n_inputs != n_inputs:
        raise InvalidProblem(
            trajectory.source,
            "inputs",
            f"each input has {trajectory.n_inputs} components, but the problem's robot has {n_inputs} inputs",
        )


def load_trajectory(path: str | Path) -> Trajectory:
    """Read the trajectory of a result JSON (spec: keys ``states`` and ``inputs``)."""
    doc, name = load_document(path)
    return trajectory_from_dict(doc, name)
