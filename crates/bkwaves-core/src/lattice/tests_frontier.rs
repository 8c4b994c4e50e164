//! The lattice with its cells next to the runs kept as lists (chain/frontier.rs) against
//! the same lattice walking around every run: the same bits.

use super::*;
use crate::boundary::{Fixed, Free, Ghost, Periodic};
use crate::chain::events::Hermite;
use crate::chain::geometry::grid::{GridAround, GridStencil};
use crate::chain::geometry::{Beyond, Geometry};
use crate::chain::{Trigger, TriggerKind};
use crate::friction::Coulomb;

/// The grid, walked around every run as a chain is (no lists).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Walked(Grid);

impl Geometry for Walked {
    type Stencil<'a> = GridStencil<'a>;
    type Nbrs = [usize; 4];
    type Around = GridAround;
    const FRONTIER: bool = false;
    fn n(&self) -> usize {
        self.0.n()
    }
    fn shape(&self) -> (usize, usize) {
        self.0.shape()
    }
    fn cells(&self) -> usize {
        self.0.cells()
    }
    fn padded(&self, k: usize) -> usize {
        self.0.padded(k)
    }
    fn index(&self, p: usize) -> usize {
        self.0.index(p)
    }
    fn blocks(&self) -> impl Iterator<Item = usize> + '_ {
        self.0.blocks()
    }
    fn is_ghost(&self, q: usize) -> bool {
        self.0.is_ghost(q)
    }
    fn beyond(&self, q: usize, p: usize) -> Beyond {
        self.0.beyond(q, p)
    }
    fn neighbours(&self, p: usize) -> [usize; 4] {
        self.0.neighbours(p)
    }
    fn around_run(&self, a: usize, b: usize) -> GridAround {
        self.0.around_run(a, b)
    }
    fn sightings(&self, r: usize) -> ([(usize, u8); 8], usize) {
        self.0.sightings(r)
    }
    fn stencil<'a>(&self, su: &'a [f64], a: usize, b: usize) -> GridStencil<'a> {
        self.0.stencil(su, a, b)
    }
    fn force<M: Medium>(&self, med: &M, p: usize, up: f64, value: impl Fn(usize) -> f64) -> f64 {
        self.0.force(med, p, up, value)
    }
    fn phi_hermite<M: Medium>(
        &self,
        med: &M,
        p: usize,
        up: Hermite,
        nb: impl Fn(usize) -> Hermite,
    ) -> Hermite {
        self.0.phi_hermite(med, p, up, nb)
    }
    fn stiffness<M: Medium>(&self, med: &M, p: usize) -> f64 {
        self.0.stiffness(med, p)
    }
    fn coupling_energy<M: Medium>(
        &self,
        med: &M,
        value: impl Fn(usize) -> f64,
        wall: impl Fn(f64) -> f64,
    ) -> f64 {
        self.0.coupling_energy(med, value, wall)
    }
    fn spacing(&self) -> f64 {
        self.0.spacing()
    }
    fn describe(&self) -> String {
        self.0.describe()
    }
    fn ghost_partner(&self, q: usize) -> Option<usize> {
        self.0.ghost_partner(q)
    }
}

/// Everything a run leaves, bit for bit.
pub(super) fn outcome<G: Geometry>(e: &crate::chain::Engine<G, Coulomb>) -> String {
    format!(
        "{:?} {:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        e.u(),
        e.u_t(),
        e.modes(),
        e.catalog.slips,
        e.catalog.events,
        e.ledger,
        e.counters,
        e.energy()
    )
}

#[test]
fn the_lists_next_to_the_runs_give_the_walks_bits() {
    // ruptures on lattices with every boundary, at v = 0 from a kick at a corner (the
    // diagonal symmetry: events in pairs at the same instant) and under loading from a
    // rough start (slips from the queue, periodic ghosts standing for stuck blocks)
    let (nx, ny) = (23, 17);
    let fixed = Fixed {
        left: 0.2,
        right: -0.1,
    };
    let cases: [(&dyn Boundary, &dyn Boundary, f64, f64); 4] = [
        (&Free, &Free, 0.0, 0.0),
        (&Periodic, &fixed, 0.02, 0.03),
        (&fixed, &Periodic, 0.01, 0.05),
        (&Periodic, &Periodic, 0.03, 0.04),
    ];
    for (k, &(bx, by, v, rough)) in cases.iter().enumerate() {
        let u0: Vec<f64> = (0..nx * ny)
            .map(|q| 0.6 + rough * ((0.37 * q as f64).sin() + (1.3 * q as f64).cos()))
            .collect();
        let cfg = ChainConfig {
            dx: 0.1,
            v,
            step: 0.05,
        };
        let grid = Grid::new(
            nx,
            ny,
            0.1,
            0.1,
            (bx.left(), bx.right()),
            (by.left(), by.right()),
        );
        let fr = Coulomb::new(0.3, if k == 1 { 1.5 } else { f64::INFINITY }).unwrap();
        let mut a = crate::chain::Engine::build(grid, cfg, fr, Uniform, "", &u0, None).unwrap();
        let mut b =
            crate::chain::Engine::build(Walked(grid), cfg, fr, Uniform, "", &u0, None).unwrap();
        let kick = Trigger {
            t: 0.0,
            block: if k == 0 { 0 } else { nx / 2 + nx * (ny / 2) },
            kind: TriggerKind::Kick { du_t: -2.0 },
        };
        a.add_trigger(kick).unwrap();
        b.add_trigger(kick).unwrap();
        let t_end = if v > 0.0 { 30.0 } else { 1.5 };
        a.run(t_end, usize::MAX, u64::MAX).unwrap();
        b.run(t_end, usize::MAX, u64::MAX).unwrap();
        assert!(a.counters.switches > 200, "case {k}: {:?}", a.counters);
        assert_eq!(outcome(&a), outcome(&b), "case {k}");
        // the lists hold exactly the cells the walk visits: the stuck ones next to a run
        let st = a.state();
        let mut listed: Vec<usize> = st.frontier.stuck(&st.dir).collect();
        listed.sort_unstable();
        listed.dedup();
        let mut walked: Vec<usize> = Vec::new();
        for &(p, q) in &st.runs {
            for (c, _, ghost) in st.geo.around_run(p, q) {
                if !ghost && !st.sliding(c) {
                    walked.push(c);
                }
            }
        }
        walked.sort_unstable();
        walked.dedup();
        assert_eq!(listed, walked, "case {k}");
    }
}

#[test]
fn the_grid_finds_rows_and_columns_without_dividing() {
    // one strip (nx <= width) and strips of several widths, the last uneven
    for (nx, width) in [
        (1usize, 62usize),
        (2, 62),
        (3, 62),
        (5, 62),
        (7, 62),
        (64, 62),
        (64, 1000),
        (1000, 62),
        (1000, 3),
        (4095, 62),
        (4095, 5000),
        (65533, 62),
        (65533, 70000),
    ] {
        let g = Grid::new(
            nx,
            3,
            0.1,
            0.1,
            (Ghost::Mirror, Ghost::Mirror),
            (Ghost::Wrap, Ghost::Wrap),
        )
        .with_strips(width);
        let (s, strip) = (g.s, g.strip);
        assert_eq!(strip, s * 5);
        if nx <= width {
            assert_eq!((g.m, s), (1, nx + 2));
        }
        let mut qs: Vec<usize> = (0..5000).collect();
        qs.extend([(1usize << 32) - 1, (1 << 32) - s, (1 << 32), (1 << 40) + 17]);
        qs.extend((0..2000).map(|k| (k * 2_147_483_647usize) % (1 << 32)));
        for q in qs {
            let (t, r) = if g.m == 1 {
                (0, q)
            } else {
                (q / strip, q % strip)
            };
            assert_eq!(g.cell(q), (t, r % s, r / s), "nx = {nx}, q = {q}");
        }
    }
}
