//! Noise: spontaneous slips of stuck blocks (issue 14; the paper's Sec. VI, "sudden
//! transitions of the blocks at rest to sliding").
//!
//! Each stuck block i slips spontaneously as a Poisson process of rate
//! lambda(x_i) = rate g(x_i), where x_i = 1 - (theta_i - phi_i) is its stress measured
//! from its slip threshold (x_i = phi_i for the paper's threshold 1; the distance to the
//! threshold is 1 - x_i) and g is one of the free boundary's laws
//! ([`crate::noise::RateLaw`]: constant, exponential exp(-(1 - x)/phi0), power x^k, a
//! piecewise-linear table), with g(1) = 1; g may fall (a table), so the bounds below use
//! its running maximum G(x) = max_{y <= x} g(y) ([`crate::noise::NoiseLaw::envelope`];
//! G = g for a non-decreasing g). A spontaneous slip is a forward kick of speed `kick` over the ground
//! (u_t -= kick), or with kick = 0 a release (the block starts sliding from rest).
//!
//! Times are exact, drawn by thinning a bounding process, never by stepping:
//! - while every block is stuck (a quiet stretch), x_i rises at k_p,i v exactly, so every
//!   x_i <= X(t) = X0 + r (t - t0), X0 the largest x_i when the stretch began (or at the
//!   last candidate) and r = v max k_p,i, so g(x_i) <= G(X(t)); candidates fall at the
//!   rate n rate G(X(t)), whose integral is in closed form
//!   ([`crate::noise::NoiseLaw::envelope_mass`]);
//! - while blocks slide, the stuck blocks next to them move with their neighbours, but a
//!   stuck block has x_i < 1 (it would slip otherwise) and g(x) <= G(1) = max_{x < 1} g
//!   there (1 for a non-decreasing g), so candidates fall at the constant rate
//!   n rate G(1).
//!
//! A candidate picks a block uniformly; it slips if stuck with probability
//! g(x_i)/G(bound) (x_i exact at that instant). When the bound changes (blocks start or
//! stop sliding) the integral of the old bound so far is subtracted from the exponential
//! variate left and the new bound taken from now: exact, because the process is
//! memoryless. The generator (xoshiro256**, seeded through splitmix64), the variate left,
//! the bound and the counters are the source's checkpoint state.

use super::super::{Trigger, TriggerKind};
use super::{Source, View};
use crate::checkpoint_bytes::{Reader, Writer};
use crate::error::{check_at_least, Result};
use crate::noise::{NoiseLaw, Rng};

/// Name in the registry and in outputs.
pub const NAME: &str = "noise";
/// Meaning.
pub const DOC: &str = "a spontaneous slip of a stuck block (noise: a Poisson process of rate \
                       rate g(x), x the block's stress from its threshold)";

/// The bounding process of the candidates.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Bound {
    /// Not taken yet (at the next call).
    Stale,
    /// Everything stuck: x_i <= x0 + r (t - t_mark).
    Quiet { x0: f64, r: f64 },
    /// Blocks slide: g(x_i) <= G(1) (stuck blocks are below their threshold).
    Sliding,
}

/// Spontaneous slips (see the module docs).
#[derive(Debug, Clone)]
pub struct Noise {
    law: NoiseLaw,
    kick: f64,
    seed: u64,
    rng: Rng,
    /// Integrated bound rate left before the next candidate (a unit exponential at draw).
    e_left: f64,
    /// Time from which `e_left` is counted and the bound holds.
    t_mark: f64,
    bound: Bound,
    /// The chain's switch count when the quiet bound was taken.
    switches: u64,
    /// Candidates drawn.
    pub candidates: u64,
    /// Spontaneous slips (accepted candidates).
    pub slips: u64,
}

impl Noise {
    /// Spontaneous slips with `law` (rate: per block and unit time at the threshold),
    /// kicks of speed `kick` >= 0 over the ground (0: a release), seeded by `seed`, from
    /// time `t` on.
    pub fn new(law: NoiseLaw, kick: f64, seed: u64, t: f64) -> Result<Self> {
        check_at_least(
            "kick",
            kick,
            0.0,
            "kick >= 0 (forward speed over the ground; 0: a release)",
        )?;
        if !kick.is_finite() {
            return Err(crate::error::Error::InvalidParameter {
                name: "kick",
                value: kick,
                allowed: "a finite kick >= 0",
            });
        }
        let mut rng = Rng::new(seed);
        let e_left = rng.exponential();
        Ok(Noise {
            law,
            kick,
            seed,
            rng,
            e_left,
            t_mark: t,
            bound: Bound::Stale,
            switches: 0,
            candidates: 0,
            slips: 0,
        })
    }

    /// The law.
    pub fn law(&self) -> &NoiseLaw {
        &self.law
    }

    /// Integral of the bound's candidate rate from `t_mark` over `tau`.
    fn mass(&self, n: f64, tau: f64) -> f64 {
        match self.bound {
            Bound::Stale => 0.0,
            Bound::Quiet { x0, r } => self.law.envelope_mass(x0, r, tau, n),
            Bound::Sliding => n * self.law.rate * self.law.sup_below_threshold() * tau.max(0.0),
        }
    }

    /// Time after `t_mark` at which the bound's integral reaches `e_left`.
    fn delay(&self, n: f64) -> f64 {
        match self.bound {
            Bound::Stale => f64::INFINITY,
            Bound::Quiet { x0, r } => self.law.envelope_time_to_mass(x0, r, self.e_left, n),
            Bound::Sliding => {
                let l = n * self.law.rate * self.law.sup_below_threshold();
                if l > 0.0 {
                    self.e_left / l
                } else {
                    f64::INFINITY
                }
            }
        }
    }

    /// Take the bound anew at the chain's time (after counting the old one's integral).
    fn rebound(&mut self, ch: &dyn View) {
        let now = ch.time();
        let n = ch.n() as f64;
        self.e_left = (self.e_left - self.mass(n, now - self.t_mark)).max(0.0);
        self.t_mark = now;
        self.switches = ch.switches();
        self.bound = if ch.n_sliding() == 0 {
            let x0 = (0..ch.n())
                .map(|k| ch.stress(k))
                .fold(f64::NEG_INFINITY, f64::max);
            Bound::Quiet {
                x0: x0.min(1.0),
                r: ch.max_loading_rate(),
            }
        } else {
            Bound::Sliding
        };
    }
}

impl Source for Noise {
    fn kind(&self) -> u8 {
        1
    }

    fn next_time(&mut self, ch: &dyn View) -> f64 {
        let stale = match self.bound {
            Bound::Stale => true,
            Bound::Quiet { .. } => ch.n_sliding() > 0 || ch.switches() != self.switches,
            Bound::Sliding => ch.n_sliding() == 0,
        };
        if stale {
            self.rebound(ch);
        }
        self.t_mark + self.delay(ch.n() as f64)
    }

    fn fire(&mut self, ch: &dyn View) -> Option<Trigger> {
        let now = ch.time();
        let n = ch.n();
        // the bound's value now (its rate g_bound / rate), then start counting afresh
        let g_bound = match self.bound {
            Bound::Quiet { x0, r } => {
                let x = x0 + r * (now - self.t_mark);
                self.bound = Bound::Quiet { x0: x, r };
                self.law.envelope_g(x)
            }
            _ => self.law.sup_below_threshold(),
        };
        self.t_mark = now;
        self.candidates += 1;
        // the draws, always in this order: block, acceptance, next variate
        let k = ((self.rng.uniform() * n as f64) as usize).min(n - 1);
        let a = self.rng.uniform();
        self.e_left = self.rng.exponential();
        if ch.sliding(k) || a * g_bound >= self.law.law.g(ch.stress(k)) {
            return None;
        }
        self.slips += 1;
        let kind = if self.kick > 0.0 {
            TriggerKind::Kick { du_t: -self.kick }
        } else {
            TriggerKind::Release { dir: 1 }
        };
        Some(Trigger {
            t: now,
            block: k,
            kind,
        })
    }

    fn fingerprint(&self, w: &mut Writer) {
        w.s(NAME);
        self.law.write(w);
        w.f(self.kick);
        w.u(self.seed);
    }

    fn save(&self, w: &mut Writer) {
        self.rng.write(w);
        w.f(self.e_left);
        w.f(self.t_mark);
        let (code, x0, r) = match self.bound {
            Bound::Stale => (0, 0.0, 0.0),
            Bound::Quiet { x0, r } => (1, x0, r),
            Bound::Sliding => (2, 0.0, 0.0),
        };
        w.u(code);
        w.f(x0);
        w.f(r);
        w.u(self.switches);
        w.u(self.candidates);
        w.u(self.slips);
    }

    fn load(&mut self, r: &mut Reader) -> Result<()> {
        self.rng = Rng::read(r)?;
        self.e_left = r.f()?;
        self.t_mark = r.f()?;
        let (code, x0, rate) = (r.u()?, r.f()?, r.f()?);
        self.bound = match code {
            0 => Bound::Stale,
            1 => Bound::Quiet { x0, r: rate },
            2 => Bound::Sliding,
            _ => {
                return Err(crate::checkpoint_bytes::bad(
                    r.i,
                    "a noise bound code 0, 1 or 2",
                ))
            }
        };
        self.switches = r.u()?;
        self.candidates = r.u()?;
        self.slips = r.u()?;
        Ok(())
    }

    fn boxed(&self) -> Box<dyn Source> {
        Box::new(self.clone())
    }

    fn as_noise(&self) -> Option<&Noise> {
        Some(self)
    }
}
