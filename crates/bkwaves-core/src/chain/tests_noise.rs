//! Noise in the chain (sources/noise.rs): the Poisson statistics of spontaneous slips
//! against the requested law, restart bit for bit, zero rate = the noiseless engine.

use super::sources::Cause;
use super::*;
use crate::boundary::{Free, Periodic};
use crate::friction::Coulomb;
use crate::noise::NoiseLaw;

fn cfg(dx: f64, v: f64) -> ChainConfig {
    ChainConfig { dx, v, step: 0.05 }
}

/// Kolmogorov-Smirnov test of samples against the uniform law on (0, 1): the p-value
/// (asymptotic Kolmogorov distribution with Stephens' small-sample correction).
fn ks_uniform(mut u: Vec<f64>) -> f64 {
    u.sort_by(f64::total_cmp);
    let n = u.len() as f64;
    let d = u
        .iter()
        .enumerate()
        .map(|(i, &x)| (x - i as f64 / n).max((i + 1) as f64 / n - x))
        .fold(0.0, f64::max);
    let lam = (n.sqrt() + 0.12 + 0.11 / n.sqrt()) * d;
    let p: f64 = (1..=100)
        .map(|k| {
            let k = k as f64;
            2.0 * (-1f64).powf(k - 1.0) * (-2.0 * k * k * lam * lam).exp()
        })
        .sum();
    p.clamp(0.0, 1.0)
}

/// A stress profile with phi well below 1 everywhere and distinct values per block.
fn ramp_state(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 0.2 + 0.3 * ((i as f64 * 0.7).sin() * 0.5 + 0.5))
        .collect()
}

/// The first spontaneous slip of `runs` seeded loading ramps (v > 0, nothing else
/// happens before it): its time, transformed by the exact distribution of the first
/// event of the requested law (1 - exp(-sum_i int lambda(phi_i + v s) ds)), should be
/// uniform. `off` scales the rate the transform assumes (1: the true one).
fn first_slip_uniforms(law: &NoiseLaw, runs: u64, off: f64) -> Vec<f64> {
    let (n, v, dx) = (12, 0.01, 0.5);
    let fr = Coulomb::new(0.3, f64::INFINITY).unwrap();
    let u0 = ramp_state(n);
    let mut out = Vec::new();
    for seed in 0..runs {
        let mut ch = Chain::new(cfg(dx, v), fr, &Free, &u0, None).unwrap();
        let phi0 = ch.phi();
        assert!(phi0.iter().all(|&x| x < 0.9));
        ch.set_noise(law.clone(), 0.0, 1000 + seed).unwrap();
        ch.run(1e6, 1, u64::MAX).unwrap();
        let e = ch.catalog.events[0];
        assert_eq!(e.kind, Cause::Source(1), "the first event is spontaneous");
        let t = e.t_start;
        // the cumulative rate of the first spontaneous slip up to t, every block alike
        let mass: f64 = phi0.iter().map(|&p| law.mass(p, v, t, 1.0)).sum();
        out.push(1.0 - (-off * mass).exp());
    }
    out
}

/// A table law with a zero stretch, a flat piece, a steep step and kinks where the
/// ramp's blocks are before their first spontaneous slip (x_i from 0.63-0.78 at the start,
/// up by 0.02-0.09: every piece from 0.62 to 1 has first slips at rate 0.5).
fn table_law(rate: f64) -> NoiseLaw {
    let u = [0.62, 0.7, 0.75, 0.751, 0.8, 1.0];
    let g = [0.0, 0.1, 0.1, 1.0, 2.0, 2.5];
    NoiseLaw::with_table("table", rate, f64::NAN, f64::NAN, &u, &g).unwrap()
}

/// A peaked table (rising, then falling, then rising to g(1) = 1) whose peak g = 4 at
/// x = 0.5 lies among the ramp's blocks (x_i from -0.07 to 0.78 at the start; 0.36 and
/// 0.49 below the peak, four blocks on the fall): the thinning bound must be the running
/// maximum G (4 from x = 0.5 on), not g at the largest stress (0.62 at 0.78), or the
/// blocks near the peak are under-sampled.
fn peaked_law(rate: f64) -> NoiseLaw {
    let u = [0.1, 0.5, 0.65, 1.0];
    let g = [0.0, 4.0, 0.4, 1.0];
    NoiseLaw::with_table("table", rate, f64::NAN, f64::NAN, &u, &g).unwrap()
}

#[test]
fn first_spontaneous_slips_on_a_loading_ramp_follow_the_law() {
    // rates such that the first slip comes long before any block reaches its threshold
    for law in [
        NoiseLaw::new("constant", 0.05, f64::NAN, f64::NAN).unwrap(),
        NoiseLaw::new("exponential", 0.5, 0.1, f64::NAN).unwrap(),
        NoiseLaw::new("power", 0.1, f64::NAN, 3.0).unwrap(),
        table_law(0.5),
        peaked_law(0.05),
    ] {
        let name = law.law.name();
        let p = ks_uniform(first_slip_uniforms(&law, 2000, 1.0));
        assert!(p > 0.01, "{name}: KS p = {p}");
        // the test can fail: the rate off by 20 % is refused
        let p_off = ks_uniform(first_slip_uniforms(&law, 2000, 1.2));
        assert!(
            p_off < 1e-3,
            "{name}: KS p = {p_off} with the rate off by 20 %"
        );
    }
}

/// Spontaneous slips over a long loaded run with a constant law: the rate is
/// rate x (number of stuck blocks), which changes during the events (a few per cent of
/// the block-time slides here: counting every block is refused).
/// The compensator between successive spontaneous slips, rate int n_stuck dt (from the
/// slip records), must be unit exponential (time rescaling).
#[test]
fn spontaneous_slips_during_events_are_poisson_in_the_stuck_blocks() {
    let (n, rate) = (40, 0.02);
    let fr = Coulomb::new(0.3, f64::INFINITY).unwrap();
    let u0: Vec<f64> = (0..n)
        .map(|i| 0.45 + 0.1 * (i as f64 * 1.3).sin())
        .collect();
    let mut ch = Chain::new(cfg(0.1, 0.01), fr, &Periodic, &u0, None).unwrap();
    let law = NoiseLaw::new("constant", rate, f64::NAN, f64::NAN).unwrap();
    ch.set_noise(law, 0.3, 7).unwrap();
    let t_end = 1500.0;
    ch.run(t_end, usize::MAX, u64::MAX).unwrap();
    let slips = &ch.catalog.slips;
    let spont: Vec<f64> = slips
        .iter()
        .filter(|r| r.kind == Cause::Source(1))
        .map(|r| r.t_start)
        .collect();
    assert!(spont.len() > 300, "{} spontaneous slips", spont.len());
    // the runs slide: a good share of the kicks come while other blocks slide
    let during = spont
        .iter()
        .filter(|&&t| {
            slips
                .iter()
                .any(|r| r.t_start < t && (r.t_end.is_nan() || r.t_end > t))
        })
        .count();
    assert!(during > 30, "{during} kicks during events");
    // sliding time in [a, b]: sum over slip intervals of their overlap
    let sliding = |a: f64, b: f64| -> f64 {
        slips
            .iter()
            .map(|r| {
                let end = if r.t_end.is_nan() { t_end } else { r.t_end };
                (end.min(b) - r.t_start.max(a)).max(0.0)
            })
            .sum()
    };
    let mut prev = 0.0;
    let mut z = Vec::new();
    for &t in &spont {
        let stuck = n as f64 * (t - prev) - sliding(prev, t);
        z.push(1.0 - (-rate * stuck).exp());
        prev = t;
    }
    let p = ks_uniform(z.clone());
    assert!(p > 0.01, "KS p = {p} over {} slips", z.len());
    // counting every block, sliding ones too, is refused (the test can fail)
    let mut prev = 0.0;
    let wrong: Vec<f64> = spont
        .iter()
        .map(|&t| {
            let u = 1.0 - (-rate * n as f64 * (t - prev)).exp();
            prev = t;
            u
        })
        .collect();
    assert!(ks_uniform(wrong) < 1e-3);
    let (cand, kicks) = ch.noise_counters().unwrap();
    assert_eq!(kicks as usize, spont.len());
    assert!(cand >= kicks);
}

fn noisy_chain(u0: &[f64], method: integrator::Method, law: &NoiseLaw) -> Chain<Coulomb> {
    let fr = Coulomb::new(0.3, 0.5).unwrap();
    let mut ch = Chain::new(cfg(0.2, 1e-2), fr, &Periodic, u0, None).unwrap();
    ch.set_integrator(method).unwrap();
    ch.set_noise(law.clone(), 0.2, 11).unwrap();
    ch.add_trigger(Trigger {
        t: 5.0,
        block: 3,
        kind: TriggerKind::Kick { du_t: -0.5 },
    })
    .unwrap();
    ch.add_snapshots(&[50.0, 100.0], 2).unwrap();
    ch
}

#[test]
fn a_noisy_chain_restored_from_a_checkpoint_continues_bit_for_bit() {
    use integrator::Method;
    let u0: Vec<f64> = (0..60)
        .map(|i| 0.5 + 0.3 * (i as f64 * 0.37).sin())
        .collect();
    let laws = [
        NoiseLaw::new("exponential", 0.05, 0.1, f64::NAN).unwrap(),
        table_law(0.05),
        peaked_law(0.05),
    ];
    for (law, method) in laws
        .iter()
        .flat_map(|l| [(l, Method::Rk4), (l, Method::Midpoint)])
    {
        let name = law.law.name();
        let mut whole = noisy_chain(&u0, method, law);
        whole.run(150.0, usize::MAX, u64::MAX).unwrap();
        let (_, kicks) = whole.noise_counters().unwrap();
        assert!(kicks >= 5, "{name}: {kicks} spontaneous slips");
        // stop on the step budget (mid-event) several times, save, restore elsewhere
        let mut part = noisy_chain(&u0, method, law);
        let mut restarts = 0;
        loop {
            let stop = part.run(150.0, usize::MAX, 333).unwrap();
            if stop != Stop::Steps {
                break;
            }
            let bytes = part.checkpoint();
            let mut other = noisy_chain(&[0.0; 60], method, law);
            other.restore(&bytes).unwrap();
            assert!(
                other.checkpoint() == bytes,
                "restore then checkpoint differs"
            );
            part = other;
            restarts += 1;
        }
        assert!(restarts > 3);
        assert!(whole.u() == part.u(), "{name} {method:?}: u differs");
        assert!(
            whole.checkpoint() == part.checkpoint(),
            "{name} {method:?}: states differ"
        );
        let spont = |c: &Chain<Coulomb>| {
            c.catalog
                .events
                .iter()
                .filter(|e| e.kind == Cause::Source(1))
                .count()
        };
        assert!(spont(&whole) >= 3, "{name}");
        // another seed differs; a noiseless chain, or one with another law (a table
        // with other values), refuses the noisy checkpoint
        let fr = Coulomb::new(0.3, 0.5).unwrap();
        let mut plain = Chain::new(cfg(0.2, 1e-2), fr, &Periodic, &u0, None).unwrap();
        plain.set_integrator(method).unwrap();
        assert!(plain.restore(&whole.checkpoint()).is_err());
        let other_table =
            NoiseLaw::with_table("table", 0.05, f64::NAN, f64::NAN, &[0.25, 1.0], &[0.0, 1.0])
                .unwrap();
        let mut another_law = noisy_chain(&u0, method, &other_table);
        assert!(another_law.restore(&whole.checkpoint()).is_err(), "{name}");
        let mut other = noisy_chain(&u0, method, law);
        other.set_noise(law.clone(), 0.2, 12).unwrap();
        other.run(150.0, usize::MAX, u64::MAX).unwrap();
        assert!(other.u() != whole.u(), "{name}");
    }
}

#[test]
fn zero_rate_is_the_noiseless_chain_and_bad_kicks_are_named() {
    let u0: Vec<f64> = (0..60)
        .map(|i| 0.5 + 0.3 * (i as f64 * 0.37).sin())
        .collect();
    let fr = Coulomb::new(0.3, 0.5).unwrap();
    let mut plain = Chain::new(cfg(0.2, 1e-2), fr, &Periodic, &u0, None).unwrap();
    let mut zero = plain.clone();
    let law = NoiseLaw::new("power", 0.0, f64::NAN, 2.0).unwrap();
    zero.set_noise(law.clone(), 0.1, 3).unwrap();
    assert!(zero.noise_counters().is_none());
    plain.run(300.0, usize::MAX, u64::MAX).unwrap();
    zero.run(300.0, usize::MAX, u64::MAX).unwrap();
    assert!(plain.checkpoint() == zero.checkpoint());
    for k in [-0.1, f64::NAN, f64::INFINITY] {
        match zero.set_noise(law.clone(), k, 1) {
            Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "kick"),
            r => panic!("kick {k}: {r:?}"),
        }
    }
}

#[test]
fn quiet_stretches_are_jumped_not_stepped() {
    // an activated noise on a slowly loaded chain: every quiet stretch is one jump per
    // candidate (or per event start), never stepped
    let fr = Coulomb::new(0.3, f64::INFINITY).unwrap();
    let u0 = ramp_state(200);
    let mut ch = Chain::new(cfg(0.5, 1e-4), fr, &Free, &u0, None).unwrap();
    let law = NoiseLaw::new("exponential", 1.0, 0.05, f64::NAN).unwrap();
    ch.set_noise(law, 0.0, 5).unwrap();
    ch.run(2000.0, usize::MAX, u64::MAX).unwrap();
    let (cand, kicks) = ch.noise_counters().unwrap();
    let events = ch.catalog.events.len() as u64;
    assert!(cand > 5 && kicks >= 1, "{cand} candidates, {kicks} kicks");
    assert!(
        ch.counters.jumps <= cand + events + 1,
        "{:?}: {cand} candidates, {events} events",
        ch.counters
    );
}

/// A chain seen by the noise source: fixed stresses, block 0 sliding (the sliding
/// bound: candidates at n rate G(1), kept with g(x_i)/G(1)).
struct FixedView {
    t: f64,
    x: Vec<f64>,
}

impl super::sources::View for FixedView {
    fn time(&self) -> f64 {
        self.t
    }
    fn n(&self) -> usize {
        self.x.len()
    }
    fn n_sliding(&self) -> usize {
        1
    }
    fn sliding(&self, k: usize) -> bool {
        k == 0
    }
    fn stress(&self, k: usize) -> f64 {
        self.x[k]
    }
    fn max_loading_rate(&self) -> f64 {
        0.0
    }
    fn switches(&self) -> u64 {
        0
    }
}

/// While blocks slide the stuck ones are only known to be below their threshold, so the
/// bound is G(1) = max_{x < 1} g: 4 for the peaked table (whose g(1) = 1). Stuck blocks
/// at its peak slip at rate 4 rate each, the others at rate g(x): over t = 2e4 the
/// spontaneous slips of each kind are Poisson with those means (the bound 1, g(1), would
/// keep at most rate per block: 4 times too few at the peak).
#[test]
fn while_blocks_slide_the_bound_is_the_largest_rate_below_the_threshold() {
    use super::sources::{noise::Noise, Source};
    let law = peaked_law(0.01);
    assert_eq!(law.sup_below_threshold(), 4.0);
    // block 1 slides; blocks 2-5 at the peak (g = 4), 6-10 at x = 0.8 (g = 0.4 + 0.6 *
    // 0.15/0.35 = 0.657)
    let mut x = vec![0.9; 1];
    x.extend([0.5; 4]);
    x.extend([0.8; 5]);
    let mut view = FixedView { t: 0.0, x };
    let mut noise = Noise::new(law.clone(), 0.0, 21, 0.0).unwrap();
    let t_end = 2e4;
    let mut slips = [0u64; 11];
    loop {
        let t = noise.next_time(&view);
        if t > t_end {
            break;
        }
        view.t = t;
        if let Some(trig) = noise.fire(&view) {
            slips[trig.block + 1] += 1;
        }
    }
    assert_eq!(slips[1], 0, "a sliding block has no rate");
    let peak: u64 = slips[2..6].iter().sum();
    let low: u64 = slips[6..].iter().sum();
    let mu_peak = 4.0 * 4.0 * 0.01 * t_end;
    let mu_low = 5.0 * law.law.g(0.8) * 0.01 * t_end;
    for (n, mu) in [(peak, mu_peak), (low, mu_low)] {
        let z = (n as f64 - mu) / mu.sqrt();
        assert!(z.abs() < 4.0, "{n} slips, expected {mu} (z = {z})");
    }
    // candidates at n rate G(1)
    let cand = noise.candidates as f64;
    let mu = 10.0 * 0.01 * 4.0 * t_end;
    assert!(
        (cand - mu).abs() < 4.0 * mu.sqrt(),
        "{cand} candidates vs {mu}"
    );
}
