"""The native engine's options as one frozen value (STYLE.md, points 1 and 5).

Built once (by the CLI from ``--minimize``, ``--effort`` and ``-O KEY=VALUE``, by bench
from ``-O native:KEY=VALUE``, or directly) and validated at the door
(:mod:`plansynth.options`): an unknown key, a value of the wrong type or out of range is
:class:`~plansynth.errors.InvalidOption` (the CLI's exit 2). The engine never writes to
it; what a run did (counters, phase times) is in its result.

>>> NativeOptions.parse(["minimize=true", "effort=0.5"]).minimize
True
>>> NativeOptions.parse(["effort=-1"])
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: native: option 'effort': -1 is below its minimum 0
>>> NativeOptions.parse(["minimise=true"])
Traceback (most recent call last):
...
plansynth.errors.InvalidOption: native: option 'minimise': not an option of this solver; its options: minimize, effort, condition_depth, max_tree_depth, max_configs, simplify, improve, quick, use_rust, conflicts, improve_states, exact_states, tree_conditions, max_clauses
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import asdict, dataclass
from typing import Any

from plansynth.errors import InvalidOption
from plansynth.options import changed, check_fields, configure, describe, option, parse_assignments

#: Conditions are enumerated up to this depth by default (programs may be deeper).
CONDITION_DEPTH = 4
#: Largest program depth the tree SAT tries before the greedy tree takes over.
MAX_TREE_DEPTH = 9


@dataclass(frozen=True)
class NativeOptions:
    """Every option of the native engine, each with what it does (``--help``, the docs)."""

    minimize: bool = option(
        False,
        "search program depths 1, 4, 5, ... over every winning strategy and return "
        "the smallest, proved minimal when the condition enumeration is complete "
        "(--minimize)",
    )
    effort: float | None = option(
        None,
        "seconds spent making the first verified program smaller with tree SAT "
        "(--effort; default 0.05 s or 10% of the budget, whichever is smaller; 0 "
        "returns the first program)",
        minimum=0,
    )
    condition_depth: int = option(CONDITION_DEPTH, "deepest condition enumerated for the exact depth search", minimum=1)
    max_tree_depth: int = option(MAX_TREE_DEPTH, "deepest decision tree tried by tree SAT", minimum=1)
    max_configs: int | None = option(
        None,
        "an explicit cap on joint obstacle configurations (default none: the "
        "game is bounded by the budget's time and --memory-mb, else 4096 MB)",
        minimum=1,
    )
    simplify: bool = option(True, "simplify programs against the game-graph check")
    improve: bool = option(True, "spend the effort at all (false is effort=0)")
    quick: bool = option(True, "read a stationary strategy off the game before trying SAT")
    use_rust: bool | None = option(
        None, "true/none: the compiled core (built with the package); false: the pure-Python references"
    )
    conflicts: int = option(5_000, "CaDiCaL conflicts allowed per tree-SAT attempt while improving", minimum=1)
    improve_states: int = option(1000, "tree SAT improves programs over at most this many states", minimum=1)
    exact_states: int = option(
        150, "the exact depth search over the whole game when it has at most this many states", minimum=1
    )
    tree_conditions: int = option(400, "conditions offered to tree SAT while improving", minimum=1)
    max_clauses: int = option(3_000_000, "largest tree-SAT encoding built", minimum=1)

    def __post_init__(self) -> None:
        check_fields(self, "native")
        if self.effort is not None and not math.isfinite(self.effort):
            raise InvalidOption("native", "effort", f"must be finite, got {self.effort}")

    @classmethod
    def parse(cls, items: Iterable[str] = (), **values: Any) -> NativeOptions:
        """Options from ``KEY=VALUE`` strings (``-O``; dashes in keys are underscores)
        and keyword values; an unknown key is an error, never dropped."""
        return configure("native", cls(), {**parse_assignments(items, "native"), **values})

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def changed(self) -> dict[str, Any]:
        """The options that differ from the defaults (what a result records)."""
        return changed(self, NativeOptions())


#: One line per option: what it does (``--help`` and the docs show these).
OPTION_DOCS: dict[str, str] = {name: doc for name, _, doc in describe(NativeOptions)}


def help_text() -> str:
    """One line per option, for ``--help`` and the docs."""
    return "; ".join(f"{k}: {v}" for k, v in OPTION_DOCS.items())


__all__ = ["NativeOptions", "InvalidOption", "OPTION_DOCS", "help_text"]
