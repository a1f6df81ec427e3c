"""Linear temporal logic over label names, the mission language of reach-avoid
problems (Shoukry et al., CDC 2016, Sections I and IV): the formulas and their parser
(:mod:`~plansynth.reach.ltl.syntax`), and their truth on the words plans give
(:mod:`~plansynth.reach.ltl.semantics`).

It sits below the problem value, which checks a mission's syntax and names at the door,
and below the mission planners and checker (:mod:`plansynth.reach.mission`), which
reach it under its earlier address :mod:`plansynth.reach.mission.ltl` as well.
"""

from plansynth.reach.ltl.semantics import Lasso, finite_word, holds, holds_at, holds_unrolled
from plansynth.reach.ltl.syntax import (
    KEYWORDS,
    And,
    Const,
    Finally,
    Formula,
    Globally,
    Iff,
    Implies,
    LtlSyntaxError,
    Next,
    Not,
    Or,
    Prop,
    Release,
    Until,
    children,
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
