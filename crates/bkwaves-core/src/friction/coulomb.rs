//! Coulomb friction with a viscous term (paper Sec. II): static threshold f_r, kinetic
//! force f_s < f_r opposing the motion, plus alpha * (speed over the ground).
//!
//! Dimensionless (beta = f_s/(f_r - f_s), gamma = alpha / (2 sqrt(k_p m))):
//! forward sliding R(s) = 2 gamma s; backward sliding R(s) = 2 gamma s - 2 beta (the
//! kinetic force flips sign, so it differs from the forward branch by 2 f_s). A stuck
//! block holds while -(1 + 2 beta) < phi < 1: |F| < f_r with F = f_s + (f_r - f_s) phi.

use super::Friction;
use crate::error::{check_at_least, Result};

/// Coulomb (static/kinetic) friction plus viscous damping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coulomb {
    /// Viscous damping gamma >= 0.
    pub gamma: f64,
    /// beta = f_s/(f_r - f_s) >= 0 (backward-slip threshold and backward kinetic force).
    pub beta: f64,
}

impl Coulomb {
    /// Validated constructor.
    pub fn new(gamma: f64, beta: f64) -> Result<Self> {
        check_at_least("gamma", gamma, 0.0, "gamma >= 0")?;
        check_at_least("beta", beta, 0.0, "beta >= 0")?;
        Ok(Coulomb { gamma, beta })
    }
}

impl Friction for Coulomb {
    fn name(&self) -> &'static str {
        "coulomb"
    }
    #[inline(always)]
    fn excess(&self, s: f64, dir: f64) -> f64 {
        // dir = +1: 2 gamma s; dir = -1: 2 gamma s - 2 beta (branch free)
        2.0 * self.gamma * s + self.beta * (dir - 1.0)
    }
    fn upper(&self) -> f64 {
        1.0
    }
    fn lower(&self) -> f64 {
        -(1.0 + 2.0 * self.beta)
    }
    fn beta(&self) -> f64 {
        self.beta
    }
    #[inline(always)]
    fn power(&self, s: f64, dir: f64) -> (f64, f64) {
        // the force applied on this branch times the speed (not beta |s|): exact books even
        // when s has just crossed zero before its stick is located
        (self.beta * s * dir, 2.0 * self.gamma * s * s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn branches_and_power_are_consistent() {
        let f = Coulomb::new(0.3, 2.0).unwrap();
        assert_eq!(f.excess(0.5, 1.0), 0.3);
        assert_eq!(f.excess(-0.5, -1.0), -0.3 - 4.0);
        assert_eq!(f.lower(), -5.0);
        // power = s (R + beta) = s f / (f_r - f_s) on both branches
        for &(s, dir) in &[(0.7, 1.0), (-0.4, -1.0)] {
            let (c, v) = f.power(s, dir);
            let total = s * (f.excess(s, dir) + f.beta);
            assert!((c + v - total).abs() < 1e-15, "{s} {dir}");
        }
        assert!(Coulomb::new(-0.1, 0.0).is_err());
        assert!(Coulomb::new(0.1, f64::NAN).is_err());
    }
}
