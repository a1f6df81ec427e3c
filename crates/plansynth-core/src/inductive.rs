//! The verifier's inductive-invariant check for safety (the compiled twin of
//! `plansynth.grid.verify.invariant`'s numpy check, its reference; a property test
//! compares the two). Manna and Pnueli, *Temporal Verification of Reactive Systems:
//! Safety*, 1995, rule INV: a set of states that holds the start, in each of whose
//! states the program's move collides with no obstacle reply and from which every
//! reply leads back into the set, proves that the program never collides.
//!
//! It takes plain tables the verifier builds in Python from the rules
//! (`plansynth.grid.semantics`): the set (per configuration a robot-cell bit set), the
//! program's inputs that do not depend on the robot's cell, the robot's end cell, swept
//! cells and wall hits per move and cell, and per configuration the obstacles' replies
//! (next configuration, cells that collide). It shares nothing with the native engine
//! but the program evaluator ([`crate::game::eval`], walked as a tree by
//! [`crate::program_tree`]): no game is solved here, and nothing the engine computed is
//! read.

use crate::game::Op;
use crate::par::map_ranges;
use crate::program_tree::ProgramTree;
use std::time::Instant;

/// The invariant's tables (see the module docs). `nw` words per configuration in
/// `table`; `n_fixed` inputs per configuration in `fixed` (the inputs after the robot's
/// (x, y)); per move and cell `ends`, `wall_hit` and `swept` (`n_swept` cells a move,
/// padded by repeating); replies in CSR form: configuration i's replies are
/// `reply_off[i]..reply_off[i + 1]`, each with its next configuration (`None`: not in
/// the set) and its colliding cells `danger[danger_off[j]..danger_off[j + 1]]`.
pub struct InvariantTables<'a> {
    pub width: usize,
    pub n_cells: usize,
    pub nw: usize,
    pub table: &'a [u64],
    pub n_fixed: usize,
    pub fixed: &'a [i64],
    pub n_moves: usize,
    pub ends: &'a [u32],
    pub wall_hit: &'a [bool],
    pub n_swept: usize,
    pub swept: &'a [u32],
    pub reply_off: &'a [u32],
    pub reply_next: &'a [Option<u32>],
    pub danger_off: &'a [u32],
    pub danger: &'a [u32],
    /// the collision rule: the robot's end cell in a block after the step (`true`), or
    /// a cell the robot sweeps swept by an obstacle too
    pub position: bool,
}

/// The first state (in configuration order, then cell order) where the set is not an
/// inductive invariant of the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// the program's value is not a move
    NoMove { key: u32, cell: u32, value: i64 },
    /// the move may collide (a wall, or an obstacle reply)
    Collides { key: u32, cell: u32, mv: u32 },
    /// a reply leads out of the set
    Leaves {
        key: u32,
        cell: u32,
        mv: u32,
        end: u32,
    },
}

/// Why the check stopped before its answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutOfTime;

/// Check every state of the set: `Ok(Ok(states checked))` when the set is inductive,
/// `Ok(Err(failure))` at its first failure. Configurations are split among the
/// threads of [`crate::par`]; the failure reported is the first in order whatever
/// their number.
pub fn check_invariant(
    t: &InvariantTables<'_>,
    prog: &[Op],
    deadline: Option<Instant>,
) -> Result<Result<usize, Failure>, OutOfTime> {
    let n_keys = t.reply_off.len() - 1;
    let parts = map_ranges(n_keys, 64, |keys| check_range(t, prog, keys, deadline));
    let mut total = 0usize;
    for p in parts {
        match p? {
            Ok(n) => total += n,
            Err(f) => return Ok(Err(f)),
        }
    }
    Ok(Ok(total))
}

fn check_range(
    t: &InvariantTables<'_>,
    prog: &[Op],
    keys: std::ops::Range<usize>,
    deadline: Option<Instant>,
) -> Result<Result<usize, Failure>, OutOfTime> {
    let tree = ProgramTree::new(prog);
    let mut x = vec![0i64; 2 + t.n_fixed];
    let mut checked = 0usize;
    for key in keys {
        if key % 256 == 0 && deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(OutOfTime);
        }
        x[2..].copy_from_slice(&t.fixed[key * t.n_fixed..(key + 1) * t.n_fixed]);
        let words = &t.table[key * t.nw..(key + 1) * t.nw];
        let replies = t.reply_off[key] as usize..t.reply_off[key + 1] as usize;
        for (wi, &w) in words.iter().enumerate() {
            let mut bits = w;
            while bits != 0 {
                let cell = wi * 64 + bits.trailing_zeros() as usize;
                bits &= bits - 1;
                checked += 1;
                x[0] = (cell % t.width) as i64;
                x[1] = (cell / t.width) as i64;
                let k = tree.run(&x);
                let (key32, cell32) = (key as u32, cell as u32);
                if !(0..t.n_moves as i64).contains(&k) {
                    return Ok(Err(Failure::NoMove {
                        key: key32,
                        cell: cell32,
                        value: k,
                    }));
                }
                let k = k as usize;
                let at = k * t.n_cells + cell;
                let end = t.ends[at] as usize;
                let collides = Failure::Collides {
                    key: key32,
                    cell: cell32,
                    mv: k as u32,
                };
                if t.wall_hit[at] {
                    return Ok(Err(collides));
                }
                let swept = &t.swept[at * t.n_swept..(at + 1) * t.n_swept];
                for j in replies.clone() {
                    let d = &t.danger[t.danger_off[j] as usize..t.danger_off[j + 1] as usize];
                    let hit = if t.position {
                        d.contains(&(end as u32))
                    } else {
                        d.iter().any(|c| swept.contains(c))
                    };
                    if hit {
                        return Ok(Err(collides));
                    }
                    let inside = t.reply_next[j].is_some_and(|nk| {
                        t.table[nk as usize * t.nw + end / 64] >> (end % 64) & 1 == 1
                    });
                    if !inside {
                        return Ok(Err(Failure::Leaves {
                            key: key32,
                            cell: cell32,
                            mv: k as u32,
                            end: end as u32,
                        }));
                    }
                }
            }
        }
    }
    Ok(Ok(checked))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 x 1 corridor, no obstacles (one configuration, one reply back to itself),
    /// moves stay and right: "stay" keeps {0}, "right" leaves it.
    fn corridor(table: &[u64]) -> InvariantTables<'_> {
        InvariantTables {
            width: 3,
            n_cells: 3,
            nw: 1,
            table,
            n_fixed: 0,
            fixed: &[],
            n_moves: 2,
            ends: &[0, 1, 2, 1, 2, 2],
            wall_hit: &[false; 6],
            n_swept: 1,
            swept: &[0, 1, 2, 1, 2, 2],
            reply_off: &[0, 1],
            reply_next: &[Some(0)],
            danger_off: &[0, 0],
            danger: &[],
            position: false,
        }
    }

    #[test]
    fn staying_keeps_the_set() {
        let t = corridor(&[0b001]);
        assert_eq!(check_invariant(&t, &[Op::Const(0)], None), Ok(Ok(1)));
    }

    #[test]
    fn moving_right_leaves_it() {
        let t = corridor(&[0b001]);
        assert_eq!(
            check_invariant(&t, &[Op::Const(1)], None),
            Ok(Err(Failure::Leaves {
                key: 0,
                cell: 0,
                mv: 1,
                end: 1
            }))
        );
    }

    #[test]
    fn no_move_is_reported() {
        let t = corridor(&[0b001]);
        assert_eq!(
            check_invariant(&t, &[Op::Const(5)], None),
            Ok(Err(Failure::NoMove {
                key: 0,
                cell: 0,
                value: 5
            }))
        );
    }
}
