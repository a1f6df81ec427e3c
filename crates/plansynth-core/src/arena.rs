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

use std::collections::HashMap as StdMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::time::Instant;

/// The multiply-rotate hash of rustc (FxHash): the keys here are small integers and
/// slices of cell indices, where SipHash's protection against chosen keys buys nothing
/// and costs most of the time of a lookup.
#[derive(Default, Clone, Copy)]
pub struct Fx(u64);

impl Hasher for Fx {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut w = [0u8; 8];
            w[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(w));
        }
    }
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_u32(&mut self, i: u32) {
        self.write_u64(i as u64);
    }
    fn write_usize(&mut self, i: usize) {
        self.write_u64(i as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

pub type HashMap<K, V> = StdMap<K, V, BuildHasherDefault<Fx>>;
pub type HashSet<K> = std::collections::HashSet<K, BuildHasherDefault<Fx>>;

/// A set of cells: bit `i` of word `i / 64` is cell `i` (`y * width + x`).
pub type Bits = Vec<u64>;

/// Or `bits` into the entry of each configuration of `succ` in the layer being built
/// (`at`: configuration -> its index in `nxt`), adding an entry for each new one.
fn merge_into(nxt: &mut Vec<(u32, Bits)>, at: &mut HashMap<u32, usize>, succ: &[u32], bits: &[u64]) {
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

/// Move every cell of `src` by `d` cells (no border check: callers mask first).
pub fn shift(src: &[u64], d: i64, out: &mut [u64]) {
    let nw = src.len();
    out.iter_mut().for_each(|w| *w = 0);
    let (ws, bs) = (d.unsigned_abs() as usize / 64, (d.unsigned_abs() % 64) as u32);
    if ws >= nw {
        return;
    }
    if d >= 0 {
        for i in (ws..nw).rev() {
            let lo = src[i - ws];
            let mut v = lo << bs;
            if bs > 0 && i > ws {
                v |= src[i - ws - 1] >> (64 - bs);
            }
            out[i] = v;
        }
    } else {
        for i in 0..nw - ws {
            let mut v = src[i + ws] >> bs;
            if bs > 0 && i + ws + 1 < nw {
                v |= src[i + ws + 1] << (64 - bs);
            }
            out[i] = v;
        }
    }
}

fn bit(m: &[u64], i: usize) -> bool {
    m[i / 64] >> (i % 64) & 1 == 1
}

/// Indices of the set bits, ascending.
pub fn ones_of(m: &[u64]) -> Vec<usize> {
    let mut out = vec![];
    for (i, &w) in m.iter().enumerate() {
        let mut w = w;
        while w != 0 {
            let b = w.trailing_zeros() as usize;
            out.push(i * 64 + b);
            w &= w - 1;
        }
    }
    out
}

fn any(m: &[u64]) -> bool {
    m.iter().any(|&w| w != 0)
}

/// One agent's move as set operations (`plansynth.grid.native.bitgrid.AgentGeometry`):
/// `valid` cells take it as written (others are clamped and stay), `free` cells take it
/// without sweeping a wall (every cell for an obstacle), `to` is the end offset and
/// `offsets` the swept offsets, each as a cell-index delta.
#[derive(Clone, Debug)]
pub struct MoveGeo {
    pub valid: Bits,
    pub free: Bits,
    pub to: i64,
    pub offsets: Vec<i64>,
}

/// The game's fixed data, all over cell indices.
#[derive(Clone, Debug)]
pub struct ArenaSpec {
    pub n_cells: usize,
    pub steps: usize,
    pub robot: Vec<MoveGeo>,
    /// per read obstacle, its moves
    pub obstacles: Vec<Vec<MoveGeo>>,
    /// per step t < steps: cells swept by the relevant obstacles that are not read
    pub abstract_danger: Vec<Bits>,
    /// per time t <= steps: robot cells on some path to the goal
    pub live: Vec<Bits>,
    pub start: usize,
    pub goal: usize,
    pub start_config: Vec<u32>,
}

/// Why exploration or induction stopped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Stop {
    Time { step: usize, configs: usize },
    Memory { step: usize, configs: usize, bytes: usize },
    Configs { configs: usize },
}

#[derive(Default, Clone, Debug)]
pub struct Layer {
    pub ids: Vec<u32>,
    pub index: HashMap<u32, u32>,
    /// `nw` words per row
    pub masks: Vec<u64>,
    pub win: Vec<u64>,
    /// CSR, filled by the exploration: the rows of layer t + 1 of row i's successor
    /// configurations are `next[next_off[i]..next_off[i + 1]]` (none: the robot has no
    /// live move from row i, which therefore loses)
    pub next_off: Vec<u32>,
    pub next: Vec<u32>,
}

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
        Arena { spec, nw, full, n_read, configs: vec![], intern: HashMap::default(), succ: vec![], layers: vec![], solved: false, deadline: None, expired: false }
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
        let masks = spec.live.len() + spec.abstract_danger.len() + 2 * spec.robot.len() + spec.obstacles.iter().map(|o| o.len()).sum::<usize>();
        let mut b = masks * self.nw * 8;
        b += self.configs.capacity() * 4 + map_bytes(&self.intern) + self.intern.len() * (self.n_read * 4 + 16);
        b += self.succ.capacity() * std::mem::size_of::<Option<Box<[u32]>>>();
        b += self.succ.iter().flatten().map(|s| s.len() * 4 + 16).sum::<usize>();
        for l in &self.layers {
            b += l.ids.capacity() * 4 + map_bytes(&l.index) + (l.masks.capacity() + l.win.capacity()) * 8;
            b += (l.next_off.capacity() + l.next.capacity()) * 4;
        }
        b
    }

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
        let v: Vec<u64> = (0..self.nw).map(|i| mask[i] & m.free[i] & m.valid[i]).collect();
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

    fn check(&self, clock: &Budget, step: usize, configs: usize, extra: usize) -> Result<(), Stop> {
        if clock.deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(Stop::Time { step, configs });
        }
        if let Some(limit) = clock.memory {
            let bytes = self.bytes() + extra;
            if bytes > limit {
                return Err(Stop::Memory { step, configs, bytes });
            }
        }
        Ok(())
    }

    /// Explore the states reachable from the start that can still reach the goal
    /// (`Arena._explore` of the reference).
    pub fn explore(&mut self, clock: &Budget) -> Result<(), Stop> {
        let nw = self.nw;
        let start_config = self.spec.start_config.clone();
        let c0 = self.config_id(&start_config);
        let mut first = vec![0u64; nw];
        first[self.spec.start / 64] |= 1 << (self.spec.start % 64);
        let first: Bits = first.iter().zip(&self.spec.live[0]).map(|(a, b)| a & b).collect();
        let mut l0 = Layer::default();
        if any(&first) {
            l0.ids.push(c0);
            l0.index.insert(c0, 0);
            l0.masks.extend_from_slice(&first);
        }
        self.layers = vec![l0];
        let mut count = 1usize;
        let (mut img, mut part, mut tmp) = (vec![0u64; nw], vec![0u64; nw], vec![0u64; nw]);
        for t in 0..self.spec.steps {
            let mut nxt = Layer::default();
            let rows = self.layers[t].ids.len();
            let (mut next_off, mut next) = (Vec::with_capacity(rows + 1), Vec::new());
            next_off.push(0u32);
            for row in 0..rows {
                if row > 0 {
                    next_off.push(next.len() as u32);
                }
                let id = self.layers[t].ids[row];
                let r: Bits = self.layers[t].masks[row * nw..(row + 1) * nw].to_vec();
                let safe = self.safe_sources(t, id);
                img.iter_mut().for_each(|w| *w = 0);
                for (k, s) in safe.iter().enumerate() {
                    let src: Bits = r.iter().zip(s).map(|(a, b)| a & b).collect();
                    self.image(&src, k, &mut part, &mut tmp);
                    img.iter_mut().zip(&part).for_each(|(a, b)| *a |= b);
                }
                img.iter_mut().zip(&self.spec.live[t + 1]).for_each(|(a, b)| *a &= b);
                if !any(&img) {
                    continue;
                }
                for &c2 in self.successors(id).iter() {
                    match nxt.index.get(&c2) {
                        Some(&i) => {
                            next.push(i);
                            let i = i as usize;
                            nxt.masks[i * nw..(i + 1) * nw].iter_mut().zip(&img).for_each(|(a, b)| *a |= b);
                        }
                        None => {
                            next.push(nxt.ids.len() as u32);
                            nxt.index.insert(c2, nxt.ids.len() as u32);
                            nxt.ids.push(c2);
                            nxt.masks.extend_from_slice(&img);
                        }
                    }
                }
                if row % 64 == 0 {
                    let held = nxt.ids.capacity() * 4 + map_bytes(&nxt.index) + nxt.masks.capacity() * 8 + next.capacity() * 4;
                    self.check(clock, t, count + nxt.ids.len(), held)?;
                }
            }
            if rows > 0 {
                next_off.push(next.len() as u32);
            }
            self.layers[t].next_off = next_off;
            self.layers[t].next = next;
            count += nxt.ids.len();
            self.layers.push(nxt);
            self.check(clock, t, count, 0)?;
            if clock.max_configs.is_some_and(|m| count > m) {
                return Err(Stop::Configs { configs: count });
            }
        }
        Ok(())
    }

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
                target.iter_mut().zip(&next.win[i * nw..(i + 1) * nw]).for_each(|(x, y)| *x &= y);
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
                    l.win[row * nw..(row + 1) * nw].iter_mut().zip(m).for_each(|(a, b)| *a |= b);
                }
                if row % 64 == 0 {
                    self.check(clock, t, 0, 0).map_err(|e| match e {
                        Stop::Memory { .. } => e,
                        _ => Stop::Time { step: t, configs: 0 },
                    })?;
                }
            }
        }
        self.solved = true;
        let s = self.spec.start;
        Ok(self.layers[0].ids.first().is_some() && bit(&self.layers[0].win[0..nw], s))
    }

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
                _ => Stop::Time { step: t, configs: 0 },
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
        let index: Vec<HashMap<u32, usize>> =
            reach.iter().map(|l| l.iter().enumerate().map(|(i, (id, _))| (*id, i)).collect()).collect();
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
                                index[t + 1].get(c2).is_some_and(|&i| bit(&reach[t + 1][i].1, e))
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
    pub fn consistent(&mut self, fwd: &[Vec<(u32, Bits)>], width: usize) -> Option<Vec<Vec<(u32, Bits)>>> {
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
                let b = bad.entry(*id).or_insert_with(|| vec![vec![0u64; nw]; n_moves]);
                for k in 0..n_moves {
                    for i in 0..nw {
                        b[k][i] |= rmask[i] & !wm[k][i];
                    }
                }
            }
        }
        let (gx, gy) = ((self.spec.goal % width) as i64, (self.spec.goal / width) as i64);
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
        if !bit(&m.free, r) || self.row(t, id).is_none_or(|row| !bit(&self.layers[t].masks[row * self.nw..], r)) {
            return false;
        }
        let valid = bit(&m.valid, r);
        let n_sw = if valid { m.offsets.len() } else { 1 };
        let oc = self.config(id);
        (0..n_sw).all(|i| {
            let x = if valid { (r as i64 + m.offsets[i]) as usize } else { r };
            !bit(&self.spec.abstract_danger[t], x) && !oc.iter().enumerate().any(|(j, &c)| self.obstacle_sweeps(j, c as usize, x))
        })
    }

    /// Whether end cell e wins at t + 1 against every obstacle reply from `id` (needs
    /// [`Arena::solve_game`]).
    pub fn end_wins(&mut self, t: usize, e: usize, id: u32) -> bool {
        let nw = self.nw;
        self.succ_of(id);
        let succ = self.succ[id as usize].as_deref().unwrap_or(&[]);
        let next = &self.layers[t + 1];
        succ.iter().all(|c2| next.index.get(c2).is_some_and(|&i| !next.win.is_empty() && bit(&next.win[i as usize * nw..], e)))
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
    pub fn check_program(&mut self, prog: &[crate::game::Op], root: usize, width: usize, clock: &Budget) -> Result<Option<(usize, usize, u32)>, Stop> {
        let steps = self.spec.steps;
        let nw = self.nw;
        let n_moves = self.spec.robot.len() as i64;
        if self.layers[0].ids.is_empty() {
            return Ok(Some((0, self.spec.start, 0)));
        }
        // per layer, per row: the robot cells queued (pairs met), and per (row, end
        // cell) whether the end cell's replies were judged and won. Zeroed allocations:
        // the pages a check never touches cost nothing.
        let mut seen: Vec<Vec<u64>> = self.layers.iter().map(|l| vec![0u64; l.ids.len() * nw]).collect();
        let mut judged: Vec<Vec<u64>> = self.layers.iter().map(|l| vec![0u64; l.ids.len() * nw]).collect();
        let mut won: Vec<Vec<u64>> = self.layers.iter().map(|l| vec![0u64; l.ids.len() * nw]).collect();
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
            let ok = a < b && !next.win.is_empty() && l.next[a..b].iter().all(|&i| bit(&next.win[i as usize * nw..], e));
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
                return Err(Stop::Time { step: t, configs: 0 });
            }
        }
        Ok(None)
    }

    /// Row of configuration `id` in layer t.
    pub fn row(&self, t: usize, id: u32) -> Option<usize> {
        self.layers.get(t)?.index.get(&id).map(|&i| i as usize)
    }
}

/// The limits of one call: a deadline, a memory limit (bytes), a configuration cap.
#[derive(Clone, Debug, Default)]
pub struct Budget {
    pub deadline: Option<Instant>,
    pub memory: Option<usize>,
    pub max_configs: Option<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ones(cells: &[usize], nw: usize) -> Bits {
        let mut m = vec![0u64; nw];
        for &c in cells {
            m[c / 64] |= 1 << (c % 64);
        }
        m
    }

    #[test]
    fn shift_moves_bits_across_words() {
        let src = ones(&[0, 63, 64, 100], 2);
        let mut out = vec![0u64; 2];
        shift(&src, 1, &mut out);
        assert_eq!(out, ones(&[1, 64, 65, 101], 2));
        shift(&src, -64, &mut out);
        assert_eq!(out, ones(&[0, 36], 2));
        shift(&src, 200, &mut out);
        assert_eq!(out, vec![0, 0]);
    }

    /// A 3x1 corridor, robot 0 -> 2 in 2 steps with stay/right; one obstacle that
    /// stays on cell 1 or leaves it (to nowhere: clamped), so the robot cannot win.
    fn line(blocker: bool) -> Arena {
        let nw = 1;
        let all = ones(&[0, 1, 2], nw);
        let robot = vec![
            MoveGeo { valid: all.clone(), free: all.clone(), to: 0, offsets: vec![0] },
            MoveGeo { valid: ones(&[0, 1], nw), free: all.clone(), to: 1, offsets: vec![1] },
        ];
        let obstacles = if blocker {
            vec![vec![MoveGeo { valid: all.clone(), free: all.clone(), to: 0, offsets: vec![0] }]]
        } else {
            vec![]
        };
        let spec = ArenaSpec {
            n_cells: 3,
            steps: 2,
            robot,
            obstacles,
            abstract_danger: vec![vec![0]; 2],
            live: vec![ones(&[0], nw), ones(&[1], nw), ones(&[2], nw)],
            start: 0,
            goal: 2,
            start_config: if blocker { vec![1] } else { vec![] },
        };
        Arena::new(spec)
    }

    #[test]
    fn free_corridor_is_won_and_a_parked_obstacle_wins_for_the_obstacles() {
        let mut a = line(false);
        a.explore(&Budget::default()).unwrap();
        assert_eq!(a.layers.iter().map(|l| l.ids.len()).collect::<Vec<_>>(), vec![1, 1, 1]);
        assert!(a.solve_game(&Budget::default()).unwrap());
        let fwd = a.winning_forward(&Budget::default()).unwrap();
        assert_eq!(fwd[2], vec![(0, ones(&[2], 1))]);
        let mut b = line(true);
        b.explore(&Budget::default()).unwrap();
        // the robot's only path runs through cell 1, where the obstacle sits
        assert_eq!(b.layers[1].ids.len(), 0);
        assert!(!b.solve_game(&Budget::default()).unwrap());
    }

    #[test]
    fn the_program_check_follows_the_program_on_the_solved_game() {
        use crate::game::Op;
        let mut a = line(false);
        a.explore(&Budget::default()).unwrap();
        assert!(a.solve_game(&Budget::default()).unwrap());
        let b = Budget::default();
        assert_eq!(a.check_program(&[Op::Const(1)], 0, 3, &b), Ok(None)); // right, right
        assert_eq!(a.check_program(&[Op::Const(0)], 0, 3, &b), Ok(Some((0, 0, 0)))); // staying never arrives
        assert_eq!(a.check_program(&[Op::Const(7)], 0, 3, &b), Ok(Some((0, 0, 0)))); // no such move
        // (ite (<= rx 0) 1 0): right first, then stays at cell 1 and misses the goal
        let p = [Op::Var(0), Op::Const(0), Op::Le(0, 1), Op::Const(1), Op::Const(0), Op::Ite(2, 3, 4)];
        assert_eq!(a.check_program(&p, 5, 3, &b), Ok(Some((1, 1, 0))));
    }

    #[test]
    fn the_memory_limit_is_checked_against_what_is_held() {
        let mut a = line(false);
        let got = a.explore(&Budget { memory: Some(1), ..Default::default() });
        assert!(matches!(got, Err(Stop::Memory { .. })));
        let mut b = line(false);
        let past = Budget { deadline: Some(Instant::now()), ..Default::default() };
        assert!(matches!(b.explore(&past), Err(Stop::Time { .. })));
    }
}
