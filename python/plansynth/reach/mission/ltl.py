"""Linear temporal logic over label names for missions: syntax, negation normal form,
semantics. Defined in :mod:`plansynth.reach.ltl` (below the problem value, which checks
a mission at the door); this is the mission planners' and checker's address for it.

>>> str(nnf(parse("!(a U (b -> X c))")))
'(!a R (b & X !c))'
>>> holds(parse("F G a"), finite_word([{"a"}, set(), {"a"}]))
True
"""

from plansynth.reach.ltl import (
    KEYWORDS,
    And,
    Const,
    Finally,
    Formula,
    Globally,
    Iff,
    Implies,
    Lasso,
    LtlSyntaxError,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
    children,
    finite_word,
    holds,
    holds_at,
    holds_unrolled,
    nnf,
    parse,
    props,
    subformulas,
)

__all__ = [
    "Formula",
    "Const",
    "Prop",
    "Not",
    "And",
    "Or",
    "Implies",
    "Iff",
    "Next",
    "Finally",
    "Globally",
    "Until",
    "Release",
    "LtlSyntaxError",
    "parse",
    "nnf",
    "props",
    "subformulas",
    "children",
    "Lasso",
    "finite_word",
    "holds",
    "holds_at",
    "holds_unrolled",
    "KEYWORDS",
]
