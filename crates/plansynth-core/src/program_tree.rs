//! A program's `ite` tree prepared for evaluation state after state: each `ite` whose
//! condition compares two variables or constants becomes a test read without
//! recursion, the rest evaluated by [`crate::game::eval`] (whose value it always
//! gives). Programs learnt by the greedy tree are such trees, so the closed loop and the
//! invariant check, which evaluate the program in every state they go through (33
//! million at 64 x 64), walk a path of tests instead of a recursion per node.

use crate::game::{eval, Op};

#[derive(Clone, Copy, Debug)]
enum Operand {
    Var(usize),
    Const(i64),
    /// any other term: evaluated by `eval`
    Op(usize),
}

#[derive(Clone, Copy, Debug)]
enum Step {
    /// compare two operands (`<=`, or `=` when `eq`), then go to `yes` or `no`
    Test {
        a: Operand,
        b: Operand,
        eq: bool,
        yes: u32,
        no: u32,
    },
    /// a condition of any other form, evaluated by `eval`
    Cond { op: usize, yes: u32, no: u32 },
    /// the program's value: this operand
    Value(Operand),
}

/// A program (flat ops, root last) as a walk of tests.
#[derive(Clone, Debug)]
pub struct ProgramTree<'a> {
    prog: &'a [Op],
    steps: Vec<Step>,
}

impl<'a> ProgramTree<'a> {
    /// Prepare `prog` (root: its last node).
    pub fn new(prog: &'a [Op]) -> ProgramTree<'a> {
        let mut t = ProgramTree {
            prog,
            steps: vec![],
        };
        if !prog.is_empty() {
            t.add(prog.len() - 1);
        }
        t
    }

    fn operand(&self, i: usize) -> Operand {
        match self.prog[i] {
            Op::Var(j) => Operand::Var(j),
            Op::Const(c) => Operand::Const(c),
            _ => Operand::Op(i),
        }
    }

    /// Add the steps of node `i`; its index.
    fn add(&mut self, i: usize) -> u32 {
        let at = self.steps.len();
        match self.prog[i] {
            Op::Ite(c, t, e) => {
                self.steps.push(Step::Value(Operand::Const(0))); // placed below
                let yes = self.add(t);
                let no = self.add(e);
                self.steps[at] = match self.prog[c] {
                    Op::Le(a, b) | Op::Eq(a, b) => Step::Test {
                        a: self.operand(a),
                        b: self.operand(b),
                        eq: matches!(self.prog[c], Op::Eq(..)),
                        yes,
                        no,
                    },
                    _ => Step::Cond { op: c, yes, no },
                };
            }
            _ => self.steps.push(Step::Value(self.operand(i))),
        }
        at as u32
    }

    #[inline]
    fn value(&self, o: Operand, x: &[i64]) -> i64 {
        match o {
            Operand::Var(j) => x[j],
            Operand::Const(c) => c,
            Operand::Op(i) => eval(self.prog, i, x),
        }
    }

    /// The program's value on inputs `x` (that of `eval` at its root).
    pub fn run(&self, x: &[i64]) -> i64 {
        let mut i = 0usize;
        loop {
            match self.steps[i] {
                Step::Test { a, b, eq, yes, no } => {
                    let (va, vb) = (self.value(a, x), self.value(b, x));
                    let holds = if eq { va == vb } else { va <= vb };
                    i = if holds { yes } else { no } as usize;
                }
                Step::Cond { op, yes, no } => {
                    i = if eval(self.prog, op, x) != 0 { yes } else { no } as usize;
                }
                Step::Value(o) => return self.value(o, x),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_walk_gives_eval_s_value() {
        // (ite (<= x0 2) (ite (= x1 x0) 3 (+ x0 x1)) (ite (not (<= x1 0)) 5 x1))
        let prog = vec![
            Op::Var(0),         // 0
            Op::Const(2),       // 1
            Op::Le(0, 1),       // 2
            Op::Var(1),         // 3
            Op::Eq(3, 0),       // 4
            Op::Const(3),       // 5
            Op::Plus(0, 3),     // 6
            Op::Ite(4, 5, 6),   // 7
            Op::Const(0),       // 8
            Op::Le(3, 8),       // 9
            Op::Not(9),         // 10
            Op::Const(5),       // 11
            Op::Ite(10, 11, 3), // 12
            Op::Ite(2, 7, 12),  // 13
        ];
        let t = ProgramTree::new(&prog);
        for a in -3..6 {
            for b in -3..6 {
                let x = [a, b];
                assert_eq!(t.run(&x), eval(&prog, 13, &x), "{x:?}");
            }
        }
    }
}
