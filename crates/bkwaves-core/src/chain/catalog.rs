//! The event catalog and the slip-front trajectories.
//!
//! An event runs from the first slip after a quiet time (no block sliding) to the last
//! re-stick. Each slip interval of a block (slip to stick) is one [`SlipRecord`]; the
//! sequence of their start times is the slip-front trajectory, their end times the
//! healing front. Blocks are numbered 0..n in outputs. Each slip and each event carries
//! its cause ([`Cause`]: a block at its threshold, the initial state, or an event source
//! such as a trigger or the noise); an event's is that of its first slip.

use super::sources::Cause;

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
#[derive(Debug, Clone, Default)]
pub struct Catalog {
    /// Finished and running events.
    pub events: Vec<EventRecord>,
    /// All slip intervals.
    pub slips: Vec<SlipRecord>,
    pub(crate) open_slip: Vec<usize>,
    pub(crate) last_event: Vec<usize>,
    pub(crate) u_first: Vec<f64>,
    pub(crate) blocks_now: Vec<usize>,
    pub(crate) open: bool,
}

const NONE: usize = usize::MAX;

impl Catalog {
    /// A catalog for n blocks.
    pub fn new(n: usize) -> Self {
        Catalog {
            open_slip: vec![NONE; n],
            last_event: vec![NONE; n],
            u_first: vec![0.0; n],
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
        if self.last_event[i] != id {
            self.last_event[i] = id;
            self.u_first[i] = u;
            self.blocks_now.push(i);
            e.n_blocks += 1;
            e.first_block = e.first_block.min(i);
            e.last_block = e.last_block.max(i);
        }
        self.open_slip[i] = self.slips.len();
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
        let k = self.open_slip[i];
        if k == NONE {
            return;
        }
        self.open_slip[i] = NONE;
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
        let drop: f64 = self
            .blocks_now
            .iter()
            .map(|&i| self.u_first[i] - u_now(i))
            .sum();
        let e = &mut self.events[id];
        e.t_end = t;
        e.stress_drop = drop / e.n_blocks.max(1) as f64;
        self.blocks_now.clear();
    }
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
}
