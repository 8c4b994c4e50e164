//! Issue 16, "step-size control where the dynamics allows it": how many steps and
//! sliding-block updates could a step-size controller save, at most, on the engine's runs?
//! (docs/benchmarks.md, "Step-size control: not kept".)
//!
//! The engine's trajectories are not changed: each run is advanced one step at a time
//! through the public API (`Chain::run` with a budget of one step), and before every step
//! the state (u, u_t, modes) is read. From it this program integrates the step the engine
//! took (modes frozen, stuck blocks drifting at v exactly, the engine's right-hand side:
//! Coulomb friction, uniform blocks, free ends) once with the step h and twice with h/2:
//!
//! - the local error of the step, e_loc = |y_h - y_{h/2,h/2}| 16/15 (Richardson; the max
//!   over the sliding blocks of |du| and |du_t|); one step of h is also compared with the
//!   engine's own result (it must agree to rounding: `check` below);
//! - the error of the dense output the events are located on, e_dense: the cubic Hermite
//!   of u and of u_t (the engine's interpolants) at the step's midpoint against the
//!   h/2 step there.
//!
//! A controller with tolerance tol would take h* = h (tol/e_loc)^(1/5) (RK4's local error
//! is O(h^5)), also h (tol_d/e_dense)^(1/4) if the events must stay as accurate (the
//! Hermite cubic's error is O(h^4)), and at most the stability limit of the highest
//! lattice mode, omega_max h* <= 2.8 (omega_max = sqrt(1 + 4/dx^2)). The steps between
//! two forced step ends (an event located in the step and the step redone to it, a cap by
//! a source or the slip queue, or a mode change) are replaced by
//! max(1, ceil(sum h/h*)) controller steps of the segment's mean sliding-block count, plus
//! the same redone steps as the engine's. The tolerance is the local error the fixed
//! default step makes where it is largest (the fast phases: the max over the run, and
//! for comparison the 99th and 90th percentiles, under which the controller refines the
//! steps above it). Everything else a real controller pays (rejected steps, safety
//! factors, step-growth limits, the error estimate itself: about 1.5 more steps' work
//! for step doubling, or a fifth stage for an embedded pair) is left out: the result is an
//! upper bound on the saving.
//!
//! cargo run --release -- [--quick]     (--quick: shorter runs, for a check)
//!
//! With `STEPSIZE_TRACE=PREFIX` set, each run also writes its steps (PREFIX.(a).csv: start
//! time, step, engine steps, sliding blocks, forced end, local and dense-output error) and
//! its event catalog (PREFIX.(a).events.csv).

use bkwaves_core::boundary::Free;
use bkwaves_core::chain::{Chain, ChainConfig, Stop, Trigger, TriggerKind, DEFAULT_STEP};
use bkwaves_core::friction::Coulomb;

/// CPU time of this process in seconds (CLOCK_PROCESS_CPUTIME_ID; the machine is shared).
fn cpu_seconds() -> f64 {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    extern "C" {
        fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
    }
    let mut ts = Timespec { sec: 0, nsec: 0 };
    // CLOCK_PROCESS_CPUTIME_ID = 2 on Linux
    unsafe { clock_gettime(2, &mut ts) };
    ts.sec as f64 + 1e-9 * ts.nsec as f64
}

/// The engine's equations for a uniform Coulomb chain with free ends.
struct Model {
    dx: f64,
    v: f64,
    gamma: f64,
    beta: f64,
}

/// One step problem: the state at the step's start (time offset 0), the modes frozen.
struct Frozen<'a> {
    model: &'a Model,
    u0: &'a [f64],
    dir: &'a [i8],
    /// The sliding blocks.
    slide: Vec<usize>,
    /// The stuck neighbours of the sliding blocks (they drift at v).
    stuck_nbrs: Vec<usize>,
}

/// A state of the sliding blocks at a time offset from the step's start (full-length
/// arrays; only the sliding blocks and their stuck neighbours are kept current).
#[derive(Clone)]
struct Y {
    u: Vec<f64>,
    w: Vec<f64>,
    tau: f64,
}

impl<'a> Frozen<'a> {
    fn new(model: &'a Model, u0: &'a [f64], dir: &'a [i8]) -> Self {
        let n = u0.len();
        let slide: Vec<usize> = (0..n).filter(|&i| dir[i] != 0).collect();
        let mut stuck_nbrs = Vec::new();
        for &i in &slide {
            for q in [i.wrapping_sub(1), i + 1] {
                if q < n && dir[q] == 0 && stuck_nbrs.last() != Some(&q) {
                    stuck_nbrs.push(q);
                }
            }
        }
        stuck_nbrs.dedup();
        Frozen {
            model,
            u0,
            dir,
            slide,
            stuck_nbrs,
        }
    }

    /// u_tt of sliding block i at stage values u (neighbours current) and u_t = w.
    fn accel(&self, u: &[f64], i: usize, w: f64) -> f64 {
        let m = self.model;
        let n = u.len();
        let left = if i == 0 { u[0] } else { u[i - 1] };
        let right = if i + 1 == n { u[n - 1] } else { u[i + 1] };
        let phi = u[i] - (left + right - 2.0 * u[i]) / (m.dx * m.dx);
        let s = m.v - w;
        let r = if self.dir[i] < 0 {
            2.0 * m.gamma * s - 2.0 * m.beta
        } else {
            2.0 * m.gamma * s
        };
        -phi + r
    }

    fn drift(&self, u: &mut [f64], tau: f64) {
        for &q in &self.stuck_nbrs {
            u[q] = self.u0[q] + self.model.v * tau;
        }
    }

    /// The accelerations of the sliding blocks at y (in the order of `slide`).
    fn accels(&self, y: &Y) -> Vec<f64> {
        self.slide
            .iter()
            .map(|&i| self.accel(&y.u, i, y.w[i]))
            .collect()
    }

    /// One classical RK4 step of size h from y.
    fn rk4(&self, y: &Y, h: f64) -> Y {
        let m = self.slide.len();
        let mut st = y.clone();
        let (mut ku, mut kw) = (vec![0.0; m], vec![0.0; m]);
        let (mut su, mut sw) = (vec![0.0; m], vec![0.0; m]);
        for (k, (c, wt)) in [(0.0, 1.0), (0.5, 2.0), (0.5, 2.0), (1.0, 1.0)]
            .into_iter()
            .enumerate()
        {
            if k > 0 {
                for (j, &i) in self.slide.iter().enumerate() {
                    st.u[i] = y.u[i] + c * h * ku[j];
                    st.w[i] = y.w[i] + c * h * kw[j];
                }
            }
            self.drift(&mut st.u, y.tau + c * h);
            for (j, &i) in self.slide.iter().enumerate() {
                ku[j] = st.w[i];
                kw[j] = self.accel(&st.u, i, st.w[i]);
                su[j] += wt * ku[j];
                sw[j] += wt * kw[j];
            }
        }
        let mut out = y.clone();
        for (j, &i) in self.slide.iter().enumerate() {
            out.u[i] = y.u[i] + h / 6.0 * su[j];
            out.w[i] = y.w[i] + h / 6.0 * sw[j];
        }
        out.tau = y.tau + h;
        self.drift(&mut out.u, out.tau);
        out
    }
}

/// What one engine step did, and the estimates for it.
#[derive(Clone, Copy)]
struct Rec {
    /// The step's start time.
    t0: f64,
    /// The step taken (after a redo: the redone step).
    h: f64,
    /// Integration steps the engine counted (2 when the step was redone to an event).
    steps: u64,
    /// Sliding blocks during the step.
    active: u64,
    /// The step ended where it had to (an event, a cap, a mode change).
    forced: bool,
    /// Local error and dense-output error (NaN: not estimated).
    e_loc: f64,
    e_dense: f64,
}

struct Measured {
    name: &'static str,
    recs: Vec<Rec>,
    h_nom: f64,
    h_stab: f64,
    /// Largest difference between this program's RK4 step and the engine's.
    check: f64,
    cpu: f64,
    sim_time: f64,
    switches: u64,
    /// Block updates by their own local error (the error bin, `err_bin`), per unit of
    /// time (index: floor(t)).
    per_block: Vec<[f64; ERR_BINS]>,
    /// Backward slips.
    backward: usize,
    /// When the last block first slipped (a front reaching the far end; NaN if never).
    t_far_end: f64,
}

/// Advance `ch` to `t_end` (or `events` events) one step at a time, estimating each step.
fn measure(
    name: &'static str,
    mut ch: Chain<Coulomb>,
    model: &Model,
    t_end: f64,
    events: usize,
) -> Measured {
    let cpu0 = cpu_seconds();
    let h_nom = DEFAULT_STEP * model.dx;
    let h_stab = 2.8 / (1.0 + 4.0 / (model.dx * model.dx)).sqrt();
    let mut recs = Vec::new();
    let mut check = 0.0f64;
    let mut events_left = events;
    let t_start = ch.time();
    let model_n = ch.n();
    let mut per_block: Vec<[f64; ERR_BINS]> = Vec::new();
    loop {
        let before = (ch.counters.steps, ch.counters.block_steps);
        let f0 = ch.catalog.finished();
        let estimable = ch.n_sliding() > 0;
        let (t0, u0, w0, dir0) = if estimable {
            (ch.time(), ch.u(), ch.u_t(), ch.modes())
        } else {
            (0.0, Vec::new(), Vec::new(), Vec::new())
        };
        let stop = ch.run(t_end, events_left, 1).unwrap();
        events_left = events_left.saturating_sub(ch.catalog.finished() - f0);
        let steps = ch.counters.steps - before.0;
        if let Some(active) = (ch.counters.block_steps - before.1).checked_div(steps) {
            let (mut e_loc, mut e_dense, mut h, mut forced) = (f64::NAN, f64::NAN, 0.0, true);
            if estimable {
                h = ch.time() - t0;
                let dir1 = ch.modes();
                forced = steps > 1 || dir1 != dir0 || h < h_nom * (1.0 - 1e-9);
                let fz = Frozen::new(model, &u0, &dir0);
                let y0 = Y {
                    u: u0.clone(),
                    w: w0.clone(),
                    tau: 0.0,
                };
                let y1 = fz.rk4(&y0, h);
                let ym = fz.rk4(&y0, 0.5 * h);
                let y2 = fz.rk4(&ym, 0.5 * h);
                // the engine's result, where the modes did not change
                let (u1, w1) = (ch.u(), ch.u_t());
                for &i in &fz.slide {
                    if dir1[i] == dir0[i] {
                        check = check
                            .max((u1[i] - y1.u[i]).abs())
                            .max((w1[i] - y1.w[i]).abs());
                    }
                }
                let (a0, a1) = (fz.accels(&y0), fz.accels(&y1));
                let (mut el, mut ed) = (0.0f64, 0.0f64);
                let bin_t = (t0.max(0.0) as usize).min(MAX_TIME_BINS - 1);
                if per_block.len() <= bin_t {
                    per_block.resize(bin_t + 1, [0.0; ERR_BINS]);
                }
                for (j, &i) in fz.slide.iter().enumerate() {
                    let e_i = (y1.u[i] - y2.u[i]).abs().max((y1.w[i] - y2.w[i]).abs());
                    per_block[bin_t][err_bin(e_i * 16.0 / 15.0)] += steps as f64;
                    el = el.max(e_i);
                    // cubic Hermite at s = 1/2
                    let hu = 0.5 * (y0.u[i] + y1.u[i]) + h * (y0.w[i] - y1.w[i]) / 8.0;
                    let hw = 0.5 * (y0.w[i] + y1.w[i]) + h * (a0[j] - a1[j]) / 8.0;
                    ed = ed.max((hu - ym.u[i]).abs()).max((hw - ym.w[i]).abs());
                }
                e_loc = el * 16.0 / 15.0;
                e_dense = ed;
            }
            recs.push(Rec {
                t0: if estimable { t0 } else { f64::NAN },
                h,
                steps,
                active,
                forced,
                e_loc,
                e_dense,
            });
        }
        if stop != Stop::Steps {
            break;
        }
    }
    if let Ok(path) = std::env::var("STEPSIZE_TRACE") {
        let mut out = String::from("t0,h,steps,active,forced,e_loc,e_dense\n");
        for r in &recs {
            out += &format!(
                "{},{},{},{},{},{},{}\n",
                r.t0, r.h, r.steps, r.active, r.forced as u8, r.e_loc, r.e_dense
            );
        }
        std::fs::write(
            format!("{path}.{}.csv", &name[..name.find(')').unwrap_or(0) + 1]),
            out,
        )
        .unwrap();
        let mut ev = String::from("t_start,t_end,n_blocks,n_slips,moment\n");
        for e in &ch.catalog.events {
            ev += &format!(
                "{},{},{},{},{}\n",
                e.t_start, e.t_end, e.n_blocks, e.n_slips, e.moment
            );
        }
        std::fs::write(
            format!(
                "{path}.{}.events.csv",
                &name[..name.find(')').unwrap_or(0) + 1]
            ),
            ev,
        )
        .unwrap();
    }
    Measured {
        name,
        recs,
        h_nom,
        h_stab,
        check,
        cpu: cpu_seconds() - cpu0,
        sim_time: ch.time() - t_start,
        switches: ch.counters.switches,
        per_block,
        backward: ch.catalog.slips.iter().filter(|r| r.dir < 0).count(),
        t_far_end: ch
            .catalog
            .slips
            .iter()
            .filter(|r| r.block + 1 == model_n)
            .map(|r| r.t_start)
            .fold(f64::NAN, f64::min),
    }
}

/// Bins of a block's local error: a tenth of a decade each from 1e-20 (bin 0: below).
const ERR_BINS: usize = 160;
/// Time bins of the per-block errors (one per unit of time).
const MAX_TIME_BINS: usize = 100_000;

fn err_bin(e: f64) -> usize {
    if e > 0.0 {
        (((e.log10() + 20.0) * 10.0).floor().max(0.0) as usize).min(ERR_BINS - 1)
    } else {
        0
    }
}

/// The upper edge of error bin k.
fn err_edge(k: usize) -> f64 {
    10f64.powf((k + 1) as f64 / 10.0 - 20.0)
}

/// Block updates of a per-block (multirate) controller as a fraction of the engine's, at
/// tolerance tol, over the steps starting in [t_a, t_b): each block its own step
/// h (tol/e_i)^(1/5) (at most the stability limit), with no forced ends and no coupling
/// between the blocks' steps (a looser bound than `bound`).
fn multirate_bound(m: &Measured, tol: f64, t_a: f64, t_b: f64) -> f64 {
    let (mut engine, mut ctrl) = (0.0, 0.0);
    for (t, hist) in m.per_block.iter().enumerate() {
        let t = t as f64;
        if t + 1.0 <= t_a || t >= t_b {
            continue;
        }
        for (k, &c) in hist.iter().enumerate() {
            engine += c;
            ctrl += c * (m.h_nom / m.h_stab).max((err_edge(k) / tol).powf(0.2));
        }
    }
    ctrl / engine
}

/// The q-quantile of the finite values of x (q = 1: the max).
fn quantile(x: impl Iterator<Item = f64>, q: f64) -> f64 {
    let mut v: Vec<f64> = x.filter(|e| e.is_finite()).collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    if v.is_empty() {
        return f64::NAN;
    }
    v[((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)]
}

/// Steps and block updates of an ideal controller (module doc), as fractions of the
/// engine's: (steps, block updates).
fn bound(m: &Measured, recs: &[Rec], tol_loc: f64, tol_dense: Option<f64>) -> (f64, f64) {
    let (mut e_steps, mut e_blocks) = (0.0, 0.0);
    let (mut c_steps, mut c_blocks) = (0.0, 0.0);
    let (mut frac, mut seg_t, mut seg_bt, mut redo_s, mut redo_b) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (k, r) in recs.iter().enumerate() {
        e_steps += r.steps as f64;
        e_blocks += (r.steps * r.active) as f64;
        redo_s += (r.steps - 1) as f64;
        redo_b += ((r.steps - 1) * r.active) as f64;
        let ratio = if r.e_loc.is_nan() || r.h <= 0.0 {
            1.0
        } else {
            let mut x = m.h_stab / r.h;
            if r.e_loc > 0.0 {
                x = x.min((tol_loc / r.e_loc).powf(0.2));
            }
            if let Some(td) = tol_dense {
                if r.e_dense > 0.0 {
                    x = x.min((td / r.e_dense).powf(0.25));
                }
            }
            x
        };
        // a step the engine did not estimate counts as one controller step
        let h = if r.h > 0.0 { r.h } else { m.h_nom };
        frac += 1.0 / ratio;
        seg_t += h;
        seg_bt += h * r.active as f64;
        if r.forced || k + 1 == recs.len() {
            let ks = (frac - 1e-9).ceil().max(1.0);
            c_steps += ks + redo_s;
            c_blocks += ks * seg_bt / seg_t + redo_b;
            (frac, seg_t, seg_bt, redo_s, redo_b) = (0.0, 0.0, 0.0, 0.0, 0.0);
        }
    }
    (c_steps / e_steps, c_blocks / e_blocks)
}

/// The bound of a run: tolerances from the steps whose start lies in `fast` (the fast
/// phase), savings over the whole run and over its phases before and after `split`.
fn report(m: &Measured, fast: (f64, f64), split: Option<f64>) {
    let recs = &m.recs;
    let n_steps: u64 = recs.iter().map(|r| r.steps).sum();
    let n_blocks: u64 = recs.iter().map(|r| r.steps * r.active).sum();
    let est = recs.iter().filter(|r| !r.e_loc.is_nan()).count();
    println!(
        "\n## {}\n  simulated {:.4} time units in {} engine steps ({} redone), {} block updates \
         (mean {:.1} sliding), {} switches ({} backward slips); {} of {} steps estimated; measurement CPU {:.1} s",
        m.name,
        m.sim_time,
        n_steps,
        recs.iter().filter(|r| r.steps > 1).count(),
        n_blocks,
        n_blocks as f64 / n_steps as f64,
        m.switches,
        m.backward,
        est,
        recs.len(),
        m.cpu
    );
    println!(
        "  one RK4 step here vs the engine's: max |difference| {:.1e} (must be rounding)",
        m.check
    );
    println!(
        "  h_nom = {:.3e}, stability cap h* <= {:.3e} ({:.1} h_nom)",
        m.h_nom,
        m.h_stab,
        m.h_stab / m.h_nom
    );
    let in_fast = |r: &&Rec| r.t0 >= fast.0 && r.t0 < fast.1;
    let el = || recs.iter().filter(in_fast).map(|r| r.e_loc);
    let ed = || recs.iter().filter(in_fast).map(|r| r.e_dense);
    println!(
        "  fast phase t in [{}, {}): local error per step: median {:.1e}, p90 {:.1e}, p99 {:.1e}, \
         max {:.1e}; dense-output error: median {:.1e}, p90 {:.1e}, p99 {:.1e}, max {:.1e}",
        fast.0,
        fast.1,
        quantile(el(), 0.5),
        quantile(el(), 0.9),
        quantile(el(), 0.99),
        quantile(el(), 1.0),
        quantile(ed(), 0.5),
        quantile(ed(), 0.9),
        quantile(ed(), 0.99),
        quantile(ed(), 1.0)
    );
    let mut phases: Vec<(String, &[Rec], f64, f64)> =
        vec![("whole run".to_string(), &recs[..], 0.0, f64::INFINITY)];
    if let Some(ts) = split {
        let k = recs.iter().position(|r| r.t0 >= ts).unwrap_or(recs.len());
        phases.push((format!("t < {ts:.4}"), &recs[..k], 0.0, ts));
        phases.push((format!("t >= {ts:.4}"), &recs[k..], ts, f64::INFINITY));
    }
    println!(
        "  | phase | tolerance (fast-phase quantile: local / dense) | block updates of the phase \
         | mean steps between forced ends | steps, local error only | block updates, local only \
         | steps, + dense output | block updates, + dense output | block updates, per-block \
         steps (multirate), local only |"
    );
    for (label, part, t_a, t_b) in &phases {
        let blocks: u64 = part.iter().map(|r| r.steps * r.active).sum();
        let ends = part.iter().filter(|r| r.forced).count().max(1);
        for (q_label, q) in [("max", 1.0), ("p99", 0.99), ("p90", 0.9)] {
            let tl = quantile(el(), q);
            let td = quantile(ed(), q);
            let (s1, b1) = bound(m, part, tl, None);
            let (s2, b2) = bound(m, part, tl, Some(td));
            let mr = multirate_bound(m, tl, *t_a, *t_b);
            println!(
                "  | {label} | {q_label}: {tl:.1e} / {td:.1e} | {blocks} | {:.2} | {s1:.3} ({:.2}x) \
                 | {b1:.3} ({:.2}x) | {s2:.3} ({:.2}x) | {b2:.3} ({:.2}x) | {mr:.3} ({:.2}x) |",
                part.len() as f64 / ends as f64,
                1.0 / s1,
                1.0 / b1,
                1.0 / s2,
                1.0 / b2,
                1.0 / mr
            );
        }
    }
    // where the work is: block updates by the step ratio h*/h a max-tolerance controller
    // would allow (local error only, before the segment constraint)
    let tl = quantile(el(), 1.0);
    let mut w: Vec<(f64, f64)> = recs
        .iter()
        .filter(|r| !r.e_loc.is_nan() && r.h > 0.0)
        .map(|r| {
            let x = (m.h_stab / r.h).min(if r.e_loc > 0.0 {
                (tl / r.e_loc).powf(0.2)
            } else {
                f64::INFINITY
            });
            (x, (r.steps * r.active) as f64)
        })
        .collect();
    w.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    let total: f64 = w.iter().map(|x| x.1).sum();
    let mut acc = 0.0;
    let mut marks = vec![];
    let mut next = [0.1, 0.25, 0.5, 0.75, 0.9].into_iter().peekable();
    for (x, b) in &w {
        acc += b;
        while let Some(&q) = next.peek() {
            if acc >= q * total {
                marks.push(format!("{:.0}%: {:.2}", q * 100.0, x));
                next.next();
            } else {
                break;
            }
        }
    }
    println!(
        "  h*/h allowed by the local error (max tolerance), quantiles over block updates, before \
         the forced ends: {}",
        marks.join(", ")
    );
}

fn front(
    u_plus: f64,
    gamma: f64,
    beta: f64,
    dx: f64,
    n: usize,
    step: f64,
) -> (Chain<Coulomb>, Model) {
    let cfg = ChainConfig { dx, v: 0.0, step };
    let fr = Coulomb::new(gamma, beta).unwrap();
    let mut ch = Chain::new(cfg, fr, &Free, &vec![u_plus; n], None).unwrap();
    ch.add_trigger(Trigger {
        t: 0.0,
        block: 0,
        kind: TriggerKind::Kick { du_t: -2.0 },
    })
    .unwrap();
    (
        ch,
        Model {
            dx,
            v: 0.0,
            gamma,
            beta,
        },
    )
}

/// The loading run of benchmarks/chain_limit (smooth initial stress, free ends).
#[allow(clippy::too_many_arguments)]
fn loading(
    n: usize,
    dx: f64,
    gamma: f64,
    beta: f64,
    v: f64,
    mean: f64,
    step: f64,
) -> (Chain<Coulomb>, Model) {
    let cfg = ChainConfig { dx, v, step };
    let fr = Coulomb::new(gamma, beta).unwrap();
    let l = n as f64 * dx;
    let u0: Vec<f64> = (0..n)
        .map(|i| {
            let x = i as f64 * dx / l * std::f64::consts::TAU;
            mean + 0.06 * (3.0 * x).sin() + 0.03 * (7.0 * x + 1.0).sin() + 0.01 * (19.0 * x).cos()
        })
        .collect();
    let ch = Chain::new(cfg, fr, &Free, &u0, None).unwrap();
    (ch, Model { dx, v, gamma, beta })
}

/// A finished run with and without step-size control.
struct Controlled {
    cpu: f64,
    steps: u64,
    block_steps: u64,
    /// Energy balance residual over the dissipated energy.
    residual: f64,
    /// Event start times and moments.
    events: Vec<(f64, f64)>,
    /// First slip time of every block (NaN: never).
    first_slip: Vec<f64>,
}

fn run_controlled(
    make: &dyn Fn(f64) -> Chain<Coulomb>,
    step: f64,
    tol: Option<f64>,
    t_end: f64,
    events: usize,
    repeat: usize,
) -> Controlled {
    let mut cpus = Vec::new();
    let mut last = None;
    for _ in 0..repeat {
        let mut ch = make(step);
        ch.set_step_control(tol).unwrap();
        let e0 = {
            let (k, c, l) = ch.energy();
            k + c + l
        };
        let c0 = cpu_seconds();
        ch.run(t_end, events, u64::MAX).unwrap();
        cpus.push(cpu_seconds() - c0);
        let (k, c, l) = ch.energy();
        let led = ch.ledger;
        let flows = led.load - led.dry - led.viscous - led.projection + led.injected;
        let residual = ((k + c + l) - e0 - flows) / (led.dry + led.viscous);
        let mut first_slip = vec![f64::NAN; ch.n()];
        for r in &ch.catalog.slips {
            if first_slip[r.block].is_nan() {
                first_slip[r.block] = r.t_start;
            }
        }
        last = Some(Controlled {
            cpu: 0.0,
            steps: ch.counters.steps,
            block_steps: ch.counters.block_steps,
            residual,
            events: ch
                .catalog
                .events
                .iter()
                .map(|e| (e.t_start, e.moment))
                .collect(),
            first_slip,
        });
    }
    cpus.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mut r = last.unwrap();
    r.cpu = cpus[cpus.len() / 2];
    r
}

/// The creeping event of (b'') alone: the state before it (all stuck, from the default
/// run) is the start of fresh chains at the default step, half of it, and with control;
/// each runs that one event. Its duration, slips, moment and final state against the
/// reference's.
fn creep_event_comparison(repeat: usize) {
    let inf = f64::INFINITY;
    let (mut ch, _) = loading(2000, 0.05, 0.45, inf, 1e-4, 0.2, DEFAULT_STEP);
    ch.run(inf, 26, u64::MAX).unwrap();
    let u_before = ch.u();
    println!(
        "\n## (b'') its 27th event alone (from the state after 26 events at the default step, t = {:.3})",
        ch.time()
    );
    println!(
        "  | run | CPU s | steps | block updates | duration | slips | moment | max |u - u_ref| at the end \
         | energy residual / dissipated |"
    );
    let one = |step: f64, tol: Option<f64>| {
        let mut cpus = vec![];
        let mut out = None;
        for _ in 0..repeat {
            let cfg = ChainConfig {
                dx: 0.05,
                v: 1e-4,
                step,
            };
            let mut c = Chain::new(
                cfg,
                Coulomb::new(0.45, inf).unwrap(),
                &Free,
                &u_before,
                None,
            )
            .unwrap();
            c.set_step_control(tol).unwrap();
            let e0 = {
                let (k, cc, l) = c.energy();
                k + cc + l
            };
            let c0 = cpu_seconds();
            c.run(inf, 1, u64::MAX).unwrap();
            cpus.push(cpu_seconds() - c0);
            let (k, cc, l) = c.energy();
            let led = c.ledger;
            let flows = led.load - led.dry - led.viscous - led.projection + led.injected;
            let ev = c.catalog.events[0];
            out = Some((
                c.counters.steps,
                c.counters.block_steps,
                ev.t_end - ev.t_start,
                ev.n_slips,
                ev.moment,
                c.u(),
                ((k + cc + l) - e0 - flows) / (led.dry + led.viscous),
                ev.t_end,
            ));
        }
        cpus.sort_by(|a, b| a.partial_cmp(b).unwrap());
        (cpus[cpus.len() / 2], out.unwrap())
    };
    let (_, reference) = one(DEFAULT_STEP / 2.0, None);
    let rows: Vec<(String, f64, Option<f64>)> = vec![
        (
            "fixed step 0.025 (reference)".into(),
            DEFAULT_STEP / 2.0,
            None,
        ),
        ("fixed step 0.05 (default)".into(), DEFAULT_STEP, None),
        ("controlled, tol 1e-12".into(), DEFAULT_STEP, Some(1e-12)),
        ("controlled, tol 1e-11".into(), DEFAULT_STEP, Some(1e-11)),
        ("controlled, tol 1e-10".into(), DEFAULT_STEP, Some(1e-10)),
    ];
    for (label, step, tol) in rows {
        let (cpu, r) = one(step, tol);
        // the final states compared at the same time: each drifts (all stuck) to the later end
        let t_end = r.7.max(reference.7);
        let du = r
            .5
            .iter()
            .zip(&reference.5)
            .map(|(a, b)| ((a + 1e-4 * (t_end - r.7)) - (b + 1e-4 * (t_end - reference.7))).abs())
            .fold(0.0, f64::max);
        println!(
            "  | {label} | {cpu:.3} | {} | {} | {:.6} | {} | {:.9} | {du:.1e} | {:.1e} |",
            r.0, r.1, r.2, r.3, r.4, r.6
        );
    }
}

/// The controller against the fixed step at matched accuracy (`--controller`): each case
/// at the default step, at half of it (the reference), and with step-size control at
/// several tolerances; CPU times, work, the energy books, and the events' start times and
/// moments (loading) or a front's c (first slips of the middle fifth of the chain)
/// against the reference.
fn controller_comparison(quick: bool) {
    let inf = f64::INFINITY;
    let repeat = if quick { 1 } else { 3 };
    let events = if quick { 6 } else { 30 };
    println!("# Step-size control against the fixed step (CPU: medians of {repeat})");
    type Make = Box<dyn Fn(f64) -> Chain<Coulomb>>;
    let cases: Vec<(&str, Make, f64, usize, bool)> = vec![
        (
            "(b'') loading: 2000 blocks, dx = 0.05, gamma = 0.45, v = 1e-4, 30 events",
            Box::new(move |step| loading(2000, 0.05, 0.45, inf, 1e-4, 0.2, step).0),
            inf,
            events,
            false,
        ),
        (
            "(a) loading: 2000 blocks, dx = 0.05, gamma = 0.3, v = 1e-4, 30 events",
            Box::new(move |step| loading(2000, 0.05, 0.3, inf, 1e-4, 0.6, step).0),
            inf,
            events,
            false,
        ),
        (
            "front u_+ = 0.6, gamma = 0.45, dx = 0.025, 2000 blocks (c from the middle fifth)",
            Box::new(move |step| front(0.6, 0.45, inf, 0.025, 2000, step).0),
            0.9 * 2000.0 * 0.025 / 1.24,
            usize::MAX,
            true,
        ),
    ];
    creep_event_comparison(repeat);
    for (name, make, t_end, ev, is_front) in &cases {
        println!("\n## {name}");
        let reference = run_controlled(make.as_ref(), DEFAULT_STEP / 2.0, None, *t_end, *ev, 1);
        let speed = |r: &Controlled| {
            let n = r.first_slip.len();
            let (a, b) = (2 * n / 5, 3 * n / 5);
            let dx = 0.025;
            dx * (b - a) as f64 / (r.first_slip[b] - r.first_slip[a])
        };
        println!(
            "  | run | CPU s | steps | block updates | energy residual / dissipated | events | \
             max |t_start - ref| | max |moment/ref - 1| | c - c_ref |"
        );
        let mut rows = vec![(
            "fixed step 0.025 (reference)".to_string(),
            None,
            DEFAULT_STEP / 2.0,
        )];
        rows.push(("fixed step 0.05 (default)".to_string(), None, DEFAULT_STEP));
        for tol in [1e-12, 1e-11, 1e-10] {
            rows.push((
                format!("controlled, tol {tol:.0e}"),
                Some(tol),
                DEFAULT_STEP,
            ));
        }
        for (label, tol, step) in rows {
            let r = if tol.is_none() && step == DEFAULT_STEP / 2.0 {
                run_controlled(make.as_ref(), step, None, *t_end, *ev, repeat)
            } else {
                run_controlled(make.as_ref(), step, tol, *t_end, *ev, repeat)
            };
            let k = r.events.len().min(reference.events.len());
            let dt = (0..k)
                .map(|i| (r.events[i].0 - reference.events[i].0).abs())
                .fold(0.0, f64::max);
            let dm = (0..k)
                .map(|i| (r.events[i].1 / reference.events[i].1 - 1.0).abs())
                .fold(0.0, f64::max);
            let dc = if *is_front {
                format!("{:+.2e}", speed(&r) - speed(&reference))
            } else {
                "-".to_string()
            };
            println!(
                "  | {label} | {:.3} | {} | {} | {:.1e} | {} | {dt:.1e} | {dm:.1e} | {dc} |",
                r.cpu,
                r.steps,
                r.block_steps,
                r.residual,
                r.events.len()
            );
        }
    }
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    if std::env::args().any(|a| a == "--controller") {
        controller_comparison(quick);
        return;
    }
    let scale = if quick { 0.2 } else { 1.0 };
    let inf = f64::INFINITY;
    println!("# Step-size control: an upper bound on the saving (issue 16)");
    println!(
        "default step {DEFAULT_STEP} dx; tolerances: the fixed step's own local and dense-output \
         errors (max, p99, p90 over the run's steps); ratios are controller / engine"
    );

    // (a) the loading run of benchmarks/chain_limit; every event is a fast phase
    let events = if quick { 6 } else { 30 };
    let (ch, m) = loading(2000, 0.05, 0.3, inf, 1e-4, 0.6, DEFAULT_STEP);
    report(
        &measure(
            "(a) loading: 2000 blocks, dx = 0.05, gamma = 0.3, v = 1e-4, beta = inf, 30 events",
            ch,
            &m,
            inf,
            events,
        ),
        (0.0, inf),
        None,
    );
    // (b'') loading cycles in the creep range: the same smooth stress about 0.2 < u_c
    let (ch, m) = loading(2000, 0.05, 0.45, inf, 1e-4, 0.2, DEFAULT_STEP);
    report(
        &measure(
            "(b'') loading in the creep range: as (a), gamma = 0.45, stress about 0.2, 30 events",
            ch,
            &m,
            inf,
            events,
        ),
        (0.0, inf),
        None,
    );
    // a front from a kick at block 0, run for twice its crossing: the fast phase is the
    // front's crossing after the kick's transient (t >= 1), the rest the chain behind it
    let n = (1000.0 * scale) as usize;
    let fronts = [
        (
            "(b) creep front: u_+ = 0.3, gamma = 0.45, beta = inf, dx = 0.05, 1000 blocks, v = 0",
            (0.3, 0.45, inf, 0.05, n, 1.05),
        ),
        (
            "(b') creep front: u_+ = 0.2, gamma = 0.3, beta = inf, dx = 0.05, 1000 blocks, v = 0",
            (0.2, 0.3, inf, 0.05, n, 1.02),
        ),
        (
            "(p) pulse (for comparison): u_+ = 0.6, gamma = 0.3, beta = inf, dx = 0.05, 1000 \
             blocks, v = 0",
            (0.6, 0.3, inf, 0.05, n, 1.24),
        ),
        (
            "(c) chatter behind a pulse: u_+ = 0.6, gamma = 0.3, beta = 0, dx = 0.05, 1000 \
             blocks, v = 0",
            (0.6, 0.3, 0.0, 0.05, n, 1.24),
        ),
        (
            "(c') chatter at gamma = 0: u_+ = 0.5, gamma = 0, beta = 0, dx = 0.1, 400 blocks, \
             v = 0",
            (0.5, 0.0, 0.0, 0.1, (400.0 * scale) as usize, 1.15),
        ),
    ];
    for (name, (u_plus, gamma, beta, dx, blocks, c)) in fronts {
        let (ch, m) = front(u_plus, gamma, beta, dx, blocks, DEFAULT_STEP);
        let t_cross = blocks as f64 * dx / c;
        let r = measure(name, ch, &m, 2.0 * t_cross, usize::MAX);
        let t_far = if r.t_far_end.is_nan() {
            t_cross
        } else {
            r.t_far_end
        };
        report(&r, (1.0, t_far), Some(t_far));
    }
    // (c'') loading cycles with backward slip
    let (ch, m) = loading(2000, 0.05, 0.3, 0.0, 1e-4, 0.6, DEFAULT_STEP);
    report(
        &measure(
            "(c'') loading with backward slip: as (a), beta = 0, 30 events",
            ch,
            &m,
            inf,
            events,
        ),
        (0.0, inf),
        None,
    );
}
