//! One traveling front measured in a direct simulation (v = 0): the `bkwaves front`
//! experiment.
//!
//! A chain of `blocks` blocks at uniform u = u_+ (free ends, all stuck) is triggered by
//! kicking block 0 forward at t = 0. The front crosses the chain; the speed is measured from
//! the slip times of a window of blocks away from the trigger and from the far end,
//! c = dx (b - a) / (t_b - t_a), exact for a steady front (one slip every dx/c). Behind
//! the front, blocks of the window that re-stick give u_- (their final u) and the pulse
//! width w = c * (time a block slides). A pulse has a steady healing front: every block
//! of the window slides for the same time. If the window blocks are still sliding long
//! after the front has passed, or stop at scattered times (driven by the ends or by
//! lattice noise), the regime is creep.

use super::{Chain, ChainConfig, Trigger, TriggerKind};
use crate::boundary::Free;
use crate::error::{check_open, Error, Result};
use crate::friction::{Friction, FrictionSpec};

/// The trigger: block 0 is kicked forward with speed KICK over the ground (a release
/// alone does not start a front when (1 - u_+) dx^2 exceeds the static deflection).
pub const KICK: f64 = 2.0;

/// Settings of a front measurement.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontOptions {
    /// Stress ahead, 0 < u_+ < 1.
    pub u_plus: f64,
    /// The friction law and its parameters.
    pub friction: FrictionSpec,
    /// Lattice spacing.
    pub dx: f64,
    /// Number of blocks.
    pub blocks: usize,
    /// Step as a fraction of dx.
    pub step: f64,
    /// Window of blocks (fractions of the chain) where c, u_- and w are measured.
    pub window: (f64, f64),
    /// Wait for the window blocks to re-stick (false: measure c only; `pulse` is then
    /// false and u_-, w NaN).
    pub heal: bool,
    /// Time to wait for re-sticking after the front left the window, in units of the
    /// time the front takes to cross the window.
    pub wait: f64,
}

impl FrontOptions {
    /// Defaults for the given physics: the default law with damping gamma (the other
    /// parameters at their defaults; an invalid gamma is reported by [`measure_front`]).
    pub fn new(u_plus: f64, gamma: f64, dx: f64, blocks: usize) -> Self {
        let law = crate::friction::LAWS[0];
        let mut values: Vec<f64> = law
            .params
            .iter()
            .map(|p| p.default.unwrap_or(0.0))
            .collect();
        if let Some(k) = law.params.iter().position(|p| p.name == "gamma") {
            values[k] = gamma;
        }
        Self::with_friction(
            u_plus,
            FrictionSpec {
                law: &crate::friction::LAWS[0],
                values,
            },
            dx,
            blocks,
        )
    }

    /// Defaults for the given law.
    pub fn with_friction(u_plus: f64, friction: FrictionSpec, dx: f64, blocks: usize) -> Self {
        FrontOptions {
            u_plus,
            friction,
            dx,
            blocks,
            step: super::DEFAULT_STEP,
            window: (0.5, 0.75),
            heal: true,
            wait: 4.0,
        }
    }
}

/// What a front measurement found.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontResult {
    /// Front speed from the window.
    pub c: f64,
    /// Largest relative deviation of a single slip interval in the window from dx/c
    /// (0 for a perfectly steady front).
    pub unsteadiness: f64,
    /// True when the window blocks re-stuck behind a steady healing front (every block
    /// slid for the same time to 1e-3): a self-healing pulse. False: creep.
    pub pulse: bool,
    /// Mean u of the window blocks when they first re-stick (NaN in creep).
    pub u_minus: f64,
    /// Pulse width c * (mean sliding time of a window block) (NaN in creep).
    pub w: f64,
    /// First slip time of every block.
    pub slip_times: Vec<f64>,
    /// End of the first slip of every block (the healing front; NaN if still sliding).
    pub stick_times: Vec<f64>,
    /// u of every block at the end of its first slip (NaN if still sliding).
    pub stick_u: Vec<f64>,
    /// Window [a, b) of block indices.
    pub window: (usize, usize),
    /// Simulated time.
    pub t_end: f64,
    /// Sliding-block updates done.
    pub block_steps: u64,
    /// Number of slip intervals recorded (a block can slip more than once).
    pub slips: usize,
    /// How many of them were backward slips.
    pub backward_slips: usize,
}

/// Run the front experiment (with the law of `o.friction`).
pub fn measure_front(o: &FrontOptions) -> Result<FrontResult> {
    (o.friction.law.front)(&o.friction.values, o)
}

/// The front experiment with law `F` built from `values` (its table order).
pub(crate) fn measure_front_with<F: Friction>(
    values: &[f64],
    o: &FrontOptions,
) -> Result<FrontResult> {
    for (p, &x) in F::PARAMS.iter().zip(values) {
        p.check(p.name, x)?;
    }
    let fr = F::from_values(values)?;
    check_open("u_plus", o.u_plus, 0.0, 1.0, "0 < u_plus < 1")?;
    let n = o.blocks;
    let a = (o.window.0 * n as f64) as usize;
    let b = (o.window.1 * n as f64) as usize;
    if n < 16 || a < 4 || b <= a + 1 || b >= n {
        return Err(Error::InvalidParameter {
            name: "blocks",
            value: n as f64,
            allowed: "blocks >= 16 (with a window inside the chain)",
        });
    }
    let cfg = ChainConfig {
        dx: o.dx,
        v: 0.0,
        step: o.step,
    };
    let mut ch = Chain::new(cfg, fr, &Free, &vec![o.u_plus; n], None)?;
    ch.add_trigger(Trigger {
        t: 0.0,
        block: 0,
        kind: TriggerKind::Kick { du_t: -KICK },
    })?;
    let mut first = vec![f64::NAN; n];
    let mut seen = 0usize;
    let chunk = 20_000u64;
    let scan = |ch: &Chain<F>, first: &mut [f64], seen: &mut usize| {
        for r in &ch.catalog.slips[*seen..] {
            if first[r.block].is_nan() {
                first[r.block] = r.t_start;
            }
        }
        *seen = ch.catalog.slips.len();
    };
    // the front must reach the far end (or the chain stop: failure to propagate)
    let t_guess = 10.0 * n as f64 * o.dx + 100.0;
    while first[n - 1].is_nan() {
        let stop = ch.run(t_guess, usize::MAX, chunk)?;
        scan(&ch, &mut first, &mut seen);
        if stop != super::Stop::Steps && first[n - 1].is_nan() {
            return Err(Error::NoConvergence {
                what: "front",
                detail: format!(
                    "the front did not cross the chain (u_plus = {}, reached block {})",
                    o.u_plus,
                    first.iter().filter(|x| x.is_finite()).count()
                ),
            });
        }
    }
    let (ta, tb) = (first[a], first[b]);
    let c = o.dx * (b - a) as f64 / (tb - ta);
    let tau = o.dx / c;
    let unsteadiness = (a..b)
        .map(|i| ((first[i + 1] - first[i]) / tau - 1.0).abs())
        .fold(0.0, f64::max);
    // wait for the window blocks to re-stick (the end of their first slip: the healing
    // front; with little damping a block may slip again later, see `slips`)
    let t_stop = ch.time() + o.wait * (tb - ta).max(1.0);
    let healed = |ch: &Chain<F>| {
        let mut first_stick = vec![f64::NAN; n];
        let mut first_u = vec![f64::NAN; n];
        let mut done = vec![false; n];
        for r in &ch.catalog.slips {
            if !done[r.block] {
                done[r.block] = true;
                first_stick[r.block] = r.t_end;
                first_u[r.block] = r.u_end;
            }
        }
        (first_stick, first_u)
    };
    if o.heal {
        loop {
            let stop = ch.run(t_stop, usize::MAX, chunk)?;
            let (st, _) = healed(&ch);
            if st[a..=b].iter().all(|x| x.is_finite()) || stop != super::Stop::Steps {
                break;
            }
        }
    }
    let (stick, stick_u) = healed(&ch);
    let dur: Vec<f64> = (a..b).map(|i| stick[i] - first[i]).collect();
    let mean_dur = dur.iter().sum::<f64>() / dur.len() as f64;
    let steady = o.heal
        && dur.iter().all(|d| d.is_finite())
        && dur.iter().all(|d| (d - mean_dur).abs() <= 1e-3 * mean_dur);
    let (mut u_minus, mut w) = (f64::NAN, f64::NAN);
    if steady {
        u_minus = stick_u[a..b].iter().sum::<f64>() / (b - a) as f64;
        w = c * mean_dur;
    }
    let pulse = steady;
    Ok(FrontResult {
        c,
        unsteadiness,
        pulse,
        u_minus,
        w,
        slip_times: first,
        stick_times: stick,
        stick_u,
        window: (a, b),
        t_end: ch.time(),
        block_steps: ch.counters.block_steps,
        slips: ch.catalog.slips.len(),
        backward_slips: ch.catalog.slips.iter().filter(|r| r.dir < 0).count(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tip::{solve_for_u_plus, TipOptions};

    fn tip_c(u: f64, gamma: f64, dx: f64) -> f64 {
        let o = TipOptions {
            dx,
            gamma,
            ..Default::default()
        };
        solve_for_u_plus(u, &o).unwrap().c
    }

    #[test]
    fn front_speed_equals_the_finite_dx_tip_solution() {
        // the tip problem at finite dx is the exact steady front of the chain
        for &(u, gamma, dx, n) in &[(0.5, 0.3, 0.1, 400), (0.9, 0.45, 0.1, 600)] {
            let exact = tip_c(u, gamma, dx);
            let mut errs = Vec::new();
            for &step in &[0.05, 0.025] {
                let mut o = FrontOptions::new(u, gamma, dx, n);
                o.step = step;
                let r = measure_front(&o).unwrap();
                assert!(r.pulse, "u {u} gamma {gamma}");
                let (a, b) = r.window;
                let mean = r.stick_u[a..b].iter().sum::<f64>() / (b - a) as f64;
                assert_eq!(mean, r.u_minus);
                errs.push((r.c / exact - 1.0).abs());
            }
            assert!(errs[0] < 1e-7, "u {u}: {errs:?}");
            assert!(errs[1] < errs[0] / 4.0, "u {u}: {errs:?}");
        }
    }

    #[test]
    fn the_default_front_has_no_backward_slip() {
        // the paper's model: with beta = 0 about half of the slips at gamma = 0 go
        // backward; the default (beta = inf) has none, and any beta large enough never
        // to be reached gives the same motion bit for bit (the forward law has no beta)
        let o = FrontOptions::new(0.5, 0.0, 0.1, 200);
        assert_eq!(o.friction.get("beta"), Some(f64::INFINITY));
        let r = measure_front(&o).unwrap();
        assert_eq!(r.backward_slips, 0);
        assert!(r.slips > 0);
        let with_beta = |beta: f64| {
            let mut x = o.clone();
            x.friction = FrictionSpec::new("coulomb", &[("gamma", 0.0), ("beta", beta)]).unwrap();
            x
        };
        let rb = measure_front(&with_beta(1e6)).unwrap();
        assert_eq!(rb.backward_slips, 0);
        assert_eq!(r.slip_times, rb.slip_times);
        assert_eq!(r.c, rb.c);
        assert!(measure_front(&with_beta(0.0)).unwrap().backward_slips > 0);
    }

    #[test]
    fn a_weak_stress_below_u_c_creeps() {
        let r = measure_front(&FrontOptions::new(0.3, 0.45, 0.05, 400)).unwrap();
        assert!(!r.pulse);
        assert!(r.u_minus.is_nan() && r.w.is_nan());
        assert!(measure_front(&FrontOptions::new(1.2, 0.3, 0.1, 400)).is_err());
        assert!(measure_front(&FrontOptions::new(0.5, 0.3, 0.1, 8)).is_err());
    }
}
