//! Noise: spontaneous slips at a rate that depends on the stress (issue 14; the open
//! question of the paper's Sec. VI).
//!
//! A rate law gives the nucleation rate density Lambda(u) = rate * g(u), with g(1) = 1 for
//! every law, so `rate` is the rate at the slip threshold:
//!
//! | law | g(u) | parameter |
//! |---|---|---|
//! | `constant` | 1 | |
//! | `exponential` | exp(-(1 - u)/phi0) (activated) | phi0 > 0 |
//! | `power` | max(u, 0)^exponent | exponent >= 0 |
//! | `table` | piecewise linear through nodes (u_k, g_k), divided by its value at u = 1 | u, g |
//!
//! `table`: u_k strictly increasing (at least two nodes), g_k >= 0 finite, and the
//! interpolant positive at u = 1 (it is divided by that value, so g(1) = 1). Outside the
//! nodes g is constant: g_first below the first node, g_last above the last (a table
//! with g_first = 0 never nucleates below its first node). Its primitive is piecewise
//! quadratic and inverted exactly piece by piece. g may fall (a peaked table).
//!
//! Engines draw by thinning under the envelope G(u) = max_{y <= u} g(y), the running
//! maximum ([`NoiseLaw::envelope`]): where every stress present is <= U, rate G(U) bounds
//! each point's rate and a candidate at u is kept with probability g(u)/G(U), exactly. G = g
//! for a non-decreasing g (every closed-form law); for a table G is a table too (flat at
//! the maximum so far, with a node where a rising piece crosses it). Where a stress is
//! only known to be below the threshold the bound is G(1) = max_{u < 1} g
//! ([`NoiseLaw::sup_below_threshold`]), which may exceed g(1) = 1.
//!
//! A law is one small struct implementing [`RateLaw`] (g, its primitive and the primitive's
//! inverse) and one line of [`law_from_name`].
//!
//! Between engine events a stuck point loads at rate v, u = U0 + v tau, so the integrated
//! rate is known in closed form, `rate (G(U0 + v tau) - G(U0))/v` with G the primitive of
//! g, and so is the time at which it reaches a given value ([`NoiseLaw::time_to_mass`]);
//! the same for the envelope ([`NoiseLaw::envelope_time_to_mass`]).
//! Engines draw exact inhomogeneous Poisson times from it (the time at which the integrated
//! rate reaches an exponential variate), never stepping in time. [`Rng`] (xoshiro256**,
//! seeded through splitmix64) is the generator; its four words go into checkpoints.

use crate::checkpoint_bytes::{Reader, Writer};
use crate::error::{Error, Result};

/// A nucleation rate law, normalised to g(1) = 1 (not necessarily monotone: see
/// [`RateLaw::envelope`]).
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
    /// The thinning envelope G(u) = max_{y <= u} g(y) (the running maximum, non-decreasing)
    /// when it differs from g; None for a non-decreasing g (then G = g).
    fn envelope(&self) -> Option<&dyn RateLaw> {
        None
    }
    /// sup of g below the threshold, max_{u < 1} g(u) = G(1) (>= g(1) = 1): the bound of
    /// the rate of a stuck block whose stress has no closed form (below its threshold).
    fn sup_below_threshold(&self) -> f64 {
        1.0
    }
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

/// The largest |u| of a table's node (the primitive from the first node must resolve
/// increments near u = 1; stresses are O(1)).
pub const TABLE_NODE_MAX: f64 = 1e3;

/// `table`: g piecewise linear through the nodes (u_k, g_k), constant outside them,
/// normalised to g(1) = 1 (see the module docs).
#[derive(Debug, Clone)]
pub struct Table {
    /// The nodes u_k, strictly increasing.
    u: Vec<f64>,
    /// g at the nodes, normalised (g(1) = 1).
    g: Vec<f64>,
    /// The primitive at the nodes, from 0 at the first node.
    cum: Vec<f64>,
    /// The nodes as given (for fingerprints): u then g.
    raw: Vec<f64>,
    /// The running maximum of g as a table (None where g is non-decreasing: G = g).
    envelope: Option<Box<Table>>,
    /// max over u < 1 of g (1 where g is non-decreasing).
    sup: f64,
}

impl Table {
    /// The law through (u_k, g_k); errors name `u` or `g` and the allowed range.
    pub fn new(u: &[f64], g: &[f64]) -> Result<Self> {
        let bad = |name, value, allowed| Error::InvalidParameter {
            name,
            value,
            allowed,
        };
        if u.len() < 2 {
            return Err(bad("u", u.len() as f64, "at least two nodes"));
        }
        if g.len() != u.len() {
            return Err(bad("g", g.len() as f64, "as many values as u has nodes"));
        }
        if let Some(&x) = u.iter().find(|x| !x.is_finite()) {
            return Err(bad("u", x, "finite nodes"));
        }
        if let Some(w) = u.windows(2).find(|w| w[1] <= w[0]) {
            return Err(bad("u", w[1], "strictly increasing nodes"));
        }
        // the primitive runs from the first node: a node far from every stress makes it
        // too large to resolve a candidate's increment near u = 1
        if let Some(&x) = u.iter().find(|x| x.abs() > TABLE_NODE_MAX) {
            return Err(bad("u", x, "nodes with |u| <= 1000"));
        }
        if let Some(&x) = g.iter().find(|x| !(x.is_finite() && **x >= 0.0)) {
            return Err(bad("g", x, "finite values >= 0"));
        }
        let mut t = Table::normalised(u.to_vec(), g.to_vec());
        t.raw = u.iter().chain(g).copied().collect();
        let at_one = t.g(1.0);
        if at_one <= 0.0 {
            return Err(bad(
                "g",
                at_one,
                "a table positive at u = 1 (g is divided by g(1))",
            ));
        }
        let g: Vec<f64> = t.g.iter().map(|x| x / at_one).collect();
        let mut t = Table {
            raw: t.raw,
            ..Table::normalised(t.u, g)
        };
        if !t.cum[t.cum.len() - 1].is_finite() {
            return Err(bad(
                "g",
                at_one,
                "values >= 0 with g/g(1) finite (and its integral over the nodes)",
            ));
        }
        if t.g.windows(2).any(|w| w[1] < w[0]) {
            // g(1) = 1 is the interpolant at 1, so the sup below 1 is the larger of 1 and
            // the nodes below 1 (a linear piece peaks at an end)
            t.sup =
                t.u.iter()
                    .zip(&t.g)
                    .filter(|(&x, _)| x < 1.0)
                    .fold(1.0, |m, (_, &y)| f64::max(m, y));
            t.envelope = Some(Box::new(t.running_max()));
        }
        Ok(t)
    }

    /// The table through nodes already normalised (no checks), with its primitive.
    fn normalised(u: Vec<f64>, g: Vec<f64>) -> Self {
        let mut cum = vec![0.0];
        let mut c = 0.0;
        for k in 0..u.len() - 1 {
            c += 0.5 * (g[k] + g[k + 1]) * (u[k + 1] - u[k]);
            cum.push(c);
        }
        Table {
            u,
            g,
            cum,
            raw: Vec::new(),
            envelope: None,
            sup: 1.0,
        }
    }

    /// G(u) = max_{y <= u} g(y) as a table: piecewise linear too, flat at the maximum so
    /// far m where g is below it, and with one more node where a rising piece crosses m
    /// (G follows g from there). Constant outside the nodes like g (below the first: g_0;
    /// above the last: the overall maximum, which the last node holds).
    fn running_max(&self) -> Table {
        let (nu, ng) = (&self.u, &self.g);
        let (mut u, mut g) = (vec![nu[0]], vec![ng[0]]);
        let mut m = ng[0];
        for k in 0..nu.len() - 1 {
            let (a, b) = (ng[k], ng[k + 1]);
            if b > m && a < m {
                // the rising piece crosses the plateau m at u*
                let x = nu[k] + (m - a) / (b - a) * (nu[k + 1] - nu[k]);
                if x > u[u.len() - 1] && x < nu[k + 1] {
                    u.push(x);
                    g.push(m);
                }
            }
            m = m.max(b);
            u.push(nu[k + 1]);
            g.push(m);
        }
        Table::normalised(u, g)
    }
}

impl RateLaw for Table {
    fn boxed(&self) -> Box<dyn RateLaw> {
        Box::new(self.clone())
    }
    fn name(&self) -> &'static str {
        "table"
    }
    fn params(&self) -> Vec<f64> {
        self.raw.clone()
    }
    fn envelope(&self) -> Option<&dyn RateLaw> {
        self.envelope.as_deref().map(|t| t as &dyn RateLaw)
    }
    fn sup_below_threshold(&self) -> f64 {
        self.sup
    }
    fn g(&self, u: f64) -> f64 {
        let (nu, last) = (&self.u, self.u.len() - 1);
        if u <= nu[0] {
            return self.g[0];
        }
        if u >= nu[last] {
            return self.g[last];
        }
        let k = nu.partition_point(|&x| x <= u) - 1;
        let s = (u - nu[k]) / (nu[k + 1] - nu[k]);
        self.g[k] + s * (self.g[k + 1] - self.g[k])
    }
    fn primitive(&self, u: f64) -> f64 {
        let (nu, last) = (&self.u, self.u.len() - 1);
        if u <= nu[0] {
            return self.g[0] * (u - nu[0]);
        }
        if u >= nu[last] {
            return self.cum[last] + self.g[last] * (u - nu[last]);
        }
        let k = nu.partition_point(|&x| x <= u) - 1;
        let (s, h) = (u - nu[k], nu[k + 1] - nu[k]);
        let slope = (self.g[k + 1] - self.g[k]) / h;
        self.cum[k] + s * (self.g[k] + 0.5 * slope * s)
    }
    fn inverse_primitive(&self, p: f64) -> f64 {
        let (nu, last) = (&self.u, self.u.len() - 1);
        if p < 0.0 {
            // below the first node: G = g_first (u - u_first); flat: the largest u
            return if self.g[0] > 0.0 {
                nu[0] + p / self.g[0]
            } else {
                nu[0]
            };
        }
        // the last node with G <= p (the end of a flat stretch at G = p)
        let k = self.cum.partition_point(|&c| c <= p) - 1;
        let d = p - self.cum[k];
        if k == last {
            return if d == 0.0 {
                nu[last]
            } else if self.g[last] > 0.0 {
                nu[last] + d / self.g[last]
            } else {
                f64::INFINITY
            };
        }
        if d == 0.0 {
            return nu[k];
        }
        // g_k s + slope s^2/2 = d, the root in [0, h] (no cancellation: both terms of the
        // denominator are >= 0, and it is > 0 since d > 0 lies inside the piece)
        let h = nu[k + 1] - nu[k];
        let slope = (self.g[k + 1] - self.g[k]) / h;
        let disc = (self.g[k] * self.g[k] + 2.0 * slope * d).max(0.0);
        let s = 2.0 * d / (self.g[k] + disc.sqrt());
        nu[k] + s.clamp(0.0, h)
    }
}

/// The law names, in registry order.
pub const LAWS: [&str; 4] = ["constant", "exponential", "power", "table"];

/// The registry: a law by name with its parameters (`phi0` for `exponential`, `exponent`
/// for `power`, the nodes `u` and values `g` for `table`; the others are ignored).
pub fn law_from_name(
    name: &str,
    phi0: f64,
    exponent: f64,
    u: &[f64],
    g: &[f64],
) -> Result<Box<dyn RateLaw>> {
    match name {
        "table" => Ok(Box::new(Table::new(u, g)?)),
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
            allowed: "\"constant\", \"exponential\", \"power\" or \"table\"",
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
        Self::with_table(name, rate, phi0, exponent, &[], &[])
    }

    /// A law by name with every law's parameters (the table's nodes `u` and values `g`).
    pub fn with_table(
        name: &str,
        rate: f64,
        phi0: f64,
        exponent: f64,
        u: &[f64],
        g: &[f64],
    ) -> Result<Self> {
        crate::error::check_at_least("rate", rate, 0.0, "rate >= 0")?;
        Ok(NoiseLaw {
            law: law_from_name(name, phi0, exponent, u, g)?,
            rate,
        })
    }

    /// Lambda(u).
    pub fn lambda(&self, u: f64) -> f64 {
        self.rate * self.law.g(u)
    }

    /// The integral over tau in [0, tau] of `length` Lambda(u0 + v tau).
    pub fn mass(&self, u0: f64, v: f64, tau: f64, length: f64) -> f64 {
        self.ramp_mass(&*self.law, u0, v, tau, length)
    }

    /// The tau >= 0 at which [`Self::mass`] reaches `e` > 0 (infinite if never).
    pub fn time_to_mass(&self, u0: f64, v: f64, e: f64, length: f64) -> f64 {
        self.ramp_time_to_mass(&*self.law, u0, v, e, length)
    }

    /// The thinning envelope G(u) = max_{y <= u} g(y): where every stress present is
    /// <= U, rate G(U) bounds the rate of each, and a candidate at u is kept with
    /// probability g(u)/G(U). G = g for a non-decreasing g (every closed-form law).
    pub fn envelope(&self) -> &dyn RateLaw {
        self.law.envelope().unwrap_or(&*self.law)
    }

    /// G(u), the envelope's value (see [`Self::envelope`]).
    pub fn envelope_g(&self, u: f64) -> f64 {
        self.envelope().g(u)
    }

    /// [`Self::mass`] of the envelope: the integral of `length` rate G(u0 + v tau).
    pub fn envelope_mass(&self, u0: f64, v: f64, tau: f64, length: f64) -> f64 {
        self.ramp_mass(self.envelope(), u0, v, tau, length)
    }

    /// [`Self::time_to_mass`] of the envelope.
    pub fn envelope_time_to_mass(&self, u0: f64, v: f64, e: f64, length: f64) -> f64 {
        self.ramp_time_to_mass(self.envelope(), u0, v, e, length)
    }

    /// max_{u < 1} g(u) = G(1) >= 1: bounds g wherever the stress is below the
    /// threshold and not otherwise known.
    pub fn sup_below_threshold(&self) -> f64 {
        self.law.sup_below_threshold()
    }

    fn ramp_mass(&self, g: &dyn RateLaw, u0: f64, v: f64, tau: f64, length: f64) -> f64 {
        if tau <= 0.0 {
            return 0.0;
        }
        if v == 0.0 {
            return length * (self.rate * g.g(u0)) * tau;
        }
        length * self.rate * (g.primitive(u0 + v * tau) - g.primitive(u0)) / v
    }

    fn ramp_time_to_mass(&self, g: &dyn RateLaw, u0: f64, v: f64, e: f64, length: f64) -> f64 {
        let scale = length * self.rate;
        if scale.is_nan() || scale <= 0.0 {
            return f64::INFINITY;
        }
        if v == 0.0 {
            let l = scale * g.g(u0);
            return if l > 0.0 { e / l } else { f64::INFINITY };
        }
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

    fn table(u: &[f64], g: &[f64]) -> NoiseLaw {
        NoiseLaw::with_table("table", 1.0, f64::NAN, f64::NAN, u, g).unwrap()
    }

    #[test]
    fn table_through_an_exponential_reproduces_its_primitive_and_times() {
        let phi0 = 0.1;
        let n = 2001;
        let u: Vec<f64> = (0..n)
            .map(|k| -0.5 + 1.7 * k as f64 / (n - 1) as f64)
            .collect();
        let g: Vec<f64> = u.iter().map(|&x| (-(1.0 - x) / phi0).exp()).collect();
        let t = table(&u, &g);
        let e = NoiseLaw::new("exponential", 1.0, phi0, f64::NAN).unwrap();
        assert!((t.lambda(1.0) - 1.0).abs() < 1e-15);
        // trapezoid error of a node spacing h: h^2 g''/12 per unit u, relative to g:
        // (h/phi0)^2/12 = 6e-6 at h = 8.5e-4
        let h: f64 = 1.7 / (n - 1) as f64;
        let bound = 1.01 * (h / phi0).powi(2) / 12.0;
        for (a, b) in [(0.0, 0.5), (0.3, 0.95), (0.8, 1.1), (-0.4, 1.0)] {
            let mt = t.mass(a, 0.01, (b - a) / 0.01, 1.0);
            let me = e.mass(a, 0.01, (b - a) / 0.01, 1.0);
            assert!((mt / me - 1.0).abs() < bound, "[{a}, {b}]: {mt} vs {me}");
        }
        // the first nucleation time for the same exponential variates, from u0 = 0.2
        let mut rng = Rng::new(3);
        for _ in 0..1000 {
            let x = rng.exponential() * 1e-3;
            let (tt, te) = (
                t.time_to_mass(0.2, 0.01, x, 1.0),
                e.time_to_mass(0.2, 0.01, x, 1.0),
            );
            // dt = phi0/v * (relative mass error) at most
            assert!(
                (tt - te).abs() < bound * phi0 / 0.01 + 1e-9 * te,
                "{tt} vs {te}"
            );
        }
    }

    #[test]
    fn table_primitive_and_inverse_round_trip_with_flat_pieces() {
        // flat zero below 0.4 (over three nodes), a steep and a shallow rise, a flat
        // positive piece through u = 1, and a rising end
        let u = [0.0, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0, 1.3];
        let g = [0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 4.0];
        let l = table(&u, &g);
        let law = &l.law;
        assert_eq!(law.g(1.0), 1.0);
        assert_eq!(law.g(-3.0), 0.0);
        assert!((law.g(0.45) - 0.25).abs() < 1e-15);
        assert_eq!(law.g(0.7), 1.0);
        let mut rng = Rng::new(9);
        let (lo, hi) = (law.primitive(-0.5), law.primitive(1.6));
        for _ in 0..20_000 {
            let x = -0.5 + 2.1 * rng.uniform();
            let p = law.primitive(x);
            let y = law.inverse_primitive(p);
            // the inverse returns the largest u with G(u) = p
            assert!((law.primitive(y) - p).abs() < 1e-12, "x = {x}: G(y) - p");
            if law.g(x) > 0.0 {
                assert!((y - x).abs() < 1e-12, "x = {x}, y = {y}");
            } else {
                assert!((y - 0.4).abs() < 1e-12, "zero stretch x = {x}: {y}");
            }
            let q = lo + (hi - lo) * rng.uniform();
            let z = law.inverse_primitive(q);
            assert!((law.primitive(z) - q).abs() < 1e-12, "q = {q}");
        }
    }

    #[test]
    fn step_table_never_nucleates_below_its_step() {
        let u_r = 0.6;
        let l = table(&[u_r - 1e-9, u_r, 1.0], &[0.0, 1.0, 1.0]);
        let mut rng = Rng::new(5);
        for _ in 0..10_000 {
            let u0 = -0.2 + 0.8 * rng.uniform();
            let v = 0.001 + rng.uniform();
            let e = rng.exponential();
            let tau = l.time_to_mass(u0, v, e, 2.0);
            assert!(
                u0 + v * tau >= u_r - 1e-9,
                "u0 = {u0}: nucleates at {}",
                u0 + v * tau
            );
            // above the step Lambda = 1: the mass e is reached after e/length more stress
            let expect = (u_r - u0 + e / 2.0 * v) / v;
            assert!(
                (tau - expect).abs() < 1e-6 * expect.max(1.0),
                "{tau} vs {expect}"
            );
        }
        assert_eq!(l.time_to_mass(0.3, 0.0, 1.0, 1.0), f64::INFINITY);
    }

    #[test]
    fn bad_tables_are_refused_naming_the_key() {
        let name = |u: &[f64], g: &[f64]| match NoiseLaw::with_table("table", 1.0, 0.0, 0.0, u, g) {
            Err(Error::InvalidParameter { name, .. }) => name,
            _ => "",
        };
        assert_eq!(name(&[1.0], &[1.0]), "u");
        assert_eq!(name(&[0.0, 0.5, 0.5, 1.0], &[1.0; 4]), "u");
        assert_eq!(name(&[0.0, f64::NAN], &[1.0; 2]), "u");
        assert_eq!(name(&[0.0, 1.0], &[1.0]), "g");
        assert_eq!(name(&[0.0, 1.0], &[-1.0, 1.0]), "g");
        assert_eq!(name(&[0.0, 1.0], &[1.0, f64::INFINITY]), "g");
        assert_eq!(name(&[0.0, 1.0, 2.0], &[1.0, 0.0, 1.0]), "g"); // zero at u = 1
                                                                   // a decreasing g is a law (the engines thin under its running maximum)
        assert_eq!(name(&[0.0, 0.5, 1.0], &[0.0, 2.0, 1.0]), "");
        assert_eq!(name(&[0.0, 1.0], &[0.5, 2.0]), "");
        // a node far from every stress: the primitive from the first node cannot resolve
        // a candidate's increment (the free boundary spun at one instant: a fuzz finding)
        assert_eq!(name(&[-8.3e287, 9.4e298], &[2.0, 10.0]), "u");
        assert_eq!(name(&[0.0, 1.0, 1001.0], &[1.0; 3]), "u");
        assert_eq!(name(&[-1e3, 1.0, 1e3], &[0.0, 1.0, 1e6]), "");
        // g/g(1) must be finite (1e300/1e-300 overflows)
        assert_eq!(name(&[0.0, 1.0], &[1e300, 1e-300]), "g");
    }

    /// The running maximum of g on a fine grid (numerically, from the definition).
    fn running_max_on(law: &dyn RateLaw, xs: &[f64]) -> Vec<f64> {
        let mut m = f64::NEG_INFINITY;
        xs.iter()
            .map(|&x| {
                m = m.max(law.g(x));
                m
            })
            .collect()
    }

    #[test]
    fn the_envelope_of_a_peaked_table_is_its_running_maximum() {
        // rise to 3, fall to 0.5, rise through the plateau 3 again (a crossing node at
        // u = 0.8 + 0.2 * 2.5/3.5), fall, and a zero stretch: g(1) = 1 after division
        let u = [-0.2, 0.0, 0.3, 0.5, 0.8, 1.0, 1.2, 1.5];
        let g = [0.0, 0.0, 3.0, 0.5, 0.5, 1.0, 4.0, 2.0];
        let l = table(&u, &g);
        let env = l.envelope();
        assert!(l.law.envelope().is_some());
        assert_eq!(l.sup_below_threshold(), 3.0); // the peak at 0.3, g(1) = 1
        let xs: Vec<f64> = (0..=400_000).map(|k| -0.5 + 2.5 * k as f64 / 4e5).collect();
        let want = running_max_on(&*l.law, &xs);
        for (&x, &m) in xs.iter().zip(&want) {
            assert!((env.g(x) - m).abs() < 1e-12, "G({x}) = {} vs {m}", env.g(x));
        }
        // G(1) = sup below 1 = 3 > g(1) = 1; above the last node the overall maximum 4
        assert!((env.g(1.0) - 3.0).abs() < 1e-12);
        assert_eq!(env.g(7.0), 4.0);
        assert_eq!(l.law.g(1.0), 1.0);
        // its primitive integrates it (trapezoid on the grid, exact but for the kinks)
        let h = xs[1] - xs[0];
        let q: f64 = want.windows(2).map(|w| 0.5 * (w[0] + w[1]) * h).sum();
        let p = env.primitive(2.0) - env.primitive(-0.5);
        assert!((p - q).abs() < 1e-9, "{p} vs {q}");
        // and the inverse undoes it
        let mut rng = Rng::new(4);
        for _ in 0..20_000 {
            let x = -0.2 + 2.0 * rng.uniform();
            let y = env.inverse_primitive(env.primitive(x));
            assert!((y - x).abs() < 1e-12 || env.g(x) == 0.0, "{x}: {y}");
        }
        // the envelope's ramp integral is G's, and the law's own stays g's
        let (mg, mu) = (
            l.envelope_mass(0.0, 0.01, 50.0, 1.0),
            l.mass(0.0, 0.01, 50.0, 1.0),
        );
        assert!((mg - (env.primitive(0.5) - env.primitive(0.0)) / 0.01).abs() < 1e-12);
        assert!((mu - (l.law.primitive(0.5) - l.law.primitive(0.0)) / 0.01).abs() < 1e-12);
        assert!(mg > mu);
        // a non-decreasing table and every closed-form law: G = g, sup 1
        let mono = table(&[0.0, 0.5, 1.0], &[0.0, 0.5, 1.0]);
        assert!(mono.law.envelope().is_none());
        assert_eq!(mono.sup_below_threshold(), 1.0);
        for l in laws() {
            assert!(l.law.envelope().is_none());
            assert_eq!(l.sup_below_threshold(), 1.0);
        }
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
