//! Local facts of the game: where the agents' moves end, the successor configurations
//! of the read obstacles, what they may sweep, and which robot moves are safe.

use super::Arena;
use crate::bits::{bit, shift, Bits};

impl Arena {
    fn obstacle_end(&self, j: usize, c: usize, k: usize) -> u32 {
        let m = &self.spec.obstacles[j][k];
        if bit(&m.valid, c) {
            (c as i64 + m.to) as u32
        } else {
            c as u32
        }
    }

    /// Successor configurations of `id` (every joint obstacle move, in the reference's
    /// order: the product of each obstacle's distinct end cells, last obstacle fastest).
    pub fn successors(&mut self, id: u32) -> Box<[u32]> {
        self.succ_of(id).into()
    }

    /// [`Arena::successors`] without a copy.
    pub fn succ_of(&mut self, id: u32) -> &[u32] {
        if self.succ[id as usize].is_none() {
            self.compute_successors(id);
        }
        self.succ[id as usize].as_deref().unwrap_or(&[])
    }

    fn compute_successors(&mut self, id: u32) {
        let oc: Vec<u32> = self.config(id).to_vec();
        let ends: Vec<Vec<u32>> = (0..self.n_read)
            .map(|j| {
                let mut e: Vec<u32> = vec![];
                for k in 0..self.spec.obstacles[j].len() {
                    let x = self.obstacle_end(j, oc[j] as usize, k);
                    if !e.contains(&x) {
                        e.push(x);
                    }
                }
                e
            })
            .collect();
        let mut out = vec![];
        let mut idx = vec![0usize; self.n_read];
        let mut cur: Vec<u32> = ends.iter().map(|e| e[0]).collect();
        loop {
            out.push(self.config_id(&cur));
            // odometer, last position fastest
            let mut j = self.n_read;
            loop {
                if j == 0 {
                    self.succ[id as usize] = Some(out.into());
                    return;
                }
                j -= 1;
                idx[j] += 1;
                if idx[j] < ends[j].len() {
                    cur[j] = ends[j][idx[j]];
                    break;
                }
                idx[j] = 0;
                cur[j] = ends[j][0];
            }
        }
    }

    /// Cells the read obstacles may sweep in one step from configuration `id`.
    pub fn config_danger(&self, id: u32) -> Bits {
        let mut d = vec![0u64; self.nw];
        let oc = self.config(id);
        for (j, &c) in oc.iter().enumerate() {
            let c = c as usize;
            for m in &self.spec.obstacles[j] {
                if bit(&m.valid, c) {
                    for &o in &m.offsets {
                        let x = (c as i64 + o) as usize;
                        d[x / 64] |= 1 << (x % 64);
                    }
                } else {
                    d[c / 64] |= 1 << (c % 64);
                }
            }
        }
        d
    }

    /// Per robot move k: cells from which k collides with nothing in step t.
    pub fn safe_sources(&self, t: usize, id: u32) -> Vec<Bits> {
        let mut danger = self.config_danger(id);
        for (w, a) in danger.iter_mut().zip(&self.spec.abstract_danger[t]) {
            *w |= a;
        }
        let mut tmp = vec![0u64; self.nw];
        self.spec
            .robot
            .iter()
            .map(|m| {
                let mut v = vec![0u64; self.nw];
                for &o in &m.offsets {
                    shift(&danger, -o, &mut tmp);
                    v.iter_mut().zip(&tmp).for_each(|(a, b)| *a |= b);
                }
                (0..self.nw)
                    .map(|i| {
                        let hit = ((v[i] & m.valid[i]) | (danger[i] & !m.valid[i])) & self.full[i];
                        m.free[i] & !hit & self.full[i]
                    })
                    .collect()
            })
            .collect()
    }

    /// End cells of robot move k from every cell of `mask` (`AgentGeometry.image`).
    pub fn image(&self, mask: &[u64], k: usize, out: &mut [u64], tmp: &mut [u64]) {
        let m = &self.spec.robot[k];
        let v: Vec<u64> = (0..self.nw)
            .map(|i| mask[i] & m.free[i] & m.valid[i])
            .collect();
        shift(&v, m.to, tmp);
        for i in 0..self.nw {
            out[i] = tmp[i] | (mask[i] & m.free[i] & !m.valid[i]);
        }
    }

    /// Cells from which robot move k is wall-free and ends in `target` (`AgentGeometry.pre`).
    pub fn pre(&self, target: &[u64], k: usize, out: &mut [u64]) {
        let m = &self.spec.robot[k];
        shift(target, -m.to, out);
        for i in 0..self.nw {
            out[i] = ((out[i] & m.valid[i]) | (target[i] & !m.valid[i])) & m.free[i];
        }
    }

    pub fn robot_end(&self, r: usize, k: usize) -> usize {
        let m = &self.spec.robot[k];
        if bit(&m.valid, r) {
            (r as i64 + m.to) as usize
        } else {
            r
        }
    }
}
