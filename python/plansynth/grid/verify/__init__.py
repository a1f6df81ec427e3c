"""The independent verifier: does a controller win a grid problem at exactly l steps?

A controller wins for path length l if, for every behaviour of the obstacles, the robot
never collides in steps 0..l-1 and stands on the goal after step l-1 (spec:
grid-problem.md, Semantics; Chasins & Newcomb, SYNT 2016, Section 3.1). This package
decides that exactly, using only :mod:`plansynth.grid.semantics` (the single definition
of a step) and :mod:`plansynth.grid.programs` (evaluation). Every program a solver
reports is checked here before it is called realizable.

Enumerating the obstacles' joint choices is hopeless on the paper's families (2^50 per
step for obstacles-50), so the verifier uses three reductions that preserve exactness.
There is no alternation to preserve: the program is fixed, so the question is whether
*some* obstacle behaviour makes the robot lose.

1. **Only read obstacles steer the robot.** The robot's next move is a function of the
   inputs the program reads (:func:`~plansynth.grid.programs.variables_of`). The robot
   and the obstacles the program reads are explored jointly, depth first, with every
   abstract state already shown safe remembered.
2. **Unread obstacles are independent of everything.** An obstacle the program never
   reads cannot influence the robot, nor can the other obstacles influence it. So it
   can collide at step t iff some cell it can occupy at time t (its t-step reachable
   set) has a move whose swept cells meet the robot's swept cells at step t. Those sets
   are computed once per obstacle, and their swept cells are merged into one "danger"
   bitmask per step.
3. **Read obstacles are tracked as sets, split only where the program looks.** Given
   the robot's moves so far, the read obstacles' possible cells form a product of one
   set per obstacle (they move independently, and the image of a product under their
   moves is a product). The program's choice is evaluated on the sets with interval
   arithmetic; where a comparison is undecided, the sets are split on it until the
   choice is constant on each part. On a part, a read obstacle can collide iff one of
   its cells has a move meeting the robot's swept cells, as in 2. A program that
   compares against a threshold (``(<= o0y 3)``) splits a set in two; only relational
   comparisons between obstacles (``(<= o0y o1y)``) approach explicit enumeration.

Two shortcuts only make losses cheaper to find: a robot farther from the goal (in robot
moves, obstacles ignored) than the steps left has lost whatever the obstacles do, and a
short depth-first probe (:data:`~.search.PROBE_NODES` expansions, obstacles nearest the robot
first) runs before the exhaustive layered search. Move tables are filled lazily from
:func:`~plansynth.grid.semantics.robot_move` and
:func:`~plansynth.grid.semantics.obstacle_move`, so a 64 x 64 grid costs only the cells
visited.

When the controller loses, the verdict carries a concrete :class:`Counterexample`: the
obstacles' joint moves, the states visited and the program's choices, which replay
through :func:`~plansynth.grid.semantics.step` to the loss it describes.

**Budgets** (STYLE.md, point 4). Without a budget the verifier is complete and answers
``wins`` or ``loses``. With a :class:`~plansynth.budget.Budget` it stops once the time or
the memory is used up and answers ``unknown`` with the phase and the reason, never a
guessed ``wins``/``loses``. Memory is what the process gains while verifying (its
resident set, checked every few thousand cells of work) and defaults to
:data:`plansynth.budget.DEFAULT_MEMORY_MB` when a budget gives none. The per-cell data is kept small so
that a large grid costs only what the search touches: move tables are filled lazily
(end cell, swept cells as indices), the unread obstacles' reachable cells are advanced
one step at a time (only the current set is kept; a set sequence that becomes periodic,
as they do once an obstacle's reach saturates, is not recomputed) and each step's
danger is a packed bitmap. On a large grid the tables and sets are numpy arrays; on a
small one (:data:`PYTHON_CELLS`) they are dicts and integer bitsets, so that verifying
a small problem does not import numpy (a tenth of a second of a ``plansynth grid
solve``); both give the same verdicts and counterexamples (tests/grid/test_verify.py).

Modules, bottom up: :mod:`.verdict` (the answer), :mod:`.controller` (the program's
grammar and the obstacles it reads), :mod:`.meter` (the budget, read cheaply),
:mod:`.tables` (what the search asks of move tables and reachable sets),
:mod:`.python_tables` and :mod:`.numpy_tables` (the two representations),
:mod:`.intervals` (the program's choice on a box of inputs), :mod:`.products` (the read
obstacles' product sets, split and merged), :mod:`.search` (the probe and the layered
search), :mod:`.replay` (runs through the semantics, and why they lose),
:mod:`.counterexample` (a loss as a concrete run) and :mod:`.decide` (:func:`verify`).

>>> from plansynth.budget import Budget
>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.programs import parse_program
>>> p = grid_problem_from_dict({"grid": [4, 1],
...     "robot": {"start": [0, 0], "goal": [3, 0], "moves": ["stay", "right"]},
...     "obstacles": [{"start": [3, 0], "moves": ["stay", "left"]}]})
>>> verify(p, parse_program("1"), 3).wins
False
>>> print(verify(p, parse_program("1"), 3).counterexample.reason)
collision at step 1 in cell (2, 0) with obstacle 0
>>> verify(p, parse_program("1"), 3, budget=Budget(seconds=60)).status.value
'loses'
"""

from plansynth.grid.programs import ProgramSyntaxError
from plansynth.grid.verify.controller import check_controller, read_obstacles
from plansynth.grid.verify.decide import PYTHON_CELLS, PYTHON_OBSTACLES, verify
from plansynth.grid.verify.replay import collision_reason
from plansynth.grid.verify.search import PROBE_NODES
from plansynth.grid.verify.verdict import Counterexample, Verdict, VerdictUnknown, VerifyStatus

__all__ = [
    "Counterexample",
    "PROBE_NODES",
    "PYTHON_CELLS",
    "PYTHON_OBSTACLES",
    "ProgramSyntaxError",
    "Verdict",
    "VerdictUnknown",
    "VerifyStatus",
    "check_controller",
    "collision_reason",
    "read_obstacles",
    "verify",
]
