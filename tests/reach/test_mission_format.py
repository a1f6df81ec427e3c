"""The reach problem format with ``labels`` and ``mission``: validation at
the door, the optional goal, round trips; and the label-refined abstraction."""

from __future__ import annotations

import copy

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon as ShPolygon

from plansynth.errors import InvalidProblem
from plansynth.reach.fileformat import reach_problem_from_dict, reach_problem_to_dict
from plansynth.reach.geometry import Box, Polygon
from plansynth.reach.mission.labels import label_abstraction

DOC = {
    "workspace": {"min": [0, 0], "max": [30, 30]},
    "obstacles": [{"min": [0, 9.5], "max": [24, 10.5]}],
    "labels": {
        "kitchen": {"min": [2, 2], "max": [6, 6]},
        "lab": {"polygon": [[20, 20], [28, 20], [28, 26]]},
        "stairs": {"min": [12, 0], "max": [14, 8]},
    },
    "mission": "F (kitchen & F lab) & G !stairs",
    "robot": {"dynamics": {"model": "double-integrator", "dt": 0.5}, "start": [1, 1, 0, 0], "input_bound": 1.0},
}


def doc(**changes):
    d = copy.deepcopy(DOC)
    for k, v in changes.items():
        if v is None:
            d.pop(k, None)
        else:
            d[k] = v
    return d


def test_a_mission_file_loads_without_a_goal_and_round_trips():
    p = reach_problem_from_dict(doc(), source="m.yaml")
    assert p.goal is None and p.mission == DOC["mission"]
    assert dict(p.labels)["lab"] == Polygon(((20, 20), (28, 20), (28, 26)))
    assert set(p.mission_labels) == {"kitchen", "lab", "stairs"}
    assert reach_problem_from_dict(reach_problem_to_dict(p)) == p


def test_the_goal_is_the_label_goal_when_given():
    p = reach_problem_from_dict(doc(goal={"min": [27, 27], "max": [29, 29]}, mission="F goal"), source="m.yaml")
    assert p.mission_labels["goal"] == Box((27, 27), (29, 29))


@pytest.mark.parametrize(
    "changes, field, reason",
    [
        ({"mission": "F kitchen & G !attic"}, "mission", "unknown label 'attic'"),
        ({"mission": "F goal"}, "mission", "unknown label 'goal'"),
        ({"mission": "F (kitchen"}, "mission", "expected '\\)'"),
        ({"mission": 3}, "mission", "expected an LTL formula"),
        ({"mission": None}, "goal", "missing required field"),
        ({"labels": {"F": {"min": [1, 1], "max": [2, 2]}}}, "labels.F", "label name"),
        ({"labels": {"a": {"min": [1, 1], "max": [1, 2]}}}, "labels.a", "degenerate box"),
        ({"labels": {"a": {"polygon": [[0, 0], [1, 1], [2, 2]]}}}, "labels.a.polygon", "degenerate"),
        ({"labels": [1, 2]}, "labels", "expected a mapping"),
    ],
)
def test_bad_missions_are_rejected_at_the_door(changes, field, reason):
    with pytest.raises(InvalidProblem, match=reason) as e:
        reach_problem_from_dict(doc(**changes), source="m.yaml")
    assert e.value.field == field and e.value.file == "m.yaml"


def test_old_files_stay_valid():
    d = doc(mission=None, labels=None, goal={"min": [27, 27], "max": [29, 29]})
    p = reach_problem_from_dict(d)
    assert p.mission is None and p.labels == ()


@settings(max_examples=25, deadline=None)
@given(
    st.lists(st.tuples(st.floats(1, 25), st.floats(1, 25), st.floats(1, 4), st.floats(1, 4)), min_size=1, max_size=3),
    st.booleans(),
)
def test_every_refined_region_is_inside_or_outside_each_label(boxes, triangle):
    labels = {f"l{i}": {"min": [x, y], "max": [x + w, y + h]} for i, (x, y, w, h) in enumerate(boxes)}
    if triangle:
        labels["tri"] = {"polygon": [[5, 12], [20, 14], [8, 25], [10, 16]]}  # non-convex
    p = reach_problem_from_dict(doc(labels=labels, mission="F l0"))
    la = label_abstraction(p)
    free = ShPolygon([(0, 0), (30, 0), (30, 30), (0, 30)]).difference(
        ShPolygon([(0, 9.5), (24, 9.5), (24, 10.5), (0, 10.5)])
    )
    union = 0.0
    for r, names in zip(la.abstraction.regions, la.labels_of):
        reg = ShPolygon(r.vertices)
        union += reg.area
        for name, shape in p.mission_labels.items():
            lab = (
                ShPolygon(shape.vertices)
                if isinstance(shape, Polygon)
                else ShPolygon(
                    [
                        (shape.lo[0], shape.lo[1]),
                        (shape.hi[0], shape.lo[1]),
                        (shape.hi[0], shape.hi[1]),
                        (shape.lo[0], shape.hi[1]),
                    ]
                )
            )
            inter = reg.intersection(lab).area
            if name in names:
                assert reg.area - inter <= 1e-6 * reg.area + 1e-9
            else:
                assert inter <= 1e-6 * reg.area + 1e-9
    assert abs(union - free.area) <= 1e-6 * free.area  # the pieces still cover the free space
    # adjacency: symmetric, and adjacent pieces touch along an edge
    for i, nb in enumerate(la.abstraction.adjacency):
        for j in nb:
            assert i in la.abstraction.adjacency[j]
            a, b = ShPolygon(la.abstraction.regions[i].vertices), ShPolygon(la.abstraction.regions[j].vertices)
            assert a.buffer(1e-6).intersection(b.buffer(1e-6)).area > 0
    assert la.abstraction.start_regions and all(
        la.abstraction.regions[s].contains(np.array([1.0, 1.0])) for s in la.abstraction.start_regions
    )
