//! Decision trees over condition behaviours: the greedy top-down tree of
//! `plansynth.grid.native.synth.greedy_program` (its exact mirror: same scores, same
//! tie-breaks), used to answer first with a correct program (Chasins & Newcomb,
//! SYNT 2016, Listing 1: a program is an `ite` tree over conditions with moves at the
//! leaves).
//!
//! A behaviour is a bitset over the states (bit i: the condition holds in state i),
//! stored as 64-bit words; `allowed[s]` is the bitmask of moves state s may play.

/// One node of a greedy tree, in pre-order: a leaf plays `Leaf(k)`; `Split(j)` tests
/// condition j, then the true subtree follows, then the false one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Node {
    Leaf(usize),
    Split(usize),
}

/// Why no tree was built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GreedyError {
    /// More than `max_nodes` splits were needed.
    TooLarge,
    /// No condition separates states that share no move (cannot happen with a complete
    /// enumeration of `=` tests; a bug of the caller otherwise).
    NoSplit,
}

/// A set of states as its non-zero words only: (word index, bits), by index. A node
/// deep in the tree holds few states, so every count at it costs what it holds, not
/// the length of the whole sample.
type Sparse = Vec<(usize, u64)>;

/// |members & mask| (mask: a whole-sample bitset).
fn count_in(members: &[(usize, u64)], mask: &[u64]) -> u32 {
    members
        .iter()
        .map(|&(w, b)| (b & mask[w]).count_ones())
        .sum()
}

/// The greedy tree over `n_states` states: a node whose states share a move becomes a
/// leaf (the smallest such move of largest count); otherwise its states are labelled by
/// greedy set cover over their allowed moves and the condition of best Gini purity
/// over those labels splits them (ties: shallower condition, then smaller term, then
/// the earliest). Gini splits keep the tree balanced, hence shallow.
pub fn greedy_tree(
    conds: &[Vec<u64>],
    keys: &[(u32, u32)],
    allowed: &[u32],
    n_moves: usize,
    max_nodes: usize,
) -> Result<Vec<Node>, GreedyError> {
    let n = allowed.len();
    let nw = n.div_ceil(64).max(1);
    let mut by_move = vec![vec![0u64; nw]; n_moves];
    for (s, &a) in allowed.iter().enumerate() {
        for (k, m) in by_move.iter_mut().enumerate() {
            if a >> k & 1 == 1 {
                m[s / 64] |= 1 << (s % 64);
            }
        }
    }
    let mut full = vec![0u64; nw];
    for s in 0..n {
        full[s / 64] |= 1 << (s % 64);
    }
    let full: Sparse = full
        .into_iter()
        .enumerate()
        .filter(|&(_, b)| b != 0)
        .collect();
    let mut out = Vec::new();
    let mut budget = max_nodes as i64;
    let live: Vec<usize> = (0..conds.len()).collect();
    grow(&full, &live, conds, keys, &by_move, &mut out, &mut budget)?;
    Ok(out)
}

fn best_common(members: &[(usize, u64)], by_move: &[Vec<u64>]) -> (u32, usize) {
    // max over (count, -k): the smallest k among the largest counts
    let mut best = (0u32, 0usize);
    for (k, m) in by_move.iter().enumerate() {
        let c = count_in(members, m);
        if k == 0 || c > best.0 {
            best = (c, k);
        }
    }
    best
}

/// A split's score: Gini purity as a fraction (num, den), maximised; ties broken by
/// (-depth, -size) of the condition, then by the earliest condition.
type Score = ((u128, u128), (i64, i64), usize);

fn better(a: &Score, b: &Option<Score>) -> bool {
    match b {
        None => true,
        Some(((bn, bd), bt, _)) => {
            let ((num, den), tie, _) = a;
            let (x, y) = (num * bd, bn * den);
            x > y || (x == y && *tie > *bt)
        }
    }
}

/// Work (member words times conditions) below which a node's conditions are scored on
/// one thread: threads cost more than they save on the small nodes deep in the tree.
const PAR_WORK: usize = 1 << 18;

fn grow(
    members: &[(usize, u64)],
    live: &[usize],
    conds: &[Vec<u64>],
    keys: &[(u32, u32)],
    by_move: &[Vec<u64>],
    out: &mut Vec<Node>,
    budget: &mut i64,
) -> Result<(), GreedyError> {
    let total: u32 = members.iter().map(|&(_, b)| b.count_ones()).sum();
    let (c, k) = best_common(members, by_move);
    if c == total {
        out.push(Node::Leaf(k));
        return Ok(());
    }
    *budget -= 1;
    if *budget < 0 {
        return Err(GreedyError::TooLarge);
    }
    // Label each member with a move by greedy set cover at this node (the move serving
    // most members first, then the next among the rest, ...; ties: the smaller move),
    // then pick the split of best Gini purity over these labels (an exact rational
    // comparison; ties: shallower condition, then smaller term, then the earliest).
    // Labels are interleaved with `members` (word i of label kk at i * n_labels + kk).
    let mut rest: Sparse = members.to_vec();
    let mut label_sets: Vec<Vec<u64>> = Vec::new();
    loop {
        rest.retain(|&(_, b)| b != 0);
        if rest.is_empty() {
            break;
        }
        let (c, kbest) = best_common(&rest, by_move);
        if c == 0 {
            break; // members without any allowed move (not from a strategy): no label
        }
        let m = &by_move[kbest];
        let mut lab = vec![0u64; members.len()];
        let mut j = 0;
        for (i, &(w, _)) in members.iter().enumerate() {
            if j < rest.len() && rest[j].0 == w {
                lab[i] = rest[j].1 & m[w];
                rest[j].1 &= !lab[i];
                j += 1;
            }
        }
        label_sets.push(lab);
    }
    let n_labels = label_sets.len();
    let lab_count: Vec<u64> = label_sets
        .iter()
        .map(|m| m.iter().map(|b| b.count_ones() as u64).sum())
        .collect();
    let mut labels = vec![0u64; members.len() * n_labels];
    for (kk, m) in label_sets.iter().enumerate() {
        for (i, &b) in m.iter().enumerate() {
            labels[i * n_labels + kk] = b;
        }
    }
    drop(label_sets);
    // Score the live conditions (those that split this node; a condition constant on a
    // node is constant on its descendants, so they score the conditions that split it
    // only), in ranges on the threads of `crate::par` when the node is large: each
    // range's best in order, then the first best of those, which is the first best of
    // all.
    let score = |range: std::ops::Range<usize>| -> (Option<Score>, Vec<usize>) {
        let mut best: Option<Score> = None;
        let mut split: Vec<usize> = Vec::new();
        let mut l = vec![0u64; n_labels];
        for &j in &live[range] {
            let cond = &conds[j];
            l.iter_mut().for_each(|x| *x = 0);
            let mut left = 0u64;
            for (i, &(w, b)) in members.iter().enumerate() {
                let c = b & cond[w];
                if c == 0 {
                    continue;
                }
                left += c.count_ones() as u64;
                let row = &labels[i * n_labels..(i + 1) * n_labels];
                for (x, &m) in l.iter_mut().zip(row) {
                    *x += (c & m).count_ones() as u64;
                }
            }
            if left == 0 || left == total as u64 {
                continue;
            }
            split.push(j);
            let right = total as u64 - left;
            let (mut sl, mut sr) = (0u128, 0u128);
            for kk in 0..n_labels {
                let (a, r) = (l[kk] as u128, (lab_count[kk] - l[kk]) as u128);
                sl += a * a;
                sr += r * r;
            }
            // sum_k l_k^2 / left + sum_k r_k^2 / right = (sl * right + sr * left) / (left * right)
            let num = sl * right as u128 + sr * left as u128;
            let den = left as u128 * right as u128;
            let s: Score = ((num, den), (-(keys[j].0 as i64), -(keys[j].1 as i64)), j);
            if better(&s, &best) {
                best = Some(s);
            }
        }
        (best, split)
    };
    let parts = if members.len().saturating_mul(live.len()) < PAR_WORK {
        vec![score(0..live.len())]
    } else {
        crate::par::map_ranges(live.len(), 16, score)
    };
    let mut best: Option<Score> = None;
    let mut split: Vec<usize> = Vec::new();
    for (b, s) in parts {
        if let Some(b) = b {
            if better(&b, &best) {
                best = Some(b);
            }
        }
        split.extend(s);
    }
    drop(labels);
    let Some((_, _, j)) = best else {
        return Err(GreedyError::NoSplit);
    };
    let cond = &conds[j];
    let left: Sparse = members
        .iter()
        .map(|&(w, b)| (w, b & cond[w]))
        .filter(|&(_, b)| b != 0)
        .collect();
    let right: Sparse = members
        .iter()
        .map(|&(w, b)| (w, b & !cond[w]))
        .filter(|&(_, b)| b != 0)
        .collect();
    out.push(Node::Split(j));
    grow(&left, &split, conds, keys, by_move, out, budget)?;
    grow(&right, &split, conds, keys, by_move, out, budget)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_split_separates_two_moves() {
        // states 0, 1 play move 0; states 2, 3 play move 1; condition 1 is {0, 1}
        let conds = vec![vec![0b0101u64], vec![0b0011u64]];
        let keys = vec![(3, 3), (3, 3)];
        let t = greedy_tree(&conds, &keys, &[1, 1, 2, 2], 2, 100).unwrap();
        assert_eq!(t, vec![Node::Split(1), Node::Leaf(0), Node::Leaf(1)]);
    }

    #[test]
    fn a_shared_move_is_a_leaf() {
        let t = greedy_tree(&[], &[], &[3, 2, 6], 3, 10).unwrap();
        assert_eq!(t, vec![Node::Leaf(1)]);
    }

    #[test]
    fn no_split_is_an_error() {
        assert_eq!(
            greedy_tree(&[vec![0b11]], &[(3, 3)], &[1, 2], 2, 10),
            Err(GreedyError::NoSplit)
        );
    }
}
