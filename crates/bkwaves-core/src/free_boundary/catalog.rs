//! What a free boundary run records: the event catalog and the shock paths.
//!
//! An event is a maximal time interval during which at least one shock exists (as in the
//! chain, where an event runs from the first slip after a quiet time to the last
//! re-stick). Its slip is integrated along the paths of its shocks: total slip (moment)
//! = int A(u_+(x)) dx over the ruptured length, by the trapezoid rule on the points where
//! the shocks were recorded (births, node crossings, ends): second order in the grid
//! spacing h. In chain units the same quantity is the chain's `moment` (sum of block
//! slips) times dx.

/// How a path point was produced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathKind {
    /// A shock given in the initial state.
    Initial,
    /// Birth where u reached 1.
    Birth,
    /// Spontaneous nucleation of a pair by noise (u < 1).
    Nucleation,
    /// The shock passed a grid node and reset it.
    Node,
    /// Two shocks met and annihilated.
    Annihilation,
    /// The shock left through a free end.
    Exit,
    /// u_+ fell to 0 ahead of the shock (it cannot propagate; eq. nocreep regime ends).
    Death,
    /// u_+ fell to u_c with the `stop` creep rule.
    CreepStop,
}

impl PathKind {
    /// Lower-case name used in tables.
    pub fn as_str(&self) -> &'static str {
        match self {
            PathKind::Initial => "initial",
            PathKind::Birth => "birth",
            PathKind::Nucleation => "nucleation",
            PathKind::Node => "node",
            PathKind::Annihilation => "annihilation",
            PathKind::Exit => "exit",
            PathKind::Death => "death",
            PathKind::CreepStop => "creep_stop",
        }
    }
}

/// One recorded point of a shock path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPoint {
    /// Shock id.
    pub shock: usize,
    /// Event id.
    pub event: usize,
    /// Time.
    pub t: f64,
    /// Position (in [x_0, x_0 + L) on a ring).
    pub x: f64,
    /// Direction +1 / -1.
    pub dir: i8,
    /// Stress ahead of the shock.
    pub u_plus: f64,
    /// Stress left behind (NaN at the end of a shock).
    pub u_minus: f64,
    /// What happened.
    pub kind: PathKind,
    /// u_+ was below u_c (creep; the documented rule applied).
    pub creep: bool,
}

/// One event (first birth to the disappearance of the last shock).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FbEvent {
    /// Event number.
    pub id: usize,
    /// Time of the first birth.
    pub t_start: f64,
    /// Time the last shock disappeared (NaN while running).
    pub t_end: f64,
    /// Place of the first birth.
    pub x_start: f64,
    /// Curvature a of u = 1 - a (x - x0)^2 + v t at the first birth (eq. a); NaN for an
    /// initial shock or a spontaneous nucleation.
    pub curvature: f64,
    /// Smallest position reached (unwrapped on a ring).
    pub x_min: f64,
    /// Largest position reached (unwrapped on a ring).
    pub x_max: f64,
    /// Total slip int A dx over the ruptured length.
    pub moment: f64,
    /// Total length swept by the shocks.
    pub swept: f64,
    /// Births where u reached 1 (pairs, or single shocks at a free end).
    pub n_births: usize,
    /// Spontaneous nucleations (pairs started by noise).
    pub n_nucleations: usize,
    /// The event began with a spontaneous nucleation (else a birth or initial shocks).
    pub spontaneous: bool,
    /// Shocks created.
    pub n_shocks: usize,
    /// Annihilations.
    pub n_annihilations: usize,
    /// Shocks that left through a free end.
    pub n_exits: usize,
    /// Shocks that died (u_+ <= 0, or u_c with the stop rule).
    pub n_deaths: usize,
    /// Node resets done in creep (u_+ < u_c) with the zero rule.
    pub n_creep: usize,
}

impl FbEvent {
    /// A new event at a birth.
    pub fn new(id: usize, t: f64, x: f64, curvature: f64) -> Self {
        FbEvent {
            id,
            t_start: t,
            t_end: f64::NAN,
            x_start: x,
            curvature,
            x_min: x,
            x_max: x,
            moment: 0.0,
            swept: 0.0,
            n_births: 0,
            n_nucleations: 0,
            spontaneous: false,
            n_shocks: 0,
            n_annihilations: 0,
            n_exits: 0,
            n_deaths: 0,
            n_creep: 0,
        }
    }

    /// Mean stress drop over the swept length (the chain's `stress_drop`: mean of u at
    /// the slip minus u after).
    pub fn stress_drop(&self) -> f64 {
        if self.swept > 0.0 {
            self.moment / self.swept
        } else {
            f64::NAN
        }
    }
}
