//! The lattice's cells in strips (chain/geometry/grid.rs) against the same lattice in one
//! strip: the same bits.
//!
//! A block's arithmetic does not depend on where its cell lies (its force reads the same
//! neighbour values, a seam ghost filled with its block's value as a periodic ghost is),
//! and an event is the earliest crossing, a minimum, whatever order the blocks are
//! searched in. So the state (u, u_t, modes), the slip records (as a set: sorted by
//! start time and block), the events, the counters and the energy are compared bit for
//! bit. Only the engine's energy books (`ledger`: sums over the runs, in memory order,
//! which the strips change) are compared to 1e-12 relative.

use super::*;
use crate::boundary::{Boundary, Fixed, Free, Periodic};
use crate::chain::catalog::SlipRecord;
use crate::chain::geometry::Geometry;
use crate::chain::integrator::Method;
use crate::chain::medium::{PerBlock, Properties};
use crate::chain::{Trigger, TriggerKind};
use crate::friction::{Coulomb, VelocityWeakening};

/// The widths of strips each case is cut into (besides one strip): the last strip
/// uneven for most lattices below.
const WIDTHS: [usize; 5] = [1, 2, 3, 4, 5];

/// A lattice to run: shape, boundaries, start, loading, what slips first, and the
/// engine's options.
#[derive(Clone)]
struct Case<'a> {
    nx: usize,
    ny: usize,
    bx: &'a dyn Boundary,
    by: &'a dyn Boundary,
    v: f64,
    /// Roughness of the start (u0 = 0.6 + rough (sin + cos)).
    rough: f64,
    /// Blocks kicked at t = 0.
    kicks: Vec<usize>,
    t_end: f64,
    local: bool,
    method: Method,
    tol: Option<f64>,
    props: Option<Properties>,
    release: bool,
}

impl<'a> Case<'a> {
    fn new(nx: usize, ny: usize, bx: &'a dyn Boundary, by: &'a dyn Boundary) -> Case<'a> {
        Case {
            nx,
            ny,
            bx,
            by,
            v: 0.0,
            rough: 0.0,
            kicks: vec![nx / 2 + nx * (ny / 2)],
            t_end: 3.0,
            local: false,
            method: Method::Rk4,
            tol: None,
            props: None,
            release: false,
        }
    }

    fn u0(&self) -> Vec<f64> {
        (0..self.nx * self.ny)
            .map(|q| 0.6 + self.rough * ((0.37 * q as f64).sin() + (1.3 * q as f64).cos()))
            .collect()
    }

    fn spec(&self) -> LatticeSpec<'a> {
        LatticeSpec {
            nx: self.nx,
            ny: self.ny,
            dy: 0.2,
            x: self.bx,
            y: self.by,
        }
    }

    fn cfg(&self) -> ChainConfig {
        ChainConfig {
            dx: 0.25,
            v: self.v,
            step: 0.05,
        }
    }

    /// The engine in strips of at most `width` columns, not yet run.
    fn build<F: Friction, M: Medium>(&self, fr: F, med: M, width: usize) -> Lattice<F, M> {
        let mut la =
            Lattice::lattice_in_strips(self.cfg(), self.spec(), width, fr, med, &self.u0(), None)
                .unwrap();
        la.set_integrator(self.method).unwrap();
        la.set_step_control(self.tol).unwrap();
        la.set_local_events(self.local);
        la.set_release(self.release);
        la.set_release_poison(self.release);
        for &b in &self.kicks {
            la.add_trigger(Trigger {
                t: 0.0,
                block: b,
                kind: TriggerKind::Kick { du_t: -2.0 },
            })
            .unwrap();
        }
        la
    }

    /// The per-block medium of `props` for the layout in strips of `width`.
    fn medium(&self, width: usize) -> PerBlock {
        let grid = crate::chain::geometry::Grid::new(
            self.nx,
            self.ny,
            0.25,
            0.2,
            (self.bx.left(), self.bx.right()),
            (self.by.left(), self.by.right()),
        )
        .with_strips(width);
        PerBlock::for_lattice(self.props.as_ref().unwrap(), &grid).unwrap()
    }
}

/// Everything a run leaves that does not depend on the layout, bit for bit (slips as a
/// set), and its energy books.
fn outcome<F: Friction, M: Medium>(la: &Lattice<F, M>) -> (String, [f64; 5]) {
    let mut slips: Vec<SlipRecord> = la.catalog.slips.clone();
    slips.sort_by(|a, b| a.t_start.total_cmp(&b.t_start).then(a.block.cmp(&b.block)));
    let mut first = vec![f64::NAN; la.n()];
    for s in &slips {
        if first[s.block].is_nan() {
            first[s.block] = s.t_start;
        }
    }
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<u64>>();
    let (kin, coup, load) = la.energy();
    let l = &la.ledger;
    (
        format!(
            "u {:?}\nu_t {:?}\nmodes {:?}\nfirst {:?}\nslips {:?}\nevents {:?}\n\
             counters {:?}\nenergy {:?}\nt {:?}",
            bits(&la.u()),
            bits(&la.u_t()),
            la.modes(),
            bits(&first),
            slips,
            la.catalog.events,
            la.counters,
            bits(&[kin, coup, load]),
            la.time().to_bits(),
        ),
        [l.load, l.dry, l.viscous, l.projection, l.injected],
    )
}

/// The books agree to `tol` relative to the largest of them.
fn books_agree(a: &[f64; 5], b: &[f64; 5], tol: f64) -> bool {
    let scale = a.iter().chain(b).fold(0.0_f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol * scale)
}

/// Run `case` in one strip and in strips of every width of `WIDTHS`: the same bits;
/// returns the one-strip run's switch count.
fn same_in_strips<F: Friction, M: Medium>(
    what: &str,
    case: &Case,
    make: impl Fn() -> F,
    med: impl Fn(usize) -> M,
) -> u64 {
    let run = |width: usize| {
        let mut la = case.build(make(), med(width), width);
        la.run(case.t_end, usize::MAX, u64::MAX).unwrap();
        la
    };
    let one = run(case.nx);
    assert_eq!(one.geometry().m, 1);
    let (want, books) = outcome(&one);
    for w in WIDTHS {
        if w >= case.nx {
            continue;
        }
        let la = run(w);
        assert!(la.geometry().m > 1);
        let (got, got_books) = outcome(&la);
        if got != want {
            let line = got
                .lines()
                .zip(want.lines())
                .find(|(a, b)| a != b)
                .map(|(a, b)| format!("\n strips: {a:.300}\n one:    {b:.300}"));
            panic!("{what}, strips of {w}: differs{}", line.unwrap_or_default());
        }
        assert!(
            books_agree(&books, &got_books, 1e-12),
            "{what}, strips of {w}: books {books:?} vs {got_books:?}"
        );
    }
    one.counters.switches
}

fn coulomb() -> Coulomb {
    Coulomb::new(0.3, f64::INFINITY).unwrap()
}

#[test]
fn fronts_along_x_along_y_and_the_diagonal_are_the_same_bits_in_strips() {
    let (nx, ny) = (13, 11);
    // along x: the left column kicked; along y: the bottom row; the diagonal: a corner;
    // a point: the centre (its front crosses the strips' corners)
    let cases: [(&str, Vec<usize>); 4] = [
        ("along x", (0..ny).map(|j| nx * j).collect()),
        ("along y", (0..nx).collect()),
        ("diagonal", vec![0]),
        ("point", vec![nx / 2 + nx * (ny / 2)]),
    ];
    for (what, kicks) in cases {
        let mut c = Case::new(nx, ny, &Free, &Free);
        c.kicks = kicks;
        let n = same_in_strips(what, &c, coulomb, |_| Uniform);
        assert!(n > 120, "{what}: {n} switches");
    }
}

#[test]
fn every_boundary_is_the_same_bits_in_strips() {
    let fixed = Fixed {
        left: 0.2,
        right: -0.1,
    };
    let sides: [(&dyn Boundary, &dyn Boundary); 6] = [
        (&Free, &Free),
        (&fixed, &fixed),
        (&Periodic, &Free),
        (&Free, &Periodic),
        (&Periodic, &Periodic),
        (&Periodic, &fixed),
    ];
    for (bx, by) in sides {
        let mut c = Case::new(12, 9, bx, by);
        // kicked next to the left edge: the front crosses the periodic side and seams
        c.kicks = vec![1 + 12 * 4];
        c.t_end = 4.0;
        let what = format!("x {}, y {}", bx.name(), by.name());
        let n = same_in_strips(&what, &c, coulomb, |_| Uniform);
        assert!(n > 150, "{what}: {n} switches");
    }
}

#[test]
fn loading_to_later_ruptures_is_the_same_bits_in_strips() {
    // quiet loading from a rough start, ruptures from the queue, sticks and slips again;
    // with the global cut and with local events
    let fixed = Fixed {
        left: 0.2,
        right: -0.1,
    };
    for (bx, by, local) in [
        (&Periodic as &dyn Boundary, &fixed as &dyn Boundary, false),
        (&fixed, &Periodic, true),
        (&Periodic, &Periodic, true),
    ] {
        let mut c = Case::new(11, 8, bx, by);
        c.v = 0.02;
        c.rough = 0.04;
        c.kicks = vec![];
        c.t_end = 30.0;
        c.local = local;
        let what = format!("loaded x {}, y {}, local {local}", bx.name(), by.name());
        let fr = || Coulomb::new(0.3, 1.5).unwrap();
        let n = same_in_strips(&what, &c, fr, |_| Uniform);
        assert!(n > 300, "{what}: {n} switches");
    }
}

#[test]
fn local_events_and_the_global_cut_are_the_same_bits_in_strips() {
    for local in [false, true] {
        let mut c = Case::new(14, 10, &Free, &Free);
        c.local = local;
        c.t_end = 5.0;
        let n = same_in_strips(&format!("local {local}"), &c, coulomb, |_| Uniform);
        assert!(n > 200, "local {local}: {n} switches");
    }
}

#[test]
fn the_midpoint_rule_and_the_step_control_are_the_same_bits_in_strips() {
    let mut c = Case::new(11, 9, &Free, &Periodic);
    c.method = Method::Midpoint;
    assert!(same_in_strips("midpoint", &c, coulomb, |_| Uniform) > 100);
    let mut c = Case::new(11, 9, &Periodic, &Free);
    c.tol = Some(1e-6);
    assert!(same_in_strips("step control", &c, coulomb, |_| Uniform) > 100);
}

#[test]
fn per_bond_springs_and_per_block_properties_are_the_same_bits_in_strips() {
    let (nx, ny) = (12, 9);
    let fixed = Fixed {
        left: 0.2,
        right: -0.1,
    };
    for (bx, by) in [
        (&Free as &dyn Boundary, &Free as &dyn Boundary),
        (&Periodic, &fixed),
        (&fixed, &Periodic),
    ] {
        let count = |n: usize, b: &dyn Boundary| match b.name() {
            "free" => n - 1,
            "fixed" => n + 1,
            _ => n,
        };
        let (cx, cy) = (ny * count(nx, bx), nx * count(ny, by));
        // springs of every bond, some zero (the lattice cut there: seams among them),
        // thresholds and masses per block
        let props = Properties {
            coupling: Some(
                (0..cx)
                    .map(|b| {
                        if b % 7 == 3 {
                            0.0
                        } else {
                            1.0 + 0.4 * (0.7 * b as f64).sin()
                        }
                    })
                    .collect(),
            ),
            coupling_y: Some(
                (0..cy)
                    .map(|b| {
                        if b % 5 == 1 {
                            0.0
                        } else {
                            1.0 + 0.3 * (1.1 * b as f64).cos()
                        }
                    })
                    .collect(),
            ),
            threshold: Some(
                (0..nx * ny)
                    .map(|k| 1.0 + 0.1 * (0.3 * k as f64).sin())
                    .collect(),
            ),
            mass: Some(
                (0..nx * ny)
                    .map(|k| 1.0 + 0.2 * (0.5 * k as f64).cos())
                    .collect(),
            ),
            loader: None,
        };
        let mut c = Case::new(nx, ny, bx, by);
        c.props = Some(props);
        c.v = 0.01;
        c.rough = 0.03;
        c.t_end = 15.0;
        let what = format!("per bond x {}, y {}", bx.name(), by.name());
        let n = same_in_strips(&what, &c, coulomb, |w| c.medium(w));
        assert!(n > 150, "{what}: {n} switches");
    }
}

#[test]
fn a_velocity_weakening_lattice_is_the_same_bits_in_strips() {
    // the stiff onset: blocks in their onset groups on their own sub-steps (chain/onset.rs)
    let mut c = Case::new(11, 8, &Free, &Periodic);
    c.t_end = 2.0;
    let fr = || VelocityWeakening::from_values(&[0.3, 0.05, f64::INFINITY]).unwrap();
    assert!(same_in_strips("velocity weakening", &c, fr, |_| Uniform) > 100);
}

#[test]
fn the_released_scratch_is_the_same_bits_in_strips() {
    // the release forced on for a small lattice, the dead cells filled with NaN: a seam
    // ghost or a dead cell read when it should not be shows as NaN in the results
    for local in [false, true] {
        let mut c = Case::new(13, 10, &Periodic, &Free);
        c.release = true;
        c.local = local;
        c.t_end = 4.0;
        let n = same_in_strips(&format!("released, local {local}"), &c, coulomb, |_| {
            Uniform
        });
        assert!(n > 200, "{n}");
        let mut la = c.build(coulomb(), Uniform, 3);
        la.run(c.t_end, usize::MAX, u64::MAX).unwrap();
        let rel = la.release_stats();
        assert!(rel.on && rel.passes > 5, "{rel:?}");
    }
}

#[test]
fn a_checkpoint_resumes_bit_for_bit_in_strips() {
    let mut c = Case::new(13, 9, &Periodic, &Free);
    c.v = 0.02;
    c.rough = 0.04;
    c.kicks = vec![];
    c.t_end = 25.0;
    let fr = || Coulomb::new(0.3, 1.5).unwrap();
    for width in [13, 3, 5] {
        // (uninterrupted but stopped at t = 12 too: a stop cuts the step there)
        let mut whole = c.build(fr(), Uniform, width);
        whole.run(12.0, usize::MAX, u64::MAX).unwrap();
        whole.run(c.t_end, usize::MAX, u64::MAX).unwrap();
        let mut first = c.build(fr(), Uniform, width);
        first.run(12.0, usize::MAX, u64::MAX).unwrap();
        assert!(first.counters.switches > 50);
        let bytes = first.checkpoint();
        let mut resumed = c.build(fr(), Uniform, width);
        resumed.restore(&bytes).unwrap();
        resumed.run(c.t_end, usize::MAX, u64::MAX).unwrap();
        assert_eq!(outcome(&whole).0, outcome(&resumed).0, "strips of {width}");
        assert!(
            whole.checkpoint() == resumed.checkpoint(),
            "strips of {width}"
        );
        // another layout's checkpoint is refused (its padded arrays mean other cells)
        let mut other = c.build(fr(), Uniform, if width == 13 { 4 } else { 13 });
        let e = other.restore(&bytes).unwrap_err().to_string();
        assert!(e.contains("same blocks"), "{e}");
    }
}

#[test]
fn a_wide_lattice_is_in_strips_and_refuses_a_checkpoint_of_one_strip() {
    // a lattice wider than 256 columns is in strips of at most 62 by default; a
    // checkpoint of the same lattice in one strip (the layout before strips) fails with
    // the clear error
    let c = Case::new(300, 2, &Free, &Free);
    let fr = coulomb;
    let la = Lattice::lattice(c.cfg(), c.spec(), fr(), Uniform, &c.u0(), None).unwrap();
    let g = *la.geometry();
    assert_eq!((g.m, g.w, g.last, g.s), (5, 60, 60, 62));
    assert!(g.describe().contains("5 strips"), "{}", g.describe());
    let mut one = c.build(fr(), Uniform, 300);
    assert_eq!(one.geometry().m, 1);
    assert!(!one.geometry().describe().contains("strips"));
    one.run(0.5, usize::MAX, u64::MAX).unwrap();
    let old = one.checkpoint();
    let mut la = la;
    let e = la.restore(&old).unwrap_err().to_string();
    assert!(e.contains("same blocks"), "{e}");
    // and a lattice of at most 256 columns is in one strip: its old checkpoints load
    let c = Case::new(256, 2, &Free, &Free);
    let la = Lattice::lattice(c.cfg(), c.spec(), fr(), Uniform, &c.u0(), None).unwrap();
    assert_eq!((la.geometry().m, la.geometry().s), (1, 258));
    let c = Case::new(257, 2, &Free, &Free);
    let la = Lattice::lattice(c.cfg(), c.spec(), fr(), Uniform, &c.u0(), None).unwrap();
    assert_eq!(
        (la.geometry().m, la.geometry().w, la.geometry().last),
        (5, 52, 49)
    );
}

#[test]
fn the_strips_keep_every_block_and_its_neighbours() {
    // block order, index and padded index, ghosts, what each ghost stands for, and the
    // sightings (each the far end of one of a block's four neighbour slots: at most 4)
    use crate::boundary::Ghost;
    use crate::chain::geometry::{Beyond, Grid};
    for (nx, ny) in [(1usize, 1usize), (2, 3), (7, 4), (13, 5), (64, 2)] {
        for x in [(Ghost::Mirror, Ghost::Mirror), (Ghost::Wrap, Ghost::Wrap)] {
            for y in [
                (Ghost::Held(0.3), Ghost::Mirror),
                (Ghost::Wrap, Ghost::Wrap),
            ] {
                let one = Grid::in_strips(nx, ny, 0.1, 0.2, x, y, nx);
                for width in [1, 2, 3, 5, 62] {
                    let g = one.with_strips(width);
                    let blocks: Vec<usize> = g.blocks().collect();
                    assert_eq!(blocks.len(), nx * ny);
                    let mut real = vec![false; g.cells()];
                    for (k, &p) in blocks.iter().enumerate() {
                        assert_eq!(g.padded(k), p);
                        assert_eq!(g.index(p), k);
                        assert!(!g.is_ghost(p));
                        real[p] = true;
                    }
                    assert_eq!(real.iter().filter(|&&r| r).count(), nx * ny);
                    for q in 0..g.cells() {
                        assert_eq!(g.is_ghost(q), !real[q], "{nx}x{ny} w {width} q {q}");
                    }
                    // the neighbours of block k in one strip and in strips: the same
                    // blocks, walls and free sides
                    let to_k = |geo: &Grid, b: Beyond| match b {
                        Beyond::Block(r) => Some(geo.index(r)),
                        Beyond::Wall(_) => None,
                    };
                    for k in 0..nx * ny {
                        let (p1, p) = (one.padded(k), g.padded(k));
                        for (q1, q) in one.neighbours(p1).into_iter().zip(g.neighbours(p)) {
                            let of = |geo: &Grid, q: usize, p: usize| {
                                if geo.is_ghost(q) {
                                    to_k(geo, geo.beyond(q, p))
                                } else {
                                    Some(geo.index(q))
                                }
                            };
                            // (a real neighbour in one strip may be a seam ghost in strips)
                            assert_eq!(of(&one, q1, p1), of(&g, q, p), "{nx}x{ny} w {width} k {k}");
                            assert_eq!(
                                one.resolve(q1).map(|r| one.index(r)),
                                g.resolve(q).map(|r| g.index(r)),
                                "{nx}x{ny} w {width} k {k}"
                            );
                        }
                        // the sightings: the same blocks and sides
                        let sight = |geo: &Grid, p: usize| {
                            let (s, n) = geo.sightings(p);
                            assert!(n <= 4);
                            let mut v: Vec<(usize, u8)> = s[..n]
                                .iter()
                                .map(|&(b, side)| (geo.index(b), side))
                                .collect();
                            v.sort_unstable();
                            v
                        };
                        assert_eq!(sight(&one, p1), sight(&g, p), "{nx}x{ny} w {width} k {k}");
                    }
                }
            }
        }
    }
}
