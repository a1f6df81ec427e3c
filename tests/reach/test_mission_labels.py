"""The label reading per region (plansynth.reach.mission.labels): every literal a region
claims holds on the whole region, checked here from the region's vertices and the labels'
own boxes, written apart from the refinement."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon as ShPolygon
from shapely.geometry import box as shbox
from test_mission_milp import sample_missions

from plansynth.reach.dynamics import single_integrator
from plansynth.reach.geometry import Box
from plansynth.reach.mission.labels import label_abstraction
from plansynth.reach.problem import ReachProblem

EPS = 1e-7  # the checker's tolerance is 1e-6; the refinement allows 1e-9 x the workspace


def _claims_hold(p) -> list[str]:
    """The claims of p's label reading that fail on the region's whole polygon: ``a``
    where a vertex lies less than a's margin deep in a, ``!a`` where the region comes
    closer to a than a's margin."""
    la = label_abstraction(p)
    boxes = dict(p.labels)
    bad = []
    for i, region in enumerate(la.abstraction.regions):
        V = np.asarray(region.vertices, float)
        poly = ShPolygon(V)
        for name in la.labels_of[i]:
            b, r = boxes[name], p.label_margin(name)
            depth = np.minimum(V - np.asarray(b.lo), np.asarray(b.hi) - V).min()
            if depth < r - EPS:
                bad.append(f"region {i} reads {name} but reaches {r - depth:.3g} past its inner edge")
        for name in la.negs_of[i]:
            b, r = boxes[name], p.label_margin(name)
            if poly.distance(shbox(*b.lo, *b.hi)) < r - EPS and poly.area > 0:
                bad.append(f"region {i} reads !{name} but comes within {r} of it")
    return bad


def test_a_sliver_region_is_cut_at_a_label_edge_it_reaches_past():
    """Found by hypothesis: margins 0.15 put three inner edges 2e-7 apart, so one region
    was a sliver 2e-7 wide that ran 4.3e-3 past t2a's inner edge, with too little area
    to be cut off, and read t2a: a plan through it failed the mission checker."""
    p = _room(
        (
            ("k1", Box((2e-07, 3.0128865792771347), (1.9000001999999998, 4.590923800317793))),
            ("k2", Box((5.1e-184, 0.14626346653898062), (0.627316936198133, 0.8008858388956515))),
            ("t2a", Box((1.3e-255, 1e-300), (0.8998634997209078, 0.7965958967127357))),
        ),
        0.15,
    )
    assert _claims_hold(p) == []
    la = label_abstraction(p)
    assert any("t2a" in s for s in la.labels_of)


def _room(labels, margin: float) -> ReachProblem:
    """A 6 x 6 room without obstacles, a single integrator, the labels, one margin."""
    return ReachProblem(
        workspace=Box((0, 0), (6, 6)),
        obstacles=(),
        goal=None,
        dynamics=single_integrator(2, 1.0),
        start=[0.5, 0.5],
        input_bound=1.5,
        labels=tuple(labels),
        mission=" & ".join(f"F {n}" for n, _ in labels),
        margin=margin,
        max_horizon=6,
    )


#: Edges on a coarse grid, nudged by nothing, a sliver's width or a rounding error, so
#: that inner and outer edges of different labels nearly coincide.
COORD = st.builds(
    lambda a, d: max(0.0, a + d),
    st.sampled_from([0.0, 0.5, 1.0, 1.5, 2.0, 3.0]),
    st.sampled_from([0.0, 2e-7, -2e-7, 1e-12, 0.15]),
)


@st.composite
def near_coincident_labels(draw):
    labels = []
    for k in range(draw(st.integers(2, 4))):
        x, y = draw(COORD), draw(COORD)
        labels.append(
            (
                f"a{k}",
                Box(
                    (x, y),
                    (x + draw(st.sampled_from([0.8, 1.0, 1.3, 2.0])), y + draw(st.sampled_from([0.8, 1.0, 1.6]))),
                ),
            )
        )
    return labels


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck))
@given(sample_missions(), st.sampled_from([0.15, 0.3]))
def test_every_claim_of_the_label_reading_holds_on_its_whole_region(p, margin):
    assert _claims_hold(replace(p, margin=margin)) == []


@settings(max_examples=80, deadline=None, suppress_health_check=list(HealthCheck))
@given(near_coincident_labels(), st.sampled_from([0.0, 0.15, 0.3]))
def test_claims_hold_where_label_edges_nearly_coincide(labels, margin):
    assert _claims_hold(_room(labels, margin)) == []
