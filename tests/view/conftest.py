"""Fixtures of the viewer's tests: solved results of the examples (once per session) and
one headless Chromium per test module (Debian's chromium and chromium-driver packages,
driven by Selenium; nothing is downloaded).

Without Chromium, its driver or Selenium the browser tests are skipped on a developer's
machine and FAIL in CI (CI=true), where .ci/run installs them."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
CHROMIUM = os.environ.get("PLANSYNTH_CHROMIUM", "/usr/bin/chromium")
CHROMEDRIVER = os.environ.get("PLANSYNTH_CHROMEDRIVER", "/usr/bin/chromedriver")


@pytest.fixture(scope="session")
def results(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """Result files of the examples the pages show, solved with the API as ``plansynth
    grid solve -o`` and ``plansynth reach solve -o`` write them (a team's with its
    planner, as ``reach solve`` picks it)."""
    from plansynth import grid, reach

    out = tmp_path_factory.mktemp("results")
    traffic = grid.load(EXAMPLES / "grid/traffic.yaml")
    paths = {
        "traffic": out / "traffic.json",
        "traffic-8": out / "traffic-8.json",
        "patrol": out / "patrol.json",
        "maze-1": out / "maze-1.json",
    }
    grid.solve(traffic).write(paths["traffic"])
    grid.solve(traffic.with_steps(8)).write(paths["traffic-8"])
    reach.solve(reach.load(EXAMPLES / "reach/mission-patrol.yaml")).write(paths["patrol"])
    reach.solve(reach.load(EXAMPLES / "reach/maze-1.yaml")).write(paths["maze-1"])
    from plansynth.reach.solve import solve as solve_reach
    from plansynth.reach.team.fileformat import load_problem

    paths["team-crossing"] = out / "team-crossing.json"
    solve_reach(load_problem(EXAMPLES / "reach/team-crossing.yaml"), "lazy-smt-team").write(paths["team-crossing"])
    assert json.loads(paths["team-crossing"].read_text())["status"] == "found"
    assert json.loads(paths["traffic"].read_text())["status"] == "realizable"
    assert json.loads(paths["traffic-8"].read_text())["status"] == "unrealizable"
    return paths


def _missing() -> str | None:
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install selenium)"
    for path in (CHROMIUM, CHROMEDRIVER):
        if not (os.path.exists(path) or shutil.which(path)):
            return f"{path} is missing (apt-get install chromium chromium-driver)"
    return None


@pytest.fixture(scope="module")
def browser() -> Any:
    """A headless Chromium for the module's tests, without network access of its own."""
    why = _missing()
    if why is not None:
        if os.environ.get("CI") == "true":
            pytest.fail(f"browser tests need Chromium in CI: {why}")
        pytest.skip(why)
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--window-size=1300,950",
        "--disable-extensions",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--metrics-recording-only",
    ):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(30)
    try:
        yield driver
    finally:
        driver.quit()


def open_page(browser: Any, url: str, kind: str, timeout: float = 20) -> None:
    """Load ``url`` and wait until its script has drawn the page (``body[data-ready]``);
    a script error fails the test with the browser's log."""
    from selenium.webdriver.support.ui import WebDriverWait

    browser.get_log("browser")  # drop what earlier pages logged (a refused re-plan's 400, say)
    browser.get(url)
    try:
        WebDriverWait(browser, timeout).until(
            lambda d: d.find_element("tag name", "body").get_attribute("data-ready") == kind
        )
    except Exception:
        raise AssertionError(f"the page did not draw; browser log: {browser.get_log('browser')}") from None
    errors = [e for e in browser.get_log("browser") if e.get("level") == "SEVERE" and e.get("source") != "network"]
    assert not errors, errors


def screenshot(browser: Any, path: Path) -> Path:
    """Save a screenshot (and a copy under docs/ when PLANSYNTH_VIEW_SCREENSHOTS names
    that folder, for the README)."""
    browser.save_screenshot(str(path))
    assert path.stat().st_size > 10_000
    docs = os.environ.get("PLANSYNTH_VIEW_SCREENSHOTS")
    if docs:
        shutil.copy(path, Path(docs) / path.name)
    return path
