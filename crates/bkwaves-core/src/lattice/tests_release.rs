//! The dead scratch given back (chain/release.rs): the same bits, and the memory given
//! back where no block slides.

use super::tests_frontier::outcome;
use super::*;
use crate::boundary::{Fixed, Free, Periodic};
use crate::chain::geometry::Geometry;
use crate::chain::release::GRANULE;
use crate::chain::{Chain, Trigger, TriggerKind};
use crate::friction::Coulomb;

/// How the dead scratch is treated.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    Kept,
    Released,
    /// Filled with NaN: a dead cell read would show in the results.
    Poisoned,
}

/// A lattice of nx x ny blocks from a rough start, kicked at block `at` at t = 0.
#[allow(clippy::too_many_arguments)]
fn lattice(
    nx: usize,
    ny: usize,
    bx: &dyn Boundary,
    by: &dyn Boundary,
    v: f64,
    rough: f64,
    beta: f64,
    local: bool,
    at: usize,
    mode: Mode,
) -> Lattice<Coulomb> {
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
        dy: 0.25,
        x: bx,
        y: by,
    };
    let fr = Coulomb::new(0.45, beta).unwrap();
    let mut la = Lattice::lattice(cfg, spec, fr, Uniform, &u0, None).unwrap();
    la.set_local_events(local);
    la.set_release(mode != Mode::Kept);
    la.set_release_poison(mode == Mode::Poisoned);
    la.add_trigger(Trigger {
        t: 0.0,
        block: at,
        kind: TriggerKind::Kick { du_t: -2.0 },
    })
    .unwrap();
    la
}

#[test]
fn the_released_scratch_changes_no_result() {
    // ruptures with the scratch kept, given back, and filled with NaN where dead: the
    // same bits (state, catalog, books, counters, checkpoints); at v = 0 from the
    // centre with local events and with the global cut, and under loading (slips from
    // the queue, quiet intervals, periodic ghosts, backward slip)
    let fixed = Fixed {
        left: 0.2,
        right: -0.1,
    };
    // (x, y boundaries, v, roughness, beta, local events)
    type Case<'a> = (&'a dyn Boundary, &'a dyn Boundary, f64, f64, f64, bool);
    let cases: [Case; 4] = [
        (&Free, &Free, 0.0, 0.0, f64::INFINITY, true),
        (&Free, &Free, 0.0, 0.0, f64::INFINITY, false),
        (&Periodic, &fixed, 0.02, 0.03, 1.5, true),
        (&fixed, &Periodic, 0.01, 0.05, f64::INFINITY, false),
    ];
    let (nx, ny) = (60, 50);
    for (k, &(bx, by, v, rough, beta, local)) in cases.iter().enumerate() {
        let at = nx / 2 + nx * (ny / 2);
        let t_end = if v > 0.0 { 40.0 } else { 12.0 };
        let runs: Vec<Lattice<Coulomb>> = [Mode::Kept, Mode::Released, Mode::Poisoned]
            .into_iter()
            .map(|mode| {
                let mut la = lattice(nx, ny, bx, by, v, rough, beta, local, at, mode);
                la.run(t_end, usize::MAX, u64::MAX).unwrap();
                la
            })
            .collect();
        assert!(
            runs[0].counters.switches > 2000,
            "case {k}: {:?}",
            runs[0].counters
        );
        let kept = runs[0].release_stats();
        assert!(!kept.on && kept.passes == 0 && kept.bytes == 0, "case {k}");
        let rel = runs[1].release_stats();
        assert!(rel.on && rel.passes > 10, "case {k}: {rel:?}");
        #[cfg(target_os = "linux")]
        assert!(rel.bytes > 0, "case {k}: {rel:?}");
        for la in &runs[1..] {
            assert_eq!(outcome(&runs[0]), outcome(la), "case {k}");
            assert!(runs[0].checkpoint() == la.checkpoint(), "case {k}");
        }
    }
}

#[test]
fn the_released_scratch_changes_no_result_of_a_chain() {
    // a loaded chain (events from the queue, quiet intervals in between): the same bits
    let n = 1000;
    let u0: Vec<f64> = (0..n)
        .map(|i| 0.5 + 0.3 * (0.01 * i as f64).sin() + 0.1 * (0.37 * i as f64).cos())
        .collect();
    let cfg = ChainConfig {
        dx: 0.1,
        v: 0.01,
        step: 0.05,
    };
    let fr = Coulomb::new(0.3, f64::INFINITY).unwrap();
    let runs: Vec<Chain<Coulomb>> = [Mode::Kept, Mode::Released, Mode::Poisoned]
        .into_iter()
        .map(|mode| {
            let mut ch = Chain::new(cfg, fr, &Free, &u0, None).unwrap();
            ch.set_release(mode != Mode::Kept);
            ch.set_release_poison(mode == Mode::Poisoned);
            ch.run(150.0, usize::MAX, u64::MAX).unwrap();
            ch
        })
        .collect();
    assert!(
        runs[0].catalog.finished() > 5,
        "{}",
        runs[0].catalog.finished()
    );
    assert!(runs[1].release_stats().passes > 20);
    for ch in &runs[1..] {
        assert_eq!(outcome(&runs[0]), outcome(ch));
        assert!(runs[0].checkpoint() == ch.checkpoint());
    }
}

#[test]
fn large_engines_give_their_dead_scratch_back_by_default() {
    // on from 2^17 cells (chain/release.rs: RELEASE_FROM)
    let cfg = ChainConfig {
        dx: 0.25,
        v: 0.0,
        step: 0.1,
    };
    let fr = Coulomb::new(0.45, f64::INFINITY).unwrap();
    for (n, on) in [(300, false), (400, true)] {
        let spec = LatticeSpec {
            nx: n,
            ny: n,
            dy: 0.25,
            x: &Free,
            y: &Free,
        };
        let la = Lattice::lattice(cfg, spec, fr, Uniform, &vec![0.6; n * n], None).unwrap();
        assert_eq!(la.release_stats().on, on, "n = {n}");
    }
}

/// The granules of the cells the runs and their neighbours cover.
fn live_granules(la: &Lattice<Coulomb>) -> usize {
    let st = la.state();
    let mut g: Vec<usize> = Vec::new();
    for &(a, b) in &st.runs {
        for (lo, hi) in [
            (a - 1, b + 1),
            (a - st.geo.s, b - st.geo.s),
            (a + st.geo.s, b + st.geo.s),
        ] {
            g.extend(lo / GRANULE..=(hi - 1) / GRANULE);
        }
    }
    g.sort_unstable();
    g.dedup();
    g.len()
}

#[cfg(target_os = "linux")]
#[test]
fn dead_scratch_pages_are_given_back() {
    // a rupture along a strip of 2400 x 24 blocks kicked at its centre: two fronts run
    // apart (a pulse: a few blocks slide behind each front, those behind them have
    // stuck again). Midway, the scratch's resident pages are those around the sliding
    // blocks (each live granule overlaps at most two pages of an array, plus the two
    // pages at the array's ends), a fraction of what the same run keeps without the
    // release (a page is 512 cells, a fifth of a row: the healed stretch of a row must
    // span whole pages); once everything has stuck, no scratch page is resident but the
    // arrays' end pages
    let (nx, ny) = (2400, 24);
    let at = nx / 2 + nx * (ny / 2);
    let strip = |mode| {
        lattice(
            nx,
            ny,
            &Free,
            &Free,
            0.0,
            0.0,
            f64::INFINITY,
            true,
            at,
            mode,
        )
    };
    let (mut kept, mut rel) = (strip(Mode::Kept), strip(Mode::Released));
    let resident = |la: &Lattice<Coulomb>| -> Vec<(&'static str, usize, usize)> {
        la.scratch_arrays()
            .into_iter()
            .map(|(name, a)| {
                let (r, all) = a.resident_pages().unwrap();
                (name, r, all)
            })
            .collect()
    };
    // (the fronts at about 1000 blocks from the centre, 5 blocks per unit time)
    let t_mid = 200.0;
    kept.run(t_mid, usize::MAX, u64::MAX).unwrap();
    rel.run(t_mid, usize::MAX, u64::MAX).unwrap();
    rel.release_dead();
    let live = live_granules(&rel);
    let (rk, rr) = (resident(&kept), resident(&rel));
    assert_eq!(rk.len(), 13);
    let (sum_k, sum_r): (usize, usize) =
        (rk.iter().map(|x| x.1).sum(), rr.iter().map(|x| x.1).sum());
    for (&(name, r, all), &(_, r_kept, _)) in rr.iter().zip(&rk) {
        assert!(
            r <= 2 * live + 2,
            "{name}: {r} resident pages of {all}, {live} live granules"
        );
        // (bu, bd: the loader and dry-power books, not kept at v = 0 without backward
        // slip, never written)
        let unused = name == "bu" || name == "bd";
        assert!(unused || r_kept > all / 2, "{name}: kept {r_kept} of {all}");
    }
    // (measured: 813 against 1270; 74-80 of 123 pages of an array against 113-122, 53
    // live granules)
    assert!(
        4 * sum_r < 3 * sum_k,
        "resident pages {sum_r} released, {sum_k} kept"
    );
    // all stuck: nothing resident but the ends
    rel.run(320.0, usize::MAX, u64::MAX).unwrap();
    assert_eq!(rel.state().n_active, 0);
    for (name, r, all) in resident(&rel) {
        assert!(
            r <= 2,
            "{name}: {r} resident pages of {all} with every block stuck"
        );
    }
    let s = rel.release_stats();
    assert!(s.bytes as usize >= 11 * 4096 * (sum_k / 11), "{s:?}");
}

#[test]
#[cfg(target_os = "linux")]
fn the_arrays_and_their_resident_bytes_are_listed() {
    // Engine::memory_arrays: the five state arrays and the scratch at the padded length,
    // resident within what is allocated (plus the two partial pages at the ends), the
    // catalog's records at their capacity; u and u_t are resident from the start
    // (written at construction)
    let (nx, ny) = (600, 400);
    let mut la = lattice(
        nx,
        ny,
        &Free,
        &Free,
        0.0,
        0.0,
        f64::INFINITY,
        true,
        300 + 600 * 200,
        Mode::Released,
    );
    // (the padded cells: in strips, a ghost frame per strip)
    let cells = la.geometry().cells();
    assert_eq!(cells, 10 * 62 * (ny + 2));
    let page = 4096;
    let before = la.memory_arrays();
    let get = |v: &[(&'static str, usize, Option<usize>)], name: &str| {
        *v.iter()
            .find(|a| a.0 == name)
            .unwrap_or_else(|| panic!("{name} listed"))
    };
    for name in ["u", "u_t", "t_ref", "mode", "threshold at onset"] {
        let (_, bytes, res) = get(&before, name);
        assert_eq!(bytes, cells * 8, "{name}");
        let res = res.expect("mincore on Linux");
        assert!(res <= bytes + 2 * page, "{name}: {res} resident of {bytes}");
    }
    // u and u_t are written for every block at construction
    assert!(get(&before, "u").2.unwrap() >= cells * 8 - 2 * page);
    // (whether the unwritten scratch is resident before the first step depends on where
    // the allocator found the memory: fresh pages from the system are not, memory a test
    // freed earlier in this process may be; the release tests above bound it after
    // madvise, which does not depend on that)
    for name in ["su", "ku", "a_end"] {
        let (_, bytes, res) = get(&before, name);
        assert_eq!(bytes, cells * 8, "{name}");
        assert!(res.unwrap() <= bytes + 2 * page, "{name}: {res:?}");
    }
    la.run(2.0, usize::MAX, u64::MAX).unwrap();
    let after = la.memory_arrays();
    let (_, slips, res) = get(&after, "catalog: slips");
    assert!(!la.catalog.slips.is_empty());
    assert_eq!(
        slips,
        la.catalog.slips.capacity() * std::mem::size_of::<crate::chain::catalog::SlipRecord>()
    );
    assert!(res.unwrap() >= (la.catalog.slips.len() * 64).saturating_sub(page));
    // the scratch was written where the rupture slid
    assert!(get(&after, "su").2.unwrap() > 4 * page);
}
