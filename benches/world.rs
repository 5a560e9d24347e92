//! What accuracy costs in time for a renderer: world-space rays per second and
//! the maximum error of each path, `f32` SIMD batch (8 lanes) vs its `f32`
//! scalar twin vs the exact `f64` path (double-double where it cancels), for
//! the sphere chord, the Gaussian segment integral and the Gaussian
//! transmittance. The scene is in world units far from the origin (centres
//! near `(100, −40, 250)`, camera rays from 20 units away), so the `f32`
//! errors include what a real renderer's coordinates cost.
//!
//! The accuracy table is printed before the timings; criterion's `thrpt` is
//! rays per second.
//!
//! Run: `cargo bench --bench world`.

#![allow(clippy::needless_range_loop)]

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample::primitive::Rays32;
use linesample::world::{Gaussian, Ray, Sphere};
use linesample::Pcg32;
use std::hint::black_box;
use std::time::Duration;

const N: usize = 4096;
const CENTRE: [f64; 3] = [100.0, -40.0, 250.0];

/// Camera rays from a point 20 units from `CENTRE` towards random points within
/// `spread` of it: SoA `f32` and the same rays in `f64` (the `f32` values
/// widened, the direction re-normalised in `f64`).
struct RaySet {
    o: [Vec<f32>; 3],
    d: [Vec<f32>; 3],
    t0: Vec<f32>,
    t1: Vec<f32>,
    rays64: Vec<Ray<3>>,
}

impl RaySet {
    fn new(seed: u64, spread: f64, segment: Option<(f32, f32)>) -> Self {
        let mut rng = Pcg32::new(seed, 11);
        let mut u = || f64::from(rng.next_u32()) / 4_294_967_296.0;
        let eye = [CENTRE[0] + 3.0, CENTRE[1] + 2.0, CENTRE[2] + 20.0];
        let mut s = Self {
            o: Default::default(),
            d: Default::default(),
            t0: vec![],
            t1: vec![],
            rays64: vec![],
        };
        for _ in 0..N {
            let target: [f64; 3] = core::array::from_fn(|j| CENTRE[j] + spread * (2.0 * u() - 1.0));
            let ray = Ray::through(eye, target).unwrap();
            let o32 = eye.map(|x| x as f32);
            let d32 = ray.dir().get().map(|x| x as f32);
            for j in 0..3 {
                s.o[j].push(o32[j]);
                s.d[j].push(d32[j]);
            }
            let (a, b) = segment.unwrap_or((f32::NEG_INFINITY, f32::INFINITY));
            s.t0.push(a);
            s.t1.push(b);
            s.rays64
                .push(Ray::new(o32.map(f64::from), d32.map(f64::from)).unwrap());
        }
        s
    }

    fn rays(&self) -> Rays32<'_, 3> {
        Rays32 {
            origin: core::array::from_fn(|j| self.o[j].as_slice()),
            dir: core::array::from_fn(|j| self.d[j].as_slice()),
            t0: &self.t0,
            t1: &self.t1,
        }
    }

    fn ends(&self, i: usize) -> (f64, f64) {
        (f64::from(self.t0[i]), f64::from(self.t1[i]))
    }
}

/// One row of the accuracy table: max |f32 SIMD − f64| over the rays,
/// absolute and relative to `scale`.
fn report(name: &str, f64s: &[f64], f32s: &[f32], scale: f64) {
    let max = f64s
        .iter()
        .zip(f32s)
        .map(|(a, b)| (f64::from(*b) - a).abs())
        .fold(0.0, f64::max);
    let hits = f64s.iter().filter(|&&a| a > 0.0).count();
    println!(
        "{name:<34} max |f32 − f64| = {max:.2e} ({:.2e} × {scale:.3e}); {hits}/{N} non-zero",
        max / scale
    );
}

fn world(c: &mut Criterion) {
    let sphere = Sphere::new(CENTRE, 2.5).unwrap();
    let gauss = Gaussian::with_peak(CENTRE, 1.0, 1.0).unwrap();
    let lines = RaySet::new(1, 3.0, None);
    let segs = RaySet::new(2, 3.0, Some((18.0, 21.0)));
    let sigma_t = 0.7f32;

    // f64 reference values and the f32 batches on the same rays.
    let mut out32 = vec![0.0f32; N];
    let mut out64 = vec![0.0f64; N];
    println!("accuracy (f32 SIMD batch against the exact f64 path, same rays):");
    for (name, rs) in [
        ("sphere chord, lines", &lines),
        ("sphere chord, segments", &segs),
    ] {
        for i in 0..N {
            let (a, b) = rs.ends(i);
            out64[i] = sphere.segment(&rs.rays64[i], a, b);
        }
        sphere.segment_batch_f32(&rs.rays(), &mut out32).unwrap();
        report(name, &out64, &out32, 2.0 * sphere.radius());
    }
    let line_peak = gauss.peak() * gauss.sigma() * (2.0 * std::f64::consts::PI).sqrt();
    for (name, rs) in [("gaussian line", &lines), ("gaussian segment", &segs)] {
        for i in 0..N {
            let (a, b) = rs.ends(i);
            out64[i] = gauss.segment(&rs.rays64[i], a, b);
        }
        gauss.segment_batch_f32(&rs.rays(), &mut out32).unwrap();
        report(name, &out64, &out32, line_peak);
        // The plain-f64 path against the exact one: its worst relative error
        // and worst run-time bound R.
        let (mut err, mut rmax) = (0.0f64, 0.0f64);
        for i in 0..N {
            let (a, b) = rs.ends(i);
            let (v, r) = gauss.segment_fast(&rs.rays64[i], a, b);
            if out64[i] != 0.0 {
                err = err.max(((v - out64[i]) / out64[i]).abs());
            }
            rmax = rmax.max(r);
        }
        println!(
            "{name:<34} f64 segment_fast: max relative error {err:.2e}, max bound R {rmax:.2e}"
        );
    }
    for i in 0..N {
        out64[i] = gauss.transmittance(
            &lines.rays64[i],
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::from(sigma_t),
        );
    }
    gauss
        .transmittance_batch_f32(&lines.rays(), sigma_t, &mut out32)
        .unwrap();
    report("gaussian transmittance, lines", &out64, &out32, 1.0);

    let mut g = c.benchmark_group("world sphere chord");
    g.throughput(Throughput::Elements(N as u64));
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(2));
    let rays = lines.rays();
    g.bench_function(BenchmarkId::new("f32 SIMD batch", N), |b| {
        b.iter(|| sphere.segment_batch_f32(black_box(&rays), black_box(&mut out32)))
    });
    g.bench_function(BenchmarkId::new("f32 scalar twin", N), |b| {
        b.iter(|| {
            for i in 0..N {
                let o = [lines.o[0][i], lines.o[1][i], lines.o[2][i]];
                let d = [lines.d[0][i], lines.d[1][i], lines.d[2][i]];
                out32[i] = sphere.segment_f32(o, d, lines.t0[i], lines.t1[i]);
            }
            black_box(&out32);
        })
    });
    g.bench_function(BenchmarkId::new("f64 exact", N), |b| {
        b.iter(|| {
            for (o, r) in out64.iter_mut().zip(&lines.rays64) {
                *o = sphere.chord(black_box(r));
            }
        })
    });
    g.bench_function(BenchmarkId::new("f64 exact, segments", N), |b| {
        b.iter(|| {
            for (i, o) in out64.iter_mut().enumerate() {
                let (t0, t1) = segs.ends(i);
                *o = sphere.segment(black_box(&segs.rays64[i]), t0, t1);
            }
        })
    });
    g.bench_function(BenchmarkId::new("f64 hit (entry, exit)", N), |b| {
        b.iter(|| {
            for (o, r) in out64.iter_mut().zip(&lines.rays64) {
                *o = sphere.hit(black_box(r)).map_or(0.0, |(a, b)| b - a);
            }
        })
    });
    g.finish();

    let mut g = c.benchmark_group("world gaussian segment");
    g.throughput(Throughput::Elements(N as u64));
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(2));
    let srays = segs.rays();
    g.bench_function(BenchmarkId::new("f32 SIMD batch", N), |b| {
        b.iter(|| gauss.segment_batch_f32(black_box(&srays), black_box(&mut out32)))
    });
    g.bench_function(BenchmarkId::new("f64 exact", N), |b| {
        b.iter(|| {
            for i in 0..N {
                let (t0, t1) = segs.ends(i);
                out64[i] = gauss.segment(black_box(&segs.rays64[i]), t0, t1);
            }
        })
    });
    g.bench_function(BenchmarkId::new("f64 fast, with error bound", N), |b| {
        b.iter(|| {
            for i in 0..N {
                let (t0, t1) = segs.ends(i);
                out64[i] = gauss.segment_fast(black_box(&segs.rays64[i]), t0, t1).0;
            }
        })
    });
    g.finish();

    let mut g = c.benchmark_group("world gaussian transmittance");
    g.throughput(Throughput::Elements(N as u64));
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(2));
    g.bench_function(BenchmarkId::new("f32 SIMD batch", N), |b| {
        b.iter(|| gauss.transmittance_batch_f32(black_box(&rays), sigma_t, black_box(&mut out32)))
    });
    g.bench_function(BenchmarkId::new("f64 exact", N), |b| {
        b.iter(|| {
            for (o, r) in out64.iter_mut().zip(&lines.rays64) {
                *o = gauss.transmittance(black_box(r), f64::NEG_INFINITY, f64::INFINITY, 0.7);
            }
        })
    });
    g.finish();
}

criterion_group!(benches, world);
criterion_main!(benches);
