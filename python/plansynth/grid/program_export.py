"""Export of a controller program (:mod:`plansynth.grid.programs`, the grammar of
Chasins & Newcomb, SYNT 2016, Listing 1) as Python and C source that a robot could run
and as a SyGuS ``define-fun``, with the function names each language allows, and a
compiled Python callable.
"""

from __future__ import annotations

import keyword
import re
from collections.abc import Callable, Sequence

from plansynth.grid.terms import Const, Term, Var

# -- evaluation and export -------------------------------------------------------------

_PY = {"and": "and", "or": "or", "<=": "<=", "=": "==", "+": "+", "-": "-"}


def _expr(t: Term, lang: str) -> str:
    if isinstance(t, Const):
        return str(t.value) if t.value >= 0 else f"({t.value})"
    if isinstance(t, Var):
        return t.name
    a = [_expr(x, lang) for x in t.args]
    if t.op == "ite":
        if lang == "c":
            return f"({a[0]} ? {a[1]} : {a[2]})"
        return f"({a[1]} if {a[0]} else {a[2]})"
    if t.op == "not":
        return f"(!{a[0]})" if lang == "c" else f"(not {a[0]})"
    if lang == "c":
        op = {"and": "&&", "or": "||", "=": "=="}.get(t.op, t.op)
    else:
        op = _PY[t.op]
    return f"({a[0]} {op} {a[1]})"


_C_KEYWORDS = frozenset(
    [
        "auto",
        "break",
        "case",
        "char",
        "const",
        "continue",
        "default",
        "do",
        "double",
        "else",
        "enum",
        "extern",
        "float",
        "for",
        "goto",
        "if",
        "inline",
        "int",
        "long",
        "register",
        "restrict",
        "return",
        "short",
        "signed",
        "sizeof",
        "static",
        "struct",
        "switch",
        "typedef",
        "union",
        "unsigned",
        "void",
        "volatile",
        "while",
        "_Alignas",
        "_Alignof",
        "_Atomic",
        "_Bool",
        "_Complex",
        "_Generic",
        "_Imaginary",
        "_Noreturn",
        "_Static_assert",
        "_Thread_local",
        "alignas",
        "alignof",
        "bool",
        "constexpr",
        "false",
        "nullptr",
        "static_assert",
        "thread_local",
        "true",
        "typeof",
        "typeof_unqual",
        "main",
    ]
)
_SYGUS_RESERVED = frozenset(
    [
        "_",
        "!",
        "as",
        "let",
        "exists",
        "forall",
        "match",
        "par",
        "assert",
        "check-sat",
        "declare-const",
        "declare-fun",
        "define-fun",
        "define-fun-rec",
        "define-sort",
        "set-logic",
        "set-option",
        "synth-fun",
        "constraint",
        "check-synth",
        "declare-var",
        "ite",
        "and",
        "or",
        "not",
        "xor",
        "distinct",
        "true",
        "false",
        "Int",
        "Bool",
    ]
)


KEYWORDS = frozenset(keyword.kwlist) | _C_KEYWORDS  # an input's name is pasted into exported code


def function_name_problem(name: str, lang: str, variables: Sequence[str] = ()) -> str | None:
    """Why ``name`` cannot name the exported controller in ``lang`` (python, c or
    sygus), or None: it must be an ASCII identifier (letters, digits, ``_``, not
    starting with a digit), not a keyword or reserved word of the language, and not one
    of the controller's inputs. Everything else would be pasted into the code as is.

    >>> function_name_problem("move", "c") is None
    True
    >>> function_name_problem("f(); system(0); int g", "c")
    "not an identifier: 'f(); system(0); int g'"
    >>> function_name_problem("lambda", "python")
    "'lambda' is a keyword in python"
    """

    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        return f"not an identifier: {name!r}"
    reserved = {"python": frozenset(keyword.kwlist), "c": _C_KEYWORDS, "sygus": _SYGUS_RESERVED}.get(lang)
    if reserved is None:
        return f"unknown language {lang!r}"
    if name in reserved:
        return f"{name!r} is a keyword in {lang}"
    if name in variables:
        return f"{name!r} is an input of the controller"
    return None


def _checked_name(name: str, lang: str, variables: Sequence[str]) -> None:
    why = function_name_problem(name, lang, variables)
    if why is not None:
        raise ValueError(f"function name: {why}")


def to_python(t: Term, variables: Sequence[str], name: str = "move") -> str:
    """Python source of the controller as a function of the spec's inputs.

    >>> from plansynth.grid.programs import parse_program
    >>> print(to_python(parse_program("(ite (<= rx 3) 2 1)"), ["rx", "ry"]))
    def move(rx: int, ry: int) -> int:
        \"\"\"Controller synthesized by plansynth: returns the robot's move number.\"\"\"
        return (2 if (rx <= 3) else 1)
    <BLANKLINE>
    """
    _checked_name(name, "python", variables)
    params = ", ".join(f"{v}: int" for v in variables)
    return (
        f"def {name}({params}) -> int:\n"
        f'    """Controller synthesized by plansynth: returns the robot\'s move number."""\n'
        f"    return {_expr(t, 'py')}\n"
    )


def to_c(t: Term, variables: Sequence[str], name: str = "move") -> str:
    """C source of the controller.

    >>> from plansynth.grid.programs import parse_program
    >>> print(to_c(parse_program("(ite (<= rx 3) 2 1)"), ["rx", "ry"]))
    /* Controller synthesized by plansynth: returns the robot's move number. */
    int move(int rx, int ry) {
        return ((rx <= 3) ? 2 : 1);
    }
    <BLANKLINE>
    """
    _checked_name(name, "c", variables)
    params = ", ".join(f"int {v}" for v in variables) or "void"
    return (
        "/* Controller synthesized by plansynth: returns the robot's move number. */\n"
        f"int {name}({params}) {{\n"
        f"    return {_expr(t, 'c')};\n"
        "}\n"
    )


def to_define_fun(t: Term, variables: Sequence[str], name: str = "move") -> str:
    """The controller as a SyGuS-IF v2 ``define-fun``."""
    _checked_name(name, "sygus", variables)
    params = " ".join(f"({v} Int)" for v in variables)
    return f"(define-fun {name} ({params}) Int {t})"


def compile_program(t: Term, variables: Sequence[str]) -> Callable[..., int]:
    """A fast Python callable taking the inputs positionally in ``variables`` order."""
    namespace: dict[str, object] = {}
    exec(to_python(t, variables, "_controller"), namespace)  # noqa: S102 - our own printer's output
    return namespace["_controller"]  # type: ignore[return-value]
