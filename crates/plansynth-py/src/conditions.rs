//! Binding of `plansynth_core::conditions`: the bottom-up condition enumeration.
use plansynth_core::conditions::{self, Arith, Cond};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::bad_value;

pub type TermRow = (u8, i64, i64, u32);
type CondRow<'py> = (Bound<'py, PyBytes>, u8, usize, usize, u32);

/// Condition enumeration (see `plansynth_core::conditions`). Returns
/// `(terms, conds, complete_to)`: terms are `(kind, a, b, depth)` with kind 0 const a,
/// 1 var a, 2 plus(a, b), 3 minus(a, b); conds are `(mask bytes little-endian, op, a, b,
/// depth)` with op 0 `<=`, 1 `=`, 2 not a, 3 and, 4 or.
#[pyfunction]
#[pyo3(signature = (states, n_vars, max_constant, max_depth, limit=None))]
fn enumerate_conditions<'py>(
    py: Python<'py>,
    states: Vec<Vec<i64>>,
    n_vars: usize,
    max_constant: i64,
    max_depth: u32,
    limit: Option<usize>,
) -> PyResult<(Vec<TermRow>, Vec<CondRow<'py>>, u32)> {
    for s in &states {
        if s.len() != n_vars {
            return Err(bad_value("every state needs n_vars values"));
        }
    }
    let e = py.detach(|| {
        conditions::enumerate_conditions(&states, n_vars, max_constant, max_depth, limit)
    });
    let terms = term_rows(&e.terms);
    let conds = e
        .conds
        .iter()
        .map(|(mask, c, d)| {
            let bytes: Vec<u8> = mask.iter().flat_map(|w| w.to_le_bytes()).collect();
            let (op, a, b) = cond_op(c);
            (PyBytes::new(py, &bytes), op, a, b, *d)
        })
        .collect();
    Ok((terms, conds, e.complete_to))
}

/// Terms as rows `(kind, a, b, depth)`: kind 0 const a, 1 var a, 2 plus(a, b), 3 minus(a, b).
pub fn term_rows(terms: &[(Arith, u32)]) -> Vec<TermRow> {
    terms
        .iter()
        .map(|(t, d)| match *t {
            Arith::Const(c) => (0u8, c, 0i64, *d),
            Arith::Var(j) => (1, j as i64, 0, *d),
            Arith::Plus(a, b) => (2, a as i64, b as i64, *d),
            Arith::Minus(a, b) => (3, a as i64, b as i64, *d),
        })
        .collect()
}

/// A condition as `(op, a, b)`: op 0 `<=`, 1 `=`, 2 not a, 3 and, 4 or.
pub fn cond_op(c: &Cond) -> (u8, usize, usize) {
    match *c {
        Cond::Le(a, b) => (0u8, a, b),
        Cond::Eq(a, b) => (1, a, b),
        Cond::Not(a) => (2, a, 0),
        Cond::And(a, b) => (3, a, b),
        Cond::Or(a, b) => (4, a, b),
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(enumerate_conditions, m)?)
}
