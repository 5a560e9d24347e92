//! Shared checks for the integrand fuzz targets (included with `#[path]`).
//!
//! For an integrand the target has constructed from arbitrary `f64` parameters,
//! [`check`] evaluates every closed form on arbitrary points, directions, lengths
//! and frequencies and asserts: no panic, no NaN/∞ for finite accepted inputs,
//! and each result within `[0, maximum possible]` (up to `1e-9` relative slack
//! for rounding):
//!
//! * `value ∈ [0, max_value]`, `segment_mean ∈ [0, max_value]`,
//!   `segment_integral ∈ [0, λ·max_value]`, `line_integral ∈ [0, √D·max_value]`;
//! * `segment_free ∈ [0, (t1 − t0)·sup F]` and `≤ the full line`;
//! * `|fourier(k)| ≤ integral`;
//! * the `f32` batch equals its scalar twin bit for bit and is finite where its
//!   inputs are moderate.
//!
//! Segment lengths are capped at 64 (longer wrapped segments only cost time,
//! linearly: `MAX_SEGMENT_LENGTH` is 2²⁰).
#![allow(dead_code)]

use arbitrary::Arbitrary;
use linesample::geom::Direction;
use linesample::integrand::Integrand;
use linesample::primitive::{Line, Rays32, Segment};

/// Inputs shared by all integrand targets.
#[derive(Arbitrary, Debug, Clone)]
pub struct Probe<const D: usize> {
    pub x: [f64; D],
    pub dir: [f64; D],
    pub length: f64,
    pub t0: f64,
    pub t1: f64,
    pub k: [i32; D],
}

fn within(v: f64, hi: f64, what: &str) {
    assert!(v.is_finite(), "{what} = {v} is not finite");
    assert!(v >= 0.0, "{what} = {v} < 0");
    assert!(v <= hi * (1.0 + 1e-9) + 1e-300, "{what} = {v} > bound {hi}");
}

/// Runs every closed form of `f` on `probes`. `sup_free` bounds `F` in free space;
/// `line_free` bounds the free-space integral over a whole line.
pub fn check<const D: usize>(
    f: &dyn Integrand<D>,
    sup_free: f64,
    line_free: f64,
    probes: &[Probe<D>],
) {
    let max = f.max_value();
    let integral = f.integral();
    assert!(max.is_finite() && max > 0.0, "max_value = {max}");
    assert!(
        integral.is_finite() && integral >= 0.0,
        "integral = {integral}"
    );
    for p in probes {
        if p.x.iter().any(|v| !v.is_finite() || v.abs() > 1e15) {
            continue;
        }
        within(f.value(&p.x), max, "value");
        within(f.value_free(&p.x), sup_free, "value_free");
        let ft = f.fourier(&p.k);
        assert!(ft.re.is_finite() && ft.im.is_finite(), "fourier {ft:?}");
        assert!(
            ft.abs() <= integral * (1.0 + 1e-9) + 1e-300,
            "fourier {ft:?} > {integral}"
        );
        let Ok(dir) = Direction::new(p.dir) else {
            continue;
        };
        if let Ok(line) = Line::new(p.x, dir) {
            within(
                f.line_integral(&line),
                (D as f64).sqrt() * max,
                "line_integral",
            );
        }
        let lambda = p.length.abs() % 64.0;
        if lambda.is_finite() {
            if let Ok(seg) = Segment::new(p.x, dir, lambda) {
                within(f.segment_integral(&seg), lambda * max, "segment_integral");
                within(f.segment_mean(&seg), max, "segment_mean");
            }
        }
        if p.t0.is_finite() || p.t0.is_infinite() {
            let (a, b) = if p.t0 <= p.t1 {
                (p.t0, p.t1)
            } else {
                (p.t1, p.t0)
            };
            if !a.is_nan() && !b.is_nan() && a < f64::INFINITY && b > f64::NEG_INFINITY {
                let v = f.segment_free(&p.x, &dir, a, b);
                let bound = if (b - a).is_finite() {
                    ((b - a) * sup_free).min(line_free)
                } else {
                    line_free
                };
                within(v, bound, "segment_free");
            }
        }
        // f32 batch vs its scalar twin, on 9 rays (one SIMD block + remainder).
        let o: [f32; D] = core::array::from_fn(|j| p.x[j] as f32);
        let d: [f32; D] = core::array::from_fn(|j| dir.get()[j] as f32);
        let (t0, t1) = (p.t0 as f32, p.t1 as f32);
        let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        let ox: [Vec<f32>; D] = core::array::from_fn(|j| vec![o[j]; 9]);
        let dx: [Vec<f32>; D] = core::array::from_fn(|j| vec![d[j]; 9]);
        let ts0 = vec![t0; 9];
        let ts1 = vec![t1; 9];
        let rays = Rays32 {
            origin: core::array::from_fn(|j| ox[j].as_slice()),
            dir: core::array::from_fn(|j| dx[j].as_slice()),
            t0: &ts0,
            t1: &ts1,
        };
        let mut out = vec![0.0f32; 9];
        f.segment_free_batch_f32(&rays, &mut out).unwrap();
        let s = f.segment_free_f32(o, d, t0, t1);
        for v in &out {
            assert_eq!(v.to_bits(), s.to_bits(), "SIMD {v} vs scalar {s}");
        }
        let moderate = o.iter().all(|v| v.abs() < 1e6)
            && !t0.is_nan()
            && !t1.is_nan()
            && t0.abs().min(t1.abs()) < 1e6;
        if moderate {
            assert!(!s.is_nan(), "f32 result NaN for {o:?} {d:?} [{t0}, {t1}]");
            assert!(s >= 0.0, "f32 result {s} < 0");
        }
    }
}
