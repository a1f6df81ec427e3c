"""The report's figures: log-scale PNG plots drawn with matplotlib (Agg, no display).

:func:`plot_family` draws time against a family's parameter for every solver (an
unfinished run as a hollow marker at its limit), beside the paper's curve;
:func:`plot_bars` draws grouped bars (hatched: no answer within the limit);
:func:`plot_chain` draws time against the number of states for the integrator chains.
Every figure is written atomically (:func:`plansynth.io.atomic_output`).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from plansynth.bench.report.cells import Cell, instances_of, param_value
from plansynth.io import atomic_output

__all__ = ["plot_family", "plot_bars", "plot_chain"]


def plot_family(
    cells: Mapping[tuple[str, str], Cell],
    family: str,
    planners: Sequence[str],
    title: str,
    xlabel: str,
    path: Path,
    paper: Mapping[float, float] | None = None,
    xkey: Any = None,
) -> bool:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    insts = instances_of(cells, family)
    if not insts:
        return False
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    markers = "osD^v<>p*"
    for i, p in enumerate(planners):
        xs, ys, xu, yu = [], [], [], []
        for exp, setup in insts:
            c = cells.get((exp, p))
            if c is None:
                continue
            x = xkey(setup) if xkey else param_value(setup)
            t = c.decided_time()
            if t is not None:
                xs.append(x)
                ys.append(max(t, 1e-3))
            elif c.limit and c.out_of_time:
                xu.append(x)
                yu.append(c.limit)
        if xs or xu:
            line = ax.plot(xs, ys, marker=markers[i % len(markers)], label=p)[0]
            if xu:
                ax.plot(
                    xu,
                    yu,
                    linestyle="none",
                    marker=markers[i % len(markers)],
                    mfc="none",
                    color=line.get_color(),
                    label=f"{p}: no answer within limit",
                )
    if paper:
        px = sorted(k for k, v in paper.items() if v is not None)
        ax.plot(px, [paper[k] for k in px], "k--", marker="x", label="paper (Enumerative 2015, 2016 machine)")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("time (s, log scale)")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
    return True


def plot_bars(
    groups: Sequence[str],
    series: Mapping[str, Sequence[float | None]],
    title: str,
    path: Path,
    limits: Mapping[str, Sequence[bool]] | None = None,
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    k = len(series)
    width = 0.8 / max(1, k)
    x = np.arange(len(groups))
    for i, (name, vals) in enumerate(series.items()):
        v = [np.nan if t is None else max(t, 1e-3) for t in vals]
        bars = ax.bar(x + (i - (k - 1) / 2) * width, v, width, label=name)
        if limits and name in limits:
            for b, lim in zip(bars, limits[name]):
                if lim:
                    b.set_hatch("//")
                    b.set_alpha(0.5)
    ax.set_xticks(x, groups)
    ax.set_yscale("log")
    ax.set_ylabel("time (s, log); hatched: no answer in limit")
    ax.set_title(title, fontsize=10)
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


def plot_chain(
    cells: Mapping[tuple[str, str], Cell],
    chains: Sequence[tuple[str, dict[str, Any]]],
    planners: Sequence[str],
    path: Path,
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    by: dict[tuple[str, int], list[tuple[int, float, bool]]] = defaultdict(list)
    for exp, setup in chains:
        n, k = int(setup["params"]["n"]), int(setup["params"]["k"])
        for p in planners:
            c = cells.get((exp, p))
            if c is None:
                continue
            t = c.decided_time()
            if t is not None:
                by[(p, n)].append((2 * k, t, False))
            elif c.out_of_time and c.limit:
                by[(p, n)].append((2 * k, c.limit, True))
    styles = ["-", "--", ":", "-."]
    for (p, n), pts in sorted(by.items()):
        pts.sort()
        done = [(x, y) for x, y, u in pts if not u]
        line = ax.plot(
            [x for x, _ in done],
            [max(y, 1e-3) for _, y in done],
            linestyle=styles[planners.index(p) % 4],
            marker="o",
            label=f"{p}, {n} passage{'s' if n > 1 else ''}",
        )[0]
        unl = [(x, y) for x, y, u in pts if u]
        if unl:
            ax.plot([x for x, _ in unl], [y for _, y in unl], "x", markersize=9, mew=2, color=line.get_color())
    ax.plot([50, 50], [1.64, 152], "k|", markersize=12, label="paper at n = 50: 1.64 s .. 152 s")
    ax.set_yscale("log")
    ax.set_xlabel("number of states n (= 2k)")
    ax.set_ylabel("time (s, log scale); x: no answer within the limit")
    ax.set_title("Reach, Figure 4: scalability with the number of states", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
