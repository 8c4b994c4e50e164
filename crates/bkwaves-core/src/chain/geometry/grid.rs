//! The square lattice: nx x ny blocks, row-major in (nx + 2) x (ny + 2) padded cells
//! (module docs of [`super`]); springs k_x along x (bonds `Medium::bond`, between p - 1
//! and p) and k_y along y (`Medium::bond_y`, between p - S and p, S = nx + 2), in the
//! paper's variables phi = k_p u - [x bonds]/dx^2 - [y bonds]/dy^2 (docs/lattice.md).

use super::{beyond_of, Beyond, Geometry, Stencil};
use crate::boundary::Ghost;
use crate::chain::events::Hermite;
use crate::chain::medium::Medium;

/// A lattice of nx x ny blocks at spacings dx, dy with ghosts on its four sides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Blocks along x.
    pub nx: usize,
    /// Blocks along y.
    pub ny: usize,
    /// Row stride of the padded arrays, nx + 2.
    pub s: usize,
    /// dx.
    pub dx: f64,
    /// dy.
    pub dy: f64,
    /// 1 / dx^2.
    pub kx: f64,
    /// 1 / dy^2.
    pub ky: f64,
    /// Ghosts beyond x = 0 and x = nx - 1.
    pub x: (Ghost, Ghost),
    /// Ghosts beyond y = 0 and y = ny - 1.
    pub y: (Ghost, Ghost),
    /// ceil(2^64 / s): q / s = (q inv_s) >> 64 for q, s < 2^32 (Lemire, Kaser and Kurz,
    /// "Faster remainder by direct computation", 2019), without a division.
    inv_s: u64,
}

impl Grid {
    /// nx x ny blocks at spacings dx, dy, with the ghosts of each axis.
    pub fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        x: (Ghost, Ghost),
        y: (Ghost, Ghost),
    ) -> Grid {
        Grid {
            nx,
            ny,
            s: nx + 2,
            dx,
            dy,
            kx: 1.0 / (dx * dx),
            ky: 1.0 / (dy * dy),
            x,
            y,
            inv_s: (u64::MAX / (nx as u64 + 2)).wrapping_add(1),
        }
    }

    /// (column, row) of padded index q (0..=nx + 1, 0..=ny + 1).
    #[inline(always)]
    pub fn cell(&self, q: usize) -> (usize, usize) {
        const SMALL: usize = 1 << 32;
        if q < SMALL && self.s < SMALL {
            let j = ((u128::from(self.inv_s) * q as u128) >> 64) as usize;
            (q - j * self.s, j)
        } else {
            (q % self.s, q / self.s)
        }
    }

    /// Padded index of block (i, j) (0-based).
    #[inline(always)]
    pub fn at(&self, i: usize, j: usize) -> usize {
        (j + 1) * self.s + i + 1
    }
}

/// The cells around a run of the lattice: its two ends along the row, then below and
/// above each block of the run.
#[derive(Debug, Clone)]
pub struct GridAround {
    ends: [(usize, usize, bool); 2],
    k: usize,
    p: usize,
    b: usize,
    s: usize,
    down: bool,
    up: bool,
}

impl Iterator for GridAround {
    type Item = (usize, usize, bool);
    #[inline]
    fn next(&mut self) -> Option<(usize, usize, bool)> {
        if self.k < 2 {
            self.k += 1;
            return Some(self.ends[self.k - 1]);
        }
        if self.p >= self.b {
            return None;
        }
        let p = self.p;
        // k = 2: below p, k = 3: above p (then the next block)
        if self.k == 2 {
            self.k = 3;
            Some((p - self.s, p, self.down))
        } else {
            self.k = 2;
            self.p += 1;
            Some((p + self.s, p, self.up))
        }
    }
}

/// The stage values left of, at, right of, below and above a run.
#[derive(Debug, Clone, Copy)]
pub struct GridStencil<'a> {
    l: &'a [f64],
    c: &'a [f64],
    r: &'a [f64],
    d: &'a [f64],
    u: &'a [f64],
    kx: f64,
    ky: f64,
    s: usize,
}

impl Stencil for GridStencil<'_> {
    #[inline(always)]
    fn centre(&self, i: usize) -> f64 {
        self.c[i]
    }
    #[inline(always)]
    fn force<M: Medium>(&self, med: &M, p: usize, i: usize) -> f64 {
        let (cl, cr) = (med.bond(p), med.bond(p + 1));
        let (cd, cu) = (med.bond_y(p), med.bond_y(p + self.s));
        let c = self.c[i];
        (cl * self.l[i] + cr * self.r[i] - (cl + cr) * c) * self.kx
            + (cd * self.d[i] + cu * self.u[i] - (cd + cu) * c) * self.ky
    }
}

impl Geometry for Grid {
    type Stencil<'a> = GridStencil<'a>;
    type Nbrs = [usize; 4];
    type Around = GridAround;
    const FRONTIER: bool = true;

    #[inline(always)]
    fn n(&self) -> usize {
        self.nx * self.ny
    }
    fn shape(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
    #[inline(always)]
    fn cells(&self) -> usize {
        self.s * (self.ny + 2)
    }
    #[inline(always)]
    fn padded(&self, k: usize) -> usize {
        self.at(k % self.nx, k / self.nx)
    }
    #[inline(always)]
    fn index(&self, p: usize) -> usize {
        let (i, j) = self.cell(p);
        (j - 1) * self.nx + (i - 1)
    }
    fn blocks(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.ny).flat_map(move |j| {
            let row = (j + 1) * self.s;
            row + 1..=row + self.nx
        })
    }
    #[inline]
    fn is_ghost(&self, q: usize) -> bool {
        let (i, j) = self.cell(q);
        i == 0 || i == self.nx + 1 || j == 0 || j == self.ny + 1
    }
    #[inline]
    fn beyond(&self, q: usize, p: usize) -> Beyond {
        let (i, j) = self.cell(q);
        if i == 0 {
            beyond_of(self.x.0, p, q + self.nx)
        } else if i == self.nx + 1 {
            beyond_of(self.x.1, p, q - self.nx)
        } else if j == 0 {
            beyond_of(self.y.0, p, q + self.ny * self.s)
        } else {
            beyond_of(self.y.1, p, q - self.ny * self.s)
        }
    }
    #[inline]
    fn ghost_partner(&self, q: usize) -> Option<usize> {
        let (i, j) = self.cell(q);
        let (g, far) = if i == 0 {
            (self.x.0, q + self.nx)
        } else if i == self.nx + 1 {
            (self.x.1, q - self.nx)
        } else if j == 0 {
            (self.y.0, q + self.ny * self.s)
        } else {
            (self.y.1, q - self.ny * self.s)
        };
        matches!(g, Ghost::Wrap).then_some(far)
    }
    #[inline(always)]
    fn neighbours(&self, p: usize) -> [usize; 4] {
        [p - 1, p + 1, p - self.s, p + self.s]
    }
    #[inline]
    fn around_run(&self, a: usize, b: usize) -> GridAround {
        let (i, j) = self.cell(a);
        GridAround {
            ends: [
                (a - 1, a, i == 1),
                (b, b - 1, b - j * self.s == self.nx + 1),
            ],
            k: 0,
            p: a,
            b,
            s: self.s,
            down: j == 1,
            up: j == self.ny,
        }
    }
    fn sightings(&self, r: usize) -> ([(usize, u8); 8], usize) {
        let (i, j) = self.cell(r);
        let (s, nx, ny) = (self.s, self.nx, self.ny);
        let mut out = [(0, 0); 8];
        let mut k = 0;
        let mut add = |p: usize, side: u8| {
            out[k] = (p, side);
            k += 1;
        };
        if i < nx {
            add(r + 1, 0);
        }
        if i > 1 {
            add(r - 1, 1);
        }
        if j < ny {
            add(r + s, 2);
        }
        if j > 1 {
            add(r - s, 3);
        }
        // periodic ghosts standing for r, next to the block on the far side
        if i == 1 && self.x.1 == Ghost::Wrap {
            add(r + nx - 1, 1);
        }
        if i == nx && self.x.0 == Ghost::Wrap {
            add(r + 1 - nx, 0);
        }
        if j == 1 && self.y.1 == Ghost::Wrap {
            add(r + (ny - 1) * s, 3);
        }
        if j == ny && self.y.0 == Ghost::Wrap {
            add(r + s - ny * s, 2);
        }
        (out, k)
    }
    #[inline(always)]
    fn stencil<'a>(&self, su: &'a [f64], a: usize, b: usize) -> GridStencil<'a> {
        let s = self.s;
        GridStencil {
            l: &su[a - 1..b - 1],
            c: &su[a..b],
            r: &su[a + 1..b + 1],
            d: &su[a - s..b - s],
            u: &su[a + s..b + s],
            kx: self.kx,
            ky: self.ky,
            s,
        }
    }
    #[inline(always)]
    fn force<M: Medium>(&self, med: &M, p: usize, up: f64, value: impl Fn(usize) -> f64) -> f64 {
        let s = self.s;
        let (cl, cr) = (med.bond(p), med.bond(p + 1));
        let (cd, cu) = (med.bond_y(p), med.bond_y(p + s));
        (cl * value(p - 1) + cr * value(p + 1) - (cl + cr) * up) * self.kx
            + (cd * value(p - s) + cu * value(p + s) - (cd + cu) * up) * self.ky
    }
    #[inline]
    fn phi_hermite<M: Medium>(
        &self,
        med: &M,
        p: usize,
        up: Hermite,
        nb: impl Fn(usize) -> Hermite,
    ) -> Hermite {
        let s = self.s;
        let (l, r, d, u) = (nb(p - 1), nb(p + 1), nb(p - s), nb(p + s));
        let (cl, cr) = (med.bond(p), med.bond(p + 1));
        let (cd, cu) = (med.bond_y(p), med.bond_y(p + s));
        let own = med.loader(p) + (cl + cr) * self.kx + (cd + cu) * self.ky;
        up.combine(own, &l.combine(cl, &r, cr), -self.kx).combine(
            1.0,
            &d.combine(cd, &u, cu),
            -self.ky,
        )
    }
    #[inline]
    fn stiffness<M: Medium>(&self, med: &M, p: usize) -> f64 {
        (med.bond(p) + med.bond(p + 1)) * self.kx
            + (med.bond_y(p) + med.bond_y(p + self.s)) * self.ky
    }
    fn coupling_energy<M: Medium>(
        &self,
        med: &M,
        value: impl Fn(usize) -> f64,
        wall: impl Fn(f64) -> f64,
    ) -> f64 {
        // each bond once: from its lower cell to the right (x) and up (y); a ghost beyond
        // the far side is a wall or the periodic partner (a ring's closing bond), beyond
        // the near side only a wall counts (the closing bond is counted from the far one)
        let s = self.s;
        let mut coup = 0.0;
        let bond = |q: usize, p: usize, b: f64, k: f64, far: bool| -> f64 {
            let up = value(p);
            let uq = if self.is_ghost(q) {
                match self.beyond(q, p) {
                    Beyond::Wall(g0) => wall(g0),
                    Beyond::Block(r) if far && r != p => value(r),
                    Beyond::Block(_) => return 0.0,
                }
            } else {
                value(q)
            };
            let d = uq - up;
            0.5 * b * d * d * k
        };
        for p in self.blocks() {
            let (i, j) = self.cell(p);
            coup += bond(p + 1, p, med.bond(p + 1), self.kx, true);
            coup += bond(p + s, p, med.bond_y(p + s), self.ky, true);
            if i == 1 {
                coup += bond(p - 1, p, med.bond(p), self.kx, false);
            }
            if j == 1 {
                coup += bond(p - s, p, med.bond_y(p), self.ky, false);
            }
        }
        coup
    }
    fn spacing(&self) -> f64 {
        self.dx.min(self.dy)
    }
    fn describe(&self) -> String {
        format!(
            "lattice {} x {}, dy = {:e}, x {:?}, y {:?}",
            self.nx, self.ny, self.dy, self.x, self.y
        )
    }
}
