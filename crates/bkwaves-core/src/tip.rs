//! The discrete problem at the tip of the wave (paper App. A), solved to machine precision.
//!
//! Rescale u_i = u_+ - u_+ dx^2 w_i and t = t_s + tau dx near the slip point. Then, exactly,
//! sliding blocks obey  w_i'' = w_{i+1} + w_{i-1} - 2 w_i + 1 - dx^2 w_i - 2 gamma dx w_i',
//! stuck blocks have w = 0, and a stuck block whose right neighbour is stuck slips when its
//! left neighbour reaches w = theta = (1 - u_+)/u_+ (eq. slip). The continuum limit
//! dx -> 0 drops the last two terms (eqs. elast1, elast2 with v_i = w_i - tau^2/2).
//!
//! A steady front slips one block every T = 1/c, so block s-k at time tau is the same
//! block history g shifted: w_{s-k}(tau) = g(tau + kT). g(t) = 0 for t <= 0 and
//!
//! ```text
//!   g''(t) = g(t+T) + g(t-T) - 2 g(t) + 1 - dx^2 g(t) - 2 gamma dx g'(t),   t > 0,
//!   g(0) = g'(0) = 0,   theta = g(T),
//! ```
//!
//! a linear differential equation with advanced and delayed arguments. On each interval
//! [jT, (j+1)T] g is smooth (its derivatives jump only at multiples of T), so it is
//! represented by Chebyshev collocation per interval; the intervals are coupled by value
//! and slope continuity. Far behind the tip the exact solution approaches the smooth
//! outer solution plus transients decaying like exp(-lambda t), with lambda the real root
//! of lambda = 2 sinh(lambda T / 2); the last interval is closed by the outer equation
//! (1 - T^2) g'' + 2 gamma dx g' + dx^2 g = 1 (for dx = 0: g = c^2 t^2 / (2(c^2 - 1)) + B t + C,
//! the paper's matching condition), and enough intervals are kept for the transients to
//! decay by `decay` e-folds. Given c the problem is linear: one banded solve gives theta and
//! u_+ = 1/(1 + theta). The inverse c(u_+) is found by bracketed root finding.
//! See docs/theory.md for the derivation and the convergence tables.

use crate::error::{check_at_least, check_open, Error, Result};
use crate::linalg::{chebyshev_lobatto, matmul, BandMatrix};

/// Numerical settings of the tip solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipOptions {
    /// Chebyshev polynomial degree per interval (nodes = degree + 1).
    pub degree: usize,
    /// E-folds of the slowest transient kept behind the tip (sets the number of intervals).
    pub decay: f64,
    /// Upper bound on the number of intervals (the solve fails beyond it).
    pub max_intervals: usize,
    /// Lattice spacing dx (0 = continuum limit).
    pub dx: f64,
    /// Viscous damping gamma (enters at order dx).
    pub gamma: f64,
}

impl Default for TipOptions {
    fn default() -> Self {
        TipOptions {
            degree: 16,
            decay: 40.0,
            max_intervals: 400_000,
            dx: 0.0,
            gamma: 0.0,
        }
    }
}

impl TipOptions {
    fn validate(&self) -> Result<()> {
        if self.degree < 4 || self.degree > 64 {
            return Err(Error::InvalidParameter {
                name: "degree",
                value: self.degree as f64,
                allowed: "4 <= degree <= 64",
            });
        }
        check_open("decay", self.decay, 0.0, f64::INFINITY, "decay > 0")?;
        check_at_least("dx", self.dx, 0.0, "dx >= 0 (0 = continuum limit)")?;
        check_at_least("gamma", self.gamma, 0.0, "gamma >= 0")?;
        Ok(())
    }
}

/// The solved tip problem for one front speed.
#[derive(Debug, Clone, PartialEq)]
pub struct TipSolution {
    /// Front speed c.
    pub c: f64,
    /// Slip threshold theta = g(T) = (1 - u_+)/u_+.
    pub theta: f64,
    /// Stress ahead of the front, u_+ = 1/(1 + theta).
    pub u_plus: f64,
    /// Number of intervals of length T kept behind the tip.
    pub intervals: usize,
    /// Slowest transient decay rate lambda (per unit tau).
    pub decay_rate: f64,
    /// Velocity g'(t) of the tip block at t = T (sanity: positive for a forward slip).
    pub tip_velocity: f64,
}

/// Smallest c - 1 the solver accepts. The lattice kept behind the tip grows like
/// 1/sqrt(c - 1) and the round-off in theta like 1/(c - 1)^2: at c - 1 = 5e-5 (u_+ = 0.01
/// at dx = 0) c is still right to ~2e-11 relative (c - 1 to ~3e-7), one solve takes about a
/// second, and below it the error and the cost grow without bound (c - 1 = 1.25e-7 gave a
/// negative theta, c - 1 = 5e-7 took 26 s). docs/theory.md, "Range of the tip solver".
pub const MIN_SPEED_EXCESS: f64 = 5e-5;
/// Largest c the solver accepts: the collocation round-off in theta grows like c^2 eps
/// (6e-11 relative at c = 1e3, 1e-8 at 1e4, 1e-4 at 1e6).
pub const MAX_SPEED: f64 = 1e3;
/// The range in words, for error messages.
const SPEED_RANGE: &str = "1 + 5e-5 <= c <= 1000 (the range the tip solver resolves to ~1e-10; \
                           at dx = 0 the closed form c = 1/sqrt(1 - u_plus^2) is exact for any \
                           u_plus: bk.front_speed)";
/// At dx = 0, the u_+ of the range ends: u_+(1 + 5e-5) = 0.00999963, u_+(1000) = 0.99999950.
const U_PLUS_RANGE: &str = "0.0099997 <= u_plus <= 0.99999949 at dx = 0 (fronts with \
                            1 + 5e-5 <= c <= 1000, the range the tip solver resolves to \
                            ~1e-10); the closed form bk.front_speed(u_plus) is exact for any \
                            0 < u_plus < 1";
const U_PLUS_TOO_LARGE: &str = "a u_plus whose front has c <= 1000 (the tip solver's range; its \
                                round-off grows like c^2)";

/// Real positive root lambda of lambda = 2 sinh(lambda T/2), T = 1/c, c > 1: the decay
/// rate of the slowest transient behind the tip. With y = lambda T/2: sinh(y)/y = c.
pub fn slowest_decay_rate(c: f64) -> f64 {
    // initial guess: small y: 1 + y^2/6 = c; large y: y - ln(2y) = ln c
    let mut y = if c < 2.0 {
        (6.0 * (c - 1.0)).sqrt()
    } else {
        (2.0 * c).ln() + (2.0 * c).ln().ln()
    };
    y = y.max(1e-300);
    for _ in 0..100 {
        // f(y) = ln(sinh y / y) - ln c, monotone increasing and nearly linear
        let f = if y < 1e-4 {
            (y * y / 6.0).ln_1p()
        } else {
            (y.sinh() / y).ln()
        } - c.ln();
        let fp = if y < 1e-4 {
            y / 3.0
        } else {
            1.0 / y.tanh() - 1.0 / y
        };
        let step = f / fp;
        let next = (y - step).max(0.5 * y);
        if (next - y).abs() <= 1e-15 * y {
            y = next;
            break;
        }
        y = next;
    }
    2.0 * y * c
}

/// Solve the tip problem for front speed c > 1: returns theta = (1 - u_+)/u_+ and u_+.
/// At dx > 0 the solution must lie in the domain where it is the discrete chain's steady
/// front ([`crate::speed::check_lattice_front`]: the tip problem lets every block slide for
/// ever, the chain re-sticks them w/dx spacings behind the tip); outside it the error names
/// u_plus, dx and gamma. [`solve_linear_for_speed`] skips that check.
pub fn solve_for_speed(c: f64, opts: &TipOptions) -> Result<TipSolution> {
    let s = solve_linear_for_speed(c, opts)?;
    check_chain_domain(s.u_plus, s.c, opts)?;
    Ok(s)
}

/// The chain-domain check of [`solve_for_speed`] and [`solve_for_u_plus`] (none at dx = 0,
/// where no block re-sticks within the tip region).
fn check_chain_domain(u_plus: f64, c: f64, opts: &TipOptions) -> Result<()> {
    if opts.dx > 0.0 {
        crate::speed::check_lattice_front(u_plus, c, opts.dx, opts.gamma)?;
    }
    Ok(())
}

/// The linear tip problem for front speed c > 1 as stated (every block behind the tip
/// slides for ever), without the chain-domain check of [`solve_for_speed`].
pub fn solve_linear_for_speed(c: f64, opts: &TipOptions) -> Result<TipSolution> {
    opts.validate()?;
    let c = check_open("c", c, 1.0, f64::INFINITY, "c > 1 (fronts are supersonic)")?;
    if !(c - 1.0 >= MIN_SPEED_EXCESS && c <= MAX_SPEED) {
        return Err(Error::InvalidParameter {
            name: "c",
            value: c,
            allowed: SPEED_RANGE,
        });
    }
    let t = 1.0 / c;
    let lambda = slowest_decay_rate(c);
    let per_interval = lambda * t;
    let intervals_f = (opts.decay / per_interval).ceil() + 4.0;
    if intervals_f.is_nan() || intervals_f > opts.max_intervals as f64 {
        return Err(Error::NoConvergence {
            what: "tip problem",
            detail: format!(
                "c = {c} needs {intervals_f} intervals (> max_intervals = {}); c is too close to 1",
                opts.max_intervals
            ),
        });
    }
    let nint = intervals_f as usize;
    let n = opts.degree;
    let m = n + 1;
    let (_, d) = chebyshev_lobatto(n, t);
    let d2 = matmul(&d, &d, m);
    let (eps, gam) = (opts.dx, opts.gamma);
    let (e2, ge) = (eps * eps, 2.0 * gam * eps);
    // g = A t^2 + h with A = 1/(2(1 - T^2)): A t^2 is the exact far-field growth of the
    // continuum problem, so h stays small and theta = A T^2 + h(T) keeps its digits.
    let amp = 0.5 / ((1.0 - t) * (1.0 + t));
    let (tau, _) = chebyshev_lobatto(n, t);
    let size = nint * m;
    let mut a = BandMatrix::zeros(size, 2 * m - 1, 2 * m - 1);
    let mut b = vec![0.0; size];
    for j in 0..nint {
        let o = j * m;
        // value continuity h_j(0) = h_{j-1}(T)   (h_{-1} = 0: the block was stuck)
        a.add(o, o, 1.0);
        if j > 0 {
            a.add(o, o - m + n, -1.0);
        }
        // slope continuity h_j'(0) = h_{j-1}'(T)
        for k in 0..m {
            a.add(o + n, o + k, d[k]);
            if j > 0 {
                a.add(o + n, o - m + k, -d[n * m + k]);
            }
        }
        let last = j + 1 == nint;
        let lead = if last { 1.0 - t * t } else { 1.0 };
        for r in 1..n {
            let row = o + r;
            for k in 0..m {
                a.add(row, o + k, lead * d2[r * m + k] + ge * d[r * m + k]);
            }
            let time = j as f64 * t + tau[r];
            // residual forcing of the subtracted A t^2 (terms of order dx)
            let mut rhs = -amp * time * (e2 * time + 4.0 * gam * eps);
            if last {
                // outer closure: (1 - T^2) g'' + 2 gamma dx g' + dx^2 g = 1
                a.add(row, o + r, e2);
            } else {
                a.add(row, o + r, 2.0 + e2);
                a.add(row, o + m + r, -1.0);
                if j > 0 {
                    a.add(row, o - m + r, -1.0);
                } else {
                    // first interval: the right neighbour is stuck, g(t - T) = 0
                    rhs -= amp * (time - t) * (time - t);
                }
            }
            b[row] = rhs;
        }
    }
    a.solve_refined(&mut b, 3)?;
    let theta = amp * t * t + b[n];
    let tip_velocity: f64 = 2.0 * amp * t + (0..m).map(|k| d[n * m + k] * b[k]).sum::<f64>();
    if !theta.is_finite() || theta <= 0.0 {
        return Err(Error::NoConvergence {
            what: "tip problem",
            detail: format!("non-physical threshold theta = {theta} at c = {c}"),
        });
    }
    Ok(TipSolution {
        c,
        theta,
        u_plus: 1.0 / (1.0 + theta),
        intervals: nint,
        decay_rate: lambda,
        tip_velocity,
    })
}

/// The front speed c for stress u_+ ahead, by root finding on [`solve_for_speed`]
/// in the variable ln(c - 1) (where ln theta is nearly linear at both ends), within the
/// solver's range 1 + [`MIN_SPEED_EXCESS`] <= c <= [`MAX_SPEED`]; a u_+ whose front lies
/// outside it is an error naming u_plus and the range. At dx > 0 the front must also lie in
/// the chain's domain of [`solve_for_speed`] ([`crate::speed::check_lattice_front`]).
pub fn solve_for_u_plus(u_plus: f64, opts: &TipOptions) -> Result<TipSolution> {
    let s = solve_linear_for_u_plus(u_plus, opts)?;
    // the given u_plus, not the solved 1/(1 + theta): u_plus = gamma is creep exactly
    check_chain_domain(u_plus, s.c, opts)?;
    Ok(s)
}

/// c(u_+) of the linear tip problem as stated, without the chain-domain check of
/// [`solve_for_u_plus`] (for comparisons with its closed form at gamma = 0).
pub fn solve_linear_for_u_plus(u_plus: f64, opts: &TipOptions) -> Result<TipSolution> {
    let u = check_open("u_plus", u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
    opts.validate()?;
    let out_of_range = |allowed| Error::InvalidParameter {
        name: "u_plus",
        value: u,
        allowed,
    };
    // (pulled in by 1e-12 so that 1 + exp(x) stays inside the range after rounding)
    let (x_lo, x_hi) = (
        MIN_SPEED_EXCESS.ln() + 1e-12,
        (MAX_SPEED - 1.0).ln() - 1e-12,
    );
    if opts.dx == 0.0 {
        // the continuum root is c = 1/sqrt(1 - u^2): check the range before solving
        let c = crate::speed::front_speed(u)?;
        if !(c - 1.0 >= MIN_SPEED_EXCESS && c <= MAX_SPEED) {
            return Err(out_of_range(U_PLUS_RANGE));
        }
    }
    let target_theta = (1.0 - u) / u;
    let target = target_theta.ln();
    let eval = |x: f64| -> Result<(f64, TipSolution)> {
        let s = solve_linear_for_speed(1.0 + x.exp(), opts).map_err(|e| match e {
            // at dx > 0 the outer equation's dx^2 g term can make the collocation system
            // singular (dx >> 1): no front the solver can reach, said in terms of dx
            Error::NoConvergence { .. } if opts.dx > 0.0 => Error::InvalidParameter {
                name: "dx",
                value: opts.dx,
                allowed: "a lattice spacing at which the finite-dx tip problem for this \
                          u_plus and gamma is solvable (here its collocation system is \
                          singular); measure the front in the chain: bk.chain.front \
                          (u_plus, gamma, dx), or bkwaves front",
            },
            e => e,
        })?;
        Ok((s.theta.ln() - target, s))
    };
    // theta decreases with c. Crude start that has both limits right within a factor 2.
    let x0 = (0.5 * u * u / (1.0 - u).sqrt()).ln().clamp(x_lo, x_hi);
    let (mut xa, (mut fa, sa)) = (x0, eval(x0)?);
    if fa == 0.0 {
        return Ok(sa);
    }
    let mut step = 0.5;
    let (mut xb, mut fb) = loop {
        let at_bound = if fa > 0.0 { xa >= x_hi } else { xa <= x_lo };
        if at_bound {
            return Err(out_of_range(if fa > 0.0 {
                U_PLUS_TOO_LARGE
            } else if opts.dx > 0.0 {
                // In the continuum the root is always supersonic; at finite dx with
                // damping the discrete front can be subsonic (c <= 1), outside this solver.
                "a stress with a supersonic steady front, c >= 1 + 5e-5; at this dx and \
                 gamma the discrete front is subsonic, marginal or too close to c = 1 for \
                 the tip solver (measure it in the chain: bk.chain.front(u_plus, gamma, \
                 dx), or bkwaves front)"
            } else {
                U_PLUS_RANGE
            }));
        }
        let xn = if fa > 0.0 { xa + step } else { xa - step }.clamp(x_lo, x_hi);
        let (fn_, sn) = eval(xn)?;
        if fn_ == 0.0 {
            return Ok(sn);
        }
        if (fn_ > 0.0) != (fa > 0.0) {
            break (xn, fn_);
        }
        xa = xn;
        fa = fn_;
        step *= 2.0;
    };
    // Illinois (modified regula falsi): superlinear and always bracketed. Stop when the
    // step in x = ln(c - 1) moves c by less than 1e-13 relative: dc/c = dx (c - 1)/c.
    // (Near c = 1 the solver's theta carries ~1e-7 relative noise, which moves c by far
    // less than that, so a tolerance on theta would never be met.)
    let mut side = 0i32;
    let mut x_prev = f64::NAN;
    for _ in 0..200 {
        let xc = (xa * fb - xb * fa) / (fb - fa);
        let (fc, sc) = eval(xc)?;
        let c = 1.0 + xc.exp();
        let tol = 1e-13 * c / (c - 1.0);
        if fc == 0.0 || (xc - x_prev).abs() < tol || (xb - xa).abs() < tol {
            // the reported u_plus = 1/(1 + theta) is the solved one; it must be the input
            // to the solver's precision in theta
            if (sc.theta / target_theta - 1.0).abs() > 1e-5 {
                return Err(Error::NoConvergence {
                    what: "tip speed root",
                    detail: format!(
                        "for u_plus = {u} the solved threshold theta = {} misses (1 - u_plus)/u_plus = {target_theta}",
                        sc.theta
                    ),
                });
            }
            return Ok(sc);
        }
        x_prev = xc;
        if (fc > 0.0) == (fb > 0.0) {
            xb = xc;
            fb = fc;
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            xa = xc;
            fa = fc;
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    Err(Error::NoConvergence {
        what: "tip speed root",
        detail: format!("200 iterations for u_plus = {u}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::speed::{front_speed, u_plus_of_speed};

    #[test]
    fn decay_rate_solves_its_equation() {
        for &c in &[1.0001, 1.05, 1.25, 2.0, 10.0, 1e4] {
            let l = slowest_decay_rate(c);
            let t = 1.0 / c;
            assert!(
                (l - 2.0 * (l * t / 2.0).sinh()).abs() < 1e-10 * l,
                "c = {c}"
            );
        }
    }

    #[test]
    fn continuum_tip_problem_gives_the_closed_form_speed() {
        let o = TipOptions::default();
        // round-off grows like 1/(c - 1)^2 as c -> 1 (see docs/theory.md)
        for &(c, tol) in &[
            (1.001, 2e-9),
            (1.01, 1e-10),
            (1.1, 1e-12),
            (1.25, 1e-13),
            (1.5, 1e-13),
            (2.0, 1e-13),
            (5.0, 1e-13),
            (30.0, 1e-13),
        ] {
            let s = solve_for_speed(c, &o).unwrap();
            let exact = u_plus_of_speed(c).unwrap();
            let err = (s.u_plus - exact).abs() / exact;
            assert!(err < tol, "c = {c}: {} vs {exact} ({err:e})", s.u_plus);
            assert!(s.tip_velocity > 0.0);
        }
    }

    #[test]
    fn converged_in_degree_and_length() {
        let base = solve_for_speed(1.2, &TipOptions::default()).unwrap();
        let finer = solve_for_speed(
            1.2,
            &TipOptions {
                degree: 24,
                decay: 60.0,
                ..Default::default()
            },
        )
        .unwrap();
        assert!((base.theta - finer.theta).abs() < 1e-12 * base.theta);
        let coarse = solve_for_speed(
            1.2,
            &TipOptions {
                degree: 6,
                ..Default::default()
            },
        )
        .unwrap();
        // a low degree shows a visible discretisation error (so the check can fail)
        assert!((coarse.theta - finer.theta).abs() > 1e-9 * base.theta);
        let short = solve_for_speed(
            1.2,
            &TipOptions {
                decay: 1.0,
                ..Default::default()
            },
        )
        .unwrap();
        assert!((short.theta - finer.theta).abs() > 1e-9 * base.theta);
    }

    #[test]
    fn inverse_finds_the_speed() {
        for &u in &[0.05, 0.3, 0.6, 0.95] {
            let s = solve_for_u_plus(u, &TipOptions::default()).unwrap();
            let c = front_speed(u).unwrap();
            assert!((s.c - c).abs() < 1e-10 * c, "u = {u}: {} vs {c}", s.c);
        }
    }

    #[test]
    fn finite_dx_approaches_the_continuum() {
        let c0 = front_speed(0.6).unwrap();
        let mut prev = f64::INFINITY;
        for &dx in &[0.2, 0.1, 0.05, 0.025] {
            let o = TipOptions {
                dx,
                gamma: 0.3,
                ..Default::default()
            };
            let s = solve_for_u_plus(0.6, &o).unwrap();
            let err = (s.c - c0).abs();
            assert!(err < prev, "dx = {dx}: error {err} did not shrink");
            prev = err;
        }
        assert!(prev < 0.05 * c0);
    }

    #[test]
    fn finite_dx_without_damping_matches_the_wiener_hopf_closed_form() {
        for &(u, dx) in &[(0.5, 0.1), (0.3, 0.05), (0.9, 0.2), (0.7, 0.4)] {
            let o = TipOptions {
                dx,
                ..Default::default()
            };
            // the linear problem and its closed form (with or without the chain's domain)
            let s = solve_linear_for_u_plus(u, &o).unwrap();
            let c = crate::speed::lattice_closed_form(u, dx).unwrap();
            assert!(
                (s.c - c).abs() < 1e-11 * c,
                "u = {u}, dx = {dx}: {} vs {c}",
                s.c
            );
        }
    }

    #[test]
    fn subsonic_discrete_front_is_reported_as_out_of_range() {
        // gamma = 0.45, dx = 0.1: the chain's front at u_+ = 0.3 moves at c = 0.99922
        let o = TipOptions {
            dx: 0.1,
            gamma: 0.45,
            max_intervals: 20_000,
            ..Default::default()
        };
        match solve_for_u_plus(0.3, &o) {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "u_plus"),
            other => panic!("expected an out-of-range error, got {other:?}"),
        }
        assert!(solve_for_u_plus(0.6, &o).unwrap().c > 1.0);
    }

    #[test]
    fn u_plus_outside_the_solvers_range_is_a_named_error() {
        let o = TipOptions::default();
        // used to return c 16% too high with u_plus = 4.5e-68, a negative-theta failure,
        // and a 26 s solve
        for &u in &[1.0 - 1e-12, 1.0 - 1e-7, 0.999_999_5, 5e-4, 1e-3, 9.99e-3] {
            match solve_for_u_plus(u, &o) {
                Err(Error::InvalidParameter { name, allowed, .. }) => {
                    assert_eq!(name, "u_plus");
                    assert!(
                        allowed.contains("u_plus") && allowed.contains("1000"),
                        "{allowed}"
                    );
                }
                other => panic!("u = {u}: expected a range error, got {other:?}"),
            }
        }
        // the ends of the range are solved, and match the closed form
        for &u in &[0.01, 0.999_999, 0.999_999_49] {
            let s = solve_for_u_plus(u, &o).unwrap();
            let c = front_speed(u).unwrap();
            assert!((s.c / c - 1.0).abs() < 1e-10, "u = {u}: {} vs {c}", s.c);
            assert!(
                (s.u_plus / u - 1.0).abs() < 1e-5,
                "u = {u}: reports {}",
                s.u_plus
            );
        }
        for &c in &[1.0 + 4e-5, 1001.0, 1e6] {
            assert!(matches!(
                solve_for_speed(c, &o),
                Err(Error::InvalidParameter { name: "c", .. })
            ));
        }
    }

    #[test]
    fn bad_options_are_errors() {
        assert!(solve_for_speed(0.9, &TipOptions::default()).is_err());
        let o = TipOptions {
            degree: 2,
            ..Default::default()
        };
        assert!(solve_for_speed(1.5, &o).is_err());
        let o = TipOptions {
            max_intervals: 10,
            ..Default::default()
        };
        assert!(solve_for_speed(1.000_001, &o).is_err());
    }
}
