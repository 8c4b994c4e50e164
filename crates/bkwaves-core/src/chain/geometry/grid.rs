//! The square lattice: nx x ny blocks in vertical strips of padded cells (module docs of
//! [`super`]); springs k_x along x (bonds `Medium::bond`, between p - 1 and p) and k_y
//! along y (`Medium::bond_y`, between p - S and p, S the strips' row stride), in the
//! paper's variables phi = k_p u - [x bonds]/dx^2 - [y bonds]/dy^2 (docs/lattice.md).
//!
//! The layout. A lattice of at most [`ONE_STRIP_UP_TO`] columns is one strip: the
//! row-major (nx + 2) x (ny + 2) layout. A wider one is cut into m = ceil(nx / W) strips
//! (W = [`STRIP_WIDTH`] unless chosen: [`Grid::with_strips`]), w = ceil(nx / m) columns
//! each but the last (nx - (m - 1) w columns).
//! Every strip is a little lattice of its own: w + 2 cells a row (stride S = w + 2, the
//! same for all strips), ny + 2 rows, its own ghost frame; strip t holds the cells
//! [t S (ny + 2), (t + 1) S (ny + 2)), and block (i, j), t = i / w, li = i - t w, sits at
//! t S (ny + 2) + (j + 1) S + li + 1 (with nx <= W one strip, row-major). A run is a
//! stretch of one row of one strip; its neighbours are p -/+ 1 and p -/+ S, whatever the
//! strip.
//!
//! A ghost column between two strips stands for the neighbouring strip's edge block as a
//! periodic ghost stands for the far side's block ([`Geometry::beyond`] gives
//! `Beyond::Block(r)`, [`Geometry::ghost_partner`] `Some(r)`): the engine fills it with
//! r's value before each stage as it fills a periodic ghost, so every block's force is
//! the same arithmetic on the same values as in one strip. The lattice's own sides are
//! the ghost columns left of strip 0 and right of strip m - 1, and the ghost rows. The
//! cells of the last strip right of its ghost column (when it is narrower) are dead:
//! ghosts that are nobody's neighbour.
//!
//! Why: a rupture's ring of sliding blocks is stepped row by row, and a row's neighbours
//! above and below are S cells away; with rows as long as the lattice the step slows as
//! nx grows (docs/benchmarks.md, "Why the step is slower inside a rupture"), and a page of
//! scratch holds a fraction of a row, so it cannot be given back behind the ring while any
//! cell of that row is live (../release.rs). In strips both are bounded by W. But a seam
//! cuts the runs that cross it, and a run costs a set-up and a scalar tail: measured
//! (docs/benchmarks.md, "The lattice's cells in strips"), strips of 62 make the step over
//! a sliding square 1.45 times faster in a 1024-wide lattice, 1.2 in a 512-wide one, the
//! same at 256, and a 128-wide rupture 0.91 times as fast: hence one strip up to
//! [`ONE_STRIP_UP_TO`] columns.

use super::{beyond_of, Beyond, Geometry, Stencil};
use crate::boundary::Ghost;
use crate::chain::events::Hermite;
use crate::chain::medium::Medium;

/// The widest strip by default (columns): 62 + 2 cells, 512 bytes a row of f64.
pub const STRIP_WIDTH: usize = 62;

/// The widest lattice kept in one strip by default (columns; module docs).
pub const ONE_STRIP_UP_TO: usize = 256;

/// ceil(2^64 / d): q / d = (q inv) >> 64 for q, d < 2^32 (Lemire, Kaser and Kurz,
/// "Faster remainder by direct computation", 2019), without a division.
fn inverse(d: usize) -> u64 {
    (u64::MAX / d as u64).wrapping_add(1)
}

/// q / d by its inverse (`inverse(d)`), exact for q, d < 2^32; by dividing otherwise.
#[inline(always)]
fn div(q: usize, d: usize, inv: u64) -> usize {
    const SMALL: usize = 1 << 32;
    if q < SMALL && d < SMALL {
        ((u128::from(inv) * q as u128) >> 64) as usize
    } else {
        q / d
    }
}

/// A lattice of nx x ny blocks at spacings dx, dy with ghosts on its four sides, laid
/// out in strips (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    /// Blocks along x.
    pub nx: usize,
    /// Blocks along y.
    pub ny: usize,
    /// Row stride of the padded arrays, w + 2 (nx + 2 in one strip).
    pub s: usize,
    /// Columns of every strip but the last, w.
    pub w: usize,
    /// Number of strips, m.
    pub m: usize,
    /// Columns of the last strip, nx - (m - 1) w.
    pub last: usize,
    /// Cells of a strip, S (ny + 2).
    pub strip: usize,
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
    /// `inverse(s)`.
    inv_s: u64,
    /// `inverse(strip)`.
    inv_strip: u64,
}

impl Grid {
    /// nx x ny blocks at spacings dx, dy, with the ghosts of each axis: one strip up to
    /// [`ONE_STRIP_UP_TO`] columns, wider in strips of at most [`STRIP_WIDTH`] columns.
    pub fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        x: (Ghost, Ghost),
        y: (Ghost, Ghost),
    ) -> Grid {
        let width = if nx <= ONE_STRIP_UP_TO {
            nx.max(1)
        } else {
            STRIP_WIDTH
        };
        Grid::in_strips(nx, ny, dx, dy, x, y, width)
    }

    /// The same lattice in strips of at most `width` >= 1 columns (module docs; `width`
    /// >= nx: one strip).
    pub fn in_strips(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        x: (Ghost, Ghost),
        y: (Ghost, Ghost),
        width: usize,
    ) -> Grid {
        assert!(width >= 1, "a strip is at least one column wide");
        let m = nx.div_ceil(width).max(1);
        let w = nx.div_ceil(m);
        // (m - 1) w < nx: m - 1 < nx / width and w <= width
        let last = nx - (m - 1) * w;
        let s = w + 2;
        let strip = s * (ny + 2);
        Grid {
            nx,
            ny,
            s,
            w,
            m,
            last,
            strip,
            dx,
            dy,
            kx: 1.0 / (dx * dx),
            ky: 1.0 / (dy * dy),
            x,
            y,
            inv_s: inverse(s),
            inv_strip: inverse(strip),
        }
    }

    /// The same lattice in strips of at most `width` columns.
    pub fn with_strips(&self, width: usize) -> Grid {
        Grid::in_strips(self.nx, self.ny, self.dx, self.dy, self.x, self.y, width)
    }

    /// Columns of strip t.
    #[inline(always)]
    pub fn width(&self, t: usize) -> usize {
        if t + 1 == self.m {
            self.last
        } else {
            self.w
        }
    }

    /// (strip, column in the strip, row) of padded index q (column 0..=w + 1: 0 and
    /// width + 1 the strip's ghost columns; row 0..=ny + 1), without a division.
    #[inline(always)]
    pub fn cell(&self, q: usize) -> (usize, usize, usize) {
        let (t, r) = if self.m == 1 {
            (0, q)
        } else {
            let t = div(q, self.strip, self.inv_strip);
            (t, q - t * self.strip)
        };
        let j = div(r, self.s, self.inv_s);
        (t, r - j * self.s, j)
    }

    /// Padded index of block (i, j) (0-based).
    #[inline(always)]
    pub fn at(&self, i: usize, j: usize) -> usize {
        let t = i / self.w;
        t * self.strip + (j + 1) * self.s + (i - t * self.w) + 1
    }

    /// Padded index of the cell at padded column ip (0..=nx + 1: 0 and nx + 1 the
    /// lattice's own ghost columns) and padded row jp (0..=ny + 1).
    pub fn at_padded(&self, ip: usize, jp: usize) -> usize {
        if ip == 0 {
            jp * self.s
        } else if ip == self.nx + 1 {
            (self.m - 1) * self.strip + jp * self.s + self.last + 1
        } else {
            let (i, t) = (ip - 1, (ip - 1) / self.w);
            t * self.strip + jp * self.s + (i - t * self.w) + 1
        }
    }

    /// The padded index of the ghost cell right of block (i, j) of a strip's last column
    /// when another strip follows (the cell standing for block (i + 1, j)), if any.
    pub fn seam_ghost(&self, i: usize, j: usize) -> Option<usize> {
        (i + 1 < self.nx && (i + 1) % self.w == 0).then(|| self.at(i, j) + 1)
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
        self.m * self.strip
    }
    #[inline(always)]
    fn padded(&self, k: usize) -> usize {
        self.at(k % self.nx, k / self.nx)
    }
    #[inline(always)]
    fn index(&self, p: usize) -> usize {
        let (t, c, j) = self.cell(p);
        (j - 1) * self.nx + t * self.w + (c - 1)
    }
    fn blocks(&self) -> impl Iterator<Item = usize> + '_ {
        // block order: row after row, each row through the strips in turn
        (0..self.ny).flat_map(move |j| {
            (0..self.m).flat_map(move |t| {
                let row = t * self.strip + (j + 1) * self.s;
                row + 1..=row + self.width(t)
            })
        })
    }
    #[inline]
    fn is_ghost(&self, q: usize) -> bool {
        let (t, c, j) = self.cell(q);
        c == 0 || c > self.width(t) || j == 0 || j == self.ny + 1
    }
    #[inline]
    fn beyond(&self, q: usize, p: usize) -> Beyond {
        match self.side_of(q) {
            Side::Seam(r) => Beyond::Block(r),
            Side::Edge(g, far) => beyond_of(g, p, far),
        }
    }
    #[inline]
    fn ghost_partner(&self, q: usize) -> Option<usize> {
        match self.side_of(q) {
            Side::Seam(r) => Some(r),
            Side::Edge(g, far) => matches!(g, Ghost::Wrap).then_some(far),
        }
    }
    #[inline(always)]
    fn neighbours(&self, p: usize) -> [usize; 4] {
        [p - 1, p + 1, p - self.s, p + self.s]
    }
    #[inline]
    fn around_run(&self, a: usize, b: usize) -> GridAround {
        // a run lies in one row of one strip: its ends are ghosts at the strip's columns
        let (t, c, j) = self.cell(a);
        GridAround {
            ends: [
                (a - 1, a, c == 1),
                (b, b - 1, c + (b - a) == self.width(t) + 1),
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
        // Each sighting (p, side) is the other end of one of r's four neighbour slots:
        // r's slot towards -x (+x, -y, +y) resolves to p exactly when p's slot towards
        // +x (-x, +y, -y) stands for r. The cases below for one slot exclude each other
        // (along x: r's neighbour in its strip, across a seam, across a periodic side;
        // along y: in the strip, across a periodic side), so there are at most four.
        let (t, c, j) = self.cell(r);
        let (s, ny, wt) = (self.s, self.ny, self.width(t));
        let mut out = [(0, 0); 8];
        let mut k = 0;
        let mut add = |p: usize, side: u8| {
            out[k] = (p, side);
            k += 1;
        };
        if c < wt {
            add(r + 1, 0);
        }
        if c > 1 {
            add(r - 1, 1);
        }
        if j < ny {
            add(r + s, 2);
        }
        if j > 1 {
            add(r - s, 3);
        }
        // seam ghosts standing for r, next to the edge block of the neighbouring strip
        if c == wt && t + 1 < self.m {
            add(r + self.strip + 1 - self.w, 0);
        }
        if c == 1 && t > 0 {
            add(r + self.w - 1 - self.strip, 1);
        }
        // periodic ghosts standing for r, next to the block on the far side
        let across = (self.m - 1) * self.strip + self.last;
        if c == 1 && t == 0 && self.x.1 == Ghost::Wrap {
            add(r + across - 1, 1);
        }
        if c == wt && t + 1 == self.m && self.x.0 == Ghost::Wrap {
            add(r + 1 - across, 0);
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
        // phi = k_p up - f with f the force's own floats (cd d + cu u - (cd + cu) up per
        // axis, as `force` and `Blocks::phi` sum them): a coupling across that does not
        // vary is an exact zero, so a lattice uniform in y (or x) locates the chain's
        // crossings to the bit, and x <-> y is a swap of two addends (docs/lattice.md,
        // "Ties")
        let along = l.combine(cl, &r, cr).combine(1.0, &up, -(cl + cr));
        let across = d.combine(cd, &u, cu).combine(1.0, &up, -(cd + cu));
        let f = along.combine(self.kx, &across, self.ky);
        up.combine(med.loader(p), &f, -1.0)
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
        // (a seam's bond is counted from its left block, across the seam ghost standing
        // for the right one, as the far side's bond: in block order, the same terms in
        // the same order as in one strip)
        for p in self.blocks() {
            let (t, c, j) = self.cell(p);
            coup += bond(p + 1, p, med.bond(p + 1), self.kx, true);
            coup += bond(p + s, p, med.bond_y(p + s), self.ky, true);
            if c == 1 && t == 0 {
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
        // (one strip: as before strips, so the checkpoints of such lattices still load)
        let mut d = format!(
            "lattice {} x {}, dy = {:e}, x {:?}, y {:?}",
            self.nx, self.ny, self.dy, self.x, self.y
        );
        if self.m > 1 {
            d += &format!(
                ", in {} strips of {} columns (the last {})",
                self.m, self.w, self.last
            );
        }
        d
    }
}

/// What a ghost cell next to a real block is: a seam between two strips (standing for
/// block r of the neighbouring strip), or a side of the lattice (its ghost kind and the
/// far side's block).
#[derive(Debug, Clone, Copy)]
enum Side {
    Seam(usize),
    Edge(Ghost, usize),
}

impl Grid {
    /// The side of ghost cell q (next to a real block: not a corner, not dead).
    #[inline]
    fn side_of(&self, q: usize) -> Side {
        let (t, c, j) = self.cell(q);
        if c == 0 {
            if t == 0 {
                Side::Edge(self.x.0, q + (self.m - 1) * self.strip + self.last)
            } else {
                Side::Seam(q + self.w - self.strip)
            }
        } else if c > self.width(t) {
            debug_assert_eq!(c, self.width(t) + 1, "a dead cell is nobody's neighbour");
            if t + 1 == self.m {
                Side::Edge(self.x.1, q - (self.m - 1) * self.strip - self.last)
            } else {
                Side::Seam(q + self.strip - self.w)
            }
        } else if j == 0 {
            Side::Edge(self.y.0, q + self.ny * self.s)
        } else {
            Side::Edge(self.y.1, q - self.ny * self.s)
        }
    }
}
