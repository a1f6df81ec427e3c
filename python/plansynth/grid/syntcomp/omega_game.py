"""The moving-obstacle game posed to ``omega``, the BDD-based GR(1) solver under TuLiP:
the peer for :mod:`plansynth.grid.syntcomp.safety`.

``omega`` (Filippidis, tulip-control/omega; PyPI ``omega``, with ``dd`` for the BDDs)
is what TuLiP's ``tulip.interfaces.omega`` calls: it builds an
``omega.symbolic.temporal.Automaton``, declares the variables, sets ``init``,
``action`` and ``win`` for the players ``env`` and ``sys``, and calls
``omega.games.gr1.solve_streett_game``, ``gr1.is_realizable`` and (for a strategy)
``gr1.make_streett_transducer``. :func:`automaton` does the same, with the game written
as Ehlers wrote it for SLUGS (description ``moving_obstacle_evasion.pdf``, Sect. I.A,
I.B, II; the rules in :mod:`plansynth.grid.syntcomp.moving_obstacle`):

* ``env`` owns the robot's cell ``rx, ry`` (0..m-1; it must update it as the robot
  commanded, stopping at the border), the obstacle's corner ``ox, oy`` (0..m-2) and the
  glitch counter ``g`` (0..c);
* ``sys`` owns the move codes ``mx, my`` (0..2 for -1, 0, +1) and ``obsmove`` (false
  exactly after the obstacle changed position, and in the first step);
* ``EnvNext`` is assumptions 1, 2, 4-7 and the glitch rules; ``SysNext`` is guarantees
  1-4 (no collision is read on the current state, as the circuits read it);
* safety only: TuLiP's encoding of a GR(1) spec without liveness, ``win['<>[]'] =
  [FALSE]`` and ``win['[]<>'] = [TRUE]``, under which ``solve_streett_game`` computes
  the safety fixpoint.

Settings, as TuLiP's users run omega: ``dd.cudd`` when it is installed (omega picks it
over the pure-Python ``dd.autoref``), with CUDD's dynamic variable reordering on (dd's
default; the variables are declared in the order above, each integer's bits low to
high, primed and unprimed copies side by side); ``qinit = '\\A \\E'`` (for every
initial environment state some initial system state; TuLiP's default for GR(1)
specifications with both initial conditions); ``moore = False`` (the system sees the
environment's step before it moves: SLUGS's and SYNTCOMP's semantics); ``plus_one =
False`` (Ehlers: an assumption and a guarantee broken in the same step is a system win;
``plus_one = True``, TuLiP's default, decides these games the same way, see the tests).
Type invariants (``x \\in a..b``) are written into the actions, as omega's own
``examples/gr1_synthesis_intro.py`` does.

:func:`synthesize` runs it in this process (and keeps the BDDs); :func:`solve` runs it
in a child process under a :class:`~plansynth.budget.Budget` (omega's fixpoint cannot be
interrupted from inside), for benchmark tables.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

from plansynth.budget import Budget
from plansynth.errors import SolverUnavailable
from plansynth.grid.result import GridStatus
from plansynth.grid.syntcomp.moving_obstacle import MovingObstacle

__all__ = [
    "automaton",
    "synthesize",
    "solve",
    "check_strategy",
    "OmegaSynthesis",
    "OmegaAnswer",
    "versions",
    "isolated",
]

ENV_VARS = ("rx", "ry", "ox", "oy", "g")
SYS_VARS = ("mx", "my", "obsmove")


def _omega() -> tuple[Any, Any]:
    try:
        import omega.games.gr1 as gr1
        import omega.symbolic.temporal as trl
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise SolverUnavailable("omega", f"pip install omega dd ({e})") from e
    return gr1, trl


def versions() -> dict[str, str]:
    """omega's and dd's versions, and which BDD package omega uses."""
    from importlib.metadata import version

    _, trl = _omega()
    aut = trl.Automaton()
    return {"omega": version("omega"), "dd": version("dd"), "bdd": type(aut.bdd).__module__}


def _all(*parts: str) -> str:
    """The conjunction of ``parts``, each in parentheses (omega's parser gives ``=>`` and
    ``<=>`` lower precedence than ``/\\``, so a bulleted list would run together)."""
    return " /\\ ".join(f"({p})" for p in parts)


def _robot_update(coord: str, move: str, top: int) -> str:
    """``EnvNext`` for one coordinate: move code 0/1/2 is -1/0/+1, stopping at 0 and top."""
    c, d = coord, move
    return _all(
        rf"({d} = 0 /\ {c} > 0) => ({c}' = {c} - 1)",
        rf"({d} = 0 /\ {c} = 0) => ({c}' = 0)",
        rf"({d} = 1) => ({c}' = {c})",
        rf"({d} = 2 /\ {c} < {top}) => ({c}' = {c} + 1)",
        rf"({d} = 2 /\ {c} = {top}) => ({c}' = {top})",
    )


def automaton(game: MovingObstacle, *, plus_one: bool = False) -> Any:
    """The game as an ``omega.symbolic.temporal.Automaton`` (see the module's docstring)."""
    _, trl = _omega()
    m, c = game.size, game.glitches
    aut = trl.Automaton()
    aut.declare_variables(
        rx=(0, m - 1),
        ry=(0, m - 1),
        ox=(0, m - 2),
        oy=(0, m - 2),
        g=(0, max(c, 1)),
        mx=(0, 2),
        my=(0, 2),
        obsmove="bool",
    )
    aut.varlist.update(env=list(ENV_VARS), sys=list(SYS_VARS))
    aut.init["env"] = _all("rx = 0", "ry = 0", f"ox = {m - 2}", f"oy = {m - 2}", "g = 0")
    aut.init["sys"] = _all(r"mx \in 0..2", r"my \in 0..2", "~ obsmove")
    aut.action["env"] = _all(
        _env_types(game, ""),
        _env_types(game, "'"),
        # assumption 2 with the border: the robot goes where its move code says
        _robot_update("rx", "mx", m - 1),
        _robot_update("ry", "my", m - 1),
        # assumption 1: the obstacle moves by at most one cell in x and in y
        "ox' <= ox + 1",
        "ox <= ox' + 1",
        "oy' <= oy + 1",
        "oy <= oy' + 1",
        # Sect. II: the counter never decreases, and rises when the obstacle moves while obsmove is false
        "g <= g'",
        r"(~ obsmove /\ (ox' # ox \/ oy' # oy)) => (g' > g)",
    )
    aut.action["sys"] = _all(
        # guarantees 3, 4: valid move codes
        r"mx' \in 0..2",
        r"my' \in 0..2",
        # guarantee 2: obsmove is false exactly after a change of the obstacle's position
        r"obsmove' <=> (ox' = ox /\ oy' = oy)",
        # guarantee 1: the robot is never within the obstacle's 2 x 2 block
        r"~ (ox <= rx /\ rx <= ox + 1 /\ oy <= ry /\ ry <= oy + 1)",
    )
    aut.win["<>[]"] = aut.bdds_from("FALSE")
    aut.win["[]<>"] = aut.bdds_from("TRUE")
    aut.qinit = r"\A \E"
    aut.moore = False
    aut.plus_one = plus_one
    return aut


@dataclass
class OmegaSynthesis:
    """What :func:`synthesize` found: the automaton (with the strategy as
    ``aut.action['impl']`` when realizable), the winning set ``z`` and the times."""

    game: MovingObstacle
    aut: Any
    status: GridStatus
    winning: Any
    strategy: Any
    seconds: dict[str, float] = field(default_factory=dict)


def synthesize(game: MovingObstacle, *, strategy: bool = True, plus_one: bool = False) -> OmegaSynthesis:
    """Solve the game with omega in this process, as TuLiP's ``synthesize_enumerated_streett``
    does up to the enumeration: ``solve_streett_game``, ``is_realizable`` and, if
    realizable and ``strategy``, ``make_streett_transducer``."""
    gr1, _ = _omega()
    t0 = time.perf_counter()
    aut = automaton(game, plus_one=plus_one)
    aut.build()
    t1 = time.perf_counter()
    z, yij, xijk = gr1.solve_streett_game(aut)
    t2 = time.perf_counter()
    realizable = _quiet(gr1.is_realizable, z, aut)
    status = GridStatus.REALIZABLE if realizable else GridStatus.UNREALIZABLE
    impl = None
    t3 = time.perf_counter()
    if realizable and strategy:
        gr1.make_streett_transducer(z, yij, xijk, aut)
        impl = aut.action["impl"]
    t4 = time.perf_counter()
    return OmegaSynthesis(
        game,
        aut,
        status,
        z,
        impl,
        {"build": t1 - t0, "winning_set": t2 - t1, "realizability": t3 - t2, "strategy": t4 - t3, "total": t4 - t0},
    )


def _quiet(fn: Any, *args: Any) -> Any:
    """``gr1.is_realizable`` prints a message when the answer is no: keep stdout clean."""
    import contextlib
    import io

    with contextlib.redirect_stdout(io.StringIO()):
        return fn(*args)


def check_strategy(syn: OmegaSynthesis) -> None:
    """Check omega's strategy with plain BDD operations, independently of its fixpoint:
    every initial environment state has an initial system state in ``z``; from ``z``,
    for every legal environment step the strategy offers a system step; and every step
    it offers keeps ``SysNext`` and leads back into ``z``. Raises ``AssertionError``."""
    aut, z, impl = syn.aut, syn.winning, syn.strategy
    if impl is None:
        raise AssertionError("no strategy to check")
    env, sys_ = aut.action["env"], aut.action["sys"]
    sys_primed = aut.varlist["sys'"]
    z_next = aut.replace_with_primed(aut.varlist["env"] + aut.varlist["sys"], z)
    impl_vars = set(aut.support(impl))
    extra = sorted(v for v in impl_vars if not any(v.startswith(p) for p in ENV_VARS + SYS_VARS))
    impl_any = aut.exist(extra, impl) if extra else impl
    types = aut.add_expr(_type_invariant(syn.game))
    # every initial environment state: some initial system state in z
    u = aut.init["env"] & ~aut.exist(aut.varlist["sys"], aut.init["sys"] & z)
    assert u == aut.false, "an initial environment state without a winning initial system state"
    # from z, after a legal environment step, the strategy offers a step ...
    offered = aut.exist(sys_primed, impl_any)
    u = z & types & env & ~offered
    assert u == aut.false, "the strategy offers no step after some legal environment step"
    # ... and each step it offers keeps SysNext and stays in z
    u = z & types & env & impl_any & ~(sys_ & z_next)
    assert u == aut.false, "the strategy leaves the winning set or breaks SysNext"


def _env_types(game: MovingObstacle, prime: str) -> str:
    """The environment's variables in their ranges (``prime`` = "'" for the next state)."""
    m, c, p = game.size, game.glitches, prime
    return (
        rf"rx{p} \in 0..{m - 1} /\ ry{p} \in 0..{m - 1} /\ ox{p} \in 0..{m - 2} /\ oy{p} \in 0..{m - 2} "
        rf"/\ g{p} \in 0..{c}"
    )


def _type_invariant(game: MovingObstacle) -> str:
    return _env_types(game, "") + r" /\ mx \in 0..2 /\ my \in 0..2"


@dataclass(frozen=True)
class OmegaAnswer:
    """A picklable answer of :func:`solve`: status, wall-clock seconds of the solve (in
    the child), the phases' seconds and the BDD sizes."""

    status: GridStatus
    seconds: float
    phases: dict[str, float] = field(default_factory=dict)
    counters: dict[str, int] = field(default_factory=dict)
    message: str = ""


def _solve_here(game: MovingObstacle, strategy: bool, checked: bool = False) -> OmegaAnswer:
    syn = synthesize(game, strategy=strategy)
    counters = {"winning_set_nodes": len(syn.winning), "bdd_nodes": len(syn.aut.bdd)}
    if syn.strategy is not None:
        counters["strategy_nodes"] = len(syn.strategy)
        if checked:  # after the timed solve: the check is not part of omega's time
            try:
                check_strategy(syn)
                counters["strategy_checked"] = 1
            except AssertionError:
                counters["strategy_checked"] = 0
    return OmegaAnswer(syn.status, syn.seconds["total"], syn.seconds, counters)


def solve(
    game: MovingObstacle, budget: Budget | None = None, *, strategy: bool = True, checked: bool = False
) -> OmegaAnswer:
    """Solve with omega in a child process within ``budget`` (time and memory); a budget
    that runs out gives ``unknown``. ``checked``: check the strategy (:func:`check_strategy`)
    after the timed solve, reported as the counter ``strategy_checked``."""
    return isolated(_solve_here, (game, strategy, checked), budget or Budget())


def isolated(fn: Any, args: tuple, budget: Budget) -> OmegaAnswer:
    """``fn(*args)`` (an :class:`OmegaAnswer`) in a child process within ``budget``;
    ``unknown`` with the reason past it or when the child fails."""
    from plansynth.isolate import Finished, Timeout, run_isolated

    start = time.perf_counter()
    outcome = run_isolated(fn, *args, timeout=budget.seconds, memory_mb=budget.memory_mb)
    if isinstance(outcome, Finished):
        return outcome.value
    elapsed = time.perf_counter() - start
    if isinstance(outcome, Timeout):
        return OmegaAnswer(GridStatus.UNKNOWN, elapsed, message=f"budget ran out in omega ({budget.seconds} s)")
    return OmegaAnswer(GridStatus.UNKNOWN, elapsed, message=f"omega failed: {outcome}")
