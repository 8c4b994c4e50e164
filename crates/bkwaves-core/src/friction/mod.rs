//! Friction laws of a sliding block: one file per law behind one trait, and one registry.
//!
//! In the dimensionless variables of the paper (eq. dimless; docs/chain.md for blocks that
//! differ) a sliding block obeys
//!
//! ```text
//!   m_i u_tt = -phi_i + R(s; theta_i),   s = v - u_t (speed over the ground),
//! ```
//!
//! where R = (f - f_s)/(f_r - f_s) is the friction force in excess of the kinetic value
//! f_s, in units of the reference drop f_r - f_s, and theta_i = (f_r,i - f_s)/(f_r - f_s)
//! is the block's static threshold (1 when all blocks are alike). A stuck block holds while
//! `lower(theta) < phi < upper(theta)`. A law says R on each sliding branch, its
//! thresholds, how its power splits, and declares its parameters in a table
//! ([`ParamSpec`]: name, range, default, doc) from which everything else is derived:
//! validation and messages, checkpoint fingerprints, output attributes, the Python
//! `bk.friction` module, the TOML `[friction]` table, the `bkwaves front` options and
//! the docs.
//!
//! Adding a law: one file implementing [`Friction`] and one line in [`LAWS`].

pub mod coulomb;
pub mod velocity_weakening;

pub use coulomb::Coulomb;
pub use velocity_weakening::VelocityWeakening;

use crate::chain::dynamic::{build_chain, ChainSpec, DynChain};
use crate::chain::front::{measure_front_with, FrontOptions, FrontResult};
use crate::error::{Error, Result};
use crate::params::{resolve, ParamSpec};

/// A friction law of a block sliding over the ground.
pub trait Friction: Clone + Send + Sync + std::fmt::Debug + 'static {
    /// Registry name (`coulomb`): the TOML `law`, the `--law` option, output attributes.
    const NAME: &'static str;
    /// One line saying what the law is.
    const DOC: &'static str;
    /// The parameter table, in the order of [`Friction::values`].
    const PARAMS: &'static [ParamSpec];
    /// The law from values in table order, each already inside its range (checks that
    /// involve several parameters go here).
    fn from_values(values: &[f64]) -> Result<Self>;
    /// Its parameter values in table order.
    fn values(&self) -> Vec<f64>;
    /// Excess friction R(s) on a block of static threshold `threshold` sliding in
    /// direction `dir` (+1 forward, -1 backward) at speed s = v - u_t over the ground.
    /// `dir` decides the branch also at s = 0, the instant of a slip.
    fn excess(&self, s: f64, dir: f64, threshold: f64) -> f64;
    /// A stuck block slips forward when phi >= upper.
    fn upper(&self, threshold: f64) -> f64 {
        threshold
    }
    /// A stuck block slips backward when phi <= lower (-inf: never).
    fn lower(&self, threshold: f64) -> f64;
    /// beta = f_s/(f_r - f_s) of the energy books: the loader-spring force of a block is
    /// (u + beta) in units of f_r - f_s. A law without backward slip returns 0 (the
    /// beta-free books): the beta terms then cancel exactly (../chain/energy.rs).
    fn beta(&self) -> f64;
    /// Dissipated power of one sliding block, split into (dry friction, viscous),
    /// in units of (f_r - f_s)^2 / sqrt(k_p m). Their sum is s * (R(s) + beta), the friction
    /// force f = f_s + (f_r - f_s) R times the speed.
    fn power(&self, s: f64, dir: f64, threshold: f64) -> (f64, f64);
    /// True when the dry part of [`Friction::power`] is 0 for every finite speed (Coulomb
    /// friction in the beta-free books): the integrator then skips booking it.
    fn dry_power_is_zero(&self) -> bool {
        false
    }
    /// A bound on |dR/ds| over both branches for thresholds up to `threshold_max`
    /// (the fastest rate the law adds to a sliding block: step-size checks).
    fn max_slope(&self, threshold_max: f64) -> f64;
    /// The law's own time scale for a unit mass (1/(growth rate at slip onset) of a
    /// weakening law): the chain's step is `step` times the smaller of dx and this times
    /// the smallest mass. Infinite (the default) for laws without one.
    fn time_scale(&self, _threshold_max: f64) -> f64 {
        f64::INFINITY
    }
    /// The law's weakening part at speed s over the ground on the branch `dir`: its size
    /// R_w and the speed scale sigma over which it varies (|dR_w/ds| = R_w/sigma; for
    /// velocity weakening R_w = theta v_f/(v_f + |s|), sigma = v_f + |s|). A sliding block
    /// whose R_w changes too fast for the chain's step (../chain/onset.rs) is integrated
    /// with its own short steps while the others keep the chain's step. (0, inf) (the
    /// default): a law without weakening.
    fn weakening(&self, _s: f64, _dir: f64, _threshold: f64) -> (f64, f64) {
        (0.0, f64::INFINITY)
    }
    /// The threshold a block uses in R while it slides, given that it slipped in direction
    /// `dir` at a located threshold crossing where its phi is `phi`. A law whose force at
    /// s = 0 equals the threshold (R(0) = upper, velocity weakening) returns the threshold
    /// that puts phi exactly on it when phi is a hair short (the crossing is located on
    /// the interpolated phi, the state's phi may differ by the location error): the block
    /// then starts with zero acceleration instead of sticking at once and slipping again
    /// at the same instant, for ever. The default (a law that ignores the threshold in R,
    /// Coulomb) returns `threshold`.
    fn onset_threshold(&self, threshold: f64, _phi: f64, _dir: f64) -> f64 {
        threshold
    }
}

/// Builds a chain with a law from its values (table order).
pub(crate) type BuildChain = fn(&[f64], ChainSpec<'_>) -> Result<Box<dyn DynChain>>;

/// A registry entry: a law's name, doc and parameter table, and the engines built
/// with it (monomorphised: the law's code is inlined in the integrator loops).
#[derive(Debug, Clone, Copy)]
pub struct Law {
    /// Registry name.
    pub name: &'static str,
    /// One line.
    pub doc: &'static str,
    /// The parameter table.
    pub params: &'static [ParamSpec],
    pub(crate) chain: BuildChain,
    pub(crate) front: fn(&[f64], &FrontOptions) -> Result<FrontResult>,
}

impl Law {
    /// The registry entry of law `F`.
    pub const fn of<F: Friction>() -> Law {
        Law {
            name: F::NAME,
            doc: F::DOC,
            params: F::PARAMS,
            chain: build_chain::<F>,
            front: measure_front_with::<F>,
        }
    }
}

impl PartialEq for Law {
    fn eq(&self, other: &Law) -> bool {
        self.name == other.name
    }
}

/// The registry of friction laws (the first is the default).
pub const LAWS: &[Law] = &[Law::of::<Coulomb>(), Law::of::<VelocityWeakening>()];

/// The default law's name.
pub const DEFAULT_LAW: &str = LAWS[0].name;

/// The law registered as `name`; an unknown name is an error listing the known ones.
pub fn law(name: &str) -> Result<&'static Law> {
    LAWS.iter()
        .find(|l| l.name == name)
        .ok_or_else(|| Error::Invalid {
            name: "friction law".to_string(),
            value: format!("{name:?}"),
            allowed: format!(
                "one of: {}",
                LAWS.iter().map(|l| l.name).collect::<Vec<_>>().join(", ")
            ),
        })
}

/// A law chosen by name with its parameter values (validated against its table, in
/// table order, defaults filled in).
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionSpec {
    /// The registry entry.
    pub law: &'static Law,
    /// Values in table order.
    pub values: Vec<f64>,
}

impl FrictionSpec {
    /// Law `name` with the given (parameter, value) pairs; errors name the unknown law,
    /// the unknown or missing parameter, or the value out of range.
    pub fn new(name: &str, given: &[(&str, f64)]) -> Result<FrictionSpec> {
        let law = law(name)?;
        let values = resolve(law.params, &format!("friction law {name}"), given)?;
        Ok(FrictionSpec { law, values })
    }

    /// The value of parameter `name`, if the law has it.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.law
            .params
            .iter()
            .position(|p| p.name == name)
            .map(|k| self.values[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registry_names_are_unique_and_tables_consistent() {
        for (k, l) in LAWS.iter().enumerate() {
            assert!(LAWS[..k].iter().all(|m| m.name != l.name), "{}", l.name);
            for p in l.params {
                if let Some(d) = p.default {
                    assert!(p.contains(d), "{}.{} default {d}", l.name, p.name);
                }
            }
        }
        assert_eq!(DEFAULT_LAW, "coulomb");
    }

    #[test]
    fn unknown_names_list_the_known_ones() {
        let e = FrictionSpec::new("colomb", &[]).unwrap_err().to_string();
        assert!(
            e.contains("\"colomb\"") && e.contains("one of: coulomb, velocity_weakening"),
            "{e}"
        );
        let e = FrictionSpec::new("coulomb", &[("gamma", 0.1), ("v_f", 1.0)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("\"v_f\"") && e.contains("gamma, beta"), "{e}");
        let s = FrictionSpec::new("coulomb", &[("gamma", 0.3)]).unwrap();
        assert_eq!(s.get("gamma"), Some(0.3));
        assert_eq!(s.get("v_f"), None);
    }
}
