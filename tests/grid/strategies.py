"""Hypothesis strategies shared by every grid test: random small problems and programs.

``problem_documents()`` draws spec documents (dicts as a YAML file would give them) for
grids 2..5 wide and high, 0..2 obstacles with 1..3 moves each (built-in moves and custom
moves with ``to``/``via`` offsets), walls, and a fixed path length l in 1..5;
``grid_problems()`` loads them through :func:`grid_problem_from_dict`, so every drawn
problem has passed the loader's validation. ``programs(problem, max_depth)`` draws terms
of the controller grammar over the problem's inputs whose paper depth is at most
``max_depth``; ``problems_and_programs()`` draws both together.

Everything is small on purpose: the brute-force oracles in ``plansynth.grid.reference``
enumerate every joint obstacle choice, and the whole grid test suite must stay fast.

Use from a test module in ``tests/grid/`` (a package, so that its test file names cannot
clash with other parts' tests)::

    from .strategies import grid_problems, programs, problems_and_programs
"""

from __future__ import annotations

from typing import Any

from hypothesis import strategies as st

from plansynth.grid.problem import BUILTIN_MOVES, GridProblem, grid_problem_from_dict
from plansynth.grid.programs import App, Const, Term, Var

#: The built-in move names (a problem file may use any of them).
BUILTIN_NAMES: tuple[str, ...] = tuple(BUILTIN_MOVES)

_offset = st.tuples(st.integers(-2, 2), st.integers(-2, 2))


@st.composite
def custom_moves(draw: st.DrawFn, name: str) -> dict[str, Any]:
    """A custom move ``{name, to, via}`` with offsets in -2..2 and 0..2 ``via`` cells."""
    to = draw(_offset)
    via = draw(st.lists(_offset, max_size=2))
    d: dict[str, Any] = {"name": name, "to": list(to)}
    if via or draw(st.booleans()):
        d["via"] = [list(v) for v in via]
    return d


@st.composite
def move_lists(draw: st.DrawFn, min_size: int = 1, max_size: int = 3) -> list[Any]:
    """A list of distinct-named moves: built-in names and custom mappings mixed."""
    n = draw(st.integers(min_size, max_size))
    out: list[Any] = []
    used: set[str] = set()
    for i in range(n):
        if draw(st.integers(0, 3)) == 0:
            name = f"m{i}"
            out.append(draw(custom_moves(name)))
        else:
            name = draw(st.sampled_from([b for b in BUILTIN_NAMES if b not in used]))
            out.append(name)
        used.add(name)
    return out


_cells_of = lambda w, h: st.tuples(st.integers(0, w - 1), st.integers(0, h - 1))  # noqa: E731


@st.composite
def problem_documents(
    draw: st.DrawFn,
    *,
    max_side: int = 5,
    min_obstacles: int = 0,
    max_obstacles: int = 2,
    max_obstacle_moves: int = 3,
    max_robot_moves: int = 5,
    max_steps: int = 5,
    walls: bool = True,
) -> dict[str, Any]:
    """A valid problem document (spec: grid-problem.md) of a small random problem."""
    w = draw(st.integers(2, max_side))
    h = draw(st.integers(2, max_side))
    cell = _cells_of(w, h)
    start = draw(cell)
    goal = draw(cell)
    wall_cells: list[tuple[int, int]] = []
    if walls:
        wall_cells = draw(
            st.lists(cell.filter(lambda c: c not in (start, goal)), max_size=min(3, w * h - 2), unique=True)
        )
    robot_moves = draw(move_lists(1, max_robot_moves))
    # Half the problems give the robot `stay` first, so that winning programs are common.
    if "stay" not in robot_moves and len(robot_moves) < max_robot_moves and draw(st.booleans()):
        robot_moves.insert(0, "stay")
    obstacles = [
        {"start": list(draw(cell)), "moves": draw(move_lists(1, max_obstacle_moves))}
        for _ in range(draw(st.integers(min_obstacles, max_obstacles)))
    ]
    doc: dict[str, Any] = {
        "grid": [w, h],
        "robot": {"start": list(start), "goal": list(goal), "moves": robot_moves},
        "obstacles": obstacles,
        "steps": draw(st.integers(1, max_steps)),
    }
    if wall_cells or draw(st.booleans()):
        doc["walls"] = [list(c) for c in wall_cells]
    return doc


def grid_problems(**kwargs: Any) -> st.SearchStrategy[GridProblem]:
    """Small random :class:`GridProblem` values (see :func:`problem_documents`)."""
    return problem_documents(**kwargs).map(lambda d: grid_problem_from_dict(d, source="<hypothesis>"))


# -- programs -------------------------------------------------------------------------
#
# Budgets follow the paper's depth (programs.depth): a literal has depth 1, a coordinate
# depth 2, an application 1 + its deepest argument. So a T term needs budget >= 1, a
# coordinate or (+ T T) budget >= 2, (<= T T) budget >= 2, (not B) / (and B B) budget
# >= 3 and (ite B S S) budget >= 3.


@st.composite
def t_terms(draw: st.DrawFn, variables: tuple[str, ...], max_constant: int, budget: int) -> Term:
    """An integer term (T) of depth <= budget (budget >= 1)."""
    kinds = ["const"]
    if budget >= 2 and variables:
        kinds += ["var", "var"]
    if budget >= 2:
        kinds += ["+", "-"]
    kind = draw(st.sampled_from(kinds))
    if kind == "const":
        return Const(draw(st.integers(-1, max_constant)))
    if kind == "var":
        return Var(draw(st.sampled_from(variables)))
    a = draw(t_terms(variables, max_constant, budget - 1))
    b = draw(t_terms(variables, max_constant, budget - 1))
    return App(kind, (a, b))


@st.composite
def b_terms(draw: st.DrawFn, variables: tuple[str, ...], max_constant: int, budget: int) -> Term:
    """A condition (B) of depth <= budget (budget >= 2)."""
    kinds = ["<=", "<=", "=", "="]
    if budget >= 3:
        kinds += ["not", "and", "or"]
    kind = draw(st.sampled_from(kinds))
    if kind in ("<=", "="):
        a = draw(t_terms(variables, max_constant, budget - 1))
        b = draw(t_terms(variables, max_constant, budget - 1))
        return App(kind, (a, b))
    if kind == "not":
        return App("not", (draw(b_terms(variables, max_constant, budget - 1)),))
    a = draw(b_terms(variables, max_constant, budget - 1))
    b = draw(b_terms(variables, max_constant, budget - 1))
    return App(kind, (a, b))


@st.composite
def start_terms(draw: st.DrawFn, variables: tuple[str, ...], n_moves: int, max_constant: int, budget: int) -> Term:
    """A controller (Start) of depth <= budget (budget >= 1)."""
    # A leaf half the time keeps the expected size moderate (an ite has two Start children).
    if budget < 3 or draw(st.booleans()):
        return Const(draw(st.integers(0, n_moves - 1)))
    c = draw(b_terms(variables, max_constant, budget - 1))
    t = draw(start_terms(variables, n_moves, max_constant, budget - 1))
    e = draw(start_terms(variables, n_moves, max_constant, budget - 1))
    return App("ite", (c, t, e))


def programs(problem: GridProblem, max_depth: int = 5) -> st.SearchStrategy[Term]:
    """Controllers of ``problem``'s grammar (its inputs, move count, constants), depth <= max_depth."""
    return start_terms(problem.variables, len(problem.robot.moves), problem.max_constant, max_depth)


@st.composite
def programs_reading_obstacles(draw: st.DrawFn, problem: GridProblem, max_depth: int = 5) -> Term:
    """Controllers that read at least one obstacle coordinate (``problem`` needs an
    obstacle); depth <= max_depth + 1. A program that reads none is put under
    ``(ite (<= oNc K) program other)`` with a random obstacle coordinate oNc."""
    assert problem.obstacles, "programs_reading_obstacles needs a problem with obstacles"
    prog = draw(programs(problem, max_depth))
    if any(v.startswith("o") for v in _variables(prog)):
        return prog
    coord = Var(draw(st.sampled_from(problem.variables[2:])))
    bound = Const(draw(st.integers(-1, problem.max_constant)))
    other = draw(programs(problem, max_depth))
    cond = App(draw(st.sampled_from(["<=", "="])), (coord, bound) if draw(st.booleans()) else (bound, coord))
    return App("ite", (cond, prog, other))


def _variables(t: Term) -> set[str]:
    if isinstance(t, Var):
        return {t.name}
    if isinstance(t, App):
        return set().union(*(_variables(a) for a in t.args))
    return set()


@st.composite
def problems_and_programs(
    draw: st.DrawFn, max_depth: int = 5, reading_obstacles: bool = False, **kwargs: Any
) -> tuple[GridProblem, Term]:
    """A random small problem together with a random program of its grammar (with
    ``reading_obstacles``, one that reads an obstacle: see :func:`programs_reading_obstacles`)."""
    if reading_obstacles:
        kwargs.setdefault("min_obstacles", 1)
        kwargs["max_obstacles"] = max(kwargs.get("max_obstacles", 2), kwargs["min_obstacles"])
    p = draw(grid_problems(**kwargs))
    if reading_obstacles:
        return p, draw(programs_reading_obstacles(p, max_depth))
    return p, draw(programs(p, max_depth))


@st.composite
def states_of(draw: st.DrawFn, problem: GridProblem):
    """An arbitrary :class:`~plansynth.grid.semantics.State` of ``problem`` (any cells in the grid)."""
    from plansynth.grid.semantics import State

    cell = _cells_of(problem.width, problem.height)
    return State(draw(cell), tuple(draw(cell) for _ in problem.obstacles))


# -- objectives and obstacles with a block, a period, glitches ------------------------

OBJECTIVES = ("exact", "reach", "safety", "recurrence")


@st.composite
def objective_documents(
    draw: st.DrawFn, objective: str | None = None, *, max_side: int = 4, max_obstacles: int = 1, max_steps: int = 4
) -> dict[str, Any]:
    """A valid problem document with one of the :data:`OBJECTIVES` and plansynth's
    obstacle extensions drawn at random: a block (``size``), a ``period`` with either
    ``schedule`` and a ``phase``, ``glitches``, ``keep_out`` cells, and
    ``collision: position``. Tiny on purpose: the oracle of :mod:`plansynth.grid.oracle`
    enumerates every state."""
    kind = objective or draw(st.sampled_from(OBJECTIVES))
    doc = draw(
        problem_documents(
            max_side=max_side,
            min_obstacles=0,
            max_obstacles=max_obstacles,
            max_obstacle_moves=3,
            max_robot_moves=5,
            max_steps=max_steps,
        )
    )
    w, h = doc["grid"]
    cell = _cells_of(w, h)
    if kind != "exact":
        doc["objective"] = kind
    if kind in ("safety", "recurrence"):
        del doc["steps"]
        goal = doc["robot"].pop("goal")
        if kind == "recurrence":
            walls = {tuple(c) for c in doc.get("walls", [])}
            others = draw(st.lists(cell.filter(lambda c: c not in walls), max_size=2))
            doc["robot"]["goals"] = [goal] + [list(c) for c in others]
            if doc["obstacles"] and draw(st.booleans()):
                doc["fair"] = True
    if draw(st.booleans()):
        doc["collision"] = "position"
    for o in doc["obstacles"]:
        bw = draw(st.integers(1, min(2, w)))
        bh = draw(st.integers(1, min(2, h)))
        if (bw, bh) != (1, 1):
            o["size"] = [bw, bh]
            o["start"] = [min(o["start"][0], w - bw), min(o["start"][1], h - bh)]
        period = draw(st.integers(1, 3))
        if period > 1:
            o["period"] = period
            if "stay" not in o["moves"]:
                o["moves"] = ["stay"] + [m for m in o["moves"] if not (isinstance(m, dict) and m["name"] == "stay")]
            if draw(st.booleans()):
                o["schedule"] = "fixed"
            if draw(st.booleans()):
                o["phase"] = draw(st.integers(0, period - 1))
            glitches = draw(st.integers(0, 2))
            if glitches:
                o["glitches"] = glitches
        if draw(st.integers(0, 3)) == 0:
            o["keep_out"] = [list(draw(cell))]
    return doc


def objective_problems(objective: str | None = None, **kwargs: Any) -> st.SearchStrategy[GridProblem]:
    """:func:`objective_documents` loaded through :func:`grid_problem_from_dict`."""
    return objective_documents(objective, **kwargs).map(lambda d: grid_problem_from_dict(d, source="<hypothesis>"))
