//! PyO3 binding of `plansynth-core`. Only conversions live here.
use plansynth_core::conditions::{self, Arith, Cond};
use plansynth_core::game::{self, GameGraph, LayerCell, Op};
use plansynth_core::tree::{self, GreedyError, Node};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

#[pyfunction]
fn core_version() -> &'static str {
    plansynth_core::version()
}

type TermRow = (u8, i64, i64, u32);
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
            return Err(pyo3::exceptions::PyValueError::new_err("every state needs n_vars values"));
        }
    }
    let e = py.detach(|| conditions::enumerate_conditions(&states, n_vars, max_constant, max_depth, limit));
    let terms = e
        .terms
        .iter()
        .map(|(t, d)| match *t {
            Arith::Const(c) => (0u8, c, 0i64, *d),
            Arith::Var(j) => (1, j as i64, 0, *d),
            Arith::Plus(a, b) => (2, a as i64, b as i64, *d),
            Arith::Minus(a, b) => (3, a as i64, b as i64, *d),
        })
        .collect();
    let conds = e
        .conds
        .iter()
        .map(|(mask, c, d)| {
            let bytes: Vec<u8> = mask.iter().flat_map(|w| w.to_le_bytes()).collect();
            let (op, a, b) = match *c {
                Cond::Le(a, b) => (0u8, a, b),
                Cond::Eq(a, b) => (1, a, b),
                Cond::Not(a) => (2, a, 0),
                Cond::And(a, b) => (3, a, b),
                Cond::Or(a, b) => (4, a, b),
            };
            (PyBytes::new(py, &bytes), op, a, b, *d)
        })
        .collect();
    Ok((terms, conds, e.complete_to))
}

fn words(mask: &[u8], nw: usize) -> Vec<u64> {
    let mut out = vec![0u64; nw];
    for (i, b) in mask.iter().enumerate() {
        if i / 8 < nw {
            out[i / 8] |= (*b as u64) << (8 * (i % 8));
        }
    }
    out
}

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
        return Err(pyo3::exceptions::PyValueError::new_err("one key per condition"));
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

fn to_ops(prog: &[(u8, i64, i64, i64)]) -> PyResult<Vec<Op>> {
    let n = prog.len() as i64;
    let idx = |v: i64| -> PyResult<usize> {
        if 0 <= v && v < n {
            Ok(v as usize)
        } else {
            Err(pyo3::exceptions::PyValueError::new_err("program node index out of range"))
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
                _ => return Err(pyo3::exceptions::PyValueError::new_err("unknown program op")),
            })
        })
        .collect()
}

/// The winning-forward game graph (see `plansynth_core::game::GameGraph`).
#[pyclass(name = "GameGraph", frozen)]
struct PyGameGraph {
    g: GameGraph,
}

#[pymethods]
impl PyGameGraph {
    #[new]
    fn new(n_moves: usize, state_of: Vec<u32>, win: Vec<u32>, off: Vec<u32>, succ: Vec<u32>, inputs: Vec<Vec<i64>>) -> PyResult<Self> {
        let n_pairs = state_of.len();
        if win.len() != n_pairs || off.len() != n_pairs * n_moves + 1 {
            return Err(pyo3::exceptions::PyValueError::new_err("inconsistent game graph sizes"));
        }
        if state_of.iter().any(|&s| s as usize >= inputs.len())
            || succ.iter().any(|&q| q as usize >= n_pairs)
            || off.windows(2).any(|w| w[0] > w[1])
            || off.last().is_some_and(|&e| e as usize != succ.len())
        {
            return Err(pyo3::exceptions::PyValueError::new_err("game graph index out of range"));
        }
        Ok(Self { g: GameGraph { n_moves, state_of, win, off, succ, inputs } })
    }

    /// `(pairs, joint states)`.
    fn sizes(&self) -> (usize, usize) {
        (self.g.state_of.len(), self.g.inputs.len())
    }

    /// The graph's arrays: `(state_of, win, off, succ, inputs)`.
    #[allow(clippy::type_complexity)]
    fn arrays(&self) -> (Vec<u32>, Vec<u32>, Vec<u32>, Vec<u32>, Vec<Vec<i64>>) {
        let g = &self.g;
        (g.state_of.clone(), g.win.clone(), g.off.clone(), g.succ.clone(), g.inputs.clone())
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
        let ops = to_ops(prog)?;
        let width = self.g.inputs.first().map_or(0, |x| x.len());
        if ops.is_empty() || ops.iter().any(|o| matches!(o, Op::Var(j) if *j >= width)) {
            return Err(pyo3::exceptions::PyValueError::new_err("empty program or variable out of range"));
        }
        // children must come before parents (no cycles, bounded recursion)
        for (i, o) in ops.iter().enumerate() {
            let kids: &[usize] = match o {
                Op::Plus(a, b) | Op::Minus(a, b) | Op::Le(a, b) | Op::Eq(a, b) | Op::And(a, b) | Op::Or(a, b) => &[*a, *b],
                Op::Not(a) => std::slice::from_ref(a),
                Op::Ite(a, b, c) => &[*a, *b, *c],
                _ => &[],
            };
            if kids.iter().any(|&k| k >= i) {
                return Err(pyo3::exceptions::PyValueError::new_err("program nodes must list children first"));
            }
        }
        Ok(ops)
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
        return Err(pyo3::exceptions::PyValueError::new_err("one successor list per configuration"));
    }
    if successors.iter().flatten().any(|&c| c as usize >= n_configs) {
        return Err(pyo3::exceptions::PyValueError::new_err("successor configuration out of range"));
    }
    let n_cells = robot_end.len() / n_moves.max(1);
    if robot_end.len() != n_cells * n_moves || start as usize >= n_cells || robot_end.iter().any(|&e| e as usize >= n_cells) {
        return Err(pyo3::exceptions::PyValueError::new_err("robot end table out of range"));
    }
    let mut cells = Vec::with_capacity(layers.len());
    for (t, c, masks) in &layers {
        if masks.len() != n_moves || *c as usize >= n_configs {
            return Err(pyo3::exceptions::PyValueError::new_err("one winning mask per move, for a known configuration"));
        }
        let nw = n_cells.div_ceil(64).max(1);
        cells.push(LayerCell { t: *t, config: *c, winning: masks.iter().map(|b| words(b.as_bytes(), nw)).collect() });
    }
    let g = py.detach(|| game::build_game_graph(n_moves, steps, width, start, &configs, &successors, &robot_end, &cells));
    Ok(PyGameGraph { g })
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(core_version, m)?)?;
    m.add_function(wrap_pyfunction!(enumerate_conditions, m)?)?;
    m.add_function(wrap_pyfunction!(greedy_tree, m)?)?;
    m.add_class::<PyGameGraph>()?;
    m.add_function(wrap_pyfunction!(build_game_graph, m)?)?;
    Ok(())
}
