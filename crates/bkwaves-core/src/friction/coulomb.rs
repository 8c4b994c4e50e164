//! Coulomb friction with a viscous term (paper Sec. II): static threshold f_r, kinetic
//! force f_s < f_r opposing the motion, plus alpha * (speed over the ground).
//!
//! Dimensionless (beta = f_s/(f_r - f_s), gamma = alpha / (2 sqrt(k_p m))):
//! forward sliding R(s) = 2 gamma s; backward sliding R(s) = 2 gamma s - 2 beta (the
//! kinetic force flips sign, so it differs from the forward branch by 2 f_s). A stuck
//! block holds while -(1 + 2 beta) < phi < 1: |F| < f_r with F = f_s + (f_r - f_s) phi.
//!
//! beta = +inf is the paper's model, no backward slip (a block slides until its speed over
//! the ground returns to zero): the backward threshold -(1 + 2 beta) is then -inf. The
//! forward branch does not contain beta, so the dynamics of a chain that only slides
//! forward is the same for every beta; the energy books then use the beta-free form
//! (see [`Friction::beta`] and ../chain/energy.rs).

use super::Friction;
use crate::error::Result;
use crate::params::ParamSpec;

/// Coulomb (static/kinetic) friction plus viscous damping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coulomb {
    /// Viscous damping gamma >= 0.
    pub gamma: f64,
    /// beta = f_s/(f_r - f_s) >= 0 (backward-slip threshold and backward kinetic force);
    /// +inf: no backward slip.
    pub beta: f64,
}

/// The viscous damping gamma = alpha / (2 sqrt(k_p m)), shared by the laws that have it.
pub const GAMMA: ParamSpec = ParamSpec {
    name: "gamma",
    lo: 0.0,
    lo_closed: true,
    hi: f64::INFINITY,
    hi_closed: false,
    default: None,
    doc: "viscous damping alpha / (2 sqrt(k_p m)): R gains 2 gamma s",
};

/// beta = f_s/(f_r - f_s), shared by the laws that have it.
pub const BETA: ParamSpec = ParamSpec {
    name: "beta",
    lo: 0.0,
    lo_closed: true,
    hi: f64::INFINITY,
    hi_closed: true,
    default: Some(f64::INFINITY),
    doc: "f_s/(f_r - f_s): a stuck block slips backward at phi <= -(threshold + 2 beta); \
          inf (default): no backward slip, the paper's model",
};

impl Coulomb {
    /// Validated constructor.
    pub fn new(gamma: f64, beta: f64) -> Result<Self> {
        GAMMA.check("gamma", gamma)?;
        BETA.check("beta", beta)?;
        Ok(Coulomb { gamma, beta })
    }

    /// True when backward slip is possible (finite beta).
    pub fn backward_slip(&self) -> bool {
        self.beta.is_finite()
    }
}

impl Friction for Coulomb {
    const NAME: &'static str = "coulomb";
    const DOC: &'static str = "static threshold, constant kinetic force f_s, viscous damping \
                               (the paper's law)";
    const PARAMS: &'static [ParamSpec] = &[GAMMA, BETA];

    fn from_values(values: &[f64]) -> Result<Self> {
        Coulomb::new(values[0], values[1])
    }
    fn values(&self) -> Vec<f64> {
        vec![self.gamma, self.beta]
    }
    #[inline(always)]
    fn excess(&self, s: f64, dir: f64, _threshold: f64) -> f64 {
        // dir = +1: 2 gamma s; dir = -1: 2 gamma s - 2 beta (a branch, not beta (dir - 1):
        // with beta = inf that is inf * 0 = NaN on the forward branch)
        let r = 2.0 * self.gamma * s;
        if dir < 0.0 {
            r - 2.0 * self.beta
        } else {
            r
        }
    }
    #[inline(always)]
    fn lower(&self, threshold: f64) -> f64 {
        // beta = inf: -inf, never reached
        -(threshold + 2.0 * self.beta)
    }
    fn beta(&self) -> f64 {
        // no backward slip: the books in the beta-free form (the beta terms cancel exactly)
        if self.backward_slip() {
            self.beta
        } else {
            0.0
        }
    }
    #[inline(always)]
    fn power(&self, s: f64, dir: f64, _threshold: f64) -> (f64, f64) {
        // the force applied on this branch times the speed (not beta |s|): exact books even
        // when s has just crossed zero before its stick is located
        (self.beta() * s * dir, 2.0 * self.gamma * s * s)
    }
    fn dry_power_is_zero(&self) -> bool {
        // beta s dir with the books' beta = 0
        self.beta() == 0.0
    }
    fn max_slope(&self, _threshold_max: f64) -> f64 {
        2.0 * self.gamma
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn branches_and_power_are_consistent() {
        let f = Coulomb::new(0.3, 2.0).unwrap();
        assert_eq!(f.excess(0.5, 1.0, 1.0), 0.3);
        assert_eq!(f.excess(-0.5, -1.0, 1.0), -0.3 - 4.0);
        assert_eq!(f.lower(1.0), -5.0);
        assert_eq!(f.lower(0.5), -4.5);
        // power = s (R + beta) = s f / (f_r - f_s) on both branches
        for &(s, dir) in &[(0.7, 1.0), (-0.4, -1.0)] {
            let (c, v) = f.power(s, dir, 1.0);
            let total = s * (f.excess(s, dir, 1.0) + f.beta);
            assert!((c + v - total).abs() < 1e-15, "{s} {dir}");
        }
        assert!(Coulomb::new(-0.1, 0.0).is_err());
        assert!(Coulomb::new(0.1, f64::NAN).is_err());
        assert!(Coulomb::new(0.1, -1.0).is_err());
        assert!(Coulomb::new(0.1, f64::NEG_INFINITY).is_err());
    }

    #[test]
    fn infinite_beta_is_forward_only_and_finite() {
        // the paper's model: no backward slip; nothing may turn into NaN (inf * 0)
        let f = Coulomb::new(0.3, f64::INFINITY).unwrap();
        assert!(!f.backward_slip());
        assert_eq!(f.excess(0.5, 1.0, 1.0), 0.3);
        assert_eq!(f.excess(0.0, 1.0, 1.0), 0.0);
        assert_eq!(f.lower(1.0), f64::NEG_INFINITY);
        assert_eq!(f.upper(1.0), 1.0);
        // forward branch and power identical to any finite beta's (beta-free books)
        let g = Coulomb::new(0.3, 0.0).unwrap();
        for &s in &[0.0, 0.7, 1e-9] {
            assert_eq!(f.excess(s, 1.0, 1.0), g.excess(s, 1.0, 1.0));
            assert_eq!(f.power(s, 1.0, 1.0), g.power(s, 1.0, 1.0));
        }
        assert_eq!(f.beta(), 0.0);
        // inf is a value of the table's beta (its default), -inf is not
        assert_eq!(BETA.default, Some(f64::INFINITY));
        assert!(BETA.contains(f64::INFINITY) && !BETA.contains(f64::NEG_INFINITY));
        assert!(!GAMMA.contains(f64::INFINITY));
    }
}
