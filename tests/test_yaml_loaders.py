"""The two YAML loaders of :mod:`plansynth.io.strict_yaml` agree: libyaml's (the fast path, used
when PyYAML has it) and the pure-Python one (the reference, and the fallback): the same
values for every document, the same refusals (nesting, aliases expanding past the
limit, duplicated or non-scalar keys, unsafe tags) for hostile ones."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from plansynth.io import strict_yaml

ROOT = Path(__file__).resolve().parents[1]


def test_the_locked_pyyaml_has_libyaml() -> None:
    """The lock's PyYAML wheel is built with libyaml, so the fast path is what the tests
    below compare with the reference (without it both sides would be the same loader)."""
    assert strict_yaml.LIBYAML


def _both(text: str) -> tuple[object, object]:
    """What each loader makes of ``text``: its value, or its error's type and text."""
    out = []
    for load in (strict_yaml.load_yaml, lambda t: yaml.load(t, Loader=strict_yaml.StrictLoader)):  # noqa: S506
        try:
            out.append(("value", load(text)))
        except Exception as exc:  # noqa: BLE001 - the comparison is the point
            out.append((type(exc).__name__, str(exc)))
    return out[0], out[1]


scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**6), 10**6),
    st.floats(allow_nan=False, allow_infinity=False, width=32),
    st.text(max_size=8),
)
documents = st.recursive(
    scalars,
    lambda kids: st.one_of(st.lists(kids, max_size=4), st.dictionaries(st.text(max_size=5), kids, max_size=4)),
    max_leaves=30,
)


@settings(max_examples=150, deadline=None)
@given(documents, st.booleans())
def test_same_values_for_every_document(doc: object, flow: bool) -> None:
    text = yaml.safe_dump(doc, default_flow_style=flow)
    fast, reference = _both(text)
    assert fast == reference and fast[0] == "value"


@pytest.mark.parametrize(
    "text",
    [
        "a: 1\na: 2\n",  # duplicated key
        "? [1, 2]\n: 3\n",  # a key that is not a plain value
        "[" * 65 + "]" * 65,  # too deep
        "[" * 64 + "1" + "]" * 64,  # a scalar one level too deep
        "[" * 63 + "1" + "]" * 63,  # deep, but within the limit
        "a: &a [*a]\n",  # an alias inside what it names
        "a: &x [1]\nb: *y\n",  # an undefined alias (PyYAML's wording)
        "a: [\n",  # not YAML
        "x: !!python/object:os.system [ls]\n",
        "a: 5e-1\nb: 1e3\nc: 0x10\nd: yes\n",  # exponent floats, YAML 1.1 ints and booleans
        "",
    ],
)
def test_same_outcome_for_hostile_and_corner_documents(text: str) -> None:
    fast, reference = _both(text)
    assert fast == reference


def test_a_billion_laughs_is_refused_by_both() -> None:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 9)]
    fast, reference = _both("\n".join(lines) + "\n")
    assert fast == reference and fast[0] == "Refused" and "expands to more than" in fast[1]


@pytest.mark.parametrize("path", sorted((ROOT / "examples").rglob("*.yaml")), ids=lambda p: p.name)
def test_same_values_for_every_example(path: Path) -> None:
    fast, reference = _both(path.read_text(encoding="utf-8"))
    assert fast == reference and fast[0] == "value"
