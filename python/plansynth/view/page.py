"""One self-contained HTML page: the data as JSON and every script and style inlined.

A page written with ``plansynth view -o`` loads nothing: its Content-Security-Policy
allows no network at all (``connect-src 'none'``), so it opens the same from a mail
attachment, beside a paper or on a machine without a network. A page served by
``plansynth view --serve`` may talk to the server that sent it, and to nothing else.

>>> html = render_page({"kind": "grid", "problem": {"name": "p"}}, title="p")
>>> html.startswith("<!DOCTYPE html>"), "connect-src 'none'" in html, "https:" in html
(True, True, False)
"""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

#: The scripts of each page, in load order (one file per concept, under static/).
SCRIPTS: dict[str, tuple[str, ...]] = {
    "grid": ("common.js", "grid_semantics.js", "grid_page.js"),
    "reach": ("common.js", "plot.js", "reach_page.js"),
    "team": ("common.js", "team_page.js"),
}


def asset(name: str) -> str:
    """The text of ``static/<name>``."""
    return resources.files("plansynth.view").joinpath("static", name).read_text(encoding="utf-8")


def _inline_json(data: Any) -> str:
    """JSON safe inside a ``<script>`` element: no ``</`` and no ``<!--`` can end it."""
    text = json.dumps(data, separators=(",", ":"), allow_nan=False)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def _inline_script(text: str) -> str:
    if "</script" in text.lower():  # our own files; a guard so an edit cannot break the page
        raise ValueError("a script must not contain </script")
    return text


def content_security_policy(*, connect: str = "'none'") -> str:
    """The policy of a self-contained page: inline scripts and styles, images only as
    ``data:`` URIs, requests only to ``connect`` (``'none'``: no network at all).

    >>> "img-src data:;" in content_security_policy()
    True
    """
    return (
        f"default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data:; "
        f"connect-src {connect}; base-uri 'none'; form-action 'none'"
    )


def render_page(data: dict[str, Any], *, title: str, serve: bool = False) -> str:
    """The page for ``data`` (a dict of :mod:`~plansynth.view.grid_data` or
    :mod:`~plansynth.view.reach_data` or :mod:`~plansynth.view.team_data`, its ``kind``
    choosing the scripts).

    ``serve``: the page plans through the server that sent it (``POST /plan``)."""
    from html import escape

    csp = content_security_policy(connect="'self'" if serve else "'none'")
    scripts = "\n".join(f"<script>\n{_inline_script(asset(name))}\n</script>" for name in SCRIPTS[data["kind"]])
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="{csp}">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="plansynth view">
<title>{escape(title)}</title>
<style>
{asset("page.css")}
</style>
</head>
<body data-serve="{"yes" if serve else "no"}">
<div id="app"></div>
<script id="plansynth-data" type="application/json">{_inline_json(data)}</script>
{scripts}
</body>
</html>
"""
