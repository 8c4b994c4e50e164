//! The grid of the two-dimensional free boundary engine: nodes (x0 + i h, y0 + j h),
//! i < nx, j < ny, stored row by row (k = j nx + i), each axis free or periodic.

use crate::error::{Error, Result};
use crate::free_boundary::Boundary;

/// Nodes, spacing and ends of each axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Nodes along x.
    pub nx: usize,
    /// Nodes along y.
    pub ny: usize,
    /// Spacing (the same along both axes: the continuum problem is isotropic).
    pub h: f64,
    /// Coordinates of node (0, 0).
    pub x0: f64,
    /// See `x0`.
    pub y0: f64,
    /// Ends along x.
    pub bx: Boundary,
    /// Ends along y.
    pub by: Boundary,
}

impl Grid {
    /// A grid, validated (each axis at least 3 nodes, h > 0, finite origin).
    pub fn new(
        nx: usize,
        ny: usize,
        h: f64,
        origin: (f64, f64),
        b: (Boundary, Boundary),
    ) -> Result<Self> {
        for (name, n) in [("nx", nx), ("ny", ny)] {
            if !(3..=(1 << 28)).contains(&n) {
                return Err(Error::InvalidParameter {
                    name,
                    value: n as f64,
                    allowed: "3 <= nodes per axis <= 2^28",
                });
            }
        }
        if nx.saturating_mul(ny) >= u32::MAX as usize {
            return Err(Error::InvalidParameter {
                name: "shape",
                value: (nx as f64) * (ny as f64),
                allowed: "nx ny < 2^32 nodes",
            });
        }
        crate::error::check_open("h", h, 0.0, f64::INFINITY, "grid spacing h > 0")?;
        crate::error::check_open(
            "x0",
            origin.0,
            f64::NEG_INFINITY,
            f64::INFINITY,
            "finite x0",
        )?;
        crate::error::check_open(
            "y0",
            origin.1,
            f64::NEG_INFINITY,
            f64::INFINITY,
            "finite y0",
        )?;
        Ok(Grid {
            nx,
            ny,
            h,
            x0: origin.0,
            y0: origin.1,
            bx: b.0,
            by: b.1,
        })
    }

    /// Number of nodes.
    #[inline]
    pub fn n(&self) -> usize {
        self.nx * self.ny
    }

    /// (i, j) of node k.
    #[inline]
    pub fn ij(&self, k: usize) -> (usize, usize) {
        (k % self.nx, k / self.nx)
    }

    /// Coordinates of node k.
    pub fn xy(&self, k: usize) -> (f64, f64) {
        let (i, j) = self.ij(k);
        (self.x0 + i as f64 * self.h, self.y0 + j as f64 * self.h)
    }

    /// The neighbour of node k one step along `axis` (0: x, 1: y) in direction `dir`
    /// (+1 or -1): wrapped on a periodic axis, None past a free end.
    #[inline]
    pub fn step(&self, k: usize, axis: usize, dir: i8) -> Option<usize> {
        let (i, j) = self.ij(k);
        let (p, n, b) = if axis == 0 {
            (i, self.nx, self.bx)
        } else {
            (j, self.ny, self.by)
        };
        let q = if dir > 0 {
            if p + 1 < n {
                p + 1
            } else if b == Boundary::Periodic {
                0
            } else {
                return None;
            }
        } else if p > 0 {
            p - 1
        } else if b == Boundary::Periodic {
            n - 1
        } else {
            return None;
        };
        Some(if axis == 0 {
            j * self.nx + q
        } else {
            q * self.nx + i
        })
    }

    /// Cells along x and y (a periodic axis has as many cells as nodes).
    pub fn cells(&self) -> (usize, usize) {
        let c = |n: usize, b: Boundary| if b == Boundary::Periodic { n } else { n - 1 };
        (c(self.nx, self.bx), c(self.ny, self.by))
    }

    /// Area of the domain (cells times h^2).
    pub fn area(&self) -> f64 {
        let (cx, cy) = self.cells();
        cx as f64 * cy as f64 * self.h * self.h
    }

    /// The node nearest to (x, y) (wrapped on periodic axes, clamped on free ones).
    pub fn nearest(&self, x: f64, y: f64) -> usize {
        let f = |z: f64, z0: f64, n: usize, b: Boundary| -> usize {
            let r = ((z - z0) / self.h).round();
            if b == Boundary::Periodic {
                (r.rem_euclid(n as f64) as usize).min(n - 1)
            } else {
                r.clamp(0.0, (n - 1) as f64) as usize
            }
        };
        f(y, self.y0, self.ny, self.by) * self.nx + f(x, self.x0, self.nx, self.bx)
    }

    /// Squared distance between nodes a and b (the shortest way round on periodic axes).
    pub fn dist2(&self, a: usize, b: usize) -> f64 {
        let (ia, ja) = self.ij(a);
        let (ib, jb) = self.ij(b);
        let d = |p: usize, q: usize, n: usize, bd: Boundary| -> f64 {
            let mut d = p.abs_diff(q);
            if bd == Boundary::Periodic {
                d = d.min(n - d);
            }
            d as f64
        };
        let dx = d(ia, ib, self.nx, self.bx);
        let dy = d(ja, jb, self.ny, self.by);
        (dx * dx + dy * dy) * self.h * self.h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_wrap_on_periodic_axes_and_stop_at_free_ends() {
        let g = Grid::new(4, 3, 0.5, (0.0, 0.0), (Boundary::Periodic, Boundary::Free)).unwrap();
        assert_eq!(g.step(0, 0, -1), Some(3));
        assert_eq!(g.step(3, 0, 1), Some(0));
        assert_eq!(g.step(0, 1, -1), None);
        assert_eq!(g.step(0, 1, 1), Some(4));
        assert_eq!(g.step(8, 1, 1), None);
        assert_eq!(g.cells(), (4, 2));
        assert!((g.area() - 2.0).abs() < 1e-15);
        assert_eq!(g.nearest(-0.2, 0.7), 4);
        assert_eq!(g.nearest(1.9, 0.1), 0);
        assert!((g.dist2(0, 3) - 0.25).abs() < 1e-15);
        assert!(Grid::new(2, 3, 0.5, (0.0, 0.0), (Boundary::Free, Boundary::Free)).is_err());
        assert!(Grid::new(3, 3, 0.0, (0.0, 0.0), (Boundary::Free, Boundary::Free)).is_err());
    }
}
