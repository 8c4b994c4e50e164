//! Convergence table of the tip solver against the closed form c = 1/sqrt(1 - u^2):
//! `cargo run --release -p bkwaves-core --example tip_convergence`.
use bkwaves_core::speed::u_plus_of_speed;
use bkwaves_core::tip::{solve_for_speed, TipOptions};
fn main() {
    for &c in &[1.0001f64, 1.001, 1.01, 1.2, 3.0] {
        let ex = u_plus_of_speed(c).unwrap();
        for &(deg, decay) in &[
            (8usize, 40.0),
            (12, 40.0),
            (16, 20.0),
            (16, 40.0),
            (16, 80.0),
            (24, 40.0),
            (32, 40.0),
        ] {
            let o = TipOptions {
                degree: deg,
                decay,
                ..Default::default()
            };
            let s = solve_for_speed(c, &o).unwrap();
            println!(
                "c={c} deg={deg} decay={decay} J={} u={:.16} relerr={:.2e}",
                s.intervals,
                s.u_plus,
                (s.u_plus - ex) / ex
            );
        }
    }
}
