//! The replay reference: the bare RK4 stencil of reference.rs over the run structure the
//! engine stepped on the loading run (a diagnostic next to the contiguous reference; the
//! C twin is the `replay` mode of ../reference.c, same arithmetic in the same order, so
//! with `cc -ffp-contract=off` the two agree bit for bit).
//!
//! For each recorded step (redone steps included, as the engine's counters count them),
//! one RK4 step over each of its runs: the runs of a step lie one after another in the
//! buffers, one held block between two runs (and one before the first, one after the
//! last), each run stepped by the four fused stage passes of reference.rs over its own
//! slice. A held block's value must be the same in every buffer a stage reads or the
//! step writes (its position may have been inside a run in an earlier step), so each run
//! first copies its two held neighbours' u and u_t into the other three buffer pairs:
//! the minimum per-run work of a run with held ends (the engine fills its runs'
//! neighbours too).

use crate::reference::stage;

/// The run structure of a sequence of steps: `counts[s]` runs in step s, whose lengths
/// are the next `counts[s]` entries of `lens`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Runs {
    pub counts: Vec<u32>,
    pub lens: Vec<u32>,
}

impl Runs {
    /// Add one step with these run lengths.
    pub fn push_step(&mut self, lens: &[u32]) {
        self.counts.push(lens.len() as u32);
        self.lens.extend_from_slice(lens);
    }

    /// The steps whose run lengths pass `keep`, in their order.
    pub fn select(&self, keep: impl Fn(&[u32]) -> bool) -> Runs {
        let mut out = Runs::default();
        let mut r = 0;
        for &c in &self.counts {
            let lens = &self.lens[r..r + c as usize];
            if keep(lens) {
                out.push_step(lens);
            }
            r += c as usize;
        }
        out
    }

    /// Block updates of one pass over the steps (the sum of the run lengths).
    pub fn updates(&self) -> u64 {
        self.lens.iter().map(|&l| l as u64).sum()
    }

    /// Buffer length the replay needs: the widest step's runs, each followed by one held
    /// block, plus the first held block.
    pub fn buffer_len(&self) -> usize {
        let mut r = 0;
        let mut widest = 0;
        for &c in &self.counts {
            let c = c as usize;
            let w: usize = self.lens[r..r + c].iter().map(|&l| l as usize + 1).sum();
            widest = widest.max(w);
            r += c;
        }
        widest + 1
    }

    /// The file the C replay reads: u32 little-endian: the number of steps, the number of
    /// runs, the counts, the lengths.
    pub fn to_bytes(&self) -> Vec<u8> {
        let head = [self.counts.len() as u32, self.lens.len() as u32];
        let all = head.iter().chain(&self.counts).chain(&self.lens);
        all.flat_map(|x| x.to_le_bytes()).collect()
    }
}

/// Buffers and parameters of the replay loop.
pub struct Replay<'a> {
    runs: &'a Runs,
    k: f64,
    g2: f64,
    v: f64,
    h: f64,
    /// u, u_t (current), the next step's accumulators and two stage buffers.
    b: [Vec<f64>; 8],
}

impl<'a> Replay<'a> {
    /// The replay of `runs` at dx, damping gamma, step h = step * dx; every buffer starts
    /// at reference.rs's initial state (u in the u buffers, u_t in the u_t buffers).
    pub fn new(runs: &'a Runs, dx: f64, gamma: f64, step: f64) -> Self {
        let len = runs.buffer_len();
        let b: [Vec<f64>; 8] = std::array::from_fn(|j| {
            (0..len)
                .map(|i| {
                    if j % 2 == 0 {
                        0.6 - 1e-3 * (0.1 * i as f64).sin()
                    } else {
                        -1e-2 * (0.1 * i as f64).cos()
                    }
                })
                .collect()
        });
        Replay {
            runs,
            k: 1.0 / (dx * dx),
            g2: 2.0 * gamma,
            v: 0.0,
            h: step * dx,
            b,
        }
    }

    #[inline(always)]
    fn passes_body(&mut self, passes: u64) {
        let (k, g2, v, h) = (self.k, self.g2, self.v, self.h);
        let (h2, h3, h6) = (0.5 * h, h / 3.0, h / 6.0);
        let (counts, lens) = (&self.runs.counts, &self.runs.lens);
        let [u, w, uo, wo, s1u, s1w, s2u, s2w] = &mut self.b;
        for _ in 0..passes {
            let mut r = 0;
            for &c in counts {
                let c = c as usize;
                let mut a = 0; // the run's left held block
                for &n in &lens[r..r + c] {
                    let n = n as usize;
                    let e = a + n + 1; // its right held block
                    for p in [a, e] {
                        (uo[p], s1u[p], s2u[p]) = (u[p], u[p], u[p]);
                        (wo[p], s1w[p], s2w[p]) = (w[p], w[p], w[p]);
                    }
                    let (u, w) = (&u[a..=e], &w[a..=e]);
                    let (uo, wo) = (&mut uo[a..=e], &mut wo[a..=e]);
                    let (s1u, s1w) = (&mut s1u[a..=e], &mut s1w[a..=e]);
                    let (s2u, s2w) = (&mut s2u[a..=e], &mut s2w[a..=e]);
                    uo[1..=n].copy_from_slice(&u[1..=n]);
                    wo[1..=n].copy_from_slice(&w[1..=n]);
                    stage(n, u, w, u, w, uo, wo, s1u, s1w, k, g2, v, h6, h2);
                    stage(n, s1u, s1w, u, w, uo, wo, s2u, s2w, k, g2, v, h3, h2);
                    stage(n, s2u, s2w, u, w, uo, wo, s1u, s1w, k, g2, v, h3, h);
                    stage(n, s1u, s1w, u, w, uo, wo, s2u, s2w, k, g2, v, h6, 0.0);
                    a = e;
                }
                r += c;
                std::mem::swap(u, uo);
                std::mem::swap(w, wo);
            }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn passes_avx2(&mut self, passes: u64) {
        self.passes_body(passes)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    unsafe fn passes_avx512(&mut self, passes: u64) {
        self.passes_body(passes)
    }

    /// Replay the steps `passes` times with AVX-512 code (None when the CPU has none).
    pub fn run_avx512(&mut self, passes: u64) -> Option<()> {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx512f") {
            // SAFETY: the feature was detected on this CPU.
            unsafe { self.passes_avx512(passes) };
            return Some(());
        }
        let _ = passes;
        None
    }

    /// Replay the steps `passes` times (AVX2 code where the CPU has it; the same bits).
    pub fn run(&mut self, passes: u64) {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY: the features were detected on this CPU.
            unsafe { self.passes_avx2(passes) };
            return;
        }
        self.passes_body(passes)
    }

    /// Replay the steps `passes` times with the baseline x86-64 code (SSE2).
    pub fn run_baseline(&mut self, passes: u64) {
        self.passes_body(passes)
    }

    /// Sum of u and u_t over the whole buffer (the checksum printed by reference.c's
    /// replay).
    pub fn checksum(&self) -> f64 {
        (0..self.b[0].len())
            .map(|i| self.b[0][i] + self.b[1][i])
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::Reference;

    #[test]
    fn one_run_of_n_blocks_is_the_contiguous_reference() {
        // every step one run of all n blocks: the replay must be reference.rs's loop, bit
        // for bit (the same initial state, stencil and held ends)
        let (n, steps) = (37, 50);
        let mut runs = Runs::default();
        for _ in 0..steps {
            runs.push_step(&[n as u32]);
        }
        assert_eq!(runs.buffer_len(), n + 2);
        let mut rep = Replay::new(&runs, 0.05, 0.3, 0.05);
        rep.run_baseline(2);
        let mut r = Reference::new(n, 0.05, 0.3, 0.05);
        r.run_baseline(2 * steps as u64);
        let (u, w) = r.state();
        assert_eq!(&rep.b[0][..], u);
        assert_eq!(&rep.b[1][..], w);
        assert!(u[1..=n].iter().any(|&x| x != rep_initial_u(1)));
    }

    fn rep_initial_u(i: usize) -> f64 {
        0.6 - 1e-3 * (0.1 * i as f64).sin()
    }

    #[test]
    fn runs_lie_one_after_another_with_held_blocks_kept() {
        // two runs of 2 and 3 blocks: positions 0, 3 and 7 are held and never change
        let mut runs = Runs::default();
        runs.push_step(&[2, 3]);
        runs.push_step(&[2, 3]);
        assert_eq!(runs.buffer_len(), 7 + 1);
        assert_eq!(runs.updates(), 10);
        let mut rep = Replay::new(&runs, 0.05, 0.3, 0.05);
        rep.run(3);
        for p in [0, 3, 7] {
            assert_eq!(rep.b[0][p], rep_initial_u(p), "held block {p} moved");
        }
        for p in [1, 2, 4, 5, 6] {
            assert_ne!(rep.b[0][p], rep_initial_u(p), "block {p} not stepped");
        }
        // a step's runs are selected whole
        let two = runs.select(|l| l.len() == 2);
        assert_eq!(two, runs);
        assert_eq!(runs.select(|l| l[0] > 2), Runs::default());
    }

    #[test]
    fn a_block_held_after_being_stepped_keeps_its_value() {
        // block 3 slides in the first step (one run of 5) and is held between two runs of
        // 2 in the second: it must keep its value from the first step
        let mut first = Runs::default();
        first.push_step(&[5]);
        let mut both = first.clone();
        both.push_step(&[2, 2]);
        let mut one = Replay::new(&first, 0.05, 0.3, 0.05);
        one.run(1);
        let mut two = Replay::new(&both, 0.05, 0.3, 0.05);
        two.run(1);
        assert_ne!(one.b[0][3], rep_initial_u(3));
        assert_eq!(two.b[0][3], one.b[0][3]);
        assert_eq!(two.b[1][3], one.b[1][3]);
        assert_ne!(two.b[0][2], one.b[0][2]);
    }

    #[test]
    fn the_file_holds_counts_then_lengths() {
        let mut runs = Runs::default();
        runs.push_step(&[4]);
        runs.push_step(&[1, 2]);
        let words: Vec<u32> = runs
            .to_bytes()
            .chunks(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(words, [2, 3, 1, 2, 4, 1, 2]);
    }
}
