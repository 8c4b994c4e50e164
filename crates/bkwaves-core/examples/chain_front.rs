//! Explore: front speed of the chain vs the finite-dx tip solver.
//! cargo run --release --example chain_front -- U GAMMA DX BLOCKS [STEP]
use bkwaves_core::chain::front::{measure_front, FrontOptions};
use bkwaves_core::tip::{solve_for_u_plus, TipOptions};
fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    let mut o = FrontOptions::new(a[0], a[1], a[2], a[3] as usize);
    if a.len() > 4 {
        o.step = a[4];
    }
    let t = std::time::Instant::now();
    let r = measure_front(&o).unwrap();
    let el = t.elapsed().as_secs_f64();
    let tip = solve_for_u_plus(
        o.u_plus,
        &TipOptions {
            dx: o.dx,
            gamma: o.friction.get("gamma").unwrap_or(0.0),
            ..Default::default()
        },
    )
    .map(|s| s.c)
    .unwrap_or(f64::NAN);
    println!(
        "c={:.12} tip={:.12} rel={:.3e} unsteady={:.2e} pulse={} u-={:.6} w={:.6} t={:.1} wall={:.2}s bs={} slips={} bwd={}",
        r.c, tip, r.c / tip - 1.0, r.unsteadiness, r.pulse, r.u_minus, r.w, r.t_end, el, r.block_steps, r.slips, r.backward_slips
    );
}
