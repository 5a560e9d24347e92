//! What accuracy costs in time: micro-benchmarks for the `paper` report.
//!
//! * [`simd_case`]: cost per evaluation of an integrand's exact `f64` ray
//!   integral ([`Integrand::segment_free`]), its `f32` scalar twin and its
//!   `f32` SIMD batch, and the error of the SIMD batch against the `f64` path.
//! * [`nufft_sweep`]: time per transform of the exact direct DFT
//!   ([`Dft::add_points`]) and of the type-1 NUFFT at each requested tolerance,
//!   with the NUFFT's achieved error against the direct sum.
//!
//! Timing method (every reported time): one untimed warm-up call, then the
//! number of calls per repeat is doubled (or scaled from the last measurement)
//! until one repeat lasts at least [`MIN_REPEAT`] (far above the resolution of
//! [`Instant`]); then `repeats` repeats of that many calls are timed and the
//! **median** of the per-call times is reported. Inputs pass through
//! [`black_box`] every call, outputs are written to buffers passed through
//! [`black_box`], so no work is hoisted out of or removed from the loop.

use std::hint::black_box;
use std::time::{Duration, Instant};

use linesample::geom::Direction;
use linesample::integrand::Integrand;
use linesample::pattern::{Pattern, Random};
use linesample::primitive::Rays32;
use linesample::spectrum::{AmplitudeView, Amplitudes, Dft, Grid};
use linesample::{Pcg32, Seed};
use linesample_nufft::Plan;
use serde::{Deserialize, Serialize};

use crate::integrand::{IntegrandSpec, Params};
use crate::io::buffer::{empty, filled};
use crate::spec::Primitive;
use crate::with_dims;
use crate::{LabError, Result};

/// Minimum duration of one timed repeat.
pub const MIN_REPEAT: Duration = Duration::from_millis(2);
/// Upper bound on the calls per timed repeat (ends calibration of a no-op).
const MAX_CALLS: u64 = 1 << 30;
/// Length `λ` of the random segments of [`simd_case`].
pub const SEGMENT_LENGTH: f64 = 0.3;
/// Relative floor of [`SimdRow::max_rel_err_f32`]: errors are divided by
/// `max(|f64 value|, REL_FLOOR · max over the rays of |f64 value|)`.
pub const REL_FLOOR: f64 = 1e-3;
/// Points per chunk of the direct DFT (sizes its scratch).
const DFT_CHUNK: usize = 128;

/// One integrand × primitive: cost per evaluation of the `f64` path and the
/// `f32` paths, and the error of the `f32` SIMD path against the `f64` path.
///
/// All three paths integrate the same `R` rays `o + t·ω`, `t ∈ [t0, t1]`, in
/// free space through the boxed integrand of [`IntegrandSpec::build`] (so the
/// two scalar paths pay one virtual call per ray, the batch one per `R`
/// rays, as in the lab); the `f32` inputs are the `f64` inputs rounded to
/// `f32`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimdRow {
    /// Integrand name ([`crate::integrand::IntegrandKind::name`]).
    pub integrand: String,
    /// Dimension `D`.
    pub dims: usize,
    /// `"segments"` or `"lines"` ([`Primitive::name`]).
    pub primitive: String,
    /// `R`, the number of distinct rays: one pass of a path evaluates each ray
    /// once, and a timed repeat of a path is a whole number (≥ 1) of passes,
    /// calibrated **per path** so that the repeat lasts at least
    /// [`MIN_REPEAT`] (so a repeat holds at least `R` evaluations; the paths
    /// differ in cost by up to a few hundred times, so one shared pass count
    /// would make the `f64` repeats needlessly long).
    pub evaluations: u64,
    /// Median ns per evaluation of the exact path: one
    /// [`Integrand::segment_free`] call per ray on the `f64` inputs.
    pub ns_f64: f64,
    /// Median ns per evaluation of the `f32` scalar path: one
    /// [`Integrand::segment_free_f32`] call per ray.
    pub ns_f32_scalar: f64,
    /// Median ns per evaluation of the SIMD path: one
    /// [`Integrand::segment_free_batch_f32`] call over all `R` rays.
    pub ns_f32_simd: f64,
    /// `max_i |s_i − e_i|`, `s_i` the SIMD value (on the rounded inputs), `e_i`
    /// the `f64` value of ray `i`.
    pub max_abs_err_f32: f64,
    /// `sqrt((1/R)·Σ_i (s_i − e_i)²)`.
    pub rms_abs_err_f32: f64,
    /// `max_i |s_i − e_i| / max(|e_i|, σ)` with `σ = REL_FLOOR · max_i |e_i|`
    /// ([`REL_FLOOR`] `= 10⁻³`), so values near zero do not dominate; if every
    /// `e_i` is 0, `σ = 1` (the absolute error).
    pub max_rel_err_f32: f64,
}

/// One NUFFT tolerance, or the exact direct sum, on one point set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NufftRow {
    /// Dimension `D`.
    pub dims: usize,
    /// Number of points `N`.
    pub n: usize,
    /// Grid half-width `K` (frequencies `[−K, K]^D`, stored as a half grid).
    pub k: usize,
    /// `"exact"` ([`Dft::add_points`]) or `"nufft"` ([`Plan::transform_into`]).
    pub method: String,
    /// Requested NUFFT tolerance (0 for exact; the plan clamps it to
    /// `[MIN_TOL, MAX_TOL]` of `linesample_nufft`).
    pub tol: f64,
    /// Median seconds per transform of all `N` points (exact: zeroing the
    /// accumulator and adding the points; NUFFT: one `transform_into` with
    /// plan construction excluded).
    pub seconds: f64,
    /// NUFFT plan construction ([`Plan::new`]): median over `repeats`
    /// constructions, each timed once (0 for exact).
    pub plan_seconds: f64,
    /// `max_ν |F(ν) − F_exact(ν)| / max_ν |F_exact(ν)|` over the stored half-grid
    /// cells (0 for exact).
    pub max_rel_err: f64,
    /// `sqrt(Σ_ν |F(ν) − F_exact(ν)|² / Σ_ν |F_exact(ν)|²)` over the stored
    /// half-grid cells, each cell once (0 for exact).
    pub rms_rel_err: f64,
}

/// Median seconds per call of `f` (method in the [module docs](self)): one
/// warm-up call, calibration of the calls per repeat to last at least
/// [`MIN_REPEAT`], then `repeats` timed repeats.
fn time_per_call(repeats: usize, mut f: impl FnMut() -> Result<()>) -> Result<f64> {
    let mut repeat = |calls: u64| {
        let t = Instant::now();
        for _ in 0..calls {
            f()?;
        }
        Ok::<_, LabError>(t.elapsed().as_secs_f64())
    };
    repeat(1)?;
    let mut calls = 1u64;
    loop {
        let secs = repeat(calls)?;
        if secs >= MIN_REPEAT.as_secs_f64() || calls >= MAX_CALLS {
            break;
        }
        // Aim 20 % past the target, growing by a factor between 2 and 16.
        let want = (calls as f64 * 1.2 * MIN_REPEAT.as_secs_f64() / secs.max(1e-9)).ceil();
        calls = (want as u64).clamp(2 * calls, 16 * calls).min(MAX_CALLS);
    }
    let mut times = empty(repeats, "timing repeats")?;
    for _ in 0..repeats {
        times.push(repeat(calls)? / calls as f64);
    }
    Ok(median(&mut times))
}

/// The median (mean of the middle two for an even count); `v` is not empty.
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// A uniform `f64` in `[0, 1)` from 53 bits of two PCG32 outputs.
fn uniform(g: &mut Pcg32) -> f64 {
    let hi = u64::from(g.next_u32());
    let lo = u64::from(g.next_u32());
    ((hi << 21) | (lo >> 11)) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A uniform random unit direction (rejection from the cube `[−1, 1]^D`).
fn random_direction<const D: usize>(g: &mut Pcg32) -> Result<Direction<D>> {
    for _ in 0..1000 {
        let v: [f64; D] = core::array::from_fn(|_| 2.0 * uniform(g) - 1.0);
        let r2: f64 = v.iter().map(|x| x * x).sum();
        if (1e-6..=1.0).contains(&r2) {
            return Direction::new(v).map_err(|e| LabError::Internal(format!("direction: {e}")));
        }
    }
    Err(LabError::Internal(
        "no random direction in 1000 draws".into(),
    ))
}

/// Checks `name ≥ 1`.
fn at_least_one(name: &str, v: usize) -> Result<()> {
    if v == 0 {
        Err(LabError::Message(format!(
            "{name} must be at least 1, got 0"
        )))
    } else {
        Ok(())
    }
}

/// Times the `f64`, `f32` scalar and `f32` SIMD ray integrals of one integrand
/// on `evaluations` random rays of `primitive` (the number of rays `R`; see
/// [`SimdRow::evaluations`] for the evaluations per timed repeat), `repeats`
/// timed repeats per path, rays drawn from `seed`.
///
/// Rays (`D = spec.dims`, 2 or 3): **segments** of length [`SEGMENT_LENGTH`]
/// with a uniform centre `c ∈ [0, 1)^D` and a uniform unit direction `ω`, as
/// the ray `o = c − (λ/2)·ω`, `t ∈ [0, λ]`; **lines** along the last axis
/// through a uniform offset `y ∈ [0, 1)^{D−1}`, `o = (y, 0)`, `t ∈ [0, 1]`.
///
/// # Errors
/// A message naming the parameter for `primitive = points`, `evaluations = 0`,
/// `repeats = 0`, `dims ∉ {2, 3}`, an integrand that cannot be built, buffers
/// that cannot be allocated, or a non-finite value from any path.
pub fn simd_case(
    spec: &IntegrandSpec,
    primitive: Primitive,
    evaluations: usize,
    repeats: usize,
    seed: u64,
) -> Result<SimdRow> {
    if primitive == Primitive::Points {
        return Err(LabError::Usage(
            "primitive points: the f32 SIMD paths integrate along rays; use segments or lines"
                .into(),
        ));
    }
    at_least_one("evaluations", evaluations)?;
    at_least_one("repeats", repeats)?;
    if !(2..=3).contains(&spec.dims) {
        return Err(LabError::Message(format!(
            "dims {}: the SIMD timing supports 2 or 3 dimensions",
            spec.dims
        )));
    }
    if let Params::Edge { normal, .. } = &spec.params {
        if normal.len() != spec.dims {
            let (got, d) = (normal.len(), spec.dims);
            return Err(LabError::Usage(format!(
                "--normal: {got} components for dims {d}"
            )));
        }
    }
    with_dims!(domain spec.dims, simd_dim(spec, primitive, evaluations, repeats, seed))
}

/// [`simd_case`] in `D` dimensions (`E = D − 1` is unused).
fn simd_dim<const D: usize, const E: usize>(
    spec: &IntegrandSpec,
    primitive: Primitive,
    rays: usize,
    repeats: usize,
    seed: u64,
) -> Result<SimdRow> {
    let integrand = spec.build::<D>()?;
    let f: &dyn Integrand<D> = &*integrand;
    let mut g = Seed::new(seed).pcg(0x5449_4d45); // "TIME"
    let lines = primitive == Primitive::Lines;
    let len = if lines { 1.0 } else { SEGMENT_LENGTH };
    let axis = Direction::axis(D - 1).map_err(|e| LabError::Internal(e.to_string()))?;
    let mut origin = empty::<[f64; D]>(rays, "ray origins")?;
    let mut dir = empty::<Direction<D>>(rays, "ray directions")?;
    for _ in 0..rays {
        let c: [f64; D] = core::array::from_fn(|_| uniform(&mut g));
        let w = if lines {
            axis
        } else {
            random_direction(&mut g)?
        };
        let v = w.get();
        // Lines: (y, 0) with y = the first D − 1 coordinates; segments: c − (λ/2)·ω.
        origin.push(core::array::from_fn(|j| match (lines, j + 1 == D) {
            (true, true) => 0.0,
            (true, false) => c[j],
            (false, _) => c[j] - 0.5 * len * v[j],
        }));
        dir.push(w);
    }
    let (t0, t1) = (
        filled(rays, 0.0, "ray starts")?,
        filled(rays, len, "ray ends")?,
    );
    let mut o32: [Vec<f32>; D] = core::array::from_fn(|_| Vec::new());
    let mut d32 = o32.clone();
    for (j, (o, d)) in o32.iter_mut().zip(&mut d32).enumerate() {
        *o = empty(rays, "f32 ray origins")?;
        o.extend(origin.iter().map(|p| p[j] as f32));
        *d = empty(rays, "f32 ray directions")?;
        d.extend(dir.iter().map(|w| w.get()[j] as f32));
    }
    let t0_32 = filled(rays, 0.0f32, "f32 ray starts")?;
    let t1_32 = filled(rays, len as f32, "f32 ray ends")?;
    let batch = Rays32 {
        origin: core::array::from_fn(|j| &o32[j][..]),
        dir: core::array::from_fn(|j| &d32[j][..]),
        t0: &t0_32,
        t1: &t1_32,
    };

    let mut out64 = filled(rays, 0.0f64, "f64 outputs")?;
    let mut out32 = filled(rays, 0.0f32, "f32 scalar outputs")?;
    let mut simd = filled(rays, 0.0f32, "f32 SIMD outputs")?;
    let run64 = || {
        let (o, w) = (black_box(&origin[..]), black_box(&dir[..]));
        for (i, out) in out64.iter_mut().enumerate() {
            *out = f.segment_free(&o[i], &w[i], t0[i], t1[i]);
        }
        black_box(&mut out64[..]);
        Ok(())
    };
    let run32 = || {
        let r = black_box(&batch);
        for (i, out) in out32.iter_mut().enumerate() {
            let o = core::array::from_fn(|j| r.origin[j][i]);
            let d = core::array::from_fn(|j| r.dir[j][i]);
            *out = f.segment_free_f32(o, d, r.t0[i], r.t1[i]);
        }
        black_box(&mut out32[..]);
        Ok(())
    };
    let run_simd = || {
        f.segment_free_batch_f32(black_box(&batch), &mut simd)
            .map_err(|e| LabError::Internal(format!("SIMD batch: {e}")))?;
        black_box(&mut simd[..]);
        Ok(())
    };
    let ns = |s: f64| s * 1e9 / rays as f64;
    let ns_f32_simd = ns(time_per_call(repeats, run_simd)?);
    let ns_f32_scalar = ns(time_per_call(repeats, run32)?);
    let ns_f64 = ns(time_per_call(repeats, run64)?);

    for (i, (&e, (&s32, &s))) in out64.iter().zip(out32.iter().zip(&simd)).enumerate() {
        for (path, v) in [
            ("f64", e),
            ("f32 scalar", s32.into()),
            ("f32 SIMD", s.into()),
        ] {
            if !f64::is_finite(v) {
                let (kind, prim) = (spec.kind.name(), primitive.name());
                return Err(LabError::Message(format!(
                    "{kind} {prim}: the {path} path gave {v} on ray {i}"
                )));
            }
        }
    }
    let peak = out64.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    let floor = if peak > 0.0 { REL_FLOOR * peak } else { 1.0 };
    let (mut max_abs, mut sum2, mut max_rel) = (0.0f64, 0.0f64, 0.0f64);
    for (&e, &s) in out64.iter().zip(&simd) {
        let d = (f64::from(s) - e).abs();
        max_abs = max_abs.max(d);
        sum2 += d * d;
        max_rel = max_rel.max(d / e.abs().max(floor));
    }
    Ok(SimdRow {
        integrand: spec.kind.name().into(),
        dims: D,
        primitive: primitive.name().into(),
        evaluations: rays as u64,
        ns_f64,
        ns_f32_scalar,
        ns_f32_simd,
        max_abs_err_f32: max_abs,
        rms_abs_err_f32: (sum2 / rays as f64).sqrt(),
        max_rel_err_f32: max_rel,
    })
}

/// Times the exact direct DFT and the NUFFT at each tolerance of `tols` on `n`
/// uniform random points in `[0, 1)^D` (the kernel's [`Random`] pattern,
/// seed `seed`, `f32` coordinates widened to `f64`), half-width `k`, `repeats`
/// timed repeats each. Rows: the exact one first, then one per tolerance in
/// the order given.
///
/// # Errors
/// A message naming the parameter for `dims ∉ {1, 2, 3}`, `n = 0`,
/// `repeats = 0`, a `k` the kernel's [`Grid::new`] rejects, a tolerance that
/// is not a finite number `> 0`, or a plan or buffer that cannot be allocated.
pub fn nufft_sweep(
    dims: usize,
    n: usize,
    k: usize,
    tols: &[f64],
    repeats: usize,
    seed: u64,
) -> Result<Vec<NufftRow>> {
    if !(1..=3).contains(&dims) {
        return Err(LabError::Message(format!(
            "dims {dims}: the NUFFT sweep supports 1, 2 or 3 dimensions"
        )));
    }
    at_least_one("n", n)?;
    at_least_one("repeats", repeats)?;
    if let Some(t) = tols.iter().find(|t| !(t.is_finite() && **t > 0.0)) {
        return Err(LabError::Message(format!(
            "tol {t}: must be a finite number > 0"
        )));
    }
    with_dims!(dims, dims, nufft_dim(n, k, tols, repeats, seed))
}

/// [`nufft_sweep`] in `D` dimensions (`E = D` is unused).
fn nufft_dim<const D: usize, const E: usize>(
    n: usize,
    k: usize,
    tols: &[f64],
    repeats: usize,
    seed: u64,
) -> Result<Vec<NufftRow>> {
    let grid = Grid::<D>::new(k).map_err(|e| format!("k {k}: {e}"))?;
    let pattern = Random::<D>::new(n).map_err(|e| format!("n {n}: {e}"))?;
    let mut p32 = filled(n, [0.0f32; D], "points")?;
    pattern
        .fill(Seed::new(seed), &mut p32)
        .map_err(|e| LabError::Internal(format!("points: {e}")))?;
    let mut points = empty::<[f64; D]>(n, "points (f64)")?;
    points.extend(p32.iter().map(|p| p.map(f64::from)));
    drop(p32);

    let scratch_len = DFT_CHUNK * Dft::<D, Vec<f64>>::points_scratch_per_sample(grid);
    let mut scratch = filled(scratch_len, 0.0, "DFT scratch")?;
    let buf = filled(Dft::<D, Vec<f64>>::buffer_len(grid), 0.0, "DFT amplitudes")?;
    let mut dft = Dft::new(grid, buf).map_err(|e| LabError::Internal(e.to_string()))?;
    let exact = || {
        dft.clear();
        dft.add_points(black_box(&points[..]), &mut scratch)
            .map_err(|e| format!("points: {e}"))?;
        black_box(&dft);
        Ok(())
    };
    let seconds = time_per_call(repeats, exact)?;
    // The exact amplitudes in grid order (the Dft's storage rows are padded).
    let mut ex_re = filled(grid.len(), 0.0, "exact amplitudes")?;
    let mut ex_im = filled(grid.len(), 0.0, "exact amplitudes")?;
    for (i, (re, im)) in ex_re.iter_mut().zip(&mut ex_im).enumerate() {
        let c = dft.amplitude_at(i);
        (*re, *im) = (c.re, c.im);
    }
    drop(dft);
    let row = |method: &str, tol, seconds, plan_seconds, (max_rel_err, rms_rel_err)| NufftRow {
        dims: D,
        n,
        k,
        method: method.into(),
        tol,
        seconds,
        plan_seconds,
        max_rel_err,
        rms_rel_err,
    };
    let mut rows = empty(tols.len() + 1, "rows")?;
    rows.push(row("exact", 0.0, seconds, 0.0, (0.0, 0.0)));

    let buf = filled(
        Amplitudes::<D, Vec<f64>>::buffer_len(grid),
        0.0,
        "NUFFT amplitudes",
    )?;
    let mut amps = Amplitudes::new(grid, buf).map_err(|e| LabError::Internal(e.to_string()))?;
    for &tol in tols {
        let mut plan_times = empty(repeats, "plan timings")?;
        let mut build = || {
            let t = Instant::now();
            let p = Plan::<D>::new(k, tol)
                .map_err(|e| LabError::Message(format!("tol {tol}, k {k}: {e}")))?;
            plan_times.push(t.elapsed().as_secs_f64());
            Ok::<_, LabError>(black_box(p))
        };
        let mut plan = build()?;
        for _ in 1..repeats {
            plan = build()?;
        }
        let run = || {
            plan.transform_into(black_box(&points[..]), &mut amps)
                .map_err(|e| format!("tol {tol}: {e}"))?;
            black_box(&amps);
            Ok(())
        };
        let seconds = time_per_call(repeats, run)?;
        let (re, im) = amps.parts();
        let errs = rel_errors(&ex_re, &ex_im, re, im);
        rows.push(row("nufft", tol, seconds, median(&mut plan_times), errs));
    }
    Ok(rows)
}

/// `(max_ν |F − E| / max_ν |E|, sqrt(Σ|F − E|² / Σ|E|²))` for amplitudes
/// `F = re + i·im` against `E = ex_re + i·ex_im` (`E ≠ 0` somewhere: `E(0) = N`).
fn rel_errors(ex_re: &[f64], ex_im: &[f64], re: &[f64], im: &[f64]) -> (f64, f64) {
    let (mut max_d, mut max_e, mut sum_d, mut sum_e) = (0.0f64, 0.0f64, 0.0, 0.0);
    let exact = ex_re.iter().zip(ex_im);
    for ((&er, &ei), (&r, &i)) in exact.zip(re.iter().zip(im)) {
        let (dr, di) = (r - er, i - ei);
        let d2 = dr * dr + di * di;
        let e2 = er * er + ei * ei;
        max_d = max_d.max(d2.sqrt());
        max_e = max_e.max(e2.sqrt());
        sum_d += d2;
        sum_e += e2;
    }
    (max_d / max_e, (sum_d / sum_e).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrand::{IntegrandKind, DEFAULT_RADIUS};

    fn ball(kind: IntegrandKind, dims: usize) -> IntegrandSpec {
        let params = Params::Ball {
            radius: DEFAULT_RADIUS,
        };
        IntegrandSpec { kind, dims, params }
    }

    /// Runs one case on 256 rays and checks the row.
    fn check_case(kind: IntegrandKind, dims: usize, primitive: Primitive) {
        let r = simd_case(&ball(kind, dims), primitive, 256, 3, 7).unwrap();
        let names = (r.integrand.as_str(), r.primitive.as_str());
        assert_eq!(
            (names, r.dims, r.evaluations),
            ((kind.name(), primitive.name()), dims, 256)
        );
        for t in [r.ns_f64, r.ns_f32_scalar, r.ns_f32_simd] {
            assert!(t.is_finite() && t > 0.0, "{r:?}");
        }
        // The kernel states ≲ 1e-6·r well inside the ball (more only within
        // ~1e-6·r of tangency); 1e-4 leaves a wide margin.
        assert!(r.max_abs_err_f32 < 1e-4, "{r:?}");
        assert!(r.rms_abs_err_f32 <= r.max_abs_err_f32, "{r:?}");
        assert!(r.max_rel_err_f32 < 1e-3, "{r:?}");
        // The comparison compares different paths: f32 differs from f64 somewhere.
        assert!(r.max_abs_err_f32 > 0.0, "{r:?}");
    }

    #[test]
    fn simd_disk_segments_and_ball_lines() {
        check_case(IntegrandKind::Disk, 2, Primitive::Segments);
        check_case(IntegrandKind::Ball, 3, Primitive::Lines);
    }

    #[test]
    fn simd_rejects_bad_input() {
        let disk = ball(IntegrandKind::Disk, 2);
        let e = simd_case(&disk, Primitive::Points, 16, 1, 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("points"), "{e}");
        let e = simd_case(&disk, Primitive::Lines, 0, 1, 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("evaluations"), "{e}");
        let e = simd_case(&disk, Primitive::Lines, 16, 0, 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("repeats"), "{e}");
        let e = simd_case(&ball(IntegrandKind::Ball, 4), Primitive::Lines, 16, 1, 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("dims 4"), "{e}");
        let bad = IntegrandSpec {
            params: Params::Ball { radius: -1.0 },
            ..disk
        };
        let e = simd_case(&bad, Primitive::Segments, 16, 1, 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("--radius"), "{e}");
        let edge = IntegrandSpec {
            kind: IntegrandKind::Edge,
            dims: 3,
            params: Params::Edge {
                normal: vec![1.0, 0.0],
                offset: 0.5,
            },
        };
        let e = simd_case(&edge, Primitive::Lines, 16, 1, 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("--normal"), "{e}");
    }

    #[test]
    fn nufft_sweep_errors_follow_tolerance() {
        let rows = nufft_sweep(2, 200, 8, &[1e-3, 1e-9], 3, 5).unwrap();
        assert_eq!(rows.len(), 3);
        let methods: Vec<_> = rows.iter().map(|r| r.method.as_str()).collect();
        assert_eq!(methods, ["exact", "nufft", "nufft"]);
        let ex = &rows[0];
        assert_eq!(
            (ex.max_rel_err, ex.rms_rel_err, ex.tol, ex.plan_seconds),
            (0.0, 0.0, 0.0, 0.0)
        );
        for r in &rows {
            assert_eq!((r.dims, r.n, r.k), (2, 200, 8));
            assert!(r.seconds.is_finite() && r.seconds > 0.0, "{r:?}");
        }
        for r in &rows[1..] {
            assert!(r.plan_seconds > 0.0, "{r:?}");
            assert!(r.max_rel_err < 10.0 * r.tol, "{r:?}");
            assert!(r.rms_rel_err < 10.0 * r.tol, "{r:?}");
            assert!(r.max_rel_err > 0.0, "{r:?}");
        }
        assert!(rows[2].max_rel_err < rows[1].max_rel_err, "{rows:?}");
    }

    #[test]
    fn nufft_sweep_rejects_bad_input() {
        let err = |dims, n, k, tols: &[f64], repeats| {
            nufft_sweep(dims, n, k, tols, repeats, 1)
                .unwrap_err()
                .to_string()
        };
        for (e, want) in [
            (err(4, 10, 4, &[1e-6], 1), "dims 4"),
            (err(2, 0, 4, &[1e-6], 1), "n must"),
            (err(2, 10, 0, &[1e-6], 1), "k 0"),
            (err(2, 10, 4, &[1e-6], 0), "repeats"),
            (err(2, 10, 4, &[0.0], 1), "tol 0"),
            (err(2, 10, 4, &[f64::NAN], 1), "tol NaN"),
            (err(2, 10, 4, &[1e-3, f64::INFINITY], 1), "tol inf"),
        ] {
            assert!(e.contains(want), "{e} (want {want})");
        }
    }

    #[test]
    fn median_and_uniform() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
        let mut g = Seed::new(1).pcg(0);
        assert!((0..1000)
            .map(|_| uniform(&mut g))
            .all(|u| (0.0..1.0).contains(&u)));
    }
}
