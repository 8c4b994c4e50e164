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
//! energy books close to the order of the method; RK4 keeps the weighted stage values per
//! block and sums over the blocks once per step ([`Integrator::books`]), so no stage has
//! a reduction and every stage vectorises.

pub mod midpoint;
pub mod rk4;

pub use midpoint::Midpoint;
pub use rk4::Rk4;

use super::geometry::{Beyond, Geometry, Stencil};
use super::medium::{Blocks, Medium};
use super::state::State;
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
    /// Acceleration of every sliding block at the state's current time t into `acc`.
    fn accel_only<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t: f64,
        acc: &mut [f64],
    ) where
        Self: Sized;
    /// Advance the sliding blocks from t0 to t0 + h. `a0` holds the accelerations at
    /// t0 (from [`Integrator::accel_only`] or the last step); the start state is saved in
    /// `u0`, `w0` for the dense output and for a redo; the accelerations at t0 + h of the
    /// new state go to `a1` (the same bits as [`Integrator::accel_only`] there). With
    /// `redo` the last step again, from the start state it saved in `u0`, `w0` (to a
    /// length h, usually shorter): the same bits as putting that state back into `st` and
    /// stepping, without the copy (`st`'s sliding u, u_t unread).
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
    ) where
        Self: Sized;
    /// The energy flows of the last step taken (of length h): called once per step
    /// taken, after any redo.
    /// `w0` is the start state's u_t the step saved.
    fn books<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        w0: &[f64],
        h: f64,
    ) -> StepIntegrals
    where
        Self: Sized;
}

/// Accelerations of the sliding blocks at the present state, time t, using `su` as the
/// stage buffer.
#[inline(always)]
pub(crate) fn accel_only_at_state<G: Geometry, F: Friction, M: Medium>(
    st: &State<G>,
    fr: &Blocks<F, M>,
    su: &mut [f64],
    t: f64,
    acc: &mut [f64],
) {
    for &(a, b) in &st.runs {
        su[a..b].copy_from_slice(&st.u[a..b]);
    }
    fill_neighbours(st, su, t);
    stage_accel::<G, F, M, false>(st, fr, su, &st.w, acc);
}

/// Accelerations at time t of the sliding blocks among `blocks` (the others are left as
/// they are), each from the present state of its own cell and its neighbours: the same
/// formula on the same values as [`accel_only_at_state`] (the coupling force in the
/// stencil's order, a stuck neighbour by its exact drift, a ghost by the boundary), so
/// the same bits, block by block. Not for a state with blocks in their stiff onset
/// (`st.ext`): the caller recomputes them all then.
pub(crate) fn accel_at_blocks<G: Geometry, F: Friction, M: Medium>(
    st: &State<G>,
    fr: &Blocks<F, M>,
    t: f64,
    blocks: &[usize],
    acc: &mut [f64],
) {
    debug_assert!(st.ext.is_empty());
    let v = st.v;
    for &p in blocks {
        if !st.sliding(p) {
            continue;
        }
        let value = |q: usize| {
            if st.geo.is_ghost(q) {
                match st.geo.beyond(q, p) {
                    Beyond::Block(r) if st.sliding(r) => st.u[r],
                    Beyond::Block(r) => st.stuck_u(r, t),
                    Beyond::Wall(g0) => g0 + v * t,
                }
            } else if st.sliding(q) {
                st.u[q]
            } else {
                st.stuck_u(q, t)
            }
        };
        let up = st.u[p];
        let f = st.geo.force(&fr.med, p, up, value);
        acc[p] = fr.accel(p, up, f, v - st.w[p], st.dir[p], st.onset[p]);
    }
}

/// Fill the stage displacement of the neighbours of every run (stuck blocks by their
/// exact drift, ghosts by the boundary) at stage time ts. Sliding values in `su` must
/// already be set.
#[inline(always)]
pub(crate) fn fill_neighbours<G: Geometry>(st: &State<G>, su: &mut [f64], ts: f64) {
    // sliding blocks outside the runs (in their stiff onset, ../onset.rs): their values
    // at the stage times (the midpoint or the end) from their own integration
    if !st.ext.is_empty() {
        for &(p, mid, end) in &st.ext {
            su[p] = if ts < st.ext_t1 { mid } else { end };
        }
    }
    if G::FRONTIER {
        // the stuck cells and ghosts next to the runs, from their lists (../frontier.rs)
        for q in st.frontier.stuck(&st.dir) {
            su[q] = st.stuck_u(q, ts);
        }
        for (q, b) in st.frontier.ghosts() {
            su[q] = match b {
                Beyond::Block(r) if st.sliding(r) => su[r],
                Beyond::Block(r) => st.stuck_u(r, ts),
                Beyond::Wall(g0) => g0 + st.v * ts,
            };
        }
        return;
    }
    for &(a, b) in &st.runs {
        for (q, p, ghost) in st.geo.around_run(a, b) {
            if ghost {
                su[q] = match st.geo.beyond(q, p) {
                    Beyond::Block(r) if st.sliding(r) => su[r],
                    Beyond::Block(r) => st.stuck_u(r, ts),
                    Beyond::Wall(g0) => g0 + st.v * ts,
                };
            } else if !st.sliding(q) {
                su[q] = st.stuck_u(q, ts);
            }
        }
    }
}

/// Accelerations of all sliding blocks from stage values su, sw: one pass per run with
/// no branch and no reduction, which the compiler vectorises. `FWD`: every sliding block
/// slides forward (dir = 1, which is then not read: the same bits).
#[inline(always)]
pub(crate) fn stage_accel<G: Geometry, F: Friction, M: Medium, const FWD: bool>(
    st: &State<G>,
    fr: &Blocks<F, M>,
    su: &[f64],
    sw: &[f64],
    acc: &mut [f64],
) {
    let v = st.v;
    for &(a, b) in &st.runs {
        let len = b - a;
        let sten = st.geo.stencil(su, a, b);
        let (sw, dir, th) = (&sw[a..b], &st.dir[a..b], &st.onset[a..b]);
        let acc = &mut acc[a..b];
        assert!(sw.len() == len && dir.len() == len);
        assert!(th.len() == len && acc.len() == len);
        for i in 0..len {
            let d = if FWD { 1.0 } else { dir[i] };
            let p = a + i;
            let f = sten.force(&fr.med, p, i);
            acc[i] = fr.accel(p, sten.centre(i), f, v - sw[i], d, th[i]);
        }
    }
}

/// The stage sums (loader displacement, dry and viscous power) of the sliding blocks at
/// stage values su, sw, summed block by block in order within each run.
pub(crate) fn stage_sums<G: Geometry, F: Friction, M: Medium>(
    st: &State<G>,
    fr: &Blocks<F, M>,
    su: &[f64],
    sw: &[f64],
) -> StageSums {
    let v = st.v;
    let mut sums = StageSums::default();
    for &(a, b) in &st.runs {
        let (mut su_, mut sd, mut sv) = (0.0, 0.0, 0.0);
        for p in a..b {
            let s = v - sw[p];
            let (pd, pv) = fr.fr.power(s, st.dir[p], st.onset[p]);
            // the loader work rate is v sum (k_p,i u_i + beta)
            su_ += fr.med.loader(p) * su[p];
            sd += pd;
            sv += pv;
        }
        sums.u += su_;
        sums.dry += sd;
        sums.visc += sv;
    }
    sums
}

/// Sum of `x` in four interleaved partial sums (element i to sum i mod 4, the four added
/// at the end): independent chains of additions, which the compiler vectorises.
#[inline(always)]
pub(crate) fn lane_sum(x: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let chunks = x.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for l in 0..4 {
            acc[l] += c[l];
        }
    }
    for (l, &r) in rest.iter().enumerate() {
        acc[l] += r;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// The vector code the kernels run (the step, the accelerations, the books, the rest
/// pre-test): on x86-64, code compiled for AVX2 or AVX-512F when the CPU has it, chosen
/// at run time. Rust never fuses a multiply and an add (no FMA), so every choice gives
/// the same bits (tested), and the engine's results do not depend on the CPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Simd {
    /// Baseline code (SSE2 on x86-64).
    Baseline,
    /// AVX2 code (256-bit registers).
    Avx2,
    /// AVX-512F code (512-bit registers).
    Avx512,
}

impl Simd {
    /// The widest code this CPU runs (std caches the detection: a load and a test).
    #[inline]
    pub fn detect() -> Simd {
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx512f") {
                return Simd::Avx512;
            }
            if std::is_x86_feature_detected!("avx2") {
                return Simd::Avx2;
            }
        }
        Simd::Baseline
    }

    /// Every code this CPU runs, baseline first (for the bit-for-bit tests).
    pub fn available() -> Vec<Simd> {
        let best = Simd::detect();
        [Simd::Baseline, Simd::Avx2, Simd::Avx512]
            .into_iter()
            .filter(|&s| s as u8 <= best as u8)
            .collect()
    }
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
// (one per engine: the size of the larger variant costs nothing)
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub enum Stepper {
    /// RK4.
    Rk4(Rk4),
    /// Implicit midpoint.
    Midpoint(Midpoint),
}

impl Stepper {
    /// Buffers for padded arrays of `len` cells (n + 2 for a chain of n blocks).
    pub fn new(method: Method, len: usize) -> Self {
        match method {
            Method::Rk4 => Stepper::Rk4(Rk4::new(len - 2)),
            Method::Midpoint => Stepper::Midpoint(Midpoint::new(len - 2)),
        }
    }
    /// Name of the method.
    pub fn name(&self) -> &'static str {
        match self {
            Stepper::Rk4(m) => m.name(),
            Stepper::Midpoint(m) => m.name(),
        }
    }
    /// See [`Integrator::accel_only`].
    pub fn accel_only<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t: f64,
        acc: &mut [f64],
    ) {
        match self {
            Stepper::Rk4(m) => m.accel_only(st, fr, t, acc),
            Stepper::Midpoint(m) => m.accel_only(st, fr, t, acc),
        }
    }
    /// See [`Integrator::step`] (`redo`: the step just taken, again from the start
    /// state it saved in `u0`, `w0`).
    #[allow(clippy::too_many_arguments)]
    pub fn step<G: Geometry, F: Friction, M: Medium>(
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
        match self {
            Stepper::Rk4(m) => m.step(st, fr, t0, h, a0, u0, w0, a1, redo),
            Stepper::Midpoint(m) => m.step(st, fr, t0, h, a0, u0, w0, a1, redo),
        }
    }
    /// The accelerations at time t of the sliding blocks among `blocks` (see
    /// [`accel_at_blocks`]): after switches that leave every u as it was, the blocks
    /// whose own equations changed.
    pub fn accel_at<G: Geometry, F: Friction, M: Medium>(
        &self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        t: f64,
        blocks: &[usize],
        acc: &mut [f64],
    ) {
        accel_at_blocks(st, fr, t, blocks, acc)
    }
    /// Whether the last step solved its equations (an explicit method always does; the
    /// midpoint rule when its fixed-point iteration converged).
    pub fn solved(&self) -> bool {
        match self {
            Stepper::Rk4(_) => true,
            Stepper::Midpoint(m) => m.converged,
        }
    }
    /// See [`Integrator::books`].
    pub fn books<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        w0: &[f64],
        h: f64,
    ) -> StepIntegrals {
        match self {
            Stepper::Rk4(m) => m.books(st, fr, w0, h),
            Stepper::Midpoint(m) => m.books(st, fr, w0, h),
        }
    }
}
