"""The winning states of each objective on the product game, as fixpoints over robot-cell
bit sets (the pure-Python reference; the compiled core runs the same iterations).

One operator does the work. For a node (configuration, mode, fairness counter) and, per
obstacle reply j, a set ``target(j)`` of robot cells the reply must find the robot in,
:func:`controllable` gives per robot move k the cells from which k is safe against
every reply and ends in every ``target(j)`` (the controllable predecessor of safety and
reachability games; Thomas, STACS 1995). Collisions enter as ``danger`` (``sweep``: the
move must sweep none of the cells any reply sweeps, exact because the obstacles move
independently) or as the successor's ``blocks`` (``position``). Moves that sweep a wall
are never safe. The arrival on the awaited goal (recurrence) or on the goal (reach) is a
property of the robot's end cell, so a target is assembled per cell class.

* :func:`safety`: the greatest fixpoint ``nu W. Cpre(W)``; the round at which a state
  leaves it is its *rank*: the obstacles force a collision within that many steps.
* :func:`reach`: the least fixpoint ``mu A. goal | Cpre(A)`` iterated l times; the
  round a state enters is its rank (the steps to the goal).
* :func:`recurrence`: the Büchi game ``nu Z. mu Y. Cpre(Y | arrive & Z)`` (Thomas 1995);
  under ``fair``, the GR(1) game with one assumption and one guarantee of Bloem et al.
  (JCSS 2012, Section 5): ``nu Z. mu Y. nu X. Cpre(arrive & Z | Y | !J & X)``, with J
  "the obstacle the fairness counter waits for changed cell" (the reduction of
  :mod:`plansynth.grid.objective`). The Y rounds of the last outer iteration rank the
  winning states: a state of rank r has a move into rank < r, or onto the goal into Z,
  or (fair) into rank r on a step without J.
* :func:`recurrence_dual`: the obstacles' side, ``mu Z'. nu Y'. mu X'. Epre(Z' | !arrive
  & J & Y' | !arrive & X')`` (the Rabin pair "the goal finitely often, J infinitely
  often"), whose ranks give the obstacles a positional winning strategy, the certificate
  of an unrealizable recurrence objective.

>>> from plansynth.grid.problem import grid_problem_from_dict
>>> from plansynth.grid.native.product.space import ProductSpace
>>> p = grid_problem_from_dict({"grid": [4, 1], "objective": "safety",
...     "robot": {"start": [0, 0], "moves": ["stay", "right", "left"]},
...     "obstacles": [{"start": [3, 0], "moves": ["stay", "left", "right"], "period": 2}]})
>>> sol = safety(ProductSpace.explore(p))
>>> sol.wins(*ProductSpace.explore(p).start())      # the obstacle corners the robot
False
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from plansynth.budget import Clock
from plansynth.grid.native.limits import check_clock
from plansynth.grid.native.product.space import ProductSpace

__all__ = ["Solution", "controllable", "environment_forces", "safety", "reach", "recurrence", "recurrence_dual"]

Target = Callable[[int, int], int]  # (reply index j, successor configuration) -> robot cells


@dataclass
class Solution:
    """Winning states of the robot (``win[node]``: a robot-cell mask per node) and the
    rounds of the last fixpoint that rank them (``layers[i][node]``: the cells of rank
    <= i). ``rounds`` counts every iteration of the operator."""

    space: ProductSpace
    win: list[int]
    layers: list[list[int]] = field(default_factory=list)
    rounds: int = 0
    outer: list[list[int]] = field(default_factory=list)  # recurrence: the final Z, kept for the moves

    def wins(self, r: int, node: int) -> bool:
        return bool(self.win[node] >> r & 1)

    def rank(self, r: int, node: int) -> int | None:
        """The first layer holding the state (None: in no layer)."""
        for i, layer in enumerate(self.layers):
            if layer[node] >> r & 1:
                return i
        return None


def controllable(space: ProductSpace, node: int, target: Target) -> list[int]:
    """Per robot move k: cells from which k is collision-free against every obstacle
    reply and ends in ``target(j, succ)`` for each reply j (see the module docstring)."""
    oc, _, _ = space.split(node)
    t_all = space.robot.full
    position = space.position
    for j, oc2 in enumerate(space.succ[oc]):
        t = target(j, oc2)
        if position:
            t &= ~space.blocks[oc2]
        t_all &= t
        if not t_all:
            break
    robot = space.robot
    out = []
    for k in range(len(robot.moves)):
        g = robot.pre(t_all, k)
        if not position and g:
            g &= ~robot.hit_sources(space.danger[oc], k)
        out.append(g)
    return out


def environment_forces(space: ProductSpace, node: int, target: Target) -> int:
    """Cells from which, for every robot move, some obstacle reply collides with it or
    finds it in ``target(j, succ)`` (the obstacles' controllable predecessor)."""
    oc, _, _ = space.split(node)
    robot = space.robot
    union = 0
    for j, oc2 in enumerate(space.succ[oc]):
        u = target(j, oc2)
        if space.position:
            u |= space.blocks[oc2]
        union |= u
    out = robot.full
    for k in range(len(robot.moves)):
        bad = ~robot.free[k] | robot.pre(union, k)
        if not space.position:
            bad |= robot.hit_sources(space.danger[oc], k)
        out &= bad
    return out & robot.full


def _arrive(space: ProductSpace, m: int) -> int:
    return space.goal_mask(m)


def _next_f(space: ProductSpace, f: int, changed: int) -> int:
    if space.F > 1 and changed >> f & 1:
        return (f + 1) % space.F
    return f


def _progress(space: ProductSpace, f: int, changed: int) -> bool:
    """J on this reply: the obstacle the fairness counter waits for changed cell (true
    for every reply without ``fair``, and when there is no obstacle)."""
    p = space.problem
    if not p.fair or not p.obstacles:
        return True
    return bool(changed >> f & 1)


def safety(space: ProductSpace, clock: Clock | None = None) -> Solution:
    """``nu W. Cpre(W)``; ``layers[i]`` hold the states *removed* in rounds <= i (rank:
    the obstacles force a collision within i + 1 steps)."""
    win = [_standing(space)] * space.n_nodes
    removed: list[list[int]] = []
    sol = Solution(space, win)
    while True:
        sol.rounds += 1
        new = []
        gone = [0] * space.n_nodes
        lost = False
        for node in range(space.n_nodes):
            oc, m, f = space.split(node)
            moves = controllable(
                space,
                node,
                lambda j, oc2, m=m, f=f, oc=oc, win=win: win[
                    space.node(oc2, m, _next_f(space, f, space.changed[oc][j]))
                ],
            )
            keep = win[node] & _or(moves)
            gone[node] = win[node] & ~keep
            lost |= bool(gone[node])
            new.append(keep)
        check_clock(clock, "the safety fixpoint", f" (round {sol.rounds})")
        if not lost:
            break
        prev = removed[-1] if removed else [0] * space.n_nodes
        removed.append([a | b for a, b in zip(prev, gone)])
        win = new
    sol.win = win
    sol.layers = removed
    return sol


def _standing(space: ProductSpace) -> int:
    """Robot cells that are not walls."""
    walls = 0
    for w in space.problem.walls:
        walls |= 1 << (w[1] * space.problem.width + w[0])
    return space.robot.full & ~walls


def _or(masks: list[int]) -> int:
    out = 0
    for x in masks:
        out |= x
    return out


def reach(space: ProductSpace, bound: int, clock: Clock | None = None) -> Solution:
    """``mu A. goal | Cpre(A)``, at most ``bound`` rounds; ``layers[i]``: rank <= i."""
    goal = space.goal_mask(0)
    standing = _standing(space)
    cur = [goal & standing] * space.n_nodes
    layers = [cur]
    sol = Solution(space, cur)
    for _ in range(bound):
        sol.rounds += 1
        new = []
        for node in range(space.n_nodes):
            oc, _, _ = space.split(node)
            moves = controllable(space, node, lambda j, oc2, cur=cur: cur[space.node(oc2)] | goal)
            new.append(cur[node] | (_or(moves) & standing))
        check_clock(clock, "the reachability fixpoint", f" (round {sol.rounds})")
        if new == cur:
            break
        cur = new
        layers.append(cur)
    sol.win, sol.layers = cur, layers
    return sol


def _recurrence_target(space: ProductSpace, node: int, z: list[int], y: list[int], x: list[int] | None) -> Target:
    """The target of one robot step in :func:`recurrence`: onto the awaited goal into Z
    (or Y, or X on a step without J), elsewhere into Y (or X on a step without J)."""
    oc, m, f = space.split(node)
    g = _arrive(space, m)
    m2 = (m + 1) % space.K

    def target(j: int, oc2: int) -> int:
        ch = space.changed[oc][j]
        f2 = _next_f(space, f, ch)
        here, there = space.node(oc2, m, f2), space.node(oc2, m2, f2)
        stay = y[here]
        on = z[there] | y[there]
        if x is not None and not _progress(space, f, ch):
            stay |= x[here]
            on |= x[there]
        return (stay & ~g) | (on & g)

    return target


def recurrence(space: ProductSpace, clock: Clock | None = None) -> Solution:
    """The Büchi game (or, under ``fair``, the one-pair GR(1) game) of the module
    docstring. ``layers[r]``: the robot's states of rank <= r in the final Z."""
    fair = space.problem.fair
    standing = _standing(space)
    z = [standing] * space.n_nodes
    sol = Solution(space, z)

    def round_(z: list[int], y: list[int], x: list[int] | None) -> list[int]:
        """One round: the states from which the robot forces the target of z, y (and x)."""
        sol.rounds += 1
        out = [
            _or(controllable(space, n, _recurrence_target(space, n, z, y, x))) & standing for n in range(space.n_nodes)
        ]
        check_clock(clock, "the recurrence fixpoint", f" (round {sol.rounds})")
        return out

    while True:
        y = [0] * space.n_nodes
        layers: list[list[int]] = []
        while True:
            if fair:
                x = [standing] * space.n_nodes
                while (nx := round_(z, y, x)) != x:
                    x = nx
                ny = x
            else:
                ny = round_(z, y, None)
            if ny == y:
                break
            y = ny
            layers.append(y)
        if y == z:
            break
        z = y
    sol.win, sol.layers, sol.outer = z, layers, [z]
    return sol


def recurrence_dual(
    space: ProductSpace, clock: Clock | None = None
) -> tuple[list[int], list[list[tuple[list[int], list[list[int]]]]]]:
    """The obstacles' winning states of the recurrence game and the ranks of their
    strategy: ``(lose, levels)`` with ``lose[node]`` the robot cells the obstacles win
    from, and per outer level i (Z' rounds) the pair (Y'_i, the X' rounds of Y'_i)."""
    fair = space.problem.fair
    standing = _standing(space)
    zp = [0] * space.n_nodes
    levels: list[tuple[list[int], list[list[int]]]] = []
    rounds = 0
    while True:
        yp = [standing] * space.n_nodes
        while True:
            xp = [0] * space.n_nodes
            xrounds: list[list[int]] = []
            while True:
                rounds += 1
                nx = [
                    environment_forces(space, n, _dual_target(space, n, zp, yp, xp, fair)) & standing
                    for n in range(space.n_nodes)
                ]
                check_clock(clock, "the obstacles' recurrence fixpoint", f" (round {rounds})")
                if nx == xp:
                    break
                xp = nx
                xrounds.append(xp)
            if xp == yp:
                break
            yp = xp
        if yp == zp:
            break
        levels.append((yp, xrounds))
        zp = yp
    return zp, levels


def _dual_target(space: ProductSpace, node: int, zp: list[int], yp: list[int], xp: list[int], fair: bool) -> Target:
    """Where the obstacles want the robot after one step: in Z' (a lower level), or off
    the awaited goal in Y' on a step with J, or off the goal in X'."""
    oc, m, f = space.split(node)
    g = _arrive(space, m)
    m2 = (m + 1) % space.K

    def target(j: int, oc2: int) -> int:
        ch = space.changed[oc][j]
        f2 = _next_f(space, f, ch)
        here, there = space.node(oc2, m, f2), space.node(oc2, m2, f2)
        off = xp[here] | (yp[here] if _progress(space, f, ch) else 0)
        return (zp[here] | off) & ~g | (zp[there] & g)

    return target
