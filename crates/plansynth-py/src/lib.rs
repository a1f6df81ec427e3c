//! PyO3 binding of `plansynth-core`. Only conversions live here.
use plansynth_core::arena::{self as arena_core, ArenaSpec, MoveGeo, Stop};
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

/// Program rows as ops, children first, variables below `n_vars`.
fn checked_ops(prog: &[(u8, i64, i64, i64)], n_vars: usize) -> PyResult<Vec<Op>> {
    let ops = to_ops(prog)?;
    if ops.is_empty() || ops.iter().any(|o| matches!(o, Op::Var(j) if *j >= n_vars)) {
        return Err(pyo3::exceptions::PyValueError::new_err("empty program or variable out of range"));
    }
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


fn bits_of(b: &Bound<'_, PyBytes>, nw: usize) -> Vec<u64> {
    words(b.as_bytes(), nw)
}

fn bytes_of<'py>(py: Python<'py>, m: &[u64]) -> Bound<'py, PyBytes> {
    let v: Vec<u8> = m.iter().flat_map(|w| w.to_le_bytes()).collect();
    PyBytes::new(py, &v)
}

fn clock(seconds: Option<f64>, memory: Option<usize>, max_configs: Option<usize>) -> arena_core::Budget {
    let deadline = seconds.map(|s| std::time::Instant::now() + std::time::Duration::from_secs_f64(s.clamp(0.0, 1e9)));
    arena_core::Budget { deadline, memory, max_configs }
}

/// `(kind, step, configurations, bytes)` of a stop: kind is "time", "memory" or "configs".
type StopRow = (&'static str, usize, usize, usize);

fn stop_row(s: Stop) -> StopRow {
    match s {
        Stop::Time { step, configs } => ("time", step, configs, 0),
        Stop::Memory { step, configs, bytes } => ("memory", step, configs, bytes),
        Stop::Configs { configs } => ("configs", 0, configs, 0),
    }
}

type RobotMove<'py> = (Bound<'py, PyBytes>, Bound<'py, PyBytes>, i64, Vec<i64>);
type ObstacleMove<'py> = (Bound<'py, PyBytes>, i64, Vec<i64>);

/// The joint game of the robot and the read obstacles (see `plansynth_core::arena`).
#[pyclass(name = "Arena")]
struct PyArena {
    a: arena_core::Arena,
    fwd: Option<Vec<Vec<(u32, Vec<u64>)>>>,
}

type StateRow = (u32, Vec<u32>, u32);
type LayerRows<'py> = Vec<Vec<(Vec<u32>, Bound<'py, PyBytes>)>>;

impl PyArena {
    fn rows_out<'py>(&self, py: Python<'py>, layers: &[Vec<(u32, Vec<u64>)>]) -> LayerRows<'py> {
        layers.iter().map(|l| l.iter().map(|(id, m)| (self.a.config(*id).to_vec(), bytes_of(py, m))).collect()).collect()
    }

    fn rows_in(&mut self, layers: &[Vec<(Vec<u32>, Bound<'_, PyBytes>)>]) -> PyResult<Vec<Vec<(u32, Vec<u64>)>>> {
        let (nw, n, cells) = (self.a.nw, self.a.spec.obstacles.len(), self.a.spec.n_cells);
        let mut out = vec![];
        for l in layers {
            let mut v = vec![];
            for (oc, m) in l {
                if oc.len() != n || oc.iter().any(|&c| c as usize >= cells) {
                    return Err(pyo3::exceptions::PyValueError::new_err("one cell on the grid per read obstacle"));
                }
                v.push((self.a.config_id(oc), bits_of(m, nw)));
            }
            out.push(v);
        }
        Ok(out)
    }

    fn start_clock(&mut self, seconds: Option<f64>) {
        self.a.deadline = clock(seconds, None, None).deadline;
        self.a.expired = false;
    }

    /// TimeoutError when the routine just run stopped at its deadline.
    fn stop_clock(&mut self) -> PyResult<()> {
        let expired = self.a.expired;
        self.a.deadline = None;
        self.a.expired = false;
        if expired {
            return Err(pyo3::exceptions::PyTimeoutError::new_err("out of time"));
        }
        Ok(())
    }

    fn states_out(&self, rows: Vec<((u32, u32), u32)>) -> Vec<StateRow> {
        rows.into_iter().map(|((r, id), m)| (r, self.a.config(id).to_vec(), m)).collect()
    }
}

#[pymethods]
impl PyArena {
    #[new]
    #[allow(clippy::too_many_arguments)]
    fn new(
        n_cells: usize,
        steps: usize,
        robot: Vec<RobotMove<'_>>,
        obstacles: Vec<Vec<ObstacleMove<'_>>>,
        abstract_danger: Vec<Bound<'_, PyBytes>>,
        live: Vec<Bound<'_, PyBytes>>,
        start: usize,
        goal: usize,
        start_config: Vec<u32>,
    ) -> PyResult<Self> {
        let nw = n_cells.div_ceil(64).max(1);
        let bad = |m: &str| Err(pyo3::exceptions::PyValueError::new_err(m.to_string()));
        if n_cells == 0 || start >= n_cells || goal >= n_cells || robot.is_empty() {
            return bad("empty grid, or start/goal off the grid");
        }
        if abstract_danger.len() != steps || live.len() != steps + 1 || start_config.len() != obstacles.len() {
            return bad("one danger mask per step, one live mask per time, one start cell per obstacle");
        }
        if start_config.iter().any(|&c| c as usize >= n_cells) || obstacles.iter().any(|o| o.is_empty()) {
            return bad("obstacle start off the grid, or an obstacle without moves");
        }
        // every valid source of a move must stay on the grid (the caller's geometry says so)
        let on_grid = |valid: &[u64], deltas: &[i64]| {
            (0..n_cells).all(|c| valid[c / 64] >> (c % 64) & 1 == 0 || deltas.iter().all(|&d| (0..n_cells as i64).contains(&(c as i64 + d))))
        };
        let mut rm = vec![];
        for (valid, free, to, offsets) in &robot {
            let valid = bits_of(valid, nw);
            let mut all = offsets.clone();
            all.push(*to);
            if !on_grid(&valid, &all) {
                return bad("a robot move leaves the grid from a valid cell");
            }
            rm.push(MoveGeo { valid, free: bits_of(free, nw), to: *to, offsets: offsets.clone() });
        }
        let mut om = vec![];
        for moves in &obstacles {
            let mut v = vec![];
            for (valid, to, offsets) in moves {
                let valid = bits_of(valid, nw);
                let mut all = offsets.clone();
                all.push(*to);
                if !on_grid(&valid, &all) {
                    return bad("an obstacle move leaves the grid from a valid cell");
                }
                v.push(MoveGeo { valid, free: vec![], to: *to, offsets: offsets.clone() });
            }
            om.push(v);
        }
        let spec = ArenaSpec {
            n_cells,
            steps,
            robot: rm,
            obstacles: om,
            abstract_danger: abstract_danger.iter().map(|b| bits_of(b, nw)).collect(),
            live: live.iter().map(|b| bits_of(b, nw)).collect(),
            start,
            goal,
            start_config,
        };
        Ok(Self { a: arena_core::Arena::new(spec), fwd: None })
    }

    /// Explore within `seconds`, `memory` bytes and `max_configs`; None, or why it stopped.
    #[pyo3(signature = (seconds=None, memory=None, max_configs=None))]
    fn explore(&mut self, py: Python<'_>, seconds: Option<f64>, memory: Option<usize>, max_configs: Option<usize>) -> Option<StopRow> {
        let c = clock(seconds, memory, max_configs);
        let a = &mut self.a;
        py.detach(|| a.explore(&c)).err().map(stop_row)
    }

    /// Backward induction: `(won, None)` or `(False, why it stopped)`.
    #[pyo3(signature = (seconds=None, memory=None))]
    fn solve_game(&mut self, py: Python<'_>, seconds: Option<f64>, memory: Option<usize>) -> (bool, Option<StopRow>) {
        let c = clock(seconds, memory, None);
        let a = &mut self.a;
        match py.detach(|| a.solve_game(&c)) {
            Ok(w) => (w, None),
            Err(s) => (false, Some(stop_row(s))),
        }
    }

    /// Rows per layer.
    fn layer_sizes(&self) -> Vec<usize> {
        self.a.layers.iter().map(|l| l.ids.len()).collect()
    }

    /// Bytes the game holds now.
    fn bytes(&self) -> usize {
        self.a.bytes()
    }

    /// Joint states explored (robot cells summed over every row of every layer).
    fn state_count(&self) -> u64 {
        self.a.layers.iter().map(|l| l.masks.iter().map(|w| w.count_ones() as u64).sum::<u64>()).sum()
    }

    /// Layer t as `(config cells, robot cells bytes)`; with `win`, the winning cells
    /// (rows that win nowhere left out).
    #[pyo3(signature = (t, win=false))]
    fn layer<'py>(&self, py: Python<'py>, t: usize, win: bool) -> PyResult<Vec<(Vec<u32>, Bound<'py, PyBytes>)>> {
        let nw = self.a.nw;
        let l = self.a.layers.get(t).ok_or_else(|| pyo3::exceptions::PyIndexError::new_err("no such layer"))?;
        let src = if win { &l.win } else { &l.masks };
        if win && src.len() != l.masks.len() {
            return Err(pyo3::exceptions::PyValueError::new_err("the game is not solved"));
        }
        Ok(l.ids
            .iter()
            .enumerate()
            .filter(|(i, _)| !win || src[i * nw..(i + 1) * nw].iter().any(|&w| w != 0))
            .map(|(i, &id)| (self.a.config(id).to_vec(), bytes_of(py, &src[i * nw..(i + 1) * nw])))
            .collect())
    }

    /// Per robot move: the cells of layer t's configuration `oc` from which it wins.
    fn winning_moves<'py>(&mut self, py: Python<'py>, t: usize, oc: Vec<u32>) -> PyResult<Vec<Bound<'py, PyBytes>>> {
        if !self.a.solved || t >= self.a.spec.steps {
            return Err(pyo3::exceptions::PyValueError::new_err("winning moves need a solved game and t < steps"));
        }
        let n = self.a.spec.robot.len();
        let row = self.a.find_config(&oc).and_then(|id| self.a.row(t, id));
        Ok(match row {
            Some(row) => self.a.winning_moves(t, row).iter().map(|m| bytes_of(py, m)).collect(),
            None => (0..n).map(|_| PyBytes::new(py, &[])).collect(),
        })
    }

    /// Successor configurations of `oc`.
    fn successors(&mut self, oc: Vec<u32>) -> PyResult<Vec<Vec<u32>>> {
        if oc.len() != self.a.spec.obstacles.len() || oc.iter().any(|&c| c as usize >= self.a.spec.n_cells) {
            return Err(pyo3::exceptions::PyValueError::new_err("one cell on the grid per read obstacle"));
        }
        let id = self.a.config_id(&oc);
        let s = self.a.successors(id);
        Ok(s.iter().map(|&c| self.a.config(c).to_vec()).collect())
    }

    /// The winning-forward layers, or why it stopped.
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (seconds=None, memory=None))]
    fn winning_forward<'py>(
        &mut self,
        py: Python<'py>,
        seconds: Option<f64>,
        memory: Option<usize>,
    ) -> PyResult<(Option<Vec<Vec<(Vec<u32>, Bound<'py, PyBytes>)>>>, Option<StopRow>)> {
        if !self.a.solved || self.a.layers[0].ids.is_empty() {
            return Err(pyo3::exceptions::PyValueError::new_err("the winning-forward layers need a solved, non-empty game"));
        }
        let c = clock(seconds, memory, None);
        let a = &mut self.a;
        let got = py.detach(|| a.winning_forward(&c));
        Ok(match got {
            Err(s) => (None, Some(stop_row(s))),
            Ok(layers) => {
                let out = self.rows_out(py, &layers);
                self.fwd = Some(layers);
                (Some(out), None)
            }
        })
    }

    /// The strategy read off the game (see `plansynth_core::arena::Arena::consistent`)
    /// over the last winning-forward layers: `(reach layers, allowed moves per state)`,
    /// or None when it meets a state without a move that wins at every time.
    #[pyo3(signature = (width, seconds=None))]
    fn consistent<'py>(&mut self, py: Python<'py>, width: usize, seconds: Option<f64>) -> PyResult<Option<(LayerRows<'py>, Vec<StateRow>)>> {
        let fwd = self.fwd.take().ok_or_else(|| pyo3::exceptions::PyValueError::new_err("call winning_forward first"))?;
        self.start_clock(seconds);
        let a = &mut self.a;
        let got = py.detach(|| {
            let reach = a.consistent(&fwd, width)?;
            let allowed = a.allowed(&reach);
            Some((reach, allowed))
        });
        self.fwd = Some(fwd);
        self.stop_clock()?;
        Ok(got.map(|(reach, allowed)| (self.rows_out(py, &reach), self.states_out(allowed))))
    }

    /// The program check on the solved game (see `Arena::check_program`): None when the
    /// program (flat ops, root last) wins, else the first failing `(t, cell, config)`;
    /// `("time", ...)` rows are never returned: out of time raises TimeoutError.
    #[pyo3(signature = (prog, width, seconds=None))]
    fn check(&mut self, py: Python<'_>, prog: Vec<(u8, i64, i64, i64)>, width: usize, seconds: Option<f64>) -> PyResult<Option<(usize, usize, Vec<u32>)>> {
        if !self.a.solved || width == 0 || self.a.spec.n_cells % width != 0 {
            return Err(pyo3::exceptions::PyValueError::new_err("the check needs a solved game and the grid width"));
        }
        let ops = checked_ops(&prog, 2 + 2 * self.a.spec.obstacles.len())?;
        let root = ops.len() - 1;
        let c = clock(seconds, None, None);
        let a = &mut self.a;
        match py.detach(|| a.check_program(&ops, root, width, &c)) {
            Ok(None) => Ok(None),
            Ok(Some((t, r, id))) => Ok(Some((t, r, self.a.config(id).to_vec()))),
            Err(_) => Err(pyo3::exceptions::PyTimeoutError::new_err("checking the program: out of time")),
        }
    }

    /// `(pairs, joint states)` of the last winning-forward layers.
    fn forward_sizes(&self) -> PyResult<(u64, u64)> {
        let fwd = self.fwd.as_ref().ok_or_else(|| pyo3::exceptions::PyValueError::new_err("call winning_forward first"))?;
        let pairs = fwd.iter().take(self.a.spec.steps).flatten().map(|(_, m)| m.iter().map(|w| w.count_ones() as u64).sum::<u64>()).sum();
        let mut union: std::collections::HashMap<u32, Vec<u64>> = std::collections::HashMap::new();
        for (id, m) in fwd.iter().take(self.a.spec.steps).flatten() {
            let u = union.entry(*id).or_insert_with(|| vec![0; m.len()]);
            u.iter_mut().zip(m).for_each(|(a, b)| *a |= b);
        }
        let states = union.values().map(|m| m.iter().map(|w| w.count_ones() as u64).sum::<u64>()).sum();
        Ok((pairs, states))
    }

    /// Allowed moves per state of `reach` (`(cell, config, move bitmask)`).
    #[pyo3(signature = (reach, seconds=None))]
    fn allowed(&mut self, py: Python<'_>, reach: Vec<Vec<(Vec<u32>, Bound<'_, PyBytes>)>>, seconds: Option<f64>) -> PyResult<Vec<StateRow>> {
        let reach = self.rows_in(&reach)?;
        self.start_clock(seconds);
        let a = &mut self.a;
        let rows = py.detach(|| a.allowed(&reach));
        self.stop_clock()?;
        Ok(self.states_out(rows))
    }

    /// States reached when every state plays any of its allowed moves.
    #[pyo3(signature = (allowed, seconds=None))]
    fn closure<'py>(&mut self, py: Python<'py>, allowed: Vec<StateRow>, seconds: Option<f64>) -> PyResult<LayerRows<'py>> {
        let mut rows = vec![];
        for (r, oc, m) in &allowed {
            if *r as usize >= self.a.spec.n_cells || oc.len() != self.a.spec.obstacles.len() {
                return Err(pyo3::exceptions::PyValueError::new_err("a state off the grid"));
            }
            rows.push(((*r, self.a.config_id(oc)), *m));
        }
        self.start_clock(seconds);
        let a = &mut self.a;
        let out = py.detach(|| a.closure(&rows));
        self.stop_clock()?;
        Ok(self.rows_out(py, &out))
    }
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(core_version, m)?)?;
    m.add_function(wrap_pyfunction!(enumerate_conditions, m)?)?;
    m.add_function(wrap_pyfunction!(greedy_tree, m)?)?;
    m.add_class::<PyGameGraph>()?;
    m.add_class::<PyArena>()?;
    m.add_function(wrap_pyfunction!(build_game_graph, m)?)?;
    Ok(())
}
