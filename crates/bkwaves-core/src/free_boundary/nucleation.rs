//! Spontaneous pair nucleation: noise in the free boundary problem (issue 14; the paper's
//! Sec. VI: "generation of pairs of counter-propagating waves at random points").
//!
//! Pairs are nucleated at a rate density Lambda(u(x, t)) ([`crate::noise::NoiseLaw`]) in
//! the stuck field away from shocks: the cells where births are looked for (no shock in
//! the cell, [`FreeBoundary::refresh_cell`]), wherever u > u_stop (0 with the creep rule
//! `zero`, u_c = gamma with `stop`): a pair needs an excitable medium, u_+ > 0, and with
//! the `stop` rule a pair at u <= u_c would end where it starts. Between 0 and u_c (rule
//! `zero`) the pair creeps like any shock there (u_- = 0, flagged).
//!
//! Event times are drawn exactly by thinning, never by stepping. Between engine events
//! every eligible point has u <= U(t) = M + v (t - epoch), M the largest cell maximum
//! (the birth tree), so Lambda(u) <= rate G(U(t)), G(u) = max_{y <= u} g(y) the running
//! maximum of the law ([`crate::noise::NoiseLaw::envelope`]; G = g for a non-decreasing
//! g): the candidate process of rate L rate G(U(t)) (L the domain length) bounds the
//! nucleation rate everywhere, and its integrated rate is in closed form
//! ([`crate::noise::NoiseLaw::envelope_mass`]). A candidate falls when that integral,
//! counted from `t_mark`, reaches the unit exponential `e_left`; its place is uniform on
//! the domain and it becomes a pair with probability g(u(x))/G(U) (0 outside eligible
//! cells).
//! After every engine event the integral up to now is subtracted from `e_left` and the
//! bound is taken anew (memorylessness makes this exact). The generator's state and the
//! clock (`e_left`, `t_mark`, `u_mark`) are in the checkpoint, so a restored run draws the
//! same numbers.

use super::catalog::PathKind;
use super::FreeBoundary;
use crate::checkpoint_bytes::{Reader, Writer};
use crate::error::Result;
use crate::noise::{NoiseLaw, Rng};

/// The noise of a run: its law and seed, the generator and the candidate clock. Shared by
/// the 1D and the 2D free boundary engines (the clock is the same thinning of a bound
/// rate; only what a candidate is differs).
#[derive(Debug, Clone)]
pub(crate) struct NoiseRun {
    pub(crate) law: NoiseLaw,
    pub(crate) seed: u64,
    pub(crate) rng: Rng,
    /// Integrated bound rate left before the next candidate (a unit exponential at draw).
    pub(crate) e_left: f64,
    /// Time from which `e_left` is counted.
    pub(crate) t_mark: f64,
    /// The bound U at `t_mark` (NaN: no eligible cell).
    pub(crate) u_mark: f64,
    /// Candidates drawn and pairs nucleated.
    pub(crate) candidates: u64,
    pub(crate) nucleations: u64,
}

impl NoiseRun {
    /// A fresh noise state for `law` seeded by `seed`, its clock started at `now`.
    pub(crate) fn new(law: NoiseLaw, seed: u64, now: f64) -> NoiseRun {
        let mut rng = Rng::new(seed);
        let e_left = rng.exponential();
        NoiseRun {
            law,
            seed,
            rng,
            e_left,
            t_mark: now,
            u_mark: f64::NAN,
            candidates: 0,
            nucleations: 0,
        }
    }

    /// The noise of an engine from `set_noise`: None for a zero rate (no noise), refused
    /// with a threshold field (the rate law Lambda(u) is written for the threshold 1).
    pub(crate) fn for_engine(
        law: NoiseLaw,
        seed: u64,
        now: f64,
        threshold_field: bool,
    ) -> Result<Option<NoiseRun>> {
        if law.rate == 0.0 {
            return Ok(None);
        }
        if threshold_field {
            return Err(crate::error::Error::InvalidParameter {
                name: "noise",
                value: law.rate,
                allowed: "no noise with a threshold field (not implemented: the rate law \
                          Lambda(u) is written for the uniform threshold 1)",
            });
        }
        Ok(Some(NoiseRun::new(law, seed, now)))
    }

    pub(crate) fn write_config(&self, w: &mut Writer) {
        self.law.write(w);
        w.u(self.seed);
    }

    pub(crate) fn write_state(&self, w: &mut Writer) {
        self.rng.write(w);
        for x in [self.e_left, self.t_mark, self.u_mark] {
            w.f(x);
        }
        w.u(self.candidates);
        w.u(self.nucleations);
    }

    pub(crate) fn read_state(&mut self, r: &mut Reader) -> Result<()> {
        self.rng = Rng::read(r)?;
        self.e_left = r.f()?;
        self.t_mark = r.f()?;
        self.u_mark = r.f()?;
        self.candidates = r.u()?;
        self.nucleations = r.u()?;
        Ok(())
    }
}

impl FreeBoundary {
    /// Turn on spontaneous nucleation with `law`, its generator seeded by `seed`, from
    /// now on. A zero rate leaves the engine exactly as without noise. Refused with a
    /// threshold field (the rate law Lambda(u) is written for the threshold 1).
    pub fn set_noise(&mut self, law: NoiseLaw, seed: u64) -> Result<()> {
        self.noise = NoiseRun::for_engine(law, seed, self.now, self.threshold.is_some())?;
        if self.noise.is_some() {
            self.noise_sync();
        }
        Ok(())
    }

    /// (candidates drawn, pairs nucleated) so far; None without noise.
    pub fn noise_counters(&self) -> Option<(u64, u64)> {
        self.noise.as_ref().map(|n| (n.candidates, n.nucleations))
    }

    /// The bound U on u over the eligible cells now (NaN if there is none).
    fn noise_bound(&self) -> f64 {
        let (m, _) = self.tree.max();
        if m.is_finite() {
            m + self.field.v * (self.now - self.field.epoch)
        } else {
            f64::NAN
        }
    }

    fn domain_length(&self) -> f64 {
        self.field.n_cells() as f64 * self.field.h
    }

    /// Time of the next candidate (infinite without noise or eligible cells).
    pub(super) fn noise_time(&self) -> f64 {
        match &self.noise {
            Some(nz) if !nz.u_mark.is_nan() => {
                let tau = nz.law.envelope_time_to_mass(
                    nz.u_mark,
                    self.field.v,
                    nz.e_left,
                    self.domain_length(),
                );
                nz.t_mark + tau
            }
            _ => f64::INFINITY,
        }
    }

    /// After an engine event: count the bound's integral up to now and take the bound anew.
    pub(super) fn noise_sync(&mut self) {
        if self.noise.is_none() {
            return;
        }
        let (u_now, len, v, now) = (
            self.noise_bound(),
            self.domain_length(),
            self.field.v,
            self.now,
        );
        let nz = self.noise.as_mut().expect("checked above");
        if !nz.u_mark.is_nan() {
            nz.e_left -= nz.law.envelope_mass(nz.u_mark, v, now - nz.t_mark, len);
        }
        nz.e_left = nz.e_left.max(0.0);
        nz.t_mark = now;
        nz.u_mark = u_now;
    }

    /// A candidate of the bound process, now: a pair at a uniform place with probability
    /// g(u)/G(U) (G the envelope). The draws (cell, place in it, acceptance, next exponential)
    /// are made in this order whatever happens, so the stream depends on the seed alone.
    pub(super) fn noise_candidate(&mut self) -> Result<()> {
        let nc = self.field.n_cells();
        let (v, now, epoch) = (self.field.v, self.now, self.field.epoch);
        let nz = self.noise.as_mut().expect("a candidate needs noise");
        nz.candidates += 1;
        let u_bound = nz.u_mark + v * (now - nz.t_mark);
        let j = ((nz.rng.uniform() * nc as f64) as usize).min(nc - 1);
        let s = nz.rng.uniform();
        let a = nz.rng.uniform();
        nz.e_left = nz.rng.exponential();
        nz.t_mark = now;
        let g_bound = nz.law.envelope_g(u_bound);
        if !self.cellmax[j].value.is_finite() {
            return Ok(());
        }
        let Some(poly) = self.gather_for_cell(j, self.shocks.len()) else {
            return Ok(());
        };
        let u = poly.eval(s) + v * (now - epoch);
        let nz = self.noise.as_ref().expect("checked above");
        if !(u > self.u_stop && u < 1.0) || a * g_bound >= nz.law.law.g(u) {
            return Ok(());
        }
        self.noise.as_mut().expect("checked above").nucleations += 1;
        let x = self.field.node_x(j) + s * self.field.h;
        self.create_shocks(
            j,
            x,
            &[(j, s, 1), (j, s, -1)],
            None,
            f64::NAN,
            u,
            PathKind::Nucleation,
        )
    }
}
