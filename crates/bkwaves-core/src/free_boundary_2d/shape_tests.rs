//! Tests of the shape options (curvature correction, diagonal planar speed) against
//! exact solutions.

use super::*;
use crate::free_boundary::speed_law::SpeedTable;
use crate::free_boundary::Boundary;

fn square(half: f64, h: f64) -> Grid {
    let n = (2.0 * half / h).round() as usize + 1;
    Grid::new(n, n, h, (-half, -half), (Boundary::Free, Boundary::Free)).unwrap()
}

/// The exact arrival time at radius r of a circle expanding at dR/dT = c - D/R from
/// radius 1 at T = 1/(c - D) (linear inside r = 1, where the seeds are):
/// T = T0 + (r - 1)/c + (D/c^2) ln((c r - D)/(c - D)).
fn t_curved(r: f64, c: f64, d: f64) -> f64 {
    let t0 = 1.0 / (c - d);
    if r <= 1.0 {
        t0 + (r - 1.0) / (c - d)
    } else {
        t0 + (r - 1.0) / c + d / (c * c) * ((c * r - d) / (c - d)).ln()
    }
}

/// Arrival times of a point source in uniform u0 (v = 0), seeded within r = 1 with
/// `seed(r)`, with the given options; returns the engine.
fn point_source(
    h: f64,
    u0: f64,
    curvature: Option<(f64, f64)>,
    diag: Option<SpeedLaw>,
    seed: impl Fn(f64) -> f64,
) -> (Grid, FreeBoundary2D) {
    let g = square(6.0, h);
    let opts = Options2D {
        v: 0.0,
        curvature,
        ..Default::default()
    };
    let mut fb = FreeBoundary2D::new(g, &vec![u0; g.n()], opts, SpeedLaw::Exact, None).unwrap();
    if let Some(l) = diag {
        fb.set_diagonal_law(l).unwrap();
    }
    let seeds: Vec<(usize, f64)> = (0..g.n())
        .filter_map(|k| {
            let (x, y) = g.xy(k);
            let r = x.hypot(y);
            (r <= 1.0).then(|| (k, seed(r)))
        })
        .collect();
    fb.trigger(&seeds).unwrap();
    fb.advance(f64::INFINITY, u64::MAX, 1).unwrap();
    (g, fb)
}

/// Max and mean error over 1 < r <= 5 of the curved circle (isotropic D).
fn curved_error(h: f64, d: f64) -> (f64, f64) {
    let u0: f64 = 0.6;
    let c = 1.0 / (1.0 - u0 * u0).sqrt();
    let (g, fb) = point_source(h, u0, Some((d, d)), None, |r| t_curved(r, c, d));
    let (mut worst, mut sum, mut n) = (0.0f64, 0.0, 0);
    for k in 0..g.n() {
        let (x, y) = g.xy(k);
        let r = x.hypot(y);
        if r > 1.0 && r <= 5.0 {
            let e = (fb.last_arrival()[k] - t_curved(r, c, d)).abs();
            worst = worst.max(e);
            sum += e;
            n += 1;
        }
    }
    (worst, sum / n as f64)
}

#[test]
fn a_curved_circle_follows_dr_dt_c_minus_d_over_r() {
    let (d, c) = (0.1, 1.25);
    // the correction itself at r = 5
    let effect = t_curved(5.0, c, d) - (t_curved(1.0, c, d) + 4.0 / c);
    let e: Vec<(f64, f64)> = [0.2, 0.1, 0.05]
        .iter()
        .map(|&h| curved_error(h, d))
        .collect();
    eprintln!("curved circle D = {d}: effect {effect:.3e}, errors (max, mean) {e:?}");
    assert!(effect > 0.1, "{effect}");
    // second order in the mean (ratio > 3.5 per halving), and the largest error at h =
    // 0.05 is 2 % of the correction (without the option it would be all of it)
    assert!(e[0].1 / e[1].1 > 3.5 && e[1].1 / e[2].1 > 3.5, "{e:?}");
    assert!(e[2].0 < 0.02 * effect, "{e:?}");
    // without the option the same seeds are off by the correction
    let u0: f64 = 0.6;
    let (g, fb) = point_source(0.05, u0, None, None, |r| t_curved(r, c, d));
    let k = g.nearest(5.0, 0.0);
    let miss = t_curved(5.0, c, d) - fb.last_arrival()[k];
    assert!((miss / effect - 1.0).abs() < 0.05, "{miss} {effect}");
}

/// A diagonal law 3 % faster than the exact one (a table through its nodes).
fn faster_diagonal() -> SpeedLaw {
    let u: Vec<f64> = (1..20).map(|i| 0.05 * i as f64).collect();
    let c: Vec<f64> = u.iter().map(|q| 1.03 / (1.0 - q * q).sqrt()).collect();
    SpeedLaw::Table(SpeedTable::new(&u, &c).unwrap())
}

#[test]
fn the_diagonal_law_sets_the_speed_along_the_diagonals() {
    // a point source in uniform u0: its front (the Wulff shape of c(theta)) moves at
    // c_axis along the axes and c_diag along the diagonals, exactly; seeded within r = 1
    // with r/c(phi) (exact along both, O(eps^2) between)
    let u0: f64 = 0.6;
    let law = faster_diagonal();
    let c_ax = 1.0 / (1.0 - u0 * u0).sqrt();
    let c_dg = law.speed(u0).unwrap();
    assert!((c_dg / c_ax - 1.03).abs() < 1e-3, "{c_dg}");
    let c_at = |x: f64, y: f64| {
        let r2 = x * x + y * y;
        let s2 = if r2 > 0.0 {
            4.0 * x * x * y * y / (r2 * r2)
        } else {
            0.0
        };
        c_ax + (c_dg - c_ax) * s2
    };
    let mut errs = Vec::new();
    for h in [0.1, 0.05] {
        let g = square(6.0, h);
        let opts = Options2D {
            v: 0.0,
            ..Default::default()
        };
        let mut fb = FreeBoundary2D::new(g, &vec![u0; g.n()], opts, SpeedLaw::Exact, None).unwrap();
        fb.set_diagonal_law(faster_diagonal()).unwrap();
        let seeds: Vec<(usize, f64)> = (0..g.n())
            .filter_map(|k| {
                let (x, y) = g.xy(k);
                let r = x.hypot(y);
                (r <= 1.0).then(|| (k, r / c_at(x, y)))
            })
            .collect();
        fb.trigger(&seeds).unwrap();
        fb.advance(f64::INFINITY, u64::MAX, 1).unwrap();
        let (mut e_ax, mut e_dg) = (0.0f64, 0.0f64);
        let n = (5.0 / h).round() as i64;
        for s in 1..=n {
            let x = s as f64 * h;
            let k = g.nearest(x, 0.0);
            e_ax = e_ax.max((fb.last_arrival()[k] - x / c_ax).abs());
            let k = g.nearest(x / 2f64.sqrt(), x / 2f64.sqrt());
            let (kx, ky) = g.xy(k);
            let r = kx.hypot(ky);
            if (ky - kx).abs() < 1e-9 && r > 1.0 && r <= 5.0 {
                e_dg = e_dg.max((fb.last_arrival()[k] - r / c_dg).abs());
            }
        }
        errs.push((e_ax, e_dg));
    }
    eprintln!("diagonal law: max errors (axis, diagonal) at h = 0.1, 0.05: {errs:?}");
    // the two speeds differ by 3 %: 0.11 in arrival time at r = 5
    let gap = 5.0 / c_ax - 5.0 / c_dg;
    assert!(gap > 0.1);
    for (a, d) in &errs {
        assert!(*a < 0.02 * gap && *d < 0.05 * gap, "{errs:?}");
    }
    assert!(errs[1].1 < errs[0].1, "{errs:?}");
}

#[test]
fn a_planar_front_is_not_curved() {
    // a front along x in a field that varies along x only (uniform in y, loaded): kappa =
    // 0 exactly and theta = 0, so the options change nothing (to rounding)
    let g = Grid::new(80, 6, 0.1, (0.0, 0.0), (Boundary::Free, Boundary::Periodic)).unwrap();
    let u0: Vec<f64> = (0..g.n())
        .map(|k| 0.55 + 0.3 * (0.4 * g.xy(k).0).sin())
        .collect();
    let run = |shape: bool| {
        let opts = Options2D {
            v: 0.01,
            curvature: shape.then_some((0.05, 0.1)),
            ..Default::default()
        };
        let mut fb = FreeBoundary2D::new(g, &u0, opts, SpeedLaw::Exact, None).unwrap();
        if shape {
            fb.set_diagonal_law(faster_diagonal()).unwrap();
        }
        let seeds: Vec<(usize, f64)> = (0..g.ny).map(|j| (j * g.nx, 0.0)).collect();
        fb.trigger(&seeds).unwrap();
        fb.advance(f64::INFINITY, u64::MAX, 1).unwrap();
        fb.last_arrival().to_vec()
    };
    let (a, b) = (run(false), run(true));
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-12, "{worst}");
    assert!(a.iter().all(|t| t.is_finite()));
}

#[test]
fn the_shape_options_checkpoint_bit_for_bit() {
    let g = Grid::new(
        48,
        40,
        0.25,
        (0.0, 0.0),
        (Boundary::Periodic, Boundary::Periodic),
    )
    .unwrap();
    let mut s = 5u64;
    let u0: Vec<f64> = (0..g.n())
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            0.4 + 0.5 * ((s >> 11) as f64 / (1u64 << 53) as f64)
        })
        .collect();
    let make = |curv: Option<(f64, f64)>, diag: bool| {
        let o = Options2D {
            v: 0.01,
            curvature: curv,
            ..Default::default()
        };
        let mut fb = FreeBoundary2D::new(g, &u0, o, SpeedLaw::Exact, None).unwrap();
        if diag {
            fb.set_diagonal_law(faster_diagonal()).unwrap();
        }
        fb
    };
    let curv = Some((0.06, 0.11));
    let mut a = make(curv, true);
    while a.live() == 0 {
        a.advance(f64::INFINITY, 1, usize::MAX).unwrap();
    }
    a.advance(f64::INFINITY, 300, usize::MAX).unwrap();
    assert!(a.live() > 0);
    let bytes = a.checkpoint();
    // another configuration is refused: no options, other D, no diagonal law
    assert!(make(None, false).restore(&bytes).is_err());
    assert!(make(Some((0.06, 0.12)), true).restore(&bytes).is_err());
    assert!(make(curv, false).restore(&bytes).is_err());
    let mut b = make(curv, true);
    b.restore(&bytes).unwrap();
    a.advance(300.0, u64::MAX, usize::MAX).unwrap();
    b.advance(300.0, u64::MAX, usize::MAX).unwrap();
    assert_eq!(a.checkpoint(), b.checkpoint());
    assert!(a.ruptures().len() > 3);
    // the option changes the run (it can fail)
    let mut c = make(None, false);
    c.advance(300.0, u64::MAX, usize::MAX).unwrap();
    assert_ne!(c.last_arrival(), a.last_arrival());
    // a negative D is refused, naming it
    let o = Options2D {
        curvature: Some((-0.1, 0.1)),
        ..Default::default()
    };
    let e = FreeBoundary2D::new(g, &u0, o, SpeedLaw::Exact, None).unwrap_err();
    assert!(e.to_string().contains("curvature D_axis"), "{e}");
}

/// Max and mean error over 1 < r <= 5 of the curved circle (isotropic D, u_+ = 0.6, v =
/// 0) on the square [-1.5, 5.5]^2 (the quadrant the errors are read in, plus the seeds),
/// at the stride p (None: the rule).
fn curved_error_quadrant(h: f64, d: f64, p: Option<i64>) -> (f64, f64) {
    let u0: f64 = 0.6;
    let c = 1.0 / (1.0 - u0 * u0).sqrt();
    let n = (7.0 / h).round() as usize + 1;
    let g = Grid::new(n, n, h, (-1.5, -1.5), (Boundary::Free, Boundary::Free)).unwrap();
    let opts = Options2D {
        v: 0.0,
        curvature: Some((d, d)),
        ..Default::default()
    };
    let mut fb = FreeBoundary2D::new(g, &vec![u0; g.n()], opts, SpeedLaw::Exact, None).unwrap();
    let seeds: Vec<(usize, f64)> = (0..g.n())
        .filter_map(|k| {
            let (x, y) = g.xy(k);
            let r = x.hypot(y);
            (r <= 1.0).then(|| (k, t_curved(r, c, d)))
        })
        .collect();
    fb.trigger(&seeds).unwrap();
    super::shape::STRIDE_OVERRIDE.with(|s| s.set(p));
    fb.advance(f64::INFINITY, u64::MAX, 1).unwrap();
    super::shape::STRIDE_OVERRIDE.with(|s| s.set(None));
    let (mut worst, mut sum, mut m) = (0.0f64, 0.0, 0);
    for k in 0..g.n() {
        let (x, y) = g.xy(k);
        let r = x.hypot(y);
        if r > 1.0 && r <= 5.0 && x >= 0.0 && y >= 0.0 {
            let e = (fb.last_arrival()[k] - t_curved(r, c, d)).abs();
            worst = worst.max(e);
            sum += e;
            m += 1;
        }
    }
    (worst, sum / m as f64)
}

/// The measurement behind the stride rule (docs/free_boundary_2d.md): errors of the
/// curved circle for strides p at h = 0.05, 0.025, 0.0125. `cargo test --release -p
/// bkwaves-core stride_table -- --ignored --nocapture` (STRIDES="2 4 6 8" to choose).
#[test]
#[ignore]
fn stride_table() {
    let hs: Vec<f64> = std::env::var("HS")
        .map(|s| s.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .unwrap_or_else(|_| vec![0.05, 0.025, 0.0125]);
    let ps: Vec<i64> = std::env::var("STRIDES")
        .map(|s| s.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .unwrap_or_else(|_| vec![2, 3, 4, 6, 8, 12, 16]);
    for &h in &hs {
        let (w, m) = curved_error_quadrant(h, 0.1, None);
        eprintln!(
            "h {h} rule p {}: max {w:.3e} mean {m:.3e}",
            super::shape::curvature_stride(h)
        );
        for &p in &ps {
            let (w, m) = curved_error_quadrant(h, 0.1, Some(p));
            eprintln!(
                "h {h} p {p} (p h {:.3}): max {w:.3e} mean {m:.3e}",
                p as f64 * h
            );
        }
    }
}

#[test]
fn a_curvature_table_interpolates_in_cos_4_theta() {
    use super::shape::Directions;
    let q = std::f64::consts::FRAC_PI_4;
    // two directions: D_axis cos^2(2 theta) + D_diag sin^2(2 theta), to rounding
    let two = Directions::new(&[0.0, q], &[0.02, 0.045]).unwrap();
    // five directions through a trigonometric polynomial of degree 4 in cos(4 theta):
    // reproduced exactly between the nodes
    let f = |t: f64| {
        0.034 - 0.0116 * (4.0 * t).cos() - 0.001 * (8.0 * t).cos() + 4e-4 * (16.0 * t).cos()
    };
    // the directions (1, 0), (3, 1), (2, 1), (3, 2), (1, 1)
    let th = vec![0.0, 1f64.atan2(3.0), 1f64.atan2(2.0), 2f64.atan2(3.0), q];
    let d: Vec<f64> = th.iter().map(|&t| f(t)).collect();
    let five = Directions::new(&th, &d).unwrap();
    for i in 0..=90 {
        let t = i as f64 * q / 90.0;
        let c2 = (2.0 * t).cos().powi(2);
        let s2 = 1.0 - c2;
        assert!((two.at(c2) - (0.02 * c2 + 0.045 * s2)).abs() < 1e-15);
        assert!(
            (five.at(c2) - f(t)).abs() < 1e-14,
            "{t} {} {}",
            five.at(c2),
            f(t)
        );
    }
    // bad tables are refused naming the parameter
    for (t, d) in [
        (vec![0.0, 0.5], vec![0.1, 0.1]),
        (vec![0.1, q], vec![0.1, 0.1]),
        (vec![0.0, 0.3, 0.2, q], vec![0.1; 4]),
        (vec![0.0, q], vec![0.1, -0.1]),
        (vec![0.0, q], vec![0.1]),
    ] {
        let e = Directions::new(&t, &d).unwrap_err().to_string();
        assert!(e.contains("curvature"), "{e}");
    }
}

#[test]
fn a_curvature_table_runs_as_the_pair_it_reduces_to() {
    // a table of two directions is the (D_axis, D_diag) option; a table of five equal
    // values is the isotropic D: the same arrival times to rounding
    let q = std::f64::consts::FRAC_PI_4;
    let (h, u0, d) = (0.2, 0.6f64, 0.1);
    let c = 1.0 / (1.0 - u0 * u0).sqrt();
    let run = |pair: (f64, f64), table: Option<(Vec<f64>, Vec<f64>)>| {
        let g = square(6.0, h);
        let opts = Options2D {
            v: 0.0,
            curvature: Some(pair),
            ..Default::default()
        };
        let mut fb = FreeBoundary2D::new(g, &vec![u0; g.n()], opts, SpeedLaw::Exact, None).unwrap();
        if let Some((t, dv)) = table {
            fb.set_curvature_directions(&t, &dv).unwrap();
        }
        let seeds: Vec<(usize, f64)> = (0..g.n())
            .filter_map(|k| {
                let (x, y) = g.xy(k);
                let r = x.hypot(y);
                (r <= 1.0).then(|| (k, t_curved(r, c, d)))
            })
            .collect();
        fb.trigger(&seeds).unwrap();
        fb.advance(f64::INFINITY, u64::MAX, 1).unwrap();
        fb.last_arrival().to_vec()
    };
    let diff = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f64, f64::max)
    };
    let pair = run((0.05, 0.12), None);
    let two = run((0.0, 0.0), Some((vec![0.0, q], vec![0.05, 0.12])));
    assert!(diff(&pair, &two) < 1e-12, "{}", diff(&pair, &two));
    let iso = run((d, d), None);
    let th = vec![0.0, 0.3, 0.45, 0.6, q];
    let five = run((0.0, 0.0), Some((th.clone(), vec![d; 5])));
    assert!(diff(&iso, &five) < 1e-12, "{}", diff(&iso, &five));
    // and a table that differs between the nodes moves the front (the test can fail)
    let bumped = run((0.0, 0.0), Some((th, vec![d, 0.3, 0.3, 0.3, d])));
    assert!(diff(&iso, &bumped) > 1e-3, "{}", diff(&iso, &bumped));
}
