//! Engine tests against closed forms (the physics validation at scale is in
//! tests/test_free_boundary.py).

use super::*;
use crate::wave::TravelingWave;

fn opts(gamma: f64, v: f64, boundary: Boundary) -> Options {
    Options {
        gamma,
        v,
        boundary,
        ..Default::default()
    }
}

/// Saw-tooth train moving right on a ring of one period L = c A / v (Sec. V).
#[test]
fn periodic_train_keeps_its_period() {
    let (up, gamma, v) = (0.7, 0.3, 1e-2);
    let w = TravelingWave::new(up, gamma).unwrap();
    let (c, a) = (w.c, w.amplitude.unwrap());
    let l = c * a / v;
    let n = 200;
    let h = l / n as f64;
    let xf = 0.37 * h; // front position at t = 0
    let u0: Vec<f64> = (0..n)
        .map(|k| {
            let x = k as f64 * h;
            let z = (x - xf).rem_euclid(l) - l; // in [-L, 0)
            ((z + l) * w.u_minus.unwrap() - z * up) / l
        })
        .collect();
    let mut fb =
        FreeBoundary::new(0.0, h, &u0, opts(gamma, v, Boundary::Periodic), &[(xf, 1)]).unwrap();
    let period = a / v;
    fb.advance(3.5 * period, u64::MAX, usize::MAX).unwrap();
    assert_eq!(fb.shocks().len(), 1);
    // passages of node 50
    let times: Vec<f64> = fb
        .path()
        .iter()
        .filter(|p| p.kind == PathKind::Node && (p.x - 50.0 * h).abs() < 1e-9 * l)
        .map(|p| p.t)
        .collect();
    assert_eq!(times.len(), 4, "{times:?}");
    for w2 in times.windows(2) {
        assert!(((w2[1] - w2[0]) / period - 1.0).abs() < 1e-9, "{w2:?}");
    }
    for p in fb.path().iter().filter(|p| p.kind == PathKind::Node) {
        assert!((p.u_plus - up).abs() < 1e-9, "{p:?}");
    }
    // speed
    let t0 = (50.0 * h - xf) / c;
    assert!((times[0] / t0 - 1.0).abs() < 1e-9, "{} {t0}", times[0]);
}

/// A symmetric source on a free segment: both shocks leave, the event is complete, the
/// slip is symmetric and the field after is symmetric.
#[test]
fn source_is_symmetric_and_shocks_leave_through_free_ends() {
    let (gamma, v, a) = (0.3, 1e-2, 1e-3);
    let n = 201;
    let xh = 10.0;
    let h = 2.0 * xh / (n - 1) as f64;
    let x0 = 0.123 * h; // between nodes
    let u0: Vec<f64> = (0..n)
        .map(|k| {
            let x = -xh + k as f64 * h;
            0.99 - a * (x - x0) * (x - x0)
        })
        .collect();
    let mut fb = FreeBoundary::new(-xh, h, &u0, opts(gamma, v, Boundary::Free), &[]).unwrap();
    fb.advance(1.0e9, u64::MAX, 1).unwrap();
    let ev = fb.events()[0];
    assert!((ev.t_start - 1.0).abs() < 1e-9, "{ev:?}"); // (1 - 0.99)/v
    assert!((ev.x_start - x0).abs() < 1e-9 * xh, "{ev:?}");
    assert!((ev.curvature / a - 1.0).abs() < 1e-9, "{ev:?}");
    assert_eq!(ev.n_exits, 2);
    assert!((ev.x_min + xh).abs() < 1e-12 && (ev.x_max - xh).abs() < 1e-12);
    // both exits at nearly the same time (source off centre by 0.123 h)
    let exits: Vec<&PathPoint> = fb
        .path()
        .iter()
        .filter(|p| p.kind == PathKind::Exit)
        .collect();
    assert_eq!(exits.len(), 2);
}

/// Two bumps: two sources whose inner shocks annihilate between them.
#[test]
fn facing_shocks_annihilate_where_they_meet() {
    let (gamma, v) = (0.2, 1e-2);
    let n = 401;
    let xh = 20.0;
    let h = 2.0 * xh / (n - 1) as f64;
    let bump = |x: f64| 0.9 - 2e-3 * (x.abs() - 10.0).powi(2);
    let u0: Vec<f64> = (0..n).map(|k| bump(-xh + k as f64 * h)).collect();
    let mut fb = FreeBoundary::new(-xh, h, &u0, opts(gamma, v, Boundary::Free), &[]).unwrap();
    fb.advance(1.0e9, u64::MAX, 1).unwrap();
    let ev = fb.events()[0];
    assert_eq!(ev.n_births, 2, "{ev:?}");
    assert_eq!(ev.n_annihilations, 1);
    assert_eq!(ev.n_exits, 2);
    let ann: Vec<&PathPoint> = fb
        .path()
        .iter()
        .filter(|p| p.kind == PathKind::Annihilation)
        .collect();
    assert_eq!(ann.len(), 2);
    assert!(ann[0].x.abs() < 1e-9, "{:?}", ann[0]);
    assert!(ann[0].u_plus < 0.95 && ann[0].u_plus > 0.5);
}

#[test]
fn rejects_bad_input() {
    let u0 = vec![0.5; 10];
    assert!(FreeBoundary::new(0.0, 1.0, &u0, opts(1.0, 1e-3, Boundary::Free), &[]).is_err());
    assert!(FreeBoundary::new(0.0, 0.0, &u0, opts(0.3, 1e-3, Boundary::Free), &[]).is_err());
    assert!(FreeBoundary::new(0.0, 1.0, &u0[..3], opts(0.3, 1e-3, Boundary::Free), &[]).is_err());
    let mut bad = u0.clone();
    bad[3] = 1.0;
    assert!(FreeBoundary::new(0.0, 1.0, &bad, opts(0.3, 1e-3, Boundary::Free), &[]).is_err());
    assert!(
        FreeBoundary::new(0.0, 1.0, &u0, opts(0.3, 1e-3, Boundary::Free), &[(20.0, 1)]).is_err()
    );
    assert!(
        FreeBoundary::new(0.0, 1.0, &u0, opts(0.3, 1e-3, Boundary::Free), &[(2.0, 0)]).is_err()
    );
    assert!(Boundary::parse("fixed").is_err());
    assert!(CreepRule::parse("x").is_err());
}

/// The same slowly varying state (two bumps on a sinusoidal ramp, ring of length 0.3/v,
/// widths ~ 1/v) run by the direct chain and by the free boundary engine: the first event
/// agrees, and the differences shrink in proportion to v (docs/validation.md, "Against
/// the direct chain"; benchmarks/fb_vs_chain measures more cases).
#[test]
fn first_event_agrees_with_the_direct_chain() {
    use crate::boundary;
    use crate::chain::{Chain, ChainConfig};
    use crate::friction::coulomb::Coulomb;
    let gamma = 0.3;
    let dx = 0.1;
    let mut prev: Option<(f64, f64)> = None;
    for &v in &[1e-3, 5e-4] {
        let l = 0.3 / v;
        let w = 40.0 * l / 300.0;
        let pd = |x: f64, c: f64| (x - c + 0.5 * l).rem_euclid(l) - 0.5 * l;
        let u0f = |x: f64| {
            0.9 + 0.015 * (2.0 * std::f64::consts::PI * x / l).sin()
                + 0.03 * (-(pd(x, 0.3 * l) / w).powi(2)).exp()
                + 0.025 * (-(pd(x, 0.7 * l) / w).powi(2)).exp()
        };
        // chain
        let n = (l / dx).round() as usize;
        let u0: Vec<f64> = (0..n).map(|i| u0f(i as f64 * dx)).collect();
        let cfg = ChainConfig {
            dx,
            v,
            ..Default::default()
        };
        let b = boundary::by_name("periodic", (0.0, 0.0)).unwrap();
        let mut ch = Chain::new(
            cfg,
            Coulomb::new(gamma, 0.0).unwrap(),
            b.as_ref(),
            &u0,
            None,
        )
        .unwrap();
        ch.run(1e12, 1, u64::MAX).unwrap();
        let ce = ch.catalog.events[0];
        // free boundary on a grid 0.5 l/300
        let h = 0.5 * l / 300.0;
        let m = (l / h).round() as usize;
        let g0: Vec<f64> = (0..m).map(|k| u0f(k as f64 * h)).collect();
        let mut fb =
            FreeBoundary::new(0.0, h, &g0, opts(gamma, v, Boundary::Periodic), &[]).unwrap();
        fb.advance(1e12, u64::MAX, 1).unwrap();
        let fe = fb.events()[0];
        // nucleation: same place; the chain starts earlier by about 2 a / v (its slip
        // condition is u - u_xx >= 1, the free boundary's u >= 1)
        assert!(
            (ce.nucleation as f64 * dx - fe.x_start).abs() < 2.0 * dx,
            "{ce:?} {fe:?}"
        );
        let off = ce.t_start - fe.t_start;
        assert!(off < 0.0 && off.abs() * v < 1e-4, "{off}");
        // slip fronts (after the offset), u after passage away from the collision zone
        let mut first = vec![f64::NAN; n];
        for s in ch.catalog.slips.iter() {
            if first[s.block].is_nan() {
                first[s.block] = s.t_start;
            }
        }
        let xcol: Vec<f64> = fb
            .path()
            .iter()
            .filter(|p| p.kind == PathKind::Annihilation)
            .map(|p| p.x)
            .collect();
        let uc = ch.u();
        let ufb = fb.u_nodes();
        let (mut dt, mut du) = (0.0f64, 0.0f64);
        for p in fb.path().iter().filter(|p| p.kind == PathKind::Node) {
            let i = (p.x / dx).round() as usize % n;
            dt = dt.max((first[i] - p.t - off).abs());
            let k = (p.x / h).round() as usize % m;
            if xcol.iter().all(|&xc| (p.x - xc).abs() > 5.0) {
                let uf = ufb[k] + v * (ch.time() - fb.time());
                du = du.max((uc[i] - uf).abs());
            }
        }
        let dm = ce.moment * dx / fe.moment - 1.0;
        assert!(dt / (fe.t_end - fe.t_start) < 5e-3, "{dt}");
        assert!(du < 5.0 * v, "{du}");
        assert!(dm.abs() < 2.5 * v, "{dm}");
        if let Some((du0, dm0)) = prev {
            // halving v (and doubling the length scales) halves both differences
            assert!((du / du0 - 0.5).abs() < 0.1, "{du} {du0}");
            assert!((dm / dm0 - 0.5).abs() < 0.1, "{dm} {dm0}");
        }
        prev = Some((du, dm));
    }
}
