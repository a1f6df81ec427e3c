"""The report as one Markdown file: its header (database, machine, how to read it, the
runs planned and missing), then the grid half and the reach half, each beside its
paper; beside it, the same report as one HTML page.
"""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from pathlib import Path

from plansynth.bench.db import ResultsDB
from plansynth.bench.errors import NoRuns
from plansynth.bench.report.cells import summarise
from plansynth.bench.report.grid import grid_section
from plansynth.bench.report.html import write_html
from plansynth.bench.report.reach import reach_section
from plansynth.io import write_output

__all__ = ["write_report"]


def write_report(
    db_path: str | Path,
    out_dir: str | Path,
    *,
    title: str = "plansynth benchmark report",
    planned: Sequence[tuple[str, str, int]] | None = None,
    image_prefix: str = "",
    html: bool = True,
) -> Path:
    """Write ``out_dir/REPORT.md`` and its PNG figures from the database; returns the path.

    ``html``: also write ``out_dir/REPORT.html``, the same report as one self-contained
    page with the figures embedded (:mod:`~plansynth.bench.report.html`); the page reads
    the figures where the Markdown names them, so with an ``image_prefix`` write it
    from the Markdown's final place instead (:func:`~plansynth.bench.report.write_html`).

    ``planned`` (resume keys) lets the report list the runs that are missing. Images
    are referred to as ``image_prefix + name`` (for a report that lives elsewhere). A
    database without a run is :class:`~plansynth.bench.errors.NoRuns`, and nothing is
    written.
    """
    out = Path(out_dir)
    with ResultsDB(db_path) as db:
        runs = db.runs()
        info = db.info()
        if planned is None and "planned" in info:
            planned = [tuple(k) for k in json.loads(info["planned"])]  # type: ignore[misc]
        done = db.done_keys()
    if not runs:
        raise NoRuns(str(db_path))
    out.mkdir(parents=True, exist_ok=True)
    cells = summarise(runs)
    machine = json.loads(info.get("machine", "{}"))
    L: list[str] = [f"# {title}", ""]
    L.append(
        f"Generated {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} from `{Path(db_path).name}` "
        f"({len(runs)} runs). Machine: {machine.get('cpuinfo', '?')}; Python {machine.get('python', '?')}; "
        + ", ".join(f"{k} {v}" for k, v in (machine.get("versions") or {}).items() if v)
        + "."
    )
    L.append("")
    L.append(
        "Times are medians over repeats, in seconds, measured by each solver around its own solve "
        "(problem construction and process start excluded). `> T` means no repeat answered within the "
        "limit T; the statuses say what happened (`unknown`: the solver's budget ran out; `timeout`: "
        "killed by the runner; `crash`/`memout`: the child died). A result counts as solved only if the "
        "independent checker accepted it (grid: `plansynth.grid.verify`; reach: `plansynth.reach.validate`). "
        "Paper numbers were measured in 2016 on the authors' machines; they are context, not a comparison."
    )
    L.append("")
    if planned:
        missing = [k for k in planned if tuple(k) not in done]
        L.append(f"Runs planned: {len(planned)}; finished: {len(planned) - len(missing)}; missing: {len(missing)}.")
        if missing:
            L.append("")
            L.append("<details><summary>Missing runs</summary>")
            L.append("")
            for e, p, r in missing[:400]:
                L.append(f"- {e} {p} #{r}")
            L.append("")
            L.append("</details>")
        L.append("")
    L += grid_section(cells, out, image_prefix)
    L += reach_section(cells, out, image_prefix)
    report = out / "REPORT.md"
    write_output(report, "\n".join(L) + "\n")
    if html:
        write_html(report)
    return report
