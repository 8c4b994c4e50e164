//! The free boundary engine (paper Sec. IV) exposed to Python as `FreeBoundaryEngine`.
//! The Python class `bkwaves.FreeBoundary` drives it in chunks (progress, Ctrl-C).

use crate::errors::to_py;
use bkwaves_core::free_boundary::{Boundary, CreepRule, FreeBoundary, Options, SpeedLaw, Stop};
use bkwaves_core::noise::NoiseLaw;
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The free boundary (shock dynamics) engine of Sec. IV, advanced event by event.
///
/// The engine behind ``bkwaves.FreeBoundary``, which validates its inputs and turns the
/// records into pandas and xarray objects; use that class. Its arguments: the grid's
/// first node ``x0`` and spacing ``h`` (dimensionless x), ``u0`` on the grid, ``gamma``
/// and ``v`` (dimensionless), then the options of ``bkwaves.FreeBoundary``.
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> eng = _core.FreeBoundaryEngine(0.0, 0.5, np.full(9, 0.6), 0.3, 0.01)
/// >>> eng.time, eng.n_shocks
/// (0.0, 0)
#[pyclass(name = "FreeBoundaryEngine", module = "bkwaves._core")]
pub struct PyFreeBoundary {
    inner: FreeBoundary,
}

#[pymethods]
impl PyFreeBoundary {
    #[new]
    #[pyo3(signature = (x0, h, u0, gamma, v, boundary="free", creep="zero",
                        shock_x=None, shock_dir=None, tol=1e-12, record_path=true,
                        speed_u=None, speed_c=None, threshold=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        x0: f64,
        h: f64,
        u0: PyReadonlyArray1<'_, f64>,
        gamma: f64,
        v: f64,
        boundary: &str,
        creep: &str,
        shock_x: Option<PyReadonlyArray1<'_, f64>>,
        shock_dir: Option<PyReadonlyArray1<'_, i64>>,
        tol: f64,
        record_path: bool,
        speed_u: Option<PyReadonlyArray1<'_, f64>>,
        speed_c: Option<PyReadonlyArray1<'_, f64>>,
        threshold: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        let opts = Options {
            gamma,
            v,
            boundary: Boundary::parse(boundary).map_err(to_py)?,
            creep: CreepRule::parse(creep).map_err(to_py)?,
            tol,
            record_path,
        };
        let mut initial = Vec::new();
        if let (Some(xs), Some(ds)) = (shock_x, shock_dir) {
            let (xs, ds) = (xs.as_array(), ds.as_array());
            if xs.len() != ds.len() {
                return Err(pyo3::exceptions::PyValueError::new_err(
                    "shock_x and shock_dir must have the same length",
                ));
            }
            for (x, d) in xs.iter().zip(ds.iter()) {
                let d = i8::try_from(*d).unwrap_or(0);
                initial.push((*x, d));
            }
        }
        let u0 = u0.as_array().to_vec();
        // a front-speed table (u_+, c), else the exact law
        let law = match (speed_u, speed_c) {
            (Some(u), Some(c)) => {
                SpeedLaw::table(&u.as_array().to_vec(), &c.as_array().to_vec()).map_err(to_py)?
            }
            _ => SpeedLaw::Exact,
        };
        let threshold = threshold.map(|t| t.as_array().to_vec());
        let inner =
            FreeBoundary::with_medium(x0, h, &u0, opts, &initial, law, threshold.as_deref())
                .map_err(to_py)?;
        Ok(PyFreeBoundary { inner })
    }

    /// Advance to t_stop at most, with at most max_steps engine events in this call,
    /// stopping once max_events events are complete. Returns "time", "steps" or "events".
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

    /// Bound the wall time of one `advance` call (seconds; inf: no bound): it returns
    /// "steps" once that much time has passed, so interrupts are answered promptly.
    fn set_chunk_wall(&mut self, seconds: f64) {
        self.inner.set_chunk_wall(seconds);
    }

    /// Spontaneous pair nucleation at Lambda(u) = rate g(u) (law "constant",
    /// "exponential" with phi0, "power" with exponent, "table" with nodes u and values g),
    /// seeded; from now on. A zero rate is no noise.
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
        self.inner.set_noise(law, seed).map_err(to_py)?;
        Ok(())
    }

    /// (candidates drawn, pairs nucleated) by the noise so far; None without noise.
    #[getter]
    fn noise_counters(&self) -> Option<(u64, u64)> {
        self.inner.noise_counters()
    }

    /// The whole state as bytes (restored bit for bit by `restore`).
    fn checkpoint<'py>(&self, py: Python<'py>) -> Bound<'py, pyo3::types::PyBytes> {
        pyo3::types::PyBytes::new(py, &self.inner.checkpoint())
    }

    /// Restore a state written by `checkpoint` of an engine with the same configuration
    /// (grid, boundary, gamma, v, creep rule, tol, record_path).
    fn restore(&mut self, data: &[u8]) -> PyResult<()> {
        self.inner.restore(data).map_err(to_py)
    }

    /// The critical stress u_c of the front-speed law: c(u_c) = 1/sqrt(1 - gamma^2).
    #[getter]
    fn critical_stress(&self) -> f64 {
        self.inner.critical_stress()
    }

    /// The front speed c(u_+) of the engine's law, for each u_+ (0 < u_+ < 1).
    fn front_speed<'py>(
        &self,
        py: Python<'py>,
        u_plus: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let law = self.inner.law();
        let c = u_plus
            .as_array()
            .iter()
            .map(|&u| law.speed(u))
            .collect::<Result<Vec<f64>, _>>()
            .map_err(to_py)?;
        Ok(c.into_pyarray(py))
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
    fn completed_events(&self) -> usize {
        self.inner.completed_events()
    }

    #[getter]
    fn n_shocks(&self) -> usize {
        self.inner.shocks().len()
    }

    /// u at the grid nodes at the current time.
    fn u_nodes<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.inner.u_nodes().into_pyarray(py)
    }

    /// Live shocks at the current time: dict of arrays id, event, x, dir, u_plus.
    fn shocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.inner.shocks();
        let d = PyDict::new(py);
        d.set_item(
            "id",
            s.iter()
                .map(|q| q.id as i64)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        d.set_item(
            "event",
            s.iter()
                .map(|q| q.event as i64)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        d.set_item(
            "x",
            s.iter().map(|q| q.x).collect::<Vec<_>>().into_pyarray(py),
        )?;
        d.set_item(
            "dir",
            s.iter()
                .map(|q| i64::from(q.dir))
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        d.set_item(
            "u_plus",
            s.iter()
                .map(|q| q.u_plus)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        Ok(d)
    }

    /// The event catalog (rows from `start` on) as a dict of arrays.
    #[pyo3(signature = (start=0))]
    fn events<'py>(&self, py: Python<'py>, start: usize) -> PyResult<Bound<'py, PyDict>> {
        let all = self.inner.events();
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
        col!("x_start", |q| q.x_start);
        col!("curvature", |q| q.curvature);
        col!("x_min", |q| q.x_min);
        col!("x_max", |q| q.x_max);
        col!("moment", |q| q.moment);
        col!("swept", |q| q.swept);
        col!("stress_drop", |q| q.stress_drop());
        col!("n_births", |q| q.n_births as i64);
        col!("n_nucleations", |q| q.n_nucleations as i64);
        col!("spontaneous", |q| q.spontaneous);
        col!("n_shocks", |q| q.n_shocks as i64);
        col!("n_annihilations", |q| q.n_annihilations as i64);
        col!("n_exits", |q| q.n_exits as i64);
        col!("n_deaths", |q| q.n_deaths as i64);
        col!("n_creep", |q| q.n_creep as i64);
        Ok(d)
    }

    /// Recorded shock path points from row `start` on, as a dict of arrays (kind as a
    /// list of str).
    #[pyo3(signature = (start=0))]
    fn path<'py>(&self, py: Python<'py>, start: usize) -> PyResult<Bound<'py, PyDict>> {
        let all = self.inner.path();
        let p = &all[start.min(all.len())..];
        let d = PyDict::new(py);
        macro_rules! col {
            ($name:expr, $f:expr) => {
                d.set_item($name, p.iter().map($f).collect::<Vec<_>>().into_pyarray(py))?;
            };
        }
        col!("shock", |q| q.shock as i64);
        col!("event", |q| q.event as i64);
        col!("t", |q| q.t);
        col!("x", |q| q.x);
        col!("dir", |q| i64::from(q.dir));
        col!("u_plus", |q| q.u_plus);
        col!("u_minus", |q| q.u_minus);
        col!("creep", |q| q.creep);
        d.set_item(
            "kind",
            p.iter().map(|q| q.kind.as_str()).collect::<Vec<_>>(),
        )?;
        Ok(d)
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyFreeBoundary>()?;
    Ok(())
}
