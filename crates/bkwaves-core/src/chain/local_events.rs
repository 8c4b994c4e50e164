//! Events whose cost is local: a switch redoes the step of its neighbourhood only
//! (issue 25; docs/lattice.md, "Local events").
//!
//! The global engine ([`super::Engine::integrate_step`]) locates the earliest switch of
//! a step, redoes the step of every sliding block up to it and goes on from there: an
//! expanding rupture over N x N blocks costs (switches ~ N^2) x (sliding ~ N) block-steps.
//! Here a step of length h is taken for every sliding block; only the blocks near a
//! switch are redone, with their own sub-steps cut at their own events.
//!
//! Why that is exact to the step's order (the light cone of the discrete system): a block
//! that slips or sticks at t_e has u and u_t continuous there; only u_tt jumps, by J.
//! Against the trajectory without the switch, the block itself moves by J (t - t_e)^2/2,
//! a neighbour (whose u_tt reads the block's u over dx^2) by J (t - t_e)^4/(24 dx^2), a
//! block at lattice distance d by J (t - t_e)^(2d+2)/((2d+2)! dx^(2d)). Within a step
//! (t - t_e <= h = `step` dx) the distance-1 neighbours move by O(h^2 (h/dx)^2), more
//! than RK4's local error O(h^2 (h/dx)^3) (u varies on the time scale dx), and the
//! distance-2 blocks by O(h^2 (h/dx)^4), less. So a switch needs its block and its
//! neighbours redone ("members"); the rest of the lattice may be stepped through it.
//!
//! One step from t0 to t1 = t0 + h:
//!
//! 1. every run of sliding blocks is stepped by RK4 (the global pass) and every switch
//!    in (t0, t1] is located on its dense output ([`Engine::detect_all`]);
//! 2. the members: each switching block and its four neighbours (stuck ones included),
//!    grouped into components (two members in one component if they are neighbours or
//!    share a neighbour, so a stuck block next to members sees one component only);
//! 3. each component is integrated over [t0, t1] by RK4 with its own sub-steps (the two
//!    halves of the step, cut at every event located in them, applied at its time),
//!    its neighbours outside read from the global pass through their quintic Hermite
//!    interpolant (u, u_t, u_tt at both ends; error O(h^6 u^(6)) = O(h^2 (h/dx)^4), the
//!    order of the light cone's); a stuck block next to the component that crosses its
//!    threshold, or a switch with a sliding neighbour outside, grows the component and
//!    redoes it;
//! 4. the run blocks near the members are stepped again ([`Engine::later_pass`]: within
//!    4 hops, from the start state the first pass saved; a block 3 or more hops from
//!    every member would end the pass with the first pass's values to the bit), reading
//!    the members' values at the stage times (t0 + h/2, t1) from the components
//!    (`State::ext`), and the switches near the members are located again: a new one (a
//!    crossing the first pass did not see) adds members and goes back to 3;
//! 5. the books are the runs' plus the components', the switches are entered in the
//!    catalog in time order, and the state is at t1.
//!
//! A step without switches is the global engine's step, to the bit. The cost of a step
//! with switches is one pass over the sliding blocks, a second over the few near its
//! switches, and the components' sub-steps,
//! (switch count) x (a few blocks) x (a few sub-steps): O(area) for a rupture, not
//! O(area x perimeter). The global engine stays selectable
//! ([`Engine::set_local_events`]); an engine starts with the global cut, and the Python
//! `bk.Lattice` and lattice configs choose local events where they apply (the chain
//! keeps the global cut; docs/lattice.md, "Local events").

use super::events::{self, Hermite};
use super::geometry::{Beyond, Geometry};
use super::integrator::{StepIntegrals, Stepper};
use super::medium::{Blocks, Medium};
use super::sources::Cause;
use super::state::State;
use super::Engine;
use crate::error::{Error, Result};
use crate::friction::Friction;

const NONE: u32 = u32::MAX;

/// Most rounds (components grown, runs redone) in one step before the step falls back
/// to the global engine's cut.
const MAX_ROUNDS: usize = 64;

/// The later passes over the runs step only the blocks within this many hops of a member
/// ([`Engine::later_pass`]): 2 hops where their result can differ from the first pass's,
/// 2 more for the reach of the stale values just outside.
const NEAR: u8 = 4;

/// A cell more than NEAR hops from every member (0: the map starts as zero pages, only
/// those written near members become resident).
const UNSEEN: u8 = 0;
/// A cell within NEAR hops of a member.
const SEEN: u8 = 1;

/// The plain forms of the shortcuts, for the tests that check that the shortcuts give
/// the same bits.
#[cfg(test)]
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Plain {
    /// The later passes over every run, not only near the members.
    pub whole_pass: bool,
    /// Every sliding block's acceleration recomputed after a step with switches.
    pub all_accel: bool,
    /// The runs copied back to the step's start before a later pass.
    pub copy_back: bool,
}

/// A switch applied inside a component, for the catalog.
#[derive(Debug, Clone, Copy)]
struct Rec {
    t: f64,
    p: usize,
    u: f64,
    kind: RecKind,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum RecKind {
    /// Slip in this direction.
    Slip(i8),
    /// Stick.
    Stick,
    /// Slides on in the other direction (a stick and a slip in the catalog).
    Reverse(i8),
}

/// The outcome of integrating a component.
enum Outcome {
    Done,
    /// These blocks must become members (with their neighbours) first.
    Grow(Vec<usize>),
}

/// One component: its members and the result of its integration.
#[derive(Debug, Clone, Default)]
struct Comp {
    /// Members (padded indices, sorted).
    blocks: Vec<usize>,
    /// Stuck blocks next to the members that are not members (watched for slips).
    watch: Vec<usize>,
    /// Is the result valid (integrated since the members last changed)?
    done: bool,
    // state during and after the integration (per member)
    dir: Vec<f64>,
    onset: Vec<f64>,
    u: Vec<f64>,
    w: Vec<f64>,
    uref: Vec<f64>,
    tref: Vec<f64>,
    /// u at t0 + h/2 and at t1.
    mid: Vec<f64>,
    end: Vec<f64>,
    /// Dense output: knot times, per knot u and u_t of every member (knot j member k at
    /// j * n + k).
    kt: Vec<f64>,
    ku: Vec<f64>,
    kw: Vec<f64>,
    books: StepIntegrals,
    projection: f64,
    recs: Vec<Rec>,
    block_steps: u64,
    substeps: u64,
}

/// The working arrays of one component's integration (per member), kept between
/// components and steps so that a component allocates nothing.
#[derive(Debug, Clone, Default)]
struct Scratch {
    su: Vec<f64>,
    sw: Vec<f64>,
    su0: Vec<f64>,
    sw0: Vec<f64>,
    sum_u: Vec<f64>,
    sum_w: Vec<f64>,
    acc0: Vec<f64>,
    acc: Vec<f64>,
    grow: Vec<usize>,
    who: Vec<(usize, i8)>,
    list: Vec<(usize, i8)>,
    cands: Vec<usize>,
}

impl Scratch {
    /// Every per-member array at n zeros, the lists empty.
    fn reset(&mut self, n: usize) {
        for a in [
            &mut self.su,
            &mut self.sw,
            &mut self.su0,
            &mut self.sw0,
            &mut self.sum_u,
            &mut self.sum_w,
            &mut self.acc0,
            &mut self.acc,
        ] {
            a.clear();
            a.resize(n, 0.0);
        }
        self.grow.clear();
        self.who.clear();
        self.list.clear();
    }
}

/// The local-event machinery of an engine (not part of the state: rebuilt every step).
#[derive(Debug, Clone, Default)]
pub(crate) struct Local {
    /// Selected (see [`Engine::set_local_events`]).
    pub on: bool,
    /// Member index of each padded cell (NONE: not a member); sized on first use.
    mem_of: Vec<u32>,
    /// Members (padded), their component, their mode and threshold at t0.
    members: Vec<usize>,
    mcomp: Vec<u32>,
    dir0: Vec<f64>,
    onset0: Vec<f64>,
    /// Was the member sliding at t0 and taken out of the runs / marked for the passes?
    out: Vec<bool>,
    comps: Vec<Comp>,
    /// Per member: its position in its component's `blocks` (set by `group`).
    pos: Vec<u32>,
    /// Components of earlier steps kept for their buffers (no allocation per component).
    pool: Vec<Comp>,
    /// The buffers of one component's integration, reused.
    scratch: Scratch,
    /// Whether the last step's components hold the dense output of its members.
    dense_valid: bool,
    /// The later pass's region ([`Engine::later_pass`]): the cells within NEAR hops of a
    /// member (sorted), the last layer found and the next, the run blocks among them
    /// as runs, those 3 or 4 hops away, and their values after the first pass.
    /// Per padded cell, SEEN if within NEAR hops of a member, else UNSEEN; sized on
    /// first use; `seen` the cells marked.
    hop: Vec<u8>,
    seen: Vec<usize>,
    layer: Vec<usize>,
    next: Vec<usize>,
    near: Vec<usize>,
    near_runs: Vec<(usize, usize)>,
    band: Vec<usize>,
    /// The stuck blocks within 3 hops of a member next to a run (the later pass's
    /// search for slips).
    near_stuck: Vec<usize>,
    saved: Vec<f64>,
    /// The plain forms of the shortcuts (tests).
    #[cfg(test)]
    pub(crate) plain: Plain,
    /// Counters: steps with switches, rounds, fallbacks to the global cut.
    pub stats: LocalStats,
}

/// What the local events did (not part of the state).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LocalStats {
    /// Steps with switches.
    pub event_steps: u64,
    /// Passes over the runs (two per step with switches, more when a component grows).
    pub passes: u64,
    /// Component integrations.
    pub components: u64,
    /// Steps handed to the global cut (too many rounds).
    pub fallbacks: u64,
    /// Block-steps of the runs' passes in steps without switches.
    pub quiet_block_steps: u64,
    /// Block-steps of the runs' first passes in steps with switches.
    pub first_block_steps: u64,
    /// Block-steps of the runs' later passes (the second, and more when a component
    /// grows), the members out.
    pub later_block_steps: u64,
    /// Block-steps of the components' sub-steps (of the components committed).
    pub component_block_steps: u64,
    /// The components' sub-steps (of the components committed).
    pub component_substeps: u64,
    /// Members, summed over the steps with switches.
    pub members: u64,
}

/// The global pass's data of a sliding block over [t0, t0 + h]: its quintic Hermite
/// interpolant.
#[derive(Clone, Copy)]
struct RunData<'a> {
    t0: f64,
    h: f64,
    u0: &'a [f64],
    w0: &'a [f64],
    a0: &'a [f64],
    u1: &'a [f64],
    w1: &'a [f64],
    a1: &'a [f64],
}

impl RunData<'_> {
    /// u and u_t of run block r at time t (the quintic Hermite interpolant).
    #[inline]
    fn at(&self, r: usize, t: f64) -> (f64, f64) {
        let h = self.h;
        if h <= 0.0 {
            return (self.u1[r], self.w1[r]);
        }
        let s = ((t - self.t0) / h).clamp(0.0, 1.0);
        let (s2, s3) = (s * s, s * s * s);
        let (s4, s5) = (s3 * s, s3 * s2);
        let h00 = 1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5;
        let h10 = s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5;
        let h20 = 0.5 * (s2 - 3.0 * s3 + 3.0 * s4 - s5);
        let h01 = 10.0 * s3 - 15.0 * s4 + 6.0 * s5;
        let h11 = -4.0 * s3 + 7.0 * s4 - 3.0 * s5;
        let h21 = 0.5 * (s3 - 2.0 * s4 + s5);
        // derivatives in s
        let d00 = -30.0 * s2 + 60.0 * s3 - 30.0 * s4;
        let d10 = 1.0 - 18.0 * s2 + 32.0 * s3 - 15.0 * s4;
        let d20 = 0.5 * (2.0 * s - 9.0 * s2 + 12.0 * s3 - 5.0 * s4);
        let d01 = -d00;
        let d11 = -12.0 * s2 + 28.0 * s3 - 15.0 * s4;
        let d21 = 0.5 * (3.0 * s2 - 8.0 * s3 + 5.0 * s4);
        let (y0, y1) = (self.u0[r], self.u1[r]);
        let (d0, d1) = (h * self.w0[r], h * self.w1[r]);
        let (c0, c1) = (h * h * self.a0[r], h * h * self.a1[r]);
        let u = h00 * y0 + h10 * d0 + h20 * c0 + h01 * y1 + h11 * d1 + h21 * c1;
        let du = d00 * y0 + d10 * d0 + d20 * c0 + d01 * y1 + d11 * d1 + d21 * c1;
        (u, du / h)
    }
}

/// What a component sees of the engine while it is integrated.
struct Ctx<'a, G: Geometry, F: Friction, M: Medium> {
    st: &'a State<G>,
    blk: &'a Blocks<F, M>,
    run: RunData<'a>,
    mem_of: &'a [u32],
    /// Per member: its position in its component's blocks.
    pos: &'a [u32],
    members: &'a [usize],
    dir0: &'a [f64],
    onset0: &'a [f64],
}

impl<G: Geometry, F: Friction, M: Medium> Ctx<'_, G, F, M> {
    /// The slot in `c` of padded block r, if it is one of c's members.
    #[inline]
    fn slot(&self, c: &Comp, r: usize) -> Option<usize> {
        let m = self.mem_of[r];
        if m == NONE {
            return None;
        }
        // (a member's position in its own component: c's slot if c is that component)
        let k = self.pos[m as usize] as usize;
        (c.blocks.get(k) == Some(&r)).then_some(k)
    }

    /// u and u_t of real block r at time t: a member of c from (su, sw) (stuck members
    /// by their drift), a sliding block from the global pass, a stuck one by its drift.
    #[inline]
    fn value(&self, c: &Comp, su: &[f64], sw: &[f64], r: usize, t: f64) -> (f64, f64) {
        let v = self.st.v;
        if let Some(k) = self.slot(c, r) {
            if c.dir[k] != 0.0 {
                return (su[k], sw[k]);
            }
            return (c.uref[k] + v * (t - c.tref[k]), v);
        }
        debug_assert!(self.mem_of[r] == NONE, "a member of another component");
        if self.st.sliding(r) {
            return self.run.at(r, t);
        }
        (self.st.stuck_u(r, t), v)
    }

    /// u and u_t of the neighbour cell q of block p at time t.
    #[inline]
    fn nbr(&self, c: &Comp, su: &[f64], sw: &[f64], q: usize, p: usize, t: f64) -> (f64, f64) {
        let v = self.st.v;
        let r = if self.st.geo.is_ghost(q) {
            match self.st.geo.beyond(q, p) {
                Beyond::Block(r) => r,
                Beyond::Wall(g0) => return (g0 + v * t, v),
            }
        } else {
            q
        };
        self.value(c, su, sw, r, t)
    }

    /// Accelerations of the sliding members at stage values (su, sw), time t (0 for
    /// stuck members, whose su must hold their drift at t).
    fn accel(&self, c: &Comp, su: &[f64], sw: &[f64], t: f64, out: &mut [f64]) {
        let v = self.st.v;
        for (k, &p) in c.blocks.iter().enumerate() {
            if c.dir[k] == 0.0 {
                out[k] = 0.0;
                continue;
            }
            let f = self
                .st
                .geo
                .force(&self.blk.med, p, su[k], |q| self.nbr(c, su, sw, q, p, t).0);
            out[k] = self.blk.accel(p, su[k], f, v - sw[k], c.dir[k], c.onset[k]);
        }
    }

    /// phi of block p (a member or a watched block) at time t from the members' current
    /// values (u, w) and the outside.
    fn phi(&self, c: &Comp, u: &[f64], w: &[f64], p: usize, t: f64) -> f64 {
        let up = self.value(c, u, w, p, t).0;
        let f = self
            .st
            .geo
            .force(&self.blk.med, p, up, |q| self.nbr(c, u, w, q, p, t).0);
        self.blk.phi_of(p, up, f)
    }

    /// The Hermite data of phi of stuck block p over [ta, tb], the members at (ua, wa)
    /// and (ub, wb) at the two ends.
    #[allow(clippy::too_many_arguments)]
    fn phi_hermite(
        &self,
        c: &Comp,
        ua: &[f64],
        wa: &[f64],
        ub: &[f64],
        wb: &[f64],
        p: usize,
        ta: f64,
        tb: f64,
    ) -> Hermite {
        let herm = |r: usize| {
            let (g0, m0) = self.value(c, ua, wa, r, ta);
            let (g1, m1) = self.value(c, ub, wb, r, tb);
            Hermite { g0, m0, g1, m1 }
        };
        let v = self.st.v;
        self.st.geo.phi_hermite(&self.blk.med, p, herm(p), |q| {
            if self.st.geo.is_ghost(q) {
                match self.st.geo.beyond(q, p) {
                    Beyond::Block(r) => herm(r),
                    Beyond::Wall(g0) => Hermite {
                        g0: g0 + v * ta,
                        m0: v,
                        g1: g0 + v * tb,
                        m1: v,
                    },
                }
            } else {
                herm(q)
            }
        })
    }

    /// Is p stuck now (a member by its component's mode, else by the engine's)?
    #[inline]
    fn stuck(&self, c: &Comp, p: usize) -> bool {
        match self.slot(c, p) {
            Some(k) => c.dir[k] == 0.0,
            None => !self.st.sliding(p),
        }
    }

    /// If p's switch needs blocks that are not members of c (p itself, or a sliding
    /// neighbour of p outside c): those blocks.
    fn needs(&self, c: &Comp, p: usize, grow: &mut Vec<usize>) {
        if self.slot(c, p).is_none() {
            grow.push(p);
            return;
        }
        for q in self.st.geo.neighbours(p) {
            if let Some(r) = self.st.resolve(q) {
                if self.slot(c, r).is_none() && self.st.sliding(r) && self.mem_of[r] == NONE {
                    grow.push(p);
                    return;
                }
            }
        }
    }
}

/// Integrate component `c` over [t0, t0 + h] (module docs, step 3).
fn integrate<G: Geometry, F: Friction, M: Medium>(
    cx: &Ctx<G, F, M>,
    c: &mut Comp,
    t0: f64,
    h: f64,
    sc: &mut Scratch,
) -> Outcome {
    let st = cx.st;
    let v = st.v;
    let n = c.blocks.len();
    // start values
    for v_ in [
        &mut c.dir,
        &mut c.onset,
        &mut c.u,
        &mut c.w,
        &mut c.uref,
        &mut c.tref,
        &mut c.mid,
        &mut c.end,
    ] {
        v_.clear();
        v_.resize(n, 0.0);
    }
    for (k, &p) in c.blocks.iter().enumerate() {
        let m = cx.mem_of[p] as usize;
        debug_assert_eq!(cx.members[m], p);
        c.dir[k] = cx.dir0[m];
        c.onset[k] = cx.onset0[m];
        if c.dir[k] != 0.0 {
            c.u[k] = cx.run.u0[p];
            c.w[k] = cx.run.w0[p];
        } else {
            c.uref[k] = st.u[p];
            c.tref[k] = st.tref[p];
            c.u[k] = st.stuck_u(p, t0);
            c.w[k] = v;
        }
    }
    c.kt.clear();
    c.ku.clear();
    c.kw.clear();
    c.books = StepIntegrals::default();
    c.projection = 0.0;
    c.recs.clear();
    c.block_steps = 0;
    c.substeps = 0;
    sc.reset(n);
    let Scratch {
        su,
        sw,
        su0,
        sw0,
        sum_u,
        sum_w,
        acc0,
        acc,
        grow,
        who,
        list: spare,
        cands,
    } = sc;
    cx.accel(c, &c.u, &c.w, t0, acc0);
    c.kt.push(t0);
    c.ku.extend_from_slice(&c.u);
    c.kw.extend_from_slice(&c.w);
    let t1 = t0 + h;
    let tm = t0 + 0.5 * h;
    let mut t = t0;
    for seg in 0..2 {
        let t_end = if seg == 0 { tm } else { t1 };
        let mut guard = 0usize;
        while t < t_end {
            guard += 1;
            if guard > 64 * (n + 4) {
                // a component that does not get through its half step: the global cut
                return Outcome::Grow(Vec::new());
            }
            let mut hs = t_end - t;
            su0.copy_from_slice(&c.u);
            sw0.copy_from_slice(&c.w);
            let mut b = rk4_substep(cx, c, su0, sw0, acc0, t, hs, su, sw, sum_u, sum_w, acc);
            // the earliest event of the sub-step, on its dense output
            let s = detect(cx, c, su0, sw0, acc0, acc, t, hs, who);
            if s < 1.0 {
                // redo it up to the event (which is then at its end)
                hs *= s;
                b = rk4_substep(cx, c, su0, sw0, acc0, t, hs, su, sw, sum_u, sum_w, acc);
            }
            let sliding = c.dir.iter().filter(|&&d| d != 0.0).count() as u64;
            c.block_steps += sliding;
            c.substeps += 1;
            c.books.u += b.u;
            c.books.dry += b.dry;
            c.books.visc += b.visc;
            let te = if t + hs >= t_end { t_end } else { t + hs };
            t = te;
            // events at te, then everything due at te (the settling of the engine)
            if !who.is_empty() {
                // the events in `spare`, `who` empty for the next sub-step
                spare.clear();
                std::mem::swap(who, spare);
                loop {
                    for &(p, kind) in spare.iter() {
                        apply(cx, c, p, kind, te, acc, grow);
                    }
                    if !grow.is_empty() {
                        return Outcome::Grow(std::mem::take(grow));
                    }
                    cx.accel(c, &c.u, &c.w, te, acc);
                    spare.clear();
                    due(cx, c, te, acc, spare, cands);
                    if spare.is_empty() {
                        break;
                    }
                }
            }
            std::mem::swap(acc0, acc);
            c.kt.push(t);
            c.ku.extend_from_slice(&c.u);
            c.kw.extend_from_slice(&c.w);
        }
        // members' u at the segment's end (stuck ones by their drift)
        let out = if seg == 0 { &mut c.mid } else { &mut c.end };
        for k in 0..n {
            out[k] = if c.dir[k] != 0.0 {
                c.u[k]
            } else {
                c.uref[k] + v * (t - c.tref[k])
            };
        }
    }
    c.done = true;
    Outcome::Done
}

/// One RK4 sub-step of the sliding members from (su0, sw0) at t over hs (stuck members
/// drift); the end values go to (c.u, c.w), the end accelerations to `acc`; returns the
/// sub-step's energy flows (the loader displacement of every member, stuck ones by
/// their drift, and the friction powers of the sliding ones).
#[allow(clippy::too_many_arguments)]
fn rk4_substep<G: Geometry, F: Friction, M: Medium>(
    cx: &Ctx<G, F, M>,
    c: &mut Comp,
    su0: &[f64],
    sw0: &[f64],
    acc0: &[f64],
    t: f64,
    hs: f64,
    su: &mut [f64],
    sw: &mut [f64],
    sum_u: &mut [f64],
    sum_w: &mut [f64],
    acc: &mut [f64],
) -> StepIntegrals {
    let st = cx.st;
    let blk = cx.blk;
    let v = st.v;
    let n = c.blocks.len();
    let hh = 0.5 * hs;
    let tm = t + hh;
    let t_next = t + hs;
    let drift = |c: &Comp, k: usize, ts: f64| c.uref[k] + v * (ts - c.tref[k]);
    let power = |c: &Comp, su: &[f64], sw: &[f64], wt: f64, b: &mut StepIntegrals| {
        for (k, &p) in c.blocks.iter().enumerate() {
            b.u += wt * blk.med.loader(p) * su[k];
            if c.dir[k] != 0.0 {
                let (pd, pv) = blk.fr.power(v - sw[k], c.dir[k], c.onset[k]);
                b.dry += wt * pd;
                b.visc += wt * pv;
            }
        }
    };
    let mut b = StepIntegrals::default();
    // stage 1 at t
    for k in 0..n {
        if c.dir[k] == 0.0 {
            su[k] = drift(c, k, t);
            sw[k] = v;
        } else {
            su[k] = su0[k];
            sw[k] = sw0[k];
        }
    }
    power(c, su, sw, 1.0, &mut b);
    for k in 0..n {
        sum_u[k] = sw0[k];
        sum_w[k] = acc0[k];
        if c.dir[k] == 0.0 {
            su[k] = drift(c, k, tm);
            sw[k] = v;
        } else {
            su[k] = su0[k] + hh * sw0[k];
            sw[k] = sw0[k] + hh * acc0[k];
        }
    }
    // stages 2 and 3 at tm (weight 2), stage 4 at t_next (weight 1); tn: the next
    // stage's time
    for (ch, wt, ts, tn) in [
        (hh, 2.0, tm, tm),
        (hs, 2.0, tm, t_next),
        (0.0, 1.0, t_next, t_next),
    ] {
        cx.accel(c, su, sw, ts, acc);
        power(c, su, sw, wt, &mut b);
        for k in 0..n {
            if c.dir[k] == 0.0 {
                continue;
            }
            let (du, dw) = (sw[k], acc[k]);
            sum_u[k] += wt * du;
            sum_w[k] += wt * dw;
            if wt == 2.0 {
                su[k] = su0[k] + ch * du;
                sw[k] = sw0[k] + ch * dw;
            }
        }
        if wt == 2.0 {
            for k in 0..n {
                if c.dir[k] == 0.0 {
                    su[k] = drift(c, k, tn);
                }
            }
        }
    }
    let h6 = hs / 6.0;
    for k in 0..n {
        if c.dir[k] == 0.0 {
            c.u[k] = drift(c, k, t_next);
            c.w[k] = v;
        } else {
            c.u[k] = su0[k] + h6 * sum_u[k];
            c.w[k] = sw0[k] + h6 * sum_w[k];
        }
    }
    cx.accel(c, &c.u, &c.w, t_next, acc);
    StepIntegrals {
        u: h6 * b.u,
        dry: h6 * b.dry,
        visc: h6 * b.visc,
    }
}

/// The earliest event in the sub-step [t, t + hs] just taken (s in (0, 1], infinity if
/// none), the blocks at it in `who`: rests of sliding members, slips of stuck members and
/// of the watched blocks.
#[allow(clippy::too_many_arguments)]
fn detect<G: Geometry, F: Friction, M: Medium>(
    cx: &Ctx<G, F, M>,
    c: &Comp,
    u0: &[f64],
    w0: &[f64],
    a0: &[f64],
    a1: &[f64],
    t: f64,
    hs: f64,
    who: &mut Vec<(usize, i8)>,
) -> f64 {
    let v = cx.st.v;
    let mut best = f64::INFINITY;
    who.clear();
    for (k, &p) in c.blocks.iter().enumerate() {
        let d = c.dir[k];
        if d == 0.0 {
            continue;
        }
        let g = Hermite {
            g0: d * (w0[k] - v),
            m0: d * a0[k],
            g1: d * (c.w[k] - v),
            m1: d * a1[k],
        };
        if g.g0 == 0.0 && g.g1 == 0.0 && g.m0 <= 0.0 && g.m1 <= 0.0 {
            continue;
        }
        super::consider(g.first_crossing(hs), (p, 0), &mut best, who);
    }
    let tb = t + hs;
    let stuck_members = c
        .blocks
        .iter()
        .enumerate()
        .filter(|&(k, _)| c.dir[k] == 0.0)
        .map(|(_, &p)| p);
    for p in stuck_members.chain(c.watch.iter().copied()) {
        if !cx.stuck(c, p) {
            continue;
        }
        let phi = cx.phi_hermite(c, u0, w0, &c.u, &c.w, p, t, tb);
        let (lo, hi) = (cx.blk.lower(p), cx.blk.upper(p));
        let fwd = Hermite {
            g0: phi.g0 - hi,
            m0: phi.m0,
            g1: phi.g1 - hi,
            m1: phi.m1,
        };
        super::consider(fwd.first_crossing(hs), (p, 1), &mut best, who);
        let bwd = Hermite {
            g0: lo - phi.g0,
            m0: -phi.m0,
            g1: lo - phi.g1,
            m1: -phi.m1,
        };
        super::consider(bwd.first_crossing(hs), (p, -1), &mut best, who);
    }
    if !best.is_finite() {
        who.clear();
    }
    best
}

/// The switches due at te after the events there (the engine's settling, inside the
/// component): stuck members and watched blocks over a threshold, sliding members back at
/// rest.
fn due<G: Geometry, F: Friction, M: Medium>(
    cx: &Ctx<G, F, M>,
    c: &Comp,
    te: f64,
    acc: &[f64],
    list: &mut Vec<(usize, i8)>,
    cands: &mut Vec<usize>,
) {
    let v = cx.st.v;
    for (k, &p) in c.blocks.iter().enumerate() {
        let d = c.dir[k];
        if d != 0.0 {
            let g = d * (c.w[k] - v);
            if g > 0.0 || (g == 0.0 && d * acc[k] >= 0.0) {
                list.push((p, 0));
            }
        }
    }
    let stuck_members = c
        .blocks
        .iter()
        .enumerate()
        .filter(|&(k, _)| c.dir[k] == 0.0)
        .map(|(_, &p)| p);
    cands.clear();
    cands.extend(stuck_members.chain(c.watch.iter().copied()));
    for &p in cands.iter() {
        if !cx.stuck(c, p) {
            continue;
        }
        let phi = cx.phi(c, &c.u, &c.w, p, te);
        if phi >= cx.blk.upper(p) {
            list.push((p, 1));
        } else if phi <= cx.blk.lower(p) {
            list.push((p, -1));
        }
    }
    // a rest that changes nothing (slides on at u_t = v in the same direction) is not due
    list.retain(|&(p, kind)| {
        if kind != 0 {
            return true;
        }
        let k = c.blocks.binary_search(&p).expect("member");
        let phi = cx.phi(c, &c.u, &c.w, p, te);
        let th = c.onset[k].min(cx.blk.med.threshold(p));
        let (lo, hi) = (cx.blk.fr.lower(th), cx.blk.fr.upper(th));
        if phi > lo && phi < hi {
            return true;
        }
        let dir = if phi >= hi { 1.0 } else { -1.0 };
        !(dir == c.dir[k] && c.w[k] == v)
    });
}

/// Apply the switch (kind 0: rest, +1/-1: slip) of block p at te inside component c (the
/// rules of `Engine::on_rest` and `Engine::slip_at_threshold`); a block that must first
/// become a member is put in `grow`.
fn apply<G: Geometry, F: Friction, M: Medium>(
    cx: &Ctx<G, F, M>,
    c: &mut Comp,
    p: usize,
    kind: i8,
    te: f64,
    _acc: &[f64],
    grow: &mut Vec<usize>,
) {
    let v = cx.st.v;
    let blk = cx.blk;
    cx.needs(c, p, grow);
    if !grow.is_empty() {
        return;
    }
    let k = c.blocks.binary_search(&p).expect("member");
    let phi = cx.phi(c, &c.u, &c.w, p, te);
    if kind == 0 {
        if c.dir[k] == 0.0 {
            return;
        }
        let th = c.onset[k].min(blk.med.threshold(p));
        let (lo, hi) = (blk.fr.lower(th), blk.fr.upper(th));
        let s = v - c.w[k];
        if phi > lo && phi < hi {
            c.projection += 0.5 * blk.med.mass(p) * s * s;
            c.w[k] = v;
            c.dir[k] = 0.0;
            c.uref[k] = c.u[k];
            c.tref[k] = te;
            c.recs.push(Rec {
                t: te,
                p,
                u: c.u[k],
                kind: RecKind::Stick,
            });
        } else {
            let dir = if phi >= hi { 1.0 } else { -1.0 };
            if dir == c.dir[k] && c.w[k] == v {
                return;
            }
            c.projection += 0.5 * blk.med.mass(p) * s * s;
            c.w[k] = v;
            if dir != c.dir[k] {
                c.recs.push(Rec {
                    t: te,
                    p,
                    u: c.u[k],
                    kind: RecKind::Reverse(dir as i8),
                });
                c.onset[k] = blk.fr.onset_threshold(blk.med.threshold(p), phi, dir);
            }
            c.dir[k] = dir;
        }
    } else {
        if c.dir[k] != 0.0 {
            return;
        }
        let u = c.uref[k] + v * (te - c.tref[k]);
        c.u[k] = u;
        c.w[k] = v;
        c.dir[k] = f64::from(kind);
        c.onset[k] = blk
            .fr
            .onset_threshold(blk.med.threshold(p), phi, f64::from(kind));
        c.recs.push(Rec {
            t: te,
            p,
            u,
            kind: RecKind::Slip(kind),
        });
    }
}

impl Local {
    /// u and u_t of block p at time t in the last step, if it was a member (its
    /// component's dense output).
    pub(crate) fn dense(&self, p: usize, t: f64) -> Option<(f64, f64)> {
        if !self.dense_valid || p >= self.mem_of.len() || self.mem_of[p] == NONE {
            return None;
        }
        let m = self.mem_of[p] as usize;
        let c = &self.comps[self.mcomp[m] as usize];
        let k = c.blocks.binary_search(&p).ok()?;
        let (a, b, s, h) = super::onset::knot_interval(&c.kt, c.blocks.len(), k, t)?;
        let hu = Hermite {
            g0: c.ku[a],
            m0: c.kw[a],
            g1: c.ku[b],
            m1: c.kw[b],
        };
        // u_t linear between knots (its slope is not kept)
        let w = c.kw[a] + s * (c.kw[b] - c.kw[a]);
        Some((hu.eval(s, h), w))
    }

    /// Forget the last step's members.
    fn clear(&mut self) {
        for &p in &self.members {
            self.mem_of[p] = NONE;
        }
        self.members.clear();
        self.mcomp.clear();
        self.dir0.clear();
        self.onset0.clear();
        self.out.clear();
        self.pos.clear();
        self.pool.append(&mut self.comps);
        self.dense_valid = false;
    }
}

impl<G: Geometry, F: Friction, M: Medium> Engine<G, F, M> {
    /// Choose how switches are located (before or between runs): `true`, the local events
    /// of this module (a switch redoes its neighbourhood only; `bk.Lattice`'s default);
    /// `false`, the global cut (a switch redoes the step of every sliding block; an
    /// engine's default, and the chain's). Local events need RK4 at a fixed step and a
    /// law without a stiff onset; with the midpoint rule, step-size control or a stiff law
    /// the global cut is used whatever is chosen here
    /// ([`Engine::try_set_local_events`] refuses instead).
    pub fn set_local_events(&mut self, on: bool) {
        self.local.on = on;
    }

    /// Whether local events are chosen ([`Engine::set_local_events`]).
    pub fn local_events(&self) -> bool {
        self.local.on
    }

    /// Take the plain forms of the local events' shortcuts (tests: the same bits).
    #[cfg(test)]
    pub(crate) fn set_local_plain(&mut self, plain: Plain) {
        self.local.plain = plain;
    }

    /// What the local events did so far.
    pub fn local_stats(&self) -> LocalStats {
        self.local.stats
    }

    /// Are the local events used for the next step?
    pub(super) fn local_active(&self) -> bool {
        self.local.on && self.local_events_unavailable().is_none()
    }

    /// Why local events cannot apply to this engine as now set (another integrator, the
    /// step-size control, a law whose onset takes sub-steps); None: they apply.
    pub fn local_events_unavailable(&self) -> Option<&'static str> {
        if self.rk.name() != "rk4" {
            Some("events = \"global\" with integrator = \"midpoint\" (local events need rk4)")
        } else if self.control.is_some() {
            Some(
                "events = \"global\" with a step_tolerance (local events need the fixed \
                 step)",
            )
        } else if self.stiff {
            Some(
                "events = \"global\" for this friction law and step (its onset takes \
                 sub-steps; local events need a law without)",
            )
        } else {
            None
        }
    }

    /// Choose local events (`true`) or the global cut, refusing local events where they
    /// cannot apply ([`Engine::local_events_unavailable`]) instead of falling back.
    pub fn try_set_local_events(&mut self, on: bool) -> Result<()> {
        if on {
            if let Some(allowed) = self.local_events_unavailable() {
                return Err(Error::Invalid {
                    name: "events".to_string(),
                    value: "\"local\"".to_string(),
                    allowed: allowed.to_string(),
                });
            }
        }
        self.local.on = on;
        Ok(())
    }

    /// u and u_t of block p at time t of the last step if it was redone locally.
    pub(super) fn local_dense(&self, p: usize, t: f64) -> Option<(f64, f64)> {
        self.local.dense(p, t)
    }

    /// Every switch in the step [t0, t0 + h] just taken by the runs: the blocks that come
    /// to rest and the stuck blocks next to the runs that cross a threshold (not those
    /// next to a member: their component watches them), appended to `out`. With `near`
    /// (after a later pass near the members, [`Engine::later_pass`]) only the run blocks
    /// within NEAR hops of a member and the stuck blocks within 3 hops are searched: the
    /// others' data (their own and their neighbours') are the first pass's, to the bit,
    /// in which they had no switch (every block with one is a member).
    fn detect_all(
        &self,
        t0: f64,
        h: f64,
        cands: &mut Vec<usize>,
        out: &mut Vec<usize>,
        near: bool,
    ) {
        let v = self.cfg.v;
        let runs = if near {
            &self.local.near_runs
        } else {
            &self.st.runs
        };
        for &(a, b) in runs {
            cands.clear();
            events::rest_candidates(
                self.simd,
                &self.st.dir[a..b],
                &self.w0[a..b],
                &self.st.w[a..b],
                &self.a_start[a..b],
                &self.a_end[a..b],
                v,
                h,
                cands,
            );
            for &i in cands.iter() {
                let p = a + i;
                let d = self.st.dir[p];
                let g = Hermite {
                    g0: d * (self.w0[p] - v),
                    m0: d * self.a_start[p],
                    g1: d * (self.st.w[p] - v),
                    m1: d * self.a_end[p],
                };
                if g.g0 == 0.0 && g.g1 == 0.0 && g.m0 <= 0.0 && g.m1 <= 0.0 {
                    continue;
                }
                if g.first_crossing(h).is_some() {
                    out.push(p);
                }
            }
            if !G::FRONTIER && !near {
                for (q, _, _) in self.st.geo.around_run(a, b) {
                    if let Some(p) = self.st.resolve(q) {
                        self.stuck_switch(p, t0, h, out);
                    }
                }
            }
        }
        if near {
            for &p in &self.local.near_stuck {
                self.stuck_switch(p, t0, h, out);
            }
        } else if G::FRONTIER {
            // the stuck blocks next to the runs from their lists (../frontier.rs: the
            // cells the walk around the runs visits; `out` is sorted below, so the order
            // of the visit does not matter)
            for p in self.st.frontier.stuck_blocks(&self.st.dir) {
                self.stuck_switch(p, t0, h, out);
            }
        }
        out.sort_unstable();
        out.dedup();
    }

    /// Does stuck block p (next to a run, not next to a member: a component watches
    /// those) cross a threshold in the step [t0, t0 + h]? Then it goes to `out`.
    #[inline]
    fn stuck_switch(&self, p: usize, t0: f64, h: f64, out: &mut Vec<usize>) {
        if self.st.sliding(p) {
            return;
        }
        let mem = &self.local.mem_of;
        if !mem.is_empty()
            && self
                .st
                .geo
                .neighbours(p)
                .into_iter()
                .any(|q| self.st.resolve(q).is_some_and(|r| mem[r] != NONE))
        {
            return;
        }
        let t1 = t0 + h;
        let up = self.herm_u(p, t0, t1);
        let phi = self
            .st
            .geo
            .phi_hermite(&self.blk.med, p, up, |q| self.herm_neighbour(q, p, t0, t1));
        let (lo, hi) = (self.blk.lower(p), self.blk.upper(p));
        let fwd = Hermite {
            g0: phi.g0 - hi,
            m0: phi.m0,
            g1: phi.g1 - hi,
            m1: phi.m1,
        };
        let bwd = Hermite {
            g0: lo - phi.g0,
            m0: -phi.m0,
            g1: lo - phi.g1,
            m1: -phi.m1,
        };
        if fwd.first_crossing(h).is_some() || bwd.first_crossing(h).is_some() {
            out.push(p);
        }
    }

    /// Make `p` and its real neighbours members (those that are not yet).
    fn add_members(&mut self, list: &[usize]) {
        let cells = self.st.geo.cells();
        if self.local.mem_of.len() != cells {
            self.local.mem_of = vec![NONE; cells];
        }
        for &p in list {
            let nb = self.st.geo.neighbours(p);
            let all = std::iter::once(Some(p)).chain(nb.into_iter().map(|q| self.st.resolve(q)));
            for r in all.flatten() {
                if self.local.mem_of[r] != NONE {
                    continue;
                }
                let l = &mut self.local;
                l.mem_of[r] = l.members.len() as u32;
                l.members.push(r);
                l.mcomp.push(NONE);
                l.dir0.push(self.st.dir[r]);
                l.onset0.push(self.st.onset[r]);
                l.out.push(false);
            }
        }
    }

    /// Group the members into components (module docs, step 2); components whose members
    /// did not change keep their result.
    fn group(&mut self) {
        let l = &mut self.local;
        let m = l.members.len();
        let mut parent: Vec<u32> = (0..m as u32).collect();
        fn find(parent: &mut [u32], mut i: u32) -> u32 {
            while parent[i as usize] != i {
                let g = parent[parent[i as usize] as usize];
                parent[i as usize] = g;
                i = g;
            }
            i
        }
        let st = &self.st;
        for i in 0..m {
            let p = l.members[i];
            for q in st.geo.neighbours(p) {
                let Some(r) = st.resolve(q) else { continue };
                let near = std::iter::once(r).chain(
                    st.geo
                        .neighbours(r)
                        .into_iter()
                        .filter_map(|q2| st.resolve(q2)),
                );
                for r2 in near {
                    let j = l.mem_of[r2];
                    if j != NONE {
                        let (a, b) = (find(&mut parent, i as u32), find(&mut parent, j));
                        if a != b {
                            parent[a.max(b) as usize] = a.min(b);
                        }
                    }
                }
            }
        }
        // the groups, by their root
        let mut root_comp: std::collections::HashMap<u32, usize> = Default::default();
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for i in 0..m {
            let r = find(&mut parent, i as u32);
            let g = *root_comp.entry(r).or_insert_with(|| {
                groups.push(Vec::new());
                groups.len() - 1
            });
            groups[g].push(l.members[i]);
        }
        let mut old: std::collections::HashMap<usize, Comp> = std::mem::take(&mut l.comps)
            .into_iter()
            .filter(|c| c.done)
            .map(|c| (c.blocks[0], c))
            .collect();
        for mut g in groups {
            g.sort_unstable();
            let c = match old.remove(&g[0]) {
                Some(c) if c.blocks == g => c,
                other => {
                    l.pool.extend(other);
                    let mut watch = Vec::new();
                    for &p in &g {
                        for q in st.geo.neighbours(p) {
                            if let Some(r) = st.resolve(q) {
                                if l.mem_of[r] == NONE && !st.sliding(r) {
                                    watch.push(r);
                                }
                            }
                        }
                    }
                    watch.sort_unstable();
                    watch.dedup();
                    let mut c = l.pool.pop().unwrap_or_default();
                    c.blocks = g;
                    c.watch = watch;
                    c.done = false;
                    c
                }
            };
            let id = l.comps.len() as u32;
            l.pos.resize(m, 0);
            for (k, &p) in c.blocks.iter().enumerate() {
                let mi = l.mem_of[p] as usize;
                l.mcomp[mi] = id;
                l.pos[mi] = k as u32;
            }
            l.comps.push(c);
        }
        l.pool.extend(old.into_values());
    }

    /// Integrate every component not yet done; the blocks to add if one must grow.
    fn integrate_components(&mut self, t0: f64, h: f64) -> Vec<usize> {
        let mut comps = std::mem::take(&mut self.local.comps);
        let mut scratch = std::mem::take(&mut self.local.scratch);
        let mut grow = Vec::new();
        {
            let cx = Ctx {
                st: &self.st,
                blk: &self.blk,
                run: RunData {
                    t0,
                    h,
                    u0: &self.u0,
                    w0: &self.w0,
                    a0: &self.a_start,
                    u1: &self.st.u,
                    w1: &self.st.w,
                    a1: &self.a_end,
                },
                mem_of: &self.local.mem_of,
                pos: &self.local.pos,
                members: &self.local.members,
                dir0: &self.local.dir0,
                onset0: &self.local.onset0,
            };
            for c in comps.iter_mut().filter(|c| !c.done) {
                match integrate(&cx, c, t0, h, &mut scratch) {
                    Outcome::Done => {}
                    Outcome::Grow(g) => {
                        c.done = false;
                        if g.is_empty() {
                            // no progress inside: hand the step to the global cut
                            grow.push(usize::MAX);
                        }
                        grow.extend(g);
                    }
                }
            }
        }
        self.local.stats.components += comps.iter().filter(|c| c.done).count() as u64;
        self.local.comps = comps;
        self.local.scratch = scratch;
        grow
    }

    /// Take the members out of the pass over the runs: sliding ones out of the runs,
    /// stuck ones marked sliding (so the runs read their values from `State::ext`).
    fn take_out_members(&mut self) {
        for i in 0..self.local.members.len() {
            if self.local.out[i] {
                continue;
            }
            let p = self.local.members[i];
            if self.local.dir0[i] != 0.0 {
                self.st.remove_from_runs(p);
            } else {
                self.st.dir[p] = 1.0;
            }
            // (the passes write its stage values: ../release.rs)
            self.st.touch(p);
            self.local.out[i] = true;
        }
    }

    /// Undo [`Engine::take_out_members`]: the members back in their state at t0.
    fn put_back_members(&mut self) {
        for i in 0..self.local.members.len() {
            if !self.local.out[i] {
                continue;
            }
            let p = self.local.members[i];
            if self.local.dir0[i] != 0.0 {
                self.st.u[p] = self.u0[p];
                self.st.w[p] = self.w0[p];
                self.st.add_to_runs(p);
            } else {
                self.st.dir[p] = 0.0;
            }
            self.local.out[i] = false;
        }
        self.relist_stuck_members();
    }

    /// The members stuck now back in the frontier's lists (a compaction while they were
    /// marked sliding may have dropped them; ../frontier.rs).
    fn relist_stuck_members(&mut self) {
        for &p in &self.local.members {
            self.st.frontier.relist(&self.st.dir, p);
        }
    }

    /// A later pass over the runs (module docs, step 4; the members out of the runs, their
    /// values in `State::ext`), from the start state the first pass saved.
    ///
    /// Only the run blocks within NEAR = 4 hops of a member are stepped. Why that gives
    /// the bits of a pass over every run: the pass differs from the first only in the
    /// members' values at the stages (and their being out of the runs). In RK4 a block's
    /// stage-2 values u0 + h/2 u_t0, u_t0 + h/2 a0 read no neighbour (a0, at t0, is the
    /// same in both passes); its stage-2 acceleration reads its neighbours' stage-2 u,
    /// so it differs only next to a member (1 hop); stage 3's u_t = u_t0 + h/2 a2 then
    /// differs within 1 hop, its u (u0 + h/2 of stage 2's u_t) nowhere, so a3 within 1
    /// hop; stage 4's u, u_t within 1 hop, a4 (reading the neighbours' stage-4 u) within
    /// 2; the new u within 1 hop, u_t and the end accelerations within 2. So every block
    /// 3 or more hops from all members ends the pass with the first pass's values, to the
    /// bit, as do its stage values and books. The blocks stepped read the stage
    /// buffers just outside them (5 hops), which hold the first pass's last stage values,
    /// not this pass's: by the same count that error reaches 2 hops in, to the blocks 3
    /// and 4 hops from the members, whose values after the first pass (the state, the
    /// end accelerations, every stage buffer) are saved before and put back after. The
    /// hops are counted through every cell (stuck ones and periodic wraps included: a
    /// superset of the paths the coupling takes).
    /// Returns whether only the blocks near the members were stepped (then
    /// [`Engine::detect_all`] searches only near them).
    fn later_pass(&mut self, t0: f64, h: f64) -> bool {
        #[cfg(test)]
        let whole = self.local.plain.whole_pass;
        #[cfg(not(test))]
        let whole = false;
        if whole || !matches!(self.rk, Stepper::Rk4(_)) {
            self.do_step(t0, h, true);
            self.local.stats.later_block_steps += self.st.n_active as u64;
            return false;
        }
        self.near_members();
        let Stepper::Rk4(rk) = &mut self.rk else {
            unreachable!()
        };
        // the first pass's values at the band (3 and 4 hops out)
        let l = &mut self.local;
        l.saved.clear();
        {
            let bufs = rk.buffers_mut();
            for &p in &l.band {
                l.saved.push(self.st.u[p]);
                l.saved.push(self.st.w[p]);
                l.saved.push(self.a_end[p]);
                for b in bufs.iter() {
                    l.saved.push(b[p]);
                }
            }
        }
        let near = l.near.len();
        let runs = std::mem::replace(&mut self.st.runs, std::mem::take(&mut l.near_runs));
        let active = std::mem::replace(&mut self.st.n_active, near);
        self.do_step(t0, h, true);
        self.local.near_runs = std::mem::replace(&mut self.st.runs, runs);
        self.st.n_active = active;
        self.local.stats.later_block_steps += near as u64;
        let Stepper::Rk4(rk) = &mut self.rk else {
            unreachable!()
        };
        let l = &mut self.local;
        let mut bufs = rk.buffers_mut();
        let per = 3 + bufs.len();
        for (k, &p) in l.band.iter().enumerate() {
            let s = &l.saved[k * per..(k + 1) * per];
            self.st.u[p] = s[0];
            self.st.w[p] = s[1];
            self.a_end[p] = s[2];
            for (b, &x) in bufs.iter_mut().zip(&s[3..]) {
                b[p] = x;
            }
        }
        true
    }

    /// The run blocks within NEAR hops of a member: `near` (sorted), `near_runs` (the
    /// same as runs), `band` (those 3 or more hops away); `near_stuck`, the stuck blocks
    /// within 3 hops next to a run.
    fn near_members(&mut self) {
        let st = &self.st;
        let l = &mut self.local;
        if l.hop.len() != st.geo.cells() {
            l.hop = vec![UNSEEN; st.geo.cells()];
        }
        let mem_of = &l.mem_of;
        let in_runs = |r: usize| st.sliding(r) && mem_of[r] == NONE;
        for &p in &l.seen {
            l.hop[p] = UNSEEN;
        }
        l.seen.clear();
        for &p in &l.members {
            l.hop[p] = SEEN;
        }
        l.seen.extend_from_slice(&l.members);
        l.layer.clear();
        l.layer.extend_from_slice(&l.members);
        l.near.clear();
        l.band.clear();
        l.near_stuck.clear();
        for hop in 1..=NEAR {
            l.next.clear();
            for &p in &l.layer {
                for q in st.geo.neighbours(p) {
                    if let Some(r) = st.resolve(q) {
                        if l.hop[r] == UNSEEN {
                            l.hop[r] = SEEN;
                            l.next.push(r);
                        }
                    }
                }
            }
            l.seen.extend_from_slice(&l.next);
            for &r in &l.next {
                if in_runs(r) {
                    l.near.push(r);
                    if hop >= 3 {
                        l.band.push(r);
                    }
                } else if hop <= 3
                    && !st.sliding(r)
                    && st
                        .geo
                        .neighbours(r)
                        .into_iter()
                        .any(|q| st.resolve(q).is_some_and(in_runs))
                {
                    l.near_stuck.push(r);
                }
            }
            std::mem::swap(&mut l.layer, &mut l.next);
        }
        l.near.sort_unstable();
        l.near_runs.clear();
        for &p in &l.near {
            match l.near_runs.last_mut() {
                Some(last) if last.1 == p => last.1 = p + 1,
                _ => l.near_runs.push((p, p + 1)),
            }
        }
    }

    /// One step of length h from t0 (capped at t_cap) with local events (module docs).
    /// Returns false, with the state back at t0, when the step is left to the global cut.
    pub(super) fn local_step(&mut self, t0: f64, h: f64, t_cap: f64) -> Result<bool> {
        self.local.clear();
        let first = self.st.n_active as u64;
        self.do_step(t0, h, false);
        let mut cands = std::mem::take(&mut self.scratch.cands);
        let mut found = std::mem::take(&mut self.scratch.test);
        found.clear();
        self.detect_all(t0, h, &mut cands, &mut found, false);
        if found.is_empty() {
            self.scratch.cands = cands;
            self.scratch.test = found;
            let integ = self.rk.books(&self.st, &self.blk, &self.w0, h);
            self.finish_step(t0, h, t_cap, integ, Vec::new(), None)?;
            self.local.stats.quiet_block_steps += first;
            return Ok(true);
        }
        self.local.stats.event_steps += 1;
        self.local.stats.passes += 1;
        self.local.stats.first_block_steps += first;
        let mut rounds = 0usize;
        let integ = loop {
            rounds += 1;
            if rounds > MAX_ROUNDS {
                break None;
            }
            // the components (with the runs' latest pass as their outside)
            self.add_members(&found);
            found.clear();
            let mut ok = true;
            loop {
                self.group();
                let grow = self.integrate_components(t0, h);
                if grow.is_empty() {
                    break;
                }
                if grow.contains(&usize::MAX) {
                    ok = false;
                    break;
                }
                rounds += 1;
                if rounds > MAX_ROUNDS {
                    ok = false;
                    break;
                }
                self.add_members(&grow);
            }
            if !ok {
                break None;
            }
            // the runs again, without the members, reading them at the stage times, from
            // the start state the first pass saved (a redo: no copy back; the members'
            // own u, u_t are not read in the pass, `State::ext` stands for them)
            #[cfg(test)]
            if self.local.plain.copy_back {
                self.restore_runs();
            }
            self.take_out_members();
            self.st.ext.clear();
            for c in &self.local.comps {
                for (k, &p) in c.blocks.iter().enumerate() {
                    self.st.ext.push((p, c.mid[k], c.end[k]));
                }
            }
            self.st.ext_t1 = t0 + h;
            let near = self.later_pass(t0, h);
            self.local.stats.passes += 1;
            self.detect_all(t0, h, &mut cands, &mut found, near);
            if found.is_empty() {
                break Some(self.rk.books(&self.st, &self.blk, &self.w0, h));
            }
        };
        self.scratch.cands = cands;
        self.scratch.test = found;
        self.st.ext.clear();
        let Some(integ) = integ else {
            // the global cut for this step: the state back at t0
            self.restore_runs();
            self.put_back_members();
            self.local.clear();
            self.local.stats.fallbacks += 1;
            return Ok(false);
        };
        self.local_commit(t0, h, t_cap, integ)?;
        Ok(true)
    }

    /// The end of a step with local events: the books, the snapshots, the members' new
    /// state, the catalog (module docs, step 5).
    fn local_commit(
        &mut self,
        t0: f64,
        h: f64,
        t_cap: f64,
        mut integ: StepIntegrals,
    ) -> Result<()> {
        let v = self.cfg.v;
        let mut block_steps = 0u64;
        let mut substeps = 0u64;
        let mut projection = 0.0;
        for c in &self.local.comps {
            integ.u += c.books.u;
            integ.dry += c.books.dry;
            integ.visc += c.books.visc;
            projection += c.projection;
            block_steps += c.block_steps;
            substeps += c.substeps;
        }
        // the stuck members at t0 are in stuck_sum (their drift over the whole step),
        // and their loader displacement is in the components' books too
        for (i, &p) in self.local.members.iter().enumerate() {
            if self.local.dir0[i] == 0.0 {
                let u0 = self.st.stuck_u(p, t0);
                integ.u -= self.blk.med.loader(p) * h * (u0 + 0.5 * v * h);
            }
        }
        self.counters.block_steps += block_steps;
        self.counters.steps += substeps;
        self.local.stats.component_block_steps += block_steps;
        self.local.stats.component_substeps += substeps;
        self.local.stats.members += self.local.members.len() as u64;
        if !(integ.u.is_finite() && integ.dry.is_finite() && integ.visc.is_finite()) {
            return Err(Error::NoConvergence {
                what: "chain integration",
                detail: format!(
                    "non-finite state at t = {t0} (a kick or initial velocity too large for \
                     step = {}?)",
                    self.cfg.step
                ),
            });
        }
        self.ledger.load += v
            * (integ.u
                + h * (self.stuck_sum
                    + 0.5 * v * h * self.stuck_loader
                    + self.beta() * self.st.n as f64));
        self.stuck_sum += v * h * self.stuck_loader;
        self.ledger.dry += integ.dry;
        self.ledger.viscous += integ.visc;
        self.ledger.projection += projection;
        self.local.dense_valid = true;
        self.dense_snapshots(t0, h);
        self.local.dense_valid = false;
        let t1 = if t0 + h >= t_cap { t_cap } else { t0 + h };
        self.t = t1;
        std::mem::swap(&mut self.a_start, &mut self.a_end);
        // the members' new state
        let mut recs: Vec<Rec> = Vec::new();
        let comps = std::mem::take(&mut self.local.comps);
        for c in &comps {
            for (k, &p) in c.blocks.iter().enumerate() {
                let i = self.local.mem_of[p] as usize;
                let (was, now) = (self.local.dir0[i], c.dir[k]);
                let kp = self.blk.med.loader(p);
                if was == 0.0 {
                    // (it was marked sliding for the passes)
                    self.st.dir[p] = 0.0;
                    if now == 0.0 && c.tref[k] == self.st.tref[p] && c.uref[k] == self.st.u[p] {
                        // stuck all through
                        continue;
                    }
                    // its drift to t1 is in stuck_sum
                    self.stuck_sum -= kp * self.st.stuck_u(p, t1);
                    self.n_stuck -= 1;
                    self.stuck_loader -= kp;
                }
                if now != 0.0 {
                    self.st.u[p] = c.u[k];
                    self.st.w[p] = c.w[k];
                    self.st.dir[p] = now;
                    self.st.onset[p] = c.onset[k];
                    self.st.add_to_runs(p);
                } else {
                    self.st.dir[p] = 0.0;
                    self.st.w[p] = v;
                    self.st.u[p] = c.uref[k];
                    self.st.tref[p] = c.tref[k];
                    self.stuck_sum += kp * self.st.stuck_u(p, t1);
                    self.n_stuck += 1;
                    self.stuck_loader += kp;
                }
            }
            recs.extend_from_slice(&c.recs);
        }
        self.local.comps = comps;
        self.relist_stuck_members();
        recs.sort_by(|a, b| a.t.total_cmp(&b.t));
        for r in &recs {
            let k = self.st.geo.index(r.p);
            match r.kind {
                RecKind::Slip(dir) => self.catalog.slip(k, r.t, r.u, dir, Cause::Threshold),
                RecKind::Stick => self.catalog.stick(k, r.t, r.u, v),
                RecKind::Reverse(dir) => {
                    self.catalog.stick(k, r.t, r.u, v);
                    self.catalog.slip(k, r.t, r.u, dir, Cause::Threshold);
                }
            }
            self.counters.switches += 1;
        }
        // the accelerations at t1: the last pass wrote those of the runs' blocks, their
        // neighbours among the members read at t1 from `State::ext`, i.e. the members'
        // values just committed; so only the members (whose equations or values came
        // from their components) and, as a safeguard, their neighbours are recomputed at
        // the next step (`Engine::integrate_step`), the same bits as all of them
        self.a_valid = recs.is_empty();
        self.a_partial = !recs.is_empty();
        #[cfg(test)]
        if self.local.plain.all_accel {
            self.a_partial = false;
        }
        self.a_fix.clear();
        if self.a_partial {
            self.a_fix.extend_from_slice(&self.local.members);
        }
        // (a step cut at t_cap or at the last stick ends elsewhere: all recomputed)
        self.a_time = if self.a_partial { t0 + h } else { f64::NAN };
        if self.st.n_active == 0 {
            // everything stuck since the last switch: the step ends there (the event
            // closes at its last stick, as with the global cut)
            if let Some(last) = recs.last() {
                let dt = t1 - last.t;
                if dt > 0.0 {
                    self.stuck_sum -= v * dt * self.stuck_loader;
                    self.ledger.load -= v
                        * dt
                        * (self.stuck_sum
                            + 0.5 * v * dt * self.stuck_loader
                            + self.beta() * self.st.n as f64);
                    self.t = last.t;
                }
            }
        }
        let members = std::mem::take(&mut self.local.members);
        for &p in &members {
            self.refresh_around(p);
        }
        self.local.members = members;
        self.need_check = true;
        self.local.clear();
        Ok(())
    }
}

impl Local {
    /// The member index per cell (measurements: its memory, ../release.rs).
    pub(crate) fn member_map(&self) -> &[u32] {
        &self.mem_of
    }

    /// The later pass's marks per cell (measurements: their memory, ../release.rs).
    pub(crate) fn near_map(&self) -> &[u8] {
        &self.hop
    }

    /// Bytes allocated by the lists per member and the components' buffers, those of
    /// the pool included (measurements: their memory, ../release.rs).
    pub(crate) fn buffer_bytes(&self) -> usize {
        fn cap<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        let comp = |c: &Comp| {
            std::mem::size_of::<Comp>()
                + cap(&c.blocks)
                + cap(&c.watch)
                + [
                    &c.dir, &c.onset, &c.u, &c.w, &c.uref, &c.tref, &c.mid, &c.end,
                ]
                .iter()
                .map(|v| cap(v))
                .sum::<usize>()
                + cap(&c.kt)
                + cap(&c.ku)
                + cap(&c.kw)
                + cap(&c.recs)
        };
        let sc = &self.scratch;
        let scratch = [
            &sc.su, &sc.sw, &sc.su0, &sc.sw0, &sc.sum_u, &sc.sum_w, &sc.acc0, &sc.acc,
        ]
        .iter()
        .map(|v| cap(v))
        .sum::<usize>()
            + cap(&sc.grow)
            + cap(&sc.who)
            + cap(&sc.list)
            + cap(&sc.cands);
        cap(&self.members)
            + cap(&self.mcomp)
            + cap(&self.dir0)
            + cap(&self.onset0)
            + cap(&self.out)
            + cap(&self.pos)
            + cap(&self.seen)
            + cap(&self.layer)
            + cap(&self.next)
            + cap(&self.near)
            + cap(&self.near_runs)
            + cap(&self.band)
            + cap(&self.near_stuck)
            + cap(&self.saved)
            + self.comps.iter().map(comp).sum::<usize>()
            + self.pool.iter().map(comp).sum::<usize>()
            + (self.comps.capacity() - self.comps.len() + self.pool.capacity() - self.pool.len())
                * std::mem::size_of::<Comp>()
            + scratch
    }
}
