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

use super::medium::{Blocks, Medium};
use super::state::{Beyond, State};
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
    fn accel<F: Friction, M: Medium>(
        &mut self,
        st: &mut State,
        fr: &Blocks<F, M>,
        t: f64,
        acc: &mut [f64],
    ) -> StageSums
    where
        Self: Sized;
    /// Advance the sliding blocks from t0 to t0 + h. `a0` holds the accelerations at
    /// t0 (from [`Integrator::accel`]) with their sums `s0`; the start state is saved
    /// in `u0`, `w0` for the dense output and for a redo.
    #[allow(clippy::too_many_arguments)]
    fn step<F: Friction, M: Medium>(
        &mut self,
        st: &mut State,
        fr: &Blocks<F, M>,
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
pub(crate) fn accel_at_state<F: Friction, M: Medium>(
    st: &State,
    fr: &Blocks<F, M>,
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
                let edge = if q == 0 { 1 } else { n };
                match st.beyond(q, edge) {
                    Beyond::Block(r) if st.sliding(r) => su[r],
                    Beyond::Block(r) => st.stuck_u(r, ts),
                    Beyond::Wall(g0) => g0 + st.v * ts,
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
pub(crate) fn stage_accel<F: Friction, M: Medium>(
    st: &State,
    fr: &Blocks<F, M>,
    su: &[f64],
    sw: &[f64],
    acc: &mut [f64],
) -> StageSums {
    let (v, k) = (st.v, st.inv_dx2);
    let mut sums = StageSums::default();
    for &(a, b) in &st.runs {
        let dir = &st.dir[a..b];
        let th = &st.onset[a..b];
        let u = &su[a - 1..b + 1];
        let w = &sw[a..b];
        let out = &mut acc[a..b];
        let (mut su_, mut sd, mut sv) = (0.0, 0.0, 0.0);
        for i in 0..b - a {
            let p = a + i;
            let ui = u[i + 1];
            let s = v - w[i];
            out[i] = fr.accel(p, u[i], ui, u[i + 2], s, dir[i], th[i], k);
            let (pd, pv) = fr.fr.power(s, dir[i], th[i]);
            // the loader work rate is v sum (k_p,i u_i + beta)
            su_ += fr.med.loader(p) * ui;
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
    /// The registry: every method with its name, order and one line of doc (the first is
    /// the default).
    pub const ALL: &'static [(Method, &'static str, u32, &'static str)] = &[
        (
            Method::Rk4,
            "rk4",
            4,
            "classical fourth-order Runge-Kutta (default)",
        ),
        (
            Method::Midpoint,
            "midpoint",
            2,
            "implicit midpoint rule: energy books closed to round-off (step <= 0.5)",
        ),
    ];

    /// Parse a method name; an unknown name is an error listing the known ones.
    pub fn by_name(name: &str) -> crate::error::Result<Method> {
        match Method::ALL.iter().find(|m| m.1 == name) {
            Some(m) => Ok(m.0),
            None => Err(crate::error::Error::Invalid {
                name: "integrator".to_string(),
                value: format!("{name:?}"),
                allowed: format!(
                    "one of: {}",
                    Method::ALL
                        .iter()
                        .map(|m| m.1)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
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
    pub fn accel<F: Friction, M: Medium>(
        &mut self,
        st: &mut State,
        fr: &Blocks<F, M>,
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
    pub fn step<F: Friction, M: Medium>(
        &mut self,
        st: &mut State,
        fr: &Blocks<F, M>,
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
