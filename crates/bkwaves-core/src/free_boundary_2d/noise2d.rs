//! Spontaneous nucleation by noise in the plane, with the 1D engine's rate laws
//! ([`crate::noise::NoiseLaw`]): ruptures start at random points at a rate density
//! Lambda(u) per unit area and time, wherever the medium is stuck, outside live ruptures,
//! with u > u_stop (an excitable medium) and u < 1.
//!
//! Drawn exactly by thinning, as in the 1D engine (`free_boundary::nucleation`): every
//! eligible point has u <= U(t) = M + 1 + v (t - epoch), M the largest b - 1 over the nodes
//! that are not trial nodes (the birth tree), so Lambda <= rate G(U(t)) (G the running
//! maximum of g) and the candidate process of rate (area) rate G(U(t)) bounds the
//! nucleation rate everywhere; its integrated rate is in closed form. A candidate falls
//! at a uniform point; u there is the bilinear interpolant of its cell's four nodes (all
//! four outside live ruptures and trial nodes, else it is rejected: the point is in or at
//! a rupture); it is kept with probability g(u)/G(U). A kept candidate starts a rupture
//! at the nearest of the four nodes, now (u_start is u at the point). The generator's
//! state and the candidate clock are in the checkpoint.

use super::{FreeBoundary2D, Origin, NONE};
use crate::error::{Error, Result};
use crate::free_boundary::nucleation::NoiseRun;
use crate::noise::NoiseLaw;

impl FreeBoundary2D {
    /// Turn on nucleation by noise with `law` (rate per unit area and time at u = 1),
    /// seeded by `seed`, from now on. A zero rate is no noise. Refused with a threshold
    /// field (the rate laws are written for the threshold 1), as in the 1D engine.
    pub fn set_noise(&mut self, law: NoiseLaw, seed: u64) -> Result<()> {
        if law.rate == 0.0 {
            self.noise = None;
            return Ok(());
        }
        if self.threshold.is_some() {
            return Err(Error::InvalidParameter {
                name: "noise",
                value: law.rate,
                allowed: "no noise with a threshold field (not implemented: the rate law \
                          Lambda(u) is written for the uniform threshold 1)",
            });
        }
        self.noise = Some(NoiseRun::new(law, seed, self.now));
        self.noise_sync();
        Ok(())
    }

    /// (candidates drawn, ruptures nucleated) so far; None without noise.
    pub fn noise_counters(&self) -> Option<(u64, u64)> {
        self.noise.as_ref().map(|n| (n.candidates, n.nucleations))
    }

    fn noise_bound(&self) -> f64 {
        let (m, _) = self.tree.max();
        if m.is_finite() {
            m + 1.0 + self.opts.v * (self.now - self.epoch)
        } else {
            f64::NAN
        }
    }

    pub(super) fn noise_time(&self) -> f64 {
        match &self.noise {
            Some(nz) if !nz.u_mark.is_nan() => {
                let tau = nz.law.envelope_time_to_mass(
                    nz.u_mark,
                    self.opts.v,
                    nz.e_left,
                    self.grid.area(),
                );
                (nz.t_mark + tau).max(self.now)
            }
            _ => f64::INFINITY,
        }
    }

    pub(super) fn noise_sync(&mut self) {
        if self.noise.is_none() {
            return;
        }
        let (u_now, area, v, now) = (self.noise_bound(), self.grid.area(), self.opts.v, self.now);
        let nz = self.noise.as_mut().expect("checked above");
        if !nz.u_mark.is_nan() {
            nz.e_left -= nz.law.envelope_mass(nz.u_mark, v, now - nz.t_mark, area);
        }
        nz.e_left = nz.e_left.max(0.0);
        nz.t_mark = now;
        nz.u_mark = u_now;
    }

    /// A candidate now: the draws (cell x, cell y, place in the cell (2), acceptance,
    /// next exponential) are made in this order whatever happens.
    pub(super) fn noise_candidate(&mut self) {
        let (cx, cy) = self.grid.cells();
        let (v, now) = (self.opts.v, self.now);
        let nz = self.noise.as_mut().expect("a candidate needs noise");
        nz.candidates += 1;
        let u_bound = nz.u_mark + v * (now - nz.t_mark);
        let i = ((nz.rng.uniform() * cx as f64) as usize).min(cx - 1);
        let j = ((nz.rng.uniform() * cy as f64) as usize).min(cy - 1);
        let sx = nz.rng.uniform();
        let sy = nz.rng.uniform();
        let a = nz.rng.uniform();
        nz.e_left = nz.rng.exponential();
        nz.t_mark = now;
        let g_bound = nz.law.envelope_g(u_bound);
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
        if !(u > self.u_stop && u < 1.0) || a * g_bound >= nz.law.law.g(u) {
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
}
