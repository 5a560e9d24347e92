//! Direct periodogram throughput: points vs N and grid size, segments, and the
//! issue's reference case (N = 4096 points on the 639² grid, k = 319).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::geom::Direction;
use linesample::pattern::{Pattern, Random};
use linesample::spectrum::{Dft, Grid};
use linesample::Seed;
use std::hint::black_box;

const CHUNK: usize = 128;

fn points<const D: usize>(c: &mut Criterion, name: &str, cases: &[(usize, usize)]) {
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    for &(n, k) in cases {
        let pts = Random::<D>::new(n).unwrap().to_vec(Seed::new(1)).unwrap();
        let g = Grid::<D>::new(k).unwrap();
        let mut dft = Dft::new_vec(g);
        let mut scratch = vec![0.0; CHUNK * Dft::<D, Vec<f64>>::points_scratch_per_sample(g)];
        // Complex multiply-adds per call: N·|half grid|.
        group.throughput(Throughput::Elements((n * g.len()) as u64));
        group.bench_with_input(
            BenchmarkId::new(format!("n{n}"), format!("k{k}")),
            &(),
            |b, ()| {
                b.iter(|| {
                    dft.clear();
                    dft.add_points(black_box(&pts), &mut scratch).unwrap();
                });
            },
        );
    }
    group.finish();
}

fn direct(c: &mut Criterion) {
    points::<2>(
        c,
        "direct_2d",
        &[
            (4096, 319),
            (1024, 319),
            (4096, 64),
            (4096, 128),
            (16384, 64),
        ],
    );
    points::<3>(c, "direct_3d", &[(4096, 32), (1024, 16)]);
    points::<1>(c, "direct_1d", &[(4096, 4096)]);
}

fn scalar_twin(c: &mut Criterion) {
    let mut group = c.benchmark_group("direct_2d_scalar_twin");
    group.sample_size(10);
    let (n, k) = (1024, 64);
    let pts = Random::<2>::new(n).unwrap().to_vec(Seed::new(1)).unwrap();
    let g = Grid::<2>::new(k).unwrap();
    let mut dft = Dft::new_vec(g);
    let mut scratch = vec![0.0; CHUNK * Dft::<2, Vec<f64>>::points_scratch_per_sample(g)];
    group.throughput(Throughput::Elements((n * g.len()) as u64));
    group.bench_function("simd_n1024_k64", |b| {
        b.iter(|| {
            dft.clear();
            dft.add_points(black_box(&pts), &mut scratch).unwrap();
        });
    });
    group.bench_function("scalar_n1024_k64", |b| {
        b.iter(|| {
            dft.clear();
            dft.add_points_scalar(black_box(&pts), &mut scratch)
                .unwrap();
        });
    });
    group.finish();
}

fn segments(c: &mut Criterion) {
    let mut group = c.benchmark_group("segments_2d");
    group.sample_size(10);
    for &(n, k) in &[(1024usize, 64usize), (4096, 319)] {
        let pts = Random::<2>::new(n).unwrap().to_vec(Seed::new(1)).unwrap();
        let g = Grid::<2>::new(k).unwrap();
        let mut dft = Dft::new_vec(g);
        let mut scratch = vec![0.0; CHUNK * Dft::<2, Vec<f64>>::segments_scratch_per_sample(g)];
        let dir = Direction::new([1.0, 0.3]).unwrap();
        group.throughput(Throughput::Elements((n * g.len()) as u64));
        group.bench_with_input(
            BenchmarkId::new(format!("n{n}"), format!("k{k}")),
            &(),
            |b, ()| {
                b.iter(|| {
                    dft.clear();
                    dft.add_segment_pattern(black_box(&pts), &dir, 0.1, &mut scratch)
                        .unwrap();
                });
            },
        );
    }
    group.finish();
}

criterion_group!(benches, direct, scalar_twin, segments);
criterion_main!(benches);
