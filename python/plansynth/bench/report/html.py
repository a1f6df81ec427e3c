"""The report as one self-contained HTML page beside its Markdown (``REPORT.html``,
``RESULTS.html``): the same text and tables, rendered from the Markdown the report
writes, with a table of contents, tables sortable by a click on a column's header, and
every figure embedded where the Markdown shows it.

The page loads nothing: the style sheet and the script are inlined, each figure is a
``data:`` URI (PNG or SVG, read from the file the Markdown names), and its
Content-Security-Policy is that of ``plansynth view -o`` pages
(:func:`plansynth.view.page.content_security_policy`: no network at all). Links in the
text (a paper's address) stay links. Raw HTML in the Markdown is kept only for the few
elements the report writes (comments, ``<details>``, ``<summary>``); anything else is
shown as text.

>>> page = render_html("# R\\n\\n## Part\\n\\n| a | b |\\n|---|---|\\n| 1 | 2 |\\n", folder=Path("."))
>>> "<title>R</title>" in page, '<a href="#part">Part</a>' in page, "<th>a</th>" in page
(True, True, True)
"""

from __future__ import annotations

import base64
import re
from html import escape
from importlib import resources
from pathlib import Path
from typing import Any
from urllib.parse import unquote

from plansynth.io import write_output

__all__ = ["render_html", "write_html", "MEDIA_TYPES"]

#: The figure files a page may embed, by suffix.
MEDIA_TYPES = {".png": "image/png", ".svg": "image/svg+xml"}

_ALLOWED_TAG = re.compile(r"<!--.*?-->|</?(?:details|summary)>", re.S)
_SCHEME = re.compile(r"^(?:[a-z][a-z0-9+.-]*:|//)", re.I)


def _asset(name: str) -> str:
    return resources.files("plansynth.bench.report").joinpath("static", name).read_text(encoding="utf-8")


def _figure_uri(folder: Path, src: str) -> str:
    """``src`` (a path relative to the Markdown's folder) as a ``data:`` URI."""
    if _SCHEME.match(src):
        raise ValueError(f"figure {src!r}: the report embeds local figure files only")
    path = folder / unquote(src)
    media = MEDIA_TYPES.get(path.suffix.lower())
    if media is None:
        raise ValueError(f"figure {src!r}: not one of {', '.join(MEDIA_TYPES)}")
    if not path.is_file():
        raise FileNotFoundError(f"figure {src!r}: the report names it, but {path} is not a file")
    return f"data:{media};base64,{base64.b64encode(path.read_bytes()).decode('ascii')}"


def _slug(text: str, taken: set[str]) -> str:
    """A heading's anchor, as GitHub makes it (lower case, words joined by ``-``), unique."""
    base = re.sub(r"[^\w\- ]", "", text.lower()).strip().replace(" ", "-") or "section"
    slug, n = base, 1
    while slug in taken:
        slug, n = f"{base}-{n}", n + 1
    taken.add(slug)
    return slug


def _plain(inline: Any) -> str:
    return "".join(c.content for c in (inline.children or []) if c.type in ("text", "code_inline"))


def _raw_html(renderer: Any, tokens: Any, idx: int, options: Any, env: Any) -> str:
    """Raw HTML kept when every tag in it is one the report writes; else shown as text."""
    content = tokens[idx].content
    return content if "<" not in _ALLOWED_TAG.sub("", content) else escape(content)


def _prepare(tokens: list[Any], folder: Path) -> tuple[str, list[tuple[int, str, str]]]:
    """Give every heading an ``id`` and every image its ``data:`` URI; returns the first
    level-1 heading's text and the headings (level, anchor, text) for the contents."""
    title, heads, taken = "", [], set()
    for i, tok in enumerate(tokens):
        if tok.type == "heading_open":
            text = _plain(tokens[i + 1])
            anchor = _slug(text, taken)
            tok.attrSet("id", anchor)
            heads.append((int(tok.tag[1]), anchor, text))
            title = title or (text if tok.tag == "h1" else "")
        for child in tok.children or []:
            if child.type == "image":
                child.attrSet("src", _figure_uri(folder, str(child.attrGet("src"))))
    return title, heads


def _contents(heads: list[tuple[int, str, str]]) -> str:
    """Nested lists of the level-2 and level-3 headings, linked to them."""
    out, level = [], 1
    for depth, anchor, text in heads:
        if depth not in (2, 3):
            continue
        if depth > level:  # a level skipped gets an item of its own, so that every list closes
            out.append("<ul>" + "<li><ul>" * (depth - level - 1))
        elif depth < level:
            out.append("</li></ul>" * (level - depth) + "</li>")
        elif out:
            out.append("</li>")
        out.append(f'<li><a href="#{escape(anchor)}">{escape(text)}</a>')
        level = depth
    if level > 1:
        out.append("</li></ul>" * (level - 1))
    return "".join(out)


def render_html(markdown: str, *, folder: Path, title: str | None = None) -> str:
    """The page for ``markdown``, its figures read relative to ``folder``; the title is
    ``title`` or the Markdown's first level-1 heading."""
    from markdown_it import MarkdownIt

    from plansynth.view.page import content_security_policy

    md = MarkdownIt("commonmark", {"html": True}).enable("table")
    md.add_render_rule("html_block", _raw_html)
    md.add_render_rule("html_inline", _raw_html)
    md.add_render_rule("table_open", lambda *a: '<div class="table"><table>\n')
    md.add_render_rule("table_close", lambda *a: "</table></div>\n")
    tokens = md.parse(markdown)
    first, heads = _prepare(tokens, folder)
    body = md.renderer.render(tokens, md.options, {})
    script = _asset("sort_tables.js")
    if "</script" in script.lower():  # our own file; a guard so that an edit cannot break the page
        raise ValueError("the report's script must not contain </script")
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="{content_security_policy()}">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="plansynth bench report">
<title>{escape(title or first or "plansynth benchmark report")}</title>
<style>
{_asset("report.css")}
</style>
</head>
<body>
<nav id="toc" aria-label="Contents"><h2>Contents</h2>
{_contents(heads)}
</nav>
<main>
{body}</main>
<script>
{script}
</script>
</body>
</html>
"""


def write_html(markdown_path: str | Path, *, title: str | None = None) -> Path:
    """Write the page of the Markdown file ``markdown_path`` beside it (same name,
    ``.html``), its figures read relative to that file; returns the page's path."""
    src = Path(markdown_path)
    page = render_html(src.read_text(encoding="utf-8"), folder=src.parent, title=title)
    path = src.with_suffix(".html")
    write_output(path, page)
    return path
