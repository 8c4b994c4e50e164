//! The front-speed law c(u_+) used by the free boundary engine: the exact continuum law
//! c = 1/sqrt(1 - u_+^2) ([`crate::speed::front_speed`], the default) or a table, e.g. the
//! renormalised speed c_eff(u_+) of a disordered medium (docs/disorder.md).
//!
//! A table (u_k, c_k) is interpolated in the variables
//!
//! ```text
//!     X = u_+^2,     Y = 1/c^2,
//! ```
//!
//! by the monotone piecewise cubic Hermite interpolant (Fritsch-Carlson slopes, PCHIP),
//! closed by the two limits every front has: c = 1 at u_+ = 0 (sound speed; node X = 0,
//! Y = 1) and c = infinity at u_+ = 1 (a block at threshold slips at once: X = 1, Y = 0,
//! where births start). In these variables the exact law is the straight line Y = 1 - X,
//! which PCHIP reproduces exactly, and so is a uniform threshold s, c(u_+/s): Y = 1 - X/s^2.
//! The engine integrates the slowness dt/dy = 1/c = sqrt(Y), which PCHIP keeps in [0, 1]
//! (monotone data give a monotone interpolant), so shocks stay supersonic.
//!
//! Validation: 0 < u_k < 1 strictly increasing, c_k > 1 finite and strictly increasing, at
//! least one node. Every error names the key (`speed.u_plus`, `speed.c`) and the range.

use crate::error::{Error, Result};

/// A front-speed law c(u_+).
#[derive(Debug, Clone, PartialEq, Default)]
pub enum SpeedLaw {
    /// c = 1/sqrt(1 - u_+^2) (the tip problem's exact continuum solution).
    #[default]
    Exact,
    /// A monotone table (see the module docs).
    Table(SpeedTable),
}

/// PCHIP of Y = 1/c^2 against X = u_+^2 through the user's nodes and the two end limits.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedTable {
    /// The user's nodes u_+ (strictly increasing in (0, 1)).
    pub u_plus: Vec<f64>,
    /// The user's speeds c (> 1, strictly increasing).
    pub c: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    slope: Vec<f64>,
}

fn table_error(name: &'static str, value: f64, allowed: &'static str) -> Error {
    Error::InvalidParameter {
        name,
        value,
        allowed,
    }
}

impl SpeedTable {
    /// Validate and build the interpolant.
    pub fn new(u_plus: &[f64], c: &[f64]) -> Result<Self> {
        if u_plus.is_empty() || u_plus.len() != c.len() {
            return Err(table_error(
                "speed.u_plus",
                u_plus.len() as f64,
                "as many nodes u_plus as speeds c, at least one",
            ));
        }
        for (k, (&u, &ck)) in u_plus.iter().zip(c).enumerate() {
            if !(u.is_finite() && u > 0.0 && u < 1.0) {
                return Err(table_error(
                    "speed.u_plus",
                    u,
                    "0 < u_plus < 1 at every node",
                ));
            }
            if !(ck.is_finite() && ck > 1.0) {
                return Err(table_error(
                    "speed.c",
                    ck,
                    "finite c > 1 at every node (fronts are supersonic)",
                ));
            }
            if k > 0 && u <= u_plus[k - 1] {
                return Err(table_error(
                    "speed.u_plus",
                    u,
                    "strictly increasing nodes u_plus",
                ));
            }
            if k > 0 && ck <= c[k - 1] {
                return Err(table_error(
                    "speed.c",
                    ck,
                    "c strictly increasing with u_plus (a front is faster in a more \
                     stressed medium)",
                ));
            }
        }
        let mut x = vec![0.0];
        let mut y = vec![1.0];
        for (&u, &ck) in u_plus.iter().zip(c) {
            x.push(u * u);
            y.push(1.0 / (ck * ck));
        }
        x.push(1.0);
        y.push(0.0);
        let slope = pchip_slopes(&x, &y);
        Ok(SpeedTable {
            u_plus: u_plus.to_vec(),
            c: c.to_vec(),
            x,
            y,
            slope,
        })
    }

    /// Y = 1/c^2 at X = u_+^2 in [0, 1].
    fn y_at(&self, xq: f64) -> f64 {
        let (x, y, d) = (&self.x, &self.y, &self.slope);
        let n = x.len();
        let i = x.partition_point(|&xi| xi <= xq).clamp(1, n - 1) - 1;
        let hk = x[i + 1] - x[i];
        let t = (xq - x[i]) / hk;
        let (t2, t3) = (t * t, t * t * t);
        (2.0 * t3 - 3.0 * t2 + 1.0) * y[i]
            + (t3 - 2.0 * t2 + t) * hk * d[i]
            + (-2.0 * t3 + 3.0 * t2) * y[i + 1]
            + (t3 - t2) * hk * d[i + 1]
    }
}

/// Fritsch-Carlson slopes of the monotone cubic Hermite interpolant: weighted harmonic
/// means of the neighbouring secants inside (zero at a local extremum), a one-sided
/// three-point estimate limited to keep monotonicity at the ends.
fn pchip_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = (0..n - 1).map(|k| x[k + 1] - x[k]).collect();
    let del: Vec<f64> = (0..n - 1).map(|k| (y[k + 1] - y[k]) / h[k]).collect();
    let mut d = vec![0.0; n];
    if n == 2 {
        d[0] = del[0];
        d[1] = del[0];
        return d;
    }
    for k in 1..n - 1 {
        if del[k - 1] * del[k] > 0.0 {
            let w1 = 2.0 * h[k] + h[k - 1];
            let w2 = h[k] + 2.0 * h[k - 1];
            d[k] = (w1 + w2) / (w1 / del[k - 1] + w2 / del[k]);
        }
    }
    let end = |h0: f64, h1: f64, d0: f64, d1: f64| {
        let s = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
        if s * d0 <= 0.0 {
            0.0
        } else if d0 * d1 <= 0.0 && s.abs() > 3.0 * d0.abs() {
            3.0 * d0
        } else {
            s
        }
    };
    d[0] = end(h[0], h[1], del[0], del[1]);
    d[n - 1] = end(h[n - 2], h[n - 3], del[n - 2], del[n - 3]);
    d
}

impl SpeedLaw {
    /// A table law (validated).
    pub fn table(u_plus: &[f64], c: &[f64]) -> Result<Self> {
        Ok(SpeedLaw::Table(SpeedTable::new(u_plus, c)?))
    }

    /// dt/dy = 1/c(u) in [0, 1]; 0 where |u| >= 1 (births, and stages of the integrator
    /// that overshoot 1).
    #[inline]
    pub fn slowness(&self, u: f64) -> f64 {
        match self {
            SpeedLaw::Exact => {
                let g = (1.0 - u) * (1.0 + u);
                if g > 0.0 {
                    g.sqrt()
                } else {
                    0.0
                }
            }
            SpeedLaw::Table(t) => {
                let xq = u * u;
                if xq >= 1.0 {
                    0.0
                } else {
                    t.y_at(xq).clamp(0.0, 1.0).sqrt()
                }
            }
        }
    }

    /// c(u_+) for 0 < u_+ < 1.
    pub fn speed(&self, u: f64) -> Result<f64> {
        match self {
            SpeedLaw::Exact => crate::speed::front_speed(u),
            SpeedLaw::Table(t) => {
                let u = crate::error::check_open("u_plus", u, 0.0, 1.0, "0 < u_plus < 1")?;
                Ok(1.0 / t.y_at(u * u).sqrt())
            }
        }
    }

    /// The stress left behind a front that meets u_+ where the threshold is `thr` (None:
    /// the uniform threshold 1), and whether the creep rule was applied. The front moves at
    /// c(u_+/thr) and leaves u_- = -u_+ E(c) (eq. um with that c); at or below the critical
    /// ratio `u_c` (creep) both creep rules leave u_- = 0 where a reset happens at all. The
    /// rule of both free boundary engines (1D and 2D): one source for it.
    pub fn reset_stress(&self, u_plus: f64, thr: Option<f64>, gamma: f64, u_c: f64) -> (f64, bool) {
        let (u, r) = match thr {
            Some(thr) => (u_plus.min(thr), (u_plus / thr).min(1.0 - 1e-16)),
            None => {
                let u = u_plus.min(1.0 - 1e-16);
                (u, u)
            }
        };
        if r > u_c {
            if let Ok(c) = self.speed(r) {
                if let Some(um) = crate::wave::u_minus_from_speed(u, c, gamma) {
                    return (um, false);
                }
            }
        }
        (0.0, true)
    }

    /// The critical stress u_c(gamma) of this law: c(u_c) = 1/sqrt(1 - gamma^2) (eq.
    /// gammac: a pulse re-sticks iff c^2 (1 - gamma^2) > 1). gamma for the exact law.
    pub fn critical_stress(&self, gamma: f64) -> f64 {
        match self {
            SpeedLaw::Exact => gamma,
            SpeedLaw::Table(t) => {
                if gamma <= 0.0 {
                    return 0.0;
                }
                // Y(X) decreasing from 1 to 0: Y(X_c) = 1 - gamma^2
                let target = (1.0 - gamma) * (1.0 + gamma);
                let (mut lo, mut hi) = (0.0f64, 1.0f64);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if t.y_at(mid) > target {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                    if hi - lo <= 1e-17 {
                        break;
                    }
                }
                (0.5 * (lo + hi)).sqrt()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_of_the_exact_law_is_the_exact_law() {
        // Y = 1 - X is a straight line: PCHIP reproduces it to rounding
        let u: Vec<f64> = [0.1, 0.35, 0.5, 0.8, 0.9].to_vec();
        let c: Vec<f64> = u.iter().map(|&u| 1.0 / (1.0f64 - u * u).sqrt()).collect();
        let t = SpeedLaw::table(&u, &c).unwrap();
        for k in 1..1000 {
            let q = k as f64 / 1000.0;
            let d = t.slowness(q) - SpeedLaw::Exact.slowness(q);
            assert!(
                d.abs() < 1e-13 / SpeedLaw::Exact.slowness(q).max(1e-3),
                "{q}: {d}"
            );
        }
        for g in [0.0, 0.2, 0.45, 0.9] {
            assert!((t.critical_stress(g) - g).abs() < 1e-12, "{g}");
        }
        // a uniform threshold s: c(u/s), Y = 1 - X/s^2, also a line (inside [0, s^2])
        let s: f64 = 1.5;
        let cs: Vec<f64> = u
            .iter()
            .map(|&u| 1.0 / (1.0 - (u / s).powi(2)).sqrt())
            .collect();
        let ts = SpeedLaw::table(&u, &cs).unwrap();
        let q = 0.6;
        assert!((ts.speed(q).unwrap() * (1.0f64 - (q / s).powi(2)).sqrt() - 1.0).abs() < 1e-13);
    }

    #[test]
    fn a_table_is_monotone_and_converges_at_third_order() {
        // c(u) = (1 + u^2/4)/sqrt(1 - u^2): not a line in (X, Y)
        let law = |u: f64| (1.0 + 0.25 * u * u) / (1.0 - u * u).sqrt();
        let mut errs = Vec::new();
        for n in [10, 20, 40] {
            let u: Vec<f64> = (1..=n).map(|k| k as f64 / (n + 1) as f64).collect();
            let c: Vec<f64> = u.iter().map(|&u| law(u)).collect();
            let t = SpeedLaw::table(&u, &c).unwrap();
            let mut worst = 0.0f64;
            let mut last = f64::INFINITY;
            for k in 1..2000 {
                let q = k as f64 / 2000.0;
                let f = t.slowness(q);
                assert!(f <= last + 1e-15, "slowness rises at u = {q}");
                last = f;
                worst = worst.max((f - 1.0 / law(q)).abs());
            }
            errs.push(worst);
        }
        // (near u = 1 the slowness ~ sqrt(1 - u) is not smooth in u, but Y is in X)
        assert!(
            errs[0] / errs[1] > 4.0 && errs[1] / errs[2] > 4.0,
            "{errs:?}"
        );
    }

    #[test]
    fn bad_tables_name_the_key_and_the_range() {
        let cases: [(&[f64], &[f64], &str); 7] = [
            (&[], &[], "speed.u_plus"),
            (&[0.5, 0.6], &[1.2], "speed.u_plus"),
            (&[0.0, 0.6], &[1.1, 1.2], "speed.u_plus"),
            (&[0.6, 1.0], &[1.1, 1.2], "speed.u_plus"),
            (&[0.6, 0.5], &[1.1, 1.2], "speed.u_plus"),
            (&[0.5, 0.6], &[1.2, 1.1], "speed.c"),
            (&[0.5, 0.6], &[0.9, 1.1], "speed.c"),
        ];
        for (u, c, key) in cases {
            match SpeedLaw::table(u, c) {
                Err(Error::InvalidParameter { name, allowed, .. }) => {
                    assert_eq!(name, key, "{u:?} {c:?}");
                    assert!(!allowed.is_empty());
                }
                other => panic!("{u:?} {c:?}: {other:?}"),
            }
        }
        assert!(SpeedLaw::table(&[0.5], &[f64::NAN]).is_err());
        assert!(SpeedLaw::table(&[0.5], &[f64::INFINITY]).is_err());
    }
}
