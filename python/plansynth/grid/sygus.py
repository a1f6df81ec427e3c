"""Compile a grid problem to a SyGuS-IF v2 specification (Chasins & Newcomb, SYNT 2016, §3.2).

The controller is the function to synthesize, ``move``, over the spec's inputs
``rx ry o0x o0y ...`` with the grammar of the paper's Listing 1. The obstacles'
choices are universally quantified: one ``declare-var`` per obstacle and step
(``o<i>m<t>``, obstacle i's move number at step t). As in the paper, the single
constraint says: if the obstacles' choices are allowable
(``obstaclePositionsAllowable``), then the robot, moving by ``move`` applied to the
current positions at every step (the path is unrolled ``l`` times with ``let``), never
collides (``noIntersection``) and ends on its goal (``correctFinalPosition``).

The formulas follow ``shared/spec/grid-problem.md`` rather than the paper's published
encoding: cells are (x, y) pairs; a move that would sweep a cell off the grid leaves the
agent in place, sweeping only its cell; walls clamp obstacles and collide with the
robot; moves sweep their ``via`` cells; a diagonal crossing is not a collision. Every
rule of :mod:`plansynth.grid.semantics` is written out once as a ``define-fun``, so the
text reads as the model it encodes, and ``tests/grid/test_crosscheck.py`` checks it
against the independent verifier.

:func:`compile_sygus` gives the synthesis problem, optionally with the grammar unrolled
by depth so that ``infeasible`` means "no controller of depth <= D" exactly.
:func:`compile_check` gives the same constraint as an SMT-LIB query with a program in
place of ``move``: it is unsat exactly when the program wins.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> p = grid_problem_from_dict({"grid": [3, 2],
...     "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]}})
>>> text = compile_sygus(p, 2)
>>> print(text[text.index("(synth-fun"):text.index("; -- the grid")].strip())
(synth-fun move ((rx Int) (ry Int)) Int
  ((Start Int) (B Bool) (T Int))
  ((Start Int (0 1 (ite B Start Start)))
   (B Bool ((and B B) (or B B) (not B) (<= T T) (= T T)))
   (T Int (rx ry (+ T T) (- T T) (- 1) 0 1 2))))
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from plansynth.errors import InvalidProblem
from plansynth.grid.problem import Cell, GridProblem, Move
from plansynth.grid.programs import Term, check_program, to_define_fun

__all__ = ["compile_sygus", "compile_check", "grammar", "choice_variable", "read_synth_answer", "SynthAnswer"]


# -- small printers --------------------------------------------------------------------


def _int(v: int) -> str:
    """An SMT-LIB integer literal (negative ones as ``(- n)``)."""
    return str(v) if v >= 0 else f"(- {-v})"


def _shift(var: str, d: int) -> str:
    """``var + d`` written readably: ``x``, ``(+ x 1)``, ``(- x 1)``."""
    if d == 0:
        return var
    return f"(+ {var} {d})" if d > 0 else f"(- {var} {-d})"


def _conj(parts: Sequence[str]) -> str:
    flat: list[str] = []
    for p in parts:  # flatten nested conjunctions: (and a (and b c)) -> (and a b c)
        flat.extend(_conjuncts(p))
    parts = [p for p in flat if p != "true"]
    if not parts:
        return "true"
    return parts[0] if len(parts) == 1 else f"(and {' '.join(parts)})"


def _conjuncts(term: str) -> list[str]:
    """The top-level conjuncts of ``term`` if it is an ``and`` of parenthesized terms."""
    if not term.startswith("(and "):
        return [term]
    out: list[str] = []
    depth, start = 0, 0
    for i in range(5, len(term) - 1):
        ch = term[i]
        if ch == "(":
            if depth == 0:
                start = i
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                out.append(term[start : i + 1])
        elif depth == 0 and not ch.isspace():
            return [term]  # an atom at top level: leave the term alone
    return out


def _disj(parts: Sequence[str]) -> str:
    parts = [p for p in parts if p != "false"]
    if not parts:
        return "false"
    return parts[0] if len(parts) == 1 else f"(or {' '.join(parts)})"


def _disj_lines(parts: Sequence[str]) -> str:
    """A disjunction laid out one disjunct a line."""
    parts = [p for p in parts if p != "false"]
    if len(parts) <= 1:
        return _disj(parts)
    return "(or " + "\n      ".join(parts) + ")"


def _away(move: Move) -> tuple[Cell, ...]:
    """The offsets a move sweeps besides its start cell."""
    return tuple(o for o in move.offsets() if o != (0, 0))


def choice_variable(obstacle: int, t: int) -> str:
    """Name of the universally quantified move choice of ``obstacle`` at step ``t``."""
    return f"o{obstacle}m{t}"


# -- the grammar (Listing 1) -------------------------------------------------------------


def grammar(problem: GridProblem, depth_bound: int | None = None) -> str:
    """The grammar of the paper's Listing 1 as a SyGuS-IF v2 grammar block.

    Without ``depth_bound`` it has the three nonterminals ``Start``, ``B`` and ``T``.
    With a bound D it is unrolled by depth (the paper's measure, see
    :func:`plansynth.grid.programs.depth`): ``S<d>``, ``B<d>``, ``T<d>`` derive exactly the
    terms of depth <= d, and ``Start`` is ``S<D>``.

    >>> from plansynth.grid.problem import grid_problem_from_dict
    >>> p = grid_problem_from_dict({"grid": [2, 2],
    ...     "robot": {"start": [0, 0], "goal": [1, 0], "moves": ["stay", "right"]}})
    >>> print(grammar(p, 3))
    ((Start Int) (B2 Bool) (S2 Int) (T1 Int))
      ((Start Int (0 1 (ite B2 S2 S2)))
       (B2 Bool ((<= T1 T1) (= T1 T1)))
       (S2 Int (0 1))
       (T1 Int ((- 1) 0 1)))
    """
    moves = [str(k) for k in range(len(problem.robot.moves))]
    consts = [_int(c) for c in range(-1, problem.max_constant + 1)]
    coords = list(problem.variables)
    rules: list[tuple[str, str, list[str]]] = []  # (name, sort, productions), Start first
    if depth_bound is None:
        rules = [
            ("Start", "Int", moves + ["(ite B Start Start)"]),
            ("B", "Bool", ["(and B B)", "(or B B)", "(not B)", "(<= T T)", "(= T T)"]),
            ("T", "Int", coords + ["(+ T T)", "(- T T)"] + consts),
        ]
    else:
        if depth_bound < 1:
            raise InvalidProblem(None, "depth_bound", f"must be >= 1, got {depth_bound}")
        D = depth_bound

        def s(d: int) -> str:
            return "Start" if d == D else f"S{d}"

        # Emit nonterminals reachable from Start, top down. B<d> exists for d >= 2.
        for d in range(D, 0, -1):
            ite = [f"(ite B{d - 1} {s(d - 1)} {s(d - 1)})"] if d >= 3 else []
            rules.append((s(d), "Int", moves + ite))
        for d in range(D - 1, 1, -1):
            logic = [f"(and B{d - 1} B{d - 1})", f"(or B{d - 1} B{d - 1})", f"(not B{d - 1})"] if d >= 3 else []
            rules.append((f"B{d}", "Bool", logic + [f"(<= T{d - 1} T{d - 1})", f"(= T{d - 1} T{d - 1})"]))
        for d in range(D - 2, 0, -1):
            arith = coords + [f"(+ T{d - 1} T{d - 1})", f"(- T{d - 1} T{d - 1})"] if d >= 2 else []
            rules.append((f"T{d}", "Int", arith + consts))
        # Only what Start can reach: S<d> needs B<d-1> (d >= 3), B<d> needs T<d-1>.
        reach = _reachable(rules)
        rules = [r for r in rules if r[0] in reach]
        # Order: Start, then by name for a stable, readable layout.
        rules = [rules[0]] + sorted(rules[1:], key=lambda r: (r[0][0], -int(r[0][1:])))
    decl = " ".join(f"({n} {srt})" for n, srt, _ in rules)
    body = "\n   ".join(f"({n} {srt} ({' '.join(ps)}))" for n, srt, ps in rules)
    return f"({decl})\n  ({body})"


def _reachable(rules: list[tuple[str, str, list[str]]]) -> set[str]:
    names = {n for n, _, _ in rules}
    prods = {n: " ".join(ps) for n, _, ps in rules}
    seen = {rules[0][0]}
    todo = [rules[0][0]]
    while todo:
        n = todo.pop()
        for tok in prods[n].replace("(", " ").replace(")", " ").split():
            if tok in names and tok not in seen:
                seen.add(tok)
                todo.append(tok)
    return seen


# -- the model as define-funs ------------------------------------------------------------


def _helpers(problem: GridProblem) -> list[str]:
    """``define-fun``s for the grid, the robot's and obstacles' moves and the three
    predicates of §3.2, written from the spec's rules (the semantics module's twins)."""
    p = problem
    out: list[str] = []
    add = out.append
    n = len(p.obstacles)

    add(f"; -- the grid: {p.width} x {p.height}, cells (x, y)")
    add(
        f"(define-fun in-grid ((x Int) (y Int)) Bool\n"
        f"  (and (<= 0 x) (<= x {p.width - 1}) (<= 0 y) (<= y {p.height - 1})))"
    )
    walls = _disj([f"(and (= x {wx}) (= y {wy}))" for wx, wy in sorted(p.walls)])
    add(f"(define-fun wall ((x Int) (y Int)) Bool\n  {walls})")
    add("(define-fun free ((x Int) (y Int)) Bool (and (in-grid x y) (not (wall x y))))")

    # Robot.
    names = ", ".join(f"{k} {m.name}" for k, m in enumerate(p.robot.moves))
    add(
        f"\n; -- the robot's move k from (x, y): moves {names}.\n"
        "; A move that would sweep a cell off the grid leaves the robot at (x, y); a wall does not."
    )

    def possible(move: Move, ok: str) -> str:
        """Every cell the move sweeps is on the grid (robot) or free (obstacle). An
        obstacle's own cell counts too: one that starts on a wall never moves."""
        cells = [f"({ok} {_shift('x', dx)} {_shift('y', dy)})" for dx, dy in _away(move)]
        own = ["(not (wall x y))"] if ok == "free" and p.walls and cells else []
        return _conj(own + cells)

    def end(moves: Sequence[Move], axis: int, var: str, choice: str, ok: str) -> str:
        expr = var
        for k in reversed(range(len(moves))):
            d = moves[k].to[axis]
            if d != 0:
                cond = _conj([f"(= {choice} {k})", possible(moves[k], ok)])
                expr = f"(ite {cond} {_shift(var, d)}\n  {expr})"
        return expr

    rm = p.robot.moves
    add(f"(define-fun robot-x ((x Int) (y Int) (k Int)) Int\n  {end(rm, 0, 'x', 'k', 'in-grid')})")
    add(f"(define-fun robot-y ((x Int) (y Int) (k Int)) Int\n  {end(rm, 1, 'y', 'k', 'in-grid')})")
    sweeps = ["(and (= cx x) (= cy y))"]
    for k, m in enumerate(rm):
        if _away(m):
            cells = _disj([f"(and (= cx {_shift('x', dx)}) (= cy {_shift('y', dy)}))" for dx, dy in _away(m)])
            sweeps.append(_conj([f"(= k {k})", possible(m, "in-grid"), cells]))
    add(
        "; does the robot, moving by k from (x, y), sweep the cell (cx, cy)?\n"
        f"(define-fun robot-sweeps ((x Int) (y Int) (k Int) (cx Int) (cy Int)) Bool\n  {_disj_lines(sweeps)})"
    )
    hits_wall = ["(wall x y)"]
    for k, m in enumerate(rm):
        if _away(m):
            cells = _disj([f"(wall {_shift('x', dx)} {_shift('y', dy)})" for dx, dy in _away(m)])
            hits_wall.append(_conj([f"(= k {k})", possible(m, "in-grid"), cells]))
    add(
        "; does the robot, moving by k from (x, y), sweep a wall?\n"
        f"(define-fun robot-hits-wall ((x Int) (y Int) (k Int)) Bool\n  {_disj_lines(hits_wall)})"
    )

    # Obstacles.
    for i, o in enumerate(p.obstacles):
        names = ", ".join(f"{k} {m.name}" for k, m in enumerate(o.moves))
        add(
            f"\n; -- obstacle {i}, from ({o.start[0]}, {o.start[1]}): moves {names}.\n"
            "; A move that would sweep a cell off the grid or a wall leaves it at (x, y)"
            + (" (a wall under\n; the obstacle's own cell included)." if p.walls else ".")
        )
        om = o.moves
        add(f"(define-fun o{i}-x ((x Int) (y Int) (c Int)) Int\n  {end(om, 0, 'x', 'c', 'free')})")
        add(f"(define-fun o{i}-y ((x Int) (y Int) (c Int)) Int\n  {end(om, 1, 'y', 'c', 'free')})")
        hits = ["(robot-sweeps rx ry k x y)"]
        for c, m in enumerate(om):
            if _away(m):
                cells = _disj([f"(robot-sweeps rx ry k {_shift('x', dx)} {_shift('y', dy)})" for dx, dy in _away(m)])
                hits.append(_conj([f"(= c {c})", possible(m, "free"), cells]))
        add(
            f"; does obstacle {i}, moving by c from (x, y), sweep a cell the robot sweeps moving by k from (rx, ry)?\n"
            f"(define-fun o{i}-hits ((x Int) (y Int) (c Int) (rx Int) (ry Int) (k Int)) Bool\n  {_disj_lines(hits)})"
        )

    # The three predicates of §3.2.
    cs = " ".join(f"(c{i} Int)" for i in range(n))
    allow = _conj([b for i, o in enumerate(p.obstacles) for b in (f"(<= 0 c{i})", f"(<= c{i} {len(o.moves) - 1})")])
    add(
        "\n; -- §3.2: the obstacles' choices at one step are moves they have\n"
        f"(define-fun obstaclePositionsAllowable ({cs}) Bool\n  {allow})"
    )
    params = " ".join(["(rx Int) (ry Int) (k Int)"] + [f"(o{i}x Int) (o{i}y Int) (c{i} Int)" for i in range(n)])
    clash = ["(robot-hits-wall rx ry k)"] + [f"(o{i}-hits o{i}x o{i}y c{i} rx ry k)" for i in range(n)]
    add(
        "; the robot moving by k meets no wall and no obstacle moving by its choice c<i>\n"
        f"(define-fun noIntersection ({params}) Bool\n  (not {_disj(clash)}))"
    )
    gx, gy = p.robot.goal
    add(f"(define-fun correctFinalPosition ((rx Int) (ry Int)) Bool (and (= rx {gx}) (= ry {gy})))")
    return out


def _constraint(problem: GridProblem, steps: int) -> tuple[list[str], str, str]:
    """(choice variables, antecedent, consequent) of the §3.2 constraint for ``steps`` steps.

    The consequent unrolls the path: at step t the robot's move is ``k<t> = (move ...)``
    applied to the positions ``rx<t> ry<t> o0x<t> ...``, which ``let`` binds step by step.
    """
    p = problem
    n = len(p.obstacles)
    if steps < 1:
        raise InvalidProblem(p.source, "steps", f"must be >= 1, got {steps}")
    choices = [choice_variable(i, t) for t in range(steps) for i in range(n)]
    allowable = (
        [f"(obstaclePositionsAllowable {' '.join(choice_variable(i, t) for i in range(n))})" for t in range(steps)]
        if n
        else []
    )
    ante = (
        "true"
        if not allowable
        else allowable[0]
        if len(allowable) == 1
        else ("(and " + "\n                    ".join(allowable) + ")")
    )

    def pos(t: int) -> list[str]:
        return [f"rx{t}", f"ry{t}"] + [f"o{i}{a}{t}" for i in range(n) for a in "xy"]

    init = [str(v) for v in (*p.robot.start, *(c for o in p.obstacles for c in o.start))]
    lines = ["(let (" + " ".join(f"({v} {e})" for v, e in zip(pos(0), init)) + ")"]
    closers = 1
    for t in range(steps):
        here = pos(t)
        lines.append(f"; step {t}")
        lines.append(f"(let ((k{t} (move {' '.join(here)})))")
        obs = " ".join(f"o{i}x{t} o{i}y{t} {choice_variable(i, t)}" for i in range(n))
        lines.append(f"(and (noIntersection rx{t} ry{t} k{t}{' ' + obs if obs else ''})")
        nxt = [f"(rx{t + 1} (robot-x rx{t} ry{t} k{t})) (ry{t + 1} (robot-y rx{t} ry{t} k{t}))"]
        for i in range(n):
            args = f"o{i}x{t} o{i}y{t} {choice_variable(i, t)}"
            nxt.append(f"(o{i}x{t + 1} (o{i}-x {args})) (o{i}y{t + 1} (o{i}-y {args}))")
        lines.append("(let (" + "\n          ".join(nxt) + ")")
        closers += 3
    lines.append(f"(correctFinalPosition rx{steps} ry{steps})" + ")" * closers)
    return choices, ante, "\n    ".join(lines)


def _header(problem: GridProblem, steps: int, what: str) -> list[str]:
    p = problem
    obs = "; ".join(f"{i} from ({o.start[0]}, {o.start[1]})" for i, o in enumerate(p.obstacles)) or "none"
    walls = " ".join(f"({x}, {y})" for x, y in sorted(p.walls)) or "none"
    return [
        f"; plansynth grid problem {p.name!r}: {what}",
        "; Encoding: Chasins & Newcomb, SYNT 2016, Section 3.2, with the semantics of the",
        "; plansynth grid spec (cells (x, y); a clamped move sweeps only its start cell;",
        "; walls clamp obstacles and collide with the robot; via cells; diagonal crossings).",
        f"; grid {p.width} x {p.height}; path length l = {steps}; robot ({p.robot.start[0]}, {p.robot.start[1]})"
        f" -> ({p.robot.goal[0]}, {p.robot.goal[1]}); obstacles: {obs}; walls: {walls}",
        "; o<i>m<t> is obstacle i's move number at step t (universally quantified).",
    ]


def sygus_limitation(problem: GridProblem) -> tuple[str, str] | None:
    """(field, reason) when ``problem`` is outside what the SyGuS encoding covers (the
    paper's model: the exact-l objective, swept-cell collisions, one-cell obstacles that
    move every step), else None.

    >>> from plansynth.grid.problem import grid_problem_from_dict
    >>> sygus_limitation(grid_problem_from_dict({"grid": [2, 2], "objective": "safety",
    ...     "robot": {"start": [0, 0], "moves": ["stay"]}}))
    ('objective', 'the SyGuS encoding covers the objective exact only, not safety (use --solver native)')
    """
    if problem.paper_model:
        return None
    if problem.objective.value != "exact":
        return (
            "objective",
            f"the SyGuS encoding covers the objective exact only, not {problem.objective.value} (use --solver native)",
        )
    if problem.collision.value != "sweep":
        return "collision", "the SyGuS encoding covers swept-cell collisions only (use --solver native)"
    i = next(i for i, o in enumerate(problem.obstacles) if not (o.plain and not o.glitching))
    return f"obstacles[{i}]", (
        "the SyGuS encoding covers one-cell obstacles that move every step (no size, period, "
        "glitches or keep_out; use --solver native)"
    )


def check_encodable(problem: GridProblem) -> None:
    """Raise :class:`~plansynth.errors.InvalidProblem` unless :func:`sygus_limitation` is None."""
    got = sygus_limitation(problem)
    if got is not None:
        from plansynth.errors import InvalidProblem

        raise InvalidProblem(problem.source, got[0], got[1])


def compile_sygus(problem: GridProblem, steps: int, depth_bound: int | None = None) -> str:
    """The SyGuS-IF v2 specification of ``problem`` at path length exactly ``steps``.

    A solution of the specification is a controller that wins at ``steps`` steps; with
    ``depth_bound`` D the grammar only derives programs of depth <= D, so a solver's
    ``infeasible`` means no controller of depth <= D wins. Pure: the same problem gives
    the same text.

    Only problems of the paper's model are encoded (:attr:`GridProblem.paper_model`);
    another objective or an obstacle with a block, a period or glitches is
    :class:`~plansynth.errors.InvalidProblem` naming the field.
    """
    check_encodable(problem)
    bound = "unbounded grammar (Listing 1)" if depth_bound is None else f"grammar bounded to depth <= {depth_bound}"
    lines = _header(problem, steps, f"synthesize a controller ({bound})")
    lines.append("(set-logic LIA)\n")
    params = " ".join(f"({v} Int)" for v in problem.variables)
    lines.append(f"(synth-fun move ({params}) Int\n  {grammar(problem, depth_bound)})\n")
    lines.extend(_helpers(problem))
    choices, ante, cons = _constraint(problem, steps)
    lines.append("")
    lines.extend(f"(declare-var {c} Int)" for c in choices)
    lines.append(f"(constraint (=> {ante}\n    {cons}))" if ante != "true" else f"(constraint\n    {cons})")
    lines.append("(check-synth)")
    return "\n".join(lines) + "\n"


def compile_check(problem: GridProblem, steps: int, program: Term) -> str:
    """SMT-LIB 2.6 text: the §3.2 constraint negated, with ``program`` as ``move``.

    The obstacles' choices become constants; the query is ``unsat`` exactly when the
    program wins at ``steps`` steps (no allowable obstacle behaviour makes it collide or
    miss the goal). ``program`` must be a term of the problem's grammar.
    """
    check_program(program, problem.variables, len(problem.robot.moves), problem.max_constant)
    lines = _header(problem, steps, f"check the controller {program}")
    lines.append("; unsat <=> the controller wins at exactly l steps")
    lines.append("(set-logic LIA)\n")
    lines.append(to_define_fun(program, problem.variables) + "\n")
    lines.extend(_helpers(problem))
    choices, ante, cons = _constraint(problem, steps)
    lines.append("")
    lines.extend(f"(declare-fun {c} () Int)" for c in choices)
    lines.append(f"(assert {ante})")
    lines.append(f"(assert (not\n    {cons}))")
    lines.append("(check-sat)")
    return "\n".join(lines) + "\n"


# -- reading a solver's answer -----------------------------------------------------------


@dataclass(frozen=True)
class SynthAnswer:
    """What a SyGuS solver printed for ``(check-synth)``, read.

    ``kind`` is ``"solution"`` (``definition`` holds the ``define-fun`` of ``move``),
    ``"infeasible"`` (no function of the grammar satisfies the constraints) or
    ``"unknown"`` (``fail``, ``unknown``, an error or nothing recognisable; ``text`` says).
    """

    kind: str
    definition: str | None
    text: str


def read_synth_answer(output: str, function: str = "move") -> SynthAnswer:
    """Read the answer to ``(check-synth)`` from a solver's output.

    >>> read_synth_answer("(\\n(define-fun move ((rx Int)) Int (ite (<= rx 3) 2 1))\\n)\\n").definition
    '(define-fun move ((rx Int)) Int (ite (<= rx 3) 2 1))'
    >>> read_synth_answer("infeasible\\n").kind
    'infeasible'
    >>> read_synth_answer("(error \\"oops\\")").kind
    'unknown'
    """
    text = output.strip()
    start = text.find(f"(define-fun {function} ")
    if start >= 0:
        depth = 0
        for i in range(start, len(text)):
            if text[i] == "(":
                depth += 1
            elif text[i] == ")":
                depth -= 1
                if depth == 0:
                    return SynthAnswer("solution", text[start : i + 1], output)
        return SynthAnswer("unknown", None, output)
    if any(line.strip() == "infeasible" for line in text.splitlines()):
        return SynthAnswer("infeasible", None, output)
    return SynthAnswer("unknown", None, output)
