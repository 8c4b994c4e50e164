//! The traveling wave behind the front (paper Sec. III and App. B), v = 0.
//!
//! Behind the slip point z = x - c t = 0 blocks slide according to eq. (slidet),
//! (c^2 - 1) u_zz - 2 c gamma u_z + u = 0 with u(0) = u_+, u_z(0) = 0 (eq. initc).
//! With xi = z / sqrt(c^2 - 1) and gt = c gamma / sqrt(c^2 - 1) (the paper's
//! gamma-tilde) it reads u_xixi - 2 gt u_xi + u = 0. gt < 1: a self-healing pulse
//! that re-sticks at z = -w (eqs. complex, ab, w, um, A); gt >= 1: creep, u -> 0
//! behind (eq. real; gt = 1 is the critically damped case, which never re-sticks
//! either). With the exact c(u_+) of [`crate::speed`], sqrt(c^2 - 1) = u_+ c and
//! gt = gamma/u_+ exactly, so the regime is decided by comparing u_+ with gamma
//! (u_+ = gamma: creep), and every quantity below is computed from differences that
//! do not cancel: c^2 - 1 and 1 - gt^2 are formed as products (u_+ - gamma)(u_+ + gamma)
//! or (s - c gamma)(s + c gamma), never as differences of nearly equal squares.

use crate::error::{check_open, Result};
use crate::speed::{check_gamma, creep_error, critical_stress, front_speed};
use std::f64::consts::PI;

/// Which kind of wave a given (u_+, gamma) produces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// u_+ > u_c: blocks re-stick a finite distance w behind the front.
    Pulse,
    /// u_+ <= u_c: blocks never re-stick at v = 0; u -> 0 behind the front
    /// (u_+ = u_c is the critically damped wave, gt = 1).
    Creep,
}

impl Regime {
    /// Lower-case name used in JSON and tables.
    pub fn as_str(&self) -> &'static str {
        match self {
            Regime::Pulse => "pulse",
            Regime::Creep => "creep",
        }
    }
}

/// The shape of eq. (slidet) behind a front, in cancellation-free variables:
/// s = sqrt(c^2 - 1) (xi = z/s), gt = c gamma/s, and one_minus_gt2 = 1 - gt^2.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Shape {
    s: f64,
    gt: f64,
    one_minus_gt2: f64,
}

impl Shape {
    /// Exact front speed c = 1/sqrt(1 - u^2): s = u c, gt = gamma/u,
    /// 1 - gt^2 = (u - gamma)(u + gamma)/u^2 (exactly 0 at u = gamma).
    fn exact(u: f64, c: f64, gamma: f64) -> Shape {
        Shape {
            s: u * c,
            gt: gamma / u,
            one_minus_gt2: ((u - gamma) / u) * ((u + gamma) / u),
        }
    }

    /// A given front speed c > 1: s = sqrt((c - 1)(c + 1)), gt = c gamma/s,
    /// 1 - gt^2 = (s - c gamma)(s + c gamma)/s^2.
    fn from_speed(c: f64, gamma: f64) -> Shape {
        let s = ((c - 1.0) * (c + 1.0)).sqrt();
        let cg = c * gamma;
        Shape {
            s,
            gt: cg / s,
            one_minus_gt2: (s - cg) * (s + cg) / (s * s),
        }
    }

    fn is_pulse(&self) -> bool {
        self.one_minus_gt2 > 0.0
    }

    /// Eq. (w): w = pi (c^2 - 1)/sqrt(c^2 (1 - gamma^2) - 1) = pi s/sqrt(1 - gt^2).
    fn width(&self) -> Option<f64> {
        self.is_pulse()
            .then(|| PI * self.s / self.one_minus_gt2.sqrt())
    }

    /// Eq. (um): u_- = -u_+ exp(-pi gt/sqrt(1 - gt^2)).
    fn u_minus(&self, u_plus: f64) -> Option<f64> {
        self.is_pulse()
            .then(|| -u_plus * (-PI * self.gt / self.one_minus_gt2.sqrt()).exp())
    }
}

/// The paper's gamma-tilde = c gamma / sqrt(c^2 - 1) for a front of speed c > 1.
pub fn gamma_tilde(c: f64, gamma: f64) -> f64 {
    Shape::from_speed(c, gamma).gt
}

/// Width w of the pulse, eq. (w), for front speed c and damping gamma.
/// `None` in the creep regime (c^2 (1 - gamma^2) <= 1), where w is infinite.
pub fn width_from_speed(c: f64, gamma: f64) -> Option<f64> {
    Shape::from_speed(c, gamma).width()
}

/// The stress u_- left behind a pulse, eq. (um). `None` in the creep regime.
pub fn u_minus_from_speed(u_plus: f64, c: f64, gamma: f64) -> Option<f64> {
    Shape::from_speed(c, gamma).u_minus(u_plus)
}

/// Everything the continuum theory says about the wave with stress u_+ ahead.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TravelingWave {
    /// Stress ahead of the front, 0 < u_+ < 1.
    pub u_plus: f64,
    /// Viscous damping gamma >= 0.
    pub gamma: f64,
    /// Front speed c(u_+).
    pub c: f64,
    /// Pulse or creep.
    pub regime: Regime,
    /// Critical stress u_c(gamma) (None for gamma >= 1: always creep).
    pub u_c: Option<f64>,
    /// Width w (pulse only), eq. (w).
    pub width: Option<f64>,
    /// Stress behind the pulse, eq. (um) (pulse only).
    pub u_minus: Option<f64>,
    /// Total slip A = u_+ - u_-, eq. (A) (pulse only).
    pub amplitude: Option<f64>,
    shape: Shape,
}

impl TravelingWave {
    /// The wave for 0 < u_+ < 1 and gamma >= 0, with the exact front speed: pulse for
    /// u_+ > gamma, creep for u_+ <= gamma (decided exactly, without forming c).
    pub fn new(u_plus: f64, gamma: f64) -> Result<Self> {
        let c = front_speed(u_plus)?;
        let gamma = check_gamma(gamma)?;
        Self::build(u_plus, c, gamma, Shape::exact(u_plus, c, gamma))
    }

    /// The App. B wave for a given front speed c > 1 (e.g. the paper's interpolation
    /// formula, or a speed measured at finite dx) instead of the exact c(u_+).
    /// `u_c` stays the exact critical stress; the regime follows from c.
    pub fn with_speed(u_plus: f64, c: f64, gamma: f64) -> Result<Self> {
        let u_plus = check_open("u_plus", u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
        let c = check_open("c", c, 1.0, f64::INFINITY, "c > 1 (fronts are supersonic)")?;
        let gamma = check_gamma(gamma)?;
        Self::build(u_plus, c, gamma, Shape::from_speed(c, gamma))
    }

    fn build(u_plus: f64, c: f64, gamma: f64, shape: Shape) -> Result<Self> {
        let u_minus = shape.u_minus(u_plus);
        Ok(TravelingWave {
            u_plus,
            gamma,
            c,
            regime: if shape.is_pulse() {
                Regime::Pulse
            } else {
                Regime::Creep
            },
            u_c: critical_stress(gamma)?,
            width: shape.width(),
            u_minus,
            amplitude: u_minus.map(|um| u_plus - um),
            shape,
        })
    }

    /// u_- as a value that must exist (pulse regime), else an error naming u_plus.
    pub fn require_u_minus(&self) -> Result<f64> {
        self.u_minus
            .ok_or_else(|| creep_error("u_plus", self.u_plus))
    }

    /// The profile u(z) at comoving coordinate z = x - c t (front at z = 0):
    /// u_+ ahead (z > 0), App. B behind; in a pulse u = u_- behind the stick point z = -w.
    pub fn profile(&self, z: f64) -> f64 {
        if z >= 0.0 {
            return self.u_plus;
        }
        if let Some(w) = self.width {
            if z <= -w {
                return self.u_minus.unwrap_or(0.0);
            }
        }
        let Shape {
            s,
            gt,
            one_minus_gt2,
        } = self.shape;
        let xi = z / s;
        let u = self.u_plus;
        if one_minus_gt2 > 0.0 {
            // eq. (complex) with eq. (ab)
            let om = one_minus_gt2.sqrt();
            (gt * xi).exp() * (u * (om * xi).cos() - u * gt / om * (om * xi).sin())
        } else if one_minus_gt2 < 0.0 {
            // eq. (real): a e^{xi k1} + b e^{xi k2}, k1,2 = gt +- r, k2 = 1/(gt + r)
            let r = (-one_minus_gt2).sqrt();
            let a = 0.5 * u * (1.0 - gt / r);
            let b = 0.5 * u * (1.0 + gt / r);
            a * (xi * (gt + r)).exp() + b * (xi / (gt + r)).exp()
        } else {
            // critically damped gt = 1 (u_+ = gamma with the exact speed)
            u * (1.0 - xi) * xi.exp()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pulse_quantities_match_the_papers_formulas_with_exact_speed() {
        let w = TravelingWave::new(0.6, 0.3).unwrap();
        assert_eq!(w.regime, Regime::Pulse);
        assert!((w.c - 1.25).abs() < 1e-15);
        let gt = gamma_tilde(w.c, 0.3);
        assert!((gt - 0.5).abs() < 1e-14); // gamma/u_+ with exact c
        let width = std::f64::consts::PI / (1.0 - gt * gt).sqrt() * (w.c * w.c - 1.0).sqrt();
        assert!((w.width.unwrap() - width).abs() < 1e-12);
        let um = -0.6 * (-std::f64::consts::PI * gt / (1.0 - gt * gt).sqrt()).exp();
        assert!((w.u_minus.unwrap() - um).abs() < 1e-14);
        assert!((w.amplitude.unwrap() - (0.6 - um)).abs() < 1e-14);
        // continuity of the profile at both ends
        assert!((w.profile(-1e-12) - 0.6).abs() < 1e-9);
        let wd = w.width.unwrap();
        assert!((w.profile(-wd + 1e-9) - um).abs() < 1e-7);
    }

    #[test]
    fn creep_below_gamma_and_always_for_gamma_at_least_one() {
        let w = TravelingWave::new(0.25, 0.3).unwrap();
        assert_eq!(w.regime, Regime::Creep);
        assert!(w.width.is_none() && w.u_minus.is_none() && w.require_u_minus().is_err());
        assert!(w.profile(-200.0).abs() < 1e-3);
        let w = TravelingWave::new(0.999, 1.0).unwrap();
        assert_eq!(w.regime, Regime::Creep);
        assert!(w.u_c.is_none());
        assert!(TravelingWave::new(0.5, -0.1).is_err());
    }

    #[test]
    fn u_plus_equal_to_gamma_is_the_critically_damped_creep() {
        // gt = gamma/u_+ = 1 exactly: no stick point, for every gamma (float c would
        // give gt = 1 - 1 ulp for some and call it a pulse of width 5e7)
        for &g in &[0.05, 0.1, 0.3, 0.45, 0.7, 0.9] {
            let w = TravelingWave::new(g, g).unwrap();
            assert_eq!(w.regime, Regime::Creep, "gamma = {g}");
            assert!(w.width.is_none() && w.u_minus.is_none());
            // the critically damped profile u (1 - xi) e^xi, xi = z / sqrt(c^2 - 1)
            let z = -0.7;
            let xi = z / (w.c * w.c - 1.0).sqrt();
            let expect = g * (1.0 - xi) * xi.exp();
            assert!((w.profile(z) - expect).abs() < 1e-12, "gamma = {g}");
            // just above gamma it is a (very wide) pulse
            let p = TravelingWave::new(g * (1.0 + 1e-12), g).unwrap();
            assert_eq!(p.regime, Regime::Pulse);
        }
    }

    #[test]
    fn tiny_u_plus_keeps_full_relative_precision() {
        // gamma = 0: w = pi u_+ / sqrt(1 - u_+^2), u_- = -u_+, whatever the size of u_+
        for &u in &[1e-4, 1e-7, 1e-9, 1e-12, 1e-300] {
            let w = TravelingWave::new(u, 0.0).unwrap();
            let exact = PI * u / (1.0 - u * u).sqrt();
            assert!((w.width.unwrap() / exact - 1.0).abs() < 1e-15, "u = {u}");
            assert_eq!(w.u_minus.unwrap(), -u);
            // the profile is u_+ cos(z/(u_+ c)) behind the front
            let z = -0.25 * exact;
            assert!(
                (w.profile(z) - u * (PI / 4.0).cos()).abs() < 1e-14 * u,
                "u = {u}"
            );
        }
        // with damping: w = pi u^2 c / sqrt((u - g)(u + g))
        let (u, g) = (2e-8, 1e-8);
        let w = TravelingWave::new(u, g).unwrap();
        let exact = PI * u * u / (3.0f64 * 1e-16).sqrt();
        assert!((w.width.unwrap() / exact - 1.0).abs() < 1e-14);
    }
}
