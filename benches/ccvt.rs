//! Time of one CCVT realisation (Balzer, Schlömer & Deussen 2009) in 2D, default
//! capacity `c = 64`, for N = 1024, 2048, 4096 (one core), and of the
//! standard (`c = 256`, warm start) and high (`c = 1024`, warm start)
//! quality settings at N = 1024 (group `ccvt_quality`).
//!
//! Run: `cargo bench --bench ccvt` (`-- ccvt_quality` for the settings only).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::pattern::Ccvt;
use linesample::Seed;
use std::hint::black_box;
use std::time::Duration;

fn ccvt_2d(c: &mut Criterion) {
    let mut g = c.benchmark_group("ccvt_2d");
    for n in [1024usize, 2048, 4096] {
        g.throughput(Throughput::Elements(n as u64));
        let p = Ccvt::<2>::new(n).unwrap();
        g.bench_function(BenchmarkId::new("generate", n), |b| {
            b.iter(|| p.generate(black_box(Seed::new(7))))
        });
    }
    g.finish();
}

fn ccvt_quality(c: &mut Criterion) {
    let mut g = c.benchmark_group("ccvt_quality");
    g.sample_size(10);
    let n = 1024usize;
    g.throughput(Throughput::Elements(n as u64));
    let base = Ccvt::<2>::new(n).unwrap();
    for (name, p) in [
        ("fast", base.clone().fast_quality().unwrap()),
        ("standard", base.clone().standard_quality().unwrap()),
        ("high", base.high_quality().unwrap()),
    ] {
        g.bench_function(BenchmarkId::new(name, n), |b| {
            b.iter(|| p.generate(black_box(Seed::new(7))))
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4))
        .sample_size(10);
    targets = ccvt_2d, ccvt_quality
}
criterion_main!(benches);
