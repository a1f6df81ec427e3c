//! Binding of `plansynth_core::product`: the product game of the robot's cells and the
//! obstacles' configurations (safety solved in the core; the learner's rounds; the
//! obstacles' rank strategy checked). A call that runs out of its seconds or memory
//! raises `plansynth.budget.BudgetExhausted` naming what it was doing.
use plansynth_core::product::{
    self as core, Limits, ObstacleMove, ObstacleSpec, ProductSpec, RobotMove, Stop,
};
use plansynth_core::tree::Node;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::conditions::{cond_op, term_rows, TermRow};
use crate::convert::{bits_of, bytes_of};
use crate::errors::{bad_value, budget_exhausted};
use crate::game::checked_ops;

fn limits(seconds: Option<f64>, max_bytes: Option<usize>) -> Limits {
    let deadline = seconds
        .map(|s| std::time::Instant::now() + std::time::Duration::from_secs_f64(s.clamp(0.0, 1e9)));
    Limits {
        deadline,
        max_bytes,
    }
}

fn stopped(phase: &str, stop: Stop) -> PyErr {
    budget_exhausted(phase, stop.resource, stop.detail)
}

type RobotRow<'py> = (Bound<'py, PyBytes>, Bound<'py, PyBytes>, i64, Vec<i64>);
type ObstacleRow<'py> = (
    usize,
    usize,
    Vec<((i64, i64), Vec<(i64, i64)>)>,
    u32,
    bool,
    u32,
    u32,
    Bound<'py, PyBytes>,
    usize,
);
type CondRow = (u8, usize, usize, u32);
type RoundOut = (
    bool,
    usize,
    usize,
    Vec<TermRow>,
    Vec<CondRow>,
    Vec<(u8, usize)>,
    [f64; 4],
);

/// The product game (see `plansynth_core::product`).
#[pyclass(name = "ProductGame")]
struct PyProductGame {
    g: core::ProductGame,
}

#[pymethods]
impl PyProductGame {
    /// Explore the configurations. `robot`: per move (valid, free, to, offsets) as cell
    /// sets and cell-index deltas; `obstacles`: per obstacle (w, h, moves as (to,
    /// offsets), period, fixed schedule, initial wait counter, glitches, blocked cells,
    /// start cell).
    #[new]
    #[pyo3(signature = (width, height, robot, obstacles, position, start, standing, seconds=None, max_bytes=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        width: usize,
        height: usize,
        robot: Vec<RobotRow<'_>>,
        obstacles: Vec<ObstacleRow<'_>>,
        position: bool,
        start: usize,
        standing: Bound<'_, PyBytes>,
        seconds: Option<f64>,
        max_bytes: Option<usize>,
    ) -> PyResult<Self> {
        let n = width * height;
        if n == 0 || start >= n || robot.is_empty() || robot.len() > 32 {
            return Err(bad_value(
                "a product game needs cells, a start on the grid and 1..32 robot moves",
            ));
        }
        let nw = n.div_ceil(64).max(1);
        let robot = robot
            .iter()
            .map(|(v, f, to, offs)| RobotMove {
                valid: bits_of(v, nw),
                free: bits_of(f, nw),
                to: *to,
                offsets: offs.clone(),
            })
            .collect();
        let mut obs = vec![];
        for (w, h, moves, period, fixed, phase0, glitches, blocked, cell) in obstacles {
            if w == 0
                || h == 0
                || period == 0
                || phase0 >= period
                || period > 255
                || glitches > 65535
                || cell >= n
            {
                return Err(bad_value("obstacle out of range"));
            }
            let moves = moves
                .into_iter()
                .map(|(to, offsets)| ObstacleMove { to, offsets })
                .collect();
            obs.push(ObstacleSpec {
                w,
                h,
                moves,
                period,
                fixed,
                phase0,
                glitches,
                blocked: bits_of(&blocked, nw),
                start: cell,
            });
        }
        let spec = ProductSpec {
            width,
            height,
            robot,
            obstacles: obs,
            position,
            start,
            standing: bits_of(&standing, nw),
        };
        let lim = limits(seconds, max_bytes);
        let g = py
            .detach(|| core::ProductGame::new(spec, lim))
            .map_err(|s| stopped("exploring the obstacles' configurations", s))?;
        Ok(Self { g })
    }

    fn n_configs(&self) -> usize {
        self.g.n_configs()
    }

    /// Configuration `id`: per obstacle (cell, wait counter, glitches left).
    fn config(&self, id: u32) -> PyResult<Vec<(usize, u32, u32)>> {
        if id as usize >= self.g.n_configs() {
            return Err(bad_value("configuration id out of range"));
        }
        Ok(self.g.config(id).iter().map(|&s| core::unpack(s)).collect())
    }

    fn successors(&self, id: u32) -> Vec<u32> {
        self.g.successors(id).to_vec()
    }

    /// Solve the safety game: true iff the robot wins from the start.
    #[pyo3(signature = (seconds=None, max_bytes=None))]
    fn solve_safety(
        &mut self,
        py: Python<'_>,
        seconds: Option<f64>,
        max_bytes: Option<usize>,
    ) -> PyResult<bool> {
        let lim = limits(seconds, max_bytes);
        let g = &mut self.g;
        py.detach(|| g.solve_safety(lim))
            .map_err(|s| stopped("the safety fixpoint", s))
    }

    fn rounds(&self) -> u32 {
        self.g.rounds
    }

    /// The winning robot cells of configuration `id`.
    fn winning<'py>(&self, py: Python<'py>, id: u32) -> Bound<'py, PyBytes> {
        let nw = self.g.nw;
        bytes_of(py, &self.g.win[id as usize * nw..(id as usize + 1) * nw])
    }

    fn allowed(&self, id: u32, r: usize) -> u32 {
        self.g.allowed(id, r)
    }

    fn rank(&self, id: u32, r: usize) -> u8 {
        self.g.rank_of(id, r)
    }

    /// Explore a program's closed loop: (states reached, states where it misplays,
    /// states new to the sample).
    #[pyo3(signature = (prog, n_vars, grow=false, seconds=None, max_bytes=None))]
    fn closure(
        &mut self,
        py: Python<'_>,
        prog: Vec<(u8, i64, i64, i64)>,
        n_vars: usize,
        grow: bool,
        seconds: Option<f64>,
        max_bytes: Option<usize>,
    ) -> PyResult<(usize, Vec<(u32, u32)>, usize)> {
        if !self.g.solved || n_vars != self.g.spec.n_vars() {
            return Err(bad_value("an unsolved game or a program over other inputs"));
        }
        let ops = checked_ops(&prog, n_vars)?;
        let lim = limits(seconds, max_bytes);
        let g = &mut self.g;
        let c = py
            .detach(|| g.closure(&ops, grow, lim))
            .map_err(|s| stopped("the program's closed loop", s))?;
        Ok((c.reached, c.bad, c.fresh))
    }

    /// The states of the last closure: (configuration id, robot cells) per configuration.
    fn reached_sets<'py>(&self, py: Python<'py>) -> Vec<(u32, Bound<'py, PyBytes>)> {
        self.g
            .reached_sets()
            .into_iter()
            .map(|(id, w)| (id, bytes_of(py, w)))
            .collect()
    }

    /// The learner's sample: (inputs, allowed moves mask) per state.
    fn sample(&self) -> Vec<(Vec<i64>, u32)> {
        self.g.sample_rows()
    }

    /// The sampled states' labels computed on cell sets (the learner's; `sample()`'s
    /// labels are their per-state reference).
    fn sample_labels(&self) -> Vec<u32> {
        self.g.sample_labels()
    }

    fn reset_sample(&mut self) {
        self.g.reset_sample()
    }

    /// Seed the learner's sample with every winning state of its (projected) game:
    /// the sample's size, or None (untouched) past `max_states` (see the core's
    /// `seed_winning`).
    fn seed_winning(&mut self, max_states: usize) -> PyResult<Option<usize>> {
        if !self.g.solved {
            return Err(bad_value("seeding the sample of an unsolved game"));
        }
        Ok(self.g.seed_winning(max_states))
    }

    /// Label the learner's states with the allowed moves that end nearest the middle
    /// of the grid only (see the core's `prefer_central`).
    fn prefer_central(&mut self, on: bool) {
        self.g.prefer_central(on)
    }

    /// The moves of `mask` from cell `r` that end nearest the middle of the grid.
    fn central_moves(&self, r: usize, mask: u32) -> u32 {
        self.g.central_moves(r, mask)
    }

    /// Learn with the glitch counters projected out (see the core's `project_glitches`).
    fn project_glitches(&mut self) {
        self.g.project_glitches()
    }

    /// One round of the learner: (closed, sample size, states reached, terms, conditions,
    /// tree nodes, seconds of its steps: labels, conditions, tree, closure). Terms `(kind, a, b, depth)`: 0 const a, 1 var a, 2 plus, 3 minus;
    /// conditions `(op, a, b, depth)`: 0 `<=`, 1 `=`, 2 not, 3 and, 4 or; nodes pre-order
    /// `(0, k)` a leaf, `(1, j)` a split on condition j. `tree_states`: on a larger
    /// sample the tree is grown on a part of about this many states, then refined on the
    /// whole (see the core's `learn_round`).
    #[pyo3(signature = (cond_depth, max_constant, max_nodes, enum_states, seconds=None, max_bytes=None, tree_states=None))]
    #[allow(clippy::too_many_arguments)]
    fn learn_round(
        &mut self,
        py: Python<'_>,
        cond_depth: u32,
        max_constant: i64,
        max_nodes: usize,
        enum_states: usize,
        seconds: Option<f64>,
        max_bytes: Option<usize>,
        tree_states: Option<usize>,
    ) -> PyResult<RoundOut> {
        if !self.g.solved {
            return Err(bad_value("learning on an unsolved game"));
        }
        let lim = limits(seconds, max_bytes);
        let g = &mut self.g;
        let r = py
            .detach(|| {
                g.learn_round(
                    cond_depth,
                    max_constant,
                    max_nodes,
                    enum_states,
                    tree_states,
                    lim,
                )
            })
            .map_err(|s| stopped("learning a program", s))?;
        let terms = term_rows(&r.terms);
        let conds = r
            .conds
            .iter()
            .map(|(c, d)| {
                let (op, a, b) = cond_op(c);
                (op, a, b, *d)
            })
            .collect();
        let nodes = r.nodes.iter().map(|n| match *n {
            Node::Leaf(k) => (0u8, k),
            Node::Split(j) => (1u8, j),
        });
        Ok((
            r.closed,
            r.sample,
            r.reached,
            terms,
            conds,
            nodes.collect(),
            r.seconds,
        ))
    }

    /// Check the obstacles' rank strategy from the start: (valid, states checked, why not).
    #[pyo3(signature = (seconds=None, max_bytes=None))]
    fn certify_safety(
        &self,
        py: Python<'_>,
        seconds: Option<f64>,
        max_bytes: Option<usize>,
    ) -> PyResult<(bool, usize, String)> {
        let lim = limits(seconds, max_bytes);
        let g = &self.g;
        let out = py
            .detach(|| g.certify_safety(lim))
            .map_err(|s| stopped("checking the obstacles' strategy", s))?;
        Ok(match out {
            Ok(n) => (true, n, String::new()),
            Err(why) => (false, 0, why),
        })
    }

    fn bytes(&self) -> usize {
        self.g.bytes()
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyProductGame>()
}
