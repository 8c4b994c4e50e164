//! Boundary conditions at the ends of a finite chain, behind one trait.
//!
//! The engine pads the chain with one ghost neighbour at each end; a boundary says what
//! the ghost is (see [`Ghost`]). The three conditions are one file each.

pub mod fixed;
pub mod free;
pub mod periodic;

pub use fixed::Fixed;
pub use free::Free;
pub use periodic::Periodic;

use crate::error::{Error, Result};

/// What the ghost neighbour beyond an end of the chain is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ghost {
    /// A copy of the end block itself: no spring beyond the end (free end).
    Mirror,
    /// A wall attached to the ground: a block that never slips, u = u0 + v t
    /// (fixed end; `u0` is its value at t = 0).
    Held(f64),
    /// The block at the other end (periodic ring).
    Wrap,
}

/// A boundary condition: the ghost neighbours beyond the left and right ends.
pub trait Boundary: Send + Sync + std::fmt::Debug {
    /// Short name used in outputs (`free`, `fixed`, `periodic`).
    fn name(&self) -> &'static str;
    /// Ghost beyond block 0.
    fn left(&self) -> Ghost;
    /// Ghost beyond block n - 1.
    fn right(&self) -> Ghost;
}

/// The registry: a boundary by name. `held` gives the ghost values of fixed ends.
pub fn by_name(name: &str, held: (f64, f64)) -> Result<Box<dyn Boundary>> {
    match name {
        "free" => Ok(Box::new(Free)),
        "fixed" => Ok(Box::new(Fixed::new(held.0, held.1)?)),
        "periodic" => Ok(Box::new(Periodic)),
        _ => Err(Error::InvalidParameter {
            name: "boundary",
            value: f64::NAN,
            allowed: "one of free, fixed, periodic",
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registry_knows_every_boundary() {
        for name in ["free", "fixed", "periodic"] {
            assert_eq!(by_name(name, (0.0, 0.0)).unwrap().name(), name);
        }
        let e = by_name("open", (0.0, 0.0)).unwrap_err().to_string();
        assert!(e.contains("free, fixed, periodic"), "{e}");
        assert_eq!(Periodic.left(), Ghost::Wrap);
        assert_eq!(Free.right(), Ghost::Mirror);
        assert_eq!(Fixed::new(0.1, 0.2).unwrap().right(), Ghost::Held(0.2));
    }
}
