"""The proved-minimal horizons table: ``lazy-smt-minimal`` beside the default search (the
timed route) on the mazes, with what the minimality holds for.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from plansynth.bench.report.cells import Cell, fmt
from plansynth.bench.report.ratios import ratio

__all__ = ["minimal_table"]


def minimal_table(cells: Mapping[tuple[str, str], Cell], mazes: Sequence[tuple[str, dict[str, Any]]]) -> list[str]:
    """The proved-minimal horizon: ``lazy-smt-minimal`` (the timed route or the window
    search, then the re-timing and probes of ``horizon_search="minimal"``) beside the
    default search, with what the minimality holds for."""
    if not any((e, "lazy-smt-minimal") in cells for e, _ in mazes):
        return []
    L = [
        "### Proved-minimal horizons",
        "",
        "`lazy-smt-minimal`: the default search (the timed route), then its horizon proved minimal (the per-axis "
        "reachable sets where the dynamics separate, else the plan re-timed by LPs "
        "alone, then single-horizon probes, every shorter horizon refuted; from a start at rest a refuted horizon "
        "refutes every shorter one). *decomposition*: minimal among plans whose consecutive samples share a convex "
        "region (segment-safe mode; see the README on claims); *problem*: for the problem as the spec defines it.",
        "",
        "| maze | lazy-smt | its horizon | lazy-smt-minimal | proved minimal horizon | minimal for | probes | "
        "LP calls | proof (s, first run) | minimal / lazy-smt |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for exp, setup in mazes:
        w, m = cells.get((exp, "lazy-smt")), cells.get((exp, "lazy-smt-minimal"))
        claim = (m.extra or {}).get("minimal", {}) if m else {}
        proved = m.horizon if m and m.solved and claim.get("minimal") else None
        proof = ((m.extra or {}).get("timings") or {}).get("minimal") if m and m.solved else None
        L.append(
            f"| {int(setup['params']['n'])} | {w.text() if w else '-'} | {w.horizon if w and w.solved else '-'} | "
            f"{m.text() if m else '-'} | {proved if proved is not None else 'not proved'} | "
            f"{claim.get('minimal_relative_to') or '-'} | {claim.get('minimal_probes') if claim.get('minimal_probes') is not None else '-'} | "
            f"{(m.extra or {}).get('lp_calls') if m else '-'} | {fmt(proof)} | {ratio(m, w)} |"
        )
    L.append("")
    return L
