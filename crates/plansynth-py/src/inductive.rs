//! Binding of `plansynth_core::inductive`: the verifier's inductive-invariant check.
//! The tables come as little-endian byte strings (numpy's `tobytes()`), the program as
//! flat ops; running out of time raises `BudgetExhausted`.
use plansynth_core::inductive::{self, Failure, InvariantTables};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::words;
use crate::errors::{bad_value, budget_exhausted};
use crate::game::checked_ops;

fn u32s(b: &Bound<'_, PyBytes>) -> Vec<u32> {
    b.as_bytes()
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fn i64s(b: &Bound<'_, PyBytes>) -> Vec<i64> {
    b.as_bytes()
        .chunks_exact(8)
        .map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}

/// The first failure as (kind, configuration, cell, move, end or value): kind 0 no
/// move (the program's value last), 1 a collision, 2 a reply that leaves the set.
type FailureRow = (u8, u32, u32, i64, i64);

/// Check an inductive invariant (see the core's `inductive`): (states checked, None)
/// when it is one, else (0, the first failure).
#[pyfunction]
#[pyo3(signature = (width, n_cells, table, n_fixed, fixed, n_moves, ends, wall_hit, n_swept, swept,
    reply_off, reply_next, danger_off, danger, position, ops, seconds=None))]
#[allow(clippy::too_many_arguments)]
pub fn check_invariant(
    py: Python<'_>,
    width: usize,
    n_cells: usize,
    table: Bound<'_, PyBytes>,
    n_fixed: usize,
    fixed: Bound<'_, PyBytes>,
    n_moves: usize,
    ends: Bound<'_, PyBytes>,
    wall_hit: Bound<'_, PyBytes>,
    n_swept: usize,
    swept: Bound<'_, PyBytes>,
    reply_off: Bound<'_, PyBytes>,
    reply_next: Bound<'_, PyBytes>,
    danger_off: Bound<'_, PyBytes>,
    danger: Bound<'_, PyBytes>,
    position: bool,
    ops: Vec<(u8, i64, i64, i64)>,
    seconds: Option<f64>,
) -> PyResult<(usize, Option<FailureRow>)> {
    let nw = n_cells.div_ceil(64).max(1);
    let reply_off = u32s(&reply_off);
    let n_keys = reply_off.len().saturating_sub(1);
    let table_bytes = table.as_bytes();
    if width == 0 || n_cells == 0 || reply_off.is_empty() || table_bytes.len() != n_keys * nw * 8 {
        return Err(bad_value(
            "the invariant's table needs nw words per configuration",
        ));
    }
    let table = words(table_bytes, n_keys * nw);
    let fixed = i64s(&fixed);
    let ends = u32s(&ends);
    let wall_hit: Vec<bool> = wall_hit.as_bytes().iter().map(|&b| b != 0).collect();
    let swept = u32s(&swept);
    let reply_next: Vec<Option<u32>> = i64s(&reply_next)
        .into_iter()
        .map(|v| (v >= 0).then_some(v as u32))
        .collect();
    let danger_off = u32s(&danger_off);
    let danger = u32s(&danger);
    let n_replies = *reply_off.last().unwrap_or(&0) as usize;
    let cells_ok = |v: &[u32]| v.iter().all(|&c| (c as usize) < n_cells);
    if fixed.len() != n_keys * n_fixed
        || ends.len() != n_moves * n_cells
        || wall_hit.len() != n_moves * n_cells
        || swept.len() != n_moves * n_cells * n_swept
        || reply_next.len() != n_replies
        || danger_off.len() != n_replies + 1
        || *danger_off.last().unwrap_or(&0) as usize != danger.len()
        || reply_off.windows(2).any(|w| w[0] > w[1])
        || danger_off.windows(2).any(|w| w[0] > w[1])
        || reply_next.iter().flatten().any(|&k| k as usize >= n_keys)
        || !cells_ok(&ends)
        || !cells_ok(&swept)
    {
        return Err(bad_value("the invariant's tables disagree in size"));
    }
    let ops = checked_ops(&ops, 2 + n_fixed)?;
    let t = InvariantTables {
        width,
        n_cells,
        nw,
        table: &table,
        n_fixed,
        fixed: &fixed,
        n_moves,
        ends: &ends,
        wall_hit: &wall_hit,
        n_swept,
        swept: &swept,
        reply_off: &reply_off,
        reply_next: &reply_next,
        danger_off: &danger_off,
        danger: &danger,
        position,
    };
    let deadline = seconds
        .map(|s| std::time::Instant::now() + std::time::Duration::from_secs_f64(s.clamp(0.0, 1e9)));
    let out = py.detach(|| inductive::check_invariant(&t, &ops, deadline));
    match out {
        Err(_) => Err(budget_exhausted(
            "checking the inductive invariant",
            "time",
            "out of time".into(),
        )),
        Ok(Ok(n)) => Ok((n, None)),
        Ok(Err(f)) => Ok((
            0,
            Some(match f {
                Failure::NoMove { key, cell, value } => (0, key, cell, -1, value),
                Failure::Collides { key, cell, mv } => (1, key, cell, mv as i64, -1),
                Failure::Leaves { key, cell, mv, end } => (2, key, cell, mv as i64, end as i64),
            }),
        )),
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_invariant, m)?)
}
