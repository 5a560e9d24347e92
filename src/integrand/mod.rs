//! Integrands with closed-form point, segment and line integrals on the unit
//! torus, and their Fourier coefficients.
//!
//! Every integrand is a free-space function `F : ℝ^D → [0, ∞)` with closed
//! forms, **periodised** on the unit torus by summing its images,
//!
//! ```text
//! f(x) = Σ_{n ∈ ℤ^D} F(x + n),       ∫_{[0,1)^D} f = ∫_{ℝ^D} F,
//! f̂_k = ∫_{[0,1)^D} f(x) e^{−2πi k·x} dx = F̂(k)   (Poisson summation).
//! ```
//!
//! * [`Ball`]: indicator of a disk (2D) or ball (3D), radius `r ≤ 1/2`, so the
//!   periodised indicator takes only the values 0 and 1.
//! * [`Gaussian`]: the normalised isotropic Gaussian density
//!   `(2πσ²)^{−D/2} e^{−|x−c|²/2σ²}` (so `∫ f = 1` for every `σ`).
//! * [`HalfSpace`]: `F = 1[n·x ≥ h]·1_{[0,1)^D}`: a straight edge at any angle,
//!   restricted to the unit box, whose periodisation is `f(x) = F(frac(x))`.
//!
//! Primitives (see [`crate::primitive`]): a [`Segment`] wraps on the torus (its
//! integral is split into pieces, one per unit cell it crosses,
//! [`crate::geom::for_each_piece`]); a [`Line`] is integrated over its chord of
//! the unit box `[0, 1]^D`.
//!
//! Each integrand has an `f64` path accurate to a few ulp (each method states its
//! error) and an `f32` SIMD batch path for free-space rays
//! ([`Integrand::segment_free_batch_f32`]) that agrees bit for bit with its scalar
//! twin ([`Integrand::segment_free_f32`]) and with the `f64` path to a stated bound.

mod ball;
mod gaussian;
mod halfspace;

pub use ball::Ball;
pub use gaussian::Gaussian;
pub use halfspace::HalfSpace;

use crate::error::ParamError;
use crate::geom::{clip_to_unit_box, for_each_piece, Direction};
use crate::num::frac;
use crate::primitive::{Line, Rays32, Segment};

/// Fourier coefficients are [`Complex`] numbers (defined in [`crate::num`]).
pub use crate::num::Complex;

/// An integrand on the unit torus with closed-form integrals along segments and
/// lines. Object safe; see the [module docs](self) for the conventions.
pub trait Integrand<const D: usize>: core::fmt::Debug + Send + Sync {
    /// The free-space function `F(x)` (not periodised).
    fn value_free(&self, x: &[f64; D]) -> f64;

    /// `∫_{t0}^{t1} F(p + t·ω) dt` in free space (no periodisation); `t0 ≤ t1`,
    /// either may be infinite; `ω` is unit, so `t` is arc length
    /// ([conventions](crate#conventions)). Exact for the given `f64` inputs up
    /// to the error stated by the implementation.
    fn segment_free(&self, p: &[f64; D], dir: &Direction<D>, t0: f64, t1: f64) -> f64;

    /// The `f32` scalar twin of the SIMD batch: `∫_{t0}^{t1} F(o + t·d) dt`,
    /// `d` as given (not normalised: `t` in units of `|d|`,
    /// [conventions](crate#conventions)).
    fn segment_free_f32(&self, o: [f32; D], d: [f32; D], t0: f32, t1: f32) -> f32;

    /// SIMD batch of [`Integrand::segment_free_f32`]: `out[i]` is the free-space
    /// integral along ray `i`. Bit-identical to the scalar twin, lane by lane.
    /// No allocation.
    ///
    /// # Errors
    /// [`ParamError::Length`] if the slices differ in length.
    fn segment_free_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError>;

    /// The periodised value `f(x) = Σ_n F(x + n)`; any finite `x`.
    fn value(&self, x: &[f64; D]) -> f64;

    /// `∫_{[0,1)^D} f = ∫_{ℝ^D} F`.
    fn integral(&self) -> f64;

    /// `∫_{t0}^{t1} f(p + t·ω) dt` for a piece that lies in the closed unit cell:
    /// `p + t·ω ∈ [0, 1]^D` for `t ∈ [t0, t1]` (up to rounding at the faces).
    fn piece_integral(&self, p: &[f64; D], dir: &Direction<D>, t0: f64, t1: f64) -> f64;

    /// `sup f`: an upper bound on the periodised value (for range checks).
    fn max_value(&self) -> f64;

    /// The Fourier coefficient `f̂_k = ∫_{[0,1)^D} f(x) e^{−2πi k·x} dx = F̂(k)`.
    fn fourier(&self, k: &[i32; D]) -> Complex;

    /// `∫_{−λ/2}^{λ/2} f(c + t·ω) dt` along the wrapped segment: the sum of
    /// [`Integrand::piece_integral`] over the unit cells the segment crosses
    /// (the centre is first reduced modulo 1, exactly).
    fn segment_integral(&self, seg: &Segment<D>) -> f64 {
        let half = 0.5 * seg.length();
        if half == 0.0 {
            return 0.0;
        }
        let c0 = seg.centre();
        let mut c = [0.0; D];
        for j in 0..D {
            c[j] = frac(c0[j]);
        }
        let dir = seg.dir();
        let mut sum = 0.0;
        for_each_piece(&c, &dir, -half, half, |p, a, b| {
            sum += self.piece_integral(p, &dir, a, b);
        });
        sum
    }

    /// The segment average `(1/λ)·∫ f` (the segment estimator's summand); the
    /// point value `f(c)` at `λ = 0` (subnormal lengths are stored as 0 by
    /// [`Segment::new`]), and continuous as `λ → 0`.
    fn segment_mean(&self, seg: &Segment<D>) -> f64 {
        if seg.length() == 0.0 {
            self.value(&seg.centre())
        } else {
            self.segment_integral(seg) / seg.length()
        }
    }

    /// `∫ f(p + t·ω) dt` over the chord of the unit box `[0, 1]^D` (zero if the
    /// line misses the box). For an axis direction this is the torus line
    /// integral over one full period.
    fn line_integral(&self, line: &Line<D>) -> f64 {
        let dir = line.dir();
        let p = line.point();
        let Some((t0, t1)) = clip_to_unit_box(&p, &dir) else {
            return 0.0;
        };
        // Re-base at the chord midpoint so the piece parameters are small.
        let tm = 0.5 * (t0 + t1);
        let w = dir.get();
        let mut q = [0.0; D];
        for j in 0..D {
            q[j] = (p[j] + tm * w[j]).clamp(0.0, 1.0);
        }
        let h = 0.5 * (t1 - t0);
        self.piece_integral(&q, &dir, -h, h)
    }
}

/// Checks `D ∈ {2, 3}`.
pub(crate) fn check_dim<const D: usize>() -> Result<(), ParamError> {
    if D == 2 || D == 3 {
        Ok(())
    } else {
        Err(ParamError::Dimension { dim: D })
    }
}

/// Checks that every component of `v` is finite.
pub(crate) fn check_finite<const D: usize>(
    name: &'static str,
    v: &[f64; D],
) -> Result<(), ParamError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(ParamError::NonFinite { name })
    }
}
