//! The same slowly varying initial state run by the direct chain (bkwaves-core `chain`)
//! and by the free boundary engine (`free_boundary`): a ring of length L = 0.3/v with two
//! smooth bumps on a sinusoidal ramp (all widths scale with 1/v, so the variation stays
//! "slow" in the sense of Sec. IV as v -> 0), gamma = 0.3.

use bkwaves_core::boundary;
use bkwaves_core::chain::{Chain, ChainConfig};
use bkwaves_core::free_boundary::catalog::PathKind;
use bkwaves_core::free_boundary::{Boundary, FreeBoundary, Options};
use bkwaves_core::friction::coulomb::Coulomb;
use std::time::Instant;

const GAMMA: f64 = 0.3;

fn pd(x: f64, c: f64, l: f64) -> f64 {
    (x - c + 0.5 * l).rem_euclid(l) - 0.5 * l
}

fn u0f(x: f64, l: f64) -> f64 {
    let w = 40.0 * l / 300.0;
    0.9 + 0.015 * (2.0 * std::f64::consts::PI * x / l).sin()
        + 0.03 * (-(pd(x, 0.3 * l, l) / w).powi(2)).exp()
        + 0.025 * (-(pd(x, 0.7 * l, l) / w).powi(2)).exp()
}

struct ChainRun {
    wall: f64,
    t_start: Vec<f64>,
    x_start: Vec<f64>,
    moment: Vec<f64>,
    first_slip: Vec<f64>,
    u_end: Vec<f64>,
    t_now: f64,
}

fn run_chain(dx: f64, v: f64, events: usize) -> ChainRun {
    let l = 0.3 / v;
    let n = (l / dx).round() as usize;
    let u0: Vec<f64> = (0..n).map(|i| u0f(i as f64 * dx, l)).collect();
    let cfg = ChainConfig {
        dx,
        v,
        ..Default::default()
    };
    let b = boundary::by_name("periodic", (0.0, 0.0)).unwrap();
    let mut ch = Chain::new(
        cfg,
        Coulomb::new(GAMMA, 0.0).unwrap(),
        b.as_ref(),
        &u0,
        None,
    )
    .unwrap();
    let t0 = Instant::now();
    ch.run(1e12, 1, u64::MAX).unwrap();
    let u_end = ch.u();
    let t_now = ch.time();
    if events > 1 {
        ch.run(1e12, events, u64::MAX).unwrap();
    }
    let wall = t0.elapsed().as_secs_f64();
    let mut first_slip = vec![f64::NAN; n];
    for s in ch.catalog.slips.iter() {
        if s.event == 0 && first_slip[s.block].is_nan() {
            first_slip[s.block] = s.t_start;
        }
    }
    let evs = &ch.catalog.events[..events.min(ch.catalog.events.len())];
    ChainRun {
        wall,
        t_start: evs.iter().map(|e| e.t_start).collect(),
        x_start: evs.iter().map(|e| e.nucleation as f64 * dx).collect(),
        moment: evs.iter().map(|e| e.moment * dx).collect(),
        first_slip,
        u_end,
        t_now,
    }
}

fn fb_engine(v: f64, h_over_l: f64) -> (FreeBoundary, f64) {
    let l = 0.3 / v;
    let h = h_over_l * l;
    let m = (l / h).round() as usize;
    let g0: Vec<f64> = (0..m).map(|i| u0f(i as f64 * h, l)).collect();
    let opts = Options {
        gamma: GAMMA,
        v,
        boundary: Boundary::Periodic,
        ..Default::default()
    };
    (FreeBoundary::new(0.0, h, &g0, opts, &[]).unwrap(), h)
}

fn accuracy() {
    println!("| dx | v | t_start chain - fb | max front time diff - offset | same / event duration | rms | max u after (off collision) | max u after (collision zone) | moment chain/fb - 1 |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let cases = [
        (0.1, 1e-3),
        (0.05, 1e-3),
        (0.025, 1e-3),
        (0.05, 5e-4),
        (0.05, 2.5e-4),
    ];
    for &(dx, v) in &cases {
        let c = run_chain(dx, v, 1);
        let (mut fb, h) = fb_engine(v, 0.5 / 300.0);
        fb.advance(1e12, u64::MAX, 1).unwrap();
        let ufb = fb.u_nodes();
        let t_fb = fb.time();
        let ev0 = fb.events()[0];
        let path: Vec<_> = fb.path().to_vec();
        let off = c.t_start[0] - ev0.t_start;
        let xcol: Vec<f64> = path
            .iter()
            .filter(|p| p.kind == PathKind::Annihilation)
            .map(|p| p.x)
            .collect();
        let (mut dtm, mut dt2, mut cnt, mut du, mut duc) = (0.0f64, 0.0f64, 0usize, 0.0f64, 0.0f64);
        for (k, &u_k) in ufb.iter().enumerate() {
            let xq = k as f64 * h;
            let i = (xq / dx).round() as usize % c.first_slip.len();
            let Some(tp) = path
                .iter()
                .find(|p| p.kind == PathKind::Node && (p.x - xq).abs() < 1e-9 * h)
                .map(|p| p.t)
            else {
                continue;
            };
            let d = c.first_slip[i] - tp - off;
            dtm = dtm.max(d.abs());
            dt2 += d * d;
            cnt += 1;
            let uf = u_k + v * (c.t_now - t_fb);
            let near = xcol.iter().any(|&xc| (xq - xc).abs() < 5.0);
            if near {
                duc = duc.max((c.u_end[i] - uf).abs());
            } else {
                du = du.max((c.u_end[i] - uf).abs());
            }
        }
        let _ = &c.x_start;
        println!(
            "| {dx} | {v} | {off:+.3e} | {dtm:.2e} | {:.2e} | {:.2e} | {du:.2e} | {duc:.2e} | {:+.2e} |",
            dtm / (ev0.t_end - ev0.t_start),
            (dt2 / cnt as f64).sqrt(),
            c.moment[0] / ev0.moment - 1.0
        );
    }
}

fn speed() {
    let v = 1e-3;
    // free boundary: median over 3 runs of 1000 events, grid h = 1 (L/300)
    let mut walls = Vec::new();
    for _ in 0..3 {
        let (mut fb, _) = fb_engine(v, 1.0 / 300.0);
        let t0 = Instant::now();
        fb.advance(1e12, u64::MAX, 1000).unwrap();
        walls.push(t0.elapsed().as_secs_f64() / fb.completed_events() as f64);
    }
    walls.sort_by(f64::total_cmp);
    let fb_per_event = walls[1];
    println!(
        "free boundary (h = 1, 1000 events, median of 3): {:.3} ms per event",
        fb_per_event * 1e3
    );
    println!();
    println!(
        "| dx | blocks | chain, first event (median of 3 runs) | free boundary per event | ratio |"
    );
    println!("|---|---|---|---|---|");
    for &dx in &[0.1, 0.05, 0.025, 0.0125] {
        let mut ws: Vec<f64> = (0..3).map(|_| run_chain(dx, v, 1).wall).collect();
        ws.sort_by(f64::total_cmp);
        let n = (0.3 / v / dx).round() as usize;
        let per = ws[1];
        println!(
            "| {dx} | {n} | {:.3} s | {:.2} ms | {:.0} |",
            per,
            fb_per_event * 1e3,
            per / fb_per_event
        );
    }
}

fn main() {
    match std::env::args().nth(1).as_deref() {
        Some("accuracy") => accuracy(),
        Some("speed") => speed(),
        Some("events") => {
            let dx: f64 = std::env::args().nth(2).unwrap().parse().unwrap();
            let v: f64 = std::env::args().nth(3).unwrap().parse().unwrap();
            let l = 0.3 / v;
            let n = (l / dx).round() as usize;
            let u0: Vec<f64> = (0..n).map(|i| u0f(i as f64 * dx, l)).collect();
            let cfg = ChainConfig {
                dx,
                v,
                ..Default::default()
            };
            let b = boundary::by_name("periodic", (0.0, 0.0)).unwrap();
            let mut ch = Chain::new(
                cfg,
                Coulomb::new(GAMMA, 0.0).unwrap(),
                b.as_ref(),
                &u0,
                None,
            )
            .unwrap();
            let ne: usize = std::env::args()
                .nth(4)
                .map(|a| a.parse().unwrap())
                .unwrap_or(4);
            for k in 1..=ne {
                let t0 = Instant::now();
                ch.run(1e12, k, u64::MAX).unwrap();
                let e = ch.catalog.events[k - 1];
                println!("chain ev {k}: wall {:.2}s t_start {:.4} dur {:.3} nucl x {:.2} blocks {} slips {} moment*dx {:.4}", t0.elapsed().as_secs_f64(), e.t_start, e.t_end - e.t_start, e.nucleation as f64 * dx, e.n_blocks, e.n_slips, e.moment * dx);
            }
            let (mut fb, _) = fb_engine(v, 0.5 / 300.0);
            fb.advance(1e12, u64::MAX, ne).unwrap();
            for e in fb.events() {
                println!(
                    "fb ev: t_start {:.4} dur {:.3} x {:.2} moment {:.4} births {}",
                    e.t_start,
                    e.t_end - e.t_start,
                    e.x_start,
                    e.moment,
                    e.n_births
                );
            }
        }
        _ => {
            eprintln!("usage: fb_vs_chain accuracy|speed");
            std::process::exit(2);
        }
    }
}
