//! The safety game's greatest fixpoint `nu W. Cpre(W)` on the product game (Thomas,
//! STACS 1995), by rounds: a round recomputes only the configurations a successor of
//! which changed in the round before (every other one would give the same set), so the
//! round at which a state leaves W is exact: the obstacles force a collision within
//! that many steps from it, whatever the robot does (the certificate of a "no",
//! `certify`). The mirror of `plansynth.grid.native.product.fixpoints.safety`.

use super::{Limits, ProductGame, Stop};
use crate::bits::shift;

impl ProductGame {
    /// Robot cells of configuration `id` from which move `k` is safe against every
    /// reply and ends, whatever the reply, in the winning set (`target`: the AND of the
    /// successors' winning sets, blocks cleared under the position rule).
    fn good(&self, id: u32, target: &[u64], tmp: &mut [u64], out: &mut [u64]) {
        out.iter_mut().for_each(|w| *w = 0);
        for k in 0..self.spec.robot.len() {
            self.good_move(id, k, target, tmp);
            for i in 0..self.nw {
                out[i] |= tmp[i];
            }
        }
    }

    /// Robot cells of configuration `id` from which move `k` is safe against every
    /// reply and ends in `target` (its [`ProductGame::target`]), into `out`.
    pub(super) fn good_move(&self, id: u32, k: usize, target: &[u64], out: &mut [u64]) {
        let m = &self.spec.robot[k];
        shift(target, -m.to, out);
        for i in 0..self.nw {
            out[i] = ((out[i] & m.valid[i]) | (target[i] & !m.valid[i])) & m.free[i];
        }
        if !self.spec.position {
            self.clear_hits(id, k, out);
        }
    }

    /// Clear from `cells` the robot cells from which move k sweeps a cell some reply of
    /// configuration `id` sweeps (the sweep rule).
    fn clear_hits(&self, id: u32, k: usize, cells: &mut [u64]) {
        let m = &self.spec.robot[k];
        let n = self.spec.n_cells() as i64;
        for &d in self.danger_cells(id) {
            let d = d as i64;
            for &o in &m.offsets {
                let r = d - o;
                if (0..n).contains(&r) && m.valid[r as usize / 64] >> (r % 64) & 1 == 1 {
                    cells[r as usize / 64] &= !(1 << (r % 64));
                }
            }
            if m.valid[d as usize / 64] >> (d % 64) & 1 == 0 {
                cells[d as usize / 64] &= !(1 << (d % 64));
            }
        }
    }

    /// The target of configuration `id`: robot cells that are winning in every
    /// successor configuration (and, under the position rule, outside its blocks).
    pub(super) fn target(&self, id: u32, out: &mut [u64]) {
        out.iter_mut().for_each(|w| *w = !0);
        for &s in self.successors(id) {
            let ws = &self.win[s as usize * self.nw..(s as usize + 1) * self.nw];
            for i in 0..self.nw {
                out[i] &= ws[i];
            }
            if self.spec.position {
                for (j, &st) in self.config(s).iter().enumerate() {
                    let cell = super::unpack(st).0;
                    for c in self.block(j, cell) {
                        out[c / 64] &= !(1 << (c % 64));
                    }
                }
            }
        }
    }

    /// Solve the safety game; true iff the robot wins from the start.
    pub fn solve_safety(&mut self, limits: Limits) -> Result<bool, Stop> {
        let (nw, n) = (self.nw, self.n_configs());
        let n_cells = self.spec.n_cells();
        // the winning sets and the ranks, before they are allocated
        limits.check(
            self.bytes() + n * nw * 8 + n * n_cells,
            "the safety fixpoint",
        )?;
        self.win = Vec::with_capacity(n * nw);
        for _ in 0..n {
            self.win.extend_from_slice(&self.spec.standing);
        }
        self.rank = vec![0u8; n * n_cells];
        limits.check(self.bytes(), "the safety fixpoint")?;
        // predecessors (CSR)
        let mut count = vec![0u32; n + 1];
        for id in 0..n {
            for &s in self.successors(id as u32) {
                count[s as usize + 1] += 1;
            }
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut pred = vec![0u32; count[n] as usize];
        let mut fill = count.clone();
        for id in 0..n {
            for &s in self.successors(id as u32) {
                pred[fill[s as usize] as usize] = id as u32;
                fill[s as usize] += 1;
            }
        }
        let mut dirty: Vec<u32> = (0..n as u32).collect();
        let mut mark = vec![false; n];
        let (mut target, mut tmp, mut good) = (vec![0u64; nw], vec![0u64; nw], vec![0u64; nw]);
        let mut round = 0u32;
        loop {
            round += 1;
            let mut changed: Vec<(u32, Vec<u64>)> = vec![];
            for (j, &id) in dirty.iter().enumerate() {
                self.target(id, &mut target);
                self.good(id, &target, &mut tmp, &mut good);
                let cur = &self.win[id as usize * nw..(id as usize + 1) * nw];
                if cur.iter().zip(&good).any(|(c, g)| c & !g != 0) {
                    changed.push((id, cur.iter().zip(&good).map(|(c, g)| c & g).collect()));
                }
                if j % 4096 == 0 {
                    limits.check(self.bytes() + changed.len() * nw * 8, "the safety fixpoint")?;
                }
            }
            if changed.is_empty() {
                break;
            }
            if round > 254 {
                return Err(Stop {
                    resource: "rounds",
                    detail: "the safety fixpoint: more than 254 rounds (ranks are bytes)".into(),
                });
            }
            let mut next: Vec<u32> = vec![];
            for (id, new) in changed {
                let base = id as usize * nw;
                for i in 0..nw {
                    let mut gone = self.win[base + i] & !new[i];
                    while gone != 0 {
                        let b = gone.trailing_zeros() as usize;
                        self.rank[id as usize * n_cells + i * 64 + b] = round as u8;
                        gone &= gone - 1;
                    }
                    self.win[base + i] = new[i];
                }
                for &p in &pred[count[id as usize] as usize..count[id as usize + 1] as usize] {
                    if !mark[p as usize] {
                        mark[p as usize] = true;
                        next.push(p);
                    }
                }
            }
            for &p in &next {
                mark[p as usize] = false;
            }
            dirty = next;
        }
        self.rounds = round;
        self.solved = true;
        Ok(self.wins(0, self.spec.start))
    }

    pub fn wins(&self, id: u32, r: usize) -> bool {
        self.win[id as usize * self.nw + r / 64] >> (r % 64) & 1 == 1
    }

    /// The robot moves of state (configuration `id`, cell `r`) that keep it winning
    /// (a bit per move; 0 outside the winning set).
    pub fn allowed(&self, id: u32, r: usize) -> u32 {
        if !self.wins(id, r) {
            return 0;
        }
        let mut mask = 0u32;
        'moves: for (k, m) in self.spec.robot.iter().enumerate() {
            if m.free[r / 64] >> (r % 64) & 1 == 0 || self.hits(id, r, k) {
                continue;
            }
            let e = self.robot_end(r, k);
            for &s in self.successors(id) {
                if !self.wins(s, e) || (self.spec.position && self.in_blocks(s, e)) {
                    continue 'moves;
                }
            }
            mask |= 1 << k;
        }
        mask
    }

    /// Whether move `k` keeps state (configuration `id`, cell `r`) winning: bit k of
    /// [`ProductGame::allowed`], for that move only.
    pub fn allows(&self, id: u32, r: usize, k: usize) -> bool {
        let m = &self.spec.robot[k];
        if !self.wins(id, r) || m.free[r / 64] >> (r % 64) & 1 == 0 || self.hits(id, r, k) {
            return false;
        }
        let e = self.robot_end(r, k);
        self.successors(id)
            .iter()
            .all(|&s| self.wins(s, e) && !(self.spec.position && self.in_blocks(s, e)))
    }

    /// Whether move `k` from `r` sweeps a cell some reply of `id` sweeps (sweep rule).
    pub fn hits(&self, id: u32, r: usize, k: usize) -> bool {
        if self.spec.position {
            return false;
        }
        let m = &self.spec.robot[k];
        let valid = m.valid[r / 64] >> (r % 64) & 1 == 1;
        let dng = self.danger_cells(id);
        if !valid {
            return dng.contains(&(r as u32));
        }
        m.offsets
            .iter()
            .any(|&o| dng.contains(&((r as i64 + o) as u32)))
    }

    /// Whether cell `c` lies in a block of configuration `id`.
    pub fn in_blocks(&self, id: u32, c: usize) -> bool {
        self.config(id)
            .iter()
            .enumerate()
            .any(|(j, &st)| self.block(j, super::unpack(st).0).any(|b| b == c))
    }

    /// The round at which state (id, r) left the winning set (0: it never did).
    pub fn rank_of(&self, id: u32, r: usize) -> u8 {
        self.rank[id as usize * self.spec.n_cells() + r]
    }
}
