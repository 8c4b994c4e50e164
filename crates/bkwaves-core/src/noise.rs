//! Noise: spontaneous slips at a rate that depends on the stress (issue 14; the open
//! question of the paper's Sec. VI).
//!
//! A rate law gives the nucleation rate density Lambda(u) = rate * g(u), with g(1) = 1 for
//! every law, so `rate` is the rate at the slip threshold and Lambda(u) <= rate wherever
//! blocks are stuck (u <= 1):
//!
//! | law | g(u) | parameter |
//! |---|---|---|
//! | `constant` | 1 | |
//! | `exponential` | exp(-(1 - u)/phi0) (activated) | phi0 > 0 |
//! | `power` | max(u, 0)^exponent | exponent >= 0 |
//!
//! A law is one small struct implementing [`RateLaw`] (g, its primitive and the primitive's
//! inverse) and one line of [`law_from_name`].
//!
//! Between engine events a stuck point loads at rate v, u = U0 + v tau, so the integrated
//! rate is known in closed form, `rate (G(U0 + v tau) - G(U0))/v` with G the primitive of
//! g, and so is the time at which it reaches a given value ([`NoiseLaw::time_to_mass`]).
//! Engines draw exact inhomogeneous Poisson times from it (the time at which the integrated
//! rate reaches an exponential variate), never stepping in time. [`Rng`] (xoshiro256**,
//! seeded through splitmix64) is the generator; its four words go into checkpoints.

use crate::checkpoint_bytes::{Reader, Writer};
use crate::error::{Error, Result};

/// A nucleation rate law, normalised to g(1) = 1.
pub trait RateLaw: std::fmt::Debug + Send + Sync {
    /// The law's name in configs (`[noise] law`).
    fn name(&self) -> &'static str;
    /// Its parameters (in the order of its parameter table), for fingerprints.
    fn params(&self) -> Vec<f64>;
    /// g(u) = Lambda(u)/rate.
    fn g(&self, u: f64) -> f64;
    /// A primitive G of g (non-decreasing, finite everywhere).
    fn primitive(&self, u: f64) -> f64;
    /// The u with G(u) = p, for p >= G(u0) at some reachable u0 (the largest such u where
    /// G is flat).
    fn inverse_primitive(&self, p: f64) -> f64;
    /// A boxed copy.
    fn boxed(&self) -> Box<dyn RateLaw>;
}

/// `constant`: g = 1.
#[derive(Debug, Clone, Copy)]
pub struct Constant;

impl RateLaw for Constant {
    fn boxed(&self) -> Box<dyn RateLaw> {
        Box::new(*self)
    }
    fn name(&self) -> &'static str {
        "constant"
    }
    fn params(&self) -> Vec<f64> {
        Vec::new()
    }
    fn g(&self, _u: f64) -> f64 {
        1.0
    }
    fn primitive(&self, u: f64) -> f64 {
        u
    }
    fn inverse_primitive(&self, p: f64) -> f64 {
        p
    }
}

/// `exponential`: g = exp(-(1 - u)/phi0), an activated law (phi0: the stress scale of the
/// activation).
#[derive(Debug, Clone, Copy)]
pub struct Exponential {
    /// phi0 > 0.
    pub phi0: f64,
}

impl RateLaw for Exponential {
    fn boxed(&self) -> Box<dyn RateLaw> {
        Box::new(*self)
    }
    fn name(&self) -> &'static str {
        "exponential"
    }
    fn params(&self) -> Vec<f64> {
        vec![self.phi0]
    }
    fn g(&self, u: f64) -> f64 {
        (-(1.0 - u) / self.phi0).exp()
    }
    fn primitive(&self, u: f64) -> f64 {
        self.phi0 * self.g(u)
    }
    fn inverse_primitive(&self, p: f64) -> f64 {
        1.0 + self.phi0 * (p / self.phi0).ln()
    }
}

/// `power`: g = max(u, 0)^exponent (no nucleation where u <= 0 unless exponent = 0).
#[derive(Debug, Clone, Copy)]
pub struct Power {
    /// exponent >= 0.
    pub exponent: f64,
}

impl RateLaw for Power {
    fn boxed(&self) -> Box<dyn RateLaw> {
        Box::new(*self)
    }
    fn name(&self) -> &'static str {
        "power"
    }
    fn params(&self) -> Vec<f64> {
        vec![self.exponent]
    }
    fn g(&self, u: f64) -> f64 {
        if u > 0.0 {
            u.powf(self.exponent)
        } else {
            0.0
        }
    }
    fn primitive(&self, u: f64) -> f64 {
        let k = self.exponent + 1.0;
        u.max(0.0).powf(k) / k
    }
    fn inverse_primitive(&self, p: f64) -> f64 {
        let k = self.exponent + 1.0;
        (k * p.max(0.0)).powf(1.0 / k)
    }
}

/// The law names, in registry order.
pub const LAWS: [&str; 3] = ["constant", "exponential", "power"];

/// The registry: a law by name with its parameters (`phi0` for `exponential`, `exponent`
/// for `power`; the others are ignored).
pub fn law_from_name(name: &str, phi0: f64, exponent: f64) -> Result<Box<dyn RateLaw>> {
    match name {
        "constant" => Ok(Box::new(Constant)),
        "exponential" => {
            crate::error::check_open("phi0", phi0, 0.0, f64::INFINITY, "phi0 > 0")?;
            Ok(Box::new(Exponential { phi0 }))
        }
        "power" => {
            crate::error::check_at_least("exponent", exponent, 0.0, "exponent >= 0")?;
            Ok(Box::new(Power { exponent }))
        }
        _ => Err(Error::InvalidParameter {
            name: "law",
            value: f64::NAN,
            allowed: "\"constant\", \"exponential\" or \"power\"",
        }),
    }
}

/// A rate law with its rate: Lambda(u) = rate g(u).
#[derive(Debug)]
pub struct NoiseLaw {
    /// The law g.
    pub law: Box<dyn RateLaw>,
    /// Lambda at u = 1 (per unit length and time in the free boundary problem).
    pub rate: f64,
}

impl Clone for NoiseLaw {
    fn clone(&self) -> Self {
        NoiseLaw {
            law: self.law.boxed(),
            rate: self.rate,
        }
    }
}

impl NoiseLaw {
    /// A law by name; `rate` >= 0 (0: no noise).
    pub fn new(name: &str, rate: f64, phi0: f64, exponent: f64) -> Result<Self> {
        crate::error::check_at_least("rate", rate, 0.0, "rate >= 0")?;
        Ok(NoiseLaw {
            law: law_from_name(name, phi0, exponent)?,
            rate,
        })
    }

    /// Lambda(u).
    pub fn lambda(&self, u: f64) -> f64 {
        self.rate * self.law.g(u)
    }

    /// The integral over tau in [0, tau] of `length` Lambda(u0 + v tau).
    pub fn mass(&self, u0: f64, v: f64, tau: f64, length: f64) -> f64 {
        if tau <= 0.0 {
            return 0.0;
        }
        if v == 0.0 {
            return length * self.lambda(u0) * tau;
        }
        let g = &self.law;
        length * self.rate * (g.primitive(u0 + v * tau) - g.primitive(u0)) / v
    }

    /// The tau >= 0 at which [`Self::mass`] reaches `e` > 0 (infinite if never).
    pub fn time_to_mass(&self, u0: f64, v: f64, e: f64, length: f64) -> f64 {
        let scale = length * self.rate;
        if scale.is_nan() || scale <= 0.0 {
            return f64::INFINITY;
        }
        if v == 0.0 {
            let l = scale * self.law.g(u0);
            return if l > 0.0 { e / l } else { f64::INFINITY };
        }
        let g = &self.law;
        let u1 = g.inverse_primitive(g.primitive(u0) + e * v / scale);
        if u1.is_finite() {
            ((u1 - u0) / v).max(0.0)
        } else {
            f64::INFINITY
        }
    }

    /// Name and parameters, for fingerprints.
    pub(crate) fn write(&self, w: &mut Writer) {
        w.s(self.law.name());
        w.f(self.rate);
        w.fs(&self.law.params());
    }
}

/// xoshiro256** (Blackman and Vigna), seeded through splitmix64.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rng {
    s: [u64; 4],
}

impl Rng {
    /// The generator for a seed.
    pub fn new(seed: u64) -> Self {
        let mut x = seed;
        let mut next = || {
            x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        Rng {
            s: [next(), next(), next(), next()],
        }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.s;
        let out = s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        out
    }

    /// Uniform on the open interval (0, 1) (53 random bits, never 0 or 1).
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
    }

    /// A unit exponential variate.
    pub fn exponential(&mut self) -> f64 {
        -self.uniform().ln()
    }

    pub(crate) fn write(&self, w: &mut Writer) {
        for x in self.s {
            w.u(x);
        }
    }

    pub(crate) fn read(r: &mut Reader) -> Result<Self> {
        Ok(Rng {
            s: [r.u()?, r.u()?, r.u()?, r.u()?],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn laws() -> Vec<NoiseLaw> {
        vec![
            NoiseLaw::new("constant", 0.7, 0.0, 0.0).unwrap(),
            NoiseLaw::new("exponential", 0.7, 0.05, 0.0).unwrap(),
            NoiseLaw::new("power", 0.7, 0.0, 2.5).unwrap(),
            NoiseLaw::new("power", 0.7, 0.0, 0.0).unwrap(),
        ]
    }

    #[test]
    fn every_law_is_rate_at_the_threshold_and_its_primitive_integrates_it() {
        for l in laws() {
            assert!((l.lambda(1.0) - 0.7).abs() < 1e-15, "{}", l.law.name());
            // mass against a midpoint-rule quadrature of Lambda along the ramp
            let (u0, v, tau, len) = (0.3, 0.01, 50.0, 3.0);
            let n = 200_000;
            let d = tau / n as f64;
            let q: f64 = (0..n)
                .map(|k| len * l.lambda(u0 + v * (k as f64 + 0.5) * d) * d)
                .sum();
            let m = l.mass(u0, v, tau, len);
            assert!((m - q).abs() < 1e-9 * q, "{}: {m} vs {q}", l.law.name());
            // and time_to_mass inverts it
            let t = l.time_to_mass(u0, v, m, len);
            assert!((t - tau).abs() < 1e-9 * tau, "{}: {t}", l.law.name());
            // v = 0: a constant rate
            let t0 = l.time_to_mass(u0, 0.0, 1.5, len);
            assert!((t0 * len * l.lambda(u0) - 1.5).abs() < 1e-12);
        }
    }

    #[test]
    fn power_law_is_silent_below_zero_then_integrates_from_zero() {
        let l = NoiseLaw::new("power", 2.0, 0.0, 1.0).unwrap();
        assert_eq!(l.lambda(-0.5), 0.0);
        // from u0 = -0.5 at v = 0.1: zero for 5 time units, then Lambda = 2 (0.1 s), whose
        // integral 0.1 s^2 reaches 0.1 at s = 1
        let tau = l.time_to_mass(-0.5, 0.1, 0.1, 1.0);
        assert!((tau - 6.0).abs() < 1e-12, "{tau}");
        assert_eq!(l.time_to_mass(-0.5, 0.0, 1.0, 1.0), f64::INFINITY);
    }

    #[test]
    fn zero_rate_never_fires_and_bad_parameters_are_named() {
        let l = NoiseLaw::new("exponential", 0.0, 0.1, 0.0).unwrap();
        assert_eq!(l.time_to_mass(0.9, 0.01, 1e-300, 10.0), f64::INFINITY);
        let name = |r: Result<NoiseLaw>| match r {
            Err(Error::InvalidParameter { name, .. }) => name,
            _ => "",
        };
        assert_eq!(name(NoiseLaw::new("exponential", 1.0, 0.0, 0.0)), "phi0");
        assert_eq!(name(NoiseLaw::new("power", 1.0, 0.0, -1.0)), "exponent");
        assert_eq!(name(NoiseLaw::new("power", -1.0, 0.0, 1.0)), "rate");
        assert_eq!(name(NoiseLaw::new("gaussian", 1.0, 0.0, 1.0)), "law");
    }

    #[test]
    fn generator_is_uniform_and_reproducible() {
        let mut a = Rng::new(42);
        let mut b = Rng::new(42);
        assert_eq!(a.next_u64(), b.next_u64());
        assert_ne!(Rng::new(1).next_u64(), Rng::new(2).next_u64());
        // chi-square of 100 000 uniforms in 20 bins (19 dof: the 99.9 % point is 43.8)
        let n = 100_000;
        let mut bins = [0u32; 20];
        let mut mean_exp = 0.0;
        for _ in 0..n {
            let x = a.uniform();
            assert!(x > 0.0 && x < 1.0);
            bins[(x * 20.0) as usize] += 1;
            mean_exp += a.exponential() / n as f64;
        }
        let e = n as f64 / 20.0;
        let chi2: f64 = bins.iter().map(|&c| (c as f64 - e).powi(2) / e).sum();
        assert!(chi2 < 43.8, "chi2 = {chi2}");
        assert!(
            (mean_exp - 1.0).abs() < 4.0 / (n as f64).sqrt(),
            "{mean_exp}"
        );
        // the state round-trips through checkpoint words
        let mut w = Writer(Vec::new());
        a.write(&mut w);
        let mut r = Reader { b: &w.0, i: 0 };
        assert_eq!(Rng::read(&mut r).unwrap(), a);
    }
}
