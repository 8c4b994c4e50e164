//! Local events (chain/local_events.rs) against the global cut on the same runs.

use super::*;
use crate::boundary::{Boundary, Fixed, Free, Periodic};
use crate::chain::{Trigger, TriggerKind};
use crate::friction::Coulomb;

/// First slip time of every block (NaN: never slipped).
fn first_slips(la: &Lattice<Coulomb>) -> Vec<f64> {
    let mut t = vec![f64::NAN; la.n()];
    for s in &la.catalog.slips {
        if t[s.block].is_nan() {
            t[s.block] = s.t_start;
        }
    }
    t
}

/// A point rupture on an n x n free lattice (u_+ = 0.6, dx = 0.25), kicked at `at`.
fn rupture(
    n: usize,
    step: f64,
    gamma: f64,
    local: bool,
    at: usize,
    t_end: f64,
) -> Lattice<Coulomb> {
    let spec = LatticeSpec {
        nx: n,
        ny: n,
        dy: 0.25,
        x: &Free,
        y: &Free,
    };
    let cfg = ChainConfig {
        dx: 0.25,
        v: 0.0,
        step,
    };
    let fr = Coulomb::new(gamma, f64::INFINITY).unwrap();
    let u0 = vec![0.6; n * n];
    let mut la = Lattice::lattice(cfg, spec, fr, Uniform, &u0, None).unwrap();
    la.set_local_events(local);
    la.add_trigger(Trigger {
        t: 0.0,
        block: at,
        kind: TriggerKind::Kick { du_t: -2.0 },
    })
    .unwrap();
    la.run(t_end, usize::MAX, u64::MAX).unwrap();
    la
}

fn max_diff(a: &[f64], b: &[f64]) -> (f64, usize) {
    let mut m = 0.0f64;
    let mut both = 0;
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.is_nan(), y.is_nan(), "{x} {y}");
        if !x.is_nan() {
            m = m.max((x - y).abs());
            both += 1;
        }
    }
    (m, both)
}

#[test]
fn local_events_converge_to_the_global_cut_at_order_four() {
    // a point rupture on 21 x 21 free blocks (dx = 0.25, gamma = 0.45, to t = 6: every
    // block slips, the centre re-sticks): both modes slip the same blocks as often; their
    // first slip times differ by the step's error (each is that far from a run at a
    // quarter of the step: measured 4.4e-6 / 5.7e-6 at step 0.1, 3.8e-7 / 4.3e-7 at 0.05,
    // 2.4e-8 / 2.9e-8 at 0.025), and the difference falls at order 4
    let n = 21;
    let at = n / 2 + n * (n / 2);
    let mut diffs = Vec::new();
    for step in [0.1, 0.05, 0.025] {
        let g = rupture(n, step, 0.45, false, at, 6.0);
        let l = rupture(n, step, 0.45, true, at, 6.0);
        assert_eq!(g.catalog.slips.len(), l.catalog.slips.len());
        assert_eq!(g.counters.switches, l.counters.switches);
        let s = l.local_stats();
        assert!(s.event_steps > 50 && s.fallbacks == 0, "{s:?}");
        assert_eq!(g.local_stats().event_steps, 0);
        let (d, both) = max_diff(&first_slips(&g), &first_slips(&l));
        assert_eq!(both, n * n);
        // the stick times too
        let ends = |la: &Lattice<Coulomb>| -> Vec<f64> {
            la.catalog.slips.iter().map(|r| r.t_end).collect()
        };
        let (e, _) = max_diff(&ends(&g), &ends(&l));
        diffs.push(d.max(e));
    }
    // measured (first slips and sticks): 1.1e-5, 3.2e-7, 1.5e-8 (ratios 34, 21); the
    // first slips alone 3.3e-6, 1.3e-7, 9.4e-9
    assert!(diffs[0] < 3e-5, "{diffs:?}");
    for k in 0..2 {
        assert!(diffs[k] / diffs[k + 1] > 10.0, "{diffs:?}");
    }
}

fn smooth_stress(nx: usize, ny: usize) -> Vec<f64> {
    let mut u = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (i as f64 / nx as f64, j as f64 / ny as f64);
            let tau = 2.0 * std::f64::consts::PI;
            u.push(
                0.6 + 0.15 * (tau * x + 0.3).sin() * (tau * y + 1.1).cos()
                    + 0.08 * (2.0 * tau * x + 3.0 * tau * y + 0.7).sin(),
            );
        }
    }
    u
}

fn loaded(step: f64, bx: &dyn Boundary, by: &dyn Boundary, local: bool) -> Lattice<Coulomb> {
    let (nx, ny) = (24, 20);
    let spec = LatticeSpec {
        nx,
        ny,
        dy: 0.3,
        x: bx,
        y: by,
    };
    let cfg = ChainConfig {
        dx: 0.25,
        v: 1e-2,
        step,
    };
    let fr = Coulomb::new(0.45, f64::INFINITY).unwrap();
    let mut la = Lattice::lattice(cfg, spec, fr, Uniform, &smooth_stress(nx, ny), None).unwrap();
    la.set_local_events(local);
    la
}

#[test]
fn energy_books_close_with_local_events() {
    // loaded at v = 0.01 from a smooth stress to t = 60 (several events, walls and
    // periodic sides): the books' residual over the work dissipated falls with the step
    // as with the global cut (lattice/tests.rs)
    let fixed = Fixed::new(0.5, 0.4).unwrap();
    for (name, bx, by) in [
        (
            "free x free",
            &Free as &dyn Boundary,
            &Free as &dyn Boundary,
        ),
        ("fixed x periodic", &fixed, &Periodic),
        ("periodic x fixed", &Periodic, &fixed),
    ] {
        let mut res = Vec::new();
        for step in [0.05, 0.025, 0.0125] {
            let mut la = loaded(step, bx, by, true);
            let (k, c, l) = la.energy();
            la.run(60.0, usize::MAX, u64::MAX).unwrap();
            assert!(la.catalog.events.len() >= 2, "{name}");
            assert!(la.local_stats().event_steps > 10, "{name}");
            let (k1, c1, l1) = la.energy();
            let lg = la.ledger;
            let r = (k1 + c1 + l1 - k - c - l)
                - (lg.load - lg.dry - lg.viscous - lg.projection + lg.injected);
            let diss = lg.dry + lg.viscous;
            assert!(diss > 0.1, "{name}: dissipation {diss}");
            res.push((r / diss).abs());
        }
        eprintln!("{name}: {res:?}");
        for k in 0..2 {
            assert!(res[k + 1] < res[k] / 5.0, "{name}: {res:?}");
        }
        assert!(res[2] < 1e-9, "{name}: {res:?}");
    }
}

#[test]
fn a_restored_checkpoint_continues_bit_for_bit_with_local_events() {
    let build = || loaded(0.05, &Periodic, &Free, true);
    let mut whole = build();
    whole.run(40.0, usize::MAX, u64::MAX).unwrap();
    assert!(whole.local_stats().event_steps > 10);
    let mut part = build();
    let mut stops = 0;
    while part.time() < 40.0 {
        if part.run(40.0, usize::MAX, 97).unwrap() == crate::chain::Stop::Steps {
            stops += 1;
            let bytes = part.checkpoint();
            let mut fresh = build();
            fresh.restore(&bytes).unwrap();
            part = fresh;
        }
    }
    assert!(stops > 3, "{stops}");
    assert_eq!(whole.u(), part.u());
    assert_eq!(whole.u_t(), part.u_t());
    assert!(whole.ledger == part.ledger);
    let show = |c: &crate::chain::catalog::Catalog| format!("{:?} {:?}", c.slips, c.events);
    assert!(
        show(&whole.catalog) == show(&part.catalog),
        "catalogs differ"
    );
    // a checkpoint of the global cut is refused by a lattice with local events
    let global = loaded(0.05, &Periodic, &Free, false);
    assert!(build().restore(&global.checkpoint()).is_err());
}
