"""Types of ``plansynth._core``, the compiled core (crates/plansynth-py over
crates/plansynth-core). Plain data crosses the boundary: cell and behaviour sets are
little-endian bytes (bit i of the string is cell or state i), programs are flat op rows
``(op, a, b, c)`` with children first and the root last (op 0 constant a, 1 variable a,
2 ``+``, 3 ``-``, 4 ``<=``, 5 ``=``, 6 ``not``, 7 ``and``, 8 ``or``, 9 ``ite``), and a
configuration is the cells of the read obstacles. A call given seconds, memory or a
configuration cap raises :class:`plansynth.budget.BudgetExhausted` past them; malformed
input raises ``ValueError``. tests/test_core_stubs.py checks this file against the module.
"""

from collections.abc import Sequence

#: A program as flat op rows ``(op, a, b, c)``, children first, root last.
_ProgramRows = Sequence[tuple[int, int, int, int]]
#: Per time, ``(configuration, robot cells)``.
_LayerRows = list[list[tuple[list[int], bytes]]]
#: A state and its moves: ``(robot cell, configuration, move bitmask)``.
_StateRow = tuple[int, list[int], int]

def core_version() -> str: ...
def enumerate_conditions(
    states: Sequence[Sequence[int]],
    n_vars: int,
    max_constant: int,
    max_depth: int,
    limit: int | None = None,
) -> tuple[list[tuple[int, int, int, int]], list[tuple[bytes, int, int, int, int]], int]:
    """``(terms, conditions, complete_to)``: terms ``(kind, a, b, depth)``, conditions
    ``(behaviour bytes, op, a, b, depth)`` (see plansynth_core::conditions)."""

def check_invariant(
    width: int,
    n_cells: int,
    table: bytes,
    n_fixed: int,
    fixed: bytes,
    n_moves: int,
    ends: bytes,
    wall_hit: bytes,
    n_swept: int,
    swept: bytes,
    reply_off: bytes,
    reply_next: bytes,
    danger_off: bytes,
    danger: bytes,
    position: bool,
    ops: _ProgramRows,
    seconds: float | None = None,
) -> tuple[int, tuple[int, int, int, int, int] | None]:
    """Check an inductive invariant (see plansynth_core::inductive): ``(states checked,
    None)`` when it is one, else ``(0, the first failure)``."""

def greedy_tree(
    conds: Sequence[bytes],
    keys: Sequence[tuple[int, int]],
    allowed: Sequence[int],
    n_moves: int,
    max_nodes: int,
) -> list[tuple[int, int]] | None:
    """Pre-order nodes ``(0, move)`` or ``(1, condition)``; None past ``max_nodes``."""

class GameGraph:
    """The winning-forward game graph and its program check (plansynth_core::game)."""

    def __new__(
        cls,
        n_moves: int,
        state_of: Sequence[int],
        win: Sequence[int],
        off: Sequence[int],
        succ: Sequence[int],
        inputs: Sequence[Sequence[int]],
    ) -> GameGraph: ...
    def sizes(self) -> tuple[int, int]: ...
    def arrays(self) -> tuple[list[int], list[int], list[int], list[int], list[list[int]]]: ...
    def check(self, prog: _ProgramRows) -> int | None: ...
    def moves(self, prog: _ProgramRows) -> list[int]: ...

def build_game_graph(
    n_moves: int,
    steps: int,
    width: int,
    start: int,
    configs: Sequence[Sequence[int]],
    successors: Sequence[Sequence[int]],
    robot_end: Sequence[int],
    layers: Sequence[tuple[int, int, Sequence[bytes]]],
) -> GameGraph: ...

class Arena:
    """The joint game of the robot and the read obstacles (plansynth_core::arena)."""

    def __new__(
        cls,
        n_cells: int,
        steps: int,
        robot: Sequence[tuple[bytes, bytes, int, Sequence[int]]],
        obstacles: Sequence[Sequence[tuple[bytes, int, Sequence[int]]]],
        abstract_danger: Sequence[bytes],
        live: Sequence[bytes],
        start: int,
        goal: int,
        start_config: Sequence[int],
    ) -> Arena: ...
    def explore(
        self, seconds: float | None = None, memory: int | None = None, max_configs: int | None = None
    ) -> None: ...
    def solve_game(self, seconds: float | None = None, memory: int | None = None) -> bool: ...
    def layer_sizes(self) -> list[int]: ...
    def bytes(self) -> int: ...
    def state_count(self) -> int: ...
    def layer(self, t: int, win: bool = False) -> list[tuple[list[int], bytes]]: ...
    def winning_moves(self, t: int, oc: Sequence[int]) -> list[bytes]: ...
    def successors(self, oc: Sequence[int]) -> list[list[int]]: ...
    def winning_forward(self, seconds: float | None = None, memory: int | None = None) -> _LayerRows: ...
    def consistent(self, width: int, seconds: float | None = None) -> tuple[_LayerRows, list[_StateRow]] | None: ...
    def check(
        self, prog: _ProgramRows, width: int, seconds: float | None = None
    ) -> tuple[int, int, list[int]] | None: ...
    def forward_sizes(self) -> tuple[int, int]: ...
    def allowed(
        self, reach: Sequence[Sequence[tuple[Sequence[int], bytes]]], seconds: float | None = None
    ) -> list[_StateRow]: ...
    def closure(
        self, allowed: Sequence[tuple[int, Sequence[int], int]], seconds: float | None = None
    ) -> _LayerRows: ...

class ProductGame:
    """The product game of robot cells and obstacle configurations (plansynth_core::product)."""

    def __new__(
        cls,
        width: int,
        height: int,
        robot: Sequence[tuple[bytes, bytes, int, Sequence[int]]],
        obstacles: Sequence[
            tuple[
                int, int, Sequence[tuple[tuple[int, int], Sequence[tuple[int, int]]]], int, bool, int, int, bytes, int
            ]
        ],
        position: bool,
        start: int,
        standing: bytes,
        seconds: float | None = None,
        max_bytes: int | None = None,
    ) -> ProductGame: ...
    def n_configs(self) -> int: ...
    def config(self, id: int) -> list[tuple[int, int, int]]: ...
    def successors(self, id: int) -> list[int]: ...
    def solve_safety(self, seconds: float | None = None, max_bytes: int | None = None) -> bool: ...
    def rounds(self) -> int: ...
    def winning(self, id: int) -> bytes: ...
    def allowed(self, id: int, r: int) -> int: ...
    def rank(self, id: int, r: int) -> int: ...
    def closure(
        self,
        prog: _ProgramRows,
        n_vars: int,
        grow: bool = False,
        seconds: float | None = None,
        max_bytes: int | None = None,
    ) -> tuple[int, list[tuple[int, int]], int]: ...
    def reached_sets(self) -> list[tuple[int, bytes]]: ...
    def sample(self) -> list[tuple[list[int], int]]: ...
    def reset_sample(self) -> None: ...
    def sample_labels(self) -> list[int]: ...
    def seed_winning(self, max_states: int) -> int | None: ...
    def prefer_central(self, on: bool) -> None: ...
    def central_moves(self, r: int, mask: int) -> int: ...
    def project_glitches(self) -> None: ...
    def learn_round(
        self,
        cond_depth: int,
        max_constant: int,
        max_nodes: int,
        enum_states: int,
        seconds: float | None = None,
        max_bytes: int | None = None,
        tree_states: int | None = None,
    ) -> tuple[
        bool,
        int,
        int,
        list[tuple[int, int, int, int]],
        list[tuple[int, int, int, int]],
        list[tuple[int, int]],
        tuple[float, float, float, float],
    ]: ...
    def certify_safety(self, seconds: float | None = None, max_bytes: int | None = None) -> tuple[bool, int, str]: ...
    def bytes(self) -> int: ...
