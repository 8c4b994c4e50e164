//! The lattice against the chain it reduces to, and its own books and symmetries.

use super::*;
use crate::boundary::{Fixed, Free, Periodic};
use crate::chain::{Chain, Trigger, TriggerKind};
use crate::friction::Coulomb;

fn cfg(dx: f64, v: f64, step: f64) -> ChainConfig {
    ChainConfig { dx, v, step }
}

/// First slip time of every block (NaN: never slipped).
fn first_slips(slips: &[crate::chain::catalog::SlipRecord], n: usize) -> Vec<f64> {
    let mut t = vec![f64::NAN; n];
    for s in slips {
        if t[s.block].is_nan() {
            t[s.block] = s.t_start;
        }
    }
    t
}

fn kick(block: usize) -> Trigger {
    Trigger {
        t: 0.0,
        block,
        kind: TriggerKind::Kick { du_t: -2.0 },
    }
}

fn fr() -> Coulomb {
    Coulomb::new(0.45, f64::INFINITY).unwrap()
}

/// A lattice at uniform stress u_plus, kicked at the blocks `kicked`, run to t_end: the
/// first slip times.
#[allow(clippy::too_many_arguments)]
fn lattice_front(
    (nx, ny): (usize, usize),
    (dx, dy): (f64, f64),
    step: f64,
    (bx, by): (&dyn Boundary, &dyn Boundary),
    kicked: impl Fn(usize, usize) -> bool,
    u_plus: f64,
    t_end: f64,
) -> Vec<f64> {
    let spec = LatticeSpec {
        nx,
        ny,
        dy,
        x: bx,
        y: by,
    };
    let u0 = vec![u_plus; nx * ny];
    let mut la = Lattice::lattice(cfg(dx, 0.0, step), spec, fr(), Uniform, &u0, None).unwrap();
    for j in 0..ny {
        for i in 0..nx {
            if kicked(i, j) {
                la.add_trigger(kick(i + nx * j)).unwrap();
            }
        }
    }
    la.run(t_end, usize::MAX, u64::MAX).unwrap();
    first_slips(&la.catalog.slips, nx * ny)
}

fn chain_front(
    n: usize,
    dx: f64,
    step: f64,
    b: &dyn Boundary,
    u_plus: f64,
    t_end: f64,
) -> Vec<f64> {
    let u0 = vec![u_plus; n];
    let mut ch = Chain::new(cfg(dx, 0.0, step), fr(), b, &u0, None).unwrap();
    ch.add_trigger(kick(0)).unwrap();
    ch.run(t_end, usize::MAX, u64::MAX).unwrap();
    first_slips(&ch.catalog.slips, n)
}

/// Largest |a - b| over blocks where both slipped; both must have slipped at the same
/// blocks, and at least `min` of them.
fn max_diff(a: &[f64], b: &[f64], min: usize) -> f64 {
    let mut d: f64 = 0.0;
    let mut both = 0;
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.is_nan(), y.is_nan(), "slipped at different blocks");
        if x.is_finite() {
            both += 1;
            d = d.max((x - y).abs());
        }
    }
    assert!(both >= min, "only {both} blocks slipped");
    d
}

/// The fields of a slip record as bits (NaN while sliding compares equal to itself).
fn record_bits(s: &crate::chain::catalog::SlipRecord) -> [u64; 5] {
    [s.t_start, s.t_end, s.u_start, s.u_end, s.slip].map(f64::to_bits)
}

#[test]
fn a_front_along_x_on_a_lattice_periodic_in_y_is_the_chain_at_dx() {
    // u depends on i only: the y coupling is +0 in the stages and in the Hermite data of
    // phi, the x coupling the chain's floats (docs/lattice.md, "Ties"), so every row is
    // the chain with the same event mode to the bit, whatever the x boundary: every slip
    // record, u and u_t at the end, the number of steps (was 6.0e-14 in slip times while
    // the event location summed phi as (k_p + 2 k_x + 2 k_y) u_p - ..., counting the y
    // springs that carry no force)
    let (n, ny, dx, step, t_end) = (120, 3, 0.1, 0.05, 8.0);
    let fixed = Fixed::new(0.6, 0.6).unwrap();
    let sides: [&dyn Boundary; 3] = [&Free, &Periodic, &fixed];
    for local in [false, true] {
        for bx in sides {
            let mut ch = Chain::new(cfg(dx, 0.0, step), fr(), bx, &[0.6; 120], None).unwrap();
            ch.set_local_events(local);
            ch.add_trigger(kick(0)).unwrap();
            ch.run(t_end, usize::MAX, u64::MAX).unwrap();
            let spec = LatticeSpec {
                nx: n,
                ny,
                dy: dx,
                x: bx,
                y: &Periodic,
            };
            let u0 = vec![0.6; n * ny];
            let mut la =
                Lattice::lattice(cfg(dx, 0.0, step), spec, fr(), Uniform, &u0, None).unwrap();
            la.set_local_events(local);
            for j in 0..ny {
                la.add_trigger(kick(n * j)).unwrap();
            }
            la.run(t_end, usize::MAX, u64::MAX).unwrap();
            let what = format!("local events {local}, x boundary {}", bx.name());
            let chain: Vec<_> = ch
                .catalog
                .slips
                .iter()
                .map(|s| (s.block, record_bits(s)))
                .collect();
            assert!(chain.len() > 100, "{what}: only {} slips", chain.len());
            let (u, u_t, uc, uc_t) = (la.u(), la.u_t(), ch.u(), ch.u_t());
            for j in 0..ny {
                let row: Vec<_> = la
                    .catalog
                    .slips
                    .iter()
                    .filter(|s| s.block / n == j)
                    .map(|s| (s.block % n, record_bits(s)))
                    .collect();
                assert!(row == chain, "{what}, row {j}: the slip records differ");
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&u[j * n..(j + 1) * n]),
                    bits(&uc),
                    "{what}, row {j}: u"
                );
                assert_eq!(
                    bits(&u_t[j * n..(j + 1) * n]),
                    bits(&uc_t),
                    "{what}, row {j}: u_t"
                );
            }
            assert_eq!(la.counters.steps, ch.counters.steps, "{what}: steps");
            eprintln!(
                "x front, {what}: {} slips a row and {} steps, the chain's bits",
                chain.len(),
                ch.counters.steps
            );
        }
    }
}

#[test]
fn with_dx_not_dy_fronts_along_each_axis_are_the_chains_at_dx_and_at_dy() {
    let (dx, dy, step) = (0.1, 0.15, 0.05);
    // along y on a lattice periodic in x: the chain at dy with the same time step
    let (nx, ny) = (2, 80);
    let chain = chain_front(ny, dy, step * dx / dy, &Free, 0.6, 8.0);
    let la = lattice_front(
        (nx, ny),
        (dx, dy),
        step,
        (&Periodic, &Free),
        |_, j| j == 0,
        0.6,
        8.0,
    );
    for i in 0..nx {
        let col: Vec<f64> = (0..ny).map(|j| la[i + nx * j]).collect();
        let d = max_diff(&col, &chain, 40);
        eprintln!("y front at dy, column {i}: largest difference {d:e}");
        assert_eq!(d, 0.0, "column {i}");
    }
    // along x on a lattice periodic in y: the chain at dx
    let (nx, ny) = (80, 2);
    let chain = chain_front(nx, dx, step, &Free, 0.6, 6.0);
    let la = lattice_front(
        (nx, ny),
        (dx, dy),
        step,
        (&Free, &Periodic),
        |i, _| i == 0,
        0.6,
        6.0,
    );
    for j in 0..ny {
        let d = max_diff(&la[j * nx..(j + 1) * nx], &chain, 40);
        eprintln!("x front at dx != dy, row {j}: largest difference {d:e}");
        assert_eq!(d, 0.0, "row {j}");
    }
}

#[test]
fn a_front_along_the_diagonal_is_the_chain_at_dx_over_sqrt2() {
    // on an N x N lattice periodic in x and y, u = f((i + j) mod N) stays a function of
    // i + j, and the five-point Laplacian of it is 2 (f_{n+1} + f_{n-1} - 2 f_n)/dx^2:
    // a ring of N blocks at spacing dx/sqrt(2), stepped with the same time step
    let (nn, dx, step) = (48, 0.2, 0.05);
    let dc = dx / 2f64.sqrt();
    let chain = chain_front(nn, dc, step * dx / dc, &Periodic, 0.6, 2.5);
    let la = lattice_front(
        (nn, nn),
        (dx, dx),
        step,
        (&Periodic, &Periodic),
        |i, j| (i + j) % nn == 0,
        0.6,
        2.5,
    );
    let mut d: f64 = 0.0;
    let mut slipped = 0;
    for j in 0..nn {
        for i in 0..nn {
            let (a, b) = (la[i + nn * j], chain[(i + j) % nn]);
            assert_eq!(a.is_nan(), b.is_nan(), "({i}, {j})");
            if a.is_finite() {
                slipped += 1;
                d = d.max((a - b).abs());
            }
        }
    }
    assert!(slipped > nn * 10, "{slipped}");
    eprintln!("diagonal front: {slipped} blocks, largest difference {d:e}");
    assert!(d < 1e-12, "{d}");
}

/// A smooth random-ish stress field on the lattice (a few Fourier modes).
fn smooth_stress(nx: usize, ny: usize) -> Vec<f64> {
    let mut u = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (i as f64 / nx as f64, j as f64 / ny as f64);
            let tau = 2.0 * std::f64::consts::PI;
            u.push(
                0.6 + 0.15 * (tau * x + 0.3).sin() * (tau * y + 1.1).cos()
                    + 0.08 * (2.0 * tau * x + 3.0 * tau * y + 0.7).sin(),
            );
        }
    }
    u
}

fn balance<G: crate::chain::geometry::Geometry>(ch: &Engine<G, Coulomb>, e0: f64) -> (f64, f64) {
    let (k, c, l) = ch.energy();
    let lg = ch.ledger;
    let resid = (k + c + l - e0) - (lg.load - lg.dry - lg.viscous - lg.projection + lg.injected);
    (resid, lg.dry + lg.viscous)
}

#[test]
fn energy_books_close_to_the_integration_order() {
    let fixed = Fixed::new(0.5, 0.4).unwrap();
    for (name, bx, by) in [
        (
            "free x free",
            &Free as &dyn Boundary,
            &Free as &dyn Boundary,
        ),
        ("fixed x periodic", &fixed, &Periodic),
        ("periodic x fixed", &Periodic, &fixed),
    ] {
        let mut res = Vec::new();
        for &step in &[0.2, 0.1, 0.05, 0.025, 0.0125] {
            let (nx, ny) = (24, 20);
            let spec = LatticeSpec {
                nx,
                ny,
                dy: 0.3,
                x: bx,
                y: by,
            };
            let u0 = smooth_stress(nx, ny);
            let mut la =
                Lattice::lattice(cfg(0.25, 1e-2, step), spec, fr(), Uniform, &u0, None).unwrap();
            let (k, c, l) = la.energy();
            la.run(60.0, usize::MAX, u64::MAX).unwrap();
            assert!(la.catalog.events.len() >= 2, "{name}");
            let (r, diss) = balance(&la, k + c + l);
            assert!(diss > 0.1, "{name}: dissipation {diss}");
            res.push((r / diss).abs());
        }
        // the residual is the integration error of the books: from step 0.05 on it falls
        // by 6-12 per halving (measured: 3e-6, 4e-7, 4e-8 of the work dissipated), order
        // 4 approached from below; between 0.1 and 0.05 by only 1.3-3 (a change of sign
        // of the residual there, in all three closures)
        assert!(res[1] < res[0] / 5.0, "{name}: {res:?}");
        for k in 2..4 {
            assert!(res[k + 1] < res[k] / 5.0, "{name}: {res:?}");
        }
        assert!(res[4] < 1e-9, "{name}: {res:?}");
    }
}

#[test]
fn the_energy_of_a_lattice_uniform_in_y_is_ny_times_the_chains() {
    // the coupling energy counts each bond once, walls included
    let fixed = Fixed::new(0.5, 0.4).unwrap();
    let u: Vec<f64> = (0..30).map(|i| 0.3 + 0.01 * (i * i % 7) as f64).collect();
    let ch = Chain::new(cfg(0.2, 0.1, 0.05), fr(), &fixed, &u, None).unwrap();
    let spec = LatticeSpec {
        nx: 30,
        ny: 4,
        dy: 0.3,
        x: &fixed,
        y: &Periodic,
    };
    let u2: Vec<f64> = (0..4).flat_map(|_| u.iter().copied()).collect();
    let la = Lattice::lattice(cfg(0.2, 0.1, 0.05), spec, fr(), Uniform, &u2, None).unwrap();
    let (a, b) = (ch.energy(), la.energy());
    for (x, y) in [(a.0, b.0), (a.1, b.1), (a.2, b.2)] {
        assert!(
            (4.0 * x - y).abs() < 1e-12 * y.abs().max(1.0),
            "{a:?} {b:?}"
        );
    }
    // and the y springs count: a field varying along y, fixed in y, free in x
    let spec = LatticeSpec {
        nx: 1,
        ny: 30,
        dy: 0.2,
        x: &Free,
        y: &fixed,
    };
    let la = Lattice::lattice(cfg(0.7, 0.1, 0.05), spec, fr(), Uniform, &u, None).unwrap();
    let b = la.energy();
    assert!((a.1 - b.1).abs() < 1e-12 * a.1, "{a:?} {b:?}");
}

#[test]
fn a_point_rupture_is_symmetric_under_the_lattice_symmetries() {
    // free edges, dx = dy, kicked at the centre of an odd lattice: the arrival times are
    // symmetric under x -> -x, y -> -y and x <-> y, to the bit: a mirrored block's sums
    // are l + r = r + l, a transposed block's the x and y couplings as two addends
    // swapped (docs/lattice.md, "Ties"; 1e-11 while the event location summed them in
    // another order)
    let nn = 31;
    let c = nn / 2;
    let t = lattice_front(
        (nn, nn),
        (0.2, 0.2),
        0.05,
        (&Free, &Free),
        |i, j| i == c && j == c,
        0.7,
        3.0,
    );
    let at = |i: usize, j: usize| t[i + nn * j];
    let mut slipped = 0;
    for j in 0..nn {
        for i in 0..nn {
            let a = at(i, j);
            for b in [at(nn - 1 - i, j), at(i, nn - 1 - j), at(j, i)] {
                assert_eq!(a.is_nan(), b.is_nan(), "({i}, {j})");
                if a.is_finite() {
                    assert_eq!(a.to_bits(), b.to_bits(), "({i}, {j}): {a} {b}");
                }
            }
            slipped += usize::from(a.is_finite());
        }
    }
    assert!(slipped > 200, "{slipped}");
}

#[test]
fn slip_times_converge_at_order_four_in_the_step() {
    // an expanding rupture: the first slip time of blocks far from the kick, at steps
    // h, h/2, h/4, h/8: successive differences fall by about 2^4
    let nn = 21;
    let times: Vec<Vec<f64>> = [0.2, 0.1, 0.05, 0.025]
        .iter()
        .map(|&step| {
            lattice_front(
                (nn, nn),
                (0.25, 0.25),
                step,
                (&Free, &Free),
                |i, j| i == 0 && j == 0,
                0.7,
                4.0,
            )
        })
        .collect();
    let far = [nn - 1, (nn - 1) * nn, nn * nn - 1, nn / 2 + nn * (nn / 2)];
    let diff =
        |a: &Vec<f64>, b: &Vec<f64>| far.iter().map(|&k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
    let d: Vec<f64> = (0..3).map(|k| diff(&times[k], &times[k + 1])).collect();
    assert!(d.iter().all(|x| x.is_finite()), "{d:?}");
    // measured: 6.3e-5, 2.3e-6, 7.7e-8 (ratios 28 and 30: order 4.8-4.9, at least the
    // order 4 of RK4; an order-2 or order-3 slip would give 4 or 8)
    for k in 0..2 {
        let ratio = d[k] / d[k + 1];
        assert!(ratio > 12.0, "{d:?}");
    }
}

#[test]
fn a_restored_checkpoint_continues_bit_for_bit() {
    let (nx, ny) = (20, 16);
    let spec = LatticeSpec {
        nx,
        ny,
        dy: 0.3,
        x: &Periodic,
        y: &Free,
    };
    let u0 = smooth_stress(nx, ny);
    let build = || Lattice::lattice(cfg(0.25, 1e-2, 0.05), spec, fr(), Uniform, &u0, None).unwrap();
    let mut whole = build();
    whole.run(40.0, usize::MAX, u64::MAX).unwrap();
    let mut part = build();
    // stop on a step budget inside an event, checkpoint, restore into a fresh lattice
    let mut stops = 0;
    while part.time() < 40.0 {
        if part.run(40.0, usize::MAX, 97).unwrap() == crate::chain::Stop::Steps {
            stops += 1;
            let bytes = part.checkpoint();
            let mut fresh = build();
            fresh.restore(&bytes).unwrap();
            part = fresh;
        }
    }
    assert!(stops > 3, "{stops}");
    assert_eq!(whole.u(), part.u());
    assert_eq!(whole.u_t(), part.u_t());
    assert!(whole.ledger == part.ledger);
    // (records of running slips hold NaN: compared by their printed bits)
    let show = |c: &crate::chain::catalog::Catalog| format!("{:?} {:?}", c.slips, c.events);
    assert!(
        show(&whole.catalog) == show(&part.catalog),
        "catalogs differ"
    );
    // a chain's checkpoint is refused by a lattice
    let ch = Chain::new(cfg(0.25, 1e-2, 0.05), fr(), &Free, &u0, None).unwrap();
    assert!(build().restore(&ch.checkpoint()).is_err());
}

#[test]
fn bad_shapes_and_spacings_are_errors_naming_the_parameter() {
    let spec = |nx, ny, dy| LatticeSpec {
        nx,
        ny,
        dy,
        x: &Free,
        y: &Free,
    };
    let e = Lattice::lattice(
        cfg(0.1, 0.0, 0.05),
        spec(0, 3, 0.1),
        fr(),
        Uniform,
        &[],
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("nx"), "{e}");
    let e = Lattice::lattice(
        cfg(0.1, 0.0, 0.05),
        spec(2, 2, -1.0),
        fr(),
        Uniform,
        &[0.0; 4],
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("dy"), "{e}");
    let e = Lattice::lattice(
        cfg(0.1, 0.0, 0.05),
        spec(2, 2, 0.1),
        fr(),
        Uniform,
        &[0.0; 3],
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("u0"), "{e}");
}
