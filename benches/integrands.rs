//! What accuracy costs in time: free-space line and segment integrals per second,
//! `f32` SIMD batch vs its `f32` scalar twin vs the `f64` scalar path (a few ulp,
//! double-double where it cancels), for the ball chord (2D, 3D) and the Gaussian
//! segment integral (3D), plus the periodised `f64` torus segment means and box
//! lines (ball and Gaussian, rays near the shape's centre and uniform on the
//! torus) for scale. The maximum error of each `f32` path against the `f64` path on the same
//! rays is printed before the timings.
//!
//! Run: `cargo bench --bench integrands` (AVX2 build from `.cargo/config.toml`).

#![allow(clippy::needless_range_loop)]

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::geom::Direction;
use linesample::integrand::{Ball, Gaussian, Integrand};
use linesample::primitive::{Line, Rays32, Segment};
use linesample::Pcg32;
use std::hint::black_box;
use std::time::Duration;

const N: usize = 4096;

/// Rays in SoA `f32` and the same rays in `f64` (the `f32` values widened, so
/// both paths see identical inputs).
struct RaySet<const D: usize> {
    o: [Vec<f32>; D],
    d: [Vec<f32>; D],
    t0: Vec<f32>,
    t1: Vec<f32>,
    o64: Vec<[f64; D]>,
    d64: Vec<Direction<D>>,
}

impl<const D: usize> RaySet<D> {
    /// Origins within `spread` of `(0.5, …)`, unit directions, and either full
    /// lines or segments `[−len/2, len/2]`.
    fn new(seed: u64, spread: f32, len: Option<f32>) -> Self {
        let mut rng = Pcg32::new(seed, 7);
        let mut u = || (rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0);
        let mut o: [Vec<f32>; D] = core::array::from_fn(|_| Vec::with_capacity(N));
        let mut d: [Vec<f32>; D] = core::array::from_fn(|_| Vec::with_capacity(N));
        let (mut t0, mut t1, mut o64, mut d64) = (vec![], vec![], vec![], vec![]);
        for _ in 0..N {
            let p: [f32; D] = core::array::from_fn(|_| 0.5 + spread * (2.0 * u() - 1.0));
            let w: [f64; D] = core::array::from_fn(|_| f64::from(2.0 * u() - 1.0) + 1e-3);
            let dir = Direction::new(w).unwrap();
            let w32: [f32; D] = core::array::from_fn(|j| dir.get()[j] as f32);
            // The f64 path uses the f32 direction re-normalised in f64.
            let dir = Direction::new(core::array::from_fn(|j| f64::from(w32[j]))).unwrap();
            for j in 0..D {
                o[j].push(p[j]);
                d[j].push(dir.get()[j] as f32);
            }
            match len {
                Some(l) => {
                    t0.push(-0.5 * l);
                    t1.push(0.5 * l);
                }
                None => {
                    t0.push(f32::NEG_INFINITY);
                    t1.push(f32::INFINITY);
                }
            }
            o64.push(core::array::from_fn(|j| f64::from(p[j])));
            d64.push(dir);
        }
        Self {
            o,
            d,
            t0,
            t1,
            o64,
            d64,
        }
    }

    fn rays(&self) -> Rays32<'_, D> {
        Rays32 {
            origin: core::array::from_fn(|j| self.o[j].as_slice()),
            dir: core::array::from_fn(|j| self.d[j].as_slice()),
            t0: &self.t0,
            t1: &self.t1,
        }
    }

    fn f64_all(&self, f: &dyn Integrand<D>, out: &mut [f64]) {
        for i in 0..N {
            out[i] = f.segment_free(
                &self.o64[i],
                &self.d64[i],
                f64::from(self.t0[i]),
                f64::from(self.t1[i]),
            );
        }
    }

    fn f32_scalar_all(&self, f: &dyn Integrand<D>, out: &mut [f32]) {
        for i in 0..N {
            // Plain loops: `array::from_fn` closures were not inlined here.
            let mut o = [0.0f32; D];
            let mut d = [0.0f32; D];
            for j in 0..D {
                o[j] = self.o[j][i];
                d[j] = self.d[j][i];
            }
            out[i] = f.segment_free_f32(o, d, self.t0[i], self.t1[i]);
        }
    }
}

/// Max absolute error of the f32 batch against f64, relative to `scale`.
fn report<const D: usize>(name: &str, f: &dyn Integrand<D>, rs: &RaySet<D>, scale: f64) {
    let mut a = vec![0.0f64; N];
    let mut b = vec![0.0f32; N];
    rs.f64_all(f, &mut a);
    f.segment_free_batch_f32(&rs.rays(), &mut b).unwrap();
    let mut max_abs = 0.0f64;
    let mut hits = 0;
    for i in 0..N {
        max_abs = max_abs.max((f64::from(b[i]) - a[i]).abs());
        hits += usize::from(a[i] > 0.0);
    }
    println!(
        "{name}: f32 SIMD vs f64: max |error| = {max_abs:.3e} = {:.2e} × scale ({scale:.3e}); {hits}/{N} rays non-zero",
        max_abs / scale
    );
}

fn bench_set<const D: usize>(c: &mut Criterion, name: &str, f: &dyn Integrand<D>, rs: &RaySet<D>) {
    let mut g = c.benchmark_group(name);
    g.throughput(Throughput::Elements(N as u64));
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(2));
    let rays = rs.rays();
    let mut out32 = vec![0.0f32; N];
    let mut out64 = vec![0.0f64; N];
    g.bench_function(BenchmarkId::new("f32 SIMD batch", N), |b| {
        b.iter(|| f.segment_free_batch_f32(black_box(&rays), black_box(&mut out32)))
    });
    g.bench_function(BenchmarkId::new("f32 scalar twin", N), |b| {
        b.iter(|| rs.f32_scalar_all(f, black_box(&mut out32)))
    });
    g.bench_function(BenchmarkId::new("f64 scalar", N), |b| {
        b.iter(|| rs.f64_all(f, black_box(&mut out64)))
    });
    g.finish();
}

fn integrands(c: &mut Criterion) {
    let ball3 = Ball::<3>::new([0.5, 0.5, 0.5], 0.25).unwrap();
    let disk = Ball::<2>::new([0.5, 0.5], 0.25).unwrap();
    let gauss3 = Gaussian::<3>::new([0.5, 0.5, 0.5], 0.1).unwrap();

    let lines3 = RaySet::<3>::new(1, 0.3, None);
    let lines2 = RaySet::<2>::new(2, 0.3, None);
    let segs3 = RaySet::<3>::new(3, 0.3, Some(0.2));
    report("chord 3D lines", &ball3, &lines3, 0.5);
    report("chord 2D lines", &disk, &lines2, 0.5);
    report("chord 3D segments λ=0.2", &ball3, &segs3, 0.2);
    let peak_line = 1.0 / (2.0 * std::f64::consts::PI * 0.01); // (2πσ²)^{-1}: 3D line peak
    report("gaussian 3D lines", &gauss3, &lines3, peak_line);
    report("gaussian 3D segments λ=0.2", &gauss3, &segs3, peak_line);

    bench_set(c, "chord 3D lines", &ball3, &lines3);
    bench_set(c, "chord 2D lines", &disk, &lines2);
    bench_set(c, "chord 3D segments", &ball3, &segs3);
    bench_set(c, "gaussian 3D lines", &gauss3, &lines3);
    bench_set(c, "gaussian 3D segments", &gauss3, &segs3);

    // The periodised f64 torus paths the lab's experiments run on (images +
    // cell walk): segment means (λ = 0.2, random directions) and oblique box
    // lines, at r = 0.25 and σ = 0.1.
    torus(c, "ball", &ball3, &disk, &segs3);
    let gauss2 = Gaussian::<2>::new([0.5, 0.5], 0.1).unwrap();
    torus(c, "gaussian σ=0.1", &gauss3, &gauss2, &segs3);
    // The same with segment centres uniform on the torus (as the lab's
    // estimators place them), not within 0.3 of the shape's centre.
    let uniform = RaySet::<3>::new(4, 0.5, Some(0.2));
    torus(c, "ball, uniform", &ball3, &disk, &uniform);
    torus(c, "gaussian σ=0.1, uniform", &gauss3, &gauss2, &uniform);
}

/// Segment means (3D and 2D, λ = 0.2) and oblique lines (2D) per second.
fn torus(
    c: &mut Criterion,
    name: &str,
    f3: &dyn Integrand<3>,
    f2: &dyn Integrand<2>,
    segs3: &RaySet<3>,
) {
    let segs: Vec<Segment<3>> = (0..N)
        .map(|i| Segment::new(segs3.o64[i], segs3.d64[i], 0.2).unwrap())
        .collect();
    let segs2: Vec<Segment<2>> = (0..N)
        .map(|i| {
            let (o, d) = (segs3.o64[i], segs3.d64[i].get());
            Segment::new(
                [o[0], o[1]],
                Direction::new([d[0], d[1] + 1e-3]).unwrap(),
                0.2,
            )
            .unwrap()
        })
        .collect();
    let lines2: Vec<Line<2>> = segs2
        .iter()
        .map(|s| Line::new(s.centre(), s.dir()).unwrap())
        .collect();
    let mut g = c.benchmark_group(format!("torus f64 {name}"));
    g.throughput(Throughput::Elements(N as u64));
    g.measurement_time(Duration::from_secs(2));
    g.bench_function(BenchmarkId::new("3D segment mean", N), |b| {
        b.iter(|| {
            segs.iter()
                .map(|s| f3.segment_mean(black_box(s)))
                .sum::<f64>()
        })
    });
    g.bench_function(BenchmarkId::new("2D segment mean", N), |b| {
        b.iter(|| {
            segs2
                .iter()
                .map(|s| f2.segment_mean(black_box(s)))
                .sum::<f64>()
        })
    });
    g.bench_function(BenchmarkId::new("2D oblique line", N), |b| {
        b.iter(|| {
            lines2
                .iter()
                .map(|l| f2.line_integral(black_box(l)))
                .sum::<f64>()
        })
    });
    g.finish();
}

criterion_group!(benches, integrands);
criterion_main!(benches);
