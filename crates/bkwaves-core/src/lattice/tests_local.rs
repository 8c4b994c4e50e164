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

/// Everything a run gives but its block-step count (which the shortcuts lower).
fn outcome_but_work<G: crate::chain::geometry::Geometry>(
    e: &crate::chain::Engine<G, Coulomb>,
) -> String {
    let mut c = e.counters;
    c.block_steps = 0;
    format!(
        "{:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        e.u(),
        e.u_t(),
        e.modes(),
        e.catalog.slips,
        e.catalog.events,
        e.ledger,
        c,
        e.energy()
    )
}

/// The local events' block-steps split (quiet steps, first passes, later passes,
/// components) adds up to the engine's count.
fn split_adds_up<G: crate::chain::geometry::Geometry>(e: &crate::chain::Engine<G, Coulomb>) {
    let s = e.local_stats();
    assert_eq!(s.fallbacks, 0, "{s:?}");
    assert_eq!(
        s.quiet_block_steps + s.first_block_steps + s.later_block_steps + s.component_block_steps,
        e.counters.block_steps,
        "{s:?}"
    );
}

#[test]
fn the_local_shortcuts_give_the_plain_forms_bits() {
    // the later passes near the members only (chain/local_events.rs, `later_pass`: a
    // block 3 or more hops from every member ends the pass with the first pass's values),
    // the later passes from the saved start state (no copy back) and the accelerations
    // after a step with switches recomputed only at the members and their neighbours:
    // each against its plain form, and all three at once, on ruptures with every kind of
    // boundary (periodic wraps, walls, free edges), under loading with viscous friction
    // and backward slips, and on a chain: the same state, catalog, books and counters but
    // the block-steps, which the near pass lowers
    use crate::chain::Chain;
    use crate::chain::Plain;
    let fixed = Fixed {
        left: 0.2,
        right: -0.1,
    };
    let all = Plain {
        whole_pass: true,
        all_accel: true,
        copy_back: true,
    };
    let plains = [
        all,
        Plain {
            whole_pass: true,
            ..Plain::default()
        },
        Plain {
            all_accel: true,
            ..Plain::default()
        },
        // (a copy back is a form of the whole pass: the near pass leaves the blocks it
        // does not step with the first pass's values, which a copy back would undo)
        Plain {
            copy_back: true,
            whole_pass: true,
            ..Plain::default()
        },
    ];
    // each plain form against the shortcuts (the copy back against the whole pass
    // without it), counting every block-step or all but them
    let against = |j: usize| if j == 3 { plains[1] } else { Plain::default() };
    type Case<'a> = (&'a dyn Boundary, &'a dyn Boundary, f64, f64, f64);
    let cases: [Case; 4] = [
        (&Free, &Free, 0.0, 0.0, f64::INFINITY),
        (&Periodic, &fixed, 0.02, 0.03, 1.5),
        (&fixed, &Periodic, 0.01, 0.05, f64::INFINITY),
        (&Periodic, &Periodic, 0.03, 0.04, 0.8),
    ];
    let (nx, ny) = (40, 30);
    for (k, &(bx, by, v, rough, beta)) in cases.iter().enumerate() {
        let run = |plain: Plain| {
            let u0: Vec<f64> = (0..nx * ny)
                .map(|q| 0.6 + rough * ((0.37 * q as f64).sin() + (1.3 * q as f64).cos()))
                .collect();
            let cfg = ChainConfig {
                dx: 0.25,
                v,
                step: 0.1,
            };
            let spec = LatticeSpec {
                nx,
                ny,
                dy: 0.3,
                x: bx,
                y: by,
            };
            let fr = Coulomb::new(0.45, beta).unwrap();
            let mut la = Lattice::lattice(cfg, spec, fr, Uniform, &u0, None).unwrap();
            la.set_local_events(true);
            la.set_local_plain(plain);
            la.add_trigger(Trigger {
                t: 0.0,
                block: nx / 3 + nx * (ny / 2),
                kind: TriggerKind::Kick { du_t: -2.0 },
            })
            .unwrap();
            la.run(if v > 0.0 { 40.0 } else { 10.0 }, usize::MAX, u64::MAX)
                .unwrap();
            split_adds_up(&la);
            la
        };
        let shortcuts = run(Plain::default());
        let s = shortcuts.local_stats();
        assert!(
            shortcuts.counters.switches > 1000,
            "case {k}: {:?}",
            shortcuts.counters
        );
        assert!(s.event_steps > 100, "case {k}: {s:?}");
        for (j, &plain) in plains.iter().enumerate() {
            let old = run(plain);
            let new = if j == 3 {
                run(against(j))
            } else {
                shortcuts.clone()
            };
            assert_eq!(
                outcome_but_work(&old),
                outcome_but_work(&new),
                "case {k}, plain {j}"
            );
            let (o, s) = (old.local_stats(), new.local_stats());
            if plain.whole_pass && !against(j).whole_pass {
                // (measured: the later passes 5 to 25 times fewer block-steps)
                assert!(
                    2 * s.later_block_steps < o.later_block_steps,
                    "case {k}: {s:?} {o:?}"
                );
                assert!(new.counters.block_steps < old.counters.block_steps);
            } else {
                assert_eq!(old.counters, new.counters, "case {k}, plain {j}");
            }
        }
    }
    // a loaded chain with local events (the walk around the runs, no frontier lists)
    let n = 600;
    let u0: Vec<f64> = (0..n)
        .map(|i| 0.5 + 0.3 * (0.01 * i as f64).sin() + 0.1 * (0.37 * i as f64).cos())
        .collect();
    let cfg = ChainConfig {
        dx: 0.1,
        v: 0.01,
        step: 0.05,
    };
    let fr = Coulomb::new(0.3, f64::INFINITY).unwrap();
    let chain = |plain: Plain| {
        let mut ch = Chain::new(cfg, fr, &Free, &u0, None).unwrap();
        ch.set_local_events(true);
        ch.set_local_plain(plain);
        ch.run(150.0, usize::MAX, u64::MAX).unwrap();
        split_adds_up(&ch);
        ch
    };
    let new = chain(Plain::default());
    assert!(
        new.local_stats().event_steps > 100,
        "{:?}",
        new.local_stats()
    );
    for (j, &plain) in plains.iter().enumerate() {
        let new = chain(against(j));
        assert_eq!(
            outcome_but_work(&chain(plain)),
            outcome_but_work(&new),
            "plain {j}"
        );
    }
}
