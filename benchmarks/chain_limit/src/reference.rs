//! The bare RK4 stencil over n contiguous sliding blocks: the real limit of the chain
//! engine's sliding-block updates (the C twin is ../reference.c, same arithmetic in the
//! same order, so with `cc -ffp-contract=off` the two agree bit for bit).
//!
//! u_tt = (u[i-1] + u[i+1] - 2 u[i]) / dx^2 - u[i] + 2 gamma (v - u_t[i]): the engine's
//! forward sliding branch (Coulomb friction, beta = inf), the ends held by stuck
//! neighbours (v = 0). Four right-hand sides per step, each fused with its RK4 update in
//! one pass that writes the next stage into a second buffer (no per-block branch, no
//! reduction), so the compiler vectorises every pass.

/// Buffers and parameters of the reference loop.
pub struct Reference {
    n: usize,
    k: f64,
    g2: f64,
    v: f64,
    h: f64,
    /// u, u_t (current), the next step's accumulators and two stage buffers.
    b: [Vec<f64>; 8],
}

/// One RK4 stage over blocks 1..=n of the given slices (0 and n + 1 are the held
/// neighbours): the right-hand side at (su, sw), added with weight wt into (uo, wo), and
/// the next stage's values u0 + cn su_t, w0 + cn a into (nu, nw).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn stage(
    n: usize,
    su: &[f64],
    sw: &[f64],
    u0: &[f64],
    w0: &[f64],
    uo: &mut [f64],
    wo: &mut [f64],
    nu: &mut [f64],
    nw: &mut [f64],
    k: f64,
    g2: f64,
    v: f64,
    wt: f64,
    cn: f64,
) {
    let it = su[..n + 2]
        .windows(3)
        .zip(&sw[1..=n])
        .zip(u0[1..=n].iter().zip(&w0[1..=n]))
        .zip(uo[1..=n].iter_mut().zip(&mut wo[1..=n]))
        .zip(nu[1..=n].iter_mut().zip(&mut nw[1..=n]));
    for ((((s, &w), (&u0, &w0)), (uo, wo)), (nu, nw)) in it {
        let a = (s[0] + s[2] - 2.0 * s[1]) * k - s[1] + g2 * (v - w);
        *uo += wt * w;
        *wo += wt * a;
        *nu = u0 + cn * w;
        *nw = w0 + cn * a;
    }
}

impl Reference {
    /// n blocks at dx, damping gamma, step h = step * dx; the initial state of reference.c.
    pub fn new(n: usize, dx: f64, gamma: f64, step: f64) -> Self {
        let len = n + 2;
        let mut b: [Vec<f64>; 8] = std::array::from_fn(|_| vec![0.0; len]);
        let [u, w, ..] = &mut b;
        for (i, (u, w)) in u.iter_mut().zip(w.iter_mut()).enumerate() {
            *u = 0.6 - 1e-3 * (0.1 * i as f64).sin();
            *w = -1e-2 * (0.1 * i as f64).cos();
        }
        for j in (2..8).step_by(2) {
            b[j][0] = b[0][0];
            b[j][len - 1] = b[0][len - 1];
            b[j + 1][0] = b[1][0];
            b[j + 1][len - 1] = b[1][len - 1];
        }
        Reference {
            n,
            k: 1.0 / (dx * dx),
            g2: 2.0 * gamma,
            v: 0.0,
            h: step * dx,
            b,
        }
    }

    #[inline(always)]
    fn steps_body(&mut self, steps: u64) {
        let (n, k, g2, v, h) = (self.n, self.k, self.g2, self.v, self.h);
        let (h2, h3, h6) = (0.5 * h, h / 3.0, h / 6.0);
        let [u, w, uo, wo, s1u, s1w, s2u, s2w] = &mut self.b;
        for _ in 0..steps {
            uo[1..=n].copy_from_slice(&u[1..=n]);
            wo[1..=n].copy_from_slice(&w[1..=n]);
            stage(n, u, w, u, w, uo, wo, s1u, s1w, k, g2, v, h6, h2);
            stage(n, s1u, s1w, u, w, uo, wo, s2u, s2w, k, g2, v, h3, h2);
            stage(n, s2u, s2w, u, w, uo, wo, s1u, s1w, k, g2, v, h3, h);
            stage(n, s1u, s1w, u, w, uo, wo, s2u, s2w, k, g2, v, h6, 0.0);
            std::mem::swap(u, uo);
            std::mem::swap(w, wo);
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn steps_avx2(&mut self, steps: u64) {
        self.steps_body(steps)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    unsafe fn steps_avx512(&mut self, steps: u64) {
        self.steps_body(steps)
    }

    /// Advance `steps` RK4 steps with AVX-512 code (None when the CPU has none).
    pub fn run_avx512(&mut self, steps: u64) -> Option<()> {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx512f") {
            // SAFETY: the feature was detected on this CPU.
            unsafe { self.steps_avx512(steps) };
            return Some(());
        }
        let _ = steps;
        None
    }

    /// Advance `steps` RK4 steps (AVX2 code where the CPU has it: Rust never fuses a
    /// multiply and an add, so both paths give the same bits).
    pub fn run(&mut self, steps: u64) {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY: the features were detected on this CPU.
            unsafe { self.steps_avx2(steps) };
            return;
        }
        self.steps_body(steps)
    }

    /// Advance `steps` RK4 steps with the baseline x86-64 code (SSE2).
    pub fn run_baseline(&mut self, steps: u64) {
        self.steps_body(steps)
    }

    /// Sum of u and u_t over the blocks (the checksum printed by reference.c).
    pub fn checksum(&self) -> f64 {
        (1..=self.n).map(|i| self.b[0][i] + self.b[1][i]).sum()
    }

    /// u and u_t, held ends included.
    #[cfg(test)]
    pub fn state(&self) -> (&[f64], &[f64]) {
        (&self.b[0], &self.b[1])
    }
}
