"""The first failing step of a mission on a word and its reason from the geometry there,
for the independent mission checker (:mod:`plansynth.reach.mission.check`, whose
docstring describes the descent).
"""

from __future__ import annotations

import numpy as np

from plansynth.reach.mission.ltl import (
    And,
    Const,
    Finally,
    FiniteWord,
    Formula,
    Globally,
    Lasso,
    Next,
    Or,
    Prop,
    Release,
    Until,
    WeakNext,
    holds_at,
    unroll,
)
from plansynth.reach.mission.word import NEG

__all__ = ["failure_reason", "first_failure"]


def first_failure(f: Formula, word: Lasso | FiniteWord, i: int) -> tuple[int, str | None]:
    """(the step where the descent from f at position i ends, the failing literal there,
    or ``"never:<text>"`` / ``"text:<text>"`` for a reason that is no literal). A
    disjunction fails where the last of its disjuncts fails. Iterative (explicit frames
    for the disjunctions)."""
    n = len(word.letters)
    memo: dict[Formula, list[bool]] = {}

    def val(g: Formula) -> list[bool]:
        if g not in memo:
            memo[g] = holds_at(g, word)
        return memo[g]

    def descend(g: Formula, i: int) -> tuple[int, str | None] | tuple[Formula, int, None]:
        """Down to a result, or to a disjunction (returned as (g, i, None))."""
        while True:
            if isinstance(g, Const):
                return i, None
            if isinstance(g, Prop):
                return i, g.name
            if isinstance(g, Or):
                return g, i, None
            if isinstance(g, And):
                g = g.left if not val(g.left)[i] else g.right
                continue
            if isinstance(g, (Next, WeakNext)):
                j = word.successor(i)
                if j is None:
                    return i, f"text:{g} needs a step after the last"
                g, i = g.arg, j
                continue
            if isinstance(g, (Globally, Release)):
                b = g.arg if isinstance(g, Globally) else g.right
                vb = val(b)
                j, seen = i, set()
                while j is not None and j not in seen and vb[j]:
                    seen.add(j)
                    j = word.successor(j)
                if j is None or vb[j]:  # pragma: no cover - R fails only where b fails
                    return i, f"text:{g} fails"
                g, i = b, j
                continue
            if isinstance(g, (Finally, Until)):
                b = g.arg if isinstance(g, Finally) else g.right
                va = [True] * n if isinstance(g, Finally) else val(g.left)
                j, seen = i, set()
                while j is not None and j not in seen and va[j]:
                    seen.add(j)
                    j = word.successor(j)
                if j is not None and not va[j]:
                    g, i = g.left, j
                    continue
                if j is None:
                    return n - 1, f"never:{b} never holds (the plan ends at step {n - 1})"
                return len(
                    word.prefix
                ), f"never:{b} never holds (checked through the loop from step {len(word.prefix)})"
            u = unroll(g)  # a bounded operator: its unrolling names the step
            if u is g:  # pragma: no cover - only bounded operators are left
                raise TypeError(f"not in negation normal form: {type(g).__name__}")
            g = u

    frames: list[list] = []  # [pending (disjunct, position) pairs, best result so far]
    todo: tuple[Formula, int] = (f, i)
    while True:
        got = descend(*todo)
        if got[-1] is None and isinstance(got[0], Or):
            g, at, _ = got
            parts, stack = [], [g]
            while stack:  # the disjuncts of a chain of | (iteratively)
                h = stack.pop()
                if isinstance(h, Or):
                    stack += [h.right, h.left]
                else:
                    parts.append(h)
            frames.append([[(d, at) for d in reversed(parts[1:])], None])
            todo = (parts[0], at)
            continue
        result = got
        while frames:
            frame = frames[-1]
            frame[1] = result if frame[1] is None else max(frame[1], result, key=lambda x: x[0])
            if frame[0]:
                todo = frame[0].pop()
                break
            frames.pop()
            result = frame[1]
        else:
            return result  # type: ignore[return-value]


def failure_reason(lit: str | None, step: int, reading: str, P, N: int, values, margins, labels, loop_start) -> str:
    """The reason a literal fails at a step, from the geometry there."""
    if lit is None:
        return "false"
    if lit.startswith(("never:", "text:")):
        return lit.split(":", 1)[1]
    neg = lit.startswith(NEG)
    name = lit[len(NEG) :] if neg else lit
    v = values[step]
    r = margins[name]
    here = v[lit]
    start_depth = float(labels[name].at_points(np.asarray(P[step : step + 1], float)[:, :2])[0])
    segment = reading == "segment" and step < N
    if neg:
        if here > -1e-9 and r > 0:
            return f"within the margin {r:g} of label {name} (distance {here:.3g})"
        if segment and start_depth <= 0:
            return f"segment {step} crosses into label {name}"
        return f"in label {name}"
    if here > -1e-9 and r > 0:
        return f"in label {name} at depth {here:.3g}, below its margin {r:g}"
    if segment and start_depth >= 0:
        return f"segment {step} crosses out of label {name}"
    return f"not in label {name}"
