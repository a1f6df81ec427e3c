"""``bench report``: Markdown tables and log-scale PNG plots from a results database,
and the same report as one self-contained HTML page with the plots embedded.

For every figure and table of the two papers the report puts the paper's number beside
ours and beside the peers' from the same run:

- grid (Chasins & Newcomb, SYNT 2016): Figure 2 (time vs program depth: ``depth``),
  Figure 3 (time vs path length: ``steps``), Figure 4 (time vs number of obstacles:
  ``obstacles``), Figure 5 (time vs grid size: ``dimensions``), Figure 6 (solver
  comparison on steps-20), plus ``figure1`` and our reactive families;
- reach (Shoukry et al., CDC 2016): Table I (mazes: lazy SMT vs RRT vs MILP) and
  Figure 4 (time vs number of states, integrator chains).

Times are medians over the repeats that solved; a cell is ``> T`` when no repeat solved
within the limit T (then the status counts say why), and ratio columns compare two
backends on the same instance (``a/b`` > 1 means ``b`` was faster). Ratios with an
unsolved side are bounds, marked ``>`` or ``<``.

The report's parts, one module each:

- :mod:`~plansynth.bench.report.cells` -- the repeats of one (instance, solver) as a
  :class:`Cell`, and how a time reads; :mod:`~plansynth.bench.report.ratios` -- two
  solvers compared; :mod:`~plansynth.bench.report.plots` -- the figures;
- :mod:`~plansynth.bench.report.grid` -- the grid half (Figures 2-6, reactive families),
  with :mod:`~plansynth.bench.report.suite` -- the runs timed through the CLI;
- :mod:`~plansynth.bench.report.reach` -- the reach half, from
  :mod:`~plansynth.bench.report.mazes` (Table I), :mod:`~plansynth.bench.report.gcs`,
  :mod:`~plansynth.bench.report.horizons` (proved-minimal horizons),
  :mod:`~plansynth.bench.report.counterexamples`, :mod:`~plansynth.bench.report.chains`
  (Figure 4), :mod:`~plansynth.bench.report.missions` and
  :mod:`~plansynth.bench.report.robust` (plans under bounded disturbances);
- :mod:`~plansynth.bench.report.write` -- the file: header, then both halves;
  :mod:`~plansynth.bench.report.html` -- the same report as one self-contained HTML page.
"""

from __future__ import annotations

from plansynth.bench.report.cells import Cell, summarise
from plansynth.bench.report.counterexamples import CX_VARIANTS
from plansynth.bench.report.html import render_html, write_html
from plansynth.bench.report.ratios import headline
from plansynth.bench.report.write import write_report

__all__ = ["Cell", "summarise", "write_report", "write_html", "render_html", "headline", "CX_VARIANTS"]
