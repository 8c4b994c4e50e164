//! bkwaves-core: engines for the Burridge-Knopoff chain with Coulomb friction
//! (C. B. Muratov, Phys. Rev. E 59, 3847 (1999)). Pure Rust, no Python.
//!
//! - [`speed`]: the front speed c(u_+) and the critical stress u_c(gamma);
//! - [`wave`]: the traveling wave behind the front (App. B);
//! - [`tip`]: the discrete tip problem (App. A) solved to machine precision;
//! - [`tip_march`]: the tip marched in time through blocks with their own thresholds;
//! - [`linalg`]: banded LU and Chebyshev kernels used by the solvers;
//! - [`noise`]: stress-dependent nucleation rate laws and the seeded generator;
//! - [`chain`]: the discrete chain simulated event by event, with [`friction`] laws
//!   and [`boundary`] conditions behind traits.

// Numerical kernels index several arrays with one loop variable; iterator chains
// would hide the stencil structure.
#![allow(clippy::needless_range_loop)]

pub mod boundary;
pub mod chain;
mod checkpoint_bytes;
pub mod error;
pub mod free_boundary;
pub mod free_boundary_2d;
pub mod friction;
pub mod lattice;
pub mod linalg;
pub mod noise;
pub mod params;
pub mod speed;
pub mod tip;
pub mod tip_march;
pub mod wave;

pub use error::{Error, Result};
