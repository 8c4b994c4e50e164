//! Parameter tables: what a friction law (or any registered component) declares about each
//! of its parameters, once. Validation, error messages, checkpoint fingerprints, output
//! attributes, the Python package, the TOML loader and the docs all read these tables.

use crate::error::{Error, Result};

/// One parameter of a registered component: name, allowed range, default and doc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamSpec {
    /// The user-facing name (the TOML key, the Python keyword, the `--option` stem).
    pub name: &'static str,
    /// Lower end of the allowed range (may be -inf).
    pub lo: f64,
    /// Is the lower end itself allowed?
    pub lo_closed: bool,
    /// Upper end of the allowed range (may be +inf: then `hi_closed` says whether +inf
    /// itself is a value, e.g. beta = inf for "no backward slip").
    pub hi: f64,
    /// Is the upper end itself allowed?
    pub hi_closed: bool,
    /// Default value; None: the parameter is required.
    pub default: Option<f64>,
    /// What the parameter is, in one line.
    pub doc: &'static str,
}

impl ParamSpec {
    /// Does `x` lie in the allowed range (NaN never does)?
    pub fn contains(&self, x: f64) -> bool {
        let above = x > self.lo || (self.lo_closed && x == self.lo);
        let below = x < self.hi || (self.hi_closed && x == self.hi);
        above && below
    }

    /// A value inside the allowed range (a stand-in for a parameter not given yet).
    pub fn inside(&self) -> f64 {
        let x = if self.lo.is_finite() && self.hi.is_finite() {
            0.5 * (self.lo + self.hi)
        } else if self.lo.is_finite() {
            self.lo + 1.0
        } else if self.hi.is_finite() {
            self.hi - 1.0
        } else {
            0.0
        };
        if self.contains(self.lo) {
            self.lo
        } else {
            x
        }
    }

    /// The allowed range in words, e.g. `0 <= gamma < inf` or `0 < v_f <= inf`.
    pub fn allowed(&self) -> String {
        let num = |x: f64| {
            if x == f64::INFINITY {
                "inf".to_string()
            } else if x == f64::NEG_INFINITY {
                "-inf".to_string()
            } else {
                format!("{x}")
            }
        };
        format!(
            "{} {} {} {} {}",
            num(self.lo),
            if self.lo_closed { "<=" } else { "<" },
            self.name,
            if self.hi_closed { "<=" } else { "<" },
            num(self.hi)
        )
    }

    /// `x` if it is allowed, else an error naming `label` (the key the user wrote, e.g.
    /// `friction.v_f`), the value and the range.
    pub fn check(&self, label: &str, x: f64) -> Result<f64> {
        if self.contains(x) {
            Ok(x)
        } else {
            Err(Error::Invalid {
                name: label.to_string(),
                value: format!("{x}"),
                allowed: self.allowed(),
            })
        }
    }
}

/// Values for a table from (name, value) pairs: every name must be in the table, every
/// required parameter given, every value in range; defaults fill the rest. `what` names
/// the component in messages (e.g. `friction law coulomb`). Values come back in table order.
pub fn resolve(table: &[ParamSpec], what: &str, given: &[(&str, f64)]) -> Result<Vec<f64>> {
    let names = || table.iter().map(|p| p.name).collect::<Vec<_>>().join(", ");
    for (k, (name, _)) in given.iter().enumerate() {
        if !table.iter().any(|p| p.name == *name) {
            return Err(Error::Invalid {
                name: format!("{what} parameter"),
                value: format!("{name:?}"),
                allowed: format!("one of: {}", names()),
            });
        }
        if given[..k].iter().any(|(n, _)| n == name) {
            return Err(Error::Invalid {
                name: format!("{what} parameter"),
                value: format!("{name:?}"),
                allowed: "each parameter given once".to_string(),
            });
        }
    }
    table
        .iter()
        .map(|p| match given.iter().find(|(n, _)| *n == p.name) {
            Some(&(_, x)) => p.check(p.name, x),
            None => p.default.ok_or_else(|| Error::Invalid {
                name: p.name.to_string(),
                value: "missing".to_string(),
                allowed: format!("a value ({} is required by the {what})", p.name),
            }),
        })
        .collect()
}

/// Check (name, value) pairs against a table without requiring the rest: unknown names
/// and values out of range are errors (a law's parameters given in parts).
pub fn check_given(table: &[ParamSpec], what: &str, given: &[(&str, f64)]) -> Result<()> {
    let mut full: Vec<(&str, f64)> = given.to_vec();
    for p in table {
        if !given.iter().any(|(n, _)| *n == p.name) {
            // a stand-in inside the range (a required v_f > 0 is not 0)
            full.push((p.name, p.default.unwrap_or_else(|| p.inside())));
        }
    }
    resolve(table, what, &full).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TABLE: &[ParamSpec] = &[
        ParamSpec {
            name: "gamma",
            lo: 0.0,
            lo_closed: true,
            hi: f64::INFINITY,
            hi_closed: false,
            default: None,
            doc: "damping",
        },
        ParamSpec {
            name: "beta",
            lo: 0.0,
            lo_closed: true,
            hi: f64::INFINITY,
            hi_closed: true,
            default: Some(f64::INFINITY),
            doc: "backward threshold",
        },
    ];

    #[test]
    fn ranges_defaults_and_messages() {
        assert_eq!(
            resolve(TABLE, "law x", &[("gamma", 0.3)]).unwrap(),
            vec![0.3, f64::INFINITY]
        );
        assert_eq!(
            resolve(TABLE, "law x", &[("beta", 2.0), ("gamma", 0.0)]).unwrap(),
            vec![0.0, 2.0]
        );
        // +inf is a value of beta (closed end), not of gamma (open end)
        let e = resolve(TABLE, "law x", &[("gamma", f64::INFINITY)]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid gamma = inf: allowed 0 <= gamma < inf"
        );
        for bad in [-0.1, f64::NAN] {
            assert!(resolve(TABLE, "law x", &[("gamma", 0.1), ("beta", bad)]).is_err());
        }
        let e = resolve(TABLE, "law x", &[("gama", 0.1)])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("\"gama\"") && e.contains("one of: gamma, beta"),
            "{e}"
        );
        let e = resolve(TABLE, "law x", &[]).unwrap_err().to_string();
        assert!(e.contains("gamma is required by the law x"), "{e}");
        let e = resolve(TABLE, "law x", &[("gamma", 0.1), ("gamma", 0.2)]).unwrap_err();
        assert!(e.to_string().contains("once"), "{e}");
        // in parts: the required gamma may be missing, a bad value may not
        assert!(check_given(TABLE, "law x", &[("beta", 1.0)]).is_ok());
        assert!(check_given(TABLE, "law x", &[("beta", -1.0)]).is_err());
        assert!(check_given(TABLE, "law x", &[("v_f", 1.0)]).is_err());
        // a required parameter with an open range (v_f > 0) not given yet is no error
        let v_f = ParamSpec {
            name: "v_f",
            lo: 0.0,
            lo_closed: false,
            hi: f64::INFINITY,
            hi_closed: false,
            default: None,
            doc: "",
        };
        assert!(check_given(&[v_f], "law y", &[]).is_ok());
        assert!(v_f.contains(v_f.inside()));
        assert!(check_given(&[v_f], "law y", &[("v_f", 0.0)]).is_err());
    }
}
