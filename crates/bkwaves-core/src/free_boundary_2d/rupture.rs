//! The rupture catalog of the two-dimensional engine.
//!
//! A rupture is one fast-marching sweep: it starts at a node (a birth where u reached the
//! threshold, a nucleation by noise, or a trigger) and ends when its front has no node
//! left to reach (every trial node of it accepted, stopped, or taken by another rupture).
//! Two ruptures alive at once annihilate where they meet: neither enters the nodes the
//! other has swept (`contacts` counts such meetings).
//!
//! - area = (nodes swept) h^2, moment = sum over them of (u_+ - u_-) h^2 (the integral of
//!   the slip density A = u_+ - u_- over the area, node quadrature); divided by dx dy it is
//!   the lattice's sum of block slips;
//! - duration = last arrival - start;
//! - perimeter: the Crofton estimate with four directions (the two axes and the two
//!   diagonals), P = (pi/8) (N_axis h + N_diag h/sqrt 2), N the boundary crossings of
//!   grid lines in those directions; exact on average over orientations (a circle of
//!   radius R >> h gives 2 pi R), within [0.948, 1.026] of the length of any straight
//!   boundary. Edges of a free domain are not counted.

/// How a rupture started.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// u reached the threshold at a node.
    Birth,
    /// Nucleated by noise (u below the threshold).
    Nucleation,
    /// Started by the user (`trigger`).
    Trigger,
}

impl Origin {
    /// Lower-case name used in tables.
    pub fn as_str(&self) -> &'static str {
        match self {
            Origin::Birth => "birth",
            Origin::Nucleation => "nucleation",
            Origin::Trigger => "trigger",
        }
    }

    pub(super) fn code(&self) -> u64 {
        match self {
            Origin::Birth => 0,
            Origin::Nucleation => 1,
            Origin::Trigger => 2,
        }
    }

    pub(super) fn from_code(c: u64) -> Option<Self> {
        [Origin::Birth, Origin::Nucleation, Origin::Trigger]
            .get(c as usize)
            .copied()
    }
}

/// One rupture.
#[derive(Debug, Clone, PartialEq)]
pub struct Rupture {
    /// Rupture number (order of start).
    pub id: usize,
    /// How it started.
    pub origin: Origin,
    /// Start time.
    pub t_start: f64,
    /// Place of the start (the nucleation point; the node for births and triggers).
    pub x_start: f64,
    /// See `x_start`.
    pub y_start: f64,
    /// Stress at the start point.
    pub u_start: f64,
    /// Last arrival time (NaN before the first).
    pub t_end: f64,
    /// Nodes swept.
    pub n_nodes: usize,
    /// Area swept, n_nodes h^2.
    pub area: f64,
    /// Integral of u_+ - u_- over the area.
    pub moment: f64,
    /// Perimeter (Crofton estimate; NaN while running).
    pub perimeter: f64,
    /// Nodes where the front stopped (u_+ at or below the stopping stress).
    pub n_stopped: usize,
    /// Nodes reset under the creep rule (u_+ <= u_c s).
    pub n_creep: usize,
    /// Meetings with other live ruptures (annihilation between ruptures).
    pub contacts: usize,
    /// The front has nothing left to sweep.
    pub complete: bool,
    /// Trial nodes of this rupture now (derived while running; 0 when complete).
    pub(super) trials: usize,
    /// Nodes swept (kept while running, and after with recorded arrivals).
    pub(super) nodes: Vec<u32>,
    /// Their arrival times (recorded arrivals only, at completion).
    pub(super) arrivals: Vec<f64>,
}

impl Rupture {
    pub(super) fn new(id: usize, origin: Origin, t: f64, xy: (f64, f64), u: f64) -> Self {
        Rupture {
            id,
            origin,
            t_start: t,
            x_start: xy.0,
            y_start: xy.1,
            u_start: u,
            t_end: f64::NAN,
            n_nodes: 0,
            area: 0.0,
            moment: 0.0,
            perimeter: f64::NAN,
            n_stopped: 0,
            n_creep: 0,
            contacts: 0,
            complete: false,
            trials: 0,
            nodes: Vec::new(),
            arrivals: Vec::new(),
        }
    }

    /// Duration, last arrival - start (NaN while running or if nothing was swept).
    pub fn duration(&self) -> f64 {
        if self.complete {
            self.t_end - self.t_start
        } else {
            f64::NAN
        }
    }

    /// Mean slip, moment / area (NaN if nothing was swept).
    pub fn mean_slip(&self) -> f64 {
        self.moment / self.area
    }

    /// The swept nodes and their arrival times (recorded arrivals only; empty otherwise).
    pub fn arrivals(&self) -> (&[u32], &[f64]) {
        if self.arrivals.is_empty() {
            (&[], &[])
        } else {
            (&self.nodes, &self.arrivals)
        }
    }
}
