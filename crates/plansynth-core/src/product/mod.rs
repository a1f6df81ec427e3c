//! The product game of the robot's cells and the obstacles' configurations, for the
//! objectives beyond the paper's (the compiled twin of `plansynth.grid.native.product`,
//! its pure-Python reference; a property test compares the two).
//!
//! The obstacles move independently of the robot, so their joint configurations (per
//! obstacle: cell, wait counter, glitches left) are explored once from the start; a set
//! of game states is one robot-cell bit set per configuration. Here: the configurations
//! and their successors ([`ProductGame::new`]), `safety` (the greatest fixpoint with
//! the round at which each state leaves it, Thomas, STACS 1995), `closure` (a program's
//! closed loop and the moves each state may play), `learn` (programs learnt on their own
//! closed loop) and `certify` (the obstacles' rank strategy checked from the start).

mod certify;
mod closure;
mod learn;
mod safety;
mod spec;
#[cfg(test)]
mod tests;

pub use spec::{ObstacleMove, ObstacleSpec, ProductSpec, RobotMove};

use crate::fx::HashMap;
use std::time::Instant;

/// Why a computation stopped before its answer: the resource and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stop {
    pub resource: &'static str,
    pub detail: String,
}

/// The budget of one call: a deadline and a byte limit.
#[derive(Clone, Copy, Debug, Default)]
pub struct Limits {
    pub deadline: Option<Instant>,
    pub max_bytes: Option<usize>,
}

impl Limits {
    pub fn check(&self, bytes: usize, what: &str) -> Result<(), Stop> {
        if self.deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(Stop {
                resource: "time",
                detail: format!("{what}: out of time"),
            });
        }
        if self.max_bytes.is_some_and(|m| bytes > m) {
            return Err(Stop {
                resource: "memory",
                detail: format!(
                    "{what}: the game outgrows the memory budget of {} MB ({} MB needed)",
                    self.max_bytes.unwrap_or(0) >> 20,
                    bytes >> 20
                ),
            });
        }
        Ok(())
    }
}

/// An obstacle's state packed in a word: cell (bits 0..32), wait counter (32..40),
/// glitches left (40..56).
pub fn pack(cell: usize, phase: u32, glitches: u32) -> u64 {
    cell as u64 | (phase as u64) << 32 | (glitches as u64) << 40
}

pub fn unpack(s: u64) -> (usize, u32, u32) {
    (
        (s & 0xffff_ffff) as usize,
        ((s >> 32) & 0xff) as u32,
        ((s >> 40) & 0xffff) as u32,
    )
}

/// The explored configurations and, once solved, the winning states.
pub struct ProductGame {
    pub spec: ProductSpec,
    pub nw: usize,
    n_obs: usize,
    configs: Vec<u64>,
    /// successor configurations (CSR)
    succ_off: Vec<u32>,
    succ: Vec<u32>,
    /// per configuration: the cells its replies may sweep (the sweep rule's danger)
    danger_off: Vec<u32>,
    danger: Vec<u32>,
    /// the winning states: `nw` words per configuration (after `solve_safety`)
    pub win: Vec<u64>,
    /// the round at which each state left the winning set (0: never), per
    /// configuration and robot cell
    pub rank: Vec<u8>,
    pub rounds: u32,
    pub solved: bool,
    /// the states of the program learner's sample (configuration, robot cell), and a
    /// bit per state telling membership
    sample: Vec<(u32, u32)>,
    in_sample: Vec<u64>,
    /// the states of the last closure (`closure`)
    seen: Vec<u64>,
    /// the learner's projection of the glitch counters (`learn::project_glitches`):
    /// per configuration the representative of its class (same cells and wait
    /// counters), and per representative its class, most glitches left first
    rep: Vec<u32>,
    family: Vec<Vec<u32>>,
    /// the learner's labels keep only the allowed moves that end nearest the grid's
    /// middle (`learn::prefer_central`)
    central: bool,
}

impl ProductGame {
    /// Explore every configuration reachable from the start (breadth first).
    pub fn new(spec: ProductSpec, limits: Limits) -> Result<ProductGame, Stop> {
        let nw = spec.nw();
        let n_obs = spec.obstacles.len();
        let mut g = ProductGame {
            spec,
            nw,
            n_obs,
            configs: vec![],
            succ_off: vec![0],
            succ: vec![],
            danger_off: vec![0],
            danger: vec![],
            win: vec![],
            rank: vec![],
            rounds: 0,
            solved: false,
            sample: vec![],
            in_sample: vec![],
            seen: vec![],
            rep: vec![],
            family: vec![],
            central: false,
        };
        let first: Vec<u64> = g
            .spec
            .obstacles
            .iter()
            .map(|o| pack(o.start, o.phase0, o.glitches))
            .collect();
        let mut index: HashMap<Vec<u64>, u32> = HashMap::default();
        index.insert(first.clone(), 0);
        g.configs.extend_from_slice(&first);
        let mut head = 0usize;
        while head < g.n_configs() {
            let oc: Vec<u64> = g.config(head as u32).to_vec();
            let replies: Vec<Vec<(u64, Vec<usize>)>> =
                (0..n_obs).map(|i| g.replies(i, oc[i])).collect();
            let mut dng: Vec<u32> = vec![];
            for row in &replies {
                for (_, swept) in row {
                    for &c in swept {
                        if !dng.contains(&(c as u32)) {
                            dng.push(c as u32);
                        }
                    }
                }
            }
            // every joint reply: the product of each obstacle's (odometer, last fastest)
            let mut idx = vec![0usize; n_obs];
            let mut out: Vec<u32> = vec![];
            loop {
                let nxt: Vec<u64> = (0..n_obs).map(|i| replies[i][idx[i]].0).collect();
                let id = match index.get(&nxt) {
                    Some(&id) => id,
                    None => {
                        let id = g.n_configs() as u32;
                        index.insert(nxt.clone(), id);
                        g.configs.extend_from_slice(&nxt);
                        id
                    }
                };
                if !out.contains(&id) {
                    out.push(id);
                }
                let mut j = n_obs;
                let mut done = true;
                while j > 0 {
                    j -= 1;
                    idx[j] += 1;
                    if idx[j] < replies[j].len() {
                        done = false;
                        break;
                    }
                    idx[j] = 0;
                }
                if done {
                    break;
                }
            }
            g.succ.extend_from_slice(&out);
            g.succ_off.push(g.succ.len() as u32);
            g.danger.extend_from_slice(&dng);
            g.danger_off.push(g.danger.len() as u32);
            head += 1;
            if head % 1024 == 0 {
                limits.check(g.bytes(), "exploring the obstacles' configurations")?;
            }
        }
        Ok(g)
    }

    pub fn n_configs(&self) -> usize {
        if self.n_obs == 0 {
            1
        } else {
            self.configs.len() / self.n_obs
        }
    }

    pub fn config(&self, id: u32) -> &[u64] {
        let i = id as usize * self.n_obs;
        &self.configs[i..i + self.n_obs]
    }

    pub fn successors(&self, id: u32) -> &[u32] {
        &self.succ[self.succ_off[id as usize] as usize..self.succ_off[id as usize + 1] as usize]
    }

    pub fn danger_cells(&self, id: u32) -> &[u32] {
        &self.danger
            [self.danger_off[id as usize] as usize..self.danger_off[id as usize + 1] as usize]
    }

    /// Bytes held by the game's arrays (capacities).
    pub fn bytes(&self) -> usize {
        self.configs.capacity() * 8
            + (self.succ.capacity()
                + self.succ_off.capacity()
                + self.danger.capacity()
                + self.danger_off.capacity())
                * 4
            + self.win.capacity() * 8
            + self.rank.capacity()
            + self.sample.capacity() * 8
            + self.in_sample.capacity() * 8
            + self.seen.capacity() * 8
    }

    /// The cells obstacle `i`'s block covers at `cell`.
    pub fn block(&self, i: usize, cell: usize) -> impl Iterator<Item = usize> + '_ {
        let o = &self.spec.obstacles[i];
        let w = self.spec.width;
        (0..o.h).flat_map(move |b| (0..o.w).map(move |a| cell + b * w + a))
    }

    /// Obstacle `i`'s distinct legal replies from state `s`: (next state, swept cells),
    /// exactly as `plansynth.grid.semantics` (a move that would sweep a cell off the
    /// grid, a wall or a kept-out cell leaves it in place, sweeping its block there; a
    /// change of cell while the wait counter is above 0 spends a glitch).
    pub fn replies(&self, i: usize, s: u64) -> Vec<(u64, Vec<usize>)> {
        let o = &self.spec.obstacles[i];
        let (cell, phase, gl) = unpack(s);
        let (w, h) = (self.spec.width as i64, self.spec.height as i64);
        let (x, y) = (
            (cell % self.spec.width) as i64,
            (cell / self.spec.width) as i64,
        );
        let mut out: Vec<(u64, Vec<usize>)> = vec![];
        for mv in &o.moves {
            let mut swept: Vec<usize> = vec![];
            let mut ok = true;
            'cells: for &(dx, dy) in &mv.offsets {
                for b in 0..o.h as i64 {
                    for a in 0..o.w as i64 {
                        let (cx, cy) = (x + dx + a, y + dy + b);
                        if cx < 0 || cy < 0 || cx >= w || cy >= h {
                            ok = false;
                            break 'cells;
                        }
                        let c = (cy * w + cx) as usize;
                        if o.blocked[c / 64] >> (c % 64) & 1 == 1 {
                            ok = false;
                            break 'cells;
                        }
                        if !swept.contains(&c) {
                            swept.push(c);
                        }
                    }
                }
            }
            let end = if ok {
                ((y + mv.to.1) * w + x + mv.to.0) as usize
            } else {
                cell
            };
            if !ok {
                swept = self.block(i, cell).collect();
            }
            let moved = end != cell;
            if moved && phase > 0 && gl == 0 {
                continue; // it waits and has no glitch left
            }
            let gl2 = if moved && phase > 0 { gl - 1 } else { gl };
            let k = o.period;
            let phase2 = if o.fixed {
                if phase == 0 {
                    k - 1
                } else {
                    phase - 1
                }
            } else if moved {
                k - 1
            } else {
                phase.saturating_sub(1)
            };
            let nxt = pack(end, phase2, gl2);
            match out.iter_mut().find(|(n, _)| *n == nxt) {
                Some((_, sw)) => {
                    for c in swept {
                        if !sw.contains(&c) {
                            sw.push(c);
                        }
                    }
                }
                None => out.push((nxt, swept)),
            }
        }
        out
    }

    /// The robot's cell after move `k` from cell `r`.
    pub fn robot_end(&self, r: usize, k: usize) -> usize {
        let m = &self.spec.robot[k];
        if m.valid[r / 64] >> (r % 64) & 1 == 1 {
            (r as i64 + m.to) as usize
        } else {
            r
        }
    }

    /// The controller's inputs of state (configuration `id`, robot cell `r`).
    pub fn inputs(&self, id: u32, r: usize, out: &mut Vec<i64>) {
        let w = self.spec.width;
        out.clear();
        out.push((r % w) as i64);
        out.push((r / w) as i64);
        for (i, &s) in self.config(id).iter().enumerate() {
            let (cell, phase, gl) = unpack(s);
            out.push((cell % w) as i64);
            out.push((cell / w) as i64);
            let o = &self.spec.obstacles[i];
            if o.periodic() {
                out.push(phase as i64);
            }
            if o.glitching() {
                out.push(gl as i64);
            }
        }
    }
}
