//! Points per second for every sampler, 2D and 3D, N = 4096 and 65536, SIMD and
//! scalar paths, next to baselines measured in the same run:
//! * `sobol_burley` (Owen-scrambled Sobol, Burley 2020) generating the same
//!   number of points (one `sample(i, dim, seed)` per coordinate);
//! * a plain memory fill of the same number of bytes (the physical limit; the
//!   C library's `memset`, which picks its own vector width), and the same
//!   bytes written by a loop of `f32x8` stores in this build (what the
//!   generators' stores alone cost);
//! * two scalar generator crates filling the same `f32` buffer with uniform
//!   numbers, as `Random` does: `rand_xoshiro`'s Xoshiro128+ (`next_u32`, top 24
//!   bits scaled, our conversion) and `fastrand` (`Rng::f32`).
//!
//! Run: `cargo bench --bench patterns` (AVX2 build, from `.cargo/config.toml`) and
//! `RUSTFLAGS="-C target-cpu=x86-64" cargo bench --bench patterns --target-dir target/baseline`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::pattern::{
    CorrelatedMultiJittered, Halton, Jittered, MultiJittered, NRooks, Pattern, Random, Sobol,
};
use linesample::sequence::Sequence;
use linesample::Seed;
use rand_core::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro128Plus;
use std::hint::black_box;
use std::time::Duration;

const SIZES: [usize; 2] = [4096, 65536];

/// Named samplers of one dimension for one `N`.
type Samplers<const D: usize> = Vec<(&'static str, Box<dyn Pattern<D>>)>;

fn samplers2(n: usize) -> Samplers<2> {
    let m = (n as f64).sqrt() as usize;
    vec![
        ("random", Box::new(Random::<2>::new(n).unwrap())),
        ("jittered", Box::new(Jittered::<2>::new([m, m]).unwrap())),
        ("n-rooks", Box::new(NRooks::<2>::new(n).unwrap())),
        ("multi-jittered", Box::new(MultiJittered::new(n).unwrap())),
        ("cmj", Box::new(CorrelatedMultiJittered::new(n).unwrap())),
        ("sobol", Box::new(Sobol::<2>::new(n).unwrap())),
        ("halton", Box::new(Halton::<2>::new(n).unwrap())),
    ]
}

fn samplers3(n: usize) -> Samplers<3> {
    // 4096 = 16³; 65536 = 64·32·32.
    let strata = if n == 4096 {
        [16, 16, 16]
    } else {
        [64, 32, 32]
    };
    vec![
        ("random", Box::new(Random::<3>::new(n).unwrap())),
        ("jittered", Box::new(Jittered::<3>::new(strata).unwrap())),
        ("n-rooks", Box::new(NRooks::<3>::new(n).unwrap())),
        ("sobol", Box::new(Sobol::<3>::new(n).unwrap())),
        ("halton", Box::new(Halton::<3>::new(n).unwrap())),
    ]
}

fn group<const D: usize>(c: &mut Criterion, samplers: fn(usize) -> Samplers<D>) {
    for n in SIZES {
        let mut g = c.benchmark_group(format!("patterns_{D}d_{n}"));
        g.throughput(Throughput::Elements(n as u64));
        let mut out = vec![[0.0f32; D]; n];
        let seed = Seed::new(7);
        for (name, p) in samplers(n) {
            g.bench_function(BenchmarkId::new(name, "simd"), |b| {
                b.iter(|| p.fill(black_box(seed), &mut out).unwrap())
            });
            g.bench_function(BenchmarkId::new(name, "scalar"), |b| {
                b.iter(|| p.fill_range_scalar(black_box(seed), 0, &mut out).unwrap())
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
        {
            g.bench_function("baseline/sobol_burley_4d", |b| {
                b.iter(|| {
                    let s = black_box(7u32);
                    for (i, p) in out.iter_mut().enumerate() {
                        let v = sobol_burley::sample_4d(i as u32, 0, s);
                        *p = core::array::from_fn(|d| v[d]);
                    }
                })
            });
        }
        g.bench_function("baseline/xoshiro128plus", |b| {
            let mut rng = Xoshiro128Plus::seed_from_u64(7);
            b.iter(|| {
                for p in out.iter_mut() {
                    *p = core::array::from_fn(|_| {
                        (rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
                    });
                }
                black_box(&mut out);
            })
        });
        g.bench_function("baseline/fastrand", |b| {
            let mut rng = fastrand::Rng::with_seed(7);
            b.iter(|| {
                for p in out.iter_mut() {
                    *p = core::array::from_fn(|_| rng.f32());
                }
                black_box(&mut out);
            })
        });
        let mut bytes = vec![0u8; n * D * 4];
        g.bench_function("baseline/memory_fill", |b| {
            b.iter(|| {
                bytes.fill(black_box(0x3f));
                black_box(&mut bytes);
            })
        });
        // The generators' own store pattern with nothing to compute: eight
        // coordinates per store, as wide as this build's vectors.
        g.bench_function("baseline/store_f32x8", |b| {
            b.iter(|| {
                let v = [black_box(0.5f32); 8];
                let (chunks, tail) = out.as_flattened_mut().as_chunks_mut::<8>();
                for c in chunks {
                    *c = v;
                }
                tail.fill(v[0]);
                black_box(&mut out);
            })
        });
        g.finish();
    }
}

/// Random access to several dimensions of one sample, as a path tracer asks
/// for them: 4096 sample indices, 8 coordinates each (dimensions `dim0 …
/// dim0 + 7`), throughput in coordinates. `sobol_burley::sample_4d` (its
/// dimension sets are groups of four) is the peer, in the same run.
fn random_access(c: &mut Criterion) {
    const INDICES: u32 = 4096;
    let mut g = c.benchmark_group("random_access");
    g.throughput(Throughput::Elements(u64::from(INDICES) * 8));
    let mut out = vec![[0.0f32; 8]; INDICES as usize];
    let seq = Sobol::<2>::new(64).unwrap();
    for dim0 in [0u32, 1000] {
        g.bench_function(BenchmarkId::new("baseline/sobol_burley_4d", dim0), |b| {
            b.iter(|| {
                let s = black_box(7u32);
                for (i, p) in out.iter_mut().enumerate() {
                    let lo = sobol_burley::sample_4d(i as u32, dim0 / 4, s);
                    let hi = sobol_burley::sample_4d(i as u32, dim0 / 4 + 1, s);
                    *p = core::array::from_fn(|d| if d < 4 { lo[d] } else { hi[d - 4] });
                }
                black_box(&mut out);
            })
        });
        g.bench_function(BenchmarkId::new("sobol/sample", dim0), |b| {
            b.iter(|| {
                let s = black_box(Seed::new(7));
                for (i, p) in out.iter_mut().enumerate() {
                    *p = core::array::from_fn(|d| Sobol::sample(i as u32, dim0 + d as u32, s));
                }
                black_box(&mut out);
            })
        });
        g.bench_function(BenchmarkId::new("sobol/sample_4d", dim0), |b| {
            b.iter(|| {
                let s = black_box(Seed::new(7));
                for (i, p) in out.iter_mut().enumerate() {
                    let lo = Sobol::sample_4d(i as u32, dim0, s);
                    let hi = Sobol::sample_4d(i as u32, dim0 + 4, s);
                    *p = core::array::from_fn(|d| if d < 4 { lo[d] } else { hi[d - 4] });
                }
                black_box(&mut out);
            })
        });
        g.bench_function(BenchmarkId::new("sobol/sample_8d", dim0), |b| {
            b.iter(|| {
                let s = black_box(Seed::new(7));
                for (i, p) in out.iter_mut().enumerate() {
                    *p = Sobol::sample_8d(i as u32, dim0, s);
                }
                black_box(&mut out);
            })
        });
        // A new seed for every call (a renderer that visits pixels in
        // random order): the key derivations cannot be hoisted out of the
        // loop, for the peer or for us.
        g.bench_function(
            BenchmarkId::new("baseline/sobol_burley_4d_seed_per_call", dim0),
            |b| {
                b.iter(|| {
                    let s0 = black_box(7u32);
                    for (i, p) in out.iter_mut().enumerate() {
                        let s = s0 ^ (i as u32).wrapping_mul(0x9E37_79B9);
                        let lo = sobol_burley::sample_4d(i as u32, dim0 / 4, s);
                        let hi = sobol_burley::sample_4d(i as u32, dim0 / 4 + 1, s);
                        *p = core::array::from_fn(|d| if d < 4 { lo[d] } else { hi[d - 4] });
                    }
                    black_box(&mut out);
                })
            },
        );
        g.bench_function(
            BenchmarkId::new("sobol/sample_8d_seed_per_call", dim0),
            |b| {
                b.iter(|| {
                    let s0 = black_box(7u64);
                    for (i, p) in out.iter_mut().enumerate() {
                        let s = Seed(s0 ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
                        *p = Sobol::sample_8d(i as u32, dim0, s);
                    }
                    black_box(&mut out);
                })
            },
        );
        // The checked trait method through a trait object, as a renderer
        // that picks its sequence at run time calls it.
        let dynamic: &dyn Sequence<2> = &seq;
        g.bench_function(BenchmarkId::new("sequence_dyn/sample_8d", dim0), |b| {
            b.iter(|| {
                let s = black_box(Seed::new(7));
                for (i, p) in out.iter_mut().enumerate() {
                    *p = dynamic.sample_8d(i as u64, dim0, s).unwrap();
                }
                black_box(&mut out);
            })
        });
    }
    g.finish();
}

fn patterns_2d(c: &mut Criterion) {
    group::<2>(c, samplers2);
}

fn patterns_3d(c: &mut Criterion) {
    group::<3>(c, samplers3);
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_millis(1200))
        .sample_size(20);
    targets = patterns_2d, patterns_3d, random_access
}
criterion_main!(benches);
