//! Fixed ends: the end block is joined by a coupling spring k_c to a wall attached to
//! the ground. In the loader frame the wall drifts like a stuck block, so its ghost
//! value is u = u0 + v t (u0 = the ghost's u at t = 0; X_wall = -(f_s + (f_r - f_s) u0)/k_p
//! at t = 0). Being fixed to the ground the wall does no work.

use super::{Boundary, Ghost};
use crate::error::{Error, Result};

/// Fixed ends with ghost values `left`, `right` at t = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fixed {
    /// Ghost u beyond block 0 at t = 0.
    pub left: f64,
    /// Ghost u beyond block n - 1 at t = 0.
    pub right: f64,
}

impl Fixed {
    /// Validated constructor (finite values).
    pub fn new(left: f64, right: f64) -> Result<Self> {
        for (name, value) in [("fixed_left", left), ("fixed_right", right)] {
            if !value.is_finite() {
                return Err(Error::InvalidParameter {
                    name,
                    value,
                    allowed: "a finite number",
                });
            }
        }
        Ok(Fixed { left, right })
    }
}

impl Boundary for Fixed {
    fn name(&self) -> &'static str {
        "fixed"
    }
    fn left(&self) -> Ghost {
        Ghost::Held(self.left)
    }
    fn right(&self) -> Ghost {
        Ghost::Held(self.right)
    }
}
