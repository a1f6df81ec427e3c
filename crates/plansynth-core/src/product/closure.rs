//! A program's closed loop on the solved product game: the states it reaches from the
//! start against every obstacle behaviour, and the states where it plays a move that
//! does not keep it winning (the mirror of
//! `plansynth.grid.native.product.program.ProductCheck.closure`). A program wins iff
//! there are none: every reached state then plays a move of the most permissive
//! winning strategy.

use super::{Limits, ProductGame, Stop};
use crate::game::Op;
use crate::program_tree::ProgramTree;

/// What one exploration of a program's closed loop found.
#[derive(Clone, Debug, Default)]
pub struct Closure {
    /// states reached (each once)
    pub reached: usize,
    /// states where the program plays a move that is not allowed (not followed)
    pub bad: Vec<(u32, u32)>,
    /// reached states that were not in the learner's sample (added to it when asked)
    pub fresh: usize,
}

impl ProductGame {
    /// Explore the closed loop of `prog` (root: its last node). With `grow`, every
    /// reached state not in the sample joins it. The reached states stay marked in
    /// `seen` (one robot-cell set per configuration) until the next call.
    pub fn closure(&mut self, prog: &[Op], grow: bool, limits: Limits) -> Result<Closure, Stop> {
        assert!(self.solved, "closure of an unsolved game");
        let (nw, n) = (self.nw, self.n_configs());
        let tree = ProgramTree::new(prog);
        self.seen.clear();
        self.seen.resize(n * nw, 0);
        if self.in_sample.len() != n * nw {
            self.in_sample = vec![0; n * nw];
        }
        let mut out = Closure::default();
        let start = (0u32, self.spec.start as u32);
        let mut queue: Vec<(u32, u32)> = vec![start];
        set(&mut self.seen, nw, start);
        let mut x: Vec<i64> = Vec::with_capacity(self.spec.n_vars());
        let mut head = 0usize;
        let n_moves = self.spec.robot.len() as i64;
        while head < queue.len() {
            let (id, r) = queue[head];
            head += 1;
            out.reached += 1;
            let key = (self.representative(id), r);
            if grow && !get(&self.in_sample, nw, key) {
                set(&mut self.in_sample, nw, key);
                if self.sample.len() == self.sample.capacity() {
                    let more = self.sample.len().max(1024);
                    let held = self.bytes();
                    reserve_within(&mut self.sample, more, held, &limits)?;
                }
                self.sample.push(key);
                out.fresh += 1;
            }
            self.inputs(id, r as usize, &mut x);
            let k = tree.run(&x);
            if !(0..n_moves).contains(&k) || !self.allows(id, r as usize, k as usize) {
                out.bad.push((id, r));
                continue;
            }
            let e = self.robot_end(r as usize, k as usize) as u32;
            for j in 0..self.successors(id).len() {
                let s = self.successors(id)[j];
                if !get(&self.seen, nw, (s, e)) {
                    set(&mut self.seen, nw, (s, e));
                    if queue.len() == queue.capacity() {
                        let more = queue.len().max(1024);
                        reserve_within(&mut queue, more, self.bytes(), &limits)?;
                    }
                    queue.push((s, e));
                }
            }
            if head % 65536 == 0 {
                limits.check(
                    self.bytes() + queue.capacity() * 8 + self.seen.capacity() * 8,
                    "the program's closed loop",
                )?;
            }
        }
        Ok(out)
    }

    /// The states of the last closure, per configuration: (configuration id, its
    /// robot-cell set as words), non-empty ones only.
    pub fn reached_sets(&self) -> Vec<(u32, &[u64])> {
        let nw = self.nw;
        (0..self.n_configs())
            .filter_map(|id| {
                let w = &self.seen[id * nw..(id + 1) * nw];
                w.iter().any(|&v| v != 0).then_some((id as u32, w))
            })
            .collect()
    }

    /// The sample's rows: (inputs, allowed moves mask) per state.
    pub fn sample_rows(&self) -> Vec<(Vec<i64>, u32)> {
        let mut x = Vec::new();
        self.sample
            .iter()
            .map(|&(id, r)| {
                let a = self.label(id, r as usize);
                self.sample_inputs(id, r as usize, &mut x);
                (x.clone(), a)
            })
            .collect()
    }

    pub fn sample_len(&self) -> usize {
        self.sample.len()
    }

    /// Start the learner's sample with the start state.
    pub fn reset_sample(&mut self) {
        self.sample.clear();
        self.in_sample = vec![0; self.n_configs() * self.nw];
        let s = (self.representative(0), self.spec.start as u32);
        set(&mut self.in_sample, self.nw, s);
        self.sample.push(s);
    }
}

#[inline]
fn get(bits: &[u64], nw: usize, (id, r): (u32, u32)) -> bool {
    bits[id as usize * nw + r as usize / 64] >> (r % 64) & 1 == 1
}

#[inline]
fn set(bits: &mut [u64], nw: usize, (id, r): (u32, u32)) {
    bits[id as usize * nw + r as usize / 64] |= 1 << (r % 64);
}

/// Reserve `more` elements in `v` within the byte budget (`held`: the bytes the game
/// holds already): a vector that doubles needs its old and its new buffer at once, and
/// an allocation the process cannot get (its address-space limit) is a `Stop` for
/// memory, not an abort of the whole process.
fn reserve_within<T>(
    v: &mut Vec<T>,
    more: usize,
    held: usize,
    limits: &Limits,
) -> Result<(), Stop> {
    let size = std::mem::size_of::<T>();
    let need = v
        .capacity()
        .saturating_mul(2)
        .saturating_add(more)
        .saturating_mul(size);
    limits.check(held.saturating_add(need), "the program's closed loop")?;
    v.try_reserve_exact(more).map_err(|_| Stop {
        resource: "memory",
        detail: format!(
            "the program's closed loop: {} MB more could not be allocated",
            more.saturating_mul(size) >> 20
        ),
    })
}

#[cfg(test)]
mod reserve_tests {
    use super::{reserve_within, Limits};

    #[test]
    fn growth_past_the_byte_budget_is_a_memory_stop() {
        let mut v: Vec<u64> = Vec::with_capacity(1024);
        let limits = Limits {
            deadline: None,
            max_bytes: Some(64 << 10),
        };
        assert!(reserve_within(&mut v, 1024, 0, &limits).is_ok());
        let stop = reserve_within(&mut v, 1 << 20, 0, &limits).unwrap_err();
        assert_eq!(stop.resource, "memory");
    }

    #[test]
    fn an_allocation_the_process_cannot_get_is_a_memory_stop() {
        let mut v: Vec<u64> = Vec::new();
        let limits = Limits {
            deadline: None,
            max_bytes: None,
        };
        let stop = reserve_within(&mut v, usize::MAX / 16, 0, &limits).unwrap_err();
        assert_eq!(stop.resource, "memory");
        assert!(stop.detail.contains("could not be allocated"));
    }
}
