//! The slow field u(x, t) on the grid of the free boundary problem.
//!
//! Nodes x_k = x_0 + k h carry b_k with u(x_k, t) = b_k + v (t - epoch) (eq. rest: a stuck
//! region loads at rate v). When a shock passes node k at time t_p with u_+ = b_k +
//! v (t_p - epoch), b_k is reset so that u jumps to u_-(u_+) (eqs. slow, um); the value
//! before the reset is kept in `prev[k]` together with the id of the shock that reset it.
//! `prev` is what makes the field seen by a shock a smooth function on *both* sides of the
//! shock: behind a shock the field it saw continues as `prev`, so the interpolant used to
//! move a shock through a cell is centred on the cell instead of extrapolated.
//!
//! Between nodes the field is a cubic through up to four contiguous nodes (local
//! polynomial interpolation, error O(h^4) in u, O(h^2) in the curvature), chosen on the
//! same side of every shock as the point where it is evaluated.
//!
//! `epoch` is moved forward from time to time (`rebase`) so that b and v (t - epoch) stay
//! of order one and no digits are lost on long runs.

/// No shock (node never reset).
pub(crate) const NONE: usize = usize::MAX;

/// A polynomial of degree <= 3 in the cell coordinate s = (x - x_j)/h.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellPoly {
    /// Monomial coefficients in s: p(s) = c[0] + c[1] s + c[2] s^2 + c[3] s^3.
    pub c: [f64; 4],
    /// Number of nodes the interpolant was built from (1..=4): its order.
    pub points: usize,
}

impl CellPoly {
    /// Interpolant through values `vals` at the integer offsets o0, o0 + 1, ... (in s).
    pub fn through(o0: i32, vals: &[f64]) -> CellPoly {
        let m = vals.len();
        debug_assert!((1..=4).contains(&m));
        // Newton divided differences on nodes z_i = o0 + i (unit spacing).
        let mut d = [0.0f64; 4];
        d[..m].copy_from_slice(vals);
        for k in 1..m {
            for i in (k..m).rev() {
                d[i] = (d[i] - d[i - 1]) / k as f64;
            }
        }
        // Expand p(s) = d0 + d1 (s - z0) + d2 (s - z0)(s - z1) + d3 (s - z0)(s - z1)(s - z2).
        let mut c = [0.0f64; 4];
        let mut basis = [1.0f64, 0.0, 0.0, 0.0];
        for k in 0..m {
            for i in 0..4 {
                c[i] += d[k] * basis[i];
            }
            // basis *= (s - z_k)
            let z = (o0 + k as i32) as f64;
            let mut nb = [0.0f64; 4];
            for i in 0..4 {
                if i + 1 < 4 {
                    nb[i + 1] += basis[i];
                }
                nb[i] -= z * basis[i];
            }
            basis = nb;
        }
        CellPoly { c, points: m }
    }

    /// p(s).
    #[inline]
    pub fn eval(&self, s: f64) -> f64 {
        self.c[0] + s * (self.c[1] + s * (self.c[2] + s * self.c[3]))
    }

    /// dp/ds.
    #[inline]
    pub fn deriv(&self, s: f64) -> f64 {
        self.c[1] + s * (2.0 * self.c[2] + s * 3.0 * self.c[3])
    }

    /// d2p/ds2.
    #[inline]
    pub fn deriv2(&self, s: f64) -> f64 {
        2.0 * self.c[2] + 6.0 * self.c[3] * s
    }

    /// Maximum of p on [0, 1]: (value, s at the maximum).
    pub fn max_on_unit(&self) -> (f64, f64) {
        let mut best = (self.eval(0.0), 0.0);
        let mut consider = |s: f64| {
            if (0.0..=1.0).contains(&s) {
                let p = self.eval(s);
                if p > best.0 {
                    best = (p, s);
                }
            }
        };
        consider(1.0);
        // p'(s) = c1 + 2 c2 s + 3 c3 s^2 = 0
        let (a, b, c) = (3.0 * self.c[3], 2.0 * self.c[2], self.c[1]);
        if a.abs() > 1e-14 * (b.abs() + c.abs()) {
            let disc = b * b - 4.0 * a * c;
            if disc >= 0.0 {
                let q = -0.5 * (b + b.signum() * disc.sqrt());
                if q != 0.0 {
                    consider(q / a);
                    consider(c / q);
                } else {
                    consider(0.0);
                }
            }
        } else if b != 0.0 {
            consider(-c / b);
        }
        best
    }
}

/// The grid and its nodal values.
#[derive(Debug, Clone)]
pub struct Field {
    /// Position of node 0.
    pub x0: f64,
    /// Grid spacing.
    pub h: f64,
    /// Number of nodes.
    pub n: usize,
    /// Periodic (ring of length n h) or free ends (segment of length (n - 1) h).
    pub periodic: bool,
    /// Loading rate v.
    pub v: f64,
    /// u(x_k, t) = b_k + v (t - epoch).
    pub b: Vec<f64>,
    /// b_k before its last reset (same epoch).
    pub prev: Vec<f64>,
    /// Id of the shock that last reset node k ([`NONE`] if never).
    pub reset_by: Vec<usize>,
    /// Time origin of b.
    pub epoch: f64,
}

impl Field {
    /// A field with u(x_k, 0) = u0[k].
    pub fn new(x0: f64, h: f64, u0: &[f64], periodic: bool, v: f64) -> Field {
        Field {
            x0,
            h,
            n: u0.len(),
            periodic,
            v,
            b: u0.to_vec(),
            prev: u0.to_vec(),
            reset_by: vec![NONE; u0.len()],
            epoch: 0.0,
        }
    }

    /// Number of cells (n on a ring, n - 1 on a segment).
    pub fn n_cells(&self) -> usize {
        if self.periodic {
            self.n
        } else {
            self.n - 1
        }
    }

    /// Length of the domain.
    pub fn length(&self) -> f64 {
        self.h * self.n_cells() as f64
    }

    /// Position of node k (k < n).
    pub fn node_x(&self, k: usize) -> f64 {
        self.x0 + k as f64 * self.h
    }

    /// Index of the node at offset `o` from node j: wrapped on a ring, None off a segment.
    pub fn node_at(&self, j: usize, o: i64) -> Option<usize> {
        let k = j as i64 + o;
        if self.periodic {
            Some(k.rem_euclid(self.n as i64) as usize)
        } else if k >= 0 && k < self.n as i64 {
            Some(k as usize)
        } else {
            None
        }
    }

    /// u at node k at time t (t must be the engine's current time or later, before the
    /// next shock reaches the node).
    #[inline]
    pub fn u_node(&self, k: usize, t: f64) -> f64 {
        self.b[k] + self.v * (t - self.epoch)
    }

    /// Move the time origin to t (b and prev shift by v (t - epoch)).
    pub fn rebase(&mut self, t: f64) {
        let d = self.v * (t - self.epoch);
        for x in self.b.iter_mut() {
            *x += d;
        }
        for x in self.prev.iter_mut() {
            *x += d;
        }
        self.epoch = t;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_reproduces_cubics_and_finds_the_maximum() {
        let f = |s: f64| 0.3 - 0.7 * (s - 0.4) * (s - 0.4) + 0.05 * s * s * s;
        for o0 in -2..=1 {
            let vals: Vec<f64> = (0..4).map(|i| f((o0 + i) as f64)).collect();
            let p = CellPoly::through(o0, &vals);
            for &s in &[0.0, 0.3, 0.77, 1.0] {
                assert!((p.eval(s) - f(s)).abs() < 1e-13);
            }
        }
        let vals: Vec<f64> = (0..4).map(|i| f((i - 1) as f64)).collect();
        let p = CellPoly::through(-1, &vals);
        let (m, s) = p.max_on_unit();
        // f' = -1.4 (s - 0.4) + 0.15 s^2 = 0
        let s_exact = (1.4 - (1.96f64 - 4.0 * 0.15 * 0.56).sqrt()) / 0.3;
        assert!((s - s_exact).abs() < 1e-12, "{s} {s_exact}");
        assert!((m - f(s_exact)).abs() < 1e-14);
        // lower orders
        let p = CellPoly::through(0, &[1.0, 3.0]);
        assert_eq!(p.points, 2);
        assert!((p.eval(0.5) - 2.0).abs() < 1e-15);
        assert_eq!(p.max_on_unit(), (3.0, 1.0));
        let p = CellPoly::through(1, &[2.0]);
        assert_eq!(p.eval(0.3), 2.0);
    }

    #[test]
    fn rebase_keeps_u() {
        let mut f = Field::new(0.0, 0.5, &[0.1, 0.2, 0.3], false, 0.01);
        let before = f.u_node(2, 37.0);
        f.rebase(30.0);
        assert!((f.u_node(2, 37.0) - before).abs() < 1e-15);
        assert_eq!(f.n_cells(), 2);
        assert_eq!(f.node_at(0, -1), None);
        let g = Field::new(0.0, 0.5, &[0.1, 0.2, 0.3], true, 0.01);
        assert_eq!(g.node_at(0, -1), Some(2));
        assert_eq!(g.length(), 1.5);
    }
}
