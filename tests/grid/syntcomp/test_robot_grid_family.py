"""The robot-grid family (after SYNTCOMP's ``tlsf/robot_grid`` maps): the embedded maps
are the TLSF files' maps, the native engine solves them with verified programs that read
the mode (a slow obstacle) or a certified "no" with explain's reason (an obstacle that
moves every step), and omega (the peer) agrees."""

from __future__ import annotations

from pathlib import Path

import pytest

from plansynth.budget import Budget
from plansynth.grid.native.explain import explain
from plansynth.grid.native.product.witness import check_product_play
from plansynth.grid.problem import grid_problem_from_dict
from plansynth.grid.result import GridStatus
from plansynth.grid.solve import solve
from plansynth.grid.syntcomp.robot_grid import grid_document, read
from plansynth.grid.syntcomp.robot_grid_maps import MAPS, map_document

DATA = Path(__file__).parent / "data" / "robot_grid"


@pytest.mark.parametrize("i", range(1, 9))
def test_the_embedded_maps_are_the_files(i):
    m = read(DATA / f"gr_{i}.tlsf.gz")
    assert MAPS[f"gr_{i}"] == m.render()
    from_file = grid_document(m)
    from_file["obstacles"][0]["keep_out"] = sorted(from_file["obstacles"][0]["keep_out"])
    assert map_document(f"gr_{i}") == from_file


def test_a_slow_obstacle_is_beaten_by_a_program_that_reads_the_mode():
    problem = grid_problem_from_dict(map_document("gr_2"))
    result = solve(problem, "native", Budget(seconds=120))
    assert result.status is GridStatus.REALIZABLE and result.verified is True
    assert "m" in {v.name for v in _vars(result.program)}


def test_a_fast_obstacle_blocks_the_corridor_certified():
    problem = grid_problem_from_dict(map_document("gr_2", period=1))
    result = solve(problem, "native", Budget(seconds=120))
    assert result.status is GridStatus.UNREALIZABLE
    assert "certified" in result.attempts[0].message
    e = explain(problem, None, Budget(seconds=120))
    assert e.kind == "game" and e.loop is not None or "collision" in e.play[-1].reason
    assert check_product_play(problem, e.play, e.loop, None)


def test_omega_agrees():
    # omega and dd come with the baselines extra, which setup installs: no skip here
    from plansynth.grid.syntcomp.omega_grid import synthesize

    for period, expected in ((2, GridStatus.REALIZABLE), (1, GridStatus.UNREALIZABLE)):
        status, _, _ = synthesize(grid_problem_from_dict(map_document("gr_1", period=period)), strategy=False)
        assert status is expected


def _vars(t):
    from plansynth.grid.programs import Var, subterms

    return [s for s in subterms(t) if isinstance(s, Var)]
