//! Spontaneous nucleation by noise in the plane, with the 1D engine's rate laws
//! ([`crate::noise::NoiseLaw`]): ruptures start at random points at a rate density
//! Lambda(u) per unit area and time, wherever the medium is stuck, outside live ruptures,
//! with u > u_stop (an excitable medium) and u < 1.
//!
//! Drawn exactly by thinning a bound process, with a bound that is local in space and
//! piecewise constant in time, so that a candidate costs O(log) and the candidates per
//! nucleation do not grow with the grid:
//!
//! - the cells are grouped in square tiles of [`TILE`] x [`TILE`] cells; each tile keeps
//!   `bmax`, an upper bound of b over the nodes of its cells (u = b + v (t - epoch)). b
//!   only falls (a front resets u_+ to u_- < u_+) or moves with the epoch (the rebase adds
//!   the same d to b and to `bmax`), so a bound stays a bound; it is tightened (recomputed
//!   over the tile) when a rupture that swept nodes of the tile completes;
//! - time runs in windows [t_0, t_w] with v (t_w - t_0) = [`WINDOW_DU`] (one window without
//!   loading): in a window every point of tile i has u <= U_i = min(1, bmax_i + v (t_w -
//!   epoch)), so Lambda(u) <= rate G(U_i) (G the running maximum of g, the law's
//!   envelope), and 0 where U_i <= u_stop (no nucleation there);
//! - the bound process has the constant rate R = rate sum_i area_i G(U_i) until the window
//!   ends or a tile is tightened (a sum tree over the tiles): the next candidate falls when
//!   R (t - t_mark) reaches the unit exponential `e_left` (consumed whenever R changes:
//!   memorylessness makes this exact); it picks tile i with probability area_i G(U_i)/sum,
//!   a uniform cell of it and a uniform point in the cell, where u is the bilinear
//!   interpolant of the cell's four nodes (all four outside live ruptures and trial nodes,
//!   else it is rejected: the point is in or at a rupture), and is kept with probability
//!   g(u)/G(U_i). A kept candidate starts a rupture at the nearest of the four nodes, now
//!   (u_start is u at the point).
//!
//! The generator's state, the candidate clock, the tile bounds and weights and the window
//! end are in the checkpoint.

use super::{FreeBoundary2D, Origin, NONE};
use crate::checkpoint_bytes::{bad, Reader, Writer};
use crate::error::Result;
use crate::free_boundary::nucleation::NoiseRun;
use crate::noise::NoiseLaw;

/// Cells per side of a tile of the noise bound.
pub(super) const TILE: usize = 16;
/// The growth of u over one window of the bound (1/256: with g = u^8 at u = 0.35 the
/// bound at the window's end is 9 % above the rate at its start).
pub(super) const WINDOW_DU: f64 = 1.0 / 256.0;

/// Sum segment tree over the tile weights (each inner node the sum of its children, so
/// the sums depend only on the leaves).
#[derive(Debug, Clone)]
struct SumTree {
    size: usize,
    s: Vec<f64>,
}

impl SumTree {
    fn new(n: usize) -> Self {
        let size = n.max(1).next_power_of_two();
        SumTree {
            size,
            s: vec![0.0; 2 * size],
        }
    }

    fn set(&mut self, i: usize, w: f64) {
        let mut p = i + self.size;
        self.s[p] = w;
        p /= 2;
        while p >= 1 {
            self.s[p] = self.s[2 * p] + self.s[2 * p + 1];
            p /= 2;
        }
    }

    fn rebuild(&mut self) {
        for p in (1..self.size).rev() {
            self.s[p] = self.s[2 * p] + self.s[2 * p + 1];
        }
    }

    fn total(&self) -> f64 {
        self.s[1]
    }

    fn leaf(&self, i: usize) -> f64 {
        self.s[self.size + i]
    }

    /// The leaf where the running sum passes `x` in [0, total).
    fn find(&self, mut x: f64) -> usize {
        let mut p = 1;
        while p < self.size {
            let l = self.s[2 * p];
            if x < l || self.s[2 * p + 1] <= 0.0 {
                p *= 2;
            } else {
                x -= l;
                p = 2 * p + 1;
            }
        }
        p - self.size
    }
}

/// The local bound of the noise (module docs).
#[derive(Debug, Clone)]
pub(super) struct Tiles {
    /// Tiles along x.
    ntx: usize,
    /// Upper bound of b over the nodes of each tile's cells.
    bmax: Vec<f64>,
    /// area_i G(U_i) per tile (0 where U_i <= u_stop).
    weight: SumTree,
    /// End of the current window.
    t_w: f64,
    /// Scratch flags (all false between calls): tiles already listed.
    dirty: Vec<bool>,
}

impl FreeBoundary2D {
    /// Turn on nucleation by noise with `law` (rate per unit area and time at u = 1),
    /// seeded by `seed`, from now on. A zero rate is no noise. Refused with a threshold
    /// field (the rate laws are written for the threshold 1), as in the 1D engine.
    pub fn set_noise(&mut self, law: NoiseLaw, seed: u64) -> Result<()> {
        self.noise = NoiseRun::for_engine(law, seed, self.now, self.threshold.is_some())?;
        self.tiles = None;
        if self.noise.is_some() {
            let (cx, cy) = self.grid.cells();
            let (ntx, nty) = (cx.div_ceil(TILE), cy.div_ceil(TILE));
            self.tiles = Some(Tiles {
                ntx,
                bmax: vec![f64::NEG_INFINITY; ntx * nty],
                weight: SumTree::new(ntx * nty),
                t_w: self.now,
                dirty: vec![false; ntx * nty],
            });
            for t in 0..ntx * nty {
                self.tighten(t);
            }
            self.new_window();
        }
        Ok(())
    }

    /// (candidates drawn, ruptures nucleated) so far; None without noise.
    pub fn noise_counters(&self) -> Option<(u64, u64)> {
        self.noise.as_ref().map(|n| (n.candidates, n.nucleations))
    }

    /// Cells [i0, i1) x [j0, j1) of tile t.
    fn tile_cells(&self, t: usize) -> (usize, usize, usize, usize) {
        let tl = self.tiles.as_ref().expect("noise on");
        let (cx, cy) = self.grid.cells();
        let (ti, tj) = (t % tl.ntx, t / tl.ntx);
        (
            ti * TILE,
            ((ti + 1) * TILE).min(cx),
            tj * TILE,
            ((tj + 1) * TILE).min(cy),
        )
    }

    /// The exact maximum of b over the nodes of tile t's cells.
    fn tighten(&mut self, t: usize) {
        let (i0, i1, j0, j1) = self.tile_cells(t);
        let (nx, ny) = (self.grid.nx, self.grid.ny);
        let mut m = f64::NEG_INFINITY;
        for j in j0..=j1 {
            let row = (j % ny) * nx;
            for i in i0..=i1 {
                m = m.max(self.b[row + i % nx]);
            }
        }
        self.tiles.as_mut().expect("noise on").bmax[t] = m;
    }

    /// The weight area_t G(U_t) of tile t in the current window.
    fn tile_weight(&self, t: usize) -> f64 {
        let tl = self.tiles.as_ref().expect("noise on");
        let nz = self.noise.as_ref().expect("noise on");
        let (i0, i1, j0, j1) = self.tile_cells(t);
        let load = if self.opts.v > 0.0 {
            self.opts.v * (tl.t_w - self.epoch)
        } else {
            0.0
        };
        let u = (tl.bmax[t] + load).min(1.0);
        if u > self.u_stop {
            let area = ((i1 - i0) * (j1 - j0)) as f64 * self.grid.h * self.grid.h;
            area * nz.law.envelope_g(u)
        } else {
            0.0
        }
    }

    /// Count the bound's integral up to now (before its rate changes).
    fn noise_settle(&mut self) {
        let now = self.now;
        let total = self.tiles.as_ref().map_or(0.0, |t| t.weight.total());
        let nz = self.noise.as_mut().expect("noise on");
        let rate = nz.law.rate * total;
        if rate > 0.0 {
            nz.e_left = (nz.e_left - rate * (now - nz.t_mark)).max(0.0);
        }
        nz.t_mark = now;
    }

    /// A new window from now: every tile's weight at its end.
    fn new_window(&mut self) {
        self.noise_settle();
        let v = self.opts.v;
        let now = self.now;
        let tl = self.tiles.as_mut().expect("noise on");
        tl.t_w = if v > 0.0 {
            now + WINDOW_DU / v
        } else {
            f64::INFINITY
        };
        let w: Vec<f64> = (0..tl.bmax.len()).map(|t| self.tile_weight(t)).collect();
        let tl = self.tiles.as_mut().expect("noise on");
        for (t, w) in w.into_iter().enumerate() {
            tl.weight.s[tl.weight.size + t] = w;
        }
        tl.weight.rebuild();
    }

    /// The rebase moved every b by d: the tile bounds move with them.
    pub(super) fn noise_rebase(&mut self, d: f64) {
        if let Some(tl) = self.tiles.as_mut() {
            for m in &mut tl.bmax {
                *m += d;
            }
        }
    }

    /// A rupture ended: tighten the tiles its nodes touched (O(area + tiles TILE^2)).
    pub(super) fn noise_rupture_done(&mut self, nodes: &[u32]) {
        if self.tiles.is_none() {
            return;
        }
        let ntx = self.tiles.as_ref().expect("checked").ntx;
        let (cx, cy) = self.grid.cells();
        let (nx, ny) = (self.grid.nx, self.grid.ny);
        let mut touched = Vec::new();
        for &k in nodes {
            let (i, j) = self.grid.ij(k as usize);
            for cj in [(j + ny - 1) % ny, j] {
                for ci in [(i + nx - 1) % nx, i] {
                    if ci < cx && cj < cy {
                        let t = (cj / TILE) * ntx + ci / TILE;
                        let tl = self.tiles.as_mut().expect("checked");
                        if !tl.dirty[t] {
                            tl.dirty[t] = true;
                            touched.push(t);
                        }
                    }
                }
            }
        }
        if touched.is_empty() {
            return;
        }
        self.noise_settle();
        for t in touched {
            self.tiles.as_mut().expect("checked").dirty[t] = false;
            self.tighten(t);
            let w = self.tile_weight(t);
            self.tiles.as_mut().expect("checked").weight.set(t, w);
        }
    }

    /// Time of the next noise event: a candidate, or the end of the window.
    pub(super) fn noise_time(&self) -> f64 {
        let (Some(nz), Some(tl)) = (&self.noise, &self.tiles) else {
            return f64::INFINITY;
        };
        let rate = nz.law.rate * tl.weight.total();
        let t = if rate > 0.0 {
            nz.t_mark + nz.e_left / rate
        } else {
            f64::INFINITY
        };
        t.min(tl.t_w).max(self.now)
    }

    /// The noise event now: the window's end or a candidate.
    pub(super) fn noise_event(&mut self) {
        let tl = self.tiles.as_ref().expect("noise on");
        let nz = self.noise.as_ref().expect("noise on");
        let rate = nz.law.rate * tl.weight.total();
        let t_cand = if rate > 0.0 {
            nz.t_mark + nz.e_left / rate
        } else {
            f64::INFINITY
        };
        if t_cand <= tl.t_w {
            self.noise_candidate();
        } else {
            self.new_window();
        }
    }

    /// A candidate now: the draws (tile, cell x, cell y, place in the cell (2),
    /// acceptance, next exponential) are made in this order whatever happens.
    fn noise_candidate(&mut self) {
        let now = self.now;
        let tl = self.tiles.as_ref().expect("noise on");
        let nz = self.noise.as_mut().expect("a candidate needs noise");
        nz.candidates += 1;
        let total = tl.weight.total();
        let t = tl.weight.find(nz.rng.uniform() * total);
        let ui = nz.rng.uniform();
        let uj = nz.rng.uniform();
        let sx = nz.rng.uniform();
        let sy = nz.rng.uniform();
        let a = nz.rng.uniform();
        nz.e_left = nz.rng.exponential();
        nz.t_mark = now;
        let w_t = tl.weight.leaf(t);
        let (i0, i1, j0, j1) = self.tile_cells(t);
        let area = ((i1 - i0) * (j1 - j0)) as f64 * self.grid.h * self.grid.h;
        let g_bound = w_t / area;
        let i = (i0 + (ui * (i1 - i0) as f64) as usize).min(i1 - 1);
        let j = (j0 + (uj * (j1 - j0) as f64) as usize).min(j1 - 1);
        let k00 = j * self.grid.nx + i;
        let k10 = self.grid.step(k00, 0, 1).expect("a cell has four nodes");
        let k01 = self.grid.step(k00, 1, 1).expect("a cell has four nodes");
        let k11 = self.grid.step(k10, 1, 1).expect("a cell has four nodes");
        let corners = [k00, k10, k01, k11];
        if corners
            .iter()
            .any(|&k| self.tent_rup[k] != NONE || self.is_live(self.label[k]))
        {
            return;
        }
        let uc = corners.map(|k| self.u_at(k, now));
        let u =
            (1.0 - sy) * ((1.0 - sx) * uc[0] + sx * uc[1]) + sy * ((1.0 - sx) * uc[2] + sx * uc[3]);
        let nz = self.noise.as_ref().expect("checked above");
        let g = nz.law.law.g(u);
        debug_assert!(
            !(u > self.u_stop && u < 1.0) || g <= g_bound * (1.0 + 1e-12),
            "the tile bound bounds the rate: g({u}) = {g} > {g_bound}"
        );
        if !(u > self.u_stop && u < 1.0) || a * g_bound >= g {
            return;
        }
        self.noise.as_mut().expect("checked above").nucleations += 1;
        let k = corners[usize::from(sx >= 0.5) + 2 * usize::from(sy >= 0.5)];
        let (x0, y0) = self.grid.xy(k00);
        let h = self.grid.h;
        let id = self
            .start(
                &[(k, now)],
                Origin::Nucleation,
                Some((x0 + sx * h, y0 + sy * h)),
            )
            .expect("the corners are outside live ruptures");
        self.ruptures[id].u_start = u;
    }

    /// The tile state (after the noise generator's) in a checkpoint.
    pub(super) fn write_tiles(&self, w: &mut Writer) {
        if let Some(tl) = &self.tiles {
            w.f(tl.t_w);
            w.fs(&tl.bmax);
            w.fs(&tl.weight.s[tl.weight.size..tl.weight.size + tl.bmax.len()]);
        }
    }

    /// Read what [`Self::write_tiles`] wrote.
    pub(super) fn read_tiles(&mut self, r: &mut Reader) -> Result<()> {
        if let Some(tl) = self.tiles.as_mut() {
            let n = tl.bmax.len();
            tl.t_w = r.f()?;
            let bmax = r.fs()?;
            let w = r.fs()?;
            if bmax.len() != n || w.len() != n {
                return Err(bad(r.i, "one noise bound per tile"));
            }
            tl.bmax = bmax;
            for (t, w) in w.into_iter().enumerate() {
                tl.weight.s[tl.weight.size + t] = w;
            }
            tl.weight.rebuild();
        }
        Ok(())
    }
}
