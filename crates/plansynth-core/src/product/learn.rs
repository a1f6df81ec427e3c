//! Programs learnt on their own closed loop (the mirror of
//! `plansynth.grid.native.product.program.learn_program`'s rounds): the greedy decision
//! tree of `crate::tree` over the conditions of `crate::conditions` maps every sampled
//! state to one of its allowed moves; the states its closed loop reaches join the
//! sample; the rounds end when the closed loop plays allowed moves only.
//!
//! On large samples the conditions are enumerated on an evenly spaced part of the
//! sample (their behaviours there decide which terms are kept); the tree is then grown
//! over every sampled state's inputs (`crate::tree_rows`: the same tree as over the
//! conditions' behaviour bit sets, without them).

use super::{Limits, ProductGame, Stop};
use crate::conditions::{enumerate_conditions, Arith, Cond};
use crate::game::Op;
use crate::tree::{GreedyError, Node};
use crate::tree_rows::greedy_tree_rows_part;

/// One round's outcome: whether the tree's closed loop plays allowed moves only, the
/// sample's size after the round, the tree (pre-order nodes over `conds`, which are over
/// `terms`) and the states its closed loop reached.
#[derive(Clone, Debug)]
pub struct Round {
    pub closed: bool,
    pub sample: usize,
    pub reached: usize,
    pub terms: Vec<(Arith, u32)>,
    pub conds: Vec<(Cond, u32)>,
    pub nodes: Vec<Node>,
    /// seconds of the round's steps: labels, conditions, tree, closure
    pub seconds: [f64; 4],
}

impl ProductGame {
    /// One round (see the module docs). `enum_states`: the part of the sample the
    /// conditions are enumerated on; `tree_states`: on a larger sample the tree is grown
    /// on an evenly spaced part of about this many states, then refined on the whole
    /// sample (`crate::tree_rows::greedy_tree_rows_part`).
    #[allow(clippy::too_many_arguments)]
    pub fn learn_round(
        &mut self,
        cond_depth: u32,
        max_constant: i64,
        max_nodes: usize,
        enum_states: usize,
        tree_states: Option<usize>,
        limits: Limits,
    ) -> Result<Round, Stop> {
        if self.sample.is_empty() {
            self.reset_sample();
        }
        let n_vars = self.spec.n_vars();
        let n = self.sample.len();
        let mut seconds = [0.0f64; 4];
        let mut t = std::time::Instant::now();
        let mut lap = |i: usize, t: &mut std::time::Instant| {
            seconds[i] += t.elapsed().as_secs_f64();
            *t = std::time::Instant::now();
        };
        // the sample's inputs, one row of `n_vars` after another
        limits.check(self.bytes() + n * (n_vars * 8 + 4), "learning a program")?;
        let mut rows: Vec<i64> = Vec::with_capacity(n * n_vars);
        let mut x = Vec::with_capacity(n_vars);
        for &(id, r) in &self.sample {
            self.sample_inputs(id, r as usize, &mut x);
            rows.extend_from_slice(&x);
        }
        let allowed = self.sample_labels();
        lap(0, &mut t);
        let stride = n.div_ceil(enum_states.max(1)).max(1);
        let part: Vec<Vec<i64>> = rows
            .chunks_exact(n_vars)
            .step_by(stride)
            .map(|x| x.to_vec())
            .collect();
        let e = enumerate_conditions(&part, n_vars, max_constant, cond_depth, Some(20_000));
        let terms = e.terms;
        let conds: Vec<(Cond, u32)> = e.conds.iter().map(|(_, c, d)| (*c, *d)).collect();
        lap(1, &mut t);
        let keys: Vec<(u32, u32)> = {
            let ts = term_sizes(&terms);
            cond_sizes(&conds, &ts)
                .into_iter()
                .zip(&conds)
                .map(|(s, (_, d))| (*d, s))
                .collect()
        };
        let part = tree_states
            .filter(|&m| m > 0 && n > m)
            .map(|m| n.div_ceil(m));
        let nodes = match greedy_tree_rows_part(
            &terms,
            &conds,
            &keys,
            rows,
            n_vars,
            &allowed,
            self.spec.robot.len(),
            max_nodes,
            part,
        ) {
            Ok(nodes) => nodes,
            Err(GreedyError::TooLarge) => {
                return Err(Stop {
                    resource: "nodes",
                    detail: format!("the greedy tree needs more than {max_nodes} splits"),
                })
            }
            Err(GreedyError::NoSplit) => {
                return Err(Stop {
                    resource: "conditions",
                    detail: "no condition separates two sampled states".into(),
                })
            }
        };
        lap(2, &mut t);
        let ops = program_ops(&terms, &conds, &nodes);
        let c = self.closure(&ops, true, limits)?;
        lap(3, &mut t);
        Ok(Round {
            closed: c.bad.is_empty(),
            sample: self.sample.len(),
            reached: c.reached,
            terms,
            conds,
            nodes,
            seconds,
        })
    }
}

impl ProductGame {
    /// Learn with the glitch counters projected out: the sample holds one state per
    /// class of configurations that differ only in glitches left, labelled with the
    /// moves allowed at the hardest level where the state still wins (most glitches
    /// left). For the obstacles of the format a move allowed there is allowed at every
    /// easier level of the class (fewer glitches left never help the obstacles), so a
    /// program that does not read the glitches can follow the labels; the closed loop of
    /// every round still checks the full states, so the projection is only a choice of
    /// labels, never an assumption of the answer.
    pub fn project_glitches(&mut self) {
        let n = self.n_configs();
        let mut index: crate::fx::HashMap<Vec<u64>, u32> = crate::fx::HashMap::default();
        self.rep = vec![0; n];
        for id in 0..n as u32 {
            // cell and wait counter (bits 0..40) of every obstacle
            let key: Vec<u64> = self
                .config(id)
                .iter()
                .map(|&s| s & 0xff_ffff_ffff)
                .collect();
            self.rep[id as usize] = *index.entry(key).or_insert(id);
        }
        let left: Vec<u32> = (0..n as u32)
            .map(|id| self.config(id).iter().map(|&s| super::unpack(s).2).sum())
            .collect();
        self.family = vec![vec![]; n];
        for id in 0..n as u32 {
            self.family[self.rep[id as usize] as usize].push(id);
        }
        for f in &mut self.family {
            f.sort_by_key(|&i| std::cmp::Reverse(left[i as usize]));
        }
        self.sample.clear();
        self.in_sample.clear();
    }

    /// The representative of configuration `id` in the learner's sample.
    pub(super) fn representative(&self, id: u32) -> u32 {
        if self.rep.is_empty() {
            id
        } else {
            self.rep[id as usize]
        }
    }

    /// The moves a sampled state is labelled with (see [`ProductGame::project_glitches`]
    /// and [`ProductGame::prefer_central`]).
    pub(super) fn label(&self, id: u32, r: usize) -> u32 {
        let mask = if self.rep.is_empty() {
            self.allowed(id, r)
        } else {
            self.family[id as usize]
                .iter()
                .find(|&&m| self.wins(m, r))
                .map_or(0, |&m| self.allowed(m, r))
        };
        if self.central {
            self.central_moves(r, mask)
        } else {
            mask
        }
    }

    /// The labels of the sampled states (those of [`ProductGame::label`], its reference),
    /// computed a configuration at a time on cell sets: per member of a sampled
    /// configuration's class, the cells where each move keeps the robot winning are
    /// those of the safety fixpoint's step (`good`), so a state costs a few bit tests
    /// instead of a lookup per move and reply. The sample is split among the threads of
    /// [`crate::par`].
    pub fn sample_labels(&self) -> Vec<u32> {
        let parts = crate::par::map_ranges(self.sample.len(), 1 << 16, |range| {
            let (nw, n_moves) = (self.nw, self.spec.robot.len());
            let mut sets = vec![0u64; n_moves * nw];
            let mut scratch = (vec![0u64; nw], vec![0u64; nw], vec![0u64; nw]);
            let mut cur: Option<u32> = None;
            let mut out = Vec::with_capacity(range.len());
            for &(id, r) in &self.sample[range] {
                if cur != Some(id) {
                    self.label_sets(id, &mut sets, &mut scratch);
                    cur = Some(id);
                }
                let (w, b) = (r as usize / 64, r % 64);
                let mask = (0..n_moves).fold(0u32, |acc, k| {
                    acc | ((sets[k * nw + w] >> b & 1) as u32) << k
                });
                out.push(if self.central {
                    self.central_moves(r as usize, mask)
                } else {
                    mask
                });
            }
            out
        });
        parts.concat()
    }

    /// Per move, the robot cells of sampled configuration `id` it is labelled with
    /// (before `prefer_central`): `n_moves` sets of `nw` words.
    fn label_sets(&self, id: u32, sets: &mut [u64], scratch: &mut (Vec<u64>, Vec<u64>, Vec<u64>)) {
        let nw = self.nw;
        let (target, tmp, left) = scratch;
        sets.iter_mut().for_each(|w| *w = 0);
        left.iter_mut().for_each(|w| *w = !0);
        let own = [id];
        let members: &[u32] = if self.rep.is_empty() {
            &own
        } else {
            &self.family[id as usize]
        };
        for &m in members {
            let win = &self.win[m as usize * nw..(m as usize + 1) * nw];
            if win.iter().zip(left.iter()).all(|(a, b)| a & b == 0) {
                continue;
            }
            self.target(m, target);
            for k in 0..self.spec.robot.len() {
                self.good_move(m, k, target, tmp);
                for i in 0..nw {
                    sets[k * nw + i] |= tmp[i] & win[i] & left[i];
                }
            }
            for i in 0..nw {
                left[i] &= !win[i];
            }
        }
    }

    /// Label the learner's states with the allowed moves that end nearest the middle of
    /// the grid (in the max norm) only. Any allowed move keeps the robot winning; these
    /// keep it where it has most room, so the program's closed loop (what the checks
    /// and the verifier go through) is smaller: on the 16 x 16 moving-obstacle game a
    /// strategy that prefers them reaches 51 thousand states, one that prefers staying
    /// 361 thousand, out of 460 thousand.
    pub fn prefer_central(&mut self, on: bool) {
        self.central = on;
    }

    /// The moves of `mask` from cell `r` whose end is nearest the middle of the grid
    /// (the max norm of twice the offset, so that it stays an integer).
    pub fn central_moves(&self, r: usize, mask: u32) -> u32 {
        let (w, h) = (self.spec.width as i64, self.spec.height as i64);
        let dist = |k: usize| {
            let e = self.robot_end(r, k) as i64;
            (2 * (e % w) - (w - 1))
                .abs()
                .max((2 * (e / w) - (h - 1)).abs())
        };
        let n = self.spec.robot.len();
        let Some(best) = (0..n).filter(|&k| mask >> k & 1 == 1).map(dist).min() else {
            return 0;
        };
        (0..n)
            .filter(|&k| mask >> k & 1 == 1 && dist(k) == best)
            .fold(0, |acc, k| acc | 1 << k)
    }

    /// A sampled state's inputs (under the projection, its glitches read as 0).
    pub(super) fn sample_inputs(&self, id: u32, r: usize, out: &mut Vec<i64>) {
        self.inputs(id, r, out);
        if self.rep.is_empty() {
            return;
        }
        let mut j = 2;
        for o in &self.spec.obstacles {
            j += 2 + o.periodic() as usize;
            if o.glitching() {
                out[j] = 0;
                j += 1;
            }
        }
    }
}

fn term_sizes(terms: &[(Arith, u32)]) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::with_capacity(terms.len());
    for (t, _) in terms {
        let s = match *t {
            Arith::Const(_) | Arith::Var(_) => 1,
            Arith::Plus(a, b) | Arith::Minus(a, b) => 1 + out[a] + out[b],
        };
        out.push(s);
    }
    out
}

fn cond_sizes(conds: &[(Cond, u32)], ts: &[u32]) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::with_capacity(conds.len());
    for (c, _) in conds {
        let s = match *c {
            Cond::Le(a, b) | Cond::Eq(a, b) => 1 + ts[a] + ts[b],
            Cond::Not(a) => 1 + out[a],
            Cond::And(a, b) | Cond::Or(a, b) => 1 + out[a] + out[b],
        };
        out.push(s);
    }
    out
}

/// The tree as program ops (children first, root last).
pub fn program_ops(terms: &[(Arith, u32)], conds: &[(Cond, u32)], nodes: &[Node]) -> Vec<Op> {
    let mut ops: Vec<Op> = vec![];
    let mut term_at: Vec<usize> = vec![];
    for (t, _) in terms {
        let op = match *t {
            Arith::Const(c) => Op::Const(c),
            Arith::Var(j) => Op::Var(j),
            Arith::Plus(a, b) => Op::Plus(term_at[a], term_at[b]),
            Arith::Minus(a, b) => Op::Minus(term_at[a], term_at[b]),
        };
        ops.push(op);
        term_at.push(ops.len() - 1);
    }
    let mut cond_at: Vec<usize> = vec![];
    for (c, _) in conds {
        let op = match *c {
            Cond::Le(a, b) => Op::Le(term_at[a], term_at[b]),
            Cond::Eq(a, b) => Op::Eq(term_at[a], term_at[b]),
            Cond::Not(a) => Op::Not(cond_at[a]),
            Cond::And(a, b) => Op::And(cond_at[a], cond_at[b]),
            Cond::Or(a, b) => Op::Or(cond_at[a], cond_at[b]),
        };
        ops.push(op);
        cond_at.push(ops.len() - 1);
    }
    let mut it = nodes.iter();
    build(&mut it, &cond_at, &mut ops);
    ops
}

fn build(it: &mut std::slice::Iter<'_, Node>, cond_at: &[usize], ops: &mut Vec<Op>) -> usize {
    match *it.next().expect("a complete pre-order tree") {
        Node::Leaf(k) => {
            ops.push(Op::Const(k as i64));
            ops.len() - 1
        }
        Node::Split(j) => {
            let t = build(it, cond_at, ops);
            let e = build(it, cond_at, ops);
            ops.push(Op::Ite(cond_at[j], t, e));
            ops.len() - 1
        }
    }
}

impl ProductGame {
    /// Seed the learner's sample with every winning state of its (projected) game: per
    /// representative configuration, the robot cells from which some configuration of
    /// its class wins (those a label exists for, [`ProductGame::label`]). The greedy
    /// tree fits every sampled state, so a program learnt on this sample plays a
    /// labelled move in every state its closed loop can reach and closes in one round,
    /// instead of growing the sample round by round through closures of its own
    /// (each of which explores most of the game again). `None` (sample untouched) when
    /// the states number more than `max_states`; else the sample's size.
    pub fn seed_winning(&mut self, max_states: usize) -> Option<usize> {
        assert!(self.solved, "seeding the sample of an unsolved game");
        let (nw, n) = (self.nw, self.n_configs());
        let mut union = vec![0u64; nw];
        let mut total = 0usize;
        for id in 0..n as u32 {
            if self.representative(id) != id {
                continue;
            }
            self.class_win(id, &mut union);
            total += union.iter().map(|w| w.count_ones() as usize).sum::<usize>();
            if total > max_states {
                return None;
            }
        }
        self.sample.clear();
        self.sample.reserve_exact(total);
        self.in_sample = vec![0; n * nw];
        for id in 0..n as u32 {
            if self.representative(id) != id {
                continue;
            }
            self.class_win(id, &mut union);
            for (i, &w) in union.iter().enumerate() {
                self.in_sample[id as usize * nw + i] = w;
                let mut bits = w;
                while bits != 0 {
                    let b = bits.trailing_zeros();
                    self.sample.push((id, i as u32 * 64 + b));
                    bits &= bits - 1;
                }
            }
        }
        Some(self.sample.len())
    }

    /// The union of the winning sets of representative `id`'s class.
    fn class_win(&self, id: u32, out: &mut [u64]) {
        let nw = self.nw;
        out.iter_mut().for_each(|w| *w = 0);
        let own = [id];
        let members: &[u32] = if self.rep.is_empty() {
            &own
        } else {
            &self.family[id as usize]
        };
        for &m in members {
            let ws = &self.win[m as usize * nw..(m as usize + 1) * nw];
            for i in 0..nw {
                out[i] |= ws[i];
            }
        }
    }
}
