//! Time stepping of the sliding blocks.
//!
//! Only blocks in runs of sliding blocks are stepped; the stuck neighbours at the ends
//! of a run enter through their exact drift u = u_ref + v (t - t_ref), evaluated at each
//! stage time, and the chain ends through their ghosts. The loader work and the
//! dissipated power are integrated by the same stages (an augmented system), so the
//! energy books close to the order of the method.

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

/// Fill the stage displacement of the neighbours of every run (stuck blocks by their
/// exact drift, ghosts by the boundary) at stage time ts. Sliding values in `su` must
/// already be set.
fn fill_neighbours(st: &State, su: &mut [f64], ts: f64) {
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
fn stage_accel<F: Friction>(
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

impl Integrator for Rk4 {
    fn name(&self) -> &'static str {
        "rk4"
    }
    fn order(&self) -> u32 {
        4
    }

    fn accel<F: Friction>(&mut self, st: &mut State, fr: &F, t: f64, acc: &mut [f64]) -> StageSums {
        for &(a, b) in &st.runs {
            self.su[a..b].copy_from_slice(&st.u[a..b]);
        }
        fill_neighbours(st, &mut self.su, t);
        stage_accel(st, fr, &self.su, &st.w, acc)
    }

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
