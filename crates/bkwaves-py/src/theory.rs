//! Closed forms the engines share with Python: c(u_+), u_c(gamma), the traveling wave.

use crate::errors::to_py;
use bkwaves_core::{speed, wave};
use numpy::{IntoPyArray, PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::PyDict;

type ArrayPair<'py> = (Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyArrayDyn<f64>>);

/// Apply a fallible scalar map elementwise; the first error is raised.
fn map_array<'py>(
    py: Python<'py>,
    x: PyReadonlyArrayDyn<'py, f64>,
    f: impl Fn(f64) -> bkwaves_core::Result<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let x = x.as_array();
    let mut out = x.to_owned();
    for v in out.iter_mut() {
        *v = f(*v).map_err(to_py)?;
    }
    Ok(out.into_pyarray(py))
}

/// c(u_+) = 1/sqrt(1 - u_+^2), elementwise.
#[pyfunction]
fn front_speed<'py>(
    py: Python<'py>,
    u_plus: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_array(py, u_plus, speed::front_speed)
}

/// c(u_+; dx) at gamma = 0 for the discrete chain (Wiener-Hopf closed form), elementwise.
#[pyfunction]
fn lattice_front_speed<'py>(
    py: Python<'py>,
    u_plus: PyReadonlyArrayDyn<'py, f64>,
    dx: f64,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_array(py, u_plus, |u| speed::lattice_front_speed(u, dx))
}

/// u_+(c) = sqrt(1 - 1/c^2), elementwise.
#[pyfunction]
fn u_plus_of_speed<'py>(
    py: Python<'py>,
    c: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_array(py, c, speed::u_plus_of_speed)
}

/// u_c(gamma), or None for gamma >= 1.
#[pyfunction]
fn critical_stress(gamma: f64) -> PyResult<Option<f64>> {
    speed::critical_stress(gamma).map_err(to_py)
}

/// The traveling wave for (u_plus, gamma) as a dict.
#[pyfunction]
fn traveling_wave<'py>(py: Python<'py>, u_plus: f64, gamma: f64) -> PyResult<Bound<'py, PyDict>> {
    let w = wave::TravelingWave::new(u_plus, gamma).map_err(to_py)?;
    let d = PyDict::new(py);
    d.set_item("u_plus", w.u_plus)?;
    d.set_item("gamma", w.gamma)?;
    d.set_item("c", w.c)?;
    d.set_item("regime", w.regime.as_str())?;
    d.set_item("u_c", w.u_c)?;
    d.set_item("w", w.width)?;
    d.set_item("u_minus", w.u_minus)?;
    d.set_item("A", w.amplitude)?;
    Ok(d)
}

/// The profile u(z) of the traveling wave at comoving positions z (front at z = 0),
/// with the exact c(u_+) unless a speed c is given.
#[pyfunction]
#[pyo3(signature = (u_plus, gamma, z, c=None))]
fn wave_profile<'py>(
    py: Python<'py>,
    u_plus: f64,
    gamma: f64,
    z: PyReadonlyArrayDyn<'py, f64>,
    c: Option<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let w = match c {
        Some(c) => wave::TravelingWave::with_speed(u_plus, c, gamma),
        None => wave::TravelingWave::new(u_plus, gamma),
    }
    .map_err(to_py)?;
    map_array(py, z, |z| {
        if z.is_nan() {
            Err(bkwaves_core::Error::InvalidParameter {
                name: "z",
                value: z,
                allowed: "finite or infinite positions (not NaN)",
            })
        } else {
            Ok(w.profile(z))
        }
    })
}

/// gamma-tilde = c gamma / sqrt(c^2 - 1) (App. B), elementwise over c.
#[pyfunction]
fn gamma_tilde<'py>(
    py: Python<'py>,
    c: PyReadonlyArrayDyn<'py, f64>,
    gamma: f64,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_array(py, c, |c| Ok(wave::gamma_tilde(c, gamma)))
}

/// u_- (eq. um) and w (eq. w) for given speed c, elementwise over c; NaN in creep.
#[pyfunction]
fn wave_from_speed<'py>(
    py: Python<'py>,
    u_plus: PyReadonlyArrayDyn<'py, f64>,
    c: PyReadonlyArrayDyn<'py, f64>,
    gamma: f64,
) -> PyResult<ArrayPair<'py>> {
    let u = u_plus.as_array();
    let c = c.as_array();
    if u.shape() != c.shape() {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "u_plus and c must have the same shape",
        ));
    }
    let um = ndarray_zip(&u, &c, |u, c| {
        wave::u_minus_from_speed(u, c, gamma).unwrap_or(f64::NAN)
    });
    let w = ndarray_zip(&u, &c, |_, c| {
        wave::width_from_speed(c, gamma).unwrap_or(f64::NAN)
    });
    Ok((um.into_pyarray(py), w.into_pyarray(py)))
}

fn ndarray_zip(
    a: &numpy::ndarray::ArrayViewD<'_, f64>,
    b: &numpy::ndarray::ArrayViewD<'_, f64>,
    f: impl Fn(f64, f64) -> f64,
) -> numpy::ndarray::ArrayD<f64> {
    let mut out = a.to_owned();
    for (o, (&x, &y)) in out.iter_mut().zip(a.iter().zip(b.iter())) {
        *o = f(x, y);
    }
    out
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(front_speed, m)?)?;
    m.add_function(wrap_pyfunction!(u_plus_of_speed, m)?)?;
    m.add_function(wrap_pyfunction!(lattice_front_speed, m)?)?;
    m.add_function(wrap_pyfunction!(critical_stress, m)?)?;
    m.add_function(wrap_pyfunction!(traveling_wave, m)?)?;
    m.add_function(wrap_pyfunction!(wave_profile, m)?)?;
    m.add_function(wrap_pyfunction!(wave_from_speed, m)?)?;
    m.add_function(wrap_pyfunction!(gamma_tilde, m)?)?;
    Ok(())
}
