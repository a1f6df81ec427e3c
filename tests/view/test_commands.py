"""The one command of docs/how-to/view.md that tests/test_readme_commands.py cannot run
to its end: ``plansynth view ... --serve`` serves until it is stopped. It runs here as a
user would run it (the installed command in a fresh process, in a folder holding a copy
of ``examples/``) until it prints its URL; the page is fetched, and Ctrl-C stops it."""

from __future__ import annotations

import shlex
import shutil
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs/how-to/view.md"
PLANSYNTH = shutil.which("plansynth", path=str(Path(sys.executable).parent)) or "plansynth"
SERVE = "plansynth view examples/reach/maze-3.yaml --serve"


def test_the_serve_command_is_the_one_documented() -> None:
    assert SERVE in DOC.read_text(encoding="utf-8")


@pytest.mark.commands
def test_the_documented_serve_command_serves_the_page_and_stops_on_ctrl_c(tmp_path: Path) -> None:
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    proc = subprocess.Popen([PLANSYNTH, *shlex.split(SERVE)[1:]], cwd=tmp_path, stdout=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        assert line.startswith("serving on http://127.0.0.1:"), line
        with urllib.request.urlopen(line.split()[2], timeout=30) as r:
            assert b"plansynth view: maze-3" in r.read()
        proc.send_signal(signal.SIGINT)
        assert proc.wait(timeout=30) == 0
    finally:
        if proc.poll() is None:
            proc.kill()
