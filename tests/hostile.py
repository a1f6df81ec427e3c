"""Hostile and malformed inputs shared by the bad-input regression tests and the fuzz
test, and a checker of the CLI's contract on them: exit status in
{0, 1, 2, 3}, no traceback, and on status 2 exactly one line, ``error: ...``.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from typer.testing import CliRunner

from plansynth.cli import app

ROOT = Path(__file__).resolve().parents[1]
FIGURE1 = ROOT / "examples" / "grid" / "figure1.yaml"
MAZE1 = ROOT / "examples" / "reach" / "maze-1.yaml"
WINNER = "(ite (<= rx 3) 2 1)"

runner = CliRunner()


def billion_laughs(levels: int = 9) -> str:
    """A YAML ``name`` value of about 600 bytes that expands to 9**levels strings
    (``name: &i [&h [... &a [lol x 9] ...], *h x 8]``)."""
    expr = "&a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol]"
    for i in range(1, levels):
        expr = f"&a{i} [{expr}, " + ", ".join([f"*a{i - 1}"] * 8) + "]"
    return f"name: {expr}\n"


def grid_text(extra: str = "", drop: tuple[str, ...] = ()) -> str:
    """figure1.yaml's text with some top-level lines dropped and ``extra`` appended."""
    lines = [ln for ln in FIGURE1.read_text(encoding="utf-8").splitlines() if not ln.startswith(drop or ("\0",))]
    return "\n".join(lines) + "\n" + extra


def hostile_grid_files(tmp: Path) -> dict[str, tuple[Path, str]]:
    """name -> (path, a fragment of the expected error) for files that must be refused."""
    out: dict[str, tuple[Path, str]] = {}

    def put(name: str, data: str | bytes, expect: str) -> None:
        p = tmp / name
        if isinstance(data, bytes):
            p.write_bytes(data)
        else:
            p.write_text(data, encoding="utf-8")
        out[name] = (p, expect)

    put("laughs.yaml", billion_laughs() + grid_text(drop=("name",)), "expands to more than")
    put("nested.yaml", "name: " + "[" * 50_000 + "]" * 50_000 + "\n" + grid_text(), "nested deeper than")
    put("complex-key.yaml", grid_text("? [1, 2]\n: 3\n"), "a mapping key must be a plain value")
    put("latin1.yaml", ("# café\n" + grid_text()).encode("latin-1"), "not UTF-8 text: byte 0xe9 at line 1, column 6")
    put("recursive.yaml", grid_text("walls: &w [*w]\n", drop=("walls",)), "")
    fifo = tmp / "fifo.yaml"
    os.mkfifo(fifo)
    out["fifo.yaml"] = (fifo, "not a regular file")
    big = tmp / "big.yaml"
    with open(big, "wb") as fh:
        fh.truncate(9 * 1024 * 1024)  # sparse: costs nothing on disk
    out["big.yaml"] = (big, "too large")
    out["/dev/zero"] = (Path("/dev/zero"), "not a regular file")
    out["directory"] = (tmp, "is a directory")
    return out


def invoke(args: list[str], **kwargs: Any):
    """Run the ``plansynth`` CLI in-process (typer's CliRunner)."""
    return runner.invoke(app, [str(a) for a in args], **kwargs)


def check_contract(result: Any, args: list[str]) -> None:
    """The CLI's contract on any input."""
    where = f"plansynth {' '.join(map(str, args))[:300]}"
    exc = result.exception
    assert exc is None or isinstance(exc, SystemExit), f"{where}: raised {exc!r}"
    assert result.exit_code in (0, 1, 2, 3), f"{where}: exit {result.exit_code}\n{result.output[-2000:]}"
    assert "Traceback" not in result.output, f"{where}: traceback\n{result.output[-3000:]}"
    if result.exit_code == 2:
        lines = [ln for ln in result.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1 and lines[0].startswith("error: "), (
            f"{where}: not one error line:\n{result.stderr[-2000:]}"
        )
