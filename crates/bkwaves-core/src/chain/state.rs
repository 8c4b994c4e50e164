//! The state of the blocks: positions, velocities and the stick/slide mode of each block,
//! plus the runs of consecutive sliding blocks the integrator works on.
//!
//! Arrays are padded with ghost cells laid out by the geometry ([`Geometry`]): for the
//! chain block i (0-based) lives at index p = i + 1, the ghosts at 0 and n + 1; for the
//! lattice, rows of nx + 2 cells. A stuck block is never stepped: its `u` holds the value
//! at time `tref` and it drifts exactly, u(t) = u + v (t - tref), u_t = v.

use super::cells::CellVec;
use super::frontier::Frontier;
pub use super::geometry::Beyond;
use super::geometry::{Geometry, Line};
use super::release::Touched;
use crate::boundary::Ghost;

/// Block state (padded indices, see the module docs).
#[derive(Debug, Clone)]
pub struct State<G: Geometry = Line> {
    /// Who neighbours whom.
    pub geo: G,
    /// Number of blocks.
    pub n: usize,
    /// Loading rate v.
    pub v: f64,
    /// Displacement u (sliding: at the current time; stuck: at `tref`).
    pub u: CellVec,
    /// Velocity u_t (stuck: v).
    pub w: CellVec,
    /// Time at which a stuck block's `u` is valid.
    pub tref: CellVec,
    /// Mode: 0 stuck, +1 sliding forward (u_t < v), -1 sliding backward (u_t > v).
    pub dir: CellVec,
    /// The threshold in R of each sliding block: its static threshold, or the phi at its
    /// slip onset where that was a hair lower ([`crate::friction::Friction::onset_threshold`]).
    pub onset: CellVec,
    /// Maximal runs [a, b) of consecutive sliding blocks (padded indices), sorted.
    pub runs: Vec<(usize, usize)>,
    /// Number of sliding blocks.
    pub n_active: usize,
    /// Sliding blocks taken out of the runs for one step (they are integrated with their
    /// own short steps, ../onset.rs): (block, u at the step's midpoint, u at its end),
    /// read by the runs' stages as their neighbours' values. Empty between steps.
    pub ext: Vec<(usize, f64, f64)>,
    /// The end time of the step the `ext` values belong to.
    pub ext_t1: f64,
    /// The cells next to the runs (a geometry with [`Geometry::FRONTIER`]; ../frontier.rs),
    /// kept by [`State::add_to_runs`] and [`State::remove_from_runs`].
    pub frontier: Frontier,
    /// Which granules of cells may hold written scratch (../release.rs; empty: off).
    pub touched: Touched,
}

impl State<Line> {
    /// A chain: all blocks stuck at time 0 with displacements `u0` (0-based, length n).
    pub fn new(u0: &[f64], v: f64, dx: f64, left: Ghost, right: Ghost) -> State<Line> {
        State::with_geometry(Line::new(u0.len(), dx, left, right), u0, v)
    }
}

impl<G: Geometry> State<G> {
    /// All blocks stuck at time 0 with displacements `u0` (in block order, one per block
    /// of the geometry).
    pub fn with_geometry(geo: G, u0: &[f64], v: f64) -> State<G> {
        let len = geo.cells();
        let mut u = CellVec::new(len, 0.0);
        for (k, &x) in u0.iter().enumerate() {
            u[geo.padded(k)] = x;
        }
        State {
            n: geo.n(),
            v,
            u,
            w: CellVec::new(len, v),
            tref: CellVec::new(len, 0.0),
            dir: CellVec::new(len, 0.0),
            onset: CellVec::new(len, 0.0),
            runs: Vec::new(),
            n_active: 0,
            ext: Vec::new(),
            ext_t1: 0.0,
            frontier: Frontier::new(len, G::FRONTIER),
            touched: Touched::default(),
            geo,
        }
    }

    /// Is real block p (padded) sliding?
    #[inline]
    pub fn sliding(&self, p: usize) -> bool {
        self.dir[p] != 0.0
    }

    /// The real block (padded index) that padded index q stands for, if any:
    /// itself for a real block, the far side's block for a periodic ghost, None for
    /// other ghosts.
    #[inline]
    pub fn resolve(&self, q: usize) -> Option<usize> {
        self.geo.resolve(q)
    }

    /// What the ghost at padded index q next to real block p stands for.
    #[inline]
    pub fn beyond(&self, q: usize, p: usize) -> Beyond {
        self.geo.beyond(q, p)
    }

    /// Exact displacement of stuck block p at time t.
    #[inline]
    pub fn stuck_u(&self, p: usize, t: f64) -> f64 {
        self.u[p] + self.v * (t - self.tref[p])
    }

    /// Displacement of real block p at time t, the state being current at t.
    #[inline]
    pub fn value(&self, p: usize, t: f64) -> f64 {
        if self.sliding(p) {
            self.u[p]
        } else {
            self.stuck_u(p, t)
        }
    }

    /// Displacement of the neighbour at padded index q of real block p, at time t.
    #[inline]
    pub fn neighbour(&self, q: usize, p: usize, t: f64) -> f64 {
        if self.geo.is_ghost(q) {
            match self.beyond(q, p) {
                Beyond::Block(r) => self.value(r, t),
                Beyond::Wall(g0) => g0 + self.v * t,
            }
        } else {
            self.value(q, t)
        }
    }

    /// Does real block p have a sliding neighbour?
    pub fn has_sliding_neighbour(&self, p: usize) -> bool {
        self.geo
            .neighbours(p)
            .into_iter()
            .any(|q| self.resolve(q).is_some_and(|r| self.sliding(r)))
    }

    /// Real neighbours of real block p (resolved through a periodic ghost).
    pub fn real_neighbours(&self, p: usize) -> impl Iterator<Item = usize> + '_ {
        self.geo
            .neighbours(p)
            .into_iter()
            .filter_map(|q| self.resolve(q))
    }

    /// The runs again from the modes (every sliding block in them), as after a
    /// checkpoint's state is read.
    pub fn rebuild_runs(&mut self) {
        self.runs.clear();
        self.n_active = 0;
        self.frontier.clear();
        let blocks: Vec<usize> = self.geo.blocks().collect();
        for p in blocks {
            if self.sliding(p) {
                self.add_to_runs(p);
            }
        }
    }

    /// Insert sliding block p into the runs (merging with neighbours; its `dir` set).
    pub fn add_to_runs(&mut self, p: usize) {
        let k = self.runs.partition_point(|r| r.0 <= p);
        let joins_left = k > 0 && self.runs[k - 1].1 == p;
        let joins_right = k < self.runs.len() && self.runs[k].0 == p + 1;
        match (joins_left, joins_right) {
            (true, true) => {
                self.runs[k - 1].1 = self.runs[k].1;
                self.runs.remove(k);
            }
            (true, false) => self.runs[k - 1].1 = p + 1,
            (false, true) => self.runs[k].0 = p,
            (false, false) => self.runs.insert(k, (p, p + 1)),
        }
        self.n_active += 1;
        if G::FRONTIER {
            self.frontier.enter(&self.geo, &self.dir, p);
        }
        self.touch(p);
    }

    /// Remove block p (which must be in a run) from the runs (splitting its run; its
    /// `dir` set: 0 if it sticks).
    pub fn remove_from_runs(&mut self, p: usize) {
        let k = self.runs.partition_point(|r| r.0 <= p) - 1;
        let (a, b) = self.runs[k];
        debug_assert!(a <= p && p < b);
        match (p == a, p + 1 == b) {
            (true, true) => {
                self.runs.remove(k);
            }
            (true, false) => self.runs[k].0 = p + 1,
            (false, true) => self.runs[k].1 = p,
            (false, false) => {
                self.runs[k].1 = p;
                self.runs.insert(k + 1, (p + 1, b));
            }
        }
        self.n_active -= 1;
        if G::FRONTIER {
            self.frontier.leave(&self.geo, &self.dir, p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_merge_and_split() {
        let mut s = State::new(&[0.0; 8], 0.0, 0.1, Ghost::Mirror, Ghost::Mirror);
        for p in [3, 5, 4, 1, 8] {
            s.dir[p] = 1.0;
            s.add_to_runs(p);
        }
        assert_eq!(s.runs, vec![(1, 2), (3, 6), (8, 9)]);
        s.remove_from_runs(4);
        assert_eq!(s.runs, vec![(1, 2), (3, 4), (5, 6), (8, 9)]);
        s.remove_from_runs(1);
        s.remove_from_runs(8);
        assert_eq!(s.runs, vec![(3, 4), (5, 6)]);
        assert_eq!(s.n_active, 2);
    }

    #[test]
    fn ghosts_resolve() {
        let s = State::new(&[0.1, 0.2, 0.3], 0.5, 0.1, Ghost::Held(1.0), Ghost::Wrap);
        assert_eq!(s.resolve(0), None);
        assert_eq!(s.resolve(4), Some(1));
        // held ghost drifts with the ground: 1 + v t
        assert!((s.neighbour(0, 1, 2.0) - 2.0).abs() < 1e-15);
        // phi of the middle block at t = 0: 0.2 - (0.1 + 0.3 - 0.4)/dx^2
        let blk = crate::chain::medium::Blocks {
            fr: crate::friction::Coulomb::new(0.0, 0.0).unwrap(),
            med: crate::chain::medium::Uniform,
        };
        assert!((blk.phi(&s, 2, 0.0) - 0.2).abs() < 1e-12);
    }
}
