//! The traveling wave behind the front (paper Sec. III and App. B), v = 0.
//!
//! Behind the slip point z = x - c t = 0 blocks slide according to eq. (slidet),
//! (c^2 - 1) u_zz - 2 c gamma u_z + u = 0 with u(0) = u_+, u_z(0) = 0 (eq. initc).
//! With xi = z / sqrt(c^2 - 1) and gt = c gamma / sqrt(c^2 - 1) (the paper's
//! gamma-tilde) it reads u_xixi - 2 gt u_xi + u = 0. gt < 1: a self-healing pulse
//! that re-sticks at z = -w (eqs. complex, ab, w, um, A); gt >= 1: creep, u -> 0
//! behind (eq. real). With the exact c(u_+) of [`crate::speed`], gt = gamma/u_+.

use crate::error::Result;
use crate::speed::{check_gamma, creep_error, critical_stress, front_speed};

/// Which kind of wave a given (u_+, gamma) produces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// u_+ > u_c: blocks re-stick a finite distance w behind the front.
    Pulse,
    /// u_+ <= u_c: blocks never re-stick at v = 0; u -> 0 behind the front.
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

/// The paper's gamma-tilde = c gamma / sqrt(c^2 - 1) for a front of speed c > 1.
pub fn gamma_tilde(c: f64, gamma: f64) -> f64 {
    c * gamma / ((c - 1.0) * (c + 1.0)).sqrt()
}

/// Width w of the pulse, eq. (w), for front speed c and damping gamma.
/// `None` in the creep regime (c^2 (1 - gamma^2) <= 1), where w is infinite.
pub fn width_from_speed(c: f64, gamma: f64) -> Option<f64> {
    let d = c * c * (1.0 - gamma * gamma) - 1.0;
    (d > 0.0).then(|| std::f64::consts::PI * (c * c - 1.0) / d.sqrt())
}

/// The stress u_- left behind a pulse, eq. (um). `None` in the creep regime.
pub fn u_minus_from_speed(u_plus: f64, c: f64, gamma: f64) -> Option<f64> {
    let d = c * c * (1.0 - gamma * gamma) - 1.0;
    (d > 0.0).then(|| -u_plus * (-std::f64::consts::PI * gamma * c / d.sqrt()).exp())
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
}

impl TravelingWave {
    /// The wave for 0 < u_+ < 1 and gamma >= 0, with the exact front speed.
    pub fn new(u_plus: f64, gamma: f64) -> Result<Self> {
        Self::with_speed(u_plus, front_speed(u_plus)?, gamma)
    }

    /// The App. B wave for a given front speed c > 1 (e.g. the paper's interpolation
    /// formula, or a speed measured at finite dx) instead of the exact c(u_+).
    /// `u_c` stays the exact critical stress; the regime follows from c.
    pub fn with_speed(u_plus: f64, c: f64, gamma: f64) -> Result<Self> {
        let u_plus = crate::error::check_open("u_plus", u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
        let c =
            crate::error::check_open("c", c, 1.0, f64::INFINITY, "c > 1 (fronts are supersonic)")?;
        let gamma = check_gamma(gamma)?;
        let u_c = critical_stress(gamma)?;
        let width = width_from_speed(c, gamma);
        let u_minus = u_minus_from_speed(u_plus, c, gamma);
        let regime = if width.is_some() {
            Regime::Pulse
        } else {
            Regime::Creep
        };
        Ok(TravelingWave {
            u_plus,
            gamma,
            c,
            regime,
            u_c,
            width,
            u_minus,
            amplitude: u_minus.map(|um| u_plus - um),
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
        let s = ((self.c - 1.0) * (self.c + 1.0)).sqrt();
        let xi = z / s;
        let gt = gamma_tilde(self.c, self.gamma);
        let u = self.u_plus;
        if gt < 1.0 {
            // eq. (complex) with eq. (ab)
            let om = (1.0 - gt * gt).sqrt();
            (gt * xi).exp() * (u * (om * xi).cos() - u * gt / om * (om * xi).sin())
        } else if gt > 1.0 {
            // eq. (real): a e^{xi k1} + b e^{xi k2}, written to avoid cancellation
            let r = (gt * gt - 1.0).sqrt();
            let a = 0.5 * u * (1.0 - gt / r);
            let b = 0.5 * u * (1.0 + gt / r);
            a * (xi * (gt + r)).exp() + b * (xi * (gt - r)).exp()
        } else {
            // critically damped limit gt = 1
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
}
