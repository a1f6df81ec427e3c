"""Controller programs: the grammar of Listing 1 of Chasins & Newcomb (SYNT 2016).

A controller is a term over the integer inputs ``rx ry o0x o0y ...``::

    Start  ::= MoveId | (ite B Start Start)
    B      ::= (and B B) | (or B B) | (not B) | (<= T T) | (= T T)
    T      ::= rx | ry | o0x | ... | (+ T T) | (- T T) | -1 | 0 | ... | d-1

This module holds the AST, a parser and printer for SyGuS-IF v2 terms (including
``(define-fun move (...) Int TERM)``), evaluation, the paper's depth measure (a
coordinate, written ``(get-x p)`` in the paper, has depth 2), size, and export as
Python and C source that a robot could run.

The terms and their measures are :mod:`plansynth.grid.terms`, the export
:mod:`plansynth.grid.program_export`; this module holds the grammar check, the parser
and the reference interpreter, and exports the others' names as it always has.

>>> prog = parse_program("(ite (<= rx 3) 2 1)")
>>> print(prog, depth(prog), size(prog))
(ite (<= rx 3) 2 1) 4 6
>>> evaluate(prog, {"rx": 4})
1
>>> print(parse_program("(ite (= ry (- 1)) 0 1)"))
(ite (= ry (- 1)) 0 1)
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

from plansynth.errors import PlansynthError
from plansynth.grid.program_export import (  # noqa: F401 - the export, imported from here too
    KEYWORDS,
    compile_program,
    function_name_problem,
    to_c,
    to_define_fun,
    to_python,
)
from plansynth.grid.terms import (  # noqa: F401 - the terms and measures, imported from here too
    SIGNATURES,
    App,
    Const,
    Term,
    Var,
    depth,
    ite,
    reads_obstacles,
    size,
    subterms,
    variables_of,
)


class ProgramSyntaxError(PlansynthError):
    """Text that is not a term of the controller grammar."""


# -- grammar check ---------------------------------------------------------------------


def check_program(t: Term, variables: Sequence[str], n_moves: int, max_constant: int) -> None:
    """Raise :class:`ProgramSyntaxError` unless ``t`` is a Start term of the grammar.

    Move numbers must lie in 0..n_moves-1, constants in -1..max_constant, and every
    coordinate must be one of ``variables``.
    """
    _check(t, "S", frozenset(variables), n_moves, max_constant)


def _check(t: Term, sort: str, names: frozenset[str], m: int, dmax: int) -> None:
    if isinstance(t, Const):
        if sort == "S" and not 0 <= t.value < m:
            raise ProgramSyntaxError(f"move number {t.value} is not in 0..{m - 1}")
        if sort == "T" and not -1 <= t.value <= dmax:
            raise ProgramSyntaxError(f"constant {t.value} is not in -1..{dmax}")
        if sort == "B":
            raise ProgramSyntaxError(f"integer {t.value} where a condition is expected")
        return
    if isinstance(t, Var):
        if sort != "T":
            raise ProgramSyntaxError(
                f"coordinate {t.name} where a {'move' if sort == 'S' else 'condition'} is expected"
            )
        if t.name not in names:
            raise ProgramSyntaxError(f"unknown input {t.name!r} (inputs: {' '.join(sorted(names))})")
        return
    arg_sorts, result = SIGNATURES[t.op]
    if result != sort:
        raise ProgramSyntaxError(f"({t.op} ...) where a {'move' if sort == 'S' else sort} term is expected")
    for a, s in zip(t.args, arg_sorts):
        _check(a, s, names, m, dmax)


# -- parsing ---------------------------------------------------------------------------

#: Deepest nesting of parentheses a program may have. Synthesized controllers are far
#: shallower (depth 5-20); the bound keeps parsing, printing, evaluation and the
#: generated Python (whose parser allows 200 nested parentheses) safe.
MAX_PROGRAM_NESTING = 100

#: Longest integer literal, in digits (the grammar's constants are below the grid size).
MAX_LITERAL_DIGITS = 9

_TOKEN = re.compile(r"[ \t\r\n\f\v]*(?:(;[^\n]*)|(\()|(\))|([^ \t\r\n\f\v()]+))", re.ASCII)
_INTEGER = re.compile(r"-?[0-9]+", re.ASCII)
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,63}", re.ASCII)  # inputs are rx, ry, o0x, ...


def _tokens(text: str) -> list[str]:
    out = []
    pos = 0
    text = text.strip(" \t\r\n\f\v")
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise ProgramSyntaxError(f"cannot read {text[pos : pos + 20]!r}")
        pos = m.end()
        if m.group(1):
            continue
        out.append(m.group(2) or m.group(3) or m.group(4))
    return out


def _sexpr(tokens: list[str], i: int) -> tuple[object, int]:
    """Read one s-expression starting at ``tokens[i]``, without recursion."""
    if i >= len(tokens):
        raise ProgramSyntaxError("unexpected end of text")
    stack: list[list[object]] = []
    while True:
        if i >= len(tokens):
            raise ProgramSyntaxError("missing ')'")
        tok = tokens[i]
        i += 1
        if tok == "(":
            if len(stack) >= MAX_PROGRAM_NESTING:
                raise ProgramSyntaxError(f"nested deeper than {MAX_PROGRAM_NESTING} parentheses")
            stack.append([])
            continue
        if tok == ")":
            if not stack:
                raise ProgramSyntaxError("unexpected ')'")
            item: object = stack.pop()
        else:
            item = tok
        if not stack:
            return item, i
        stack[-1].append(item)


def parse_sexpr(text: str) -> object:
    """Parse one s-expression into nested lists of strings.

    Nesting deeper than :data:`MAX_PROGRAM_NESTING` is a :class:`ProgramSyntaxError`.
    """
    tokens = _tokens(text)
    value, i = _sexpr(tokens, 0)
    if i != len(tokens):
        raise ProgramSyntaxError(f"trailing text after the term: {' '.join(tokens[i : i + 5])[:200]!r}")
    return value


def parse_program(text: str) -> Term:
    """Parse a controller: a bare term or ``(define-fun move (...) Int TERM)``.

    Also accepts a solver's answer wrapped in parentheses, as cvc5 prints it:
    ``((define-fun move ...))``. n-ary ``and``/``or``/``+`` are folded to binary, as a
    balanced tree (so a 20,000-term ``and`` is 15 levels deep, not 20,000). Digits are
    ASCII only, as in SyGuS-IF.
    """
    sx = parse_sexpr(text)
    # Unwrap "((define-fun ...))" as printed by `(check-synth)`.
    while isinstance(sx, list) and len(sx) == 1 and isinstance(sx[0], list):
        sx = sx[0]
    if isinstance(sx, list) and sx and sx[0] == "define-fun":
        if len(sx) != 5:
            raise ProgramSyntaxError("define-fun needs a name, parameters, a sort and a body")
        sx = sx[4]
    return _term(sx)


def _literal(token: str) -> int:
    digits = token.lstrip("-")
    if len(digits) > MAX_LITERAL_DIGITS:
        raise ProgramSyntaxError(f"integer literal {token[:20]}... has more than {MAX_LITERAL_DIGITS} digits")
    return int(token)


def _fold(op: str, args: Sequence[Term]) -> Term:
    """``args`` joined by the associative ``op`` as a balanced binary tree.

    For three arguments this is ``(op (op a b) c)``, as a left fold gives.
    """
    if len(args) == 1:
        return args[0]
    mid = (len(args) + 1) // 2
    return App(op, (_fold(op, args[:mid]), _fold(op, args[mid:])))


def _term(sx: object) -> Term:
    if isinstance(sx, str):
        if _INTEGER.fullmatch(sx):
            return Const(_literal(sx))
        if _NAME.fullmatch(sx) and sx not in SIGNATURES:
            if sx in KEYWORDS:
                raise ProgramSyntaxError(
                    f"{sx!r} cannot name an input: it is a keyword of Python or C, and programs are exported to both"
                )
            return Var(sx)
        raise ProgramSyntaxError(f"unexpected token {sx[:40]!r}")
    if not isinstance(sx, list) or not sx or not isinstance(sx[0], str):
        raise ProgramSyntaxError(f"unexpected term {str(sx)[:60]}")
    op, rest = sx[0], sx[1:]
    if (
        op == "-"
        and len(rest) == 1
        and isinstance(rest[0], str)
        and _INTEGER.fullmatch(rest[0])
        and not rest[0].startswith("-")
    ):
        return Const(-_literal(rest[0]))  # SyGuS writes the constant -1 as (- 1)
    if op not in SIGNATURES:
        raise ProgramSyntaxError(f"unknown operator {op[:40]!r}")
    args = tuple(_term(a) for a in rest)
    arity = len(SIGNATURES[op][0])
    if op in ("and", "or", "+") and len(args) > 2:
        return _fold(op, args)
    if len(args) != arity:
        raise ProgramSyntaxError(f"{op} takes {arity} arguments, got {len(args)}")
    return App(op, args)


def evaluate(t: Term, env: Mapping[str, int]) -> int | bool:
    """Evaluate a term under an assignment of the inputs (a reference interpreter)."""
    if isinstance(t, Const):
        return t.value
    if isinstance(t, Var):
        return env[t.name]
    op, args = t.op, t.args
    if op == "ite":
        return evaluate(args[1], env) if evaluate(args[0], env) else evaluate(args[2], env)
    if op == "and":
        return bool(evaluate(args[0], env)) and bool(evaluate(args[1], env))
    if op == "or":
        return bool(evaluate(args[0], env)) or bool(evaluate(args[1], env))
    if op == "not":
        return not evaluate(args[0], env)
    x, y = (evaluate(a, env) for a in args)
    if op == "<=":
        return x <= y
    if op == "=":
        return x == y
    if op == "+":
        return x + y
    return x - y
