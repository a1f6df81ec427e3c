"""``plansynth view --serve``: a local page that plans.

A :class:`http.server.ThreadingHTTPServer` bound to 127.0.0.1 only serves one page
(``GET /``) and answers ``POST /plan``: the body is ``{"problem": {...}, "timeout": T}``,
the problem being the dict a problem file holds, edited in the page. The server checks
it with plansynth's own loader first, so a problem the CLI would refuse is refused with
the CLI's words (:class:`~plansynth.errors.InvalidProblem`: the edited problem, the
field, the reason; HTTP 400). A valid one is planned in an isolated child process
(:func:`plansynth.isolate.run_isolated`) with the budget ``T`` (at most
:data:`MAX_TIMEOUT` seconds), so a stuck solve cannot hang the server; the answer is
the page's data for the new problem and result, with the answer as ``plansynth reach
solve`` words it (:func:`~plansynth.view.reach_data.reach_words`).

Requests whose ``Host`` is not this server's address (DNS rebinding) or whose
``Origin`` is another site are refused. Ctrl-C or SIGTERM stops the server, kills a
running re-plan's child and returns.
"""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Callable
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

from plansynth.errors import PlansynthError

#: The largest budget a re-plan may ask for, in seconds.
MAX_TIMEOUT = 30.0
#: Seconds a re-plan's child may take beyond its budget (start, abstraction, page data).
GRACE = 20.0
#: The largest request body accepted.
MAX_BODY = 1 << 20

EDITED = "the edited problem"


def load_edited(doc: Any) -> Any:
    """The reach problem of an edited problem document, checked as the CLI checks a file."""
    from plansynth.reach.fileformat import reach_problem_from_dict

    return reach_problem_from_dict(doc, source=EDITED, default_name="edited")


def serve_data(
    problem: Any, result: dict[str, Any] | None, timeout: float, *, source: str = "<result>"
) -> dict[str, Any]:
    """The reach page's data for a served page: the problem's own document (what the page
    edits), and the budget it asks for by default."""
    from plansynth.reach.fileformat import reach_problem_to_dict
    from plansynth.view.reach_data import reach_page_data

    data = reach_page_data(problem, result, source=source)
    data.update(problem_doc=reach_problem_to_dict(problem), timeout=timeout, max_timeout=MAX_TIMEOUT)
    return data


def plan_edited(doc: dict[str, Any], seconds: float) -> dict[str, Any]:
    """Plan an edited problem within ``seconds`` (run in a child process): the page's data."""
    from plansynth.budget import Budget
    from plansynth.reach import solve

    problem = load_edited(doc)
    result = solve(problem, "lazy-smt", Budget(seconds=seconds))
    return serve_data(problem, result.to_json_dict(), seconds)


def clamp_timeout(value: Any, default: float) -> float:
    """A re-plan's budget: ``value`` if it is a number, within 0.1..MAX_TIMEOUT seconds.

    >>> clamp_timeout(300, 10), clamp_timeout("x", 10), clamp_timeout(None, 5)
    (30.0, 10.0, 5.0)
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != value:
        return float(min(default, MAX_TIMEOUT))
    return float(min(max(value, 0.1), MAX_TIMEOUT))


class PlanServer(ThreadingHTTPServer):
    """The page and its ``/plan`` endpoint; one re-plan runs at a time."""

    daemon_threads = True

    def __init__(
        self,
        page: str,
        port: int,
        timeout: float,
        planner: Callable[[dict[str, Any], float], dict[str, Any]] = plan_edited,
    ) -> None:
        super().__init__(("127.0.0.1", port), _Handler)
        self.page = page.encode("utf-8")
        self.timeout_default = timeout
        self.planner = planner
        self.plan_lock = threading.Lock()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.server_address[1]}/"

    def plan(self, body: Any) -> tuple[int, dict[str, Any]]:
        """The HTTP status and JSON answer of ``POST /plan``."""
        from plansynth.isolate import Crash, Finished, run_isolated

        if not isinstance(body, dict) or not isinstance(body.get("problem"), dict):
            return 400, {"error": 'expected {"problem": {...}, "timeout": seconds}'}
        doc = body["problem"]
        try:
            load_edited(doc)  # refused here with the CLI's words, before any child starts
        except PlansynthError as exc:
            return 400, {"error": str(exc)}
        seconds = clamp_timeout(body.get("timeout"), self.timeout_default)
        with self.plan_lock:
            start = time.perf_counter()
            outcome = run_isolated(self.planner, doc, seconds, timeout=seconds + GRACE)
            took = time.perf_counter() - start
        if isinstance(outcome, Finished):
            return 200, {"data": outcome.value, "words": outcome.value["words"], "seconds": took}
        if isinstance(outcome, Crash):
            last = (outcome.error or f"exit code {outcome.exitcode}").strip().splitlines()[-1:]
            return 500, {"error": f"the planner failed: {' '.join(last)}"}
        data = serve_data(load_edited(doc), None, seconds)
        words = ["status: unknown", f"message: the re-plan was stopped after {took:.1f} s (budget {seconds:g} s)"]
        data.update(status="unknown", words=words)
        return 200, {"data": data, "words": words, "seconds": took}


class _Handler(BaseHTTPRequestHandler):
    server: PlanServer
    protocol_version = "HTTP/1.1"

    def log_message(self, format: str, *args: Any) -> None:  # quiet: the command prints the URL only
        pass

    def _send(self, status: int, body: bytes, content_type: str) -> None:
        self.send_response(status)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.end_headers()
        self.wfile.write(body)

    def _json(self, status: int, answer: dict[str, Any]) -> None:
        self._send(status, json.dumps(answer, allow_nan=False).encode("utf-8"), "application/json")

    def _local(self) -> bool:
        """The request names this server (not another host name resolving here), and
        comes from its own page when it says where it comes from."""
        port = self.server.server_address[1]
        hosts = {f"127.0.0.1:{port}", f"localhost:{port}"}
        origin = self.headers.get("Origin")
        return self.headers.get("Host") in hosts and (origin is None or origin in {f"http://{h}" for h in hosts})

    def do_GET(self) -> None:  # noqa: N802 - http.server's name
        if not self._local():
            return self._json(403, {"error": "this server answers its own page only"})
        if self.path.split("?")[0] in ("/", "/index.html"):
            return self._send(200, self.server.page, "text/html; charset=utf-8")
        self._json(404, {"error": f"no such page: {self.path[:100]}"})

    def do_POST(self) -> None:  # noqa: N802
        if not self._local():
            return self._json(403, {"error": "this server answers its own page only"})
        if self.path != "/plan":
            return self._json(404, {"error": f"no such endpoint: {self.path[:100]}"})
        try:
            length = int(self.headers.get("Content-Length", ""))
        except ValueError:
            return self._json(411, {"error": "a Content-Length is required"})
        if not 0 < length <= MAX_BODY:
            return self._json(413, {"error": f"the body must hold 1..{MAX_BODY} bytes"})
        try:
            body = json.loads(self.rfile.read(length).decode("utf-8"))
        except (UnicodeDecodeError, ValueError) as exc:
            return self._json(400, {"error": f"not JSON: {exc}"})
        status, answer = self.server.plan(body)
        self._json(status, answer)


def serve_forever(server: PlanServer, announce: Callable[[str], None] = print) -> None:
    """Serve until Ctrl-C or SIGTERM (which the CLI turns into KeyboardInterrupt), then
    stop every re-plan child and close the socket."""
    import signal

    from plansynth.isolate import cancel_all

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.default_int_handler)  # also when started with SIGINT ignored (&)
    announce(f"serving on {server.url} (Ctrl-C stops)")
    try:
        server.serve_forever(poll_interval=0.2)
    except KeyboardInterrupt:
        pass
    finally:
        cancel_all()
        server.server_close()
