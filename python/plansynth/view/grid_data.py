"""The grid page's data: a problem, its controller and the evidence, as plain JSON.

The page evaluates nothing that Python has not described here: the board (walls, goal,
starts), every agent's moves with the offsets they sweep (``to`` first, then ``via``:
:meth:`plansynth.grid.problem.Move.offsets`), so that the page's step (static/
grid_semantics.js) applies the rules of :mod:`plansynth.grid.semantics` (Chasins &
Newcomb, SYNT 2016, Section 3.1, as ``shared/spec/grid-problem.md`` words them), and the
controller as its term tree (:mod:`plansynth.grid.programs`, Listing 1), which the page
evaluates as :func:`~plansynth.grid.programs.evaluate` does. A browser test compares the
page's moves with :func:`~plansynth.grid.semantics.step` on random obstacle moves.

The evidence depends on the answer:

* ``realizable``: the independent verifier's verdict (:func:`plansynth.grid.verify`);
  a controller that loses (a result for an edited problem, say) comes with the
  verifier's counterexample, replayed by the page;
* ``unrealizable``: the obstacles' winning strategy from
  :func:`plansynth.grid.native.explain.explain`, tabulated over every state the robot
  can reach against it (:func:`strategy_table`), so that the page plays it against any
  move the user makes.

>>> from plansynth.grid import load
>>> d = grid_page_data(load("examples/grid/figure1.yaml"), {"status": "realizable", "steps": 6,
...                    "program": "(ite (<= rx 3) 2 1)"}, source="r.json")
>>> d["kind"], d["steps"], d["verdict"]["status"], d["program"]["op"]
('grid', 6, 'wins', 'ite')
>>> d["problem"]["robot"]["moves"][1]
{'name': 'up', 'offsets': [[0, 0], [0, 1]], 'to': [0, 1]}
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from plansynth.budget import Budget
from plansynth.errors import InvalidProblem
from plansynth.grid import GridProblem, verify
from plansynth.grid.programs import App, Const, ProgramSyntaxError, Term, Var, check_program, parse_program
from plansynth.grid.semantics import State, initial_state, step
from plansynth.io import show
from plansynth.view.status import result_status

#: Most (step, state) entries of an unrealizable problem's strategy table; beyond it the
#: page plays the strategy only along the table's states and says where it stops.
MAX_STRATEGY_STATES = 20_000

#: Seconds the verifier and the explanation may take while a page is built.
EVIDENCE_SECONDS = 60.0


def problem_json(problem: GridProblem) -> dict[str, Any]:
    """The board and every agent's moves, with the offsets each move sweeps."""

    def moves(ms) -> list[dict[str, Any]]:
        return [{"name": m.name, "offsets": [list(o) for o in m.offsets()], "to": list(m.to)} for m in ms]

    return {
        "name": problem.name,
        "width": problem.width,
        "height": problem.height,
        "walls": [list(w) for w in sorted(problem.walls)],
        "robot": {
            "start": list(problem.robot.start),
            "goal": list(problem.robot.goal),
            "moves": moves(problem.robot.moves),
        },
        "obstacles": [{"start": list(o.start), "moves": moves(o.moves)} for o in problem.obstacles],
        "variables": list(problem.variables),
    }


def term_json(t: Term) -> dict[str, Any]:
    """A term as a tree: ``{"c": value}``, ``{"v": name}`` or ``{"op": op, "a": [args]}``.

    >>> term_json(parse_program("(ite (= rx (- 1)) 0 1)"))
    {'op': 'ite', 'a': [{'op': '=', 'a': [{'v': 'rx'}, {'c': -1}]}, {'c': 0}, {'c': 1}]}
    """
    if isinstance(t, Const):
        return {"c": t.value}
    if isinstance(t, Var):
        return {"v": t.name}
    assert isinstance(t, App)
    return {"op": t.op, "a": [term_json(a) for a in t.args]}


def state_json(s: State) -> dict[str, Any]:
    return {"robot": list(s.robot), "obstacles": [list(o) for o in s.obstacles]}


def read_grid_result(raw: Any, problem: GridProblem, source: str) -> tuple[str, int | None, Term | None]:
    """Status, path length and program of a grid result document, checked against
    ``problem``: a result of the other half, or a program that is not a controller of
    this problem (another problem's inputs or moves), is an :class:`InvalidProblem`
    naming ``source`` and the field."""
    status = result_status(raw, source, "grid")
    steps = raw.get("steps")
    if steps is not None and (isinstance(steps, bool) or not isinstance(steps, int) or steps < 1):
        raise InvalidProblem(source, "steps", f"expected a positive integer, got {show(steps)}")
    program = None
    if raw.get("program") is not None:
        if not isinstance(raw["program"], str):
            raise InvalidProblem(source, "program", f"expected the program as a string, got {show(raw['program'])}")
        try:
            program = parse_program(raw["program"])
            check_program(program, problem.variables, len(problem.robot.moves), problem.max_constant)
        except ProgramSyntaxError as exc:
            raise InvalidProblem(source, "program", f"not a controller of {problem.name}: {exc}") from None
    if status == "realizable" and (program is None or steps is None):
        raise InvalidProblem(source, "program" if program is None else "steps", "a realizable result needs both")
    return status, steps, program


def check_recorded_problem(problem: GridProblem, raw: Mapping[str, Any], source: str, base: Path | None = None) -> None:
    """A result names the problem file it was solved for (``problem``); when that file
    can be read and holds another problem than ``problem`` (its name aside), the result
    is for another problem: an :class:`InvalidProblem` naming ``source``."""
    from dataclasses import replace

    from plansynth.errors import PlansynthError
    from plansynth.grid import load

    where = raw.get("problem")
    if not isinstance(where, str) or not where:
        return
    for path in (Path(where), *((base / where,) if base is not None else ())):
        try:
            recorded = load(path)
        except (PlansynthError, OSError, ValueError):
            continue
        if replace(recorded, name=problem.name).to_dict() != problem.to_dict():
            raise InvalidProblem(
                source,
                "problem",
                f"the result was solved for {where}, which holds another problem than {problem.source or problem.name}",
            )
        return


def grid_page_data(
    problem: GridProblem,
    result: Mapping[str, Any] | None,
    *,
    source: str = "<result>",
    budget_seconds: float = EVIDENCE_SECONDS,
) -> dict[str, Any]:
    """Everything the grid page shows (see the module docstring); ``result`` is a result
    document (spec: Result file) or None for the board alone."""
    data: dict[str, Any] = {
        "kind": "grid",
        "problem": problem_json(problem),
        "status": None,
        "steps": None,
        "program": None,
        "program_text": None,
        "verdict": None,
        "counterexample": None,
        "explanation": None,
        "result_problem": None,
    }
    if result is None:
        data["steps"] = _default_steps(problem)
        return data
    status, steps, program = read_grid_result(result, problem, source)
    steps = steps or _default_steps(problem)
    recorded = result.get("problem")
    data.update(
        status=status,
        steps=steps,
        result_problem=Path(recorded).name if isinstance(recorded, str) and recorded else None,
    )
    if program is not None:
        data.update(program=term_json(program), program_text=str(program))
        verdict = verify(problem, program, steps, budget=Budget(seconds=budget_seconds))
        data["verdict"] = {
            "status": verdict.status.value,
            "message": verdict.message,
            "states_explored": verdict.states_explored,
        }
        cex = verdict.counterexample
        if cex is not None:
            data["counterexample"] = {
                "states": [state_json(s) for s in cex.states],
                "robot_moves": list(cex.robot_moves),
                "obstacle_moves": [list(j) for j in cex.obstacle_moves],
                "reason": cex.reason,
            }
    elif status == "unrealizable":
        data["explanation"] = explanation_json(problem, steps, budget_seconds)
    return data


def _default_steps(problem: GridProblem) -> int:
    return problem.steps if problem.steps is not None else problem.path_lengths()[-1]


def explanation_json(problem: GridProblem, steps: int, seconds: float = EVIDENCE_SECONDS) -> dict[str, Any]:
    """Why no controller wins at ``steps``: :func:`~plansynth.grid.native.explain.explain`'s
    kind and summary, its play against the robot's best try, and (kind ``game``) the
    obstacles' strategy as a table (:func:`strategy_table`)."""
    from plansynth.grid.native.explain import explain

    e = explain(problem, steps, Budget(seconds=seconds))
    out: dict[str, Any] = {
        "kind": e.kind,
        "summary": e.summary,
        "steps": steps,
        "play": [
            {
                "t": turn.t,
                "state": state_json(turn.state),
                "robot_move": turn.robot_move,
                "obstacle_moves": list(turn.obstacle_moves),
                "reason": turn.reason,
            }
            for turn in e.play
        ],
        "strategy": None,
        "complete": None,
    }
    if e.strategy is not None:
        table, complete = strategy_table(problem, e.strategy, steps)
        out.update(strategy=table, complete=complete)
    return out


def state_key(t: int, s: State) -> str:
    """The page's key of a state at step ``t``: ``"t|rx,ry|o0x,o0y|..."``.

    >>> state_key(2, State((1, 4), ((2, 5), (3, 3))))
    '2|1,4|2,5|3,3'
    """
    return "|".join([str(t), *(f"{x},{y}" for x, y in (s.robot, *s.obstacles))])


def strategy_table(
    problem: GridProblem, strategy: Any, steps: int, max_states: int = MAX_STRATEGY_STATES
) -> tuple[dict[str, list[list[int]]], bool]:
    """The obstacles' reply to every robot move in every state the robot can reach
    against ``strategy`` (an :class:`~plansynth.grid.native.explain.ObstacleStrategy`):
    ``{state_key: [joint move per robot move]}``, and whether the table holds every such
    state (False when it stopped at ``max_states``)."""
    table: dict[str, list[list[int]]] = {}
    layer = {initial_state(problem)}
    for t in range(steps):
        nxt: set[State] = set()
        for s in sorted(layer):
            if len(table) >= max_states:
                return table, False
            replies = []
            for k in range(len(problem.robot.moves)):
                joint, _ = strategy.reply(t, s, k)
                replies.append(list(joint))
                out = step(problem, s, k, joint)
                if not out.collided:
                    nxt.add(out.state)
            table[state_key(t, s)] = replies
        layer = nxt
    return table, True
