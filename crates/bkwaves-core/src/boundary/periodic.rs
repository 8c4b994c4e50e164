//! Periodic ring: block n - 1 and block 0 are neighbours.

use super::{Boundary, Ghost};

/// Periodic ring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Periodic;

impl Boundary for Periodic {
    fn name(&self) -> &'static str {
        "periodic"
    }
    fn left(&self) -> Ghost {
        Ghost::Wrap
    }
    fn right(&self) -> Ghost {
        Ghost::Wrap
    }
}
