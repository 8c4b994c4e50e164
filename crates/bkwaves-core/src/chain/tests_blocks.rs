//! Tests of the friction-law registry and of per-block properties against exact
//! symmetries of the equations (docs/chain.md) and the uniform engine.

use super::dynamic::ChainSpec;
use super::medium::{Ends, PerBlock, Properties};
use super::*;
use crate::boundary::{Fixed, Free, Periodic};
use crate::friction::{Coulomb, Friction, Law};
use crate::params::ParamSpec;

fn cfg(dx: f64, v: f64, step: f64) -> ChainConfig {
    ChainConfig { dx, v, step }
}

fn smooth(n: usize, seed: u64, mean: f64, amp: f64) -> Vec<f64> {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64) / ((1u64 << 53) as f64)
    };
    let ph: Vec<(f64, f64)> = (1..=4).map(|k| (k as f64, next())).collect();
    (0..n)
        .map(|i| {
            let x = i as f64 / n as f64;
            mean + amp
                * ph.iter()
                    .map(|&(k, p)| (2.0 * std::f64::consts::PI * (k * x + p)).sin() / k)
                    .sum::<f64>()
        })
        .collect()
}

fn first_slips<F: Friction, M: medium::Medium>(ch: &Chain<F, M>) -> Vec<f64> {
    let mut first = vec![f64::NAN; ch.n()];
    for r in &ch.catalog.slips {
        if first[r.block].is_nan() {
            first[r.block] = r.t_start;
        }
    }
    first
}

/// A law written only here: Coulomb plus a constant extra drag `drag` while sliding
/// forward, and no backward slip. Registering it is the one line `Law::of::<Drag>()`.
#[derive(Debug, Clone, Copy)]
struct Drag {
    gamma: f64,
    drag: f64,
}

impl Friction for Drag {
    const NAME: &'static str = "constant_drag";
    const DOC: &'static str = "Coulomb plus a constant extra drag";
    const PARAMS: &'static [ParamSpec] = &[
        crate::friction::coulomb::GAMMA,
        ParamSpec {
            name: "drag",
            lo: 0.0,
            lo_closed: true,
            hi: 1.0,
            hi_closed: false,
            default: Some(0.0),
            doc: "extra friction force while sliding, in units of f_r - f_s",
        },
    ];
    fn from_values(v: &[f64]) -> Result<Self> {
        Ok(Drag {
            gamma: v[0],
            drag: v[1],
        })
    }
    fn values(&self) -> Vec<f64> {
        vec![self.gamma, self.drag]
    }
    fn excess(&self, s: f64, _dir: f64, _threshold: f64) -> f64 {
        self.drag + 2.0 * self.gamma * s
    }
    fn lower(&self, _threshold: f64) -> f64 {
        f64::NEG_INFINITY
    }
    fn beta(&self) -> f64 {
        0.0
    }
    fn power(&self, s: f64, _dir: f64, _threshold: f64) -> (f64, f64) {
        (self.drag * s, 2.0 * self.gamma * s * s)
    }
    fn max_slope(&self, _threshold_max: f64) -> f64 {
        2.0 * self.gamma
    }
}

const DRAG: Law = Law::of::<Drag>();

#[test]
fn a_third_law_is_one_impl_and_one_registry_line() {
    // A drag d is a Coulomb chain with thresholds 1 - d seen with u shifted by d:
    // u_tt = -phi + d + 2 gamma s = -(phi - d) + 2 gamma s, slip at phi >= 1 <=> phi - d >= 1 - d.
    let (n, d, gamma, u_plus) = (200, 0.2, 0.5, 0.7);
    let props = Properties::default();
    let u0 = vec![u_plus; n];
    let spec = ChainSpec {
        cfg: cfg(0.1, 0.0, 0.05),
        boundary: &Free,
        u0: &u0,
        u_t0: None,
        properties: &props,
        plane: None,
    };
    let bad = (DRAG.chain)(&[gamma, 1.5], spec).unwrap_err().to_string();
    assert_eq!(bad, "invalid drag = 1.5: allowed 0 <= drag < 1");
    let mut dragged = (DRAG.chain)(&[gamma, d], spec).unwrap();
    let kick = Trigger {
        t: 0.0,
        block: 0,
        kind: TriggerKind::Kick { du_t: -2.0 },
    };
    dragged.add_trigger(kick).unwrap();
    dragged.run(15.0, usize::MAX, u64::MAX).unwrap();
    assert_eq!(dragged.friction().0, "constant_drag");

    let lowered = Properties {
        threshold: Some(vec![1.0 - d; n]),
        ..Default::default()
    };
    let med = PerBlock::new(&lowered, n, Ends::Free).unwrap();
    // (a large beta keeps Coulomb blocks from slipping backward, as the drag law does)
    let fr = Coulomb::new(gamma, 10.0).unwrap();
    let shifted: Vec<f64> = u0.iter().map(|u| u - d).collect();
    let mut plain =
        Chain::with_medium(cfg(0.1, 0.0, 0.05), fr, med, &Free, &shifted, None).unwrap();
    plain.add_trigger(kick).unwrap();
    plain.run(15.0, usize::MAX, u64::MAX).unwrap();
    assert!(plain.catalog.slips.iter().all(|r| r.dir > 0));
    let a = &dragged.catalog().slips;
    let b = &plain.catalog.slips;
    assert!(
        a.len() > n / 2 && a.len() == b.len(),
        "{} {}",
        a.len(),
        b.len()
    );
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.block, y.block);
        assert!((x.t_start - y.t_start).abs() < 1e-11, "{x:?} {y:?}");
        assert!((x.u_start - d - y.u_start).abs() < 1e-11, "{x:?} {y:?}");
    }
    let (ua, ub) = (dragged.u(), plain.u());
    for i in 0..n {
        assert!((ua[i] - d - ub[i]).abs() < 1e-11);
    }
}

#[test]
fn alike_blocks_given_as_arrays_are_the_uniform_engine_bit_for_bit() {
    for (b, ends) in [
        (
            Box::new(Free) as Box<dyn crate::boundary::Boundary>,
            Ends::Free,
        ),
        (Box::new(Fixed::new(0.6, 0.5).unwrap()), Ends::Walls),
        (Box::new(Periodic), Ends::Ring),
    ] {
        let n = 60;
        let bonds = match ends {
            Ends::Free => n - 1,
            Ends::Walls => n + 1,
            Ends::Ring => n,
        };
        let ones = Properties {
            threshold: Some(vec![1.0; n]),
            mass: Some(vec![1.0; n]),
            loader: Some(vec![1.0; n]),
            coupling: Some(vec![1.0; bonds]),
            coupling_y: None,
        };
        let u0 = smooth(n, 3, 0.6, 0.15);
        let fr = Coulomb::new(0.3, 0.5).unwrap();
        let c = cfg(0.2, 1e-2, 0.1);
        let mut uni = Chain::new(c, fr, b.as_ref(), &u0, None).unwrap();
        let med = PerBlock::new(&ones, n, ends).unwrap();
        let mut per = Chain::with_medium(c, fr, med, b.as_ref(), &u0, None).unwrap();
        uni.run(80.0, usize::MAX, u64::MAX).unwrap();
        per.run(80.0, usize::MAX, u64::MAX).unwrap();
        assert!(uni.catalog.events.len() >= 2);
        let show = |c: &Catalog| format!("{:?}{:?}", c.slips, c.events);
        assert!(show(&uni.catalog) == show(&per.catalog), "{ends:?}");
        assert!(uni.u() == per.u() && uni.u_t() == per.u_t(), "{ends:?}");
        assert!(
            uni.ledger == per.ledger && uni.energy() == per.energy(),
            "{ends:?}"
        );
    }
}

#[test]
fn a_uniform_threshold_s_is_the_chain_with_u_scaled_by_s() {
    // every term is linear in (u, v, kicks, beta) and the thresholds scale with them
    let (n, s) = (120, 1.3);
    let u0 = smooth(n, 5, 0.7, 0.2);
    let run = |scale: f64, props: &Properties| {
        let med = PerBlock::new(props, n, Ends::Ring).unwrap();
        let fr = Coulomb::new(0.3, 0.25 * scale).unwrap();
        let us: Vec<f64> = u0.iter().map(|u| u * scale).collect();
        let mut ch =
            Chain::with_medium(cfg(0.2, 1e-3 * scale, 0.05), fr, med, &Periodic, &us, None)
                .unwrap();
        ch.add_trigger(Trigger {
            t: 0.0,
            block: 7,
            kind: TriggerKind::Kick { du_t: -scale },
        })
        .unwrap();
        ch.run(400.0, usize::MAX, u64::MAX).unwrap();
        ch
    };
    let a = run(1.0, &Properties::default());
    let b = run(
        s,
        &Properties {
            threshold: Some(vec![s; n]),
            ..Default::default()
        },
    );
    assert!(a.catalog.events.len() >= 3);
    assert_eq!(a.catalog.slips.len(), b.catalog.slips.len());
    for (x, y) in a.catalog.slips.iter().zip(&b.catalog.slips) {
        assert_eq!((x.block, x.dir), (y.block, y.dir));
        assert!(
            (x.t_start - y.t_start).abs() < 1e-9 * (1.0 + x.t_start),
            "{x:?} {y:?}"
        );
        assert!((s * x.slip - y.slip).abs() < 1e-9, "{x:?} {y:?}");
    }
}

#[test]
fn a_uniform_mass_m_rescales_time_by_sqrt_m() {
    // m u_tt = -phi - 2 gamma u_t (v = 0); with tau = t / sqrt(m) this is the unit-mass
    // chain with damping gamma / sqrt(m) and velocities sqrt(m) times larger. m = 4 and a
    // step twice as large is the same discretisation in tau (times scale by exactly 2).
    let n = 150;
    let run = |m: f64, gamma: f64, kick: f64, step: f64| {
        let props = Properties {
            mass: Some(vec![m; n]),
            ..Default::default()
        };
        let med = PerBlock::new(&props, n, Ends::Free).unwrap();
        let fr = Coulomb::new(gamma, 0.0).unwrap();
        let mut ch =
            Chain::with_medium(cfg(0.1, 0.0, step), fr, med, &Free, &vec![0.6; n], None).unwrap();
        ch.add_trigger(Trigger {
            t: 0.0,
            block: 0,
            kind: TriggerKind::Kick { du_t: kick },
        })
        .unwrap();
        ch.run(1e3, 1, u64::MAX).unwrap();
        ch
    };
    let a = run(1.0, 0.2, -2.0, 0.05);
    let b = run(4.0, 0.4, -1.0, 0.1);
    let (ta, tb) = (first_slips(&a), first_slips(&b));
    assert!(ta.iter().all(|t| t.is_finite()));
    for i in 0..n {
        assert!(
            (2.0 * ta[i] - tb[i]).abs() < 1e-10 * (1.0 + tb[i]),
            "{i}: {} {}",
            ta[i],
            tb[i]
        );
    }
    let (ua, ub) = (a.u(), b.u());
    for i in 0..n {
        assert!((ua[i] - ub[i]).abs() < 1e-10, "{i}");
    }
}

#[test]
fn phi_is_the_per_bond_stencil_for_every_boundary() {
    let n = 7;
    let dx: f64 = 0.3;
    let u0 = smooth(n, 9, 0.2, 0.3);
    let kp = smooth(n, 10, 1.0, 0.3);
    for (b, ends, bonds) in [
        (
            Box::new(Free) as Box<dyn crate::boundary::Boundary>,
            Ends::Free,
            n - 1,
        ),
        (Box::new(Fixed::new(0.1, -0.2).unwrap()), Ends::Walls, n + 1),
        (Box::new(Periodic), Ends::Ring, n),
    ] {
        let kc = smooth(bonds, 11, 1.0, 0.4);
        let props = Properties {
            loader: Some(kp.clone()),
            coupling: Some(kc.clone()),
            threshold: Some(vec![50.0; n]),
            ..Default::default()
        };
        let med = PerBlock::new(&props, n, ends).unwrap();
        let fr = Coulomb::new(0.3, 0.0).unwrap();
        let ch = Chain::with_medium(cfg(dx, 0.0, 0.05), fr, med, b.as_ref(), &u0, None).unwrap();
        let phi = ch.phi();
        for i in 0..n {
            // force of each spring on block i, as the user numbered the bonds
            let (left, right) = match ends {
                Ends::Free => (
                    (i > 0).then(|| (kc[i - 1], u0[i - 1])),
                    (i + 1 < n).then(|| (kc[i], u0[i + 1])),
                ),
                Ends::Walls => (
                    Some((kc[i], if i == 0 { 0.1 } else { u0[i - 1] })),
                    Some((kc[i + 1], if i + 1 == n { -0.2 } else { u0[i + 1] })),
                ),
                Ends::Ring => (
                    Some((kc[(i + n - 1) % n], u0[(i + n - 1) % n])),
                    Some((kc[i], u0[(i + 1) % n])),
                ),
            };
            let pull: f64 = [left, right]
                .iter()
                .flatten()
                .map(|&(k, uj)| k * (uj - u0[i]))
                .sum();
            let want = kp[i] * u0[i] - pull / (dx * dx);
            assert!(
                (phi[i] - want).abs() < 1e-12,
                "{ends:?} {i}: {} {want}",
                phi[i]
            );
        }
    }
}

#[test]
fn energy_books_of_a_disordered_chain_close_to_round_off_with_midpoint() {
    // every property differs from block to block: the books close only if the
    // accelerations, the energy and the loader work use the same per-block values
    let n = 60;
    for (b, ends, bonds) in [
        (
            Box::new(Free) as Box<dyn crate::boundary::Boundary>,
            Ends::Free,
            n - 1,
        ),
        (Box::new(Fixed::new(0.5, 0.4).unwrap()), Ends::Walls, n + 1),
        (Box::new(Periodic), Ends::Ring, n),
    ] {
        let props = Properties {
            threshold: Some(smooth(n, 1, 1.0, 0.15)),
            mass: Some(smooth(n, 2, 1.0, 0.3)),
            loader: Some(smooth(n, 3, 1.0, 0.3)),
            coupling: Some(smooth(bonds, 4, 1.0, 0.3)),
            coupling_y: None,
        };
        let mut res = Vec::new();
        for method in [integrator::Method::Midpoint, integrator::Method::Rk4] {
            let med = PerBlock::new(&props, n, ends).unwrap();
            let fr = Coulomb::new(0.3, 0.5).unwrap();
            let u0 = smooth(n, 7, 0.6, 0.15);
            let mut ch =
                Chain::with_medium(cfg(0.2, 1e-2, 0.1), fr, med, b.as_ref(), &u0, None).unwrap();
            ch.set_integrator(method).unwrap();
            ch.add_trigger(Trigger {
                t: 3.0,
                block: 5,
                kind: TriggerKind::Kick { du_t: -0.7 },
            })
            .unwrap();
            let (k, c, l) = ch.energy();
            let e0 = k + c + l;
            ch.run(120.0, usize::MAX, u64::MAX).unwrap();
            assert!(ch.catalog.events.len() >= 3, "{ends:?}");
            let (k, c, l) = ch.energy();
            let lg = ch.ledger;
            let flows = lg.load - lg.dry - lg.viscous - lg.projection + lg.injected;
            res.push((((k + c + l) - e0 - flows) / (lg.dry + lg.viscous)).abs());
        }
        assert!(res[0] < 1e-12, "{ends:?} midpoint {res:?}");
        assert!(res[1] < 1e-6, "{ends:?} rk4 {res:?}");
    }
}

#[test]
fn checkpoints_carry_the_law_table_and_the_medium() {
    let n = 30;
    let u0 = smooth(n, 2, 0.6, 0.2);
    let th = smooth(n, 5, 1.0, 0.1);
    let make = |t: &[f64]| {
        let props = Properties {
            threshold: Some(t.to_vec()),
            ..Default::default()
        };
        let med = PerBlock::new(&props, n, Ends::Free).unwrap();
        let fr = Coulomb::new(0.3, 0.5).unwrap();
        Chain::with_medium(cfg(0.2, 1e-2, 0.1), fr, med, &Free, &u0, None).unwrap()
    };
    let mut a = make(&th);
    a.run(30.0, usize::MAX, 300).unwrap();
    let bytes = a.checkpoint();
    let mut same = make(&th);
    same.restore(&bytes).unwrap();
    assert!(same.checkpoint() == bytes);
    let mut other_th = th.clone();
    other_th[17] += 1e-9;
    let mut different = make(&other_th);
    assert!(different.restore(&bytes).is_err());
}
