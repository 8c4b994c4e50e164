//! Classical fourth-order Runge-Kutta for the runs of sliding blocks.
//!
//! Each stage is one pass per run that evaluates the right-hand side at the stage values
//! and, in the same loop, adds it to the RK4 sums and writes the next stage's values into
//! a second buffer (two stage buffers, used in turn): no per-block branch and no
//! reduction, so the compiler vectorises it. Stage 1 (at the start state, whose
//! accelerations the last step left) only saves the state and sets stage 2's values;
//! stage 2 starts the sums; the last stage writes the new state, and one more pass its
//! accelerations (the next step's stage 1). When every sliding block slides forward the
//! stages do not read the direction (it is passed as the constant 1: the same bits).
//! On x86-64 CPUs with AVX2 or AVX-512F the
//! step, the accelerations and the books run as code compiled for them ([`Simd`],
//! detected at run time; Rust never fuses a multiply and an add, so every path gives the
//! same bits).

use super::{
    accel_only_at_state, fill_neighbours, lane_sum, stage_accel, Integrator, Simd, StepIntegrals,
};
use crate::chain::cells::CellVec;
use crate::chain::geometry::{Geometry, Stencil};
use crate::chain::medium::{Blocks, Medium};
use crate::chain::state::State;
use crate::friction::Friction;

/// Classical fourth-order Runge-Kutta.
#[derive(Debug, Clone)]
pub struct Rk4 {
    su: CellVec,
    sw: CellVec,
    tu: CellVec,
    tw: CellVec,
    ku: CellVec,
    kw: CellVec,
    /// Stage 4's u_t (stage 2's is left in `sw`, stage 3's in `tw`): the viscous power
    /// book is summed from the four stages' u_t once per step taken ([`Rk4::books_body`]).
    vw: CellVec,
    /// Per block, the RK4-weighted sums over the stages of the loader displacement and
    /// the dry power (the energy books, reduced once per step).
    bu: CellVec,
    bd: CellVec,
    /// Which of (bu, bd) the last step kept: the loader term is skipped at v = 0 (no
    /// loader work), the dry power for a law whose dry power is 0 (beta-free Coulomb).
    kept: (bool, bool),
    /// The vector code the kernels run (the widest this CPU has).
    simd: Simd,
}

impl Rk4 {
    /// The buffers over the cells, by name (all of them scratch: ../release.rs).
    pub fn buffers(&self) -> [(&'static str, &CellVec); 9] {
        [
            ("su", &self.su),
            ("sw", &self.sw),
            ("tu", &self.tu),
            ("tw", &self.tw),
            ("ku", &self.ku),
            ("kw", &self.kw),
            ("bu", &self.bu),
            ("bd", &self.bd),
            ("vw", &self.vw),
        ]
    }

    /// The buffers over the cells, to give their dead pages back (../release.rs).
    pub(crate) fn buffers_mut(&mut self) -> [&mut CellVec; 9] {
        [
            &mut self.su,
            &mut self.sw,
            &mut self.tu,
            &mut self.tw,
            &mut self.ku,
            &mut self.kw,
            &mut self.bu,
            &mut self.bd,
            &mut self.vw,
        ]
    }

    /// Buffers for a chain of n blocks.
    pub fn new(n: usize) -> Self {
        Rk4 {
            su: CellVec::new(n + 2, 0.0),
            sw: CellVec::new(n + 2, 0.0),
            tu: CellVec::new(n + 2, 0.0),
            tw: CellVec::new(n + 2, 0.0),
            ku: CellVec::new(n + 2, 0.0),
            kw: CellVec::new(n + 2, 0.0),
            bu: CellVec::new(n + 2, 0.0),
            bd: CellVec::new(n + 2, 0.0),
            vw: CellVec::new(n + 2, 0.0),
            kept: (true, true),
            simd: Simd::detect(),
        }
    }
}

/// One RK4 stage over every run: the right-hand side at the stage values (cu, cw; the
/// neighbours of the runs filled in), added with weight `wt` to the sums (ku, kw); the
/// next stage's values u0 + ch cw, w0 + ch a go to (nu, nw). `FIRST` (stage 2): the sums
/// start from stage 1's values (w0, a0 and the books' rates at the start state), computed
/// here rather than stored by stage 1 and read back (the same operations on the same
/// values, so the same bits).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn stage<
    G: Geometry,
    F: Friction,
    M: Medium,
    const LOAD: bool,
    const DRY: bool,
    const FWD: bool,
    const FIRST: bool,
>(
    st: &State<G>,
    fr: &Blocks<F, M>,
    cu: &[f64],
    cw: &[f64],
    u0: &[f64],
    w0: &[f64],
    a0: &[f64],
    ku: &mut [f64],
    kw: &mut [f64],
    nu: &mut [f64],
    nw: &mut [f64],
    books: [&mut [f64]; 2],
    wt: f64,
    ch: f64,
) {
    let [bu, bd] = books;
    let v = st.v;
    for &(a, b) in &st.runs {
        // equal-length slices and an index: no bounds checks, one vectorised loop
        let len = b - a;
        let sten = st.geo.stencil(cu, a, b);
        let (cw, dir, th) = (&cw[a..b], &st.dir[a..b], &st.onset[a..b]);
        let (u0, w0, a0) = (&u0[a..b], &w0[a..b], &a0[a..b]);
        let (ku, kw) = (&mut ku[a..b], &mut kw[a..b]);
        let (nu, nw) = (&mut nu[a..b], &mut nw[a..b]);
        let (bu, bd) = (&mut bu[a..b], &mut bd[a..b]);
        assert!(cw.len() == len && dir.len() == len);
        assert!(th.len() == len && u0.len() == len && w0.len() == len && ku.len() == len);
        assert!(kw.len() == len && nu.len() == len && nw.len() == len && bu.len() == len);
        assert!(bd.len() == len && a0.len() == len);
        for i in 0..len {
            let (w, d) = (cw[i], if FWD { 1.0 } else { dir[i] });
            let uc = sten.centre(i);
            let f = sten.force(&fr.med, a + i, i);
            let acc = fr.accel(a + i, uc, f, v - w, d, th[i]);
            // stage 1's terms (weight 1) or the sums so far
            let (ku0, kw0, bu0, bd0) = if FIRST {
                let (pd, _) = fr.fr.power(v - w0[i], d, th[i]);
                (w0[i], a0[i], fr.med.loader(a + i) * u0[i], pd)
            } else {
                (ku[i], kw[i], bu[i], bd[i])
            };
            ku[i] = ku0 + wt * w;
            kw[i] = kw0 + wt * acc;
            nu[i] = u0[i] + ch * w;
            nw[i] = w0[i] + ch * acc;
            if LOAD {
                bu[i] = bu0 + wt * (fr.med.loader(a + i) * uc);
            }
            if DRY {
                let (pd, _) = fr.fr.power(v - w, d, th[i]);
                bd[i] = bd0 + wt * pd;
            }
        }
    }
}

/// The last stage: its right-hand side completes the sums and the new state
/// u = u0 + h/6 ku, u_t = w0 + h/6 kw is written into `st`, u also into `nu`; then the
/// accelerations of the new state at t1 = t0 + h go to `a1` (the run neighbours of `nu`
/// filled at t1: the same formula on the same values as [`Integrator::accel_only`], so
/// the same bits, without its copy of the state).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn last_stage<
    G: Geometry,
    F: Friction,
    M: Medium,
    const LOAD: bool,
    const DRY: bool,
    const FWD: bool,
>(
    st: &mut State<G>,
    fr: &Blocks<F, M>,
    cu: &[f64],
    cw: &[f64],
    u0: &[f64],
    w0: &[f64],
    ku: &[f64],
    kw: &[f64],
    nu: &mut [f64],
    books: [&mut [f64]; 2],
    h6: f64,
    t1: f64,
    a1: &mut [f64],
) {
    let [bu, bd] = books;
    let v = st.v;
    let State {
        geo,
        u: su,
        w: sw,
        dir,
        onset,
        runs,
        ..
    } = &mut *st;
    for &(a, b) in runs.iter() {
        let len = b - a;
        let sten = geo.stencil(cu, a, b);
        let (cw, dir, th) = (&cw[a..b], &dir[a..b], &onset[a..b]);
        let (u0, w0, ku, kw) = (&u0[a..b], &w0[a..b], &ku[a..b], &kw[a..b]);
        let (su, sw, nu) = (&mut su[a..b], &mut sw[a..b], &mut nu[a..b]);
        let (bu, bd) = (&mut bu[a..b], &mut bd[a..b]);
        assert!(cw.len() == len && dir.len() == len);
        assert!(th.len() == len && u0.len() == len && w0.len() == len && ku.len() == len);
        assert!(kw.len() == len && su.len() == len && sw.len() == len && bu.len() == len);
        assert!(bd.len() == len && nu.len() == len);
        for i in 0..len {
            let (w, d) = (cw[i], if FWD { 1.0 } else { dir[i] });
            let uc = sten.centre(i);
            let f = sten.force(&fr.med, a + i, i);
            let acc = fr.accel(a + i, uc, f, v - w, d, th[i]);
            su[i] = u0[i] + h6 * (ku[i] + w);
            nu[i] = su[i];
            sw[i] = w0[i] + h6 * (kw[i] + acc);
            if LOAD {
                bu[i] += fr.med.loader(a + i) * uc;
            }
            if DRY {
                let (pd, _) = fr.fr.power(v - w, d, th[i]);
                bd[i] += pd;
            }
        }
    }
    fill_neighbours(st, nu, t1);
    stage_accel::<G, F, M, FWD>(st, fr, nu, &st.w, a1);
}

/// The RK4-weighted viscous power of a run's blocks, ((p1 + 2 p2) + 2 p3) + p4 per block
/// from the four stages' u_t `[dir, th, w1, w2, w3, w4]`, into `out` (one pass without
/// a reduction, which the compiler vectorises).
#[inline(always)]
fn visc_per_block<F: Friction, M: Medium>(
    fr: &Blocks<F, M>,
    v: f64,
    x: [&[f64]; 6],
    out: &mut [f64],
) {
    let [dir, th, w1, w2, w3, w4] = x;
    let len = out.len();
    assert!(dir.len() == len && th.len() == len && w1.len() == len);
    assert!(w2.len() == len && w3.len() == len && w4.len() == len);
    for i in 0..len {
        let pv = |w: f64| fr.fr.power(v - w, dir[i], th[i]).1;
        out[i] = ((pv(w1[i]) + 2.0 * pv(w2[i])) + 2.0 * pv(w3[i])) + pv(w4[i]);
    }
}

impl Rk4 {
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn step_body<G: Geometry, F: Friction, M: Medium, const LOAD: bool, const DRY: bool>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t0: f64,
        h: f64,
        a0: &[f64],
        u0: &mut [f64],
        w0: &mut [f64],
        a1: &mut [f64],
        redo: bool,
    ) {
        let Rk4 { su, sw, kept, .. } = self;
        *kept = (LOAD, DRY);
        // stage 1 (at t0): the derivatives are (w, a0); save the start state, set stage
        // 2's values, and find whether every block slides forward (an and without a
        // branch); stage 2 starts the RK4 sums and the books
        let hh = 0.5 * h;
        let mut forward = true;
        if redo {
            // a redo: the start state is in (u0, w0) already
            for &(a, b) in &st.runs {
                let len = b - a;
                let (u, w, acc) = (&u0[a..b], &w0[a..b], &a0[a..b]);
                let (su, sw, dir) = (&mut su[a..b], &mut sw[a..b], &st.dir[a..b]);
                assert!(u.len() == len && w.len() == len && acc.len() == len);
                assert!(su.len() == len && sw.len() == len && dir.len() == len);
                for i in 0..len {
                    su[i] = u[i] + hh * w[i];
                    sw[i] = w[i] + hh * acc[i];
                    forward &= dir[i] == 1.0;
                }
            }
        } else {
            for &(a, b) in &st.runs {
                let len = b - a;
                let (u, w, acc) = (&st.u[a..b], &st.w[a..b], &a0[a..b]);
                let (u0, w0) = (&mut u0[a..b], &mut w0[a..b]);
                let (su, sw, dir) = (&mut su[a..b], &mut sw[a..b], &st.dir[a..b]);
                assert!(u.len() == len && w.len() == len && acc.len() == len && u0.len() == len);
                assert!(w0.len() == len && su.len() == len && sw.len() == len && dir.len() == len);
                for i in 0..len {
                    u0[i] = u[i];
                    w0[i] = w[i];
                    su[i] = u[i] + hh * w[i];
                    sw[i] = w[i] + hh * acc[i];
                    forward &= dir[i] == 1.0;
                }
            }
        }
        // stages 2 to 4, with dir read only if some block slides backward
        if forward {
            self.stages_2_to_4::<G, F, M, LOAD, DRY, true>(st, fr, t0, h, a0, u0, w0, a1)
        } else {
            self.stages_2_to_4::<G, F, M, LOAD, DRY, false>(st, fr, t0, h, a0, u0, w0, a1)
        }
    }

    /// Stages 2 and 3 at t0 + h/2 (weight 2), stage 4 at t0 + h (weight 1) and the end
    /// accelerations, from stage 1's values and sums.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn stages_2_to_4<
        G: Geometry,
        F: Friction,
        M: Medium,
        const LOAD: bool,
        const DRY: bool,
        const FWD: bool,
    >(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t0: f64,
        h: f64,
        a0: &[f64],
        u0: &[f64],
        w0: &[f64],
        a1: &mut [f64],
    ) {
        let Rk4 {
            su,
            sw,
            tu,
            tw,
            ku,
            kw,
            vw,
            bu,
            bd,
            ..
        } = self;
        let hh = 0.5 * h;
        let tm = t0 + 0.5 * h;
        fill_neighbours(st, su, tm);
        stage::<G, F, M, LOAD, DRY, FWD, true>(
            st,
            fr,
            su,
            sw,
            u0,
            w0,
            a0,
            ku,
            kw,
            tu,
            tw,
            [bu, bd],
            2.0,
            hh,
        );
        fill_neighbours(st, tu, tm);
        stage::<G, F, M, LOAD, DRY, FWD, false>(
            st,
            fr,
            tu,
            tw,
            u0,
            w0,
            a0,
            ku,
            kw,
            su,
            vw,
            [bu, bd],
            2.0,
            h,
        );
        let t1 = t0 + h;
        fill_neighbours(st, su, t1);
        // (stage 4's u_t in vw: stage 2's stays in sw, stage 3's in tw, for the books)
        last_stage::<G, F, M, LOAD, DRY, FWD>(
            st,
            fr,
            su,
            vw,
            u0,
            w0,
            ku,
            kw,
            tu,
            [bu, bd],
            h / 6.0,
            t1,
            a1,
        );
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    unsafe fn step_avx2<G: Geometry, F: Friction, M: Medium, const LOAD: bool, const DRY: bool>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t0: f64,
        h: f64,
        a0: &[f64],
        u0: &mut [f64],
        w0: &mut [f64],
        a1: &mut [f64],
        redo: bool,
    ) {
        self.step_body::<G, F, M, LOAD, DRY>(st, fr, t0, h, a0, u0, w0, a1, redo)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    #[allow(clippy::too_many_arguments)]
    unsafe fn step_avx512<
        G: Geometry,
        F: Friction,
        M: Medium,
        const LOAD: bool,
        const DRY: bool,
    >(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t0: f64,
        h: f64,
        a0: &[f64],
        u0: &mut [f64],
        w0: &mut [f64],
        a1: &mut [f64],
        redo: bool,
    ) {
        self.step_body::<G, F, M, LOAD, DRY>(st, fr, t0, h, a0, u0, w0, a1, redo)
    }

    /// The step with the books it needs: (loader term, dry power) kept or not.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn step_with<G: Geometry, F: Friction, M: Medium, const LOAD: bool, const DRY: bool>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t0: f64,
        h: f64,
        a0: &[f64],
        u0: &mut [f64],
        w0: &mut [f64],
        a1: &mut [f64],
        redo: bool,
    ) {
        match self.simd {
            // SAFETY (both): `simd` is a code this CPU runs (Simd::detect, or a test's
            // choice among Simd::available).
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => unsafe {
                self.step_avx512::<G, F, M, LOAD, DRY>(st, fr, t0, h, a0, u0, w0, a1, redo)
            },
            #[cfg(target_arch = "x86_64")]
            Simd::Avx2 => unsafe {
                self.step_avx2::<G, F, M, LOAD, DRY>(st, fr, t0, h, a0, u0, w0, a1, redo)
            },
            _ => self.step_body::<G, F, M, LOAD, DRY>(st, fr, t0, h, a0, u0, w0, a1, redo),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn accel_avx2<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        t: f64,
        acc: &mut [f64],
    ) {
        accel_only_at_state(st, fr, &mut self.su, t, acc)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    unsafe fn accel_avx512<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        t: f64,
        acc: &mut [f64],
    ) {
        accel_only_at_state(st, fr, &mut self.su, t, acc)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn books_avx2<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        w0: &[f64],
        h: f64,
    ) -> StepIntegrals {
        self.books_body(st, fr, w0, h)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    unsafe fn books_avx512<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        w0: &[f64],
        h: f64,
    ) -> StepIntegrals {
        self.books_body(st, fr, w0, h)
    }

    /// The step's flows: h/6 times the per-block RK4-weighted stage sums, reduced here
    /// once per step (the same quadrature as an augmented RK4 system). The viscous power
    /// is weighted here from the four stages' u_t (w0 the step's start; stage 2's in sw,
    /// 3's in tw, 4's in vw), block by block in the order the stages would have added it
    /// ((p1 + 2 p2) + 2 p3) + p4, so its bits are those of a sum kept in the stages; the
    /// loader and dry books, which need the stages' u or are kept only for some laws,
    /// are summed in the stages.
    #[inline(always)]
    fn books_body<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        w0: &[f64],
        h: f64,
    ) -> StepIntegrals {
        let (mut u, mut dry, mut visc) = (0.0, 0.0, 0.0);
        let (load, dry_kept) = self.kept;
        let v = st.v;
        for &(a, b) in &st.runs {
            if load {
                u += lane_sum(&self.bu[a..b]);
            }
            if dry_kept {
                dry += lane_sum(&self.bd[a..b]);
            }
            let (dir, th) = (&st.dir[a..b], &st.onset[a..b]);
            let (w1, w2, w3, w4) = (&w0[a..b], &self.sw[a..b], &self.tw[a..b], &self.vw[a..b]);
            // per block into ku (the RK4 sums, free once the step is taken), then summed
            let per_block = &mut self.ku[a..b];
            visc_per_block(fr, v, [dir, th, w1, w2, w3, w4], per_block);
            visc += lane_sum(per_block);
        }
        let h6 = h / 6.0;
        StepIntegrals {
            u: h6 * u,
            dry: h6 * dry,
            visc: h6 * visc,
        }
    }
}

impl Integrator for Rk4 {
    fn name(&self) -> &'static str {
        "rk4"
    }
    fn order(&self) -> u32 {
        4
    }

    fn accel_only<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t: f64,
        acc: &mut [f64],
    ) {
        match self.simd {
            // SAFETY (both): `simd` is a code this CPU runs.
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => unsafe { self.accel_avx512(st, fr, t, acc) },
            #[cfg(target_arch = "x86_64")]
            Simd::Avx2 => unsafe { self.accel_avx2(st, fr, t, acc) },
            _ => accel_only_at_state(st, fr, &mut self.su, t, acc),
        }
    }

    /// A step, or (`redo`) the last one again from the start state it saved.
    #[allow(clippy::too_many_arguments)]
    fn step<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &mut State<G>,
        fr: &Blocks<F, M>,
        t0: f64,
        h: f64,
        a0: &[f64],
        u0: &mut [f64],
        w0: &mut [f64],
        a1: &mut [f64],
        redo: bool,
    ) {
        // no loader work at v = 0; no dry power for beta-free Coulomb friction
        match (st.v != 0.0, !fr.fr.dry_power_is_zero()) {
            (true, true) => {
                self.step_with::<G, F, M, true, true>(st, fr, t0, h, a0, u0, w0, a1, redo)
            }
            (true, false) => {
                self.step_with::<G, F, M, true, false>(st, fr, t0, h, a0, u0, w0, a1, redo)
            }
            (false, true) => {
                self.step_with::<G, F, M, false, true>(st, fr, t0, h, a0, u0, w0, a1, redo)
            }
            (false, false) => {
                self.step_with::<G, F, M, false, false>(st, fr, t0, h, a0, u0, w0, a1, redo)
            }
        }
    }

    fn books<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        w0: &[f64],
        h: f64,
    ) -> StepIntegrals {
        self.books_any(st, fr, w0, h)
    }
}

impl Rk4 {
    fn books_any<G: Geometry, F: Friction, M: Medium>(
        &mut self,
        st: &State<G>,
        fr: &Blocks<F, M>,
        w0: &[f64],
        h: f64,
    ) -> StepIntegrals {
        match self.simd {
            // SAFETY (both): `simd` is a code this CPU runs.
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => unsafe { self.books_avx512(st, fr, w0, h) },
            #[cfg(target_arch = "x86_64")]
            Simd::Avx2 => unsafe { self.books_avx2(st, fr, w0, h) },
            _ => self.books_body(st, fr, w0, h),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::boundary::Ghost;
    use crate::chain::medium::Uniform;
    use crate::friction::Coulomb;

    /// A 9 x 7 grid (wrapped across x, a held wall and a free edge across y) at v > 0,
    /// t = 0.3, with stuck blocks of several reference times and sliding blocks of both
    /// directions in several runs, some at the edges.
    fn grid_state() -> State<crate::chain::geometry::Grid> {
        use crate::chain::geometry::Grid;
        let (nx, ny) = (9, 7);
        let geo = Grid::new(
            nx,
            ny,
            0.1,
            0.12,
            (Ghost::Wrap, Ghost::Wrap),
            (Ghost::Held(0.2), Ghost::Mirror),
        );
        let u0: Vec<f64> = (0..nx * ny)
            .map(|q| 0.5 + 0.1 * (0.37 * q as f64).sin())
            .collect();
        let mut st = State::with_geometry(geo, &u0, 0.03);
        for j in 0..ny {
            for i in 0..nx {
                let p = geo.at(i, j);
                st.tref[p] = 0.05 * ((i + j) % 4) as f64;
                if (i * 3 + j * 5) % 7 < 4 {
                    st.dir[p] = if (i + 2 * j) % 5 == 0 { -1.0 } else { 1.0 };
                    st.onset[p] = 1.0 + 0.01 * i as f64;
                    st.w[p] = 0.03 - 0.2 * (0.7 * p as f64).cos();
                    st.add_to_runs(p);
                }
            }
        }
        st
    }

    #[test]
    fn the_accelerations_of_chosen_blocks_are_those_of_all_bit_for_bit() {
        // accel_at_blocks (after switches: only the switched blocks) against
        // accel_only_at_state over every run, on a grid with every kind of ghost
        let st = grid_state();
        let fr = Blocks {
            fr: Coulomb::new(0.3, 0.5).unwrap(),
            med: Uniform,
        };
        let len = st.u.len();
        let mut all = vec![f64::NAN; len];
        let mut su = vec![0.0; len];
        accel_only_at_state(&st, &fr, &mut su, 0.3, &mut all);
        let sliding: Vec<usize> = (0..len).filter(|&p| st.sliding(p)).collect();
        assert!(sliding.len() > 20 && st.runs.len() > 5);
        let mut some = vec![f64::NAN; len];
        // (the stuck blocks among them are skipped)
        super::super::accel_at_blocks(&st, &fr, 0.3, &(0..len).collect::<Vec<_>>(), &mut some);
        for &p in &sliding {
            assert_eq!(some[p].to_bits(), all[p].to_bits(), "block {p}");
        }
        assert!((0..len)
            .filter(|p| !st.sliding(*p))
            .all(|p| some[p].is_nan()));
    }

    #[test]
    fn a_redo_is_a_restore_and_a_step_bit_for_bit() {
        let fr = Blocks {
            fr: Coulomb::new(0.3, 0.5).unwrap(),
            med: Uniform,
        };
        let st0 = grid_state();
        let len = st0.u.len();
        let run = |redo: bool| {
            let mut st = st0.clone();
            let mut rk = Rk4::new(len - 2);
            let mut a0 = vec![0.0; len];
            let (mut u0, mut w0, mut a1) = (a0.clone(), a0.clone(), a0.clone());
            rk.accel_only(&mut st, &fr, 0.3, &mut a0);
            rk.step(
                &mut st, &fr, 0.3, 0.004, &a0, &mut u0, &mut w0, &mut a1, false,
            );
            if redo {
                rk.step(
                    &mut st, &fr, 0.3, 0.0013, &a0, &mut u0, &mut w0, &mut a1, true,
                );
            } else {
                for &(a, b) in &st.runs.clone() {
                    st.u[a..b].copy_from_slice(&u0[a..b]);
                    st.w[a..b].copy_from_slice(&w0[a..b]);
                }
                rk.step(
                    &mut st, &fr, 0.3, 0.0013, &a0, &mut u0, &mut w0, &mut a1, false,
                );
            }
            let books = rk.books(&st, &fr, &w0, 0.0013);
            (st.u.to_vec(), st.w.to_vec(), a1, books)
        };
        let (with_redo, with_copy) = (run(true), run(false));
        assert_eq!(with_redo, with_copy);
        // and the step did move the sliding blocks (a redo that did nothing fails)
        assert_ne!(with_redo.0, st0.u.to_vec());
    }

    #[test]
    fn every_vector_code_gives_the_baseline_step_bit_for_bit() {
        // two runs of sliding blocks (one block backward) on a ring: one from block 1,
        // whose left neighbour is the ghost of the sliding block n; the step, the end
        // accelerations and the books with each code this CPU runs (baseline, AVX2,
        // AVX-512F) give the same bits
        let n = 170;
        let u0: Vec<f64> = (0..n).map(|i| 0.5 + 0.1 * (0.3 * i as f64).sin()).collect();
        let mut st = State::new(&u0, 0.01, 0.1, Ghost::Wrap, Ghost::Wrap);
        for p in (1..20).chain(25..=n) {
            st.dir[p] = if p == 30 { -1.0 } else { 1.0 };
            st.onset[p] = 1.0;
            st.w[p] = 0.01 - 0.2 * (0.7 * p as f64).cos();
            st.add_to_runs(p);
        }
        let fr = Blocks {
            fr: Coulomb::new(0.3, 0.5).unwrap(),
            med: Uniform,
        };
        let run = |simd: Simd| {
            let mut st = st.clone();
            let mut rk = Rk4::new(n);
            rk.simd = simd;
            let (mut a0, mut u0, mut w0) = (vec![0.0; n + 2], vec![0.0; n + 2], vec![0.0; n + 2]);
            let mut a1 = vec![0.0; n + 2];
            let mut out = Vec::new();
            rk.accel_only(&mut st, &fr, 0.0, &mut a0);
            for k in 0..50 {
                let t0 = 0.005 * k as f64;
                rk.step(
                    &mut st, &fr, t0, 0.005, &a0, &mut u0, &mut w0, &mut a1, false,
                );
                out.push((rk.books(&st, &fr, &w0, 0.005), a1.clone()));
                // the step's end accelerations are those of the new state at t0 + h
                rk.accel_only(&mut st, &fr, t0 + 0.005, &mut a0);
                assert_eq!(a1, a0, "{simd:?}, step {k}");
            }
            (st.u, st.w, out)
        };
        let codes = Simd::available();
        assert_eq!(codes[0], Simd::Baseline);
        assert_eq!(codes.last(), Some(&Simd::detect()));
        let baseline = run(Simd::Baseline);
        for &simd in &codes[1..] {
            assert_eq!(run(simd), baseline, "{simd:?}");
        }
    }

    #[test]
    fn an_all_forward_step_is_the_general_step_bit_for_bit() {
        // when every sliding block slides forward the step does not read dir: run R1
        // alone (that path) and R1 with a second run R2 that has a backward block (the
        // general path); the runs are separated by stuck blocks, so R1's new state, end
        // accelerations and per-block books must be the same bits in both
        let n = 60;
        let u0: Vec<f64> = (0..n).map(|i| 0.5 + 0.1 * (0.3 * i as f64).sin()).collect();
        let mut st = State::new(&u0, 0.02, 0.1, Ghost::Wrap, Ghost::Wrap);
        let (r1, r2) = (1..30, 40..50);
        for p in r1.clone() {
            st.dir[p] = 1.0;
            st.onset[p] = 1.0;
            st.w[p] = 0.01 - 0.2 * (0.7 * p as f64).cos();
            st.add_to_runs(p);
        }
        let fr = Blocks {
            fr: Coulomb::new(0.3, 0.5).unwrap(),
            med: Uniform,
        };
        let mut both = st.clone();
        for p in r2 {
            both.dir[p] = if p == 45 { -1.0 } else { 1.0 };
            both.onset[p] = 1.0;
            both.w[p] = 0.01 - 0.2 * (0.7 * p as f64).cos();
            both.add_to_runs(p);
        }
        let all_forward =
            |st: &State| (st.runs.iter()).all(|&(a, b)| st.dir[a..b].iter().all(|&d| d == 1.0));
        assert!(all_forward(&st) && !all_forward(&both));
        let run = |mut st: State| {
            let mut rk = Rk4::new(n);
            let mut a0 = vec![0.0; n + 2];
            let (mut u0, mut w0, mut a1) = (a0.clone(), a0.clone(), a0.clone());
            rk.accel_only(&mut st, &fr, 0.0, &mut a0);
            let mut out = Vec::new();
            for k in 0..20 {
                let t0 = 0.005 * k as f64;
                rk.step(
                    &mut st, &fr, t0, 0.005, &a0, &mut u0, &mut w0, &mut a1, false,
                );
                std::mem::swap(&mut a0, &mut a1);
                let r = r1.clone();
                out.push((st.u[r.clone()].to_vec(), st.w[r.clone()].to_vec()));
                out.push((a0[r.clone()].to_vec(), rk.bd[r.clone()].to_vec()));
                // (the viscous book per block: left in ku by books)
                rk.books(&st, &fr, &w0, 0.005);
                out.push((rk.bu[r.clone()].to_vec(), rk.ku[r].to_vec()));
            }
            out
        };
        assert_eq!(run(st), run(both));
    }
}
