//! The lattice's front shape as options: a curvature correction of the normal speed and
//! a planar speed that depends on the direction of the normal.
//!
//! On the lattice (docs/lattice.md) an expanding rupture is slower than a planar front by
//! D/R with D = a dx (theory.md section 7: the speed is set by the tip at the scale dx,
//! where the curvature enters as kappa dx), and the planar speed itself differs along the
//! axes and the diagonals (the chain at dx, at dx/sqrt 2). With the options a front moves
//! along its normal n at
//!
//! ```text
//!     c_n = c_axis(u) + (c_diag(u) - c_axis(u)) sin^2(2 theta) - D(theta) kappa,
//!     D(theta) = D_axis cos^2(2 theta) + D_diag sin^2(2 theta),
//! ```
//!
//! theta the angle of n to the x axis (sin^2(2 theta) = 0 along the axes, 1 along the
//! diagonals), c_axis the engine's law, c_diag the diagonal law (without it c_diag =
//! c_axis), kappa = div(grad T/|grad T|) the front's curvature (1/R for an expanding
//! circle), and c_n >= 1 (the correction keeps a front supersonic: the law is a small
//! correction, not meant for R of a few nodes).
//!
//! **The direction** comes from the local update's own stencil at the trial time tau:
//! the upwind differences g_a = sqrt(alpha_a) (tau - d_a)_+/h along each axis, so the
//! normal and T are solved together (the bracket of [`super::eikonal::solve`] still
//! holds: c_n >= 1 keeps Y <= 1). Along the axes and diagonals the front of a point
//! source in a uniform medium then moves at c_axis and c_diag exactly (its Wulff shape
//! has those normals there).
//!
//! **The curvature** at a trial node q comes from the accepted nodes of its rupture
//! whose eight neighbours at the stride p are accepted too (interior nodes, at least p
//! nodes behind the front): there centred differences give T_x, T_y, T_xx, T_yy, T_xy and
//!
//! ```text
//!     kappa_k = (T_xx T_y^2 - 2 T_x T_y T_xy + T_yy T_x^2) / |grad T|^3.
//! ```
//!
//! It is carried to q along the normal: in a uniform medium a front's rays are straight
//! and its curvature obeys d kappa/ds = -kappa^2 along them (parallel curves), so
//! kappa_q = kappa_k/(1 + kappa_k s), s = n_k . (x_q - x_k) the distance from k to q
//! along k's normal. This is exact for a circle and first order in the distance (O(s
//! kappa grad c/c)) where the speed varies. kappa_q is the mean over the interior nodes
//! within p + 2 nodes of q, limited to |kappa| <= 1/(2h) (the front's radius is not
//! resolved below two nodes; a kink where two fronts of one rupture meet has no curvature
//! to speak of). With no interior node in the window (a rupture a few nodes across)
//! kappa = 0.
//!
//! **The stride.** The differences are taken at a stride of p nodes, p = round(1/sqrt(h))
//! and at least 2 ([`curvature_stride`]), and the interior nodes are those whose neighbours at
//! stride p are accepted. Near the axes the marched T is right to O(h^2) but the curvature
//! there is a difference of O(h^2 kappa) between neighbouring rows, the size of that
//! error: at stride 1 kappa came out wrong by more than itself along the axes. At stride
//! p the grid's error is O(1/p^2) relative; the transport over the p + 2 nodes adds
//! O(p h) where the speed varies: p h ~ sqrt(h) balances them. The window reaches p + 2
//! nodes because when q first becomes a trial node the row just behind the front is not
//! all accepted yet.
//!
//! Fast marching keeps the earliest of the updates of a trial node, which is right when
//! each update can only lower T (more upwind neighbours). With the curvature term a later
//! update of the same rupture sees more of the front around q (more interior nodes), and
//! it replaces the earlier one, later or not. Without the options the engine's arithmetic
//! is unchanged (bit for bit).

use super::eikonal::Term;
use super::FreeBoundary2D;
use crate::error::{Error, Result};
use crate::free_boundary::SpeedLaw;

/// cos(2 theta)^2 of the normal whose squared components along x and y are gx2, gy2
/// (1 along an axis, 0 along a diagonal; 1 where there is no gradient yet).
#[inline]
pub(super) fn cos2_sq(gx2: f64, gy2: f64) -> f64 {
    let s = gx2 + gy2;
    if s > 0.0 {
        let c = (gx2 - gy2) / s;
        c * c
    } else {
        1.0
    }
}

#[cfg(test)]
thread_local! {
    /// A stride that replaces the rule (measurements of the rule in the tests).
    pub(super) static STRIDE_OVERRIDE: std::cell::Cell<Option<i64>> =
        const { std::cell::Cell::new(None) };
}

/// The stride (in nodes) of the differences that give the curvature (module docs).
/// p = round(1/sqrt(h)), at least 2: a difference at stride p has the relative error
/// O(h^2/(p h)^2) from the grid and the bias O(p h) from the transport; p h ~ sqrt(h)
/// balances them.
pub(super) fn curvature_stride(h: f64) -> i64 {
    #[cfg(test)]
    if let Some(p) = STRIDE_OVERRIDE.with(std::cell::Cell::get) {
        return p;
    }
    (1.0 / h.sqrt()).round().clamp(2.0, 64.0) as i64
}

/// The curvature coefficient D(theta) as a table over directions theta_k in [0, pi/4]
/// (the first 0, the last pi/4; the square lattice's symmetries give every other
/// direction), interpolated by the trigonometric polynomial in cos(4 theta) through them:
/// D(theta) = sum_k D_k l_k(cos 4 theta), l_k the Lagrange basis in x = cos 4 theta at
/// the nodes x_k = cos 4 theta_k. With the two directions 0 and pi/4 this is
/// D_axis cos^2(2 theta) + D_diag sin^2(2 theta) (x = 2 cos^2(2 theta) - 1).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Directions {
    pub(super) theta: Vec<f64>,
    pub(super) d: Vec<f64>,
    x: Vec<f64>,
    /// prod_{j != k} (x_k - x_j)
    den: Vec<f64>,
}

impl Directions {
    pub(super) fn new(theta: &[f64], d: &[f64]) -> Result<Self> {
        let quarter = std::f64::consts::FRAC_PI_4;
        let fail = |name, value, allowed| {
            Err(Error::InvalidParameter {
                name,
                value,
                allowed,
            })
        };
        if theta.len() != d.len() || !(2..=16).contains(&theta.len()) {
            return fail(
                "curvature directions",
                theta.len() as f64,
                "2 to 16 directions theta, as many as coefficients D",
            );
        }
        let m = theta.len();
        if let Some(&bad) = theta.iter().find(|t| !t.is_finite()) {
            return fail("curvature theta", bad, "finite directions in [0, pi/4]");
        }
        if theta[0].abs() > 1e-12 || (theta[m - 1] - quarter).abs() > 1e-12 {
            return fail(
                "curvature theta",
                if theta[0].abs() > 1e-12 {
                    theta[0]
                } else {
                    theta[m - 1]
                },
                "the first direction 0 (an axis), the last pi/4 (the diagonal)",
            );
        }
        for k in 1..m {
            if theta[k].is_nan() || theta[k] <= theta[k - 1] + 1e-6 {
                return fail(
                    "curvature theta",
                    theta[k],
                    "strictly increasing directions in [0, pi/4], at least 1e-6 apart",
                );
            }
        }
        if let Some(&bad) = d.iter().find(|x| !(x.is_finite() && **x >= 0.0)) {
            return fail("curvature D", bad, "finite D >= 0 (c_n = c - D kappa)");
        }
        let mut th = theta.to_vec();
        th[0] = 0.0;
        th[m - 1] = quarter;
        let x: Vec<f64> = th
            .iter()
            .enumerate()
            .map(|(k, t)| match k {
                0 => 1.0,
                _ if k == m - 1 => -1.0,
                _ => (4.0 * t).cos(),
            })
            .collect();
        let den = (0..m)
            .map(|k| (0..m).filter(|&j| j != k).map(|j| x[k] - x[j]).product())
            .collect();
        Ok(Directions {
            theta: th,
            d: d.to_vec(),
            x,
            den,
        })
    }

    /// D at the normal whose cos^2(2 theta) is c2.
    pub(super) fn at(&self, c2: f64) -> f64 {
        let x = 2.0 * c2 - 1.0;
        let m = self.x.len();
        let mut sum = 0.0;
        for k in 0..m {
            let mut l = self.d[k] / self.den[k];
            for j in 0..m {
                if j != k {
                    l *= x - self.x[j];
                }
            }
            sum += l;
        }
        sum
    }
}

impl FreeBoundary2D {
    /// The curvature coefficient D(theta) as a table over directions (the [`Directions`]
    /// docs): theta_k in radians, 0 first and pi/4 last, strictly increasing; D_k >= 0.
    /// Replaces the engine's curvature option (D_axis, D_diag). Only before the first
    /// rupture.
    pub fn set_curvature_directions(&mut self, theta: &[f64], d: &[f64]) -> Result<()> {
        if !self.ruptures.is_empty() {
            return Err(Error::InvalidParameter {
                name: "curvature directions",
                value: self.ruptures.len() as f64,
                allowed: "set before the first rupture",
            });
        }
        let dirs = Directions::new(theta, d)?;
        self.opts.curvature = Some((dirs.d[0], dirs.d[dirs.d.len() - 1]));
        self.curv_dirs = Some(dirs);
        Ok(())
    }

    /// The curvature coefficient D the engine uses at the normal of angle theta to the x
    /// axis (radians), or None without the curvature option.
    pub fn curvature_at_angle(&self, theta: f64) -> Option<f64> {
        let (da, dd) = self.opts.curvature?;
        let c2 = (2.0 * theta).cos().powi(2);
        Some(match &self.curv_dirs {
            Some(dirs) => dirs.at(c2),
            None => da * c2 + dd * (1.0 - c2),
        })
    }

    /// The curvature table (theta, D), if set by [`Self::set_curvature_directions`].
    pub fn curvature_directions(&self) -> Option<(&[f64], &[f64])> {
        self.curv_dirs
            .as_ref()
            .map(|t| (t.theta.as_slice(), t.d.as_slice()))
    }

    /// Set the planar speed along the diagonals (module docs): c_axis is the engine's
    /// law. Only before the first rupture.
    pub fn set_diagonal_law(&mut self, law: SpeedLaw) -> Result<()> {
        if !self.ruptures.is_empty() {
            return Err(Error::InvalidParameter {
                name: "diagonal law",
                value: self.ruptures.len() as f64,
                allowed: "set before the first rupture",
            });
        }
        self.law_diag = Some(law);
        Ok(())
    }

    /// The planar speed law along the diagonals, if set.
    pub fn diagonal_law(&self) -> Option<&SpeedLaw> {
        self.law_diag.as_ref()
    }

    /// Whether the front's shape options are on.
    #[inline]
    pub(super) fn shaped(&self) -> bool {
        self.opts.curvature.is_some() || self.law_diag.is_some()
    }

    /// kappa at node q from the interior nodes of rupture r around it (module docs).
    pub(super) fn curvature_at(&self, q: usize, r: u32) -> f64 {
        let p = curvature_stride(self.grid.h);
        let tb = self.stopped[q];
        let ok = |j: usize| self.label[j] == r && self.t_arr[j] >= tb;
        let (iq, jq) = self.grid.ij(q);
        let h = self.grid.h;
        let w = p + 2;
        let (mut sum, mut n) = (0.0f64, 0usize);
        for dj in -w..=w {
            for di in -w..=w {
                let Some(k) = self.offset(iq, jq, di, dj) else {
                    continue;
                };
                if !ok(k) {
                    continue;
                }
                let (ik, jk) = self.grid.ij(k);
                let mut t = [[0.0f64; 3]; 3];
                let mut interior = true;
                'nb: for (b, row) in t.iter_mut().enumerate() {
                    for (a, cell) in row.iter_mut().enumerate() {
                        let (oa, ob) = ((a as i64 - 1) * p, (b as i64 - 1) * p);
                        match self.offset(ik, jk, oa, ob) {
                            Some(j) if ok(j) => *cell = self.t_arr[j],
                            _ => {
                                interior = false;
                                break 'nb;
                            }
                        }
                    }
                }
                if !interior {
                    continue;
                }
                // centred differences at the stride p (in units of p h)
                let tx = 0.5 * (t[1][2] - t[1][0]);
                let ty = 0.5 * (t[2][1] - t[0][1]);
                let txx = t[1][2] - 2.0 * t[1][1] + t[1][0];
                let tyy = t[2][1] - 2.0 * t[1][1] + t[0][1];
                let txy = 0.25 * (t[2][2] - t[0][2] - t[2][0] + t[0][0]);
                let g2 = tx * tx + ty * ty;
                if g2.is_nan() || g2 <= 0.0 {
                    continue;
                }
                let g = g2.sqrt();
                let ph = p as f64 * h;
                let kap = (txx * ty * ty - 2.0 * tx * ty * txy + tyy * tx * tx) / (g2 * g) / ph;
                // carried from k to q along k's normal
                let s = (tx * (-di) as f64 + ty * (-dj) as f64) / g * h;
                let den = 1.0 + kap * s;
                if !(den > 0.25 && kap.is_finite()) {
                    continue;
                }
                sum += kap / den;
                n += 1;
            }
        }
        if n == 0 {
            return 0.0;
        }
        let lim = 0.5 / h;
        (sum / n as f64).clamp(-lim, lim)
    }

    /// Squared slowness with the shape options at stress u, threshold s, curvature kappa
    /// and the normal of the stencil `terms` (on `axes`) at tau.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn shaped_y(
        &self,
        u: f64,
        s: f64,
        kappa: f64,
        terms: &[Term],
        axes: &[usize],
        tau: f64,
    ) -> f64 {
        let mut g = [0.0f64; 2];
        for (t, &a) in terms.iter().zip(axes) {
            let e = tau - t.d;
            if e > 0.0 {
                g[a] = t.alpha * e * e;
            }
        }
        let c2 = cos2_sq(g[0], g[1]);
        let f = self.law.slowness(u / s);
        if f <= 0.0 {
            return 0.0;
        }
        let mut c = 1.0 / f;
        if let Some(ld) = &self.law_diag {
            let fd = ld.slowness(u / s);
            if fd <= 0.0 {
                return 0.0;
            }
            c += (1.0 / fd - c) * (1.0 - c2);
        }
        if let Some((da, dd)) = self.opts.curvature {
            let d = match &self.curv_dirs {
                Some(dirs) => dirs.at(c2),
                None => da * c2 + dd * (1.0 - c2),
            };
            c -= d * kappa;
        }
        if c > 1.0 {
            1.0 / (c * c)
        } else {
            1.0
        }
    }
}
