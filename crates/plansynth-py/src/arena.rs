//! Binding of `plansynth_core::arena`: the joint game of the robot and the read
//! obstacles. A call that runs out of its seconds, memory or configurations raises
//! `plansynth.budget.BudgetExhausted` naming its phase.
use plansynth_core::arena::{self as arena_core, ArenaSpec, MoveGeo, Stop};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::{bits_of, bytes_of};
use crate::errors::{bad_value, budget_exhausted};
use crate::game::checked_ops;

fn clock(
    seconds: Option<f64>,
    memory: Option<usize>,
    max_configs: Option<usize>,
) -> arena_core::Budget {
    let deadline = seconds
        .map(|s| std::time::Instant::now() + std::time::Duration::from_secs_f64(s.clamp(0.0, 1e9)));
    arena_core::Budget {
        deadline,
        memory,
        max_configs,
    }
}

/// The `BudgetExhausted` of a core routine that stopped in `phase`, saying where and
/// what ran out; `memory` is the limit the routine was given (bytes).
fn stopped(phase: &str, stop: Stop, memory: Option<usize>) -> PyErr {
    match stop {
        Stop::Time { step, configs } => {
            let held = if configs > 0 { format!(" ({configs} obstacle configurations)") } else { String::new() };
            budget_exhausted(phase, "time", format!("{phase} at step {step}{held}: out of time"))
        }
        Stop::Memory { step, configs, bytes } => budget_exhausted(
            phase,
            "memory",
            format!(
                "{phase} at step {step}: the game outgrows the memory budget of {} MB ({} MB held, {configs} obstacle configurations)",
                memory.unwrap_or(0) >> 20,
                bytes >> 20
            ),
        ),
        Stop::Configs { configs } => {
            budget_exhausted(phase, "configurations", format!("more than {} obstacle configurations", configs.saturating_sub(1)))
        }
    }
}

type RobotMove<'py> = (Bound<'py, PyBytes>, Bound<'py, PyBytes>, i64, Vec<i64>);
type ObstacleMove<'py> = (Bound<'py, PyBytes>, i64, Vec<i64>);

/// The joint game of the robot and the read obstacles (see `plansynth_core::arena`).
#[pyclass(name = "Arena")]
struct PyArena {
    a: arena_core::Arena,
    fwd: Option<CoreLayers>,
}

type StateRow = (u32, Vec<u32>, u32);
/// Per time, `(configuration id, robot cells)`: layers as the core holds them.
type CoreLayers = Vec<Vec<(u32, Vec<u64>)>>;
type LayerRows<'py> = Vec<Vec<(Vec<u32>, Bound<'py, PyBytes>)>>;

impl PyArena {
    fn rows_out<'py>(&self, py: Python<'py>, layers: &[Vec<(u32, Vec<u64>)>]) -> LayerRows<'py> {
        layers
            .iter()
            .map(|l| {
                l.iter()
                    .map(|(id, m)| (self.a.config(*id).to_vec(), bytes_of(py, m)))
                    .collect()
            })
            .collect()
    }

    fn rows_in(&mut self, layers: &[Vec<(Vec<u32>, Bound<'_, PyBytes>)>]) -> PyResult<CoreLayers> {
        let (nw, n, cells) = (self.a.nw, self.a.spec.obstacles.len(), self.a.spec.n_cells);
        let mut out = vec![];
        for l in layers {
            let mut v = vec![];
            for (oc, m) in l {
                if oc.len() != n || oc.iter().any(|&c| c as usize >= cells) {
                    return Err(bad_value("one cell on the grid per read obstacle"));
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

    /// `BudgetExhausted` naming `phase` when the routine just run stopped at its deadline.
    fn stop_clock(&mut self, phase: &str) -> PyResult<()> {
        let expired = self.a.expired;
        self.a.deadline = None;
        self.a.expired = false;
        if expired {
            return Err(budget_exhausted(
                phase,
                "time",
                format!("{phase}: out of time"),
            ));
        }
        Ok(())
    }

    fn states_out(&self, rows: Vec<((u32, u32), u32)>) -> Vec<StateRow> {
        rows.into_iter()
            .map(|((r, id), m)| (r, self.a.config(id).to_vec(), m))
            .collect()
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
        let bad = |m: &str| Err(bad_value(m));
        if n_cells == 0 || start >= n_cells || goal >= n_cells || robot.is_empty() {
            return bad("empty grid, or start/goal off the grid");
        }
        if abstract_danger.len() != steps
            || live.len() != steps + 1
            || start_config.len() != obstacles.len()
        {
            return bad(
                "one danger mask per step, one live mask per time, one start cell per obstacle",
            );
        }
        if start_config.iter().any(|&c| c as usize >= n_cells)
            || obstacles.iter().any(|o| o.is_empty())
        {
            return bad("obstacle start off the grid, or an obstacle without moves");
        }
        // every valid source of a move must stay on the grid (the caller's geometry says so)
        let on_grid = |valid: &[u64], deltas: &[i64]| {
            (0..n_cells).all(|c| {
                valid[c / 64] >> (c % 64) & 1 == 0
                    || deltas
                        .iter()
                        .all(|&d| (0..n_cells as i64).contains(&(c as i64 + d)))
            })
        };
        let mut rm = vec![];
        for (valid, free, to, offsets) in &robot {
            let valid = bits_of(valid, nw);
            let mut all = offsets.clone();
            all.push(*to);
            if !on_grid(&valid, &all) {
                return bad("a robot move leaves the grid from a valid cell");
            }
            rm.push(MoveGeo {
                valid,
                free: bits_of(free, nw),
                to: *to,
                offsets: offsets.clone(),
            });
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
                v.push(MoveGeo {
                    valid,
                    free: vec![],
                    to: *to,
                    offsets: offsets.clone(),
                });
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
        Ok(Self {
            a: arena_core::Arena::new(spec),
            fwd: None,
        })
    }

    /// Explore within `seconds`, `memory` bytes and `max_configs` (`BudgetExhausted`
    /// past any of them).
    #[pyo3(signature = (seconds=None, memory=None, max_configs=None))]
    fn explore(
        &mut self,
        py: Python<'_>,
        seconds: Option<f64>,
        memory: Option<usize>,
        max_configs: Option<usize>,
    ) -> PyResult<()> {
        let c = clock(seconds, memory, max_configs);
        let a = &mut self.a;
        py.detach(|| a.explore(&c))
            .map_err(|s| stopped("exploring the game", s, memory))
    }

    /// Backward induction: whether the robot wins when it may see the time
    /// (`BudgetExhausted` past `seconds` or `memory` bytes).
    #[pyo3(signature = (seconds=None, memory=None))]
    fn solve_game(
        &mut self,
        py: Python<'_>,
        seconds: Option<f64>,
        memory: Option<usize>,
    ) -> PyResult<bool> {
        let c = clock(seconds, memory, None);
        let a = &mut self.a;
        py.detach(|| a.solve_game(&c))
            .map_err(|s| stopped("solving the game", s, memory))
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
        self.a
            .layers
            .iter()
            .map(|l| l.masks.iter().map(|w| w.count_ones() as u64).sum::<u64>())
            .sum()
    }

    /// Layer t as `(config cells, robot cells bytes)`; with `win`, the winning cells
    /// (rows that win nowhere left out).
    #[pyo3(signature = (t, win=false))]
    fn layer<'py>(
        &self,
        py: Python<'py>,
        t: usize,
        win: bool,
    ) -> PyResult<Vec<(Vec<u32>, Bound<'py, PyBytes>)>> {
        let nw = self.a.nw;
        let l = self
            .a
            .layers
            .get(t)
            .ok_or_else(|| pyo3::exceptions::PyIndexError::new_err("no such layer"))?;
        let src = if win { &l.win } else { &l.masks };
        if win && src.len() != l.masks.len() {
            return Err(bad_value("the game is not solved"));
        }
        Ok(l.ids
            .iter()
            .enumerate()
            .filter(|(i, _)| !win || src[i * nw..(i + 1) * nw].iter().any(|&w| w != 0))
            .map(|(i, &id)| {
                (
                    self.a.config(id).to_vec(),
                    bytes_of(py, &src[i * nw..(i + 1) * nw]),
                )
            })
            .collect())
    }

    /// Per robot move: the cells of layer t's configuration `oc` from which it wins.
    fn winning_moves<'py>(
        &mut self,
        py: Python<'py>,
        t: usize,
        oc: Vec<u32>,
    ) -> PyResult<Vec<Bound<'py, PyBytes>>> {
        if !self.a.solved || t >= self.a.spec.steps {
            return Err(bad_value("winning moves need a solved game and t < steps"));
        }
        let n = self.a.spec.robot.len();
        let row = self.a.find_config(&oc).and_then(|id| self.a.row(t, id));
        Ok(match row {
            Some(row) => self
                .a
                .winning_moves(t, row)
                .iter()
                .map(|m| bytes_of(py, m))
                .collect(),
            None => (0..n).map(|_| PyBytes::new(py, &[])).collect(),
        })
    }

    /// Successor configurations of `oc`.
    fn successors(&mut self, oc: Vec<u32>) -> PyResult<Vec<Vec<u32>>> {
        if oc.len() != self.a.spec.obstacles.len()
            || oc.iter().any(|&c| c as usize >= self.a.spec.n_cells)
        {
            return Err(bad_value("one cell on the grid per read obstacle"));
        }
        let id = self.a.config_id(&oc);
        let s = self.a.successors(id);
        Ok(s.iter().map(|&c| self.a.config(c).to_vec()).collect())
    }

    /// The winning-forward layers (kept for the calls below; `BudgetExhausted` past
    /// `seconds` or `memory` bytes).
    #[pyo3(signature = (seconds=None, memory=None))]
    fn winning_forward<'py>(
        &mut self,
        py: Python<'py>,
        seconds: Option<f64>,
        memory: Option<usize>,
    ) -> PyResult<LayerRows<'py>> {
        if !self.a.solved || self.a.layers[0].ids.is_empty() {
            return Err(bad_value(
                "the winning-forward layers need a solved, non-empty game",
            ));
        }
        let c = clock(seconds, memory, None);
        let a = &mut self.a;
        let layers = py
            .detach(|| a.winning_forward(&c))
            .map_err(|s| stopped("following winning moves", s, memory))?;
        let out = self.rows_out(py, &layers);
        self.fwd = Some(layers);
        Ok(out)
    }

    /// The strategy read off the game (see `plansynth_core::arena::Arena::consistent`)
    /// over the last winning-forward layers: `(reach layers, allowed moves per state)`,
    /// or None when it meets a state without a move that wins at every time.
    #[pyo3(signature = (width, seconds=None))]
    fn consistent<'py>(
        &mut self,
        py: Python<'py>,
        width: usize,
        seconds: Option<f64>,
    ) -> PyResult<Option<(LayerRows<'py>, Vec<StateRow>)>> {
        let fwd = self
            .fwd
            .take()
            .ok_or_else(|| bad_value("call winning_forward first"))?;
        self.start_clock(seconds);
        let a = &mut self.a;
        let got = py.detach(|| {
            let reach = a.consistent(&fwd, width)?;
            let allowed = a.allowed(&reach);
            Some((reach, allowed))
        });
        self.fwd = Some(fwd);
        self.stop_clock("reading a strategy off the game")?;
        Ok(got.map(|(reach, allowed)| (self.rows_out(py, &reach), self.states_out(allowed))))
    }

    /// The program check on the solved game (see `Arena::check_program`): None when the
    /// program (flat ops, root last) wins, else the first failing `(t, cell, config)`;
    /// out of time raises `BudgetExhausted`.
    #[pyo3(signature = (prog, width, seconds=None))]
    fn check(
        &mut self,
        py: Python<'_>,
        prog: Vec<(u8, i64, i64, i64)>,
        width: usize,
        seconds: Option<f64>,
    ) -> PyResult<Option<(usize, usize, Vec<u32>)>> {
        if !self.a.solved || width == 0 || self.a.spec.n_cells % width != 0 {
            return Err(bad_value(
                "the check needs a solved game and the grid width",
            ));
        }
        let ops = checked_ops(&prog, 2 + 2 * self.a.spec.obstacles.len())?;
        let root = ops.len() - 1;
        let c = clock(seconds, None, None);
        let a = &mut self.a;
        match py.detach(|| a.check_program(&ops, root, width, &c)) {
            Ok(None) => Ok(None),
            Ok(Some((t, r, id))) => Ok(Some((t, r, self.a.config(id).to_vec()))),
            Err(_) => Err(budget_exhausted(
                "checking programs on the game",
                "time",
                "checking programs on the game: out of time".to_string(),
            )),
        }
    }

    /// `(pairs, joint states)` of the last winning-forward layers.
    fn forward_sizes(&self) -> PyResult<(u64, u64)> {
        let fwd = self
            .fwd
            .as_ref()
            .ok_or_else(|| bad_value("call winning_forward first"))?;
        let pairs = fwd
            .iter()
            .take(self.a.spec.steps)
            .flatten()
            .map(|(_, m)| m.iter().map(|w| w.count_ones() as u64).sum::<u64>())
            .sum();
        let mut union: std::collections::HashMap<u32, Vec<u64>> = std::collections::HashMap::new();
        for (id, m) in fwd.iter().take(self.a.spec.steps).flatten() {
            let u = union.entry(*id).or_insert_with(|| vec![0; m.len()]);
            u.iter_mut().zip(m).for_each(|(a, b)| *a |= b);
        }
        let states = union
            .values()
            .map(|m| m.iter().map(|w| w.count_ones() as u64).sum::<u64>())
            .sum();
        Ok((pairs, states))
    }

    /// Allowed moves per state of `reach` (`(cell, config, move bitmask)`).
    #[pyo3(signature = (reach, seconds=None))]
    fn allowed(
        &mut self,
        py: Python<'_>,
        reach: Vec<Vec<(Vec<u32>, Bound<'_, PyBytes>)>>,
        seconds: Option<f64>,
    ) -> PyResult<Vec<StateRow>> {
        let reach = self.rows_in(&reach)?;
        self.start_clock(seconds);
        let a = &mut self.a;
        let rows = py.detach(|| a.allowed(&reach));
        self.stop_clock("the allowed moves of the strategy")?;
        Ok(self.states_out(rows))
    }

    /// States reached when every state plays any of its allowed moves.
    #[pyo3(signature = (allowed, seconds=None))]
    fn closure<'py>(
        &mut self,
        py: Python<'py>,
        allowed: Vec<StateRow>,
        seconds: Option<f64>,
    ) -> PyResult<LayerRows<'py>> {
        let mut rows = vec![];
        for (r, oc, m) in &allowed {
            if *r as usize >= self.a.spec.n_cells || oc.len() != self.a.spec.obstacles.len() {
                return Err(bad_value("a state off the grid"));
            }
            rows.push(((*r, self.a.config_id(oc)), *m));
        }
        self.start_clock(seconds);
        let a = &mut self.a;
        let out = py.detach(|| a.closure(&rows));
        self.stop_clock("the states the strategy reaches")?;
        Ok(self.rows_out(py, &out))
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyArena>()
}
