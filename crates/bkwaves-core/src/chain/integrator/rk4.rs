//! Classical fourth-order Runge-Kutta for the runs of sliding blocks.

use super::{accel_at_state, fill_neighbours, stage_accel, Integrator, StageSums, StepIntegrals};
use crate::chain::medium::{Blocks, Medium};
use crate::chain::state::State;
use crate::friction::Friction;

/// Classical fourth-order Runge-Kutta.
#[derive(Debug, Clone, Default)]
pub struct Rk4 {
    su: Vec<f64>,
    sw: Vec<f64>,
    acc: Vec<f64>,
    ku: Vec<f64>,
    kw: Vec<f64>,
}

impl Rk4 {
    /// Buffers for a chain of n blocks.
    pub fn new(n: usize) -> Self {
        Rk4 {
            su: vec![0.0; n + 2],
            sw: vec![0.0; n + 2],
            acc: vec![0.0; n + 2],
            ku: vec![0.0; n + 2],
            kw: vec![0.0; n + 2],
        }
    }
}

impl Integrator for Rk4 {
    fn name(&self) -> &'static str {
        "rk4"
    }
    fn order(&self) -> u32 {
        4
    }

    fn accel<F: Friction, M: Medium>(
        &mut self,
        st: &mut State,
        fr: &Blocks<F, M>,
        t: f64,
        acc: &mut [f64],
    ) -> StageSums {
        accel_at_state(st, fr, &mut self.su, t, acc)
    }

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
    ) -> StepIntegrals {
        let Rk4 {
            su,
            sw,
            acc,
            ku,
            kw,
        } = self;
        // stage 1 (at t0): derivatives (w, a0); set stage 2 values
        for &(a, b) in &st.runs {
            for p in a..b {
                u0[p] = st.u[p];
                w0[p] = st.w[p];
                ku[p] = w0[p];
                kw[p] = a0[p];
                su[p] = u0[p] + 0.5 * h * w0[p];
                sw[p] = w0[p] + 0.5 * h * a0[p];
            }
        }
        let mut integ = StepIntegrals {
            u: s0.u,
            dry: s0.dry,
            visc: s0.visc,
        };
        let coeff = [(0.5, 2.0), (1.0, 2.0), (0.0, 1.0)]; // (next stage c, this weight)
        let times = [t0 + 0.5 * h, t0 + 0.5 * h, t0 + h];
        for stage in 0..3 {
            fill_neighbours(st, su, times[stage]);
            let sums = stage_accel(st, fr, su, sw, acc);
            let (cn, wt) = coeff[stage];
            integ.u += wt * sums.u;
            integ.dry += wt * sums.dry;
            integ.visc += wt * sums.visc;
            for &(a, b) in &st.runs {
                for p in a..b {
                    ku[p] += wt * sw[p];
                    kw[p] += wt * acc[p];
                    su[p] = u0[p] + cn * h * sw[p];
                    sw[p] = w0[p] + cn * h * acc[p];
                }
            }
        }
        let h6 = h / 6.0;
        for &(a, b) in &st.runs {
            for p in a..b {
                st.u[p] = u0[p] + h6 * ku[p];
                st.w[p] = w0[p] + h6 * kw[p];
            }
        }
        integ.u *= h6;
        integ.dry *= h6;
        integ.visc *= h6;
        integ
    }
}
