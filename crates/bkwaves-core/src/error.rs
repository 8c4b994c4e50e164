//! Errors of the core: every failure a user can provoke is a value, never a panic.

use std::fmt;

/// What went wrong in a core computation.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A parameter is outside its allowed range (or not finite).
    InvalidParameter {
        /// The parameter's user-facing name, e.g. `u_plus`.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// The allowed range in words, e.g. `0 < u_plus < 1`.
        allowed: &'static str,
    },
    /// A parameter is invalid, described by names built at run time: a per-block value
    /// (`threshold[17]`), a key of a parameter table, an unknown name of a registry.
    Invalid {
        /// What the user gave, e.g. `threshold[17]` or `friction law`.
        name: String,
        /// The offending value as text (a number or a quoted name).
        value: String,
        /// What is allowed, e.g. `one of: coulomb, velocity_weakening`.
        allowed: String,
    },
    /// A numerical method did not reach its tolerance.
    NoConvergence {
        /// What was being computed.
        what: &'static str,
        /// Details (iterations, residual).
        detail: String,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidParameter {
                name,
                value,
                allowed,
            } => write!(f, "invalid {name} = {value}: allowed {allowed}"),
            Error::Invalid {
                name,
                value,
                allowed,
            } => write!(f, "invalid {name} = {value}: allowed {allowed}"),
            Error::NoConvergence { what, detail } => {
                write!(f, "{what} did not converge: {detail}")
            }
        }
    }
}

impl std::error::Error for Error {}

/// Result type of the core.
pub type Result<T> = std::result::Result<T, Error>;

/// Check `lo < value < hi` (open interval) and finiteness.
pub fn check_open(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    allowed: &'static str,
) -> Result<f64> {
    if value.is_finite() && value > lo && value < hi {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            allowed,
        })
    }
}

/// Check `value >= lo` and finiteness.
pub fn check_at_least(
    name: &'static str,
    value: f64,
    lo: f64,
    allowed: &'static str,
) -> Result<f64> {
    if value.is_finite() && value >= lo {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            allowed,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_parameter_value_and_range() {
        let e = check_open("u_plus", 1.5, 0.0, 1.0, "0 < u_plus < 1").unwrap_err();
        let s = e.to_string();
        assert!(
            s.contains("u_plus") && s.contains("1.5") && s.contains("0 < u_plus < 1"),
            "{s}"
        );
        assert!(check_open("u_plus", f64::NAN, 0.0, 1.0, "").is_err());
        assert!(check_at_least("gamma", -0.1, 0.0, "gamma >= 0").is_err());
        assert!(check_at_least("gamma", f64::INFINITY, 0.0, "gamma >= 0").is_err());
        assert_eq!(check_at_least("gamma", 0.0, 0.0, "gamma >= 0"), Ok(0.0));
    }
}
