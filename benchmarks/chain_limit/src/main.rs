//! The chain engine against the real limit (issue 16; docs/benchmarks.md).
//!
//! 1. The reference: the bare RK4 stencil over n contiguous sliding blocks
//!    (src/reference.rs), in Rust (baseline x86-64 code and AVX2 code) and in C
//!    (reference.c, built here with `cc -O3 -march=native`), with the same n and step:
//!    block updates per second of each and their ratios.
//! 2. The regression benchmark (not timed in CI): the engine's sliding-block updates per
//!    second on one front (u_+ = 0.6, gamma = 0.45, dx = 0.00625, beta = inf) and on a
//!    loading run (2000 blocks, dx = 0.05, gamma = 0.3, v = 1e-4, 30 events), each as a
//!    ratio to the best reference over the engine's mean number of sliding blocks,
//!    measured in the same round. Rounds are repeated; medians and spreads are printed.
//!
//! All times are CPU times of the work (the machine is shared: wall time would count the
//! other jobs).
//!
//! cargo run --release -- [--repeat R] [--json FILE]
//!
//! `--engine-only front|loading R`: only that engine run, R times, and its CPU times (no
//! reference: for a sampling profile of the engine, `perf record -g`).

mod reference;

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
use bkwaves_core::chain::{Chain, ChainConfig, Trigger, TriggerKind};
use bkwaves_core::friction::Coulomb;
use reference::Reference;
use std::path::PathBuf;
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

/// Loading cycles: a smooth initial stress, `events` events.
fn engine_loading(n: usize, dx: f64, gamma: f64, v: f64, events: usize) -> EngineRun {
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
    let mut ch = Chain::new(cfg, fr, &Free, &u0, None).unwrap();
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

/// The front: (u_+, gamma, dx, blocks).
const FRONT: (f64, f64, f64, usize) = (0.6, 0.45, 0.00625, 4000);
/// The loading run: (blocks, dx, gamma, v, events).
const LOAD: (usize, f64, f64, f64, usize) = (2000, 0.05, 0.3, 1e-4, 30);

fn stats(x: &[f64]) -> (f64, f64, f64) {
    let mut s = x.to_vec();
    s.sort_by(f64::total_cmp);
    (s[s.len() / 2], s[0], s[s.len() - 1])
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut repeat = 5usize;
    let mut json: Option<String> = None;
    let mut k = 1;
    while k < args.len() {
        match args[k].as_str() {
            "--repeat" => {
                repeat = args[k + 1].parse().expect("--repeat N");
                k += 1;
            }
            "--engine-only" => {
                let which = args[k + 1].as_str();
                let r: usize = args[k + 2].parse().expect("--engine-only front|loading R");
                for _ in 0..r {
                    let run = match which {
                        "front" => engine_front(FRONT.0, FRONT.1, FRONT.2, FRONT.3),
                        "loading" => engine_loading(LOAD.0, LOAD.1, LOAD.2, LOAD.3, LOAD.4),
                        _ => panic!("--engine-only front|loading R"),
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
            a => panic!(
                "unknown argument {a} (--repeat N, --json FILE, --engine-only front|loading R)"
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
    let mut rows: Vec<[f64; 12]> = Vec::new();
    for round in 0..repeat {
        let front = engine_front(front_u, front_gamma, front_dx, front_n);
        let load = engine_loading(load_n, load_dx, load_gamma, load_v, load_events);
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
        let (rs_l, _) = rust_reference(nl, load_dx, load_gamma, work, Code::Baseline);
        let (ra_l, _) = rust_reference(nl, load_dx, load_gamma, work, Code::Avx2);
        let (r5_l, _) = rust_reference(nl, load_dx, load_gamma, work, Code::Avx512);
        let (c_l, _) = c_reference(&c_fast, nl, load_dx, load_gamma, work);
        let best_l = rs_l.max(ra_l).max(r5_l).max(c_l);
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
    ] {
        let (m, lo, hi) = ratio(a, b);
        println!("  {label}: {m:.3} [{lo:.3}, {hi:.3}]");
    }
    out += "  \"columns\": \"median, min, max\"\n}\n";
    if let Some(f) = json {
        std::fs::write(f, out).unwrap();
    }
}
