"""Strict YAML loading within the document limits: a key written twice or a key that
is not a plain value is an error, exponent numbers without a dot are floats, and
nesting and the size a document expands to through aliases are bounded before
anything expands (a "billion laughs" document is refused in microseconds). With
libyaml's C parser when PyYAML has it, else the pure-Python one; both apply the same
limits and construct the same values.
"""

from __future__ import annotations

import re
from typing import Any

import yaml

from plansynth.io.fields import key_text

__all__ = ["load_yaml", "StrictLoader", "DuplicateKey", "Refused", "MAX_NESTING", "MAX_NODES", "LIBYAML"]

#: Deepest nesting of lists and mappings in a document (the formats need at most 5).
MAX_NESTING = 64
#: Most values (scalars, lists, mappings) one document may hold, each use of a YAML
#: alias ``*a`` counting as a full copy of what it names.
MAX_NODES = 1_000_000


class DuplicateKey(Exception):
    def __init__(self, key: str, where: str = "") -> None:
        self.key, self.where = key, where


class Refused(Exception):
    """A document beyond the limits (nesting, size through aliases, complex keys)."""


def _where(node: yaml.Node) -> str:
    return f"line {node.start_mark.line + 1}, column {node.start_mark.column + 1}"


def load_yaml(text: str) -> Any:
    """One YAML document within the module's limits: with libyaml (PyYAML's C parser, about
    8x faster: a 3 kB problem file in 7 ms instead of 55 ms, most of a small ``grid
    solve``'s parse) when PyYAML was built with it, else with the pure-Python loader.
    Both apply the same limits and construct the same values (tests/test_io.py)."""
    if not LIBYAML:
        return yaml.load(text, Loader=StrictLoader)  # noqa: S506 - a SafeLoader subclass
    # libyaml composes nodes recursively in C: the nesting is refused from its event
    # stream first, before anything deep is composed
    try:
        _check_event_nesting(yaml.cyaml.CParser(text))
        loader = _StrictCLoader(text)
        try:
            node = loader.get_single_node()
            check_expanded_size(node)
            return None if node is None else loader.construct_document(node)
        finally:
            loader.dispose()
    except yaml.MarkedYAMLError:
        # not YAML: PyYAML's own parser words the error better (it names an undefined
        # alias, and what it expected); the cost of a second parse is only paid here
        return yaml.load(text, Loader=StrictLoader)  # noqa: S506 - a SafeLoader subclass


def _check_event_nesting(parser: Any) -> None:
    """Refuse more than MAX_NESTING levels, counted as :class:`StrictLoader` counts them
    (every value, scalars and keys included, one level below its container)."""
    depth = 0
    try:
        while parser.check_event():
            event = parser.get_event()
            if isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
                depth += 1
                level = depth
            elif isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
                depth -= 1
                continue
            elif isinstance(event, yaml.ScalarEvent):
                level = depth + 1
            else:
                continue
            if level > MAX_NESTING:
                raise Refused(f"nested deeper than {MAX_NESTING} levels (line {event.start_mark.line + 1})")
    finally:
        parser.dispose()


_BOOL_TAG, _STR_TAG = "tag:yaml.org,2002:bool", "tag:yaml.org,2002:str"


class _NoDuplicateKeys:
    """Mapping construction that refuses a key written twice, or a key that is not a
    plain value (mixed in before PyYAML's SafeConstructor); a key YAML 1.1 would read as
    a boolean from ``yes``/``no``/``on``/``off`` is kept as the word (a label named
    ``on``), while ``true``/``false`` keys stay booleans."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
        seen: set[Any] = set()
        for key_node, _ in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                kind = "list" if isinstance(key_node, yaml.SequenceNode) else "mapping"
                raise Refused(f"a mapping key must be a plain value, not a {kind} ({_where(key_node)})")
            if key_node.tag == _BOOL_TAG and key_node.value.lower() not in ("true", "false"):
                key_node.tag = _STR_TAG  # a key "on", "off", "yes", "no" is a name, as written
            key = self.construct_object(key_node, deep=deep)  # type: ignore[attr-defined]
            if key in seen:
                raise DuplicateKey(key_text(key), f" (line {key_node.start_mark.line + 1})")
            seen.add(key)
        return super().construct_mapping(node, deep=deep)  # type: ignore[misc]


class StrictLoader(_NoDuplicateKeys, yaml.SafeLoader):
    """PyYAML's safe loader with the module's limits, plus two fixes:

    - a key written twice in one mapping is an error (plain PyYAML silently keeps the
      last one, hiding a typo in a problem file), and so is a key that is not a scalar
      (``? [1, 2] : 3``); a key ``on``, ``off``, ``yes`` or ``no`` is the word, not a
      boolean;
    - numbers with an exponent and no dot (``5e-1``, ``1e3``, ``1.0e5``) are floats, as a
      user means them (YAML 1.1 reads them as strings).
    """

    def __init__(self, stream: Any) -> None:
        super().__init__(stream)
        self._nesting = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            return super().compose_node(parent, index)
        self._nesting += 1
        try:
            if self._nesting > MAX_NESTING:
                mark = self.peek_event().start_mark
                raise Refused(f"nested deeper than {MAX_NESTING} levels (line {mark.line + 1})")
            return super().compose_node(parent, index)
        finally:
            self._nesting -= 1

    def compose_document(self) -> Any:
        node = super().compose_document()
        check_expanded_size(node)
        return node


LIBYAML = bool(getattr(yaml, "__with_libyaml__", False))
if LIBYAML:

    class _StrictCLoader(_NoDuplicateKeys, yaml.CSafeLoader):
        """:class:`StrictLoader` on libyaml's parser and composer (the limits are
        checked around it by :func:`load_yaml`)."""


_EXPONENT_FLOAT = re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$")
for _loader in (StrictLoader, _StrictCLoader) if LIBYAML else (StrictLoader,):
    _loader.add_implicit_resolver("tag:yaml.org,2002:float", _EXPONENT_FLOAT, list("-+0123456789."))


def check_expanded_size(root: Any) -> None:
    """Refuse a node graph that expands to more than MAX_NODES values, or a cycle.

    Aliases make the composed document a graph with shared nodes; what the rest of the
    program sees (and prints) is its expansion as a tree. Counted iteratively with one
    visit per distinct node, so even a billion-laughs graph costs microseconds.
    """
    if root is None:
        return
    size: dict[int, int] = {}
    active: set[int] = set()
    stack: list[tuple[Any, bool]] = [(root, False)]
    while stack:
        node, done = stack.pop()
        key = id(node)
        if done:
            active.discard(key)
            if isinstance(node, yaml.MappingNode):
                total = 1 + sum(size[id(k)] + size[id(v)] for k, v in node.value)
            elif isinstance(node, yaml.SequenceNode):
                total = 1 + sum(size[id(c)] for c in node.value)
            else:
                total = 1
            if total > MAX_NODES:
                raise Refused(
                    f"expands to more than {MAX_NODES} values, each alias *name counting as a copy "
                    f"of what it names ({_where(node)})"
                )
            size[key] = total
            continue
        if key in size:
            continue
        if key in active:
            raise Refused(f"an alias refers to a value that contains it ({_where(node)})")
        active.add(key)
        stack.append((node, True))
        if isinstance(node, yaml.MappingNode):
            children = [c for pair in node.value for c in pair]
        elif isinstance(node, yaml.SequenceNode):
            children = list(node.value)
        else:
            children = []
        for c in children:
            if id(c) in active:
                raise Refused(f"an alias refers to a value that contains it ({_where(c)})")
            if id(c) not in size:
                stack.append((c, False))
