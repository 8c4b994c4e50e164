//! Energy accounting.
//!
//! In units of (f_r - f_s)^2 / k_p (energy) and sqrt(m / k_p) (time), with
//! s_i = v - u_t,i the block speed over the ground and beta = f_s/(f_r - f_s):
//!
//! ```text
//!   E = sum_i s_i^2 / 2                          kinetic
//!     + sum_bonds (u_j - u_i)^2 / (2 dx^2)       coupling springs (incl. a fixed wall)
//!     + sum_i (u_i + beta)^2 / 2                 loader springs, (k_p X_i^2 / 2)
//!   dE/dt = v sum_i (u_i + beta)                 loader work rate
//!         - sum_sliding [beta s_i dir_i + 2 gamma s_i^2]   kinetic friction + viscous
//! ```
//!
//! (a fixed-end wall is attached to the ground and does no work; beta s dir = beta |s| on
//! the block's branch).
//!
//! Without backward slip (beta = inf, the paper's model; also any beta in a run where no
//! block slides backward) the beta terms cancel exactly, and the books are kept in the
//! beta-free form (beta = 0 above, [`crate::friction::Friction::beta`]). Expanding
//! (u + beta)^2/2 = u^2/2 + beta u + beta^2/2, the beta part of dE/dt is
//!
//! ```text
//!   d/dt [beta sum_i u_i] = beta sum_i u_t,i = beta (n v - sum_sliding s_i)
//! ```
//!
//! (a stuck block has u_t = v, a sliding one u_t = v - s), while the beta part of the
//! flows is the loader's v n beta minus the dry friction beta sum_sliding s_i dir_i, the
//! same thing when every dir_i = +1. The forward branch R = 2 gamma s contains no beta,
//! so neither the motion nor the beta-free balance depends on beta.
//!
//! The engine integrates
//! the two rates with the same quadrature as the motion and also books the kinetic
//! energy removed when a stick sets u_t = v exactly (`projection`, of the order of the
//! integration error squared) and the energy of kicks (`injected`).

use super::geometry::Geometry;
use super::medium::Medium;
use super::state::State;

/// Energy flows accumulated over a run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Ledger {
    /// Work done by the loader.
    pub load: f64,
    /// Work of the kinetic (dry) friction force f_s.
    pub dry: f64,
    /// Viscous dissipation.
    pub viscous: f64,
    /// Kinetic energy removed by setting u_t = v at sticks.
    pub projection: f64,
    /// Energy put in by kicks.
    pub injected: f64,
}

/// Energy of the chain split as (kinetic, coupling springs, loader springs) at time t.
/// With per-block properties (docs/chain.md) the terms are m_i s_i^2/2,
/// k_c (u_j - u_i)^2/(2 dx^2) per bond and k_p,i (u_i + beta/k_p,i)^2/2.
pub fn energy<G: Geometry, M: Medium>(
    st: &State<G>,
    med: &M,
    beta: f64,
    t: f64,
) -> (f64, f64, f64) {
    let mut kin = 0.0;
    let mut load = 0.0;
    let val = |p: usize| st.value(p, t);
    for p in st.geo.blocks() {
        let s = st.v - st.w[p];
        kin += 0.5 * med.mass(p) * s * s;
        let u = val(p);
        let kp = med.loader(p);
        let y = u + beta / kp;
        load += 0.5 * kp * y * y;
    }
    // the bonds, those beyond the ends included (to a wall, or a ring's closing bond)
    let coup = st.geo.coupling_energy(med, val, |g0| g0 + st.v * t);
    (kin, coup, load)
}
