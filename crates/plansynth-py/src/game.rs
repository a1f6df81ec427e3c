//! Binding of `plansynth_core::game`: programs as flat ops, the winning-forward game
//! graph and its program check.
use plansynth_core::game::{self, GameGraph, LayerCell, Op};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::words;
use crate::errors::bad_value;

fn to_ops(prog: &[(u8, i64, i64, i64)]) -> PyResult<Vec<Op>> {
    let n = prog.len() as i64;
    let idx = |v: i64| -> PyResult<usize> {
        if 0 <= v && v < n {
            Ok(v as usize)
        } else {
            Err(bad_value("program node index out of range"))
        }
    };
    prog.iter()
        .map(|&(op, a, b, c)| {
            Ok(match op {
                0 => Op::Const(a),
                1 => Op::Var(a as usize),
                2 => Op::Plus(idx(a)?, idx(b)?),
                3 => Op::Minus(idx(a)?, idx(b)?),
                4 => Op::Le(idx(a)?, idx(b)?),
                5 => Op::Eq(idx(a)?, idx(b)?),
                6 => Op::Not(idx(a)?),
                7 => Op::And(idx(a)?, idx(b)?),
                8 => Op::Or(idx(a)?, idx(b)?),
                9 => Op::Ite(idx(a)?, idx(b)?, idx(c)?),
                _ => return Err(bad_value("unknown program op")),
            })
        })
        .collect()
}

/// Program rows as ops, children first, variables below `n_vars`.
pub fn checked_ops(prog: &[(u8, i64, i64, i64)], n_vars: usize) -> PyResult<Vec<Op>> {
    let ops = to_ops(prog)?;
    if ops.is_empty() || ops.iter().any(|o| matches!(o, Op::Var(j) if *j >= n_vars)) {
        return Err(bad_value("empty program or variable out of range"));
    }
    for (i, o) in ops.iter().enumerate() {
        let kids: &[usize] = match o {
            Op::Plus(a, b)
            | Op::Minus(a, b)
            | Op::Le(a, b)
            | Op::Eq(a, b)
            | Op::And(a, b)
            | Op::Or(a, b) => &[*a, *b],
            Op::Not(a) => std::slice::from_ref(a),
            Op::Ite(a, b, c) => &[*a, *b, *c],
            _ => &[],
        };
        if kids.iter().any(|&k| k >= i) {
            return Err(bad_value("program nodes must list children first"));
        }
    }
    Ok(ops)
}

/// The winning-forward game graph (see `plansynth_core::game::GameGraph`).
#[pyclass(name = "GameGraph", frozen)]
struct PyGameGraph {
    g: GameGraph,
}

#[pymethods]
impl PyGameGraph {
    #[new]
    fn new(
        n_moves: usize,
        state_of: Vec<u32>,
        win: Vec<u32>,
        off: Vec<u32>,
        succ: Vec<u32>,
        inputs: Vec<Vec<i64>>,
    ) -> PyResult<Self> {
        let n_pairs = state_of.len();
        if win.len() != n_pairs || off.len() != n_pairs * n_moves + 1 {
            return Err(bad_value("inconsistent game graph sizes"));
        }
        if state_of.iter().any(|&s| s as usize >= inputs.len())
            || succ.iter().any(|&q| q as usize >= n_pairs)
            || off.windows(2).any(|w| w[0] > w[1])
            || off.last().is_some_and(|&e| e as usize != succ.len())
        {
            return Err(bad_value("game graph index out of range"));
        }
        Ok(Self {
            g: GameGraph {
                n_moves,
                state_of,
                win,
                off,
                succ,
                inputs,
            },
        })
    }

    /// `(pairs, joint states)`.
    fn sizes(&self) -> (usize, usize) {
        (self.g.state_of.len(), self.g.inputs.len())
    }

    /// The graph's arrays: `(state_of, win, off, succ, inputs)`.
    #[allow(clippy::type_complexity)]
    fn arrays(&self) -> (Vec<u32>, Vec<u32>, Vec<u32>, Vec<u32>, Vec<Vec<i64>>) {
        let g = &self.g;
        (
            g.state_of.clone(),
            g.win.clone(),
            g.off.clone(),
            g.succ.clone(),
            g.inputs.clone(),
        )
    }

    /// None when the program (flat ops, root last) wins, else the first failing pair.
    fn check(&self, py: Python<'_>, prog: Vec<(u8, i64, i64, i64)>) -> PyResult<Option<u32>> {
        let ops = self.ops(&prog)?;
        let root = ops.len() - 1;
        Ok(py.detach(|| self.g.check(&ops, root)))
    }

    /// The move the program plays in each joint state.
    fn moves(&self, py: Python<'_>, prog: Vec<(u8, i64, i64, i64)>) -> PyResult<Vec<i64>> {
        let ops = self.ops(&prog)?;
        let root = ops.len() - 1;
        Ok(py.detach(|| self.g.moves(&ops, root)))
    }
}

impl PyGameGraph {
    fn ops(&self, prog: &[(u8, i64, i64, i64)]) -> PyResult<Vec<Op>> {
        checked_ops(prog, self.g.inputs.first().map_or(0, |x| x.len()))
    }
}

/// Explore the winning-forward graph (see `plansynth_core::game::build_game_graph`).
/// `layers` are `(t, config, [winning mask bytes per move])`.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn build_game_graph(
    py: Python<'_>,
    n_moves: usize,
    steps: u32,
    width: u32,
    start: u32,
    configs: Vec<Vec<u32>>,
    successors: Vec<Vec<u32>>,
    robot_end: Vec<u32>,
    layers: Vec<(u32, u32, Vec<Bound<'_, PyBytes>>)>,
) -> PyResult<PyGameGraph> {
    let n_configs = configs.len();
    if successors.len() != n_configs || n_configs == 0 || width == 0 {
        return Err(bad_value("one successor list per configuration"));
    }
    if successors
        .iter()
        .flatten()
        .any(|&c| c as usize >= n_configs)
    {
        return Err(bad_value("successor configuration out of range"));
    }
    let n_cells = robot_end.len() / n_moves.max(1);
    if robot_end.len() != n_cells * n_moves
        || start as usize >= n_cells
        || robot_end.iter().any(|&e| e as usize >= n_cells)
    {
        return Err(bad_value("robot end table out of range"));
    }
    let mut cells = Vec::with_capacity(layers.len());
    for (t, c, masks) in &layers {
        if masks.len() != n_moves || *c as usize >= n_configs {
            return Err(bad_value(
                "one winning mask per move, for a known configuration",
            ));
        }
        let nw = n_cells.div_ceil(64).max(1);
        cells.push(LayerCell {
            t: *t,
            config: *c,
            winning: masks.iter().map(|b| words(b.as_bytes(), nw)).collect(),
        });
    }
    let g = py.detach(|| {
        game::build_game_graph(
            n_moves,
            steps,
            width,
            start,
            &configs,
            &successors,
            &robot_end,
            &cells,
        )
    });
    Ok(PyGameGraph { g })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyGameGraph>()?;
    m.add_function(wrap_pyfunction!(build_game_graph, m)?)
}
