//! A bare compiled RK4 stencil loop: n blocks, all sliding, fixed neighbours, Coulomb +
//! viscous forward branch; the reference rate of block updates for docs/benchmarks.md.
//! cargo run --release --example bench_stencil -- N STEPS
use std::time::Instant;

fn main() {
    let a: Vec<usize> = std::env::args()
        .skip(1)
        .map(|x| x.parse().unwrap())
        .collect();
    let (n, steps) = (a[0], a[1]);
    let (dx, gamma, v) = (0.01f64, 0.3f64, 0.0f64);
    let k = 1.0 / (dx * dx);
    let h = 0.05 * dx;
    let mut u: Vec<f64> = (0..n + 2)
        .map(|i| 0.6 - 1e-3 * (i as f64 * 0.1).sin())
        .collect();
    let mut w = vec![0.0f64; n + 2];
    let (mut su, mut sw) = (u.clone(), w.clone());
    let (mut ku, mut kw) = (vec![0.0; n + 2], vec![0.0; n + 2]);
    let mut acc = vec![0.0; n + 2];
    let rhs = |su: &[f64], sw: &[f64], acc: &mut [f64]| {
        for p in 1..=n {
            acc[p] = (su[p - 1] + su[p + 1] - 2.0 * su[p]) * k - su[p] + 2.0 * gamma * (v - sw[p]);
        }
    };
    let t0 = Instant::now();
    for _ in 0..steps {
        su.copy_from_slice(&u);
        sw.copy_from_slice(&w);
        for (stage, (c, b)) in [(0.5, 1.0), (0.5, 2.0), (1.0, 2.0), (0.0, 1.0)]
            .iter()
            .enumerate()
        {
            rhs(&su, &sw, &mut acc);
            for p in 1..=n {
                if stage == 0 {
                    ku[p] = 0.0;
                    kw[p] = 0.0;
                }
                ku[p] += b * sw[p];
                kw[p] += b * acc[p];
                su[p] = u[p] + c * h * sw[p];
                sw[p] = w[p] + c * h * acc[p];
            }
        }
        for p in 1..=n {
            u[p] += h / 6.0 * ku[p];
            w[p] += h / 6.0 * kw[p];
        }
    }
    let el = t0.elapsed().as_secs_f64();
    let chk: f64 = u.iter().sum();
    println!(
        "{{\"n\": {n}, \"steps\": {steps}, \"seconds\": {el}, \"block_updates_per_s\": {}, \"checksum\": {chk}}}",
        (n * steps) as f64 / el
    );
}
