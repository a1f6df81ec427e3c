//! The bounded game of the robot and the read obstacles: joint-state exploration and
//! backward induction (Chasins & Newcomb, SYNT 2016, Section 3.1: reach the goal at
//! exactly l steps without collision, whatever the obstacles do).
//!
//! The compiled twin of `plansynth.grid.native.arena.Arena` (its pure-Python reference):
//! for each time t and tuple of read obstacle cells (a *configuration*) the robot's cells
//! are one bit set, so a robot step is a few word shifts. Configurations are interned
//! once (ids shared by every time); a layer maps configuration ids to robot-cell sets in
//! the order they were first met, exactly as the reference's dicts do, so both number
//! everything the same way. Obstacles that matter but are not read are folded into a
//! per-step danger set by the caller.
//!
//! The exploration is bounded by a deadline, a memory limit checked against the bytes
//! the data structures actually hold (their capacities), and an optional cap on
//! configurations; past either it stops with [`Stop`] naming the step and the resource.
//!
//! Here: the game and its interned configurations. `spec` (the fixed data), `limits`
//! (the budget of a call), `moves` (local facts: ends, successors, danger, safe moves),
//! `explore` (forward exploration), `induction` (backward induction), `strategy` (the
//! winning-forward layers and what a stationary strategy may play) and `program` (the
//! program check on the solved game).

mod explore;
mod induction;
mod limits;
mod moves;
mod program;
mod spec;
mod strategy;
#[cfg(test)]
mod tests;

pub use crate::bits::Bits;
pub use limits::{Budget, Stop};
pub use spec::{ArenaSpec, Layer, MoveGeo};

use crate::fx::HashMap;
use std::time::Instant;

/// The explored game.
pub struct Arena {
    pub spec: ArenaSpec,
    pub nw: usize,
    full: Bits,
    n_read: usize,
    configs: Vec<u32>,
    intern: HashMap<Box<[u32]>, u32>,
    succ: Vec<Option<Box<[u32]>>>,
    pub layers: Vec<Layer>,
    pub solved: bool,
    /// The deadline of the strategy routines ([`Arena::allowed`], [`Arena::closure`],
    /// [`Arena::consistent`]): past it they stop early and set `expired`.
    pub deadline: Option<Instant>,
    pub expired: bool,
}

/// Bytes a hash map of this capacity holds (entries plus one control byte each).
fn map_bytes<K, V>(m: &HashMap<K, V>) -> usize {
    m.capacity() * (std::mem::size_of::<(K, V)>() + 1)
}

impl Arena {
    pub fn new(spec: ArenaSpec) -> Arena {
        let nw = spec.n_cells.div_ceil(64).max(1);
        let mut full = vec![0u64; nw];
        for c in 0..spec.n_cells {
            full[c / 64] |= 1 << (c % 64);
        }
        let n_read = spec.obstacles.len();
        Arena {
            spec,
            nw,
            full,
            n_read,
            configs: vec![],
            intern: HashMap::default(),
            succ: vec![],
            layers: vec![],
            solved: false,
            deadline: None,
            expired: false,
        }
    }

    /// The id of a configuration, interned on first use.
    pub fn config_id(&mut self, oc: &[u32]) -> u32 {
        if let Some(&i) = self.intern.get(oc) {
            return i;
        }
        let i = self.succ.len() as u32;
        self.configs.extend_from_slice(oc);
        self.intern.insert(oc.into(), i);
        self.succ.push(None);
        i
    }

    pub fn find_config(&self, oc: &[u32]) -> Option<u32> {
        self.intern.get(oc).copied()
    }

    pub fn config(&self, id: u32) -> &[u32] {
        let i = id as usize * self.n_read;
        &self.configs[i..i + self.n_read]
    }

    pub fn n_configs(&self) -> usize {
        self.succ.len()
    }

    /// Whether `deadline` has passed (and remember it in `expired`).
    pub fn out_of_time(&mut self) -> bool {
        if !self.expired && self.deadline.is_some_and(|d| Instant::now() >= d) {
            self.expired = true;
        }
        self.expired
    }

    /// Bytes held by the explored game now (capacities, not lengths).
    pub fn bytes(&self) -> usize {
        let spec = &self.spec;
        let masks = spec.live.len()
            + spec.abstract_danger.len()
            + 2 * spec.robot.len()
            + spec.obstacles.iter().map(|o| o.len()).sum::<usize>();
        let mut b = masks * self.nw * 8;
        b += self.configs.capacity() * 4
            + map_bytes(&self.intern)
            + self.intern.len() * (self.n_read * 4 + 16);
        b += self.succ.capacity() * std::mem::size_of::<Option<Box<[u32]>>>();
        b += self
            .succ
            .iter()
            .flatten()
            .map(|s| s.len() * 4 + 16)
            .sum::<usize>();
        for l in &self.layers {
            b += l.ids.capacity() * 4
                + map_bytes(&l.index)
                + (l.masks.capacity() + l.win.capacity()) * 8;
            b += (l.next_off.capacity() + l.next.capacity()) * 4;
        }
        b
    }

    /// Row of configuration `id` in layer t.
    pub fn row(&self, t: usize, id: u32) -> Option<usize> {
        self.layers.get(t)?.index.get(&id).map(|&i| i as usize)
    }
}
