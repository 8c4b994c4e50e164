//! Core errors mapped to named Python exceptions.

use bkwaves_core::Error;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    bkwaves._core,
    ParameterError,
    PyValueError,
    "A parameter is out of its allowed range or not finite."
);
create_exception!(
    bkwaves._core,
    ConvergenceError,
    PyRuntimeError,
    "A numerical method did not reach its tolerance."
);

/// Convert a core error into the matching Python exception.
pub fn to_py(e: Error) -> PyErr {
    match e {
        Error::InvalidParameter { .. } | Error::Invalid { .. } => {
            ParameterError::new_err(e.to_string())
        }
        Error::NoConvergence { .. } => ConvergenceError::new_err(e.to_string()),
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ParameterError", m.py().get_type::<ParameterError>())?;
    m.add("ConvergenceError", m.py().get_type::<ConvergenceError>())?;
    Ok(())
}
