"""LTL missions under a disturbance: the mission's problem tightened by the tube, its
labels read robustly.

A mission's plan runs forever (a lasso repeats its loop, a finite plan rests at its end)
while the error sets keep growing towards their limit, so a mission is tightened by the
tube's cap (the largest error set, :mod:`plansynth.reach.tube`), the same at every step:
the obstacles grow by the cap's box and the workspace, the state bounds and the input
bound shrink by it. Then the mission planners (``lazy-smt``, ``milp-ltl``) plan the
tightened mission unchanged.

**Labels.** With the error in B (the cap's box around the nominal position), a label
``a`` holds *for sure* when the whole tube is inside it and fails for sure when the
tube stays out of its interior; in between, the disturbance decides. So every label
becomes two: ``a__in`` (the positions whose tube is inside a: a shrunk by B, exact for
a convex a) and ``a__out`` (the positions whose tube meets a's interior: a grown by B),
and the mission, in negation normal form, reads ``a`` as ``a__in`` ("visit means the
whole tube inside") and ``!a`` as ``!a__out`` ("avoid means the tube outside"). A
formula in negation normal form is monotone in its literals, so a plan whose word
satisfies the rewritten mission satisfies the mission under every disturbance. A label
smaller than the tube never holds for sure: ``a`` becomes ``false``.

>>> from dataclasses import replace
>>> from plansynth.reach.mission.families import mission_problem
>>> from plansynth.reach.disturbance import Disturbance
>>> from plansynth.reach.robust.tighten import robust_design
>>> p = replace(mission_problem("maze-1", "avoid-until"), disturbance=Disturbance(box=(0.02, 0.02, 0.05, 0.05)))
>>> t = tightened_mission(p, robust_design(p))
>>> p.mission, t.problem.mission
('!h U door', '(!h__out U door__in)')
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from plansynth.errors import InvalidProblem
from plansynth.reach.geometry import Box, Polygon, Shape, halfspaces
from plansynth.reach.ltl.syntax import Const, Formula, Not, Prop, children, nnf, parse
from plansynth.reach.problem import ReachProblem
from plansynth.reach.robot import clipped, configuration_space, grown_by_box
from plansynth.reach.robust.tighten import RELATIVE, RobustDesign, Tightened, unplannable

__all__ = ["tightened_mission", "robust_formula", "IN", "OUT"]

IN, OUT = "__in", "__out"


def robust_formula(f: Formula, inside: dict[str, str | None], outside: dict[str, str]) -> Formula:
    """``f`` in negation normal form with ``a`` read as ``inside[a]`` (``false`` when
    None) and ``!a`` as ``!outside[a]``.

    >>> str(robust_formula(parse("G F a & !(b U c)"), {"a": "A", "b": "B", "c": None}, {"b": "b2", "c": "C"}))
    '(G F A & (!b2 R !C))'
    """
    return _rewrite(nnf(f), inside, outside)


def _rewrite(f: Formula, inside: dict[str, str | None], outside: dict[str, str]) -> Formula:
    if isinstance(f, Prop):
        name = inside[f.name]
        return Const(False) if name is None else Prop(name)
    if isinstance(f, Not):  # (negation normal form: only on a label)
        assert isinstance(f.arg, Prop)
        return Not(Prop(outside[f.arg.name]))
    kids = children(f)
    if not kids:
        return f
    return type(f)(*(_rewrite(k, inside, outside) for k in kids))  # type: ignore[call-arg]


def _shrunk(shape: Shape, lo: tuple[float, ...], hi: tuple[float, ...], tiny: float) -> Shape | None:
    """The positions p of the convex ``shape`` with ``p + [-lo, hi]`` inside it (None: none
    with area above ``tiny``)."""
    if isinstance(shape, Box):
        a = tuple(l + d for l, d in zip(shape.lo, lo))
        b = tuple(h - d for h, d in zip(shape.hi, hi))
        return Box(a, b) if all(y - x > 0 for x, y in zip(a, b)) and np.prod(np.subtract(b, a)) > tiny else None
    from plansynth.reach.mission.labels import clip

    H, h = halfspaces(shape)
    reach = np.maximum(H * np.array(hi), -H * np.array(lo)).sum(axis=1)  # h_B(H_k) for B = [-lo, hi]
    V = np.asarray(shape.vertices, float)
    poly: list[tuple[float, float]] = [tuple(v) for v in V]  # type: ignore[misc]
    for row, c in zip(H, h - reach):
        poly = clip(poly, row, float(c))
        if len(poly) < 3:
            return None
    area = 0.5 * abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1])))
    return Polygon(tuple(poly)) if area > tiny else None


def tightened_mission(problem: ReachProblem, design: RobustDesign) -> Tightened:
    """The mission's problem tightened by the tube's cap (module doc): a problem with a
    rewritten mission over the labels ``a__in`` and ``a__out``, no goal, no tube."""
    base = configuration_space(problem)
    pos = list(problem.dynamics.position)
    lo, hi = design.position_lo, design.position_hi
    ws = base.workspace
    shrunk_ws = Box(tuple(a + d for a, d in zip(ws.lo, lo)), tuple(b - d for b, d in zip(ws.hi, hi)))
    if shrunk_ws.is_degenerate():
        return Tightened(
            design, None, "infeasible", f"no robust plan: the tube is wider than the workspace ({RELATIVE})"
        )
    grow_lo, grow_hi = tuple(-v for v in hi), tuple(lo)
    obstacles = tuple(c for o in base.obstacles for c in clipped(grown_by_box(o, grow_lo, grow_hi), shrunk_ws))
    ub = problem.input_bound - float(max(np.max(design.input_lo, initial=0.0), np.max(design.input_hi, initial=0.0)))
    if not ub > 0:
        return Tightened(
            design,
            None,
            "infeasible",
            f"no robust plan: the feedback's share of the input exceeds its bound ({RELATIVE})",
        )
    sb = base.state_bounds
    if sb is not None:
        s_lo = np.array(sb.lo) + design.state_lo
        s_hi = np.array(sb.hi) - design.state_hi
        s_lo[pos] = np.maximum(s_lo[pos], shrunk_ws.lo)
        s_hi[pos] = np.minimum(s_hi[pos], shrunk_ws.hi)
        if np.any(s_lo > s_hi):
            return Tightened(
                design, None, "infeasible", f"no robust plan: the tube is wider than the state bounds ({RELATIVE})"
            )
        sb = Box(tuple(s_lo), tuple(s_hi))
    formula = parse(problem.mission or "true")
    labels = problem.mission_labels
    tiny = 1e-12 * ws.volume()
    inside: dict[str, str | None] = {}
    outside: dict[str, str] = {}
    new_labels: list[tuple[str, Shape]] = []
    taken = set(labels)
    for name in sorted(labels):
        shape = labels[name]
        inner = _shrunk(shape, lo, hi, tiny)
        a_in, a_out = _fresh(name + IN, taken), _fresh(name + OUT, taken)
        inside[name] = None if inner is None else a_in
        outside[name] = a_out
        if inner is not None:
            new_labels.append((a_in, inner))
        new_labels.append((a_out, grown_by_box(shape, grow_lo, grow_hi)))
    mission = str(robust_formula(formula, inside, outside))
    try:
        planned = replace(
            base,
            workspace=shrunk_ws,
            obstacles=obstacles,
            state_bounds=sb,
            input_bound=ub,
            goal=None,
            labels=tuple(new_labels),
            mission=mission,
            disturbance=None,
            tube=None,
            name=f"{problem.name} (tightened)",
        )
    except InvalidProblem as exc:
        return unplannable(design, exc, "every set tightened by the tube's largest cross-section")
    note = "a mission is tightened by the tube's largest cross-section at every step (its plan runs forever)"
    return Tightened(design, planned, note=note)


def _fresh(name: str, taken: set[str]) -> str:
    while name in taken:
        name += "_"
    taken.add(name)
    return name
