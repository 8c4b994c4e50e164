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
/// Returns an error when dx sqrt(1 - u_+^2) > 2 u_+ (no steady front of this kind: the
/// continuum description fails for u_+ of order dx, as the paper notes).
pub fn lattice_front_speed(u_plus: f64, dx: f64) -> Result<f64> {
    let u = check_open("u_plus", u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
    let dx = check_open("dx", dx, 0.0, f64::INFINITY, "dx > 0")?;
    let arg = dx * ((1.0 - u) * (1.0 + u)).sqrt() / (2.0 * u);
    if arg > 1.0 {
        return Err(Error::InvalidParameter {
            name: "u_plus",
            value: u,
            allowed: "dx sqrt(1 - u_plus^2) <= 2 u_plus (a steady lattice front exists)",
        });
    }
    Ok(dx / (2.0 * u * arg.asin()))
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
            let c = lattice_front_speed(u, dx).unwrap();
            let predicted = -dx * dx * (1.0 - u * u) / (24.0 * u * u);
            assert!(((c / c0 - 1.0) / predicted - 1.0).abs() < 1e-3, "u = {u}");
        }
        assert!(lattice_front_speed(0.01, 1.0).is_err());
        assert!(lattice_front_speed(0.5, 0.0).is_err());
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
