"""Every relative link of the README, the contributors' guide and the documentation
pages names a file of the repository, as GitHub resolves it.

``mkdocs build --strict`` checks the links that stay inside the site (anchors included);
this checks the rest: the README's and CONTRIBUTING.md's links, and the pages' links that
leave docs/ (pictures in ``examples/``, ``benchmarks/RESULTS.md``), which the site turns
into copies or plain text (docs/_tools/mkdocs_hooks.py).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCUMENTS = [
    "README.md",
    "CONTRIBUTING.md",
    *sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md")),
]
LINK = re.compile(r"!?\[[^\]\n]*\]\(([^)\s]+)\)")


def _links(text: str) -> list[str]:
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)  # code blocks hold no links
    return [t for t in LINK.findall(text) if not re.match(r"^[a-z]+:|^#", t)]


@pytest.mark.parametrize("document", DOCUMENTS)
def test_every_relative_link_names_a_file(document: str) -> None:
    page = ROOT / document
    broken = [
        target
        for target in _links(page.read_text(encoding="utf-8"))
        if not (page.parent / target.split("#", 1)[0]).resolve().exists()
    ]
    assert not broken, f"{document}: links to nothing: {broken}"


def test_the_readme_is_a_map() -> None:
    """The README says what plansynth is, the two commands, a short tour and where to go
    next; everything else lives in docs/."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 200
    assert "bash scripts/setup.sh && .venv/bin/plansynth grid solve examples/grid/figure1.yaml --solver cvc5" in text
    assert "bash scripts/test.sh" in text
    linked = {t.split("#", 1)[0] for t in _links(text)}
    pages = {p.relative_to(ROOT).as_posix() for p in (ROOT / "docs").rglob("*.md")}
    assert pages <= linked | {"docs/index.md"}, f"pages the README does not link: {sorted(pages - linked)}"
