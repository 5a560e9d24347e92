//! Spatial quality of CCVT point sets (Balzer, Schlömer & Deussen 2009) per
//! quality setting, as a Markdown table.
//!
//! For each setting and `N` it prints the normalised minimum distance
//! `δ_min = min_i min_{j≠i} |x_i − x_j| / d_hex` and the normalised mean
//! nearest-neighbour distance `δ_avg = (1/N)·Σ_i min_{j≠i} |x_i − x_j| / d_hex`
//! (toroidal distances; `d_hex = √(2/(√3·N))` is the spacing of the hexagonal
//! packing of `N` points in the unit square, Schlömer, Heck & Deussen 2011,
//! §2), as mean ± standard error over seeds, with the time per set.
//!
//! Run: `cargo run --release --example ccvt_quality` (about a minute on two
//! cores). `-- --sweep` adds the table of what limits `δ` (capacity, jitter of
//! the discrete points, warm start, iteration cap) at `N = 1024`.

use linesample::pattern::Ccvt;
use linesample::Seed;
use std::time::Instant;

/// `(δ_min, δ_avg)` of a 2D point set on the unit torus (brute force, `O(N²)`).
fn deltas(p: &[[f64; 2]]) -> (f64, f64) {
    let n = p.len();
    let mut dmin2 = f64::INFINITY;
    let mut sum = 0.0;
    for (i, a) in p.iter().enumerate() {
        let mut best = f64::INFINITY;
        for (j, b) in p.iter().enumerate() {
            if i == j {
                continue;
            }
            let mut d2 = 0.0;
            for k in 0..2 {
                let d = (a[k] - b[k]).abs();
                let d = d.min(1.0 - d);
                d2 += d * d;
            }
            best = best.min(d2);
        }
        dmin2 = dmin2.min(best);
        sum += best.sqrt();
    }
    let dhex = (2.0 / (3f64.sqrt() * n as f64)).sqrt();
    (dmin2.sqrt() / dhex, sum / n as f64 / dhex)
}

/// Mean and standard error of the mean.
fn mean_se(x: &[f64]) -> (f64, f64) {
    let k = x.len() as f64;
    let m = x.iter().sum::<f64>() / k;
    if x.len() < 2 {
        return (m, f64::NAN);
    }
    let v = x.iter().map(|a| (a - m).powi(2)).sum::<f64>() / (k - 1.0);
    (m, (v / k).sqrt())
}

/// `(δ_min, δ_avg, seconds)` for seeds `0..seeds`, two seeds at a time.
fn measure(p: &Ccvt<2>, seeds: u64) -> Vec<(f64, f64, f64)> {
    let threads = std::thread::available_parallelism()
        .map_or(1, |t| t.get())
        .min(2) as u64;
    let mut out = vec![(0.0, 0.0, 0.0); seeds as usize];
    std::thread::scope(|s| {
        for (t, chunk) in out.chunks_mut(seeds.div_ceil(threads) as usize).enumerate() {
            s.spawn(move || {
                for (k, o) in chunk.iter_mut().enumerate() {
                    let seed = t as u64 * seeds.div_ceil(threads) + k as u64;
                    let t0 = Instant::now();
                    let r = p.generate(Seed::new(seed));
                    let dt = t0.elapsed().as_secs_f64();
                    let (a, b) = deltas(r.sites_f64());
                    *o = (a, b, dt);
                }
            });
        }
    });
    out
}

fn row(label: &str, n: usize, p: &Ccvt<2>, seeds: u64, published: &str) {
    let m = measure(p, seeds);
    let a: Vec<f64> = m.iter().map(|x| x.0).collect();
    let b: Vec<f64> = m.iter().map(|x| x.1).collect();
    let t: Vec<f64> = m.iter().map(|x| x.2).collect();
    let (am, ae) = mean_se(&a);
    let (bm, be) = mean_se(&b);
    let (tm, _) = mean_se(&t);
    println!(
        "| {label} | {n} | {seeds} | {am:.3} ± {ae:.3} | {bm:.3} ± {be:.3} | {tm:.2} | {published} |"
    );
}

fn main() {
    let sweep = std::env::args().any(|a| a == "--sweep");
    println!("## CCVT spatial quality (2D torus; δ in units of d_hex = √(2/(√3·N)))\n");
    println!("Time per set: wall-clock seconds of one `generate`, two sets in parallel on");
    println!("two cores (so contended). Published: see the column notes below.\n");
    println!("| setting | N | seeds | δ_min | δ_avg | s / set | published |");
    println!("|---|---|---|---|---|---|---|");
    let fpo = "FPO (not CCVT): 0.925 / 0.932 [a]";
    for (label, n, seeds) in [
        ("fast (default, c = 64)", 1024usize, 8u64),
        ("fast (default, c = 64)", 4096, 4),
        ("standard (c = 256, warm)", 1024, 8),
        ("standard (c = 256, warm)", 4096, 2),
        ("high (c = 1024, warm)", 1024, 4),
    ] {
        let base = Ccvt::<2>::new(n).unwrap();
        let p = match label.split(' ').next().unwrap() {
            "fast" => base.fast_quality(),
            "standard" => base.standard_quality(),
            _ => base.high_quality(),
        }
        .unwrap();
        let published = if n == 1024 { fpo } else { "–" };
        row(label, n, &p, seeds, published);
    }
    println!();
    println!("[a] Schlömer, Heck & Deussen, *Farthest-Point Optimized Point Sets with");
    println!("Maximized Minimum Distance*, HPG 2011, Figure 1: FPO of a random set of 1024");
    println!("points after 63 iterations, δ_X = 0.925, δ̄_X = 0.932 (a maximised-distance");
    println!("method, the upper reference). The CCVT values of that paper's comparison and");
    println!("of Schlömer's thesis (Konstanz 2012, Table 4.1) could not be retrieved here.");

    if sweep {
        println!("\n## What limits δ (N = 1024, 4 seeds each)\n");
        println!("| capacity c | jitter δ | warm start | max iterations | N | seeds | δ_min | δ_avg | s / set | published |");
        println!("|---|---|---|---|---|---|---|---|---|---|");
        for (c, jit, warm, it) in [
            (64usize, 0.1, false, 1000usize),
            (64, 1.0, false, 1000),
            (64, 0.0, false, 1000),
            (256, 0.1, false, 1000),
            (256, 1.0, false, 1000),
            (256, 0.1, true, 1000),
            (1024, 0.1, false, 30),
            (1024, 0.1, false, 60),
            (1024, 0.1, false, 1000),
            (1024, 0.1, true, 1000),
        ] {
            let p = Ccvt::<2>::new(1024)
                .unwrap()
                .capacity(c)
                .unwrap()
                .jitter(jit)
                .unwrap()
                .max_iterations(it)
                .unwrap()
                .warm_start(warm);
            let label = format!("{c} | {jit} | {warm} | {it}");
            row(&label, 1024, &p, 4, "–");
        }
    }
}
