"""Comparing two solvers on one instance: time ratios, with bounds where one side did
not finish, and the time over its one-cold-LP limit.

``a/b`` > 1 means ``b`` was faster; a ratio with an unsolved side is a bound, marked
``>`` or ``<``.

>>> from plansynth.bench.report.cells import Cell
>>> fast = Cell(runs=1, solved=1, median=1.0, worst=1.0, limit=60.0, statuses={"solved": 1})
>>> slow = Cell(runs=1, solved=0, median=None, worst=None, limit=60.0, statuses={"unknown": 1},
...             extra={"median_any": 60.0})
>>> ratio(slow, fast), ratio(fast, slow)
('> 60', '< 0.0167')
"""

from __future__ import annotations

import statistics
from collections.abc import Mapping
from typing import Any

from plansynth.bench.report.cells import Cell, fmt

__all__ = ["ratio", "ratio_value", "over_limit", "headline"]


def over_limit(c: Cell | None) -> str:
    """``total / limit``: the median time over the median one-cold-LP time."""
    if c is None or not c.solved or c.median is None:
        return "-"
    lim = (c.extra or {}).get("oracle_lp")
    if not lim:
        return "-"
    return f"{fmt(c.median)} / {fmt(lim)} = {c.median / lim:.3g}x"


def ratio(a: Cell | None, b: Cell | None) -> str:
    """time(a) / time(b) on one instance, with bounds when one side did not finish."""
    if a is None or b is None:
        return "-"
    rv = ratio_value(a, b)
    if rv is None:
        return "-"
    return f"{'' if rv[1] == '=' else rv[1] + ' '}{rv[0]:.3g}"


def ratio_value(a: Cell | None, b: Cell | None) -> tuple[float, str] | None:
    if a is None or b is None:
        return None
    ta, tb = a.decided_time(), b.decided_time()
    if ta is not None and tb is not None:
        return ta / max(tb, 1e-6), "="
    if ta is None and tb is not None and a.used_its_limit:
        return a.limit / max(tb, 1e-6), ">"
    if tb is None and ta is not None and b.used_its_limit:
        return ta / b.limit, "<"
    return None


def headline(cells: Mapping[tuple[str, str], Cell], a: str, b: str, prefix: str) -> dict[str, Any]:
    """Median and worst of time(a)/time(b) over instances of ``prefix`` both decided."""
    vals = []
    bounds = []
    for (exp, p), c in cells.items():
        if p != a or not exp.startswith(prefix):
            continue
        rv = ratio_value(c, cells.get((exp, b)))
        if rv is None:
            continue
        (vals if rv[1] == "=" else bounds).append((rv[0], exp, rv[1]))
    if not vals and not bounds:
        return {"n": 0}
    exact = sorted(v for v, _, _ in vals)
    return {
        "n": len(vals),
        "median": statistics.median(exact) if exact else None,
        "worst_for_b": max(vals)[0:2] if vals else None,  # largest a/b
        "best_for_b": min(vals)[0:2] if vals else None,
        "bounds": [(float(f"{v:.3g}"), e, s) for v, e, s in bounds],
    }
