//! The motion of one shock through one cell (eq. fast), integrated in *position*.
//!
//! Eq. (fast) says dx_i/dt = s_i c(u_+) with u_+ = B(x) + v t the field ahead. With the
//! exact speed c(u) = 1/sqrt(1 - u^2) its inverse is
//!
//! ```text
//!     dt/dy = 1/c(u_+) = sqrt((1 - u_+)(1 + u_+)),    u_+ = B(x_start + s y) + v t,
//! ```
//!
//! with y >= 0 the distance travelled. In this form the right side is bounded (0 <= dt/dy
//! <= 1: shocks are supersonic) and the birth of a pair, where u_+ = 1 and the speed is
//! infinite, is a regular starting point t(0) = t_b, dt/dy(0) = 0: the x0 +- sqrt(b t) law
//! of eq. (b) comes out of the integration instead of being imposed (tested in mod.rs).
//! Node crossings are at fixed y, so the events of the engine that dominate the work need
//! no root finding at all.
//!
//! The integrator is Dormand-Prince 5(4) with step control on the local error of t,
//! storing (y, t, dt/dy) at every accepted step; t(y) between them is the cubic Hermite
//! interpolant (fourth order), used for collisions, thresholds and snapshots.

use crate::error::{Error, Result};
use crate::free_boundary::field::CellPoly;
use crate::free_boundary::speed_law::SpeedLaw;

/// One accepted step: distance y from the start, time t, dt/dy there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrajPoint {
    /// Distance travelled from the start of the trajectory.
    pub y: f64,
    /// Time.
    pub t: f64,
    /// dt/dy = 1/c(u_+).
    pub f: f64,
}

/// How a trajectory through a cell ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrajEnd {
    /// The shock reaches the far node of the cell.
    Node,
    /// u_+ falls to the stopping threshold inside the cell (death, or creep with the
    /// "stop" rule).
    Threshold,
}

/// The path t(y) of a shock through (part of) a cell.
#[derive(Debug, Clone)]
pub struct Trajectory {
    /// Cell coordinate s = (x - x_j)/h of the start.
    pub s_start: f64,
    /// Direction +1 (towards larger x) or -1.
    pub dir: i8,
    /// Accepted points, y increasing from 0.
    pub pts: Vec<TrajPoint>,
    /// How it ends (at the last point).
    pub end: TrajEnd,
}

/// The field ahead of the shock in its cell: u_+ = poly(s) + v (t - epoch), and the
/// static threshold there (None: 1).
#[derive(Debug, Clone, Copy)]
pub struct CellField {
    /// Interpolant of b in the cell coordinate.
    pub poly: CellPoly,
    /// Interpolant of the threshold s(x) (None: uniform threshold 1). The shock moves at
    /// c(u_+/s) and stops where u_+/s reaches the stopping ratio.
    pub thr: Option<CellPoly>,
    /// Grid spacing.
    pub h: f64,
    /// Loading rate.
    pub v: f64,
    /// Time origin of b.
    pub epoch: f64,
}

impl CellField {
    /// u at cell coordinate s and time t.
    #[inline]
    pub fn u(&self, s: f64, t: f64) -> f64 {
        self.poly.eval(s) + self.v * (t - self.epoch)
    }
}

// Dormand-Prince 5(4) tableau.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// 5th minus 4th order weights (error estimate)
const E1: f64 = 35.0 / 384.0 - 5179.0 / 57600.0;
const E3: f64 = 500.0 / 1113.0 - 7571.0 / 16695.0;
const E4: f64 = 125.0 / 192.0 - 393.0 / 640.0;
const E5: f64 = -2187.0 / 6784.0 + 92097.0 / 339200.0;
const E6: f64 = 11.0 / 84.0 - 187.0 / 2100.0;
const E7: f64 = -1.0 / 40.0;

/// Integrate a shock from cell coordinate `s_start` at time `t0` in direction `dir`
/// to the far node of the cell, or until u_+/s <= `u_stop` (s the threshold, 1 without
/// a threshold field). `tol` is the local error
/// allowed per step in t, relative to the cell width h. `law` gives dt/dy = 1/c(u_+).
#[allow(clippy::too_many_arguments)]
pub fn integrate(
    field: &CellField,
    law: &SpeedLaw,
    s_start: f64,
    dir: i8,
    t0: f64,
    u_stop: f64,
    tol: f64,
    out: &mut Trajectory,
) -> Result<()> {
    let h = field.h;
    let sd = f64::from(dir);
    let total = if dir > 0 {
        (1.0 - s_start) * h
    } else {
        s_start * h
    };
    let total = total.max(0.0);
    out.s_start = s_start;
    out.dir = dir;
    out.pts.clear();
    let base = field.v * (t0 - field.epoch);
    // u_+/s: the engine's variable (u_+ itself without a threshold field)
    let ufun = |y: f64, tau: f64| {
        let s = s_start + sd * y / h;
        let u = field.poly.eval(s) + base + field.v * tau;
        match &field.thr {
            None => u,
            Some(p) => u / p.eval(s),
        }
    };
    let rhs = |y: f64, tau: f64| law.slowness(ufun(y, tau));
    let u0 = ufun(0.0, 0.0);
    out.pts.push(TrajPoint {
        y: 0.0,
        t: t0,
        f: law.slowness(u0),
    });
    if u0 <= u_stop {
        out.end = TrajEnd::Threshold;
        return Ok(());
    }
    if total == 0.0 {
        out.end = TrajEnd::Node;
        return Ok(());
    }
    let atol = tol * h;
    let mut y = 0.0f64;
    let mut tau = 0.0f64;
    let mut k1 = out.pts[0].f;
    // Steps are capped at h/4 so that the Hermite dense output (error ~ dy^4) stays
    // within ~1e-13 h of the integrated path for fields varying on scales >> h.
    let max_step = 0.25 * h;
    let mut dy = total.min(max_step);
    let mut steps = 0usize;
    while y < total {
        steps += 1;
        if steps > 1_000_000 {
            return Err(Error::NoConvergence {
                what: "shock trajectory in a cell",
                detail: format!("more than 1e6 steps (y = {y}, cell width {h})"),
            });
        }
        let last = total - y <= dy * (1.0 + 1e-12);
        let step = if last { total - y } else { dy };
        let (tau_new, k7, err_sum) = dp_step(&rhs, y, tau, k1, step);
        let y_new = if last { total } else { y + step };
        let err = (step * err_sum).abs();
        if err <= atol || step < 1e-14 * h {
            y = y_new;
            tau = tau_new;
            k1 = k7;
            out.pts.push(TrajPoint {
                y,
                t: t0 + tau,
                f: k7,
            });
            let u_new = ufun(y, tau);
            if u_new <= u_stop {
                // Locate the threshold on the dense output and cut the trajectory there.
                let n = out.pts.len();
                let (p0, p1) = (out.pts[n - 2], out.pts[n - 1]);
                let g = |yy: f64| {
                    let t = hermite(&p0, &p1, yy);
                    let s = s_start + sd * yy / h;
                    let u = field.poly.eval(s) + field.v * (t - field.epoch);
                    match &field.thr {
                        None => u - u_stop,
                        Some(p) => u / p.eval(s) - u_stop,
                    }
                };
                let (mut lo, mut hi) = (p0.y, p1.y);
                for _ in 0..100 {
                    let mid = 0.5 * (lo + hi);
                    if g(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                    if hi - lo <= 1e-15 * h {
                        break;
                    }
                }
                let yc = 0.5 * (lo + hi);
                // t at the threshold by one more step from p0 (the dense output is only
                // fourth order between accepted points)
                let (tau_c, _, _) = dp_step(&rhs, p0.y, p0.t - t0, p0.f, yc - p0.y);
                let tc = t0 + tau_c;
                out.pts[n - 1] = TrajPoint {
                    y: yc,
                    t: tc,
                    f: law.slowness(u_stop),
                };
                out.end = TrajEnd::Threshold;
                return Ok(());
            }
            let fac = if err > 0.0 {
                (0.9 * (atol / err).powf(0.2)).clamp(0.2, 5.0)
            } else {
                5.0
            };
            dy = (step * fac).min(max_step);
        } else {
            dy = step * (0.9 * (atol / err).powf(0.2)).clamp(0.1, 0.9);
        }
    }
    out.end = TrajEnd::Node;
    Ok(())
}

/// One Dormand-Prince step from (y, tau) with k1 = rhs(y, tau): (tau_new, rhs at the new
/// point, the error weight sum (times the step gives the local error estimate)).
fn dp_step(
    rhs: &impl Fn(f64, f64) -> f64,
    y: f64,
    tau: f64,
    k1: f64,
    step: f64,
) -> (f64, f64, f64) {
    let k2 = rhs(y + C2 * step, tau + step * A21 * k1);
    let k3 = rhs(y + C3 * step, tau + step * (A31 * k1 + A32 * k2));
    let k4 = rhs(y + C4 * step, tau + step * (A41 * k1 + A42 * k2 + A43 * k3));
    let k5 = rhs(
        y + C5 * step,
        tau + step * (A51 * k1 + A52 * k2 + A53 * k3 + A54 * k4),
    );
    let k6 = rhs(
        y + step,
        tau + step * (A61 * k1 + A62 * k2 + A63 * k3 + A64 * k4 + A65 * k5),
    );
    let tau_new = tau + step * (B1 * k1 + B3 * k3 + B4 * k4 + B5 * k5 + B6 * k6);
    let k7 = rhs(y + step, tau_new);
    let e = E1 * k1 + E3 * k3 + E4 * k4 + E5 * k5 + E6 * k6 + E7 * k7;
    (tau_new, k7, e)
}

/// Cubic Hermite interpolation of t between two accepted points.
#[inline]
pub fn hermite(p0: &TrajPoint, p1: &TrajPoint, y: f64) -> f64 {
    let d = p1.y - p0.y;
    if d <= 0.0 {
        return p0.t;
    }
    let th = (y - p0.y) / d;
    let th2 = th * th;
    let th3 = th2 * th;
    (2.0 * th3 - 3.0 * th2 + 1.0) * p0.t
        + (th3 - 2.0 * th2 + th) * d * p0.f
        + (-2.0 * th3 + 3.0 * th2) * p1.t
        + (th3 - th2) * d * p1.f
}

/// dt/dy of the cubic Hermite interpolant.
#[inline]
fn hermite_slope(p0: &TrajPoint, p1: &TrajPoint, y: f64) -> f64 {
    let d = p1.y - p0.y;
    if d <= 0.0 {
        return p0.f;
    }
    let th = (y - p0.y) / d;
    let th2 = th * th;
    ((6.0 * th2 - 6.0 * th) * p0.t + (-6.0 * th2 + 6.0 * th) * p1.t) / d
        + (3.0 * th2 - 4.0 * th + 1.0) * p0.f
        + (3.0 * th2 - 2.0 * th) * p1.f
}

impl Trajectory {
    /// An empty trajectory.
    pub fn new() -> Self {
        Trajectory {
            s_start: 0.0,
            dir: 1,
            pts: Vec::with_capacity(8),
            end: TrajEnd::Node,
        }
    }

    /// Distance covered by the whole trajectory.
    pub fn y_end(&self) -> f64 {
        self.pts.last().map_or(0.0, |p| p.y)
    }

    /// Time at the end of the trajectory.
    pub fn t_end(&self) -> f64 {
        self.pts.last().map_or(f64::NAN, |p| p.t)
    }

    /// Time at distance y (0 <= y <= y_end).
    pub fn t_at(&self, y: f64) -> f64 {
        let pts = &self.pts;
        if y <= pts[0].y {
            return pts[0].t;
        }
        let i = pts.partition_point(|p| p.y < y);
        if i >= pts.len() {
            return pts[pts.len() - 1].t;
        }
        hermite(&pts[i - 1], &pts[i], y)
    }

    /// Distance reached at time t (clamped to the trajectory).
    pub fn y_at(&self, t: f64) -> f64 {
        let pts = &self.pts;
        if t <= pts[0].t {
            return pts[0].y;
        }
        let i = pts.partition_point(|p| p.t < t);
        if i >= pts.len() {
            return pts[pts.len() - 1].y;
        }
        let (p0, p1) = (&pts[i - 1], &pts[i]);
        // Safeguarded Newton on the Hermite cubic (monotone in practice), from the
        // linear guess; bisection steps keep it inside the bracket.
        let (mut lo, mut hi) = (p0.y, p1.y);
        let mut y = if p1.t > p0.t {
            p0.y + (p1.y - p0.y) * (t - p0.t) / (p1.t - p0.t)
        } else {
            0.5 * (lo + hi)
        };
        let tol = 1e-14 * (1.0 + hi.abs());
        for _ in 0..100 {
            let g = hermite(p0, p1, y) - t;
            if g == 0.0 {
                break;
            }
            if g < 0.0 {
                lo = y;
            } else {
                hi = y;
            }
            let d = hermite_slope(p0, p1, y);
            let mut next = if d > 0.0 { y - g / d } else { f64::NAN };
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            let done = (next - y).abs() <= tol || hi - lo <= tol;
            y = next;
            if done {
                break;
            }
        }
        y
    }

    /// Cell coordinate s at distance y.
    pub fn s_at(&self, y: f64, h: f64) -> f64 {
        self.s_start + f64::from(self.dir) * y / h
    }
}

impl Default for Trajectory {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(b: f64, v: f64, h: f64) -> CellField {
        CellField {
            poly: CellPoly::through(0, &[b]),
            thr: None,
            h,
            v,
            epoch: 0.0,
        }
    }

    #[test]
    fn uniform_field_has_the_closed_form_solution() {
        // B = const: du/dy = v sqrt(1 - u^2) so u(y) = sin(v y + asin(u0)),
        // t(y) = (u(y) - u0)/v.
        let (u0, v, h) = (0.6, 0.05, 2.0);
        let f = flat(u0, v, h);
        let mut tr = Trajectory::new();
        integrate(&f, &SpeedLaw::Exact, 0.0, 1, 0.0, -1.0, 1e-13, &mut tr).unwrap();
        assert_eq!(tr.end, TrajEnd::Node);
        // accepted points: the integration error (tol 1e-13 per step)
        for p in &tr.pts {
            let exact = ((v * p.y + u0.asin()).sin() - u0) / v;
            assert!((p.t - exact).abs() < 1e-13, "{}: {}", p.y, p.t - exact);
        }
        // between them: the cubic Hermite dense output, error ~ dy^4 t''''/384
        for &y in &[0.3, 1.1, 2.0] {
            let exact = ((v * y + u0.asin()).sin() - u0) / v;
            assert!(
                (tr.t_at(y) - exact).abs() < 1e-10,
                "{y}: {}",
                tr.t_at(y) - exact
            );
            assert!((tr.y_at(exact) - y).abs() < 1e-9);
        }
        // leftwards from s = 1 gives the same
        let mut tl = Trajectory::new();
        integrate(&f, &SpeedLaw::Exact, 1.0, -1, 0.0, -1.0, 1e-13, &mut tl).unwrap();
        assert!((tl.t_end() - tr.t_end()).abs() < 1e-13);
    }

    #[test]
    fn threshold_is_located_on_the_path() {
        // B decreasing linearly, v = 0: u_+ = 0.5 - 0.4 s, reaches 0.2 at s = 0.75.
        let f = CellField {
            poly: CellPoly::through(0, &[0.5, 0.1]),
            thr: None,
            h: 1.0,
            v: 0.0,
            epoch: 0.0,
        };
        let mut tr = Trajectory::new();
        integrate(&f, &SpeedLaw::Exact, 0.0, 1, 0.0, 0.2, 1e-13, &mut tr).unwrap();
        assert_eq!(tr.end, TrajEnd::Threshold);
        assert!((tr.y_end() - 0.75).abs() < 1e-12);
        // t = int_0^0.75 sqrt(1 - (0.5 - 0.4 y)^2) dy, by Simpson on a fine grid
        let n = 2000;
        let g = |y: f64| (1.0 - (0.5 - 0.4 * y).powi(2)).sqrt();
        let dy = 0.75 / n as f64;
        let mut s = g(0.0) + g(0.75);
        for i in 1..n {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * g(i as f64 * dy);
        }
        let simpson = s * dy / 3.0;
        assert!(
            (tr.t_end() - simpson).abs() < 1e-12,
            "{}",
            tr.t_end() - simpson
        );
    }

    #[test]
    fn birth_at_u_equal_one_starts_as_square_root_of_time() {
        // u = 1 - a x^2 + v t from x = 0 at t = 0 (eq. a): x ~ sqrt(b t) (eq. b).
        let (a, v, h) = (0.02, 0.01, 1.0);
        let f = CellField {
            poly: CellPoly::through(0, &[1.0, 1.0 - a * h * h, 1.0 - 4.0 * a * h * h]),
            thr: None,
            h,
            v,
            epoch: 0.0,
        };
        let mut tr = Trajectory::new();
        integrate(&f, &SpeedLaw::Exact, 0.0, 1, 0.0, 0.0, 1e-13, &mut tr).unwrap();
        let b = (v + (v * v + 8.0 * a).sqrt()) / (2.0 * a);
        let mut last = f64::INFINITY;
        for &y in &[1e-1, 3e-2, 1e-2, 3e-3] {
            let t = tr.t_at(y);
            let rel = (y / (b * t).sqrt() - 1.0).abs();
            assert!(rel < last, "{y}: {rel}");
            last = rel;
        }
        assert!(last < 1e-3, "{last}");
    }
}
