//! Ambient-occlusion visibility in closed form (`world::occlusion`), in the
//! paper's AO scene (seven spheres on a ground sphere): half-planes per
//! second for the occluded intervals of every sphere, the whole line's
//! visible cosine weight (the AO line estimator's summand), and a wrapped
//! segment of length 1 in `θ`. The shading point is where the camera ray of
//! pixel (410, 305) meets the ground, `(−0.940, −0.008, 3.925)` (pbrt's
//! camera conventions; `lab/tests/scene.rs` checks it), with azimuths
//! `φ = π(k + ½)/N`. The bench's point is rounded to three decimals, so its
//! AO (printed, 0.7148) differs from the lab's exact hit point (0.714721) by
//! about 1e−4.
//!
//! The second group is the line summand in `f32`
//! (`world::occlusion_f32::AoPoint32`, prepared once for the point): the
//! 8-lane SIMD batch, its scalar twin, and the `f64` path from the same
//! azimuths (`HalfPlane::at_azimuth` + `visible`, so both include the
//! per-azimuth frame); the max `|f32 − f64|` over the bench's lines is
//! printed first.
//!
//! Run: `cargo bench --bench occlusion`; criterion's `thrpt` is half-planes
//! (lines) per second on one core.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use linesample_scene::occlusion_f32::AoPoint32;
use linesample_scene::HalfPlane;
use std::f64::consts::{FRAC_PI_2, PI};
use std::hint::black_box;

#[path = "../../tests/common/ao_scene.rs"]
mod ao_scene;

const N: usize = 4096;

/// The bench's inputs: the scene, the shading point and frame, the `N`
/// half-planes at `φ = π(k + ½)/N`, the same azimuths in `f32` and the
/// segments' start angles.
struct Setup {
    spheres: Vec<linesample::world::Sphere<3>>,
    point: [f64; 3],
    normal: [f64; 3],
    tangent: [f64; 3],
    planes: Vec<HalfPlane>,
    phis: Vec<f32>,
    theta0s: Vec<f32>,
}

/// Builds the [`Setup`] and prints the point's AO from its `N` lines.
fn setup() -> Setup {
    let spheres = ao_scene::spheres();
    // The ground point of pixel (410, 305), pushed onto the ground sphere.
    let p0 = [-0.940_f64, -0.008, 3.925];
    let d = [p0[0], p0[1] + 1000.0, p0[2]];
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let normal = [d[0] / l, d[1] / l, d[2] / l];
    let point = [
        1000.0 * normal[0],
        1000.0 * normal[1] - 1000.0,
        1000.0 * normal[2],
    ];
    let planes: Vec<HalfPlane> = (0..N)
        .map(|k| {
            let phi = PI * (k as f64 + 0.5) / N as f64;
            HalfPlane::at_azimuth(point, normal, [1.0, 0.0, 0.0], phi).unwrap()
        })
        .collect();
    let mut scratch = vec![(0.0, 0.0); 2 * spheres.len()];
    let ao: f64 = planes
        .iter()
        .map(|h| {
            h.visible(&spheres, 500.0, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
                .unwrap()
        })
        .sum::<f64>()
        / N as f64;
    println!("AO at pixel (410, 305) from {N} stratified lines: {ao:.6}");
    // The f32 batch's azimuths, rounded to f32; the f64 reference widens
    // the same values.
    let phis: Vec<f32> = (0..N)
        .map(|k| (PI * (k as f64 + 0.5) / N as f64) as f32)
        .collect();
    let theta0s: Vec<f32> = (0..N)
        .map(|k| (-FRAC_PI_2 + PI * ((k * 37) % N) as f64 / N as f64) as f32)
        .collect();
    Setup {
        spheres,
        point,
        normal,
        tangent: [1.0, 0.0, 0.0],
        planes,
        phis,
        theta0s,
    }
}

/// The `f64` line of azimuth `phi` through `at_azimuth` + `visible`.
fn line64(s: &Setup, phi: f32, scratch: &mut [(f64, f64)]) -> f64 {
    HalfPlane::at_azimuth(s.point, s.normal, s.tangent, f64::from(phi))
        .unwrap()
        .visible(&s.spheres, 500.0, -FRAC_PI_2, FRAC_PI_2, scratch)
        .unwrap()
}

/// The `f64` group: occluded intervals, whole lines, wrapped segments.
fn f64_visibility(c: &mut Criterion, s: &Setup) {
    let (spheres, planes) = (&s.spheres, &s.planes);
    let mut scratch = vec![(0.0, 0.0); 2 * spheres.len()];
    let mut g = c.benchmark_group("AO visibility (8 spheres, f64)");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function(
        BenchmarkId::new("occluded intervals, all spheres", N),
        |b| {
            b.iter(|| {
                let mut n = 0usize;
                for h in planes {
                    for s in spheres {
                        n += h.occluded(black_box(s), 500.0).pieces().len();
                    }
                }
                n
            })
        },
    );
    g.bench_function(BenchmarkId::new("line (whole half-plane)", N), |b| {
        b.iter(|| {
            planes
                .iter()
                .map(|h| {
                    h.visible(
                        black_box(spheres),
                        500.0,
                        -FRAC_PI_2,
                        FRAC_PI_2,
                        &mut scratch,
                    )
                    .unwrap()
                })
                .sum::<f64>()
        })
    });
    g.bench_function(BenchmarkId::new("segment, length 1, wrapped", N), |b| {
        b.iter(|| {
            planes
                .iter()
                .enumerate()
                .map(|(k, h)| {
                    let t0 = -FRAC_PI_2 + PI * ((k * 37) % N) as f64 / N as f64;
                    h.visible_wrapped(black_box(spheres), 500.0, t0, 1.0, &mut scratch)
                        .unwrap()
                })
                .sum::<f64>()
        })
    });
    g.finish();
}

/// Prints the `f32` batch's AO and its largest difference from the `f64`
/// lines and wrapped segments at the same (widened) azimuths.
fn f32_accuracy(s: &Setup, ao32: &AoPoint32<8>) {
    let mut scratch = vec![(0.0, 0.0); 2 * s.spheres.len()];
    let mut out = vec![0.0f32; N];
    ao32.line_batch_f32(&s.phis, &mut out).unwrap();
    let (mut worst, mut sum32) = (0.0f64, 0.0f64);
    for (&phi, &v) in s.phis.iter().zip(&out) {
        worst = worst.max((f64::from(v) - line64(s, phi, &mut scratch)).abs());
        sum32 += f64::from(v);
    }
    let mut seg = vec![0.0f32; N];
    ao32.segment_batch_f32(&s.phis, &s.theta0s, 1.0, &mut seg)
        .unwrap();
    let mut worst_seg = 0.0f64;
    for ((&phi, &t0), &v) in s.phis.iter().zip(&s.theta0s).zip(&seg) {
        let want = HalfPlane::at_azimuth(s.point, s.normal, s.tangent, f64::from(phi))
            .unwrap()
            .visible_wrapped(&s.spheres, 500.0, f64::from(t0), 1.0, &mut scratch)
            .unwrap();
        worst_seg = worst_seg.max((f64::from(v) - want).abs());
    }
    println!(
        "f32 AO ({} of {} spheres kept): AO {:.6}, max |f32 − f64| over the {N} lines {worst:.2e}, \
         over the {N} wrapped segments of length 1 {worst_seg:.2e}",
        ao32.occluders(),
        s.spheres.len(),
        sum32 / N as f64
    );
}

/// The line summand in `f32` (SIMD batch, scalar twin) against `f64`, and
/// the `f32` wrapped segments.
fn f32_against_f64(c: &mut Criterion, s: &Setup, ao32: &AoPoint32<8>) {
    let (spheres, phis) = (&s.spheres, &s.phis);
    let mut scratch = vec![(0.0, 0.0); 2 * spheres.len()];
    let (mut out, mut seg) = (vec![0.0f32; N], vec![0.0f32; N]);
    let mut g = c.benchmark_group("AO line summand (8 spheres), f32 vs f64");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function(
        BenchmarkId::new("f32 SIMD batch (line_batch_f32)", N),
        |b| {
            b.iter(|| {
                ao32.line_batch_f32(black_box(phis), &mut out).unwrap();
                out[N - 1]
            })
        },
    );
    g.bench_function(BenchmarkId::new("f32 scalar twin (line_f32)", N), |b| {
        b.iter(|| {
            black_box(phis)
                .iter()
                .map(|&phi| ao32.line_f32(phi))
                .sum::<f32>()
        })
    });
    g.bench_function(BenchmarkId::new("f64 (at_azimuth + visible)", N), |b| {
        b.iter(|| {
            black_box(phis)
                .iter()
                .map(|&phi| line64(s, phi, &mut scratch))
                .sum::<f64>()
        })
    });
    let base = HalfPlane::new(s.point, s.normal, s.tangent).unwrap();
    g.bench_function(BenchmarkId::new("f64 (rotated + visible)", N), |b| {
        b.iter(|| {
            black_box(phis)
                .iter()
                .map(|&phi| {
                    base.rotated(f64::from(phi))
                        .visible(spheres, 500.0, -FRAC_PI_2, FRAC_PI_2, &mut scratch)
                        .unwrap()
                })
                .sum::<f64>()
        })
    });
    g.bench_function(
        BenchmarkId::new("f32 SIMD batch, segment length 1, wrapped", N),
        |b| {
            b.iter(|| {
                ao32.segment_batch_f32(black_box(phis), &s.theta0s, 1.0, &mut seg)
                    .unwrap();
                seg[N - 1]
            })
        },
    );
    g.finish();
}

/// A point sample's visibility (one ray against every sphere, by its
/// quadratic) at the same azimuths and angles: points per second; then the
/// `f32` set-up of one point.
fn points_and_setup(c: &mut Criterion, s: &Setup) {
    let base = HalfPlane::new(s.point, s.normal, s.tangent).unwrap();
    let mut g = c.benchmark_group("AO point visibility (8 spheres, f64)");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function(BenchmarkId::new("rotated + sees", N), |b| {
        b.iter(|| {
            black_box(&s.phis)
                .iter()
                .zip(&s.theta0s)
                .filter(|(&phi, &t)| {
                    base.rotated(f64::from(phi))
                        .sees(&s.spheres, 500.0, f64::from(t) + 0.5)
                })
                .count()
        })
    });
    g.finish();

    let mut g = c.benchmark_group("AO f32 set-up");
    g.throughput(Throughput::Elements(1));
    g.bench_function("AoPoint32::new (8 spheres)", |b| {
        b.iter(|| {
            AoPoint32::<8>::new(black_box(s.point), s.normal, s.tangent, &s.spheres, 500.0)
                .unwrap()
                .occluders()
        })
    });
    g.finish();
}

/// Every group, in order.
fn occlusion(c: &mut Criterion) {
    let s = setup();
    f64_visibility(c, &s);
    let ao32 = AoPoint32::<8>::new(s.point, s.normal, s.tangent, &s.spheres, 500.0).unwrap();
    f32_accuracy(&s, &ao32);
    f32_against_f64(c, &s, &ao32);
    points_and_setup(c, &s);
}

criterion_group!(benches, occlusion);
criterion_main!(benches);
