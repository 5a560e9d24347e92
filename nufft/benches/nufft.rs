//! Criterion benches of the type-1 NUFFT (`linesample_nufft`).
//!
//! - `nufft/targets`: the cases (2D N = 65536, K = 128 i.e. a 257²
//!   grid; 2D N = 4096, K = 319 i.e. 639²; 3D N = 4096, K = 32 i.e. 65³) at
//!   ε = 1e-6 and 1e-12, automatic σ given the point count, `transform` only
//!   (the plan is built outside the timed loop).
//! - `nufft/sweep_n`: 2D, K = 128, ε = 1e-6, N = 1024 … 262144.
//! - `nufft/sweep_k`: 2D, N = 16384, ε = 1e-6, K = 16 … 512.
//!
//! `cargo bench -p linesample-nufft --bench nufft`; the side-by-side comparison
//! with FINUFFT is `nufft/tools/nufft_vs_finufft.sh`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample_nufft::Plan;

/// The shared SplitMix64 points (seed 42; the Python FINUFFT script uses the
/// same stream).
fn points<const D: usize>(n: usize) -> Vec<[f64; D]> {
    linesample_nufft::testdata::points::<D>(42, n)
}

fn bench_case<const D: usize>(
    c: &mut Criterion,
    group: &str,
    id: String,
    n: usize,
    k: usize,
    tol: f64,
) {
    let pts = points::<D>(n);
    let mut plan = Plan::<D>::new_for_points(k, tol, n).expect("valid plan");
    let (mut re, mut im) = (vec![0.0; plan.half_len()], vec![0.0; plan.half_len()]);
    let mut g = c.benchmark_group(group);
    g.throughput(Throughput::Elements(n as u64));
    g.sample_size(20);
    g.bench_function(BenchmarkId::from_parameter(id), |b| {
        b.iter(|| {
            plan.transform(&pts, &mut re, &mut im)
                .expect("finite points")
        })
    });
    g.finish();
}

fn targets(c: &mut Criterion) {
    for tol in [1e-6, 1e-12] {
        bench_case::<2>(
            c,
            "nufft/targets",
            format!("2d_N65536_K128_tol{tol:e}"),
            65536,
            128,
            tol,
        );
        bench_case::<2>(
            c,
            "nufft/targets",
            format!("2d_N4096_K319_tol{tol:e}"),
            4096,
            319,
            tol,
        );
        bench_case::<3>(
            c,
            "nufft/targets",
            format!("3d_N4096_K32_tol{tol:e}"),
            4096,
            32,
            tol,
        );
    }
}

fn sweeps(c: &mut Criterion) {
    for n in [1024, 4096, 16384, 65536, 262144] {
        bench_case::<2>(c, "nufft/sweep_n", format!("2d_K128_N{n}"), n, 128, 1e-6);
    }
    for k in [16, 32, 64, 128, 256, 512] {
        bench_case::<2>(
            c,
            "nufft/sweep_k",
            format!("2d_N16384_K{k}"),
            16384,
            k,
            1e-6,
        );
    }
}

criterion_group!(benches, targets, sweeps);
criterion_main!(benches);
