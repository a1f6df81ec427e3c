//! plansynth-core: the compiled hot loops of plansynth.
//!
//! This crate knows nothing of Python (rustworkx-core's rule): plain data in, plain
//! data out. The PyO3 binding lives in `plansynth-py`.

pub mod arena;
pub mod bits;
pub mod conditions;
pub mod fx;
pub mod game;
pub mod inductive;
pub mod par;
pub mod product;
pub mod program_tree;
pub mod tree;
pub mod tree_rows;

/// Version of the core, reported in results so a run can be traced to its build.
pub fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

#[cfg(test)]
mod tests {
    #[test]
    fn version_is_set() {
        assert!(!super::version().is_empty());
    }
}
