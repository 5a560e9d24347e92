//! Time of one CCVT realisation (Balzer, Schlömer & Deussen 2009) in 2D, default
//! capacity `c = 64`, for N = 1024, 2048, 4096 (one core).
//!
//! Run: `cargo bench --bench ccvt`.

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

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4))
        .sample_size(10);
    targets = ccvt_2d
}
criterion_main!(benches);
