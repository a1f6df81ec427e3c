"""Every ``plansynth`` command of docs/how-to/view.md, run as a user would: the
installed command in a fresh process, in a folder holding a copy of ``examples/``.
A ``--serve`` command runs until it prints its URL, answers it, and is stopped."""

from __future__ import annotations

import re
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

#: documented command -> the files it writes ("serve": it serves a page until stopped)
CASES: dict[str, tuple[str, ...]] = {
    "plansynth grid solve examples/grid/traffic.yaml -o traffic.json": ("traffic.json",),
    "plansynth view examples/grid/traffic.yaml --result traffic.json -o traffic.html": ("traffic.html",),
    "plansynth reach solve examples/reach/mission-patrol.yaml -o patrol.json": ("patrol.json",),
    "plansynth view examples/reach/mission-patrol.yaml --result patrol.json -o patrol.html": ("patrol.html",),
    "plansynth grid solve examples/grid/traffic.yaml --steps 8 -o traffic-8.json": ("traffic-8.json",),
    "plansynth view examples/grid/traffic.yaml --result traffic-8.json -o why.html": ("why.html",),
    "plansynth view examples/reach/maze-3.yaml --serve": ("serve",),
}


def documented() -> list[str]:
    blocks = re.findall(r"```bash\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S)
    return [line.strip() for block in blocks for line in block.splitlines() if line.strip().startswith("plansynth ")]


def test_every_documented_command_has_a_case() -> None:
    assert documented() == list(CASES)


@pytest.mark.commands
def test_the_documented_commands_in_order(tmp_path: Path) -> None:
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    for command in documented():
        argv = [PLANSYNTH, *shlex.split(command)[1:]]
        if CASES[command] == ("serve",):
            proc = subprocess.Popen(argv, cwd=tmp_path, stdout=subprocess.PIPE, text=True)
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
            continue
        out = subprocess.run(argv, cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert out.returncode in (0, 1), (command, out.stdout, out.stderr)  # grid solve at l = 8: 1, unrealizable
        for name in CASES[command]:
            assert (tmp_path / name).stat().st_size > 0, command
