//! Who neighbours whom: the one thing in which the chain and the lattice differ.
//!
//! The engine ([`super::Engine`]) keeps every per-block array padded with ghost cells
//! and steps maximal runs [a, b) of sliding blocks that are consecutive in memory. A
//! geometry says how the padded arrays are laid out and what stands around a block:
//!
//! - [`Line`]: the chain, blocks 1..=n of n + 2 cells, ghosts 0 and n + 1;
//! - [`Grid`]: the square lattice (docs/lattice.md): up to 256 columns row-major in
//!   (nx + 2) x (ny + 2) cells, wider in vertical strips of at most 62 columns, each
//!   row-major with its own ghost frame ([`grid`]): a run is a stretch of one row of a strip
//!   (ghost columns separate the rows and the strips), its x neighbours are p -/+ 1 as in
//!   the chain, its y neighbours p -/+ S (S the strips' row stride); a ghost column
//!   between two strips stands for the neighbouring strip's block as a periodic ghost
//!   does for the far side's.
//!
//! Everything the engine asks of a geometry goes through [`Geometry`]: the blocks and
//! their 0-based numbering, the ghosts (through [`Ghost`] per side, resolved by
//! [`Geometry::beyond`]), the coupling force from neighbour values (the kernels read it
//! through a [`Stencil`] of equal-length slices, so the run loops vectorise), the
//! Hermite data of phi for event location, and the coupling energy. The engine is
//! monomorphised over the geometry: the chain runs the same code it always ran.

pub mod grid;
pub mod line;

pub use grid::Grid;
pub use line::Line;

use super::events::Hermite;
use super::medium::Medium;
use crate::boundary::Ghost;

/// What a ghost cell next to a real block stands for: a real block (padded index; the
/// block itself for a free side, the far side's block for a periodic one) or a wall
/// fixed to the ground (its u at t = 0; it drifts as u0 + v t).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Beyond {
    /// A real block (padded index).
    Block(usize),
    /// A wall with u = u0 + v t.
    Wall(f64),
}

/// The coupling force of the blocks of one run from stage values, read by the kernels
/// (block a + i of the run at offset i).
pub trait Stencil {
    /// The displacement of the block at offset i.
    fn centre(&self, i: usize) -> f64;
    /// The coupling force sum_q k_pq (u_q - u_p) / d_pq^2 on padded block p = a + i.
    fn force<M: Medium>(&self, med: &M, p: usize, i: usize) -> f64;
}

/// A layout of blocks and their neighbours (module docs).
pub trait Geometry: Clone + Send + Sync + std::fmt::Debug + 'static {
    /// The stage values around a run.
    type Stencil<'a>: Stencil;
    /// The padded neighbours of a block (ghost cells included).
    type Nbrs: IntoIterator<Item = usize> + Copy;
    /// The cells around a run ([`Geometry::around_run`]).
    type Around: Iterator<Item = (usize, usize, bool)>;
    /// Whether the engine keeps the cells next to the runs as lists
    /// ([`super::frontier`]) instead of walking around every run: a lattice, where the
    /// walk visits the cells above and below every block of a run.
    const FRONTIER: bool;

    /// Number of real blocks.
    fn n(&self) -> usize;
    /// (nx, ny): (n, 1) for a chain.
    fn shape(&self) -> (usize, usize);
    /// Length of the padded arrays.
    fn cells(&self) -> usize;
    /// Padded index of block k (0-based, the numbering of outputs).
    fn padded(&self, k: usize) -> usize;
    /// Block number (0-based) of real padded index p.
    fn index(&self, p: usize) -> usize;
    /// The padded indices of the real blocks, in block order.
    fn blocks(&self) -> impl Iterator<Item = usize> + '_;
    /// Is padded index q a ghost cell?
    fn is_ghost(&self, q: usize) -> bool;
    /// What the ghost cell q next to real block p stands for.
    fn beyond(&self, q: usize, p: usize) -> Beyond;
    /// The neighbours of real block p (padded, ghosts included).
    fn neighbours(&self, p: usize) -> Self::Nbrs;
    /// The cells q next to the run [a, b) that are outside it (its ends along the row,
    /// and across for the lattice) as (q, p, ghost): p the run's block next to q,
    /// `ghost` whether q is a ghost cell. A cell may come more than once (next to several
    /// blocks of the run). (An iterator, not a callback: the engine's loops over it
    /// inline, which a closure called per cell did not: 25 % of a loading run.)
    fn around_run(&self, a: usize, b: usize) -> Self::Around;
    /// The real blocks p next to a cell q standing for stuck block r (q = r itself, or a seam
    /// or periodic ghost of r), each with the side of p that q is on: 0 left (q = p - 1),
    /// 1 right (q = p + 1), 2 below (the previous row), 3 above; the first `k` of the
    /// array returned as (array, k). ([`super::frontier::walk_order`].)
    fn sightings(&self, r: usize) -> ([(usize, u8); 8], usize);
    /// The stencil of the run [a, b) over stage values `su` (neighbours filled in).
    fn stencil<'a>(&self, su: &'a [f64], a: usize, b: usize) -> Self::Stencil<'a>;
    /// The coupling force on real block p with displacement `up`, `value(q)` giving the
    /// displacement of each neighbour cell q (ghosts resolved by the caller).
    fn force<M: Medium>(&self, med: &M, p: usize, up: f64, value: impl Fn(usize) -> f64) -> f64;
    /// The Hermite data of phi = k_p u - force of block p over a step, from its own
    /// (`up`) and its neighbour cells' (`nb(q)`).
    fn phi_hermite<M: Medium>(
        &self,
        med: &M,
        p: usize,
        up: Hermite,
        nb: impl Fn(usize) -> Hermite,
    ) -> Hermite;
    /// Sum of the coupling stiffnesses of block p over the squared spacings (for the
    /// step's stability bound: the fastest rate is at most sqrt((k_p + 2 this)/m)).
    fn stiffness<M: Medium>(&self, med: &M, p: usize) -> f64;
    /// Energy of the coupling springs, `value(p)` the displacement of real block p and
    /// `wall(u0)` that of a wall.
    fn coupling_energy<M: Medium>(
        &self,
        med: &M,
        value: impl Fn(usize) -> f64,
        wall: impl Fn(f64) -> f64,
    ) -> f64;
    /// The smallest lattice spacing (the step is a fraction of it).
    fn spacing(&self) -> f64;
    /// The ghosts of every side, for checkpoint fingerprints.
    fn describe(&self) -> String;

    /// The real block a padded cell stands for: itself, the far side's block for a
    /// periodic or seam ghost, None for other ghosts.
    #[inline]
    fn resolve(&self, q: usize) -> Option<usize> {
        if self.is_ghost(q) {
            self.ghost_partner(q)
        } else {
            Some(q)
        }
    }
    /// The real block a periodic ghost cell q, or a ghost between two strips of a
    /// lattice, stands for (None for other ghosts).
    fn ghost_partner(&self, q: usize) -> Option<usize>;
}

/// The real block a ghost of kind `g` stands for, seen from real block p, with `far`
/// the far side's block (used by both geometries).
#[inline]
pub(crate) fn beyond_of(g: Ghost, p: usize, far: usize) -> Beyond {
    match g {
        Ghost::Mirror => Beyond::Block(p),
        Ghost::Held(g0) => Beyond::Wall(g0),
        Ghost::Wrap => Beyond::Block(far),
    }
}
