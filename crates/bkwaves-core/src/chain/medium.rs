//! The blocks' own properties: static threshold, mass, loader-spring and coupling-spring
//! stiffness, uniform ([`Uniform`]) or one value per block and per bond ([`PerBlock`]).
//!
//! In units of reference values (m, k_p, k_c, f_r - f_s; docs/chain.md) block i has mass
//! m_i, loader spring k_p,i, static threshold theta_i, and the bond between blocks i and
//! i+1 the coupling k_c,i+1/2. With u the displacement in units of (f_r - f_s)/k_p measured
//! from the point where block i's loader spring pulls with f_s,
//!
//! ```text
//!   phi_i = k_p,i u_i - [k_c,i+1/2 (u_{i+1} - u_i) - k_c,i-1/2 (u_i - u_{i-1})] / dx^2
//!   sliding:  m_i u_tt = -phi_i + R(s_i; theta_i);   stuck: u_t = v
//!   a stuck block slips forward at phi_i >= theta_i, backward at phi_i <= -(theta_i + 2 beta)
//! ```
//!
//! Every formula of the engine is written once, for per-block values, in an order of
//! operations that makes the [`Uniform`] medium (all values exactly 1, constants the
//! compiler folds away) reproduce the uniform engine bit for bit and at its speed.

use super::geometry::{Geometry, Grid};
use super::state::State;
use crate::boundary::Ghost;
use crate::error::{Error, Result};
use crate::friction::Friction;

/// The blocks' physics: a friction law and the medium's per-block properties.
#[derive(Debug, Clone)]
pub struct Blocks<F: Friction, M: Medium> {
    /// The friction law.
    pub fr: F,
    /// The per-block properties.
    pub med: M,
}

impl<F: Friction, M: Medium> Blocks<F, M> {
    /// A stuck block p slips forward when phi >= upper.
    #[inline(always)]
    pub fn upper(&self, p: usize) -> f64 {
        self.fr.upper(self.med.threshold(p))
    }
    /// A stuck block p slips backward when phi <= lower.
    #[inline(always)]
    pub fn lower(&self, p: usize) -> f64 {
        self.fr.lower(self.med.threshold(p))
    }
    /// phi of block p from its displacement and the coupling force f on it
    /// ([`Geometry::force`], [`super::geometry::Stencil::force`]).
    #[inline(always)]
    pub fn phi_of(&self, p: usize, up: f64, f: f64) -> f64 {
        self.med.loader(p) * up - f
    }
    /// phi = k_p u - (coupling forces) of real block p at time t (state current at t).
    #[inline(always)]
    pub fn phi<G: Geometry>(&self, st: &State<G>, p: usize, t: f64) -> f64 {
        let up = st.value(p, t);
        let f = st.geo.force(
            &self.med,
            p,
            up,
            #[inline(always)]
            |q| st.neighbour(q, p, t),
        );
        self.phi_of(p, up, f)
    }
    /// Acceleration of sliding block p (direction `dir`, speed s over the ground, threshold
    /// `th` in R: `State::onset`) from its displacement and the coupling force f on it.
    #[inline(always)]
    pub fn accel(&self, p: usize, up: f64, f: f64, s: f64, dir: f64, th: f64) -> f64 {
        (f - self.med.loader(p) * up + self.fr.excess(s, dir, th)) * self.med.inv_mass(p)
    }
}

/// Per-block properties seen by the engine (padded indices: block i at p = i + 1).
pub trait Medium: Clone + Send + Sync + std::fmt::Debug + 'static {
    /// Static threshold theta of block p.
    fn threshold(&self, p: usize) -> f64;
    /// Loader-spring stiffness of block p.
    fn loader(&self, p: usize) -> f64;
    /// Mass of block p.
    fn mass(&self, p: usize) -> f64;
    /// 1 / mass of block p.
    fn inv_mass(&self, p: usize) -> f64;
    /// Coupling stiffness of the bond between padded p - 1 and p (p = 1..=n + 1; the
    /// bonds 1 and n + 1 join the ends to their ghosts).
    fn bond(&self, p: usize) -> f64;
    /// Coupling stiffness across (k_y) of the bond between padded p - S and p in a
    /// lattice of row stride S (the chain never asks).
    fn bond_y(&self, p: usize) -> f64;
    /// Largest threshold.
    fn max_threshold(&self) -> f64;
    /// Everything that defines the medium, for checkpoint fingerprints.
    fn fingerprint(&self) -> Vec<f64>;
}

/// All blocks alike: every property 1 (the paper's chain).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Uniform;

impl Medium for Uniform {
    #[inline(always)]
    fn threshold(&self, _p: usize) -> f64 {
        1.0
    }
    #[inline(always)]
    fn loader(&self, _p: usize) -> f64 {
        1.0
    }
    #[inline(always)]
    fn mass(&self, _p: usize) -> f64 {
        1.0
    }
    #[inline(always)]
    fn inv_mass(&self, _p: usize) -> f64 {
        1.0
    }
    #[inline(always)]
    fn bond(&self, _p: usize) -> f64 {
        1.0
    }
    #[inline(always)]
    fn bond_y(&self, _p: usize) -> f64 {
        1.0
    }
    fn max_threshold(&self) -> f64 {
        1.0
    }
    fn fingerprint(&self) -> Vec<f64> {
        Vec::new()
    }
}

/// The per-block properties a user gives (0-based; None: uniform 1). `coupling` has one
/// value per bond: n - 1 for free ends (bond i joins blocks i and i + 1), n + 1 for fixed
/// ends (bond 0 joins the left wall and block 0, bond i blocks i - 1 and i, bond n block
/// n - 1 and the right wall), n for a ring (bond i joins blocks i and (i + 1) mod n).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Properties {
    /// Static thresholds theta_i > 0.
    pub threshold: Option<Vec<f64>>,
    /// Masses m_i > 0.
    pub mass: Option<Vec<f64>>,
    /// Loader springs k_p,i > 0.
    pub loader: Option<Vec<f64>>,
    /// Coupling springs k_c > 0, per bond (a lattice: its x bonds, k_x >= 0, row after
    /// row, each row's bonds laid out as a chain's along x).
    pub coupling: Option<Vec<f64>>,
    /// A lattice's y bonds k_y >= 0, a row of bonds after another, each column's bonds
    /// laid out as a chain's along y (the chain: None).
    pub coupling_y: Option<Vec<f64>>,
}

impl Properties {
    /// No property given: the uniform chain.
    pub fn is_uniform(&self) -> bool {
        self.threshold.is_none()
            && self.mass.is_none()
            && self.loader.is_none()
            && self.coupling.is_none()
            && self.coupling_y.is_none()
    }
}

/// Per-block values (padded arrays of n + 2).
#[derive(Debug, Clone, PartialEq)]
pub struct PerBlock {
    threshold: Vec<f64>,
    loader: Vec<f64>,
    mass: Vec<f64>,
    inv_mass: Vec<f64>,
    bond: Vec<f64>,
    /// The lattice's bonds across (None: the chain, or all 1).
    bond_y: Option<Vec<f64>>,
    max_threshold: f64,
}

/// How the ends of the chain close, as the per-bond layout needs it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ends {
    /// No spring beyond the ends (n - 1 bonds).
    Free,
    /// Walls at both ends (n + 1 bonds).
    Walls,
    /// A ring (n bonds).
    Ring,
}

fn per_block(name: &str, given: &Option<Vec<f64>>, n: usize, lo_closed: bool) -> Result<Vec<f64>> {
    let mut out = vec![1.0; n + 2];
    if let Some(a) = given {
        if a.len() != n {
            return Err(Error::Invalid {
                name: name.to_string(),
                value: format!("{} values", a.len()),
                allowed: format!("one value per block ({n})"),
            });
        }
        for (i, &x) in a.iter().enumerate() {
            if !(x.is_finite() && (x > 0.0 || (lo_closed && x == 0.0))) {
                return Err(Error::Invalid {
                    name: format!("{name}[{i}]"),
                    value: format!("{x}"),
                    allowed: format!("finite {name} {} 0", if lo_closed { ">=" } else { ">" }),
                });
            }
            out[i + 1] = x;
        }
    }
    Ok(out)
}

impl PerBlock {
    /// Validated per-block values for n blocks with the given ends: an array of the wrong
    /// length or a bad value names the property and the block (or bond).
    pub fn new(props: &Properties, n: usize, ends: Ends) -> Result<PerBlock> {
        if props.coupling_y.is_some() {
            return Err(Error::Invalid {
                name: "coupling_y".to_string(),
                value: "given".to_string(),
                allowed: "bonds across only in a lattice".to_string(),
            });
        }
        let threshold = per_block("threshold", &props.threshold, n, false)?;
        let loader = per_block("loader", &props.loader, n, false)?;
        let mass = per_block("mass", &props.mass, n, false)?;
        let mut bond = vec![1.0; n + 2];
        if let Some(c) = &props.coupling {
            let (want, first) = match ends {
                Ends::Free => (n.saturating_sub(1), 2),
                Ends::Walls => (n + 1, 1),
                Ends::Ring => (n, 2),
            };
            let c = Some(c.clone());
            let vals = per_block("coupling", &c, want, false).map_err(|e| match e {
                Error::Invalid { name, value, .. } if !name.contains('[') => Error::Invalid {
                    name,
                    value,
                    allowed: format!(
                        "one value per bond ({want} for {n} blocks with {} ends)",
                        match ends {
                            Ends::Free => "free",
                            Ends::Walls => "fixed",
                            Ends::Ring => "periodic",
                        }
                    ),
                },
                e => e,
            })?;
            bond[first..first + want].copy_from_slice(&vals[1..=want]);
            if ends == Ends::Ring {
                // the closing bond (blocks n - 1 and 0) seen from both ends
                bond[1] = bond[n + 1];
            }
        }
        let inv_mass = mass.iter().map(|m| 1.0 / m).collect();
        let max_threshold = threshold[1..=n].iter().copied().fold(0.0, f64::max);
        Ok(PerBlock {
            threshold,
            loader,
            mass,
            inv_mass,
            bond,
            bond_y: None,
            max_threshold,
        })
    }

    /// Validated per-block values of a lattice (threshold, mass, loader: one value per
    /// block in block order, row after row; `coupling`: the x bonds, `coupling_y`: the
    /// y bonds, [`lattice_bonds`]): a bad value names the property and the block or bond.
    pub fn for_lattice(props: &Properties, grid: &Grid) -> Result<PerBlock> {
        let n = grid.n();
        let spread = |a: Vec<f64>| {
            let mut out = vec![1.0; grid.cells()];
            for k in 0..n {
                out[grid.padded(k)] = a[k + 1];
            }
            out
        };
        let threshold = spread(per_block("threshold", &props.threshold, n, false)?);
        let loader = spread(per_block("loader", &props.loader, n, false)?);
        let mass = spread(per_block("mass", &props.mass, n, false)?);
        let inv_mass = mass.iter().map(|m| 1.0 / m).collect();
        let max_threshold = grid.blocks().map(|p| threshold[p]).fold(0.0, f64::max);
        let (bond, bond_y) = lattice_bonds(props, grid)?;
        Ok(PerBlock {
            threshold,
            loader,
            mass,
            inv_mass,
            bond,
            bond_y: Some(bond_y),
            max_threshold,
        })
    }
}

/// How the ghosts of one side close the bonds of a line of blocks.
fn ends_of(g: Ghost) -> Ends {
    match g {
        Ghost::Mirror => Ends::Free,
        Ghost::Held(_) => Ends::Walls,
        Ghost::Wrap => Ends::Ring,
    }
}

/// The number of bonds of a line of n blocks and the padded index of the first one.
fn bond_layout(n: usize, ends: Ends) -> (usize, usize) {
    match ends {
        Ends::Free => (n.saturating_sub(1), 2),
        Ends::Walls => (n + 1, 1),
        Ends::Ring => (n, 2),
    }
}

/// The padded bond arrays (x: `Medium::bond`, y: `Medium::bond_y`) of a lattice from
/// its per-bond springs: along x each row is a chain of nx blocks (nx - 1 bonds between
/// free sides, nx + 1 with walls, nx periodic: bond i of a row joins blocks i and i + 1,
/// or the wall and block 0 first with walls), given row after row (ny rows of them);
/// along y each column is a chain of ny blocks laid out the same way, given as rows of
/// bonds (bond row b holds the b-th bond of every column, nx values). Springs are
/// finite and >= 0 (a zero bond cuts the lattice there); none given: all 1.
pub fn lattice_bonds(props: &Properties, grid: &Grid) -> Result<(Vec<f64>, Vec<f64>)> {
    let (nx, ny) = (grid.nx, grid.ny);
    let mut bx = vec![1.0; grid.cells()];
    let mut by = vec![1.0; grid.cells()];
    // (name, springs, blocks per line, lines, ends) of the x and the y bonds
    let axes = [
        (
            "coupling",
            props.coupling.as_deref(),
            nx,
            ny,
            ends_of(grid.x.0),
        ),
        (
            "coupling_y",
            props.coupling_y.as_deref(),
            ny,
            nx,
            ends_of(grid.y.0),
        ),
    ];
    for (axis, (name, given, n, lines, ends)) in axes.into_iter().enumerate() {
        let Some(vals) = given else { continue };
        let (want, first) = bond_layout(n, ends);
        if vals.len() != want * lines {
            return Err(Error::Invalid {
                name: name.to_string(),
                value: format!("{} values", vals.len()),
                allowed: format!(
                    "one value per bond ({lines} lines of {want} bonds for {n} blocks with {} \
                     sides: {})",
                    match ends {
                        Ends::Free => "free",
                        Ends::Walls => "fixed",
                        Ends::Ring => "periodic",
                    },
                    want * lines
                ),
            });
        }
        if let Some(k) = vals.iter().position(|&x| !(x.is_finite() && x >= 0.0)) {
            return Err(Error::Invalid {
                name: format!("{name}[{k}]"),
                value: format!("{}", vals[k]),
                allowed: format!("finite {name} >= 0"),
            });
        }
        for line in 0..lines {
            // padded position pp along the line (0..=n + 1) -> cell of the grid
            let cell = |pp: usize| {
                if axis == 0 {
                    grid.at_padded(pp, line + 1)
                } else {
                    grid.at_padded(line + 1, pp)
                }
            };
            let out = if axis == 0 { &mut bx } else { &mut by };
            for b in 0..want {
                // x: bond b of row `line` is vals[line * want + b]; y: bond b of column
                // `line` is in bond row b, vals[b * nx + line]
                let v = if axis == 0 {
                    vals[line * want + b]
                } else {
                    vals[b * nx + line]
                };
                out[cell(first + b)] = v;
            }
            if ends == Ends::Ring {
                // the closing bond seen from both ends
                out[cell(1)] = out[cell(n + 1)];
            }
        }
    }
    // a bond across a seam between two strips seen from both sides: from the right
    // block's cell (as any x bond) and from the ghost right of the left block
    for j in 0..ny {
        for i in 0..nx {
            if let Some(q) = grid.seam_ghost(i, j) {
                bx[q] = bx[grid.at(i + 1, j)];
            }
        }
    }
    Ok((bx, by))
}

impl Medium for PerBlock {
    #[inline(always)]
    fn threshold(&self, p: usize) -> f64 {
        self.threshold[p]
    }
    #[inline(always)]
    fn loader(&self, p: usize) -> f64 {
        self.loader[p]
    }
    #[inline(always)]
    fn mass(&self, p: usize) -> f64 {
        self.mass[p]
    }
    #[inline(always)]
    fn inv_mass(&self, p: usize) -> f64 {
        self.inv_mass[p]
    }
    #[inline(always)]
    fn bond(&self, p: usize) -> f64 {
        self.bond[p]
    }
    #[inline(always)]
    fn bond_y(&self, p: usize) -> f64 {
        self.bond_y.as_ref().map_or(1.0, |b| b[p])
    }
    fn max_threshold(&self) -> f64 {
        self.max_threshold
    }
    fn fingerprint(&self) -> Vec<f64> {
        let mut f: Vec<f64> = [&self.threshold, &self.loader, &self.mass, &self.bond]
            .iter()
            .flat_map(|a| a.iter().copied())
            .collect();
        // a lattice's bonds across, when not all 1 (the fingerprints of lattices with
        // uniform springs stay those they were)
        if let Some(by) = self.bond_y.as_ref().filter(|b| b.iter().any(|&x| x != 1.0)) {
            f.extend_from_slice(by);
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bonds_follow_the_ends_and_errors_name_block_and_property() {
        let props = Properties {
            coupling: Some(vec![2.0, 3.0, 4.0]),
            ..Default::default()
        };
        let ring = PerBlock::new(&props, 3, Ends::Ring).unwrap();
        // bond i joins blocks i, i+1 mod 3: padded bonds 2, 3 and the closing 4 = 1
        assert_eq!(ring.bond, vec![1.0, 4.0, 2.0, 3.0, 4.0]);
        let free = PerBlock::new(&props, 4, Ends::Free).unwrap();
        assert_eq!(free.bond, vec![1.0, 1.0, 2.0, 3.0, 4.0, 1.0]);
        let walls = PerBlock::new(&props, 2, Ends::Walls).unwrap();
        assert_eq!(walls.bond, vec![1.0, 2.0, 3.0, 4.0]);
        let e = PerBlock::new(&props, 3, Ends::Free)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("coupling") && e.contains("2 for 3 blocks with free ends"),
            "{e}"
        );
        let bad = Properties {
            threshold: Some(vec![1.0, 1.0, -0.5, 1.0]),
            ..Default::default()
        };
        let e = PerBlock::new(&bad, 4, Ends::Free).unwrap_err().to_string();
        assert_eq!(
            e,
            "invalid threshold[2] = -0.5: allowed finite threshold > 0"
        );
        let bad = Properties {
            mass: Some(vec![1.0, f64::NAN]),
            ..Default::default()
        };
        let e = PerBlock::new(&bad, 2, Ends::Free).unwrap_err().to_string();
        assert!(e.starts_with("invalid mass[1] = NaN"), "{e}");
        assert!(Properties::default().is_uniform());
    }
}
