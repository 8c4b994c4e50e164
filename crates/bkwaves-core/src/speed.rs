//! The front speed c(u_+) of the traveling shock in the continuum limit.
//!
//! The paper (App. A) obtains c(u_+) numerically from the discrete problem at the
//! tip of the wave and offers an interpolation formula good to a few per cent
//! (eq. c). Solving that tip problem to machine precision ([`crate::tip`]) shows
//! that its answer is, to the solver's precision (~1e-13 relative over
//! 0.01 <= u_+ <= 0.999), the closed form
//!
//! ```text
//!     c(u_+) = 1 / sqrt(1 - u_+^2),     equivalently  u_+ = sqrt(1 - 1/c^2).
//! ```
//!
//! It reproduces every limit the paper states: c = 1 + u_+^2/2 + ... (eq. c1), and
//! (1 - u_+)/u_+ = 1/(2c^2) + 3/(8c^4) + 5/(16c^6) + 35/(128c^8) + ... (eq. ca;
//! the paper quotes 0.2719 for the last coefficient, the binomial value is
//! 35/128 = 0.2734). See docs/theory.md. This module is the single source of
//! truth for c(u_+) used by every engine and by the Python package.

use crate::error::{check_at_least, check_open, Error, Result};

/// Front speed c(u_+) = 1/sqrt(1 - u_+^2) for 0 < u_+ < 1 (continuum limit, v = 0).
pub fn front_speed(u_plus: f64) -> Result<f64> {
    let u = check_open("u_plus", u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
    // (1-u)(1+u) keeps full relative precision near u -> 1.
    Ok(1.0 / ((1.0 - u) * (1.0 + u)).sqrt())
}

/// Front speed of the discrete chain at lattice spacing dx > 0 without damping
/// (gamma = 0, v = 0):
///
/// ```text
///     c(u_+; dx) = dx / (2 u_+ asin(dx sqrt(1 - u_+^2) / (2 u_+)))
/// ```
///
/// from the Wiener-Hopf solution of the finite-dx tip problem (docs/theory.md): the
/// slip threshold is set by the lattice mode that co-moves with the front. It tends to
/// [`front_speed`] as dx -> 0 with a relative correction -dx^2 (1 - u_+^2)/(24 u_+^2).
///
/// The tip problem behind it lets every block slide for ever; in the chain a block
/// re-sticks about w/dx blocks behind the tip, and that feeds back on the tip speed: the
/// closed form is returned only inside [`check_lattice_front`]'s domain (docs/theory.md,
/// "Narrow pulses"); elsewhere the error names u_plus, dx and gamma and points to the chain.
pub fn lattice_front_speed(u_plus: f64, dx: f64) -> Result<f64> {
    let u = check_open("u_plus", u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
    let dx = check_open("dx", dx, 0.0, f64::INFINITY, "dx > 0")?;
    let c = lattice_closed_form(u, dx).ok_or_else(|| narrow_pulse_error(u))?;
    check_lattice_front(u, c, dx, 0.0)?;
    Ok(c)
}

/// The Wiener-Hopf closed form of the linear (never re-sticking) finite-dx tip problem at
/// gamma = 0, without the domain check of [`lattice_front_speed`]; `None` where
/// dx sqrt(1 - u_+^2) >= 2 u_+ (no root). For comparisons with the numerical tip solver.
pub fn lattice_closed_form(u_plus: f64, dx: f64) -> Option<f64> {
    let arg = dx * ((1.0 - u_plus) * (1.0 + u_plus)).sqrt() / (2.0 * u_plus);
    (arg < 1.0).then(|| dx / (2.0 * u_plus * arg.asin()))
}

/// Smallest [`resticking_exponent`] at which the speed of the (never re-sticking) tip
/// problem is trusted as the chain's: the chain's speed differs from it by
/// |dc/c| ~ a exp(-X) with a = 0.01 ... 0.25 (measured for 0 <= gamma <= 0.3,
/// 0.05 <= dx <= 0.4, docs/theory.md), i.e. below ~5e-10 for X >= 20.
pub const MIN_RESTICKING_EXPONENT: f64 = 20.0;

/// The rate lambda > 0 at which the lattice behind a front of speed c > 1 carries a
/// disturbance forward to the tip: exp(lambda t) solves the linearised sliding equation
/// of the tip problem, g'' = g(t + T) + g(t - T) - 2 g - dx^2 g - 2 gamma dx g', T = 1/c,
/// when 4 sinh^2(lambda T/2) = lambda^2 + 2 gamma dx lambda + dx^2 (K(lambda) = 0). The
/// smallest positive root is the slowest decay towards the tip (the complex roots with
/// Re > 0 decay several times faster; the lattice wave co-moving with the front, on the
/// imaginary axis at gamma = 0, moves into Re < 0 with damping: radiation stays behind).
pub fn resticking_decay_rate(c: f64, dx: f64, gamma: f64) -> f64 {
    let t = 1.0 / c;
    // f(l) = ln(2 sinh(l T/2)) - ln(sqrt(l^2 + 2 gamma dx l + dx^2)): < 0 below the root
    let f = |l: f64| {
        (2.0 * (0.5 * l * t).sinh()).ln() - 0.5 * (l * (l + 2.0 * gamma * dx) + dx * dx).ln()
    };
    let (mut lo, mut hi) = (1e-12_f64, 1.0_f64);
    while f(hi) < 0.0 && hi < 1e6 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// X = lambda tau_r: how many e-folds of [`resticking_decay_rate`] lie between the tip of
/// a front of speed c > 1 at spacing dx and damping gamma and the block that re-sticks
/// behind it, tau_r = w/(c dx) tip time units later, w = w(u_+, gamma) App. B's pulse
/// width (eq. w, with the exact continuum speed). +inf in creep (u_+ <= gamma: App. B's
/// wave never re-sticks). At gamma = 0 and small u_+: X ~ sqrt(12) pi u_+^2/dx.
pub fn resticking_exponent(u_plus: f64, c: f64, dx: f64, gamma: f64) -> f64 {
    let width = crate::wave::TravelingWave::new(u_plus, gamma)
        .ok()
        .and_then(|w| w.width);
    match width {
        None => f64::INFINITY,
        Some(w) => resticking_decay_rate(c, dx, gamma) * w / (c * dx),
    }
}

/// The domain in which the speed c of the finite-dx tip problem (which lets every block
/// behind the tip slide for ever) is the discrete chain's speed: c > 1 and
/// X = [`resticking_exponent`] >= [`MIN_RESTICKING_EXPONENT`]; creep (u_+ <= gamma) needs
/// only c > 1. The one check used by [`lattice_front_speed`] (gamma = 0) and by the
/// numerical tip solver at dx > 0 ([`crate::tip::solve_for_u_plus`]); the error names
/// u_plus, dx and gamma and points to the chain.
pub fn check_lattice_front(u_plus: f64, c: f64, dx: f64, gamma: f64) -> Result<()> {
    let supersonic = c > 1.0;
    let x = if supersonic {
        resticking_exponent(u_plus, c, dx, gamma)
    } else {
        f64::NAN
    };
    if x >= MIN_RESTICKING_EXPONENT {
        Ok(())
    } else {
        Err(narrow_pulse_error(u_plus))
    }
}

fn narrow_pulse_error(u_plus: f64) -> Error {
    Error::InvalidParameter {
        name: "u_plus",
        value: u_plus,
        allowed: "a front whose tip problem is the chain's at this dx and gamma: c > 1 and, \
                  for a pulse (u_plus > gamma), X = lambda w/(c dx) >= 20 (w the pulse width \
                  of App. B, lambda the decay rate of the lattice behind the tip: blocks \
                  re-stick w/dx spacings behind the tip and change c by ~0.1 exp(-X)); \
                  roughly u_plus^2/dx >= 2 for small u_plus and gamma. Otherwise measure \
                  the front in the chain: bk.chain.front(u_plus, gamma, dx)",
    }
}

/// Inverse of [`front_speed`]: the stress u_+ ahead of a front moving at speed c > 1.
pub fn u_plus_of_speed(c: f64) -> Result<f64> {
    let c = check_open("c", c, 1.0, f64::INFINITY, "c > 1 (fronts are supersonic)")?;
    Ok(((c - 1.0) * (c + 1.0)).sqrt() / c)
}

/// The stress threshold u_+ - 1 relation of the tip problem: theta = (1 - u_+)/u_+.
pub fn theta_of_u_plus(u_plus: f64) -> Result<f64> {
    let u = check_open("u_plus", u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
    Ok((1.0 - u) / u)
}

/// Critical stress u_c(gamma) separating creep (u_+ < u_c) from self-healing pulses
/// (u_+ > u_c), eq. (gammac): gamma = sqrt(c(u_c)^2 - 1)/c(u_c). With the exact
/// c(u_+) this is simply u_c = gamma. Returns `None` for gamma >= 1, where every
/// wave creeps (the paper, Sec. III).
pub fn critical_stress(gamma: f64) -> Result<Option<f64>> {
    let g = check_at_least("gamma", gamma, 0.0, "gamma >= 0")?;
    if g < 1.0 {
        Ok(Some(g))
    } else {
        Ok(None)
    }
}

/// Check a damping parameter (gamma >= 0, finite).
pub fn check_gamma(gamma: f64) -> Result<f64> {
    check_at_least("gamma", gamma, 0.0, "gamma >= 0")
}

/// Error for a u_+ at which a quantity does not exist.
pub(crate) fn creep_error(name: &'static str, value: f64) -> Error {
    Error::InvalidParameter {
        name,
        value,
        allowed: "u_plus > u_c(gamma) = gamma (pulse regime)",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn limits_of_the_paper() {
        // eq. (c1): c = 1 + u^2/2 for small u
        let u = 1e-3;
        let c = front_speed(u).unwrap();
        assert!(((c - 1.0) / (u * u) - 0.5).abs() < 1e-6);
        // eq. (ca) leading term: theta ~ 1/(2 c^2) for large c
        let c = 1e3;
        let th = theta_of_u_plus(u_plus_of_speed(c).unwrap()).unwrap();
        assert!((th * 2.0 * c * c - 1.0).abs() < 1e-5);
        // round trip
        // (c -> u_+ is ill-conditioned as c -> 1: c - 1 ~ u^2/2 loses digits)
        for &u in &[1e-3, 0.1, 0.5, 0.9, 0.999_999] {
            let back = u_plus_of_speed(front_speed(u).unwrap()).unwrap();
            assert!((back - u).abs() < 1e-12 / u, "{u} {back}");
        }
    }

    #[test]
    fn lattice_speed_tends_to_the_continuum_with_its_dx_squared_correction() {
        for &u in &[0.2, 0.5, 0.9] {
            let c0 = front_speed(u).unwrap();
            let dx = 1e-3;
            let c = lattice_closed_form(u, dx).unwrap();
            let predicted = -dx * dx * (1.0 - u * u) / (24.0 * u * u);
            assert!(((c / c0 - 1.0) / predicted - 1.0).abs() < 1e-3, "u = {u}");
        }
        assert!(lattice_front_speed(0.01, 1.0).is_err());
        // narrow pulses: re-sticking near the tip; the chain runs at 0.97527 and 1.01049
        for &(u, dx) in &[(0.1, 0.1), (0.2, 0.1), (0.3, 0.1), (0.3, 0.2), (0.15, 0.05)] {
            match lattice_front_speed(u, dx) {
                Err(Error::InvalidParameter { name, allowed, .. }) => {
                    assert_eq!(name, "u_plus");
                    assert!(allowed.contains("dx") && allowed.contains("chain"));
                }
                other => panic!("u = {u}, dx = {dx}: {other:?}"),
            }
        }
        assert!(lattice_front_speed(0.45, 0.1).is_ok() && lattice_front_speed(0.3, 0.025).is_ok());
        assert!(lattice_front_speed(0.5, 0.0).is_err());
    }

    #[test]
    fn resticking_decay_rate_solves_the_damped_dispersion_relation_and_its_limits() {
        for &(c, dx, gamma) in &[(1.03, 0.1, 0.1), (1.2, 0.2, 0.3), (2.0, 0.05, 0.45)] {
            let l = resticking_decay_rate(c, dx, gamma);
            let k = l * l + 2.0 * gamma * dx * l + dx * dx - 4.0 * (0.5 * l / c).sinh().powi(2);
            assert!(k.abs() < 1e-12 * l * l, "c {c}: K(lambda) = {k}");
            // damping makes the lattice carry the disturbance less far: lambda grows
            assert!(l > resticking_decay_rate(c, dx, 0.0));
        }
        // dx -> 0: the continuum rate lambda = 2 sinh(lambda T/2) of the tip solver
        for &c in &[1.01, 1.5, 10.0] {
            let l = resticking_decay_rate(c, 1e-9, 0.3);
            assert!(
                (l / crate::tip::slowest_decay_rate(c) - 1.0).abs() < 1e-7,
                "c {c}"
            );
        }
    }

    #[test]
    fn one_chain_domain_for_every_gamma() {
        // gamma = 0 reduces to the undamped exponent: small u_+, X ~ sqrt(12) pi u^2/dx
        let (u, dx) = (0.02, 1e-5);
        let x = resticking_exponent(u, lattice_closed_form(u, dx).unwrap(), dx, 0.0);
        assert!(
            (x / (12f64.sqrt() * PI * u * u / dx) - 1.0).abs() < 1e-3,
            "X = {x}"
        );
        // gamma > 0: the tip solver's speeds at (u_+, gamma, dx) = (0.3, 0.1, 0.2) (X = 5.5,
        // the chain runs 2.5e-4 faster) and (0.4, 0.1, 0.2) (X = 10.2, 2.8e-6) are refused,
        // (0.6, 0.3, 0.2) (X = 31.8) and the creep (0.45, 0.45, 0.2) are the chain's
        for &(u, gamma, c) in &[(0.3, 0.1, 1.009_806_684), (0.4, 0.1, 1.066_224_640)] {
            match check_lattice_front(u, c, 0.2, gamma) {
                Err(Error::InvalidParameter { name, allowed, .. }) => {
                    assert_eq!(name, "u_plus");
                    for word in ["dx", "gamma", "bk.chain.front(u_plus, gamma, dx)"] {
                        assert!(allowed.contains(word), "{allowed}");
                    }
                }
                other => panic!("u = {u}: {other:?}"),
            }
        }
        assert!(check_lattice_front(0.6, 1.215_247_386, 0.2, 0.3).is_ok());
        assert!(resticking_exponent(0.45, 1.051_382_740, 0.2, 0.45).is_infinite());
        assert!(check_lattice_front(0.45, 1.051_382_740, 0.2, 0.45).is_ok());
        assert!(check_lattice_front(0.45, 0.99, 0.2, 0.45).is_err());
    }

    #[test]
    fn rejects_bad_input() {
        for &u in &[0.0, 1.0, -0.1, 1.1, f64::NAN] {
            assert!(front_speed(u).is_err());
        }
        assert!(u_plus_of_speed(1.0).is_err());
        assert!(u_plus_of_speed(0.5).is_err());
        assert_eq!(critical_stress(0.3).unwrap(), Some(0.3));
        assert_eq!(critical_stress(1.2).unwrap(), None);
        assert!(critical_stress(-1.0).is_err());
    }
}
