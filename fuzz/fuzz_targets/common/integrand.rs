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
//! * the `f32` batch, one ray per probe (every lane different, up to
//!   [`MAX_LANES`] lanes: two SIMD blocks and a remainder), equals its scalar twin
//!   bit for bit, lane by lane; where a lane is moderate (unit direction,
//!   `|o| < 1e6`, one end below `1e6`) it is non-negative and within the
//!   integrand's documented `f32`-vs-`f64` bound of the `f64` path at the same
//!   inputs (the target's `f32_ref` gives the reference and the bound).
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

/// Most lanes in one batch: two 8-wide blocks and a remainder.
pub const MAX_LANES: usize = 19;

/// One `f32` ray of the batch: `o + t·d`, `t ∈ [t0, t1]`.
#[derive(Debug, Clone, Copy)]
pub struct Ray32<const D: usize> {
    pub o: [f32; D],
    pub d: [f32; D],
    pub t0: f32,
    pub t1: f32,
}

impl<const D: usize> Ray32<D> {
    /// The ray in `f64` with a unit direction and the ends rescaled to its arc
    /// length, and `|d|` (`None` for a zero or non-finite `d`).
    pub fn to_f64(&self) -> Option<([f64; D], Direction<D>, f64, f64, f64)> {
        let o = self.o.map(f64::from);
        let d = self.d.map(f64::from);
        let nd = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(nd.is_finite() && nd > 0.0) {
            return None;
        }
        let dir = Direction::new(d).ok()?;
        Some((o, dir, f64::from(self.t0) * nd, f64::from(self.t1) * nd, nd))
    }
}

/// `|t|` for finite `t`, else 0 (the finite ends that enter an error bound).
pub fn fin(t: f32) -> f64 {
    if t.is_finite() {
        f64::from(t).abs()
    } else {
        0.0
    }
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
    f32_ref: &dyn Fn(&Ray32<D>) -> Option<(f64, f64)>,
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
    }
    // f32 batch vs its scalar twin and the f64 path, on one ray per probe: every
    // lane has its own origin, direction and ends (a splatted batch would hide a
    // lane mix-up or a wrong remainder loop).
    let mut lanes: Vec<(Ray32<D>, bool)> = Vec::new();
    for p in probes.iter().take(MAX_LANES) {
        let o: [f32; D] = core::array::from_fn(|j| p.x[j] as f32);
        // A unit direction where one exists (the moderate case the bounds are
        // stated for), the raw one otherwise (only the bit-for-bit check).
        let unit = Direction::new(p.dir).ok();
        let d: [f32; D] = match unit {
            Some(u) => u.get().map(|x| x as f32),
            None => p.dir.map(|x| x as f32),
        };
        let (t0, t1) = (p.t0 as f32, p.t1 as f32);
        let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        lanes.push((Ray32 { o, d, t0, t1 }, unit.is_some()));
    }
    let n = lanes.len();
    let ox: [Vec<f32>; D] = core::array::from_fn(|j| lanes.iter().map(|(r, _)| r.o[j]).collect());
    let dx: [Vec<f32>; D] = core::array::from_fn(|j| lanes.iter().map(|(r, _)| r.d[j]).collect());
    let ts0: Vec<f32> = lanes.iter().map(|(r, _)| r.t0).collect();
    let ts1: Vec<f32> = lanes.iter().map(|(r, _)| r.t1).collect();
    let rays = Rays32 {
        origin: core::array::from_fn(|j| ox[j].as_slice()),
        dir: core::array::from_fn(|j| dx[j].as_slice()),
        t0: &ts0,
        t1: &ts1,
    };
    let mut out = vec![f32::NAN; n];
    f.segment_free_batch_f32(&rays, &mut out).unwrap();
    if n > 0 {
        // A batch whose slices disagree in length is an error, not a panic.
        let mut short = vec![0.0f32; n - 1];
        assert!(f.segment_free_batch_f32(&rays, &mut short).is_err());
    }
    for (i, (r, unit)) in lanes.iter().enumerate() {
        let s = f.segment_free_f32(r.o, r.d, r.t0, r.t1);
        // Bit for bit; two NaNs count as equal (their payloads carry no meaning).
        assert!(
            out[i].to_bits() == s.to_bits() || (out[i].is_nan() && s.is_nan()),
            "lane {i} of {n}: SIMD {} vs scalar {s} for {r:?}",
            out[i]
        );
        let moderate = *unit
            && r.o.iter().all(|v| v.abs() < 1e6)
            && r.d.iter().any(|&v| v != 0.0)
            && !r.t0.is_nan()
            && !r.t1.is_nan()
            && r.t0.abs().min(r.t1.abs()) < 1e6;
        if !moderate {
            continue;
        }
        assert!(!s.is_nan(), "f32 result NaN for {r:?}");
        assert!(s >= 0.0, "f32 result {s} < 0 for {r:?}");
        if let Some((want, bound)) = f32_ref(r) {
            let err = (f64::from(s) - want).abs();
            assert!(
                err <= bound,
                "lane {i}: f32 {s:e} vs f64 {want:e}: error {err:e} > stated bound {bound:e} for {r:?}"
            );
        }
    }
}
