//! The cells next to the runs of sliding blocks, kept as lists updated at each switch
//! (the lattice; docs/benchmarks.md, "The lattice against a bare stencil").
//!
//! The stages need the stage values of the stuck blocks and ghost cells next to the runs,
//! and the event search and settling test the stuck blocks there. A chain has two such
//! cells per run ([`super::geometry::Geometry::around_run`]); a lattice has the cells above
//! and below every block of a run, nearly all of them sliding inside a rupture, and
//! walking them (a load and a branch per cell, four times a step) cost more than the
//! stages themselves. A geometry with [`super::geometry::Geometry::FRONTIER`] keeps
//! instead, per cell, the number of its neighbours that are in a run, and two lists:
//!
//! - the real cells with such a neighbour that are stuck when listed;
//! - the ghost cells with such a neighbour, with what each stands for.
//!
//! Entries are removed lazily: a listed cell is live while it has a neighbour in a run
//! and (a real cell) is stuck; dead entries are dropped when they outnumber the live
//! ones. The live set is exactly the set of cells the walk around the runs would visit
//! and use, so the stage values written are the same bits. The event search and the
//! settling visit the same stuck blocks in another order; the events they find at one
//! instant are put back in the order of the walk ([`walk_order`]), so a lattice run
//! gives the same bits as with the walk (tested against it).

use super::geometry::{Beyond, Geometry};
use super::medium::Medium;
use super::Engine;
use crate::friction::Friction;

/// Low bits of a mark: the number of neighbours in a run (at most 4).
const COUNT: u8 = 0x0f;
/// A mark's bit: the cell is in one of the lists.
const LISTED: u8 = 0x80;

/// The cells next to the runs (module docs). Empty for a geometry without
/// [`Geometry::FRONTIER`].
#[derive(Debug, Clone, Default)]
pub struct Frontier {
    /// Per padded cell: neighbours in a run (low bits) and whether it is listed.
    mark: Vec<u8>,
    /// Listed real cells (live: a neighbour in a run, and stuck).
    stuck: Vec<usize>,
    /// Listed ghost cells and what they stand for, seen from their one real neighbour
    /// (live: that neighbour in a run).
    ghosts: Vec<(usize, Beyond)>,
    /// Entries that may have died since the lists were last compacted.
    dead: usize,
}

impl Frontier {
    /// The lists for a geometry of `cells` padded cells (none without `enabled`).
    pub fn new(cells: usize, enabled: bool) -> Frontier {
        Frontier {
            mark: if enabled { vec![0; cells] } else { Vec::new() },
            ..Frontier::default()
        }
    }

    /// The per-cell marks and the two lists (measurements: their memory).
    pub(crate) fn parts(&self) -> (&[u8], &[usize], &[(usize, Beyond)]) {
        (&self.mark, &self.stuck, &self.ghosts)
    }

    /// Back to no block in a run.
    pub fn clear(&mut self) {
        self.mark.fill(0);
        self.stuck.clear();
        self.ghosts.clear();
        self.dead = 0;
    }

    /// Real block p has joined the runs (its `dir` already set).
    pub fn enter<G: Geometry>(&mut self, geo: &G, dir: &[f64], p: usize) {
        if self.mark[p] & LISTED != 0 {
            // listed as stuck: it slides now
            self.dead += 1;
        }
        for q in geo.neighbours(p) {
            let m = self.mark[q] + 1;
            self.mark[q] = m;
            if m & LISTED == 0 {
                if geo.is_ghost(q) {
                    self.ghosts.push((q, geo.beyond(q, p)));
                    self.mark[q] |= LISTED;
                } else if dir[q] == 0.0 {
                    self.stuck.push(q);
                    self.mark[q] |= LISTED;
                }
            }
        }
        self.compact(dir);
    }

    /// Real block p has left the runs (its `dir` already set: 0 if it sticks).
    pub fn leave<G: Geometry>(&mut self, geo: &G, dir: &[f64], p: usize) {
        for q in geo.neighbours(p) {
            let m = self.mark[q] - 1;
            self.mark[q] = m;
            if m & COUNT == 0 {
                self.dead += 1;
            }
        }
        let m = self.mark[p];
        if m & COUNT != 0 && m & LISTED == 0 && dir[p] == 0.0 {
            self.stuck.push(p);
            self.mark[p] |= LISTED;
        }
        self.compact(dir);
    }

    /// Real block p is stuck again after being marked sliding outside the runs (a member
    /// of a local-event component, ../local_events.rs): list it again if it has a
    /// neighbour in a run and a compaction dropped it meanwhile.
    pub fn relist(&mut self, dir: &[f64], p: usize) {
        if self.mark.is_empty() {
            return;
        }
        let m = self.mark[p];
        if m & COUNT != 0 && m & LISTED == 0 && dir[p] == 0.0 {
            self.stuck.push(p);
            self.mark[p] |= LISTED;
        }
    }

    /// Drop the dead entries once they may outnumber the live ones, and put the lists
    /// back in the cells' order: entries are appended as the runs reach them, in no
    /// order over the lattice, and the step, the event search and the settling read
    /// each listed cell's arrays (and its neighbours'); in the cells' order those reads
    /// go forward through memory (issue 25: the 512 x 512 quadrant's event search). The
    /// lists' order changes no result (module docs).
    fn compact(&mut self, dir: &[f64]) {
        if self.dead <= (self.stuck.len() + self.ghosts.len()) / 2 + 64 {
            return;
        }
        let mark = &mut self.mark;
        self.stuck.retain(|&q| {
            let live = mark[q] & COUNT != 0 && dir[q] == 0.0;
            if !live {
                mark[q] &= !LISTED;
            }
            live
        });
        self.ghosts.retain(|&(q, _)| {
            let live = mark[q] & COUNT != 0;
            if !live {
                mark[q] &= !LISTED;
            }
            live
        });
        // a listed cell is in its list once (LISTED): sorting by the cell is a total
        // order
        self.stuck.sort_unstable();
        self.ghosts.sort_unstable_by_key(|&(q, _)| q);
        self.dead = 0;
    }

    /// The stuck real cells next to a run.
    #[inline]
    pub fn stuck<'a>(&'a self, dir: &'a [f64]) -> impl Iterator<Item = usize> + 'a {
        let mark = &self.mark;
        self.stuck
            .iter()
            .copied()
            .filter(move |&q| mark[q] & COUNT != 0 && dir[q] == 0.0)
    }

    /// The ghost cells next to a run, with what each stands for.
    #[inline]
    pub fn ghosts(&self) -> impl Iterator<Item = (usize, Beyond)> + '_ {
        let mark = &self.mark;
        self.ghosts
            .iter()
            .copied()
            .filter(move |&(q, _)| mark[q] & COUNT != 0)
    }

    /// The stuck real blocks that a cell next to a run stands for: the stuck cells, and
    /// the stuck far-side blocks of periodic ghosts (a block may come twice).
    #[inline]
    pub fn stuck_blocks<'a>(&'a self, dir: &'a [f64]) -> impl Iterator<Item = usize> + 'a {
        self.stuck(dir)
            .chain(self.ghosts().filter_map(move |(_, b)| match b {
                Beyond::Block(r) if dir[r] == 0.0 => Some(r),
                _ => None,
            }))
    }
}

/// The runs and the cells next to them at one time (measurements of the lattice's
/// shape, issue 25).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Shape {
    /// Runs of sliding blocks, and the blocks in them.
    pub runs: usize,
    pub in_runs: usize,
    /// Live entries of the lists: stuck real cells, and ghost cells, next to a run.
    pub stuck: usize,
    pub ghosts: usize,
    /// Entries in the lists, dead ones included.
    pub listed: usize,
}

impl<G: Geometry, F: Friction, M: Medium> Engine<G, F, M> {
    /// The runs and the cells next to them now (the lists are empty for a chain).
    pub fn shape(&self) -> Shape {
        let st = &self.st;
        let fr = &st.frontier;
        Shape {
            runs: st.runs.len(),
            in_runs: st.runs.iter().map(|&(a, b)| b - a).sum(),
            stuck: fr.stuck(&st.dir).count(),
            ghosts: fr.ghosts().count(),
            listed: fr.stuck.len() + fr.ghosts.len(),
        }
    }
}

/// Where the walk around the runs (runs in order; in each, its two ends, then below and
/// above each of its blocks: [`Geometry::around_run`]) first meets the cell standing for
/// stuck block r: (start of the run, position in its walk), or None if it does not.
pub fn walk_order<G: Geometry>(
    geo: &G,
    runs: &[(usize, usize)],
    r: usize,
) -> Option<(usize, usize)> {
    let (seen, k) = geo.sightings(r);
    let mut best: Option<(usize, usize)> = None;
    for &(p, side) in &seen[..k] {
        let Some((a, _)) = run_of(runs, p) else {
            continue;
        };
        let pos = match side {
            0 | 1 => side as usize,
            _ => side as usize + 2 * (p - a),
        };
        if best.is_none_or(|b| (a, pos) < b) {
            best = Some((a, pos));
        }
    }
    best
}

/// The run holding padded block p, if any.
#[inline]
pub fn run_of(runs: &[(usize, usize)], p: usize) -> Option<(usize, usize)> {
    let k = runs.partition_point(|r| r.0 <= p);
    (k > 0 && runs[k - 1].1 > p).then(|| runs[k - 1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::Ghost;
    use crate::chain::geometry::Grid;

    #[test]
    fn a_compaction_leaves_the_lists_in_the_cells_order() {
        // nine tenths of the blocks of a 40 x 40 lattice in strips of 9 join the runs in a
        // scrambled order (a multiplicative walk over the blocks): entries come in no
        // order, and a compaction must leave both lists sorted by cell
        let g = Grid::in_strips(
            40,
            40,
            0.1,
            0.1,
            (Ghost::Mirror, Ghost::Mirror),
            (Ghost::Mirror, Ghost::Mirror),
            9,
        );
        let mut dir = vec![0.0; g.cells()];
        let mut fr = Frontier::new(g.cells(), true);
        let blocks: Vec<usize> = g.blocks().collect();
        let n = blocks.len();
        let (mut compactions, mut k) = (0, 1usize);
        let mut checked = 0;
        for _ in 0..n * 9 / 10 {
            k = k * 7 % (n + 1); // 7 generates the units mod 1601 (prime)
            let p = blocks[k - 1];
            if dir[p] != 0.0 {
                continue;
            }
            dir[p] = 1.0;
            let dead = fr.dead;
            fr.enter(&g, &dir, p);
            // (only a compaction lowers the count of dead entries)
            if fr.dead < dead {
                compactions += 1;
                checked = checked.max(fr.stuck.len().min(fr.ghosts.len()));
                assert!(fr.stuck.is_sorted(), "stuck list out of order");
                assert!(
                    fr.ghosts.iter().map(|e| e.0).is_sorted(),
                    "ghost list out of order"
                );
            }
        }
        assert!(
            compactions >= 1 && checked >= 20,
            "{compactions} compactions, {checked}"
        );
        // and the lists still hold exactly the live cells
        let mut live: Vec<usize> = fr.stuck(&dir).collect();
        live.sort_unstable();
        let mut want: Vec<usize> = blocks
            .iter()
            .copied()
            .filter(|&q| {
                dir[q] == 0.0
                    && g.neighbours(q)
                        .iter()
                        .any(|&r| !g.is_ghost(r) && dir[r] != 0.0)
            })
            .collect();
        want.sort_unstable();
        assert_eq!(live, want);
    }
}
