"""The report as one HTML page (REPORT.html, RESULTS.html): written beside the Markdown,
with the same tables and every figure embedded, loading nothing from the network."""

from __future__ import annotations

import base64
import re
from pathlib import Path

import pytest
from tests.bench.html_page import Page, markdown_headers, markdown_images, read_page
from tests.bench.test_report import _fill
from typer.testing import CliRunner

from plansynth.bench.cli import app
from plansynth.bench.report import render_html, write_report

ROOT = Path(__file__).resolve().parents[2]
BENCHMARKS = ROOT / "benchmarks"


def assert_offline(page: Page, text: str) -> None:
    """Nothing the page loads comes from elsewhere: images are data: URIs, scripts and
    styles are inline, links go to an anchor of the page or, in the text, to a web page;
    the Content-Security-Policy allows no network."""
    for tag, attrs in page.tags:
        assert tag not in ("link", "iframe", "object", "embed", "base", "form"), (tag, attrs)
        assert "src" not in attrs or (tag == "img" and attrs["src"].startswith("data:image/")), (tag, attrs)
        assert not {"srcset", "poster", "action", "background"} & set(attrs), (tag, attrs)
        if "href" in attrs:
            assert tag == "a" and (attrs["href"].startswith("#") or re.match(r"https?://", attrs["href"])), attrs
    style = text[text.index("<style>") : text.index("</style>")]
    assert "url(" not in style and "@import" not in style
    assert not any(re.search(r"https?:|fetch\(|XMLHttpRequest|import\(", s) for s in page.scripts)
    (csp,) = [a["content"] for t, a in page.tags if t == "meta" and a.get("http-equiv") == "Content-Security-Policy"]
    assert "default-src 'none'" in csp and "connect-src 'none'" in csp and "img-src data:;" in csp


def assert_same_report(markdown: Path, html: Path) -> None:
    """Every table's header row in order, and every figure where the Markdown puts it,
    embedded with the bytes of the file the Markdown names."""
    md, text = markdown.read_text(encoding="utf-8"), html.read_text(encoding="utf-8")
    page = read_page(text)
    assert page.headers == markdown_headers(md) and page.headers
    images = markdown_images(md)
    assert [i["alt"] for i in page.images] == [alt for alt, _ in images] and images
    for img, (_, src) in zip(page.images, images):
        media, _, data = img["src"].partition(";base64,")
        assert media == "data:image/png" and base64.b64decode(data) == (markdown.parent / src).read_bytes()
    assert_offline(page, text)
    # the contents link every section, and every anchor is unique
    assert len(set(page.anchors)) == len(page.anchors)
    assert page.contents and {h[1:] for h in page.contents} <= set(page.anchors)


def test_report_writes_the_html_page_beside_the_markdown(tmp_path):
    _fill(tmp_path / "r.db")
    out = tmp_path / "rep"
    md = write_report(tmp_path / "r.db", out, planned=[("grid/steps/steps-20", "native", 0)])
    html = out / "REPORT.html"
    assert_same_report(md, html)
    text = html.read_text()
    assert "<title>plansynth benchmark report</title>" in text
    # a cell's text, the missing runs (raw <details> the report writes) and a paper number
    assert "&gt; 60 (1 timeout)" in text and "<summary>Missing runs</summary>" in text
    assert "<td>steps-5</td>\n<td>4.2</td>" in text
    assert '<a href="#figure-3-time-vs-number-of-steps-family-steps">' in text
    assert html.stat().st_size < 2_000_000  # three small figures


def test_the_html_option_of_report_and_publish(tmp_path):
    _fill(tmp_path / "r.db")
    r = CliRunner().invoke(app, ["report", "--db", str(tmp_path / "r.db"), "--out", str(tmp_path / "a")])
    assert r.exit_code == 0, r.output
    assert "REPORT.html" in r.output and (tmp_path / "a/REPORT.html").is_file()
    r = CliRunner().invoke(app, ["report", "--db", str(tmp_path / "r.db"), "--out", str(tmp_path / "b"), "--no-html"])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "b/REPORT.md").is_file() and not list((tmp_path / "b").glob("*.html"))
    r = CliRunner().invoke(
        app, ["publish", "--report-only", "--db", str(tmp_path / "r.db"), "--out", str(tmp_path / "c"), "--no-html"]
    )
    assert r.exit_code == 0, r.output
    assert (tmp_path / "c/RESULTS.md").is_file() and not list((tmp_path / "c").rglob("*.html"))
    for command in ("report", "publish"):
        assert "--no-html" in CliRunner().invoke(app, [command, "--help"]).output


def test_raw_html_other_than_the_reports_own_is_shown_as_text(tmp_path):
    md = (
        "# T\n\n<!-- a note -->\n\n<details><summary>Missing runs</summary>\n\n- x\n\n</details>\n\n"
        "<script>alert(1)</script>\n\nA cell <img src=x onerror=alert(2)> and <b>bold</b>, wall <= T + 1 s.\n\n"
        "See [the paper](https://example.org/paper.pdf).\n"
    )
    text = render_html(md, folder=tmp_path)
    page = read_page(text)
    assert "<details><summary>Missing runs</summary>" in text and "<!-- a note -->" in text
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in text and "&lt;img src=x onerror=alert(2)&gt;" in text
    assert "&lt;b&gt;bold&lt;/b&gt;" in text and "wall &lt;= T + 1 s" in text
    assert [i for i in page.images] == [] and len(page.scripts) == 1  # only the page's own script
    assert ("a", {"href": "https://example.org/paper.pdf"}) in page.tags  # a plain link in the text stays
    assert_offline(page, text)


def test_a_figure_must_be_a_local_image_file(tmp_path):
    (tmp_path / "notes.txt").write_text("x")
    with pytest.raises(ValueError, match="local figure files only"):
        render_html("![f](https://example.org/f.png)\n", folder=tmp_path)
    with pytest.raises(ValueError, match="local figure files only"):
        render_html("![f](//example.org/f.png)\n", folder=tmp_path)
    with pytest.raises(ValueError, match="not one of .png, .svg"):
        render_html("![f](notes.txt)\n", folder=tmp_path)
    with pytest.raises(FileNotFoundError, match="'gone.png': the report names it"):
        render_html("![f](gone.png)\n", folder=tmp_path)
    (tmp_path / "f.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"/>')
    (img,) = read_page(render_html("![f](f.svg)\n", folder=tmp_path)).images
    assert img["src"].startswith("data:image/svg+xml;base64,")


def test_the_contents_nest_sections_under_parts():
    md = "# R\n\n### Before any part\n\n## Part A\n\n### One\n\n### One\n\n## Part B\n\n#### Deep\n"
    text = render_html(md, folder=Path("."))
    nav = text[text.index("<nav") : text.index("</nav>")]
    assert nav.count("<ul>") == nav.count("</ul>") and nav.count("<li>") == nav.count("</li>")
    assert '<li><a href="#part-a">Part A</a><ul><li><a href="#one">One</a></li><li><a href="#one-1">One</a>' in nav
    assert "Deep" not in nav and "#r" not in nav  # the title and level-4 headings stay out


def test_publish_report_only_keeps_results_md_and_writes_results_html(tmp_path):
    """`bench publish --report-only` from the committed database: the committed
    RESULTS.md again (but its Generated line), and RESULTS.html beside it; the committed
    RESULTS.html is the page of the committed RESULTS.md and figures. When this fails
    after a change to the report, regenerate both: plansynth bench publish --report-only"""
    r = CliRunner().invoke(
        app, ["publish", "--report-only", "--db", str(BENCHMARKS / "results.db"), "--out", str(tmp_path)]
    )
    assert r.exit_code == 0, r.output

    def body(path: Path) -> list[str]:
        return [line for line in path.read_text(encoding="utf-8").splitlines() if not line.startswith("Generated ")]

    assert body(tmp_path / "RESULTS.md") == body(BENCHMARKS / "RESULTS.md")
    assert_same_report(tmp_path / "RESULTS.md", tmp_path / "RESULTS.html")
    committed = BENCHMARKS / "RESULTS.html"
    assert_same_report(BENCHMARKS / "RESULTS.md", committed)
    page = render_html((BENCHMARKS / "RESULTS.md").read_text(encoding="utf-8"), folder=BENCHMARKS)
    assert committed.read_text(encoding="utf-8") == page
