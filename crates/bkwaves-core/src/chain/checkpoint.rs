//! Checkpoints: the whole state of a chain as bytes, restored bit for bit.
//!
//! A run continued from a checkpoint equals the uninterrupted run exactly (same steps,
//! same events, same books), provided the checkpoint is taken where `run` returned on its
//! step or event budget (a `t_end` inside an event caps a step, which an uninterrupted
//! run would not do). The bytes hold a fingerprint of the configuration (blocks, dx, v,
//! step, boundary, friction law and its parameter table's values, the per-block
//! properties, integrator, the event sources' configurations): they are restored into a
//! chain built with the same configuration, and anything else is refused.
//!
//! Every field is named once: [`chain_state!`] lists the chain's fields, each record type
//! lists its own ([`record!`]), and the same list is written by [`Chain::checkpoint`] and
//! read by [`Chain::restore`] through [`Field`]. The slip queue and the event sources
//! write and read themselves (each source its own state, random generator included).

use super::catalog::{EventRecord, Marks, SlipRecord};
use super::cells::CellVec;
use super::events::SlipQueue;
use super::geometry::Geometry;
use super::medium::Medium;
use super::sources::Cause;
use super::Engine;
use crate::checkpoint_bytes::{bad, Reader as R, Writer as W};
use crate::error::Result;
use crate::friction::Friction;

const MAGIC: &[u8; 8] = b"BKCHAIN6";

/// A value of the state, written and read by one code path.
pub(crate) trait Field {
    fn put(&self, w: &mut W);
    fn get(&mut self, r: &mut R) -> Result<()>;
}

impl Field for f64 {
    fn put(&self, w: &mut W) {
        w.f(*self);
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        *self = r.f()?;
        Ok(())
    }
}

impl Field for u64 {
    fn put(&self, w: &mut W) {
        w.u(*self);
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        *self = r.u()?;
        Ok(())
    }
}

impl Field for usize {
    fn put(&self, w: &mut W) {
        w.z(*self);
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        *self = r.z()?;
        Ok(())
    }
}

impl Field for bool {
    fn put(&self, w: &mut W) {
        w.b(*self);
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        *self = r.b()?;
        Ok(())
    }
}

impl Field for i8 {
    fn put(&self, w: &mut W) {
        w.i(*self);
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        *self = r.dir()?;
        Ok(())
    }
}

impl Field for Cause {
    fn put(&self, w: &mut W) {
        w.u(self.code());
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        *self = Cause::from_code(r.u()?).ok_or_else(|| bad(r.i, "a known slip cause"))?;
        Ok(())
    }
}

/// A sequence: its length, then its items (each at least one 8-byte word).
impl<T: Field + Default> Field for Vec<T> {
    fn put(&self, w: &mut W) {
        w.u(self.len() as u64);
        for x in self {
            x.put(w);
        }
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        let k = r.len(8)?;
        self.clear();
        for _ in 0..k {
            let mut x = T::default();
            x.get(r)?;
            self.push(x);
        }
        Ok(())
    }
}

/// The catalog's bookkeeping per block: four vectors, as the dense layout wrote them.
impl Field for Marks {
    fn put(&self, w: &mut W) {
        self.open_slip.put(w);
        self.last_event.put(w);
        self.u_first.put(w);
        self.blocks_now.put(w);
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        self.open_slip.get(r)?;
        self.last_event.get(r)?;
        self.u_first.get(r)?;
        self.blocks_now.get(r)
    }
}

/// An array over the cells: as a `Vec<f64>` (its length, then its values).
impl Field for CellVec {
    fn put(&self, w: &mut W) {
        w.u(self.len() as u64);
        for &x in self.iter() {
            w.f(x);
        }
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        let k = r.len(8)?;
        if k != self.len() {
            *self = CellVec::new(k, 0.0);
        }
        for x in self.iter_mut() {
            *x = r.f()?;
        }
        Ok(())
    }
}

/// An array of accelerations as a checkpoint writes it: its values in the cells of
/// these runs, 0 elsewhere. The other values are dead (never read before written: they
/// are stale values of earlier steps, or zeros where the memory was given back,
/// ../release.rs), so a restored run's checkpoints equal the uninterrupted one's
/// whatever was given back when. Read back as a [`CellVec`].
struct Accels<'a>(&'a CellVec, &'a [(usize, usize)]);

impl Field for Accels<'_> {
    fn put(&self, w: &mut W) {
        w.u(self.0.len() as u64);
        let mut p = 0;
        for &(a, b) in self.1 {
            for _ in p..a {
                w.f(0.0);
            }
            for &x in &self.0[a..b] {
                w.f(x);
            }
            p = b;
        }
        for _ in p..self.0.len() {
            w.f(0.0);
        }
    }
    fn get(&mut self, r: &mut R) -> Result<()> {
        Err(bad(
            r.i,
            "accelerations read into a CellVec (Accels only writes)",
        ))
    }
}

/// A record type's fields, in checkpoint order.
macro_rules! record {
    ($t:ty { $($f:ident),* $(,)? }) => {
        impl Field for $t {
            fn put(&self, w: &mut W) {
                $(self.$f.put(w);)*
            }
            fn get(&mut self, r: &mut R) -> Result<()> {
                $(self.$f.get(r)?;)*
                Ok(())
            }
        }
    };
}

record!(EventRecord {
    id,
    nucleation,
    first_block,
    last_block,
    n_blocks,
    n_slips,
    t_start,
    t_end,
    moment,
    stress_drop,
    kind
});
record!(SlipRecord {
    event,
    block,
    dir,
    t_start,
    t_end,
    u_start,
    u_end,
    slip,
    kind
});

/// The chain's state fields, in checkpoint order, as references (`&` to write, `&mut` to
/// read): the one list of what a checkpoint holds besides the queue and the sources.
macro_rules! chain_state {
    ($c:ident, $dyn:ty, $acc0:expr, $acc1:expr, $marks:expr, $($r:tt)+) => {{
        let fields: Vec<$dyn> = vec![
            $($r)+ $c.t,
            $($r)+ $c.stuck_sum,
            $($r)+ $c.n_stuck,
            $($r)+ $c.stuck_loader,
            $($r)+ $c.need_check,
            $($r)+ $c.full_check,
            $($r)+ $c.a_valid,
            // the accelerations at the start of the next step (a_start) and a_end: written
            // canonically ([`Accels`]), read as they are
            $acc0,
            $acc1,
            $($r)+ $c.st.u,
            $($r)+ $c.st.w,
            $($r)+ $c.st.tref,
            $($r)+ $c.st.dir,
            $($r)+ $c.st.onset,
            $($r)+ $c.snap_times,
            $($r)+ $c.snap_every,
            $($r)+ $c.ledger.load,
            $($r)+ $c.ledger.dry,
            $($r)+ $c.ledger.viscous,
            $($r)+ $c.ledger.projection,
            $($r)+ $c.ledger.injected,
            $($r)+ $c.counters.steps,
            $($r)+ $c.counters.block_steps,
            $($r)+ $c.counters.switches,
            $($r)+ $c.counters.jumps,
            $($r)+ $c.catalog.events,
            $($r)+ $c.catalog.slips,
            // the catalog's bookkeeping per block in its dense layout ([`Marks`])
            $marks,
            $($r)+ $c.catalog.open,
            $($r)+ $c.snapshots.t,
            $($r)+ $c.snapshots.u,
            $($r)+ $c.snapshots.u_t,
        ];
        fields
    }};
}

impl<G: Geometry, F: Friction, M: Medium> Engine<G, F, M> {
    fn fingerprint(&self, w: &mut W) {
        w.u(self.st.n as u64);
        w.f(self.cfg.dx);
        w.f(self.cfg.v);
        w.f(self.cfg.step);
        w.s(self.boundary_name);
        w.s(&self.st.geo.describe());
        // the law by its table: name, then every parameter's name and value
        w.s(F::NAME);
        for (p, x) in F::PARAMS.iter().zip(self.blk.fr.values()) {
            w.s(p.name);
            w.f(x);
        }
        w.fs(&self.blk.med.fingerprint());
        w.s(self.rk.name());
        // the step-size control, when on (a default chain's bytes are unchanged)
        if let Some(c) = &self.control {
            w.s("step_tolerance");
            w.f(c.tol);
        }
        // local events, when chosen (a chain's bytes are unchanged)
        if self.local_events() {
            w.s("local_events");
        }
        w.u(self.sources.len() as u64);
        for s in &self.sources {
            s.fingerprint(w);
        }
    }

    /// The whole state as bytes (see the module docs).
    pub fn checkpoint(&self) -> Vec<u8> {
        let mut w = W(MAGIC.to_vec());
        self.fingerprint(&mut w);
        let (runs, valid) = (&self.st.runs[..], self.a_valid);
        let (acc0, acc1) = (
            Accels(&self.a_start, if valid { runs } else { &[] }),
            Accels(&self.a_end, &[]),
        );
        let marks = self.catalog.marks();
        for f in chain_state!(self, &dyn Field, &acc0, &acc1, &marks, &) {
            f.put(&mut w);
        }
        if let Some(c) = &self.control {
            c.h.put(&mut w);
            c.switches_seen.put(&mut w);
        }
        let q = self.queue.entries();
        w.u(q.len() as u64);
        for (t, p) in q {
            w.f(t);
            w.u(p as u64);
        }
        for s in &self.sources {
            s.save(&mut w);
        }
        w.0
    }

    /// Restore a state written by [`Chain::checkpoint`] of a chain with the same
    /// configuration. On error the chain is unchanged.
    pub fn restore(&mut self, bytes: &[u8]) -> Result<()> {
        let mut r = R { b: bytes, i: 0 };
        let magic = r.take(8)?;
        if magic != MAGIC {
            return Err(bad(
                0,
                if magic.starts_with(b"BKCHAIN") {
                    "a checkpoint of this engine's format (BKCHAIN6); these bytes are of \
                     another format, written by another bkwaves version"
                } else {
                    "bytes written by Chain::checkpoint"
                },
            ));
        }
        let mut fp = W(Vec::new());
        self.fingerprint(&mut fp);
        if r.take(fp.0.len())? != fp.0.as_slice() {
            return Err(bad(
                8,
                "a checkpoint of a chain with the same blocks, dx, v, step, boundary, \
                 friction law and parameters, per-block properties, integrator, step-size \
                 control, event location (local or global) and event sources",
            ));
        }
        let (n, n2) = (self.st.n, self.st.geo.cells());
        let mut next = self.clone();
        let mut marks = Marks::default();
        for f in chain_state!(
            next,
            &mut dyn Field,
            &mut next.a_start,
            &mut next.a_end,
            &mut marks,
            &mut
        ) {
            f.get(&mut r)?;
        }
        // stale accelerations are all recomputed after a restore (the same bits)
        next.a_partial = false;
        next.a_time = f64::NAN;
        if let Some(c) = next.control.as_mut() {
            c.h.get(&mut r)?;
            c.switches_seen.get(&mut r)?;
            if !(c.h >= c.h_min && c.h <= c.h_max) {
                return Err(bad(
                    r.i,
                    "a controlled step between the fixed step and the limit",
                ));
            }
        }
        let st = &next.st;
        if [
            &next.a_start,
            &next.a_end,
            &st.u,
            &st.w,
            &st.tref,
            &st.dir,
            &st.onset,
        ]
        .iter()
        .any(|a| a.len() != n2)
        {
            return Err(bad(r.i, "arrays of the padded length"));
        }
        if let Err(what) = next.catalog.set_marks(marks) {
            return Err(bad(r.i, what));
        }
        next.queue = SlipQueue::new(n2);
        for _ in 0..r.len(16)? {
            let (t, p) = (r.f()?, r.z()?);
            if p >= n2 || next.st.geo.is_ghost(p) {
                return Err(bad(r.i, "queue entries of real blocks"));
            }
            next.queue.push(p, t);
        }
        for s in next.sources.iter_mut() {
            s.load(&mut r)?;
        }
        if next.triggers().blocks().any(|b| b >= n) {
            return Err(bad(r.i, "triggers of real blocks"));
        }
        if r.i != bytes.len() {
            return Err(bad(r.i, "a checkpoint with nothing after its end"));
        }
        next.st.rebuild_runs();
        // the arrays were all written: every granule may be given back (release.rs)
        next.st.touched.mark_all();
        // scratch of the integrator: as a freshly built chain has it
        next.u0 = CellVec::new(n2, 0.0);
        next.w0 = CellVec::new(n2, 0.0);
        *self = next;
        Ok(())
    }
}
