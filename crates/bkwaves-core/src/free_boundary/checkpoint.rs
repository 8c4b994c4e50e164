//! Checkpoints: the whole state of a free boundary run as bytes, restored bit for bit.
//!
//! A run continued from a checkpoint equals the uninterrupted run exactly (same engine
//! events, same node values, same shock paths and catalog) provided the continuation makes
//! the same [`FreeBoundary::advance`] calls as the uninterrupted run would have made from
//! that point (a checkpoint taken where `advance` returned on its step budget, continued
//! with the same `t_stop`, is the usual case). The bytes hold a fingerprint of the
//! configuration (x0, h, number of nodes, boundary, gamma, v, creep rule, tol,
//! record_path, noise, front-speed law, threshold field): they are restored into an engine built with the same configuration (its
//! initial field and shocks do not matter: they are replaced), and anything else is
//! refused.
//!
//! Stored: the field (b, prev, reset_by, epoch), the reset stamps, every live shock with
//! its cell, trajectory (the accepted points are its dense output) and cell interpolant,
//! the per-cell maxima, the catalog, the path and the counters. Rebuilt: the stopping
//! threshold (from the options), the max-tree over the cell maxima (setting every leaf
//! in order, as the constructor does, gives the same tree: each inner node is the maximum
//! of its children) and the event queue (`schedule`: the shocks of each cell, then the
//! pairing of every cell with shocks, which depends only on the shocks' order in the cell
//! and their trajectories). The position of each shock now is written (a derived value,
//! kept so that the byte layout is that of earlier versions) and ignored on reading.

use super::births::{CellMax, MaxTree};
use super::catalog::{FbEvent, PathKind, PathPoint};
use super::field::{CellPoly, NONE};
use super::shock::{CellField, TrajEnd, TrajPoint, Trajectory};
use super::{Boundary, CreepRule, FreeBoundary, ShockState, SpeedLaw};
use crate::checkpoint_bytes::{bad, Reader as R, Writer as W};
use crate::error::Result;

const MAGIC: &[u8; 8] = b"BKFREEB3";

const KINDS: [PathKind; 8] = [
    PathKind::Initial,
    PathKind::Birth,
    PathKind::Node,
    PathKind::Annihilation,
    PathKind::Exit,
    PathKind::Death,
    PathKind::CreepStop,
    PathKind::Nucleation,
];

fn kind_code(k: PathKind) -> u64 {
    KINDS
        .iter()
        .position(|&q| q == k)
        .expect("every kind is listed") as u64
}

impl FreeBoundary {
    fn fingerprint(&self, w: &mut W) {
        let f = &self.field;
        w.f(f.x0);
        w.f(f.h);
        w.u(f.n as u64);
        w.b(f.periodic);
        w.f(f.v);
        let o = &self.opts;
        w.f(o.gamma);
        w.f(o.v);
        w.u(match o.boundary {
            Boundary::Free => 0,
            Boundary::Periodic => 1,
        });
        w.u(match o.creep {
            CreepRule::Zero => 0,
            CreepRule::Stop => 1,
        });
        w.f(o.tol);
        w.b(o.record_path);
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
    }

    /// The whole state as bytes (see the module docs).
    pub fn checkpoint(&self) -> Vec<u8> {
        let mut w = W(MAGIC.to_vec());
        self.fingerprint(&mut w);
        let f = &self.field;
        w.f(f.epoch);
        w.fs(&f.b);
        w.fs(&f.prev);
        w.zs(&f.reset_by);
        w.us(&self.reset_stamp);
        w.us(&self.prev_stamp);
        w.u(self.stamp);
        w.z(self.next_id);
        w.f(self.now);
        w.u(self.steps);
        w.z(self.open.unwrap_or(NONE));
        w.u(self.shocks.len() as u64);
        for (i, sh) in self.shocks.iter().enumerate() {
            w.z(sh.id);
            w.i(sh.dir);
            w.z(sh.cell);
            w.z(sh.event);
            w.b(sh.born);
            w.u(sh.stamp);
            // (the position now: derived from the trajectory, kept in the layout)
            for x in [sh.xl_unw, sh.last_x_unw, sh.last_a, self.shock_s(i)] {
                w.f(x);
            }
            let tr = &sh.traj;
            w.f(tr.s_start);
            w.i(tr.dir);
            w.u(match tr.end {
                TrajEnd::Node => 0,
                TrajEnd::Threshold => 1,
            });
            w.u(tr.pts.len() as u64);
            for p in &tr.pts {
                w.f(p.y);
                w.f(p.t);
                w.f(p.f);
            }
            let cf = &sh.cf;
            for x in cf.poly.c {
                w.f(x);
            }
            w.u(cf.poly.points as u64);
            w.f(cf.h);
            w.f(cf.v);
            w.f(cf.epoch);
        }
        w.u(self.cellmax.len() as u64);
        for cm in &self.cellmax {
            w.f(cm.value);
            w.f(cm.s);
            w.f(cm.a);
        }
        w.u(self.events.len() as u64);
        for e in &self.events {
            w.z(e.id);
            for x in [
                e.t_start,
                e.t_end,
                e.x_start,
                e.curvature,
                e.x_min,
                e.x_max,
                e.moment,
                e.swept,
            ] {
                w.f(x);
            }
            for x in [
                e.n_births,
                e.n_nucleations,
                e.n_shocks,
                e.n_annihilations,
                e.n_exits,
                e.n_deaths,
                e.n_creep,
            ] {
                w.z(x);
            }
            w.b(e.spontaneous);
        }
        w.u(self.path.len() as u64);
        for p in &self.path {
            w.z(p.shock);
            w.z(p.event);
            w.f(p.t);
            w.f(p.x);
            w.i(p.dir);
            w.f(p.u_plus);
            w.f(p.u_minus);
            w.u(kind_code(p.kind));
            w.b(p.creep);
        }
        if let Some(nz) = &self.noise {
            nz.write_state(&mut w);
        }
        w.0
    }

    /// Restore a state written by [`FreeBoundary::checkpoint`] of an engine with the same
    /// configuration. On error the engine is unchanged.
    pub fn restore(&mut self, bytes: &[u8]) -> Result<()> {
        let mut r = R { b: bytes, i: 0 };
        if r.take(8)? != MAGIC {
            return Err(bad(0, "bytes written by FreeBoundary::checkpoint"));
        }
        let mut fp = W(Vec::new());
        self.fingerprint(&mut fp);
        if r.take(fp.0.len())? != fp.0.as_slice() {
            return Err(bad(
                8,
                "a checkpoint of a free boundary run with the same grid (x0, h, nodes), \
                 boundary, gamma, v, creep rule, tol, record_path, noise (law, rate, \
                 parameters, seed), front-speed law (table) and threshold field",
            ));
        }
        let n = self.field.n;
        let nc = self.field.n_cells();
        let mut field = self.field.clone();
        field.epoch = r.f()?;
        field.b = r.fs()?;
        field.prev = r.fs()?;
        field.reset_by = r.zs()?;
        let reset_stamp = r.us()?;
        let prev_stamp = r.us()?;
        if [
            field.b.len(),
            field.prev.len(),
            field.reset_by.len(),
            reset_stamp.len(),
            prev_stamp.len(),
        ]
        .iter()
        .any(|&k| k != n)
        {
            return Err(bad(r.i, "node arrays of one value per grid node"));
        }
        let stamp = r.u()?;
        let next_id = r.z()?;
        let now = r.f()?;
        let steps = r.u()?;
        let open = r.z()?;
        let open = (open != NONE).then_some(open);
        let n_shocks = r.len(8)?;
        let mut shocks = Vec::with_capacity(n_shocks);
        for _ in 0..n_shocks {
            let id = r.z()?;
            let dir = r.dir()?;
            let cell = r.z()?;
            let event = r.z()?;
            let born = r.b()?;
            let sstamp = r.u()?;
            let (xl_unw, last_x_unw, last_a) = (r.f()?, r.f()?, r.f()?);
            let _position_now = r.f()?;
            let s_start = r.f()?;
            let tdir = r.dir()?;
            let end = match r.u()? {
                0 => TrajEnd::Node,
                1 => TrajEnd::Threshold,
                _ => return Err(bad(r.i, "a well-formed checkpoint (trajectory end)")),
            };
            let k = r.len(24)?;
            if k == 0 {
                return Err(bad(r.i, "trajectories with at least one point"));
            }
            let mut pts = Vec::with_capacity(k);
            for _ in 0..k {
                pts.push(TrajPoint {
                    y: r.f()?,
                    t: r.f()?,
                    f: r.f()?,
                });
            }
            let c = [r.f()?, r.f()?, r.f()?, r.f()?];
            let points = r.z()?;
            if !(1..=4).contains(&points) {
                return Err(bad(r.i, "cell interpolants through 1 to 4 nodes"));
            }
            let (h, v, epoch) = (r.f()?, r.f()?, r.f()?);
            if cell >= nc || id >= next_id {
                return Err(bad(r.i, "shocks in the grid's cells with known ids"));
            }
            shocks.push(ShockState {
                id,
                dir,
                cell,
                traj: Trajectory {
                    s_start,
                    dir: tdir,
                    pts,
                    end,
                },
                cf: CellField {
                    poly: CellPoly { c, points },
                    // (derived from the threshold field: set below)
                    thr: None,
                    h,
                    v,
                    epoch,
                },
                event,
                born,
                stamp: sstamp,
                xl_unw,
                last_x_unw,
                last_a,
                pos: super::PositionCache::empty(),
            });
        }
        if r.len(24)? != nc {
            return Err(bad(r.i, "one maximum per cell of the grid"));
        }
        let mut cellmax = Vec::with_capacity(nc);
        for _ in 0..nc {
            cellmax.push(CellMax {
                value: r.f()?,
                s: r.f()?,
                a: r.f()?,
            });
        }
        let n_events = r.len(17 * 8)?;
        let mut events = Vec::with_capacity(n_events);
        for _ in 0..n_events {
            let id = r.z()?;
            let fl = [
                r.f()?,
                r.f()?,
                r.f()?,
                r.f()?,
                r.f()?,
                r.f()?,
                r.f()?,
                r.f()?,
            ];
            let ints = [r.z()?, r.z()?, r.z()?, r.z()?, r.z()?, r.z()?, r.z()?];
            let spontaneous = r.b()?;
            events.push(FbEvent {
                id,
                t_start: fl[0],
                t_end: fl[1],
                x_start: fl[2],
                curvature: fl[3],
                x_min: fl[4],
                x_max: fl[5],
                moment: fl[6],
                swept: fl[7],
                n_births: ints[0],
                n_nucleations: ints[1],
                spontaneous,
                n_shocks: ints[2],
                n_annihilations: ints[3],
                n_exits: ints[4],
                n_deaths: ints[5],
                n_creep: ints[6],
            });
        }
        if open.is_some_and(|e| e >= events.len()) || shocks.iter().any(|s| s.event >= events.len())
        {
            return Err(bad(r.i, "shocks and the open event in the catalog"));
        }
        let n_path = r.len(9 * 8)?;
        let mut path = Vec::with_capacity(n_path);
        for _ in 0..n_path {
            let (shock, event, t, x) = (r.z()?, r.z()?, r.f()?, r.f()?);
            let dir = r.dir()?;
            let (u_plus, u_minus) = (r.f()?, r.f()?);
            let code = r.u()?;
            let kind = *KINDS
                .get(code as usize)
                .ok_or_else(|| bad(r.i, "a well-formed checkpoint (path kind)"))?;
            let creep = r.b()?;
            path.push(PathPoint {
                shock,
                event,
                t,
                x,
                dir,
                u_plus,
                u_minus,
                kind,
                creep,
            });
        }
        let mut noise = self.noise.clone();
        if let Some(nz) = noise.as_mut() {
            nz.read_state(&mut r)?;
        }
        if r.i != bytes.len() {
            return Err(bad(r.i, "a checkpoint with nothing after its end"));
        }
        let mut tree = MaxTree::new(nc);
        for (j, cm) in cellmax.iter().enumerate() {
            tree.set(j, cm.value);
        }
        self.field = field;
        self.reset_stamp = reset_stamp;
        self.prev_stamp = prev_stamp;
        self.stamp = stamp;
        self.shocks = shocks;
        for i in 0..self.shocks.len() {
            self.shocks[i].cf.thr = self.thr_poly(self.shocks[i].cell);
        }
        self.next_id = next_id;
        self.now = now;
        self.cellmax = cellmax;
        self.tree = tree;
        self.events = events;
        self.open = open;
        self.path = path;
        self.steps = steps;
        self.noise = noise;
        self.rebuild_schedule();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Options, Stop};
    use super::*;

    fn opts(boundary: Boundary) -> Options {
        Options {
            gamma: 0.3,
            v: 1e-2,
            boundary,
            ..Default::default()
        }
    }

    /// A smooth deterministic field with several maxima below 1.
    fn field(n: usize, h: f64) -> Vec<f64> {
        let l = n as f64 * h;
        let tau = std::f64::consts::TAU;
        (0..n)
            .map(|k| {
                let x = k as f64 * h;
                0.6 + 0.12 * (tau * x / l * 3.0 + 0.4).sin()
                    + 0.07 * (tau * x / l * 7.0 + 1.3).cos()
                    + 0.03 * (tau * x / l * 11.0 + 2.1).sin()
            })
            .collect()
    }

    fn same(a: &FreeBoundary, b: &FreeBoundary) {
        assert_eq!(a.now.to_bits(), b.now.to_bits());
        assert_eq!(a.steps, b.steps);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.u_nodes()), bits(&b.u_nodes()));
        assert_eq!(bits(&a.field.b), bits(&b.field.b));
        assert_eq!(bits(&a.field.prev), bits(&b.field.prev));
        assert_eq!(a.field.reset_by, b.field.reset_by);
        // every field, bit for bit (NaN-aware: the debug text of the values)
        assert_eq!(format!("{:?}", a.shocks()), format!("{:?}", b.shocks()));
        assert_eq!(format!("{:?}", a.events), format!("{:?}", b.events));
        assert_eq!(format!("{:?}", a.path), format!("{:?}", b.path));
        assert_eq!(a.checkpoint(), b.checkpoint());
    }

    /// Run `chunk` steps at a time to `t_end`; at each of several cuts (spread over the
    /// run) checkpoint into a fresh engine built from another initial field and continue
    /// it; compare with the uninterrupted run. Returns how many cuts had live shocks.
    fn continued_equals_uninterrupted(boundary: Boundary, chunk: u64) -> usize {
        let (n, h) = (300, 0.5);
        let u0 = field(n, h);
        let t_end = 600.0;
        let make = |u: &[f64]| FreeBoundary::new(-3.0, h, u, opts(boundary), &[]).unwrap();
        let mut reference = make(&u0);
        while reference.advance(t_end, chunk, usize::MAX).unwrap() == Stop::Steps {}
        assert!(
            reference.completed_events() >= 3,
            "{}",
            reference.events.len()
        );
        let chunks = (reference.steps / chunk) as usize;
        assert!(chunks >= 20, "{chunks}");
        let mut with_shocks = 0;
        for q in 1..10 {
            let cut = q * chunks / 10;
            let mut first = make(&u0);
            for _ in 0..cut {
                assert_eq!(
                    first.advance(t_end, chunk, usize::MAX).unwrap(),
                    Stop::Steps
                );
            }
            with_shocks += usize::from(!first.shocks.is_empty());
            let bytes = first.checkpoint();
            let mut second = make(&vec![0.1; n]);
            second.restore(&bytes).unwrap();
            same(&first, &second);
            while second.advance(t_end, chunk, usize::MAX).unwrap() == Stop::Steps {}
            same(&reference, &second);
        }
        with_shocks
    }

    #[test]
    fn restored_run_equals_the_uninterrupted_one_with_live_shocks() {
        let with_shocks = continued_equals_uninterrupted(Boundary::Free, 37);
        assert!(with_shocks >= 3, "{with_shocks}");
    }

    #[test]
    fn restored_run_on_a_ring_equals_the_uninterrupted_one() {
        let with_shocks = continued_equals_uninterrupted(Boundary::Periodic, 29);
        assert!(with_shocks >= 3, "{with_shocks}");
    }

    #[test]
    fn restore_refuses_other_configurations_and_bad_bytes() {
        let u0 = field(100, 0.5);
        let mut a = FreeBoundary::new(0.0, 0.5, &u0, opts(Boundary::Free), &[]).unwrap();
        a.advance(40.0, 50, usize::MAX).unwrap();
        let bytes = a.checkpoint();
        let before = |f: &FreeBoundary| f.checkpoint();
        for other in [
            FreeBoundary::new(0.0, 0.5, &u0, opts(Boundary::Periodic), &[]).unwrap(),
            FreeBoundary::new(0.0, 0.25, &u0, opts(Boundary::Free), &[]).unwrap(),
            FreeBoundary::new(0.0, 0.5, &u0[..99], opts(Boundary::Free), &[]).unwrap(),
            FreeBoundary::new(
                0.0,
                0.5,
                &u0,
                Options {
                    creep: CreepRule::Stop,
                    ..opts(Boundary::Free)
                },
                &[],
            )
            .unwrap(),
        ] {
            let mut other = other;
            let keep = before(&other);
            let e = other.restore(&bytes).unwrap_err();
            assert!(matches!(
                e,
                crate::error::Error::InvalidParameter {
                    name: "checkpoint",
                    ..
                }
            ));
            assert_eq!(before(&other), keep);
        }
        let mut b = FreeBoundary::new(0.0, 0.5, &u0, opts(Boundary::Free), &[]).unwrap();
        let keep = b.checkpoint();
        assert!(b.restore(&bytes[..bytes.len() - 3]).is_err());
        assert!(b.restore(b"BKCHAIN1").is_err());
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(b.restore(&longer).is_err());
        assert_eq!(b.checkpoint(), keep);
        b.restore(&bytes).unwrap();
        same(&a, &b);
    }
}
