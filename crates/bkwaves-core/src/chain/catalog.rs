//! The event catalog and the slip-front trajectories.
//!
//! An event runs from the first slip after a quiet time (no block sliding) to the last
//! re-stick. Each slip interval of a block (slip to stick) is one [`SlipRecord`]; the
//! sequence of their start times is the slip-front trajectory, their end times the
//! healing front. Blocks are numbered 0..n in outputs. Each slip and each event carries
//! its cause ([`Cause`]: a block at its threshold, the initial state, or an event source
//! such as a trigger or the noise); an event's is that of its first slip.

use super::sources::Cause;
use std::collections::BTreeMap;

/// One slip interval of one block.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SlipRecord {
    /// Event it belongs to.
    pub event: usize,
    /// Block (0-based).
    pub block: usize,
    /// +1 forward, -1 backward.
    pub dir: i8,
    /// Slip time.
    pub t_start: f64,
    /// Stick time (NaN while still sliding).
    pub t_end: f64,
    /// u at the slip.
    pub u_start: f64,
    /// u at the stick (NaN while still sliding).
    pub u_end: f64,
    /// Distance slid over the ground, in units of u: integral of (v - u_t) dt
    /// = v (t_end - t_start) - (u_end - u_start); negative for backward slip.
    pub slip: f64,
    /// What started it.
    pub kind: Cause,
}

/// One event (first slip to last re-stick).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EventRecord {
    /// Event number (0, 1, ...).
    pub id: usize,
    /// Time of the first slip.
    pub t_start: f64,
    /// Time of the last re-stick (NaN while still running).
    pub t_end: f64,
    /// Block that slipped first.
    pub nucleation: usize,
    /// Lowest block index that slipped.
    pub first_block: usize,
    /// Highest block index that slipped.
    pub last_block: usize,
    /// Number of distinct blocks that slipped.
    pub n_blocks: usize,
    /// Number of slip intervals (a block can slip more than once).
    pub n_slips: usize,
    /// Total slip of all blocks (the moment in chain units: sum of slips, in units of u).
    pub moment: f64,
    /// Mean over the slipped blocks of u at their first slip minus u at the end.
    pub stress_drop: f64,
    /// What started it (the cause of its first slip).
    pub kind: Cause,
}

/// Builder of the catalog while a run goes on.
///
/// Its bookkeeping per block is kept near what a running event needs (issue 25: a
/// rupture across a large lattice): a bit per block for "slipped in the running event",
/// the open slip of each sliding block only, and the first slip of each block of the
/// running event (its u there is that slip's `u_start`). What a checkpoint writes is the
/// same bytes as a dense layout's ([`Marks`]).
#[derive(Debug, Clone, Default)]
pub struct Catalog {
    /// Finished and running events.
    pub events: Vec<EventRecord>,
    /// All slip intervals.
    pub slips: Vec<SlipRecord>,
    /// Number of blocks.
    n: usize,
    /// The open slip interval (index in `slips`) of each block sliding now.
    open_slip: BTreeMap<usize, usize>,
    /// Bit i: block i has slipped in the running event (none between events).
    in_event: Vec<u64>,
    /// The first slip (index in `slips`) of each block of the running event, in the
    /// order of the blocks' first slips.
    first_slips: Vec<usize>,
    pub(crate) open: bool,
}

const NONE: usize = usize::MAX;

impl Catalog {
    /// A catalog for n blocks.
    pub fn new(n: usize) -> Self {
        Catalog {
            n,
            in_event: vec![0; n.div_ceil(64)],
            ..Default::default()
        }
    }

    /// Is an event running?
    pub fn event_open(&self) -> bool {
        self.open
    }

    /// Number of finished events.
    pub fn finished(&self) -> usize {
        self.events.len() - usize::from(self.open)
    }

    /// Block `i` (0-based) slipped at time t with displacement u, started by `kind`.
    pub fn slip(&mut self, i: usize, t: f64, u: f64, dir: i8, kind: Cause) {
        if !self.open {
            self.open = true;
            self.events.push(EventRecord {
                id: self.events.len(),
                t_start: t,
                t_end: f64::NAN,
                nucleation: i,
                first_block: i,
                last_block: i,
                n_blocks: 0,
                n_slips: 0,
                moment: 0.0,
                stress_drop: f64::NAN,
                kind,
            });
        }
        let id = self.events.len() - 1;
        let e = &mut self.events[id];
        e.n_slips += 1;
        let (w, bit) = (i / 64, 1u64 << (i % 64));
        if self.in_event[w] & bit == 0 {
            self.in_event[w] |= bit;
            self.first_slips.push(self.slips.len());
            e.n_blocks += 1;
            e.first_block = e.first_block.min(i);
            e.last_block = e.last_block.max(i);
        }
        self.open_slip.insert(i, self.slips.len());
        self.slips.push(SlipRecord {
            event: id,
            block: i,
            dir,
            t_start: t,
            t_end: f64::NAN,
            u_start: u,
            u_end: f64::NAN,
            slip: f64::NAN,
            kind,
        });
    }

    /// Block `i` stuck at time t with displacement u (loading rate v).
    pub fn stick(&mut self, i: usize, t: f64, u: f64, v: f64) {
        let Some(k) = self.open_slip.remove(&i) else {
            return;
        };
        let r = &mut self.slips[k];
        r.t_end = t;
        r.u_end = u;
        r.slip = v * (t - r.t_start) - (u - r.u_start);
        let ev = r.event;
        self.events[ev].moment += r.slip;
    }

    /// Nothing slides any more at time t: close the running event. `u_now(i)` gives the
    /// displacement of block i at t.
    pub fn quiet(&mut self, t: f64, u_now: impl Fn(usize) -> f64) {
        if !self.open {
            return;
        }
        self.open = false;
        let id = self.events.len() - 1;
        // the blocks in the order of their first slips, as u at the first slip minus u now
        let slips = &self.slips;
        let drop: f64 = self
            .first_slips
            .iter()
            .map(|&k| slips[k].u_start - u_now(slips[k].block))
            .sum();
        let e = &mut self.events[id];
        e.t_end = t;
        e.stress_drop = drop / e.n_blocks.max(1) as f64;
        for &k in &self.first_slips {
            let i = slips[k].block;
            self.in_event[i / 64] &= !(1u64 << (i % 64));
        }
        self.first_slips.clear();
    }

    /// The bookkeeping per block as a checkpoint writes it (the dense layout: the open
    /// slip and the last event of every block, u at its first slip in the running event,
    /// the blocks of the running event).
    pub(crate) fn marks(&self) -> Marks {
        let mut m = Marks {
            open_slip: vec![NONE; self.n],
            last_event: vec![NONE; self.n],
            u_first: vec![0.0; self.n],
            blocks_now: Vec::with_capacity(self.first_slips.len()),
        };
        for (&i, &k) in &self.open_slip {
            m.open_slip[i] = k;
        }
        for &k in &self.first_slips {
            let r = &self.slips[k];
            m.last_event[r.block] = r.event;
            m.u_first[r.block] = r.u_start;
            m.blocks_now.push(r.block);
        }
        m
    }

    /// Take the bookkeeping per block from a checkpoint's dense layout (after the events
    /// and slips were read). A mark of an event before the running one (which a dense
    /// layout may hold) means the same as none. Err names what is inconsistent.
    pub(crate) fn set_marks(&mut self, m: Marks) -> std::result::Result<(), &'static str> {
        let n = self.n;
        if m.open_slip.len() != n || m.last_event.len() != n || m.u_first.len() != n {
            return Err("catalog arrays of n values");
        }
        let mut open_slip = BTreeMap::new();
        for (i, &k) in m.open_slip.iter().enumerate() {
            if k != NONE {
                if self
                    .slips
                    .get(k)
                    .is_none_or(|r| r.block != i || !r.t_end.is_nan())
                {
                    return Err("open slips of the catalog's slips");
                }
                open_slip.insert(i, k);
            }
        }
        // the first slip of each block in the running event: its slips are the last ones
        let mut in_event = vec![0u64; n.div_ceil(64)];
        let mut first_slips = Vec::with_capacity(m.blocks_now.len());
        if self.open {
            let id = self.events.len() - 1;
            let from = self.slips.partition_point(|r| r.event < id);
            let mut first = BTreeMap::new();
            for (k, r) in self.slips.iter().enumerate().skip(from) {
                first.entry(r.block).or_insert(k);
            }
            for &i in &m.blocks_now {
                let k = match first.get(&i) {
                    Some(&k) if m.last_event[i] == id && m.u_first[i] == self.slips[k].u_start => k,
                    _ => return Err("blocks of the running event with their first slips"),
                };
                if in_event[i / 64] & (1u64 << (i % 64)) != 0 {
                    return Err("blocks of the running event listed once");
                }
                in_event[i / 64] |= 1u64 << (i % 64);
                first_slips.push(k);
            }
            if first_slips.len() != first.len() || first.len() != self.events[id].n_blocks {
                return Err("blocks of the running event with their first slips");
            }
        } else if !m.blocks_now.is_empty() {
            return Err("no blocks of a running event when none runs");
        }
        self.open_slip = open_slip;
        self.in_event = in_event;
        self.first_slips = first_slips;
        Ok(())
    }

    /// Bytes of the bookkeeping per block besides the records (measurements): the bits,
    /// the open slips (an estimate per entry of the map) and the running event's list.
    pub fn bookkeeping_bytes(&self) -> usize {
        8 * self.in_event.len() + 48 * self.open_slip.len() + 8 * self.first_slips.capacity()
    }
}

/// The catalog's bookkeeping per block in a checkpoint's dense layout
/// ([`Catalog::marks`]).
#[derive(Debug, Clone, Default)]
pub(crate) struct Marks {
    pub open_slip: Vec<usize>,
    pub last_event: Vec<usize>,
    pub u_first: Vec<f64>,
    pub blocks_now: Vec<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_event_collects_its_slips() {
        let mut c = Catalog::new(4);
        c.slip(2, 1.0, 0.5, 1, Cause::Threshold);
        c.slip(3, 1.5, 0.5, 1, Cause::Initial);
        c.stick(2, 2.0, -0.1, 0.0);
        c.slip(2, 2.5, -0.1, 1, Cause::Source(0));
        c.stick(2, 3.0, -0.2, 0.0);
        c.stick(3, 3.5, -0.3, 0.0);
        assert!(c.event_open());
        c.quiet(3.5, |i| if i == 2 { -0.2 } else { -0.3 });
        assert_eq!(c.finished(), 1);
        let e = c.events[0];
        assert_eq!((e.nucleation, e.first_block, e.last_block), (2, 2, 3));
        assert_eq!((e.n_blocks, e.n_slips), (2, 3));
        assert!((e.moment - (0.6 + 0.1 + 0.8)).abs() < 1e-15);
        assert!((e.stress_drop - 0.75).abs() < 1e-15);
        assert_eq!(c.slips.len(), 3);
        assert_eq!(e.kind, Cause::Threshold);
        assert_eq!(c.slips[2].kind.name(), "trigger");
    }

    #[test]
    fn the_bookkeeping_goes_through_its_dense_layout_and_back() {
        // two events, the second running with one block sliding: marks() is the dense
        // layout the catalog wrote before (an older event's mark means none), set_marks()
        // takes it back, and the two catalogs go on to the same records
        let mut c = Catalog::new(130);
        c.slip(3, 1.0, 0.5, 1, Cause::Threshold);
        c.stick(3, 2.0, 0.1, 0.0);
        c.quiet(2.0, |_| 0.1);
        c.slip(70, 3.0, 0.7, 1, Cause::Threshold);
        c.slip(129, 3.5, 0.9, -1, Cause::Threshold);
        c.stick(70, 4.0, 0.2, 0.0);
        c.slip(70, 4.5, 0.2, 1, Cause::Threshold);
        c.stick(129, 5.0, 0.3, 0.0);
        let m = c.marks();
        assert_eq!(m.open_slip[70], 3);
        assert_eq!(m.open_slip.iter().filter(|&&k| k != NONE).count(), 1);
        assert_eq!(
            (m.last_event[70], m.last_event[129], m.last_event[3]),
            (1, 1, NONE)
        );
        assert_eq!((m.u_first[70], m.u_first[129]), (0.7, 0.9));
        assert_eq!(m.blocks_now, vec![70, 129]);
        let mut d = Catalog::new(130);
        d.events = c.events.clone();
        d.slips = c.slips.clone();
        d.open = c.open;
        let base = d.clone();
        let mut old = m.clone();
        old.last_event[3] = 0; // a dense layout kept the finished event's mark
        d.set_marks(old).unwrap();
        for x in [&mut c, &mut d] {
            x.stick(70, 6.0, 0.1, 0.0);
            x.slip(3, 6.5, 0.4, 1, Cause::Threshold);
            x.stick(3, 7.0, 0.0, 0.0);
            x.quiet(7.0, |i| {
                [0.1, 0.0, 0.3][(i > 3) as usize + (i > 70) as usize]
            });
        }
        assert_eq!(c.events, d.events);
        assert_eq!(c.slips, d.slips);
        let e = c.events[1];
        assert_eq!((e.n_blocks, e.n_slips), (3, 4));
        // (0.7 - 0.1) + (0.9 - 0.3) + (0.4 - 0.0), in the order of the first slips
        assert_eq!(
            e.stress_drop,
            ((0.7 - 0.1) + (0.9 - 0.3) + (0.4 - 0.0)) / 3.0
        );
        // inconsistent layouts are refused
        base.clone().set_marks(m.clone()).unwrap();
        let mut bad = m.clone();
        bad.u_first[70] = 0.0;
        assert!(base.clone().set_marks(bad).is_err());
        let mut bad = m.clone();
        bad.open_slip[71] = 3;
        assert!(base.clone().set_marks(bad).is_err());
        let mut bad = m.clone();
        bad.blocks_now.push(70);
        assert!(base.clone().set_marks(bad).is_err());
        let mut bad = m;
        bad.blocks_now.pop();
        assert!(base.clone().set_marks(bad).is_err());
    }
}
