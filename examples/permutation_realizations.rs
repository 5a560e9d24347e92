//! Single-realisation statistics of the permutation-based patterns against
//! the same constructions built on exact Fisher–Yates shuffles.
//!
//! `hash::permute` uses multiply-add-shift Feistel rounds: the pair law of
//! its values over keys is that of ideal random round functions (see the
//! `hash` module docs), so expected periodograms and variances are the ideal
//! ones by construction. What pairs do not control is the structure inside
//! one realisation. This example measures three statistics of the
//! periodogram `P(ν) = |Σ_k e^{−2πi ν·x_k}|² / N` of each realisation, over
//! the integer frequencies `ν ∈ [−24, 24]²` off both axes (N-rooks and its
//! relatives are exact on the axes): its maximum, its mean, and its mean at
//! `‖ν‖∞ ≤ 6`. Each is given as mean ± standard error over realisations, for
//! the crate's N-rooks, multi-jittered and correlated multi-jittered points
//! and for the same constructions with Fisher–Yates permutations driven by
//! PCG32, with the z-score of the difference. Lattice-like structure or
//! repeated rows would show as a larger maximum or a shifted mean.
//!
//! Run: `cargo run --release --example permutation_realizations` (about
//! 40 s on one core).

use linesample::pattern::{CorrelatedMultiJittered, MultiJittered, NRooks, Pattern};
use linesample::rng::Pcg32;
use linesample::Seed;

/// Largest frequency per axis.
const K: i64 = 24;

/// 64 bits from two PCG32 outputs.
fn next_u64(r: &mut Pcg32) -> u64 {
    (u64::from(r.next_u32()) << 32) | u64::from(r.next_u32())
}

/// Uniform in `[0, 1)` (53 bits).
fn uniform(r: &mut Pcg32) -> f64 {
    (next_u64(r) >> 11) as f64 / (1u64 << 53) as f64
}

/// A uniformly random permutation of `[0, n)` (Fisher–Yates; Lemire's
/// multiply-shift index, bias below `n/2⁶⁴`).
fn shuffle(r: &mut Pcg32, n: usize) -> Vec<usize> {
    let mut a: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        let j = ((u128::from(next_u64(r)) * (i as u128 + 1)) >> 64) as usize;
        a.swap(i, j);
    }
    a
}

/// N-rooks: `x = (π_x(k) + u)/n`, `y = (π_y(k) + v)/n`.
fn ideal_nrooks(r: &mut Pcg32, n: usize) -> Vec<[f64; 2]> {
    let (px, py) = (shuffle(r, n), shuffle(r, n));
    (0..n)
        .map(|k| {
            let x = (px[k] as f64 + uniform(r)) / n as f64;
            [x, (py[k] as f64 + uniform(r)) / n as f64]
        })
        .collect()
}

/// (Correlated) multi-jitter on an `m × m` grid: point `(i, j)` at
/// `x = (i·m + π_i(j) + u)/N`, `y = (j·m + σ_j(i) + v)/N`, with one `π` and
/// one `σ` for all columns and rows when `correlated`.
fn ideal_mj(r: &mut Pcg32, m: usize, correlated: bool) -> Vec<[f64; 2]> {
    let count = if correlated { 1 } else { m };
    let px: Vec<Vec<usize>> = (0..count).map(|_| shuffle(r, m)).collect();
    let py: Vec<Vec<usize>> = (0..count).map(|_| shuffle(r, m)).collect();
    let n = m * m;
    (0..n)
        .map(|k| {
            let (i, j) = (k % m, k / m);
            let (ci, cj) = if correlated { (0, 0) } else { (i, j) };
            let x = ((i * m + px[ci][j]) as f64 + uniform(r)) / n as f64;
            [x, ((j * m + py[cj][i]) as f64 + uniform(r)) / n as f64]
        })
        .collect()
}

/// `(max P, mean P, mean P at |ν|∞ ≤ 6)` over the off-axis frequencies.
fn stats(pts: &[[f64; 2]]) -> [f64; 3] {
    let w = (2 * K + 1) as usize;
    let mut s = vec![(0.0f64, 0.0f64); w * w];
    let mut ex = vec![(0.0, 0.0); w];
    let mut ey = vec![(0.0, 0.0); w];
    for p in pts {
        for (e, c) in [(&mut ex, p[0]), (&mut ey, p[1])] {
            for k in -K..=K {
                let a = -2.0 * std::f64::consts::PI * k as f64 * c;
                e[(k + K) as usize] = (a.cos(), a.sin());
            }
        }
        for (a, &(xr, xi)) in ex.iter().enumerate() {
            for (b, &(yr, yi)) in ey.iter().enumerate() {
                let t = &mut s[a * w + b];
                t.0 += xr * yr - xi * yi;
                t.1 += xr * yi + xi * yr;
            }
        }
    }
    let n = pts.len() as f64;
    let (mut max, mut sum, mut count, mut low, mut low_count) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
    for a in 0..w {
        for b in 0..w {
            let (kx, ky) = (a as i64 - K, b as i64 - K);
            if kx == 0 || ky == 0 {
                continue;
            }
            let p = (s[a * w + b].0.powi(2) + s[a * w + b].1.powi(2)) / n;
            max = max.max(p);
            sum += p;
            count += 1.0;
            if kx.abs() <= 6 && ky.abs() <= 6 {
                low += p;
                low_count += 1.0;
            }
        }
    }
    [max, sum / count, low / low_count]
}

/// Mean and standard error of each statistic.
fn summary(v: &[[f64; 3]]) -> [(f64, f64); 3] {
    let r = v.len() as f64;
    core::array::from_fn(|i| {
        let m = v.iter().map(|x| x[i]).sum::<f64>() / r;
        let var = v.iter().map(|x| (x[i] - m).powi(2)).sum::<f64>() / (r - 1.0);
        (m, (var / r).sqrt())
    })
}

fn crate_points(p: &dyn Pattern<2>, seed: u64) -> Vec<[f64; 2]> {
    let pts = p.to_vec(Seed::new(seed)).expect("pattern fill");
    pts.iter()
        .map(|q| [f64::from(q[0]), f64::from(q[1])])
        .collect()
}

fn main() {
    let mut rng = Pcg32::new(0x5EED, 7);
    println!("| pattern | N | realisations | statistic | crate | Fisher–Yates | z |");
    println!("|---|---|---|---|---|---|---|");
    let cases: [(&str, usize, usize); 7] = [
        ("n-rooks", 1024, 200),
        ("n-rooks", 4096, 200),
        ("n-rooks", 65536, 40),
        ("mj", 1024, 200),
        ("mj", 4096, 200),
        ("cmj", 1024, 200),
        ("cmj", 4096, 200),
    ];
    for (name, n, reps) in cases {
        let m = (n as f64).sqrt() as usize;
        let pattern: Box<dyn Pattern<2>> = match name {
            "n-rooks" => Box::new(NRooks::<2>::new(n).expect("n")),
            "mj" => Box::new(MultiJittered::new(n).expect("n")),
            _ => Box::new(CorrelatedMultiJittered::new(n).expect("n")),
        };
        let ours: Vec<[f64; 3]> = (0..reps as u64)
            .map(|s| stats(&crate_points(pattern.as_ref(), s)))
            .collect();
        let ideal: Vec<[f64; 3]> = (0..reps)
            .map(|_| {
                stats(&match name {
                    "n-rooks" => ideal_nrooks(&mut rng, n),
                    "mj" => ideal_mj(&mut rng, m, false),
                    _ => ideal_mj(&mut rng, m, true),
                })
            })
            .collect();
        let (a, b) = (summary(&ours), summary(&ideal));
        for (i, label) in ["max P", "mean P", "mean P, ‖ν‖∞ ≤ 6"].iter().enumerate() {
            let z = (a[i].0 - b[i].0) / (a[i].1.powi(2) + b[i].1.powi(2)).sqrt();
            let f = |(m, se): (f64, f64)| {
                if m < 0.01 {
                    format!("{m:.3e} ± {se:.1e}")
                } else {
                    format!("{m:.4} ± {se:.4}")
                }
            };
            println!(
                "| {name} | {n} | {reps} | {label} | {} | {} | {z:+.2} |",
                f(a[i]),
                f(b[i])
            );
        }
    }
}
