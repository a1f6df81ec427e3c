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

fn popcount_and(a: &[u64], b: &[u64], words: &[usize]) -> u32 {
    words.iter().map(|&w| (a[w] & b[w]).count_ones()).sum()
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
    let mut out = Vec::new();
    let mut budget = max_nodes as i64;
    grow(&full, conds, keys, &by_move, &mut out, &mut budget)?;
    Ok(out)
}

fn best_common(members: &[u64], by_move: &[Vec<u64>], words: &[usize]) -> (u32, usize) {
    // max over (count, -k): the smallest k among the largest counts
    let mut best = (0u32, 0usize);
    for (k, m) in by_move.iter().enumerate() {
        let c = popcount_and(members, m, words);
        if k == 0 || c > best.0 {
            best = (c, k);
        }
    }
    best
}

fn grow(
    members: &[u64],
    conds: &[Vec<u64>],
    keys: &[(u32, u32)],
    by_move: &[Vec<u64>],
    out: &mut Vec<Node>,
    budget: &mut i64,
) -> Result<(), GreedyError> {
    let words: Vec<usize> = (0..members.len()).filter(|&w| members[w] != 0).collect();
    let total: u32 = words.iter().map(|&w| members[w].count_ones()).sum();
    let (c, k) = best_common(members, by_move, &words);
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
    let mut rest: Vec<u64> = members.to_vec();
    let mut labels: Vec<Vec<u64>> = Vec::new();
    loop {
        let rw: Vec<usize> = (0..rest.len()).filter(|&w| rest[w] != 0).collect();
        if rw.is_empty() {
            break;
        }
        let (c, kbest) = best_common(&rest, by_move, &rw);
        if c == 0 {
            break; // members without any allowed move (not from a strategy): no label
        }
        let lab: Vec<u64> = rest
            .iter()
            .zip(&by_move[kbest])
            .map(|(a, b)| a & b)
            .collect();
        for (r, l) in rest.iter_mut().zip(&lab) {
            *r &= !l;
        }
        labels.push(lab);
    }
    let lab_count: Vec<u64> = labels
        .iter()
        .map(|m| words.iter().map(|&w| m[w].count_ones() as u64).sum())
        .collect();
    // key = purity num/den (maximised), then (-depth, -size); first maximum wins
    let mut best: Option<((u128, u128), (i64, i64), usize)> = None;
    for (j, cond) in conds.iter().enumerate() {
        let left = popcount_and(cond, members, &words) as u64;
        if left == 0 || left == total as u64 {
            continue;
        }
        let right = total as u64 - left;
        let (mut sl, mut sr) = (0u128, 0u128);
        for (kk, m) in labels.iter().enumerate() {
            let l = popcount_and(cond, m, &words) as u128;
            let r = lab_count[kk] as u128 - l;
            sl += l * l;
            sr += r * r;
        }
        // sum_k l_k^2 / left + sum_k r_k^2 / right = (sl * right + sr * left) / (left * right)
        let num = sl * right as u128 + sr * left as u128;
        let den = left as u128 * right as u128;
        let tie = (-(keys[j].0 as i64), -(keys[j].1 as i64));
        let better = match &best {
            None => true,
            Some(((bn, bd), bt, _)) => {
                let (a, b) = (num * bd, bn * den);
                a > b || (a == b && tie > *bt)
            }
        };
        if better {
            best = Some(((num, den), tie, j));
        }
    }
    let Some((_, _, j)) = best else {
        return Err(GreedyError::NoSplit);
    };
    let cond = &conds[j];
    let left: Vec<u64> = members.iter().zip(cond).map(|(a, b)| a & b).collect();
    let right: Vec<u64> = members.iter().zip(cond).map(|(a, b)| a & !b).collect();
    out.push(Node::Split(j));
    grow(&left, conds, keys, by_move, out, budget)?;
    grow(&right, conds, keys, by_move, out, budget)
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
