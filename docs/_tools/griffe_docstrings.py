"""A griffe extension that lets mkdocstrings render plansynth's docstrings.

plansynth's docstrings are written for ``help()`` and doctest, in the reStructuredText
habits of the scientific Python world, not in Markdown. Three things would read badly
on the site, and this extension rewrites them when griffe loads each docstring (the
source is left alone):

* cross-reference roles, ``:class:`~plansynth.budget.Budget```, become links to the
  object's API entry (an *optional* autorefs link: plain code when the object has no
  entry on the site, never a broken link);
* doctest examples (``>>>`` lines and their output) become ``pycon`` code blocks
  instead of Markdown block quotes;
* a paragraph ending in ``::`` (a reST literal block follows) ends in ``:``.

Loaded by mkdocs.yml (``plugins: mkdocstrings: handlers: python: options: extensions``).
"""

from __future__ import annotations

import html
import re
from typing import Any

import griffe

ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|exc|obj|const):`(~?)([\w.]+)(?:\(\))?`")


def _identifier(target: str, obj: griffe.Object) -> str:
    """The dotted path a role names: written in full, or relative to the object's module."""
    if target.startswith("plansynth.") or target.split(".")[0] in {"numpy", "typer", "pathlib", "enum"}:
        return target
    module = obj.module.path if obj.module is not None else obj.path
    return f"{module}.{target}"


def rewrite_roles(text: str, obj: griffe.Object) -> str:
    def link(match: re.Match[str]) -> str:
        short, target = match.group(1) == "~", match.group(2)
        shown = target.rsplit(".", 1)[-1] if short else target
        ident = html.escape(_identifier(target, obj), quote=True)
        return f'<autoref identifier="{ident}" optional><code>{html.escape(shown)}</code></autoref>'

    return ROLE.sub(link, text)


def fence_doctests(text: str) -> str:
    """Wrap each run of doctest lines (``>>>``, ``...`` and the output up to a blank
    line) in a ``pycon`` fence, keeping its indentation."""
    out: list[str] = []
    lines = text.split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        stripped = line.lstrip()
        if stripped.startswith(">>>"):
            indent = line[: len(line) - len(stripped)]
            out.append(f"{indent}```pycon")
            while i < len(lines) and lines[i].strip():
                out.append(lines[i])
                i += 1
            out.append(f"{indent}```")
            continue
        out.append(line)
        i += 1
    return "\n".join(out)


def literal_colons(text: str) -> str:
    return re.sub(r"(?<=\S)::$", ":", text, flags=re.M)


class ReSTDocstrings(griffe.Extension):
    """Rewrite roles, doctests and ``::`` in every docstring griffe loads."""

    def on_object(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.is_alias or obj.docstring is None:
            return
        value = obj.docstring.value
        value = fence_doctests(value)
        value = literal_colons(value)
        obj.docstring.value = rewrite_roles(value, obj)
