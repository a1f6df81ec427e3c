"""The planner protocol, the registry and the options values."""

from __future__ import annotations

import dataclasses

import pytest

from plansynth.budget import Budget
from plansynth.errors import InvalidOption
from plansynth.reach.families import maze
from plansynth.reach.lazy.options import CONFIGURATIONS, COUNTEREXAMPLES, LazyOptions
from plansynth.reach.planners import SHARED_OPTIONS, get_planner, planners
from plansynth.reach.result import ReachStatus
from plansynth.reach.solve import configure, solve


def test_lazy_options_are_one_frozen_value() -> None:
    opts = LazyOptions()
    with pytest.raises(dataclasses.FrozenInstanceError):
        opts.counterexample = "trivial"  # type: ignore[misc]
    assert LazyOptions.paper() == CONFIGURATIONS["lazy-smt-paper"]
    assert hash(LazyOptions.paper()) == hash(LazyOptions.paper())  # usable as a key


def test_the_paper_configuration_is_the_published_loop() -> None:
    p = LazyOptions.paper()
    assert (p.counterexample, p.generalize, p.slack_weights, p.horizon_search) == (
        "zeroprefix",
        False,
        "uniform",
        "linear",
    )
    assert not (p.transit or p.guided or p.timed_route or p.widen or p.wait_shifts)
    assert p.segment_safe and p.lower_bound  # what both modes share
    assert CONFIGURATIONS["lazy-smt-paper-trivial"] == dataclasses.replace(p, counterexample="trivial")
    # our loops: the counterexample comparison's and the window search alone, without the timed route
    assert CONFIGURATIONS["lazy-smt-zeroprefix"] == LazyOptions(counterexample="zeroprefix", timed_route=False)
    assert CONFIGURATIONS["lazy-smt-window"] == LazyOptions(timed_route=False)
    assert CONFIGURATIONS["lazy-smt-minimal"] == LazyOptions(horizon_search="minimal", exact_segments=False)


def test_the_minimal_configuration_proves_maze_1s_horizon() -> None:
    r = solve(maze(1), "lazy-smt-minimal")
    assert r.status.value == "found" and r.validated is True and r.horizon == 57
    # the bench's configuration keeps one region per step: the claim is through the
    # decomposition (--prove asks for the claim about the problem)
    assert r.counters["minimal"] is True and r.counters["minimal_relative_to"] == "decomposition"
    assert r.counters["transitions"] == "regions"
    assert r.options["horizon_search"] == "minimal"


def test_the_counterexample_names_agree_with_conplan() -> None:
    from plansynth.reach.lazy import conplan

    assert COUNTEREXAMPLES == ("farkas", *conplan.COUNTEREXAMPLES)


def test_every_planner_has_a_name_a_version_and_options() -> None:
    for name in planners():
        p = get_planner(name)
        assert p.name == name
        assert p.version().split()[0] in {"python-sat", "highspy", "ompl", "drake", "fastpathplanning"}
        assert p.defaults is not None or p.mission_defaults is not None
        for mission, value in ((False, p.defaults), (True, p.mission_defaults)):
            if value is not None:
                assert dataclasses.is_dataclass(value) and p.configure(mission=mission) == value
        assert set(SHARED_OPTIONS) & set(p.option_names()) or name in ("milp-bigm", "rrt", "est", "kpiece")


def test_a_planners_version_names_every_solver_it_calls() -> None:
    """The lazy planner and its configurations (DIS-PLAN in CaDiCaL, CON-PLAN in HiGHS)
    report both packages; the mission MILP reports HiGHS; solve() records the version of
    the registered planner that ran, with its name (not the name of its loop)."""
    for name in ("lazy-smt", "lazy-smt-paper", "lazy-smt-minimal"):
        version = get_planner(name).version()
        assert version.startswith("python-sat") and ", highspy" in version, version
    assert get_planner("milp-ltl").version().startswith("highspy")
    r = solve(maze(1), "lazy-smt-paper", Budget(seconds=60))
    assert (r.solver, r.planner, r.solver_version) == (
        "lazy-smt-paper",
        "lazy-smt-paper",
        get_planner("lazy-smt-paper").version(),
    )
    record = r.to_json_dict()
    assert record["solver"] == record["planner"] == "lazy-smt-paper"
    assert record["solver_version"] == r.solver_version and "versions" in record
    assert record["options"]["counterexample"] == "zeroprefix" and record["seconds"] == r.seconds


def test_every_options_field_has_a_help_line() -> None:
    from plansynth.options import describe

    for name in planners():
        p = get_planner(name)
        for value in (p.defaults, p.mission_defaults):
            if value is not None:
                assert all(doc for _, _, doc in describe(value)), (name, type(value).__name__)


def test_an_option_the_planner_does_not_take_is_an_error_not_dropped() -> None:
    with pytest.raises(InvalidOption, match="milp: option 'counterexample': not an option"):
        configure("milp", counterexample="trivial")
    with pytest.raises(InvalidOption, match="lazy-smt-zeroprefix: option 'counterexample'.*fixed"):
        solve(maze(1), "lazy-smt-zeroprefix", counterexample="trivial")
    with pytest.raises(InvalidOption, match="rrt: option 'max_horizon'"):
        solve(maze(1), "rrt", Budget(seconds=1), max_horizon=10)
    with pytest.raises(InvalidOption, match="expected MilpOptions, got LazyOptions"):
        solve(maze(1), "milp", Budget(seconds=1), LazyOptions())


def test_named_configurations_take_the_shared_options() -> None:
    opts = configure("lazy-smt-paper", max_horizon=70, segment_safe=False)
    assert opts == LazyOptions.paper(max_horizon=70, segment_safe=False)


def test_solve_records_the_options_value_it_was_given() -> None:
    r = solve(maze(1), "lazy-smt", Budget(seconds=60), LazyOptions(counterexample="trivial", generalize=False))
    assert r.status is ReachStatus.FOUND and r.validated is True
    assert r.options["counterexample"] == "trivial" and r.options["generalize"] is False
    same = solve(maze(1), "lazy-smt", Budget(seconds=60), counterexample="trivial", generalize=False)
    assert (same.horizon, same.counters["lp_calls"], same.counters["sat_calls"]) == (
        r.horizon,
        r.counters["lp_calls"],
        r.counters["sat_calls"],
    )


def test_planners_do_not_validate_solve_does() -> None:
    from plansynth.reach.planners.baselines import MILP

    raw = MILP.solve(maze(1), Budget(seconds=60), configure("milp", max_horizon=57, start_horizon=57))
    assert raw.status is ReachStatus.FOUND and raw.validated is None
    checked = solve(maze(1), "milp", Budget(seconds=60), max_horizon=57, start_horizon=57)
    assert checked.validated is True and checked.validation is not None and checked.validation.ok


def test_an_option_of_reach_avoid_planning_given_for_a_mission_is_an_error() -> None:
    from plansynth.reach.mission.families import mission_problem

    p = mission_problem("maze-1", "visit")
    with pytest.raises(
        InvalidOption,
        match="lazy-smt: option 'counterexample': not an option of this planner for a "
        "problem with a mission; its options: max_horizon, semantics",
    ):
        solve(p, "lazy-smt", Budget(seconds=30), counterexample="trivial")
    with pytest.raises(InvalidOption, match="option 'counterexample': not an option .* with a mission"):
        solve(p, "lazy-smt", Budget(seconds=30), LazyOptions(counterexample="trivial"))  # (bench's options value)
    r = solve(p, "lazy-smt", Budget(seconds=60), transit=False)  # a mission option goes through
    assert r.status is ReachStatus.FOUND and r.options.get("transit") is False
    # the reach-avoid options value's shared fields carry over to the mission's
    r = solve(p, "lazy-smt", Budget(seconds=60), LazyOptions(max_horizon=40), semantics="finite")
    assert r.status is ReachStatus.FOUND and r.options["max_horizon"] == 40 and r.options["semantics"] == "finite"
    assert r.mission["semantics"] == "finite" and r.solver == "lazy-smt"


def test_missions_run_through_the_lazy_planner_object_and_the_one_loop(monkeypatch) -> None:
    """lazy-smt plans a mission with the same planner object (MissionOptions) and the one
    lazy loop; the named configurations that make sense for missions take them too, and
    the others, like the reach-avoid baselines, refuse a mission (one error naming the
    mission planners)."""
    from plansynth.reach.lazy import loop
    from plansynth.reach.mission.families import mission_problem
    from plansynth.reach.mission.options import MissionOptions

    p = mission_problem("maze-1", "avoid-until")
    assert get_planner("lazy-smt").configure(mission=True) == MissionOptions()
    calls = []
    original = loop.lazy_loop

    def counted(*args, **kwargs):
        calls.append(type(args[0]).__name__)
        return original(*args, **kwargs)

    monkeypatch.setattr(loop, "lazy_loop", counted)
    import plansynth.reach.mission.planner as mission_planner

    monkeypatch.setattr(mission_planner, "lazy_loop", counted)
    r = solve(p, "lazy-smt-minimal", Budget(seconds=60))
    assert r.status is ReachStatus.FOUND and r.horizon == 30 and r.mission["ok"] is True
    assert r.solver == "lazy-smt-minimal" and calls == ["MissionDisPlan"]
    with pytest.raises(
        InvalidOption,
        match="lazy-smt-paper: option 'planner': does not plan LTL missions "
        r"\(mission planners: lazy-smt, lazy-smt-minimal, milp-ltl",
    ):
        solve(p, "lazy-smt-paper", Budget(seconds=30))
    with pytest.raises(InvalidOption, match="milp: option 'planner': does not plan LTL missions"):
        solve(p, "milp", Budget(seconds=30))
    with pytest.raises(
        InvalidOption, match="milp-ltl: option 'planner': plans LTL missions, and this problem has none"
    ):
        solve(maze(1), "milp-ltl", Budget(seconds=30))


def test_a_decomposition_computed_before_is_an_input_of_the_planners_over_it() -> None:
    from plansynth.reach.abstraction import abstract

    p = maze(1)
    ab = abstract(p)
    for name in ("lazy-smt", "milp"):
        r = solve(p, name, Budget(seconds=60), abstraction=ab, max_horizon=60)
        assert r.status is ReachStatus.FOUND and r.timings.get("abstraction", 0.0) == 0.0, name
    with pytest.raises(InvalidOption, match="rrt: option 'abstraction'"):
        solve(p, "rrt", Budget(seconds=1), abstraction=ab)
