//! The implicit midpoint rule for the runs of sliding blocks.
//!
//! y1 = y0 + h f(t0 + h/2, (y0 + y1)/2). Between events the chain is linear, and for a
//! quadratic energy E(y, t) (the loader frame makes fixed-end walls move linearly in t),
//! E(y1) - E(y0) = grad E(y_m) . (y1 - y0) exactly, = h P(y_m, t_m) with P the power
//! balance dE/dt: the energy books close to round-off when the loader work and the
//! dissipation are booked as h times their midpoint rates. The midpoint equations
//! w_m = w0 + h/2 a(u0 + h/2 w_m, w_m) are solved by fixed-point iteration, a contraction
//! with factor about (h/dx)^2 + h gamma, iterated to round-off.

use super::{
    accel_only_at_state, fill_neighbours, stage_accel, stage_sums, Integrator, StageSums,
    StepIntegrals,
};
use crate::chain::geometry::Geometry;
use crate::chain::medium::{Blocks, Medium};
use crate::chain::state::State;
use crate::friction::Friction;

/// Implicit midpoint rule (order 2).
#[derive(Debug, Clone, Default)]
pub struct Midpoint {
    su: Vec<f64>,
    sw: Vec<f64>,
    acc: Vec<f64>,
    /// Fixed-point iterations done (all steps).
    pub iterations: u64,
    /// Whether the last step's fixed-point iteration converged (its last change <= 1e-10
    /// of the velocities' scale; it stops earlier, at round-off, when it can).
    pub converged: bool,
    /// The energy flows of the last step: h times the stage sums at the midpoint.
    last: StepIntegrals,
}

impl Midpoint {
    /// Buffers for a chain of n blocks.
    pub fn new(n: usize) -> Self {
        Midpoint {
            su: vec![0.0; n + 2],
            sw: vec![0.0; n + 2],
            acc: vec![0.0; n + 2],
            iterations: 0,
            converged: true,
            last: StepIntegrals::default(),
        }
    }
}

impl Integrator for Midpoint {
    fn name(&self) -> &'static str {
        "midpoint"
    }
    fn order(&self) -> u32 {
        2
    }

    fn accel_only<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t: f64,
        acc: &mut [f64],
    ) {
        accel_only_at_state(st, fr, &mut self.su, t, acc)
    }

    /// A step, or (`redo`) the last one again from the start state it saved.
    #[allow(clippy::too_many_arguments)]
    fn step<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t0: f64,
        h: f64,
        a0: &[f64],
        u0: &mut [f64],
        w0: &mut [f64],
        a1: &mut [f64],
        redo: bool,
    ) {
        let Midpoint {
            su,
            sw,
            acc,
            iterations,
            converged,
            last,
        } = self;
        let hh = 0.5 * h;
        let tm = t0 + hh;
        for &(a, b) in &st.runs {
            for p in a..b {
                if !redo {
                    u0[p] = st.u[p];
                    w0[p] = st.w[p];
                }
                sw[p] = w0[p] + hh * a0[p];
            }
        }
        let mut sums = StageSums::default();
        for it in 0..200 {
            for &(a, b) in &st.runs {
                for p in a..b {
                    su[p] = u0[p] + hh * sw[p];
                }
            }
            fill_neighbours(st, su, tm);
            stage_accel::<G, F, M, false>(st, fr, su, sw, acc);
            sums = stage_sums(st, fr, su, sw);
            let mut diff: f64 = 0.0;
            let mut scale: f64 = 1.0;
            for &(a, b) in &st.runs {
                for p in a..b {
                    let next = w0[p] + hh * acc[p];
                    diff = diff.max((next - sw[p]).abs());
                    scale = scale.max(next.abs());
                    sw[p] = next;
                }
            }
            *iterations += 1;
            if diff <= 4.0 * f64::EPSILON * scale || it == 199 {
                // solved: to round-off, or (a factor near the bound 0.8, whose rounding
                // noise in the last bits is amplified by 1/(1 - factor)) to 1e-10; else
                // the chain reports the step as not solved, never a silent result
                *converged = diff <= 1e-10 * scale;
                break;
            }
        }
        // the converged midpoint state: u1 = u0 + h w_m, w1 = 2 w_m - w0
        for &(a, b) in &st.runs {
            for p in a..b {
                st.u[p] = u0[p] + h * sw[p];
                st.w[p] = 2.0 * sw[p] - w0[p];
            }
        }
        *last = StepIntegrals {
            u: h * sums.u,
            dry: h * sums.dry,
            visc: h * sums.visc,
        };
        accel_only_at_state(st, fr, su, t0 + h, a1);
    }

    fn books<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        _st: &State<G>,
        _fr: &Blocks<F, M>,
        _w0: &[f64],
        _h: f64,
    ) -> StepIntegrals {
        // exact for this method: h times the power at the midpoint (the module docs)
        self.last
    }
}

impl Midpoint {}
