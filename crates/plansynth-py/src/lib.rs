//! PyO3 binding of `plansynth-core`: conversions and exceptions only, one module per
//! core module (`conditions`, `tree`, `game`, `arena`, `product`, `inductive`). Running out of a budget raises
//! `plansynth.budget.BudgetExhausted`, the one exception of every budget in plansynth.
use pyo3::prelude::*;

mod arena;
mod conditions;
mod convert;
mod errors;
mod game;
mod inductive;
mod product;
mod tree;

/// The version of the compiled core.
#[pyfunction]
fn core_version() -> &'static str {
    plansynth_core::version()
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(core_version, m)?)?;
    conditions::register(m)?;
    tree::register(m)?;
    game::register(m)?;
    arena::register(m)?;
    product::register(m)?;
    inductive::register(m)?;
    Ok(())
}
