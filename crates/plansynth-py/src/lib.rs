//! PyO3 binding of `plansynth-core`. Only conversions live here.
use pyo3::prelude::*;

#[pyfunction]
fn core_version() -> &'static str {
    plansynth_core::version()
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(core_version, m)?)?;
    Ok(())
}
