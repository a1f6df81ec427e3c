"""``plansynth reach validate``: check a result file against its problem with the
independent validator, a mission's plan with the mission checker, a team's plan with
the team validator, and a plan under a disturbance in the worst case and in sampled
runs."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer
from rich.console import Console
from rich.markup import escape

from plansynth.budget import Budget
from plansynth.cli_support import fail
from plansynth.errors import InvalidProblem, PlansynthError
from plansynth.reach.commands.common import read_result
from plansynth.reach.commands.readings import mission_readings

VALIDATE_EPILOG = """\
Examples:

  plansynth reach validate examples/reach/maze-3.yaml traj.json

  plansynth reach validate examples/reach/maze-3.yaml traj.json --segment-safe

  plansynth reach validate examples/reach/maze-3-windy.yaml plan.json --disturbances 1000 --nominal

  plansynth reach validate examples/reach/team-swap-windy.yaml team.json --disturbances 200 --nominal

A problem with a disturbance (robot.disturbance, or a team's robots[i].disturbance): the
plan is also checked against the worst case at every step, with the gain K the result
records (else the problem's design; a team: each robot's, and every pair's separation
by the sum of both robots' error sets); --disturbances N simulates the closed loop (a
team: every robot's) under N random and N vertex disturbance sequences; --nominal runs
a nominal plan under the same sequences.

Exit status: 0 valid, 1 invalid, 2 bad input.
"""


def validate_command(
    file: Path = typer.Argument(..., help="Reach problem file."),
    result_file: Path = typer.Argument(..., help="Result JSON with states and inputs."),
    segment_safe: bool = typer.Option(
        False, "--segment-safe", help="Also require every segment to avoid the obstacles."
    ),
    tol: float = typer.Option(1e-6, "--tol", help="Tolerance of every check."),
    dynamics: str | None = typer.Option(
        None,
        "--dynamics",
        help="exact (x' = A x + B u required) or curve (samples of a continuous-time curve: the dynamics residual is reported, not required); default: curve for a result whose guarantee is curve (gcs), else exact. A mission's plan is checked exactly.",
    ),
    reading: str | None = typer.Option(
        None, "--reading", help="Missions: check in this reading (segment or sample) instead of the file's."
    ),
    end: str | None = typer.Option(
        None, "--end", help="Missions: a finite plan's end (rest or free) instead of the file's."
    ),
    margin: float | None = typer.Option(None, "--margin", help="Missions: the label margin instead of the file's."),
    obstacle_margin: float | None = typer.Option(
        None, "--obstacle-margin", help="Missions: the obstacle margin instead of the file's."
    ),
    disturbances: int = typer.Option(
        0,
        "--disturbances",
        min=0,
        max=1_000_000,
        help="A problem with a disturbance: also simulate the closed loop under this many random and this many vertex disturbance sequences.",
    ),
    seed: int = typer.Option(0, "--seed", min=0, help="The disturbance sequences' random seed."),
    nominal: bool = typer.Option(
        False,
        "--nominal",
        help="With --disturbances: also plan the problem without its disturbance (lazy-smt) and run that plan, with the same gain, under the same sequences.",
    ),
) -> None:
    """Check a trajectory against a problem with the independent validator (and a
    mission's plan with the mission checker, which reports the achieved margin; a team's
    plan with the team validator)."""
    from plansynth.reach.team.fileformat import load_problem
    from plansynth.reach.trajectory import trajectory_from_dict
    from plansynth.reach.validate import tolerance_problem, validate

    console = Console(soft_wrap=True)
    err = Console(stderr=True, soft_wrap=True)
    if dynamics is not None and dynamics not in ("exact", "curve"):
        raise typer.BadParameter("must be exact or curve", param_hint="--dynamics")
    try:
        problem = load_problem(file)
        if getattr(problem, "robots", None) is None:
            problem = mission_readings(None, problem, reading, end, margin, obstacle_margin)
        doc = read_result(result_file)
        if getattr(problem, "robots", None) is not None:  # a team: the team validator
            from plansynth.reach.team.commands import validate_file

            why = tolerance_problem(problem.robot_problems[0], tol)
            if why is not None:
                raise typer.BadParameter(why, param_hint="--tol")
            if disturbances and not any(r.disturbance is not None for r in problem.robots):
                raise typer.BadParameter(
                    "no robot of the team has a disturbance (robots[i].disturbance)", param_hint="--disturbances"
                )
            if nominal and not disturbances:
                raise typer.BadParameter("needs --disturbances", param_hint="--nominal")
            ok, lines = validate_file(
                problem, doc, str(result_file), tol=tol, disturbances=disturbances, seed=seed, nominal=nominal
            )
            for line in lines:
                console.print(escape(line), highlight=False)
            raise typer.Exit(0 if ok else 1)
        trajectory = trajectory_from_dict(doc, str(result_file))
        claim = doc.get("segment_safe")
        if claim is not None and not isinstance(claim, bool):
            raise InvalidProblem(str(result_file), "segment_safe", f"expected true or false, got {claim!r}")
        if problem.mission is not None:
            from plansynth.reach.mission.check import check_result_mission

            check_result_mission(doc, trajectory.horizon, str(result_file))
    except PlansynthError as exc:
        raise fail(err, exc) from None
    if problem.mission is not None and dynamics == "curve":
        raise typer.BadParameter(
            "a mission's plan is a trajectory of the exact dynamics (curve: reach-avoid results only)",
            param_hint="--dynamics",
        )
    why = tolerance_problem(problem, tol)
    if why is not None:
        raise typer.BadParameter(why, param_hint="--tol")
    # a claim in the file is checked: a file that says segment_safe must be segment-safe
    claimed = claim is True or doc.get("guarantee") == "segments"
    if claimed and not segment_safe:
        console.print("the result claims segment safety: segments are checked too", highlight=False)
    if disturbances and problem.disturbance is None:
        raise typer.BadParameter("the problem has no disturbance (robot.disturbance)", param_hint="--disturbances")
    if nominal and not disturbances:
        raise typer.BadParameter("needs --disturbances", param_hint="--nominal")
    if problem.mission is not None:  # LTL missions: validator + mission checker
        from plansynth.reach.mission.check import validate_mission_file

        planned = doc.get("mission") or {}
        for key in ("reading", "end"):
            if planned.get(key) not in (None, getattr(problem, key)):
                console.print(
                    f"the plan was made with {key} {planned[key]!s}; it is checked with {key} "
                    f"{getattr(problem, key)} (--{key} {planned[key]!s} checks it as it was made)",
                    highlight=False,
                    markup=False,
                )
        ok, lines = validate_mission_file(problem, trajectory, doc, segment_safe=segment_safe or claimed, tol=tol)
        for line in lines:
            console.print(line, highlight=False)
        if problem.disturbance is not None:
            ok = (
                _validate_robust(console, err, problem, trajectory, doc, result_file, tol, disturbances, seed, nominal)
                and ok
            )
        raise typer.Exit(0 if ok else 1)
    if dynamics is None:
        dynamics = "curve" if doc.get("guarantee") == "curve" else "exact"
    report = validate(problem, trajectory, require_segment_safe=segment_safe or claimed, tol=tol, dynamics=dynamics)
    if dynamics == "curve":
        console.print(
            "dynamics: curve (the samples of a continuous-time curve; x' = A x + B u is not required)", highlight=False
        )
    style = "bold green" if report.ok else "bold red"
    console.print(
        f"[{style}]{'valid' if report.ok else 'INVALID'}[/{style}]: {escape(report.summary())}", highlight=False
    )
    for v in report.violations[:50]:
        console.print(f"  {escape(str(v))}", highlight=False)
    if len(report.violations) > 50:
        console.print(f"  ... and {len(report.violations) - 50} more", highlight=False)
    ok = report.ok
    if problem.disturbance is not None:
        ok = (
            _validate_robust(console, err, problem, trajectory, doc, result_file, tol, disturbances, seed, nominal)
            and ok
        )
    raise typer.Exit(0 if ok else 1)


def _validate_robust(
    console: Console,
    err: Console,
    problem: Any,
    trajectory: Any,
    doc: dict[str, Any],
    result_file: Path,
    tol: float,
    disturbances: int,
    seed: int,
    nominal: bool,
) -> bool:
    """``reach validate`` on a problem with a disturbance: the worst case at every step
    with the result's gain (else the problem's design), then the sampled runs."""
    import numpy as np

    from plansynth.reach.robust.check import check_robust
    from plansynth.reach.robust.simulate import simulate
    from plansynth.reach.robust.tighten import robust_design

    try:
        K, source = _result_gain(doc, str(result_file), problem)
        if K is None:
            K, source = robust_design(problem).K, "the problem's feedback design"
    except PlansynthError as exc:
        raise fail(err, exc) from None
    mission = doc.get("mission") if isinstance(doc.get("mission"), dict) else {}
    loop = mission.get("loop_start")
    if loop is None and mission.get("semantics") == "finite":
        loop = trajectory.horizon
    segments = doc.get("guarantee", "segments") != "samples"
    report = check_robust(problem, trajectory, K, tol=tol, loop_start=loop, segments=segments)
    gain = "; ".join(", ".join(f"{v + 0.0:.4g}" for v in row) for row in np.asarray(K))
    console.print(f"feedback: u = v + K (x - x_nom), K = [{gain}] ({source})", highlight=False)
    style = "bold green" if report.ok else "bold red"
    console.print(
        f"[{style}]{'robust' if report.ok else 'NOT robust'}[/{style}]: {escape(report.summary())}", highlight=False
    )
    for v in report.violations[:20]:
        console.print(f"  {escape(str(v))}", highlight=False)
    for note in report.notes:
        console.print(f"  note: {escape(note)}", highlight=False)
    ok = report.ok
    if disturbances:
        runs = simulate(problem, trajectory, K, sequences=disturbances, seed=seed, tol=tol, loop_start=loop)
        style = "bold green" if runs.violated == 0 else "bold red"
        console.print(f"[{style}]simulated[/{style}]: {escape(runs.summary())}", highlight=False)
        ok = ok and runs.violated == 0
        if nominal:
            _nominal_runs(console, problem, K, disturbances, seed, tol)
    return ok


def _result_gain(doc: dict[str, Any], name: str, problem: Any) -> tuple[Any, str]:
    """The gain K a result file records (``robust.feedback.gain``), checked; (None, "")
    when it records none."""
    import numpy as np

    robust = doc.get("robust")
    if robust is None:
        return None, ""
    try:
        K = np.array(robust["feedback"]["gain"], dtype=float)
    except (KeyError, TypeError, ValueError):
        raise InvalidProblem(name, "robust.feedback.gain", "expected the gain K as a list of rows of numbers") from None
    m, n = problem.dynamics.n_inputs, problem.dynamics.n_states
    if K.shape != (m, n) or not np.all(np.isfinite(K)):
        raise InvalidProblem(name, "robust.feedback.gain", f"expected an {m} x {n} matrix of finite numbers")
    return K, "the result's"


def _nominal_runs(console: Console, problem: Any, K: Any, disturbances: int, seed: int, tol: float) -> None:
    """A nominal plan (lazy-smt, the disturbance ignored) under the same sequences."""
    from dataclasses import replace

    from plansynth.reach.robust.simulate import simulate
    from plansynth.reach.solve import solve

    plain = replace(problem, disturbance=None)
    result = solve(plain, "lazy-smt", Budget(seconds=60.0))
    if result.trajectory is None:
        console.print(f"nominal plan: none ({escape(result.message)})", highlight=False)
        return
    runs = simulate(
        problem,
        result.trajectory,
        K,
        sequences=disturbances,
        seed=seed,
        tol=tol,
        loop_start=(result.mission or {}).get("loop_start"),
    )
    kinds = ", ".join(f"{k} in {v}" for k, v in runs.kinds_violated.items())
    console.print(
        f"nominal plan (horizon {result.horizon}, the disturbance ignored), same gain and sequences: "
        f"{escape(runs.summary())}" + (f"; runs with each violation: {escape(kinds)}" if kinds else ""),
        highlight=False,
    )
