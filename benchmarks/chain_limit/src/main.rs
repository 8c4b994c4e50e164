//! The chain engine against the real limit (issue 16; docs/benchmarks.md).
//!
//! 1. The reference: the bare RK4 stencil over n contiguous sliding blocks
//!    (src/reference.rs), in Rust (baseline x86-64 code and AVX2 code) and in C
//!    (reference.c, built here with `cc -O3 -march=native`), with the same n and step:
//!    block updates per second of each and their ratios.
//! 2. The regression benchmark (not timed in CI): the engine's sliding-block updates per
//!    second on one front (u_+ = 0.6, gamma = 0.45, dx = 0.00625, beta = inf) and on a
//!    loading run (2000 blocks, dx = 0.05, gamma = 0.3, v = 1e-4, 30 events), and on the
//!    same loading run on a four times finer lattice (8000 blocks, dx = 0.0125: the
//!    paper's continuum regime, wide pulses), each as a ratio to the best reference over
//!    the engine's mean number of sliding blocks, measured in the same round. Rounds are repeated; medians and spreads are printed.
//! 3. A diagnostic (not the goal's reference): the replay reference (src/replay.rs and the
//!    `replay` mode of reference.c): the same stencil over the run structure the engine
//!    steps on the loading run (recorded once, step by step: the lengths of the runs of
//!    sliding blocks of every step, redone steps included), and the engine's ratio to it.
//!
//! All times are CPU times of the work (the machine is shared: wall time would count the
//! other jobs).
//!
//! cargo run --release -- [--repeat R] [--json FILE]
//!
//! `--engine-only front|loading R`: only that engine run, R times, and its CPU times (no
//! reference: for a sampling profile of the engine, `perf record -g`).
//!
//! `--replay-only R`: record the loading run's run structure, print it, and time the
//! replay reference and the loading run R times (no front, no contiguous reference).

mod reference;
mod replay;

/// CPU time of this process in seconds (CLOCK_PROCESS_CPUTIME_ID): on a shared machine
/// wall time counts the other jobs too. Linux (and other POSIX systems with this clock).
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

/// A CPU-time stopwatch.
struct Cpu(f64);
impl Cpu {
    fn start() -> Self {
        Cpu(cpu_seconds())
    }
    fn elapsed(&self) -> f64 {
        cpu_seconds() - self.0
    }
}

use bkwaves_core::boundary::Free;
use bkwaves_core::chain::{Chain, ChainConfig, Stop, Trigger, TriggerKind};
use bkwaves_core::friction::Coulomb;
use reference::Reference;
use replay::{Replay, Runs};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Which code the Rust reference runs.
#[derive(Clone, Copy)]
enum Code {
    Baseline,
    Avx2,
    Avx512,
}

/// Updates per second of the Rust reference over n blocks (about `work` updates).
fn rust_reference(n: usize, dx: f64, gamma: f64, work: f64, code: Code) -> (f64, f64) {
    let steps = (work / n as f64).ceil() as u64;
    let mut r = Reference::new(n, dx, gamma, 0.05);
    r.run(10); // warm the caches
    let mut r = Reference::new(n, dx, gamma, 0.05);
    let t = Cpu::start();
    match code {
        Code::Baseline => r.run_baseline(steps),
        Code::Avx2 => r.run(steps),
        Code::Avx512 => {
            if r.run_avx512(steps).is_none() {
                return (0.0, f64::NAN);
            }
        }
    }
    let s = t.elapsed();
    ((n as u64 * steps) as f64 / s, r.checksum())
}

/// Updates per second of the C reference (and its checksum).
fn c_reference(exe: &PathBuf, n: usize, dx: f64, gamma: f64, work: f64) -> (f64, f64) {
    let steps = (work / n as f64).ceil() as u64;
    let out = Command::new(exe)
        .args([n.to_string(), steps.to_string()])
        .args([dx.to_string(), gamma.to_string(), "0.05".to_string()])
        .output()
        .expect("run the C reference");
    let s = String::from_utf8(out.stdout).unwrap();
    let mut it = s.split_whitespace().map(|x| x.parse::<f64>().unwrap());
    let (sec, chk) = (it.next().unwrap(), it.next().unwrap());
    ((n as u64 * steps) as f64 / sec, chk)
}

/// Updates per second of the Rust replay of `runs` (about `work` updates) and its
/// checksum.
fn rust_replay(runs: &Runs, dx: f64, gamma: f64, work: f64, code: Code) -> (f64, f64) {
    let passes = (work / runs.updates() as f64).ceil() as u64;
    Replay::new(runs, dx, gamma, 0.05).run(1); // warm the caches
    let mut r = Replay::new(runs, dx, gamma, 0.05);
    let t = Cpu::start();
    match code {
        Code::Baseline => r.run_baseline(passes),
        Code::Avx2 => r.run(passes),
        Code::Avx512 => {
            if r.run_avx512(passes).is_none() {
                return (0.0, f64::NAN);
            }
        }
    }
    let s = t.elapsed();
    ((runs.updates() * passes) as f64 / s, r.checksum())
}

/// Updates per second of the C replay of the runs in `file` (`updates` per pass, about
/// `work` updates) and its checksum.
fn c_replay(
    exe: &PathBuf,
    file: &PathBuf,
    updates: u64,
    dx: f64,
    gamma: f64,
    work: f64,
) -> (f64, f64) {
    let passes = (work / updates as f64).ceil() as u64;
    let out = Command::new(exe)
        .arg("replay")
        .arg(file)
        .args([passes.to_string(), dx.to_string(), gamma.to_string()])
        .arg("0.05")
        .output()
        .expect("run the C replay");
    assert!(out.status.success(), "the C replay failed");
    let s = String::from_utf8(out.stdout).unwrap();
    let mut it = s.split_whitespace().map(|x| x.parse::<f64>().unwrap());
    let (sec, chk) = (it.next().unwrap(), it.next().unwrap());
    ((updates * passes) as f64 / sec, chk)
}

fn build_c(flags: &[&str], name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let exe = dir.join("target").join(name);
    let st = Command::new("cc")
        .args(flags)
        .arg(dir.join("reference.c"))
        .arg("-o")
        .arg(&exe)
        .arg("-lm")
        .status()
        .expect("cc (gcc) is needed for the C reference");
    assert!(st.success(), "cc failed");
    exe
}

struct EngineRun {
    seconds: f64,
    block_steps: u64,
    steps: u64,
    switches: u64,
    /// The bits of the final u, u_t and energy books folded together: a change that
    /// should keep trajectories bit for bit must keep it.
    fingerprint: u64,
}

/// A fingerprint of a chain's final state (the bits of u, u_t, the time and the energy
/// books).
fn fingerprint(ch: &Chain<Coulomb>) -> u64 {
    let l = &ch.ledger;
    let books = [
        ch.time(),
        l.load,
        l.dry,
        l.viscous,
        l.projection,
        l.injected,
    ];
    let vals = ch.u().into_iter().chain(ch.u_t()).chain(books);
    vals.fold(0xcbf29ce484222325u64, |f, x| {
        (f ^ x.to_bits()).wrapping_mul(0x100000001b3)
    })
}

impl EngineRun {
    fn rate(&self) -> f64 {
        self.block_steps as f64 / self.seconds
    }
    fn mean_sliding(&self) -> usize {
        (self.block_steps as f64 / self.steps as f64).round() as usize
    }
}

/// One front from a kicked end across `n` blocks, stopped before it reaches the far end.
fn engine_front(u_plus: f64, gamma: f64, dx: f64, n: usize) -> EngineRun {
    let cfg = ChainConfig {
        dx,
        v: 0.0,
        ..Default::default()
    };
    let fr = Coulomb::new(gamma, f64::INFINITY).unwrap();
    let mut ch = Chain::new(cfg, fr, &Free, &vec![u_plus; n], None).unwrap();
    ch.add_trigger(Trigger {
        t: 0.0,
        block: 0,
        kind: TriggerKind::Kick { du_t: -2.0 },
    })
    .unwrap();
    // c = 1/sqrt(1 - u_+^2) (docs/theory.md): stop at 90 % of the crossing
    let c = 1.0 / (1.0 - u_plus * u_plus).sqrt();
    let t_end = 0.9 * n as f64 * dx / c;
    let t = Cpu::start();
    ch.run(t_end, usize::MAX, u64::MAX).unwrap();
    let seconds = t.elapsed();
    EngineRun {
        seconds,
        block_steps: ch.counters.block_steps,
        steps: ch.counters.steps,
        switches: ch.counters.switches,
        fingerprint: fingerprint(&ch),
    }
}

/// The loading chain: a smooth initial stress (run it for the events of `LOAD`).
fn loading_chain(n: usize, dx: f64, gamma: f64, v: f64) -> Chain<Coulomb> {
    let cfg = ChainConfig {
        dx,
        v,
        ..Default::default()
    };
    let fr = Coulomb::new(gamma, f64::INFINITY).unwrap();
    let l = n as f64 * dx;
    let u0: Vec<f64> = (0..n)
        .map(|i| {
            let x = i as f64 * dx / l * std::f64::consts::TAU;
            0.6 + 0.06 * (3.0 * x).sin() + 0.03 * (7.0 * x + 1.0).sin() + 0.01 * (19.0 * x).cos()
        })
        .collect();
    Chain::new(cfg, fr, &Free, &u0, None).unwrap()
}

/// Loading cycles: a smooth initial stress, `events` events, in one call (timed).
fn engine_loading(n: usize, dx: f64, gamma: f64, v: f64, events: usize) -> EngineRun {
    let mut ch = loading_chain(n, dx, gamma, v);
    let t = Cpu::start();
    ch.run(f64::INFINITY, events, u64::MAX).unwrap();
    let seconds = t.elapsed();
    EngineRun {
        seconds,
        block_steps: ch.counters.block_steps,
        steps: ch.counters.steps,
        switches: ch.counters.switches,
        fingerprint: fingerprint(&ch),
    }
}

/// The lengths of the runs of sliding blocks (nonzero modes) into `lens`.
fn run_lengths(modes: &[i8], lens: &mut Vec<u32>) {
    lens.clear();
    let mut len = 0u32;
    for &m in modes.iter().chain([0i8].iter()) {
        if m != 0 {
            len += 1;
        } else if len > 0 {
            lens.push(len);
            len = 0;
        }
    }
}

/// The loading run's run structure, recorded step by step (not timed), with the
/// counters and fingerprint of that stepped run.
struct Recorded {
    runs: Runs,
    steps: u64,
    switches: u64,
    block_steps: u64,
    fingerprint: u64,
    /// Steps that were redone up to an event (counted twice, as in the engine's counters).
    redone: u64,
    /// Steps after a quiet interval (their runs read from a copy of the chain stopped at
    /// the end of the interval).
    after_quiet: u64,
    /// Per call of the stepped run: (sliding blocks, steps, time-stamp counter ticks of
    /// the call; 0 for the calls after a quiet interval, which also jump).
    calls: Vec<(u32, u32, u64)>,
    /// Time-stamp counter ticks per second (against the wall clock over the recording).
    ticks_per_s: f64,
}

/// The time-stamp counter (0 where there is none): ticks of one call of the stepped run.
fn ticks() -> u64 {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: rdtsc has no preconditions on x86-64.
    return unsafe { std::arch::x86_64::_rdtsc() };
    #[cfg(not(target_arch = "x86_64"))]
    0
}

/// Run the loading chain one step per call (`Chain::run(.., 1)`) and record the run
/// lengths of every step from the modes it starts from. A call returns with the state the
/// next step starts from (the events of the step taken, settling, due slips all done), so
/// the modes after one call are those of the next step, unless nothing slides: then the
/// next call first jumps over the quiet interval to the next slip. For those steps a copy
/// of the chain taken before the call is run to the time of that slip (the earliest slip
/// the call recorded), which stops right before the step, and it is checked to reach the
/// same state as the chain after one more step. A step redone up to an event shows as
/// two steps in the counters (the engine counts both, with the same sliding blocks): it
/// is recorded twice. Checked: every step's block updates (from the counters) equal its
/// runs' total.
fn record_loading_runs(n: usize, dx: f64, gamma: f64, v: f64, events: usize) -> Recorded {
    let mut ch = loading_chain(n, dx, gamma, v);
    let mut runs = Runs::default();
    let mut lens = Vec::new();
    let (mut redone, mut after_quiet) = (0, 0);
    let mut calls = Vec::new();
    let (wall, tick0) = (std::time::Instant::now(), ticks());
    loop {
        let before = ch.counters;
        let n_slips = ch.catalog.slips.len();
        let remaining = events.saturating_sub(ch.catalog.finished());
        let quiet = (ch.n_sliding() == 0).then(|| ch.clone());
        if quiet.is_none() {
            run_lengths(&ch.modes(), &mut lens);
        }
        let t0 = ticks();
        let stop = ch.run(f64::INFINITY, remaining, 1).unwrap();
        let dt = ticks() - t0;
        let steps = ch.counters.steps - before.steps;
        if steps == 0 {
            assert_eq!(
                stop,
                Stop::Events,
                "a call without a step stops at the events"
            );
            break;
        }
        let after_quiet_step = quiet.is_some();
        if let Some(mut q) = quiet {
            let t_slip = ch.catalog.slips[n_slips..]
                .iter()
                .map(|r| r.t_start)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(q.run(t_slip, remaining, u64::MAX).unwrap(), Stop::Time);
            assert_eq!(q.counters.steps, before.steps, "the copy stepped");
            run_lengths(&q.modes(), &mut lens);
            q.run(f64::INFINITY, remaining, 1).unwrap();
            assert_eq!(q.counters, ch.counters, "the copy's step differs");
            assert_eq!(fingerprint(&q), fingerprint(&ch), "the copy's step differs");
            after_quiet += 1;
        }
        assert!(steps <= 2, "one call, one step (and its redo)");
        redone += steps - 1;
        let sliding: u64 = lens.iter().map(|&l| l as u64).sum();
        assert_eq!(
            ch.counters.block_steps - before.block_steps,
            steps * sliding,
            "the recorded runs are not the blocks the engine stepped"
        );
        for _ in 0..steps {
            runs.push_step(&lens);
        }
        let dt = if after_quiet_step { 0 } else { dt };
        calls.push((sliding as u32, steps as u32, dt));
        if stop == Stop::Events {
            break;
        }
    }
    assert_eq!(runs.updates(), ch.counters.block_steps);
    Recorded {
        runs,
        steps: ch.counters.steps,
        switches: ch.counters.switches,
        block_steps: ch.counters.block_steps,
        fingerprint: fingerprint(&ch),
        redone,
        after_quiet,
        calls,
        ticks_per_s: (ticks() - tick0) as f64 / wall.elapsed().as_secs_f64(),
    }
}

/// "lo-hi", "lo" when equal, "lo+" when hi is the largest value of its type.
fn span(lo: u64, hi: u64) -> String {
    if hi == lo {
        format!("{lo}")
    } else if hi == u64::MAX || hi == u32::MAX as u64 || hi == usize::MAX as u64 {
        format!("{lo}+")
    } else {
        format!("{lo}-{hi}")
    }
}

/// Print the run structure: steps and block updates by sliding blocks per step, by runs
/// per step, and runs and updates by run length (shares in %).
fn print_run_structure(rec: &Recorded) {
    let runs = &rec.runs;
    let (steps, updates) = (runs.counts.len() as f64, runs.updates() as f64);
    println!(
        "loading run structure: {} steps ({} redone, {} after a quiet interval), {} block \
         updates, {} runs ({:.2} per step, {:.2} blocks per run)",
        runs.counts.len(),
        rec.redone,
        rec.after_quiet,
        runs.updates(),
        runs.lens.len(),
        runs.lens.len() as f64 / steps,
        updates / runs.lens.len() as f64
    );
    // per step: (sliding blocks, runs)
    let mut per_step = Vec::with_capacity(runs.counts.len());
    let mut r = 0;
    for &c in &runs.counts {
        let c = c as usize;
        let n: u64 = runs.lens[r..r + c].iter().map(|&l| l as u64).sum();
        per_step.push((n, c as u64));
        r += c;
    }
    let bins = [
        (1, 2),
        (3, 5),
        (6, 10),
        (11, 30),
        (31, 60),
        (61, 100),
        (101, 200),
    ];
    let bins: Vec<(u64, u64)> = bins.into_iter().chain([(201, u64::MAX)]).collect();
    println!("  sliding blocks per step: % of steps, % of updates, runs per step (mean)");
    for &(lo, hi) in &bins {
        let sel: Vec<&(u64, u64)> = per_step
            .iter()
            .filter(|s| (lo..=hi).contains(&s.0))
            .collect();
        let upd: u64 = sel.iter().map(|s| s.0).sum();
        let nruns: u64 = sel.iter().map(|s| s.1).sum();
        println!(
            "    {}: {:.1} %, {:.1} %, {:.2}",
            span(lo, hi),
            100.0 * sel.len() as f64 / steps,
            100.0 * upd as f64 / updates,
            nruns as f64 / sel.len().max(1) as f64
        );
    }
    println!("  runs per step: % of steps, % of updates, sliding blocks per step (mean)");
    for (lo, hi) in [(1, 1), (2, 2), (3, 3), (4, 6), (7, u64::MAX)] {
        let sel: Vec<&(u64, u64)> = per_step
            .iter()
            .filter(|s| (lo..=hi).contains(&s.1))
            .collect();
        let upd: u64 = sel.iter().map(|s| s.0).sum();
        println!(
            "    {}: {:.1} %, {:.1} %, {:.1}",
            span(lo, hi),
            100.0 * sel.len() as f64 / steps,
            100.0 * upd as f64 / updates,
            upd as f64 / sel.len().max(1) as f64
        );
    }
    println!("  run length: % of runs stepped, % of updates");
    let nr = runs.lens.len() as f64;
    for (lo, hi) in [
        (1, 1),
        (2, 3),
        (4, 10),
        (11, 30),
        (31, 100),
        (101, u32::MAX),
    ] {
        let sel: Vec<u32> = runs
            .lens
            .iter()
            .copied()
            .filter(|l| (lo..=hi).contains(l))
            .collect();
        let upd: u64 = sel.iter().map(|&l| l as u64).sum();
        println!(
            "    {}: {:.1} %, {:.1} %",
            span(lo as u64, hi as u64),
            100.0 * sel.len() as f64 / nr,
            100.0 * upd as f64 / updates
        );
    }
}

/// The replay reference's rates (Rust baseline, AVX2, AVX-512F, C), each over about `work`
/// updates, its arithmetic checked: the Rust codes give the same bits, and the Rust loop
/// those of the C loop built without contraction (one pass).
fn replay_rates(
    runs: &Runs,
    file: &PathBuf,
    c_fast: &PathBuf,
    c_exact: &PathBuf,
    work: f64,
) -> [f64; 4] {
    let (_, dx, gamma, _, _) = LOAD;
    let (rs, chk_rs) = rust_replay(runs, dx, gamma, work, Code::Baseline);
    let (ra, chk_ra) = rust_replay(runs, dx, gamma, work, Code::Avx2);
    let (r5, chk_r5) = rust_replay(runs, dx, gamma, work, Code::Avx512);
    let (c, _) = c_replay(c_fast, file, runs.updates(), dx, gamma, work);
    let one = runs.updates() as f64;
    let (_, chk_c) = c_replay(c_exact, file, runs.updates(), dx, gamma, one);
    let (_, chk_r1) = rust_replay(runs, dx, gamma, one, Code::Avx2);
    assert_eq!(
        chk_rs, chk_ra,
        "the Rust replay's baseline and AVX2 paths differ"
    );
    assert!(
        chk_r5.is_nan() || chk_r5 == chk_rs,
        "the Rust replay's baseline and AVX-512 paths differ"
    );
    assert_eq!(
        chk_c, chk_r1,
        "the Rust and C replays (no contraction) differ"
    );
    assert!(chk_r1.is_finite(), "the replay's state is not finite");
    [rs, ra, r5, c]
}

/// The front: (u_+, gamma, dx, blocks).
const FRONT: (f64, f64, f64, usize) = (0.6, 0.45, 0.00625, 4000);
/// The loading run: (blocks, dx, gamma, v, events).
const LOAD: (usize, f64, f64, f64, usize) = (2000, 0.05, 0.3, 1e-4, 30);
/// The same loading run on a four times finer lattice (the same length, the same initial
/// stress): the paper's continuum regime dx << 1, where the pulses are wide in blocks.
const LOAD_FINE: (usize, f64, f64, f64, usize) = (8000, 0.0125, 0.3, 1e-4, 30);

/// The contiguous reference's rates over n blocks (Rust baseline, AVX2, AVX-512F, C).
fn contiguous_rates(n: usize, dx: f64, gamma: f64, work: f64, c_fast: &PathBuf) -> [f64; 4] {
    let (rs, _) = rust_reference(n, dx, gamma, work, Code::Baseline);
    let (ra, _) = rust_reference(n, dx, gamma, work, Code::Avx2);
    let (r5, _) = rust_reference(n, dx, gamma, work, Code::Avx512);
    let (c, _) = c_reference(c_fast, n, dx, gamma, work);
    [rs, ra, r5, c]
}

fn stats(x: &[f64]) -> (f64, f64, f64) {
    let mut s = x.to_vec();
    s.sort_by(f64::total_cmp);
    (s[s.len() / 2], s[0], s[s.len() - 1])
}

/// Where the loading run's time goes, by sliding blocks per step: the stepped engine run's
/// time (time-stamp counter per call: wall time, so a call longer than 20 us, which a step
/// of <= 200 blocks is not, is taken as preempted and left out; each call also pays for
/// itself, see the one-call run's time per step, `one_call` seconds) and the replay
/// reference over those steps alone.
fn time_by_class(
    rec: &Recorded,
    one_call: f64,
    runs_file: &Path,
    c_fast: &PathBuf,
    c_exact: &PathBuf,
    work: f64,
) {
    let clip = (20e-6 * rec.ticks_per_s) as u64;
    let timed = rec.calls.iter().filter(|c| c.2 > 0 && c.2 <= clip);
    let total: u64 = timed.clone().map(|c| c.2).sum();
    let steps_timed: u64 = timed.map(|c| c.1 as u64).sum();
    println!(
        "stepped engine run: {:.4} s over {steps_timed} steps ({:.1} ns per step; \
         {} calls over 20 us left out; time-stamp counter at {:.3e}/s); the one-call run \
         (fastest round): {:.1} ns per step",
        total as f64 / rec.ticks_per_s,
        1e9 * total as f64 / rec.ticks_per_s / steps_timed as f64,
        rec.calls.iter().filter(|c| c.2 > clip).count(),
        rec.ticks_per_s,
        1e9 * one_call / rec.steps as f64
    );
    for (lo, hi) in [(1, 10), (11, 30), (31, usize::MAX)] {
        let calls = rec
            .calls
            .iter()
            .filter(|c| (lo..=hi).contains(&(c.0 as usize)) && c.2 > 0 && c.2 <= clip);
        let t: u64 = calls.clone().map(|c| c.2).sum();
        let n: u64 = calls.map(|c| c.1 as u64).sum();
        println!(
            "stepped engine, steps with {} sliding blocks: {:.1} % of its time, \
             {:.1} ns per step",
            span(lo as u64, hi as u64),
            100.0 * t as f64 / total as f64,
            1e9 * t as f64 / rec.ticks_per_s / n as f64
        );
    }
    for (lo, hi) in [(1, 10), (11, 30), (31, usize::MAX)] {
        let part = rec
            .runs
            .select(|l| (lo..=hi).contains(&l.iter().map(|&x| x as usize).sum::<usize>()));
        let file = runs_file.with_extension(format!("{lo}.bin"));
        std::fs::write(&file, part.to_bytes()).unwrap();
        let rates = replay_rates(&part, &file, c_fast, c_exact, work);
        let best = rates.iter().copied().fold(0.0, f64::max);
        println!(
            "replay of the steps with {} sliding blocks ({} steps, {} updates, \
             {:.2} runs per step): Rust sse2 {:.3e}, Rust avx2 {:.3e}, Rust avx512 \
             {:.3e}, C {:.3e}; best {:.1} ns per step",
            span(lo as u64, hi as u64),
            part.counts.len(),
            part.updates(),
            part.lens.len() as f64 / part.counts.len() as f64,
            rates[0],
            rates[1],
            rates[2],
            rates[3],
            1e9 * part.updates() as f64 / best / part.counts.len() as f64
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut repeat = 5usize;
    let mut json: Option<String> = None;
    let mut replay_only: Option<usize> = None;
    let mut k = 1;
    while k < args.len() {
        match args[k].as_str() {
            "--repeat" => {
                repeat = args[k + 1].parse().expect("--repeat N");
                k += 1;
            }
            "--engine-only" => {
                let which = args[k + 1].as_str();
                let r: usize = args[k + 2]
                    .parse()
                    .expect("--engine-only front|loading|loading_fine R");
                for _ in 0..r {
                    let run = match which {
                        "front" => engine_front(FRONT.0, FRONT.1, FRONT.2, FRONT.3),
                        "loading" => engine_loading(LOAD.0, LOAD.1, LOAD.2, LOAD.3, LOAD.4),
                        "loading_fine" => {
                            let (n, dx, g, v, e) = LOAD_FINE;
                            engine_loading(n, dx, g, v, e)
                        }
                        _ => panic!("--engine-only front|loading|loading_fine R"),
                    };
                    println!(
                        "{which}: {:.4} s, state fingerprint {:016x}",
                        run.seconds, run.fingerprint
                    );
                }
                return;
            }
            "--json" => {
                json = Some(args[k + 1].clone());
                k += 1;
            }
            "--replay-only" => {
                replay_only = Some(args[k + 1].parse().expect("--replay-only R"));
                k += 1;
            }
            a => panic!(
                "unknown argument {a} (--repeat N, --json FILE, --engine-only \
                 front|loading|loading_fine R, --replay-only R)"
            ),
        }
        k += 1;
    }
    std::fs::create_dir_all(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target")).unwrap();
    let c_fast = build_c(&["-O3", "-march=native"], "reference_c");
    let c_exact = build_c(
        &["-O3", "-march=native", "-ffp-contract=off"],
        "reference_c_nofma",
    );
    let work = 1.5e8; // block updates per reference measurement
    let (front_u, front_gamma, front_dx, front_n) = FRONT;
    let (load_n, load_dx, load_gamma, load_v, load_events) = LOAD;
    println!(
        "machine: {} cores; load average: {}",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    // the loading run's run structure, recorded once (deterministic), for the replay
    let rec = record_loading_runs(load_n, load_dx, load_gamma, load_v, load_events);
    print_run_structure(&rec);
    let runs_file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/loading_runs.bin");
    std::fs::write(&runs_file, rec.runs.to_bytes()).unwrap();
    let replay_work = work / 3.0; // block updates per replay measurement
    let same_run = |load: &EngineRun| {
        assert_eq!(
            (
                load.fingerprint,
                load.steps,
                load.switches,
                load.block_steps
            ),
            (rec.fingerprint, rec.steps, rec.switches, rec.block_steps),
            "the loading run stepped one step per call is not the one-call run"
        );
    };
    if let Some(r) = replay_only {
        let mut fastest = f64::INFINITY;
        for round in 0..r {
            let load = engine_loading(load_n, load_dx, load_gamma, load_v, load_events);
            same_run(&load);
            fastest = fastest.min(load.seconds);
            let [rs, ra, r5, c] =
                replay_rates(&rec.runs, &runs_file, &c_fast, &c_exact, replay_work);
            let best = rs.max(ra).max(r5).max(c);
            println!(
                "round {round}: loading engine {:.3e}/s ({:.3} s); replay reference Rust sse2 \
                 {rs:.3e}, Rust avx2 {ra:.3e}, Rust avx512 {r5:.3e}, C {c:.3e}; engine/best \
                 replay {:.3}",
                load.rate(),
                load.seconds,
                load.rate() / best
            );
        }
        time_by_class(&rec, fastest, &runs_file, &c_fast, &c_exact, replay_work);
        return;
    }
    let (fine_n, fine_dx, fine_gamma, fine_v, fine_events) = LOAD_FINE;
    let mut rows: Vec<[f64; 23]> = Vec::new();
    for round in 0..repeat {
        let front = engine_front(front_u, front_gamma, front_dx, front_n);
        let load = engine_loading(load_n, load_dx, load_gamma, load_v, load_events);
        same_run(&load);
        let nf = front.mean_sliding().max(1);
        let nl = load.mean_sliding().max(1);
        let (rs_f, chk_rs) = rust_reference(nf, front_dx, front_gamma, work, Code::Baseline);
        let (ra_f, chk_ra) = rust_reference(nf, front_dx, front_gamma, work, Code::Avx2);
        let (r5_f, chk_r5) = rust_reference(nf, front_dx, front_gamma, work, Code::Avx512);
        let (c_f, _) = c_reference(&c_fast, nf, front_dx, front_gamma, work);
        let (_, chk_c) = c_reference(&c_exact, nf, front_dx, front_gamma, 1e6);
        let (_, chk_r1) = rust_reference(nf, front_dx, front_gamma, 1e6, Code::Avx2);
        assert_eq!(chk_rs, chk_ra, "the Rust baseline and AVX2 paths differ");
        assert!(
            chk_r5.is_nan() || chk_r5 == chk_rs,
            "the Rust baseline and AVX-512 paths differ"
        );
        assert_eq!(chk_c, chk_r1, "Rust and C (no contraction) differ");
        let best_f = rs_f.max(ra_f).max(r5_f).max(c_f);
        let [rs_l, ra_l, r5_l, c_l] = contiguous_rates(nl, load_dx, load_gamma, work, &c_fast);
        let best_l = rs_l.max(ra_l).max(r5_l).max(c_l);
        let fine = engine_loading(fine_n, fine_dx, fine_gamma, fine_v, fine_events);
        let nq = fine.mean_sliding().max(1);
        let [rs_q, ra_q, r5_q, c_q] = contiguous_rates(nq, fine_dx, fine_gamma, work, &c_fast);
        let best_q = rs_q.max(ra_q).max(r5_q).max(c_q);
        let [rs_p, ra_p, r5_p, c_p] =
            replay_rates(&rec.runs, &runs_file, &c_fast, &c_exact, replay_work);
        let best_p = rs_p.max(ra_p).max(r5_p).max(c_p);
        println!(
            "round {round}: front: {nf} sliding on average, {} steps, {} switches, engine \
             {:.3e}/s ({:.3} s, state fingerprint {:016x}); reference Rust sse2 {rs_f:.3e}, \
             Rust avx2 {ra_f:.3e}, Rust avx512 {r5_f:.3e}, C -O3 -march=native {c_f:.3e}; \
             engine/best {:.3}",
            front.steps,
            front.switches,
            front.rate(),
            front.seconds,
            front.fingerprint,
            front.rate() / best_f
        );
        println!(
            "round {round}: loading: {nl} sliding on average, {} steps, {} switches, engine \
             {:.3e}/s ({:.3} s, state fingerprint {:016x}); reference Rust sse2 {rs_l:.3e}, \
             Rust avx2 {ra_l:.3e}, Rust avx512 {r5_l:.3e}, C {c_l:.3e}; engine/best {:.3}",
            load.steps,
            load.switches,
            load.rate(),
            load.seconds,
            load.fingerprint,
            load.rate() / best_l
        );
        println!(
            "round {round}: loading: replay reference (the same stencil over the engine's \
             recorded runs) Rust sse2 {rs_p:.3e}, Rust avx2 {ra_p:.3e}, Rust avx512 \
             {r5_p:.3e}, C {c_p:.3e}; engine/best replay {:.3} (engine/best contiguous \
             {nl}-block reference {:.3})",
            load.rate() / best_p,
            load.rate() / best_l
        );
        println!(
            "round {round}: loading, dx = {fine_dx}: {nq} sliding on average, {} steps, {} \
             switches, engine {:.3e}/s ({:.3} s, state fingerprint {:016x}); reference Rust \
             sse2 {rs_q:.3e}, Rust avx2 {ra_q:.3e}, Rust avx512 {r5_q:.3e}, C {c_q:.3e}; \
             engine/best {:.3}",
            fine.steps,
            fine.switches,
            fine.rate(),
            fine.seconds,
            fine.fingerprint,
            fine.rate() / best_q
        );
        rows.push([
            front.rate(),
            rs_f,
            ra_f,
            r5_f,
            c_f,
            front.rate() / best_f,
            load.rate(),
            rs_l,
            ra_l,
            r5_l,
            c_l,
            load.rate() / best_l,
            rs_p,
            ra_p,
            r5_p,
            c_p,
            load.rate() / best_p,
            fine.rate(),
            rs_q,
            ra_q,
            r5_q,
            c_q,
            fine.rate() / best_q,
        ]);
    }
    let names = [
        "front_engine_updates_per_s",
        "front_reference_rust_sse2",
        "front_reference_rust_avx2",
        "front_reference_rust_avx512",
        "front_reference_c",
        "front_engine_over_best_reference",
        "loading_engine_updates_per_s",
        "loading_reference_rust_sse2",
        "loading_reference_rust_avx2",
        "loading_reference_rust_avx512",
        "loading_reference_c",
        "loading_engine_over_best_reference",
        "loading_replay_rust_sse2",
        "loading_replay_rust_avx2",
        "loading_replay_rust_avx512",
        "loading_replay_c",
        "loading_engine_over_best_replay",
        "loading_fine_engine_updates_per_s",
        "loading_fine_reference_rust_sse2",
        "loading_fine_reference_rust_avx2",
        "loading_fine_reference_rust_avx512",
        "loading_fine_reference_c",
        "loading_fine_engine_over_best_reference",
    ];
    let mut out = String::from("{\n");
    println!("medians of {repeat} rounds [min, max]:");
    for (j, name) in names.iter().enumerate() {
        let col: Vec<f64> = rows.iter().map(|r| r[j]).collect();
        let (med, lo, hi) = stats(&col);
        println!("  {name}: {med:.4e} [{lo:.4e}, {hi:.4e}]");
        out += &format!("  \"{name}\": [{med:e}, {lo:e}, {hi:e}],\n");
    }
    let ratio = |a: usize, b: usize| {
        let col: Vec<f64> = rows.iter().map(|r| r[a] / r[b]).collect();
        stats(&col)
    };
    for (label, a, b) in [
        ("front: Rust avx512 / C", 3, 4),
        ("front: Rust avx2 / C", 2, 4),
        ("front: Rust sse2 / C", 1, 4),
        ("loading: Rust avx512 / C", 9, 10),
        ("loading: Rust avx2 / C", 8, 10),
        ("loading replay: Rust avx512 / C", 14, 15),
        ("loading replay: Rust avx2 / C", 13, 15),
        ("loading replay / contiguous reference, C", 15, 10),
        ("loading, fine: Rust avx512 / C", 20, 21),
    ] {
        let (m, lo, hi) = ratio(a, b);
        println!("  {label}: {m:.3} [{lo:.3}, {hi:.3}]");
    }
    out += "  \"columns\": \"median, min, max\"\n}\n";
    if let Some(f) = json {
        std::fs::write(f, out).unwrap();
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn run_lengths_are_the_runs_of_nonzero_modes() {
        let mut lens = vec![9];
        super::run_lengths(&[0, 1, 1, 0, -1, 0, 0, 1, -1, 1], &mut lens);
        assert_eq!(lens, [2, 1, 3]);
        super::run_lengths(&[0, 0], &mut lens);
        assert!(lens.is_empty());
    }
}
