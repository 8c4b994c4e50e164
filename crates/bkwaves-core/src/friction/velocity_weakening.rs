//! Velocity-weakening friction of Carlson-Langer form (paper Sec. VI): the force of a
//! block sliding at speed V over the ground is f = f_s + (f_r - f_s)/(1 + V/V_f) + alpha V,
//! falling from the static threshold f_r at V = 0 to the kinetic level f_s at V >> V_f.
//!
//! Dimensionless (v_f = V_f sqrt(k_p m)/(f_r - f_s), block threshold theta):
//! forward R(s) = theta/(1 + s/v_f) + 2 gamma s, continuous with the static threshold
//! (R(0) = theta); backward (finite beta) R(s) = 2 gamma s - 2 beta - theta/(1 + |s|/v_f).
//! As v_f -> 0 it becomes the Coulomb law. At slip onset it is stiff: a block just over
//! its threshold has s_t = (theta/v_f) s + ..., growing at the rate theta/v_f, so the
//! chain's step is also limited to a fraction of v_f/theta ([`Friction::time_scale`]).

use super::coulomb::{BETA, GAMMA};
use super::Friction;
use crate::error::Result;
use crate::params::ParamSpec;

/// Carlson-Langer velocity weakening plus viscous damping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityWeakening {
    /// Viscous damping gamma >= 0.
    pub gamma: f64,
    /// Characteristic velocity v_f > 0 (in units of (f_r - f_s)/sqrt(k_p m)).
    pub v_f: f64,
    /// beta = f_s/(f_r - f_s); inf: no backward slip.
    pub beta: f64,
}

/// The characteristic velocity of the weakening.
pub const V_F: ParamSpec = ParamSpec {
    name: "v_f",
    lo: 0.0,
    lo_closed: false,
    hi: f64::INFINITY,
    hi_closed: false,
    default: None,
    doc: "characteristic velocity V_f sqrt(k_p m)/(f_r - f_s): R = theta/(1 + s/v_f) + 2 gamma s",
};

impl Friction for VelocityWeakening {
    const NAME: &'static str = "velocity_weakening";
    const DOC: &'static str = "Carlson-Langer: the force falls from f_r to f_s as \
                               1/(1 + V/V_f), plus viscous damping (paper Sec. VI)";
    const PARAMS: &'static [ParamSpec] = &[GAMMA, V_F, BETA];

    fn from_values(values: &[f64]) -> Result<Self> {
        Ok(VelocityWeakening {
            gamma: GAMMA.check("gamma", values[0])?,
            v_f: V_F.check("v_f", values[1])?,
            beta: BETA.check("beta", values[2])?,
        })
    }
    fn values(&self) -> Vec<f64> {
        vec![self.gamma, self.v_f, self.beta]
    }
    #[inline(always)]
    fn excess(&self, s: f64, dir: f64, threshold: f64) -> f64 {
        // |s|: a forward-sliding block whose s dips below 0 inside a step (before its
        // stick is located) sees the same force as at |s|, never the pole at s = -v_f
        let weak = threshold / (1.0 + s.abs() / self.v_f);
        let r = 2.0 * self.gamma * s;
        if dir < 0.0 {
            r - 2.0 * self.beta - weak
        } else {
            r + weak
        }
    }
    #[inline(always)]
    fn lower(&self, threshold: f64) -> f64 {
        -(threshold + 2.0 * self.beta)
    }
    fn beta(&self) -> f64 {
        if self.beta.is_finite() {
            self.beta
        } else {
            0.0
        }
    }
    #[inline(always)]
    fn power(&self, s: f64, dir: f64, threshold: f64) -> (f64, f64) {
        // s (R + beta): the dry part is the force on this branch, f - alpha V, times s
        let weak = threshold / (1.0 + s.abs() / self.v_f);
        ((self.beta() + weak) * s * dir, 2.0 * self.gamma * s * s)
    }
    fn max_slope(&self, threshold_max: f64) -> f64 {
        threshold_max / self.v_f + 2.0 * self.gamma
    }
    fn time_scale(&self, threshold_max: f64) -> f64 {
        self.v_f / threshold_max
    }
    #[inline(always)]
    fn weakening(&self, s: f64, _dir: f64, threshold: f64) -> (f64, f64) {
        // theta/(1 + |s|/v_f) = theta v_f/(v_f + |s|), varying over the speed v_f + |s|
        let d = self.v_f + s.abs();
        (threshold * self.v_f / d, d)
    }
    fn onset_threshold(&self, threshold: f64, phi: f64, dir: f64) -> f64 {
        // R(0) on the slip's branch equals phi: forward R(0) = t, backward -(t + 2 beta)
        let at_phi = if dir < 0.0 {
            -(phi + 2.0 * self.beta)
        } else {
            phi
        };
        // never above the block's own threshold (a slip located past it starts as is)
        if at_phi.is_finite() {
            threshold.min(at_phi)
        } else {
            threshold
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::friction::Coulomb;

    #[test]
    fn the_force_falls_from_the_threshold_to_the_coulomb_law() {
        let f = VelocityWeakening::from_values(&[0.3, 0.01, 0.5]).unwrap();
        let c = Coulomb::new(0.3, 0.5).unwrap();
        // continuous with the static threshold at s = 0, on both branches
        assert_eq!(f.excess(0.0, 1.0, 1.2), 1.2);
        assert_eq!(f.excess(0.0, -1.0, 1.2), f.lower(1.2));
        // half the drop at s = v_f; Coulomb far beyond v_f
        assert!((f.excess(0.01, 1.0, 1.0) - (0.5 + 0.006)).abs() < 1e-15);
        for &(s, dir) in &[(5.0, 1.0), (-5.0, -1.0)] {
            let gap = f.excess(s, dir, 1.0) - c.excess(s, dir, 1.0);
            assert!((gap.abs() - 1.0 / (1.0 + 500.0)).abs() < 1e-15, "{s}");
        }
        // power = s (R + beta) on both branches
        for &(s, dir) in &[(0.7, 1.0), (-0.4, -1.0), (0.003, 1.0)] {
            let (d, v) = f.power(s, dir, 0.9);
            let total = s * (f.excess(s, dir, 0.9) + f.beta);
            assert!((d + v - total).abs() < 1e-15, "{s} {dir}");
        }
        assert!(VelocityWeakening::from_values(&[0.3, 0.0, 0.5]).is_err());
        let inf = VelocityWeakening::from_values(&[0.3, 0.1, f64::INFINITY]).unwrap();
        assert_eq!(inf.lower(1.0), f64::NEG_INFINITY);
        assert!(inf.excess(0.2, 1.0, 1.0).is_finite() && inf.beta() == 0.0);
        assert_eq!(f.time_scale(2.0), 0.005);
        // a slip located a hair before the state's phi reaches the threshold starts on
        // that phi (zero force at onset); one located past it keeps the threshold
        assert_eq!(f.onset_threshold(1.2, 1.2 - 1e-9, 1.0), 1.2 - 1e-9);
        assert_eq!(f.onset_threshold(1.2, 1.3, 1.0), 1.2);
        let t = f.onset_threshold(1.2, f.lower(1.2) + 1e-9, -1.0);
        assert_eq!(f.excess(0.0, -1.0, t), f.lower(1.2) + 1e-9);
        assert_eq!(c.onset_threshold(1.2, 1.0, 1.0), 1.2);
    }
}
