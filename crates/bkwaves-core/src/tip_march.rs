//! The tip of a front marched in time through blocks with their own thresholds (quenched
//! disorder, docs/disorder.md): only a window of blocks around the tip is simulated, so
//! the cost per block does not grow with the distance travelled.
//!
//! The chain at v = 0 with the Coulomb law, forward slips only (beta = inf, the default
//! front), in the paper's variables (docs/chain.md, crate::chain::medium):
//!
//! ```text
//!   phi_i = u_i - (u_{i+1} + u_{i-1} - 2 u_i)/dx^2
//!   stuck:    u_i' = 0                    slips forward when phi_i >= s_i
//!   sliding:  u_i'' = -phi_i - 2 gamma u_i'  sticks when u_i' rises back to 0
//! ```
//!
//! (the per-block threshold s_i moves the static level only; the kinetic level is 0 for
//! every block, as in the chain's `PerBlock` medium). Ahead of the front every block is
//! stuck at u = u_+. In the tip variables of [`crate::tip`], u_i = u_+ - u_+ dx^2 w_i and
//! t = t_s + tau dx, a stuck block i whose right neighbour is still at u_+ has
//! phi_i = u_+ + u_+ w_{i-1}, so it slips when its left neighbour reaches
//!
//! ```text
//!   w_{i-1} = Theta_i = s_i/u_+ - 1       (uniform s_i = 1: theta = (1 - u_+)/u_+)
//! ```
//!
//! and sliding blocks obey w_i'' = w_{i+1} + w_{i-1} - 2 w_i + 1 - dx^2 w_i - 2 gamma dx w_i'.
//! A threshold s_i <= u_+ (Theta_i <= 0) would slip at t = 0 by itself and is refused.
//!
//! The front is supersonic (c > 1) and lattice signals travel at speed <= 1 (the lattice
//! Green's function J_2k(2t/dx) is super-exponentially small outside the light cone), so
//! the slip times at the tip do not depend on blocks far behind it. The march starts as
//! `bk.chain.front` does (free left end at block 0, every block stuck at u_+, block 0
//! kicked forward with speed [`crate::chain::front::KICK`]) and keeps the blocks from the
//! tip back to at least `behind` blocks behind it; the block just behind the window is held
//! at its position when it is dropped (a fixed end). The error this causes at the tip is
//! measured (tests: `behind` and 2 `behind` agree to < 1e-10 in every slip time).
//!
//! Between events the system is linear with constant coefficients: each step of length
//! `step dx` is a Taylor series of degree `order` in time (coefficients from the ODEs'
//! recursion, exact to round-off for order 20 at step 0.5: the fastest lattice frequency
//! is 2/dx, the remainder ~ 1/21!). Slips (phi_i - s_i of a stuck block crossing 0) and
//! sticks (u_i' of a sliding block crossing 0 upward) are located on these polynomials by
//! sampling and bisection to round-off, and the march restarts at each event, as the chain
//! does with its RK4 steps.

use crate::error::{check_at_least, check_open, Error, Result};

/// Settings of the marcher.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarchOptions {
    /// Lattice spacing dx.
    pub dx: f64,
    /// Viscous damping gamma.
    pub gamma: f64,
    /// Blocks kept behind the tip (at least; the window is trimmed in chunks).
    pub behind: usize,
    /// Time step as a fraction of dx.
    pub step: f64,
    /// Degree of the Taylor series per step.
    pub order: usize,
}

impl MarchOptions {
    /// Defaults at this dx and gamma: 64 blocks behind, steps of dx/2, degree 20.
    pub fn new(dx: f64, gamma: f64) -> Self {
        MarchOptions {
            dx,
            gamma,
            behind: 64,
            step: 0.5,
            order: 20,
        }
    }

    fn validate(&self) -> Result<()> {
        check_open("dx", self.dx, 0.0, 1.0, "0 < dx < 1")?;
        check_at_least("gamma", self.gamma, 0.0, "gamma >= 0")?;
        if !(self.step > 0.0 && self.step <= 1.0) {
            return Err(Error::InvalidParameter {
                name: "step",
                value: self.step,
                allowed: "0 < step <= 1 (a fraction of dx)",
            });
        }
        if self.behind < 4 {
            return Err(Error::InvalidParameter {
                name: "behind",
                value: self.behind as f64,
                allowed: "behind >= 4 blocks",
            });
        }
        if !(8..=40).contains(&self.order) {
            return Err(Error::InvalidParameter {
                name: "order",
                value: self.order as f64,
                allowed: "8 <= order <= 40",
            });
        }
        Ok(())
    }
}

/// What a march found.
#[derive(Debug, Clone, PartialEq)]
pub struct MarchResult {
    /// First slip time of every block (block 0: 0, its kick; NaN if never reached).
    pub slip_times: Vec<f64>,
    /// True if the front stopped before the last block (no slip ahead for a long time).
    pub stopped: bool,
    /// Taylor steps taken (including the ones cut short at events).
    pub steps: u64,
    /// Slip and stick events located.
    pub events: u64,
    /// Largest number of blocks simulated at once.
    pub max_window: usize,
}

/// The left end of the window: the chain's free end (block 0 still in the window) or the
/// fixed position of the last dropped block.
#[derive(Debug, Clone, Copy)]
enum Tail {
    Free,
    Held(f64),
}

/// Blocks dropped from the tail at once (amortises the shift of the window's arrays).
const DROP: usize = 32;
/// Sub-intervals of a step sampled for sign changes before bisection.
const SAMPLES: usize = 4;

/// March a front into blocks with thresholds `threshold` (block i slips forward when
/// u_i - Lap_i/dx^2 >= threshold[i]) at stress u_plus ahead, started as
/// `bk.chain.front` starts it, until the last block slips.
pub fn march(u_plus: f64, threshold: &[f64], o: &MarchOptions) -> Result<MarchResult> {
    check_open("u_plus", u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
    o.validate()?;
    let n = threshold.len();
    if n < 2 {
        return Err(Error::Invalid {
            name: "threshold".into(),
            value: format!("{n} values"),
            allowed: "at least 2 blocks".into(),
        });
    }
    for (i, &s) in threshold.iter().enumerate() {
        if !(s.is_finite() && s > u_plus) {
            return Err(Error::Invalid {
                name: format!("threshold[{i}]"),
                value: format!("{s}"),
                allowed: format!(
                    "finite threshold > u_plus = {u_plus} (a block at or below u_plus slips \
                     by itself at t = 0)"
                ),
            });
        }
    }
    let mut m = Marcher::new(u_plus, threshold, o);
    m.run();
    Ok(MarchResult {
        slip_times: m.first,
        stopped: m.stopped,
        steps: m.steps,
        events: m.events,
        max_window: m.max_window,
    })
}

struct Marcher<'a> {
    u_plus: f64,
    s: &'a [f64],
    dx: f64,
    inv_dx2: f64,
    gamma: f64,
    behind: usize,
    h: f64,
    order: usize,
    /// Global index of window block 0.
    lo: usize,
    tail: Tail,
    u: Vec<f64>,
    p: Vec<f64>,
    sliding: Vec<bool>,
    /// Taylor coefficients, coef[k * width + j] (width = current window length).
    coef: Vec<f64>,
    t: f64,
    first: Vec<f64>,
    stopped: bool,
    steps: u64,
    events: u64,
    max_window: usize,
}

#[derive(Clone, Copy)]
enum Event {
    Slip(usize),
    Stick(usize),
}

impl<'a> Marcher<'a> {
    fn new(u_plus: f64, s: &'a [f64], o: &MarchOptions) -> Self {
        let mut first = vec![f64::NAN; s.len()];
        first[0] = 0.0;
        Marcher {
            u_plus,
            s,
            dx: o.dx,
            inv_dx2: 1.0 / (o.dx * o.dx),
            gamma: o.gamma,
            behind: o.behind,
            h: o.step * o.dx,
            order: o.order,
            lo: 0,
            tail: Tail::Free,
            // block 0 kicked forward, block 1 stuck at u_+ (the rest implicit at u_+)
            u: vec![u_plus, u_plus],
            p: vec![-crate::chain::front::KICK, 0.0],
            sliding: vec![true, false],
            coef: Vec::new(),
            t: 0.0,
            first,
            stopped: false,
            steps: 0,
            events: 0,
            max_window: 2,
        }
    }

    fn width(&self) -> usize {
        self.u.len()
    }

    /// Taylor coefficient k of the left neighbour of window block 0.
    fn left_ghost(&self, k: usize) -> f64 {
        match self.tail {
            // free end: the ghost moves with block 0 (no coupling force)
            Tail::Free => self.coef[k * self.width()],
            Tail::Held(x) => {
                if k == 0 {
                    x
                } else {
                    0.0
                }
            }
        }
    }

    /// Taylor coefficient k of the right neighbour of the last window block (stuck at u_+).
    fn right_ghost(&self, k: usize) -> f64 {
        if k == 0 {
            self.u_plus
        } else {
            0.0
        }
    }

    /// Coefficient k of window block j's neighbour at offset -1 or +1.
    fn neighbour(&self, k: usize, j: usize, right: bool) -> f64 {
        let w = self.width();
        if right {
            if j + 1 < w {
                self.coef[k * w + j + 1]
            } else {
                self.right_ghost(k)
            }
        } else if j > 0 {
            self.coef[k * w + j - 1]
        } else {
            self.left_ghost(k)
        }
    }

    fn taylor(&mut self) {
        let w = self.width();
        let kmax = self.order;
        self.coef.clear();
        self.coef.resize((kmax + 1) * w, 0.0);
        self.coef[..w].copy_from_slice(&self.u);
        for j in 0..w {
            if self.sliding[j] {
                self.coef[w + j] = self.p[j];
            }
        }
        // only the range of sliding blocks has nonzero coefficients of order >= 1
        let (Some(first), Some(last)) = (
            self.sliding.iter().position(|&x| x),
            self.sliding.iter().rposition(|&x| x),
        ) else {
            return;
        };
        let mask: Vec<f64> = self
            .sliding
            .iter()
            .map(|&x| f64::from(u8::from(x)))
            .collect();
        let (inner_lo, inner_hi) = (first.max(1), (last + 1).min(w - 1));
        // (k+1)(k+2) c_{k+2} = Lap(c_k)/dx^2 - c_k - 2 gamma (k+1) c_{k+1}
        for k in 0..kmax - 1 {
            let g2 = 2.0 * self.gamma * (k + 1) as f64;
            let den = 1.0 / ((k + 1) * (k + 2)) as f64;
            {
                let (head, tail) = self.coef.split_at_mut((k + 2) * w);
                let rk = &head[k * w..(k + 1) * w];
                let rk1 = &head[(k + 1) * w..(k + 2) * w];
                let out = &mut tail[..w];
                for j in inner_lo..inner_hi {
                    let lap = rk[j - 1] + rk[j + 1] - 2.0 * rk[j];
                    out[j] = mask[j] * ((lap * self.inv_dx2 - rk[j] - g2 * rk1[j]) * den);
                }
            }
            // the window's ends: their neighbours are the ghosts
            for j in [0, w - 1] {
                if self.sliding[j] {
                    let ck = self.coef[k * w + j];
                    let lap = self.neighbour(k, j, false) + self.neighbour(k, j, true) - 2.0 * ck;
                    let rhs = lap * self.inv_dx2 - ck - g2 * self.coef[(k + 1) * w + j];
                    self.coef[(k + 2) * w + j] = rhs * den;
                }
            }
        }
    }

    /// u of window block j at time tau into the step.
    fn value(&self, j: usize, tau: f64) -> f64 {
        let w = self.width();
        if !self.sliding[j] {
            return self.u[j];
        }
        let mut acc = 0.0;
        for k in (0..=self.order).rev() {
            acc = acc * tau + self.coef[k * w + j];
        }
        acc
    }

    /// u' of window block j at tau.
    fn velocity(&self, j: usize, tau: f64) -> f64 {
        let w = self.width();
        if !self.sliding[j] {
            return 0.0;
        }
        let mut acc = 0.0;
        for k in (1..=self.order).rev() {
            acc = acc * tau + k as f64 * self.coef[k * w + j];
        }
        acc
    }

    /// phi - threshold of the stuck window block j at tau.
    fn slip_margin(&self, j: usize, tau: f64) -> f64 {
        let g = self.lo + j;
        let ul = if j > 0 {
            self.value(j - 1, tau)
        } else {
            match self.tail {
                Tail::Free => self.u[0],
                Tail::Held(x) => x,
            }
        };
        let ur = if j + 1 < self.width() {
            self.value(j + 1, tau)
        } else {
            self.u_plus
        };
        let uj = self.u[j];
        uj - (ul + ur - 2.0 * uj) * self.inv_dx2 - self.s[g]
    }

    /// First tau in (0, limit] where f crosses from < 0 to >= 0 (f < 0 just after 0 is
    /// assumed), located by bisection to round-off (the >= 0 end); None if none is seen.
    fn first_crossing(&self, f: impl Fn(f64) -> f64, limit: f64) -> Option<f64> {
        let dt = self.h / SAMPLES as f64;
        let mut a = 0.0;
        let mut k = 1;
        while a < limit {
            let b = (k as f64 * dt).min(limit);
            if f(b) >= 0.0 {
                let (mut lo, mut hi) = (a, b);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    if f(mid) >= 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Some(hi);
            }
            a = b;
            k += 1;
        }
        None
    }

    fn earliest_event(&self) -> Option<(f64, Event)> {
        let w = self.width();
        let mut best: Option<(f64, Event)> = None;
        for j in 0..w {
            let limit = best.map_or(self.h, |b| b.0);
            if self.sliding[j] {
                let p0 = self.p[j];
                // sliding forward means u' < 0; at onset u' = 0 and u'' = -phi < 0
                let onset_down = p0 == 0.0 && self.coef[2 * w + j] < 0.0;
                if p0 > 0.0 || (p0 == 0.0 && !onset_down) {
                    return Some((0.0, Event::Stick(j)));
                }
                // u' <= p0 + sum_k k |c_k| limit^(k-1) on [0, limit]: no crossing if < 0
                let mut bound = 0.0;
                for k in (2..=self.order).rev() {
                    bound = bound * limit + k as f64 * self.coef[k * w + j].abs();
                }
                if p0 + bound * limit < 0.0 {
                    continue;
                }
                if let Some(tau) = self.first_crossing(|x| self.velocity(j, x), limit) {
                    if best.is_none_or(|b| tau < b.0) {
                        best = Some((tau, Event::Stick(j)));
                    }
                }
            } else {
                let moving_left = j > 0 && self.sliding[j - 1];
                let moving_right = j + 1 < w && self.sliding[j + 1];
                if !(moving_left || moving_right) {
                    continue;
                }
                if self.slip_margin(j, 0.0) >= 0.0 {
                    return Some((0.0, Event::Slip(j)));
                }
                if let Some(tau) = self.first_crossing(|x| self.slip_margin(j, x), limit) {
                    if best.is_none_or(|b| tau < b.0) {
                        best = Some((tau, Event::Slip(j)));
                    }
                }
            }
        }
        best
    }

    fn advance(&mut self, tau: f64) {
        for j in 0..self.width() {
            if self.sliding[j] {
                let (u, p) = (self.value(j, tau), self.velocity(j, tau));
                self.u[j] = u;
                self.p[j] = p;
            }
        }
        self.t += tau;
    }

    fn run(&mut self) {
        let n = self.s.len();
        let patience = 10.0 + 100.0 * self.dx;
        let mut last_progress = 0.0;
        loop {
            if !self.first[n - 1].is_nan() {
                return;
            }
            if !self.sliding.iter().any(|&x| x) || self.t - last_progress > patience {
                self.stopped = true;
                return;
            }
            self.taylor();
            self.steps += 1;
            match self.earliest_event() {
                None => {
                    let h = self.h;
                    self.advance(h);
                }
                Some((tau, ev)) => {
                    self.advance(tau);
                    self.events += 1;
                    match ev {
                        Event::Stick(j) => {
                            self.sliding[j] = false;
                            self.p[j] = 0.0;
                        }
                        Event::Slip(j) => {
                            self.sliding[j] = true;
                            self.p[j] = 0.0;
                            let g = self.lo + j;
                            if self.first[g].is_nan() {
                                self.first[g] = self.t;
                                last_progress = self.t;
                            }
                            if j + 1 == self.width() && g + 1 < n {
                                self.u.push(self.u_plus);
                                self.p.push(0.0);
                                self.sliding.push(false);
                                self.max_window = self.max_window.max(self.width());
                            }
                            self.trim(g);
                        }
                    }
                }
            }
        }
    }

    /// Drop blocks more than `behind` behind the tip block `tip` (in chunks of DROP).
    fn trim(&mut self, tip: usize) {
        if tip >= self.lo + self.behind + DROP {
            let held = self.u[DROP - 1];
            self.u.drain(..DROP);
            self.p.drain(..DROP);
            self.sliding.drain(..DROP);
            self.lo += DROP;
            self.tail = Tail::Held(held);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tip::{solve_for_u_plus, TipOptions};

    fn speed(ts: &[f64], a: usize, dx: f64) -> f64 {
        let b = ts.len() - 1;
        dx * (b - a) as f64 / (ts[b] - ts[a])
    }

    #[test]
    fn uniform_thresholds_give_the_collocation_tip_speed() {
        for &(u, gamma, dx) in &[(0.5, 0.0, 0.1), (0.6, 0.3, 0.1), (0.8, 0.45, 0.05)] {
            let o = MarchOptions::new(dx, gamma);
            let r = march(u, &vec![1.0; 400], &o).unwrap();
            assert!(!r.stopped);
            let c = speed(&r.slip_times, 200, dx);
            let tip = solve_for_u_plus(
                u,
                &TipOptions {
                    dx,
                    gamma,
                    ..Default::default()
                },
            )
            .unwrap()
            .c;
            assert!((c / tip - 1.0).abs() < 1e-10, "u {u}: {c} vs {tip}");
            // every interval far behind the trigger is the steady one
            for i in 200..399 {
                let dt = r.slip_times[i + 1] - r.slip_times[i];
                assert!((dt * tip / dx - 1.0).abs() < 1e-9, "block {i}");
            }
            assert!(r.max_window <= o.behind + DROP + 2);
        }
    }

    #[test]
    fn truncation_behind_the_tip_does_not_reach_it() {
        let th: Vec<f64> = (0..600)
            .map(|i| 1.0 + 0.1 * ((i as f64 * 0.7).sin() + (i as f64 * 0.31).cos()) / 2.0)
            .collect();
        let run = |behind| {
            let o = MarchOptions {
                behind,
                ..MarchOptions::new(0.1, 0.2)
            };
            march(0.6, &th, &o).unwrap().slip_times
        };
        let (short, long) = (run(32), run(128));
        let worst = short
            .iter()
            .zip(&long)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-10, "{worst}");
        // a window too short is visible (so the check can fail)
        let tiny = run(4);
        let off = tiny
            .iter()
            .zip(&long)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(off > 1e-8, "{off}");
    }

    #[test]
    fn step_and_order_converged() {
        let th: Vec<f64> = (0..300)
            .map(|i| 1.0 + 0.08 * (i as f64 * 1.3).sin())
            .collect();
        let base = march(0.5, &th, &MarchOptions::new(0.1, 0.1)).unwrap();
        let fine = march(
            0.5,
            &th,
            &MarchOptions {
                step: 0.25,
                order: 24,
                ..MarchOptions::new(0.1, 0.1)
            },
        )
        .unwrap();
        for (a, b) in base.slip_times.iter().zip(&fine.slip_times) {
            assert!((a - b).abs() < 1e-11 * b.max(1.0), "{a} vs {b}");
        }
        let coarse = march(
            0.5,
            &th,
            &MarchOptions {
                step: 1.0,
                order: 8,
                ..MarchOptions::new(0.1, 0.1)
            },
        )
        .unwrap();
        let off = coarse
            .slip_times
            .iter()
            .zip(&fine.slip_times)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(off > 1e-9, "{off}");
    }

    #[test]
    fn bad_thresholds_name_the_block() {
        let o = MarchOptions::new(0.1, 0.0);
        let e = march(0.6, &[1.0, 1.0, 0.55, 1.0], &o)
            .unwrap_err()
            .to_string();
        assert!(e.contains("threshold[2]") && e.contains("u_plus"), "{e}");
        assert!(march(1.2, &[1.0; 4], &o).is_err());
        let bad = MarchOptions { behind: 1, ..o };
        assert!(march(0.6, &[1.0; 4], &bad).is_err());
    }
}
