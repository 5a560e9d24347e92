//! Progressive multi-jittered (0,2) sequences, time per set: PMJ02 and PMJ02BN
//! (10 candidates), 2D, N = 4096 and 65536, generated allocation-free into
//! reused buffers ([`Pmj02::generate`]) and through the allocating `Pattern::fill`,
//! next to `sobol_burley` (Owen-scrambled Sobol, Burley 2020; one
//! `sample(i, dim, seed)` per coordinate) for the same number of points,
//! measured in the same run.
//!
//! Reference: UTK's PMJ02 command-line sampler took 436 ms for N = 4096 on the
//! development machine (target: at least 100× faster, ≤ 4.4 ms).
//!
//! `pmj_tables`: [`Pmj02Tables::generate`], 16 sets of 1024 points, PMJ02
//! and PMJ02BN (throughput in table points). `pmj_pixel`: random access per
//! coordinate, `tables.pixel(x, y).sample(i, d, seed)` over 64 × 64 pixels,
//! 16 samples each, dimensions 0–1 (pair 0, table order) and 2–7 (pairs 1–3,
//! batch-permuted), with `ZSobol::sample` on the same loop as a reference
//! (throughput in coordinates).
//!
//! Run: `cargo bench --bench pmj`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::pattern::{Pattern, Pmj02, Pmj02Tables, ZSobol};
use linesample::sequence::Sequence;
use linesample::Seed;
use std::hint::black_box;
use std::time::Duration;

const SIZES: [usize; 2] = [4096, 65536];

fn pmj(c: &mut Criterion) {
    for n in SIZES {
        let mut g = c.benchmark_group(format!("pmj_2d_{n}"));
        g.throughput(Throughput::Elements(n as u64));
        let mut out = vec![[0.0f32; 2]; n];
        for (name, p) in [
            ("pmj02", Pmj02::new(n).unwrap()),
            ("pmj02bn", Pmj02::blue_noise(n).unwrap()),
        ] {
            let mut scratch = vec![0u32; p.scratch_len()];
            g.bench_function(BenchmarkId::new(name, "generate"), |b| {
                b.iter(|| {
                    p.generate(black_box(Seed::new(7)), &mut out, &mut scratch)
                        .unwrap()
                })
            });
            g.bench_function(BenchmarkId::new(name, "fill"), |b| {
                b.iter(|| p.fill(black_box(Seed::new(7)), &mut out).unwrap())
            });
        }
        g.bench_function("baseline/sobol_burley", |b| {
            b.iter(|| {
                let s = black_box(7u32);
                for (i, p) in out.iter_mut().enumerate() {
                    *p = core::array::from_fn(|d| sobol_burley::sample(i as u32, d as u32, s));
                }
            })
        });
        g.finish();
    }
}

/// Sets and points of the table benchmarks.
const SETS: u32 = 16;
const POINTS: usize = 1024;
/// Pixels per side and samples per pixel of the access benchmarks.
const SIDE: u32 = 64;
const SPP: u64 = 16;

fn tables(c: &mut Criterion) {
    let mut g = c.benchmark_group("pmj_tables");
    g.throughput(Throughput::Elements(u64::from(SETS) * POINTS as u64));
    for (name, p) in [
        ("pmj02", Pmj02::new(POINTS).unwrap()),
        ("pmj02bn", Pmj02::blue_noise(POINTS).unwrap()),
    ] {
        let mut table = vec![[0u32; 2]; Pmj02Tables::table_len(p, SETS).unwrap()];
        let mut scratch = vec![0u32; Pmj02Tables::scratch_len(p)];
        g.bench_function(BenchmarkId::new(name, format!("{SETS}x{POINTS}")), |b| {
            b.iter(|| {
                Pmj02Tables::generate(p, SETS, black_box(Seed::new(7)), &mut table, &mut scratch)
                    .map(|t| t.points())
                    .unwrap()
            })
        });
    }
    g.finish();
}

fn pixel_access(c: &mut Criterion) {
    let mut g = c.benchmark_group("pmj_pixel");
    let seed = Seed::new(3);
    for (name, p) in [
        ("pmj02", Pmj02::new(POINTS).unwrap()),
        ("pmj02bn", Pmj02::blue_noise(POINTS).unwrap()),
    ] {
        let t = Pmj02Tables::new(p, SETS, Seed::new(7)).unwrap();
        for (dims, label) in [(0..2u32, "pair0"), (2..8, "pairs1-3")] {
            let per = u64::from(SIDE * SIDE) * SPP * u64::from(dims.end - dims.start);
            g.throughput(Throughput::Elements(per));
            g.bench_function(BenchmarkId::new(name, label), |b| {
                b.iter(|| {
                    let mut acc = 0.0f32;
                    for y in 0..SIDE {
                        for x in 0..SIDE {
                            let px = t.pixel(x, y);
                            for i in 0..SPP {
                                for d in dims.clone() {
                                    acc += px.sample(i, d, black_box(seed)).unwrap();
                                }
                            }
                        }
                    }
                    acc
                })
            });
        }
    }
    let z = ZSobol::new(SIDE, SIDE, SPP as u32).unwrap();
    g.throughput(Throughput::Elements(u64::from(SIDE * SIDE) * SPP * 6));
    g.bench_function("baseline/zsobol/dims2-7", |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for y in 0..SIDE {
                for x in 0..SIDE {
                    for i in 0..SPP as u32 {
                        for d in 2..8 {
                            acc += z.sample(x, y, i, d, black_box(seed)).unwrap();
                        }
                    }
                }
            }
            acc
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1200))
        .sample_size(20);
    targets = pmj, tables, pixel_access
}
criterion_main!(benches);
