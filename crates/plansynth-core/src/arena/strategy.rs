//! What the solved game offers a stationary strategy (positions only, SYNT 2016 Section
//! 3.1): the winning-forward layers, the allowed moves of each state, the states they
//! reach, and a strategy read off the game without SAT.

use super::{Arena, Budget, Stop};
use crate::bits::{any, bit, ones_of, Bits};
use crate::fx::HashMap;

/// Or `bits` into the entry of each configuration of `succ` in the layer being built
/// (`at`: configuration -> its index in `nxt`), adding an entry for each new one.
fn merge_into(
    nxt: &mut Vec<(u32, Bits)>,
    at: &mut HashMap<u32, usize>,
    succ: &[u32],
    bits: &[u64],
) {
    for &c2 in succ {
        match at.get(&c2) {
            Some(&i) => nxt[i].1.iter_mut().zip(bits).for_each(|(a, b)| *a |= b),
            None => {
                at.insert(c2, nxt.len());
                nxt.push((c2, bits.to_vec()));
            }
        }
    }
}

impl Arena {
    /// The winning-forward layers (`stationary.winning_forward`): states reachable
    /// from the start with moves that win. Per time, `(config id, robot cells)` in the
    /// reference's order.
    pub fn winning_forward(&mut self, clock: &Budget) -> Result<Vec<Vec<(u32, Bits)>>, Stop> {
        let nw = self.nw;
        let mut out: Vec<Vec<(u32, Bits)>> = vec![];
        let c0 = self.layers[0].ids[0];
        let mut s0 = vec![0u64; nw];
        s0[self.spec.start / 64] |= 1 << (self.spec.start % 64);
        out.push(vec![(c0, s0)]);
        let (mut img, mut part, mut tmp) = (vec![0u64; nw], vec![0u64; nw], vec![0u64; nw]);
        for t in 0..self.spec.steps {
            let mut nxt: Vec<(u32, Bits)> = vec![];
            let mut at: HashMap<u32, usize> = HashMap::default();
            for (id, r) in std::mem::take(&mut out[t]).into_iter() {
                let row = match self.layers[t].index.get(&id) {
                    Some(&i) => i as usize,
                    None => {
                        out[t].push((id, r));
                        continue;
                    }
                };
                let wm = self.winning_moves(t, row);
                img.iter_mut().for_each(|w| *w = 0);
                for (k, w) in wm.iter().enumerate() {
                    let src: Bits = r.iter().zip(w).map(|(a, b)| a & b).collect();
                    self.image(&src, k, &mut part, &mut tmp);
                    img.iter_mut().zip(&part).for_each(|(a, b)| *a |= b);
                }
                if any(&img) {
                    let succ = self.successors(id);
                    merge_into(&mut nxt, &mut at, &succ, &img);
                }
                out[t].push((id, r));
            }
            out.push(nxt);
            self.check(clock, t, 0, 0).map_err(|e| match e {
                Stop::Memory { .. } => e,
                _ => Stop::Time {
                    step: t,
                    configs: 0,
                },
            })?;
        }
        Ok(out)
    }

    /// Moves of each state of `reach` that win and stay inside `reach` at every time it
    /// is met (`stationary._allowed`): `((robot cell, config id), move bitmask)` in the
    /// order states are first met.
    pub fn allowed(&mut self, reach: &[Vec<(u32, Bits)>]) -> Vec<((u32, u32), u32)> {
        let steps = self.spec.steps;
        let n_moves = self.spec.robot.len();
        let index: Vec<HashMap<u32, usize>> = reach
            .iter()
            .map(|l| l.iter().enumerate().map(|(i, (id, _))| (*id, i)).collect())
            .collect();
        let mut at: HashMap<(u32, u32), usize> = HashMap::default();
        let mut out: Vec<((u32, u32), u32)> = vec![];
        for t in 0..steps.min(reach.len()) {
            for (n, (id, rmask)) in reach[t].iter().enumerate() {
                if n % 1024 == 0 && self.out_of_time() {
                    return out;
                }
                let wm = match self.row(t, *id) {
                    Some(row) => self.winning_moves(t, row),
                    None => vec![vec![0u64; self.nw]; n_moves],
                };
                let succ = self.successors(*id);
                for r in ones_of(rmask) {
                    let mut ok = 0u32;
                    for (k, w) in wm.iter().enumerate() {
                        if !bit(w, r) {
                            continue;
                        }
                        if t + 1 < steps {
                            let e = self.robot_end(r, k);
                            let inside = succ.iter().all(|c2| {
                                index[t + 1]
                                    .get(c2)
                                    .is_some_and(|&i| bit(&reach[t + 1][i].1, e))
                            });
                            if !inside {
                                continue;
                            }
                        }
                        ok |= 1 << k;
                    }
                    match at.get(&(r as u32, *id)) {
                        Some(&i) => out[i].1 &= ok,
                        None => {
                            at.insert((r as u32, *id), out.len());
                            out.push(((r as u32, *id), ok));
                        }
                    }
                }
            }
        }
        out
    }

    /// States reached from the start when every state may play any of its allowed moves
    /// (`stationary._closure`); `allowed` as [`Arena::allowed`] gives it.
    pub fn closure(&mut self, allowed: &[((u32, u32), u32)]) -> Vec<Vec<(u32, Bits)>> {
        let nw = self.nw;
        let moves: HashMap<(u32, u32), u32> = allowed.iter().copied().collect();
        let c0 = self.layers[0].ids[0];
        let mut s0 = vec![0u64; nw];
        s0[self.spec.start / 64] |= 1 << (self.spec.start % 64);
        let mut out: Vec<Vec<(u32, Bits)>> = vec![vec![(c0, s0)]];
        for t in 0..self.spec.steps {
            let mut nxt: Vec<(u32, Bits)> = vec![];
            let mut at: HashMap<u32, usize> = HashMap::default();
            for i in 0..out[t].len() {
                if i % 1024 == 0 && self.out_of_time() {
                    return out;
                }
                let id = out[t][i].0;
                let mut ends = vec![0u64; nw];
                for r in ones_of(&out[t][i].1) {
                    let m = moves.get(&(r as u32, id)).copied().unwrap_or(0);
                    for k in 0..self.spec.robot.len() {
                        if m >> k & 1 == 1 {
                            let e = self.robot_end(r, k);
                            ends[e / 64] |= 1 << (e % 64);
                        }
                    }
                }
                let succ = self.successors(id);
                merge_into(&mut nxt, &mut at, &succ, &ends);
            }
            out.push(nxt);
        }
        out
    }

    /// A stationary strategy read off the game without SAT
    /// (`stationary.consistent_strategy`): per state, among the moves that win at every
    /// time the state is met on `fwd`, the one heading most for the goal (then the
    /// lowest number). Returns the reach layers it visits, or None when some reached
    /// state has no such move. `width` gives cell coordinates.
    pub fn consistent(
        &mut self,
        fwd: &[Vec<(u32, Bits)>],
        width: usize,
    ) -> Option<Vec<Vec<(u32, Bits)>>> {
        let nw = self.nw;
        let n_moves = self.spec.robot.len();
        let steps = self.spec.steps;
        let mut bad: HashMap<u32, Vec<Bits>> = HashMap::default();
        for t in 0..steps.min(fwd.len()) {
            for (n, (id, rmask)) in fwd[t].iter().enumerate() {
                if n % 1024 == 0 && self.out_of_time() {
                    return None;
                }
                let wm = match self.row(t, *id) {
                    Some(row) => self.winning_moves(t, row),
                    None => vec![vec![0u64; nw]; n_moves],
                };
                let b = bad
                    .entry(*id)
                    .or_insert_with(|| vec![vec![0u64; nw]; n_moves]);
                for k in 0..n_moves {
                    for i in 0..nw {
                        b[k][i] |= rmask[i] & !wm[k][i];
                    }
                }
            }
        }
        let (gx, gy) = (
            (self.spec.goal % width) as i64,
            (self.spec.goal / width) as i64,
        );
        let dist = |c: usize| ((c % width) as i64 - gx).abs() + ((c / width) as i64 - gy).abs();
        let mut choice: HashMap<(u32, u32), Option<usize>> = HashMap::default();
        let c0 = self.layers[0].ids[0];
        let mut s0 = vec![0u64; nw];
        s0[self.spec.start / 64] |= 1 << (self.spec.start % 64);
        let mut reach: Vec<Vec<(u32, Bits)>> = vec![vec![(c0, s0)]];
        for t in 0..steps {
            let mut nxt: Vec<(u32, Bits)> = vec![];
            let mut at: HashMap<u32, usize> = HashMap::default();
            for i in 0..reach[t].len() {
                if i % 1024 == 0 && self.out_of_time() {
                    return None;
                }
                let id = reach[t][i].0;
                let mut ends = vec![0u64; nw];
                for r in ones_of(&reach[t][i].1) {
                    let k = *choice.entry((r as u32, id)).or_insert_with(|| {
                        let b = bad.get(&id);
                        let mut best: Option<((i64, usize), usize)> = None;
                        for k in 0..n_moves {
                            if b.is_none_or(|b| bit(&b[k], r)) {
                                continue;
                            }
                            let e = self.robot_end(r, k);
                            let rank = (dist(e) - dist(r), k);
                            if best.is_none_or(|(bb, _)| rank < bb) {
                                best = Some((rank, k));
                            }
                        }
                        best.map(|(_, k)| k)
                    });
                    let k = k?;
                    let e = self.robot_end(r, k);
                    ends[e / 64] |= 1 << (e % 64);
                }
                let succ = self.successors(id);
                merge_into(&mut nxt, &mut at, &succ, &ends);
            }
            reach.push(nxt);
        }
        Some(reach)
    }
}
