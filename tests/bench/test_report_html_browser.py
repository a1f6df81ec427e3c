"""The HTML report in a real browser (headless Chromium, the viewer's fixture): its
script runs under its own Content-Security-Policy without an error, every table and
figure is drawn, and a click on a column's header sorts the rows."""

from __future__ import annotations

from typing import Any

from tests.bench.html_page import markdown_headers, markdown_images
from tests.bench.test_report import _fill
from tests.view.conftest import browser, open_page  # noqa: F401, F811 - browser is a fixture

from plansynth.bench.report import render_html, write_report

BOUNDS = """# Sorting

## Times

| instance | time (s) |
|---|---|
| steps-10 | > 60 (1 timeout) |
| steps-5 | 2.5 |
| x | - |
| steps-20 | 60 |
| steps-7 | 0.04 |
"""


def _column(browser: Any, n: int) -> list[str]:
    return browser.execute_script(
        "return Array.from(document.querySelector('main table').tBodies[0].rows).map(r => r.cells[arguments[0]].textContent)",
        n,
    )


def test_the_report_page_draws_every_table_and_figure(browser, tmp_path):
    _fill(tmp_path / "r.db")
    md = write_report(tmp_path / "r.db", tmp_path / "rep")
    markdown = md.read_text()
    open_page(browser, (tmp_path / "rep/REPORT.html").as_uri(), "report")  # fails on a script or CSP error
    images = browser.execute_script(
        "return Array.from(document.images).map(i => [i.alt, i.complete, i.naturalWidth, i.getBoundingClientRect().width])"
    )
    assert [alt for alt, *_ in images] == [alt for alt, _ in markdown_images(markdown)]
    assert all(complete and natural > 100 and shown > 100 for _, complete, natural, shown in images), images
    headers = browser.execute_script(
        "return Array.from(document.querySelectorAll('main table')).filter(t => t.getBoundingClientRect().height > 0)"
        ".map(t => Array.from(t.tHead.rows[0].cells).map(c => c.textContent.trim()))"
    )
    assert headers == markdown_headers(markdown)
    # the contents' links lead to the sections
    links = browser.execute_script("return Array.from(document.querySelectorAll('#toc a')).map(a => a.hash.slice(1))")
    assert links and all(browser.execute_script("return !!document.getElementById(arguments[0])", a) for a in links)


def test_a_click_on_a_header_sorts_numbers_bounds_and_names(browser, tmp_path):
    page = tmp_path / "sort.html"
    page.write_text(render_html(BOUNDS, folder=tmp_path))
    open_page(browser, page.as_uri(), "report")
    name, time = browser.find_elements("css selector", "main table thead th")
    time.click()
    assert _column(browser, 1) == ["0.04", "2.5", "60", "> 60 (1 timeout)", "-"]
    assert time.get_attribute("aria-sort") == "ascending"
    time.click()
    assert _column(browser, 1) == ["-", "> 60 (1 timeout)", "60", "2.5", "0.04"]
    assert time.get_attribute("aria-sort") == "descending"
    name.click()
    assert _column(browser, 0) == ["steps-5", "steps-7", "steps-10", "steps-20", "x"]
    assert time.get_attribute("aria-sort") is None and name.get_attribute("aria-sort") == "ascending"
