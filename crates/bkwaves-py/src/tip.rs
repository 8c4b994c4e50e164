//! The tip solver (paper App. A) exposed to Python.

use crate::errors::to_py;
use bkwaves_core::tip::{self, TipOptions, TipSolution};
use bkwaves_core::tip_march::{march, MarchOptions};
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

fn options(degree: usize, decay: f64, dx: f64, gamma: f64) -> TipOptions {
    TipOptions {
        degree,
        decay,
        dx,
        gamma,
        ..Default::default()
    }
}

fn to_dict<'py>(py: Python<'py>, s: &TipSolution) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("c", s.c)?;
    d.set_item("theta", s.theta)?;
    d.set_item("u_plus", s.u_plus)?;
    d.set_item("intervals", s.intervals)?;
    d.set_item("decay_rate", s.decay_rate)?;
    d.set_item("tip_velocity", s.tip_velocity)?;
    Ok(d)
}

/// Solve the tip problem for a given front speed c (chain_domain: refuse, at dx > 0, a
/// front that is not the chain's; false: the linear tip problem as stated).
#[pyfunction]
#[pyo3(signature = (c, degree=16, decay=40.0, dx=0.0, gamma=0.0, chain_domain=true))]
fn tip_solve_speed<'py>(
    py: Python<'py>,
    c: f64,
    degree: usize,
    decay: f64,
    dx: f64,
    gamma: f64,
    chain_domain: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let o = options(degree, decay, dx, gamma);
    let solve = if chain_domain {
        tip::solve_for_speed
    } else {
        tip::solve_linear_for_speed
    };
    let s = py.detach(|| solve(c, &o)).map_err(to_py)?;
    to_dict(py, &s)
}

/// Solve the tip problem for the front speed at stress u_plus ahead (chain_domain as in
/// `tip_solve_speed`).
#[pyfunction]
#[pyo3(signature = (u_plus, degree=16, decay=40.0, dx=0.0, gamma=0.0, chain_domain=true))]
fn tip_solve_u_plus<'py>(
    py: Python<'py>,
    u_plus: f64,
    degree: usize,
    decay: f64,
    dx: f64,
    gamma: f64,
    chain_domain: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let o = options(degree, decay, dx, gamma);
    let solve = if chain_domain {
        tip::solve_for_u_plus
    } else {
        tip::solve_linear_for_u_plus
    };
    let s = py.detach(|| solve(u_plus, &o)).map_err(to_py)?;
    to_dict(py, &s)
}

/// March a front through blocks with thresholds `threshold` (bkwaves_core::tip_march):
/// the first slip time of every block and the march's counters.
#[pyfunction]
#[pyo3(signature = (u_plus, threshold, dx, gamma, behind=64, step=0.5, order=20))]
#[allow(clippy::too_many_arguments)]
fn tip_march<'py>(
    py: Python<'py>,
    u_plus: f64,
    threshold: PyReadonlyArray1<'py, f64>,
    dx: f64,
    gamma: f64,
    behind: usize,
    step: f64,
    order: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let th = threshold.as_slice()?.to_vec();
    let o = MarchOptions {
        dx,
        gamma,
        behind,
        step,
        order,
    };
    let r = py.detach(|| march(u_plus, &th, &o)).map_err(to_py)?;
    let d = PyDict::new(py);
    d.set_item("slip_times", r.slip_times.into_pyarray(py))?;
    d.set_item("stopped", r.stopped)?;
    d.set_item("steps", r.steps)?;
    d.set_item("events", r.events)?;
    d.set_item("max_window", r.max_window)?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(tip_march, m)?)?;
    m.add_function(wrap_pyfunction!(tip_solve_speed, m)?)?;
    m.add_function(wrap_pyfunction!(tip_solve_u_plus, m)?)?;
    Ok(())
}
