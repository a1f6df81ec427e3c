"""Figure 4 of Shoukry et al. (CDC 2016, Section VI): time against the number of states,
on integrator chains of order k (2k states) with their figure, and on the paper's own
setting, seeded random controllable (A, B).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from pathlib import Path

from plansynth.bench.report.cells import Cell, instances_of
from plansynth.bench.report.plots import plot_chain
from plansynth.bench.report.ratios import over_limit

__all__ = ["chains_section", "random_dynamics_section"]


def chains_section(
    cells: Mapping[tuple[str, str], Cell], reach_planners: Sequence[str], out: Path, image_prefix: str
) -> list[str]:
    """Figure 4 on the integrator chains (family ``chain``): table and figure."""
    chains = instances_of(cells, "chain")
    if not chains:
        return []
    L: list[str] = []
    L.append("### Figure 4: scalability with the number of states (integrator chains)")
    L.append("")
    L.append(
        "The paper reports 1.64 s (1 passage) to 152 s (4 passages) at n = 50 states, with random A, B; "
        "we use integrator chains of order k (n = 2k states)."
    )
    L.append("")
    used = [p for p in reach_planners if any((e, p) in cells for e, _ in chains)]
    hdr = ["passages", "k", "states n"] + used + ["lazy-smt horizon", "lazy-smt total / limit"]
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))
    for exp, setup in chains:
        n, k = int(setup["params"]["n"]), int(setup["params"]["k"])
        row = [str(n), str(k), str(2 * k)] + [cells[(exp, p)].text() if (exp, p) in cells else "-" for p in used]
        lz = cells.get((exp, "lazy-smt"))
        row += [str(lz.horizon) if lz and lz.solved else "-", over_limit(lz)]
        L.append("| " + " | ".join(row) + " |")
    L.append("")
    plot_chain(cells, chains, used, out / "reach-figure4.png")
    L.append(f"![Figure 4]({image_prefix}reach-figure4.png)")
    L.append("")
    return L


def random_dynamics_section(cells: Mapping[tuple[str, str], Cell], reach_planners: Sequence[str]) -> list[str]:
    """Figure 4 on random dynamics (family ``random-dynamics``): the table, introduced by
    :func:`plansynth.reach.families.random_dynamics`'s own description."""
    rdyn = instances_of(cells, "random-dynamics")
    if not rdyn:
        return []
    from plansynth.reach.families import random_dynamics

    L: list[str] = []
    L.append("### Figure 4 with random dynamics (the paper's setting: random A, B)")
    L.append("")
    text = " ".join((random_dynamics.__doc__ or "").split("\n\n")[1].split())
    L.append(re.sub(r":\w+:`~?(?:[\w.]+\.)?(\w+)`", r"`\1`", text).replace("``", "`"))
    L.append("")
    used = [p for p in reach_planners if any((e, p) in cells for e, _ in rdyn)]
    hdr = ["passages", "states n", "seed"] + used + ["lazy-smt horizon", "lazy-smt total / limit"]
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))
    for exp, setup in sorted(rdyn, key=lambda es: (int(es[1]["params"]["n"]), int(es[1]["params"]["states"]))):
        pr = setup["params"]
        row = [str(pr["n"]), str(pr["states"]), str(pr.get("seed", 0))]
        row += [cells[(exp, p)].text() if (exp, p) in cells else "-" for p in used]
        lz = cells.get((exp, "lazy-smt"))
        row += [str(lz.horizon) if lz and lz.solved else "-", over_limit(lz)]
        L.append("| " + " | ".join(row) + " |")
    L.append("")
    return L
