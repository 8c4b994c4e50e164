//! Tests of the chain engine against exact solutions and symmetries.

use super::*;
use crate::boundary::{Fixed, Free, Periodic};
use crate::friction::Coulomb;

fn cfg(dx: f64, v: f64, step: f64) -> ChainConfig {
    ChainConfig { dx, v, step }
}

/// Exact single block sliding forward from u(0) = y0 + 2 gamma v... : returns u(t), u_t(t)
/// for u'' = -u + 2 gamma (v - u'), u(0) = a, u'(0) = b (underdamped, gamma < 1).
fn oscillator(a: f64, b: f64, gamma: f64, v: f64, t: f64) -> (f64, f64) {
    let om = (1.0 - gamma * gamma).sqrt();
    let y0 = a - 2.0 * gamma * v;
    let (ca, cb) = (y0, (b + gamma * y0) / om);
    let e = (-gamma * t).exp();
    let (c, s) = ((om * t).cos(), (om * t).sin());
    let y = e * (ca * c + cb * s);
    let yp = e * ((-gamma * ca + om * cb) * c + (-gamma * cb - om * ca) * s);
    (y + 2.0 * gamma * v, yp)
}

/// First t > 0 where the exact u_t returns to v from below (Newton on a bracket).
fn exact_stick(a: f64, b: f64, gamma: f64, v: f64) -> f64 {
    let om = (1.0 - gamma * gamma).sqrt();
    let f = |t: f64| oscillator(a, b, gamma, v, t).1 - v;
    // bracket by scanning
    let (mut lo, mut hi) = (1e-9, 1e-9);
    let dt = 0.01;
    while f(hi) < 0.0 || hi < 1e-3 {
        lo = hi;
        hi += dt;
        assert!(hi < 4.0 * std::f64::consts::PI / om);
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn single_block_matches_the_damped_oscillator_to_round_off() {
    for &(gamma, v, beta) in &[
        (0.0, 0.0, 0.0),
        (0.3, 0.0, 0.5),
        (0.3, 0.1, 0.5),
        (0.7, 0.02, 1.0),
    ] {
        // one block, free ends: Lap = 0, phi = u. h = 0.05 * 0.002 = 1e-4.
        let fr = Coulomb::new(gamma, beta).unwrap();
        let u0 = if v > 0.0 { 0.7 } else { 0.8 };
        let mut ch = Chain::new(cfg(0.002, v, 0.05), fr, &Free, &[u0], None).unwrap();
        if v == 0.0 {
            ch.add_trigger(Trigger {
                t: 0.0,
                block: 0,
                kind: TriggerKind::Release { dir: 1 },
            })
            .unwrap();
        }
        ch.run(1e4, 2, u64::MAX).unwrap();
        let slips = &ch.catalog.slips;
        assert!(!slips.is_empty(), "no slip");
        // first slip: exact loading time
        let t_slip = if v > 0.0 { (1.0 - u0) / v } else { 0.0 };
        assert!((slips[0].t_start - t_slip).abs() < 1e-12 * (1.0 + t_slip));
        let a = if v > 0.0 { 1.0 } else { u0 };
        let ts = exact_stick(a, v, gamma, v);
        let (u_exact, _) = oscillator(a, v, gamma, v, ts);
        let r = slips[0];
        let err_t = (r.t_end - t_slip - ts).abs();
        let err_u = (r.u_end - u_exact).abs();
        // the stick time is conditioned by the acceleration there, u_tt = -u
        // (h = 1e-4: truncation ~1e-16; what is left is round-off over ~4e4 steps)
        let tol_t = 5e-12 * (1.0 / u_exact.abs()).max(1.0);
        assert!(
            err_t < tol_t,
            "gamma {gamma} v {v}: stick time error {err_t:e}"
        );
        assert!(
            err_u < 5e-12,
            "gamma {gamma} v {v}: stick u error {err_u:e}"
        );
        if v > 0.0 {
            // reloads exactly: next slip when u = 1 again
            let t2 = r.t_end + (1.0 - r.u_end) / v;
            assert!(
                (slips[1].t_start - t2).abs() < 1e-12 * t2,
                "{} vs {t2}",
                slips[1].t_start
            );
            assert_eq!(ch.catalog.finished(), 2);
        }
    }
}

#[test]
fn single_block_error_is_fourth_order_in_the_step() {
    let (gamma, v) = (0.3, 0.0);
    let ts = exact_stick(0.8, 0.0, gamma, v);
    let mut errs = Vec::new();
    for &step in &[0.4, 0.2, 0.1] {
        // dx = 1: h = step
        let fr = Coulomb::new(gamma, 0.0).unwrap();
        let mut ch = Chain::new(cfg(1.0, v, step), fr, &Free, &[0.8], None).unwrap();
        ch.add_trigger(Trigger {
            t: 0.0,
            block: 0,
            kind: TriggerKind::Release { dir: 1 },
        })
        .unwrap();
        ch.run(10.0, 1, u64::MAX).unwrap();
        errs.push((ch.catalog.slips[0].t_end - ts).abs());
    }
    for k in 0..2 {
        let order = (errs[k] / errs[k + 1]).log2();
        assert!(order > 3.5 && order < 5.5, "errors {errs:?}");
    }
}

fn smooth_stress(n: usize, seed: u64) -> Vec<f64> {
    // deterministic smooth random profile in (0.2, 0.95)
    let mut x = seed;
    let mut rnd = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let modes: Vec<(f64, f64, f64)> = (1..6).map(|k| (k as f64, rnd(), rnd())).collect();
    (0..n)
        .map(|i| {
            let xi = i as f64 / n as f64;
            let s: f64 = modes
                .iter()
                .map(|&(k, a, ph)| a / k * (2.0 * std::f64::consts::PI * (k * xi + ph)).sin())
                .sum();
            0.6 + 0.12 * s
        })
        .collect()
}

fn balance(ch: &Chain<Coulomb>, e0: f64) -> (f64, f64) {
    let (k, c, l) = ch.energy();
    let e1 = k + c + l;
    let lg = ch.ledger;
    let resid = (e1 - e0) - (lg.load - lg.dry - lg.viscous - lg.projection + lg.injected);
    (resid, lg.dry + lg.viscous)
}

#[test]
fn energy_balance_closes_to_the_integration_order() {
    let mut compared = 0;
    for (bname, b) in [
        ("free", Box::new(Free) as Box<dyn Boundary>),
        ("fixed", Box::new(Fixed::new(0.5, 0.4).unwrap())),
        ("periodic", Box::new(Periodic)),
    ] {
        // beta = 0.5 and beta = inf (no backward slip, the beta-free books of energy.rs)
        let mut resid = [Vec::new(), Vec::new()];
        let mut backward = [Vec::new(), Vec::new()];
        for (which, beta) in [0.5, f64::INFINITY].into_iter().enumerate() {
            let mut res = Vec::new();
            for &step in &[0.2, 0.1, 0.05, 0.025, 0.0125] {
                let fr = Coulomb::new(0.3, beta).unwrap();
                let u0 = smooth_stress(60, 7);
                let mut ch = Chain::new(cfg(0.2, 1e-2, step), fr, b.as_ref(), &u0, None).unwrap();
                let (k, c, l) = ch.energy();
                let e0 = k + c + l;
                // a fixed time: on the ring a pulse can circulate for ever (re-entry)
                ch.run(120.0, usize::MAX, u64::MAX).unwrap();
                assert!(ch.catalog.events.len() >= 3, "{bname}");
                let (r, diss) = balance(&ch, e0);
                assert!(diss > 0.1, "{bname}: dissipation {diss}");
                res.push((r / diss).abs());
                resid[which].push(r);
                backward[which].push(ch.catalog.slips.iter().filter(|s| s.dir < 0).count());
            }
            // the residual is the integration error of the books: it falls like h^4 or
            // faster (the event sequences differ a little between steps)
            for k in 0..4 {
                assert!(res[k + 1] < res[k] / 5.0, "{bname} beta {beta}: {res:?}");
            }
            if beta.is_finite() {
                assert!(res[4] < 1e-10, "{bname}: {res:?}");
            }
        }
        // where no block slid backward with beta = 0.5 either, the motion is the same and
        // the beta terms cancel exactly: both books leave the same residual (to round-off
        // of the beta = 0.5 sums, ~5e4 steps of O(1) terms), not just one of the same order
        assert!(backward[1].iter().all(|&b| b == 0), "{bname}");
        for (k, (r5, ri)) in resid[0].iter().zip(&resid[1]).enumerate() {
            if backward[0][k] == 0 {
                compared += 1;
                assert!(
                    (r5 - ri).abs() < 1e-10 + 1e-3 * r5.abs(),
                    "{bname}: {resid:?}"
                );
            }
        }
    }
    assert!(compared >= 5, "{compared}");
}

#[test]
fn mirror_symmetry_of_a_front() {
    let n = 120;
    let run = |block: usize| {
        let fr = Coulomb::new(0.3, 0.0).unwrap();
        let mut ch = Chain::new(cfg(0.1, 0.0, 0.05), fr, &Free, &vec![0.6; n], None).unwrap();
        ch.add_trigger(Trigger {
            t: 0.0,
            block,
            kind: TriggerKind::Release { dir: 1 },
        })
        .unwrap();
        ch.run(30.0, 1, u64::MAX).unwrap();
        let mut first = vec![f64::NAN; n];
        for r in &ch.catalog.slips {
            if first[r.block].is_nan() {
                first[r.block] = r.t_start;
            }
        }
        first
    };
    let left = run(0);
    let right = run(n - 1);
    for i in 0..n {
        assert!(left[i].is_finite());
        assert!((left[i] - right[n - 1 - i]).abs() < 1e-12, "block {i}");
    }
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let fr = Coulomb::new(0.3, 0.0).unwrap();
    assert!(Chain::new(cfg(0.1, 0.0, 0.05), fr, &Free, &[], None).is_err());
    assert!(Chain::new(cfg(-0.1, 0.0, 0.05), fr, &Free, &[0.1], None).is_err());
    assert!(Chain::new(cfg(0.1, -1.0, 0.05), fr, &Free, &[0.1], None).is_err());
    assert!(Chain::new(cfg(0.1, 0.0, 2.0), fr, &Free, &[0.1], None).is_err());
    assert!(Chain::new(cfg(0.1, 0.0, 0.05), fr, &Free, &[f64::NAN], None).is_err());
    let mut ch = Chain::new(cfg(0.1, 0.0, 0.05), fr, &Free, &[0.1], None).unwrap();
    assert!(ch
        .add_trigger(Trigger {
            t: 0.0,
            block: 3,
            kind: TriggerKind::Release { dir: 1 }
        })
        .is_err());
    assert!(ch.run(-1.0, 1, 10).is_err());
    assert!(ch.run(f64::NAN, 1, 10).is_err());
    // an absurd kick overflows: an error, not a panic or a hang
    let mut ch = Chain::new(cfg(0.1, 0.0, 0.05), fr, &Free, &[0.1; 5], None).unwrap();
    ch.add_trigger(Trigger {
        t: 0.0,
        block: 2,
        kind: TriggerKind::Kick { du_t: -1e300 },
    })
    .unwrap();
    assert!(ch.run(10.0, 1, 1_000_000).is_err());
}

#[test]
fn midpoint_energy_books_close_to_round_off() {
    use super::integrator::Method;
    for (bname, b) in [
        ("free", Box::new(Free) as Box<dyn Boundary>),
        ("fixed", Box::new(Fixed::new(0.5, 0.4).unwrap())),
        ("periodic", Box::new(Periodic)),
    ] {
        for beta in [0.5, f64::INFINITY] {
            let fr = Coulomb::new(0.3, beta).unwrap();
            let u0 = smooth_stress(60, 7);
            let mut ch = Chain::new(cfg(0.2, 1e-2, 0.1), fr, b.as_ref(), &u0, None).unwrap();
            ch.set_integrator(Method::Midpoint).unwrap();
            assert_eq!(ch.integrator(), "midpoint");
            let (k, c, l) = ch.energy();
            let e0 = k + c + l;
            ch.run(120.0, usize::MAX, u64::MAX).unwrap();
            assert!(ch.catalog.events.len() >= 3, "{bname}");
            let (r, diss) = balance(&ch, e0);
            eprintln!("midpoint {bname}: residual/dissipation {:e}", r / diss);
            // round-off: the energies are O(10), the books sum ~1e5 steps
            assert!((r / diss).abs() < 1e-12, "{bname}: {:e}", r / diss);
            // (the kinetic energy removed at sticks, from locating them on the cubic dense
            // output of a second-order method, is booked, not hidden)
            assert!(ch.ledger.projection < 1e-8 * diss, "{bname}");
            if !beta.is_finite() {
                // the beta-free books: no dry-friction work is booked
                assert_eq!(ch.ledger.dry, 0.0);
            }
        }
    }
}

#[test]
fn midpoint_is_second_order_on_the_single_block() {
    use super::integrator::Method;
    let ts = exact_stick(0.8, 0.0, 0.3, 0.0);
    let mut errs = Vec::new();
    for &step in &[0.2, 0.1, 0.05] {
        let fr = Coulomb::new(0.3, 0.0).unwrap();
        let mut ch = Chain::new(cfg(1.0, 0.0, step), fr, &Free, &[0.8], None).unwrap();
        ch.set_integrator(Method::Midpoint).unwrap();
        ch.add_trigger(Trigger {
            t: 0.0,
            block: 0,
            kind: TriggerKind::Release { dir: 1 },
        })
        .unwrap();
        ch.run(10.0, 1, u64::MAX).unwrap();
        errs.push((ch.catalog.slips[0].t_end - ts).abs());
    }
    for k in 0..2 {
        let order = (errs[k] / errs[k + 1]).log2();
        assert!(order > 1.7 && order < 2.5, "errors {errs:?}");
    }
}

#[test]
fn a_block_over_the_backward_threshold_at_rest_reverses() {
    // one block from u = 1.5 (over the threshold: slips forward at t = 0), gamma = 0.1,
    // beta = 0.02. Forward half-period: u -> -1.5 e^(-gamma pi / omega) = -1.0956 at
    // u_t = v = 0, below -(1 + 2 beta) = -1.04: it reverses and slides backward around
    // u = -2 beta, then sticks at rest with -1.04 < u < 1.
    let (gamma, beta) = (0.1f64, 0.02f64);
    let om = (1.0 - gamma * gamma).sqrt();
    let damp = (-gamma * std::f64::consts::PI / om).exp();
    let u1 = -1.5 * damp;
    let u2 = -2.0 * beta + (u1 + 2.0 * beta).abs() * damp;
    let fr = Coulomb::new(gamma, beta).unwrap();
    let mut ch = Chain::new(cfg(0.002, 0.0, 0.05), fr, &Free, &[1.5], None).unwrap();
    ch.run(20.0, 1, u64::MAX).unwrap();
    let s = &ch.catalog.slips;
    assert_eq!(s.len(), 2, "{s:?}");
    assert_eq!((s[0].dir, s[1].dir), (1, -1));
    let half = std::f64::consts::PI / om;
    assert!((s[0].t_end - half).abs() < 1e-10, "{}", s[0].t_end);
    assert!((s[0].u_end - u1).abs() < 1e-11);
    assert!((s[1].t_end - 2.0 * half).abs() < 1e-10, "{}", s[1].t_end);
    assert!((s[1].u_end - u2).abs() < 1e-11, "{} vs {u2}", s[1].u_end);
    assert!(s[1].slip < 0.0, "backward slip is negative");
    assert_eq!(ch.modes(), vec![0]);
    assert_eq!(ch.catalog.finished(), 1);
}

#[test]
fn without_backward_slip_a_block_at_rest_below_the_threshold_sticks() {
    // as above with beta = inf (the paper's model): at the end of the forward half-period
    // u = -1.0956 at rest; there is no backward threshold, so it sticks there
    let gamma = 0.1f64;
    let om = (1.0 - gamma * gamma).sqrt();
    let u1 = -1.5 * (-gamma * std::f64::consts::PI / om).exp();
    let fr = Coulomb::new(gamma, f64::INFINITY).unwrap();
    let mut ch = Chain::new(cfg(0.002, 0.0, 0.05), fr, &Free, &[1.5], None).unwrap();
    ch.run(20.0, 1, u64::MAX).unwrap();
    let s = &ch.catalog.slips;
    assert_eq!(s.len(), 1, "{s:?}");
    assert_eq!(s[0].dir, 1);
    assert!((s[0].t_end - std::f64::consts::PI / om).abs() < 1e-10);
    assert!((s[0].u_end - u1).abs() < 1e-11);
    assert_eq!(ch.modes(), vec![0]);
    assert!(ch.u().iter().all(|x| x.is_finite()));
}

#[test]
fn without_backward_slip_backward_motion_is_refused() {
    let fr = Coulomb::new(0.3, f64::INFINITY).unwrap();
    let mut ch = Chain::new(cfg(0.1, 0.0, 0.05), fr, &Free, &[0.5; 4], None).unwrap();
    for kind in [
        TriggerKind::Kick { du_t: 0.5 },
        TriggerKind::Release { dir: -1 },
    ] {
        let e = ch.add_trigger(Trigger {
            t: 0.0,
            block: 1,
            kind,
        });
        assert!(
            matches!(
                e,
                Err(Error::InvalidParameter {
                    name: "trigger",
                    ..
                })
            ),
            "{e:?}"
        );
    }
    for kind in [
        TriggerKind::Kick { du_t: -0.5 },
        TriggerKind::Release { dir: 1 },
    ] {
        ch.add_trigger(Trigger {
            t: 0.0,
            block: 1,
            kind,
        })
        .unwrap();
    }
    let e = Chain::new(cfg(0.1, 0.0, 0.05), fr, &Free, &[0.5; 2], Some(&[0.0, 0.1]));
    assert!(
        matches!(e, Err(Error::InvalidParameter { name: "u_t0", .. })),
        "{e:?}"
    );
    assert!(Chain::new(
        cfg(0.1, 0.0, 0.05),
        fr,
        &Free,
        &[0.5; 2],
        Some(&[0.0, -0.1])
    )
    .is_ok());
}

#[test]
fn a_restored_checkpoint_continues_bit_for_bit() {
    use super::integrator::Method;
    for method in [Method::Rk4, Method::Midpoint] {
        let fr = Coulomb::new(0.3, 0.5).unwrap();
        let u0 = smooth_stress(80, 11);
        let make = || {
            let mut ch = Chain::new(cfg(0.2, 1e-2, 0.1), fr, &Periodic, &u0, None).unwrap();
            ch.set_integrator(method).unwrap();
            ch.add_snapshots(&[50.0, 100.0, 150.0], 2).unwrap();
            ch.add_trigger(Trigger {
                t: 5.0,
                block: 3,
                kind: TriggerKind::Kick { du_t: -0.5 },
            })
            .unwrap();
            ch
        };
        let mut whole = make();
        whole.run(150.0, usize::MAX, u64::MAX).unwrap();
        // stop on the step budget in the middle of events, save, restore elsewhere
        let mut first = make();
        assert_eq!(first.run(150.0, usize::MAX, 777).unwrap(), Stop::Steps);
        let bytes = first.checkpoint();
        let mut other = Chain::new(cfg(0.2, 1e-2, 0.1), fr, &Periodic, &[0.0; 80], None).unwrap();
        other.set_integrator(method).unwrap();
        other.restore(&bytes).unwrap();
        assert!(
            other.checkpoint() == bytes,
            "restore then checkpoint differs"
        );
        while other.run(150.0, usize::MAX, 1000).unwrap() == Stop::Steps {}
        assert!(whole.catalog.events.len() >= 3);
        assert!(whole.u() == other.u(), "{method:?}: u differs");
        // (records of open slips hold NaN, so compare printed values: NaN == NaN there)
        let show = |c: &Chain<Coulomb>| format!("{:?}{:?}", c.catalog.slips, c.catalog.events);
        assert!(show(&whole) == show(&other), "{method:?}: catalogs differ");
        assert!(
            whole.snapshots == other.snapshots,
            "{method:?}: snapshots differ"
        );
        assert!(whole.ledger == other.ledger, "{method:?}: books differ");
        assert!(
            whole.checkpoint() == other.checkpoint(),
            "{method:?}: states differ"
        );
        // a different configuration is refused, and leaves the chain as it was
        let fr2 = Coulomb::new(0.31, 0.5).unwrap();
        let mut wrong = Chain::new(cfg(0.2, 1e-2, 0.1), fr2, &Periodic, &u0, None).unwrap();
        wrong.set_integrator(method).unwrap();
        let before = wrong.checkpoint();
        assert!(wrong.restore(&bytes).is_err());
        assert!(wrong.restore(&bytes[..bytes.len() - 3]).is_err());
        assert!(wrong.checkpoint() == before);
        // bytes of another format version are refused, naming the format
        let mut old = bytes.clone();
        old[..8].copy_from_slice(b"BKCHAIN5");
        let e = other.restore(&old).unwrap_err().to_string();
        assert!(
            e.contains("BKCHAIN6") && e.contains("another format"),
            "{e}"
        );
        assert!(other.checkpoint() == whole.checkpoint());
    }
}

#[test]
fn an_event_that_never_ends_stops_on_its_slip_or_duration_limit() {
    // gamma >= 1 at v = 0: a creep front; blocks behind it relax towards u = 0 without
    // their speed ever returning to v, so the event never ends (each block slips about
    // once, then slides on).
    let make = || {
        let fr = Coulomb::new(1.5, 0.0).unwrap();
        let mut ch = Chain::new(cfg(0.1, 0.0, 0.05), fr, &Free, &[0.6; 200], None).unwrap();
        ch.add_trigger(Trigger {
            t: 0.0,
            block: 0,
            kind: TriggerKind::Kick { du_t: -2.0 },
        })
        .unwrap();
        ch
    };
    let mut free_run = make();
    assert_eq!(free_run.run(60.0, 1, u64::MAX).unwrap(), Stop::Time);
    assert!(free_run.catalog.event_open() && free_run.catalog.finished() == 0);
    let (slips_60, _) = free_run.open_event().unwrap();
    assert!((200..400).contains(&slips_60), "{slips_60}");
    // a slip bound
    let mut by_slips = make();
    by_slips.set_run_limits(150, f64::INFINITY, u64::MAX);
    assert_eq!(by_slips.run(1e9, 1, u64::MAX).unwrap(), Stop::LongEvent);
    let (slips, duration) = by_slips.open_event().unwrap();
    assert!(slips > 150 && slips <= 150 + 200, "{slips}");
    assert!(duration < 60.0);
    // with the limit still exceeded, the next call returns at once
    let t = by_slips.time();
    assert_eq!(by_slips.run(1e9, 1, u64::MAX).unwrap(), Stop::LongEvent);
    assert_eq!(by_slips.time(), t);
    // a duration bound: the slips hardly grow, the event goes on
    let mut by_time = make();
    by_time.set_run_limits(10_000, 80.0, u64::MAX);
    assert_eq!(by_time.run(1e9, 1, u64::MAX).unwrap(), Stop::LongEvent);
    let (slips, duration) = by_time.open_event().unwrap();
    assert!(slips < 2 * slips_60, "{slips}");
    assert!(
        duration > 80.0 && duration < 80.0 + 0.05 * 0.1 + 1e-12,
        "{duration}"
    );
}

#[test]
fn a_run_call_is_bounded_in_work_not_only_in_steps() {
    let n = 2000;
    let make = || {
        let fr = Coulomb::new(0.3, 0.0).unwrap();
        Chain::new(
            cfg(0.05, 0.0, 0.05),
            fr,
            &Free,
            &vec![0.5; n],
            Some(&vec![-0.5; n]),
        )
        .unwrap()
    };
    let mut whole = make();
    assert_eq!(whole.run(3.0, usize::MAX, u64::MAX).unwrap(), Stop::Time);
    let mut chunked = make();
    let budget = 50_000u64;
    chunked.set_run_limits(usize::MAX, f64::INFINITY, budget);
    let mut calls = 0;
    loop {
        let before = chunked.counters;
        let stop = chunked.run(3.0, usize::MAX, u64::MAX).unwrap();
        let done = (chunked.counters.steps - before.steps)
            + (chunked.counters.block_steps - before.block_steps);
        // every block slides: a call stops within one step (and its redo) of its budget
        assert!(done < budget + 2 * (1 + n as u64), "{done}");
        calls += 1;
        if stop == Stop::Time {
            break;
        }
        assert_eq!(stop, Stop::Steps);
    }
    assert!(calls > 5, "{calls}");
    // chunking does not change the trajectory
    assert!(whole.u() == chunked.u() && whole.u_t() == chunked.u_t());
}

#[test]
fn a_step_far_below_round_off_of_v_reaches_a_tiny_t_end() {
    // blocks over their threshold at t = 0 slip with u_t = v; to t_end = 1e-30 the whole
    // step changes u_t by ~1e-30, below ulp(v): the rest test must not see a crossing in
    // the rounded cubic (it used to halve the step for ever, t creeping towards t_end).
    for &t_end in &[1e-30, 1e-100, 1e-310] {
        let fr = Coulomb::new(0.3, 5.0).unwrap();
        let u0 = [0.5, 2.0, 0.5, 3.0, 0.2];
        let mut ch = Chain::new(cfg(0.1, 1e-3, 0.05), fr, &Free, &u0, None).unwrap();
        let stop = ch.run(t_end, usize::MAX, 10_000).unwrap();
        assert_eq!(
            stop,
            Stop::Time,
            "t_end {t_end:e}: stopped at t = {:e}",
            ch.t
        );
        assert_eq!(ch.t, t_end);
        assert!(ch.counters.steps < 100, "{} steps", ch.counters.steps);
    }
}
