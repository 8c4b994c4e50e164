//! Which shock does what next: the shocks of each cell and a queue of their next events.
//!
//! The engine's next event is the earliest of a birth (the max-tree of [`super::births`]),
//! a shock reaching the end of its trajectory through its cell, and two facing shocks of
//! one cell meeting. Scanning every shock for the last two at every engine event made an
//! event with N shocks cost O(N) per node crossing, O(N^2) in all. Here:
//!
//! - `cells[c]` lists the shocks in cell c (indices, ascending): the shocks near a point
//!   (what the interpolants and the birth search look at) are found in O(1);
//! - the pairing of facing shocks is a property of one cell: it is recomputed only for the
//!   cells whose shocks changed since the last event (`dirty`: a shock entered, left, was
//!   renumbered or started a new trajectory), at O(k^2) for k shocks in the cell;
//! - the candidate events sit in ordered sets, `ends` (unpaired shocks by the end time of
//!   their trajectory, then index) and `meetings` (each paired right-mover a by its
//!   meeting time, then by decreasing a), so the earliest is read in O(log N) and an
//!   update costs O(log N).
//!
//! The orders reproduce the ties of the scan they replace (a meeting before a birth before
//! a trajectory end at equal times; among meetings the highest index of the right-mover,
//! among ends the lowest index), and a pairing recomputed only when its cell changes equals
//! the one recomputed at every event because it depends on the order of the shocks in the
//! cell, which does not change until two of them meet (a processed event) and on meeting
//! times that are functions of the trajectories alone.

use std::cmp::{Ordering, Reverse};
use std::collections::{BTreeMap, BTreeSet};

/// A time ordered by `f64::total_cmp` (NaN is never queued; -0 is stored as +0).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Time(f64);

impl Time {
    fn new(t: f64) -> Option<Time> {
        (!t.is_nan()).then_some(Time(t + 0.0))
    }
}

impl PartialEq for Time {
    fn eq(&self, o: &Self) -> bool {
        self.0.total_cmp(&o.0) == Ordering::Equal
    }
}

impl Eq for Time {}

impl PartialOrd for Time {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

impl Ord for Time {
    fn cmp(&self, o: &Self) -> Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// The shocks of every cell and the queue of their next ends and meetings (see the module
/// docs). Derived from the shocks: not part of a checkpoint, rebuilt on restore.
#[derive(Debug, Clone, Default)]
pub(crate) struct Schedule {
    /// Shock indices in each cell, ascending.
    cells: Vec<Vec<usize>>,
    /// Unpaired shocks by (end time of the trajectory, index).
    ends: BTreeSet<(Time, usize)>,
    /// Per shock index: its key in `ends`.
    end_at: Vec<Option<Time>>,
    /// (meeting time, Reverse(a)) -> (b, cell coordinate of the meeting) for right-mover a
    /// meeting left-mover b in their cell.
    meetings: BTreeMap<(Time, Reverse<usize>), (usize, f64)>,
    /// Per shock index: its key in `meetings` (as the right-mover a).
    meets_at: Vec<Option<Time>>,
    /// Cells whose shocks changed since they were last paired.
    dirty: Vec<usize>,
}

impl Schedule {
    /// An empty schedule over `n_cells` cells.
    pub(crate) fn new(n_cells: usize) -> Self {
        Schedule {
            cells: vec![Vec::new(); n_cells],
            ..Default::default()
        }
    }

    /// The shocks of cell c, ascending.
    pub(crate) fn in_cell(&self, c: usize) -> &[usize] {
        &self.cells[c]
    }

    fn put(&mut self, c: usize, i: usize) {
        let v = &mut self.cells[c];
        let at = v.partition_point(|&q| q < i);
        v.insert(at, i);
        self.dirty.push(c);
    }

    fn take(&mut self, c: usize, i: usize) {
        let v = &mut self.cells[c];
        let at = v.partition_point(|&q| q < i);
        debug_assert_eq!(v.get(at), Some(&i));
        v.remove(at);
        self.dirty.push(c);
    }

    /// A new shock, index i (= the number of shocks before it), in cell c.
    pub(crate) fn add(&mut self, i: usize, c: usize) {
        debug_assert_eq!(i, self.end_at.len());
        self.end_at.push(None);
        self.meets_at.push(None);
        self.put(c, i);
    }

    /// Shock i moved from cell `from` to cell `to`.
    pub(crate) fn moved(&mut self, i: usize, from: usize, to: usize) {
        self.take(from, i);
        self.put(to, i);
    }

    /// Something about the shocks of cell c changed (a trajectory restarted).
    pub(crate) fn touch(&mut self, c: usize) {
        self.dirty.push(c);
    }

    /// Shock i (in cell `ci`) is removed and the last shock (index `last`, in cell `cl`)
    /// takes its index, as `Vec::swap_remove` does.
    pub(crate) fn swap_remove(&mut self, i: usize, ci: usize, last: usize, cl: usize) {
        self.unqueue(i);
        self.take(ci, i);
        if i != last {
            self.unqueue(last);
            self.take(cl, last);
            self.put(cl, i);
        }
        self.end_at.pop();
        self.meets_at.pop();
    }

    /// Remove shock i's entries from the queue.
    pub(crate) fn unqueue(&mut self, i: usize) {
        if let Some(t) = self.end_at[i].take() {
            self.ends.remove(&(t, i));
        }
        if let Some(t) = self.meets_at[i].take() {
            self.meetings.remove(&(t, Reverse(i)));
        }
    }

    /// The cells to pair again (each once), emptying the list.
    pub(crate) fn take_dirty(&mut self) -> Vec<usize> {
        let mut d = std::mem::take(&mut self.dirty);
        d.sort_unstable();
        d.dedup();
        d
    }

    /// Queue the end of unpaired shock i's trajectory at t.
    pub(crate) fn queue_end(&mut self, i: usize, t: f64) {
        if let Some(t) = Time::new(t) {
            self.ends.insert((t, i));
            self.end_at[i] = Some(t);
        }
    }

    /// Queue right-mover a meeting left-mover b at time t, cell coordinate s.
    pub(crate) fn queue_meeting(&mut self, a: usize, b: usize, t: f64, s: f64) {
        if let Some(t) = Time::new(t) {
            self.meetings.insert((t, Reverse(a)), (b, s));
            self.meets_at[a] = Some(t);
        }
    }

    /// The earliest meeting (of the highest right-mover index at equal times):
    /// (time, a, b, s).
    pub(crate) fn first_meeting(&self) -> Option<(f64, usize, usize, f64)> {
        self.meetings
            .first_key_value()
            .map(|(&(t, Reverse(a)), &(b, s))| (t.0, a, b, s))
    }

    /// The earliest end of an unpaired shock's trajectory (lowest index at equal times).
    pub(crate) fn first_end(&self) -> Option<(f64, usize)> {
        self.ends.first().map(|&(t, i)| (t.0, i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queue_orders_like_the_scan_it_replaces() {
        let mut s = Schedule::new(4);
        for (i, c) in [(0, 2), (1, 2), (2, 0), (3, 2)] {
            s.add(i, c);
        }
        assert_eq!(s.in_cell(2), &[0, 1, 3]);
        assert_eq!(s.take_dirty(), vec![0, 2]);
        s.queue_end(0, 2.0);
        s.queue_end(2, 1.5);
        s.queue_end(1, 1.5);
        s.queue_end(3, f64::NAN);
        // lowest index among equal end times; NaN never queued
        assert_eq!(s.first_end(), Some((1.5, 1)));
        s.queue_meeting(0, 1, 1.0, 0.5);
        s.queue_meeting(2, 3, 1.0, 0.25);
        // highest right-mover among equal meeting times
        assert_eq!(s.first_meeting(), Some((1.0, 2, 3, 0.25)));
        // removing shock 1 renumbers shock 3 as 1 and drops both from the queue
        s.swap_remove(1, 2, 3, 2);
        assert_eq!(s.in_cell(2), &[0, 1]);
        assert_eq!(s.first_end(), Some((1.5, 2)));
        s.unqueue(2);
        assert_eq!(s.first_meeting(), Some((1.0, 0, 1, 0.5)));
        assert_eq!(s.first_end(), Some((2.0, 0)));
        s.moved(0, 2, 3);
        assert_eq!((s.in_cell(2), s.in_cell(3)), (&[1][..], &[0][..]));
        assert_eq!(s.take_dirty(), vec![2, 3]);
        // -0 and +0 are one time
        s.queue_end(1, -0.0);
        assert_eq!(s.first_end(), Some((0.0, 1)));
    }
}
