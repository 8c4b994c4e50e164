//! Checkpoints: the whole state of a chain as bytes, restored bit for bit.
//!
//! A run continued from a checkpoint equals the uninterrupted run exactly (same steps,
//! same events, same books), provided the checkpoint is taken where `run` returned on its
//! step or event budget (a `t_end` inside an event caps a step, which an uninterrupted
//! run would not do). The bytes hold a fingerprint of the configuration (blocks, dx, v,
//! step, boundary, friction law and its parameter table's values, the per-block
//! properties, integrator): they are restored into
//! a chain built with the same configuration, and anything else is refused.

use super::catalog::{EventRecord, SlipRecord};
use super::events::SlipQueue;
use super::medium::Medium;
use super::{Chain, Trigger, TriggerKind};
use crate::checkpoint_bytes::{bad, Reader as R, Writer as W};
use crate::error::Result;
use crate::friction::Friction;

const MAGIC: &[u8; 8] = b"BKCHAIN3";

impl<F: Friction, M: Medium> Chain<F, M> {
    fn fingerprint(&self, w: &mut W) {
        w.u(self.st.n as u64);
        w.f(self.cfg.dx);
        w.f(self.cfg.v);
        w.f(self.cfg.step);
        w.s(self.boundary_name);
        w.s(&format!("{:?}", (self.st.left, self.st.right)));
        // the law by its table: name, then every parameter's name and value
        w.s(F::NAME);
        for (p, x) in F::PARAMS.iter().zip(self.blk.fr.values()) {
            w.s(p.name);
            w.f(x);
        }
        w.fs(&self.blk.med.fingerprint());
        w.s(self.rk.name());
    }

    /// The whole state as bytes (see the module docs).
    pub fn checkpoint(&self) -> Vec<u8> {
        let mut w = W(MAGIC.to_vec());
        self.fingerprint(&mut w);
        w.f(self.t);
        w.f(self.stuck_sum);
        w.u(self.n_stuck as u64);
        w.f(self.stuck_loader);
        w.b(self.need_check);
        w.b(self.full_check);
        w.b(self.a_valid);
        for x in [self.s_start.u, self.s_start.dry, self.s_start.visc] {
            w.f(x);
        }
        w.fs(&self.a_start);
        w.fs(&self.st.u);
        w.fs(&self.st.w);
        w.fs(&self.st.tref);
        w.fs(&self.st.dir);
        w.fs(&self.st.onset);
        let q = self.queue.entries();
        w.u(q.len() as u64);
        for (t, p) in q {
            w.f(t);
            w.u(p as u64);
        }
        w.u(self.triggers.len() as u64);
        for tr in &self.triggers {
            w.f(tr.t);
            w.u(tr.block as u64);
            match tr.kind {
                TriggerKind::Release { dir } => {
                    w.u(0);
                    w.f(f64::from(dir));
                }
                TriggerKind::Kick { du_t } => {
                    w.u(1);
                    w.f(du_t);
                }
            }
        }
        w.fs(&self.snap_times);
        w.u(self.snap_every as u64);
        let l = self.ledger;
        for x in [l.load, l.dry, l.viscous, l.projection, l.injected] {
            w.f(x);
        }
        let c = self.counters;
        for x in [c.steps, c.block_steps, c.switches, c.jumps] {
            w.u(x);
        }
        let cat = &self.catalog;
        w.u(cat.events.len() as u64);
        for e in &cat.events {
            for x in [
                e.id,
                e.nucleation,
                e.first_block,
                e.last_block,
                e.n_blocks,
                e.n_slips,
            ] {
                w.u(x as u64);
            }
            for x in [e.t_start, e.t_end, e.moment, e.stress_drop] {
                w.f(x);
            }
        }
        w.u(cat.slips.len() as u64);
        for r in &cat.slips {
            w.u(r.event as u64);
            w.u(r.block as u64);
            w.f(f64::from(r.dir));
            for x in [r.t_start, r.t_end, r.u_start, r.u_end, r.slip] {
                w.f(x);
            }
        }
        w.zs(&cat.open_slip);
        w.zs(&cat.last_event);
        w.fs(&cat.u_first);
        w.zs(&cat.blocks_now);
        w.b(cat.open);
        let sn = &self.snapshots;
        w.fs(&sn.t);
        for rows in [&sn.u, &sn.u_t] {
            w.u(rows.len() as u64);
            for r in rows {
                w.fs(r);
            }
        }
        w.0
    }

    /// Restore a state written by [`Chain::checkpoint`] of a chain with the same
    /// configuration. On error the chain is unchanged.
    pub fn restore(&mut self, bytes: &[u8]) -> Result<()> {
        let mut r = R { b: bytes, i: 0 };
        if r.take(8)? != MAGIC {
            return Err(bad(0, "bytes written by Chain::checkpoint"));
        }
        let mut fp = W(Vec::new());
        self.fingerprint(&mut fp);
        if r.take(fp.0.len())? != fp.0.as_slice() {
            return Err(bad(
                8,
                "a checkpoint of a chain with the same blocks, dx, v, step, boundary, \
                 friction law and parameters, per-block properties and integrator",
            ));
        }
        let n2 = self.st.n + 2;
        let mut next = Chain {
            cfg: self.cfg,
            blk: self.blk.clone(),
            boundary_name: self.boundary_name,
            st: self.st.clone(),
            rk: self.rk.clone(),
            queue: SlipQueue::new(n2),
            t: r.f()?,
            h: self.h,
            a_start: Vec::new(),
            a_end: vec![0.0; n2],
            s_start: Default::default(),
            s_end: Default::default(),
            a_valid: false,
            u0: vec![0.0; n2],
            w0: vec![0.0; n2],
            stuck_sum: r.f()?,
            n_stuck: r.z()?,
            stuck_loader: r.f()?,
            triggers: Vec::new(),
            snap_times: Vec::new(),
            snap_every: 0,
            catalog: Default::default(),
            ledger: Default::default(),
            snapshots: Default::default(),
            counters: Default::default(),
            need_check: false,
            full_check: false,
            // run limits are not state: the restored chain keeps its own
            event_slip_limit: self.event_slip_limit,
            event_duration_limit: self.event_duration_limit,
            chunk_work: self.chunk_work,
        };
        next.need_check = r.b()?;
        next.full_check = r.b()?;
        next.a_valid = r.b()?;
        next.s_start.u = r.f()?;
        next.s_start.dry = r.f()?;
        next.s_start.visc = r.f()?;
        let arrays = [r.fs()?, r.fs()?, r.fs()?, r.fs()?, r.fs()?, r.fs()?];
        if arrays.iter().any(|a| a.len() != n2) {
            return Err(bad(r.i, "arrays of n + 2 values"));
        }
        let [a_start, u, w, tref, dir, onset] = arrays;
        next.a_start = a_start;
        next.st.u = u;
        next.st.w = w;
        next.st.tref = tref;
        next.st.dir = dir;
        next.st.onset = onset;
        next.st.runs.clear();
        next.st.n_active = 0;
        for p in 1..=next.st.n {
            if next.st.dir[p] != 0.0 {
                next.st.add_to_runs(p);
            }
        }
        for _ in 0..r.len(8)? {
            let (t, p) = (r.f()?, r.z()?);
            if p == 0 || p > next.st.n {
                return Err(bad(r.i, "queue entries of real blocks"));
            }
            next.queue.push(p, t);
        }
        for _ in 0..r.len(8)? {
            let (t, block, kind, value) = (r.f()?, r.z()?, r.u()?, r.f()?);
            let kind = if kind == 0 {
                TriggerKind::Release {
                    dir: if value < 0.0 { -1 } else { 1 },
                }
            } else {
                TriggerKind::Kick { du_t: value }
            };
            if block >= next.st.n {
                return Err(bad(r.i, "triggers of real blocks"));
            }
            next.triggers.push(Trigger { t, block, kind });
        }
        next.snap_times = r.fs()?;
        next.snap_every = r.z()?;
        let l = &mut next.ledger;
        l.load = r.f()?;
        l.dry = r.f()?;
        l.viscous = r.f()?;
        l.projection = r.f()?;
        l.injected = r.f()?;
        let c = &mut next.counters;
        c.steps = r.u()?;
        c.block_steps = r.u()?;
        c.switches = r.u()?;
        c.jumps = r.u()?;
        let cat = &mut next.catalog;
        for _ in 0..r.len(8)? {
            let ints = [r.z()?, r.z()?, r.z()?, r.z()?, r.z()?, r.z()?];
            let fl = [r.f()?, r.f()?, r.f()?, r.f()?];
            cat.events.push(EventRecord {
                id: ints[0],
                nucleation: ints[1],
                first_block: ints[2],
                last_block: ints[3],
                n_blocks: ints[4],
                n_slips: ints[5],
                t_start: fl[0],
                t_end: fl[1],
                moment: fl[2],
                stress_drop: fl[3],
            });
        }
        for _ in 0..r.len(8)? {
            let (event, block, dir) = (r.z()?, r.z()?, r.f()?);
            let fl = [r.f()?, r.f()?, r.f()?, r.f()?, r.f()?];
            cat.slips.push(SlipRecord {
                event,
                block,
                dir: dir as i8,
                t_start: fl[0],
                t_end: fl[1],
                u_start: fl[2],
                u_end: fl[3],
                slip: fl[4],
            });
        }
        cat.open_slip = r.zs()?;
        cat.last_event = r.zs()?;
        cat.u_first = r.fs()?;
        cat.blocks_now = r.zs()?;
        cat.open = r.b()?;
        let n = next.st.n;
        if cat.open_slip.len() != n || cat.last_event.len() != n || cat.u_first.len() != n {
            return Err(bad(r.i, "catalog arrays of n values"));
        }
        next.snapshots.t = r.fs()?;
        let mut rows = [Vec::new(), Vec::new()];
        for rr in rows.iter_mut() {
            for _ in 0..r.len(8)? {
                rr.push(r.fs()?);
            }
        }
        let [su, sw] = rows;
        next.snapshots.u = su;
        next.snapshots.u_t = sw;
        if r.i != bytes.len() {
            return Err(bad(r.i, "a checkpoint with nothing after its end"));
        }
        *self = next;
        Ok(())
    }
}
