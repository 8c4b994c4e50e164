//! The lattice engine against the real limit (issue 25; docs/benchmarks.md).
//!
//! 1. The reference: the bare RK4 five-point stencil over an m x m grid of sliding blocks
//!    (every block sliding forward, Coulomb friction, beta = inf; one fused pass per
//!    stage, two stage buffers), as baseline x86-64 code and as AVX2 code (the engine
//!    picks the widest code its CPU runs); the best is the reference.
//! 2. The engine: an expanding rupture from a point (u_+ = 0.6, gamma = 0.45, dx = dy =
//!    0.05, v = 0) on a quadrant of `size` x `size` blocks with free edges (mirror
//!    planes), kicked at its corner and stopped when the front has crossed 90 % of it:
//!    sliding-block updates per CPU second, as a ratio to the reference over m^2 blocks
//!    measured in the same round (global cut: m^2 = block-steps / steps, the mean of
//!    its steps, all full passes; local events, whose steps count their components'
//!    sub-steps: the time average below). Each round runs the rupture with the global
//!    cut and with local events (`--events both`, the default; or one of them), and
//!    also reports the CPU time a bare stencil would take for the same rupture (the
//!    time-averaged number of sliding blocks, from a sampled run of its own, times T/h
//!    steps of the fixed step h, at the reference's rate over that many blocks) over the
//!    engine's CPU time.
//! 3. Memory: the memory allocated (VmData) by building a lattice of n x n blocks, per
//!    block, and the resident memory (VmRSS) it adds: a page of a zeroed array is resident
//!    only once written, so the resident figure grows to the allocated one as a rupture
//!    crosses the lattice (`--full` runs one across it and reports the peak).
//!
//! All times are CPU times of the work (the machine is shared).
//!
//! 4. `--kernel M` (alone): the engine's RK4 step by itself (no event search, no redo)
//!    over an M x M square of sliding blocks, against the reference over M x M;
//!    `--kernel M,W`: the same square in the corner of a W x W grid (rows of M sliding
//!    blocks at the stride of W, as a rupture's runs lie in a wider lattice; in strips,
//!    at the strips' stride, cut at their seams).
//!
//! 5. `--shape S` (alone, after `--size`): the rupture's runs and the stuck cells and
//!    ghosts next to them, averaged over S equally spaced times (global cut).
//!
//! `--strips W` (before the others): the lattice's cells in strips of at most W columns
//! (default the engine's layout: one strip up to 256 columns, strips of 62 beyond; W >=
//! the lattice's width: one strip, row-major).
//!
//! cargo run --release -- [--strips W] [--repeat R] [--size L] [--memory N1,N2,..]
//!     [--full N,dx,gamma] [--events local|global|both] [--give-back on|off] [--smaps]
//!     [--kernel M[,W]] [--shape S]

use bkwaves_core::boundary::Free;
use bkwaves_core::chain::cells::CellVec;
use bkwaves_core::chain::medium::Uniform;
use bkwaves_core::chain::{ChainConfig, Trigger, TriggerKind};
use bkwaves_core::friction::Coulomb;
use bkwaves_core::lattice::{Lattice, LatticeSpec};

/// CPU time of this process in seconds (CLOCK_PROCESS_CPUTIME_ID). Linux.
fn cpu_seconds() -> f64 {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    extern "C" {
        fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
    }
    const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
    let mut ts = Timespec { sec: 0, nsec: 0 };
    // SAFETY: clock_gettime writes one timespec into the struct we own.
    let rc = unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime");
    ts.sec as f64 + 1e-9 * ts.nsec as f64
}

/// `--smaps`: after the `--full` run, the resident memory of every mapping of at least
/// 256 kB (/proc/self/smaps), per block, with the arrays it holds where known.
static SMAPS: std::sync::OnceLock<bool> = std::sync::OnceLock::new();

/// Print the mappings of /proc/self/smaps with at least 256 kB resident: start, size and
/// resident bytes, per block of the lattice, and the name of a known array in it.
fn smaps_report(known: &[(String, usize)], blocks: f64) {
    let s = std::fs::read_to_string("/proc/self/smaps").unwrap_or_default();
    let mut maps: Vec<(usize, usize, String, f64)> = Vec::new();
    for line in s.lines() {
        let head = line.split_whitespace().next().unwrap_or("");
        if let Some((a, b)) = head.split_once('-') {
            if let (Ok(a), Ok(b)) = (usize::from_str_radix(a, 16), usize::from_str_radix(b, 16)) {
                let name = line.split_whitespace().nth(5).unwrap_or("").to_string();
                maps.push((a, b, name, 0.0));
                continue;
            }
        }
        if let Some(rest) = line.strip_prefix("Rss:") {
            let kb: f64 = rest
                .trim()
                .trim_end_matches("kB")
                .trim()
                .parse()
                .unwrap_or(0.0);
            if let Some(m) = maps.last_mut() {
                m.3 = kb * 1024.0;
            }
        }
    }
    let total: f64 = maps.iter().map(|m| m.3).sum();
    println!(
        "smaps: {} mappings, resident {:.1} bytes per block in all (VmRSS {:.1}); those \
         of 256 kB or more:",
        maps.len(),
        total / blocks,
        status_bytes("VmRSS:") / blocks
    );
    let mut small = 0.0;
    for (a, b, name, rss) in &maps {
        if *rss < 262144.0 {
            small += rss;
            continue;
        }
        let held: Vec<&str> = known
            .iter()
            .filter(|(_, p)| (*a..*b).contains(p))
            .map(|(k, _)| k.as_str())
            .collect();
        println!(
            "smaps:   {a:#x} size {:9.1} MB ({:6.2} B/block) resident {:9.1} MB ({:6.2} \
             B/block) {name} {}",
            (b - a) as f64 / 1e6,
            (b - a) as f64 / blocks,
            rss / 1e6,
            rss / blocks,
            held.join(",")
        );
    }
    println!("smaps:   the rest: {:.2} B/block", small / blocks);
    // glibc's own books: the heap (brk) in use and free, and its mmapped chunks
    #[repr(C)]
    #[derive(Default)]
    struct Mallinfo2 {
        arena: usize,
        ordblks: usize,
        smblks: usize,
        hblks: usize,
        hblkhd: usize,
        usmblks: usize,
        fsmblks: usize,
        uordblks: usize,
        fordblks: usize,
        keepcost: usize,
    }
    extern "C" {
        fn mallinfo2() -> Mallinfo2;
    }
    // SAFETY: mallinfo2 only reads the allocator's statistics
    let m = unsafe { mallinfo2() };
    println!(
        "malloc: heap {:.2} B/block ({:.2} in use, {:.2} free), mmapped chunks {:.2} B/block \
         ({} of them)",
        m.arena as f64 / blocks,
        m.uordblks as f64 / blocks,
        m.fordblks as f64 / blocks,
        m.hblkhd as f64 / blocks,
        m.hblks
    );
}

/// A memory figure of this process in bytes from /proc/self/status: "VmRSS" (resident)
/// or "VmData" (allocated: the heap and anonymous mappings, touched or not).
fn status_bytes(key: &str) -> f64 {
    let s = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    s.lines()
        .find(|l| l.starts_with(key))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|k| k.parse::<f64>().ok())
        .map_or(f64::NAN, |k| 1024.0 * k)
}

const U_PLUS: f64 = 0.6;
const GAMMA: f64 = 0.45;
const DX: f64 = 0.05;
const STEP: f64 = 0.05;

/// The bare stencil: m x m sliding blocks in (m + 2)^2 padded cells, the border held.
struct Reference {
    m: usize,
    k: f64,
    g2: f64,
    h: f64,
    /// u, w, then the RK4 sums (ku, kw) and two stage buffers (su, sw), (tu, tw), each
    /// at its own offset in the memory page as the engine's arrays (`CellVec`: arrays
    /// that all start at one offset run the loop up to 1.3 times slower, 4K aliasing).
    b: [CellVec; 8],
}

#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn stage(
    m: usize,
    cu: &[f64],
    cw: &[f64],
    u0: &[f64],
    w0: &[f64],
    ku: &mut [f64],
    kw: &mut [f64],
    nu: &mut [f64],
    nw: &mut [f64],
    k: f64,
    g2: f64,
    wt: f64,
    cn: f64,
    first: bool,
) {
    let s = m + 2;
    for j in 1..=m {
        let a = j * s + 1;
        let b = a + m;
        let (l, c, r) = (&cu[a - 1..b - 1], &cu[a..b], &cu[a + 1..b + 1]);
        let (d, up) = (&cu[a - s..b - s], &cu[a + s..b + s]);
        let (w, u0, w0) = (&cw[a..b], &u0[a..b], &w0[a..b]);
        let (ku, kw) = (&mut ku[a..b], &mut kw[a..b]);
        let (nu, nw) = (&mut nu[a..b], &mut nw[a..b]);
        for i in 0..m {
            let acc = (l[i] + r[i] - 2.0 * c[i]) * k + (d[i] + up[i] - 2.0 * c[i]) * k - c[i]
                + g2 * (0.0 - w[i]);
            if first {
                ku[i] = wt * w[i];
                kw[i] = wt * acc;
            } else {
                ku[i] += wt * w[i];
                kw[i] += wt * acc;
            }
            nu[i] = u0[i] + cn * w[i];
            nw[i] = w0[i] + cn * acc;
        }
    }
}

impl Reference {
    fn new(m: usize) -> Reference {
        let len = (m + 2) * (m + 2);
        let mut b: [CellVec; 8] = std::array::from_fn(|_| CellVec::new(len, 0.0));
        let x = |q: usize| 0.1 * q as f64;
        let [u, w, ..] = &mut b;
        for (q, (u, w)) in u.iter_mut().zip(w.iter_mut()).enumerate() {
            *u = 0.6 - 1e-3 * x(q).sin();
            *w = -1e-2 * x(q).cos();
        }
        for j in 2..8 {
            b[j] = b[j % 2].clone();
        }
        Reference {
            m,
            k: 1.0 / (DX * DX),
            g2: 2.0 * GAMMA,
            h: STEP * DX,
            b,
        }
    }

    #[inline(always)]
    fn body(&mut self, steps: u64) {
        let (m, k, g2, h) = (self.m, self.k, self.g2, self.h);
        let [u, w, ku, kw, su, sw, tu, tw] = &mut self.b;
        for _ in 0..steps {
            // stage 1 at (u, w): sums start; next stage values in (su, sw)
            stage(m, u, w, u, w, ku, kw, su, sw, k, g2, 1.0, 0.5 * h, true);
            stage(m, su, sw, u, w, ku, kw, tu, tw, k, g2, 2.0, 0.5 * h, false);
            stage(m, tu, tw, u, w, ku, kw, su, sw, k, g2, 2.0, h, false);
            // stage 4: the sums complete; the new state
            stage(m, su, sw, u, w, ku, kw, tu, tw, k, g2, 1.0, 0.0, false);
            let s = m + 2;
            for j in 1..=m {
                let a = j * s + 1;
                for q in a..a + m {
                    u[q] += h / 6.0 * ku[q];
                    w[q] += h / 6.0 * kw[q];
                }
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn run_avx2(&mut self, steps: u64) {
        self.body(steps)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    unsafe fn run_avx512(&mut self, steps: u64) {
        self.body(steps)
    }

    fn checksum(&self) -> f64 {
        self.b[0].iter().sum::<f64>() + self.b[1].iter().sum::<f64>()
    }
}

/// Updates per CPU second of the reference over m x m blocks (about `work` updates),
/// the best of baseline, AVX2 and AVX-512F code (those this CPU runs).
fn reference(m: usize, work: f64) -> f64 {
    let steps = (work / (m * m) as f64).ceil().max(1.0) as u64;
    let mut best: f64 = 0.0;
    for code in 0..3 {
        let mut r = Reference::new(m);
        let t = cpu_seconds();
        match code {
            0 => r.body(steps),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the CPU runs AVX2 (checked).
            1 if std::is_x86_feature_detected!("avx2") => unsafe { r.run_avx2(steps) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the CPU runs AVX-512F (checked).
            2 if std::is_x86_feature_detected!("avx512f") => unsafe { r.run_avx512(steps) },
            _ => continue,
        }
        let s = cpu_seconds() - t;
        assert!(r.checksum().is_finite());
        best = best.max((m * m) as f64 * steps as f64 / s);
    }
    best
}

fn lattice(n: usize, local: bool) -> Lattice<Coulomb> {
    lattice_at(n, DX, GAMMA, 0, local)
}

/// `--give-back on|off`: the engine's release of dead scratch pages forced on or off
/// (`Engine::set_release`; unset: the engine's default, on from 2^17 cells).
static GIVE_BACK: std::sync::OnceLock<bool> = std::sync::OnceLock::new();

/// `--strips W`: the widest strip of the lattice's cells (columns).
static STRIPS: std::sync::OnceLock<usize> = std::sync::OnceLock::new();

/// A grid in strips of `--strips` columns if given, else in the engine's default layout.
fn in_strips(g: bkwaves_core::chain::geometry::Grid) -> bkwaves_core::chain::geometry::Grid {
    STRIPS.get().map_or(g, |&w| g.with_strips(w))
}

/// An n x n lattice at uniform u_+ (free edges), kicked at block `at`.
fn lattice_at(n: usize, dx: f64, gamma: f64, at: usize, local: bool) -> Lattice<Coulomb> {
    let spec = LatticeSpec {
        nx: n,
        ny: n,
        dy: dx,
        x: &Free,
        y: &Free,
    };
    let cfg = ChainConfig {
        dx,
        v: 0.0,
        step: STEP,
    };
    let fr = Coulomb::new(gamma, f64::INFINITY).unwrap();
    let u0 = vec![U_PLUS; n * n];
    let mut la = match STRIPS.get() {
        Some(&w) => Lattice::lattice_in_strips(cfg, spec, w, fr, Uniform, &u0, None),
        None => Lattice::lattice(cfg, spec, fr, Uniform, &u0, None),
    }
    .unwrap();
    la.set_local_events(local);
    if let Some(on) = GIVE_BACK.get() {
        la.set_release(*on);
    }
    la.add_trigger(Trigger {
        t: 0.0,
        block: at,
        kind: TriggerKind::Kick { du_t: -2.0 },
    })
    .unwrap();
    la
}

/// The end time of the quadrant's rupture: the front has crossed 90 % of it (speed
/// about c = 1/sqrt(1 - u_+^2) = 1.25 in x per time).
fn rupture_end(size: usize) -> f64 {
    0.9 * size as f64 * DX / 1.25
}

/// The engine's rupture: (block-steps per CPU second, block-steps per step, block-steps,
/// steps, switches, CPU seconds).
fn engine(size: usize, local: bool) -> (f64, f64, u64, u64, u64, f64) {
    let mut la = lattice(size, local);
    let t = cpu_seconds();
    la.run(rupture_end(size), usize::MAX, u64::MAX).unwrap();
    let s = cpu_seconds() - t;
    let c = la.counters;
    if local {
        split(&la);
    }
    (
        c.block_steps as f64 / s,
        c.block_steps as f64 / c.steps as f64,
        c.block_steps,
        c.steps,
        c.switches,
        s,
    )
}

/// Where local events' block-steps went: the runs' passes in steps without switches,
/// their first and later passes in steps with switches, the components' sub-steps.
fn split(la: &Lattice<Coulomb>) {
    let c = la.counters;
    let l = la.local_stats();
    let share = |x: u64| 100.0 * x as f64 / c.block_steps as f64;
    println!(
        "local events' block-steps: quiet steps {} ({:.1} %), first passes {} ({:.1} \
             %), later passes {} ({:.1} %), components {} ({:.1} %) in {} sub-steps; {} \
             steps with switches, {} passes, {} components, {} members, {} fallbacks",
        l.quiet_block_steps,
        share(l.quiet_block_steps),
        l.first_block_steps,
        share(l.first_block_steps),
        l.later_block_steps,
        share(l.later_block_steps),
        l.component_block_steps,
        share(l.component_block_steps),
        l.component_substeps,
        l.event_steps,
        l.passes,
        l.components,
        l.members,
        l.fallbacks,
    );
}

/// The time average of the number of sliding blocks over the quadrant's rupture, from
/// `samples` equally spaced times (a run of its own, stopped at each: not timed; local
/// events). A bare stencil with the fixed step h needs (this) x T/h updates for the
/// rupture; block-steps / steps is no such mean (the global cut's steps are cut short
/// by the events, local events count their components' sub-steps as steps).
fn mean_sliding(size: usize, samples: usize) -> f64 {
    let mut la = lattice(size, true);
    let t_end = rupture_end(size);
    let mut sum = 0.0;
    for k in 1..=samples {
        la.run(t_end * k as f64 / samples as f64, usize::MAX, u64::MAX)
            .unwrap();
        sum += la.n_sliding() as f64;
    }
    sum / samples as f64
}

/// The runs and the cells next to them over the quadrant's rupture (`--shape S`: S
/// equally spaced times of a run of its own, global cut), summed over the samples:
/// runs, blocks in runs, live stuck cells and ghosts next to the runs, list entries.
fn shape(size: usize, samples: usize) {
    let mut la = lattice(size, false);
    let t_end = rupture_end(size);
    let mut sum = [0usize; 5];
    for k in 1..=samples {
        la.run(t_end * k as f64 / samples as f64, usize::MAX, u64::MAX)
            .unwrap();
        let s = la.shape();
        for (x, y) in sum
            .iter_mut()
            .zip([s.runs, s.in_runs, s.stuck, s.ghosts, s.listed])
        {
            *x += y;
        }
    }
    let [runs, blocks, stuck, ghosts, listed] = sum.map(|x| x as f64 / samples as f64);
    println!(
        "shape of the {size} x {size} rupture (global cut, mean of {samples} times): {runs:.0} \
         runs of {:.1} blocks ({blocks:.0} sliding in runs); next to them {stuck:.0} stuck \
         cells and {ghosts:.0} ghosts ({:.3} and {:.3} per block in a run; {listed:.0} list \
         entries)",
        blocks / runs,
        stuck / blocks,
        ghosts / blocks
    );
}

/// The engine's RK4 step alone (no event search, no redo) over an m x m square of
/// sliding blocks inside a ring of stuck ones, in the corner of a grid of
/// max(m, width) + 2 blocks a side, its cells in strips (`--strips`): (block-steps per CPU
/// second, a checksum: the sum of u over the blocks in block order, the same bits in any
/// layout), `steps` steps, each with the end accelerations the next one starts from.
fn engine_step(m: usize, width: usize, steps: u64) -> (f64, f64) {
    use bkwaves_core::boundary::Ghost;
    use bkwaves_core::chain::geometry::{Geometry, Grid};
    use bkwaves_core::chain::integrator::{Method, Stepper};
    use bkwaves_core::chain::medium::Blocks;
    use bkwaves_core::chain::state::State;
    let n = m.max(width) + 2;
    let geo = Grid::new(
        n,
        n,
        DX,
        DX,
        (Ghost::Mirror, Ghost::Mirror),
        (Ghost::Mirror, Ghost::Mirror),
    );
    let geo = in_strips(geo);
    let u0: Vec<f64> = (0..n * n)
        .map(|q| 0.6 - 1e-3 * (0.1 * q as f64).sin())
        .collect();
    let mut st = State::with_geometry(geo, &u0, 0.0);
    for j in 1..=m {
        for i in 1..=m {
            let p = geo.at(i, j);
            st.dir[p] = 1.0;
            st.onset[p] = 1.0;
            // (of the block's index in one strip: the same start in any layout)
            let row_major = (j + 1) * (n + 2) + i + 1;
            st.w[p] = -1e-2 * (0.1 * row_major as f64).cos();
            st.add_to_runs(p);
        }
    }
    let fr = Blocks {
        fr: Coulomb::new(GAMMA, f64::INFINITY).unwrap(),
        med: Uniform,
    };
    let len = geo.cells();
    let mut rk = Stepper::new(Method::Rk4, len);
    let (mut a0, mut a1) = (CellVec::new(len, 0.0), CellVec::new(len, 0.0));
    let (mut us, mut ws) = (CellVec::new(len, 0.0), CellVec::new(len, 0.0));
    rk.accel_only(&mut st, &fr, 0.0, &mut a0);
    let h = STEP * DX;
    let t = cpu_seconds();
    for k in 0..steps {
        rk.step(
            &mut st,
            &fr,
            k as f64 * h,
            h,
            &a0,
            &mut us,
            &mut ws,
            &mut a1,
            false,
        );
        std::mem::swap(&mut a0, &mut a1);
    }
    let s = cpu_seconds() - t;
    let sum = geo.blocks().map(|p| st.u[p]).sum::<f64>();
    ((m * m) as f64 * steps as f64 / s, sum)
}

/// The events of the rounds' ruptures.
#[derive(Debug, Clone, Copy)]
enum Events {
    Local,
    Global,
    Both,
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (mut repeat, mut size, mut memory) = (3usize, 512usize, vec![1024usize, 2048]);
    let mut full: Option<(usize, f64, f64)> = None;
    // the engine's events in the rounds: both (the default), local (the lattice's
    // default) or the global cut; --full and --memory with local events unless global
    let mut events = Events::Both;
    let mut k = 1;
    while k < args.len() {
        match args[k].as_str() {
            "--repeat" => repeat = args[k + 1].parse().expect("--repeat R"),
            "--size" => size = args[k + 1].parse().expect("--size L"),
            "--memory" => {
                memory = args[k + 1]
                    .split(',')
                    .filter(|s| !s.is_empty())
                    .map(|s| s.parse().expect("--memory N1,N2"))
                    .collect()
            }
            "--kernel" => {
                // the step alone against the reference, over m x m blocks
                let bad = "--kernel M or M,W";
                let v: Vec<usize> = (args[k + 1].split(','))
                    .map(|s| s.parse().expect(bad))
                    .collect();
                assert!(v.len() == 1 || v.len() == 2, "{bad}");
                let (m, width) = (v[0], v.get(1).copied().unwrap_or(v[0]));
                let steps = (4e8 / (m * m) as f64).ceil() as u64;
                for _ in 0..repeat {
                    let (e, c) = engine_step(m, width, steps);
                    let r = reference(m, 4e8);
                    println!(
                        "kernel {m} x {m} in a {width}-wide grid: engine step {e:.3e}/s, \
                         reference {r:.3e}/s, ratio {:.3} (checksum {c:.6})",
                        e / r
                    );
                }
                return;
            }
            "--shape" => {
                // the rupture's runs and the cells next to them, then nothing else
                let n: usize = args[k + 1].parse().expect("--shape S: samples >= 1");
                assert!(n >= 1, "--shape S: samples >= 1");
                shape(size, n);
                return;
            }
            "--full" => {
                let v: Vec<&str> = args[k + 1].split(',').collect();
                let bad = "--full N,dx,gamma";
                assert!(v.len() == 3, "{bad}");
                full = Some((
                    v[0].parse().expect(bad),
                    v[1].parse().expect(bad),
                    v[2].parse().expect(bad),
                ));
            }
            "--events" => {
                events = match args[k + 1].as_str() {
                    "local" => Events::Local,
                    "global" => Events::Global,
                    "both" => Events::Both,
                    e => panic!("--events {e}: local, global or both"),
                }
            }
            "--give-back" => {
                let on = match args[k + 1].as_str() {
                    "on" => true,
                    "off" => false,
                    e => panic!("--give-back {e}: on or off"),
                };
                GIVE_BACK.set(on).expect("--give-back once");
            }
            "--strips" => {
                let w: usize = args[k + 1].parse().expect("--strips W: columns >= 1");
                assert!(w >= 1, "--strips W: columns >= 1");
                STRIPS.set(w).expect("--strips once");
            }
            "--smaps" => {
                // a flag: no value follows
                SMAPS.set(true).expect("--smaps once");
                k += 1;
                continue;
            }
            a => panic!(
                "unknown argument {a} (--strips W, --repeat R, --size L, --memory N1,N2, --full N,dx,gamma, \
                 --events local|global|both, --give-back on|off, --smaps, --kernel M[,W], --shape S)"
            ),
        }
        k += 2;
    }
    let modes: Vec<bool> = match events {
        Events::Local => vec![true],
        Events::Global => vec![false],
        Events::Both => vec![false, true],
    };
    println!(
        "lattice rupture: quadrant {size} x {size}, u+ = {U_PLUS}, gamma = {GAMMA}, \
         dx = dy = {DX}, step {STEP}, events {events:?}"
    );
    // the rupture as a bare stencil would take it: every sliding block at every step
    // of the fixed step h, the time-averaged number of sliding blocks over T/h steps
    let h = STEP * DX;
    let t_end = rupture_end(size);
    let mean = if repeat > 0 {
        mean_sliding(size, 200)
    } else {
        f64::NAN
    };
    let fixed_steps = (t_end / h).ceil();
    let stencil_work = mean * fixed_steps;
    let m_t = (mean.sqrt().round() as usize).max(2);
    if repeat > 0 {
        println!(
            "rupture to t = {t_end:.3}: time-averaged sliding blocks {mean:.0} (200 \
             samples), a stencil at h = {h} takes {fixed_steps} steps, {stencil_work:.4e} \
             updates (the reference over {m_t} x {m_t})"
        );
    }
    let mut ratios = vec![Vec::new(); 2];
    let mut speedups = vec![Vec::new(); 2];
    for round in 0..repeat {
        for &loc in &modes {
            let (eng, per_step, work, steps, switches, cpu) = engine(size, loc);
            // updates per CPU second against the reference over m^2 blocks: for the
            // global cut m^2 = block-steps / steps, as since the first measurement (its
            // steps are full passes over the sliding blocks); for local events (whose
            // steps count the components' sub-steps) the time average
            let m = if loc {
                m_t
            } else {
                (per_step.sqrt().round() as usize).max(2)
            };
            let refr = reference(m, work as f64);
            let ratio = eng / refr;
            // the CPU a bare stencil would take for this rupture, at the reference's
            // rate over m_t x m_t blocks
            let ref_t = if m == m_t {
                refr
            } else {
                reference(m_t, stencil_work)
            };
            let stencil_cpu = stencil_work / ref_t;
            let speedup = stencil_cpu / cpu;
            let mode = if loc { "local" } else { "global" };
            ratios[usize::from(loc)].push(ratio);
            speedups[usize::from(loc)].push(speedup);
            println!(
                "round {round}: events {mode}: engine {eng:.3e} updates/s ({work} \
                 block-steps, {per_step:.0} per step, {steps} steps, {switches} switches, \
                 {cpu:.2} s CPU), reference {m} x {m}: {refr:.3e}/s, ratio {ratio:.3}; \
                 a bare stencil: {stencil_cpu:.2} s CPU (reference {m_t} x {m_t} \
                 {ref_t:.3e}/s), stencil CPU / engine CPU {speedup:.3}"
            );
        }
    }
    let summary = |v: &mut Vec<f64>| {
        let (lo, hi) = (
            v.iter().copied().fold(f64::INFINITY, f64::min),
            v.iter().copied().fold(0.0, f64::max),
        );
        format!("median {:.3} [{lo:.3}, {hi:.3}]", median(v))
    };
    for &loc in &modes {
        let mode = if loc { "local" } else { "global" };
        let k = usize::from(loc);
        println!(
            "events {mode}: engine / reference (updates per CPU second) {}; stencil CPU / \
             engine CPU {}",
            summary(&mut ratios[k]),
            summary(&mut speedups[k])
        );
    }
    // --memory and --full: local events unless --events global
    let local = !matches!(events, Events::Global);
    for n in memory {
        let (data0, rss0) = (status_bytes("VmData:"), status_bytes("VmRSS:"));
        let la = lattice(n, local);
        let (data1, rss1) = (status_bytes("VmData:"), status_bytes("VmRSS:"));
        let blocks = (n * n) as f64;
        println!(
            "memory: {n} x {n} lattice: {:.1} bytes per block allocated, {:.1} resident \
             before its first step",
            (data1 - data0) / blocks,
            (rss1 - rss0) / blocks,
        );
        drop(la);
    }
    if let Some((n, dx, gamma)) = full {
        // a rupture from the centre across the whole lattice: the front (speed about
        // c = 1/sqrt(1 - u_+^2) = 1.25) stopped at 95 % of the way to the edges
        let mut la = lattice_at(n, dx, gamma, n / 2 + n * (n / 2), local);
        let t_end = 0.95 * 0.5 * n as f64 * dx / 1.25;
        let t = cpu_seconds();
        la.run(t_end, usize::MAX, u64::MAX).unwrap();
        let s = cpu_seconds() - t;
        let c = la.counters;
        if SMAPS.get().copied().unwrap_or(false) {
            // where the resident memory is at the end, mapping by mapping (the arrays of
            // 128 kB or more are mappings of their own), before anything else is allocated
            let mut known: Vec<(String, usize)> = la
                .scratch_arrays()
                .into_iter()
                .map(|(name, a)| (name.to_string(), a.as_ptr() as usize))
                .collect();
            known.push(("catalog.slips".into(), la.catalog.slips.as_ptr() as usize));
            known.push(("catalog.events".into(), la.catalog.events.as_ptr() as usize));
            smaps_report(&known, (n * n) as f64);
            // the engine's arrays one by one (mincore over their pages)
            let blocks = (n * n) as f64;
            let mut sum = 0.0;
            for (name, bytes, resident) in la.memory_arrays() {
                let r = resident.map(|r| r as f64);
                sum += r.unwrap_or(bytes as f64);
                println!(
                    "arrays:   {name:28} allocated {:7.2} B/block, resident {}",
                    bytes as f64 / blocks,
                    match r {
                        Some(r) => format!("{:7.2} B/block", r / blocks),
                        None => "(not measured: counted as allocated)".to_string(),
                    }
                );
            }
            println!(
                "arrays: {:.1} B/block in all, VmRSS {:.1}, VmHWM {:.1}",
                sum / blocks,
                status_bytes("VmRSS:") / blocks,
                status_bytes("VmHWM:") / blocks
            );
        }
        let slipped = {
            let mut seen = vec![false; n * n];
            for r in &la.catalog.slips {
                seen[r.block] = true;
            }
            seen.iter().filter(|&&x| x).count()
        };
        println!(
            "full: {n} x {n} lattice, dx = {dx}, gamma = {gamma}, u+ = {U_PLUS}, to t = {t_end:.2}: \
             {s:.1} s CPU, {} steps, {} block-steps ({:.3e}/s, mean sliding {:.0}), \
             {} switches, {} slips, {slipped} blocks slipped ({:.1} %), peak resident {:.1} \
             bytes per block (VmHWM {:.0} MB); events {}: {:?}",
            c.steps,
            c.block_steps,
            c.block_steps as f64 / s,
            c.block_steps as f64 / c.steps as f64,
            c.switches,
            la.catalog.slips.len(),
            100.0 * slipped as f64 / (n * n) as f64,
            status_bytes("VmHWM:") / (n * n) as f64,
            status_bytes("VmHWM:") / 1e6,
            if local { "local" } else { "global" },
            la.local_stats(),
        );
        if local {
            split(&la);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_step_is_rk4_of_the_sliding_lattice() {
        // one step of the fused reference against RK4 written out block by block:
        // u_tt = (Laplacian u)/dx^2 - u - 2 gamma u_t on the m x m interior, border held
        let m = 5;
        let mut r = Reference::new(m);
        let (u0, w0) = (r.b[0].clone(), r.b[1].clone());
        r.body(1);
        let s = m + 2;
        let (k, g2, h) = (r.k, r.g2, r.h);
        let rhs = |u: &[f64], w: &[f64]| -> (Vec<f64>, Vec<f64>) {
            let (mut du, mut dw) = (vec![0.0; s * s], vec![0.0; s * s]);
            for j in 1..=m {
                for i in 1..=m {
                    let q = j * s + i;
                    let lap = u[q - 1] + u[q + 1] + u[q - s] + u[q + s] - 4.0 * u[q];
                    du[q] = w[q];
                    dw[q] = k * lap - u[q] - g2 * w[q];
                }
            }
            (du, dw)
        };
        let axpy = |x: &[f64], a: f64, y: &[f64]| -> Vec<f64> {
            x.iter().zip(y).map(|(x, y)| x + a * y).collect()
        };
        let (k1u, k1w) = rhs(&u0, &w0);
        let (k2u, k2w) = rhs(&axpy(&u0, h / 2.0, &k1u), &axpy(&w0, h / 2.0, &k1w));
        let (k3u, k3w) = rhs(&axpy(&u0, h / 2.0, &k2u), &axpy(&w0, h / 2.0, &k2w));
        let (k4u, k4w) = rhs(&axpy(&u0, h, &k3u), &axpy(&w0, h, &k3w));
        for q in 0..s * s {
            let u = u0[q] + h / 6.0 * (k1u[q] + 2.0 * k2u[q] + 2.0 * k3u[q] + k4u[q]);
            let w = w0[q] + h / 6.0 * (k1w[q] + 2.0 * k2w[q] + 2.0 * k3w[q] + k4w[q]);
            assert!((r.b[0][q] - u).abs() < 1e-13, "u at {q}");
            assert!((r.b[1][q] - w).abs() < 1e-12, "u_t at {q}");
        }
    }
}
