//! Small dense numerical kernels: a banded LU solver with partial pivoting and
//! Chebyshev-Gauss-Lobatto differentiation matrices. No external dependencies.

use crate::error::{Error, Result};

/// A square band matrix with `kl` sub- and `ku` super-diagonals, stored by columns
/// with `kl` extra super-diagonals for the fill-in of partial pivoting
/// (the layout of LAPACK's `dgbtrf`).
#[derive(Debug, Clone)]
pub struct BandMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    ld: usize,
    data: Vec<f64>,
}

impl BandMatrix {
    /// An all-zero n x n band matrix.
    pub fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        let ld = 2 * kl + ku + 1;
        BandMatrix {
            n,
            kl,
            ku,
            ld,
            data: vec![0.0; ld * n],
        }
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        // row i, column j, valid for j - (kl + ku) <= i <= j + kl
        j * self.ld + (self.kl + self.ku + i) - j
    }

    /// Add `value` to entry (i, j); the entry must lie inside the band.
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        assert!(
            i < self.n && j < self.n && i + self.ku >= j && j + self.kl >= i,
            "entry ({i}, {j}) outside the band (kl = {}, ku = {})",
            self.kl,
            self.ku
        );
        let k = self.idx(i, j);
        self.data[k] += value;
    }

    /// y = b - A x with error-free products and compensated sums (about twice the
    /// working precision), for iterative refinement.
    pub fn residual(&self, x: &[f64], b: &[f64]) -> Vec<f64> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let mut hi = b.to_vec();
        let mut lo = vec![0.0; n];
        for j in 0..n {
            let xj = x[j];
            if xj == 0.0 {
                continue;
            }
            let i0 = j.saturating_sub(ku);
            let i1 = (j + kl).min(n - 1);
            for i in i0..=i1 {
                let a = self.data[self.idx(i, j)];
                if a == 0.0 {
                    continue;
                }
                let p = -a * xj;
                let pe = (-a).mul_add(xj, -p);
                let s = hi[i] + p;
                let bb = s - hi[i];
                let se = (hi[i] - (s - bb)) + (p - bb);
                hi[i] = s;
                lo[i] += se + pe;
            }
        }
        hi.iter().zip(&lo).map(|(h, l)| h + l).collect()
    }

    /// Solve A x = b (b becomes x) by LU followed by `steps` rounds of iterative
    /// refinement with residuals in extended precision.
    pub fn solve_refined(self, b: &mut [f64], steps: usize) -> Result<()> {
        if steps == 0 {
            return self.solve_in_place(b);
        }
        let original = self.clone();
        let rhs = b.to_vec();
        let lu = self.factor()?;
        lu.apply(b);
        for _ in 0..steps {
            let mut r = original.residual(b, &rhs);
            lu.apply(&mut r);
            for (x, dx) in b.iter_mut().zip(&r) {
                *x += dx;
            }
        }
        Ok(())
    }

    /// Solve A x = b in place (b becomes x); A is consumed by its LU factors.
    pub fn solve_in_place(self, b: &mut [f64]) -> Result<()> {
        let lu = self.factor()?;
        lu.apply(b);
        Ok(())
    }

    /// LU factorisation with partial pivoting.
    pub fn factor(mut self) -> Result<BandLu> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let mut ipiv = vec![0usize; n];
        let mut ju = 0usize;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            let mut p = 0usize;
            let mut best = self.data[self.idx(j, j)].abs();
            for i in 1..=km {
                let a = self.data[self.idx(j + i, j)].abs();
                if a > best {
                    best = a;
                    p = i;
                }
            }
            ipiv[j] = j + p;
            if best == 0.0 || !best.is_finite() {
                return Err(Error::NoConvergence {
                    what: "banded LU",
                    detail: format!("singular or non-finite pivot in column {j}"),
                });
            }
            ju = ju.max((j + ku + p).min(n - 1));
            if p != 0 {
                for c in j..=ju {
                    let (a, bb) = (self.idx(j, c), self.idx(j + p, c));
                    self.data.swap(a, bb);
                }
            }
            let piv = self.data[self.idx(j, j)];
            for i in 1..=km {
                let k = self.idx(j + i, j);
                self.data[k] /= piv;
            }
            for c in (j + 1)..=ju {
                let a = self.data[self.idx(j, c)];
                if a != 0.0 {
                    for i in 1..=km {
                        let l = self.data[self.idx(j + i, j)];
                        let k = self.idx(j + i, c);
                        self.data[k] -= l * a;
                    }
                }
            }
        }
        Ok(BandLu { a: self, ipiv })
    }
}

/// LU factors of a [`BandMatrix`], reusable for several right-hand sides.
#[derive(Debug, Clone)]
pub struct BandLu {
    a: BandMatrix,
    ipiv: Vec<usize>,
}

impl BandLu {
    /// Overwrite b with the solution of A x = b.
    pub fn apply(&self, b: &mut [f64]) {
        let lu = &self.a;
        let (n, kl, ku) = (lu.n, lu.kl, lu.ku);
        let ipiv = &self.ipiv;
        // forward substitution with the row interchanges
        for j in 0..n {
            let l = ipiv[j];
            if l != j {
                b.swap(l, j);
            }
            let km = kl.min(n - 1 - j);
            let bj = b[j];
            if bj != 0.0 {
                for i in 1..=km {
                    b[j + i] -= lu.data[lu.idx(j + i, j)] * bj;
                }
            }
        }
        // back substitution with U (bandwidth kl + ku)
        for j in (0..n).rev() {
            b[j] /= lu.data[lu.idx(j, j)];
            let bj = b[j];
            let lo = j.saturating_sub(kl + ku);
            for i in lo..j {
                b[i] -= lu.data[lu.idx(i, j)] * bj;
            }
        }
    }
}

/// Chebyshev-Gauss-Lobatto nodes on [0, h] in increasing order (n + 1 nodes) and the
/// first-derivative matrix D with (D f)_m = f'(tau_m) exactly for polynomials of degree <= n.
pub fn chebyshev_lobatto(n: usize, h: f64) -> (Vec<f64>, Vec<f64>) {
    assert!(n >= 2);
    let m = n + 1;
    // x_k = -cos(pi k / n) in [-1, 1], increasing, written as a sine so that the
    // nodes are exactly symmetric; differences x_i - x_j are formed from sines too
    // (no cancellation), which keeps D accurate to a few ulps for large n.
    let pi = std::f64::consts::PI;
    let x: Vec<f64> = (0..m)
        .map(|k| (pi * (2.0 * k as f64 - n as f64) / (2.0 * n as f64)).sin())
        .collect();
    let diff = |i: usize, j: usize| {
        2.0 * (pi * (i + j) as f64 / (2.0 * n as f64)).sin()
            * (pi * (i as f64 - j as f64) / (2.0 * n as f64)).sin()
    };
    let cw: Vec<f64> = (0..m)
        .map(|k| {
            let e = if k == 0 || k == n { 2.0 } else { 1.0 };
            if k % 2 == 0 {
                e
            } else {
                -e
            }
        })
        .collect();
    let mut d = vec![0.0; m * m];
    for i in 0..m {
        let mut s = 0.0;
        for j in 0..m {
            if i != j {
                let v = cw[i] / cw[j] / diff(i, j);
                d[i * m + j] = v;
                s += v;
            }
        }
        d[i * m + i] = -s; // negative-sum trick: exact derivative of constants
    }
    let scale = 2.0 / h;
    for v in d.iter_mut() {
        *v *= scale;
    }
    let tau = x.iter().map(|&xi| 0.5 * h * (xi + 1.0)).collect();
    (tau, d)
}

/// Product of two m x m row-major matrices.
pub fn matmul(a: &[f64], b: &[f64], m: usize) -> Vec<f64> {
    let mut c = vec![0.0; m * m];
    for i in 0..m {
        for k in 0..m {
            let aik = a[i * m + k];
            for j in 0..m {
                c[i * m + j] += aik * b[k * m + j];
            }
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn banded_solve_matches_a_dense_tridiagonal_with_pivoting() {
        // matrix with a zero diagonal entry forces pivoting
        let n = 7;
        let mut a = BandMatrix::zeros(n, 2, 1);
        let mut dense = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in i.saturating_sub(2)..(i + 2).min(n) {
                let v = if i == j && i == 0 {
                    0.0
                } else {
                    1.0 + ((3 * i + 5 * j) % 7) as f64
                };
                a.add(i, j, v);
                dense[i][j] = v;
            }
        }
        let x_true: Vec<f64> = (0..n).map(|i| (i as f64) - 2.5).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| dense[i][j] * x_true[j]).sum())
            .collect();
        a.solve_in_place(&mut b).unwrap();
        for i in 0..n {
            assert!(
                (b[i] - x_true[i]).abs() < 1e-12,
                "{i}: {} vs {}",
                b[i],
                x_true[i]
            );
        }
    }

    #[test]
    fn singular_matrix_is_an_error_not_a_panic() {
        let a = BandMatrix::zeros(3, 1, 1);
        let mut b = vec![1.0; 3];
        assert!(a.solve_in_place(&mut b).is_err());
    }

    #[test]
    fn chebyshev_derivative_is_exact_for_polynomials() {
        let (tau, d) = chebyshev_lobatto(8, 0.7);
        assert!(tau[0].abs() < 1e-15 && (tau[8] - 0.7).abs() < 1e-15);
        let f: Vec<f64> = tau.iter().map(|t| t.powi(5) - 2.0 * t * t + 1.0).collect();
        for i in 0..9 {
            let df: f64 = (0..9).map(|j| d[i * 9 + j] * f[j]).sum();
            let exact = 5.0 * tau[i].powi(4) - 4.0 * tau[i];
            assert!((df - exact).abs() < 1e-12);
        }
    }
}
