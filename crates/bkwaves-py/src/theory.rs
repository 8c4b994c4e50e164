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

/// The front speed c(u_+) = 1/sqrt(1 - u_+^2) of the continuum limit, elementwise.
///
/// The exact solution of the paper's tip problem (App. A); ``bkwaves.front_speed`` is the
/// validated Python entry point.
///
/// Parameters
/// ----------
/// u_plus : numpy.ndarray of float
///     Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
///
/// Returns
/// -------
/// numpy.ndarray of float
///     c, in units of the sound speed a sqrt(k_c/m), of the shape of u_plus.
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> _core.front_speed(np.array([0.6]))
/// array([1.25])
#[pyfunction]
fn front_speed<'py>(
    py: Python<'py>,
    u_plus: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_array(py, u_plus, speed::front_speed)
}

/// The discrete chain's front speed at gamma = 0 (Wiener-Hopf closed form), elementwise.
///
/// c = dx / (2 u_+ asin(dx sqrt(1 - u_+^2) / (2 u_+))), for pulses wide in lattice units
/// (``bkwaves.front_speed(u, dx=dx)`` checks that domain).
///
/// Parameters
/// ----------
/// u_plus : numpy.ndarray of float
///     Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
/// dx : float
///     Lattice spacing sqrt(k_p/k_c) (dimensionless), with dx sqrt(1 - u_+^2) <= 2 u_+.
///
/// Returns
/// -------
/// numpy.ndarray of float
///     c, in units of the sound speed a sqrt(k_c/m).
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> _core.lattice_front_speed(np.array([0.6]), 0.1)
/// array([1.24907291])
#[pyfunction]
fn lattice_front_speed<'py>(
    py: Python<'py>,
    u_plus: PyReadonlyArrayDyn<'py, f64>,
    dx: f64,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_array(py, u_plus, |u| speed::lattice_front_speed(u, dx))
}

/// The stress ahead of a front of speed c, u_+(c) = sqrt(1 - 1/c^2), elementwise.
///
/// Parameters
/// ----------
/// c : numpy.ndarray of float
///     Front speed (> 1, units of the sound speed).
///
/// Returns
/// -------
/// numpy.ndarray of float
///     u_+ in (0, 1).
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> _core.u_plus_of_speed(np.array([1.25]))
/// array([0.6])
#[pyfunction]
fn u_plus_of_speed<'py>(
    py: Python<'py>,
    c: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_array(py, c, speed::u_plus_of_speed)
}

/// The critical stress u_c(gamma) of eq. (gammac): pulses for u_+ > u_c, creep below.
///
/// With the exact speed, u_c = gamma.
///
/// Parameters
/// ----------
/// gamma : float
///     Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
///
/// Returns
/// -------
/// float or None
///     u_c, or None for gamma >= 1 (every wave creeps).
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> _core.critical_stress(0.3)
/// 0.3
#[pyfunction]
fn critical_stress(gamma: f64) -> PyResult<Option<f64>> {
    speed::critical_stress(gamma).map_err(to_py)
}

/// The traveling wave behind a front (App. B) as a dict.
///
/// ``bkwaves.traveling_wave`` wraps it in a ``TravelingWave``.
///
/// Parameters
/// ----------
/// u_plus : float
///     Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
/// gamma : float
///     Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
///
/// Returns
/// -------
/// dict
///     ``u_plus``, ``gamma``, ``c``, ``regime`` ("pulse" or "creep"), ``u_c``, ``w``
///     (width), ``u_minus`` and ``A`` (total slip); the last three None in creep.
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> w = _core.traveling_wave(0.6, 0.3)
/// >>> w["regime"], round(w["u_minus"], 6)
/// ('pulse', -0.09782)
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

/// The profile u(z) of the traveling wave (App. B) at comoving positions z = x - c t.
///
/// Parameters
/// ----------
/// u_plus : float
///     Stress ahead of the front, 0 < u_plus < 1 (dimensionless).
/// gamma : float
///     Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
/// z : numpy.ndarray of float
///     Positions relative to the front (dimensionless, the paper's x; z > 0 ahead;
///     not NaN).
/// c : float, optional
///     The front speed in units of the sound speed (default: the exact c(u_+)).
///
/// Returns
/// -------
/// numpy.ndarray of float
///     u(z), of the shape of z.
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> _core.wave_profile(0.6, 0.3, np.array([0.0, -1.0]))
/// array([0.6       , 0.28718902])
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

/// The effective damping gamma-tilde = c gamma / sqrt(c^2 - 1) of App. B, elementwise in c.
///
/// Below 1 the wave is a pulse, at 1 or above it creeps.
///
/// Parameters
/// ----------
/// c : numpy.ndarray of float
///     Front speed (> 1, units of the sound speed).
/// gamma : float
///     Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
///
/// Returns
/// -------
/// numpy.ndarray of float
///     gamma-tilde (dimensionless).
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> _core.gamma_tilde(np.array([1.25]), 0.3)
/// array([0.5])
#[pyfunction]
fn gamma_tilde<'py>(
    py: Python<'py>,
    c: PyReadonlyArrayDyn<'py, f64>,
    gamma: f64,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map_array(py, c, |c| Ok(wave::gamma_tilde(c, gamma)))
}

/// The stress behind a pulse u_- (eq. um) and its width w (eq. w) for given speeds.
///
/// Parameters
/// ----------
/// u_plus : numpy.ndarray of float
///     Stress ahead of the front (dimensionless).
/// c : numpy.ndarray of float
///     Front speed in units of the sound speed, of the shape of u_plus (exact,
///     interpolated or measured).
/// gamma : float
///     Viscous damping alpha/(2 sqrt(k_p m)), >= 0 (dimensionless).
///
/// Returns
/// -------
/// u_minus : numpy.ndarray of float
///     Stress left behind (dimensionless); NaN in creep.
/// w : numpy.ndarray of float
///     Pulse width in units of a sqrt(k_c/k_p); NaN in creep.
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> _core.wave_from_speed(np.array([0.6]), np.array([1.25]), 0.3)
/// (array([-0.09782012]), array([2.72069905]))
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
