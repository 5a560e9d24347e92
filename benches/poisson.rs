//! Poisson-disk sampling, points per second: ours (Bridson on the torus, scratch
//! and output buffers reused) next to `fast_poisson` 1.0 (Bridson, non-periodic,
//! k-d tree, allocating) at the same radius, 2D and 3D, N ≈ 4096 and 65536
//! (radii chosen beforehand, by trial runs, so that `fast_poisson` gives about
//! N points for seed 7);
//! plus maximal dart throwing (active-box dart throwing, Ebeida et al. 2011;
//! maximal, exact minimum distance) at every size, in the same groups.
//!
//! The throughput of each benchmark uses the number of points that generator
//! produces for seed 7 (printed before the group runs): our sets are periodic and
//! denser per unit area than `fast_poisson`'s non-periodic ones, so the counts
//! differ slightly.
//!
//! Run: `cargo bench --bench poisson`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::pattern::{PoissonDisk, PoissonMethod};
use linesample::Seed;
use std::hint::black_box;
use std::time::Duration;

/// (label, radius) for ≈ 4096 and ≈ 65536 points.
const RADII_2D: [(&str, f64); 2] = [("4096", 0.01241), ("65536", 0.003095)];
const RADII_3D: [(&str, f64); 2] = [("4096", 0.05361), ("65536", 0.02097)];

fn ours<const D: usize>(
    name: &str,
    r: f64,
    method: PoissonMethod,
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
) {
    let p = PoissonDisk::<D>::with_radius(r)
        .unwrap()
        .with_method(method);
    let mut scratch = vec![0u32; p.scratch_len()];
    let mut out = vec![[0.0f32; D]; p.max_points()];
    let n = p.generate(Seed::new(7), &mut scratch, &mut out).unwrap();
    eprintln!("{D}D r={r} {name}: {n} points");
    group.throughput(Throughput::Elements(n as u64));
    group.bench_function(BenchmarkId::new(name, r), |b| {
        b.iter(|| {
            p.generate(black_box(Seed::new(7)), &mut scratch, &mut out)
                .unwrap()
        })
    });
}

fn theirs<const D: usize>(
    r: f64,
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
) where
    fast_poisson::Poisson<D>: Default,
{
    let gen = || {
        fast_poisson::Poisson::<D>::new()
            .with_dimensions([1.0; D], r)
            .with_seed(7)
            .generate()
    };
    let n = gen().len();
    eprintln!("{D}D r={r} fast_poisson: {n} points");
    group.throughput(Throughput::Elements(n as u64));
    group.bench_function(BenchmarkId::new("fast_poisson", r), |b| {
        b.iter(|| black_box(gen()))
    });
}

fn poisson_2d(c: &mut Criterion) {
    for (label, r) in RADII_2D {
        let mut g = c.benchmark_group(format!("poisson_2d_{label}"));
        ours::<2>("ours_bridson", r, PoissonMethod::Bridson, &mut g);
        theirs::<2>(r, &mut g);
        ours::<2>(
            "ours_maximal_dart",
            r,
            PoissonMethod::MaximalDartThrowing,
            &mut g,
        );
        g.finish();
    }
}

fn poisson_3d(c: &mut Criterion) {
    for (label, r) in RADII_3D {
        let mut g = c.benchmark_group(format!("poisson_3d_{label}"));
        ours::<3>("ours_bridson", r, PoissonMethod::Bridson, &mut g);
        theirs::<3>(r, &mut g);
        ours::<3>(
            "ours_maximal_dart",
            r,
            PoissonMethod::MaximalDartThrowing,
            &mut g,
        );
        g.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1500))
        .sample_size(10);
    targets = poisson_2d, poisson_3d
}
criterion_main!(benches);
