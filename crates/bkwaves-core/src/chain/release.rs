//! The scratch's memory given back where no block slides (issue 25).
//!
//! The engine's arrays over the cells are of two kinds. The state (u, u_t, t_ref, mode,
//! threshold at onset: ../state.rs) persists. The scratch of the step does not: RK4's
//! stage values, sums and books (integrator/rk4.rs), the step's start values u0, u_t0
//! and its end accelerations are written for a cell before they are read in every step
//! (the runs' own cells in the step's first pass, the cells next to the runs by
//! `fill_neighbours`, the blocks taken out of the runs through `State::ext`), and the
//! start accelerations are read only for blocks in a run (recomputed for every run when
//! a block joins one: `a_valid`). So between two steps the scratch of a cell that is
//! neither in a run nor next to one is dead: its contents are never read again before
//! being written.
//!
//! An array's page stays resident once written, so a rupture that sweeps a large lattice
//! leaves every scratch page it crossed resident (13 arrays, 104 bytes per block), though
//! only the sliding ring behind the front needs them. Every [`RELEASE_EVERY`] steps (and
//! when the engine falls quiet) the pages of the scratch that hold only dead cells are
//! given back to the system ([`CellVec::release`]: `madvise(MADV_DONTNEED)` on Linux,
//! nothing elsewhere); they read back as zeros and come back, zeroed, when written.
//! Results are the same bits with or without it (tested, also with the released cells
//! filled with NaN instead).
//!
//! Bookkeeping, so that a pass costs the runs plus the memory that died since the last
//! one: the cells are cut into granules of [`GRANULE`] cells (a page of f64), and a bit
//! per granule says whether it may hold written scratch. A block joining a run marks its
//! granule and its neighbours' ([`State::add_to_runs`]), as does a block taken into a
//! local-event component; a pass marks the granules the runs and their neighbours
//! overlap, and gives back the marked granules wholly outside them (with the partial
//! pages at their ends, up to the live cells), clearing their marks.
//!
//! The checkpoint writes the accelerations canonically (at the cells of the runs when
//! valid, 0 elsewhere: ../checkpoint.rs), so that a restored run's checkpoints equal the
//! uninterrupted one's whatever was given back when.

use super::cells::{resident_bytes_of, CellVec};
use super::geometry::Geometry;
use super::integrator::Stepper;
use super::medium::Medium;
use super::state::State;
use super::Engine;
use crate::friction::Friction;

/// Cells per granule of the bookkeeping (4096 bytes of f64: a page).
pub(crate) const GRANULE: usize = 512;

/// Steps between two passes.
pub(crate) const RELEASE_EVERY: u32 = 32;

/// Engines with at least this many cells give their dead scratch back by default (1 MB
/// per array; smaller ones keep it: [`Engine::set_release`]).
pub(crate) const RELEASE_FROM: usize = 1 << 17;

/// Which granules may hold written scratch (empty: the release is off).
#[derive(Debug, Clone, Default)]
pub struct Touched {
    bits: Vec<u64>,
    /// Some bit may be set.
    any: bool,
}

impl Touched {
    /// For `cells` cells, nothing written.
    pub(crate) fn new(cells: usize) -> Touched {
        Touched {
            bits: vec![0; cells.div_ceil(GRANULE).div_ceil(64)],
            any: false,
        }
    }

    /// Is the bookkeeping on?
    #[inline(always)]
    pub(crate) fn on(&self) -> bool {
        !self.bits.is_empty()
    }

    /// Cell p's granule may be written.
    #[inline(always)]
    pub(crate) fn mark(&mut self, p: usize) {
        if let Some(w) = self.bits.get_mut(p / GRANULE / 64) {
            *w |= 1 << (p / GRANULE % 64);
            self.any = true;
        }
    }

    /// Every granule overlapping cells [lo, hi) may be written.
    fn mark_range(&mut self, lo: usize, hi: usize) {
        if lo >= hi {
            return;
        }
        for g in lo / GRANULE..=(hi - 1) / GRANULE {
            if let Some(w) = self.bits.get_mut(g / 64) {
                *w |= 1 << (g % 64);
                self.any = true;
            }
        }
    }

    /// Every granule may be written (after the arrays were read back from a checkpoint).
    pub(crate) fn mark_all(&mut self) {
        self.bits.fill(u64::MAX);
        self.any = self.on();
    }

    /// The maximal stretches [g0, g1) of marked granules among g in [lo, hi), their
    /// marks cleared.
    fn take(&mut self, lo: usize, hi: usize, out: &mut Vec<(usize, usize)>) {
        let mut g = lo;
        while g < hi {
            let (w, b) = (g / 64, g % 64);
            // the marks of granules g.. in this word
            let bits = self.bits[w] >> b;
            if bits == 0 {
                g = (w + 1) * 64;
                continue;
            }
            g += bits.trailing_zeros() as usize;
            if g >= hi {
                break;
            }
            let g0 = g;
            while g < hi && self.bits[g / 64] & (1 << (g % 64)) != 0 {
                self.bits[g / 64] &= !(1 << (g % 64));
                g += 1;
            }
            out.push((g0, g));
        }
    }
}

/// The release's settings, working lists and counters (not part of the state).
#[derive(Debug, Clone, Default)]
pub(crate) struct Release {
    /// Steps until the next pass.
    countdown: u32,
    /// Fill the dead cells with NaN instead of giving them back (tests: a dead cell
    /// read would show in the results).
    pub poison: bool,
    /// Bytes given back in all (a page given back twice counts twice) and passes made.
    pub bytes: u64,
    pub passes: u64,
    /// The live intervals of a pass, and the stretches to give back.
    live: Vec<(usize, usize)>,
    dead: Vec<(usize, usize)>,
}

/// What the release has done (not part of the state).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReleaseStats {
    /// Whether dead scratch is given back ([`Engine::set_release`]).
    pub on: bool,
    /// Passes made.
    pub passes: u64,
    /// Bytes given back (a page given back, written again and given back again counts
    /// each time).
    pub bytes: u64,
}

impl<G: Geometry, F: Friction, M: Medium> Engine<G, F, M> {
    /// Give the dead scratch's memory back to the system (module docs of
    /// `chain/release.rs`; on by default for engines of 2^17 cells or more). Changes no
    /// result.
    pub fn set_release(&mut self, on: bool) {
        if on == self.st.touched.on() {
            return;
        }
        if on {
            self.st.touched = Touched::new(self.st.geo.cells());
            // whatever was written before
            self.st.touched.mark_all();
        } else {
            self.st.touched = Touched::default();
        }
    }

    /// Fill the dead scratch with NaN instead of giving it back (tests: a dead cell read
    /// would show in the results).
    #[cfg(test)]
    pub(crate) fn set_release_poison(&mut self, on: bool) {
        self.release.poison = on;
    }

    /// What the release has done.
    pub fn release_stats(&self) -> ReleaseStats {
        ReleaseStats {
            on: self.st.touched.on(),
            passes: self.release.passes,
            bytes: self.release.bytes,
        }
    }

    /// The scratch arrays over the cells, by name (tests and measurements).
    pub fn scratch_arrays(&self) -> Vec<(&'static str, &CellVec)> {
        let mut v = vec![
            ("u0", &self.u0),
            ("w0", &self.w0),
            ("a_start", &self.a_start),
            ("a_end", &self.a_end),
        ];
        if let Stepper::Rk4(rk) = &self.rk {
            v.extend(rk.buffers());
        }
        v
    }

    /// The engine's arrays by name, with their allocated and resident bytes (resident:
    /// Linux's `mincore` over the pages holding them, None elsewhere; a page shared with
    /// a neighbouring allocation counts for both): the state, the scratch, the books per
    /// cell and the catalog (measurements of the memory per block, issue 25).
    pub fn memory_arrays(&self) -> Vec<(&'static str, usize, Option<usize>)> {
        fn of<T>(name: &'static str, v: &[T], cap: usize) -> (&'static str, usize, Option<usize>) {
            let bytes = cap * std::mem::size_of::<T>();
            (name, bytes, resident_bytes_of(v.as_ptr().cast(), bytes))
        }
        let cell = |name: &'static str, a: &CellVec| {
            let bytes = a.len() * 8;
            (name, bytes, resident_bytes_of(a.as_ptr().cast(), bytes))
        };
        let st = &self.st;
        let mut out = vec![
            cell("u", &st.u),
            cell("u_t", &st.w),
            cell("t_ref", &st.tref),
            cell("mode", &st.dir),
            cell("threshold at onset", &st.onset),
        ];
        for (name, a) in self.scratch_arrays() {
            out.push(cell(name, a));
        }
        let (version, heap_cap, entry) = self.queue.parts();
        out.push(of("queue: version", version, version.len()));
        out.push(("queue: heap", heap_cap * entry, None));
        let (mark, stuck, ghosts) = st.frontier.parts();
        out.push(of("frontier: counts", mark, mark.len()));
        out.push(of("frontier: stuck list", stuck, stuck.len()));
        out.push(of("frontier: ghost list", ghosts, ghosts.len()));
        let mem = self.local.member_map();
        out.push(of("local events: member map", mem, mem.len()));
        let near = self.local.near_map();
        out.push(of("local events: near marks", near, near.len()));
        out.push(("local events: buffers", self.local.buffer_bytes(), None));
        out.push(("runs", st.runs.capacity() * 16, None));
        let cat = &self.catalog;
        out.push(of("catalog: slips", &cat.slips, cat.slips.capacity()));
        out.push(of("catalog: events", &cat.events, cat.events.capacity()));
        out.push(("catalog: bookkeeping", cat.bookkeeping_bytes(), None));
        out
    }

    /// At the start of a step: a pass every [`RELEASE_EVERY`] steps.
    #[inline]
    pub(super) fn release_tick(&mut self) {
        if !self.st.touched.on() {
            return;
        }
        if self.release.countdown == 0 {
            self.release.countdown = RELEASE_EVERY;
            self.release_dead();
        }
        self.release.countdown -= 1;
    }

    /// When nothing slides: a pass if anything was written since the last.
    #[inline]
    pub(super) fn release_quiet(&mut self) {
        if self.st.touched.any {
            self.release_dead();
        }
    }

    /// One pass (between steps): give back the marked granules outside the runs and
    /// the cells next to them.
    pub(crate) fn release_dead(&mut self) {
        let cells = self.st.geo.cells();
        let mut live = std::mem::take(&mut self.release.live);
        let mut dead = std::mem::take(&mut self.release.dead);
        live.clear();
        // the runs and the cells next to them: the same offsets for every block of a run,
        // so each of the five stretches pushed (the runs, then the runs shifted to each
        // neighbour) is in order already, and the stable sort merges them (it finds
        // ordered stretches) instead of sorting the whole anew (issue 25: at 512 x 512
        // the unstable sort was 0.4 % of the rupture's time)
        let runs = &self.st.runs;
        live.extend_from_slice(runs);
        if let Some(&(a0, _)) = runs.first() {
            for q0 in self.st.geo.neighbours(a0) {
                let d = q0.wrapping_sub(a0);
                for &(a, b) in runs {
                    // (both geometries' neighbours are p plus fixed offsets: -/+ 1 and
                    // -/+ S, the one row stride of all strips)
                    debug_assert!(
                        (self.st.geo.neighbours(a).into_iter()).any(|q| q == a.wrapping_add(d))
                    );
                    let q = a.wrapping_add(d);
                    live.push((q, q + (b - a)));
                }
            }
        }
        live.sort();
        let touched = &mut self.st.touched;
        for &(lo, hi) in &live {
            touched.mark_range(lo, hi.min(cells));
        }
        // the gaps between the live intervals, and their marked granules
        dead.clear();
        let mut covered = 0usize;
        for &(next, end) in live.iter().chain(std::iter::once(&(cells, cells))) {
            let (lo, hi) = (covered, next);
            covered = covered.max(end);
            if hi <= lo {
                continue;
            }
            // the granules wholly inside [lo, hi) (the last one may be short)
            let g_lo = lo.div_ceil(GRANULE);
            let g_hi = if hi == cells {
                cells.div_ceil(GRANULE)
            } else {
                hi / GRANULE
            };
            let k = dead.len();
            touched.take(g_lo, g_hi, &mut dead);
            // as cells, with the partial pages at the ends up to the gap's ends
            for d in &mut dead[k..] {
                *d = (
                    lo.max(d.0.saturating_sub(1) * GRANULE),
                    hi.min((d.1 + 1) * GRANULE),
                );
            }
        }
        touched.any = !live.is_empty();
        let mut bytes = 0usize;
        let poison = self.release.poison;
        let mut give = |a: &mut CellVec| {
            for &(lo, hi) in &dead {
                if poison {
                    a[lo..hi].fill(f64::NAN);
                } else {
                    bytes += a.release(lo, hi);
                }
            }
        };
        give(&mut self.u0);
        give(&mut self.w0);
        give(&mut self.a_start);
        give(&mut self.a_end);
        if let Stepper::Rk4(rk) = &mut self.rk {
            for a in rk.buffers_mut() {
                give(a);
            }
        }
        self.release.bytes += bytes as u64;
        self.release.passes += 1;
        self.release.live = live;
        self.release.dead = dead;
    }
}

impl<G: Geometry> State<G> {
    /// Mark block p's granule and its neighbours' as written (the release's
    /// bookkeeping: module docs).
    #[inline(always)]
    pub(crate) fn touch(&mut self, p: usize) {
        if self.touched.on() {
            self.touched.mark(p);
            for q in self.geo.neighbours(p) {
                self.touched.mark(q);
            }
        }
    }
}
