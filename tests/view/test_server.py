"""``plansynth view --serve``: the ``/plan`` round trip over HTTP, the refusals, and a
server that dies with its command, leaving nothing running."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any

import pytest
from tests.view.conftest import EXAMPLES

from plansynth.reach.fileformat import load_reach_problem, reach_problem_to_dict
from plansynth.view import build_page
from plansynth.view.server import PlanServer

MAZE1 = EXAMPLES / "reach/maze-1.yaml"


@pytest.fixture(scope="module")
def server() -> Any:
    s = PlanServer(build_page(MAZE1, serve=True), 0, 20)
    thread = threading.Thread(target=s.serve_forever, kwargs={"poll_interval": 0.1}, daemon=True)
    thread.start()
    yield s
    s.shutdown()
    s.server_close()


def _post(url: str, body: Any, headers: dict[str, str] | None = None) -> tuple[int, dict]:
    data = body if isinstance(body, bytes) else json.dumps(body).encode()
    req = urllib.request.Request(
        url + "plan", data=data, headers={"Content-Type": "application/json", **(headers or {})}
    )
    try:
        with urllib.request.urlopen(req, timeout=120) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read())


def test_plan_round_trip(server: Any) -> None:
    from plansynth.reach import solve
    from plansynth.view.reach_data import reach_words

    doc = reach_problem_to_dict(load_reach_problem(MAZE1))
    status, answer = _post(server.url, {"problem": doc, "timeout": 20})
    assert status == 200
    data = answer["data"]
    assert data["status"] == "found" and data["validation"]["ok"]
    assert data["trajectory"]["states"][0] == [1.0, 1.0, 0.0, 0.0]
    # the words are the CLI's: the same rows as plansynth reach solve's table for the same problem
    direct = solve(load_reach_problem(MAZE1)).to_json_dict()
    assert (
        answer["words"][:2]
        == reach_words(direct)[:2]
        == ["status: found", f"horizon: {direct['horizon']} (not proved minimal)"]
    )


def test_the_words_match_the_cli(tmp_path: Path) -> None:
    out = subprocess.run(
        [sys.executable, "-m", "plansynth.cli", "reach", "solve", str(MAZE1), "-o", str(tmp_path / "r.json")],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "COLUMNS": "200"},
    )
    from plansynth.view.reach_data import reach_words

    rows = [" ".join(line.strip("│┃ ").split()) for line in out.stdout.splitlines()]
    for word in reach_words(json.loads((tmp_path / "r.json").read_text()))[:4]:
        item, value = word.split(": ", 1)
        assert any(r.startswith(item) and value in r for r in rows), (word, out.stdout)


def test_bad_problems_are_refused_with_the_loaders_words(server: Any) -> None:
    doc = reach_problem_to_dict(load_reach_problem(MAZE1))
    doc["robot"]["start"] = [40, 1, 0, 0]
    status, answer = _post(server.url, {"problem": doc})
    assert status == 400
    assert answer["error"].startswith("the edited problem: robot.start:")
    assert _post(server.url, {"problem": "x"})[0] == 400
    assert _post(server.url, b"{not json")[0] == 400
    assert _post(server.url, {"problem": doc}, {"Host": "evil.example:80"})[0] == 403
    assert _post(server.url, {"problem": doc}, {"Origin": "http://evil.example"})[0] == 403


def test_the_command_serves_and_dies_with_nothing_left(tmp_path: Path) -> None:
    from plansynth.procs import descendants

    proc = subprocess.Popen(
        [sys.executable, "-m", "plansynth.cli", "view", str(MAZE1), "--serve", "--port", "0"],
        stdout=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        line = proc.stdout.readline()
        assert line.startswith("serving on http://127.0.0.1:"), line
        url = line.split()[2]
        with urllib.request.urlopen(url, timeout=30) as r:
            assert b'"kind":"reach"' in r.read()
        doc = reach_problem_to_dict(load_reach_problem(MAZE1))
        assert _post(url, {"problem": doc, "timeout": 20})[0] == 200  # a re-plan child has run
        children = descendants(proc.pid)
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == 0
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and any(os.path.exists(f"/proc/{p}") for p in children):
            time.sleep(0.1)
        left = [
            p
            for p in children
            if os.path.exists(f"/proc/{p}")
            and "Z" not in Path(f"/proc/{p}/stat").read_text().split(")")[-1].split()[:1]
        ]
        assert not left
        with pytest.raises(OSError):
            urllib.request.urlopen(url, timeout=5)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
