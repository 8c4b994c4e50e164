//! The two-dimensional free boundary engine exposed to Python as `FreeBoundary2DEngine`.
//! The Python class `bkwaves.FreeBoundary2D` drives it in chunks (progress, Ctrl-C).

use crate::errors::to_py;
use bkwaves_core::free_boundary::{Boundary, CreepRule, SpeedLaw, Stop};
use bkwaves_core::free_boundary_2d::{FreeBoundary2D, Grid, Options2D};
use bkwaves_core::noise::NoiseLaw;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Swept nodes and their arrival times, as numpy arrays.
type Arrivals<'py> = (
    Bound<'py, numpy::PyArray1<i64>>,
    Bound<'py, numpy::PyArray1<f64>>,
);

/// The two-dimensional free boundary engine: fronts by fast marching (Sec. IV in the plane).
///
/// The engine behind ``bkwaves.FreeBoundary2D``, which validates its inputs and turns
/// the records into pandas and xarray objects; use that class. Its arguments: ``nx``,
/// ``ny`` nodes of spacing ``h`` from (``x0``, ``y0``) (dimensionless x), ``u0`` (nx ny
/// dimensionless stresses, row after row), ``gamma`` and ``v`` (dimensionless), then the
/// options of ``bkwaves.FreeBoundary2D``.
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> eng = _core.FreeBoundary2DEngine(4, 3, 1.0, 0.0, 0.0, np.full(12, 0.6), 0.3, 0.01)
/// >>> eng.time, len(eng.u_nodes())
/// (0.0, 12)
#[pyclass(name = "FreeBoundary2DEngine", module = "bkwaves._core")]
pub struct PyFreeBoundary2D {
    inner: FreeBoundary2D,
}

#[pymethods]
impl PyFreeBoundary2D {
    #[new]
    #[pyo3(signature = (nx, ny, h, x0, y0, u0, gamma, v, boundary_x="periodic",
                        boundary_y="periodic", creep="zero", second_order=true,
                        record_arrivals=false, speed_u=None, speed_c=None, threshold=None,
                        curvature=None, diagonal_u=None, diagonal_c=None,
                        curvature_theta=None, curvature_d=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        nx: usize,
        ny: usize,
        h: f64,
        x0: f64,
        y0: f64,
        u0: PyReadonlyArray1<'_, f64>,
        gamma: f64,
        v: f64,
        boundary_x: &str,
        boundary_y: &str,
        creep: &str,
        second_order: bool,
        record_arrivals: bool,
        speed_u: Option<PyReadonlyArray1<'_, f64>>,
        speed_c: Option<PyReadonlyArray1<'_, f64>>,
        threshold: Option<PyReadonlyArray1<'_, f64>>,
        curvature: Option<(f64, f64)>,
        diagonal_u: Option<PyReadonlyArray1<'_, f64>>,
        diagonal_c: Option<PyReadonlyArray1<'_, f64>>,
        curvature_theta: Option<PyReadonlyArray1<'_, f64>>,
        curvature_d: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        let bx = Boundary::parse(boundary_x).map_err(to_py)?;
        let by = Boundary::parse(boundary_y).map_err(to_py)?;
        let grid = Grid::new(nx, ny, h, (x0, y0), (bx, by)).map_err(to_py)?;
        let opts = Options2D {
            gamma,
            v,
            creep: CreepRule::parse(creep).map_err(to_py)?,
            second_order,
            record_arrivals,
            curvature,
        };
        let law = match (speed_u, speed_c) {
            (Some(u), Some(c)) => {
                SpeedLaw::table(&u.as_array().to_vec(), &c.as_array().to_vec()).map_err(to_py)?
            }
            _ => SpeedLaw::Exact,
        };
        let u0 = u0.as_array().to_vec();
        let threshold = threshold.map(|t| t.as_array().to_vec());
        let mut inner =
            FreeBoundary2D::new(grid, &u0, opts, law, threshold.as_deref()).map_err(to_py)?;
        if let (Some(u), Some(c)) = (diagonal_u, diagonal_c) {
            let law =
                SpeedLaw::table(&u.as_array().to_vec(), &c.as_array().to_vec()).map_err(to_py)?;
            inner.set_diagonal_law(law).map_err(to_py)?;
        }
        if let (Some(t), Some(d)) = (curvature_theta, curvature_d) {
            inner
                .set_curvature_directions(t.as_slice()?, d.as_slice()?)
                .map_err(to_py)?;
        }
        Ok(PyFreeBoundary2D { inner })
    }

    /// The curvature coefficient D at the normal of angle theta (radians) to the x axis,
    /// as the engine interpolates it, or None without the curvature option.
    fn curvature_at(&self, theta: f64) -> Option<f64> {
        self.inner.curvature_at_angle(theta)
    }

    /// Advance to t_stop at most, with at most max_steps engine events in this call,
    /// stopping once max_events ruptures are complete. Returns "time", "steps" or "events".
    fn advance(
        &mut self,
        py: Python<'_>,
        t_stop: f64,
        max_steps: u64,
        max_events: usize,
    ) -> PyResult<&'static str> {
        let inner = &mut self.inner;
        let r = py
            .detach(|| inner.advance(t_stop, max_steps, max_events))
            .map_err(to_py)?;
        Ok(match r {
            Stop::Time => "time",
            Stop::Steps => "steps",
            Stop::Events => "events",
        })
    }

    /// Nucleation by noise at Lambda(u) = rate g(u) per unit area (the 1D engine's laws).
    #[pyo3(signature = (law, rate, seed, phi0=f64::NAN, exponent=f64::NAN, u=Vec::new(), g=Vec::new()))]
    #[allow(clippy::too_many_arguments)]
    fn set_noise(
        &mut self,
        law: &str,
        rate: f64,
        seed: u64,
        phi0: f64,
        exponent: f64,
        u: Vec<f64>,
        g: Vec<f64>,
    ) -> PyResult<()> {
        let law = NoiseLaw::with_table(law, rate, phi0, exponent, &u, &g).map_err(to_py)?;
        self.inner.set_noise(law, seed).map_err(to_py)
    }

    /// (candidates drawn, ruptures nucleated) by the noise; None without noise.
    #[getter]
    fn noise_counters(&self) -> Option<(u64, u64)> {
        self.inner.noise_counters()
    }

    /// Start a rupture whose nodes (flat indices j nx + i) are reached at the given times.
    fn trigger(
        &mut self,
        nodes: PyReadonlyArray1<'_, i64>,
        times: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<usize> {
        let (n, t) = (nodes.as_array(), times.as_array());
        if n.len() != t.len() {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "nodes and times must have the same length",
            ));
        }
        let seeds: Vec<(usize, f64)> = n
            .iter()
            .zip(t.iter())
            .map(|(&k, &t)| (usize::try_from(k).unwrap_or(usize::MAX), t))
            .collect();
        self.inner.trigger(&seeds).map_err(to_py)
    }

    /// Start a rupture now on the disk of the given radius around (x, y).
    fn trigger_disk(&mut self, x: f64, y: f64, radius: f64) -> PyResult<usize> {
        self.inner.trigger_disk(x, y, radius).map_err(to_py)
    }

    /// The whole state as bytes (restored bit for bit by `restore`).
    fn checkpoint<'py>(&self, py: Python<'py>) -> Bound<'py, pyo3::types::PyBytes> {
        pyo3::types::PyBytes::new(py, &self.inner.checkpoint())
    }

    /// Restore a state written by `checkpoint` of an engine with the same configuration.
    fn restore(&mut self, data: &[u8]) -> PyResult<()> {
        self.inner.restore(data).map_err(to_py)
    }

    /// The critical stress u_c of the front-speed law.
    #[getter]
    fn critical_stress(&self) -> f64 {
        self.inner.critical_stress()
    }

    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }

    #[getter]
    fn steps(&self) -> u64 {
        self.inner.steps()
    }

    #[getter]
    fn completed(&self) -> usize {
        self.inner.completed()
    }

    #[getter]
    fn live(&self) -> usize {
        self.inner.live()
    }

    /// u at the nodes now (flat, row by row).
    fn u_nodes<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.inner.u_nodes().into_pyarray(py)
    }

    /// The last arrival time at each node (NaN where no front has passed).
    fn last_arrival<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.inner.last_arrival().to_vec().into_pyarray(py)
    }

    /// The swept nodes (flat indices) of rupture `id` and their arrival times (recorded
    /// arrivals and a complete rupture only; else empty).
    fn arrivals<'py>(&self, py: Python<'py>, id: usize) -> PyResult<Arrivals<'py>> {
        let r =
            self.inner.ruptures().get(id).ok_or_else(|| {
                pyo3::exceptions::PyIndexError::new_err(format!("no rupture {id}"))
            })?;
        let (n, t) = r.arrivals();
        Ok((
            n.iter()
                .map(|&k| i64::from(k))
                .collect::<Vec<_>>()
                .into_pyarray(py),
            t.to_vec().into_pyarray(py),
        ))
    }

    /// The rupture catalog (rows from `start` on) as a dict of arrays.
    #[pyo3(signature = (start=0))]
    fn ruptures<'py>(&self, py: Python<'py>, start: usize) -> PyResult<Bound<'py, PyDict>> {
        let all = self.inner.ruptures();
        let e = &all[start.min(all.len())..];
        let d = PyDict::new(py);
        macro_rules! col {
            ($name:expr, $f:expr) => {
                d.set_item($name, e.iter().map($f).collect::<Vec<_>>().into_pyarray(py))?;
            };
        }
        col!("id", |q| q.id as i64);
        col!("t_start", |q| q.t_start);
        col!("t_end", |q| q.t_end);
        col!("duration", |q| q.duration());
        col!("x_start", |q| q.x_start);
        col!("y_start", |q| q.y_start);
        col!("u_start", |q| q.u_start);
        col!("n_nodes", |q| q.n_nodes as i64);
        col!("area", |q| q.area);
        col!("moment", |q| q.moment);
        col!("mean_slip", |q| q.mean_slip());
        col!("perimeter", |q| q.perimeter);
        col!("n_stopped", |q| q.n_stopped as i64);
        col!("n_creep", |q| q.n_creep as i64);
        col!("contacts", |q| q.contacts as i64);
        col!("complete", |q| q.complete);
        d.set_item(
            "origin",
            e.iter().map(|q| q.origin.as_str()).collect::<Vec<_>>(),
        )?;
        Ok(d)
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyFreeBoundary2D>()?;
    Ok(())
}
