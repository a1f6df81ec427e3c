//! The program check on the game graph: does a controller program win the bounded game?
//!
//! The graph is the time-expanded winning-forward graph of the native engine
//! (`plansynth.grid.native.check.GameGraph`, its pure-Python reference): nodes are pairs
//! (time, joint state) reachable from the start with moves that win the time-dependent
//! game (backward induction); each pair has the mask of its winning moves and, per
//! winning move, its successor pairs (one per obstacle reply). Every pair of the graph
//! is winning, so a program wins iff in every pair it reaches it plays a winning move
//! (Chasins & Newcomb, SYNT 2016, Section 3.1: the robot reaches the goal at exactly l
//! steps without collision whatever the obstacles do).

/// A program of the grammar as a flat tree: node i is `Op`, children by index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Const(i64),
    Var(usize),
    Plus(usize, usize),
    Minus(usize, usize),
    Le(usize, usize),
    Eq(usize, usize),
    Not(usize),
    And(usize, usize),
    Or(usize, usize),
    Ite(usize, usize, usize),
}

/// Evaluate node `i` of `prog` on the input vector `x` (Booleans are 0/1).
pub fn eval(prog: &[Op], i: usize, x: &[i64]) -> i64 {
    match prog[i] {
        Op::Const(c) => c,
        Op::Var(j) => x[j],
        Op::Plus(a, b) => eval(prog, a, x).wrapping_add(eval(prog, b, x)),
        Op::Minus(a, b) => eval(prog, a, x).wrapping_sub(eval(prog, b, x)),
        Op::Le(a, b) => (eval(prog, a, x) <= eval(prog, b, x)) as i64,
        Op::Eq(a, b) => (eval(prog, a, x) == eval(prog, b, x)) as i64,
        Op::Not(a) => (eval(prog, a, x) == 0) as i64,
        Op::And(a, b) => (eval(prog, a, x) != 0 && eval(prog, b, x) != 0) as i64,
        Op::Or(a, b) => (eval(prog, a, x) != 0 || eval(prog, b, x) != 0) as i64,
        Op::Ite(c, t, e) => {
            if eval(prog, c, x) != 0 {
                eval(prog, t, x)
            } else {
                eval(prog, e, x)
            }
        }
    }
}

/// The time-expanded winning-forward graph. Pair 0 is the start.
#[derive(Clone, Debug, Default)]
pub struct GameGraph {
    pub n_moves: usize,
    /// per pair: index of its joint state in `inputs`
    pub state_of: Vec<u32>,
    /// per pair: bitmask of winning moves
    pub win: Vec<u32>,
    /// CSR: successors of (pair p, move k) are `succ[off[p * n_moves + k] .. off[p * n_moves + k + 1]]`
    pub off: Vec<u32>,
    pub succ: Vec<u32>,
    /// per joint state: the controller's inputs (rx, ry, o0x, o0y, ...)
    pub inputs: Vec<Vec<i64>>,
}

impl GameGraph {
    /// The move `prog` plays in each joint state (root at node `root`).
    pub fn moves(&self, prog: &[Op], root: usize) -> Vec<i64> {
        self.inputs.iter().map(|x| eval(prog, root, x)).collect()
    }

    /// `None` when the program wins; otherwise the first pair (in breadth-first order)
    /// where it plays a move that is not winning.
    pub fn check(&self, prog: &[Op], root: usize) -> Option<u32> {
        let mut cache: Vec<i64> = vec![i64::MIN; self.inputs.len()];
        let mut seen = vec![false; self.state_of.len()];
        let mut queue: Vec<u32> = Vec::new();
        if self.state_of.is_empty() {
            return Some(0);
        }
        seen[0] = true;
        queue.push(0);
        let mut head = 0;
        while head < queue.len() {
            let p = queue[head] as usize;
            head += 1;
            let s = self.state_of[p] as usize;
            if cache[s] == i64::MIN {
                cache[s] = eval(prog, root, &self.inputs[s]);
            }
            let k = cache[s];
            if k < 0 || k as usize >= self.n_moves || self.win[p] >> k & 1 == 0 {
                return Some(p as u32);
            }
            let i = p * self.n_moves + k as usize;
            for &q in &self.succ[self.off[i] as usize..self.off[i + 1] as usize] {
                if !seen[q as usize] {
                    seen[q as usize] = true;
                    queue.push(q);
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line() -> GameGraph {
        // one state per time on a line 0 -> 1 -> 2; move 1 ("right") wins, move 0 does not
        GameGraph {
            n_moves: 2,
            state_of: vec![0, 1],
            win: vec![0b10, 0b10],
            off: vec![0, 0, 1, 1, 1],
            succ: vec![1],
            inputs: vec![vec![0], vec![1]],
        }
    }

    #[test]
    fn a_constant_move_wins_or_fails_where_expected() {
        let g = line();
        assert_eq!(g.check(&[Op::Const(1)], 0), None);
        assert_eq!(g.check(&[Op::Const(0)], 0), Some(0));
        // (ite (<= rx 0) 1 0) fails at the second pair
        let p = [
            Op::Var(0),
            Op::Const(0),
            Op::Le(0, 1),
            Op::Const(1),
            Op::Const(0),
            Op::Ite(2, 3, 4),
        ];
        assert_eq!(g.check(&p, 5), Some(1));
        assert_eq!(g.moves(&p, 5), vec![1, 0]);
    }
}

/// What [`build_game_graph`] needs of the explored game, per (time, configuration) of
/// the winning-forward layers.
pub struct LayerCell {
    pub t: u32,
    pub config: u32,
    /// per move k: robot cells of `robot` from which k wins at (t, config)
    pub winning: Vec<Vec<u64>>,
}

fn bit(m: &[u64], i: usize) -> bool {
    m.get(i / 64).is_some_and(|w| w >> (i % 64) & 1 == 1)
}

/// The time-expanded winning-forward graph, explored breadth-first from
/// `(0, start, config 0)` exactly as the Python reference
/// `plansynth.grid.native.check.GameGraph.from_arena` does (same numbering of pairs and
/// joint states). `configs[c]` are the cells of the read obstacles of configuration c,
/// `successors[c]` its successor configurations, `robot_end[r * n_moves + k]` the robot's
/// end cell, `width` the grid width (cell index = y * width + x).
pub fn build_game_graph(
    n_moves: usize,
    steps: u32,
    width: u32,
    start: u32,
    configs: &[Vec<u32>],
    successors: &[Vec<u32>],
    robot_end: &[u32],
    layers: &[LayerCell],
) -> GameGraph {
    use std::collections::HashMap;
    let at: HashMap<(u32, u32), usize> = layers
        .iter()
        .enumerate()
        .map(|(i, l)| ((l.t, l.config), i))
        .collect();
    let mut pair_id: HashMap<(u32, u32, u32), u32> = HashMap::new();
    let mut order: Vec<(u32, u32, u32)> = vec![(0, start, 0)];
    pair_id.insert((0, start, 0), 0);
    let mut state_id: HashMap<(u32, u32), u32> = HashMap::new();
    let mut g = GameGraph {
        n_moves,
        off: vec![0],
        ..Default::default()
    };
    let mut ends: HashMap<(u32, u32, u32), Vec<u32>> = HashMap::new();
    let mut head = 0;
    while head < order.len() {
        let (t, r, c) = order[head];
        head += 1;
        let s = *state_id.entry((r, c)).or_insert_with(|| {
            let mut x = vec![(r % width) as i64, (r / width) as i64];
            for &o in &configs[c as usize] {
                x.push((o % width) as i64);
                x.push((o / width) as i64);
            }
            g.inputs.push(x);
            (g.inputs.len() - 1) as u32
        });
        g.state_of.push(s);
        let cell = at.get(&(t, c)).map(|&i| &layers[i]);
        let mut w = 0u32;
        for k in 0..n_moves {
            if cell.is_some_and(|l| bit(&l.winning[k], r as usize)) {
                w |= 1 << k;
                if t + 1 < steps {
                    let e = robot_end[r as usize * n_moves + k];
                    let ids = ends.entry((t, e, c)).or_insert_with(|| {
                        successors[c as usize]
                            .iter()
                            .map(|&c2| {
                                let key = (t + 1, e, c2);
                                *pair_id.entry(key).or_insert_with(|| {
                                    order.push(key);
                                    (order.len() - 1) as u32
                                })
                            })
                            .collect()
                    });
                    g.succ.extend_from_slice(ids);
                }
            }
            g.off.push(g.succ.len() as u32);
        }
        g.win.push(w);
    }
    g
}

#[cfg(test)]
mod build_tests {
    use super::*;

    #[test]
    fn a_line_of_three_cells() {
        // robot 0 -> 2 on a 3x1 grid in 2 steps, moves stay (0) and right (1); no obstacles
        let layers = vec![
            LayerCell {
                t: 0,
                config: 0,
                winning: vec![vec![0], vec![0b001]],
            },
            LayerCell {
                t: 1,
                config: 0,
                winning: vec![vec![0], vec![0b010]],
            },
        ];
        let g = build_game_graph(
            2,
            2,
            3,
            0,
            &[vec![]],
            &[vec![0]],
            &[0, 1, 1, 2, 2, 2],
            &layers,
        );
        assert_eq!(g.state_of, vec![0, 1]);
        assert_eq!(g.win, vec![0b10, 0b10]);
        assert_eq!(g.inputs, vec![vec![0, 0], vec![1, 0]]);
        assert_eq!(g.check(&[Op::Const(1)], 0), None);
    }
}
