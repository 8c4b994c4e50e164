//! Where and when the next pair is born: the maximum of the field over the grid.
//!
//! Away from shocks u = b(x) + v t grows uniformly, so the next birth is at the maximum M
//! of b (the interpolant, located between grid points) at t = epoch + (1 - M)/v. Each cell
//! keeps the maximum of its interpolant on [x_j, x_{j+1}] (cells touching a shock are
//! excluded: the field there is discontinuous and the shock sweeps it anyway); a
//! segment tree gives the global maximum in O(1) and is updated in O(log n) when a node
//! is reset, so births cost nothing between events.

/// The maximum of the interpolant in one cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellMax {
    /// Maximum of b in the cell (-inf when the cell is excluded).
    pub value: f64,
    /// Cell coordinate s in [0, 1] of the maximum.
    pub s: f64,
    /// Curvature a = -b''/2 there (per unit x^2).
    pub a: f64,
}

impl CellMax {
    /// An excluded cell.
    pub const NONE: CellMax = CellMax {
        value: f64::NEG_INFINITY,
        s: 0.0,
        a: f64::NAN,
    };
}

/// Max segment tree over cells.
#[derive(Debug, Clone)]
pub struct MaxTree {
    size: usize,
    val: Vec<f64>,
    arg: Vec<usize>,
}

impl MaxTree {
    /// A tree over n leaves, all -inf.
    pub fn new(n: usize) -> Self {
        let size = n.max(1).next_power_of_two();
        MaxTree {
            size,
            val: vec![f64::NEG_INFINITY; 2 * size],
            arg: (0..2 * size).map(|i| i.saturating_sub(size)).collect(),
        }
    }

    /// Set leaf i.
    pub fn set(&mut self, i: usize, v: f64) {
        let mut p = i + self.size;
        self.val[p] = v;
        p /= 2;
        while p >= 1 {
            let (l, r) = (2 * p, 2 * p + 1);
            let (v, a) = if self.val[r] > self.val[l] {
                (self.val[r], self.arg[r])
            } else {
                (self.val[l], self.arg[l])
            };
            self.val[p] = v;
            self.arg[p] = a;
            p /= 2;
        }
    }

    /// (maximum, leaf).
    pub fn max(&self) -> (f64, usize) {
        (self.val[1], self.arg[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tree_tracks_the_maximum() {
        let mut t = MaxTree::new(5);
        assert_eq!(t.max().0, f64::NEG_INFINITY);
        for (i, v) in [0.3, -1.0, 0.7, 0.1, 0.2].iter().enumerate() {
            t.set(i, *v);
        }
        assert_eq!(t.max(), (0.7, 2));
        t.set(2, 0.0);
        assert_eq!(t.max(), (0.3, 0));
        t.set(4, 2.0);
        assert_eq!(t.max(), (2.0, 4));
    }
}
