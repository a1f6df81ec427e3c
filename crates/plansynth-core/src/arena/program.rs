//! The program check on the solved game, without building its graph: is each move the
//! program plays safe, and does it win against every obstacle reply?

use std::time::Instant;

use super::{Arena, Budget, Stop};
use crate::bits::bit;

impl Arena {
    /// Whether read obstacle j on cell c may sweep cell x in one step.
    fn obstacle_sweeps(&self, j: usize, c: usize, x: usize) -> bool {
        self.spec.obstacles[j].iter().any(|m| {
            if bit(&m.valid, c) {
                m.offsets.iter().any(|&o| c as i64 + o == x as i64)
            } else {
                c == x
            }
        })
    }

    /// Whether robot move k is safe at (t, cell r, configuration id) of the explored
    /// game: (t, r, id) is explored, and k sweeps no wall and nothing an obstacle may
    /// sweep in step t (read, or folded into the step's danger).
    pub fn move_safe(&self, t: usize, r: usize, id: u32, k: usize) -> bool {
        let m = &self.spec.robot[k];
        if !bit(&m.free, r)
            || self
                .row(t, id)
                .is_none_or(|row| !bit(&self.layers[t].masks[row * self.nw..], r))
        {
            return false;
        }
        let valid = bit(&m.valid, r);
        let n_sw = if valid { m.offsets.len() } else { 1 };
        let oc = self.config(id);
        (0..n_sw).all(|i| {
            let x = if valid {
                (r as i64 + m.offsets[i]) as usize
            } else {
                r
            };
            !bit(&self.spec.abstract_danger[t], x)
                && !oc
                    .iter()
                    .enumerate()
                    .any(|(j, &c)| self.obstacle_sweeps(j, c as usize, x))
        })
    }

    /// Whether end cell e wins at t + 1 against every obstacle reply from `id` (needs
    /// [`Arena::solve_game`]).
    pub fn end_wins(&mut self, t: usize, e: usize, id: u32) -> bool {
        let nw = self.nw;
        self.succ_of(id);
        let succ = self.succ[id as usize].as_deref().unwrap_or(&[]);
        let next = &self.layers[t + 1];
        succ.iter().all(|c2| {
            next.index
                .get(c2)
                .is_some_and(|&i| !next.win.is_empty() && bit(&next.win[i as usize * nw..], e))
        })
    }

    /// Whether robot move k wins at (t, cell r, configuration id) of the solved game.
    pub fn move_wins(&mut self, t: usize, r: usize, id: u32, k: usize) -> bool {
        self.move_safe(t, r, id, k) && self.end_wins(t, self.robot_end(r, k), id)
    }

    /// The program check on the solved game without building its graph: follow the
    /// program from the start, breadth-first over (time, robot cell, configuration);
    /// None when it plays a winning move in every pair it reaches (it then wins the
    /// bounded game, SYNT 2016 Section 3.1), else the first pair where it does not.
    /// `width` gives the controller's inputs (rx, ry, o0x, o0y, ...).
    pub fn check_program(
        &mut self,
        prog: &[crate::game::Op],
        root: usize,
        width: usize,
        clock: &Budget,
    ) -> Result<Option<(usize, usize, u32)>, Stop> {
        let steps = self.spec.steps;
        let nw = self.nw;
        let n_moves = self.spec.robot.len() as i64;
        if self.layers[0].ids.is_empty() {
            return Ok(Some((0, self.spec.start, 0)));
        }
        // per layer, per row: the robot cells queued (pairs met), and per (row, end
        // cell) whether the end cell's replies were judged and won. Zeroed allocations:
        // the pages a check never touches cost nothing.
        let mut seen: Vec<Vec<u64>> = self
            .layers
            .iter()
            .map(|l| vec![0u64; l.ids.len() * nw])
            .collect();
        let mut judged: Vec<Vec<u64>> = self
            .layers
            .iter()
            .map(|l| vec![0u64; l.ids.len() * nw])
            .collect();
        let mut won: Vec<Vec<u64>> = self
            .layers
            .iter()
            .map(|l| vec![0u64; l.ids.len() * nw])
            .collect();
        let set = |m: &mut Vec<u64>, row: usize, c: usize| -> bool {
            let w = &mut m[row * nw + c / 64];
            let had = *w >> (c % 64) & 1 == 1;
            *w |= 1 << (c % 64);
            had
        };
        let s0 = self.spec.start;
        let mut queue: Vec<(u32, u32, u32)> = vec![(0, 0, s0 as u32)];
        set(&mut seen[0], 0, s0);
        let mut head = 0;
        let mut x: Vec<i64> = vec![];
        while head < queue.len() {
            let (t, row, r) = queue[head];
            head += 1;
            let (t, row, r) = (t as usize, row as usize, r as usize);
            let id = self.layers[t].ids[row];
            x.clear();
            x.push((r % width) as i64);
            x.push((r / width) as i64);
            for &c in self.config(id) {
                x.push((c as usize % width) as i64);
                x.push((c as usize / width) as i64);
            }
            let k = crate::game::eval(prog, root, &x);
            if !(0..n_moves).contains(&k) || !self.move_safe(t, r, id, k as usize) {
                return Ok(Some((t, r, id)));
            }
            // every (r, k) of this row ending in e has the same replies
            let e = self.robot_end(r, k as usize);
            if bit(&judged[t][row * nw..], e) {
                if !bit(&won[t][row * nw..], e) {
                    return Ok(Some((t, r, id)));
                }
                continue;
            }
            set(&mut judged[t], row, e);
            let l = &self.layers[t];
            let (a, b) = (l.next_off[row] as usize, l.next_off[row + 1] as usize);
            let next = &self.layers[t + 1];
            let ok = a < b
                && !next.win.is_empty()
                && l.next[a..b]
                    .iter()
                    .all(|&i| bit(&next.win[i as usize * nw..], e));
            if !ok {
                return Ok(Some((t, r, id)));
            }
            set(&mut won[t], row, e);
            if t + 1 < steps {
                for &i in &self.layers[t].next[a..b] {
                    if !set(&mut seen[t + 1], i as usize, e) {
                        queue.push((t as u32 + 1, i, e as u32));
                    }
                }
            }
            if head % 4096 == 0 && clock.deadline.is_some_and(|d| Instant::now() >= d) {
                return Err(Stop::Time {
                    step: t,
                    configs: 0,
                });
            }
        }
        Ok(None)
    }
}
