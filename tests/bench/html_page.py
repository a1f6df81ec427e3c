"""What a report page holds, read back with the standard library's HTML parser (not the
renderer that wrote it), and the tables and figures its Markdown names: the oracle the
HTML report's tests compare against."""

from __future__ import annotations

import re
from html.parser import HTMLParser

_SEPARATOR = re.compile(r"^\|(\s*:?-+:?\s*\|)+\s*$")
_VOID = {"area", "br", "col", "hr", "img", "input", "link", "meta", "source", "wbr"}
_IMAGE = re.compile(r"!\[([^\]]*)\]\(([^)\s]+)\)")


class Page(HTMLParser):
    """Every start tag with its attributes, the header rows of the tables, the images,
    the headings' anchors and the contents' links, and the text of ``<script>``s."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str]]] = []
        self.headers: list[list[str]] = []
        self.images: list[dict[str, str]] = []
        self.anchors: list[str] = []
        self.contents: list[str] = []
        self.scripts: list[str] = []
        self._th: list[str] | None = None
        self._in: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {k: v or "" for k, v in attrs}
        self.tags.append((tag, a))
        if tag not in _VOID:
            self._in.append(tag)
        if tag == "tr" and "thead" in self._in:
            self.headers.append([])
        elif tag == "th" and "main" in self._in:
            self._th = []
        elif tag == "img":
            self.images.append(a)
        elif tag in ("h1", "h2", "h3", "h4") and "main" in self._in:
            self.anchors.append(a.get("id", ""))
        elif tag == "a" and "nav" in self._in:
            self.contents.append(a.get("href", ""))

    def handle_startendtag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.handle_starttag(tag, attrs)  # <img ... />: nothing to close

    def handle_endtag(self, tag: str) -> None:
        if tag not in self._in:
            return
        if tag == "th" and self._th is not None:
            self.headers[-1].append("".join(self._th).strip())
            self._th = None
        while self._in and self._in.pop() != tag:
            pass

    def handle_data(self, data: str) -> None:
        if self._th is not None:
            self._th.append(data)
        if self._in and self._in[-1] == "script":
            self.scripts.append(data)


def read_page(text: str) -> Page:
    page = Page()
    page.feed(text)
    page.close()
    return page


def markdown_headers(markdown: str) -> list[list[str]]:
    """The header row of every table of ``markdown``, as the reader sees it (no backticks
    or emphasis marks)."""
    lines = markdown.splitlines()
    rows = []
    for line, below in zip(lines, lines[1:]):
        if line.startswith("|") and _SEPARATOR.match(below):
            assert "\\|" not in line, line  # a header with an escaped bar: split it by hand
            cells = line.strip().strip("|").split("|")
            rows.append([re.sub(r"[`*]", "", c).strip() for c in cells])
    return rows


def markdown_images(markdown: str) -> list[tuple[str, str]]:
    """(alt, src) of every image of ``markdown``, in order."""
    return _IMAGE.findall(markdown)
