//! The chain: blocks 1..=n of n + 2 padded cells, ghosts 0 and n + 1 (module docs of
//! [`super`]); every formula in the order of operations the chain engine always used, so
//! the chain's results are the same bits.

use super::{beyond_of, Beyond, Geometry, Stencil};
use crate::boundary::Ghost;
use crate::chain::events::Hermite;
use crate::chain::medium::Medium;

/// A chain of n blocks at spacing dx with the given ghosts beyond its ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// Number of blocks.
    pub n: usize,
    /// 1 / dx^2.
    pub k: f64,
    /// dx.
    pub dx: f64,
    /// Ghost beyond the left end.
    pub left: Ghost,
    /// Ghost beyond the right end.
    pub right: Ghost,
}

impl Line {
    /// n blocks at spacing dx.
    pub fn new(n: usize, dx: f64, left: Ghost, right: Ghost) -> Line {
        Line {
            n,
            k: 1.0 / (dx * dx),
            dx,
            left,
            right,
        }
    }
}

/// The stage values left of, at and right of a run.
#[derive(Debug, Clone, Copy)]
pub struct LineStencil<'a> {
    l: &'a [f64],
    c: &'a [f64],
    r: &'a [f64],
    k: f64,
}

impl Stencil for LineStencil<'_> {
    #[inline(always)]
    fn centre(&self, i: usize) -> f64 {
        self.c[i]
    }
    #[inline(always)]
    fn force<M: Medium>(&self, med: &M, p: usize, i: usize) -> f64 {
        let (cl, cr) = (med.bond(p), med.bond(p + 1));
        (cl * self.l[i] + cr * self.r[i] - (cl + cr) * self.c[i]) * self.k
    }
}

impl Geometry for Line {
    type Stencil<'a> = LineStencil<'a>;
    type Nbrs = [usize; 2];
    type Around = std::array::IntoIter<(usize, usize, bool), 2>;
    const FRONTIER: bool = false;

    #[inline(always)]
    fn n(&self) -> usize {
        self.n
    }
    fn shape(&self) -> (usize, usize) {
        (self.n, 1)
    }
    #[inline(always)]
    fn cells(&self) -> usize {
        self.n + 2
    }
    #[inline(always)]
    fn padded(&self, k: usize) -> usize {
        k + 1
    }
    #[inline(always)]
    fn index(&self, p: usize) -> usize {
        p - 1
    }
    fn blocks(&self) -> impl Iterator<Item = usize> + '_ {
        1..=self.n
    }
    #[inline(always)]
    fn is_ghost(&self, q: usize) -> bool {
        q == 0 || q == self.n + 1
    }
    #[inline]
    fn beyond(&self, q: usize, p: usize) -> Beyond {
        if q == 0 {
            beyond_of(self.left, p, self.n)
        } else {
            beyond_of(self.right, p, 1)
        }
    }
    #[inline]
    fn ghost_partner(&self, q: usize) -> Option<usize> {
        if q == 0 {
            matches!(self.left, Ghost::Wrap).then_some(self.n)
        } else {
            matches!(self.right, Ghost::Wrap).then_some(1)
        }
    }
    #[inline(always)]
    fn neighbours(&self, p: usize) -> [usize; 2] {
        [p - 1, p + 1]
    }
    #[inline(always)]
    fn around_run(&self, a: usize, b: usize) -> Self::Around {
        [(a - 1, a, a == 1), (b, b - 1, b == self.n + 1)].into_iter()
    }
    fn sightings(&self, r: usize) -> ([(usize, u8); 8], usize) {
        let mut out = [(0, 0); 8];
        let mut k = 0;
        let mut add = |p: usize, side: u8| {
            out[k] = (p, side);
            k += 1;
        };
        if r < self.n {
            add(r + 1, 0);
        }
        if r > 1 {
            add(r - 1, 1);
        }
        // periodic ghosts: 0 stands for block n, n + 1 for block 1
        if r == self.n && self.left == Ghost::Wrap {
            add(1, 0);
        }
        if r == 1 && self.right == Ghost::Wrap {
            add(self.n, 1);
        }
        (out, k)
    }
    #[inline(always)]
    fn stencil<'a>(&self, su: &'a [f64], a: usize, b: usize) -> LineStencil<'a> {
        LineStencil {
            l: &su[a - 1..b - 1],
            c: &su[a..b],
            r: &su[a + 1..b + 1],
            k: self.k,
        }
    }
    #[inline(always)]
    fn force<M: Medium>(&self, med: &M, p: usize, up: f64, value: impl Fn(usize) -> f64) -> f64 {
        let (cl, cr) = (med.bond(p), med.bond(p + 1));
        (cl * value(p - 1) + cr * value(p + 1) - (cl + cr) * up) * self.k
    }
    #[inline(always)]
    fn phi_hermite<M: Medium>(
        &self,
        med: &M,
        p: usize,
        up: Hermite,
        nb: impl Fn(usize) -> Hermite,
    ) -> Hermite {
        let k = self.k;
        let (l, r) = (nb(p - 1), nb(p + 1));
        let (cl, cr) = (med.bond(p), med.bond(p + 1));
        // phi = k_p up - f with f the force's own floats ((cl l + cr r - (cl + cr) up) k,
        // as `force` and `Blocks::phi` form it; the lattice's form, docs/lattice.md "Ties")
        let lap = l.combine(cl, &r, cr).combine(1.0, &up, -(cl + cr));
        up.combine(med.loader(p), &lap, -k)
    }
    #[inline]
    fn stiffness<M: Medium>(&self, med: &M, p: usize) -> f64 {
        (med.bond(p) + med.bond(p + 1)) * self.k
    }
    fn coupling_energy<M: Medium>(
        &self,
        med: &M,
        value: impl Fn(usize) -> f64,
        wall: impl Fn(f64) -> f64,
    ) -> f64 {
        let n = self.n;
        let mut coup = 0.0;
        for p in 1..n {
            let d = value(p + 1) - value(p);
            coup += 0.5 * med.bond(p + 1) * d * d * self.k;
        }
        // the bonds beyond the ends: to a wall (one at each end), or to another block (a
        // ring's closing bond, counted once, from the right end); a free end has none
        let end_bond = |q: usize, edge: usize| -> f64 {
            let bond = med.bond(if q == 0 { 1 } else { n + 1 });
            match self.beyond(q, edge) {
                Beyond::Wall(g0) => {
                    let d = value(edge) - wall(g0);
                    0.5 * bond * d * d * self.k
                }
                Beyond::Block(r) if r != edge && q == n + 1 => {
                    let d = value(r) - value(edge);
                    0.5 * bond * d * d * self.k
                }
                Beyond::Block(_) => 0.0,
            }
        };
        coup + (end_bond(0, 1) + end_bond(n + 1, n))
    }
    fn spacing(&self) -> f64 {
        self.dx
    }
    fn describe(&self) -> String {
        format!("{:?}", (self.left, self.right))
    }
}
