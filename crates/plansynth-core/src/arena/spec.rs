//! The game's fixed data (the robot's and the read obstacles' moves as set operations,
//! the danger of the obstacles not read, the live cells) and the shape of a layer.

use crate::bits::Bits;
use crate::fx::HashMap;

/// One agent's move as set operations (`plansynth.grid.native.bitgrid.AgentGeometry`):
/// `valid` cells take it as written (others are clamped and stay), `free` cells take it
/// without sweeping a wall (every cell for an obstacle), `to` is the end offset and
/// `offsets` the swept offsets, each as a cell-index delta.
#[derive(Clone, Debug)]
pub struct MoveGeo {
    pub valid: Bits,
    pub free: Bits,
    pub to: i64,
    pub offsets: Vec<i64>,
}

/// The game's fixed data, all over cell indices.
#[derive(Clone, Debug)]
pub struct ArenaSpec {
    pub n_cells: usize,
    pub steps: usize,
    pub robot: Vec<MoveGeo>,
    /// per read obstacle, its moves
    pub obstacles: Vec<Vec<MoveGeo>>,
    /// per step t < steps: cells swept by the relevant obstacles that are not read
    pub abstract_danger: Vec<Bits>,
    /// per time t <= steps: robot cells on some path to the goal
    pub live: Vec<Bits>,
    pub start: usize,
    pub goal: usize,
    pub start_config: Vec<u32>,
}

#[derive(Default, Clone, Debug)]
pub struct Layer {
    pub ids: Vec<u32>,
    pub index: HashMap<u32, u32>,
    /// `nw` words per row
    pub masks: Vec<u64>,
    pub win: Vec<u64>,
    /// CSR, filled by the exploration: the rows of layer t + 1 of row i's successor
    /// configurations are `next[next_off[i]..next_off[i + 1]]` (none: the robot has no
    /// live move from row i, which therefore loses)
    pub next_off: Vec<u32>,
    pub next: Vec<u32>,
}
