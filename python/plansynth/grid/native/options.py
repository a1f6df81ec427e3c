"""The native engine's options as one frozen value (STYLE.md, points 1 and 5).

Built once (by the CLI from ``--minimize``, ``--effort`` and ``-O KEY=VALUE``, by bench
from ``-O native:KEY=VALUE``, or directly) and validated at the door: an unknown key,
a value of the wrong type or out of range is :class:`InvalidOption` (the CLI's exit 2).
The engine never writes to it; what a run did (counters, phase times) is in its result.

>>> NativeOptions.parse(["minimize=true", "effort=0.5"]).minimize
True
>>> NativeOptions.parse(["effort=-1"])
Traceback (most recent call last):
...
plansynth.grid.native.options.InvalidOption: native option effort=-1: must be >= 0
>>> NativeOptions.parse(["minimise=true"])
Traceback (most recent call last):
...
plansynth.grid.native.options.InvalidOption: unknown native solver option 'minimise'; the options are: minimize, effort, condition_depth, max_tree_depth, max_configs, simplify, improve, quick, use_rust, conflicts, improve_states, exact_states, tree_conditions, max_clauses
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import asdict, dataclass, fields
from typing import Any

from plansynth.errors import PlansynthError

#: Conditions are enumerated up to this depth by default (programs may be deeper).
CONDITION_DEPTH = 4
#: Largest program depth the tree SAT tries before the greedy tree takes over.
MAX_TREE_DEPTH = 9


class InvalidOption(PlansynthError, TypeError):
    """A native option that does not exist, is not KEY=VALUE, or has a bad value."""


#: One line per option: what it does (the README and ``--help`` show these).
OPTION_DOCS: dict[str, str] = {
    "minimize": "search program depths 1, 4, 5, ... over every winning strategy and return the smallest, "
                "proved minimal when the condition enumeration is complete (--minimize)",
    "effort": "seconds spent making the first verified program smaller with tree SAT (--effort; default "
              "0.05 s or 10% of the budget, whichever is smaller; 0 returns the first program)",
    "condition_depth": "deepest condition enumerated for the exact depth search (default 4)",
    "max_tree_depth": "deepest decision tree tried by tree SAT (default 9)",
    "max_configs": "an explicit cap on joint obstacle configurations (default none: the game is bounded by "
                   "the budget's time and --memory-mb, else 4096 MB)",
    "simplify": "simplify programs against the game-graph check (default true)",
    "improve": "spend the effort at all (default true; false is effort=0)",
    "quick": "read a stationary strategy off the game before trying SAT (default true)",
    "use_rust": "true/none: the compiled core (built with the package); false: the pure-Python references",
    "conflicts": "CaDiCaL conflicts allowed per tree-SAT attempt while improving (default 5000)",
    "improve_states": "tree SAT improves programs over at most this many states (default 1000)",
    "exact_states": "the exact depth search over the whole game when it has at most this many states (default 150)",
    "tree_conditions": "conditions offered to tree SAT while improving (default 400)",
    "max_clauses": "largest tree-SAT encoding built (default 3,000,000 clauses)",
}


@dataclass(frozen=True)
class NativeOptions:
    """Every option of the native engine (see :data:`OPTION_DOCS` for each one)."""

    minimize: bool = False
    effort: float | None = None
    condition_depth: int = CONDITION_DEPTH
    max_tree_depth: int = MAX_TREE_DEPTH
    max_configs: int | None = None
    simplify: bool = True
    improve: bool = True
    quick: bool = True
    use_rust: bool | None = None
    conflicts: int = 5_000
    improve_states: int = 1000
    exact_states: int = 150
    tree_conditions: int = 400
    max_clauses: int = 3_000_000

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            kind = f.type if isinstance(f.type, str) else str(f.type)
            optional = "None" in kind
            if value is None:
                if not optional:
                    raise InvalidOption(f"native option {f.name}: a value is needed")
                continue
            if kind.startswith("bool"):
                ok = isinstance(value, bool)
            elif kind.startswith("int"):
                ok = isinstance(value, int) and not isinstance(value, bool)
            else:  # float
                ok = isinstance(value, (int, float)) and not isinstance(value, bool)
            if not ok:
                raise InvalidOption(f"native option {f.name}={value!r}: expected {kind.replace(' | None', '')}")
            if f.name == "effort" and not 0 <= value < float("inf"):
                raise InvalidOption(f"native option effort={value}: must be >= 0")
            if kind.startswith("int") and value < 1:
                raise InvalidOption(f"native option {f.name}={value}: must be >= 1")

    @classmethod
    def parse(cls, items: Iterable[str] = (), **values: Any) -> "NativeOptions":
        """Options from ``KEY=VALUE`` strings (``-O``; dashes in keys are underscores)
        and keyword values; an unknown key is an error, never dropped."""
        out: dict[str, Any] = {}
        for item in items:
            key, sep, value = item.partition("=")
            if not sep:
                raise InvalidOption(f"native solver option {item!r} is not KEY=VALUE")
            out[key.strip().replace("-", "_")] = _parse(value.strip())
        out.update(values)
        known = [f.name for f in fields(cls)]
        for key in out:
            if key not in known:
                raise InvalidOption(f"unknown native solver option {key!r}; the options are: {', '.join(known)}")
        return cls(**out)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def changed(self) -> dict[str, Any]:
        """The options that differ from the defaults (what a result records)."""
        default = NativeOptions()
        return {k: v for k, v in asdict(self).items() if getattr(default, k) != v}


def _parse(value: str) -> Any:
    low = value.lower()
    if low in ("true", "yes", "on"):
        return True
    if low in ("false", "no", "off"):
        return False
    if low in ("none", "null"):
        return None
    for cast in (int, float):
        try:
            return cast(value)
        except ValueError:
            pass
    return value


def help_text() -> str:
    """One line per option, for ``--help`` and the README."""
    return "; ".join(f"{k}: {v}" for k, v in OPTION_DOCS.items())


__all__ = ["NativeOptions", "InvalidOption", "OPTION_DOCS", "help_text"]
