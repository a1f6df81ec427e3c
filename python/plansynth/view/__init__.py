"""Interactive pages in the browser for both halves (``plansynth view``).

* the grid page (:mod:`~plansynth.view.grid_data`, static/grid_page.js): a reactive
  controller (Chasins & Newcomb, SYNT 2016) against obstacles the user moves, its
  program beside the board with the branch that fired; a refuted controller's
  counterexample; for an unrealizable problem, the obstacles' winning strategy played
  against the user's robot moves;
* the reach page (:mod:`~plansynth.view.reach_data`, static/reach_page.js): the
  workspace, regions, labels and a trajectory (Shoukry et al., CDC 2016) with its
  states and inputs against their bounds and the labels holding at each step;
* the team page (:mod:`~plansynth.view.team_data`, static/team_page.js): a team of
  robots, each in its own colour, and the moving obstacles where they are at each step;
* :mod:`~plansynth.view.server`: the reach page served on 127.0.0.1, re-planning the
  problem the user edits.

:func:`build_page` is the API of ``plansynth view``; this module imports neither half
until it is called.

>>> html = build_page("examples/grid/figure1.yaml")
>>> '"kind":"grid"' in html and "<script>" in html
True
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = ["build_page", "problem_kind", "read_result"]


def problem_kind(path: str | Path) -> str:
    """``"grid"``, ``"reach"`` or ``"team"``: which half a problem file belongs to (its
    top-level ``grid`` or ``workspace`` key), a reach problem being a team's when it has
    ``robots``, ``separation`` or ``moving_obstacles``; anything else is an InvalidProblem."""
    from plansynth.errors import InvalidProblem
    from plansynth.io import load_document

    doc, name = load_document(path)
    if isinstance(doc, dict) and "grid" in doc:
        return "grid"
    if isinstance(doc, dict) and "workspace" in doc:
        from plansynth.reach.team.fileformat import is_team_document

        return "team" if is_team_document(doc) else "reach"
    raise InvalidProblem(name, "<document>", "neither a grid problem (key grid) nor a reach problem (key workspace)")


def read_result(path: str | Path) -> tuple[dict[str, Any], str]:
    """A result document (a JSON object) and the name to report it by."""
    from plansynth.errors import InvalidProblem
    from plansynth.io import load_document

    doc, name = load_document(path)
    if not isinstance(doc, dict):
        raise InvalidProblem(name, "<document>", "a result file must be a JSON object")
    return doc, name


def build_page(
    problem: str | Path, result: str | Path | None = None, *, serve: bool = False, timeout: float = 10.0
) -> str:
    """The HTML page of the problem file ``problem`` and the result file ``result``
    (None: the problem alone). ``serve``: a reach page that re-plans through
    :mod:`~plansynth.view.server`, asking ``timeout`` seconds per plan by default
    (single-robot reach problems only)."""
    from plansynth.view.page import render_page

    kind = problem_kind(problem)
    if serve and kind != "reach":
        from plansynth.errors import InvalidProblem

        raise InvalidProblem(str(problem), "<document>", f"a {kind} problem: only a single-robot reach page re-plans")
    doc, name = read_result(result) if result is not None else (None, "")
    if kind == "team":
        from plansynth.reach.team.fileformat import load_problem
        from plansynth.view.team_data import team_page_data

        team = load_problem(problem)
        return render_page(team_page_data(team, doc, source=name), title=f"plansynth view: {team.name}")
    if kind == "grid":
        from plansynth.grid import load
        from plansynth.view.grid_data import check_recorded_problem, grid_page_data

        p = load(problem)
        if doc is not None:
            check_recorded_problem(p, doc, name, Path(result).parent)
        data = grid_page_data(p, doc, source=name)
    else:
        from plansynth.reach import load as load_reach
        from plansynth.view.reach_data import reach_page_data

        p = load_reach(problem)
        if serve:
            from plansynth.view.server import serve_data

            data = serve_data(p, doc, timeout, source=name)
        else:
            data = reach_page_data(p, doc, source=name)
    return render_page(data, title=f"plansynth view: {p.name}", serve=serve)
