"""MkDocs hooks (mkdocs.yml ``hooks:``): one set of Markdown files for GitHub and the site.

The pages under docs/ are written so that they read on GitHub as they are: a picture
of an example links to the repository's ``examples/`` folder and a page may link to a
file of the repository (``benchmarks/RESULTS.md``), both by a relative path that leaves
docs/. The site has only docs/, so these hooks

* copy the pictures of ``examples/`` into the site (``assets/examples/``) and point
  every image link into ``examples/`` at the copy;
* turn every other link that leaves docs/ into its text (the site has no such file);
* publish the repository's CONTRIBUTING.md as the page ``contributing.md`` (its links
  into ``docs/`` made relative to the site), and point the pages' links to
  ``CONTRIBUTING.md`` at it.

So ``mkdocs build --strict`` checks every link that stays in the site.
"""

from __future__ import annotations

import posixpath
import re
from pathlib import Path
from typing import Any

from mkdocs.structure.files import File, Files

ROOT = Path(__file__).resolve().parents[2]
PICTURES = (".gif", ".png", ".svg", ".jpg")
LINK = re.compile(r"(!?)\[([^\]\n]*)\]\(([^)\s]+)\)")


def on_files(files: Files, config: Any) -> Files:
    for path in sorted((ROOT / "examples").rglob("*")):
        if path.suffix in PICTURES:
            uri = "assets/examples/" + path.relative_to(ROOT / "examples").as_posix()
            files.append(File.generated(config, uri, abs_src_path=str(path)))
    contributing = (ROOT / "CONTRIBUTING.md").read_text(encoding="utf-8")
    contributing = re.sub(r"\]\(docs/", "](", contributing)
    files.append(File.generated(config, "contributing.md", content=contributing))
    return files


def _outside(page_uri: str, target: str) -> str | None:
    """The repository path ``target`` names when, relative to the page, it leaves docs/."""
    if re.match(r"^[a-z]+:|^#|^/", target):
        return None
    path = target.split("#", 1)[0]
    joined = posixpath.normpath(posixpath.join(posixpath.dirname(page_uri), path))
    if not joined.startswith("../"):
        return None
    return joined[len("../") :]


def on_page_markdown(markdown: str, page: Any, config: Any, files: Files) -> str:
    uri = page.file.src_uri

    def fix(match: re.Match[str]) -> str:
        bang, text, target = match.groups()
        repo_path = _outside(uri, target)
        if repo_path is None:
            return match.group(0)
        if repo_path == "CONTRIBUTING.md":  # published as the page contributing.md
            return f"{bang}[{text}]({posixpath.relpath('contributing.md', posixpath.dirname(uri) or '.')})"
        if repo_path.startswith("examples/") and repo_path.endswith(PICTURES):
            asset = "assets/" + repo_path
            return f"{bang}[{text}]({posixpath.relpath(asset, posixpath.dirname(uri) or '.')})"
        return text

    return LINK.sub(fix, markdown)
