//! The discrete Burridge-Knopoff chain with stick-slip friction, simulated event by event.
//!
//! Dimensionless equations (paper eqs. dimless, rest, slide, slip; ../../docs/chain.md):
//! with phi_i = u_i - Lap_i / dx^2 and s_i = v - u_t,i (speed over the ground),
//!
//! - a stuck block drifts with the loader, u_t = v, exactly (never stepped);
//! - a sliding block obeys u_tt = -phi + R(s) (friction law, [`crate::friction`]);
//!   for Coulomb friction R = 2 gamma s forward and 2 gamma s - 2 beta backward;
//! - a stuck block slips forward when phi >= upper (= 1), backward when phi <= lower
//!   (= -(1 + 2 beta); beta = inf, the default of the front experiment and of the Python
//!   API, is the paper's model: no backward slip);
//! - a sliding block whose u_t returns to v sticks if lower < phi < upper there; otherwise
//!   it goes on sliding in the direction the force pushes it (forward if phi >= upper,
//!   backward if phi <= lower).
//!
//! Runs of sliding blocks are stepped with RK4 (step h = `step` * dx, or `step` times the
//! friction law's own time scale if that is shorter); every stick and
//! every slip of a stuck neighbour is located in time on the cubic Hermite dense output
//! of the step, the step is redone up to that instant and the event applied there.
//! Stuck blocks whose neighbours are stuck have phi rising at exactly v: their slip
//! times sit in a priority queue and quiet intervals are skipped in one jump.

pub mod catalog;
pub mod cells;
pub mod checkpoint;
pub mod dynamic;
pub mod energy;
pub mod events;
pub mod front;
pub mod frontier;
pub mod geometry;
pub mod integrator;
mod local_events;
pub mod medium;
mod onset;
pub mod release;
pub mod sources;
pub mod state;
pub mod step_control;

use crate::boundary::Boundary;
use crate::error::{check_at_least, check_open, Error, Result};
use crate::friction::Friction;
use crate::noise::NoiseLaw;
use catalog::Catalog;
use cells::CellVec;
use energy::Ledger;
use events::{Hermite, SlipQueue};
use geometry::{Beyond, Geometry, Line};
use integrator::{Method, Simd, Stepper};
pub use local_events::LocalStats;
#[cfg(test)]
pub(crate) use local_events::Plain;
use medium::{Blocks, Medium, Uniform};
pub use onset::OnsetStats;
use sources::{Cause, Source, View};
use state::State;
use step_control::StepControl;

/// Largest bound on the midpoint iteration's contraction factor accepted: 0.8^200 < 1e-19,
/// so its 200 passes reach round-off from any start.
const MIDPOINT_CONTRACTION: f64 = 0.8;

/// Numerical and loading settings of a chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainConfig {
    /// Lattice spacing dx = sqrt(k_p / k_c).
    pub dx: f64,
    /// Loading rate v >= 0.
    pub v: f64,
    /// Time step as a fraction of dx (h = step * dx; of the friction law's time scale,
    /// m_min v_f / theta_max for velocity weakening, if that is shorter).
    pub step: f64,
}

impl Default for ChainConfig {
    fn default() -> Self {
        ChainConfig {
            dx: 0.1,
            v: 0.0,
            step: DEFAULT_STEP,
        }
    }
}

/// The onset's sub-steps (onset.rs) are used when the law's step m_min v_f/theta_max is
/// shorter than dx/ONSET_GAIN: above it stepping every block at the law's step costs less
/// (docs/benchmarks.md, "Onset": the two cost the same at v_f/dx = 0.02).
pub const ONSET_GAIN: f64 = 50.0;

/// Default step fraction h/dx: converges front speeds to about 1e-7 relative at fixed dx
/// (see docs/validation.md).
pub const DEFAULT_STEP: f64 = 0.05;

/// What a trigger does to its block.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TriggerKind {
    /// Remove static friction for an instant: the block starts sliding in direction
    /// `dir` (+1 forward, -1 backward) from its present state.
    Release {
        /// +1 or -1.
        dir: i8,
    },
    /// Add `du_t` to the block's velocity u_t (it then slides, forward if u_t < v).
    Kick {
        /// velocity change of u_t.
        du_t: f64,
    },
}

impl TriggerKind {
    /// The registry: name and meaning of the value each kind takes.
    pub const ALL: &'static [(&'static str, &'static str)] = &[
        (
            "kick",
            "value added to the block's u_t (negative: forward over the ground); it then slides",
        ),
        (
            "release",
            "the block starts sliding from its present state; value: direction (+1 forward, \
             -1 backward)",
        ),
    ];

    /// The trigger kind `name` with its value; an unknown name lists the known ones.
    pub fn by_name(name: &str, value: f64) -> Result<TriggerKind> {
        match name {
            "release" => Ok(TriggerKind::Release {
                dir: if value < 0.0 { -1 } else { 1 },
            }),
            "kick" => Ok(TriggerKind::Kick { du_t: value }),
            _ => Err(Error::Invalid {
                name: "trigger kind".to_string(),
                value: format!("{name:?}"),
                allowed: format!(
                    "one of: {}",
                    TriggerKind::ALL
                        .iter()
                        .map(|k| k.0)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            }),
        }
    }
}

/// A trigger applied to one block at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trigger {
    /// Time.
    pub t: f64,
    /// Block (0-based).
    pub block: usize,
    /// What happens.
    pub kind: TriggerKind,
}

/// Why a call to [`Chain::run`] returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// t reached t_end.
    Time,
    /// max_events events finished.
    Events,
    /// The step or work budget of this call was used up (call again to go on).
    Steps,
    /// The running event has more slips, or has lasted longer, than the limits set by
    /// [`Chain::set_run_limits`]: the chain slides on without re-sticking (steady
    /// sliding, creep, or a pulse circling a ring). Raise the limits to go on.
    LongEvent,
}

/// Snapshots of u and u_t.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Snapshots {
    /// Times.
    pub t: Vec<f64>,
    /// u at each time (n values each).
    pub u: Vec<Vec<f64>>,
    /// u_t at each time.
    pub u_t: Vec<Vec<f64>>,
}

/// Counters of the work done.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Integration steps (including redone partial steps).
    pub steps: u64,
    /// Sliding-block updates (blocks x steps).
    pub block_steps: u64,
    /// Slips and sticks located.
    pub switches: u64,
    /// Quiet intervals skipped.
    pub jumps: u64,
}

/// The engine: blocks laid out by the geometry `G` ([`Line`]: the chain, [`geometry::Grid`]:
/// the lattice), friction law `F`, per-block properties `M` (uniform by default).
#[derive(Debug, Clone)]
pub struct Engine<G: Geometry, F: Friction, M: Medium = Uniform> {
    cfg: ChainConfig,
    blk: Blocks<F, M>,
    boundary_name: &'static str,
    st: State<G>,
    rk: Stepper,
    /// The vector code of the event pre-test (the widest this CPU runs, detected once).
    simd: Simd,
    queue: SlipQueue,
    t: f64,
    h: f64,
    /// RK4's stability limit of the step (2.5 over the fastest rate of a sliding block).
    h_stable: f64,
    /// Bound on the contraction factor of the implicit midpoint's fixed-point iteration at
    /// this step: (h/2)^2 max (stiffness/mass) + (h/2) max |dR/ds|/m (module midpoint).
    midpoint_contraction: f64,
    /// Opt-in step-size control (None: the fixed step h, the default).
    control: Option<StepControl>,
    /// The law has a stiff onset (a finite time scale) and the integrator is RK4: blocks
    /// in it are integrated with their own sub-steps (onset.rs).
    stiff: bool,
    /// Whether the fixed-step RK4 engine uses the onset's sub-steps (step dx), as chosen
    /// when built; `stiff` is this unless another integrator or the step-size control
    /// is on (restored when they are turned off again: [`Engine::choose_step`]).
    sub_steps: bool,
    /// The step h_law of the midpoint integrator (step times the smaller of dx and the
    /// law's time scale: it has no sub-steps).
    h_law: f64,
    /// The patch of blocks in their stiff onset and its integration (not part of the
    /// state: rebuilt every step).
    onset: onset::Onset,
    /// Local events (local_events.rs: whether chosen, and the work of one step).
    local: local_events::Local,
    a_start: CellVec,
    a_end: CellVec,
    a_valid: bool,
    /// a_start is stale only at the blocks in `a_fix` (switched since it was valid:
    /// a switch changes its block's own equation, not any u), and was valid at time
    /// `a_time` (NaN: unknown): then only those blocks are recomputed (the same bits).
    /// Not in a checkpoint: a restored engine recomputes them all.
    a_partial: bool,
    a_fix: Vec<usize>,
    a_time: f64,
    u0: CellVec,
    w0: CellVec,
    stuck_sum: f64,
    n_stuck: usize,
    stuck_loader: f64,
    /// Largest loader stiffness (phi of a stuck block among stuck ones rises at most at
    /// this times v).
    max_loader: f64,
    /// Event sources (`sources::SOURCES`): the triggers first.
    sources: Vec<Box<dyn Source>>,
    snap_times: Vec<f64>,
    snap_every: usize,
    /// Event catalog and slip records.
    pub catalog: Catalog,
    /// Energy flows.
    pub ledger: Ledger,
    /// Snapshots taken.
    pub snapshots: Snapshots,
    /// Work counters.
    pub counters: Counters,
    need_check: bool,
    full_check: bool,
    /// Run limits (not part of the state): slips in and duration of one event, work per
    /// `run` call.
    event_slip_limit: usize,
    event_duration_limit: f64,
    chunk_work: u64,
    /// Wall time per `run` call in seconds (infinite: no bound), and the snapshot values
    /// written in the current call (counted as work); neither is part of the state.
    chunk_wall: f64,
    snap_work: u64,
    /// Work lists reused from step to step (not part of the state).
    scratch: Scratch,
    /// The dead scratch given back (release.rs; not part of the state).
    release: release::Release,
}

/// Lists the step loop fills and empties again every step: kept so that no step
/// allocates.
#[derive(Debug, Clone, Default)]
struct Scratch {
    /// Blocks of a run that may come to rest in the step.
    cands: Vec<usize>,
    /// The events at the earliest located time: (block, 0 rest / +1, -1 slip).
    who: Vec<(usize, i8)>,
    /// Settling: blocks to test, blocks back at rest, blocks that changed.
    test: Vec<usize>,
    rest: Vec<usize>,
    changed: Vec<usize>,
}

/// The chain simulator: the engine on a line of blocks.
pub type Chain<F, M = Uniform> = Engine<Line, F, M>;

impl<F: Friction> Engine<Line, F, Uniform> {
    /// A chain of `u0.len()` alike blocks with displacements `u0` and velocities `u_t0`
    /// (default v: all stuck). Blocks with u_t != v start sliding; blocks over a
    /// static threshold slip at t = 0.
    pub fn new(
        cfg: ChainConfig,
        friction: F,
        boundary: &dyn Boundary,
        u0: &[f64],
        u_t0: Option<&[f64]>,
    ) -> Result<Self> {
        Chain::with_medium(cfg, friction, Uniform, boundary, u0, u_t0)
    }
}

impl<F: Friction, M: Medium> Engine<Line, F, M> {
    /// A chain of `u0.len()` blocks with the per-block properties `medium` (see
    /// [`Chain::new`]; the medium must have been built for this many blocks).
    pub fn with_medium(
        cfg: ChainConfig,
        friction: F,
        medium: M,
        boundary: &dyn Boundary,
        u0: &[f64],
        u_t0: Option<&[f64]>,
    ) -> Result<Self> {
        if u0.is_empty() {
            return Err(Error::InvalidParameter {
                name: "n",
                value: 0.0,
                allowed: "n >= 1 blocks",
            });
        }
        check_open("dx", cfg.dx, 0.0, f64::INFINITY, "dx > 0")?;
        let geo = Line::new(u0.len(), cfg.dx, boundary.left(), boundary.right());
        Engine::build(geo, cfg, friction, medium, boundary.name(), u0, u_t0)
    }
}

impl<G: Geometry, F: Friction, M: Medium> Engine<G, F, M> {
    /// The engine on the geometry `geo` (its blocks, spacings and ghosts checked by the
    /// caller), blocks with displacements `u0` and velocities `u_t0` in block order.
    pub(crate) fn build(
        geo: G,
        cfg: ChainConfig,
        friction: F,
        medium: M,
        boundary_name: &'static str,
        u0: &[f64],
        u_t0: Option<&[f64]>,
    ) -> Result<Self> {
        let n = geo.n();
        check_at_least("v", cfg.v, 0.0, "v >= 0")?;
        check_open("step", cfg.step, 0.0, 1.0, "0 < step < 1 (time step / dx)")?;
        // the step: a fraction of dx, and of the law's own time scale if it has one
        // (m_min v_f/theta_max for velocity weakening; none for Coulomb: h = step dx)
        let m_min = geo
            .blocks()
            .map(|p| medium.mass(p))
            .fold(f64::INFINITY, f64::min);
        // (the midpoint rule, and RK4 under step-size control, step a stiff law's onset
        // with h_law for every block; RK4 at its fixed step keeps step dx and gives the
        // blocks in their onset their own sub-steps: onset.rs)
        let h_law = cfg.step
            * geo
                .spacing()
                .min(friction.time_scale(medium.max_threshold()) * m_min);
        let h_coarse = cfg.step * geo.spacing();
        // RK4 stability: |h lambda| < 2.78 on the imaginary axis; the fastest mode of a
        // sliding run has |lambda| <= max_i sqrt((k_p,i + 2 sum_bonds k_c/d^2)/m_i)
        // (Gershgorin; sqrt(1 + 4/dx^2) for alike blocks in a chain, sqrt(1 + 4/dx^2 +
        // 4/dy^2) in a lattice) plus max |dR/ds|/m (damping).
        let (mut elastic, mut inv_m): (f64, f64) = (0.0, 0.0);
        for p in geo.blocks() {
            let stiff = medium.loader(p) + 2.0 * geo.stiffness(&medium, p);
            elastic = elastic.max((stiff * medium.inv_mass(p)).sqrt());
            inv_m = inv_m.max(medium.inv_mass(p));
        }
        let damping = friction.max_slope(medium.max_threshold()) * inv_m;
        let lam = elastic + damping;
        // the blocks left in the runs have a weakening rate below 1/dx (onset.rs), so
        // their fastest rate is elastic + max|dR/ds| without the weakening + 1/dx
        let lam_coarse = elastic + friction.max_slope(0.0) * inv_m + 1.0 / geo.spacing();
        // (sub-steps pay only where the law's step is much shorter than dx: for
        // m v_f/theta >= dx/ONSET_GAIN every block steps at h_law as before)
        let stiff_ok = h_law * ONSET_GAIN < h_coarse && h_coarse * lam_coarse <= 2.5;
        let h = if stiff_ok { h_coarse } else { h_law };
        if h_law * lam > 2.5 || lam.is_nan() {
            return Err(Error::InvalidParameter {
                name: "step",
                value: cfg.step,
                allowed: "step * dx * (fastest rate of a sliding block: sqrt(1 + 4/dx^2) + \
                          2 gamma for alike Coulomb blocks in a chain, sqrt(1 + 4/dx^2 + \
                          4/dy^2) + 2 gamma in a lattice) <= 2.5 (RK4 stability)",
            });
        }
        if u0.len() != n {
            return Err(Error::InvalidParameter {
                name: "u0",
                value: u0.len() as f64,
                allowed: "one displacement per block",
            });
        }
        for &x in u0 {
            if !x.is_finite() {
                return Err(Error::InvalidParameter {
                    name: "u0",
                    value: x,
                    allowed: "finite values",
                });
            }
        }
        let len = geo.cells();
        let mut st = State::with_geometry(geo, u0, cfg.v);
        if let Some(w) = u_t0 {
            if w.len() != n {
                return Err(Error::InvalidParameter {
                    name: "u_t0",
                    value: w.len() as f64,
                    allowed: "one velocity per block (same length as u0)",
                });
            }
            for (i, &x) in w.iter().enumerate() {
                if !x.is_finite() {
                    return Err(Error::InvalidParameter {
                        name: "u_t0",
                        value: x,
                        allowed: "finite values",
                    });
                }
                let p = st.geo.padded(i);
                if x > cfg.v && friction.lower(medium.threshold(p)) == f64::NEG_INFINITY {
                    return Err(Error::InvalidParameter {
                        name: "u_t0",
                        value: x,
                        allowed: "u_t0 <= v: without backward slip (beta = inf) no block \
                                  moves backward over the ground",
                    });
                }
                st.w[p] = x;
            }
        }
        let max_loader = st
            .geo
            .blocks()
            .map(|p| medium.loader(p))
            .fold(0.0, f64::max);
        let mut ch = Engine {
            cfg,
            blk: Blocks {
                fr: friction,
                med: medium,
            },
            boundary_name,
            rk: Stepper::new(Method::Rk4, len),
            simd: Simd::detect(),
            queue: SlipQueue::new(len),
            t: 0.0,
            h,
            h_stable: 2.5 / lam,
            midpoint_contraction: 0.25 * h_law * h_law * elastic * elastic + 0.5 * h_law * damping,
            control: None,
            stiff: stiff_ok,
            sub_steps: stiff_ok,
            h_law,
            onset: onset::Onset::default(),
            local: local_events::Local::default(),
            a_start: CellVec::new(len, 0.0),
            a_end: CellVec::new(len, 0.0),
            a_valid: false,
            a_partial: false,
            a_fix: Vec::new(),
            a_time: f64::NAN,
            u0: CellVec::new(len, 0.0),
            w0: CellVec::new(len, 0.0),
            stuck_sum: 0.0,
            n_stuck: n,
            stuck_loader: 0.0,
            max_loader,
            sources: vec![Box::new(sources::triggers::Triggers::default())],
            snap_times: Vec::new(),
            snap_every: 0,
            catalog: Catalog::new(n),
            ledger: Ledger::default(),
            snapshots: Snapshots::default(),
            counters: Counters::default(),
            need_check: true,
            full_check: true,
            event_slip_limit: usize::MAX,
            event_duration_limit: f64::INFINITY,
            chunk_work: u64::MAX,
            chunk_wall: f64::INFINITY,
            snap_work: 0,
            scratch: Scratch::default(),
            release: release::Release::default(),
            st,
        };
        if len >= release::RELEASE_FROM {
            ch.set_release(true);
        }
        let blocks: Vec<usize> = ch.st.geo.blocks().collect();
        for (k, &p) in blocks.iter().enumerate() {
            ch.stuck_sum += ch.blk.med.loader(p) * u0[k];
            ch.stuck_loader += ch.blk.med.loader(p);
        }
        for &p in &blocks {
            let w = ch.st.w[p];
            if w != ch.cfg.v {
                let dir = if w < ch.cfg.v { 1 } else { -1 };
                ch.start_sliding(p, dir, Cause::Initial);
            }
        }
        for &p in &blocks {
            ch.refresh_queue(p);
        }
        Ok(ch)
    }

    /// Choose the integrator (before the first run): RK4 (default) or the implicit
    /// midpoint rule, whose energy books close to round-off (order 2; its fixed-point
    /// solve needs step <= 0.5, and a contraction factor (h/2)^2 (1 + 4/dx^2) + h gamma
    /// <= 0.8 for alike Coulomb blocks, so that its 200 passes reach round-off).
    pub fn set_integrator(&mut self, method: Method) -> Result<()> {
        if method == Method::Midpoint && self.control.is_some() {
            return Err(Error::Invalid {
                name: "step_tolerance".to_string(),
                value: "set".to_string(),
                allowed: "step-size control with the rk4 integrator only".to_string(),
            });
        }
        if method == Method::Midpoint && self.cfg.step > 0.5 {
            return Err(Error::InvalidParameter {
                name: "step",
                value: self.cfg.step,
                allowed: "step <= 0.5 with the midpoint integrator",
            });
        }
        if method == Method::Midpoint
            && (self.midpoint_contraction > MIDPOINT_CONTRACTION
                || self.midpoint_contraction.is_nan())
        {
            return Err(Error::InvalidParameter {
                name: "step",
                value: self.cfg.step,
                allowed: "with the midpoint integrator, (h/2)^2 max(stiffness/mass) + (h/2) \
                          max|dR/ds|/mass <= 0.8, h the time step ((step dx/2)^2 \
                          (1 + 4/dx^2) + step dx gamma for alike Coulomb blocks): its \
                          fixed-point solve must contract; a smaller step, or rk4",
            });
        }
        self.rk = Stepper::new(method, self.st.geo.cells());
        self.choose_step();
        self.a_valid = false;
        self.a_partial = false;
        Ok(())
    }

    /// The fixed step and whether the onset takes sub-steps, for the integrator and the
    /// step-size control now chosen: RK4 at its fixed step keeps the step (and the
    /// sub-steps) chosen when built; the midpoint rule and the step-size control step
    /// every block at the law's step h_law (no sub-steps).
    fn choose_step(&mut self) {
        self.stiff = self.sub_steps && self.rk.name() == "rk4" && self.control.is_none();
        self.h = if self.stiff {
            self.cfg.step * self.st.geo.spacing()
        } else {
            self.h_law
        };
    }

    /// Opt-in step-size control (before the first run; `chain/step_control.rs`): with
    /// `Some(tol)` the step grows above `step` dx, up to RK4's stability limit, while the
    /// step's error indicator (max over the sliding blocks of the corrected trapezoid
    /// defect, ~ h^5 u^(5)/720) stays below tol; it never goes below `step` dx. `None`:
    /// the fixed step (the default; the same trajectories bit for bit).
    pub fn set_step_control(&mut self, tol: Option<f64>) -> Result<()> {
        self.control = match tol {
            None => None,
            Some(tol) => {
                if self.rk.name() != "rk4" {
                    return Err(Error::Invalid {
                        name: "step_tolerance".to_string(),
                        value: format!("{tol}"),
                        allowed: "step-size control with the rk4 integrator only".to_string(),
                    });
                }
                // the controller works from the law's step (no sub-steps)
                Some(StepControl::new(tol, self.h_law, self.h_stable)?)
            }
        };
        self.choose_step();
        Ok(())
    }

    /// The step-size control's tolerance (None: the fixed step).
    pub fn step_tolerance(&self) -> Option<f64> {
        self.control.map(|c| c.tol)
    }

    /// Name of the integrator.
    pub fn integrator(&self) -> &'static str {
        self.rk.name()
    }

    /// Current time.
    pub fn time(&self) -> f64 {
        self.t
    }
    /// Number of blocks.
    pub fn n(&self) -> usize {
        self.st.n
    }
    /// Number of sliding blocks.
    pub fn n_sliding(&self) -> usize {
        self.st.n_active
    }
    /// The configuration.
    pub fn config(&self) -> ChainConfig {
        self.cfg
    }
    /// The friction law.
    pub fn friction(&self) -> &F {
        &self.blk.fr
    }
    /// The per-block properties.
    pub fn medium(&self) -> &M {
        &self.blk.med
    }
    /// Name of the boundary condition.
    pub fn boundary_name(&self) -> &'static str {
        self.boundary_name
    }

    /// Displacements u at the current time (0-based).
    pub fn u(&self) -> Vec<f64> {
        self.st
            .geo
            .blocks()
            .map(|p| self.st.value(p, self.t))
            .collect()
    }
    /// Velocities u_t at the current time.
    pub fn u_t(&self) -> Vec<f64> {
        self.st.geo.blocks().map(|p| self.st.w[p]).collect()
    }
    /// Modes (0 stuck, +1 forward, -1 backward) at the current time.
    pub fn modes(&self) -> Vec<i8> {
        self.st.geo.blocks().map(|p| self.st.dir[p] as i8).collect()
    }
    /// phi = u - Lap u/dx^2 at the current time.
    pub fn phi(&self) -> Vec<f64> {
        self.st
            .geo
            .blocks()
            .map(|p| self.blk.phi(&self.st, p, self.t))
            .collect()
    }
    /// The geometry.
    pub fn geometry(&self) -> &G {
        &self.st.geo
    }

    /// The state of the blocks (for tests).
    #[cfg(test)]
    pub(crate) fn state(&self) -> &State<G> {
        &self.st
    }

    /// Energy (kinetic, coupling springs, loader springs) now.
    pub fn energy(&self) -> (f64, f64, f64) {
        energy::energy(&self.st, &self.blk.med, self.beta(), self.t)
    }

    fn beta(&self) -> f64 {
        self.blk.fr.beta()
    }

    /// Schedule a trigger.
    pub fn add_trigger(&mut self, tr: Trigger) -> Result<()> {
        if tr.block >= self.st.n {
            return Err(Error::InvalidParameter {
                name: "trigger block",
                value: tr.block as f64,
                allowed: "0 <= block < n",
            });
        }
        check_at_least("trigger time", tr.t, self.t, "trigger time >= current time")?;
        if let TriggerKind::Kick { du_t } = tr.kind {
            if !du_t.is_finite() {
                return Err(Error::InvalidParameter {
                    name: "kick",
                    value: du_t,
                    allowed: "finite",
                });
            }
        }
        if self.blk.lower(self.st.geo.padded(tr.block)) == f64::NEG_INFINITY {
            let backward = match tr.kind {
                TriggerKind::Kick { du_t } => du_t > 0.0,
                TriggerKind::Release { dir } => dir < 0,
            };
            if backward {
                return Err(Error::InvalidParameter {
                    name: "trigger",
                    value: match tr.kind {
                        TriggerKind::Kick { du_t } => du_t,
                        TriggerKind::Release { dir } => f64::from(dir),
                    },
                    allowed: "forward triggers only (kick du_t <= 0, release direction +1): \
                              without backward slip (beta = inf) no block moves backward",
                });
            }
        }
        self.triggers().push(tr);
        Ok(())
    }

    /// Spontaneous slips of stuck blocks from now on (`sources::noise`): a Poisson process
    /// of rate `law` (per block and unit time; rate g(x), x = 1 - (threshold - phi)), each
    /// a forward kick of speed `kick` over the ground (0: a release), its generator seeded
    /// by `seed`. A zero rate removes the noise (the noiseless engine, bit for bit).
    pub fn set_noise(&mut self, law: NoiseLaw, kick: f64, seed: u64) -> Result<()> {
        let noise = sources::noise::Noise::new(law, kick, seed, self.t)?;
        self.sources.retain(|s| s.as_noise().is_none());
        if noise.law().rate > 0.0 {
            self.sources.push(Box::new(noise));
        }
        Ok(())
    }

    /// (candidates drawn, spontaneous slips) of the noise so far; None without noise.
    pub fn noise_counters(&self) -> Option<(u64, u64)> {
        self.sources
            .iter()
            .find_map(|s| s.as_noise())
            .map(|n| (n.candidates, n.slips))
    }

    /// Ask for snapshots at these times (>= now) and/or at the end of every k-th event.
    pub fn add_snapshots(&mut self, times: &[f64], every_events: usize) -> Result<()> {
        for &t in times {
            check_at_least("snapshot time", t, self.t, "snapshot times >= current time")?;
            self.snap_times.push(t);
        }
        self.snap_times.sort_by(|a, b| b.total_cmp(a));
        self.snap_every = every_events;
        Ok(())
    }

    // ----- mode changes ------------------------------------------------------------

    /// The scheduled triggers (always the first source).
    fn triggers(&mut self) -> &mut sources::triggers::Triggers {
        self.sources[0]
            .as_triggers()
            .expect("the first source is the triggers")
    }

    fn start_sliding(&mut self, p: usize, dir: i8, cause: Cause) {
        let t = self.t;
        let u = self.st.stuck_u(p, t);
        let kp = self.blk.med.loader(p);
        self.stuck_sum -= kp * u;
        self.n_stuck -= 1;
        self.stuck_loader -= kp;
        self.st.u[p] = u;
        self.st.dir[p] = dir as f64;
        self.st.onset[p] = self.blk.med.threshold(p);
        self.st.add_to_runs(p);
        self.catalog.slip(self.st.geo.index(p), t, u, dir, cause);
        self.counters.switches += 1;
        self.switched(p);
    }

    /// Stuck block p crosses its threshold in direction `dir` (a located or due slip):
    /// it slides with the law's onset threshold (see `Friction::onset_threshold`).
    fn slip_at_threshold(&mut self, p: usize, dir: i8) {
        let phi = self.blk.phi(&self.st, p, self.t);
        self.start_sliding(p, dir, Cause::Threshold);
        self.st.onset[p] =
            self.blk
                .fr
                .onset_threshold(self.blk.med.threshold(p), phi, f64::from(dir));
    }

    fn stick(&mut self, p: usize) {
        let t = self.t;
        let s = self.cfg.v - self.st.w[p];
        self.ledger.projection += 0.5 * self.blk.med.mass(p) * s * s;
        self.st.w[p] = self.cfg.v;
        self.st.dir[p] = 0.0;
        self.st.tref[p] = t;
        self.st.remove_from_runs(p);
        let kp = self.blk.med.loader(p);
        self.stuck_sum += kp * self.st.u[p];
        self.n_stuck += 1;
        self.stuck_loader += kp;
        self.catalog
            .stick(self.st.geo.index(p), t, self.st.u[p], self.cfg.v);
        self.counters.switches += 1;
        self.switched(p);
    }

    /// The equation of block p changed (it slipped, stuck, or came to rest and slides
    /// on): its acceleration is stale, and no other's (its u is as it was).
    fn switched(&mut self, p: usize) {
        if self.a_valid {
            self.a_partial = true;
            self.a_fix.clear();
        }
        self.a_valid = false;
        self.a_fix.push(p);
    }

    /// The sliding block p has u_t = v (within the located event): stick or go on.
    /// Returns false when nothing changed: it slides on in the same direction, already at
    /// u_t = v (a block just slipped at its onset threshold, with zero acceleration).
    fn on_rest(&mut self, p: usize) -> bool {
        let phi = self.blk.phi(&self.st, p, self.t);
        // its thresholds: those of the threshold it slides with (its static one, or a
        // hair lower when it slipped there: Friction::onset_threshold)
        let th = self.st.onset[p].min(self.blk.med.threshold(p));
        let (lo, hi) = (self.blk.fr.lower(th), self.blk.fr.upper(th));
        if phi > lo && phi < hi {
            self.stick(p);
        } else {
            let dir = if phi >= hi { 1.0 } else { -1.0 };
            if dir == self.st.dir[p] && self.st.w[p] == self.cfg.v {
                return false;
            }
            // still over a threshold: slide on in the direction of the force
            let s = self.cfg.v - self.st.w[p];
            self.ledger.projection += 0.5 * self.blk.med.mass(p) * s * s;
            self.st.w[p] = self.cfg.v;
            if dir != self.st.dir[p] {
                // reversal: close the slip record and open one in the new direction
                let (u, k) = (self.st.u[p], self.st.geo.index(p));
                self.catalog.stick(k, self.t, u, self.cfg.v);
                self.catalog.slip(k, self.t, u, dir as i8, Cause::Threshold);
                self.counters.switches += 1;
                // a slip at the other threshold
                self.st.onset[p] = self
                    .blk
                    .fr
                    .onset_threshold(self.blk.med.threshold(p), phi, dir);
            }
            self.st.dir[p] = dir;
            self.switched(p);
        }
        true
    }

    /// Re-evaluate the queue entry of real block p and its neighbours.
    fn refresh_around(&mut self, p: usize) {
        self.refresh_queue(p);
        for q in self.st.geo.neighbours(p) {
            if let Some(r) = self.st.resolve(q) {
                self.refresh_queue(r);
            }
        }
    }

    fn refresh_queue(&mut self, p: usize) {
        if self.st.sliding(p) || self.st.has_sliding_neighbour(p) || self.cfg.v <= 0.0 {
            self.queue.invalidate(p);
        } else {
            // phi of a stuck block among stuck ones rises at k_p,i v
            let phi = self.blk.phi(&self.st, p, self.t);
            let rate = self.blk.med.loader(p) * self.cfg.v;
            let dt = ((self.blk.upper(p) - phi) / rate).max(0.0);
            self.queue.push(p, self.t + dt);
        }
    }

    // ----- settling: events due now ---------------------------------------------------

    /// Apply every switch due at the current time until none is left. With `wall`
    /// (the start of a call bounded by [`Chain::set_chunk_wall`]) it stops between two
    /// rounds once that time is spent and returns false: a cascade through a uniform
    /// chain slips one more block a round, each round over every sliding block (n^2/2
    /// an event); the next call settles on from the same state.
    fn settle(&mut self, wall: Option<std::time::Instant>) -> Result<bool> {
        let t = self.t;
        let mut rounds = 0usize;
        loop {
            rounds += 1;
            if rounds > 4 * self.st.n + 16 {
                return Err(Error::NoConvergence {
                    what: "chain event settling",
                    detail: format!("switches did not settle at t = {t}"),
                });
            }
            let mut changed = std::mem::take(&mut self.scratch.changed);
            changed.clear();
            // stuck blocks over a threshold: all of them on a full check, else the
            // neighbours of the runs
            let mut cands = std::mem::take(&mut self.scratch.test);
            cands.clear();
            if self.full_check {
                let st = &self.st;
                cands.extend(st.geo.blocks().filter(|&p| !st.sliding(p)));
            } else if G::FRONTIER {
                // the stuck blocks next to the runs from their lists, those over a
                // threshold in the order the walk around the runs meets them
                // (frontier.rs: the same bits as the walk)
                let st = &self.st;
                let mut over: Vec<((usize, usize), usize)> = Vec::new();
                for p in st.frontier.stuck_blocks(&st.dir) {
                    let phi = self.blk.phi(st, p, t);
                    if phi >= self.blk.upper(p) || phi <= self.blk.lower(p) {
                        let key = frontier::walk_order(&st.geo, &st.runs, p);
                        over.push((key.unwrap_or((usize::MAX, 0)), p));
                    }
                }
                over.sort_unstable();
                over.dedup();
                cands.extend(over.iter().map(|&(_, p)| p));
            } else {
                let st = &self.st;
                for &(a, b) in &st.runs {
                    for (q, _, _) in st.geo.around_run(a, b) {
                        if let Some(r) = st.resolve(q) {
                            if !st.sliding(r) {
                                cands.push(r);
                            }
                        }
                    }
                }
            }
            for &p in &cands {
                if self.st.sliding(p) {
                    continue;
                }
                let phi = self.blk.phi(&self.st, p, t);
                if phi >= self.blk.upper(p) {
                    self.slip_at_threshold(p, 1);
                    changed.push(p);
                } else if phi <= self.blk.lower(p) {
                    self.slip_at_threshold(p, -1);
                    changed.push(p);
                }
            }
            self.scratch.test = cands;
            // sliding blocks back at rest
            let mut rest = std::mem::take(&mut self.scratch.rest);
            rest.clear();
            let mut maybe = std::mem::take(&mut self.scratch.cands);
            for &(a, b) in &self.st.runs {
                // (a vectorised pre-test: u_t at or past v, in the run's order)
                maybe.clear();
                let (dir, w) = (&self.st.dir[a..b], &self.st.w[a..b]);
                events::at_rest_candidates(self.simd, dir, w, self.cfg.v, &mut maybe);
                for &i in &maybe {
                    let p = a + i;
                    let g = self.st.dir[p] * (self.st.w[p] - self.cfg.v);
                    if g > 0.0 || (g == 0.0 && self.st.dir[p] * self.accel_of(p) >= 0.0) {
                        rest.push(p);
                    }
                }
            }
            self.scratch.cands = maybe;
            for &p in &rest {
                if self.st.sliding(p) && self.on_rest(p) {
                    changed.push(p);
                }
            }
            self.scratch.rest = rest;
            self.full_check = false;
            let done = changed.is_empty();
            for &p in &changed {
                self.refresh_around(p);
            }
            self.scratch.changed = changed;
            if done {
                break;
            }
            if let Some(started) = wall {
                if self.wall_spent(rounds as u64, started) {
                    return Ok(false);
                }
            }
        }
        if self.st.n_active == 0 {
            self.close_event();
        }
        Ok(true)
    }

    fn close_event(&mut self) {
        if !self.catalog.event_open() {
            return;
        }
        let st = &self.st;
        let t = self.t;
        self.catalog.quiet(t, |i| st.stuck_u(st.geo.padded(i), t));
        let k = self.catalog.finished();
        if self.snap_every > 0 && k % self.snap_every == 0 {
            self.snapshot_now();
        }
    }

    /// Acceleration of sliding block p at the current time.
    fn accel_of(&self, p: usize) -> f64 {
        let phi = self.blk.phi(&self.st, p, self.t);
        let s = self.cfg.v - self.st.w[p];
        (-phi + self.blk.fr.excess(s, self.st.dir[p], self.st.onset[p])) * self.blk.med.inv_mass(p)
    }

    fn snapshot_now(&mut self) {
        self.snap_work += self.st.n as u64;
        self.snapshots.t.push(self.t);
        self.snapshots.u.push(self.u());
        self.snapshots.u_t.push(self.u_t());
    }

    /// Hermite data of the displacement of real block r over the last step [t0, t1].
    #[inline(always)]
    fn herm_u(&self, r: usize, t0: f64, t1: f64) -> Hermite {
        if self.st.sliding(r) {
            Hermite {
                g0: self.u0[r],
                m0: self.w0[r],
                g1: self.st.u[r],
                m1: self.st.w[r],
            }
        } else {
            let v = self.cfg.v;
            Hermite {
                g0: self.st.stuck_u(r, t0),
                m0: v,
                g1: self.st.stuck_u(r, t1),
                m1: v,
            }
        }
    }

    /// Hermite data of the neighbour at padded index q of stuck block p.
    #[inline(always)]
    fn herm_neighbour(&self, q: usize, p: usize, t0: f64, t1: f64) -> Hermite {
        if self.st.geo.is_ghost(q) {
            match self.st.beyond(q, p) {
                Beyond::Block(r) => self.herm_u(r, t0, t1),
                Beyond::Wall(g0) => {
                    let v = self.cfg.v;
                    Hermite {
                        g0: g0 + v * t0,
                        m0: v,
                        g1: g0 + v * t1,
                        m1: v,
                    }
                }
            }
        } else {
            self.herm_u(q, t0, t1)
        }
    }

    /// Earliest event in the step just taken: its s in (0, 1] (infinity if none), the
    /// events at that s left in `who` (`cands` is a work list).
    /// Blocks in `skip` (integrated with their own sub-steps, onset.rs) are not tested
    /// for rest here.
    fn detect(
        &self,
        t0: f64,
        h: f64,
        cands: &mut Vec<usize>,
        who: &mut Vec<(usize, i8)>,
        skip: &[usize],
    ) -> f64 {
        let v = self.cfg.v;
        let mut best = f64::INFINITY;
        who.clear();
        for &(a, b) in &self.st.runs {
            // the blocks that may come to rest in the step (a vectorised cheap test)
            cands.clear();
            events::rest_candidates(
                self.simd,
                &self.st.dir[a..b],
                &self.w0[a..b],
                &self.st.w[a..b],
                &self.a_start[a..b],
                &self.a_end[a..b],
                v,
                h,
                cands,
            );
            for &i in cands.iter() {
                let p = a + i;
                if skip.contains(&p) {
                    continue;
                }
                let d = self.st.dir[p];
                let g = Hermite {
                    g0: d * (self.w0[p] - v),
                    m0: d * self.a_start[p],
                    g1: d * (self.st.w[p] - v),
                    m1: d * self.a_end[p],
                };
                // at rest to round-off over the whole step (v + u_tt h == v: a step much
                // shorter than ulp(v)/|u_tt|) and pushed away from rest at both ends: the
                // cubic's bump above zero comes from the rounded end value, not from the
                // motion (u_t moves away from v monotonically); no crossing. Counting it
                // halved such a step for ever (a kept-sliding block at rest again at the
                // bump, t never reaching a t_end of 1e-30).
                if g.g0 == 0.0 && g.g1 == 0.0 && g.m0 <= 0.0 && g.m1 <= 0.0 {
                    continue;
                }
                consider(g.first_crossing(h), (p, 0), &mut best, who);
            }
            if G::FRONTIER {
                continue;
            }
            for (q, _, _) in self.st.geo.around_run(a, b) {
                let Some(p) = self.st.resolve(q) else {
                    continue;
                };
                if !self.st.sliding(p) {
                    self.slip_crossing(p, t0, h, &mut best, who);
                }
            }
        }
        if G::FRONTIER {
            // the stuck blocks next to the runs from their lists (frontier.rs); the
            // events at the earliest time in the order of the walk (the same bits)
            for p in self.st.frontier.stuck_blocks(&self.st.dir) {
                self.slip_crossing(p, t0, h, &mut best, who);
            }
            if best.is_finite() && who.len() > 1 {
                let st = &self.st;
                who.sort_by_cached_key(|&(p, kind)| {
                    if kind == 0 {
                        let (a, _) = frontier::run_of(&st.runs, p).unwrap_or((usize::MAX, 0));
                        (a, 0, p.wrapping_sub(a), 0)
                    } else {
                        let (a, pos) =
                            frontier::walk_order(&st.geo, &st.runs, p).unwrap_or((usize::MAX, 0));
                        (a, 1, pos, u8::from(kind < 0))
                    }
                });
            }
        }
        if !best.is_finite() {
            who.clear();
        }
        best
    }

    /// The crossings of its thresholds by the phi of stuck block p in the step of length
    /// h from t0 (forward, then backward), offered to the earliest events so far.
    #[inline(always)]
    fn slip_crossing(&self, p: usize, t0: f64, h: f64, best: &mut f64, who: &mut Vec<(usize, i8)>) {
        let t1 = t0 + h;
        let up = self.herm_u(p, t0, t1);
        let phi = self.st.geo.phi_hermite(
            &self.blk.med,
            p,
            up,
            #[inline(always)]
            |q| self.herm_neighbour(q, p, t0, t1),
        );
        let (lo, hi) = (self.blk.lower(p), self.blk.upper(p));
        let fwd = Hermite {
            g0: phi.g0 - hi,
            m0: phi.m0,
            g1: phi.g1 - hi,
            m1: phi.m1,
        };
        consider(fwd.first_crossing(h), (p, 1), best, who);
        let bwd = Hermite {
            g0: lo - phi.g0,
            m0: -phi.m0,
            g1: lo - phi.g1,
            m1: -phi.m1,
        };
        consider(bwd.first_crossing(h), (p, -1), best, who);
    }

    /// Snapshots due in (t0, t0 + h] from the dense output of the last step.
    fn dense_snapshots(&mut self, t0: f64, h: f64) {
        let t1 = t0 + h;
        while let Some(&ts) = self.snap_times.last() {
            if ts > t1 {
                break;
            }
            self.snap_times.pop();
            let s = if h > 0.0 {
                ((ts - t0) / h).clamp(0.0, 1.0)
            } else {
                1.0
            };
            let n = self.st.n;
            let mut u = Vec::with_capacity(n);
            let mut w = Vec::with_capacity(n);
            for p in self.st.geo.blocks() {
                if let Some((ou, ow)) = self.onset_dense(p, ts).or_else(|| self.local_dense(p, ts))
                {
                    // a block in its onset: its own dense output
                    u.push(ou);
                    w.push(ow);
                } else if self.st.sliding(p) {
                    let hu = self.herm_u(p, t0, t1);
                    let hw = Hermite {
                        g0: self.w0[p],
                        m0: self.a_start[p],
                        g1: self.st.w[p],
                        m1: self.a_end[p],
                    };
                    u.push(hu.eval(s, h));
                    w.push(hw.eval(s, h));
                } else {
                    u.push(self.st.stuck_u(p, ts));
                    w.push(self.cfg.v);
                }
            }
            self.snap_work += n as u64;
            self.snapshots.t.push(ts);
            self.snapshots.u.push(u);
            self.snapshots.u_t.push(w);
        }
    }

    /// Snapshots due in (t, t_next] while everything is stuck (exact): all of them, or
    /// (returning false) as many as `budget` values of work allow, at least one; the
    /// rest are taken by the next call (a stuck block's u depends on the time only, so
    /// this is exact wherever the cut falls).
    fn quiet_snapshots(&mut self, t_next: f64, budget: u64) -> bool {
        let first = self.snap_work;
        while let Some(&ts) = self.snap_times.last() {
            if ts > t_next {
                break;
            }
            if self.snap_work > first && self.snap_work - first >= budget {
                return false;
            }
            self.snap_times.pop();
            self.snap_work += self.st.n as u64;
            self.snapshots.t.push(ts);
            self.snapshots.u.push(
                self.st
                    .geo
                    .blocks()
                    .map(|p| self.st.stuck_u(p, ts))
                    .collect(),
            );
            self.snapshots.u_t.push(vec![self.cfg.v; self.st.n]);
        }
        true
    }

    fn apply_trigger(&mut self, tr: Trigger, cause: Cause) {
        let p = self.st.geo.padded(tr.block);
        let v = self.cfg.v;
        match tr.kind {
            TriggerKind::Release { dir } => {
                if !self.st.sliding(p) {
                    self.start_sliding(p, if dir >= 0 { 1 } else { -1 }, cause);
                }
            }
            TriggerKind::Kick { du_t } => {
                let s_old = v - self.st.w[p];
                let w_new = self.st.w[p] + du_t;
                let s_new = v - w_new;
                self.ledger.injected +=
                    0.5 * self.blk.med.mass(p) * (s_new * s_new - s_old * s_old);
                if !self.st.sliding(p) {
                    if w_new == v {
                        return;
                    }
                    self.start_sliding(p, if w_new < v { 1 } else { -1 }, cause);
                }
                self.st.w[p] = w_new;
                self.a_valid = false;
                self.a_partial = false;
            }
        }
        self.refresh_around(p);
    }

    /// Limits of [`Chain::run`]: it returns [`Stop::LongEvent`] when the running event
    /// has more than `event_slips` slips or has lasted longer than `event_duration`, and
    /// [`Stop::Steps`] once a call has done `chunk_work` units of work (one per step plus
    /// one per sliding block per step, redone partial steps included), so a call on a
    /// large sliding chain hands control back as soon as one on a small one. Defaults:
    /// no limits. Limits are not part of the state (checkpoints omit them).
    pub fn set_run_limits(&mut self, event_slips: usize, event_duration: f64, chunk_work: u64) {
        self.event_slip_limit = event_slips;
        self.event_duration_limit = if event_duration.is_nan() {
            f64::INFINITY
        } else {
            event_duration
        };
        self.chunk_work = chunk_work.max(1);
    }

    /// Bound the wall time of one [`Chain::run`] call: it returns [`Stop::Steps`] once
    /// `seconds` have passed (checked every few steps, after at least one step, jump or
    /// snapshot), so that the caller answers an interrupt promptly however the work of
    /// a step varies. Infinite (the default): no bound. Returning there changes nothing
    /// in the results (the next call continues exactly), but where it returns depends on
    /// the machine.
    pub fn set_chunk_wall(&mut self, seconds: f64) {
        self.chunk_wall = if seconds > 0.0 {
            seconds
        } else {
            f64::INFINITY
        };
    }

    /// The snapshots taken so far, handed over and no longer kept (a long run's
    /// snapshots are written out as they come instead of accumulating).
    pub fn take_snapshots(&mut self) -> Snapshots {
        std::mem::take(&mut self.snapshots)
    }

    /// Slips and duration so far of the running event (None when none is running).
    pub fn open_event(&self) -> Option<(usize, f64)> {
        if !self.catalog.event_open() {
            return None;
        }
        let e = self.catalog.events.last()?;
        Some((e.n_slips, self.t - e.t_start))
    }

    /// Work counted against `chunk_work`: integration steps plus block-steps (redone
    /// partial steps included), as in [`Counters`].
    fn work_done(&self) -> u64 {
        self.counters.steps + self.counters.block_steps
    }

    /// Advance to `t_end`, or until `max_events` more events have finished, or at most
    /// `max_steps` integration steps in this call (to hand control back for progress
    /// reports and interrupts; call again to continue), or until the work or event-slip
    /// limits of [`Chain::set_run_limits`] are reached.
    pub fn run(&mut self, t_end: f64, max_events: usize, max_steps: u64) -> Result<Stop> {
        if t_end.is_nan() || t_end < self.t {
            return Err(Error::InvalidParameter {
                name: "t_end",
                value: t_end,
                allowed: "t_end >= current time",
            });
        }
        let target_events = self.catalog.finished().saturating_add(max_events);
        let mut steps = 0u64;
        let work0 = self.work_done();
        self.snap_work = 0;
        let started = std::time::Instant::now();
        let mut passes = 0u32;
        let mut jumps = 0u64;
        // switches applied at one instant (sources fired, threshold slips popped): a
        // uniform chain's blocks slip one by one at the same time, each followed by a
        // settle over the sliding runs (n^2/2 block visits an event), with no step
        // between them: the wall bound is checked among them too
        let mut acts = 0u64;
        loop {
            if self.need_check {
                if !self.settle(Some(started))? {
                    return Ok(Stop::Steps);
                }
                self.need_check = false;
            }
            if self.catalog.finished() >= target_events {
                return Ok(Stop::Events);
            }
            // the sources: one due now acts (in registry order); else the earliest time
            let (due, t_source) = self.next_source();
            if let Some(k) = due {
                let mut srcs = std::mem::take(&mut self.sources);
                let fired = srcs[k].fire(self);
                let kind = srcs[k].kind();
                self.sources = srcs;
                if let Some(tr) = fired {
                    self.apply_trigger(tr, Cause::Source(kind));
                    self.need_check = true;
                }
                acts += 1;
                if self.wall_spent(acts, started) {
                    return Ok(Stop::Steps);
                }
                continue;
            }
            let tq = self.queue.peek().map_or(f64::INFINITY, |(t, _)| t);
            if tq <= self.t {
                // every block due now slips before any neighbourhood is refreshed: the
                // closed-form time puts phi at its threshold only to round-off (1 - ulp
                // as often as 1), so a block due at this instant whose neighbour slipped
                // first, re-tested by its phi in the settling, could be left stuck and
                // found again in the next step, a few ulps of t later (the twins of a
                // lattice uniform across y split so; docs/lattice.md, "Ties")
                let mut due = std::mem::take(&mut self.scratch.changed);
                due.clear();
                while let Some((tp, p)) = self.queue.peek() {
                    if tp > self.t {
                        break;
                    }
                    self.queue.pop();
                    due.push(p);
                }
                for &p in &due {
                    self.slip_at_threshold(p, 1);
                }
                for &p in &due {
                    self.refresh_around(p);
                }
                self.scratch.changed = due;
                self.need_check = true;
                acts += 1;
                if self.wall_spent(acts, started) {
                    return Ok(Stop::Steps);
                }
                continue;
            }
            if self.t >= t_end {
                self.quiet_or_dense_tail();
                return Ok(Stop::Time);
            }
            let work = self.work_done() - work0 + self.snap_work;
            if steps >= max_steps || work >= self.chunk_work {
                return Ok(Stop::Steps);
            }
            passes = passes.wrapping_add(1);
            if self.chunk_wall.is_finite()
                && passes % 16 == 0
                && (steps > 0 || jumps > 0 || self.snap_work > 0)
                && started.elapsed().as_secs_f64() >= self.chunk_wall
            {
                return Ok(Stop::Steps);
            }
            if let Some((slips, duration)) = self.open_event() {
                if slips > self.event_slip_limit || duration > self.event_duration_limit {
                    return Ok(Stop::LongEvent);
                }
            }
            let t_next = tq.min(t_source).min(t_end);
            if self.st.n_active == 0 {
                // quiet: everything drifts exactly; jump (once the snapshots on the way
                // are taken: as many as the work budget allows per call)
                if !self.quiet_snapshots(t_next, self.chunk_work.saturating_sub(work)) {
                    return Ok(Stop::Steps);
                }
                let dt = t_next - self.t;
                self.ledger.load += self.cfg.v
                    * dt
                    * (self.stuck_sum
                        + 0.5 * self.cfg.v * dt * self.stuck_loader
                        + self.beta() * self.st.n as f64);
                self.stuck_sum += self.cfg.v * dt * self.stuck_loader;
                self.t = t_next;
                self.counters.jumps += 1;
                self.release_quiet();
                jumps += 1;
                continue;
            }
            steps += 1;
            self.integrate_step(t_next)?;
        }
    }

    /// Whether a call that has applied `acts` switches at one instant has used its wall
    /// time ([`Chain::set_chunk_wall`]; checked every 8th: each is followed by a settle).
    /// The state between two of them is a loop state like any other (`need_check` set,
    /// checkpointed): the next call goes on exactly where this one stopped.
    fn wall_spent(&self, acts: u64, started: std::time::Instant) -> bool {
        self.chunk_wall.is_finite()
            && acts % 8 == 0
            && started.elapsed().as_secs_f64() >= self.chunk_wall
    }

    /// The first source due now (if any), else the earliest time a source acts.
    fn next_source(&mut self) -> (Option<usize>, f64) {
        let mut srcs = std::mem::take(&mut self.sources);
        let mut earliest = f64::INFINITY;
        let mut due = None;
        for (k, s) in srcs.iter_mut().enumerate() {
            let ts = s.next_time(self);
            if ts <= self.t {
                due = Some(k);
                break;
            }
            earliest = earliest.min(ts);
        }
        self.sources = srcs;
        (due, earliest)
    }

    fn quiet_or_dense_tail(&mut self) {
        // snapshots requested exactly at the current time
        if self.st.n_active == 0 {
            self.quiet_snapshots(self.t, u64::MAX);
        } else {
            let t = self.t;
            while let Some(&ts) = self.snap_times.last() {
                if ts > t {
                    break;
                }
                self.snap_times.pop();
                self.snap_work += self.st.n as u64;
                self.snapshots.t.push(t);
                self.snapshots.u.push(self.u());
                self.snapshots.u_t.push(self.u_t());
            }
        }
    }

    /// One step (capped at t_cap), with event location and a redo up to the event.
    fn integrate_step(&mut self, t_cap: f64) -> Result<()> {
        self.release_tick();
        let t0 = self.t;
        let mut h = self.h.min(t_cap - t0);
        if let Some(c) = self.control.as_mut() {
            // after a switch or a kick: back to the fixed step
            if !self.a_valid || self.counters.switches != c.switches_seen {
                c.reset();
            }
            h = c.h.min(t_cap - t0);
        }
        if !self.a_valid {
            let mut a = std::mem::take(&mut self.a_start);
            if self.a_partial && self.a_time == t0 && self.st.ext.is_empty() {
                // only switches since a_start was valid at t0: their blocks and their
                // neighbours (these for safety: their values are unchanged)
                let mut fix = std::mem::take(&mut self.a_fix);
                let k = fix.len();
                for i in 0..k {
                    for q in self.st.geo.neighbours(fix[i]) {
                        if let Some(r) = self.st.resolve(q) {
                            fix.push(r);
                        }
                    }
                }
                self.rk.accel_at(&self.st, &self.blk, t0, &fix, &mut a);
                fix.clear();
                self.a_fix = fix;
            } else {
                self.rk.accel_only(&mut self.st, &self.blk, t0, &mut a);
            }
            self.a_start = a;
            self.a_valid = true;
            self.a_partial = false;
            self.a_time = t0;
        }
        if self.local_active() && self.local_step(t0, h, t_cap)? {
            // local events (local_events.rs); false: this step takes the global cut
            return Ok(());
        }
        if self.stiff {
            // blocks in their stiff onset at the start: their own sub-steps (onset.rs)
            self.onset.blocks.clear();
            if self.onset_patch(h, false) {
                return self.onset_step(t0, h, t_cap);
            }
        }
        self.do_step(t0, h, false);
        self.check_solved(t0)?;
        if self.stiff && self.onset_patch(h, true) {
            // a block came into the stiff range in the step (about to stick): redo it
            self.onset.stats.turned_block_steps += self.st.n_active as u64;
            self.restore_runs();
            return self.onset_step(t0, h, t_cap);
        }
        let mut indicator = None;
        // (at the fixed step the indicator only decides whether to grow: every 4th step)
        let indicate = |c: &StepControl, steps: u64| h > c.h_min || steps % 4 == 0;
        if let Some(c) = self.control.filter(|c| indicate(c, self.counters.steps)) {
            let mut d = self.step_indicator(h);
            if d > c.tol && h > c.h_min {
                // too long: redo it at the fixed step
                h = c.h_min.min(t_cap - t0);
                self.do_step(t0, h, true);
                d = self.step_indicator(h);
            }
            indicator = Some(d);
        }
        let (mut cands, mut events) = (
            std::mem::take(&mut self.scratch.cands),
            std::mem::take(&mut self.scratch.who),
        );
        let s = self.detect(t0, h, &mut cands, &mut events, &[]);
        self.scratch.cands = cands;
        // (s = infinity: no event in the step; s = 1: at its end, nothing to redo)
        if s < 1.0 {
            // redo the step up to the event
            h *= s;
            self.do_step(t0, h, true);
            self.check_solved(t0)?;
        }
        // the energy flows of the step taken, once (not in the stages, not for a redo)
        let integ = self.rk.books(&self.st, &self.blk, &self.w0, h);
        self.finish_step(t0, h, t_cap, integ, events, indicator)?;
        // the end accelerations (now a_start) are those of the state at t0 + h
        self.a_time = t0 + h;
        Ok(())
    }

    /// The end of a step of length h taken from t0 (capped at t_cap): the books, the
    /// snapshots in it, the clock, and the events located at its end.
    fn finish_step(
        &mut self,
        t0: f64,
        h: f64,
        t_cap: f64,
        integ: integrator::StepIntegrals,
        events: Vec<(usize, i8)>,
        indicator: Option<f64>,
    ) -> Result<()> {
        if !(integ.u.is_finite() && integ.dry.is_finite() && integ.visc.is_finite()) {
            return Err(Error::NoConvergence {
                what: "chain integration",
                detail: format!(
                    "non-finite state at t = {t0} (a kick or initial velocity too large for \
                     step = {}?)",
                    self.cfg.step
                ),
            });
        }
        // books
        self.ledger.load += self.cfg.v
            * (integ.u
                + h * (self.stuck_sum
                    + 0.5 * self.cfg.v * h * self.stuck_loader
                    + self.beta() * self.st.n as f64));
        self.stuck_sum += self.cfg.v * h * self.stuck_loader;
        self.ledger.dry += integ.dry;
        self.ledger.viscous += integ.visc;
        self.dense_snapshots(t0, h);
        self.t = if t0 + h >= t_cap { t_cap } else { t0 + h };
        // the end accelerations become the next start ones
        std::mem::swap(&mut self.a_start, &mut self.a_end);
        self.a_valid = true;
        self.a_time = f64::NAN;
        if !events.is_empty() {
            for &(p, kind) in &events {
                if kind == 0 {
                    if self.st.sliding(p) {
                        self.on_rest(p);
                    }
                } else if !self.st.sliding(p) {
                    self.slip_at_threshold(p, kind);
                }
                self.refresh_around(p);
            }
            self.need_check = true;
        }
        if let Some(c) = self.control.as_mut() {
            if !events.is_empty() {
                c.reset();
            } else if let Some(d) = indicator {
                c.update(h, d);
            }
            c.switches_seen = self.counters.switches;
        }
        self.scratch.who = events;
        Ok(())
    }

    /// An error if the step just taken did not solve its implicit equations (the midpoint
    /// rule's fixed-point iteration not converged in its passes): never a silent result.
    fn check_solved(&self, t0: f64) -> Result<()> {
        if self.rk.solved() {
            return Ok(());
        }
        Err(Error::NoConvergence {
            what: "midpoint integrator",
            detail: format!(
                "the fixed-point solve of the step at t = {t0} did not converge (step = {}; a \
                 smaller step, or the rk4 integrator)",
                self.cfg.step
            ),
        })
    }

    /// The sliding runs back to the start of the step (for a redo).
    fn restore_runs(&mut self) {
        for &(a, b) in &self.st.runs {
            self.st.u[a..b].copy_from_slice(&self.u0[a..b]);
            self.st.w[a..b].copy_from_slice(&self.w0[a..b]);
        }
    }

    /// The step-size control's error indicator of the step of length h just taken.
    fn step_indicator(&self, h: f64) -> f64 {
        step_control::indicator(
            &self.st.runs,
            h,
            &self.u0,
            &self.w0,
            &self.a_start,
            &self.st.u,
            &self.st.w,
            &self.a_end,
        )
    }

    /// A step from t0 to t0 + h; with `redo` the step just taken again from its start
    /// (saved in u0, w0), to the length h: the same bits as `restore_runs` and a step,
    /// without the copy back. The step writes the end accelerations too (in its last
    /// pass, for RK4).
    fn do_step(&mut self, t0: f64, h: f64, redo: bool) {
        self.rk.step(
            &mut self.st,
            &self.blk,
            t0,
            h,
            &self.a_start,
            &mut self.u0,
            &mut self.w0,
            &mut self.a_end,
            redo,
        );
        self.counters.steps += 1;
        self.counters.block_steps += self.st.n_active as u64;
    }
}

/// An event at s (if any) of block p: the earliest so far replaces the list, one at the
/// same s joins it.
#[inline(always)]
fn consider(s: Option<f64>, p: (usize, i8), best: &mut f64, who: &mut Vec<(usize, i8)>) {
    if let Some(s) = s {
        if s < *best {
            *best = s;
            who.clear();
            who.push(p);
        } else if s == *best && !who.contains(&p) {
            who.push(p);
        }
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_blocks;
#[cfg(test)]
mod tests_laws;
#[cfg(test)]
mod tests_noise;
#[cfg(test)]
mod tests_step_control;

impl<G: Geometry, F: Friction, M: Medium> View for Engine<G, F, M> {
    fn time(&self) -> f64 {
        self.t
    }
    fn n(&self) -> usize {
        self.st.n
    }
    fn n_sliding(&self) -> usize {
        self.st.n_active
    }
    fn sliding(&self, k: usize) -> bool {
        self.st.sliding(self.st.geo.padded(k))
    }
    fn stress(&self, k: usize) -> f64 {
        // phi + (1 - upper): phi itself, to the bit, for the threshold 1
        let p = self.st.geo.padded(k);
        self.blk.phi(&self.st, p, self.t) + (1.0 - self.blk.upper(p))
    }
    fn max_loading_rate(&self) -> f64 {
        self.max_loader * self.cfg.v
    }
    fn switches(&self) -> u64 {
        self.counters.switches
    }
}
