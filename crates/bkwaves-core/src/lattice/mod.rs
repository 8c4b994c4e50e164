//! The plane: the Burridge-Knopoff lattice simulated exactly (docs/lattice.md).
//!
//! Blocks (i, j) on a square lattice, one scalar displacement each, springs k_x along x
//! and k_y along y, in the paper's variables
//! phi_ij = u_ij - (u_{i+1,j} + u_{i-1,j} - 2 u_ij)/dx^2 - (u_{i,j+1} + u_{i,j-1} - 2 u_ij)/dy^2,
//! with stick, slip, sliding and loading exactly as in the chain: the same engine
//! ([`crate::chain::Engine`]) on the [`Grid`] geometry, so friction laws, media, event
//! sources, the integrators, event location and checkpoints are the chain's.

use crate::boundary::Boundary;
use crate::chain::geometry::Grid;
use crate::chain::medium::{Medium, Uniform};
use crate::chain::{ChainConfig, Engine};
use crate::error::{check_open, Error, Result};
use crate::friction::Friction;

/// The lattice simulator: the engine on a grid of blocks.
pub type Lattice<F, M = Uniform> = Engine<Grid, F, M>;

/// The shape and spacings of a lattice, and its boundary along each axis.
#[derive(Debug, Clone, Copy)]
pub struct LatticeSpec<'a> {
    /// Blocks along x (the slip direction's springs k_x).
    pub nx: usize,
    /// Blocks along y.
    pub ny: usize,
    /// dy = sqrt(k_p / k_y) (dx is `ChainConfig::dx`).
    pub dy: f64,
    /// Boundary across x = 0 and x = nx - 1.
    pub x: &'a dyn Boundary,
    /// Boundary across y = 0 and y = ny - 1.
    pub y: &'a dyn Boundary,
}

impl<F: Friction, M: Medium> Engine<Grid, F, M> {
    /// A lattice of nx x ny blocks with displacements `u0` and velocities `u_t0` in block
    /// order (k = i + nx j, row after row; default v: all stuck). The step is `step`
    /// times min(dx, dy).
    pub fn lattice(
        cfg: ChainConfig,
        spec: LatticeSpec,
        friction: F,
        medium: M,
        u0: &[f64],
        u_t0: Option<&[f64]>,
    ) -> Result<Self> {
        Self::on_grid(cfg, spec, None, friction, medium, u0, u_t0)
    }

    /// [`Engine::lattice`] with its cells in strips of at most `width` columns
    /// (chain/geometry/grid.rs; `width` >= nx: one strip, row-major; by default one strip
    /// up to 256 columns, strips of 62 beyond). The layout changes
    /// no result: the same bits (lattice/tests_strips.rs), but a [`crate::chain::medium::PerBlock`]
    /// medium must be made for the same layout ([`Grid::with_strips`]).
    pub fn lattice_in_strips(
        cfg: ChainConfig,
        spec: LatticeSpec,
        width: usize,
        friction: F,
        medium: M,
        u0: &[f64],
        u_t0: Option<&[f64]>,
    ) -> Result<Self> {
        if width == 0 {
            return Err(Error::InvalidParameter {
                name: "strip width",
                value: 0.0,
                allowed: ">= 1 columns",
            });
        }
        Self::on_grid(cfg, spec, Some(width), friction, medium, u0, u_t0)
    }

    /// The lattice in the default layout (`width` None) or in strips of `width`.
    fn on_grid(
        cfg: ChainConfig,
        spec: LatticeSpec,
        width: Option<usize>,
        friction: F,
        medium: M,
        u0: &[f64],
        u_t0: Option<&[f64]>,
    ) -> Result<Self> {
        for (name, v) in [("nx", spec.nx), ("ny", spec.ny)] {
            if v == 0 {
                return Err(Error::InvalidParameter {
                    name,
                    value: 0.0,
                    allowed: ">= 1 blocks",
                });
            }
        }
        check_open("dx", cfg.dx, 0.0, f64::INFINITY, "dx > 0")?;
        check_open("dy", spec.dy, 0.0, f64::INFINITY, "dy > 0")?;
        if u0.len() != spec.nx * spec.ny {
            return Err(Error::InvalidParameter {
                name: "u0",
                value: u0.len() as f64,
                allowed: "one displacement per block (nx ny values)",
            });
        }
        let grid = Grid::new(
            spec.nx,
            spec.ny,
            cfg.dx,
            spec.dy,
            (spec.x.left(), spec.x.right()),
            (spec.y.left(), spec.y.right()),
        );
        let grid = width.map_or(grid, |w| grid.with_strips(w));
        Engine::build(grid, cfg, friction, medium, spec.x.name(), u0, u_t0)
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_bonds;
#[cfg(test)]
mod tests_frontier;
#[cfg(test)]
mod tests_local;
#[cfg(test)]
mod tests_release;
#[cfg(test)]
mod tests_strips;
