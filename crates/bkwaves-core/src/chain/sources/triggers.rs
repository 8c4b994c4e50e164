//! Triggers scheduled by the user: kicks and releases at given times
//! (`Chain::add_trigger`), kept in a binary heap: scheduling N of them costs O(N log N)
//! and the run loop reads the earliest in O(1). Triggers due at the same time act in the
//! reverse order of scheduling (the last scheduled first), as the engine always did.

use super::super::{Trigger, TriggerKind};
use super::{Source, View};
use crate::checkpoint_bytes::{bad, Reader, Writer};
use crate::error::Result;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Name in the registry and in outputs.
pub const NAME: &str = "trigger";
/// Meaning.
pub const DOC: &str = "a kick or release scheduled by the user (Chain.kick, Chain.release)";

#[derive(Debug, Clone, Copy)]
struct Entry {
    tr: Trigger,
    seq: u64,
}

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    /// The heap's top is the earliest time, and among equal times the latest scheduled.
    fn cmp(&self, o: &Self) -> Ordering {
        #[cfg(test)]
        COMPARISONS.with(|c| c.set(c.get() + 1));
        o.tr.t.total_cmp(&self.tr.t).then(self.seq.cmp(&o.seq))
    }
}

/// The scheduled triggers.
#[derive(Debug, Clone, Default)]
pub struct Triggers {
    heap: BinaryHeap<Entry>,
    seq: u64,
}

#[cfg(test)]
thread_local! {
    /// Comparisons of trigger entries made by this thread (tests check the O(N log N) cost).
    pub(crate) static COMPARISONS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

impl Triggers {
    /// Schedule a trigger (already validated by the chain).
    pub fn push(&mut self, tr: Trigger) {
        self.heap.push(Entry { tr, seq: self.seq });
        self.seq += 1;
    }

    /// Number of triggers still to come.
    pub fn len(&self) -> usize {
        self.heap.len()
    }

    /// No trigger left?
    pub fn is_empty(&self) -> bool {
        self.heap.is_empty()
    }
}

impl Source for Triggers {
    fn kind(&self) -> u8 {
        0
    }
    fn next_time(&mut self, _ch: &dyn View) -> f64 {
        self.heap.peek().map_or(f64::INFINITY, |e| e.tr.t)
    }
    fn fire(&mut self, _ch: &dyn View) -> Option<Trigger> {
        self.heap.pop().map(|e| e.tr)
    }
    fn fingerprint(&self, w: &mut Writer) {
        w.s(NAME);
    }
    fn save(&self, w: &mut Writer) {
        let mut all: Vec<Entry> = self.heap.iter().copied().collect();
        all.sort_by(|a, b| b.cmp(a)); // in the order they act
        w.u(self.seq);
        w.u(all.len() as u64);
        for e in all {
            w.f(e.tr.t);
            w.u(e.tr.block as u64);
            match e.tr.kind {
                TriggerKind::Release { dir } => {
                    w.u(0);
                    w.f(f64::from(dir));
                }
                TriggerKind::Kick { du_t } => {
                    w.u(1);
                    w.f(du_t);
                }
            }
            w.u(e.seq);
        }
    }
    fn load(&mut self, r: &mut Reader) -> Result<()> {
        let seq = r.u()?;
        let mut heap = BinaryHeap::new();
        for _ in 0..r.len(40)? {
            let (t, block, kind, value, s) = (r.f()?, r.z()?, r.u()?, r.f()?, r.u()?);
            let kind = match kind {
                0 => TriggerKind::Release {
                    dir: if value < 0.0 { -1 } else { 1 },
                },
                1 => TriggerKind::Kick { du_t: value },
                _ => return Err(bad(r.i, "trigger kinds 0 (release) or 1 (kick)")),
            };
            heap.push(Entry {
                tr: Trigger { t, block, kind },
                seq: s,
            });
        }
        self.heap = heap;
        self.seq = seq;
        Ok(())
    }
    fn boxed(&self) -> Box<dyn Source> {
        Box::new(self.clone())
    }
    fn as_triggers(&mut self) -> Option<&mut Triggers> {
        Some(self)
    }
}

/// The blocks the triggers act on, for the chain's check of a restored checkpoint.
impl Triggers {
    pub(crate) fn blocks(&self) -> impl Iterator<Item = usize> + '_ {
        self.heap.iter().map(|e| e.tr.block)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::Free;
    use crate::chain::{Chain, ChainConfig};
    use crate::friction::Coulomb;

    /// Comparisons made scheduling `n` kicks at scattered times on a chain and running
    /// through all of them.
    fn comparisons_for(n: usize) -> u64 {
        let cfg = ChainConfig {
            dx: 0.1,
            v: 0.0,
            step: 0.05,
        };
        let fr = Coulomb::new(0.3, f64::INFINITY).unwrap();
        let mut ch = Chain::new(cfg, fr, &Free, &[0.2; 8], None).unwrap();
        COMPARISONS.with(|c| c.set(0));
        for k in 0..n {
            // a permutation of 0..n (7919 is prime, coprime with the sizes used)
            let t = ((k * 7919) % n) as f64;
            // du_t = 0 on a stuck block: the trigger fires and changes nothing
            ch.add_trigger(Trigger {
                t,
                block: k % 8,
                kind: TriggerKind::Kick { du_t: 0.0 },
            })
            .unwrap();
        }
        ch.run(n as f64, usize::MAX, u64::MAX).unwrap();
        assert!(ch.triggers().is_empty());
        COMPARISONS.with(|c| c.get())
    }

    #[test]
    fn scheduling_n_triggers_costs_n_log_n() {
        let (small, big) = (comparisons_for(10_000), comparisons_for(100_000));
        // N log2 N: the ratio is 10 * 16.6/13.3 = 12.5; re-sorting the list on every push
        // (the engine before) is quadratic: a ratio of 100
        let ratio = big as f64 / small as f64;
        assert!(ratio < 20.0, "ratio {ratio} ({small}, {big})");
        let n = 100_000f64;
        assert!(
            (big as f64) < 4.0 * n * n.log2(),
            "{big} comparisons for 1e5"
        );
    }

    #[test]
    fn triggers_at_the_same_time_act_last_scheduled_first() {
        let mut tr = Triggers::default();
        for (t, block) in [(2.0, 0), (1.0, 1), (2.0, 2), (1.0, 3)] {
            tr.push(Trigger {
                t,
                block,
                kind: TriggerKind::Release { dir: 1 },
            });
        }
        let order: Vec<usize> = std::iter::from_fn(|| tr.heap.pop().map(|e| e.tr.block)).collect();
        assert_eq!(order, vec![3, 1, 2, 0]);
    }
}
