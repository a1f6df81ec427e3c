"""Runs for inspection (plansynth.grid.simulate) and their pictures (plansynth.grid.render)."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.figure import Figure
from PIL import Image

from plansynth.grid.problem import GridProblem, grid_problem_from_dict, load_grid_problem
from plansynth.grid.programs import Term, evaluate, parse_program
from plansynth.grid.render import HOLD_FRAMES, animate, draw_state
from plansynth.grid.semantics import initial_state, obstacle_move, robot_move, step
from plansynth.grid.simulate import Collision, Run, simulate
from plansynth.grid.verify import verify

from .strategies import problems_and_programs

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "grid"
WINNER = parse_program("(ite (<= rx 3) 2 1)")
LOSER = parse_program("(ite (<= rx 1) 2 1)")


@pytest.fixture(scope="module")
def figure1() -> GridProblem:
    return load_grid_problem(EXAMPLES / "figure1.yaml")


def check_run(p: GridProblem, program: Term, run: Run) -> None:
    """The run is the program's, step by step, and stops at its first collision."""
    assert run.states[0] == initial_state(p)
    n = len(run.robot_moves)
    assert len(run.states) == n + 1 == len(run.obstacle_moves) + 1 and n <= run.steps
    for t in range(n):
        assert run.robot_moves[t] == evaluate(program, dict(zip(p.variables, run.states[t].inputs())))
        out = step(p, run.states[t], run.robot_moves[t], run.obstacle_moves[t])
        assert out.state == run.states[t + 1]
        if out.collided:
            assert t == n - 1 and run.collision is not None and run.collision.step == t
    if run.collision is None:
        assert n == run.steps
        assert run.on_goal == (run.states[-1].robot == p.robot.goal)
    else:
        assert not run.on_goal


# -- simulate ---------------------------------------------------------------------------------


def test_adversarial_run_of_a_losing_controller_is_the_counterexample(figure1: GridProblem) -> None:
    run = simulate(figure1, LOSER, 6)
    cex = verify(figure1, LOSER, 6).counterexample
    assert not run.wins and run.mode == "adversarial"
    assert (run.states, run.robot_moves, run.obstacle_moves) == (cex.states, cex.robot_moves, cex.obstacle_moves)
    assert run.collision == Collision(2, (2, 3), 0)
    assert run.outcome == cex.reason == "collision at step 2 in cell (2, 3) with obstacle 0"
    check_run(figure1, LOSER, run)


def test_adversarial_run_of_a_winning_controller_presses_the_robot(figure1: GridProblem) -> None:
    run = simulate(figure1, WINNER, 6)
    assert run.wins and run.on_goal and run.collision is None
    assert run.outcome == "on the goal (4, 4) after step 5"
    check_run(figure1, WINNER, run)
    for t, state in enumerate(run.states[:-1]):  # every obstacle took a move ending nearest the robot
        rx, ry = robot_move(figure1, state.robot, run.robot_moves[t])[0]
        for i, (c, j) in enumerate(zip(state.obstacles, run.obstacle_moves[t])):

            def d(k: int) -> int:
                x, y = obstacle_move(figure1, i, c, k)[0]
                return abs(x - rx) + abs(y - ry)

            assert d(j) == min(d(k) for k in range(len(figure1.obstacles[i].moves)))
    assert run.states[3].obstacles == ((2, 2), (3, 2))  # they came down to meet it


def test_random_runs_are_seeded(figure1: GridProblem) -> None:
    a = simulate(figure1, LOSER, 6, obstacles="random", seed=1)
    b = simulate(figure1, LOSER, 6, obstacles="random", seed=1)
    assert a == b and a.mode == "random"
    runs = {simulate(figure1, LOSER, 6, obstacles="random", seed=s).obstacle_moves for s in range(6)}
    assert len(runs) > 1
    for s in range(6):
        check_run(figure1, LOSER, simulate(figure1, LOSER, 6, obstacles="random", seed=s))


def test_simulate_rejects_unknown_modes(figure1: GridProblem) -> None:
    with pytest.raises(ValueError, match="obstacles must be one of adversarial, random"):
        simulate(figure1, WINNER, 6, obstacles="lazy")


@settings(max_examples=80)
@given(problems_and_programs(max_depth=5), st.integers(0, 3))
def test_a_winning_controller_wins_every_simulated_run(pp: tuple[GridProblem, Term], seed: int) -> None:
    p, program = pp
    wins = verify(p, program, p.steps).wins
    for mode in ("adversarial", "random"):
        run = simulate(p, program, p.steps, obstacles=mode, seed=seed)
        check_run(p, program, run)
        assert run.wins == wins
        if wins:
            assert run.on_goal, (mode, run.outcome)
        elif mode == "adversarial":
            assert not run.on_goal


# -- render ----------------------------------------------------------------------------------


def test_draw_state_writes_a_png(tmp_path: Path, figure1: GridProblem) -> None:
    run = simulate(figure1, WINNER, 6)
    fig = draw_state(figure1, run, 2, tmp_path / "s.png")
    assert isinstance(fig, Figure)
    title = fig.axes[0].get_title(loc="left")
    assert "figure1: l = 6, controller wins (adversarial obstacles)" in title
    assert "step 2 of 6: robot right | o0 down, o1 down" in title
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert texts.count("0") == 1 and texts.count("1") == 1 and "goal" in texts  # numbered obstacles
    with Image.open(tmp_path / "s.png") as im:
        assert im.format == "PNG"
        colours = {c for _, c in im.convert("RGB").getcolors(1 << 20)}
    assert (0x1F, 0x5F, 0xBF) in colours  # the robot is drawn


def test_last_frame_states_the_outcome_and_marks_the_collision(figure1: GridProblem) -> None:
    run = simulate(figure1, LOSER, 6)
    fig = draw_state(figure1, run, len(run.states) - 1)
    ax = fig.axes[0]
    assert "after step 2: collision at step 2 in cell (2, 3) with obstacle 0" in ax.get_title(loc="left")
    cross = [l for l in ax.lines if l.get_color() == "black"]
    assert len(cross) == 2
    xs = sorted(x for l in cross for x in l.get_xdata())
    assert xs[0] == pytest.approx(2.05) and xs[-1] == pytest.approx(2.95)  # on cell (2, 3)


def test_walls_are_drawn_and_steps_are_checked(tmp_path: Path) -> None:
    p = grid_problem_from_dict(
        {"grid": [3, 2], "robot": {"start": [0, 0], "goal": [2, 0], "moves": ["stay", "right"]}, "walls": [[1, 1]]}
    )
    run = simulate(p, parse_program("1"), 2)
    fig = draw_state(p, run, 0)
    assert any(len(c.get_paths()) == 1 and c.get_facecolor()[0][0] < 0.3 for c in fig.axes[0].collections[1:])
    with pytest.raises(ValueError, match="step 3 is not in 0..2"):
        draw_state(p, run, 3)


def test_animate_writes_a_gif_with_a_frame_per_state(tmp_path: Path, figure1: GridProblem) -> None:
    run = simulate(figure1, LOSER, 6)
    out = animate(figure1, run, tmp_path / "run.gif", fps=4)
    with Image.open(out) as im:
        assert im.format == "GIF"
        # Pillow merges identical consecutive frames, so the held last frame may count once.
        assert len(run.states) <= im.n_frames <= len(run.states) + HOLD_FRAMES
        assert im.n_frames > 1
    with pytest.raises(ValueError, match="fps must be positive"):
        animate(figure1, run, tmp_path / "x.gif", fps=0)


def test_large_grids_render(tmp_path: Path) -> None:
    p = load_grid_problem(EXAMPLES / "scale64.yaml")
    run = simulate(p, parse_program("(ite (<= 32 rx) 1 2)"), 60)
    assert run.on_goal
    fig = draw_state(p, run, 20, tmp_path / "big.png")
    assert fig.get_figwidth() <= 9 and "... (8 obstacles)" in fig.axes[0].get_title(loc="left")
