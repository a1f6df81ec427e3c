"""The pages in a real browser (headless Chromium): what they show is what plansynth
computes. The grid page's controller moves equal plansynth's step semantics and
program evaluation on random obstacle moves (the oracle: plansynth.grid.semantics.step
and plansynth.grid.programs.evaluate); a refuted controller's page replays the
verifier's counterexample; an unrealizable problem's page answers every robot move with
explain's strategy; the reach page's positions at each step equal the result file; the
served page re-plans a dragged start and shows the CLI's words. Screenshots are saved
in pytest's tmp dir."""

from __future__ import annotations

import json
import random
import threading
from pathlib import Path
from typing import Any

import pytest
from tests.view.conftest import EXAMPLES, open_page, screenshot

from plansynth.grid import load as load_grid
from plansynth.grid.programs import evaluate, parse_program
from plansynth.grid.semantics import State, initial_state, step
from plansynth.view import build_page

TRAFFIC = EXAMPLES / "grid/traffic.yaml"


def _write(tmp_path: Path, name: str, html: str) -> str:
    path = tmp_path / name
    path.write_text(html, encoding="utf-8")
    return path.as_uri()


def _shown_state(browser: Any) -> State:
    robot = browser.find_element("id", "robot")
    obstacles = sorted(
        browser.find_elements("css selector", "#board .obstacle"), key=lambda e: int(e.get_attribute("data-i"))
    )
    return State(
        (int(robot.get_attribute("data-x")), int(robot.get_attribute("data-y"))),
        tuple((int(o.get_attribute("data-x")), int(o.get_attribute("data-y"))) for o in obstacles),
    )


def _set_step(browser: Any, t: int) -> None:
    browser.execute_script(
        "const s = document.getElementById('step'); s.value = arguments[0];s.dispatchEvent(new Event('input'));", t
    )


def _env(problem: Any, s: State) -> dict[str, int]:
    return dict(zip(problem.variables, s.inputs()))


def test_grid_page_moves_equal_plansynth_on_random_adversaries(browser: Any, results: dict, tmp_path: Path) -> None:
    from selenium.webdriver.support.ui import Select

    problem = load_grid(TRAFFIC)
    raw = json.loads(results["traffic"].read_text())
    program, steps = parse_program(raw["program"]), raw["steps"]
    url = _write(tmp_path, "traffic.html", build_page(TRAFFIC, results["traffic"]))
    for seed in range(3):
        open_page(browser, url, "grid")
        rng = random.Random(seed)
        state = initial_state(problem)
        assert _shown_state(browser) == state
        selects = browser.find_elements("css selector", "select.obstacle-move")
        for t in range(steps):
            k = evaluate(program, _env(problem, state))
            fired = browser.find_element("css selector", "#program .leaf.fired")
            assert int(fired.get_attribute("data-move")) == k, f"seed {seed}, step {t}: the branch shown"
            joint = tuple(rng.randrange(len(o.moves)) for o in problem.obstacles)
            for sel, j in zip(selects, joint):
                Select(sel).select_by_value(str(j))
            browser.find_element("id", "apply").click()
            out = step(problem, state, k, joint)
            assert _shown_state(browser) == out.state, f"seed {seed}, step {t}, obstacle moves {joint}"
            assert not out.collided  # the verified controller wins against every behaviour
            state = out.state
        outcome = browser.find_element("id", "outcome")
        assert outcome.text == f"on the goal (5, 4) after step {steps - 1}" and "win" in outcome.get_attribute("class")
    screenshot(browser, tmp_path / "view-grid.png")


def test_refuted_controller_replays_the_counterexample(browser: Any, tmp_path: Path) -> None:
    from plansynth.grid import verify

    problem = load_grid(TRAFFIC)
    program = parse_program("(ite (<= 4 o0y) 0 2)")  # waits for car 0 only: car 1 hits it
    verdict = verify(problem, program, 9)
    cex = verdict.counterexample
    assert cex is not None
    result = tmp_path / "bad.json"
    result.write_text(json.dumps({"status": "realizable", "steps": 9, "program": str(program)}))
    open_page(browser, _write(tmp_path, "bad.html", build_page(TRAFFIC, result)), "grid")
    for t, s in enumerate(cex.states):
        _set_step(browser, t)
        assert _shown_state(browser) == s, f"step {t}"
    outcome = browser.find_element("id", "outcome")
    assert "lose" in outcome.get_attribute("class")
    assert cex.reason.startswith(outcome.text.split(":")[0]) or outcome.text in cex.reason
    # the worst-case adversary finds a loss from the start as well
    _set_step(browser, 0)
    for _ in range(9):
        buttons = browser.find_elements("css selector", "#worst:not([disabled])")
        if not buttons:
            break
        buttons[0].click()
    assert "lose" in browser.find_element("id", "outcome").get_attribute("class")
    assert "force a loss" in browser.find_element("id", "note").text


def test_unrealizable_page_plays_the_obstacles_strategy(browser: Any, results: dict, tmp_path: Path) -> None:
    from plansynth.grid.native.explain import explain

    problem = load_grid(TRAFFIC)
    strategy = explain(problem, 8).strategy
    open_page(browser, _write(tmp_path, "t8.html", build_page(TRAFFIC, results["traffic-8"])), "grid")
    for seed in range(2):
        _set_step(browser, 0)
        rng = random.Random(seed)
        state, lost = initial_state(problem), False
        for t in range(8):
            k = rng.choice([0, 2, 2])  # stay or right, towards the goal
            joint, _ = strategy.reply(t, state, k)
            browser.find_element("css selector", f".robot-move[data-k='{k}']").click()
            out = step(problem, state, k, joint)
            assert _shown_state(browser) == out.state, f"seed {seed}, step {t}, robot move {k}"
            state = out.state
            if out.collided:
                lost = True
                break
        lost = lost or state.robot != problem.robot.goal
        assert lost  # the strategy beats every controller, so every run of the user's
        assert "lose" in browser.find_element("id", "outcome").get_attribute("class")
    screenshot(browser, tmp_path / "view-grid-unrealizable.png")


def test_reach_page_positions_equal_the_result(browser: Any, results: dict, tmp_path: Path) -> None:
    problem_path = EXAMPLES / "reach/mission-patrol.yaml"
    doc = json.loads(results["patrol"].read_text())
    open_page(browser, _write(tmp_path, "patrol.html", build_page(problem_path, results["patrol"])), "reach")
    robot = browser.find_element("id", "robot")
    for t, state in enumerate(doc["states"]):
        _set_step(browser, t)
        assert (float(robot.get_attribute("data-x")), float(robot.get_attribute("data-y"))) == (state[0], state[1])
    words = browser.find_element("id", "words").text.splitlines()
    assert words[0] == "status: found" and words[1].startswith(f"horizon: {doc['horizon']}")
    loop = browser.find_element("id", "loop").get_attribute("points").split()
    assert len(loop) == len(doc["states"]) - doc["mission"]["loop_start"]
    assert len(browser.find_elements("css selector", ".plot")) == 6  # x y vx vy ux uy
    regions = browser.find_elements("css selector", "#workspace .region")
    assert regions and regions[0].is_displayed()
    browser.find_element("id", "toggle-regions").click()
    assert not regions[0].is_displayed()
    browser.find_element("id", "toggle-regions").click()
    _set_step(browser, 0)
    chips = [c.get_attribute("data-label") for c in browser.find_elements("css selector", "#labels-holding .chip")]
    assert chips == ["a"]  # the start lies in label a
    _set_step(browser, 4)
    screenshot(browser, tmp_path / "view-reach.png")


@pytest.fixture()
def plan_server() -> Any:
    from plansynth.view import build_page
    from plansynth.view.server import PlanServer

    class Server(PlanServer):
        """Keeps the documents it planned and its answers."""

        planned: list = []

        def plan(self, body: Any) -> tuple[int, dict]:
            status, answer = super().plan(body)
            self.planned.append((body, status, answer))
            return status, answer

    page = build_page(EXAMPLES / "reach/maze-1.yaml", serve=True, timeout=20)
    server = Server(page, 0, 20)
    thread = threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True)
    thread.start()
    try:
        yield server
    finally:
        server.shutdown()
        server.server_close()


def test_served_page_replans_a_dragged_start(browser: Any, plan_server: Any, tmp_path: Path) -> None:
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.support.ui import WebDriverWait

    from plansynth.reach import Trajectory, validate
    from plansynth.view.server import load_edited

    open_page(browser, plan_server.url, "reach")
    wait = WebDriverWait(browser, 60)
    wait.until(lambda d: d.find_element("tag name", "body").get_attribute("data-plans") == "1")
    assert browser.find_element("id", "words").text.startswith("status: found")
    start = browser.find_element("id", "start")
    ActionChains(browser).drag_and_drop_by_offset(start, 40, -40).perform()  # 20 px per metre: to (3, 3)
    wait.until(lambda d: d.find_element("tag name", "body").get_attribute("data-plans") == "2")
    body, status, answer = plan_server.planned[-1]
    assert status == 200 and body["problem"]["robot"]["start"][:2] == [3, 3]
    robot = browser.find_element("id", "robot")
    assert (float(robot.get_attribute("data-x")), float(robot.get_attribute("data-y"))) == (3.0, 3.0)
    shown = browser.find_element("id", "words").text.splitlines()
    assert shown == answer["words"] and shown[0] == "status: found"
    traj = answer["data"]["trajectory"]
    report = validate(load_edited(body["problem"]), Trajectory(traj["states"], traj["inputs"]))
    assert report.ok, report.summary()  # checked independently of the server
    # a mission naming no label is refused with the loader's words, and nothing is planned
    field = browser.find_element("id", "mission-input")
    field.clear()
    field.send_keys("F nowhere")
    browser.find_element("id", "plan").click()
    wait.until(lambda d: d.find_element("tag name", "body").get_attribute("data-plans") == "3")
    error = browser.find_element("id", "error").text
    assert plan_server.planned[-1][1] == 400
    assert error == "error: " + plan_server.planned[-1][2]["error"]
    assert error.startswith("error: the edited problem: mission:")
    screenshot(browser, tmp_path / "view-serve.png")


def test_team_page_shows_each_robot_and_the_moving_obstacle(browser: Any, results: dict, tmp_path: Path) -> None:
    """The page ``plansynth view -o`` writes for a team: one trajectory per robot, each
    robot where the result file has it, and the cart where the problem's waypoints put
    it at each step's time (plansynth.reach.team.problem.MovingObstacle.position)."""
    from typer.testing import CliRunner

    from plansynth.cli import app
    from plansynth.reach.team.fileformat import load_problem

    problem_path = EXAMPLES / "reach/team-crossing.yaml"
    problem = load_problem(problem_path)
    doc = json.loads(results["team-crossing"].read_text())
    page = tmp_path / "crossing.html"
    run = CliRunner().invoke(
        app, ["view", str(problem_path), "--result", str(results["team-crossing"]), "-o", str(page)]
    )
    assert run.exit_code == 0 and "page written to" in run.output, run.output
    open_page(browser, page.as_uri(), "team")
    paths = browser.find_elements("css selector", "#workspace .team-path")
    assert len(paths) == len(doc["robots"]) == 2
    assert len({p.get_attribute("stroke") for p in paths}) == 2  # each robot in its own colour
    for p, robot in zip(paths, doc["robots"]):
        assert len(p.get_attribute("points").split()) == len(robot["states"])
    cart = problem.moving_obstacles[0]
    for t in range(len(doc["robots"][0]["states"])):
        _set_step(browser, t)
        for i, robot in enumerate(doc["robots"]):
            shown = browser.find_element("css selector", f"#now .team-robot[data-robot='{i}']")
            assert (float(shown.get_attribute("data-x")), float(shown.get_attribute("data-y"))) == tuple(
                robot["states"][t][:2]
            ), f"robot {robot['name']}, step {t}"
        moving = browser.find_element("css selector", "#now .moving")
        shown = (float(moving.get_attribute("data-x")), float(moving.get_attribute("data-y")))
        assert shown == pytest.approx(tuple(cart.position(problem.time_of(t))), abs=1e-12), f"cart, step {t}"
    _set_step(browser, 3)
    assert "cart at (3.5, 2)" in browser.find_element("id", "step-info").text  # t = 3 s: halfway up
    words = browser.find_element("id", "words").text.splitlines()
    assert words[0] == "status: found" and words[1].startswith(f"horizon: {doc['horizon']}")
    assert browser.find_element("id", "validation").text.startswith("independent team validator: valid")
    screenshot(browser, tmp_path / "view-team.png")
