//! The PyO3 binding of bkwaves-core, imported as `bkwaves._core`.
//!
//! Thin by design: convert arrays and errors, release the GIL around long calls.
//! One file per engine area; this file registers them.

use pyo3::prelude::*;

mod chain;
mod errors;
mod free_boundary;
mod free_boundary_2d;
mod theory;
mod tip;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    chain::register(m)?;
    free_boundary::register(m)?;
    free_boundary_2d::register(m)?;
    theory::register(m)?;
    tip::register(m)?;
    Ok(())
}
