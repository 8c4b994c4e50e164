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

/// Solve the tip problem (App. A) for a given front speed c.
///
/// ``bkwaves.tip_solve(c=...)`` is the validated Python entry point.
///
/// Parameters
/// ----------
/// c : float
///     Front speed, > 1 (units of the sound speed).
/// degree : int, default 16
///     Polynomial degree per interval between slips.
/// decay : float, default 40
///     e-folds of the slowest transient kept behind the tip.
/// dx : float, default 0
///     Lattice spacing sqrt(k_p/k_c) (dimensionless); 0 is the continuum limit.
/// gamma : float, default 0
///     Viscous damping alpha/(2 sqrt(k_p m)) (dimensionless; enters at dx > 0).
/// chain_domain : bool, default True
///     At dx > 0, refuse a front that is not the chain's (a narrow pulse); False solves the
///     linear tip problem as stated.
///
/// Returns
/// -------
/// dict
///     ``c``, ``theta`` = (1 - u_+)/u_+, ``u_plus``, ``intervals`` kept behind the tip,
///     ``decay_rate`` of the slowest transient and ``tip_velocity``.
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> round(_core.tip_solve_speed(1.25)["u_plus"], 10)
/// 0.6
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

/// Solve the tip problem (App. A) for the front speed at stress u_plus ahead.
///
/// ``bkwaves.tip_solve(u_plus)`` is the validated Python entry point.
///
/// Parameters
/// ----------
/// u_plus : float
///     Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
/// degree : int, default 16
///     Polynomial degree per interval between slips.
/// decay : float, default 40
///     e-folds of the slowest transient kept behind the tip.
/// dx : float, default 0
///     Lattice spacing sqrt(k_p/k_c) (dimensionless); 0 is the continuum limit.
/// gamma : float, default 0
///     Viscous damping alpha/(2 sqrt(k_p m)) (dimensionless; enters at dx > 0).
/// chain_domain : bool, default True
///     At dx > 0, refuse a front that is not the chain's (a narrow pulse); False solves the
///     linear tip problem as stated.
///
/// Returns
/// -------
/// dict
///     ``c``, ``theta`` = (1 - u_+)/u_+, ``u_plus``, ``intervals`` kept behind the tip,
///     ``decay_rate`` of the slowest transient and ``tip_velocity``.
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> round(_core.tip_solve_u_plus(0.6)["c"], 10)
/// 1.25
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

/// March a front through blocks with static thresholds ``threshold`` (v = 0, Coulomb).
///
/// ``bkwaves.disorder.tip_march`` is the validated Python entry point.
///
/// Parameters
/// ----------
/// u_plus : float
///     Stress ahead of the front (dimensionless).
/// threshold : numpy.ndarray of float
///     Static threshold of every block (1: the paper's chain).
/// dx : float
///     Lattice spacing sqrt(k_p/k_c) (dimensionless).
/// gamma : float
///     Viscous damping alpha/(2 sqrt(k_p m)) (dimensionless).
/// behind : int, default 64
///     Blocks kept behind the tip (at least).
/// step : float, default 0.5
///     Time step as a fraction of dx (in units of dx sqrt(m/k_p)).
/// order : int, default 20
///     Degree of the Taylor series per step.
///
/// Returns
/// -------
/// dict
///     ``slip_times`` (first slip time of every block, in units of sqrt(m/k_p)),
///     ``stopped`` (the front died), and the counters ``steps``, ``events``,
///     ``max_window``.
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> r = _core.tip_march(0.6, np.ones(50), 0.1, 0.3)
/// >>> r["stopped"], len(r["slip_times"])
/// (False, 50)
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
