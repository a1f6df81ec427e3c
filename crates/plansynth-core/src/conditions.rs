//! Bottom-up enumeration of the controller grammar's conditions up to observational
//! equivalence (the Enumerative SyGuS idea; Chasins & Newcomb, SYNT 2016, Section 4).
//!
//! The exact mirror of the pure-Python reference
//! `plansynth.grid.native.conditions._enumerate`: the same loops in the same order, so
//! both return the same behaviours with the same terms. A behaviour is a bitset over
//! the given states (bit i: true in state i), stored as 64-bit words.

use std::collections::HashMap;

/// An integer term: constant, variable (index into the state vector), `+` or `-` of
/// two earlier terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arith {
    Const(i64),
    Var(usize),
    Plus(usize, usize),
    Minus(usize, usize),
}

/// A condition: comparison of two arithmetic terms, or a Boolean combination of two
/// earlier conditions (indices into the condition list).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cond {
    Le(usize, usize),
    Eq(usize, usize),
    Not(usize),
    And(usize, usize),
    Or(usize, usize),
}

/// The enumeration: arithmetic terms (with depths), conditions (with behaviours and
/// depths), and the largest depth enumerated completely.
#[derive(Debug, Default)]
pub struct Enumeration {
    pub terms: Vec<(Arith, u32)>,
    pub conds: Vec<(Vec<u64>, Cond, u32)>,
    pub complete_to: u32,
}

/// Arithmetic terms up to `max_depth`, one per value vector over `states`.
pub fn arithmetic_terms(
    states: &[Vec<i64>],
    n_vars: usize,
    max_constant: i64,
    max_depth: u32,
) -> (Vec<(Arith, u32)>, Vec<Vec<i64>>) {
    let n = states.len();
    let mut seen: HashMap<Vec<i64>, usize> = HashMap::new();
    let mut terms: Vec<(Arith, u32)> = Vec::new();
    let mut values: Vec<Vec<i64>> = Vec::new();
    let push = |vec: Vec<i64>,
                t: Arith,
                d: u32,
                terms: &mut Vec<(Arith, u32)>,
                values: &mut Vec<Vec<i64>>,
                seen: &mut HashMap<Vec<i64>, usize>| {
        if !seen.contains_key(&vec) {
            seen.insert(vec.clone(), terms.len());
            terms.push((t, d));
            values.push(vec);
        }
    };
    for c in -1..=max_constant {
        push(
            vec![c; n],
            Arith::Const(c),
            1,
            &mut terms,
            &mut values,
            &mut seen,
        );
    }
    if max_depth >= 2 {
        for j in 0..n_vars {
            let vec: Vec<i64> = states.iter().map(|s| s[j]).collect();
            push(vec, Arith::Var(j), 2, &mut terms, &mut values, &mut seen);
        }
    }
    for d in 3..=max_depth {
        let prev = terms.len();
        for ia in 0..prev {
            for ib in 0..prev {
                let (da, db) = (terms[ia].1, terms[ib].1);
                if da.max(db) != d - 1 {
                    continue;
                }
                if ia <= ib {
                    let vec: Vec<i64> = values[ia]
                        .iter()
                        .zip(&values[ib])
                        .map(|(x, y)| x + y)
                        .collect();
                    push(
                        vec,
                        Arith::Plus(ia, ib),
                        d,
                        &mut terms,
                        &mut values,
                        &mut seen,
                    );
                }
                let vec: Vec<i64> = values[ia]
                    .iter()
                    .zip(&values[ib])
                    .map(|(x, y)| x - y)
                    .collect();
                push(
                    vec,
                    Arith::Minus(ia, ib),
                    d,
                    &mut terms,
                    &mut values,
                    &mut seen,
                );
            }
        }
    }
    (terms, values)
}

struct Found {
    index: HashMap<Vec<u64>, usize>,
    conds: Vec<(Vec<u64>, Cond, u32)>,
    limit: Option<usize>,
}

impl Found {
    /// Add a behaviour if new; false once the limit is reached (as the reference).
    fn add(&mut self, mask: Vec<u64>, c: Cond, d: u32) -> bool {
        if self.index.contains_key(&mask) {
            return true;
        }
        self.index.insert(mask.clone(), self.conds.len());
        self.conds.push((mask, c, d));
        match self.limit {
            None => true,
            Some(l) => self.conds.len() < l,
        }
    }
}

/// Every condition behaviour of depth <= `max_depth` on `states` (see module docs).
pub fn enumerate_conditions(
    states: &[Vec<i64>],
    n_vars: usize,
    max_constant: i64,
    max_depth: u32,
    limit: Option<usize>,
) -> Enumeration {
    let n = states.len();
    let words = n.div_ceil(64).max(1);
    let mut full = vec![0u64; words];
    for i in 0..n {
        full[i / 64] |= 1 << (i % 64);
    }
    let (terms, values) =
        arithmetic_terms(states, n_vars, max_constant, (max_depth.max(2) - 1).max(1));
    let mut found = Found {
        index: HashMap::new(),
        conds: Vec::new(),
        limit,
    };
    let mut complete_to = 1;
    'levels: for d in 2..=max_depth {
        let before = found.conds.len();
        for ia in 0..terms.len() {
            let da = terms[ia].1;
            if da > d - 1 {
                continue;
            }
            for ib in 0..terms.len() {
                let db = terms[ib].1;
                if db > d - 1 || da.max(db) != d - 1 {
                    continue;
                }
                let mut le = vec![0u64; words];
                let mut eq = vec![0u64; words];
                let (va, vb) = (&values[ia], &values[ib]);
                for i in 0..n {
                    if va[i] <= vb[i] {
                        le[i / 64] |= 1 << (i % 64);
                        if va[i] == vb[i] {
                            eq[i / 64] |= 1 << (i % 64);
                        }
                    }
                }
                if !found.add(le, Cond::Le(ia, ib), d) {
                    break 'levels;
                }
                if ia < ib && !found.add(eq, Cond::Eq(ia, ib), d) {
                    break 'levels;
                }
            }
        }
        for ia in 0..before {
            if found.conds[ia].2 != d - 1 {
                continue;
            }
            let ma = found.conds[ia].0.clone();
            let not: Vec<u64> = ma.iter().zip(&full).map(|(m, f)| f & !m).collect();
            if !found.add(not, Cond::Not(ia), d) {
                break 'levels;
            }
            for ib in 0..before {
                if found.conds[ib].2 == d - 1 && ib < ia {
                    continue;
                }
                let mb = &found.conds[ib].0;
                let and: Vec<u64> = ma.iter().zip(mb).map(|(x, y)| x & y).collect();
                let or: Vec<u64> = ma.iter().zip(mb).map(|(x, y)| x | y).collect();
                if !found.add(and, Cond::And(ia, ib), d) {
                    break 'levels;
                }
                if !found.add(or, Cond::Or(ia, ib), d) {
                    break 'levels;
                }
            }
        }
        complete_to = d;
    }
    Enumeration {
        terms,
        conds: found.conds,
        complete_to,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_states_on_a_row() {
        let states = vec![vec![0, 0], vec![1, 0], vec![2, 0]];
        let e = enumerate_conditions(&states, 2, 2, 3, None);
        // rx <= 0 holds in the first state only
        assert!(e.conds.iter().any(|(m, _, d)| m[0] == 0b001 && *d == 3));
        let mut masks: Vec<_> = e.conds.iter().map(|c| c.0.clone()).collect();
        masks.sort();
        masks.dedup();
        assert_eq!(masks.len(), e.conds.len());
        assert_eq!(e.complete_to, 3);
    }

    #[test]
    fn limit_stops_early() {
        let states = vec![vec![0, 0], vec![1, 0], vec![2, 3]];
        let e = enumerate_conditions(&states, 2, 3, 4, Some(5));
        assert_eq!(e.conds.len(), 5);
        assert!(e.complete_to < 4);
    }
}
