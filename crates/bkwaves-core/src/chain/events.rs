//! Locating stick and slip in time, and the queue of slip times of quiet blocks.
//!
//! Within a step [t0, t0 + h] every event function g (u_t - v for a sliding block, the
//! distance of phi to a static threshold for a stuck neighbour of a sliding block) is
//! known through its values and time derivatives at both ends: the cubic Hermite
//! interpolant is the integrator's dense output. Its first root in (0, 1] is found
//! exactly: the cubic is split into monotone pieces at the roots of its derivative and
//! the sign change is located to the last bit (safeguarded Newton steps narrow the
//! bracket, bisection finishes it).

use super::integrator::Simd;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Hermite data of one function over a step: value and derivative at both ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hermite {
    /// g(t0)
    pub g0: f64,
    /// g'(t0)
    pub m0: f64,
    /// g(t0 + h)
    pub g1: f64,
    /// g'(t0 + h)
    pub m1: f64,
}

/// A bound on the derivative basis functions of the cubic Hermite interpolant on [0, 1]
/// (|h10|, |h11| <= 4/27 < 0.1482): a cubic with g0, g1 < 0 stays below
/// max(g0, g1) + 0.1482 h (|m0| + |m1|), so where that is negative it has no root.
pub const EXTREMUM_BOUND: f64 = 0.1482;

impl Hermite {
    /// Value at s = (t - t0)/h in [0, 1].
    #[inline]
    pub fn eval(&self, s: f64, h: f64) -> f64 {
        let c = self.coefficients(h);
        ((c[3] * s + c[2]) * s + c[1]) * s + c[0]
    }

    /// Time derivative at s (per unit time).
    #[inline]
    pub fn deriv(&self, s: f64, h: f64) -> f64 {
        let c = self.coefficients(h);
        if h == 0.0 {
            return self.m0;
        }
        ((3.0 * c[3] * s + 2.0 * c[2]) * s + c[1]) / h
    }

    #[inline]
    fn coefficients(&self, h: f64) -> [f64; 4] {
        let (g0, g1, d0, d1) = (self.g0, self.g1, h * self.m0, h * self.m1);
        [
            g0,
            d0,
            -3.0 * g0 - 2.0 * d0 + 3.0 * g1 - d1,
            2.0 * g0 + d0 - 2.0 * g1 + d1,
        ]
    }

    /// A linear combination a * self + b * other.
    #[inline]
    pub fn combine(&self, a: f64, other: &Hermite, b: f64) -> Hermite {
        Hermite {
            g0: a * self.g0 + b * other.g0,
            m0: a * self.m0 + b * other.m0,
            g1: a * self.g1 + b * other.g1,
            m1: a * self.m1 + b * other.m1,
        }
    }

    /// The first s in (0, 1] where the interpolant reaches g >= 0, the function being
    /// inside (g < 0, or g = 0 and decreasing) at s = 0. Returns the smallest s (to the
    /// last bit) at which the interpolant is >= 0.
    ///
    /// The cheap rejection is inlined into the caller (most calls end there: a stuck
    /// neighbour far from its threshold); the root search is not.
    #[inline(always)]
    pub fn first_crossing(&self, h: f64) -> Option<f64> {
        // cheap rejection: |h10|, |h11| <= 4/27 on [0, 1]
        let bound = self.g0.max(self.g1) + EXTREMUM_BOUND * h * (self.m0.abs() + self.m1.abs());
        if bound < 0.0 {
            return None;
        }
        self.root_search::<true>(h)
    }

    /// [`Hermite::first_crossing`] past its cheap rejection (`NEWTON`: the sign change
    /// located by [`locate`]; else by bisecting the whole piece, as before [`locate`]).
    #[inline(never)]
    fn root_search<const NEWTON: bool>(&self, h: f64) -> Option<f64> {
        let c = self.coefficients(h);
        let q = |s: f64| ((c[3] * s + c[2]) * s + c[1]) * s + c[0];
        let dq = |s: f64| (3.0 * c[3] * s + 2.0 * c[2]) * s + c[1];
        // critical points: 3 c3 s^2 + 2 c2 s + c1 = 0
        let mut cuts = [0.0, 1.0, 1.0, 1.0];
        let mut nc = 1;
        let (qa, qb, qc) = (3.0 * c[3], 2.0 * c[2], c[1]);
        let mut add = |s: f64| {
            if s > 0.0 && s < 1.0 {
                cuts[nc] = s;
                nc += 1;
            }
        };
        if qa != 0.0 {
            let disc = qb * qb - 4.0 * qa * qc;
            if disc >= 0.0 {
                let sq = disc.sqrt();
                let r = -0.5 * (qb + qb.signum() * sq);
                if r != 0.0 {
                    add(r / qa);
                    add(qc / r);
                } else {
                    add(0.0);
                }
            }
        } else if qb != 0.0 {
            add(-qc / qb);
        }
        cuts[nc] = 1.0;
        let pts = &mut cuts[..=nc];
        pts.sort_by(|a, b| a.total_cmp(b));
        for k in 0..nc {
            let (lo, hi) = (pts[k], pts[k + 1]);
            if hi <= lo {
                continue;
            }
            let q_hi = q(hi);
            if q_hi < 0.0 {
                continue;
            }
            // q(lo) < 0 here (or lo = 0, the inside start); locate to the last bit
            let q_lo = q(lo);
            if lo > 0.0 && q_lo >= 0.0 {
                return Some(lo);
            }
            return Some(if NEWTON {
                locate(q, dq, lo, q_lo, hi, q_hi)
            } else {
                bisect(q, lo, hi)
            });
        }
        None
    }
}

/// Most Newton steps [`locate`] takes before it hands the bracket to [`bisect`] (from the
/// secant point, the steps converge quadratically: 3.7 on average on the loading run of
/// docs/benchmarks.md, then two bisection passes).
const NEWTON_STEPS: u32 = 12;

/// The sign change of q on [lo, hi] (q(lo) = `q_lo` < 0 or lo the inside start, q(hi) =
/// `q_hi` >= 0; `dq` the derivative): the bracket is narrowed by safeguarded Newton steps
/// (from the secant point; a step that leaves the bracket is a halving; every evaluated
/// point replaces the end of its sign), then a bracket of a few ulps around the converged
/// point is tried, and [`bisect`] finishes. Returns the upper end of a bracket of two
/// adjacent floats, as [`bisect`]: the same float as bisecting the whole piece whenever
/// the computed q changes sign once in it (with rounding noise that makes it change sign
/// several times near the root, one of those changes).
#[inline]
fn locate(
    q: impl Fn(f64) -> f64,
    dq: impl Fn(f64) -> f64,
    mut lo: f64,
    q_lo: f64,
    mut hi: f64,
    q_hi: f64,
) -> f64 {
    let mut x = if q_lo < 0.0 {
        lo - q_lo * ((hi - lo) / (q_hi - q_lo))
    } else {
        hi
    };
    for _ in 0..NEWTON_STEPS {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            return hi;
        }
        if !(x > lo && x < hi) {
            x = mid;
        }
        let qx = q(x);
        if qx >= 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let step = qx / dq(x);
        let next = x - step;
        if step.abs() <= 4.0 * f64::EPSILON * x.abs() {
            // converged: the root is within a few ulps of `next`; bracket it there
            let e = 8.0 * f64::EPSILON * next.abs();
            let (a, b) = (next - e, next + e);
            let (qa, qb) = (q(a), q(b));
            if a > lo && a < hi && qa < 0.0 {
                lo = a;
            }
            if b > lo && b < hi && qb >= 0.0 {
                hi = b;
            }
            break;
        }
        x = next;
    }
    bisect(q, lo, hi)
}

/// Most bisection steps [`bisect`] takes (the bracket [lo, hi] is halved at most this
/// often).
const BISECTION_STEPS: u32 = 200;

/// Bisection of q on [lo, hi] (q(lo) < 0 or lo the inside start, q(hi) >= 0): halve at
/// mid = (lo + hi)/2, keep the half where the sign changes, until mid is lo or hi (the
/// last bit) or after [`BISECTION_STEPS`] halvings; returns hi.
///
/// Two halvings per pass: q at the mid and at both possible next mids are independent,
/// so they are evaluated together (speculatively) and the right one is picked without a
/// branch; the chain of dependent operations is half as long as one halving at a time,
/// and every halving uses the same mid and the same q(mid) as one at a time, so the
/// result is the same to the last bit (tested against the one-at-a-time loop).
#[inline]
fn bisect(q: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let mut steps = 0u32;
    while steps < BISECTION_STEPS {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        // the next mid is (lo + mid)/2 if q(mid) >= 0, else (mid + hi)/2
        let (left, right) = (0.5 * (lo + mid), 0.5 * (mid + hi));
        let (q_mid, q_left, q_right) = (q(mid), q(left), q(right));
        let up = q_mid >= 0.0;
        hi = pick(up, mid, hi);
        lo = pick(up, lo, mid);
        steps += 1;
        if steps >= BISECTION_STEPS {
            break;
        }
        let (next, q_next) = (pick(up, left, right), pick(up, q_left, q_right));
        if next <= lo || next >= hi {
            break;
        }
        let up = q_next >= 0.0;
        hi = pick(up, next, hi);
        lo = pick(up, lo, next);
        steps += 1;
    }
    hi
}

/// `a` if `c`, else `b`, by a bit mask (no branch: the compiler would otherwise branch
/// on the unpredictable sign of q and evaluate only the q it needs, one after another).
#[inline(always)]
fn pick(c: bool, a: f64, b: f64) -> f64 {
    let mask = (c as u64).wrapping_neg();
    f64::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// The sliding blocks of a run that may come to rest in a step of length h: those whose
/// u_t - v (times their direction) may reach 0 on the Hermite cubic by a cheap bound on
/// the cubic (a valid bound, so no root is missed). Appends their
/// offsets in the run to `out`. Blocks are tested eight at a time without a branch (the
/// compiler vectorises the test), a group with no candidate costs no branch per block.
/// `simd` is the vector code to run, one this CPU runs ([`Simd::detect`], detected once
/// by the caller, or one of [`Simd::available`]).
#[allow(clippy::too_many_arguments)]
pub fn rest_candidates(
    simd: Simd,
    dir: &[f64],
    w0: &[f64],
    w1: &[f64],
    a0: &[f64],
    a1: &[f64],
    v: f64,
    h: f64,
    out: &mut Vec<usize>,
) {
    match simd {
        // SAFETY (both): `simd` is a code this CPU runs.
        #[cfg(target_arch = "x86_64")]
        Simd::Avx512 => unsafe { rest_candidates_avx512(dir, w0, w1, a0, a1, v, h, out) },
        #[cfg(target_arch = "x86_64")]
        Simd::Avx2 => unsafe { rest_candidates_avx2(dir, w0, w1, a0, a1, v, h, out) },
        _ => rest_candidates_body(dir, w0, w1, a0, a1, v, h, out),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn rest_candidates_avx2(
    dir: &[f64],
    w0: &[f64],
    w1: &[f64],
    a0: &[f64],
    a1: &[f64],
    v: f64,
    h: f64,
    out: &mut Vec<usize>,
) {
    rest_candidates_body(dir, w0, w1, a0, a1, v, h, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[allow(clippy::too_many_arguments)]
unsafe fn rest_candidates_avx512(
    dir: &[f64],
    w0: &[f64],
    w1: &[f64],
    a0: &[f64],
    a1: &[f64],
    v: f64,
    h: f64,
    out: &mut Vec<usize>,
) {
    rest_candidates_body(dir, w0, w1, a0, a1, v, h, out)
}

#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn rest_candidates_body(
    dir: &[f64],
    w0: &[f64],
    w1: &[f64],
    a0: &[f64],
    a1: &[f64],
    v: f64,
    h: f64,
    out: &mut Vec<usize>,
) {
    const G: usize = 8;
    let hb = EXTREMUM_BOUND * h;
    // g = d (u_t - v) with slopes d a: on [0, 1] the Hermite cubic is g0 h00 + g1 h01 +
    // h (g0' h10 + g1' h11) with h00 + h01 = 1 (both >= 0), 0 <= h10 <= 4/27 and
    // -4/27 <= h11 <= 0, so only a rising start or a falling end can lift it above
    // max(g0, g1) (tighter than first_crossing's own test, which stays the judge)
    let bound = |d: f64, w0: f64, w1: f64, m0: f64, m1: f64| {
        (d * (w0 - v)).max(d * (w1 - v)) + hb * ((d * m0).max(0.0) + (-d * m1).max(0.0))
    };
    // a bound that is not negative (NaN included) leaves the block to the root search
    let candidate = |b: f64| b >= 0.0 || b.is_nan();
    let n = dir.len();
    let m = n / G * G;
    let groups = dir[..m]
        .chunks_exact(G)
        .zip(w0[..m].chunks_exact(G))
        .zip(w1[..m].chunks_exact(G))
        .zip(a0[..m].chunks_exact(G).zip(a1[..m].chunks_exact(G)))
        .enumerate();
    for (g, (((d, w0), w1), (m0, m1))) in groups {
        let mut b = [0.0; G];
        for l in 0..G {
            b[l] = bound(d[l], w0[l], w1[l], m0[l], m1[l]);
        }
        // one test per group: does any lane hold a candidate (the lanes' tests or-ed
        // without a branch)
        let any = b.iter().fold(false, |any, &x| any | candidate(x));
        if any {
            out.extend((0..G).filter(|&l| candidate(b[l])).map(|l| g * G + l));
        }
    }
    for i in m..n {
        if candidate(bound(dir[i], w0[i], w1[i], a0[i], a1[i])) {
            out.push(i);
        }
    }
}

/// The sliding blocks of a run that may be at rest now (the settling's test): the
/// indices i with dir (u_t - v) >= 0, in order (a vectorised pre-test; the settling
/// tests each of them exactly).
pub fn at_rest_candidates(simd: Simd, dir: &[f64], w: &[f64], v: f64, out: &mut Vec<usize>) {
    match simd {
        // SAFETY (both): `simd` is a code this CPU runs.
        #[cfg(target_arch = "x86_64")]
        Simd::Avx512 => unsafe { at_rest_candidates_avx512(dir, w, v, out) },
        #[cfg(target_arch = "x86_64")]
        Simd::Avx2 => unsafe { at_rest_candidates_avx2(dir, w, v, out) },
        _ => at_rest_candidates_body(dir, w, v, out),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn at_rest_candidates_avx2(dir: &[f64], w: &[f64], v: f64, out: &mut Vec<usize>) {
    at_rest_candidates_body(dir, w, v, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn at_rest_candidates_avx512(dir: &[f64], w: &[f64], v: f64, out: &mut Vec<usize>) {
    at_rest_candidates_body(dir, w, v, out)
}

#[inline(always)]
fn at_rest_candidates_body(dir: &[f64], w: &[f64], v: f64, out: &mut Vec<usize>) {
    const G: usize = 8;
    let n = dir.len().min(w.len());
    let m = n / G * G;
    let groups = dir[..m]
        .chunks_exact(G)
        .zip(w[..m].chunks_exact(G))
        .enumerate();
    for (g, (d, w)) in groups {
        let mut b = [0.0; G];
        for l in 0..G {
            b[l] = d[l] * (w[l] - v);
        }
        // one test per group, the lanes or-ed without a branch
        let any = b.iter().fold(false, |any, &x| any | (x >= 0.0));
        if any {
            out.extend((0..G).filter(|&l| b[l] >= 0.0).map(|l| g * G + l));
        }
    }
    out.extend((m..n).filter(|&i| dir[i] * (w[i] - v) >= 0.0));
}

#[derive(Debug, Clone, Copy)]
struct Entry {
    t: f64,
    block: usize,
    version: u32,
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
    // min-heap on time, ties broken by block index
    fn cmp(&self, o: &Self) -> Ordering {
        o.t.total_cmp(&self.t).then(o.block.cmp(&self.block))
    }
}

/// Slip times of stuck blocks whose neighbours are stuck too: their phi rises at the
/// exact rate v, so the time it reaches the threshold is known in closed form.
/// Entries are invalidated lazily by a per-block version number: O(log N) per change.
#[derive(Debug, Clone, Default)]
pub struct SlipQueue {
    heap: BinaryHeap<Entry>,
    version: Vec<u32>,
}

impl SlipQueue {
    /// A queue for blocks with padded indices 0..len.
    pub fn new(len: usize) -> Self {
        SlipQueue {
            heap: BinaryHeap::new(),
            version: vec![0; len],
        }
    }

    /// The versions per cell, and the heap's (allocated entries, bytes per entry)
    /// (measurements: their memory).
    pub(crate) fn parts(&self) -> (&[u32], usize, usize) {
        (
            &self.version,
            self.heap.capacity(),
            std::mem::size_of::<Entry>(),
        )
    }

    /// Schedule block p to slip at time t (replacing any earlier entry).
    pub fn push(&mut self, p: usize, t: f64) {
        if self.heap.len() > 4 * self.version.len() + 1024 {
            // drop stale entries so long runs keep O(N) memory
            let version = &self.version;
            self.heap.retain(|e| version[e.block] == e.version);
        }
        self.version[p] = self.version[p].wrapping_add(1);
        self.heap.push(Entry {
            t,
            block: p,
            version: self.version[p],
        });
    }

    /// Forget block p's entry.
    pub fn invalidate(&mut self, p: usize) {
        self.version[p] = self.version[p].wrapping_add(1);
    }

    /// Earliest valid (time, block).
    pub fn peek(&mut self) -> Option<(f64, usize)> {
        while let Some(e) = self.heap.peek() {
            if self.version[e.block] == e.version {
                return Some((e.t, e.block));
            }
            self.heap.pop();
        }
        None
    }

    /// Remove the earliest valid entry.
    pub fn pop(&mut self) -> Option<(f64, usize)> {
        let top = self.peek()?;
        self.heap.pop();
        self.invalidate(top.1);
        Some(top)
    }

    /// All valid entries (time, block), sorted by block.
    pub fn entries(&self) -> Vec<(f64, usize)> {
        let mut v: Vec<(f64, usize)> = self
            .heap
            .iter()
            .filter(|e| self.version[e.block] == e.version)
            .map(|e| (e.t, e.block))
            .collect();
        v.sort_by_key(|e| e.1);
        v
    }

    /// Number of stored entries (valid or stale).
    pub fn len(&self) -> usize {
        self.heap.len()
    }

    /// True when nothing is stored.
    pub fn is_empty(&self) -> bool {
        self.heap.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_of_a_cubic_is_exact() {
        // g(t) = t^3 - 0.125 on [0, 1]: root at 0.5, data from the exact cubic
        let g = Hermite {
            g0: -0.125,
            m0: 0.0,
            g1: 0.875,
            m1: 3.0,
        };
        let s = g.first_crossing(1.0).unwrap();
        assert!((s - 0.5).abs() < 1e-15, "{s}");
        assert!(g.eval(s, 1.0) >= 0.0);
        // a dip below and back: g = -(t - 0.5)^2 + 0.01 on [0, 1], h = 2
        // in s: t = 2 s; g(s) = -(2 s - 0.5)^2 + 0.01, roots 2 s = 0.4, 0.6
        let g = Hermite {
            g0: -0.24,
            m0: 1.0,
            g1: -2.24,
            m1: -3.0,
        };
        let s = g.first_crossing(2.0).unwrap();
        assert!((s - 0.2).abs() < 1e-14, "{s}");
        // starts at zero going down: no crossing
        let g = Hermite {
            g0: 0.0,
            m0: -1.0,
            g1: -0.5,
            m1: 0.0,
        };
        assert_eq!(g.first_crossing(1.0), None);
    }

    /// The bisection one halving at a time (as it was before two per pass).
    fn bisect_one_at_a_time(q: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
        for _ in 0..BISECTION_STEPS {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if q(mid) >= 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }

    #[test]
    fn two_halvings_per_pass_give_the_bisection_bit_for_bit() {
        let mut x = 0x2545f4914f6cdd1du64;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut checked = 0;
        for k in 0..20000 {
            // random cubics (some with tiny or huge coefficients, some flat enough that
            // rounding makes q non-monotone near the root), random brackets
            let scale = [1.0, 1e-12, 1e8, 1e-300][k % 4];
            let c = [
                scale * rnd(),
                scale * rnd(),
                scale * rnd(),
                if k % 7 == 0 { 0.0 } else { scale * rnd() },
            ];
            let q = |s: f64| ((c[3] * s + c[2]) * s + c[1]) * s + c[0];
            let (a, b) = (rnd() + 0.5, rnd() + 0.5);
            let (lo, hi) = if k % 5 == 0 {
                (0.0, a.max(b))
            } else {
                (a.min(b), a.max(b))
            };
            let fast = bisect(q, lo, hi);
            let slow = bisect_one_at_a_time(q, lo, hi);
            assert_eq!(
                fast.to_bits(),
                slow.to_bits(),
                "cubic {c:?} on [{lo}, {hi}]"
            );
            checked += 1;
        }
        assert_eq!(checked, 20000);
        // the step limit binds: a root at 0 from lo = 0 halves hi 200 times
        let q = |s: f64| s;
        assert_eq!(bisect(q, 0.0, 1.0), 0.5f64.powi(200));
        assert_eq!(bisect(q, 0.0, 1.0), bisect_one_at_a_time(q, 0.0, 1.0));
        let q = |s: f64| if s > 0.0 { 1.0 } else { -1.0 };
        assert_eq!(bisect(q, 0.0, 0.75), bisect_one_at_a_time(q, 0.0, 0.75));
        // NaN values count as below (lo moves), as before
        let q = |s: f64| if s < 0.3 { f64::NAN } else { s - 0.6 };
        assert_eq!(bisect(q, 0.0, 1.0), bisect_one_at_a_time(q, 0.0, 1.0));
    }

    #[test]
    fn newton_then_bisection_finds_the_sign_change_of_the_bisection() {
        let mut x = 0x5851f42d4c957f2du64;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let (mut same, mut tried) = (0, 0);
        for k in 0..20000 {
            // Hermite data like the engine's (some tiny, some huge, some with a double
            // root or a flat piece), through first_crossing's own splitting
            let scale = [1.0, 1e-12, 1e8, 1e-300][k % 4];
            let g = Hermite {
                g0: -scale * (rnd() + 0.5).abs(),
                m0: scale * 8.0 * rnd(),
                g1: scale * 2.0 * rnd(),
                m1: if k % 9 == 0 { 0.0 } else { scale * 8.0 * rnd() },
            };
            let c = g.coefficients(1.0);
            let q = |s: f64| ((c[3] * s + c[2]) * s + c[1]) * s + c[0];
            let Some(s) = g.first_crossing(1.0) else {
                continue;
            };
            tried += 1;
            assert!(q(s) >= 0.0, "{g:?}: q({s}) = {}", q(s));
            // the bisection of the whole piece, as before the Newton steps
            let slow = g.root_search::<false>(1.0).unwrap();
            if slow.to_bits() == s.to_bits() {
                same += 1;
                continue;
            }
            // they differ only where the computed cubic changes sign more than once:
            // both are sign changes (q below at the float before, >= 0 at it), a few
            // ulps apart (rounding noise around the root)
            let before = |x: f64| f64::from_bits(x.to_bits() - 1);
            for x in [s, slow] {
                assert!(q(before(x)) < 0.0 && q(x) >= 0.0, "{g:?}: {s} {slow}");
            }
            // within the noise: Horner's rounding error (a few eps times sum |c_i| s^i)
            // over the slope q', plus a few ulps; at the scale 1e-300 the values are
            // subnormal, with an absolute rounding of 2^-1074
            let p = ((c[3].abs() * s + c[2].abs()) * s + c[1].abs()) * s + c[0].abs();
            let dq = (3.0 * c[3] * s + 2.0 * c[2]) * s + c[1];
            let noise = (16.0 * f64::EPSILON * p + 16.0 * 5e-324) / dq.abs();
            let apart = (s - slow).abs();
            assert!(
                apart <= noise + 16.0 * f64::EPSILON * s,
                "{g:?}: {s} {slow} ({apart:e} apart, noise {noise:e})"
            );
        }
        // most cubics have one sign change (the same float); the rest are the extreme
        // scales' noise (about 2.5 % of these draws)
        assert!(tried > 5000, "{tried}");
        assert!(same as f64 >= 0.95 * tried as f64, "{same} of {tried}");
        // the inside start (g0 = 0, decreasing) and an exact cubic root
        let g = Hermite {
            g0: -0.125,
            m0: 0.0,
            g1: 0.875,
            m1: 3.0,
        };
        assert_eq!(g.first_crossing(1.0), g.root_search::<false>(1.0));
        let g = Hermite {
            g0: 0.0,
            m0: -1.0,
            g1: 0.5,
            m1: 4.0,
        };
        assert_eq!(g.first_crossing(1.0), g.root_search::<false>(1.0));
    }

    #[test]
    fn the_rest_pre_test_keeps_every_block_the_root_search_would_find() {
        // pseudo-random Hermite data of u_t - v for 203 blocks (groups of 8 and a tail),
        // some far from rest, some crossing, some NaN: rest_candidates must keep every
        // block whose first_crossing is Some (and may keep more)
        let mut x = 0x9e3779b97f4a7c15u64;
        let mut rnd = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let n = 203;
        let (v, h) = (0.1, 0.01);
        let mut cols: [Vec<f64>; 5] = Default::default();
        for i in 0..n {
            let d = if i % 3 == 0 { -1.0 } else { 1.0 };
            let scale = if i % 5 == 0 { 1e-3 } else { 1.0 };
            let w0 = v - d * scale * (rnd() + 0.5);
            // every 7th block may cross (u_t - v changes sign), the others stay away
            let w1 = v - d * scale * (rnd() + if i % 7 == 0 { 0.0 } else { 0.6 });
            let row = [d, w0, w1, 10.0 * rnd(), 10.0 * rnd()];
            for (c, r) in cols.iter_mut().zip(row) {
                c.push(r);
            }
        }
        cols[2][77] = f64::NAN;
        let mut out = Vec::new();
        let [d, w0, w1, a0, a1] = &cols;
        rest_candidates(Simd::detect(), d, w0, w1, a0, a1, v, h, &mut out);
        // every vector code this CPU runs keeps the same candidates
        for simd in Simd::available() {
            let mut other = Vec::new();
            rest_candidates(simd, d, w0, w1, a0, a1, v, h, &mut other);
            assert_eq!(other, out, "{simd:?}");
        }
        let mut found = 0;
        for i in 0..n {
            let g = Hermite {
                g0: d[i] * (w0[i] - v),
                m0: d[i] * a0[i],
                g1: d[i] * (w1[i] - v),
                m1: d[i] * a1[i],
            };
            if g.first_crossing(h).is_some() {
                found += 1;
                assert!(out.contains(&i), "block {i} missed");
            }
        }
        assert!(found > 20 && out.len() < n / 2, "{found} {}", out.len());
    }

    #[test]
    fn queue_is_ordered_and_lazy() {
        let mut q = SlipQueue::new(5);
        q.push(1, 3.0);
        q.push(2, 1.0);
        q.push(3, 2.0);
        q.push(2, 4.0); // reschedule: the old entry is stale
        q.invalidate(3);
        assert_eq!(q.pop(), Some((3.0, 1)));
        assert_eq!(q.pop(), Some((4.0, 2)));
        assert_eq!(q.pop(), None);
        // many reschedules: stale entries are dropped, the order is kept
        let mut q = SlipQueue::new(3);
        for k in 0..100_000 {
            q.push(k % 3, 1e6 - k as f64);
        }
        assert!(q.len() <= 4 * 3 + 1024 + 1);
        assert_eq!(q.pop(), Some((1e6 - 99_999.0, 0)));
        assert_eq!(q.pop(), Some((1e6 - 99_998.0, 2)));
        assert_eq!(q.pop(), Some((1e6 - 99_997.0, 1)));
        assert_eq!(q.pop(), None);
    }
}
