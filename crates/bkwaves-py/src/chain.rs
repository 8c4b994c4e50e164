//! The chain simulator exposed to Python: `ChainEngine` (state kept in Rust, advanced in
//! chunks with the GIL released), `front_measure` (the `bkwaves front` experiment) and the
//! core's registries (friction laws with their parameter tables, boundaries, integrators,
//! triggers) and defaults, so that Python never repeats them.

use crate::errors::to_py;
use bkwaves_core::boundary;
use bkwaves_core::chain::dynamic::{build, ChainSpec, DynChain, Plane};
use bkwaves_core::chain::front::{measure_front, FrontOptions};
use bkwaves_core::chain::integrator::Method;
use bkwaves_core::chain::medium::Properties;
use bkwaves_core::chain::sources::causes;
use bkwaves_core::chain::{ChainConfig, Stop, Trigger, TriggerKind};
use bkwaves_core::friction::{FrictionSpec, DEFAULT_LAW, LAWS};
use bkwaves_core::noise::NoiseLaw;
use bkwaves_core::params::ParamSpec;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// A chain of blocks with a registered friction law, advanced event by event.
///
/// The engine behind ``bkwaves.Chain``, which validates its inputs, builds the per-block
/// properties and turns the records into pandas and xarray objects; use that class.
/// Its arguments: ``u0`` (dimensionless stresses), ``dx``, ``v`` (dimensionless) and
/// ``step`` (a fraction of dx), then the friction law with its parameters (``gamma``
/// dimensionless) and the options of ``bkwaves.Chain``.
///
/// Examples
/// --------
/// >>> import numpy as np
/// >>> from bkwaves import _core
/// >>> eng = _core.ChainEngine(np.full(10, 0.6), 0.1, 0.0, 0.05, friction={"gamma": 0.3})
/// >>> eng.n, eng.time, eng.boundary
/// (10, 0.0, 'free')
#[pyclass(module = "bkwaves._core")]
pub struct ChainEngine {
    inner: Box<dyn DynChain>,
}

/// The (name, value) pairs of a dict of parameters.
fn named_values(params: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, f64)>> {
    let mut given = Vec::new();
    if let Some(d) = params {
        for (k, v) in d.iter() {
            given.push((k.extract::<String>()?, v.extract::<f64>()?));
        }
    }
    Ok(given)
}

/// A friction law by name with its parameters given as a dict (validated by its table).
fn friction_spec(law: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<FrictionSpec> {
    let given = named_values(params)?;
    let pairs: Vec<(&str, f64)> = given.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    FrictionSpec::new(law, &pairs).map_err(to_py)
}

fn opt_vec(a: Option<PyReadonlyArray1<'_, f64>>) -> PyResult<Option<Vec<f64>>> {
    a.map(|a| Ok(a.as_slice()?.to_vec())).transpose()
}

fn param_dict<'py>(py: Python<'py>, p: &ParamSpec) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", p.name)?;
    d.set_item("lo", p.lo)?;
    d.set_item("lo_closed", p.lo_closed)?;
    d.set_item("hi", p.hi)?;
    d.set_item("hi_closed", p.hi_closed)?;
    d.set_item("default", p.default)?;
    d.set_item("doc", p.doc)?;
    d.set_item("allowed", p.allowed())?;
    Ok(d)
}

/// The registered friction laws, the default first.
///
/// Returns
/// -------
/// list of dict
///     One ``{name, doc, params}`` per law; ``params`` lists ``{name, lo, lo_closed, hi,
///     hi_closed, default, doc, allowed}`` (default None: required).
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> [law["name"] for law in _core.friction_laws()]
/// ['coulomb', 'velocity_weakening']
#[pyfunction]
fn friction_laws<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for law in LAWS {
        let d = PyDict::new(py);
        d.set_item("name", law.name)?;
        d.set_item("doc", law.doc)?;
        let ps = PyList::empty(py);
        for p in law.params {
            ps.append(param_dict(py, p)?)?;
        }
        d.set_item("params", ps)?;
        out.append(d)?;
    }
    Ok(out)
}

/// Validate the parameters of a friction law against its table.
///
/// Parameters
/// ----------
/// law : str
///     The law's name (``friction_laws()``).
/// params : dict, optional
///     Its parameters by name.
/// partial : bool, default False
///     Check only the given parameters (missing required ones are no error).
///
/// Returns
/// -------
/// dict
///     Every parameter in table order with defaults filled in (``partial``: the given ones).
///
/// Raises
/// ------
/// bkwaves.ParameterError
///     An unknown law or parameter, a missing required one, or a value out of range.
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> _core.friction_resolve("coulomb", {"gamma": 0.3})
/// {'gamma': 0.3, 'beta': inf}
#[pyfunction]
#[pyo3(signature = (law, params=None, partial=false))]
fn friction_resolve<'py>(
    py: Python<'py>,
    law: &str,
    params: Option<&Bound<'py, PyDict>>,
    partial: bool,
) -> PyResult<Bound<'py, PyDict>> {
    if partial {
        let entry = bkwaves_core::friction::law(law).map_err(to_py)?;
        let d = PyDict::new(py);
        let given = named_values(params)?;
        let pairs: Vec<(&str, f64)> = given.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        bkwaves_core::params::check_given(entry.params, &format!("friction law {law}"), &pairs)
            .map_err(to_py)?;
        for (k, v) in &pairs {
            d.set_item(*k, *v)?;
        }
        return Ok(d);
    }
    let spec = friction_spec(law, params)?;
    let d = PyDict::new(py);
    for (p, x) in spec.law.params.iter().zip(&spec.values) {
        d.set_item(p.name, *x)?;
    }
    Ok(d)
}

/// The chain's boundary conditions, the default first.
///
/// Returns
/// -------
/// list of dict
///     ``{name, doc}`` per boundary.
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> [b["name"] for b in _core.boundaries()]
/// ['free', 'fixed', 'periodic']
#[pyfunction]
fn boundaries<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for b in boundary::BOUNDARIES {
        let d = PyDict::new(py);
        d.set_item("name", b.name)?;
        d.set_item("doc", b.doc)?;
        out.append(d)?;
    }
    Ok(out)
}

/// The chain's integrators, the default first.
///
/// Returns
/// -------
/// list of dict
///     ``{name, order, doc}`` per integrator (order: of the global error in the step).
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> [(i["name"], i["order"]) for i in _core.integrators()]
/// [('rk4', 4), ('midpoint', 2)]
#[pyfunction]
fn integrators<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for (_, name, order, doc) in Method::ALL {
        let d = PyDict::new(py);
        d.set_item("name", *name)?;
        d.set_item("order", *order)?;
        d.set_item("doc", *doc)?;
        out.append(d)?;
    }
    Ok(out)
}

/// The kinds of trigger a chain accepts (``Chain.kick``, ``Chain.release``, TOML
/// ``[[triggers]]``).
///
/// Returns
/// -------
/// list of dict
///     ``{name, doc}`` per kind.
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> [t["name"] for t in _core.triggers()]
/// ['kick', 'release']
#[pyfunction]
fn triggers<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for (name, doc) in TriggerKind::ALL {
        let d = PyDict::new(py);
        d.set_item("name", *name)?;
        d.set_item("doc", *doc)?;
        out.append(d)?;
    }
    Ok(out)
}

/// The causes of slips and events: the values of the ``kind`` column of the catalogs.
///
/// Returns
/// -------
/// list of dict
///     ``{name, doc}`` per cause: "threshold", "initial", then the sources of the core's
///     registry.
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> [c["name"] for c in _core.slip_causes()]
/// ['threshold', 'initial', 'trigger', 'noise']
#[pyfunction]
fn slip_causes<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for (name, doc) in causes() {
        let d = PyDict::new(py);
        d.set_item("name", name)?;
        d.set_item("doc", doc)?;
        out.append(d)?;
    }
    Ok(out)
}

/// The chain's defaults.
///
/// Returns
/// -------
/// dict
///     ``step`` (time step as a fraction of dx), ``boundary``, ``integrator``, ``law`` and
///     ``front_kick`` (the forward kick of the front experiment, units of
///     (f_r - f_s)/sqrt(k_p m)).
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> _core.defaults()["step"], _core.defaults()["integrator"]
/// (0.05, 'rk4')
#[pyfunction]
fn defaults<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("step", bkwaves_core::chain::DEFAULT_STEP)?;
    d.set_item("boundary", boundary::BOUNDARIES[0].name)?;
    d.set_item("integrator", Method::ALL[0].1)?;
    d.set_item("law", DEFAULT_LAW)?;
    d.set_item("front_kick", bkwaves_core::chain::front::KICK)?;
    Ok(d)
}

fn vec1<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    v.into_pyarray(py)
}

fn int1<'py>(py: Python<'py>, v: Vec<i64>) -> Bound<'py, PyArray1<i64>> {
    v.into_pyarray(py)
}

fn mat<'py>(py: Python<'py>, rows: &[Vec<f64>], n: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.iter().copied()).collect();
    let a = numpy::ndarray::Array2::from_shape_vec((rows.len(), n), flat)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

#[pymethods]
impl ChainEngine {
    /// A chain of len(u0) blocks. law: a registered friction law, friction: its
    /// parameters (dict); threshold, mass, loader (one per block) and coupling (one per
    /// bond: n - 1 free, n + 1 fixed, n periodic): per-block properties (None: all 1).
    /// shape=(nx, ny): the lattice instead (u0 and per-block arrays in block order, row
    /// after row; `boundary` across x, `boundary_y` across y, spacing dy across;
    /// coupling: the x bonds row after row, coupling_y: the y bonds, a row of bonds
    /// after another, each line's bonds as a chain's).
    #[new]
    #[pyo3(signature = (u0, dx, v, step, law="coulomb", friction=None, boundary="free",
                        fixed=(0.0, 0.0), u_t0=None, threshold=None, mass=None, loader=None,
                        coupling=None, shape=None, dy=None, boundary_y="free",
                        fixed_y=(0.0, 0.0), coupling_y=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        u0: PyReadonlyArray1<'_, f64>,
        dx: f64,
        v: f64,
        step: f64,
        law: &str,
        friction: Option<&Bound<'_, PyDict>>,
        boundary: &str,
        fixed: (f64, f64),
        u_t0: Option<PyReadonlyArray1<'_, f64>>,
        threshold: Option<PyReadonlyArray1<'_, f64>>,
        mass: Option<PyReadonlyArray1<'_, f64>>,
        loader: Option<PyReadonlyArray1<'_, f64>>,
        coupling: Option<PyReadonlyArray1<'_, f64>>,
        shape: Option<(usize, usize)>,
        dy: Option<f64>,
        boundary_y: &str,
        fixed_y: (f64, f64),
        coupling_y: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        let b = boundary::by_name(boundary, fixed).map_err(to_py)?;
        let by = boundary::by_name(boundary_y, fixed_y).map_err(to_py)?;
        let plane = shape.map(|(nx, ny)| Plane {
            nx,
            ny,
            dy: dy.unwrap_or(dx),
            y: by.as_ref(),
        });
        let spec = friction_spec(law, friction)?;
        let properties = Properties {
            threshold: opt_vec(threshold)?,
            mass: opt_vec(mass)?,
            loader: opt_vec(loader)?,
            coupling: opt_vec(coupling)?,
            coupling_y: opt_vec(coupling_y)?,
        };
        let u0 = u0.as_slice()?;
        let w = match &u_t0 {
            Some(a) => Some(a.as_slice()?),
            None => None,
        };
        let chain = ChainSpec {
            cfg: ChainConfig { dx, v, step },
            boundary: b.as_ref(),
            u0,
            u_t0: w,
            properties: &properties,
            plane,
        };
        let inner = build(&spec, chain).map_err(to_py)?;
        Ok(ChainEngine { inner })
    }

    /// The friction law: (name, {parameter: value}).
    fn friction<'py>(&self, py: Python<'py>) -> PyResult<(&'static str, Bound<'py, PyDict>)> {
        let (name, values) = self.inner.friction();
        let d = PyDict::new(py);
        for (k, x) in values {
            d.set_item(k, x)?;
        }
        Ok((name, d))
    }

    /// Static thresholds of the blocks.
    fn thresholds<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec1(py, self.inner.thresholds())
    }

    /// Choose the integrator: "rk4" (default) or "midpoint" (energy books to round-off).
    fn set_integrator(&mut self, name: &str) -> PyResult<()> {
        let m = Method::by_name(name).map_err(to_py)?;
        self.inner.set_integrator(m).map_err(to_py)
    }

    #[getter]
    fn integrator(&self) -> &'static str {
        self.inner.integrator()
    }

    /// Step-size control (docs/chain.md): the step grows above `step` dx, up to RK4's
    /// stability limit, while the step's error indicator stays below `step_tolerance`;
    /// None: the fixed step (default).
    #[pyo3(signature = (step_tolerance=None))]
    fn set_step_control(&mut self, step_tolerance: Option<f64>) -> PyResult<()> {
        self.inner.set_step_control(step_tolerance).map_err(to_py)
    }

    #[getter]
    fn step_tolerance(&self) -> Option<f64> {
        self.inner.step_tolerance()
    }

    /// How slips and sticks are located: "local" (only the neighbourhood of a switch is
    /// redone; docs/lattice.md, "Local events") or "global" (every sliding block is
    /// redone up to it). "local" where it cannot apply (another integrator, step-size
    /// control, a law whose onset takes sub-steps) is refused, naming `events`.
    fn set_events(&mut self, mode: &str) -> PyResult<()> {
        let on = match mode {
            "local" => true,
            "global" => false,
            _ => {
                return Err(to_py(bkwaves_core::Error::Invalid {
                    name: "events".to_string(),
                    value: format!("{mode:?}"),
                    allowed: "one of: local, global".to_string(),
                }))
            }
        };
        self.inner.set_local_events(on).map_err(to_py)
    }

    /// "local" or "global" (`set_events`).
    #[getter]
    fn events(&self) -> &'static str {
        if self.inner.local_events() {
            "local"
        } else {
            "global"
        }
    }

    /// Why local events cannot apply to this engine as set (None: they can).
    #[getter]
    fn local_events_unavailable(&self) -> Option<&'static str> {
        self.inner.local_events_unavailable()
    }

    /// What the local events did: {event_steps, passes, components, fallbacks, and the
    /// block-steps split: quiet_block_steps, first_block_steps, later_block_steps,
    /// component_block_steps, component_substeps, members}.
    fn local_stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.inner.local_stats();
        let d = PyDict::new(py);
        d.set_item("event_steps", s.event_steps)?;
        d.set_item("passes", s.passes)?;
        d.set_item("components", s.components)?;
        d.set_item("fallbacks", s.fallbacks)?;
        d.set_item("quiet_block_steps", s.quiet_block_steps)?;
        d.set_item("first_block_steps", s.first_block_steps)?;
        d.set_item("later_block_steps", s.later_block_steps)?;
        d.set_item("component_block_steps", s.component_block_steps)?;
        d.set_item("component_substeps", s.component_substeps)?;
        d.set_item("members", s.members)?;
        Ok(d)
    }

    /// Where the onsets' block-steps went (a law with a stiff onset: chain/onset.rs):
    /// {steps (with a patch), group_passes, turned_block_steps (plain steps thrown away as
    /// a block turned stiff in them), and per cause of the patch's integration (first,
    /// growth, redo up to an event): integrations_*, group_block_steps_*,
    /// loose_block_steps_* (the groups' first, loose passes), runs_block_steps_*}.
    fn onset_stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.inner.onset_stats();
        let d = PyDict::new(py);
        d.set_item("steps", s.steps)?;
        d.set_item("group_passes", s.group_passes)?;
        d.set_item("turned_block_steps", s.turned_block_steps)?;
        for (k, cause) in ["first", "growth", "redo"].iter().enumerate() {
            d.set_item(format!("integrations_{cause}"), s.integrations[k])?;
            d.set_item(format!("group_block_steps_{cause}"), s.group_block_steps[k])?;
            d.set_item(format!("loose_block_steps_{cause}"), s.loose_block_steps[k])?;
            d.set_item(format!("runs_block_steps_{cause}"), s.runs_block_steps[k])?;
        }
        Ok(d)
    }

    /// The whole state as bytes (restored bit for bit by `restore`).
    fn checkpoint<'py>(&self, py: Python<'py>) -> Bound<'py, pyo3::types::PyBytes> {
        pyo3::types::PyBytes::new(py, &self.inner.checkpoint())
    }

    /// Restore a state written by `checkpoint` of a chain with the same configuration.
    fn restore(&mut self, data: &[u8]) -> PyResult<()> {
        self.inner.restore(data).map_err(to_py)
    }

    /// Schedule a trigger: kind "release" (value = direction +1/-1) or "kick" (value =
    /// change of u_t).
    fn add_trigger(&mut self, t: f64, block: usize, kind: &str, value: f64) -> PyResult<()> {
        let kind = TriggerKind::by_name(kind, value).map_err(to_py)?;
        self.inner
            .add_trigger(Trigger { t, block, kind })
            .map_err(to_py)
    }

    /// Spontaneous slips of stuck blocks from now on: a Poisson process of rate
    /// rate g(x) per block (law "constant", "exponential" with phi0, "power" with
    /// exponent, "table" with nodes u and values g; x = 1 - (threshold - phi)), each a
    /// forward kick of speed `kick` over the ground (0: a release), seeded. A zero rate is
    /// no noise.
    #[pyo3(signature = (law, rate, seed, kick=0.0, phi0=f64::NAN, exponent=f64::NAN,
                        u=Vec::new(), g=Vec::new()))]
    #[allow(clippy::too_many_arguments)]
    fn set_noise(
        &mut self,
        law: &str,
        rate: f64,
        seed: u64,
        kick: f64,
        phi0: f64,
        exponent: f64,
        u: Vec<f64>,
        g: Vec<f64>,
    ) -> PyResult<()> {
        let law = NoiseLaw::with_table(law, rate, phi0, exponent, &u, &g).map_err(to_py)?;
        self.inner.set_noise(law, kick, seed).map_err(to_py)
    }

    /// (candidates drawn, spontaneous slips) by the noise so far; None without noise.
    #[getter]
    fn noise_counters(&self) -> Option<(u64, u64)> {
        self.inner.noise_counters()
    }

    /// Snapshots at the given times and/or at the end of every k-th event (0 = never).
    fn add_snapshots(
        &mut self,
        times: PyReadonlyArray1<'_, f64>,
        every_events: usize,
    ) -> PyResult<()> {
        self.inner
            .add_snapshots(times.as_slice()?, every_events)
            .map_err(to_py)
    }

    /// Advance (GIL released) to t_end, max_events more finished events or max_steps
    /// steps, whichever comes first. Returns "time", "events", "steps" or "long_event"
    /// (see `set_run_limits`).
    fn advance(
        &mut self,
        py: Python<'_>,
        t_end: f64,
        max_events: usize,
        max_steps: u64,
    ) -> PyResult<&'static str> {
        let inner = &mut self.inner;
        let stop = py
            .detach(|| inner.run(t_end, max_events, max_steps))
            .map_err(to_py)?;
        Ok(match stop {
            Stop::Time => "time",
            Stop::Events => "events",
            Stop::Steps => "steps",
            Stop::LongEvent => "long_event",
        })
    }

    /// Run limits: `advance` returns "long_event" when the running event has more than
    /// `event_slips` slips or has lasted longer than `event_duration`, and "steps" after
    /// `chunk_work` units of work (one per step plus one per sliding block per step).
    fn set_run_limits(&mut self, event_slips: usize, event_duration: f64, chunk_work: u64) {
        self.inner
            .set_run_limits(event_slips, event_duration, chunk_work);
    }

    /// Bound the wall time of one `advance` call (seconds; inf: no bound): it returns
    /// "steps" once that much time has passed, so interrupts are answered promptly.
    fn set_chunk_wall(&mut self, seconds: f64) {
        self.inner.set_chunk_wall(seconds);
    }

    /// The snapshots taken since the last call, handed over and dropped by the engine:
    /// (t, u[k, i], u_t[k, i]). `snapshots` counts from the first one not yet taken.
    #[allow(clippy::type_complexity)]
    fn take_snapshots<'py>(
        &mut self,
        py: Python<'py>,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
    )> {
        let n = self.inner.n();
        let s = self.inner.take_snapshots();
        Ok((vec1(py, s.t), mat(py, &s.u, n)?, mat(py, &s.u_t, n)?))
    }

    /// (slips, duration) of the running event, or None.
    #[getter]
    fn open_event(&self) -> Option<(usize, f64)> {
        self.inner.open_event()
    }

    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }
    #[getter]
    fn n(&self) -> usize {
        self.inner.n()
    }
    /// (nx, ny): (n, 1) for a chain.
    #[getter]
    fn shape(&self) -> (usize, usize) {
        self.inner.shape()
    }
    #[getter]
    fn n_sliding(&self) -> usize {
        self.inner.n_sliding()
    }
    #[getter]
    fn events_finished(&self) -> usize {
        self.inner.catalog().finished()
    }
    /// Number of slip rows of finished events: these rows never change again (the slips
    /// of the running event follow them).
    #[getter]
    fn slips_final(&self) -> usize {
        let c = self.inner.catalog();
        let done = c.finished();
        c.slips.partition_point(|r| r.event < done)
    }
    #[getter]
    fn boundary(&self) -> &'static str {
        self.inner.boundary_name()
    }

    fn u<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec1(py, self.inner.u())
    }
    fn u_t<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec1(py, self.inner.u_t())
    }
    fn phi<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec1(py, self.inner.phi())
    }
    fn modes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        int1(py, self.inner.modes().into_iter().map(i64::from).collect())
    }

    /// Energy now: (kinetic, coupling springs, loader springs).
    fn energy(&self) -> (f64, f64, f64) {
        self.inner.energy()
    }

    /// Energy flows so far.
    fn ledger<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let l = self.inner.ledger();
        let d = PyDict::new(py);
        d.set_item("loader_work", l.load)?;
        d.set_item("friction_work", l.dry)?;
        d.set_item("viscous_work", l.viscous)?;
        d.set_item("stick_projection", l.projection)?;
        d.set_item("injected", l.injected)?;
        Ok(d)
    }

    /// Work counters.
    fn counters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.inner.counters();
        let d = PyDict::new(py);
        d.set_item("steps", c.steps)?;
        d.set_item("block_steps", c.block_steps)?;
        d.set_item("switches", c.switches)?;
        d.set_item("jumps", c.jumps)?;
        Ok(d)
    }

    /// The event catalog as a dict of arrays (rows from `start` on).
    #[pyo3(signature = (start=0))]
    fn catalog<'py>(&self, py: Python<'py>, start: usize) -> PyResult<Bound<'py, PyDict>> {
        let all = &self.inner.catalog().events;
        let e = &all[start.min(all.len())..];
        let d = PyDict::new(py);
        let f = |g: &dyn Fn(&bkwaves_core::chain::catalog::EventRecord) -> f64| {
            e.iter().map(g).collect::<Vec<f64>>()
        };
        let i = |g: &dyn Fn(&bkwaves_core::chain::catalog::EventRecord) -> usize| {
            e.iter().map(|r| g(r) as i64).collect::<Vec<i64>>()
        };
        d.set_item("event", int1(py, i(&|r| r.id)))?;
        d.set_item("t_start", vec1(py, f(&|r| r.t_start)))?;
        d.set_item("t_end", vec1(py, f(&|r| r.t_end)))?;
        d.set_item("nucleation", int1(py, i(&|r| r.nucleation)))?;
        d.set_item("first_block", int1(py, i(&|r| r.first_block)))?;
        d.set_item("last_block", int1(py, i(&|r| r.last_block)))?;
        d.set_item("n_blocks", int1(py, i(&|r| r.n_blocks)))?;
        d.set_item("n_slips", int1(py, i(&|r| r.n_slips)))?;
        d.set_item("moment", vec1(py, f(&|r| r.moment)))?;
        d.set_item("stress_drop", vec1(py, f(&|r| r.stress_drop)))?;
        d.set_item("kind", e.iter().map(|r| r.kind.name()).collect::<Vec<_>>())?;
        Ok(d)
    }

    /// Slip intervals (the slip-front trajectories), rows `start..stop` (default: all), as
    /// a dict of arrays.
    #[pyo3(signature = (start=0, stop=None))]
    fn slips<'py>(
        &self,
        py: Python<'py>,
        start: usize,
        stop: Option<usize>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let all = &self.inner.catalog().slips;
        let stop = stop.unwrap_or(all.len()).min(all.len());
        let s = &all[start.min(stop)..stop];
        let d = PyDict::new(py);
        d.set_item(
            "event",
            int1(py, s.iter().map(|r| r.event as i64).collect()),
        )?;
        d.set_item(
            "block",
            int1(py, s.iter().map(|r| r.block as i64).collect()),
        )?;
        d.set_item(
            "direction",
            int1(py, s.iter().map(|r| i64::from(r.dir)).collect()),
        )?;
        d.set_item("t_start", vec1(py, s.iter().map(|r| r.t_start).collect()))?;
        d.set_item("t_end", vec1(py, s.iter().map(|r| r.t_end).collect()))?;
        d.set_item("u_start", vec1(py, s.iter().map(|r| r.u_start).collect()))?;
        d.set_item("u_end", vec1(py, s.iter().map(|r| r.u_end).collect()))?;
        d.set_item("slip", vec1(py, s.iter().map(|r| r.slip).collect()))?;
        d.set_item("kind", s.iter().map(|r| r.kind.name()).collect::<Vec<_>>())?;
        Ok(d)
    }

    /// Snapshots from number `start` on: (t, u[k, i], u_t[k, i]).
    #[allow(clippy::type_complexity)]
    #[pyo3(signature = (start=0))]
    fn snapshots<'py>(
        &self,
        py: Python<'py>,
        start: usize,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
    )> {
        let s = self.inner.snapshots();
        let n = self.inner.n();
        let k = start.min(s.t.len());
        Ok((
            vec1(py, s.t[k..].to_vec()),
            mat(py, &s.u[k..], n)?,
            mat(py, &s.u_t[k..], n)?,
        ))
    }
}

/// One front across a uniformly stressed chain at v = 0 (the ``bkwaves front`` experiment).
///
/// ``bkwaves.chain.front`` is the validated Python entry point (it sizes the chain and
/// checks convergence).
///
/// Parameters
/// ----------
/// u_plus : float
///     Stress ahead of the front (dimensionless).
/// dx : float
///     Lattice spacing sqrt(k_p/k_c) (dimensionless).
/// blocks : int
///     Chain length in blocks.
/// step : float, default 0.05
///     Time step as a fraction of dx (in units of dx sqrt(m/k_p)).
/// law : str, default "coulomb"
///     Friction law (``friction_laws()``).
/// friction : dict, optional
///     Its parameters (``{"gamma": ...}`` for Coulomb).
/// window : (float, float), default (0.5, 0.75)
///     The part of the chain (fractions of its length) where the front is measured.
/// heal : bool, default True
///     Run until the blocks behind the front have re-stuck.
///
/// Returns
/// -------
/// dict
///     ``c`` (front speed over the window), ``unsteadiness``, ``pulse``, ``u_minus``, ``w``,
///     per-block ``slip_times``, ``stick_times`` and ``stick_u``, ``window`` (blocks),
///     ``t_end``, and the counters ``block_steps``, ``slips``, ``backward_slips``.
///
/// Examples
/// --------
/// >>> from bkwaves import _core
/// >>> m = _core.front_measure(0.6, 0.1, 300, friction={"gamma": 0.3})
/// >>> round(m["c"], 6), m["pulse"]
/// (1.233616, True)
#[pyfunction]
#[pyo3(signature = (u_plus, dx, blocks, step=bkwaves_core::chain::DEFAULT_STEP, law="coulomb",
                    friction=None, window=(0.5, 0.75), heal=true))]
#[allow(clippy::too_many_arguments)]
fn front_measure<'py>(
    py: Python<'py>,
    u_plus: f64,
    dx: f64,
    blocks: usize,
    step: f64,
    law: &str,
    friction: Option<&Bound<'py, PyDict>>,
    window: (f64, f64),
    heal: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let spec = friction_spec(law, friction)?;
    let mut o = FrontOptions::with_friction(u_plus, spec, dx, blocks);
    o.step = step;
    o.window = window;
    o.heal = heal;
    let r = py.detach(|| measure_front(&o)).map_err(to_py)?;
    let d = PyDict::new(py);
    d.set_item("c", r.c)?;
    d.set_item("unsteadiness", r.unsteadiness)?;
    d.set_item("pulse", r.pulse)?;
    d.set_item("u_minus", r.u_minus)?;
    d.set_item("w", r.w)?;
    d.set_item("slip_times", vec1(py, r.slip_times))?;
    d.set_item("stick_times", vec1(py, r.stick_times))?;
    d.set_item("stick_u", vec1(py, r.stick_u))?;
    d.set_item("window", r.window)?;
    d.set_item("t_end", r.t_end)?;
    d.set_item("block_steps", r.block_steps)?;
    d.set_item("slips", r.slips)?;
    d.set_item("backward_slips", r.backward_slips)?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<ChainEngine>()?;
    m.add_function(wrap_pyfunction!(front_measure, m)?)?;
    m.add_function(wrap_pyfunction!(friction_laws, m)?)?;
    m.add_function(wrap_pyfunction!(friction_resolve, m)?)?;
    m.add_function(wrap_pyfunction!(boundaries, m)?)?;
    m.add_function(wrap_pyfunction!(integrators, m)?)?;
    m.add_function(wrap_pyfunction!(triggers, m)?)?;
    m.add_function(wrap_pyfunction!(slip_causes, m)?)?;
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    Ok(())
}
