//! The stiff onset of a weakening friction law, integrated where and when it happens
//! (issue 22; docs/velocity_weakening.md, "Cost").
//!
//! A block sliding with velocity-weakening friction R(s) = theta/(1 + s/v_f) + 2 gamma s
//! obeys m s_t = phi - R(s) (s = v - u_t its speed over the ground). Linearised about
//! s = 0, m s_t = (phi - theta) + (theta/v_f - 2 gamma) s: just after its slip a block
//! runs away from rest at the rate theta/(m v_f), until s ~ v_f; there R ~ theta v_f/s
//! and the rate |R'(s)|/m = theta v_f/(m (v_f + s)^2) falls below the lattice rate 1/dx
//! once s > sqrt(theta v_f dx). Pushed by its sliding neighbour (phi - theta ~ t/(c dx)),
//! the block spends v_f ln(c dx/v_f) in the exponential phase and about sqrt(v_f dx) more
//! before it is no longer stiff: a time ~ v_f ln(1/r), r = v_f/dx, against dx/c between
//! two slips. The same happens, in reverse and shorter, as a block comes to rest.
//!
//! So only the newest block of a front (and a block about to stick) is stiff, and only
//! for a short time. The chain keeps its step H = `step` dx for every other block; a
//! sliding block whose rate |R'(s)|/m exceeds 1/dx at the start or the end of a step
//! (or whose u_t crosses v in it), or whose motion RK4 at H would shift in time by more
//! than [`shift_tol`], together with its sliding neighbours (the patch), is taken out of
//! the runs and integrated by RK4 with its own sub-steps, which land on the step's
//! midpoint and end. A sub-step is sized by the time shift RK4 makes in a block's
//! motion ([`shift`]: its error in u_t over its acceleration), held below
//! `shift_tol` = [`SHIFT_TOL`] step^5 dx. In the exponential phase (rate nu = theta/(m v_f))
//! that allows h nu = (120 shift_tol nu)^(1/5): the sub-steps lengthen, in units of the
//! growth time, as v_f falls (the whole onset is a time shift of order v_f), so the
//! ln(1/r) e-folds take ~ ln(1/r) r^(1/5)/step sub-steps instead of ln(1/r)/step; in the
//! 1/s tail after it they grow geometrically with the time since the slip, by a factor
//! that also grows like r^(-1/5). The tolerance falls like step^5 as the step does, so
//! the whole front keeps RK4's order 4 in `step`.
//!
//! The two parts see each other as follows:
//!
//! - the runs' RK4 stages read the patch blocks' values at the stage times (the step's
//!   start, midpoint and end) from the patch's own integration;
//! - the patch's sub-steps read a sliding neighbour outside the patch from the runs' step:
//!   its cubic Hermite interpolant over the step (the first pass, before the runs have been
//!   stepped, its Taylor polynomial u + u_t tau + u_tt tau^2/2);
//! - the two are iterated (patch, runs, patch, ...) until the patch's values at the stage
//!   times change by less than `PASS_TOL` (each round trip changes them by ~ (H/dx)^4).
//!
//! The patch falls into groups, each with its own sub-steps. A block's class is how much
//! shorter than step dx its own sub-steps start (log2, from its state at the step's
//! start, at the least speed over the ground its start acceleration takes it to in the
//! step); it takes the class of its stiffest neighbour in the patch if that is higher
//! (the neighbours of a stiff block feel its kink: they share its sub-steps, below); a
//! group is a connected set of neighbours of one class. So a block near rest and its
//! sliding neighbours step together, and a block a hundred times farther from rest next
//! to them no longer takes their sub-steps (in a plane healing after a rupture the patch
//! holds hundreds of blocks, tens of them near rest at different speeds:
//! docs/lattice.md). The groups are taken stiffest first, each reading the runs, stuck
//! blocks and the other groups: a group already stepped in this pass from its dense
//! output, one not yet stepped from its last pass's (from its Taylor polynomial before
//! its first); they and the runs are iterated together until no group's stage values
//! change by more than `PASS_TOL` over (h/dx)^2 (what a neighbour reads changes its
//! motion by (h/dx)^2 times that). A group's sub-steps are also held short enough for
//! the weakening of its neighbours in other groups as the spring passes it on
//! ([`seen_unit`]). A front periodic in y has identical rows: their blocks have one
//! class, fall into one group, and each row takes the chain's sub-steps
//! (tests/test_lattice_vw.py).
//!
//! A step's patch takes the blocks that will be stiff in the step, as their start state
//! tells ([`LOOKAHEAD_A`]): a block of the runs that turns stiff in the step grows the
//! patch after it, and the step is integrated again. A step cut at an event (the earliest
//! rest of a patch block, or any switch elsewhere) is integrated again up to it; that redo
//! starts from the dense output of the integration it cuts short: the groups' stage values
//! at the new midpoint and end seed the runs' step in place of a first, loose pass, then
//! every group is stepped at the full tolerance and they are iterated as above (a group
//! not yet stepped is read from that dense output too). The counts of each are in
//! [`OnsetStats`] (docs/lattice.md, "Velocity weakening on the lattice").
//!
//! The patch includes the stiff block's sliding neighbours because the stiff block's
//! acceleration jumps from 0 to ~1 within a time ~ v_f ln(1/r), inside a step: a
//! neighbour stepped with H would sample that kink at three points only (an error
//! ~ H (v_f ln(1/r))^2/dx^2 per slip); the neighbours' own motion has the kink smoothed in
//! its fourth derivative, which the runs' RK4 integrates to ~ H (v_f ln(1/r))^4/dx^4.
//! Every part is a fourth-order method whose steps, or tolerances, scale with `step`,
//! so the whole converges at order 4 in `step`.

use super::events::Hermite;
use super::geometry::{Beyond, Geometry};
use super::integrator::StepIntegrals;
use super::medium::{Blocks, Medium};
use super::state::State;
use crate::friction::Friction;

/// The largest change of the patch's stage values between two passes, times (h/dx)^2
/// (what it changes in the runs next to the patch), accepted.
pub(crate) const PASS_TOL: f64 = 1e-13;
/// The largest sub-step times the rate nu of the weakening force, in units of the step:
/// 2 at the default step (RK4 on the onset's growth e^{nu t} is then still accurate to
/// 1/10 per sub-step; the time shift holds it far shorter until nu is ~ 1e12 dx).
pub(crate) const Z_MAX: f64 = 40.0;
/// The most a sub-step grows over the last (the first of a pass is step/nu: the jerk
/// that [`shift`] needs is known from the second on).
pub(crate) const GROWTH: f64 = 4.0;
/// The time-shift tolerance of the first pass of a coupled patch, in units of
/// [`shift_tol`]: its values only feed the runs' step, and the next pass (at the full
/// tolerance) measures what their difference does to the runs (at most the shift over
/// ~100 sub-steps times (h/dx)^2 h: far below [`PASS_TOL`] at 32, which halves the
/// sub-steps that the time shift limits, since those scale like tol^(1/5)).
pub(crate) const FIRST_PASS_LOOSE: f64 = 32.0;
/// The patch at a step's start takes the blocks that will be stiff in the step as far
/// as their start state tells: at the least speed their start acceleration takes them to
/// in the step, with this many times that acceleration (it changes in the step: by a few
/// per cent for a block slowing down towards rest, by up to twice for one pushed away
/// from it; the time shift goes like its cube in the 1/s tail). A block missed grows the
/// patch after the step, which is then integrated again: on the 48 x 32 rupture healing
/// (docs/lattice.md) 1.0 left 256 growths in 2255 steps, 1.25 leaves 30.
pub(crate) const LOOKAHEAD_A: f64 = 1.25;
/// The most passes (patch, runs) per step.
pub(crate) const MAX_PASSES: usize = 6;

/// Where the onsets' work went (counters for diagnosis: not part of a checkpoint; zero
/// when no law has a stiff onset). A step with a patch integrates the patch and the runs
/// once for the step (cause 0), again each time the patch grows (cause 1: a block of the
/// runs turned stiff in the step) and again up to the earliest event (cause 2).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OnsetStats {
    /// Steps taken with a patch.
    pub steps: u64,
    /// Integrations of the patch and the runs, per cause (first, growth, redo).
    pub integrations: [u64; 3],
    /// Block-steps of the patch's groups' sub-steps, per cause.
    pub group_block_steps: [u64; 3],
    /// Of those, the block-steps of the groups' first (loose) passes, per cause.
    pub loose_block_steps: [u64; 3],
    /// Block-steps of the runs' steps inside the integrations, per cause.
    pub runs_block_steps: [u64; 3],
    /// Block-steps of plain steps thrown away because a block turned stiff in them.
    pub turned_block_steps: u64,
    /// Groups stepped, summed over the integrations' passes.
    pub group_passes: u64,
}

/// The patch of one step and its integration (reused from step to step).
#[derive(Debug, Clone, Default)]
pub(crate) struct Onset {
    /// What the onsets did so far (the patch's own, not its parts').
    pub stats: OnsetStats,
    /// The cause of the integration under way (an index of [`OnsetStats`]' arrays).
    cause: usize,
    /// The patch blocks (padded indices, sorted); empty when the last step had none.
    pub blocks: Vec<usize>,
    /// The groups of the integration before the last (a redo up to an event starts from
    /// their dense output: [`Engine::onset_pass`]).
    seed: Vec<Onset>,
    /// The patch's connected components (no block of one is a neighbour of a block of
    /// another), each integrated with its own sub-steps: the whole patch's state, dense
    /// output, books and rests are theirs (the fields below, in the patch, are the
    /// aggregate: rests and books; a part's fields are its own).
    pub parts: Vec<Onset>,
    /// Their u, u_t at the step's start.
    pub u0: Vec<f64>,
    pub w0: Vec<f64>,
    /// Their u, u_t at the end of the last pass, u at its midpoint.
    pub u: Vec<f64>,
    pub w: Vec<f64>,
    pub mid: Vec<f64>,
    /// The dense output of the last pass: knot times, and per knot the blocks' u, u_t,
    /// u_tt (block k of knot j at j * len + k).
    pub kt: Vec<f64>,
    pub ku: Vec<f64>,
    pub kw: Vec<f64>,
    pub ka: Vec<f64>,
    /// Per knot and block, what the block's weakening asks of a neighbour's sub-step h:
    /// the neighbour's time shift through the spring is h^5 times this ([`seen_unit`]).
    pub kx: Vec<f64>,
    /// The patch's energy flows over the last pass.
    pub books: StepIntegrals,
    /// The earliest rest of a patch block in the last pass (time; infinite if none) and
    /// the blocks at rest then.
    pub rest_t: f64,
    pub rest_who: Vec<usize>,
    /// Sub-steps of the last pass.
    pub substeps: u64,
    /// The first planned sub-step of the last pass (its start time, its blocks): another
    /// pass over the same step (from the same state) starts from it instead of from
    /// step/nu (nothing is carried from one step to the next: a run restarted from a
    /// checkpoint takes the same sub-steps).
    first: (f64, f64),
    first_blocks: Vec<usize>,
    // stage buffers
    su: Vec<f64>,
    sw: Vec<f64>,
    acc: Vec<f64>,
    acc0: Vec<f64>,
    accp: Vec<f64>,
    su0: Vec<f64>,
    sw0: Vec<f64>,
    sum_u: Vec<f64>,
    sum_w: Vec<f64>,
}

impl Onset {
    /// The slot of padded block r in the patch.
    #[inline]
    fn slot(&self, r: usize) -> Option<usize> {
        self.blocks.binary_search(&r).ok()
    }

    /// Size the buffers for the current blocks.
    pub fn resize(&mut self) {
        let n = self.blocks.len();
        for v in [
            &mut self.u0,
            &mut self.w0,
            &mut self.u,
            &mut self.w,
            &mut self.mid,
            &mut self.su,
            &mut self.sw,
            &mut self.acc,
            &mut self.acc0,
            &mut self.accp,
            &mut self.su0,
            &mut self.sw0,
            &mut self.sum_u,
            &mut self.sum_w,
        ] {
            v.clear();
            v.resize(n, 0.0);
        }
    }

    /// u and u_t of patch block p at time t in [t0, t1] of the last pass (its dense
    /// output: the cubic Hermite interpolant between the sub-step knots).
    pub fn dense(&self, p: usize, t: f64) -> Option<(f64, f64)> {
        let k = self.slot(p)?;
        let (a, b, s, h) = knot_interval(&self.kt, self.blocks.len(), k, t)?;
        let hu = Hermite {
            g0: self.ku[a],
            m0: self.kw[a],
            g1: self.ku[b],
            m1: self.kw[b],
        };
        let hw = Hermite {
            g0: self.kw[a],
            m0: self.ka[a],
            g1: self.kw[b],
            m1: self.ka[b],
        };
        Some((hu.eval(s, h), hw.eval(s, h)))
    }
}

/// The sub-step interval of knot times `kt` that holds t, for slot k of n blocks stored
/// knot by knot: the indices (a, b) of the slot's values at its two knots, the fraction s
/// of the interval at t (clamped to [0, 1]) and its length h; None with fewer than two
/// knots. (The dense output of a patch here and of a local-event component.)
pub(super) fn knot_interval(
    kt: &[f64],
    n: usize,
    k: usize,
    t: f64,
) -> Option<(usize, usize, f64, f64)> {
    let nk = kt.len();
    if nk < 2 {
        return None;
    }
    let j = kt.partition_point(|&x| x <= t).clamp(1, nk - 1) - 1;
    let (ta, tb) = (kt[j], kt[j + 1]);
    let h = tb - ta;
    let s = if h > 0.0 {
        ((t - ta) / h).clamp(0.0, 1.0)
    } else {
        1.0
    };
    Some((j * n + k, (j + 1) * n + k, s, h))
}

/// The RK4 error of a sliding block's u_t over a step h, as the time shift it makes in
/// the block's motion (the error over its acceleration), from the block's weakening
/// force R_w (size `rw`, speed scale `sigma`), its acceleration `a` and the size `jerk`
/// of its rate of change (0: unknown). R_w changes at the rate
/// nu = max(R_w/(sigma m), |a|/sigma) (its own growth rate at the onset, the rate at
/// which s crosses the scale sigma after it); what varies at that rate is at most R_w/m
/// and at most the acceleration on the time 1/nu, A = |a| + jerk/nu. So the fifth
/// derivative of u_t is about nu^4 min(R_w/m, A), RK4's error h^5 nu^4 min(R_w/m, A)/120,
/// and the time shift that over A: in the exponential phase (A << R_w/m) (h nu)^5/(120 nu),
/// in the 1/s tail after it h^5 nu^4 R_w/(120 m |a|).
#[inline(always)]
fn shift(rw_m: f64, sigma: f64, a: f64, jerk: f64, h: f64) -> f64 {
    let nu = (rw_m.max(a.abs())) / sigma;
    let big_a = a.abs() + if nu > 0.0 { jerk / nu } else { 0.0 };
    if big_a <= 0.0 {
        return 0.0;
    }
    let hn = h * nu;
    let hn2 = hn * hn;
    h * hn2 * hn2 * rw_m.min(big_a) / (120.0 * big_a)
}

/// What a sliding block's weakening asks of a neighbour's sub-step h: the time shift
/// RK4 makes in the neighbour's motion is about h^5 times this. The neighbour feels the
/// block's u through a spring, two time derivatives below the block's acceleration, so
/// the fifth derivative of its u_t is that of the block's over (nu dx)^2 (nu the rate of
/// [`shift`]): the block's own time shift per h^5 ([`shift`] at h = 1, no jerk) over
/// max(1, (nu dx)^2). A neighbour on its own sub-steps (another group of the patch)
/// takes them no longer than this allows.
#[inline(always)]
fn seen_unit(rw_m: f64, sigma: f64, a: f64, spacing: f64) -> f64 {
    let nu = (rw_m.max(a.abs())) / sigma;
    if nu.is_nan() || nu <= 0.0 {
        return 0.0;
    }
    let g = (nu * spacing) * (nu * spacing);
    shift(rw_m, sigma, a, 0.0, 1.0) / g.max(1.0)
}

/// The time shift a step may make in a block's motion through its weakening force:
/// [`SHIFT_TOL`] step^5 dx (RK4's error per step in a Coulomb block's slip time is about
/// step^5 dx times its derivatives; the onset is held far below it, so that the chain's
/// error stays the Coulomb chain's and falls like step^4).
#[inline(always)]
pub(crate) fn shift_tol(step: f64, spacing: f64) -> f64 {
    let s2 = step * step;
    SHIFT_TOL * s2 * s2 * step * spacing
}

/// The time shift per step, in units of step^5 dx, that the onset's sub-steps (and a
/// block left in the runs) may make ([`shift_tol`]).
pub(crate) const SHIFT_TOL: f64 = 1e-4;

/// Is sliding block p, at speed s over the ground and acceleration a, in its onset for
/// a step of length h (`spacing` = dx, `step` = h/dx of the chain)? Either its weakening
/// rate R_w/(sigma m) exceeds 1/dx (the exponential phase: RK4 at step dx would not even
/// be stable), or RK4 at h would shift its motion by more than [`shift_tol`] ([`shift`]:
/// in the 1/s tail after the onset R_w ~ 1/t decays only like the time since the slip).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn is_stiff<G: Geometry, F: Friction, M: Medium>(
    st: &State<G>,
    blk: &Blocks<F, M>,
    p: usize,
    s: f64,
    a: f64,
    h: f64,
    step: f64,
    spacing: f64,
) -> bool {
    let (rw, sigma) = blk.fr.weakening(s, st.dir[p], st.onset[p]);
    let rw_m = rw * blk.med.inv_mass(p);
    if rw_m * spacing > sigma {
        return true;
    }
    shift(rw_m, sigma, a, 0.0, h) > shift_tol(step, spacing)
}

/// Accelerations of the patch blocks at stage values (su, sw) at time t, `outside(r, t)`
/// the displacement of a real block r outside the patch.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn accel<G: Geometry, F: Friction, M: Medium>(
    st: &State<G>,
    blk: &Blocks<F, M>,
    blocks: &[usize],
    su: &[f64],
    sw: &[f64],
    t: f64,
    outside: &impl Fn(usize, f64) -> f64,
    out: &mut [f64],
) {
    for (k, &p) in blocks.iter().enumerate() {
        let up = su[k];
        let f = st.geo.force(&blk.med, p, up, |q| {
            let r = if st.geo.is_ghost(q) {
                match st.geo.beyond(q, p) {
                    Beyond::Block(r) => r,
                    Beyond::Wall(g0) => return g0 + st.v * t,
                }
            } else {
                q
            };
            match blocks.binary_search(&r) {
                Ok(j) => su[j],
                Err(_) => outside(r, t),
            }
        });
        out[k] = blk.accel(p, up, f, st.v - sw[k], st.dir[p], st.onset[p]);
    }
}

/// One pass of a group of the patch over [t0, t0 + h] from its start values (`on.u0`,
/// `on.w0`), with sub-steps `step` min(dx, 1/rate) that land on t0 + h/2 and t0 + h;
/// `outside(r, t)` the displacement of a real block r outside the group, `nb_limit(p, t,
/// hf, tol)` the longest sub-step (at most hf) from t that block p's neighbours in other
/// groups allow. Leaves the end values, the midpoint values, the dense output (with each
/// knot's [`seen_unit`]), the books and the earliest rest in `on`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn pass<G: Geometry, F: Friction, M: Medium>(
    on: &mut Onset,
    st: &State<G>,
    blk: &Blocks<F, M>,
    t0: f64,
    h: f64,
    step: f64,
    spacing: f64,
    loose: f64,
    outside: impl Fn(usize, f64) -> f64,
    nb_limit: impl Fn(usize, f64, f64, f64) -> f64,
) {
    let n = on.blocks.len();
    let v = st.v;
    let blocks = std::mem::take(&mut on.blocks);
    on.u.copy_from_slice(&on.u0);
    on.w.copy_from_slice(&on.w0);
    on.kt.clear();
    on.ku.clear();
    on.kw.clear();
    on.ka.clear();
    on.kx.clear();
    on.books = StepIntegrals::default();
    on.rest_t = f64::INFINITY;
    on.rest_who.clear();
    on.substeps = 0;
    let mut t = t0;
    accel(st, blk, &blocks, &on.u, &on.w, t, &outside, &mut on.acc0);
    on.kt.push(t);
    on.ku.extend_from_slice(&on.u);
    on.kw.extend_from_slice(&on.w);
    on.ka.extend_from_slice(&on.acc0);
    push_seen(on, st, blk, &blocks, spacing);
    let h_max = step * spacing;
    let tol = loose * shift_tol(step, spacing);
    // the last sub-step (0: none yet in this pass) and the accelerations at its start;
    // the last planned sub-step (before it was cut to land on the segment's end)
    let (mut h_prev, mut h_grow) = (0.0, 0.0);
    if loose == 1.0 && on.first.0 == t0 && on.first_blocks == blocks {
        h_grow = on.first.1 / GROWTH;
    }
    let mut first_h = f64::NAN;
    for seg in 0..2 {
        let t_end = if seg == 0 { t0 + 0.5 * h } else { t0 + h };
        while t < t_end {
            // the sub-step: each block's RK4 time shift (`shift`) at most `shift_tol`,
            // h nu at most Z_MAX step, at most step dx; at the pass's first sub-step (no
            // jerk known yet) step/nu, then growing at most GROWTH-fold per sub-step
            let mut hf = h_max;
            let mut nu_max: f64 = 0.0;
            for (k, &p) in blocks.iter().enumerate() {
                if st.dir[p] * (on.w[k] - v) > 0.0 {
                    // past its rest in this pass (located: the step is redone up to
                    // it), its motion beyond is not used: it sets no sub-step
                    continue;
                }
                let (rw, sigma) = blk.fr.weakening(v - on.w[k], st.dir[p], st.onset[p]);
                let rw_m = rw * blk.med.inv_mass(p);
                let a = on.acc0[k];
                let nu = rw_m.max(a.abs()) / sigma;
                if nu.is_nan() || nu <= 0.0 {
                    continue;
                }
                nu_max = nu_max.max(nu);
                let jerk = if h_prev > 0.0 {
                    (a - on.accp[k]).abs() / h_prev
                } else {
                    0.0
                };
                // shift(h) = h^5 shift(1): the longest h with shift <= tol (the fifth
                // root only when it binds)
                let unit = shift(rw_m, sigma, a, jerk, 1.0);
                let hk = hf.min(Z_MAX * step / nu);
                let hk2 = hk * hk;
                hf = if unit * hk2 * hk2 * hk > tol {
                    (tol / unit).powf(0.2)
                } else {
                    hk
                };
            }
            // no longer than the blocks' neighbours in other groups of the patch allow
            // (their weakening as the spring passes it on: `seen_unit`)
            for &p in &blocks {
                hf = nb_limit(p, t, hf, tol);
            }
            if h_grow > 0.0 {
                hf = hf.min(GROWTH * h_grow);
            } else if nu_max > 0.0 {
                hf = hf.min(step / nu_max);
            }
            // (never below the clock's resolution: a v_f so small that its onset is
            // shorter than that is taken as a Coulomb slip, not stepped for ever)
            let hf = hf.max(8.0 * f64::EPSILON * t.abs().max(h));
            let h_plan = hf;
            if first_h.is_nan() {
                first_h = h_plan;
            }
            let left = t_end - t;
            let t_next = if left <= hf {
                t_end
            } else if left < 2.0 * hf {
                t + 0.5 * left
            } else {
                t + hf
            };
            let hf = t_next - t;
            let hh = 0.5 * hf;
            let tm = t + hh;
            // classical RK4 over the patch
            on.su0.copy_from_slice(&on.u);
            on.sw0.copy_from_slice(&on.w);
            let power = |su: &[f64], sw: &[f64], wt: f64, books: &mut StepIntegrals| {
                for (k, &p) in blocks.iter().enumerate() {
                    let (pd, pv) = blk.fr.power(v - sw[k], st.dir[p], st.onset[p]);
                    books.u += wt * blk.med.loader(p) * su[k];
                    books.dry += wt * pd;
                    books.visc += wt * pv;
                }
            };
            let mut b = StepIntegrals::default();
            power(&on.u, &on.w, 1.0, &mut b);
            for k in 0..n {
                on.sum_u[k] = on.w[k];
                on.sum_w[k] = on.acc0[k];
                on.su[k] = on.u[k] + hh * on.w[k];
                on.sw[k] = on.w[k] + hh * on.acc0[k];
            }
            // stages 2 and 3 (at tm, weight 2), stage 4 (at t_next, weight 1)
            for (c, wt, ts) in [(hh, 2.0, tm), (hf, 2.0, tm), (0.0, 1.0, t_next)] {
                accel(st, blk, &blocks, &on.su, &on.sw, ts, &outside, &mut on.acc);
                power(&on.su, &on.sw, wt, &mut b);
                for k in 0..n {
                    let (du, dw) = (on.sw[k], on.acc[k]);
                    on.sum_u[k] += wt * du;
                    on.sum_w[k] += wt * dw;
                    if wt == 2.0 {
                        on.su[k] = on.su0[k] + c * du;
                        on.sw[k] = on.sw0[k] + c * dw;
                    }
                }
            }
            let h6 = hf / 6.0;
            for k in 0..n {
                on.u[k] = on.su0[k] + h6 * on.sum_u[k];
                on.w[k] = on.sw0[k] + h6 * on.sum_w[k];
            }
            on.books.u += h6 * b.u;
            on.books.dry += h6 * b.dry;
            on.books.visc += h6 * b.visc;
            accel(
                st,
                blk,
                &blocks,
                &on.u,
                &on.w,
                t_next,
                &outside,
                &mut on.acc,
            );
            // rest of a patch block in the sub-step (the rule of Engine::detect); none
            // once the sub-step starts at or after the earliest rest found (a later one
            // cannot come first)
            for (k, &p) in blocks.iter().enumerate() {
                if t >= on.rest_t {
                    break;
                }
                let d = st.dir[p];
                let g = Hermite {
                    g0: d * (on.sw0[k] - v),
                    m0: d * on.acc0[k],
                    g1: d * (on.w[k] - v),
                    m1: d * on.acc[k],
                };
                if g.g0 == 0.0 && g.g1 == 0.0 && g.m0 <= 0.0 && g.m1 <= 0.0 {
                    continue;
                }
                // g0 <= 0 (inside) and g1 < 0 with slopes whose cubic is monotone (h m0,
                // h m1 of the sign of g1 - g0 and at most 3 times it: Fritsch and
                // Carlson's box): g stays below max(g0, g1), no crossing, no search (a
                // block in its onset or slowing down, every sub-step)
                let fall = g.g1 - g.g0;
                let box3 = |x: f64| {
                    if fall < 0.0 {
                        x <= 0.0 && x >= 3.0 * fall
                    } else {
                        x >= 0.0 && x <= 3.0 * fall
                    }
                };
                if g.g1 < 0.0 && fall != 0.0 && box3(hf * g.m0) && box3(hf * g.m1) {
                    continue;
                }
                if let Some(s) = g.first_crossing(hf) {
                    let te = t + s * hf;
                    if te < on.rest_t {
                        on.rest_t = te;
                        on.rest_who.clear();
                        on.rest_who.push(p);
                    } else if te == on.rest_t && !on.rest_who.contains(&p) {
                        on.rest_who.push(p);
                    }
                }
            }
            on.accp.copy_from_slice(&on.acc0);
            h_prev = hf;
            h_grow = h_plan;
            std::mem::swap(&mut on.acc0, &mut on.acc);
            t = t_next;
            on.substeps += 1;
            on.kt.push(t);
            on.ku.extend_from_slice(&on.u);
            on.kw.extend_from_slice(&on.w);
            on.ka.extend_from_slice(&on.acc0);
            push_seen(on, st, blk, &blocks, spacing);
        }
        if seg == 0 {
            on.mid.copy_from_slice(&on.u);
        }
    }
    if loose == 1.0 {
        // (a loose pass's sub-steps are no start for a pass at the full tolerance)
        on.first = (t0, first_h);
        on.first_blocks.clone_from(&blocks);
    }
    on.blocks = blocks;
}

/// Append the knot's [`seen_unit`] of every block (`on.w`, `on.acc0` at the knot) to
/// `on.kx` (0 for a block past its rest: its motion beyond is not used).
fn push_seen<G: Geometry, F: Friction, M: Medium>(
    on: &mut Onset,
    st: &State<G>,
    blk: &Blocks<F, M>,
    blocks: &[usize],
    spacing: f64,
) {
    let v = st.v;
    for (k, &p) in blocks.iter().enumerate() {
        let x = if st.dir[p] * (on.w[k] - v) > 0.0 {
            0.0
        } else {
            let (rw, sigma) = blk.fr.weakening(v - on.w[k], st.dir[p], st.onset[p]);
            seen_unit(rw * blk.med.inv_mass(p), sigma, on.acc0[k], spacing)
        };
        on.kx.push(x);
    }
}

impl<G: Geometry, F: Friction, M: Medium> super::Engine<G, F, M> {
    /// Collect the patch of the step into `self.onset.blocks`: the sliding blocks that are
    /// stiff at the step's start (`after` false: from the present state) or, for the step
    /// just taken (`after` true), at its start or end or whose u_t crossed v in it, with
    /// their sliding neighbours. True if there is any (else the patch is left empty).
    pub(super) fn onset_patch(&mut self, h: f64, after: bool) -> bool {
        let spacing = self.st.geo.spacing();
        let step = self.cfg.step;
        let v = self.cfg.v;
        let mut fast = std::mem::take(&mut self.onset.blocks);
        fast.clear();
        for &(a, b) in &self.st.runs {
            for p in a..b {
                let s1 = v - self.st.w[p];
                let (s, a) = if after {
                    let s0 = v - self.w0[p];
                    let a = self.a_start[p].abs().max(self.a_end[p].abs());
                    if s0 * s1 <= 0.0 {
                        (0.0, a)
                    } else {
                        (s0.abs().min(s1.abs()), a)
                    }
                } else {
                    // what the block will be in the step, not only at its start (a block
                    // of the runs that turns stiff in the step grows the patch, and the
                    // step is integrated again): at the least speed its start
                    // acceleration takes it to in the step (s_t = -u_tt), at LOOKAHEAD_A
                    // times that acceleration
                    let a = self.a_start[p];
                    let s2 = s1 - a * h;
                    let am = LOOKAHEAD_A * a.abs();
                    if s1 * s2 <= 0.0 {
                        (0.0, am)
                    } else {
                        (s1.abs().min(s2.abs()), am)
                    }
                };
                if is_stiff(&self.st, &self.blk, p, s, a, h, step, spacing) {
                    fast.push(p);
                }
            }
        }
        let any = !fast.is_empty();
        self.onset.blocks = fast;
        if any {
            self.onset_add_neighbours();
        }
        any
    }

    /// Add the sliding neighbours of the patch blocks to the patch (sorted, unique).
    fn onset_add_neighbours(&mut self) {
        let mut all = std::mem::take(&mut self.onset.blocks);
        let n = all.len();
        for k in 0..n {
            let p = all[k];
            for r in self.st.real_neighbours(p) {
                if self.st.sliding(r) {
                    all.push(r);
                }
            }
        }
        all.sort_unstable();
        all.dedup();
        self.onset.blocks = all;
    }

    /// After a step with a patch: add the blocks of the runs that were stiff in it (the
    /// rule of [`Engine::onset_patch`] with `after`) and their sliding neighbours. True if
    /// the patch grew.
    fn onset_grow(&mut self, h: f64) -> bool {
        let spacing = self.st.geo.spacing();
        let step = self.cfg.step;
        let v = self.cfg.v;
        let mut more = Vec::new();
        for &(a, b) in &self.st.runs {
            for p in a..b {
                if self.onset.blocks.binary_search(&p).is_ok() {
                    continue;
                }
                let (s0, s1) = (v - self.w0[p], v - self.st.w[p]);
                let s = if s0 * s1 <= 0.0 {
                    0.0
                } else {
                    s0.abs().min(s1.abs())
                };
                let a = self.a_start[p].abs().max(self.a_end[p].abs());
                if is_stiff(&self.st, &self.blk, p, s, a, h, step, spacing) {
                    more.push(p);
                }
            }
        }
        if more.is_empty() {
            return false;
        }
        self.onset.blocks.extend(more);
        self.onset_add_neighbours();
        true
    }

    /// One step of length h from t0 with the patch in `self.onset.blocks`: the patch and
    /// the runs iterated (module docs), the patch grown while blocks of the runs turn
    /// stiff in the step, events located (the patch's rests on its own dense output) and
    /// the step redone up to the earliest.
    pub(super) fn onset_step(&mut self, t0: f64, mut h: f64, t_cap: f64) -> super::Result<()> {
        self.onset.stats.steps += 1;
        self.onset_cause(0);
        let mut integ = self.onset_pass(t0, h, false);
        let mut rounds = 0;
        while rounds < 8 && self.onset_grow(h) {
            rounds += 1;
            self.restore_runs();
            self.onset_cause(1);
            integ = self.onset_pass(t0, h, false);
        }
        let (mut cands, mut events) = (
            std::mem::take(&mut self.scratch.cands),
            std::mem::take(&mut self.scratch.who),
        );
        let skip = std::mem::take(&mut self.onset.blocks);
        let mut s = self.detect(t0, h, &mut cands, &mut events, &skip);
        self.onset.blocks = skip;
        self.scratch.cands = cands;
        let sr = (self.onset.rest_t - t0) / h;
        if sr < s {
            s = sr;
            events.clear();
        }
        if sr == s {
            for &p in &self.onset.rest_who {
                if !events.contains(&(p, 0)) {
                    events.push((p, 0));
                }
            }
        }
        if s < 1.0 {
            self.restore_runs();
            h *= s;
            self.onset_cause(2);
            integ = self.onset_pass(t0, h, true);
        }
        self.finish_step(t0, h, t_cap, integ, events, None)
    }

    /// Integrate the patch and the runs over [t0, t0 + h] (module docs), leaving every
    /// sliding block at t0 + h, the start values in u0, w0, the end accelerations in
    /// a_end; returns the step's energy flows.
    fn onset_pass(&mut self, t0: f64, h: f64, seeded: bool) -> StepIntegrals {
        let spacing = self.st.geo.spacing();
        let step = self.cfg.step;
        let v = self.cfg.v;
        let patch = std::mem::take(&mut self.onset.blocks);
        // each block's class: how much shorter than step dx its own sub-steps start
        // (log2, from its start state, at the least speed over the ground its start
        // acceleration would take it to in the step)
        let h_max = step * spacing;
        let tol = shift_tol(step, spacing);
        let class: Vec<i32> = patch
            .iter()
            .map(|&p| {
                let (s0, a) = (v - self.st.w[p], self.a_start[p]);
                let s1 = s0 - a * h;
                let s = if s0 * s1 <= 0.0 {
                    0.0
                } else {
                    s0.abs().min(s1.abs())
                };
                let (rw, sigma) = self.blk.fr.weakening(s, self.st.dir[p], self.st.onset[p]);
                let rw_m = rw * self.blk.med.inv_mass(p);
                let nu = rw_m.max(a.abs()) / sigma;
                if nu.is_nan() || nu <= 0.0 {
                    return 0;
                }
                let hk = h_max.min(Z_MAX * step / nu);
                let unit = shift(rw_m, sigma, a, 0.0, 1.0);
                let hk = if unit * hk.powi(5) > tol {
                    (tol / unit).powf(0.2)
                } else {
                    hk
                };
                (h_max / hk).log2().floor().clamp(0.0, 60.0) as i32
            })
            .collect();
        // a block takes the class of its stiffest neighbour in the patch if that is
        // higher: the neighbours of a stiff block share its sub-steps (they feel its
        // kink through the spring: module docs), as a whole patch did before
        let class: Vec<i32> = patch
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let mut c = class[i];
                for r in self.st.real_neighbours(p) {
                    if let Ok(q) = patch.binary_search(&r) {
                        c = c.max(class[q]);
                    }
                }
                c
            })
            .collect();
        // the patch's groups: connected through neighbours of one class, each with its
        // own sub-steps, stiffest first. A group reads the runs, stuck blocks and the
        // other groups (their dense output, or their Taylor polynomial before their first
        // pass), and they are iterated as the patch and the runs are
        if seeded {
            // the last integration's groups seed this one (their buffers are reused)
            std::mem::swap(&mut self.onset.parts, &mut self.onset.seed);
        }
        let seed = std::mem::take(&mut self.onset.seed);
        let mut parts = std::mem::take(&mut self.onset.parts);
        let mut comp = vec![usize::MAX; patch.len()];
        let mut n_parts = 0;
        let mut stack = Vec::new();
        let mut order: Vec<usize> = (0..patch.len()).collect();
        order.sort_by_key(|&i| (-class[i], i));
        for &i in &order {
            if comp[i] != usize::MAX {
                continue;
            }
            if parts.len() <= n_parts {
                parts.push(Onset::default());
            }
            let blocks = &mut parts[n_parts].blocks;
            blocks.clear();
            comp[i] = n_parts;
            stack.push(i);
            while let Some(j) = stack.pop() {
                blocks.push(patch[j]);
                for r in self.st.real_neighbours(patch[j]) {
                    if let Ok(q) = patch.binary_search(&r) {
                        if comp[q] == usize::MAX && class[q] == class[i] {
                            comp[q] = n_parts;
                            stack.push(q);
                        }
                    }
                }
            }
            blocks.sort_unstable();
            n_parts += 1;
        }
        parts.truncate(n_parts);
        // per group: does it see a sliding block of the runs, the other groups it sees
        let mut runs_adj = vec![false; n_parts];
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n_parts];
        for (i, on) in parts.iter_mut().enumerate() {
            on.resize();
            on.kt.clear();
            for (k, &p) in on.blocks.iter().enumerate() {
                on.u0[k] = self.st.u[p];
                on.w0[k] = self.st.w[p];
                self.u0[p] = self.st.u[p];
                self.w0[p] = self.st.w[p];
            }
            for &p in &on.blocks {
                for r in self.st.real_neighbours(p) {
                    if !self.st.sliding(r) {
                        continue;
                    }
                    match patch.binary_search(&r) {
                        Ok(q) if comp[q] != i => {
                            if !adj[i].contains(&comp[q]) {
                                adj[i].push(comp[q]);
                            }
                        }
                        Ok(_) => {}
                        Err(_) => runs_adj[i] = true,
                    }
                }
            }
        }
        // (a group that sees a sliding block outside it is iterated with it)
        let coupled: Vec<bool> = (0..n_parts)
            .map(|i| runs_adj[i] || !adj[i].is_empty())
            .collect();
        let any_coupled = coupled.iter().any(|&c| c);
        // a redo up to an event (seeded): the groups' stage values as the last
        // integration's dense output gives them at the new midpoint and end, in place of a
        // first pass at the loose tolerance: the runs are stepped with them, then every
        // group at the full tolerance, and they are iterated as below (a group not yet
        // stepped is read from that dense output too)
        let mut seed_of = Vec::new();
        let mut seed_val = Vec::new();
        let mut seeded = seeded && any_coupled;
        if seeded {
            seed_of.resize(patch.len(), usize::MAX);
            for (j, g) in seed.iter().enumerate() {
                for &p in &g.blocks {
                    if let Ok(q) = patch.binary_search(&p) {
                        seed_of[q] = j;
                    }
                }
            }
            for (q, &p) in patch.iter().enumerate() {
                let g = seed.get(seed_of[q]);
                let at = |t: f64| g.and_then(|g| g.dense(p, t)).map(|x| x.0);
                match (at(t0 + 0.5 * h), at(t0 + h)) {
                    (Some(m), Some(e)) => seed_val.push((m, e)),
                    _ => {
                        seeded = false;
                        break;
                    }
                }
            }
        }
        if seeded {
            // (a group's first planned sub-step, as in another pass over the step)
            for on in parts.iter_mut() {
                let q = patch.binary_search(&on.blocks[0]).expect("a patch block");
                let g = &seed[seed_of[q]];
                if g.first.0 == t0 && g.first_blocks == on.blocks {
                    on.first = g.first;
                    on.first_blocks.clone_from(&g.first_blocks);
                }
            }
        }
        let r2 = (h / spacing) * (h / spacing);
        // the groups to step in the next pass: all in the first; then those whose inputs
        // changed by more than PASS_TOL / r2 since they were stepped (what they read
        // would change their motion by r2 times that)
        let mut dirty = vec![true; n_parts];
        for &p in &patch {
            self.st.remove_from_runs(p);
        }
        let mut coarse_done = false;
        let mut passes = 0;
        let mut coarse = StepIntegrals::default();
        // per group, its mid and end values of the last pass
        let mut prev: Vec<(Vec<f64>, Vec<f64>)> = vec![(Vec::new(), Vec::new()); n_parts];
        loop {
            // the largest change of a group that the runs see
            let mut change_runs = 0.0f64;
            if seeded && !coarse_done {
                for (i, on) in parts.iter_mut().enumerate() {
                    for (k, &p) in on.blocks.iter().enumerate() {
                        let q = patch.binary_search(&p).expect("a patch block");
                        (on.mid[k], on.u[k]) = seed_val[q];
                    }
                    prev[i].0.clone_from(&on.mid);
                    prev[i].1.clone_from(&on.u);
                }
            }
            for i in 0..n_parts {
                if !dirty[i] || (seeded && !coarse_done) {
                    continue;
                }
                dirty[i] = false;
                let mut on = std::mem::take(&mut parts[i]);
                {
                    let (st, blk, u0, w0, a0) =
                        (&self.st, &self.blk, &self.u0, &self.w0, &self.a_start);
                    let (parts, patch, comp, seed, seed_of) =
                        (&parts, &patch, &comp, &seed, &seed_of);
                    // the group of the patch holding real block r, if not this one
                    let other = |r: usize| -> Option<&Onset> {
                        let q = patch.binary_search(&r).ok()?;
                        (comp[q] != i).then(|| &parts[comp[q]])
                    };
                    let outside = |r: usize, t: f64| -> f64 {
                        if !st.sliding(r) {
                            return st.stuck_u(r, t);
                        }
                        let tau = t - t0;
                        if let Some(g) = other(r) {
                            if let Some((u, _)) = g.dense(r, t) {
                                return u;
                            }
                            if seeded {
                                let q = patch.binary_search(&r).expect("a patch block");
                                if let Some((u, _)) = seed[seed_of[q]].dense(r, t) {
                                    return u;
                                }
                            }
                            return u0[r] + tau * (w0[r] + 0.5 * tau * a0[r]);
                        }
                        if coarse_done {
                            let hu = Hermite {
                                g0: u0[r],
                                m0: w0[r],
                                g1: st.u[r],
                                m1: st.w[r],
                            };
                            hu.eval(tau / h, h)
                        } else {
                            st.u[r] + tau * (st.w[r] + 0.5 * tau * a0[r])
                        }
                    };
                    // the longest sub-step from t (at most hf) that block p's neighbours
                    // in other groups allow: their `seen_unit` at their knots in it (at
                    // their start before their first pass)
                    let nb_limit = |p: usize, t: f64, mut hf: f64, tol: f64| -> f64 {
                        for r in st.real_neighbours(p) {
                            let Some(g) = other(r) else { continue };
                            let lim = |x: f64, hf: f64| -> f64 {
                                if x * hf.powi(5) > tol {
                                    (tol / x).powf(0.2)
                                } else {
                                    hf
                                }
                            };
                            let n = g.blocks.len();
                            let nk = g.kt.len();
                            let k = g.slot(r).expect("a block of the group");
                            if nk < 2 {
                                let (rw, sigma) =
                                    blk.fr.weakening(v - w0[r], st.dir[r], st.onset[r]);
                                let x = seen_unit(rw * blk.med.inv_mass(r), sigma, a0[r], spacing);
                                hf = lim(x, hf);
                                continue;
                            }
                            let mut j = g.kt.partition_point(|&x| x <= t).clamp(1, nk - 1) - 1;
                            hf = lim(g.kx[j * n + k], hf);
                            while j + 1 < nk && g.kt[j] < t + hf {
                                j += 1;
                                hf = lim(g.kx[j * n + k], hf);
                            }
                        }
                        hf
                    };
                    // the first pass of a coupled group only gives the runs and the other
                    // groups its values (the next pass replaces them, and checks what the
                    // difference did: PASS_TOL): at FIRST_PASS_LOOSE times the tolerance
                    let loose = if coupled[i] && !coarse_done {
                        FIRST_PASS_LOOSE
                    } else {
                        1.0
                    };
                    pass(
                        &mut on, st, blk, t0, h, step, spacing, loose, outside, nb_limit,
                    );
                }
                let bs = on.substeps * on.blocks.len() as u64;
                self.counters.block_steps += bs;
                let c = self.onset.cause;
                self.onset.stats.group_block_steps[c] += bs;
                self.onset.stats.group_passes += 1;
                if coupled[i] && !coarse_done {
                    self.onset.stats.loose_block_steps[c] += bs;
                }
                let (pm, pe) = &mut prev[i];
                if coarse_done {
                    // the runs and the other groups saw the last pass's values: they are
                    // off by about (h/dx)^2 times the change of this pass
                    let mut change = 0.0f64;
                    for k in 0..on.blocks.len() {
                        change = change
                            .max((on.mid[k] - pm[k]).abs())
                            .max((on.u[k] - pe[k]).abs());
                    }
                    if change * r2 > PASS_TOL {
                        for &j in &adj[i] {
                            dirty[j] = true;
                        }
                        if runs_adj[i] {
                            change_runs = change_runs.max(change);
                        }
                    }
                }
                pm.clone_from(&on.mid);
                pe.clone_from(&on.u);
                parts[i] = on;
            }
            if coarse_done {
                // (the first pass was at the loose tolerance, read the groups after it
                // and the runs from their Taylor polynomials: every coupled group is
                // stepped again after it, below)
                let runs_stale = change_runs * r2 > PASS_TOL;
                if !any_coupled || passes >= MAX_PASSES || (!runs_stale && !dirty.contains(&true)) {
                    break;
                }
                if !runs_stale {
                    passes += 1;
                    continue;
                }
                // the runs read changed values: step them again; what that changes in
                // the groups next to them is r2 times what it changes in the runs,
                // about r2 times change_runs
                for i in 0..n_parts {
                    if runs_adj[i] && change_runs * r2 * r2 > PASS_TOL {
                        dirty[i] = true;
                    }
                }
                self.restore_runs();
            } else if seeded {
                dirty.fill(true);
            } else {
                dirty.copy_from_slice(&coupled);
            }
            self.st.ext.clear();
            for on in &parts {
                for (k, &p) in on.blocks.iter().enumerate() {
                    self.st.ext.push((p, on.mid[k], on.u[k]));
                }
            }
            self.st.ext_t1 = t0 + h;
            self.onset.stats.runs_block_steps[self.onset.cause] += self.st.n_active as u64;
            self.do_step(t0, h, false);
            coarse = self.rk.books(&self.st, &self.blk, &self.w0, h);
            coarse_done = true;
            passes += 1;
            if !any_coupled {
                break;
            }
        }
        self.st.ext.clear();
        // the patch's state, rests and books: its parts'
        let (mut rest_t, mut rest_who) = (f64::INFINITY, std::mem::take(&mut self.onset.rest_who));
        rest_who.clear();
        let mut b = StepIntegrals::default();
        for on in &parts {
            for (k, &p) in on.blocks.iter().enumerate() {
                self.st.u[p] = on.u[k];
                self.st.w[p] = on.w[k];
                self.st.add_to_runs(p);
            }
            if on.rest_t < rest_t {
                rest_t = on.rest_t;
                rest_who.clear();
            }
            if on.rest_t == rest_t && rest_t.is_finite() {
                rest_who.extend_from_slice(&on.rest_who);
            }
            b.u += on.books.u;
            b.dry += on.books.dry;
            b.visc += on.books.visc;
        }
        self.onset.rest_t = rest_t;
        self.onset.rest_who = rest_who;
        self.onset.books = b;
        self.onset.parts = parts;
        self.onset.seed = seed;
        self.onset.blocks = patch;
        self.rk
            .accel_only(&mut self.st, &self.blk, t0 + h, &mut self.a_end);
        StepIntegrals {
            u: coarse.u + b.u,
            dry: coarse.dry + b.dry,
            visc: coarse.visc + b.visc,
        }
    }

    /// The cause of the next integration (counted in [`OnsetStats`]).
    fn onset_cause(&mut self, cause: usize) {
        self.onset.cause = cause;
        self.onset.stats.integrations[cause] += 1;
    }

    /// What the onsets did so far.
    pub fn onset_stats(&self) -> OnsetStats {
        self.onset.stats
    }

    /// u and u_t of block p at time t if it is in the last step's patch.
    pub(super) fn onset_dense(&self, p: usize, t: f64) -> Option<(f64, f64)> {
        if self.onset.blocks.is_empty() || self.onset.blocks.binary_search(&p).is_err() {
            return None;
        }
        self.onset
            .parts
            .iter()
            .find(|on| on.blocks.binary_search(&p).is_ok())
            .and_then(|on| on.dense(p, t))
    }
}
