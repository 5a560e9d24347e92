//! Fuzzes the world-space closed forms (`linesample::world`) with arbitrary
//! `f64` shapes and rays: a rejected parameter is fine; a panic, a NaN for
//! finite accepted inputs, or a value outside what the geometry allows is not.
//!
//! Oracles (each exact consequence of the definitions, up to a few ulp):
//! * sphere: `0 ≤ chord ≤ 2r`; `hit` gives `t− < t+` with `t+ − t−` equal to
//!   the chord up to the rounding of the roots; `0 ≤ segment ≤ min(chord,
//!   t1 − t0)`; a point at the mid-chord is inside;
//! * Gaussian: `0 ≤ segment ≤ line`, `T, 1 − T ∈ [0, 1]`, `T + opacity = 1`;
//!   `segment_fast` within its run-time bound `R` of `segment`;
//! * half-space and slab: `0 ≤ segment ≤ t1 − t0`; the slab's segment is at
//!   most the half-space's;
//! * every `f32` batch equals its scalar twin bit for bit, lane by lane.
//!
//! Run: `cargo fuzz run --sanitizer none world`.

#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use linesample::primitive::Rays32;
use linesample::world::{Gaussian, HalfSpace, Ray, Slab, Sphere};

const U: f64 = f64::EPSILON;

#[derive(Arbitrary, Debug)]
struct Case<const D: usize> {
    centre: [f64; D],
    size: f64,
    peak: f64,
    h: [f64; 2],
    origin: [f64; D],
    dir: [f64; D],
    t: [f64; 2],
    rays32: Vec<([f32; D], [f32; D], f32, f32)>,
}

#[derive(Arbitrary, Debug)]
enum Input {
    D2(Case<2>),
    D3(Case<3>),
}

fn run<const D: usize>(c: &Case<D>) {
    let (t0, t1) = (c.t[0].min(c.t[1]), c.t[0].max(c.t[1]));
    let ray = Ray::new(c.origin, c.dir).ok();
    if let Ok(s) = Sphere::new(c.centre, c.size.abs()) {
        let r = s.radius();
        if let Some(ray) = &ray {
            let chord = s.chord(ray);
            assert!(
                (0.0..=2.0 * r * (1.0 + 4.0 * U)).contains(&chord),
                "chord {chord:e} r {r:e}"
            );
            if let Some((a, b)) = s.hit(ray) {
                assert!(a <= b, "hit {a:e} > {b:e}");
                // Near tangency both are only as good as the documented
                // conditioning term 2⁻¹⁰⁰(r/h + r²/h²) (h the half chord).
                let k = r / (0.5 * chord);
                let cond = 2f64.powi(-100) * (k + k * k) * chord;
                let tol = 4.0 * U * (a.abs() + b.abs()) + 1e-13 * chord + cond + 1e-300;
                assert!(
                    ((b - a) - chord).abs() <= tol,
                    "hit {a:e}..{b:e} vs chord {chord:e}"
                );
            } else {
                // A miss or tangency: the chord is at most rounding-level.
                assert!(chord <= 1e-6 * r, "no hit but chord {chord:e}");
            }
            if !t0.is_nan() && !t1.is_nan() {
                let seg = s.segment(ray, t0, t1);
                // The same conditioning term near tangency (found by fuzzing:
                // a chord of 8.6e−155 of a radius-8578 circle, h²
                // subnormal, where the segment and the chord differ by
                // 1.9e−12 relative, far inside 2⁻¹⁰⁰r²/h²).
                let k = r / (0.5 * chord);
                let cond = if chord > 0.0 {
                    2f64.powi(-100) * (k + k * k) * chord
                } else {
                    0.0
                };
                let cap = chord.min(t1 - t0) * (1.0 + 8.0 * U) + cond + 1e-300;
                assert!(seg >= 0.0 && seg <= cap, "segment {seg:e} > {cap:e}");
            }
        }
        batch_matches(
            &c.rays32,
            |o, d, a, b| s.segment_f32(o, d, a, b),
            |rays, out| s.segment_batch_f32(rays, out).unwrap(),
        );
    }
    if let Ok(g) = Gaussian::with_peak(c.centre, c.size.abs(), c.peak.abs()) {
        if let Some(ray) = &ray {
            let line = g.line(ray);
            assert!(line >= 0.0 && !line.is_nan(), "line {line:e}");
            if t0.is_finite() && t1.is_finite() {
                let seg = g.segment(ray, t0, t1);
                assert!(
                    seg >= 0.0 && seg <= line * (1.0 + 1e-13) + 1e-300,
                    "segment {seg:e} > line {line:e}"
                );
                // The plain-f64 path stays within its own bound of the exact
                // one (whose error is below 1e-14).
                let (fv, fr) = g.segment_fast(ray, t0, t1);
                if fr.is_finite() && seg >= f64::MIN_POSITIVE {
                    assert!(
                        (fv - seg).abs() <= (1.5 * fr + 2e-14) * seg,
                        "segment_fast {fv:e} vs {seg:e}, R {fr:e}"
                    );
                }
                let tr = g.transmittance(ray, t0, t1, 1.0);
                let op = g.opacity(ray, t0, t1, 1.0);
                assert!(
                    (0.0..=1.0).contains(&tr) && (0.0..=1.0).contains(&op),
                    "T {tr:e} α {op:e}"
                );
                assert!((tr + op - 1.0).abs() <= 4.0 * U, "T + α = {}", tr + op);
            }
        }
        batch_matches(
            &c.rays32,
            |o, d, a, b| g.segment_f32(o, d, a, b),
            |rays, out| g.segment_batch_f32(rays, out).unwrap(),
        );
        batch_matches(
            &c.rays32,
            |o, d, a, b| g.transmittance_f32(o, d, a, b, 0.5),
            |rays, out| g.transmittance_batch_f32(rays, 0.5, out).unwrap(),
        );
    }
    let (h0, h1) = (c.h[0].min(c.h[1]), c.h[0].max(c.h[1]));
    if let (Ok(hs), Ok(slab)) = (HalfSpace::new(c.dir, h0), Slab::new(c.dir, h0, h1)) {
        if let Some(ray) = &ray {
            if t0.is_finite() && t1.is_finite() && (t1 - t0).is_finite() {
                let len = t1 - t0;
                let a = hs.segment(ray, t0, t1);
                let b = slab.segment(ray, t0, t1);
                // (+1e-300: below the normal range the length is only good to
                // a few subnormal ulps; found by fuzzing, 2.265e-309.)
                assert!(
                    (0.0..=len * (1.0 + 4.0 * U) + 1e-300).contains(&a),
                    "half-space {a:e} > {len:e}"
                );
                assert!(
                    (0.0..=a * (1.0 + 8.0 * U) + 1e-300).contains(&b),
                    "slab {b:e} > half-space {a:e}"
                );
            }
        }
        batch_matches(
            &c.rays32,
            |o, d, a, b| hs.segment_f32(o, d, a, b),
            |rays, out| hs.segment_batch_f32(rays, out).unwrap(),
        );
        batch_matches(
            &c.rays32,
            |o, d, a, b| slab.segment_f32(o, d, a, b),
            |rays, out| slab.segment_batch_f32(rays, out).unwrap(),
        );
    }
}

/// The batch over up to 19 rays equals the scalar twin bit for bit.
fn batch_matches<const D: usize>(
    rays: &[([f32; D], [f32; D], f32, f32)],
    scalar: impl Fn([f32; D], [f32; D], f32, f32) -> f32,
    simd: impl Fn(&Rays32<'_, D>, &mut [f32]),
) {
    let rays = &rays[..rays.len().min(19)];
    let o: [Vec<f32>; D] = core::array::from_fn(|j| rays.iter().map(|r| r.0[j]).collect());
    let d: [Vec<f32>; D] = core::array::from_fn(|j| rays.iter().map(|r| r.1[j]).collect());
    let t0: Vec<f32> = rays.iter().map(|r| r.2).collect();
    let t1: Vec<f32> = rays.iter().map(|r| r.3).collect();
    let batch = Rays32 {
        origin: core::array::from_fn(|j| o[j].as_slice()),
        dir: core::array::from_fn(|j| d[j].as_slice()),
        t0: &t0,
        t1: &t1,
    };
    let mut out = vec![0.0f32; rays.len()];
    simd(&batch, &mut out);
    for (i, r) in rays.iter().enumerate() {
        let s = scalar(r.0, r.1, r.2, r.3);
        assert!(
            s.to_bits() == out[i].to_bits() || (s.is_nan() && out[i].is_nan()),
            "lane {i}: batch {:e} vs scalar {s:e}",
            out[i]
        );
    }
}

fuzz_target!(|input: Input| match input {
    Input::D2(c) => run(&c),
    Input::D3(c) => run(&c),
});
