//! The free boundary problem in the plane: ruptures as fronts over a slowly loading
//! field, solved by fast marching (docs/free_boundary_2d.md).
//!
//! Away from fronts the medium is stuck and u_t = v. A front whose radius of curvature is
//! much larger than its width has the planar structure locally, so it moves along its
//! normal at c(u_+/s) (u_+ the stress ahead when it arrives, s the threshold, 1 by default)
//! and leaves u_-(u_+) behind: the 1D engine's rules, from the same code
//! ([`SpeedLaw::slowness`], [`SpeedLaw::reset_stress`]). The arrival time T of a rupture
//! born at t_0 obeys the eikonal equation
//!
//! ```text
//!     |grad T| = 1 / c(u(x, T)),     u(x, T) = u(x, t_0) + v (T - t_0),
//! ```
//!
//! whose speed depends on T only through the stress of the node itself: the local update
//! of fast marching is a scalar equation in T ([`eikonal`]), and the marching stays causal
//! (the update is never earlier than the neighbours it uses). The engine is event driven
//! with no time step: the next event is the earliest of the smallest trial arrival time
//! (accept the node: reset it to u_-), the next birth (the node where u - s is largest
//! reaches 0 at epoch - max(b - s)/v, read from a max-tree over the nodes) and the next
//! noise candidate. Quiet loading costs nothing.
//!
//! Rules (the 1D engine's, node by node):
//! - a node whose u_+ at arrival is at or below the stopping stress (0 with the creep rule
//!   `zero`, u_c s with `stop`; the 1D engine's shock death) stops the front there: it is
//!   not swept, and may be reached later in the same rupture only by a front arriving
//!   after that time (its earlier neighbours are no longer upwind of it);
//! - behind a front u_- < 0 in the pulse regime, and a node swept by a live rupture is
//!   never entered again by it or by another live rupture: fronts annihilate where they
//!   meet (between ruptures: `contacts`);
//! - a node that is a trial node of a live front is not a birth site (the front sweeps
//!   it, at infinite speed where u reaches s): the 1D engine's "a maximum reaching 1 in a
//!   cell a shock is crossing is swept by that shock";
//! - a node reaching the threshold at the instant (to rounding) a live rupture sweeps one
//!   of its eight neighbours is part of that rupture, not a birth of its own: a ridge
//!   through diagonal nodes, or a maximum shared by two, is one rupture (the diagonal
//!   node is no trial node of the front, whose stencil is along the axes);
//! - ties: a front arrival before a birth before a noise candidate; among arrivals the
//!   smaller node index.

pub mod checkpoint;
pub mod eikonal;
pub mod grid;
mod noise2d;
pub mod rupture;
mod shape;
#[cfg(test)]
mod shape_tests;
#[cfg(test)]
mod tests;

use crate::error::{check_at_least, Error, Result};
use crate::free_boundary::births::MaxTree;
use crate::free_boundary::nucleation::NoiseRun;
use crate::free_boundary::{CreepRule, SpeedLaw, Stop};
use eikonal::Term;
pub use grid::Grid;
pub use rupture::{Origin, Rupture};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// No rupture / no node.
const NONE: u32 = u32::MAX;

/// Births whose stresses reached the threshold within this (relative to the threshold) of
/// each other, on neighbouring nodes, are one rupture ([`FreeBoundary2D::birth`]): ties to
/// rounding, far below any stress the grid resolves (a h^2 ~ 1e-4 for a maximum of
/// curvature 1e-2 at h = 0.1).
const BIRTH_TIE: f64 = 1e-12;

/// Settings of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options2D {
    /// Damping gamma, 0 <= gamma < 1.
    pub gamma: f64,
    /// Loading rate v >= 0.
    pub v: f64,
    /// Creep rule (as in the 1D engine).
    pub creep: CreepRule,
    /// Second-order upwind differences where the stencil allows (else first order).
    pub second_order: bool,
    /// Keep each rupture's arrival times.
    pub record_arrivals: bool,
    /// The curvature correction c_n = c - D kappa: (D along the axes, D along the
    /// diagonals), or None (the `shape` module).
    pub curvature: Option<(f64, f64)>,
}

impl Default for Options2D {
    fn default() -> Self {
        Options2D {
            gamma: 0.3,
            v: 1e-3,
            creep: CreepRule::Zero,
            second_order: true,
            record_arrivals: false,
            curvature: None,
        }
    }
}

/// A trial arrival in the heap: earliest time first, then the smaller node.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry {
    t: f64,
    k: u32,
    ver: u32,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        o.t.total_cmp(&self.t).then(o.k.cmp(&self.k))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// The two-dimensional free boundary engine.
#[derive(Debug, Clone)]
pub struct FreeBoundary2D {
    grid: Grid,
    opts: Options2D,
    law: SpeedLaw,
    /// The planar speed along the diagonals (the `shape` module), or None.
    law_diag: Option<SpeedLaw>,
    /// The curvature coefficient as a table over directions (the `shape` module), or None.
    curv_dirs: Option<shape::Directions>,
    u_c: f64,
    u_stop: f64,
    threshold: Option<Vec<f64>>,
    /// u(k, t) = b[k] + v (t - epoch).
    b: Vec<f64>,
    epoch: f64,
    now: f64,
    /// Last arrival time at each node (NaN: never swept).
    t_arr: Vec<f64>,
    /// Rupture that last swept each node (NONE: never).
    label: Vec<u32>,
    /// Time the front last stopped at each node (-inf: never).
    stopped: Vec<f64>,
    /// Trial arrival time and its rupture (NONE: not a trial node).
    tent: Vec<f64>,
    tent_rup: Vec<u32>,
    /// Version of each node's heap entry (older entries are stale).
    ver: Vec<u32>,
    /// Trial nodes whose time was given (seeds of a trigger or a birth): never lowered.
    seed: Vec<bool>,
    heap: BinaryHeap<Entry>,
    /// max over non-trial nodes of b - s.
    tree: MaxTree,
    ruptures: Vec<Rupture>,
    live: usize,
    completed: usize,
    steps: u64,
    noise: Option<NoiseRun>,
    /// The noise's local bound (with noise only).
    tiles: Option<noise2d::Tiles>,
}

impl FreeBoundary2D {
    /// A run on `grid` with initial stress `u0` (row by row, k = j nx + i; u0 < s
    /// everywhere), front-speed law `law` and optional threshold field (> 0 at every node;
    /// None: s = 1).
    pub fn new(
        grid: Grid,
        u0: &[f64],
        opts: Options2D,
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
        if !opts.v.is_finite() {
            return Err(Error::InvalidParameter {
                name: "v",
                value: opts.v,
                allowed: "finite v >= 0",
            });
        }
        if let Some((da, dd)) = opts.curvature {
            for (name, d) in [("curvature D_axis", da), ("curvature D_diag", dd)] {
                if !(d.is_finite() && d >= 0.0) {
                    return Err(Error::InvalidParameter {
                        name,
                        value: d,
                        allowed: "finite D >= 0 (c_n = c - D kappa)",
                    });
                }
            }
        }
        let n = grid.n();
        if u0.len() != n {
            return Err(Error::InvalidParameter {
                name: "u0",
                value: u0.len() as f64,
                allowed: "one value per grid node (nx ny)",
            });
        }
        if let Some(th) = threshold {
            if th.len() != n {
                return Err(Error::InvalidParameter {
                    name: "threshold",
                    value: th.len() as f64,
                    allowed: "one threshold per grid node (nx ny)",
                });
            }
            if let Some(&s) = th.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
                return Err(Error::InvalidParameter {
                    name: "threshold",
                    value: s,
                    allowed: "finite threshold > 0 at every node",
                });
            }
        }
        for (k, &u) in u0.iter().enumerate() {
            let s = threshold.map_or(1.0, |t| t[k]);
            if !(u.is_finite() && u < s) {
                return Err(Error::InvalidParameter {
                    name: "u0",
                    value: u,
                    allowed: "finite u0 < threshold (1 by default) everywhere (u = threshold \
                              starts a slip at t = 0)",
                });
            }
        }
        let u_c = law.critical_stress(opts.gamma);
        let u_stop = match opts.creep {
            CreepRule::Zero => 0.0,
            CreepRule::Stop => u_c,
        };
        let mut fb = FreeBoundary2D {
            grid,
            opts,
            law,
            law_diag: None,
            curv_dirs: None,
            u_c,
            u_stop,
            threshold: threshold.map(<[f64]>::to_vec),
            b: u0.to_vec(),
            epoch: 0.0,
            now: 0.0,
            t_arr: vec![f64::NAN; n],
            label: vec![NONE; n],
            stopped: vec![f64::NEG_INFINITY; n],
            tent: vec![f64::NAN; n],
            tent_rup: vec![NONE; n],
            ver: vec![0; n],
            seed: vec![false; n],
            heap: BinaryHeap::new(),
            tree: MaxTree::new(n),
            ruptures: Vec::new(),
            live: 0,
            completed: 0,
            steps: 0,
            noise: None,
            tiles: None,
        };
        for k in 0..n {
            fb.tree.set(k, fb.b[k] - fb.thr(k));
        }
        Ok(fb)
    }

    // ------------------------------------------------------------------ accessors
    /// Current time.
    pub fn time(&self) -> f64 {
        self.now
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The options.
    pub fn options(&self) -> &Options2D {
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

    /// The threshold field (None: s = 1).
    pub fn threshold(&self) -> Option<&[f64]> {
        self.threshold.as_deref()
    }

    /// u at every node now (row by row).
    pub fn u_nodes(&self) -> Vec<f64> {
        let d = self.opts.v * (self.now - self.epoch);
        self.b.iter().map(|&b| b + d).collect()
    }

    /// The last arrival time at every node (NaN where no front has passed).
    pub fn last_arrival(&self) -> &[f64] {
        &self.t_arr
    }

    /// The rupture catalog (complete and running).
    pub fn ruptures(&self) -> &[Rupture] {
        &self.ruptures
    }

    /// Ruptures complete.
    pub fn completed(&self) -> usize {
        self.completed
    }

    /// Ruptures running.
    pub fn live(&self) -> usize {
        self.live
    }

    /// Engine events so far (front arrivals, births, noise candidates).
    pub fn steps(&self) -> u64 {
        self.steps
    }

    #[inline]
    fn thr(&self, k: usize) -> f64 {
        self.threshold.as_ref().map_or(1.0, |t| t[k])
    }

    #[inline]
    fn u_at(&self, k: usize, t: f64) -> f64 {
        self.b[k] + self.opts.v * (t - self.epoch)
    }

    #[inline]
    fn is_live(&self, r: u32) -> bool {
        r != NONE && !self.ruptures[r as usize].complete
    }

    // ------------------------------------------------------------------ starts
    /// Start a rupture now whose given nodes are reached at the given times (>= now; the
    /// seeds of the march, never lowered by it). Every node must be free of live ruptures.
    pub fn trigger(&mut self, seeds: &[(usize, f64)]) -> Result<usize> {
        self.start(seeds, Origin::Trigger, None)
    }

    /// Trigger a rupture now on the disk of radius `radius` around (x, y): every node in
    /// it is reached now (at least the nearest node).
    pub fn trigger_disk(&mut self, x: f64, y: f64, radius: f64) -> Result<usize> {
        check_at_least("radius", radius, 0.0, "radius >= 0")?;
        let c = self.grid.nearest(x, y);
        let r2 = radius * radius;
        let (cx, cy) = self.grid.xy(c);
        let reach = (radius / self.grid.h).ceil() as i64 + 1;
        let mut seeds = vec![(c, self.now)];
        let (ic, jc) = self.grid.ij(c);
        for dj in -reach..=reach {
            for di in -reach..=reach {
                if di == 0 && dj == 0 {
                    continue;
                }
                let Some(k) = self.offset(ic, jc, di, dj) else {
                    continue;
                };
                let (kx, ky) = (
                    cx + di as f64 * self.grid.h - x,
                    cy + dj as f64 * self.grid.h - y,
                );
                if kx * kx + ky * ky <= r2 && !seeds.iter().any(|s| s.0 == k) {
                    seeds.push((k, self.now));
                }
            }
        }
        self.start(&seeds, Origin::Trigger, Some((x, y)))
    }

    /// Node (i + di, j + dj), wrapped on periodic axes, None outside a free one.
    fn offset(&self, i: usize, j: usize, di: i64, dj: i64) -> Option<usize> {
        let g = &self.grid;
        let f = |p: usize, d: i64, n: usize, b| -> Option<usize> {
            let q = p as i64 + d;
            if b == crate::free_boundary::Boundary::Periodic {
                Some(q.rem_euclid(n as i64) as usize)
            } else if (0..n as i64).contains(&q) {
                Some(q as usize)
            } else {
                None
            }
        };
        Some(f(j, dj, g.ny, g.by)? * g.nx + f(i, di, g.nx, g.bx)?)
    }

    fn start(
        &mut self,
        seeds: &[(usize, f64)],
        origin: Origin,
        at: Option<(f64, f64)>,
    ) -> Result<usize> {
        if seeds.is_empty() {
            return Err(Error::InvalidParameter {
                name: "seeds",
                value: 0.0,
                allowed: "at least one node",
            });
        }
        for &(k, t) in seeds {
            if k >= self.grid.n() {
                return Err(Error::InvalidParameter {
                    name: "seed node",
                    value: k as f64,
                    allowed: "a node index < nx ny",
                });
            }
            if !(t.is_finite() && t >= self.now) {
                return Err(Error::InvalidParameter {
                    name: "seed time",
                    value: t,
                    allowed: "finite and not before the engine's time",
                });
            }
            // (a birth may fall on a node a long live rupture swept: it starts anew there)
            let swept_live = origin != Origin::Birth && self.is_live(self.label[k]);
            if self.tent_rup[k] != NONE || swept_live {
                return Err(Error::InvalidParameter {
                    name: "seed node",
                    value: k as f64,
                    allowed: "a node outside every live rupture",
                });
            }
        }
        let id = self.ruptures.len();
        if id >= NONE as usize {
            return Err(Error::InvalidParameter {
                name: "ruptures",
                value: id as f64,
                allowed: "fewer than 2^32 - 1 ruptures in one engine",
            });
        }
        let k0 = seeds[0].0;
        let xy = at.unwrap_or_else(|| self.grid.xy(k0));
        let u = self.u_at(k0, self.now);
        self.ruptures
            .push(Rupture::new(id, origin, self.now, xy, u));
        self.live += 1;
        for &(k, t) in seeds {
            if self.tent_rup[k] != NONE {
                continue; // a node given twice: the first time
            }
            self.seed[k] = true;
            self.set_trial(k, t, id as u32);
        }
        Ok(id)
    }

    fn set_trial(&mut self, k: usize, t: f64, r: u32) {
        let old = self.tent_rup[k];
        if old != r {
            if old != NONE {
                self.ruptures[old as usize].trials -= 1;
            } else {
                self.tree.set(k, f64::NEG_INFINITY);
            }
            self.ruptures[r as usize].trials += 1;
        }
        self.tent[k] = t;
        self.tent_rup[k] = r;
        self.ver[k] = self.ver[k].wrapping_add(1);
        self.heap.push(Entry {
            t,
            k: k as u32,
            ver: self.ver[k],
        });
    }

    // ------------------------------------------------------------------ the march
    /// The earliest valid trial entry (stale ones dropped).
    fn front_time(&mut self) -> f64 {
        while let Some(e) = self.heap.peek() {
            let k = e.k as usize;
            if self.tent_rup[k] != NONE && self.ver[k] == e.ver {
                return e.t;
            }
            self.heap.pop();
        }
        f64::INFINITY
    }

    fn birth_time(&self) -> f64 {
        let (m, _) = self.tree.max();
        if self.opts.v > 0.0 && m.is_finite() {
            (self.epoch - m / self.opts.v).max(self.now)
        } else {
            f64::INFINITY
        }
    }

    /// Accept (or stop at) the earliest trial node.
    fn arrive(&mut self) {
        let e = self.heap.pop().expect("front_time found an entry");
        let k = e.k as usize;
        let r = self.tent_rup[k];
        let t = e.t.max(self.now);
        self.now = t;
        self.tent_rup[k] = NONE;
        self.ver[k] = self.ver[k].wrapping_add(1);
        self.seed[k] = false;
        self.ruptures[r as usize].trials -= 1;
        let s = self.thr(k);
        let u_plus = self.u_at(k, t);
        if u_plus <= self.u_stop * s {
            self.stopped[k] = t;
            self.ruptures[r as usize].n_stopped += 1;
            self.tree.set(k, self.b[k] - s);
            self.maybe_end(r);
            return;
        }
        let thr = self.threshold.is_some().then_some(s);
        let (um, creep) = self
            .law
            .reset_stress(u_plus, thr, self.opts.gamma, self.u_c);
        self.b[k] = um - self.opts.v * (t - self.epoch);
        self.tree.set(k, self.b[k] - s);
        self.label[k] = r;
        self.t_arr[k] = t;
        let h2 = self.grid.h * self.grid.h;
        {
            let rup = &mut self.ruptures[r as usize];
            rup.n_nodes += 1;
            rup.area += h2;
            rup.moment += (u_plus - um) * h2;
            rup.n_creep += usize::from(creep);
            rup.t_end = t;
            rup.nodes.push(k as u32);
        }
        for axis in 0..2 {
            for dir in [-1i8, 1] {
                if let Some(q) = self.grid.step(k, axis, dir) {
                    self.consider(q, r);
                }
            }
        }
        self.maybe_end(r);
    }

    /// A neighbour q of a node just swept by rupture r: its trial time from r.
    fn consider(&mut self, q: usize, r: u32) {
        let other = self.tent_rup[q];
        if other != NONE && self.seed[q] {
            return;
        }
        let lq = self.label[q];
        if self.is_live(lq) {
            if lq != r {
                self.ruptures[r as usize].contacts += 1;
            }
            return;
        }
        let t = self.update(q, r).max(self.now);
        // with the curvature term a later update of the same rupture sees more of the
        // front around q: it replaces the earlier one, later or not (the `shape` module)
        let newer = other == r && self.opts.curvature.is_some();
        if other == NONE || t < self.tent[q] || newer {
            if other != NONE && other != r {
                self.ruptures[r as usize].contacts += 1;
                self.ruptures[other as usize].contacts += 1;
                self.set_trial(q, t, r);
                self.maybe_end(other);
            } else {
                self.set_trial(q, t, r);
            }
        }
    }

    /// The arrival time at q from the nodes rupture r has swept around it.
    fn update(&self, q: usize, r: u32) -> f64 {
        let tb = self.stopped[q];
        let ok = |j: usize| self.label[j] == r && self.t_arr[j] >= tb;
        let mut terms = [Term { alpha: 1.0, d: 0.0 }; 2];
        let mut axes = [0usize; 2];
        let mut m = [f64::INFINITY; 2];
        let mut na = 0;
        for axis in 0..2 {
            let mut best: Option<(f64, f64, f64)> = None; // (T1, alpha, m)
            for dir in [-1i8, 1] {
                let Some(j1) = self.grid.step(q, axis, dir) else {
                    continue;
                };
                if !ok(j1) {
                    continue;
                }
                let t1 = self.t_arr[j1];
                if best.is_some_and(|b| b.0 <= t1) {
                    continue;
                }
                let mut cand = (t1, 1.0, t1);
                if self.opts.second_order {
                    if let Some(j2) = self.grid.step(j1, axis, dir) {
                        if j2 != q && ok(j2) && self.t_arr[j2] <= t1 {
                            let t2 = self.t_arr[j2];
                            cand = (t1, 2.25, (4.0 * t1 - t2) / 3.0);
                        }
                    }
                }
                best = Some(cand);
            }
            if let Some((_, alpha, mm)) = best {
                terms[na].alpha = alpha;
                axes[na] = axis;
                m[na] = mm;
                na += 1;
            }
        }
        debug_assert!(na > 0, "a neighbour was just swept");
        let m_lo = m[0].min(m[1]);
        for a in 0..na {
            terms[a].d = m[a] - m_lo;
        }
        let s = self.thr(q);
        let law = &self.law;
        let u_lo = self.u_at(q, m_lo);
        let (h, v) = (self.grid.h, self.opts.v);
        if self.shaped() {
            let kappa = if self.opts.curvature.is_some() {
                self.curvature_at(q, r)
            } else {
                0.0
            };
            let (tm, ax) = (&terms[..na], &axes[..na]);
            let y = |u: f64, tau: f64| self.shaped_y(u, s, kappa, tm, ax, tau);
            return m_lo + eikonal::solve(tm, h, u_lo, v, y);
        }
        let y = |u: f64, _: f64| {
            let f = law.slowness(u / s);
            f * f
        };
        m_lo + eikonal::solve(&terms[..na], h, u_lo, v, y)
    }

    fn maybe_end(&mut self, r: u32) {
        let ri = r as usize;
        if self.ruptures[ri].trials > 0 || self.ruptures[ri].complete {
            return;
        }
        let perimeter = self.perimeter(r);
        let keep = self.opts.record_arrivals;
        let arrivals: Vec<f64> = if keep {
            self.ruptures[ri]
                .nodes
                .iter()
                .map(|&k| self.t_arr[k as usize])
                .collect()
        } else {
            Vec::new()
        };
        let nodes = std::mem::take(&mut self.ruptures[ri].nodes);
        self.noise_rupture_done(&nodes);
        self.ruptures[ri].nodes = nodes;
        let rup = &mut self.ruptures[ri];
        rup.perimeter = perimeter;
        rup.complete = true;
        if rup.n_nodes == 0 {
            rup.t_end = rup.t_start;
        }
        if keep {
            rup.arrivals = arrivals;
        } else {
            rup.nodes = Vec::new();
        }
        self.live -= 1;
        self.completed += 1;
    }

    /// Crofton estimate of the perimeter of the nodes labelled r (rupture module docs).
    fn perimeter(&self, r: u32) -> f64 {
        let (mut n_axis, mut n_diag) = (0usize, 0usize);
        for &k in &self.ruptures[r as usize].nodes {
            let k = k as usize;
            for axis in 0..2 {
                for dir in [-1i8, 1] {
                    if let Some(q) = self.grid.step(k, axis, dir) {
                        n_axis += usize::from(self.label[q] != r);
                        if axis == 0 {
                            for dy in [-1i8, 1] {
                                if let Some(d) = self.grid.step(q, 1, dy) {
                                    n_diag += usize::from(self.label[d] != r);
                                }
                            }
                        }
                    }
                }
            }
        }
        let h = self.grid.h;
        std::f64::consts::PI / 8.0 * (n_axis as f64 * h + n_diag as f64 * h / 2f64.sqrt())
    }

    /// A birth at the node where u - s is largest, now; absorbed by a live rupture that
    /// swept one of the node's eight neighbours at this instant (a tie to rounding: the
    /// two reached the threshold together, their fronts are connected: one rupture).
    fn birth(&mut self) {
        let (_, k) = self.tree.max();
        if let Some(r) = self.absorbing_rupture(k) {
            self.seed[k] = true;
            self.set_trial(k, self.now, r);
            return;
        }
        let id = self
            .start(&[(k, self.now)], Origin::Birth, None)
            .expect("a birth node is outside live ruptures");
        self.ruptures[id].u_start = self.thr(k);
    }

    /// The live rupture that swept one of the eight neighbours of node k at this instant
    /// (within [`BIRTH_TIE`] of stress at the loading rate), if any: a birth at k is then
    /// part of it. Along a ridge through diagonal nodes (or a maximum shared by two diagonal
    /// nodes) the nodes reach the threshold together, but a diagonal node is not a trial
    /// node of its neighbour's front (the stencil is along the axes) and was born apart.
    fn absorbing_rupture(&self, k: usize) -> Option<u32> {
        let (i, j) = self.grid.ij(k);
        let tie = BIRTH_TIE * self.thr(k);
        for dj in -1i64..=1 {
            for di in -1i64..=1 {
                if di == 0 && dj == 0 {
                    continue;
                }
                let Some(q) = self.offset(i, j, di, dj) else {
                    continue;
                };
                let r = self.label[q];
                if self.is_live(r) && self.opts.v * (self.now - self.t_arr[q]) <= tie {
                    return Some(r);
                }
            }
        }
        None
    }

    /// Move the epoch to now (b and v (t - epoch) would otherwise both grow like v t).
    fn rebase(&mut self) {
        let d = self.opts.v * (self.now - self.epoch);
        for k in 0..self.b.len() {
            self.b[k] += d;
        }
        self.epoch = self.now;
        self.noise_rebase(d);
        for k in 0..self.b.len() {
            let val = if self.tent_rup[k] != NONE {
                f64::NEG_INFINITY
            } else {
                self.b[k] - self.thr(k)
            };
            self.tree.set(k, val);
        }
    }

    /// Advance to `t_stop` at most, with at most `max_steps` engine events in this call,
    /// stopping once `max_events` ruptures are complete.
    pub fn advance(&mut self, t_stop: f64, max_steps: u64, max_events: usize) -> Result<Stop> {
        if t_stop.is_nan() {
            return Err(Error::InvalidParameter {
                name: "t_stop",
                value: t_stop,
                allowed: "a time (not NaN)",
            });
        }
        let mut done = 0u64;
        loop {
            if self.completed >= max_events {
                return Ok(Stop::Events);
            }
            if done >= max_steps {
                return Ok(Stop::Steps);
            }
            let tf = self.front_time();
            let tb = self.birth_time();
            let tn = self.noise_time();
            let t = tf.min(tb).min(tn);
            if t > t_stop {
                if t_stop > self.now {
                    self.now = t_stop;
                }
                return Ok(Stop::Time);
            }
            if tf <= tb && tf <= tn {
                self.arrive();
            } else if tb <= tn {
                self.now = tb;
                self.birth();
            } else {
                self.now = tn;
                self.noise_event();
            }
            done += 1;
            self.steps += 1;
            if self.opts.v * (self.now - self.epoch) > 1.0 {
                self.rebase();
            }
        }
    }
}
