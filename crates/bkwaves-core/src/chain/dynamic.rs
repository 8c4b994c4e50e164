//! A chain whose friction law and medium are chosen at run time (by name, from the
//! registries), for the Python binding and the command line. Each (law, medium) pair is
//! a monomorphised [`Chain`]: the law's and the medium's code is inlined in the
//! integrator loops; only the calls below go through a vtable.

use super::catalog::Catalog;
use super::energy::Ledger;
use super::geometry::{Geometry, Grid};
use super::integrator::Method;
use super::medium::{Ends, Medium, PerBlock, Properties, Uniform};
use super::{
    Chain, ChainConfig, Counters, Engine, LocalStats, OnsetStats, Snapshots, Stop, Trigger,
};
use crate::boundary::{Boundary, Ghost};
use crate::error::Result;
use crate::friction::{Friction, FrictionSpec};
use crate::lattice::LatticeSpec;
use crate::noise::NoiseLaw;

/// What a chain is built from, besides its friction law.
#[derive(Debug, Clone, Copy)]
pub struct ChainSpec<'a> {
    /// Numerical and loading settings.
    pub cfg: ChainConfig,
    /// Boundary condition.
    pub boundary: &'a dyn Boundary,
    /// Initial displacements (one per block).
    pub u0: &'a [f64],
    /// Initial velocities (default: v, all stuck).
    pub u_t0: Option<&'a [f64]>,
    /// Per-block properties (all None: the uniform chain, bit for bit the paper's engine).
    pub properties: &'a Properties,
    /// The plane: a lattice of nx x ny blocks (u0 in block order, row after row;
    /// `boundary` closes it across x); None: a chain.
    pub plane: Option<Plane<'a>>,
}

/// The lattice's shape, its spacing across and the boundary across y.
#[derive(Debug, Clone, Copy)]
pub struct Plane<'a> {
    /// Blocks along x.
    pub nx: usize,
    /// Blocks along y.
    pub ny: usize,
    /// dy = sqrt(k_p / k_y).
    pub dy: f64,
    /// Boundary across y.
    pub y: &'a dyn Boundary,
}

/// A chain with its law and medium behind a vtable: everything the binding uses.
pub trait DynChain: Send + Sync + std::fmt::Debug {
    /// See [`Chain::set_integrator`].
    fn set_integrator(&mut self, method: Method) -> Result<()>;
    /// Name of the integrator.
    fn integrator(&self) -> &'static str;
    /// See [`Chain::set_step_control`].
    fn set_step_control(&mut self, tol: Option<f64>) -> Result<()>;
    /// See [`Chain::step_tolerance`].
    fn step_tolerance(&self) -> Option<f64>;
    /// See [`Engine::try_set_local_events`].
    fn set_local_events(&mut self, on: bool) -> Result<()>;
    /// Whether local events are chosen.
    fn local_events(&self) -> bool;
    /// See [`Engine::local_events_unavailable`].
    fn local_events_unavailable(&self) -> Option<&'static str>;
    /// See [`Engine::local_stats`].
    fn local_stats(&self) -> LocalStats;
    /// See [`Engine::onset_stats`].
    fn onset_stats(&self) -> OnsetStats;
    /// See [`Chain::checkpoint`].
    fn checkpoint(&self) -> Vec<u8>;
    /// See [`Chain::restore`].
    fn restore(&mut self, bytes: &[u8]) -> Result<()>;
    /// See [`Chain::add_trigger`].
    fn add_trigger(&mut self, tr: Trigger) -> Result<()>;
    /// See [`Chain::add_snapshots`].
    fn add_snapshots(&mut self, times: &[f64], every_events: usize) -> Result<()>;
    /// See [`Chain::set_noise`].
    fn set_noise(&mut self, law: NoiseLaw, kick: f64, seed: u64) -> Result<()>;
    /// See [`Chain::noise_counters`].
    fn noise_counters(&self) -> Option<(u64, u64)>;
    /// See [`Chain::run`].
    fn run(&mut self, t_end: f64, max_events: usize, max_steps: u64) -> Result<Stop>;
    /// See [`Chain::set_run_limits`].
    fn set_run_limits(&mut self, event_slips: usize, event_duration: f64, chunk_work: u64);
    /// See [`Chain::set_chunk_wall`].
    fn set_chunk_wall(&mut self, seconds: f64);
    /// See [`Chain::take_snapshots`].
    fn take_snapshots(&mut self) -> Snapshots;
    /// See [`Chain::open_event`].
    fn open_event(&self) -> Option<(usize, f64)>;
    /// Current time.
    fn time(&self) -> f64;
    /// Number of blocks.
    fn n(&self) -> usize;
    /// (nx, ny): (n, 1) for a chain.
    fn shape(&self) -> (usize, usize);
    /// Number of sliding blocks.
    fn n_sliding(&self) -> usize;
    /// Name of the boundary condition.
    fn boundary_name(&self) -> &'static str;
    /// The friction law's name and its (parameter, value) pairs in table order.
    fn friction(&self) -> (&'static str, Vec<(&'static str, f64)>);
    /// Static thresholds of the blocks (0-based).
    fn thresholds(&self) -> Vec<f64>;
    /// Displacements u now.
    fn u(&self) -> Vec<f64>;
    /// Velocities u_t now.
    fn u_t(&self) -> Vec<f64>;
    /// Modes (0 stuck, +1 forward, -1 backward) now.
    fn modes(&self) -> Vec<i8>;
    /// phi now.
    fn phi(&self) -> Vec<f64>;
    /// Energy (kinetic, coupling springs, loader springs) now.
    fn energy(&self) -> (f64, f64, f64);
    /// Event catalog and slip records.
    fn catalog(&self) -> &Catalog;
    /// Energy flows.
    fn ledger(&self) -> Ledger;
    /// Work counters.
    fn counters(&self) -> Counters;
    /// Snapshots taken.
    fn snapshots(&self) -> &Snapshots;
}

impl<G: Geometry, F: Friction, M: Medium> DynChain for Engine<G, F, M> {
    fn set_run_limits(&mut self, event_slips: usize, event_duration: f64, chunk_work: u64) {
        Engine::set_run_limits(self, event_slips, event_duration, chunk_work)
    }
    fn set_chunk_wall(&mut self, seconds: f64) {
        Engine::set_chunk_wall(self, seconds)
    }
    fn take_snapshots(&mut self) -> Snapshots {
        Engine::take_snapshots(self)
    }
    fn open_event(&self) -> Option<(usize, f64)> {
        Engine::open_event(self)
    }
    fn set_integrator(&mut self, method: Method) -> Result<()> {
        Engine::set_integrator(self, method)
    }
    fn set_step_control(&mut self, tol: Option<f64>) -> Result<()> {
        Engine::set_step_control(self, tol)
    }
    fn step_tolerance(&self) -> Option<f64> {
        Engine::step_tolerance(self)
    }
    fn integrator(&self) -> &'static str {
        Engine::integrator(self)
    }
    fn set_local_events(&mut self, on: bool) -> Result<()> {
        Engine::try_set_local_events(self, on)
    }
    fn local_events(&self) -> bool {
        Engine::local_events(self)
    }
    fn local_events_unavailable(&self) -> Option<&'static str> {
        Engine::local_events_unavailable(self)
    }
    fn local_stats(&self) -> LocalStats {
        Engine::local_stats(self)
    }
    fn onset_stats(&self) -> OnsetStats {
        Engine::onset_stats(self)
    }
    fn checkpoint(&self) -> Vec<u8> {
        Engine::checkpoint(self)
    }
    fn restore(&mut self, bytes: &[u8]) -> Result<()> {
        Engine::restore(self, bytes)
    }
    fn add_trigger(&mut self, tr: Trigger) -> Result<()> {
        Engine::add_trigger(self, tr)
    }
    fn add_snapshots(&mut self, times: &[f64], every_events: usize) -> Result<()> {
        Engine::add_snapshots(self, times, every_events)
    }
    fn set_noise(&mut self, law: NoiseLaw, kick: f64, seed: u64) -> Result<()> {
        Engine::set_noise(self, law, kick, seed)
    }
    fn noise_counters(&self) -> Option<(u64, u64)> {
        Engine::noise_counters(self)
    }
    fn run(&mut self, t_end: f64, max_events: usize, max_steps: u64) -> Result<Stop> {
        Engine::run(self, t_end, max_events, max_steps)
    }
    fn time(&self) -> f64 {
        Engine::time(self)
    }
    fn n(&self) -> usize {
        Engine::n(self)
    }
    fn shape(&self) -> (usize, usize) {
        self.geometry().shape()
    }
    fn n_sliding(&self) -> usize {
        Engine::n_sliding(self)
    }
    fn boundary_name(&self) -> &'static str {
        Engine::boundary_name(self)
    }
    fn friction(&self) -> (&'static str, Vec<(&'static str, f64)>) {
        let values = Engine::friction(self).values();
        (
            F::NAME,
            F::PARAMS.iter().map(|p| p.name).zip(values).collect(),
        )
    }
    fn thresholds(&self) -> Vec<f64> {
        (self.geometry().blocks())
            .map(|p| self.medium().threshold(p))
            .collect()
    }
    fn u(&self) -> Vec<f64> {
        Engine::u(self)
    }
    fn u_t(&self) -> Vec<f64> {
        Engine::u_t(self)
    }
    fn modes(&self) -> Vec<i8> {
        Engine::modes(self)
    }
    fn phi(&self) -> Vec<f64> {
        Engine::phi(self)
    }
    fn energy(&self) -> (f64, f64, f64) {
        Engine::energy(self)
    }
    fn catalog(&self) -> &Catalog {
        &self.catalog
    }
    fn ledger(&self) -> Ledger {
        self.ledger
    }
    fn counters(&self) -> Counters {
        self.counters
    }
    fn snapshots(&self) -> &Snapshots {
        &self.snapshots
    }
}

/// How the boundary closes the chain, for the layout of per-bond values.
fn ends(b: &dyn Boundary) -> Ends {
    match b.left() {
        Ghost::Mirror => Ends::Free,
        Ghost::Held(_) => Ends::Walls,
        Ghost::Wrap => Ends::Ring,
    }
}

/// Build a chain with law `F` from its values (table order): the uniform engine when no
/// per-block property is given, else the per-block one.
pub(crate) fn build_chain<F: Friction>(
    values: &[f64],
    spec: ChainSpec<'_>,
) -> Result<Box<dyn DynChain>> {
    for (p, &x) in F::PARAMS.iter().zip(values) {
        p.check(p.name, x)?;
    }
    let fr = F::from_values(values)?;
    let ChainSpec {
        cfg,
        boundary,
        u0,
        u_t0,
        properties,
        plane,
    } = spec;
    if let Some(pl) = plane {
        let ls = LatticeSpec {
            nx: pl.nx,
            ny: pl.ny,
            dy: pl.dy,
            x: boundary,
            y: pl.y,
        };
        if properties.is_uniform() {
            return Ok(Box::new(Engine::lattice(cfg, ls, fr, Uniform, u0, u_t0)?));
        }
        let grid = Grid::new(
            pl.nx,
            pl.ny,
            cfg.dx,
            pl.dy,
            (boundary.left(), boundary.right()),
            (pl.y.left(), pl.y.right()),
        );
        let med = PerBlock::for_lattice(properties, &grid)?;
        return Ok(Box::new(Engine::lattice(cfg, ls, fr, med, u0, u_t0)?));
    }
    if properties.is_uniform() {
        return Ok(Box::new(Chain::with_medium(
            cfg, fr, Uniform, boundary, u0, u_t0,
        )?));
    }
    let med = PerBlock::new(properties, u0.len(), ends(boundary))?;
    Ok(Box::new(Chain::with_medium(
        cfg, fr, med, boundary, u0, u_t0,
    )?))
}

/// A chain with the friction law `friction` (see [`ChainSpec`]).
pub fn build(friction: &FrictionSpec, spec: ChainSpec<'_>) -> Result<Box<dyn DynChain>> {
    (friction.law.chain)(&friction.values, spec)
}
