//! The exceptions the binding raises: a budget that runs out is the Python class
//! `plansynth.budget.BudgetExhausted(phase, resource, detail)`, so that
//! `except BudgetExhausted` catches what the core stops with.
use pyo3::prelude::*;

pyo3::import_exception!(plansynth.budget, BudgetExhausted);

/// `BudgetExhausted(phase, resource, detail)`: the budget ran out in `phase`;
/// `resource` is what ran out ("time", "memory", "configurations").
pub fn budget_exhausted(phase: &str, resource: &str, detail: String) -> PyErr {
    BudgetExhausted::new_err((phase.to_string(), resource.to_string(), detail))
}

/// A `ValueError` saying what is wrong with the arguments.
pub fn bad_value(message: &str) -> PyErr {
    pyo3::exceptions::PyValueError::new_err(message.to_string())
}
