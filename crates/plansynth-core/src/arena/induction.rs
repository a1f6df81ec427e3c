//! Backward induction over the explored game: the moves that win at each time, and
//! whether the robot wins when it may see the time.

use super::{Arena, Budget, Stop};
use crate::bits::{any, bit, Bits};

impl Arena {
    /// Per robot move k: robot cells of row `row` of layer t from which k wins at t
    /// (needs [`Arena::solve_game`]'s `win[t + 1]`).
    pub fn winning_moves(&mut self, t: usize, row: usize) -> Vec<Bits> {
        let nw = self.nw;
        let id = self.layers[t].ids[row];
        let l = &self.layers[t];
        let (a, b) = (l.next_off[row] as usize, l.next_off[row + 1] as usize);
        // no successor rows: the robot has no live move here (an empty AND would be all)
        let mut target = vec![if a == b { 0 } else { !0u64 }; nw];
        let next = &self.layers[t + 1];
        for &i in &l.next[a..b] {
            if next.win.is_empty() {
                target.iter_mut().for_each(|w| *w = 0);
            } else {
                let i = i as usize;
                target
                    .iter_mut()
                    .zip(&next.win[i * nw..(i + 1) * nw])
                    .for_each(|(x, y)| *x &= y);
            }
            if !any(&target) {
                break;
            }
        }
        let safe = self.safe_sources(t, id);
        let r = &self.layers[t].masks[row * nw..(row + 1) * nw];
        let mut out = Vec::with_capacity(safe.len());
        let mut p = vec![0u64; nw];
        for (k, s) in safe.iter().enumerate() {
            if any(&target) {
                self.pre(&target, k, &mut p);
            } else {
                p.iter_mut().for_each(|w| *w = 0);
            }
            out.push((0..nw).map(|i| p[i] & s[i] & r[i]).collect());
        }
        out
    }

    /// Backward induction (`Arena.solve_game`): true iff the robot wins when it may
    /// also see the time. Leaves `win` of every layer (zero rows lose).
    pub fn solve_game(&mut self, clock: &Budget) -> Result<bool, Stop> {
        let nw = self.nw;
        let steps = self.spec.steps;
        for l in self.layers.iter_mut() {
            l.win = vec![0u64; l.masks.len()];
        }
        let g = self.spec.goal;
        {
            let last = &mut self.layers[steps];
            for row in 0..last.ids.len() {
                let v = last.masks[row * nw + g / 64] & (1 << (g % 64));
                last.win[row * nw + g / 64] = v;
            }
        }
        for t in (0..steps).rev() {
            for row in 0..self.layers[t].ids.len() {
                let wm = self.winning_moves(t, row);
                let l = &mut self.layers[t];
                for m in &wm {
                    l.win[row * nw..(row + 1) * nw]
                        .iter_mut()
                        .zip(m)
                        .for_each(|(a, b)| *a |= b);
                }
                if row % 64 == 0 {
                    self.check(clock, t, 0, 0).map_err(|e| match e {
                        Stop::Memory { .. } => e,
                        _ => Stop::Time {
                            step: t,
                            configs: 0,
                        },
                    })?;
                }
            }
        }
        self.solved = true;
        let s = self.spec.start;
        Ok(self.layers[0].ids.first().is_some() && bit(&self.layers[0].win[0..nw], s))
    }
}
