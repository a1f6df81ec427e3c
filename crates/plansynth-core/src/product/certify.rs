//! The certificate of an unrealizable safety game: the obstacles' rank strategy played
//! from the start against every robot move (the mirror of
//! `plansynth.grid.native.product.certify.check_refutation` for safety). In every state
//! reached, each robot move must either meet a colliding reply or have a reply into a
//! state of smaller rank; ranks only decrease, so every play collides within the
//! start's rank.

use super::{Limits, ProductGame, Stop};

impl ProductGame {
    /// `Ok(states checked)` when the rank strategy wins from the start; `Err` with the
    /// first state where it does not (or the budget).
    pub fn certify_safety(&self, limits: Limits) -> Result<Result<usize, String>, Stop> {
        assert!(self.solved);
        let nw = self.nw;
        let mut seen = vec![0u64; self.n_configs() * nw];
        let start = (0u32, self.spec.start as u32);
        let mut queue = vec![start];
        seen[self.spec.start / 64] |= 1 << (self.spec.start % 64);
        let mut head = 0;
        while head < queue.len() {
            let (id, r) = queue[head];
            head += 1;
            let rank = self.rank_of(id, r as usize);
            if rank == 0 {
                return Ok(Err(format!("state ({id}, {r}) is winning for the robot")));
            }
            for (k, m) in self.spec.robot.iter().enumerate() {
                if m.free[r as usize / 64] >> (r % 64) & 1 == 0 || self.hits(id, r as usize, k) {
                    continue; // a wall, or a reply that collides with the move
                }
                let e = self.robot_end(r as usize, k);
                let mut best: Option<(u8, u32)> = None;
                for &s in self.successors(id) {
                    if self.spec.position && self.in_blocks(s, e) {
                        best = Some((0, s));
                        break;
                    }
                    let rs = self.rank_of(s, e);
                    if rs != 0 && best.is_none_or(|(b, _)| rs < b) {
                        best = Some((rs, s));
                    }
                }
                match best {
                    Some((0, _)) => continue, // collides
                    Some((rs, s)) if rs < rank => {
                        let w = &mut seen[s as usize * nw + e / 64];
                        if *w >> (e % 64) & 1 == 0 {
                            *w |= 1 << (e % 64);
                            queue.push((s, e as u32));
                        }
                    }
                    _ => {
                        return Ok(Err(format!(
                        "state ({id}, {r}) of rank {rank}: move {k} has no reply of smaller rank"
                    )))
                    }
                }
            }
            if head % 65536 == 0 {
                limits.check(
                    self.bytes() + seen.capacity() * 8 + queue.capacity() * 8,
                    "checking the obstacles' strategy",
                )?;
            }
        }
        Ok(Ok(queue.len()))
    }
}
