//! Time stepping of the sliding blocks: one file per method behind [`Integrator`].
//!
//! - [`rk4`]: classical RK4 (default; order 4; the energy books close to O(h^4));
//! - [`midpoint`]: the implicit midpoint rule (order 2; conserves quadratic invariants, so
//!   the energy books close to round-off: E(t+h) - E(t) = h P(midpoint) exactly).
//!
//! Only blocks in runs of sliding blocks are stepped; the stuck neighbours at the ends
//! of a run enter through their exact drift u = u_ref + v (t - t_ref), evaluated at each
//! stage time, and the chain ends through their ghosts. The loader work and the
//! dissipated power are integrated by the same stages (an augmented system), so the
//! energy books close to the order of the method.

pub mod midpoint;
pub mod rk4;

pub use midpoint::Midpoint;
pub use rk4::Rk4;

use super::state::State;
use crate::boundary::Ghost;
use crate::friction::Friction;

/// Sums over the sliding blocks at one stage: displacement (for the loader work), dry
/// friction power and viscous power.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageSums {
    /// sum of u over the sliding blocks.
    pub u: f64,
    /// sum of the dry-friction power.
    pub dry: f64,
    /// sum of the viscous power.
    pub visc: f64,
}

/// The quadrature of a step: integrals over [t0, t0 + h] of the stage sums.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepIntegrals {
    /// integral of sum_sliding u dt.
    pub u: f64,
    /// dry-friction work.
    pub dry: f64,
    /// viscous work.
    pub visc: f64,
}

/// An explicit one-step method for the sliding blocks, with a dense output given by the
/// end-point values and derivatives (cubic Hermite).
pub trait Integrator: std::fmt::Debug + Send {
    /// Name in outputs.
    fn name(&self) -> &'static str;
    /// Order of convergence.
    fn order(&self) -> u32;
    /// Acceleration of every sliding block at the state's current time t into `acc`,
    /// returning the stage sums there.
    fn accel<F: Friction>(&mut self, st: &mut State, fr: &F, t: f64, acc: &mut [f64]) -> StageSums
    where
        Self: Sized;
    /// Advance the sliding blocks from t0 to t0 + h. `a0` holds the accelerations at
    /// t0 (from [`Integrator::accel`]) with their sums `s0`; the start state is saved
    /// in `u0`, `w0` for the dense output and for a redo.
    #[allow(clippy::too_many_arguments)]
    fn step<F: Friction>(
        &mut self,
        st: &mut State,
        fr: &F,
        t0: f64,
        h: f64,
        a0: &[f64],
        s0: StageSums,
        u0: &mut [f64],
        w0: &mut [f64],
    ) -> StepIntegrals
    where
        Self: Sized;
}

/// Fill the stage displacement of the neighbours of every run (stuck blocks by their
/// exact drift, ghosts by the boundary) at stage time ts. Sliding values in `su` must
/// already be set.
/// Accelerations of the sliding blocks at the present state, time t, using `su` as the
/// stage buffer (the first stage of every integrator).
pub(crate) fn accel_at_state<F: Friction>(
    st: &State,
    fr: &F,
    su: &mut [f64],
    t: f64,
    acc: &mut [f64],
) -> StageSums {
    for &(a, b) in &st.runs {
        su[a..b].copy_from_slice(&st.u[a..b]);
    }
    fill_neighbours(st, su, t);
    stage_accel(st, fr, su, &st.w, acc)
}

pub(crate) fn fill_neighbours(st: &State, su: &mut [f64], ts: f64) {
    let n = st.n;
    for &(a, b) in &st.runs {
        for q in [a - 1, b] {
            let val = if q == 0 || q == n + 1 {
                let (g, edge) = if q == 0 { (st.left, 1) } else { (st.right, n) };
                match g {
                    Ghost::Mirror => su[edge],
                    Ghost::Held(g0) => g0 + st.v * ts,
                    Ghost::Wrap => {
                        let r = if q == 0 { n } else { 1 };
                        if st.sliding(r) {
                            su[r]
                        } else {
                            st.stuck_u(r, ts)
                        }
                    }
                }
            } else {
                st.stuck_u(q, ts)
            };
            su[q] = val;
        }
    }
}

/// Accelerations of all sliding blocks from stage values su, sw.
#[inline]
pub(crate) fn stage_accel<F: Friction>(
    st: &State,
    fr: &F,
    su: &[f64],
    sw: &[f64],
    acc: &mut [f64],
) -> StageSums {
    let (v, k) = (st.v, st.inv_dx2);
    let mut sums = StageSums::default();
    for &(a, b) in &st.runs {
        let dir = &st.dir[a..b];
        let u = &su[a - 1..b + 1];
        let w = &sw[a..b];
        let out = &mut acc[a..b];
        let (mut su_, mut sd, mut sv) = (0.0, 0.0, 0.0);
        for i in 0..b - a {
            let ui = u[i + 1];
            let s = v - w[i];
            out[i] = (u[i] + u[i + 2] - 2.0 * ui) * k - ui + fr.excess(s, dir[i]);
            let (pd, pv) = fr.power(s, dir[i]);
            su_ += ui;
            sd += pd;
            sv += pv;
        }
        sums.u += su_;
        sums.dry += sd;
        sums.visc += sv;
    }
    sums
}

/// The integrators by name (the registry).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Classical fourth-order Runge-Kutta.
    Rk4,
    /// Implicit midpoint rule (energy books to round-off).
    Midpoint,
}

impl Method {
    /// Parse a method name.
    pub fn by_name(name: &str) -> crate::error::Result<Method> {
        match name {
            "rk4" => Ok(Method::Rk4),
            "midpoint" => Ok(Method::Midpoint),
            _ => Err(crate::error::Error::InvalidParameter {
                name: "integrator",
                value: f64::NAN,
                allowed: "one of rk4, midpoint",
            }),
        }
    }
}

/// One of the integrators (static dispatch).
#[derive(Debug, Clone)]
pub enum Stepper {
    /// RK4.
    Rk4(Rk4),
    /// Implicit midpoint.
    Midpoint(Midpoint),
}

impl Stepper {
    /// Buffers for n blocks.
    pub fn new(method: Method, n: usize) -> Self {
        match method {
            Method::Rk4 => Stepper::Rk4(Rk4::new(n)),
            Method::Midpoint => Stepper::Midpoint(Midpoint::new(n)),
        }
    }
    /// Name of the method.
    pub fn name(&self) -> &'static str {
        match self {
            Stepper::Rk4(m) => m.name(),
            Stepper::Midpoint(m) => m.name(),
        }
    }
    /// See [`Integrator::accel`].
    pub fn accel<F: Friction>(
        &mut self,
        st: &mut State,
        fr: &F,
        t: f64,
        acc: &mut [f64],
    ) -> StageSums {
        match self {
            Stepper::Rk4(m) => m.accel(st, fr, t, acc),
            Stepper::Midpoint(m) => m.accel(st, fr, t, acc),
        }
    }
    /// See [`Integrator::step`].
    #[allow(clippy::too_many_arguments)]
    pub fn step<F: Friction>(
        &mut self,
        st: &mut State,
        fr: &F,
        t0: f64,
        h: f64,
        a0: &[f64],
        s0: StageSums,
        u0: &mut [f64],
        w0: &mut [f64],
    ) -> StepIntegrals {
        match self {
            Stepper::Rk4(m) => m.step(st, fr, t0, h, a0, s0, u0, w0),
            Stepper::Midpoint(m) => m.step(st, fr, t0, h, a0, s0, u0, w0),
        }
    }
}
