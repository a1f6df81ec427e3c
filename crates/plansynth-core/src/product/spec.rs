//! The product game's fixed data: the grid, the robot's moves as set operations and
//! each obstacle's dynamics (its block, moves, period, schedule, glitches and the cells
//! it may not cover), all over cell indices `y * width + x`.

use crate::bits::Bits;

/// One robot move as set operations (`plansynth.grid.native.bitgrid.AgentGeometry`):
/// `valid` cells take it as written (others are clamped and stay), `free` cells take it
/// without sweeping a wall, `to` is the end offset and `offsets` the swept offsets, as
/// cell-index deltas.
#[derive(Clone, Debug)]
pub struct RobotMove {
    pub valid: Bits,
    pub free: Bits,
    pub to: i64,
    pub offsets: Vec<i64>,
}

/// One obstacle move: its end offset and every offset it sweeps (`Move.offsets()`: the
/// start `(0, 0)` first, then the end, then the `via` cells, without repeats).
#[derive(Clone, Debug)]
pub struct ObstacleMove {
    pub to: (i64, i64),
    pub offsets: Vec<(i64, i64)>,
}

/// One obstacle (`plansynth.grid.problem.Obstacle`): its block `w x h`, its moves,
/// its `period` and schedule (`fixed`: the counter turns every step; else `rest`),
/// the initial wait counter, its glitches and the cells it may not cover (walls and
/// kept-out cells).
#[derive(Clone, Debug)]
pub struct ObstacleSpec {
    pub w: usize,
    pub h: usize,
    pub moves: Vec<ObstacleMove>,
    pub period: u32,
    pub fixed: bool,
    pub phase0: u32,
    pub glitches: u32,
    pub blocked: Bits,
    pub start: usize,
}

impl ObstacleSpec {
    /// Whether the controller reads its wait counter (`o<i>p`).
    pub fn periodic(&self) -> bool {
        self.period > 1
    }

    /// Whether the controller reads its glitches left (`o<i>g`).
    pub fn glitching(&self) -> bool {
        self.glitches > 0
    }
}

/// The whole game's fixed data (one product game: safety, for now in the core).
#[derive(Clone, Debug)]
pub struct ProductSpec {
    pub width: usize,
    pub height: usize,
    pub robot: Vec<RobotMove>,
    pub obstacles: Vec<ObstacleSpec>,
    /// collisions of positions (`collision: position`) rather than of swept cells
    pub position: bool,
    pub start: usize,
    /// robot cells that are not walls
    pub standing: Bits,
}

impl ProductSpec {
    pub fn n_cells(&self) -> usize {
        self.width * self.height
    }

    pub fn nw(&self) -> usize {
        self.n_cells().div_ceil(64).max(1)
    }

    /// The controller's inputs per state: `rx ry`, per obstacle `x y [p] [g]`.
    pub fn n_vars(&self) -> usize {
        2 + self
            .obstacles
            .iter()
            .map(|o| 2 + o.periodic() as usize + o.glitching() as usize)
            .sum::<usize>()
    }
}
