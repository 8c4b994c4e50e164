//! The local update of fast marching with a speed that depends on the arrival time.
//!
//! At a node not yet reached, the arrival time T of the front obeys |grad T| = F(u(T)),
//! F = 1/c the slowness and u(T) = u_lo + v (T - m_lo) the stress the node will hold at T
//! (it loads at rate v until the front arrives). Upwind differences along each axis a
//! that has an accepted neighbour give
//!
//! ```text
//!     sum_a alpha_a (T - m_a)_+^2 = h^2 Y(u(T)),        Y = F^2 = 1/c^2,
//! ```
//!
//! first order: alpha = 1, m = T_1 (the neighbour's time); second order (Sethian's
//! higher-accuracy fast marching, when the next node on the same side is accepted and
//! earlier, T_2 <= T_1): alpha = 9/4, m = (4 T_1 - T_2)/3, from the one-sided difference
//! (3 T - 4 T_1 + T_2)/(2 h). The left side is zero at T = min m and increases with T;
//! Y(u) decreases with u for u >= 0 (a front is faster in a more stressed medium) and u
//! increases with T, so the right side decreases: one root, found here by bracketing.
//! Since Y <= 1 (fronts are supersonic), G(T) = left - right is <= 0 at min m and >= 0 at
//! min m + h/sqrt(alpha): the bracket. The terms (.)_+ switch an axis on only where T has
//! passed its m, which is the usual "drop the axis whose neighbour is too late" rule.
//!
//! The solve works in tau = T - min m, so the digits of large absolute times are not lost
//! in the differences. With v = 0 and a first-order stencil this is the textbook
//! quadratic; the root is then exact to rounding (tested).

/// One axis of the stencil: its coefficient alpha and offset d = m - min m >= 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    /// 1 (first order) or 9/4 (second order).
    pub alpha: f64,
    /// m_a - min m.
    pub d: f64,
}

/// tau >= 0 with sum_a alpha_a (tau - d_a)_+^2 = h^2 y(u_lo + v tau, tau): the arrival
/// time after min m. `y` is the squared slowness Y(u, tau) in [0, 1] (tau: for a speed
/// that depends on the direction of the stencil's gradient, see the `shape` module).
pub fn solve(terms: &[Term], h: f64, u_lo: f64, v: f64, y: impl Fn(f64, f64) -> f64) -> f64 {
    let g = |tau: f64| -> f64 {
        let mut s = 0.0;
        for t in terms {
            let e = tau - t.d;
            if e > 0.0 {
                s += t.alpha * e * e;
            }
        }
        s - h * h * y(u_lo + v * tau, tau)
    };
    let a0 = terms
        .iter()
        .filter(|t| t.d == 0.0)
        .map(|t| t.alpha)
        .fold(f64::INFINITY, f64::min);
    let (mut lo, mut hi) = (0.0f64, h / a0.sqrt());
    let (mut fa, mut fb) = (g(lo), g(hi));
    if fa >= 0.0 {
        return 0.0;
    }
    if fb <= 0.0 {
        return hi;
    }
    let mut side = 0i8;
    let mut last = f64::NAN;
    for _ in 0..200 {
        let mut t = hi - fb * (hi - lo) / (fb - fa);
        if !(t > lo && t < hi) {
            t = 0.5 * (lo + hi);
        }
        if t == last {
            return t;
        }
        last = t;
        let ft = g(t);
        if ft == 0.0 {
            return t;
        }
        if ft < 0.0 {
            lo = t;
            fa = ft;
            if side < 0 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            hi = t;
            fb = ft;
            if side > 0 {
                fa *= 0.5;
            }
            side = 1;
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_slowness_is_the_textbook_quadratic() {
        let h = 0.1;
        let f: f64 = 0.6;
        // one axis: tau = h f
        let t = solve(&[Term { alpha: 1.0, d: 0.0 }], h, 0.5, 0.0, |_, _| f * f);
        assert!((t - h * f).abs() < 1e-16, "{t}");
        // two axes, d = 0.02: (tau)^2 + (tau - d)^2 = h^2 f^2
        let d = 0.02;
        let t = solve(
            &[Term { alpha: 1.0, d: 0.0 }, Term { alpha: 1.0, d }],
            h,
            0.5,
            0.0,
            |_, _| f * f,
        );
        let exact = (d + (2.0 * h * h * f * f - d * d).sqrt()) / 2.0;
        assert!((t - exact).abs() < 1e-16, "{t} {exact}");
        // the second axis too late: one-axis answer
        let t = solve(
            &[Term { alpha: 1.0, d: 0.0 }, Term { alpha: 1.0, d: 0.5 }],
            h,
            0.5,
            0.0,
            |_, _| f * f,
        );
        assert!((t - h * f).abs() < 1e-16);
        // second order: (9/4) tau^2 = h^2 f^2
        let t = solve(
            &[Term {
                alpha: 2.25,
                d: 0.0,
            }],
            h,
            0.5,
            0.0,
            |_, _| f * f,
        );
        assert!((t - h * f / 1.5).abs() < 1e-16);
    }

    #[test]
    fn the_speed_is_taken_at_the_arrival_time() {
        // Y = 1 - u^2, u = u_lo + v tau: tau^2 = h^2 (1 - (u_lo + v tau)^2), a quadratic
        let (h, u_lo, v) = (0.1, 0.7, 0.3);
        let t = solve(&[Term { alpha: 1.0, d: 0.0 }], h, u_lo, v, |u, _| {
            1.0 - u * u
        });
        // (1 + h^2 v^2) tau^2 + 2 h^2 u_lo v tau - h^2 (1 - u_lo^2) = 0
        let (a, b, c) = (
            1.0 + h * h * v * v,
            2.0 * h * h * u_lo * v,
            -h * h * (1.0 - u_lo * u_lo),
        );
        let exact = (-b + (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
        assert!((t - exact).abs() < 1e-15, "{t} {exact}");
        // at the threshold the front arrives at once
        assert_eq!(
            solve(&[Term { alpha: 1.0, d: 0.0 }], h, 1.0, v, |u, _| (1.0
                - u * u)
                .max(0.0)),
            0.0
        );
    }
}
