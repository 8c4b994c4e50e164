//! The free boundary problem of Sec. IV: shocks moving over a slowly loading field.
//!
//! For v << 1 and slowly varying u the chain reduces to (paper eqs. slow, fast):
//!
//! - a slow field u(x, t) that grows at rate v where no shock passes (eq. rest);
//! - shocks i at x_i(t) with directions s_i = +-1 moving at dx_i/dt = s_i c(u_+),
//!   u_+ = u just ahead, c(u) = 1/sqrt(1 - u^2) ([`crate::speed::front_speed`]);
//! - as a shock passes, u jumps from u_+ to u_-(u_+) (eq. um,
//!   [`crate::wave::u_minus_from_speed`]);
//! - a pair of counter-propagating shocks is born where u reaches 1; shocks moving
//!   towards each other annihilate when they meet; shocks leave through free ends or wrap
//!   on a ring; a shock that meets u_+ <= 0 dies.
//!
//! The engine is event-driven with no global time step. The field lives on a grid
//! ([`field`]); a shock is moved through one cell at a time by integrating the inverse
//! speed dt/dx in position ([`shock`]), which removes the infinite speed at a birth. The
//! next event is the earliest of: a shock reaching a node (reset the node, enter the next
//! cell), two facing shocks meeting in a cell (root of t_1(x) = t_2(x) on their dense
//! outputs), u_+ reaching the stopping threshold inside a cell, or the maximum of the field
//! reaching 1 ([`births`]). The shocks of each cell and a queue of their next events
//! (`schedule`) make an engine event cost O(log N) in the number N of shocks, not O(N)
//! (docs/free_boundary.md, "Cost").
//!
//! Noise ([`nucleation`], optional): pairs nucleated at random points at a rate density
//! Lambda(u) ([`crate::noise`]), drawn exactly by thinning, as one more kind of event.
//!
//! Creep (u_+ < u_c = gamma) is outside the paper's theory (Sec. IV assumes it never
//! happens). It is never silent: each node reset in creep is flagged in the path and
//! counted in the event, and [`CreepRule`] decides what happens: `Zero` (default) keeps the
//! shock running and leaves u_- = 0, the v -> 0 limit of the creep profile (App. B, eq.
//! real: u -> 0 behind the front); `Stop` ends the shock where u_+ reaches u_c.

pub mod births;
pub mod catalog;
pub mod checkpoint;
pub mod field;
pub(crate) mod nucleation;
mod schedule;
pub mod shock;
pub mod speed_law;

use crate::error::{check_at_least, Error, Result};
use births::{CellMax, MaxTree};
use catalog::{FbEvent, PathKind, PathPoint};
use field::{CellPoly, Field};
use nucleation::NoiseRun;
use schedule::Schedule;
use shock::{CellField, TrajEnd, TrajPoint, Trajectory};
pub use speed_law::SpeedLaw;

/// Ends of the domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Boundary {
    /// A segment [x_0, x_{n-1}]; shocks leave through the ends.
    Free,
    /// A ring of length n h; shocks wrap.
    Periodic,
}

impl Boundary {
    /// Parse "free" or "periodic".
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "free" => Ok(Boundary::Free),
            "periodic" => Ok(Boundary::Periodic),
            _ => Err(Error::InvalidParameter {
                name: "boundary",
                value: f64::NAN,
                allowed: "\"free\" or \"periodic\"",
            }),
        }
    }
}

/// What a shock does when u_+ falls below u_c = gamma (creep, outside the paper's theory).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CreepRule {
    /// Keep running, leave u_- = 0 behind (v -> 0 limit of the creep profile); the shock
    /// dies when u_+ reaches 0.
    Zero,
    /// End the shock where u_+ reaches u_c.
    Stop,
}

impl CreepRule {
    /// Parse "zero" or "stop".
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "zero" => Ok(CreepRule::Zero),
            "stop" => Ok(CreepRule::Stop),
            _ => Err(Error::InvalidParameter {
                name: "creep",
                value: f64::NAN,
                allowed: "\"zero\" or \"stop\"",
            }),
        }
    }
}

/// Settings of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Damping gamma, 0 <= gamma < 1.
    pub gamma: f64,
    /// Loading rate v >= 0.
    pub v: f64,
    /// Ends of the domain.
    pub boundary: Boundary,
    /// Creep rule.
    pub creep: CreepRule,
    /// Local error per integration step in t, relative to the grid spacing.
    pub tol: f64,
    /// Record every node crossing of every shock (else only births and ends).
    pub record_path: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            gamma: 0.3,
            v: 1e-3,
            boundary: Boundary::Free,
            creep: CreepRule::Zero,
            tol: 1e-12,
            record_path: true,
        }
    }
}

/// Why [`FreeBoundary::advance`] returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The requested time was reached.
    Time,
    /// The step budget of this call was used (call again to continue).
    Steps,
    /// The requested number of completed events was reached.
    Events,
}

#[derive(Debug, Clone)]
struct ShockState {
    id: usize,
    dir: i8,
    cell: usize,
    traj: Trajectory,
    cf: CellField,
    event: usize,
    born: bool,
    stamp: u64,
    /// Unwrapped position of the left node of the current cell.
    xl_unw: f64,
    last_x_unw: f64,
    last_a: f64,
    /// The last position computed from the trajectory.
    pos: PositionCache,
}

/// (time, cell coordinate) of the last position of a shock computed from its trajectory;
/// time NaN when none was computed since the trajectory last changed. Written through a
/// shared reference (the neighbour searches read positions), so atomics (relaxed: the
/// engine is used from one thread at a time) rather than a `Cell`, to stay `Sync`.
#[derive(Debug, Default)]
struct PositionCache {
    t: std::sync::atomic::AtomicU64,
    s: std::sync::atomic::AtomicU64,
}

impl PositionCache {
    const RELAXED: std::sync::atomic::Ordering = std::sync::atomic::Ordering::Relaxed;

    fn empty() -> Self {
        let c = PositionCache::default();
        c.clear();
        c
    }

    fn clear(&self) {
        self.t.store(f64::NAN.to_bits(), Self::RELAXED);
    }

    /// The cell coordinate cached for time t, if any.
    fn get(&self, t: f64) -> Option<f64> {
        (f64::from_bits(self.t.load(Self::RELAXED)) == t)
            .then(|| f64::from_bits(self.s.load(Self::RELAXED)))
    }

    fn set(&self, t: f64, s: f64) {
        self.s.store(s.to_bits(), Self::RELAXED);
        self.t.store(t.to_bits(), Self::RELAXED);
    }
}

impl Clone for PositionCache {
    fn clone(&self) -> Self {
        let c = PositionCache::default();
        c.t.store(self.t.load(Self::RELAXED), Self::RELAXED);
        c.s.store(self.s.load(Self::RELAXED), Self::RELAXED);
        c
    }
}

/// A shock as seen from outside at the current time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShockView {
    /// Shock id.
    pub id: usize,
    /// Event id.
    pub event: usize,
    /// Position.
    pub x: f64,
    /// Direction.
    pub dir: i8,
    /// Stress just ahead.
    pub u_plus: f64,
}

/// The free boundary engine.
#[derive(Debug, Clone)]
pub struct FreeBoundary {
    opts: Options,
    u_stop: f64,
    /// Critical stress of the law: pulse above, creep at or below.
    u_c: f64,
    /// The front-speed law c(u_+).
    law: SpeedLaw,
    /// The static threshold s at the nodes (None: s = 1 everywhere).
    threshold: Option<Vec<f64>>,
    field: Field,
    reset_stamp: Vec<u64>,
    /// reset_stamp before the last reset (when `prev` was written).
    prev_stamp: Vec<u64>,
    stamp: u64,
    shocks: Vec<ShockState>,
    next_id: usize,
    now: f64,
    cellmax: Vec<CellMax>,
    tree: MaxTree,
    events: Vec<FbEvent>,
    open: Option<usize>,
    path: Vec<PathPoint>,
    steps: u64,
    /// Wall time per `advance` call in seconds (infinite: no bound; not part of the
    /// state).
    chunk_wall: f64,
    /// The shocks of each cell and the queue of their next events (derived state).
    sched: Schedule,
    /// Spontaneous nucleation (None: no noise; [`nucleation`]).
    noise: Option<NoiseRun>,
    /// Test only: find neighbours and next events by scanning every shock (the
    /// reference the schedule is checked against).
    #[cfg(test)]
    scan: bool,
    /// Test only: shocks looked at by the neighbour searches and the event selection.
    #[cfg(test)]
    visits: std::cell::Cell<u64>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Next {
    None,
    Birth,
    ShockEnd(usize),
    Collision(usize, usize, f64),
    Noise,
}

impl FreeBoundary {
    /// A run on nodes x_k = x0 + k h with initial field u0 (all < 1) and optional initial
    /// shocks (position, direction +-1).
    pub fn new(x0: f64, h: f64, u0: &[f64], opts: Options, initial: &[(f64, i8)]) -> Result<Self> {
        Self::with_law(x0, h, u0, opts, initial, SpeedLaw::Exact)
    }

    /// [`Self::new`] with shocks moving at c(u_+) given by `law` (e.g. a table of the
    /// renormalised speed c_eff of a disordered medium). Everything that depends on c
    /// follows the law: u_-(u_+) (eq. um with this c), the regime (pulse iff
    /// c^2 (1 - gamma^2) > 1) and the critical stress u_c where the "stop" rule ends a
    /// shock (docs/free_boundary.md, "Front-speed law").
    pub fn with_law(
        x0: f64,
        h: f64,
        u0: &[f64],
        opts: Options,
        initial: &[(f64, i8)],
        law: SpeedLaw,
    ) -> Result<Self> {
        Self::with_medium(x0, h, u0, opts, initial, law, None)
    }

    /// [`Self::with_law`] in a medium whose static threshold varies slowly: block x slips
    /// when u - u_xx >= s(x) (s at the nodes, > 0; None: s = 1). Varying on scales much
    /// longer than dx and the pulse width, the medium is locally the uniform one scaled by
    /// s (docs/disorder.md (a)): a shock moves at c(u_+/s), leaves u_- = -u_+ E(c) (eq. um
    /// with that c), creeps where u_+/s <= u_c; pairs are born where u reaches s
    /// (docs/free_boundary.md, "Threshold field").
    pub fn with_medium(
        x0: f64,
        h: f64,
        u0: &[f64],
        opts: Options,
        initial: &[(f64, i8)],
        law: SpeedLaw,
        threshold: Option<&[f64]>,
    ) -> Result<Self> {
        if !(opts.gamma.is_finite() && (0.0..1.0).contains(&opts.gamma)) {
            return Err(Error::InvalidParameter {
                name: "gamma",
                value: opts.gamma,
                allowed:
                    "0 <= gamma < 1 (for gamma >= 1 every wave creeps: no free boundary problem)",
            });
        }
        check_at_least("v", opts.v, 0.0, "v >= 0")?;
        crate::error::check_open("h", h, 0.0, f64::INFINITY, "grid spacing h > 0")?;
        crate::error::check_open("x0", x0, f64::NEG_INFINITY, f64::INFINITY, "finite x0")?;
        crate::error::check_open("tol", opts.tol, 0.0, 1e-3, "0 < tol < 1e-3")?;
        if u0.len() < 5 {
            return Err(Error::InvalidParameter {
                name: "n_nodes",
                value: u0.len() as f64,
                allowed: "at least 5 grid nodes",
            });
        }
        if let Some(th) = threshold {
            if th.len() != u0.len() {
                return Err(Error::InvalidParameter {
                    name: "threshold",
                    value: th.len() as f64,
                    allowed: "one threshold per grid node",
                });
            }
            for (&s, &u) in th.iter().zip(u0) {
                if !(s.is_finite() && s > 0.0) {
                    return Err(Error::InvalidParameter {
                        name: "threshold",
                        value: s,
                        allowed: "finite threshold > 0 at every node",
                    });
                }
                if !(u.is_finite() && u < s) {
                    return Err(Error::InvalidParameter {
                        name: "u0",
                        value: u,
                        allowed: "finite u0 < threshold everywhere (u = threshold starts a \
                                  slip at t = 0)",
                    });
                }
            }
        }
        for &u in u0 {
            if !(u.is_finite() && (threshold.is_some() || u < 1.0)) {
                return Err(Error::InvalidParameter {
                    name: "u0",
                    value: u,
                    allowed: "finite u0 < 1 everywhere (u = 1 starts a slip at t = 0)",
                });
            }
        }
        let periodic = opts.boundary == Boundary::Periodic;
        let field = Field::new(x0, h, u0, periodic, opts.v);
        let u_c = law.critical_stress(opts.gamma);
        let u_stop = match opts.creep {
            CreepRule::Zero => 0.0,
            CreepRule::Stop => u_c,
        };
        let nc = field.n_cells();
        let mut fb = FreeBoundary {
            opts,
            u_stop,
            u_c,
            law,
            threshold: threshold.map(<[f64]>::to_vec),
            reset_stamp: vec![0; field.n],
            prev_stamp: vec![0; field.n],
            stamp: 0,
            shocks: Vec::new(),
            next_id: 0,
            now: 0.0,
            cellmax: vec![CellMax::NONE; nc],
            tree: MaxTree::new(nc),
            events: Vec::new(),
            open: None,
            path: Vec::new(),
            steps: 0,
            chunk_wall: f64::INFINITY,
            sched: Schedule::new(nc),
            noise: None,
            #[cfg(test)]
            scan: false,
            #[cfg(test)]
            visits: Default::default(),
            field,
        };
        // initial shocks
        for &(x, dir) in initial {
            if dir != 1 && dir != -1 {
                return Err(Error::InvalidParameter {
                    name: "shock direction",
                    value: f64::from(dir),
                    allowed: "+1 or -1",
                });
            }
            let mut r = (x - x0) / h;
            if periodic {
                r = r.rem_euclid(nc as f64);
            } else if !(x.is_finite() && r > 0.0 && r < nc as f64) {
                return Err(Error::InvalidParameter {
                    name: "shock position",
                    value: x,
                    allowed: "strictly inside the domain [x_0, x_{n-1}]",
                });
            }
            if !r.is_finite() {
                return Err(Error::InvalidParameter {
                    name: "shock position",
                    value: x,
                    allowed: "finite",
                });
            }
            let cell = (r.floor() as usize).min(nc - 1);
            let s = r - cell as f64;
            let ev = match fb.open {
                Some(e) => e,
                None => {
                    let id = fb.events.len();
                    fb.events.push(FbEvent::new(id, 0.0, x0 + r * h, f64::NAN));
                    fb.open = Some(id);
                    id
                }
            };
            fb.events[ev].n_shocks += 1;
            let id = fb.next_id;
            fb.next_id += 1;
            let mut traj = Trajectory::new();
            traj.s_start = s;
            traj.dir = dir;
            traj.pts.push(TrajPoint {
                y: 0.0,
                t: 0.0,
                f: 0.0,
            });
            let xl = fb.field.node_x(cell);
            fb.shocks.push(ShockState {
                id,
                dir,
                cell,
                traj,
                cf: CellField {
                    poly: CellPoly::through(0, &[0.0]),
                    thr: None,
                    h,
                    v: opts.v,
                    epoch: 0.0,
                },
                event: ev,
                born: false,
                stamp: 0,
                xl_unw: xl,
                last_x_unw: xl + s * h,
                last_a: f64::NAN,
                pos: PositionCache::empty(),
            });
            fb.sched.add(fb.shocks.len() - 1, cell);
        }
        for i in 0..fb.shocks.len() {
            let poly = fb.gather_for_shock(i);
            let (s, dir) = (fb.shocks[i].traj.s_start, fb.shocks[i].dir);
            fb.start_trajectory(i, poly, s, dir)?;
            let up = fb.shocks[i].cf.u(s, 0.0);
            let (um, creep) = fb.u_minus(up, fb.thr_at(fb.shocks[i].cell, s));
            fb.shocks[i].last_a = up - um;
            let x = fb.field.node_x(fb.shocks[i].cell) + s * h;
            fb.record(i, x, up, um, PathKind::Initial, creep);
        }
        for j in 0..nc {
            fb.refresh_cell(j);
        }
        Ok(fb)
    }

    // ------------------------------------------------------------------ accessors
    /// Current time.
    pub fn time(&self) -> f64 {
        self.now
    }

    /// The grid field.
    pub fn field(&self) -> &Field {
        &self.field
    }

    /// u at the nodes at the current time.
    pub fn u_nodes(&self) -> Vec<f64> {
        (0..self.field.n)
            .map(|k| self.field.u_node(k, self.now))
            .collect()
    }

    /// The live shocks at the current time.
    pub fn shocks(&self) -> Vec<ShockView> {
        (0..self.shocks.len())
            .map(|i| {
                let sh = &self.shocks[i];
                let s = self.shock_s(i);
                ShockView {
                    id: sh.id,
                    event: sh.event,
                    x: self.field.node_x(sh.cell) + s * self.field.h,
                    dir: sh.dir,
                    u_plus: sh.cf.u(s, self.now),
                }
            })
            .collect()
    }

    /// The event catalog (the last one may still be running: t_end NaN).
    pub fn events(&self) -> &[FbEvent] {
        &self.events
    }

    /// Completed events.
    pub fn completed_events(&self) -> usize {
        self.events.len() - usize::from(self.open.is_some())
    }

    /// Recorded shock path points.
    pub fn path(&self) -> &[PathPoint] {
        &self.path
    }

    /// Engine events processed so far (node crossings, births, collisions, ends).
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Options of the run.
    pub fn options(&self) -> &Options {
        &self.opts
    }

    /// The front-speed law.
    pub fn law(&self) -> &SpeedLaw {
        &self.law
    }

    /// The critical stress u_c of the law: c(u_c) = 1/sqrt(1 - gamma^2).
    pub fn critical_stress(&self) -> f64 {
        self.u_c
    }

    // ------------------------------------------------------------------ physics
    /// u_- for a given u_+ where the threshold is `thr`, and whether the creep rule was
    /// applied: the front there moves at c(u_+/thr) and leaves -u_+ E(c) (eq. um).
    fn u_minus(&self, u_plus: f64, thr: f64) -> (f64, bool) {
        let thr = self.threshold.is_some().then_some(thr);
        self.law
            .reset_stress(u_plus, thr, self.opts.gamma, self.u_c)
    }

    /// The threshold's interpolant in cell j (the most centred cubic through the nodes;
    /// it is smooth and never reset), or None for the uniform threshold 1.
    fn thr_poly(&self, j: usize) -> Option<CellPoly> {
        let th = self.threshold.as_ref()?;
        let mut vals = [f64::NAN; 8];
        let mut ok = [false; 8];
        for (idx, o) in (-3i64..=4).enumerate() {
            if let Some(k) = self.field.node_at(j, o) {
                vals[idx] = th[k];
                ok[idx] = true;
            }
        }
        choose_window(&vals, &ok, &[0, 1])
    }

    /// The threshold at cell coordinate s of cell j (1 without a threshold field).
    fn thr_at(&self, j: usize, s: f64) -> f64 {
        self.thr_poly(j).map_or(1.0, |p| p.eval(s))
    }

    /// The threshold at node k (1 without a threshold field).
    fn thr_node(&self, k: usize) -> f64 {
        self.threshold.as_ref().map_or(1.0, |th| th[k])
    }

    /// The threshold field at the nodes (None: s = 1).
    pub fn threshold(&self) -> Option<&[f64]> {
        self.threshold.as_deref()
    }

    // ------------------------------------------------------------------ geometry
    /// Cell coordinate of shock i now, from its trajectory (computed once per shock and
    /// engine time: the neighbour searches ask for it several times).
    fn shock_s(&self, i: usize) -> f64 {
        let sh = &self.shocks[i];
        if let Some(s) = sh.pos.get(self.now) {
            return s;
        }
        let s = sh.traj.s_at(sh.traj.y_at(self.now), self.field.h);
        sh.pos.set(self.now, s);
        s
    }

    /// Indices (ascending) of the shocks in the cells within `reach` cells of cell j.
    ///
    /// Everything the engine asks about other shocks is local: which shocks lie between a
    /// point and the nodes of its interpolation stencil (offsets -3..=4, so shocks at most
    /// 4 cells away) or touch a cell. Shocks further away have offsets outside every range
    /// tested, so leaving them out changes nothing (ascending order keeps the ties).
    fn shocks_near(&self, j: usize, reach: usize) -> Near {
        let nc = self.field.n_cells();
        let everywhere = self.field.periodic && 2 * reach + 1 >= nc;
        #[cfg(test)]
        let everywhere = everywhere || self.scan;
        let mut out = Near::default();
        if everywhere {
            (0..self.shocks.len()).for_each(|q| out.push(q));
        } else {
            let (lo, hi) = if self.field.periodic {
                (j + nc - reach, j + nc + reach)
            } else {
                (j.saturating_sub(reach), (j + reach).min(nc - 1))
            };
            for c in lo..=hi {
                self.sched.in_cell(c % nc).iter().for_each(|&q| out.push(q));
            }
            out.sort();
        }
        #[cfg(test)]
        self.visits.set(self.visits.get() + out.len() as u64);
        out
    }

    /// Position of shock q relative to node j, in cells (signed along +x, wrapped to about
    /// (-n/2, n/2] on a ring): the integer cell offset plus the shock's cell coordinate.
    ///
    /// Shocks are placed relative to nodes and cells only through this: it is exact at the
    /// nodes (s = 0 or 1 after a crossing) whatever the size of the domain. Differences of
    /// wrapped floating-point positions are not: their rounding (~1e-16 L) exceeds any
    /// fixed fraction of h on large rings, and a node just reset by a shock then appeared
    /// to be ahead of it (the interpolant of the next cell mixed u_- into the field ahead,
    /// its cubic overshot 1 and spurious pairs were born next to every shock).
    fn offset(&self, j: usize, q: usize) -> f64 {
        let mut d = self.shocks[q].cell as i64 - j as i64;
        if self.field.periodic {
            let nc = self.field.n_cells() as i64;
            d = (d + nc / 2).rem_euclid(nc) - nc / 2;
        }
        d as f64 + self.shock_s(q)
    }

    /// The value shock `i` saw (or would see) at node k behind it, if known.
    fn behind_value(&self, i: usize, k: usize) -> Option<f64> {
        let sh = &self.shocks[i];
        let f = &self.field;
        if f.reset_by[k] == sh.id {
            return Some(f.prev[k]);
        }
        if sh.born {
            // untouched since the birth: the field the pair was born in
            if self.reset_stamp[k] <= sh.stamp {
                return Some(f.b[k]);
            }
            // reset once since the birth (by the partner, or by a shock that met it):
            // the value before that reset is still the field of the birth
            if self.prev_stamp[k] <= sh.stamp {
                return Some(f.prev[k]);
            }
        }
        None
    }

    /// The interpolant of the field seen by shock i in its current cell.
    fn gather_for_shock(&self, i: usize) -> CellPoly {
        let sh = &self.shocks[i];
        let j = sh.cell;
        let dirf = f64::from(sh.dir);
        let s_now = self.shock_s(i);
        // distances ahead of shock i, in cells
        let others: Vec<(f64, usize)> = self
            .shocks_near(j, 4)
            .iter()
            .copied()
            .filter(|&q| q != i)
            .map(|q| (dirf * (self.offset(j, q) - s_now), q))
            .collect();
        let mut vals = [f64::NAN; 8];
        let mut ok = [false; 8];
        for (idx, o) in (-3i64..=4).enumerate() {
            let Some(k) = self.field.node_at(j, o) else {
                continue;
            };
            let d_node = dirf * (o as f64 - s_now);
            let v = if d_node > 1e-12 {
                // the nearest shock between S and the node, if any
                let nearest = others
                    .iter()
                    .filter(|(d, _)| *d > 0.0 && *d <= d_node + 1e-12)
                    .min_by(|p, q| p.0.total_cmp(&q.0));
                match nearest {
                    None => Some(self.field.b[k]),
                    // a facing shock: beyond it, the field it saw continues the field S
                    // sees (they meet first); its partner and stamps are checked there
                    Some(&(_, q)) if self.shocks[q].dir == -sh.dir => self.behind_value(q, k),
                    Some(_) => None,
                }
            } else {
                self.behind_value(i, k)
            };
            if let Some(v) = v {
                vals[idx] = v;
                ok[idx] = true;
            }
        }
        let ahead = if sh.dir > 0 { 1 } else { 0 };
        // If the node ahead is not known (several shocks crowd the cell), extrapolate the
        // field the shock saw from behind it.
        let behind = 1 - ahead;
        choose_window(&vals, &ok, &[ahead])
            .or_else(|| choose_window(&vals, &ok, &[behind]))
            .unwrap_or_else(|| {
                CellPoly::through(
                    0,
                    &[self.field.b[self.field.node_at(j, ahead).unwrap_or(j)]],
                )
            })
    }

    /// The interpolant of the field in cell j, or None when a shock touches the cell
    /// (shocks with index >= `upto` are ignored).
    ///
    /// Beyond a shock facing the cell (moving towards it: the cell is ahead of it), the
    /// values that shock saw continue the field of the cell (`behind_value`), as in
    /// [`Self::gather_for_shock`]: the field ahead of a shock is the unswept field, and
    /// its interpolant is the one it had before the shock passed, centred on the cell and
    /// identical to the one the shock itself moves on. Beyond a shock moving away from the
    /// cell, the field is another one (unswept ahead of it, the cell swept) and is not
    /// used.
    ///
    /// Using only the nodes on the cell's side instead made the interpolant of a cell just
    /// ahead of a fresh shock one-sided; near a sharp maximum (curvature ~1e-2, h = 0.2)
    /// that extrapolation overshoots the field by ~1e-4, so the cell ahead "reached 1"
    /// at once and a spurious pair was born in front of the shock, which sweeps that
    /// point at once, before u = u_0 + v t < 1 there can reach 1.
    fn gather_for_cell(&self, j: usize, upto: usize) -> Option<CellPoly> {
        let eps = 1e-12;
        // (offset from node j, shock) of the shocks near the cell, ascending in the shock
        let rs: Vec<(f64, usize)> = self
            .shocks_near(j, 4)
            .iter()
            .copied()
            .filter(|&q| q < upto)
            .map(|q| (self.offset(j, q), q))
            .collect();
        if rs.iter().any(|&(r, _)| r >= -eps && r <= 1.0 + eps) {
            return None;
        }
        let mut vals = [f64::NAN; 8];
        let mut ok = [false; 8];
        for (idx, o) in (-3i64..=4).enumerate() {
            let Some(k) = self.field.node_at(j, o) else {
                continue;
            };
            let of = o as f64;
            // (distance from the cell, shock) of the shocks between the cell and node k;
            // `towards` is the direction of a shock facing the cell from that side
            let (between, towards): (Vec<(f64, usize)>, i8) = if o < 0 {
                let b = rs
                    .iter()
                    .filter(|&&(r, _)| r >= of - eps && r <= eps)
                    .map(|&(r, q)| (-r, q))
                    .collect();
                (b, 1)
            } else if o > 1 {
                let b = rs
                    .iter()
                    .filter(|&&(r, _)| r >= 1.0 - eps && r <= of + eps)
                    .map(|&(r, q)| (r - 1.0, q))
                    .collect();
                (b, -1)
            } else {
                (Vec::new(), 0)
            };
            // the nearest one (of a pair born at one point, the one facing the cell)
            let nearest = between.iter().min_by(|p, q| {
                p.0.total_cmp(&q.0).then_with(|| {
                    let fp = self.shocks[p.1].dir == towards;
                    let fq = self.shocks[q.1].dir == towards;
                    fq.cmp(&fp)
                })
            });
            let v = match nearest {
                None => Some(self.field.b[k]),
                Some(&(_, q)) if self.shocks[q].dir == towards => self.behind_value(q, k),
                Some(_) => None,
            };
            if let Some(v) = v {
                vals[idx] = v;
                ok[idx] = true;
            }
        }
        choose_window(&vals, &ok, &[0, 1])
    }

    /// Does a shock lie in the closed span of cell c?
    fn cell_touches_shock(&self, c: usize) -> bool {
        self.shocks_near(c, 1)
            .iter()
            .any(|&q| (-1e-12..=1.0 + 1e-12).contains(&self.offset(c, q)))
    }

    fn refresh_cell(&mut self, j: usize) {
        let cm = match self.gather_for_cell(j, self.shocks.len()) {
            Some(mut p) => {
                // with a threshold field, births are where u - s reaches 0: the maximum
                // of b - s + 1 (reaching 1 like b does without one)
                if let Some(t) = self.thr_poly(j) {
                    p.c[0] += 1.0 - t.c[0];
                    for q in 1..4 {
                        p.c[q] -= t.c[q];
                    }
                    p.points = p.points.max(t.points);
                }
                let (value, s) = p.max_on_unit();
                let h = self.field.h;
                // A maximum at a node next to a cell a shock is crossing is the edge of the
                // field ahead of that shock, which sweeps it: not a birth.
                let across = if s == 0.0 {
                    self.field
                        .node_at(j, -1)
                        .filter(|_| self.field.periodic || j > 0)
                } else if s == 1.0 {
                    self.field
                        .node_at(j, 1)
                        .filter(|&k| k < self.field.n_cells() || self.field.periodic)
                } else {
                    None
                };
                let blocked = across.is_some_and(|c| self.cell_touches_shock(c));
                if blocked {
                    CellMax::NONE
                } else {
                    CellMax {
                        value,
                        s,
                        a: -p.deriv2(s) / (2.0 * h * h),
                    }
                }
            }
            None => CellMax::NONE,
        };
        self.cellmax[j] = cm;
        self.tree.set(j, cm.value);
    }

    fn refresh_around(&mut self, k: usize) {
        let nc = self.field.n_cells() as i64;
        // cells whose stencil (offsets -3..=4) contains node k
        for o in -4i64..=3 {
            let j = k as i64 + o;
            let j = if self.field.periodic {
                j.rem_euclid(nc)
            } else if j < 0 || j >= nc {
                continue;
            } else {
                j
            };
            self.refresh_cell(j as usize);
        }
    }

    fn start_trajectory(&mut self, i: usize, poly: CellPoly, s: f64, dir: i8) -> Result<()> {
        let cf = CellField {
            poly,
            thr: self.thr_poly(self.shocks[i].cell),
            h: self.field.h,
            v: self.field.v,
            epoch: self.field.epoch,
        };
        let (now, u_stop, tol) = (self.now, self.u_stop, self.opts.tol);
        let sh = &mut self.shocks[i];
        sh.cf = cf;
        sh.pos.clear();
        self.sched.touch(sh.cell);
        shock::integrate(&cf, &self.law, s, dir, now, u_stop, tol, &mut sh.traj)
    }

    fn record(&mut self, i: usize, x: f64, u_plus: f64, u_minus: f64, kind: PathKind, creep: bool) {
        let keep = self.opts.record_path || kind != PathKind::Node;
        if keep {
            let sh = &self.shocks[i];
            let l = self.field.length();
            let x = if self.field.periodic {
                self.field.x0 + (x - self.field.x0).rem_euclid(l)
            } else {
                x
            };
            self.path.push(PathPoint {
                shock: sh.id,
                event: sh.event,
                t: self.now,
                x,
                dir: sh.dir,
                u_plus,
                u_minus,
                kind,
                creep,
            });
        }
    }

    /// Add the slip between the shock's last recorded point and x_unw (slip density a).
    fn accumulate(&mut self, i: usize, x_unw: f64, a: f64, creep: bool) {
        let sh = &mut self.shocks[i];
        let dxl = (x_unw - sh.last_x_unw).abs();
        let ev = &mut self.events[sh.event];
        if sh.last_a.is_finite() {
            ev.moment += 0.5 * (sh.last_a + a) * dxl;
        }
        ev.swept += dxl;
        ev.x_min = ev.x_min.min(x_unw);
        ev.x_max = ev.x_max.max(x_unw);
        if creep {
            ev.n_creep += 1;
        }
        sh.last_x_unw = x_unw;
        sh.last_a = a;
    }

    fn remove_shock(&mut self, i: usize) {
        let last = self.shocks.len() - 1;
        let (ci, cl) = (self.shocks[i].cell, self.shocks[last].cell);
        self.sched.swap_remove(i, ci, last, cl);
        self.shocks.swap_remove(i);
        if self.shocks.is_empty() {
            if let Some(e) = self.open.take() {
                self.events[e].t_end = self.now;
            }
        }
    }

    // ------------------------------------------------------------------ the run
    /// Bound the wall time of one [`FreeBoundary::advance`] call: it returns
    /// [`Stop::Steps`] once `seconds` have passed (checked every few engine events, after
    /// at least one), so that the caller answers an interrupt promptly. Returning there
    /// changes nothing in the results. Infinite (the default): no bound.
    pub fn set_chunk_wall(&mut self, seconds: f64) {
        self.chunk_wall = if seconds > 0.0 {
            seconds
        } else {
            f64::INFINITY
        };
    }

    /// Advance to `t_stop` at most, processing at most `max_steps` engine events and
    /// stopping once `max_events` events are complete.
    pub fn advance(&mut self, t_stop: f64, max_steps: u64, max_events: usize) -> Result<Stop> {
        if t_stop.is_nan() {
            return Err(Error::InvalidParameter {
                name: "t_end",
                value: t_stop,
                allowed: "a time >= the current time",
            });
        }
        let mut done = 0u64;
        let started = std::time::Instant::now();
        loop {
            if self.completed_events() >= max_events {
                return Ok(Stop::Events);
            }
            if done >= max_steps {
                return Ok(Stop::Steps);
            }
            if self.chunk_wall.is_finite()
                && done > 0
                && done % 16 == 0
                && started.elapsed().as_secs_f64() >= self.chunk_wall
            {
                return Ok(Stop::Steps);
            }
            let (t, next) = self.next_event(t_stop);
            if let Next::None = next {
                // (with nothing left to happen and no finite end, time stays where it is)
                if t_stop > self.now && t_stop.is_finite() {
                    self.now = t_stop;
                }
                return Ok(Stop::Time);
            }
            self.now = t.max(self.now);
            match next {
                Next::Birth => self.birth()?,
                Next::ShockEnd(i) => self.shock_end(i)?,
                Next::Collision(a, b, s) => self.collision(a, b, s),
                Next::Noise => self.noise_candidate()?,
                Next::None => unreachable!(),
            }
            self.steps += 1;
            done += 1;
            if self.field.v * (self.now - self.field.epoch) > 1.0 {
                self.rebase();
            }
            self.noise_sync();
        }
    }

    fn rebase(&mut self) {
        let d = self.field.v * (self.now - self.field.epoch);
        self.field.rebase(self.now);
        for j in 0..self.cellmax.len() {
            if self.cellmax[j].value.is_finite() {
                self.cellmax[j].value += d;
                self.tree.set(j, self.cellmax[j].value);
            }
        }
    }

    /// The earliest of: a birth, a meeting of facing shocks, the end of an unpaired
    /// shock's trajectory (before or at `t_stop`; at equal times in that order, see
    /// [`schedule`]).
    fn next_event(&mut self, t_stop: f64) -> (f64, Next) {
        #[cfg(test)]
        if self.scan {
            return self.next_event_by_scan(t_stop);
        }
        self.pair_changed_cells();
        let mut best_t = t_stop;
        let mut best = Next::None;
        if let Some(tb) = self.birth_time() {
            if tb <= best_t {
                best_t = tb;
                best = Next::Birth;
            }
        }
        if let Some((tc, a, b, s)) = self.sched.first_meeting() {
            if tc <= best_t {
                best_t = tc;
                best = Next::Collision(a, b, s);
            }
        }
        if let Some((te, i)) = self.sched.first_end() {
            if te < best_t || (te == best_t && matches!(best, Next::None)) {
                best_t = te;
                best = Next::ShockEnd(i);
            }
        }
        // (infinite without noise: never chosen, even when t_stop is infinite too)
        let tn = self.noise_time();
        if tn.is_finite() && (tn < best_t || (tn == best_t && matches!(best, Next::None))) {
            best_t = tn.max(self.now);
            best = Next::Noise;
        }
        (best_t, best)
    }

    /// When the maximum of the field reaches 1 (none without loading or without cells
    /// free of shocks).
    fn birth_time(&self) -> Option<f64> {
        if self.field.v > 0.0 {
            let (m, _) = self.tree.max();
            if m.is_finite() {
                return Some((self.field.epoch + (1.0 - m) / self.field.v).max(self.now));
            }
        }
        None
    }

    /// Facing shocks of one cell meet before either reaches its far node (the meeting
    /// point lies between them), so a paired shock's own end is not queued; where
    /// u_+ >= 1 the paths are flat in t and the times agree only to rounding. For each
    /// right-mover a of the cell, the nearest shock ahead of it in the cell (a left-mover
    /// wins a tie: the left shock of a pair born at one point is the one facing a), if it
    /// moves left and the two paths meet. Done for the cells whose shocks changed since the
    /// last engine event.
    fn pair_changed_cells(&mut self) {
        for c in self.sched.take_dirty() {
            #[cfg(test)]
            self.visits
                .set(self.visits.get() + self.sched.in_cell(c).len() as u64);
            if let &[q] = self.sched.in_cell(c) {
                // a shock alone in its cell (the usual case): its end is next
                self.sched.unqueue(q);
                self.sched.queue_end(q, self.shocks[q].traj.t_end());
                continue;
            }
            let members = self.sched.in_cell(c).to_vec();
            let s_now: Vec<f64> = members.iter().map(|&q| self.shock_s(q)).collect();
            for &q in &members {
                self.sched.unqueue(q);
            }
            let mut paired = vec![false; members.len()];
            for (ia, &a) in members.iter().enumerate() {
                if self.shocks[a].dir < 0 {
                    continue;
                }
                let sa = s_now[ia];
                let mut near: Option<(f64, usize)> = None;
                for (ib, &b) in members.iter().enumerate() {
                    let sb = s_now[ib];
                    if b == a || sb <= sa {
                        continue;
                    }
                    let better = match near {
                        None => true,
                        Some((s0, ib0)) => {
                            sb < s0
                                || (sb == s0
                                    && self.shocks[b].dir < 0
                                    && self.shocks[members[ib0]].dir > 0)
                        }
                    };
                    if better {
                        near = Some((sb, ib));
                    }
                }
                let Some((_, ib)) = near else { continue };
                let b = members[ib];
                if self.shocks[b].dir > 0 {
                    continue;
                }
                if let Some((tc, s)) = self.meeting(a, b) {
                    paired[ia] = true;
                    paired[ib] = true;
                    let tc = tc
                        .min(self.shocks[a].traj.t_end())
                        .min(self.shocks[b].traj.t_end());
                    self.sched.queue_meeting(a, b, tc, s);
                }
            }
            for (iq, &q) in members.iter().enumerate() {
                if !paired[iq] {
                    self.sched.queue_end(q, self.shocks[q].traj.t_end());
                }
            }
        }
    }

    /// Rebuild the schedule from the shocks (after a restore).
    fn rebuild_schedule(&mut self) {
        self.sched = Schedule::new(self.field.n_cells());
        for i in 0..self.shocks.len() {
            self.sched.add(i, self.shocks[i].cell);
        }
    }

    /// Meeting of right-moving a and left-moving b in the same cell: (time, s).
    ///
    /// A function of the two trajectories alone (not of the current time): the root is
    /// bracketed by where the paths start and end in the cell, so the meeting computed
    /// when the pair forms is the one found at any later time (the event queue relies on
    /// it, and a restored checkpoint finds the same meeting).
    fn meeting(&self, a: usize, b: usize) -> Option<(f64, f64)> {
        let h = self.field.h;
        let (ta, tb) = (&self.shocks[a].traj, &self.shocks[b].traj);
        if ta.s_start >= tb.s_start {
            return None;
        }
        let a_hi = ta.s_start + ta.y_end() / h;
        let b_lo = tb.s_start - tb.y_end() / h;
        let lo = ta.s_start.max(b_lo);
        let hi = tb.s_start.min(a_hi);
        if lo > hi {
            return None;
        }
        let f = |s: f64| {
            ta.t_at(((s - ta.s_start) * h).max(0.0)) - tb.t_at(((tb.s_start - s) * h).max(0.0))
        };
        if f(lo) > 0.0 || f(hi) < 0.0 {
            return None;
        }
        let (mut l, mut r) = (lo, hi);
        for _ in 0..200 {
            let m = 0.5 * (l + r);
            if f(m) < 0.0 {
                l = m;
            } else {
                r = m;
            }
            if r - l <= 1e-15 {
                break;
            }
        }
        let s = 0.5 * (l + r);
        Some((ta.t_at(((s - ta.s_start) * h).max(0.0)), s))
    }

    fn birth(&mut self) -> Result<()> {
        let (_, j) = self.tree.max();
        let cm = self.cellmax[j];
        let h = self.field.h;
        let n = self.field.n;
        let free = !self.field.periodic;
        let x = self.field.node_x(j) + cm.s * h;
        // (cell, s, dir) of each new shock; node reset at a node birth
        let mut starts: Vec<(usize, f64, i8)> = Vec::new();
        let mut node: Option<usize> = None;
        let mut curvature = cm.a;
        if cm.s == 0.0 || cm.s == 1.0 {
            let k = if cm.s == 0.0 {
                j
            } else {
                self.field.node_at(j, 1).unwrap_or(j)
            };
            node = Some(k);
            if free && k == 0 {
                starts.push((0, 0.0, 1));
            } else if free && k == n - 1 {
                starts.push((n - 2, 1.0, -1));
            } else {
                let left = self.field.node_at(k, -1).unwrap_or(0);
                starts.push((k, 0.0, 1));
                starts.push((left, 1.0, -1));
                // curvature at a node: from the two neighbours (second difference)
                let km = self.field.node_at(k, -1);
                let kp = self.field.node_at(k, 1);
                if let (Some(km), Some(kp)) = (km, kp) {
                    let f = &self.field;
                    let g = |q: usize| f.b[q] - self.thr_node(q);
                    curvature = if self.threshold.is_some() {
                        -(g(km) - 2.0 * g(k) + g(kp)) / (2.0 * h * h)
                    } else {
                        -(f.b[km] - 2.0 * f.b[k] + f.b[kp]) / (2.0 * h * h)
                    };
                }
            }
        } else {
            starts.push((j, cm.s, 1));
            starts.push((j, cm.s, -1));
        }
        // u reached the threshold there (1 without a threshold field)
        let u_b = match node {
            Some(k) => self.thr_node(k),
            None => self.thr_at(j, cm.s),
        };
        self.create_shocks(j, x, &starts, node, curvature, u_b, PathKind::Birth)
    }

    /// New shocks (cell, s, dir) at x in cell j, with u_+ = u_b there: a birth where u
    /// reached the threshold (`PathKind::Birth`; at a node, `node` is reset) or a spontaneous
    /// nucleation (`PathKind::Nucleation`, [`nucleation`]).
    #[allow(clippy::too_many_arguments)]
    fn create_shocks(
        &mut self,
        j: usize,
        x: f64,
        starts: &[(usize, f64, i8)],
        node: Option<usize>,
        curvature: f64,
        u_b: f64,
        kind: PathKind,
    ) -> Result<()> {
        let h = self.field.h;
        let spontaneous = kind == PathKind::Nucleation;
        let ev = match self.open {
            Some(e) => e,
            None => {
                let id = self.events.len();
                let mut e = FbEvent::new(id, self.now, x, curvature);
                e.spontaneous = spontaneous;
                self.events.push(e);
                self.open = Some(id);
                id
            }
        };
        if spontaneous {
            self.events[ev].n_nucleations += 1;
        } else {
            self.events[ev].n_births += 1;
        }
        self.events[ev].n_shocks += starts.len();
        let first = self.shocks.len();
        let ids: Vec<usize> = (0..starts.len()).map(|q| self.next_id + q).collect();
        for (q, &(cell, s, dir)) in starts.iter().enumerate() {
            let mut traj = Trajectory::new();
            traj.s_start = s;
            traj.dir = dir;
            traj.pts.push(TrajPoint {
                y: 0.0,
                t: self.now,
                f: 0.0,
            });
            let xl = self.field.node_x(cell);
            self.shocks.push(ShockState {
                id: ids[q],
                dir,
                cell,
                traj,
                cf: CellField {
                    poly: CellPoly::through(0, &[1.0]),
                    thr: None,
                    h,
                    v: self.field.v,
                    epoch: self.field.epoch,
                },
                event: ev,
                born: true,
                stamp: self.stamp,
                xl_unw: xl,
                last_x_unw: xl + s * h,
                last_a: f64::NAN,
                pos: PositionCache::empty(),
            });
            self.sched.add(self.shocks.len() - 1, cell);
        }
        self.next_id += starts.len();
        // interpolants before any node is reset
        let polys: Vec<CellPoly> = (0..starts.len())
            .map(|q| {
                if node.is_none() {
                    self.gather_for_cell_ignoring_new(j, first)
                } else {
                    self.gather_for_shock(first + q)
                }
            })
            .collect();
        // (a birth is where u reached the threshold: u_b is the threshold there; noise,
        // which is refused with a threshold field, nucleates at threshold 1)
        let thr_b = if kind == PathKind::Birth { u_b } else { 1.0 };
        let (um_b, creep_b) = self.u_minus(u_b, thr_b);
        if let Some(k) = node {
            let u_plus = self.field.u_node(k, self.now);
            let (um, _) = self.u_minus(u_plus, self.thr_node(k));
            let f = &mut self.field;
            f.prev[k] = f.b[k];
            f.b[k] = um - f.v * (self.now - f.epoch);
            f.reset_by[k] = ids[0];
            self.stamp += 1;
            self.prev_stamp[k] = self.reset_stamp[k];
            self.reset_stamp[k] = self.stamp;
        }
        for (q, &(_, s, dir)) in starts.iter().enumerate() {
            let i = first + q;
            self.start_trajectory(i, polys[q], s, dir)?;
            self.shocks[i].last_a = u_b - um_b;
            let xu = self.shocks[i].last_x_unw;
            self.accumulate(i, xu, u_b - um_b, creep_b);
            self.record(i, x, u_b, um_b, kind, creep_b);
        }
        self.refresh_around(node.unwrap_or(j));
        Ok(())
    }

    /// The birth-cell interpolant, ignoring the shocks just created (index >= first).
    fn gather_for_cell_ignoring_new(&self, j: usize, first: usize) -> CellPoly {
        self.gather_for_cell(j, first)
            .unwrap_or_else(|| CellPoly::through(0, &[self.field.b[j]]))
    }

    fn shock_end(&mut self, i: usize) -> Result<()> {
        let h = self.field.h;
        let end = self.shocks[i].traj.end;
        let dir = self.shocks[i].dir;
        let cell = self.shocks[i].cell;
        if end == TrajEnd::Threshold {
            let y = self.shocks[i].traj.y_end();
            let s = self.shocks[i].traj.s_at(y, h);
            let x = self.field.node_x(cell) + s * h;
            let xu = self.shocks[i].xl_unw + s * h;
            let up = self.u_stop * self.thr_at(cell, s);
            let kind = if self.opts.creep == CreepRule::Stop && self.opts.gamma > 0.0 {
                PathKind::CreepStop
            } else {
                PathKind::Death
            };
            let a = if kind == PathKind::CreepStop { up } else { 0.0 };
            self.accumulate(i, xu, a, false);
            self.record(i, x, up, f64::NAN, kind, kind == PathKind::CreepStop);
            let ev = self.shocks[i].event;
            self.events[ev].n_deaths += 1;
            self.remove_shock(i);
            self.refresh_around(cell);
            return Ok(());
        }
        let k = if dir > 0 {
            self.field.node_at(cell, 1).unwrap_or(cell)
        } else {
            cell
        };
        let u_plus = self.field.u_node(k, self.now);
        let x_unw = self.shocks[i].xl_unw + if dir > 0 { h } else { 0.0 };
        let xk = self.field.node_x(k);
        if u_plus <= self.u_stop * self.thr_node(k) {
            let kind = if self.opts.creep == CreepRule::Stop && self.opts.gamma > 0.0 {
                PathKind::CreepStop
            } else {
                PathKind::Death
            };
            self.accumulate(i, x_unw, 0.0_f64.max(u_plus), false);
            self.record(i, xk, u_plus, f64::NAN, kind, kind == PathKind::CreepStop);
            let ev = self.shocks[i].event;
            self.events[ev].n_deaths += 1;
            self.remove_shock(i);
            self.refresh_around(k);
            return Ok(());
        }
        let (um, creep) = self.u_minus(u_plus, self.thr_node(k));
        {
            let id = self.shocks[i].id;
            let f = &mut self.field;
            f.prev[k] = f.b[k];
            f.b[k] = um - f.v * (self.now - f.epoch);
            f.reset_by[k] = id;
            self.stamp += 1;
            self.prev_stamp[k] = self.reset_stamp[k];
            self.reset_stamp[k] = self.stamp;
        }
        self.accumulate(i, x_unw, u_plus - um, creep);
        let n = self.field.n;
        let exits = !self.field.periodic && ((dir > 0 && k == n - 1) || (dir < 0 && k == 0));
        if exits {
            self.record(i, xk, u_plus, um, PathKind::Exit, creep);
            let ev = self.shocks[i].event;
            self.events[ev].n_exits += 1;
            self.remove_shock(i);
            self.refresh_around(k);
            return Ok(());
        }
        self.record(i, xk, u_plus, um, PathKind::Node, creep);
        let (new_cell, s0) = if dir > 0 {
            (k, 0.0)
        } else {
            (self.field.node_at(k, -1).unwrap_or(0), 1.0)
        };
        self.sched.moved(i, cell, new_cell);
        {
            let sh = &mut self.shocks[i];
            sh.xl_unw += if dir > 0 { h } else { -h };
            sh.cell = new_cell;
            sh.traj.s_start = s0;
            sh.pos.clear();
            sh.traj.pts.clear();
            sh.traj.pts.push(TrajPoint {
                y: 0.0,
                t: self.now,
                f: 0.0,
            });
        }
        let poly = self.gather_for_shock(i);
        self.start_trajectory(i, poly, s0, dir)?;
        self.refresh_around(k);
        Ok(())
    }

    fn collision(&mut self, a: usize, b: usize, s: f64) {
        let h = self.field.h;
        let cell = self.shocks[a].cell;
        let x = self.field.node_x(cell) + s * h;
        // u_+ at the meeting point from both interpolants (they may differ where the cell
        // is crowded with shocks); u <= 1 wherever blocks are stuck
        let thr = self.thr_at(cell, s);
        let up =
            (0.5 * (self.shocks[a].cf.u(s, self.now) + self.shocks[b].cf.u(s, self.now))).min(thr);
        // (u_+ <= 0 can only be a rounding-level overshoot of a death threshold here)
        let (um, creep) = if up > 0.0 {
            self.u_minus(up, thr)
        } else {
            (up, false)
        };
        for &i in &[a, b] {
            let xu = self.shocks[i].xl_unw + s * h;
            self.accumulate(i, xu, up - um, creep);
            self.record(i, x, up, um, PathKind::Annihilation, creep);
        }
        let ev = self.shocks[a].event;
        self.events[ev].n_annihilations += 1;
        // if the two shocks belong to different events (cannot happen: events are
        // defined by overlap in time), merge nothing.
        let (hi, lo) = if a > b { (a, b) } else { (b, a) };
        self.remove_shock(hi);
        self.remove_shock(lo);
        self.refresh_around(cell);
    }
}

/// Shock indices near a cell: on the stack while there are few (the usual case; the
/// neighbour searches run several times per engine event).
enum Near {
    Few([usize; 16], usize),
    Many(Vec<usize>),
}

impl Default for Near {
    fn default() -> Self {
        Near::Few([0; 16], 0)
    }
}

impl Near {
    fn push(&mut self, q: usize) {
        match self {
            Near::Few(buf, n) if *n < buf.len() => {
                buf[*n] = q;
                *n += 1;
            }
            Near::Few(buf, n) => {
                let mut v = buf[..*n].to_vec();
                v.push(q);
                *self = Near::Many(v);
            }
            Near::Many(v) => v.push(q),
        }
    }

    fn as_slice(&self) -> &[usize] {
        match self {
            Near::Few(buf, n) => &buf[..*n],
            Near::Many(v) => v,
        }
    }

    fn iter(&self) -> std::slice::Iter<'_, usize> {
        self.as_slice().iter()
    }

    #[cfg(test)]
    fn len(&self) -> usize {
        self.as_slice().len()
    }

    fn sort(&mut self) {
        match self {
            Near::Few(buf, n) => buf[..*n].sort_unstable(),
            Near::Many(v) => v.sort_unstable(),
        }
    }
}

/// Pick the most centred window of contiguous valid nodes (offsets -3..=4 at indices
/// 0..8) that contains the required offsets, with up to four points.
fn choose_window(vals: &[f64; 8], ok: &[bool; 8], need: &[i64]) -> Option<CellPoly> {
    for m in (1..=4usize).rev() {
        let mut best: Option<(f64, usize)> = None;
        for start in 0..=(8 - m) {
            if !(start..start + m).all(|q| ok[q]) {
                continue;
            }
            let o0 = start as i64 - 3;
            if !need.iter().all(|&o| o >= o0 && o < o0 + m as i64) {
                continue;
            }
            let centre = o0 as f64 + (m as f64 - 1.0) / 2.0;
            let score = (centre - 0.5).abs();
            if best.is_none_or(|(b, _)| score < b) {
                best = Some((score, start));
            }
        }
        if let Some((_, start)) = best {
            return Some(CellPoly::through(start as i32 - 3, &vals[start..start + m]));
        }
    }
    None
}

#[cfg(test)]
mod tests;
