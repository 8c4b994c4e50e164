//! Checkpoints of the two-dimensional engine: the whole state as bytes, restored bit for
//! bit. A run continued from a checkpoint equals the uninterrupted run exactly when it
//! makes the same [`FreeBoundary2D::advance`] calls from that point.
//!
//! The bytes hold a fingerprint of the configuration (grid, boundaries, gamma, v, creep
//! rule, stencil order, record_arrivals, noise law and seed, front-speed law, threshold
//! field, and the shape options when they are on) and are refused by an engine configured otherwise. Stored: the field and its
//! epoch, the time, every per-node array of the march (arrival, label, stop time, trial
//! time and rupture, entry version, seed flag), the catalog with the running ruptures'
//! node lists, the counters, the noise generator and the noise's tile bounds, weights and
//! window end. Rebuilt: the birth max-tree (each
//! inner node is the maximum of its children, whatever the order of the leaves) and the
//! heap (one entry per trial node: the stale entries of the original heap are never
//! popped as valid, so the order of the valid ones, by time then node, is the same).

use super::{Entry, FreeBoundary2D, Origin, Rupture, NONE};
use crate::checkpoint_bytes::{bad, Reader as R, Writer as W};
use crate::error::Result;
use crate::free_boundary::{Boundary, CreepRule, SpeedLaw};

const MAGIC: &[u8; 8] = b"BKFB2D02";

impl FreeBoundary2D {
    fn fingerprint(&self, w: &mut W) {
        let g = &self.grid;
        w.u(g.nx as u64);
        w.u(g.ny as u64);
        w.f(g.h);
        w.f(g.x0);
        w.f(g.y0);
        for b in [g.bx, g.by] {
            w.b(b == Boundary::Periodic);
        }
        let o = &self.opts;
        w.f(o.gamma);
        w.f(o.v);
        w.b(o.creep == CreepRule::Stop);
        w.b(o.second_order);
        w.b(o.record_arrivals);
        match &self.noise {
            None => w.u(0),
            Some(nz) => {
                w.u(1);
                nz.write_config(w);
            }
        }
        match &self.law {
            SpeedLaw::Exact => w.u(0),
            SpeedLaw::Table(t) => {
                w.u(1);
                w.fs(&t.u_plus);
                w.fs(&t.c);
            }
        }
        match &self.threshold {
            None => w.u(0),
            Some(th) => {
                w.u(1);
                w.fs(th);
            }
        }
        // the shape options (appended only when on: a checkpoint without them has the
        // bytes it had before they existed)
        if self.shaped() {
            w.s("shape");
            match (o.curvature, &self.curv_dirs) {
                (None, _) => w.u(0),
                (Some(_), Some(dirs)) => {
                    w.u(2);
                    w.fs(&dirs.theta);
                    w.fs(&dirs.d);
                }
                (Some((da, dd)), None) => {
                    w.u(1);
                    w.f(da);
                    w.f(dd);
                }
            }
            match &self.law_diag {
                None => w.u(0),
                Some(SpeedLaw::Exact) => w.u(1),
                Some(SpeedLaw::Table(t)) => {
                    w.u(2);
                    w.fs(&t.u_plus);
                    w.fs(&t.c);
                }
            }
        }
    }

    /// The whole state as bytes (see the module docs).
    pub fn checkpoint(&self) -> Vec<u8> {
        let mut w = W(MAGIC.to_vec());
        self.fingerprint(&mut w);
        for x in [self.now, self.epoch] {
            w.f(x);
        }
        w.u(self.steps);
        w.z(self.live);
        w.z(self.completed);
        w.fs(&self.b);
        w.fs(&self.t_arr);
        w.fs(&self.stopped);
        w.fs(&self.tent);
        let u32s =
            |w: &mut W, v: &[u32]| w.us(&v.iter().map(|&x| u64::from(x)).collect::<Vec<_>>());
        u32s(&mut w, &self.label);
        u32s(&mut w, &self.tent_rup);
        u32s(&mut w, &self.ver);
        w.us(&self.seed.iter().map(|&x| u64::from(x)).collect::<Vec<_>>());
        w.u(self.ruptures.len() as u64);
        for r in &self.ruptures {
            w.z(r.id);
            w.u(r.origin.code());
            for x in [
                r.t_start,
                r.x_start,
                r.y_start,
                r.u_start,
                r.t_end,
                r.area,
                r.moment,
                r.perimeter,
            ] {
                w.f(x);
            }
            for x in [r.n_nodes, r.n_stopped, r.n_creep, r.contacts, r.trials] {
                w.z(x);
            }
            w.b(r.complete);
            u32s(&mut w, &r.nodes);
            w.fs(&r.arrivals);
        }
        if let Some(nz) = &self.noise {
            nz.write_state(&mut w);
        }
        self.write_tiles(&mut w);
        w.0
    }

    /// Restore a state written by [`Self::checkpoint`] of an engine with the same
    /// configuration (refused otherwise, and on malformed bytes).
    pub fn restore(&mut self, data: &[u8]) -> Result<()> {
        let mut fp = W(MAGIC.to_vec());
        self.fingerprint(&mut fp);
        if data.len() < fp.0.len() || data[..fp.0.len()] != fp.0[..] {
            return Err(crate::error::Error::InvalidParameter {
                name: "checkpoint",
                value: f64::NAN,
                allowed: "a checkpoint of a two-dimensional free boundary engine with this \
                          configuration (grid, boundaries, gamma, v, creep, stencil, \
                          record_arrivals, noise, speed law, threshold)",
            });
        }
        let mut r = R {
            b: data,
            i: fp.0.len(),
        };
        let n = self.grid.n();
        let mut e = self.clone();
        e.now = r.f()?;
        e.epoch = r.f()?;
        e.steps = r.u()?;
        e.live = r.z()?;
        e.completed = r.z()?;
        let sized = |v: Vec<f64>, at: usize| -> Result<Vec<f64>> {
            if v.len() == n {
                Ok(v)
            } else {
                Err(bad(at, "one value per node"))
            }
        };
        e.b = sized(r.fs()?, r.i)?;
        e.t_arr = sized(r.fs()?, r.i)?;
        e.stopped = sized(r.fs()?, r.i)?;
        e.tent = sized(r.fs()?, r.i)?;
        let read_u32s = |r: &mut R, len: Option<usize>| -> Result<Vec<u32>> {
            let v = r.us()?;
            if len.is_some_and(|l| l != v.len()) || v.iter().any(|&x| x > u64::from(u32::MAX)) {
                return Err(bad(r.i, "a well-formed checkpoint (node arrays)"));
            }
            Ok(v.into_iter().map(|x| x as u32).collect())
        };
        e.label = read_u32s(&mut r, Some(n))?;
        e.tent_rup = read_u32s(&mut r, Some(n))?;
        e.ver = read_u32s(&mut r, Some(n))?;
        e.seed = read_u32s(&mut r, Some(n))?
            .into_iter()
            .map(|x| x != 0)
            .collect();
        let nr = r.len(8)?;
        e.ruptures = Vec::with_capacity(nr);
        for _ in 0..nr {
            let id = r.z()?;
            let origin = Origin::from_code(r.u()?).ok_or_else(|| bad(r.i, "a rupture origin"))?;
            let mut q = Rupture::new(id, origin, 0.0, (0.0, 0.0), 0.0);
            q.t_start = r.f()?;
            q.x_start = r.f()?;
            q.y_start = r.f()?;
            q.u_start = r.f()?;
            q.t_end = r.f()?;
            q.area = r.f()?;
            q.moment = r.f()?;
            q.perimeter = r.f()?;
            q.n_nodes = r.z()?;
            q.n_stopped = r.z()?;
            q.n_creep = r.z()?;
            q.contacts = r.z()?;
            q.trials = r.z()?;
            q.complete = r.b()?;
            q.nodes = read_u32s(&mut r, None)?;
            q.arrivals = r.fs()?;
            if q.nodes.iter().any(|&k| k as usize >= n) {
                return Err(bad(r.i, "rupture nodes on the grid"));
            }
            e.ruptures.push(q);
        }
        let nrup = e.ruptures.len();
        if e.label
            .iter()
            .chain(&e.tent_rup)
            .any(|&l| l != NONE && l as usize >= nrup)
        {
            return Err(bad(r.i, "labels of ruptures in the catalog"));
        }
        if let Some(nz) = e.noise.as_mut() {
            nz.read_state(&mut r)?;
        }
        e.read_tiles(&mut r)?;
        if r.i != data.len() {
            return Err(bad(r.i, "a checkpoint that ends where its state ends"));
        }
        e.heap.clear();
        for k in 0..n {
            if e.tent_rup[k] != NONE {
                e.tree.set(k, f64::NEG_INFINITY);
                e.heap.push(Entry {
                    t: e.tent[k],
                    k: k as u32,
                    ver: e.ver[k],
                });
            } else {
                e.tree.set(k, e.b[k] - e.thr(k));
            }
        }
        *self = e;
        Ok(())
    }
}
