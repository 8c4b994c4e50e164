//! Tests of the opt-in step-size control (`step_control.rs`) against an exact solution,
//! the fixed step, and checkpoints.

use super::integrator::Method;
use super::*;
use crate::boundary::Free;
use crate::friction::Coulomb;

const GAMMA: f64 = 1.5;
const V: f64 = 1e-3;
const DELTA: f64 = 0.3;

/// The slow decay rate of u'' = -u + 2 gamma (v - u') (overdamped, gamma > 1).
fn slow_rate() -> f64 {
    GAMMA - (GAMMA * GAMMA - 1.0).sqrt()
}

/// A uniform chain that creeps: every block starts on the slow eigenmode,
/// u = 2 gamma v + DELTA e^(-lambda t), u_t = -lambda DELTA e^(-lambda t) < v, so it
/// slides forward for ever (s > 0) with Lap u = 0: each block is that exact solution.
fn creeping(n: usize, tol: Option<f64>) -> Chain<Coulomb> {
    let cfg = ChainConfig {
        dx: 0.05,
        v: V,
        step: DEFAULT_STEP,
    };
    let u0 = vec![2.0 * GAMMA * V + DELTA; n];
    let w0 = vec![-slow_rate() * DELTA; n];
    let fr = Coulomb::new(GAMMA, f64::INFINITY).unwrap();
    let mut ch = Chain::new(cfg, fr, &Free, &u0, Some(&w0)).unwrap();
    ch.set_step_control(tol).unwrap();
    ch
}

#[test]
fn a_creeping_chain_is_followed_with_long_steps_to_the_exact_solution() {
    let t_end = 20.0;
    let exact = 2.0 * GAMMA * V + DELTA * (-slow_rate() * t_end).exp();
    let mut errors = vec![];
    for tol in [None, Some(1e-12)] {
        let mut ch = creeping(40, tol);
        let e0 = {
            let (k, c, l) = ch.energy();
            k + c + l
        };
        ch.run(t_end, usize::MAX, u64::MAX).unwrap();
        assert_eq!(ch.time(), t_end);
        assert_eq!(ch.n_sliding(), 40, "{tol:?}: a block stuck");
        let err = ch.u().iter().map(|u| (u - exact).abs()).fold(0.0, f64::max);
        let (k, c, l) = ch.energy();
        let led = ch.ledger;
        let residual =
            ((k + c + l) - e0 - (led.load - led.dry - led.viscous)).abs() / (led.dry + led.viscous);
        errors.push((err, ch.counters.steps, residual));
    }
    let (fixed, controlled) = (errors[0], errors[1]);
    // the fixed step: 20 / (0.05 dx) = 8000 steps; the controlled step grows to RK4's
    // stability limit 2.5 / (sqrt(1 + 4/dx^2) + 2 gamma) = 0.058: about 350 steps (397)
    assert_eq!(fixed.1, 8000);
    assert!(
        controlled.1 < 450,
        "controlled steps {} (fixed 8000)",
        controlled.1
    );
    // still the exact solution: RK4's global error at lambda h = 0.022 is ~(lambda h)^4/120
    // relative per unit time, ~1e-10 DELTA over t = 20 at most (measured: 1.7e-12; the
    // fixed step 6e-17); the books close to 7e-10 of the dissipated energy (1e-14)
    assert!(fixed.0 < 1e-14, "fixed step error {:e}", fixed.0);
    assert!(controlled.0 < 1e-10, "controlled error {:e}", controlled.0);
    assert!(controlled.2 < 1e-8, "energy books {:e}", controlled.2);
}

#[test]
fn a_tolerance_never_met_is_the_fixed_step_bit_for_bit() {
    // loading cycles with events; a tolerance below every step's indicator keeps the
    // fixed step (the controller never steps shorter), so the same bits
    let run = |tol: Option<f64>| {
        let cfg = ChainConfig {
            dx: 0.2,
            v: 1e-2,
            step: 0.1,
        };
        let u0: Vec<f64> = (0..60)
            .map(|i| 0.5 + 0.3 * (i as f64 * 0.37).sin() * (i as f64 * 0.11).cos())
            .collect();
        let mut ch = Chain::new(cfg, Coulomb::new(0.3, 0.5).unwrap(), &Free, &u0, None).unwrap();
        ch.set_step_control(tol).unwrap();
        ch.run(200.0, usize::MAX, u64::MAX).unwrap();
        ch
    };
    let (a, b) = (run(None), run(Some(1e-300)));
    assert!(a.catalog.events.len() >= 3);
    assert!(a.u() == b.u() && a.u_t() == b.u_t());
    assert!(a.ledger == b.ledger && a.counters == b.counters);
    let show = |c: &Chain<Coulomb>| format!("{:?}{:?}", c.catalog.slips, c.catalog.events);
    assert!(show(&a) == show(&b));
}

#[test]
fn a_controlled_run_restored_from_a_checkpoint_continues_bit_for_bit() {
    let make = || {
        let mut ch = creeping(30, Some(1e-12));
        // a kick (back to the fixed step) and a stick later
        ch.add_trigger(Trigger {
            t: 3.0,
            block: 7,
            kind: TriggerKind::Kick { du_t: -0.4 },
        })
        .unwrap();
        ch
    };
    let mut whole = make();
    whole.run(12.0, usize::MAX, u64::MAX).unwrap();
    let mut first = make();
    // (stopped before the kick, while the step is long)
    assert_eq!(first.run(12.0, usize::MAX, 30).unwrap(), Stop::Steps);
    assert!(first.time() > 0.5 && first.time() < 3.0, "{}", first.time());
    let bytes = first.checkpoint();
    let mut other = creeping(30, Some(1e-12));
    other.restore(&bytes).unwrap();
    assert!(other.checkpoint() == bytes);
    while other.run(12.0, usize::MAX, 50).unwrap() == Stop::Steps {}
    assert!(whole.checkpoint() == other.checkpoint(), "states differ");
    // (the fixed step would take 4800 steps; with the kick's 168 switches: 1097)
    assert!(whole.counters.steps < 2000, "{}", whole.counters.steps);
    // the tolerance is part of the configuration: another one, or none, is refused
    for tol in [None, Some(1e-11)] {
        let mut wrong = creeping(30, tol);
        let e = wrong.restore(&bytes).unwrap_err().to_string();
        assert!(e.contains("step-size control"), "{e}");
    }
}

#[test]
fn step_control_is_refused_with_the_midpoint_rule_and_bad_tolerances() {
    let mut ch = creeping(5, None);
    ch.set_integrator(Method::Midpoint).unwrap();
    let e = ch.set_step_control(Some(1e-12)).unwrap_err().to_string();
    assert!(e.contains("step_tolerance") && e.contains("rk4"), "{e}");
    let mut ch = creeping(5, Some(1e-12));
    let e = ch.set_integrator(Method::Midpoint).unwrap_err().to_string();
    assert!(e.contains("step_tolerance"), "{e}");
    for bad in [0.0, -1e-9, f64::NAN, f64::INFINITY] {
        let e = creeping(5, None)
            .set_step_control(Some(bad))
            .unwrap_err()
            .to_string();
        assert!(e.contains("step_tolerance"), "{e}");
    }
}

#[test]
fn a_front_keeps_the_fixed_step_and_its_speed() {
    // the tip is always sliding and fast: the indicator there is far above 1e-12, so the
    // controller keeps the fixed step and c (a broken indicator would not)
    let c_of = |tol: Option<f64>| {
        let cfg = ChainConfig {
            dx: 0.1,
            v: 0.0,
            step: DEFAULT_STEP,
        };
        let fr = Coulomb::new(0.45, f64::INFINITY).unwrap();
        let mut ch = Chain::new(cfg, fr, &Free, &[0.6; 300], None).unwrap();
        ch.set_step_control(tol).unwrap();
        ch.add_trigger(Trigger {
            t: 0.0,
            block: 0,
            kind: TriggerKind::Kick { du_t: -2.0 },
        })
        .unwrap();
        ch.run(20.0, usize::MAX, u64::MAX).unwrap();
        let first = |b: usize| {
            ch.catalog
                .slips
                .iter()
                .find(|r| r.block == b)
                .map_or(f64::NAN, |r| r.t_start)
        };
        (0.1 * 100.0 / (first(200) - first(100)), ch.counters.steps)
    };
    let (fixed, controlled) = (c_of(None), c_of(Some(1e-12)));
    // a supersonic front crossed the window (c = 1.2259 at this dx)
    assert!(fixed.0 > 1.0 && fixed.0 < 1.3, "c = {}", fixed.0);
    assert!(
        (controlled.0 - fixed.0).abs() < 1e-10,
        "c {} vs {}",
        controlled.0,
        fixed.0
    );
    assert!(controlled.1 as f64 > 0.9 * fixed.1 as f64);
}

/// A velocity-weakening chain at v_f/dx = 1e-4 (onset sub-steps on by default) with one
/// kicked block, run to t = 3.
fn weakening_run(
    setup: impl Fn(&mut Chain<crate::friction::VelocityWeakening>),
) -> Chain<crate::friction::VelocityWeakening> {
    let cfg = ChainConfig {
        dx: 0.05,
        v: 0.0,
        step: DEFAULT_STEP,
    };
    let fr = crate::friction::VelocityWeakening {
        gamma: 0.3,
        v_f: 5e-6,
        beta: f64::INFINITY,
    };
    let mut ch = Chain::new(cfg, fr, &Free, &[0.55; 60], None).unwrap();
    setup(&mut ch);
    ch.add_trigger(Trigger {
        t: 0.0,
        block: 0,
        kind: TriggerKind::Kick { du_t: -0.5 },
    })
    .unwrap();
    ch.run(3.0, usize::MAX, u64::MAX).unwrap();
    ch
}

#[test]
fn turning_the_step_control_or_the_midpoint_rule_off_restores_the_onset_sub_steps() {
    // the step-size control and the midpoint rule step every block at the law's step
    // (step v_f/theta here); turned off again, the chain is the default one bit for bit
    // (its step dx and the onset's sub-steps), not the law's step
    let plain = weakening_run(|_| {});
    let controlled = weakening_run(|ch| ch.set_step_control(Some(1e-10)).unwrap());
    let restored = weakening_run(|ch| {
        ch.set_step_control(Some(1e-10)).unwrap();
        ch.set_step_control(None).unwrap();
    });
    let via_midpoint = weakening_run(|ch| {
        ch.set_integrator(Method::Midpoint).unwrap();
        ch.set_integrator(Method::Rk4).unwrap();
    });
    assert!(plain.counters.switches > 20, "the front must cross");
    // the law's step takes ~ dx/v_f times more steps
    assert!(controlled.counters.steps > 10 * plain.counters.steps);
    for ch in [&restored, &via_midpoint] {
        assert_eq!(ch.counters.steps, plain.counters.steps);
        assert_eq!(ch.counters.block_steps, plain.counters.block_steps);
        assert_eq!(ch.u(), plain.u());
        assert_eq!(ch.u_t(), plain.u_t());
    }
}
