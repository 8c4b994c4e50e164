//! Free ends: no spring beyond the end block, Lap_0 = u_1 - u_0.

use super::{Boundary, Ghost};

/// Free ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Free;

impl Boundary for Free {
    fn name(&self) -> &'static str {
        "free"
    }
    fn left(&self) -> Ghost {
        Ghost::Mirror
    }
    fn right(&self) -> Ghost {
        Ghost::Mirror
    }
}
