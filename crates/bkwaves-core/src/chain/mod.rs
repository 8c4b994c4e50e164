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
//! Runs of sliding blocks are stepped with RK4 (step h = `step` * dx); every stick and
//! every slip of a stuck neighbour is located in time on the cubic Hermite dense output
//! of the step, the step is redone up to that instant and the event applied there.
//! Stuck blocks whose neighbours are stuck have phi rising at exactly v: their slip
//! times sit in a priority queue and quiet intervals are skipped in one jump.

pub mod catalog;
pub mod checkpoint;
pub mod energy;
pub mod events;
pub mod front;
pub mod integrator;
pub mod state;

use crate::boundary::Boundary;
use crate::error::{check_at_least, check_open, Error, Result};
use crate::friction::Friction;
use catalog::Catalog;
use energy::Ledger;
use events::{Hermite, SlipQueue};
use integrator::{Method, StageSums, Stepper};
use state::State;

/// Numerical and loading settings of a chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainConfig {
    /// Lattice spacing dx = sqrt(k_p / k_c).
    pub dx: f64,
    /// Loading rate v >= 0.
    pub v: f64,
    /// Time step as a fraction of dx (h = step * dx).
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
    /// The step budget of this call was used up (call again to go on).
    Steps,
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

/// The chain simulator.
#[derive(Debug, Clone)]
pub struct Chain<F: Friction> {
    cfg: ChainConfig,
    fr: F,
    boundary_name: &'static str,
    st: State,
    rk: Stepper,
    queue: SlipQueue,
    t: f64,
    h: f64,
    a_start: Vec<f64>,
    a_end: Vec<f64>,
    s_start: StageSums,
    s_end: StageSums,
    a_valid: bool,
    u0: Vec<f64>,
    w0: Vec<f64>,
    stuck_sum: f64,
    n_stuck: usize,
    triggers: Vec<Trigger>,
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
}

impl<F: Friction> Chain<F> {
    /// A chain of `u0.len()` blocks with displacements `u0` and velocities `u_t0`
    /// (default v: all stuck). Blocks with u_t != v start sliding; blocks over a
    /// static threshold slip at t = 0.
    pub fn new(
        cfg: ChainConfig,
        friction: F,
        boundary: &dyn Boundary,
        u0: &[f64],
        u_t0: Option<&[f64]>,
    ) -> Result<Self> {
        let n = u0.len();
        if n == 0 {
            return Err(Error::InvalidParameter {
                name: "n",
                value: 0.0,
                allowed: "n >= 1 blocks",
            });
        }
        check_open("dx", cfg.dx, 0.0, f64::INFINITY, "dx > 0")?;
        check_at_least("v", cfg.v, 0.0, "v >= 0")?;
        check_open("step", cfg.step, 0.0, 1.0, "0 < step < 1 (time step / dx)")?;
        let h = cfg.step * cfg.dx;
        // RK4 stability: |h lambda| < 2.78 on the imaginary axis; the fastest mode of a
        // sliding block has |lambda| <= sqrt(1 + 4/dx^2) + 2 |dR/ds| (damping).
        let damp = (fr_slope(&friction)).abs();
        let lam = (1.0 + 4.0 / (cfg.dx * cfg.dx)).sqrt() + damp;
        if h * lam > 2.5 {
            return Err(Error::InvalidParameter {
                name: "step",
                value: cfg.step,
                allowed: "step * dx * (sqrt(1 + 4/dx^2) + 2 gamma) <= 2.5 (RK4 stability)",
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
        let mut st = State::new(u0, cfg.v, cfg.dx, boundary.left(), boundary.right());
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
                if x > cfg.v && friction.lower() == f64::NEG_INFINITY {
                    return Err(Error::InvalidParameter {
                        name: "u_t0",
                        value: x,
                        allowed: "u_t0 <= v: without backward slip (beta = inf) no block \
                                  moves backward over the ground",
                    });
                }
                st.w[i + 1] = x;
            }
        }
        let mut ch = Chain {
            cfg,
            fr: friction,
            boundary_name: boundary.name(),
            rk: Stepper::new(Method::Rk4, n),
            queue: SlipQueue::new(n + 2),
            t: 0.0,
            h,
            a_start: vec![0.0; n + 2],
            a_end: vec![0.0; n + 2],
            s_start: StageSums::default(),
            s_end: StageSums::default(),
            a_valid: false,
            u0: vec![0.0; n + 2],
            w0: vec![0.0; n + 2],
            stuck_sum: 0.0,
            n_stuck: n,
            triggers: Vec::new(),
            snap_times: Vec::new(),
            snap_every: 0,
            catalog: Catalog::new(n),
            ledger: Ledger::default(),
            snapshots: Snapshots::default(),
            counters: Counters::default(),
            need_check: true,
            full_check: true,
            st,
        };
        ch.stuck_sum = u0.iter().sum();
        for p in 1..=n {
            let w = ch.st.w[p];
            if w != ch.cfg.v {
                let dir = if w < ch.cfg.v { 1 } else { -1 };
                ch.start_sliding(p, dir);
            }
        }
        for p in 1..=n {
            ch.refresh_queue(p);
        }
        Ok(ch)
    }

    /// Choose the integrator (before the first run): RK4 (default) or the implicit
    /// midpoint rule, whose energy books close to round-off (order 2; its fixed-point
    /// solve needs step <= 0.5).
    pub fn set_integrator(&mut self, method: Method) -> Result<()> {
        if method == Method::Midpoint && self.cfg.step > 0.5 {
            return Err(Error::InvalidParameter {
                name: "step",
                value: self.cfg.step,
                allowed: "step <= 0.5 with the midpoint integrator",
            });
        }
        self.rk = Stepper::new(method, self.st.n);
        self.a_valid = false;
        Ok(())
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
        &self.fr
    }
    /// Name of the boundary condition.
    pub fn boundary_name(&self) -> &'static str {
        self.boundary_name
    }

    /// Displacements u at the current time (0-based).
    pub fn u(&self) -> Vec<f64> {
        (1..=self.st.n).map(|p| self.st.value(p, self.t)).collect()
    }
    /// Velocities u_t at the current time.
    pub fn u_t(&self) -> Vec<f64> {
        self.st.w[1..=self.st.n].to_vec()
    }
    /// Modes (0 stuck, +1 forward, -1 backward) at the current time.
    pub fn modes(&self) -> Vec<i8> {
        self.st.dir[1..=self.st.n]
            .iter()
            .map(|&d| d as i8)
            .collect()
    }
    /// phi = u - Lap u/dx^2 at the current time.
    pub fn phi(&self) -> Vec<f64> {
        (1..=self.st.n).map(|p| self.st.phi(p, self.t)).collect()
    }

    /// Energy (kinetic, coupling springs, loader springs) now.
    pub fn energy(&self) -> (f64, f64, f64) {
        energy::energy(&self.st, self.beta(), self.t)
    }

    fn beta(&self) -> f64 {
        self.fr.beta()
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
        if self.fr.lower() == f64::NEG_INFINITY {
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
        self.triggers.push(tr);
        // keep sorted by decreasing time (pop from the end)
        self.triggers.sort_by(|a, b| b.t.total_cmp(&a.t));
        Ok(())
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

    fn start_sliding(&mut self, p: usize, dir: i8) {
        let t = self.t;
        let u = self.st.stuck_u(p, t);
        self.stuck_sum -= u;
        self.n_stuck -= 1;
        self.st.u[p] = u;
        self.st.dir[p] = dir as f64;
        self.st.add_to_runs(p);
        self.catalog.slip(p - 1, t, u, dir);
        self.counters.switches += 1;
        self.a_valid = false;
    }

    fn stick(&mut self, p: usize) {
        let t = self.t;
        let s = self.cfg.v - self.st.w[p];
        self.ledger.projection += 0.5 * s * s;
        self.st.w[p] = self.cfg.v;
        self.st.dir[p] = 0.0;
        self.st.tref[p] = t;
        self.st.remove_from_runs(p);
        self.stuck_sum += self.st.u[p];
        self.n_stuck += 1;
        self.catalog.stick(p - 1, t, self.st.u[p], self.cfg.v);
        self.counters.switches += 1;
        self.a_valid = false;
    }

    /// The sliding block p has u_t = v (within the located event): stick or go on.
    fn on_rest(&mut self, p: usize) {
        let phi = self.st.phi(p, self.t);
        let (lo, hi) = (self.fr.lower(), self.fr.upper());
        if phi > lo && phi < hi {
            self.stick(p);
        } else {
            // still over a threshold: slide on in the direction of the force
            let s = self.cfg.v - self.st.w[p];
            self.ledger.projection += 0.5 * s * s;
            self.st.w[p] = self.cfg.v;
            let dir = if phi >= hi { 1.0 } else { -1.0 };
            if dir != self.st.dir[p] {
                // reversal: close the slip record and open one in the new direction
                let u = self.st.u[p];
                self.catalog.stick(p - 1, self.t, u, self.cfg.v);
                self.catalog.slip(p - 1, self.t, u, dir as i8);
                self.counters.switches += 1;
            }
            self.st.dir[p] = dir;
            self.a_valid = false;
        }
    }

    /// Re-evaluate the queue entry of real block p and its neighbours.
    fn refresh_around(&mut self, p: usize) {
        self.refresh_queue(p);
        for r in self.st.real_neighbours(p).into_iter().flatten() {
            self.refresh_queue(r);
        }
    }

    fn refresh_queue(&mut self, p: usize) {
        if self.st.sliding(p) || self.st.has_sliding_neighbour(p) || self.cfg.v <= 0.0 {
            self.queue.invalidate(p);
        } else {
            let phi = self.st.phi(p, self.t);
            let dt = ((self.fr.upper() - phi) / self.cfg.v).max(0.0);
            self.queue.push(p, self.t + dt);
        }
    }

    // ----- settling: events due now ---------------------------------------------------

    /// Apply every switch due at the current time until none is left.
    fn settle(&mut self) -> Result<()> {
        let (lo, hi) = (self.fr.lower(), self.fr.upper());
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
            let mut changed: Vec<usize> = Vec::new();
            // stuck blocks over a threshold: all of them on a full check, else the
            // neighbours of the runs
            let mut cands: Vec<usize> = Vec::new();
            if self.full_check {
                cands.extend((1..=self.st.n).filter(|&p| !self.st.sliding(p)));
            } else {
                for &(a, b) in &self.st.runs {
                    for q in [a - 1, b] {
                        if let Some(r) = self.st.resolve(q) {
                            if !self.st.sliding(r) {
                                cands.push(r);
                            }
                        }
                    }
                }
            }
            for p in cands {
                if self.st.sliding(p) {
                    continue;
                }
                let phi = self.st.phi(p, t);
                if phi >= hi {
                    self.start_sliding(p, 1);
                    changed.push(p);
                } else if phi <= lo {
                    self.start_sliding(p, -1);
                    changed.push(p);
                }
            }
            // sliding blocks back at rest
            let mut rest: Vec<usize> = Vec::new();
            for &(a, b) in &self.st.runs {
                for p in a..b {
                    let g = self.st.dir[p] * (self.st.w[p] - self.cfg.v);
                    if g > 0.0 || (g == 0.0 && self.st.dir[p] * self.accel_of(p) >= 0.0) {
                        rest.push(p);
                    }
                }
            }
            for p in rest {
                if self.st.sliding(p) {
                    self.on_rest(p);
                    changed.push(p);
                }
            }
            self.full_check = false;
            if changed.is_empty() {
                break;
            }
            for p in changed {
                self.refresh_around(p);
            }
        }
        if self.st.n_active == 0 {
            self.close_event();
        }
        Ok(())
    }

    fn close_event(&mut self) {
        if !self.catalog.event_open() {
            return;
        }
        let st = &self.st;
        let t = self.t;
        self.catalog.quiet(t, |i| st.stuck_u(i + 1, t));
        let k = self.catalog.finished();
        if self.snap_every > 0 && k % self.snap_every == 0 {
            self.snapshot_now();
        }
    }

    /// Acceleration of sliding block p at the current time.
    fn accel_of(&self, p: usize) -> f64 {
        let phi = self.st.phi(p, self.t);
        -phi + self.fr.excess(self.cfg.v - self.st.w[p], self.st.dir[p])
    }

    fn snapshot_now(&mut self) {
        self.snapshots.t.push(self.t);
        self.snapshots.u.push(self.u());
        self.snapshots.u_t.push(self.u_t());
    }

    /// Hermite data of the displacement of real block r over the last step [t0, t1].
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
    fn herm_neighbour(&self, q: usize, p: usize, t0: f64, t1: f64) -> Hermite {
        use crate::boundary::Ghost;
        if q == 0 || q == self.st.n + 1 {
            let g = if q == 0 { self.st.left } else { self.st.right };
            match g {
                Ghost::Mirror => self.herm_u(p, t0, t1),
                Ghost::Held(g0) => {
                    let v = self.cfg.v;
                    Hermite {
                        g0: g0 + v * t0,
                        m0: v,
                        g1: g0 + v * t1,
                        m1: v,
                    }
                }
                Ghost::Wrap => self.herm_u(self.st.resolve(q).unwrap_or(p), t0, t1),
            }
        } else {
            self.herm_u(q, t0, t1)
        }
    }

    /// Earliest event in the step just taken: (s in (0, 1], block).
    fn detect(&self, t0: f64, h: f64) -> Option<(f64, Vec<(usize, i8)>)> {
        let v = self.cfg.v;
        let (lo, hi) = (self.fr.lower(), self.fr.upper());
        let t1 = t0 + h;
        let mut best = f64::INFINITY;
        let mut who: Vec<(usize, i8)> = Vec::new();
        let consider =
            |s: Option<f64>, p: (usize, i8), best: &mut f64, who: &mut Vec<(usize, i8)>| {
                if let Some(s) = s {
                    if s < *best {
                        *best = s;
                        who.clear();
                        who.push(p);
                    } else if s == *best && !who.contains(&p) {
                        who.push(p);
                    }
                }
            };
        for &(a, b) in &self.st.runs {
            for p in a..b {
                let d = self.st.dir[p];
                let g = Hermite {
                    g0: d * (self.w0[p] - v),
                    m0: d * self.a_start[p],
                    g1: d * (self.st.w[p] - v),
                    m1: d * self.a_end[p],
                };
                consider(g.first_crossing(h), (p, 0), &mut best, &mut who);
            }
            for q in [a - 1, b] {
                let Some(p) = self.st.resolve(q) else {
                    continue;
                };
                if self.st.sliding(p) {
                    continue;
                }
                let k = self.st.inv_dx2;
                let up = self.herm_u(p, t0, t1);
                let l = self.herm_neighbour(p - 1, p, t0, t1);
                let r = self.herm_neighbour(p + 1, p, t0, t1);
                let phi = up.combine(1.0 + 2.0 * k, &l.combine(1.0, &r, 1.0), -k);
                let fwd = Hermite {
                    g0: phi.g0 - hi,
                    m0: phi.m0,
                    g1: phi.g1 - hi,
                    m1: phi.m1,
                };
                consider(fwd.first_crossing(h), (p, 1), &mut best, &mut who);
                let bwd = Hermite {
                    g0: lo - phi.g0,
                    m0: -phi.m0,
                    g1: lo - phi.g1,
                    m1: -phi.m1,
                };
                consider(bwd.first_crossing(h), (p, -1), &mut best, &mut who);
            }
        }
        best.is_finite().then_some((best, who))
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
            for p in 1..=n {
                if self.st.sliding(p) {
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
            self.snapshots.t.push(ts);
            self.snapshots.u.push(u);
            self.snapshots.u_t.push(w);
        }
    }

    /// Snapshots due in (t, t_next] while everything is stuck (exact).
    fn quiet_snapshots(&mut self, t_next: f64) {
        while let Some(&ts) = self.snap_times.last() {
            if ts > t_next {
                break;
            }
            self.snap_times.pop();
            self.snapshots.t.push(ts);
            self.snapshots
                .u
                .push((1..=self.st.n).map(|p| self.st.stuck_u(p, ts)).collect());
            self.snapshots.u_t.push(vec![self.cfg.v; self.st.n]);
        }
    }

    fn apply_trigger(&mut self, tr: Trigger) {
        let p = tr.block + 1;
        let v = self.cfg.v;
        match tr.kind {
            TriggerKind::Release { dir } => {
                if !self.st.sliding(p) {
                    self.start_sliding(p, if dir >= 0 { 1 } else { -1 });
                }
            }
            TriggerKind::Kick { du_t } => {
                let s_old = v - self.st.w[p];
                let w_new = self.st.w[p] + du_t;
                let s_new = v - w_new;
                self.ledger.injected += 0.5 * (s_new * s_new - s_old * s_old);
                if !self.st.sliding(p) {
                    if w_new == v {
                        return;
                    }
                    self.start_sliding(p, if w_new < v { 1 } else { -1 });
                }
                self.st.w[p] = w_new;
                self.a_valid = false;
            }
        }
        self.refresh_around(p);
    }

    /// Advance to `t_end`, or until `max_events` more events have finished, or at most
    /// `max_steps` integration steps in this call (to hand control back for progress
    /// reports and interrupts; call again to continue).
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
        loop {
            if self.need_check {
                self.settle()?;
                self.need_check = false;
            }
            if self.catalog.finished() >= target_events {
                return Ok(Stop::Events);
            }
            if let Some(&tr) = self.triggers.last() {
                if tr.t <= self.t {
                    self.triggers.pop();
                    self.apply_trigger(tr);
                    self.need_check = true;
                    continue;
                }
            }
            let tq = self.queue.peek().map_or(f64::INFINITY, |(t, _)| t);
            if tq <= self.t {
                let (_, p) = self.queue.pop().expect("peeked");
                self.start_sliding(p, 1);
                self.refresh_around(p);
                self.need_check = true;
                continue;
            }
            if self.t >= t_end {
                self.quiet_or_dense_tail();
                return Ok(Stop::Time);
            }
            if steps >= max_steps {
                return Ok(Stop::Steps);
            }
            let ttr = self.triggers.last().map_or(f64::INFINITY, |tr| tr.t);
            let t_next = tq.min(ttr).min(t_end);
            if self.st.n_active == 0 {
                // quiet: everything drifts exactly; jump
                let dt = t_next - self.t;
                self.ledger.load += self.cfg.v
                    * dt
                    * (self.stuck_sum
                        + 0.5 * self.cfg.v * dt * self.n_stuck as f64
                        + self.beta() * self.st.n as f64);
                self.stuck_sum += self.cfg.v * dt * self.n_stuck as f64;
                self.quiet_snapshots(t_next);
                self.t = t_next;
                self.counters.jumps += 1;
                continue;
            }
            steps += 1;
            self.integrate_step(t_next)?;
        }
    }

    fn quiet_or_dense_tail(&mut self) {
        // snapshots requested exactly at the current time
        if self.st.n_active == 0 {
            self.quiet_snapshots(self.t);
        } else {
            let t = self.t;
            while let Some(&ts) = self.snap_times.last() {
                if ts > t {
                    break;
                }
                self.snap_times.pop();
                self.snapshots.t.push(t);
                self.snapshots.u.push(self.u());
                self.snapshots.u_t.push(self.u_t());
            }
        }
    }

    /// One step (capped at t_cap), with event location and a redo up to the event.
    fn integrate_step(&mut self, t_cap: f64) -> Result<()> {
        let t0 = self.t;
        if !self.a_valid {
            let mut a = std::mem::take(&mut self.a_start);
            self.s_start = self.rk.accel(&mut self.st, &self.fr, t0, &mut a);
            self.a_start = a;
            self.a_valid = true;
        }
        let mut h = self.h.min(t_cap - t0);
        let mut integ = self.do_step(t0, h);
        let mut events: Vec<(usize, i8)> = Vec::new();
        if let Some((s, who)) = self.detect(t0, h) {
            if s < 1.0 {
                // redo the step up to the event
                for &(a, b) in &self.st.runs {
                    self.st.u[a..b].copy_from_slice(&self.u0[a..b]);
                    self.st.w[a..b].copy_from_slice(&self.w0[a..b]);
                }
                h *= s;
                integ = self.do_step(t0, h);
            }
            events = who;
        }
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
                    + 0.5 * self.cfg.v * h * self.n_stuck as f64
                    + self.beta() * self.st.n as f64));
        self.stuck_sum += self.cfg.v * h * self.n_stuck as f64;
        self.ledger.dry += integ.dry;
        self.ledger.viscous += integ.visc;
        self.dense_snapshots(t0, h);
        self.t = if t0 + h >= t_cap { t_cap } else { t0 + h };
        // the end accelerations become the next start ones
        std::mem::swap(&mut self.a_start, &mut self.a_end);
        self.s_start = self.s_end;
        self.a_valid = true;
        if !events.is_empty() {
            for (p, kind) in events {
                if kind == 0 {
                    if self.st.sliding(p) {
                        self.on_rest(p);
                    }
                } else if !self.st.sliding(p) {
                    self.start_sliding(p, kind);
                }
                self.refresh_around(p);
            }
            self.need_check = true;
        }
        Ok(())
    }

    fn do_step(&mut self, t0: f64, h: f64) -> integrator::StepIntegrals {
        let integ = self.rk.step(
            &mut self.st,
            &self.fr,
            t0,
            h,
            &self.a_start,
            self.s_start,
            &mut self.u0,
            &mut self.w0,
        );
        let mut a = std::mem::take(&mut self.a_end);
        let s_end = self.rk.accel(&mut self.st, &self.fr, t0 + h, &mut a);
        self.a_end = a;
        self.s_end = s_end;
        self.counters.steps += 1;
        self.counters.block_steps += self.st.n_active as u64;
        integ
    }
}

fn fr_slope<F: Friction>(f: &F) -> f64 {
    // |dR/ds| estimated by a difference on the forward branch
    (f.excess(1.0, 1.0) - f.excess(0.0, 1.0)).abs()
}

#[cfg(test)]
mod tests;
