//! Friction laws of a sliding block, behind one trait.
//!
//! In the dimensionless variables of the paper (eq. dimless) a sliding block obeys
//!
//! ```text
//!   u_tt = -phi + R(s),   phi = u - Lap u / dx^2,   s = v - u_t,
//! ```
//!
//! where s is the block's speed over the ground (s > 0: forward, the direction of the
//! loader) and R(s) = (f(s) - f_s)/(f_r - f_s) is the friction force in excess of the
//! kinetic value f_s, in units of f_r - f_s. A stuck block holds while
//! `lower() < phi < upper()`. A law only has to say R(s) on each sliding branch, its
//! thresholds and how its power splits; velocity-weakening laws fit the same trait.

pub mod coulomb;

pub use coulomb::Coulomb;

/// A friction law of a block sliding over the ground.
pub trait Friction: Clone + Send + Sync + std::fmt::Debug {
    /// Short name used in outputs (e.g. `coulomb`).
    fn name(&self) -> &'static str;
    /// Excess friction R(s) on a block sliding in direction `dir` (+1 forward, -1
    /// backward) at speed s = v - u_t over the ground. `dir` decides the branch also
    /// at s = 0, the instant of a slip.
    fn excess(&self, s: f64, dir: f64) -> f64;
    /// A stuck block slips forward when phi >= upper.
    fn upper(&self) -> f64;
    /// A stuck block slips backward when phi <= lower.
    fn lower(&self) -> f64;
    /// beta = f_s/(f_r - f_s) of the energy books: the loader-spring force of a block is
    /// (u + beta) in units of f_r - f_s. A law without backward slip returns 0 (the
    /// beta-free books): the beta terms then cancel exactly (../chain/energy.rs).
    fn beta(&self) -> f64;
    /// Dissipated power of one sliding block, split into (dry friction, viscous),
    /// in units of (f_r - f_s)^2 / sqrt(k_p m). Their sum is s * (R(s) + beta), the friction
    /// force f = f_s + (f_r - f_s) R times the speed.
    fn power(&self, s: f64, dir: f64) -> (f64, f64);
}
