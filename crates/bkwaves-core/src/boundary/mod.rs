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

/// Builds a boundary from the ghost values of walls at t = 0.
pub type BuildBoundary = fn((f64, f64)) -> Result<Box<dyn Boundary>>;

/// A registry entry: a boundary condition by name.
#[derive(Debug, Clone, Copy)]
pub struct BoundaryEntry {
    /// Registry name (`boundary = "..."`).
    pub name: &'static str,
    /// One line.
    pub doc: &'static str,
    /// Build it; `held` gives the ghost values of walls at t = 0.
    pub build: BuildBoundary,
}

/// The registry of boundary conditions (the first is the default).
pub const BOUNDARIES: &[BoundaryEntry] = &[
    BoundaryEntry {
        name: "free",
        doc: "no spring beyond the end blocks",
        build: |_| Ok(Box::new(Free)),
    },
    BoundaryEntry {
        name: "fixed",
        doc: "the end blocks are joined by a coupling spring to walls fixed to the ground",
        build: |held| Ok(Box::new(Fixed::new(held.0, held.1)?)),
    },
    BoundaryEntry {
        name: "periodic",
        doc: "a ring: block n - 1 and block 0 are neighbours",
        build: |_| Ok(Box::new(Periodic)),
    },
];

/// A boundary by name; an unknown name is an error listing the known ones. `held`
/// gives the ghost values of fixed ends.
pub fn by_name(name: &str, held: (f64, f64)) -> Result<Box<dyn Boundary>> {
    match BOUNDARIES.iter().find(|b| b.name == name) {
        Some(b) => (b.build)(held),
        None => Err(Error::Invalid {
            name: "boundary".to_string(),
            value: format!("{name:?}"),
            allowed: format!(
                "one of: {}",
                BOUNDARIES
                    .iter()
                    .map(|b| b.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
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
        assert!(
            e.contains("\"open\"") && e.contains("one of: free, fixed, periodic"),
            "{e}"
        );
        assert_eq!(Periodic.left(), Ghost::Wrap);
        assert_eq!(Free.right(), Ghost::Mirror);
        assert_eq!(Fixed::new(0.1, 0.2).unwrap().right(), Ghost::Held(0.2));
    }
}
