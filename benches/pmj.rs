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
//! Run: `cargo bench --bench pmj`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::pattern::{Pattern, Pmj02};
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

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1200))
        .sample_size(20);
    targets = pmj
}
criterion_main!(benches);
