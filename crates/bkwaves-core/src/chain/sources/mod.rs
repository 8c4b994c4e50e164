//! Event sources: what starts slips besides the loading (docs/chain.md, "Event sources").
//!
//! The run loop of [`super::Chain`] holds a list of sources. Each one says when it next
//! wants to act ([`Source::next_time`]) and, at that time, what it does ([`Source::fire`]:
//! a kick or a release of one block, or nothing); the loop caps its steps and quiet jumps
//! at the earliest source time, exactly as at the slip queue's. A source keeps its own
//! state, random generator included, and writes and reads it itself in checkpoints
//! ([`Source::save`], [`Source::load`]; its configuration goes into the checkpoint's
//! fingerprint through [`Source::fingerprint`]).
//!
//! A source is one file of this folder and one line of [`SOURCES`]:
//! - [`triggers`]: kicks and releases scheduled by the user (`Chain::add_trigger`), in a
//!   binary heap (N triggers cost O(N log N));
//! - [`noise`]: spontaneous slips of stuck blocks, a Poisson process whose rate depends
//!   on each block's distance to its threshold (issue 14).

pub mod noise;
pub mod triggers;

use super::Trigger;
use crate::checkpoint_bytes::{Reader, Writer};
use crate::error::Result;

/// The registry: name and meaning of each source kind (the catalog's `kind` of an event
/// opened by it).
pub const SOURCES: &[(&str, &str)] = &[(triggers::NAME, triggers::DOC), (noise::NAME, noise::DOC)];

/// The causes of slips that are no source: a block at its threshold, the initial state.
pub const OTHER_CAUSES: [(&str, &str); 2] = [
    (
        "threshold",
        "a stuck block reached its static threshold (the loading)",
    ),
    (
        "initial",
        "the initial state (an initial velocity u_t0 != v)",
    ),
];

/// Every cause of a slip by name and meaning, in code order (the `kind` of slips and
/// events in outputs).
pub fn causes() -> impl Iterator<Item = (&'static str, &'static str)> {
    OTHER_CAUSES.iter().chain(SOURCES.iter()).copied()
}

/// What opened a slip: the loading (a block reached its threshold), the initial state, or
/// a source (by its index in [`SOURCES`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Cause {
    /// A stuck block reached its static threshold (the paper's slips).
    #[default]
    Threshold,
    /// An initial velocity (u_t0 != v) or an initial stress over the threshold.
    Initial,
    /// A source of [`SOURCES`] (index).
    Source(u8),
}

impl Cause {
    /// Name in outputs (`kind` of slips and events).
    pub fn name(self) -> &'static str {
        match self {
            Cause::Threshold => OTHER_CAUSES[0].0,
            Cause::Initial => OTHER_CAUSES[1].0,
            Cause::Source(k) => SOURCES.get(usize::from(k)).map_or("source", |s| s.0),
        }
    }

    /// Code in checkpoints.
    pub(crate) fn code(self) -> u64 {
        match self {
            Cause::Threshold => 0,
            Cause::Initial => 1,
            Cause::Source(k) => 2 + u64::from(k),
        }
    }

    /// From a checkpoint code.
    pub(crate) fn from_code(c: u64) -> Option<Cause> {
        match c {
            0 => Some(Cause::Threshold),
            1 => Some(Cause::Initial),
            c if c >= 2 && ((c - 2) as usize) < SOURCES.len() => Some(Cause::Source((c - 2) as u8)),
            _ => None,
        }
    }
}

/// What a source sees of the chain or lattice (blocks numbered 0..n as in outputs).
pub trait View {
    /// Current time.
    fn time(&self) -> f64;
    /// Number of blocks.
    fn n(&self) -> usize;
    /// Number of sliding blocks.
    fn n_sliding(&self) -> usize;
    /// Is block k sliding?
    fn sliding(&self, k: usize) -> bool;
    /// The block's stress relative to its slip threshold, x = 1 - (upper - phi): 1 at the
    /// threshold, phi itself for the paper's uniform threshold 1.
    fn stress(&self, k: usize) -> f64;
    /// The largest rate at which x of a stuck block rises while every block is stuck
    /// (max over blocks of k_p,i v).
    fn max_loading_rate(&self) -> f64;
    /// A number that changes whenever a block starts or stops sliding.
    fn switches(&self) -> u64;
}

/// A source of events in the chain's run loop.
pub(crate) trait Source: std::fmt::Debug + Send + Sync {
    /// Index of its kind in [`SOURCES`].
    fn kind(&self) -> u8;
    /// The time (>= now) at which it next wants to act; infinite if never. Called before
    /// every step or quiet jump, which end at that time at the latest.
    fn next_time(&mut self, ch: &dyn View) -> f64;
    /// Act now (the time [`Source::next_time`] returned has come): a kick or release of a
    /// block, or nothing (a rejected candidate).
    fn fire(&mut self, ch: &dyn View) -> Option<Trigger>;
    /// Its configuration, for the checkpoint's fingerprint.
    fn fingerprint(&self, w: &mut Writer);
    /// Its state (generator included).
    fn save(&self, w: &mut Writer);
    /// Read the state written by [`Source::save`].
    fn load(&mut self, r: &mut Reader) -> Result<()>;
    /// A boxed copy.
    fn boxed(&self) -> Box<dyn Source>;
    /// The noise source, if this is it (for its counters).
    fn as_noise(&self) -> Option<&noise::Noise> {
        None
    }
    /// The triggers source, if this is it (for scheduling).
    fn as_triggers(&mut self) -> Option<&mut triggers::Triggers> {
        None
    }
}

impl Clone for Box<dyn Source> {
    fn clone(&self) -> Self {
        self.boxed()
    }
}
