"""The native engine on every objective: its answer equals the brute-force oracle's on
random small problems, every program it returns passes the objective's verifier, and
every "no" carries the obstacles' strategy, checked against every robot move
(plansynth.grid.native.product)."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, reject, settings
from hypothesis import strategies as st

from plansynth.budget import Budget
from plansynth.grid.native.engine import Engine
from plansynth.grid.native.product.certify import check_refutation
from plansynth.grid.oracle import TooLarge, brute_force
from plansynth.grid.problem import grid_problem_from_dict
from plansynth.grid.result import GridStatus
from plansynth.grid.semantics import joint_choices
from plansynth.grid.solve import solve
from plansynth.grid.verify import VerifyStatus, verify

from .strategies import OBJECTIVES, objective_problems

SETTINGS = settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def check_answer(problem):
    out = Engine().solve_length(problem, problem.steps, Budget(seconds=60))
    try:
        oracle = brute_force(problem, problem.steps, limit=3000)
    except TooLarge:  # the exact objective's backtracking over positional strategies
        reject()
    if out.status is GridStatus.UNKNOWN:
        # only the exact objective's positional read-off may leave a won game undecided
        assert problem.objective.value == "exact" and oracle is GridStatus.REALIZABLE, out.message
        return out
    assert out.status is oracle, out.message
    if out.status is GridStatus.REALIZABLE:
        assert verify(problem, out.program, problem.steps).status is VerifyStatus.WINS
    else:
        ref = out.witness
        if ref is not None and hasattr(ref, "strategy"):  # the product engine's certificate, checked again
            assert check_refutation(problem, ref.strategy, problem.steps).valid
    return out


@pytest.mark.parametrize("objective", OBJECTIVES)
@SETTINGS
@given(data=st.data())
def test_engine_agrees_with_the_oracle(objective, data):
    check_answer(data.draw(objective_problems(objective)))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_two_obstacles_and_the_fairness_counter(data):
    check_answer(data.draw(objective_problems(max_obstacles=2, max_side=3)))


CORRIDOR = {
    "grid": [3, 3],
    "objective": "recurrence",
    "collision": "position",
    "walls": [[1, 0]],
    "robot": {"start": [0, 1], "goals": [[2, 1], [0, 1]], "moves": ["stay", "right", "left"]},
    "obstacles": [{"start": [1, 1], "moves": ["stay", "up", "down"], "period": 2}],
}


def test_fairness_decides_the_corridor():
    """The obstacle guards the only crossing. It may sit there forever, unless it is
    assumed to move infinitely often: then the robot slips through while it rests."""
    unfair = solve(grid_problem_from_dict(CORRIDOR), "native", Budget(seconds=60))
    assert unfair.status is GridStatus.UNREALIZABLE and unfair.steps is None
    assert "certified" in unfair.attempts[0].message
    fair = solve(grid_problem_from_dict({**CORRIDOR, "fair": True}), "native", Budget(seconds=60))
    assert fair.status is GridStatus.REALIZABLE and fair.verified is True
    assert "m" in str(fair.program) or "o0" in str(fair.program)


def test_a_wrong_strategy_is_rejected():
    p = grid_problem_from_dict(
        {**CORRIDOR, "objective": "safety", "robot": {"start": [0, 1], "moves": ["stay", "right"]}}
    )

    def lazy(state, k, t):  # never moves: the robot is safe by staying
        return next(j for j in joint_choices(p, state) if j == (0,))

    cert = check_refutation(p, lazy, None)
    assert not cert.valid and "cycle" in cert.reason


def test_sygus_backends_refuse_the_new_objectives():
    p = grid_problem_from_dict(CORRIDOR)
    out = solve(p, "cvc5", Budget(seconds=10))
    assert out.status is GridStatus.UNKNOWN and "covers the objective exact only" in out.message


# -- the compiled safety game and the inductive-invariant check ------------------------

from plansynth.grid.native.options import NativeOptions  # noqa: E402
from plansynth.grid.native.product import fixpoints  # noqa: E402
from plansynth.grid.native.product.compiled import CompiledSafety  # noqa: E402
from plansynth.grid.native.product.space import ProductSpace  # noqa: E402
from plansynth.grid.oracle import game_graph  # noqa: E402
from plansynth.grid.programs import compile_program  # noqa: E402
from plansynth.grid.semantics import controller_inputs  # noqa: E402
from plansynth.grid.verify.invariant import check_invariant, state_key  # noqa: E402

from .strategies import programs  # noqa: E402


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_compiled_safety_equals_the_reference(data):
    """The core's configurations, winning sets and ranks are the reference's."""
    problem = data.draw(objective_problems("safety", max_obstacles=2, max_side=4))
    space = ProductSpace.explore(problem)
    ref = fixpoints.safety(space)
    game = CompiledSafety(problem, None, None)
    won = game.solve()
    assert game.n_configs == space.n_configs
    index = {c: i for i, c in enumerate(space.configs)}
    for oc in range(game.n_configs):
        i = index[game.config_key(oc)]
        assert game.winning(oc) == ref.win[i]
        n = problem.width * problem.height
        for r in range(n):
            rank = ref.rank(r, i)
            assert game.core.rank(oc, r) == (0 if rank is None else rank + 1) or not (ref.space.robot.full >> r & 1)
    r0, n0 = space.start()
    assert won == ref.wins(r0, n0)
    python = Engine(NativeOptions(use_rust=False)).solve_length(problem, None, Budget(seconds=60))
    compiled = Engine().solve_length(problem, None, Budget(seconds=60))
    assert python.status is compiled.status


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_the_invariant_check_accepts_exactly_inductive_sets(data):
    """A winning program's closed loop is an inductive invariant (accepted); a losing
    program's is not (never accepted)."""
    problem = data.draw(objective_problems("safety"))
    program = data.draw(programs(problem, 5))
    f = compile_program(program, problem.variables)
    graph = game_graph(problem, 50_000, lambda s: f(*controller_inputs(problem, s)))
    invariant: dict = {}
    for s in graph:
        key = state_key(problem, s)
        invariant[key] = invariant.get(key, 0) | 1 << (s.robot[1] * problem.width + s.robot[0])
    wins = brute_force(problem, controller=lambda s: f(*controller_inputs(problem, s))) is GridStatus.REALIZABLE
    verdict = check_invariant(problem, program, invariant)
    assert (verdict.status is VerifyStatus.WINS) == wins, verdict.message
    # the same verdict a few states at a time (a chunk of configurations holds at least one)
    from plansynth.grid.verify import invariant as module

    saved, module.CHUNK_STATES = module.CHUNK_STATES, data.draw(st.integers(1, 5))
    try:
        assert check_invariant(problem, program, invariant).status is verdict.status
    finally:
        module.CHUNK_STATES = saved


@settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(data=st.data())
def test_the_compiled_invariant_check_equals_numpy(data, monkeypatch):
    """The core's invariant check (on one or two threads) gives the numpy reference's
    verdict, on closed loops and on sets with states added or dropped."""
    problem = data.draw(objective_problems("safety"))
    program = data.draw(programs(problem, 5))
    f = compile_program(program, problem.variables)
    graph = game_graph(problem, 50_000, lambda s: f(*controller_inputs(problem, s)))
    invariant: dict = {}
    for s in graph:
        key = state_key(problem, s)
        invariant[key] = invariant.get(key, 0) | 1 << (s.robot[1] * problem.width + s.robot[0])
    keys = sorted(invariant)
    n = problem.width * problem.height
    for _ in range(data.draw(st.integers(0, 3))):
        key = data.draw(st.sampled_from(keys))
        invariant[key] ^= 1 << data.draw(st.integers(0, n - 1))  # a state added or dropped
    reference = check_invariant(problem, program, invariant, compiled=False)
    monkeypatch.setenv("PLANSYNTH_THREADS", data.draw(st.sampled_from(["1", "2"])))
    compiled = check_invariant(problem, program, invariant, compiled=True)
    assert compiled.status is reference.status, (compiled.message, reference.message)
    if reference.status is VerifyStatus.WINS:
        assert compiled.states_explored == reference.states_explored


def test_the_engine_hands_the_verifier_an_invariant():
    from plansynth.grid.syntcomp.moving_obstacle import grid_document

    problem = grid_problem_from_dict(grid_document(8, 0))
    out = Engine().solve_length(problem, None, Budget(seconds=120))
    assert out.status is GridStatus.REALIZABLE and isinstance(out.witness, dict)
    assert check_invariant(problem, out.program, out.witness).status is VerifyStatus.WINS
    result = solve(problem, "native", Budget(seconds=120))
    assert result.verified is True
    assert "an inductive invariant of" in result.message  # not a search of the closed loop


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_tabulated_replies_equal_the_rules(data):
    """The invariant check's obstacle replies (per cell tabulated) are those of playing
    every joint move through the semantics' step, in states of random walks."""
    from plansynth.grid.semantics import initial_state, step
    from plansynth.grid.verify.replies import ObstacleReplies, replies_by_step

    problem = data.draw(objective_problems("safety", max_obstacles=2))
    by = ObstacleReplies(problem)
    s = initial_state(problem)
    for _ in range(data.draw(st.integers(1, 8))):
        assert sorted(by.of(s)) == sorted(replies_by_step(problem, s))
        joints = list(joint_choices(problem, s))
        s = step(problem, s, 0, data.draw(st.sampled_from(joints))).state


def _projected_winning(game: CompiledSafety) -> set[tuple]:
    """The reference of the core's seeded sample: per class of configurations equal but
    for their glitches left, the inputs (glitches read as 0) of every robot cell from
    which some member of the class wins."""
    problem = game.problem
    w = problem.width
    out: set[tuple] = set()
    for oc in range(game.n_configs):
        mask = game.winning(oc)
        key = tuple(((c, p, 0) for c, p, _ in game.config_key(oc)))
        for r in range(problem.width * problem.height):
            if mask >> r & 1:
                out.add((key, (r % w, r // w)))
    return out


def _central(problem, cell, allowed: int) -> int:
    """The reference of the core's central labels: the moves of ``allowed`` whose end
    (:func:`~plansynth.grid.semantics.robot_end`) is nearest the middle, in the max norm."""
    from plansynth.grid.semantics import robot_end

    def dist(k: int) -> int:
        x, y = robot_end(problem, cell, k)
        return max(abs(2 * x - (problem.width - 1)), abs(2 * y - (problem.height - 1)))

    ks = [k for k in range(len(problem.robot.moves)) if allowed >> k & 1]
    best = min(dist(k) for k in ks)
    return sum(1 << k for k in ks if dist(k) == best)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_the_seeded_learner_closes_in_one_round(data):
    """Seeded with every winning state of its glitch-projected game (compared with the
    reference above), the learner's first tree closes, and its program wins."""
    problem = data.draw(objective_problems("safety", max_obstacles=2, max_side=4))
    game = CompiledSafety(problem, None, None)
    if not game.solve():
        reject()
    if any(o.glitching for o in problem.obstacles):
        game.core.project_glitches()
    seeded = game.core.seed_winning(10_000)
    assert seeded is not None and game.core.seed_winning(seeded - 1) is None
    rows = game.core.sample()
    assert len(rows) == seeded
    assert game.core.sample_labels() == [a for _, a in rows]  # on cell sets, as per state
    index = {v: i for i, v in enumerate(problem.variables)}
    got = set()
    for x, allowed in rows:
        assert allowed
        cells, j = [], 2
        for o in problem.obstacles:
            cell = (x[j], x[j + 1])
            j += 2
            phase = x[j] if o.periodic else 0
            j += o.periodic
            assert not o.glitching or x[j] == 0
            j += o.glitching
            cells.append((cell, phase, 0))
        got.add((tuple(cells), (x[index["rx"]], x[index["ry"]])))
    assert got == _projected_winning(game)
    if data.draw(st.booleans()):
        # labels of the moves that end nearest the middle only (compared with the rules)
        game.core.prefer_central(True)
        central = game.core.sample()
        for (x, allowed), (y, kept) in zip(rows, central, strict=True):
            assert x == y and kept == _central(problem, (x[0], x[1]), allowed)
        assert game.core.sample_labels() == [a for _, a in central]
    closed, _, _, program, _ = game.learn_round(3, 1_000_000, 20_000)
    assert closed
    assert verify(problem, program, None).status is VerifyStatus.WINS
