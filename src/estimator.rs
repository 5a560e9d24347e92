//! Monte Carlo estimators with point, segment and line samples (Singh, Miller &
//! Jarosz 2017; derivations in `docs/theory.md`, Estimators), driven by any
//! [`Pattern`].
//!
//! | estimator | summand | `N` counts |
//! |---|---|---|
//! | [`PointEstimator`] | `f(x_k)` | points |
//! | [`SegmentEstimator`] | `(1/λ)∫_{−λ/2}^{λ/2} f(c_k + tω_k) dt` (wrapped) | segments |
//! | [`LineEstimator`] | `A·∫_{chord} f(y_k + tω) dt` | lines |
//!
//! * Homogenisation: with `homogenise = true` every realisation adds a uniform
//!   random toroidal shift (in `f64`) to the pattern, drawn from the seed, so the
//!   estimator is unbiased and the variance is that of the stationary process
//!   the theory describes (Pilleboue et al. 2015; `docs/theory.md`,
//!   Homogenisation and the toroidal shift).
//! * Segments: the centres come from a `D`-dimensional pattern and the segments
//!   wrap on the torus, so the mean along a segment integrates to `∫ f` over
//!   the centres (Fubini): the estimator is unbiased for uniformly distributed
//!   centres, and its pdf-weighted form would be unbiased for any centre
//!   density (`docs/theory.md`, Estimators).
//! * Lines along an axis are torus lines (offsets in `[0,1)^{D−1}`). Lines in any
//!   other direction are clipped to the unit box (`docs/theory.md`, Lines on
//!   the torus); their offsets are drawn on the
//!   bounding rectangle `R` of the box's projection onto `ω^⊥` (in the basis
//!   [`Direction::frame`]) and the estimator multiplies by its area `A = |R|`
//!   (lines that miss the box contribute 0). For axis directions `A = 1` and both
//!   conventions coincide.
//! * Direction groups ([`Directions::Groups`]): `K` directions, each with its own
//!   independent realisation of the pattern (`pattern.len()` primitives per
//!   group, `N = K·pattern.len()`); the estimate is the mean of the group
//!   estimates, so `Var = (1/K²) Σ_j Var_j` (`docs/theory.md`, Estimators).
//!
//! Estimators never allocate: the caller passes `scratch` (`f32` words, length
//! [`Estimator::scratch_len`]) for the pattern points. A seed fixes the estimate.

use crate::error::{EstimateError, ParamError};
#[cfg(test)]
use crate::geom::dot;
use crate::geom::Direction;
use crate::integrand::{check_dim, Integrand};
use crate::num::frac;
use crate::pattern::{Pattern, Shifted};
use crate::primitive::{check_length, Line, Segment};
use crate::rng::{mix64, Seed};
use crate::stats::RunningStats;

/// Seed purpose of the estimator's homogenisation shift.
const SHIFT_PURPOSE: u64 = 0x4553_5453_4849_4654;
/// Seed purpose of random directions.
const DIRECTION_PURPOSE: u64 = 0x4553_5444_4952_0000;
/// Seed purpose of the per-group pattern realisations.
const GROUP_PURPOSE: u64 = 0x4553_5447_524f_5550;

/// How primitives are oriented.
#[derive(Clone, Copy, Debug)]
pub enum Directions<'a, const D: usize> {
    /// One fixed direction for all primitives.
    Fixed(Direction<D>),
    /// An independent uniformly distributed direction on `S^{D−1}` per primitive
    /// (a function of the seed and the primitive's index only).
    Random,
    /// `K` groups, each with its own fixed direction and an independent
    /// realisation of the pattern.
    Groups(&'a [Direction<D>]),
}

/// A Monte Carlo estimator of `∫_{[0,1)^D} f`. Object safe.
pub trait Estimator<const D: usize> {
    /// `N`, the number of primitives per realisation.
    fn count(&self) -> usize;

    /// Length of the `f32` scratch buffer [`Estimator::estimate`] needs.
    fn scratch_len(&self) -> usize;

    /// One estimate of `∫ f` for `seed` (a realisation seed, e.g.
    /// `Seed::new(s).realization(r)`).
    ///
    /// # Errors
    /// [`ParamError::Length`] (`scratch`) if `scratch` is shorter than
    /// [`Estimator::scratch_len`]; pattern errors are passed through.
    fn estimate(
        &self,
        f: &dyn Integrand<D>,
        seed: Seed,
        homogenise: bool,
        scratch: &mut [f32],
    ) -> Result<f64, EstimateError>;
}

/// Runs realisations `first .. first + count` (realisation `r` uses
/// `seed.realization(r)`) and returns their statistics (sequential, so the
/// result is a function of the arguments only; split the range and
/// [`RunningStats::merge`] the parts in order to parallelise).
///
/// # Errors
/// As [`Estimator::estimate`].
pub fn run_realisations<const D: usize>(
    est: &dyn Estimator<D>,
    f: &dyn Integrand<D>,
    seed: Seed,
    first: u64,
    count: u64,
    homogenise: bool,
    scratch: &mut [f32],
) -> Result<RunningStats, EstimateError> {
    let mut st = RunningStats::new();
    for r in first..first.saturating_add(count) {
        st.push(est.estimate(f, seed.realization(r), homogenise, scratch)?);
    }
    Ok(st)
}

/// The homogenisation shift of a realisation (zero when `homogenise` is off).
fn shift_for<const K: usize>(seed: Seed, homogenise: bool) -> [f64; K] {
    if homogenise {
        Shifted::<()>::shift::<K>(Seed::new(seed.stream(SHIFT_PURPOSE)))
    } else {
        [0.0; K]
    }
}

/// Pattern points (with the shift) into `scratch`, as `[f32; K]`.
fn fill_points<'s, const K: usize>(
    pattern: &dyn Pattern<K>,
    seed: Seed,
    scratch: &'s mut [f32],
) -> Result<&'s mut [[f32; K]], EstimateError> {
    let need = pattern.len() * K;
    if scratch.len() < need {
        return Err(ParamError::Length {
            name: "scratch",
            expected: need,
            got: scratch.len(),
        }
        .into());
    }
    let pts: &mut [[f32; K]] = bytemuck::cast_slice_mut(&mut scratch[..need]);
    pattern.fill(seed, pts)?;
    Ok(pts)
}

/// `(1/N) Σ_k summand(k, y_k)` over the pattern's points `y_k`, shifted (in
/// `f64`, modulo 1) by the realisation's homogenisation shift.
fn mean_over_pattern<const K: usize>(
    pattern: &dyn Pattern<K>,
    seed: Seed,
    homogenise: bool,
    scratch: &mut [f32],
    mut summand: impl FnMut(usize, &[f64; K]) -> f64,
) -> Result<f64, EstimateError> {
    let s = shift_for::<K>(seed, homogenise);
    let pts = fill_points(pattern, seed, scratch)?;
    let mut sum = 0.0;
    for (k, x) in pts.iter().enumerate() {
        sum += summand(k, &shifted_point(x, &s));
    }
    Ok(sum / pts.len() as f64)
}

#[inline]
fn shifted_point<const K: usize>(x: &[f32; K], s: &[f64; K]) -> [f64; K] {
    let mut y = [0.0; K];
    for j in 0..K {
        y[j] = frac(f64::from(x[j]) + s[j]);
    }
    y
}

/// Uniform direction on `S^{D−1}` for primitive `k` (D = 2: angle `2πu`;
/// D = 3: `z = 1 − 2u`, azimuth `2πv`, Archimedes' hat-box theorem).
fn random_direction<const D: usize>(seed: Seed, k: usize) -> Direction<D> {
    let h = mix64(seed.stream(DIRECTION_PURPOSE) ^ mix64(k as u64));
    let u = (h >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0);
    let h2 = mix64(h ^ 0x9e37_79b9_7f4a_7c15);
    let v = (h2 >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0);
    let tau = core::f64::consts::TAU;
    let mut w = [0.0; D];
    if D == 2 {
        w[0] = libm::cos(tau * u);
        w[1] = libm::sin(tau * u);
    } else {
        let z = 1.0 - 2.0 * u;
        let r = crate::num::scalar::sqrt((1.0 - z * z).max(0.0));
        w[0] = r * libm::cos(tau * v);
        w[1] = r * libm::sin(tau * v);
        w[2] = z;
    }
    // Finite and unit up to rounding by construction.
    Direction::from_unit(w)
}

/// Rejects an empty group list.
fn check_groups<const D: usize>(dirs: &Directions<'_, D>) -> Result<(), ParamError> {
    match dirs {
        Directions::Groups([]) => Err(ParamError::Count {
            name: "directions",
            value: 0,
        }),
        _ => Ok(()),
    }
}

/// Number of pattern realisations per estimate: `K` for groups, else 1.
fn group_count<const D: usize>(dirs: &Directions<'_, D>) -> usize {
    match dirs {
        Directions::Groups(g) => g.len(),
        _ => 1,
    }
}

/// Runs `group(seed, direction)` once per direction group (`None`: random
/// directions) and averages: group `j` of a [`Directions::Groups`] list gets
/// its own seed stream, so its pattern realisation is independent.
fn over_groups<const D: usize>(
    dirs: &Directions<'_, D>,
    seed: Seed,
    mut group: impl FnMut(Seed, Option<Direction<D>>) -> Result<f64, EstimateError>,
) -> Result<f64, EstimateError> {
    match *dirs {
        Directions::Fixed(d) => group(seed, Some(d)),
        Directions::Random => group(seed, None),
        Directions::Groups(g) => {
            let mut sum = 0.0;
            for (j, d) in g.iter().enumerate() {
                sum += group(Seed::new(seed.stream(GROUP_PURPOSE ^ j as u64)), Some(*d))?;
            }
            Ok(sum / g.len() as f64)
        }
    }
}

/// Point estimator `Î = (1/N) Σ f(x_k)` with `x_k` from a `D`-dimensional pattern.
#[derive(Clone, Copy)]
pub struct PointEstimator<'p, const D: usize> {
    pattern: &'p dyn Pattern<D>,
}

impl<const D: usize> core::fmt::Debug for PointEstimator<'_, D> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PointEstimator")
            .field("n", &self.pattern.len())
            .finish()
    }
}

impl<'p, const D: usize> PointEstimator<'p, D> {
    /// Points from `pattern`.
    ///
    /// # Errors
    /// [`ParamError::Dimension`] unless `D ∈ {2, 3}`.
    pub fn new(pattern: &'p dyn Pattern<D>) -> Result<Self, ParamError> {
        check_dim::<D>()?;
        Ok(Self { pattern })
    }
}

impl<const D: usize> Estimator<D> for PointEstimator<'_, D> {
    fn count(&self) -> usize {
        self.pattern.len()
    }
    fn scratch_len(&self) -> usize {
        self.pattern.len() * D
    }
    fn estimate(
        &self,
        f: &dyn Integrand<D>,
        seed: Seed,
        homogenise: bool,
        scratch: &mut [f32],
    ) -> Result<f64, EstimateError> {
        mean_over_pattern(self.pattern, seed, homogenise, scratch, |_, x| f.value(x))
    }
}

/// Point estimator with a sampling density: `Î = (1/N) Σ f(x_k)/p(x_k)` for
/// points `x_k` distributed with density `p` on the torus (the caller warps the
/// pattern). Points with `p = 0` contribute 0.
pub fn point_estimate_pdf<const D: usize>(
    f: &dyn Integrand<D>,
    points: &[[f64; D]],
    pdf: impl Fn(&[f64; D]) -> f64,
) -> f64 {
    if points.is_empty() {
        return 0.0;
    }
    let sum: f64 = points
        .iter()
        .map(|x| {
            let p = pdf(x);
            if p > 0.0 {
                f.value(x) / p
            } else {
                0.0
            }
        })
        .sum();
    sum / points.len() as f64
}

/// Segment estimator `Î = (1/N) Σ (1/λ)∫_{−λ/2}^{λ/2} f(c_k + tω_k) dt` with
/// centres from a `D`-dimensional pattern and segments wrapped on the torus.
#[derive(Clone, Copy)]
pub struct SegmentEstimator<'p, const D: usize> {
    pattern: &'p dyn Pattern<D>,
    length: f64,
    dirs: Directions<'p, D>,
}

impl<const D: usize> core::fmt::Debug for SegmentEstimator<'_, D> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SegmentEstimator")
            .field("n", &self.count())
            .field("length", &self.length)
            .field("dirs", &self.dirs)
            .finish()
    }
}

impl<'p, const D: usize> SegmentEstimator<'p, D> {
    /// Segments of length `λ` (`0 ≤ λ ≤` [`MAX_SEGMENT_LENGTH`](crate::geom::MAX_SEGMENT_LENGTH); `λ = 0` is the
    /// point estimator).
    ///
    /// # Errors
    /// [`ParamError::Dimension`], [`ParamError::NonFinite`] / `OutOfRange`
    /// (`length`), [`ParamError::Count`] (`directions`) for an empty group list.
    pub fn new(
        pattern: &'p dyn Pattern<D>,
        length: f64,
        dirs: Directions<'p, D>,
    ) -> Result<Self, ParamError> {
        check_dim::<D>()?;
        let length = check_length(length)?;
        check_groups(&dirs)?;
        Ok(Self {
            pattern,
            length,
            dirs,
        })
    }
}

impl<const D: usize> Estimator<D> for SegmentEstimator<'_, D> {
    fn count(&self) -> usize {
        self.pattern.len() * group_count(&self.dirs)
    }
    fn scratch_len(&self) -> usize {
        self.pattern.len() * D
    }
    fn estimate(
        &self,
        f: &dyn Integrand<D>,
        seed: Seed,
        homogenise: bool,
        scratch: &mut [f32],
    ) -> Result<f64, EstimateError> {
        over_groups(&self.dirs, seed, |sj, dir| {
            mean_over_pattern(self.pattern, sj, homogenise, scratch, |k, c| {
                let w = dir.unwrap_or_else(|| random_direction::<D>(sj, k));
                f.segment_mean(&Segment::from_parts(*c, w, self.length))
            })
        })
    }
}

/// Line estimator: lines with direction(s) `ω`, offsets from a
/// `K = D − 1`-dimensional pattern on the plane `ω^⊥` (see the module docs for
/// the box convention); `Î = A·(1/N) Σ ∫_{chord} f(y_k + tω) dt`.
#[derive(Clone, Copy)]
pub struct LineEstimator<'p, const D: usize, const K: usize> {
    pattern: &'p dyn Pattern<K>,
    dirs: Directions<'p, D>,
}

impl<const D: usize, const K: usize> core::fmt::Debug for LineEstimator<'_, D, K> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("LineEstimator")
            .field("n", &self.count())
            .field("dirs", &self.dirs)
            .finish()
    }
}

/// The line through the offset `x ∈ [0,1)^{D−1}` (rectangle coordinates) and its
/// rectangle area `A`.
fn offset_line<const D: usize>(dir: &Direction<D>, x: &[f64]) -> (Line<D>, f64) {
    if let Some(a) = dir.as_axis() {
        // Torus line: the offsets are the other coordinates; A = 1.
        let mut p = [0.0; D];
        let mut k = 0;
        for j in 0..D {
            if j != a {
                p[j] = x[k];
                k += 1;
            }
        }
        return (Line::from_parts(p, *dir), 1.0);
    }
    let frame = dir.frame();
    let mut p = [0.0; D];
    let mut area = 1.0;
    for i in 0..D - 1 {
        let u = &frame[i];
        // Range of u·v over the box vertices: Σ_j min/max(0, u_j).
        let lo: f64 = u.iter().map(|&c| c.min(0.0)).sum();
        let hi: f64 = u.iter().map(|&c| c.max(0.0)).sum();
        let y = lo + (hi - lo) * x[i];
        area *= hi - lo;
        for j in 0..D {
            p[j] += y * u[j];
        }
    }
    (Line::from_parts(p, *dir), area)
}

impl<'p, const D: usize, const K: usize> LineEstimator<'p, D, K> {
    /// Lines with offsets from `pattern` (`K = D − 1` dimensions).
    ///
    /// # Errors
    /// [`ParamError::Dimension`] unless `D ∈ {2, 3}` and `K = D − 1`;
    /// [`ParamError::Count`] (`directions`) for an empty group list.
    pub fn new(pattern: &'p dyn Pattern<K>, dirs: Directions<'p, D>) -> Result<Self, ParamError> {
        check_dim::<D>()?;
        if K + 1 != D {
            return Err(ParamError::Dimension { dim: K });
        }
        check_groups(&dirs)?;
        Ok(Self { pattern, dirs })
    }
}

impl<const D: usize, const K: usize> Estimator<D> for LineEstimator<'_, D, K> {
    fn count(&self) -> usize {
        self.pattern.len() * group_count(&self.dirs)
    }
    fn scratch_len(&self) -> usize {
        self.pattern.len() * K
    }
    fn estimate(
        &self,
        f: &dyn Integrand<D>,
        seed: Seed,
        homogenise: bool,
        scratch: &mut [f32],
    ) -> Result<f64, EstimateError> {
        over_groups(&self.dirs, seed, |sj, dir| {
            mean_over_pattern(self.pattern, sj, homogenise, scratch, |k, y| {
                let w = dir.unwrap_or_else(|| random_direction::<D>(sj, k));
                let (line, area) = offset_line(&w, y);
                area * f.line_integral(&line)
            })
        })
    }
}

/// The line estimator's summand `A·∫_{chord} f` at rectangle offset `x`; its
/// mean over `x ∈ [0,1)^{D−1}` is `∫_{box} f` (tested below).
#[cfg(test)]
fn line_summand<const D: usize>(f: &dyn Integrand<D>, dir: &Direction<D>, x: &[f64]) -> f64 {
    let (line, area) = offset_line(dir, x);
    area * f.line_integral(&line)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::Complex;
    use crate::primitive::Rays32;

    /// `F = 1` on the unit box: line integrals are chord lengths of the box.
    #[derive(Debug)]
    struct One;

    impl<const D: usize> Integrand<D> for One {
        fn value_free(&self, x: &[f64; D]) -> f64 {
            f64::from(u8::from(x.iter().all(|v| (0.0..1.0).contains(v))))
        }
        fn segment_free(&self, _: &[f64; D], _: &Direction<D>, t0: f64, t1: f64) -> f64 {
            t1 - t0
        }
        fn segment_free_f32(&self, _: [f32; D], _: [f32; D], t0: f32, t1: f32) -> f32 {
            t1 - t0
        }
        fn segment_free_batch_f32(
            &self,
            _: &Rays32<'_, D>,
            _: &mut [f32],
        ) -> Result<(), ParamError> {
            Ok(())
        }
        fn value(&self, _: &[f64; D]) -> f64 {
            1.0
        }
        fn integral(&self) -> f64 {
            1.0
        }
        fn piece_integral(&self, _: &[f64; D], _: &Direction<D>, t0: f64, t1: f64) -> f64 {
            t1 - t0
        }
        fn max_value(&self) -> f64 {
            1.0
        }
        fn fourier(&self, _: &[i32; D]) -> Complex {
            Complex::default()
        }
    }

    /// The box convention: averaging `A·chord` over the offset rectangle gives
    /// the volume of the box (1), for oblique directions (midpoint rule; the
    /// chord length is piecewise linear in the offset).
    #[test]
    fn box_lines_integrate_the_box() {
        for w in [[1.0, 0.7], [0.2, -1.0], [1.0, 1.0], [-3.0, 0.01]] {
            let d = Direction::new(w).unwrap();
            let m = 200_000;
            let s: f64 = (0..m)
                .map(|i| line_summand::<2>(&One, &d, &[(i as f64 + 0.5) / m as f64]))
                .sum();
            assert!((s / m as f64 - 1.0).abs() < 1e-8, "{w:?}: {}", s / m as f64);
        }
        for w in [[0.3, -0.4, 1.0], [1.0, 1.0, 1.0], [0.0, 0.6, 0.8]] {
            let d = Direction::new(w).unwrap();
            let m = 400;
            let mut s = 0.0;
            for i in 0..m {
                for j in 0..m {
                    let x = [(i as f64 + 0.5) / m as f64, (j as f64 + 0.5) / m as f64];
                    s += line_summand::<3>(&One, &d, &x);
                }
            }
            let mean = s / (m * m) as f64;
            assert!((mean - 1.0).abs() < 1e-4, "{w:?}: {mean}");
        }
        // Axis lines are torus lines: A = 1 and the chord is one period.
        let z = Direction::<3>::axis(2).unwrap();
        assert_eq!(line_summand::<3>(&One, &z, &[0.3, 0.9]), 1.0);
    }

    #[test]
    fn random_directions_are_unit_and_uniform() {
        let seed = Seed::new(5);
        let mut mean = [0.0f64; 3];
        let mut zz = 0.0;
        let n = 20_000;
        for k in 0..n {
            let w = random_direction::<3>(seed, k).get();
            assert!((dot(&w, &w) - 1.0).abs() < 1e-15);
            for j in 0..3 {
                mean[j] += w[j] / n as f64;
            }
            zz += w[2] * w[2] / n as f64;
        }
        // E[w] = 0 (SE 1/√(3n)), E[w_z²] = 1/3 (SE √(4/45/n)); |z| ≤ 5, the
        // suite's rule (tests/README.md).
        let se = (1.0 / (3.0 * n as f64)).sqrt();
        assert!(mean.iter().all(|m| m.abs() < 5.0 * se), "{mean:?}");
        assert!(
            (zz - 1.0 / 3.0).abs() < 5.0 * (4.0 / 45.0 / n as f64).sqrt(),
            "{zz}"
        );
    }
}
