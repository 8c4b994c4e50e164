//! Opt-in step-size control (issue 16; docs/chain.md, "Step-size control").
//!
//! The fixed step h_min = `step` dx is the floor: the controller never steps shorter, so
//! wherever the dynamics is fast it takes exactly the fixed step. Where the sliding
//! blocks move smoothly (a chain creeping with the loader) it lengthens the step, up to
//! RK4's stability limit, while the step's error indicator stays below the tolerance.
//!
//! The indicator costs no stage: from the step's start and end values of u, u_t and u_tt
//! (all three at both ends are the engine's anyway), the corrected trapezoid rule's
//! defect of each sliding block,
//!
//!   d = u1 - u0 - h (w0 + w1)/2 + h^2 (a1 - a0)/12  =  -h^5 u^(5)/720 + O(h^7),
//!
//! measures the solution's fifth derivative over the step, as RK4's local error does
//! (for a mode of frequency omega: |d| = (omega h)^5 |u|/720, RK4's error in u
//! (omega h)^5 |u|/120). The controller bounds max |d| over the sliding blocks.
//!
//! Rules: a step whose indicator exceeds the tolerance is redone at h_min (unless it was
//! h_min); the next step is h_next = 0.9 h (tol/d)^(1/5), at most twice the last and the
//! stability limit, at least h_min; after any switch (a slip, stick or reversal) or a
//! kick the step returns to h_min (a new slip is a fast transient).

use crate::error::{Error, Result};

/// The controller's settings and state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepControl {
    /// Largest indicator max |d| a step may make.
    pub tol: f64,
    /// The fixed step (the floor) and the stability limit (the ceiling).
    pub h_min: f64,
    pub h_max: f64,
    /// The step to try next.
    pub h: f64,
    /// The chain's switch count when the last step ended (a change means an event).
    pub switches_seen: u64,
}

/// Safety factor of the step update.
const SAFETY: f64 = 0.9;
/// Largest growth of the step from one step to the next.
const GROWTH: f64 = 2.0;

impl StepControl {
    /// A controller with tolerance `tol` between the fixed step `h_min` and the
    /// stability limit `h_max`; `tol` is checked and named `step_tolerance`.
    pub fn new(tol: f64, h_min: f64, h_max: f64) -> Result<Self> {
        if !(tol.is_finite() && tol > 0.0) {
            return Err(Error::InvalidParameter {
                name: "step_tolerance",
                value: tol,
                allowed: "0 < step_tolerance < inf (largest error indicator of one step)",
            });
        }
        Ok(StepControl {
            tol,
            h_min,
            h_max: h_max.max(h_min),
            h: h_min,
            switches_seen: 0,
        })
    }

    /// The step after one of length h whose indicator was `d` (no event in it).
    pub fn update(&mut self, h: f64, d: f64) {
        let factor = if d > 0.0 {
            SAFETY * (self.tol / d).powf(0.2)
        } else {
            GROWTH
        };
        self.h = (h * factor.min(GROWTH)).min(self.h_max).max(self.h_min);
    }

    /// Back to the fixed step (after an event).
    pub fn reset(&mut self) {
        self.h = self.h_min;
    }
}

/// The indicator of a step over the sliding runs: max |d| (module docs) from the start
/// values (u0, w0, a0) and the end values (u1, w1, a1) of each run.
#[allow(clippy::too_many_arguments)]
pub fn indicator(
    runs: &[(usize, usize)],
    h: f64,
    u0: &[f64],
    w0: &[f64],
    a0: &[f64],
    u1: &[f64],
    w1: &[f64],
    a1: &[f64],
) -> f64 {
    let (half, twelfth) = (0.5 * h, h * h / 12.0);
    let defect = |u0: f64, w0: f64, a0: f64, u1: f64, w1: f64, a1: f64| {
        ((u1 - u0) - half * (w0 + w1) + twelfth * (a1 - a0)).abs()
    };
    // eight independent maxima (so the loop vectorises), folded at the end; a NaN is
    // dropped here (the step's books catch a non-finite state)
    const L: usize = 8;
    let mut m = [0.0f64; L];
    for &(a, b) in runs {
        let (u0, w0, a0) = (&u0[a..b], &w0[a..b], &a0[a..b]);
        let (u1, w1, a1) = (&u1[a..b], &w1[a..b], &a1[a..b]);
        let k = (b - a) / L * L;
        for c in (0..k).step_by(L) {
            for j in 0..L {
                let i = c + j;
                let d = defect(u0[i], w0[i], a0[i], u1[i], w1[i], a1[i]);
                m[j] = if d > m[j] { d } else { m[j] };
            }
        }
        for i in k..(b - a) {
            let d = defect(u0[i], w0[i], a0[i], u1[i], w1[i], a1[i]);
            m[0] = if d > m[0] { d } else { m[0] };
        }
    }
    m.iter().fold(0.0, |x: f64, &y| if y > x { y } else { x })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// For u = cos(omega t) the indicator is (omega h)^5/720 to leading order, at any
    /// phase where u^(5) = omega^5 sin(omega t) is near its peak.
    #[test]
    fn indicator_is_the_fifth_derivative_term() {
        for &(omega, h) in &[(1.0, 0.05), (40.0, 0.0025), (3.0, 0.01)] {
            let t0 = std::f64::consts::FRAC_PI_2 / omega - 0.5 * h;
            let t1 = t0 + h;
            let f = |t: f64| ((omega * t).cos(), -omega * (omega * t).sin());
            let acc = |t: f64| -omega * omega * (omega * t).cos();
            let (u0, w0) = f(t0);
            let (u1, w1) = f(t1);
            let d = indicator(
                &[(0, 1)],
                h,
                &[u0],
                &[w0],
                &[acc(t0)],
                &[u1],
                &[w1],
                &[acc(t1)],
            );
            let expect = (omega * h).powi(5) / 720.0;
            assert!(
                (d / expect - 1.0).abs() < 0.02,
                "omega {omega} h {h}: {d:e} vs {expect:e}"
            );
        }
    }

    #[test]
    fn the_step_grows_at_most_twice_and_stays_between_its_bounds() {
        let mut c = StepControl::new(1e-9, 0.01, 0.5).unwrap();
        c.update(0.01, 0.0);
        assert_eq!(c.h, 0.02);
        c.update(0.4, 1e-20);
        assert_eq!(c.h, 0.5);
        c.update(0.02, 1.0);
        assert_eq!(c.h, 0.01);
        // at the tolerance: 0.9 of the step
        c.update(0.1, 1e-9);
        assert!((c.h - 0.09).abs() < 1e-15);
        c.reset();
        assert_eq!(c.h, 0.01);
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = StepControl::new(bad, 0.01, 0.5).unwrap_err().to_string();
            assert!(e.contains("step_tolerance"), "{e}");
        }
    }
}
