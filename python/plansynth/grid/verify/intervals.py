"""The program's choice on a box of inputs: Kleene three-valued truth of its conditions
over integer intervals (reduction 3 of :mod:`plansynth.grid.verify`). Where a
comparison is undecided on the box, the box is split on it (:mod:`.products`).

>>> from plansynth.grid.programs import parse_program
>>> p = parse_program("(ite (<= o0y 3) 1 2)")
>>> choose(p, {"o0y": (0, 2)}, {}), choose(p, {"o0y": (4, 9)}, {})
(1, 2)
>>> print(choose(p, {"o0y": (2, 5)}, {}))
(<= o0y 3)
"""

from __future__ import annotations

from plansynth.grid.programs import App, Const, Term, Var

__all__ = ["Env", "UNDECIDED", "choose", "truth", "undecided_atom", "interval"]

#: Each input's (lowest, highest) value.
Env = dict[str, tuple[int, int]]
#: The truth value of a condition that holds on part of the box only.
UNDECIDED = None


def choose(program: Term, env: Env, known: dict[int, bool]) -> int | App:
    """The program's move if it is the same for every input in the intervals ``env``,
    else an undecided comparison to split on. ``known`` fixes atoms decided by splits."""
    t = program
    while isinstance(t, App):  # (ite B S S)
        cond = t.args[0]
        v = truth(cond, env, known)
        if v is UNDECIDED:
            return undecided_atom(cond, env, known)
        t = t.args[1] if v else t.args[2]
    assert isinstance(t, Const)
    return t.value


def truth(b: Term, env: Env, known: dict[int, bool]) -> bool | None:
    """Kleene three-valued truth of a condition over intervals."""
    assert isinstance(b, App)
    op = b.op
    if op == "not":
        v = truth(b.args[0], env, known)
        return None if v is None else not v
    if op == "and":
        a = truth(b.args[0], env, known)
        if a is False:
            return False
        c = truth(b.args[1], env, known)
        if c is False:
            return False
        return True if (a and c) else None
    if op == "or":
        a = truth(b.args[0], env, known)
        if a is True:
            return True
        c = truth(b.args[1], env, known)
        if c is True:
            return True
        return False if (a is False and c is False) else None
    if id(b) in known:
        return known[id(b)]
    lo1, hi1 = interval(b.args[0], env)
    lo2, hi2 = interval(b.args[1], env)
    if op == "<=":
        if hi1 <= lo2:
            return True
        if lo1 > hi2:
            return False
        return None
    # "="
    if lo1 == hi1 == lo2 == hi2:
        return True
    if hi1 < lo2 or hi2 < lo1:
        return False
    return None


def undecided_atom(b: Term, env: Env, known: dict[int, bool]) -> App:
    """A comparison inside the undecided condition ``b`` that is itself undecided."""
    assert isinstance(b, App)
    if b.op in ("not", "and", "or"):
        for a in b.args:
            if truth(a, env, known) is UNDECIDED:
                return undecided_atom(a, env, known)
        raise AssertionError("an undecided condition has an undecided part")  # pragma: no cover
    return b


def interval(t: Term, env: Env) -> tuple[int, int]:
    """The (lowest, highest) value of an arithmetic term over the intervals ``env``."""
    if isinstance(t, Const):
        return t.value, t.value
    if isinstance(t, Var):
        return env[t.name]
    a0, a1 = interval(t.args[0], env)
    b0, b1 = interval(t.args[1], env)
    if t.op == "+":
        return a0 + b0, a1 + b1
    return a0 - b1, a1 - b0  # "-"
