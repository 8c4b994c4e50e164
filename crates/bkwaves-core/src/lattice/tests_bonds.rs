//! Per-bond coupling springs in the lattice (`Properties::coupling`, `coupling_y`):
//! the exact reductions (docs/lattice.md).

use super::*;
use crate::boundary::{Fixed, Free, Periodic};
use crate::chain::medium::{Ends, PerBlock, Properties};
use crate::chain::Chain;
use crate::friction::Coulomb;

fn fr() -> Coulomb {
    Coulomb::new(0.45, 0.6).unwrap()
}

/// A loaded lattice (v = 0.01) from a stress varying along both axes, run to t_end.
fn lattice<M: Medium>(
    (nx, ny): (usize, usize),
    (bx, by): (&dyn Boundary, &dyn Boundary),
    med: M,
    u0: &[f64],
    t_end: f64,
) -> Lattice<Coulomb, M> {
    lattice_at(0.05, (nx, ny), (bx, by), med, u0, t_end)
}

fn lattice_at<M: Medium>(
    step: f64,
    (nx, ny): (usize, usize),
    (bx, by): (&dyn Boundary, &dyn Boundary),
    med: M,
    u0: &[f64],
    t_end: f64,
) -> Lattice<Coulomb, M> {
    let spec = LatticeSpec {
        nx,
        ny,
        dy: 0.15,
        x: bx,
        y: by,
    };
    let cfg = ChainConfig {
        dx: 0.1,
        v: 0.01,
        step,
    };
    let mut la = Lattice::lattice(cfg, spec, fr(), med, u0, None).unwrap();
    la.run(t_end, usize::MAX, u64::MAX).unwrap();
    la
}

fn stress(nx: usize, ny: usize) -> Vec<f64> {
    (0..nx * ny)
        .map(|k| {
            let (i, j) = ((k % nx) as f64, (k / nx) as f64);
            0.62 + 0.25 * (0.45 * i + 1.3 * j).sin() + 0.1 * (0.9 * j).cos()
        })
        .collect()
}

fn bonds(n: usize, phase: f64) -> Vec<f64> {
    (0..n)
        .map(|b| 1.0 + 0.4 * (0.7 * b as f64 + phase).sin())
        .collect()
}

fn bond_count(n: usize, b: &dyn Boundary) -> usize {
    match b.name() {
        "free" => n - 1,
        "fixed" => n + 1,
        _ => n,
    }
}

fn grid_of(nx: usize, ny: usize, bx: &dyn Boundary, by: &dyn Boundary) -> Grid {
    Grid::new(
        nx,
        ny,
        0.1,
        0.15,
        (bx.left(), bx.right()),
        (by.left(), by.right()),
    )
}

#[test]
fn uniform_per_bond_springs_are_the_uniform_lattice_bit_for_bit() {
    let (nx, ny) = (14, 11);
    let u0 = stress(nx, ny);
    let fixed = Fixed::new(0.6, 0.7).unwrap();
    let sides: [(&dyn Boundary, &dyn Boundary); 3] =
        [(&Free, &Free), (&fixed, &Periodic), (&Periodic, &fixed)];
    for (bx, by) in sides {
        let props = Properties {
            coupling: Some(vec![1.0; ny * bond_count(nx, bx)]),
            coupling_y: Some(vec![1.0; nx * bond_count(ny, by)]),
            ..Default::default()
        };
        let med = PerBlock::for_lattice(&props, &grid_of(nx, ny, bx, by)).unwrap();
        let a = lattice((nx, ny), (bx, by), Uniform, &u0, 40.0);
        let b = lattice((nx, ny), (bx, by), med, &u0, 40.0);
        assert!(a.catalog.slips.len() > 50, "{}", a.catalog.slips.len());
        assert_eq!(a.u(), b.u(), "{} x {}", bx.name(), by.name());
        assert_eq!(a.u_t(), b.u_t());
        let t = |la: &[crate::chain::catalog::SlipRecord]| {
            la.iter().map(|s| (s.block, s.t_start)).collect::<Vec<_>>()
        };
        assert_eq!(t(&a.catalog.slips), t(&b.catalog.slips));
    }
}

/// Largest |a - b| relative to the spread of a.
fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let spread = a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / spread
}

/// The largest difference (relative) between the lines of a lattice cut into
/// independent lines by zero bonds (along x: rows, `across` false; along y: columns) and
/// the chains with those lines' springs and stresses, at time step `step` (of the
/// smaller spacing), and the same against the chains with another line's springs.
fn lines_against_chains(across: bool, b: &dyn Boundary, step: f64) -> (f64, f64) {
    let (nx, ny) = if across { (4, 36) } else { (40, 5) };
    let (n, lines) = if across { (ny, nx) } else { (nx, ny) };
    let u0 = stress(nx, ny);
    let nb = bond_count(n, b);
    let springs: Vec<Vec<f64>> = (0..lines).map(|l| bonds(nb, 2.0 * l as f64)).collect();
    let (bx, by): (&dyn Boundary, &dyn Boundary) = if across { (&Free, b) } else { (b, &Free) };
    let props = if across {
        Properties {
            coupling: Some(vec![0.0; ny * (nx - 1)]),
            // bond row k holds the k-th bond of every column
            coupling_y: Some(
                (0..nb)
                    .flat_map(|k| springs.iter().map(move |c| c[k]))
                    .collect(),
            ),
            ..Default::default()
        }
    } else {
        Properties {
            coupling: Some(springs.concat()),
            coupling_y: Some(vec![0.0; nx * (ny - 1)]),
            ..Default::default()
        }
    };
    let med = PerBlock::for_lattice(&props, &grid_of(nx, ny, bx, by)).unwrap();
    let la = lattice_at(step, (nx, ny), (bx, by), med, &u0, 40.0);
    let u = la.u();
    let at = |l: usize, k: usize| if across { l + nx * k } else { k + nx * l };
    let ends = match b.name() {
        "free" => Ends::Free,
        "fixed" => Ends::Walls,
        _ => Ends::Ring,
    };
    let chain = |l: usize, with: usize| {
        let props = Properties {
            coupling: Some(springs[with].clone()),
            ..Default::default()
        };
        let med = PerBlock::new(&props, n, ends).unwrap();
        // the chain along y has spacing dy; its step (step dy) is the lattice's
        let (dx, st) = if across {
            (0.15, step * 0.1 / 0.15)
        } else {
            (0.1, step)
        };
        let cfg = ChainConfig {
            dx,
            v: 0.01,
            step: st,
        };
        let c0: Vec<f64> = (0..n).map(|k| u0[at(l, k)]).collect();
        let mut ch = Chain::with_medium(cfg, fr(), med, b, &c0, None).unwrap();
        ch.run(40.0, usize::MAX, u64::MAX).unwrap();
        assert!(
            ch.catalog.slips.len() > 5,
            "line {l}: {}",
            ch.catalog.slips.len()
        );
        ch.u()
    };
    let (mut same, mut other) = (0.0_f64, f64::INFINITY);
    for l in 0..lines {
        let lu: Vec<f64> = (0..n).map(|k| u[at(l, k)]).collect();
        same = same.max(rel_diff(&chain(l, l), &lu));
        other = other.min(rel_diff(&chain(l, (l + 1) % lines), &lu));
    }
    (same, other)
}

#[test]
fn a_lattice_whose_y_bonds_are_zero_is_ny_independent_chains() {
    // every row its own stress and x springs, no bond across: each row is the chain with
    // those springs (free, fixed and periodic ends). The lattice cuts its steps at every
    // row's events, a chain at its own, so they agree to the integrator's accuracy, not
    // to the bit: the difference falls as the step is halved (order 4: by 16; measured
    // free ends: 3.4e-5 -> 1.1e-6, by 31), while the chain with another row's springs
    // stays 1e-3 and more away
    let fixed = Fixed::new(0.6, 0.7).unwrap();
    for b in [&Free as &dyn Boundary, &fixed, &Periodic] {
        let (d1, other) = lines_against_chains(false, b, 0.05);
        let (d2, _) = lines_against_chains(false, b, 0.025);
        assert!(d1 < 1e-4 && d2 < d1 / 8.0, "{}: {d1:e} -> {d2:e}", b.name());
        assert!(other > 1e-3, "{}: {other:e}", b.name());
        eprintln!("{}: {d1:e} -> {d2:e}, other {other:e}", b.name());
    }
}

#[test]
fn a_lattice_whose_x_bonds_are_zero_is_nx_independent_chains_along_y() {
    // the y layout: column i's bonds are the i-th values of the bond rows
    let fixed = Fixed::new(0.65, 0.55).unwrap();
    for b in [&Free as &dyn Boundary, &fixed, &Periodic] {
        let (d1, other) = lines_against_chains(true, b, 0.05);
        let (d2, _) = lines_against_chains(true, b, 0.025);
        assert!(d1 < 1e-4 && d2 < d1 / 8.0, "{}: {d1:e} -> {d2:e}", b.name());
        eprintln!("{}: {d1:e} -> {d2:e}, other {other:e}", b.name());
        assert!(other > 1e-3, "{}: {other:e}", b.name());
    }
}

#[test]
fn bad_bonds_name_the_property_and_the_bond() {
    let grid = grid_of(5, 4, &Free, &Periodic);
    let e = |props: Properties| {
        PerBlock::for_lattice(&props, &grid)
            .unwrap_err()
            .to_string()
    };
    let msg = e(Properties {
        coupling: Some(vec![1.0; 15]),
        ..Default::default()
    });
    assert!(
        msg.contains("coupling") && msg.contains("4 lines of 4 bonds"),
        "{msg}"
    );
    let mut ky = vec![1.0; 20];
    ky[7] = -0.5;
    let msg = e(Properties {
        coupling_y: Some(ky),
        ..Default::default()
    });
    assert_eq!(
        msg,
        "invalid coupling_y[7] = -0.5: allowed finite coupling_y >= 0"
    );
    let chain = PerBlock::new(
        &Properties {
            coupling_y: Some(vec![1.0]),
            ..Default::default()
        },
        3,
        Ends::Free,
    );
    assert!(chain.unwrap_err().to_string().contains("coupling_y"));
}
