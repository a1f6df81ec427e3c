//! Binding of `plansynth_core::tree`: the greedy decision tree over behaviours.
use plansynth_core::tree::{self, GreedyError, Node};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::words;
use crate::errors::bad_value;

/// The greedy decision tree (see `plansynth_core::tree::greedy_tree`). `conds` are
/// little-endian behaviour bytes, `keys` (depth, size) per condition, `allowed` a move
/// bitmask per state. Returns the pre-order nodes: `(0, k)` a leaf playing k, `(1, j)`
/// a split on condition j; None when more than `max_nodes` splits are needed.
#[pyfunction]
fn greedy_tree(
    py: Python<'_>,
    conds: Vec<Bound<'_, PyBytes>>,
    keys: Vec<(u32, u32)>,
    allowed: Vec<u32>,
    n_moves: usize,
    max_nodes: usize,
) -> PyResult<Option<Vec<(u8, usize)>>> {
    if keys.len() != conds.len() {
        return Err(bad_value("one key per condition"));
    }
    let nw = allowed.len().div_ceil(64).max(1);
    let masks: Vec<Vec<u64>> = conds.iter().map(|b| words(b.as_bytes(), nw)).collect();
    let out = py.detach(|| tree::greedy_tree(&masks, &keys, &allowed, n_moves, max_nodes));
    match out {
        Ok(nodes) => Ok(Some(
            nodes
                .into_iter()
                .map(|n| match n {
                    Node::Leaf(k) => (0u8, k),
                    Node::Split(j) => (1u8, j),
                })
                .collect(),
        )),
        Err(GreedyError::TooLarge) => Ok(None),
        Err(GreedyError::NoSplit) => Err(pyo3::exceptions::PyAssertionError::new_err(
            "no condition separates states with disjoint allowed moves",
        )),
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(greedy_tree, m)?)
}
