//! The isotropic Gaussian `A·e^{−|x − c|²/2σ²}` in free space: [`Gaussian`].
//!
//! Along a ray `p + tω`, with `q = p − c`, `a = |ω|²`, `b = q·ω`, the foot
//! parameter `t_c = −b/a` and the squared distance of the line from the centre
//! `ρ² = |q|² − b²/a = |q × ω|²/a` (Lagrange's identity, no cancellation),
//!
//! ```text
//! ∫_{t0}^{t1} F = A e^{−ρ²/2σ²} (σ√2/√a) G(u0, u1),
//! G(u0, u1) = ∫_{u0}^{u1} e^{−u²} du,   u = √a (t − t_c)/(σ√2).
//! ```
//!
//! See [`Gaussian::segment`] for how `G` and the exponentials are evaluated
//! without cancellation.

use super::{check_dim, check_finite, check_range, Ray};
use crate::error::ParamError;
use crate::num::lane::{F32Lane, F64Lane};
use crate::num::Dd;
use crate::primitive::Rays32;
use crate::special::{erfcx, erfcx_lane, exp_neg_dd, exp_neg_lane, gauss_mid};
use core::f64::consts::{SQRT_2, TAU};
use wide::f64x4;

/// `√π/2`.
const SQRT_PI_HALF: f64 = 0.886_226_925_452_758;

/// The isotropic Gaussian `F(x) = A·e^{−|x − c|²/2σ²}` in `ℝ^D` (`D = 2, 3`):
/// normalised (`A = (2πσ²)^{−D/2}`, [`Gaussian::normalised`]) or with a given
/// peak `A` ([`Gaussian::with_peak`]; `A = 1` is the unnormalised Gaussian a
/// splat renderer uses as a density).
///
/// Any finite centre, `σ ∈ [10⁻⁶, 10⁶]`. Every `f64` method keeps its relative
/// accuracy far into the tail (values down to `10⁻³⁰⁰`, see
/// [`Gaussian::segment`]); the `f32` batch has an absolute bound relative to
/// the line's peak ([`Gaussian::segment_f32`]).
#[derive(Clone, Copy, Debug)]
pub struct Gaussian<const D: usize> {
    centre: [f64; D],
    sigma: f64,
    /// `1/(2σ²)` as a double-double.
    inv_two_s2: Dd,
    /// The peak `A`.
    peak: f64,
    /// `A·σ√2` (the prefactor of `G`).
    line_norm: f64,
}

impl<const D: usize> Gaussian<D> {
    /// Smallest accepted `σ`.
    pub const SIGMA_MIN: f64 = 1e-6;
    /// Largest accepted `σ`.
    pub const SIGMA_MAX: f64 = 1e6;
    /// Smallest accepted peak ([`Gaussian::with_peak`]).
    pub const PEAK_MIN: f64 = 1e-300;
    /// Largest accepted peak.
    pub const PEAK_MAX: f64 = 1e300;

    /// The normalised density `(2πσ²)^{−D/2} e^{−|x−c|²/2σ²}` (`∫ F = 1`).
    ///
    /// # Errors
    /// [`ParamError::Dimension`] unless `D ∈ {2, 3}`; [`ParamError::NonFinite`]
    /// (`centre`, `sigma`); [`ParamError::OutOfRange`] (`sigma`) unless
    /// `10⁻⁶ ≤ σ ≤ 10⁶`.
    pub fn normalised(centre: impl Into<[f64; D]>, sigma: f64) -> Result<Self, ParamError> {
        let centre = centre.into();
        Self::check(&centre, sigma)?;
        // (2πσ²)^{−D/2} = σ^{−D} (2π)^{−D/2}.
        let (peak, line_norm) = if D == 2 {
            (1.0 / (TAU * sigma * sigma), SQRT_2 / (TAU * sigma))
        } else {
            (
                1.0 / (TAU * crate::num::scalar::sqrt(TAU) * (sigma * sigma * sigma)),
                SQRT_2 / (TAU * crate::num::scalar::sqrt(TAU) * (sigma * sigma)),
            )
        };
        Ok(Self::build(centre, sigma, peak, line_norm))
    }

    /// `A·e^{−|x−c|²/2σ²}` with peak `A = peak`.
    ///
    /// # Errors
    /// As [`Gaussian::normalised`], plus [`ParamError::NonFinite`] (`peak`) and
    /// [`ParamError::OutOfRange`] (`peak`) unless `10⁻³⁰⁰ ≤ A ≤ 10³⁰⁰`.
    pub fn with_peak(
        centre: impl Into<[f64; D]>,
        sigma: f64,
        peak: f64,
    ) -> Result<Self, ParamError> {
        let centre = centre.into();
        Self::check(&centre, sigma)?;
        let peak = check_range("peak", peak, Self::PEAK_MIN, Self::PEAK_MAX)?;
        Ok(Self::build(centre, sigma, peak, peak * (sigma * SQRT_2)))
    }

    fn check(centre: &[f64; D], sigma: f64) -> Result<(), ParamError> {
        check_dim::<D>()?;
        check_finite("centre", centre)?;
        check_range("sigma", sigma, Self::SIGMA_MIN, Self::SIGMA_MAX)?;
        Ok(())
    }

    fn build(centre: [f64; D], sigma: f64, peak: f64, line_norm: f64) -> Self {
        let s2 = Dd::prod(sigma, sigma);
        let two_s2 = Dd {
            hi: 2.0 * s2.hi,
            lo: 2.0 * s2.lo,
        };
        Self {
            centre,
            sigma,
            inv_two_s2: Dd::div(Dd::new(1.0), two_s2),
            peak,
            line_norm,
        }
    }

    /// The centre `c`.
    #[must_use]
    pub fn centre(&self) -> [f64; D] {
        self.centre
    }

    /// The standard deviation `σ`.
    #[must_use]
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// The peak value `A = F(c)`.
    #[must_use]
    pub fn peak(&self) -> f64 {
        self.peak
    }

    /// `∫_{ℝ^D} F = A·(2πσ²)^{D/2}` (1 for the normalised Gaussian; may
    /// overflow for huge `A·σ^D`).
    #[must_use]
    pub fn integral(&self) -> f64 {
        let s = self.sigma * crate::num::scalar::sqrt(TAU);
        if D == 2 {
            self.peak * s * s
        } else {
            self.peak * s * s * s
        }
    }

    /// `x / (2σ²)` in double-double, as a product with the double-double
    /// reciprocal (relative error `≤ 11u²`).
    #[inline]
    fn over_two_s2(&self, x: Dd) -> Dd {
        // An exponent that overflows (a line ~1e152 from the centre of a
        // narrow Gaussian) is +∞, not the NaN of an overflowing double-double
        // product (found by the `world` fuzz target).
        if x.hi * self.inv_two_s2.hi == f64::INFINITY {
            return Dd::new(f64::INFINITY);
        }
        x.mul(self.inv_two_s2)
    }

    /// `F(x) = A·e^{−|x−c|²/2σ²}` with the squared distance in double-double:
    /// relative error ≤ 4 ulp down to the normal range.
    #[must_use]
    pub fn value(&self, x: &[f64; D]) -> f64 {
        let mut d2 = Dd::new(0.0);
        for j in 0..D {
            let d = Dd::diff(x[j], self.centre[j]);
            d2 = d2.add(d.mul(d));
        }
        exp_neg_dd(self.over_two_s2(d2), self.peak)
    }

    /// `∫_{−∞}^{∞} F(o + tω) dt = A·σ√(2π)·e^{−ρ²/2σ²}` (`ρ` the distance from
    /// the centre to the line; `t` arc length, [conventions](crate#conventions)),
    /// the error of [`Gaussian::segment`].
    #[must_use]
    pub fn line(&self, ray: &Ray<D>) -> f64 {
        self.segment(ray, f64::NEG_INFINITY, f64::INFINITY)
    }

    /// `∫_{t0}^{t1} F(o + tω) dt`, any `t0 ≤ t1` (either may be infinite;
    /// `t0 > t1` gives the negated integral, NaN propagates; `t` is arc length
    /// along the ray's unit `ω`, [conventions](crate#conventions)).
    ///
    /// Evaluation (all with `q = o − c`, `a`, `b`, `t_c = −b/a` and
    /// `ρ² = |q × ω|²/a` in double-double, so the endpoint offsets `t − t_c` are
    /// exact to `2⁻¹⁰⁰`; hence there is **no** conditioning loss near tangency or
    /// where the ends clip the support):
    /// * straddling (`u0 < 0 < u1`): `G = (√π/2)(erf(u1) + erf(−u0))`, times
    ///   `e^{−ρ²/2σ²}`;
    /// * same sign, mirrored to `0 ≤ v0 < v1 ≤ ∞`, if `v1² − v0² ≥ 1`:
    ///   `G = (√π/2) e^{−v0²}[erfcx(v0) − e^{−(v1²−v0²)} erfcx(v1)]`
    ///   ([`crate::special::erfcx`]; cancellation ≤ 1.6×), and the exponentials
    ///   `e^{−ρ²/2σ²} e^{−v0²}` are merged into one
    ///   `e^{−|q + t_near ω|²/2σ²}` whose argument is a double-double;
    /// * same sign with `v1² − v0² < 1` (short, including `λ → 0`): around the
    ///   midpoint `m`, `G = e^{−m²}·∫_{−h}^{h} e^{−s²−2ms} ds`
    ///   ([`crate::special::gauss_mid`], a cancellation-free series), again
    ///   with one merged exponential; continuous as `λ → 0` (`≈ λ·F(midpoint)`).
    ///
    /// Error bound: relative error ≤ `1e−14` (≈ 45 ulp) for all inputs whose
    /// result is at least `2.2e−308`; the bound does not grow with the exponent
    /// (values of `1e−300` are as accurate as values of `1`). Below the normal
    /// range the result degrades gracefully into subnormals and 0.
    #[must_use]
    pub fn segment(&self, ray: &Ray<D>, t0: f64, t1: f64) -> f64 {
        let o = ray.origin();
        let q: [Dd; D] = core::array::from_fn(|j| Dd::diff(o[j], self.centre[j]));
        self.segment_signed(&q, &ray.dir().get(), t0, t1)
    }

    /// [`Gaussian::segment`] for an exact offset `q = o − c` and any finite
    /// non-zero `w`, with the sign and NaN conventions.
    #[inline]
    pub(crate) fn segment_signed(&self, q: &[Dd; D], w: &[f64; D], t0: f64, t1: f64) -> f64 {
        if t0.is_nan() || t1.is_nan() {
            return f64::NAN;
        }
        if t0 == t1 {
            return 0.0;
        }
        if t0 > t1 {
            return -self.segment_offset(q, w, t1, t0);
        }
        self.segment_offset(q, w, t0, t1)
    }

    /// Optical depth `τ = σ_t·∫_{t0}^{t1} F(o + tω) dt` of a medium whose
    /// density is `F` and whose extinction coefficient per unit density is
    /// `sigma_t` (error of [`Gaussian::segment`], plus one rounding).
    #[must_use]
    pub fn optical_depth(&self, ray: &Ray<D>, t0: f64, t1: f64, sigma_t: f64) -> f64 {
        sigma_t * self.segment(ray, t0, t1)
    }

    /// Transmittance `T = e^{−τ}` along `[t0, t1]` ([`Gaussian::optical_depth`]):
    /// relative error `≤ τ·1e−14 + 1 ulp` (the relative error of `τ` times
    /// `τ`), so `≤ 1e−13` relative for `τ ≤ 10`.
    #[must_use]
    pub fn transmittance(&self, ray: &Ray<D>, t0: f64, t1: f64, sigma_t: f64) -> f64 {
        libm::exp(-self.optical_depth(ray, t0, t1, sigma_t))
    }

    /// Opacity `1 − T = −expm1(−τ)`, without the cancellation of `1 − e^{−τ}`
    /// for a thin medium: relative error `≤ 1e−14 + 1 ulp` for every `τ` (the
    /// alpha a Gaussian-splat renderer composites).
    #[must_use]
    pub fn opacity(&self, ray: &Ray<D>, t0: f64, t1: f64, sigma_t: f64) -> f64 {
        -libm::expm1(-self.optical_depth(ray, t0, t1, sigma_t))
    }

    /// The free-space integral along `q + tω` where `q = p − centre` is given
    /// exactly as double-doubles; `t0 < t1`.
    pub(crate) fn segment_offset(&self, q: &[Dd; D], w: &[f64; D], t0: f64, t1: f64) -> f64 {
        self.segment_with(q, w, &self.line_consts(w), t0, t1)
    }

    /// The constants of [`Gaussian::segment_with`] that depend only on the
    /// direction (computed once per direction, e.g. once per piece of a
    /// wrapped segment rather than once per image).
    #[inline]
    pub(crate) fn line_consts(&self, w: &[f64; D]) -> LineConsts {
        let mut a = Dd::new(0.0);
        for &x in w {
            a = a.add(Dd::prod(x, x));
        }
        let sa = crate::num::scalar::sqrt(a.hi);
        LineConsts {
            a,
            inv_a: a.recip(),
            inv: sa / (self.sigma * SQRT_2),
            mult: self.line_norm / sa,
        }
    }

    /// [`Gaussian::segment_offset`] with the direction's constants given.
    /// Quotients by `a` are products with its double-double reciprocal
    /// (relative error `≤ 15u²`, the reciprocal's `8u²` and the product's `7u²`,
    /// instead of `4u²`: far below the `f64`
    /// rounding of the result).
    pub(crate) fn segment_with(
        &self,
        q: &[Dd; D],
        w: &[f64; D],
        k: &LineConsts,
        t0: f64,
        t1: f64,
    ) -> f64 {
        let a = k.a;
        // Sums start from their first term (adding it to 0 would give the
        // same bits at the cost of a double-double addition).
        let mut b = q[0].mul_f64(w[0]);
        for j in 1..D {
            b = b.add(q[j].mul_f64(w[j]));
        }
        // |q × ω|² (Lagrange: a ρ² = |q|²a − b²).
        let pairs = cross_pairs::<D>();
        let cross = |(i, k): (usize, usize)| {
            let x = q[i].mul_f64(w[k]).sub(q[k].mul_f64(w[i]));
            x.mul(x)
        };
        let mut cr2 = cross(pairs[0]);
        for &p in &pairs[1..] {
            cr2 = cr2.add(cross(p));
        }
        if !cr2.hi.is_finite() {
            // |q × ω|² overflows: the line passes at least ~1e154 from the
            // centre (σ ≤ 1e6), where the integrand is 0 in f64 (found by
            // the `world` fuzz target: a centre at 6e257 gave NaN).
            return 0.0;
        }
        let rho2 = cr2.mul(k.inv_a);
        let tc = b.mul(k.inv_a).neg();
        let (inv, mult) = (k.inv, k.mult);
        let s0 = if t0 == f64::NEG_INFINITY {
            Dd::new(t0)
        } else {
            Dd::new(t0).sub(tc)
        };
        let s1 = if t1 == f64::INFINITY {
            Dd::new(t1)
        } else {
            Dd::new(t1).sub(tc)
        };
        // An offset that overflows (an end beyond the f64 range, seen from a
        // foot near it: found by the `world` fuzz target) keeps its infinite
        // leading part instead of becoming NaN.
        let wide = |x: Dd, t: f64| {
            let r = t - tc.hi;
            if r.is_finite() {
                x.to_f64()
            } else {
                r
            }
        };
        let u0 = wide(s0, t0) * inv;
        let u1 = wide(s1, t1) * inv;
        if u0 < 0.0 && u1 > 0.0 {
            // Straddles the foot point: no cancellation in erf + erf.
            let g = SQRT_PI_HALF * (libm::erf(u1) + libm::erf(-u0));
            let e = self.over_two_s2(rho2);
            return exp_neg_dd(e, mult * g);
        }
        // Same sign: mirror so that 0 ≤ v0 < v1, near endpoint s_near.
        let (v0, v1, s_near) = if u1 <= 0.0 {
            (-u1, -u0, s1)
        } else {
            (u0, u1, s0)
        };
        if v0 > 40.0 {
            // The whole segment is more than 40 scaled units beyond the foot
            // point: the value is below e^{−1600}·(prefactor ≤ 1e12), i.e. 0 in
            // f64. Returning early also avoids overflowing squares for huge
            // parameters (found by fuzzing: |t| ≈ 1e217 gave NaN).
            return 0.0;
        }
        let dv = (t1 - t0) * inv; // v1 − v0, relative error of a few ulp
        let delta = dv * (v1 + v0); // v1² − v0²
        if delta >= 1.0 {
            // Long: G = (√π/2) e^{−v0²} [erfcx(v0) − e^{−(v1²−v0²)} erfcx(v1)],
            // cancellation at most 1/(1 − e^{−1}) ≈ 1.6.
            // The tail term is skipped when it cannot change the difference:
            // for δ > 40, e^{−δ} < 4.3e−18 < 2⁻⁵⁶/3, and erfcx(v1) ≤ erfcx(v0)
            // (erfcx decreases on [0, ∞); its computed values within a few
            // ulp), so the computed tail is below a quarter of the spacing of
            // doubles below erfcx(v0) and fl(erfcx(v0) − tail) = erfcx(v0):
            // the same bits, without an `exp` and an `erfcx` (most far images
            // of a long periodised piece).
            let tail = if v1 == f64::INFINITY || delta > 40.0 {
                0.0
            } else {
                libm::exp(-delta) * erfcx(v1)
            };
            let g = SQRT_PI_HALF * (erfcx(v0) - tail);
            // Exponent: (ρ² + a s_near²)/2σ² = squared distance of the near
            // endpoint from the centre over 2σ², in double-double.
            let e = self.over_two_s2(rho2.add(a.mul(s_near.mul(s_near))));
            exp_neg_dd(e, mult * g)
        } else {
            // Short: around the midpoint m with half-width h (|m|h ≤ 1/4, h ≤ 1/2).
            let sm = s0.add(s1);
            let sm = Dd {
                hi: 0.5 * sm.hi,
                lo: 0.5 * sm.lo,
            };
            let m = sm.to_f64() * inv;
            let h = 0.5 * dv;
            let g = gauss_mid(m, h);
            let e = self.over_two_s2(rho2.add(a.mul(sm.mul(sm))));
            exp_neg_dd(e, mult * g)
        }
    }

    /// `∫_{t0}^{t1} F(o + tω) dt` in plain `f64` (no double-double), with a
    /// run-time bound on its relative error: `(value, R)`, `|value − exact| ≤
    /// R·|exact|` (first order; `R = ∞` when no useful bound holds: `R ≥ 10⁻³`, the
    /// exponent beyond `700`, a result below `1e−290`, `erfc` values below
    /// `1e−280`, where they lose precision on the way to underflow).
    ///
    /// The formula of [`Gaussian::segment`] without its safeguards:
    /// `ρ² = |q × ω|²`, `t_c = −q·ω` and the arguments `u = (t − t_c)/(σ√2)` in
    /// `f64` (`q = o − c` rounded), `G = (√π/2)(erfc(v0) − erfc(v1))` on one
    /// side of the foot (`v = |u|`) or `(√π/2)((1 − erfc(|u0|)) + (1 −
    /// erfc(u1)))` straddling it, value `A·σ√2·e^{−ρ²/2σ²}·G`, with this
    /// crate's branch-free `erfc(z) = e^{−z²}·erfcx(z)` ([`crate::special::erfcx`]'s
    /// polynomial, relative error `≤ (14 + z²)u`) and a polynomial `exp`
    /// (`≤ 4u`). `R` adds first-order bounds for the exponent (`ρ²` and its
    /// roundings, which grow with `|q|ρ/σ²`), the arguments, the two `erfc`,
    /// the cancellation of their difference and the sensitivity of `G` to its
    /// arguments (at most `(2z + 1.5)·erfc(z)` per unit at an end `z = |u|`,
    /// by the Mills-ratio bound `erfc(v) > (2/√π)e^{−v²}/(v + √(v² + 2))`,
    /// Abramowitz & Stegun 7.1.13, widened for the argument's own
    /// uncertainty; see `far_kernel`). Typically `R ≈ 10⁻¹⁴…10⁻¹²`. The same
    /// kernel runs in `f64` SIMD lanes (bit for bit) for the far images of the
    /// torus Gaussian's periodised sums, whose error then stays below `2⁻⁶⁰`
    /// of the sum. Tested against the independent references
    /// (`tests/world_gaussian.rs`): the error never exceeds `R`.
    #[must_use]
    pub fn segment_fast(&self, ray: &Ray<D>, t0: f64, t1: f64) -> (f64, f64) {
        if t0 > t1 {
            let (v, r) = self.segment_fast(ray, t1, t0);
            return (-v, r);
        }
        let o = ray.origin();
        let w = ray.dir().get();
        let mut y = [0.0; D];
        let mut dy = 0.0f64;
        for j in 0..D {
            y[j] = o[j] - self.centre[j];
            dy = dy.max(f64::EPSILON * y[j].abs());
        }
        let k = self.line_consts(&w);
        far_kernel::<f64, D>(&self.far_consts(&w, &k, t0, t1), y, dy)
    }

    /// [`Gaussian::segment_fast`]'s kernel for four offsets `y ≈ q` at once
    /// (`f64` SIMD lanes, `wide::f64x4`), each given as doubles with an error
    /// bound `dy` (`|y_j − q_j| ≤ dy`), with the piece's constants
    /// ([`Gaussian::far_consts`], formed once per piece): the far images of
    /// a periodised piece.
    /// `(values, R)` per lane, `R = ∞` where no useful bound holds. Each lane
    /// is exactly the scalar kernel's result (`far_kernel` on `f64`, tested
    /// lane by lane), so results do not depend on how the images are grouped.
    pub(crate) fn segment_far4(
        c: &FarConsts<D>,
        y: &[[f64; D]; 4],
        dy: &[f64; 4],
    ) -> ([f64; 4], [f64; 4]) {
        let yl: [f64x4; D] =
            core::array::from_fn(|j| f64x4::from([y[0][j], y[1][j], y[2][j], y[3][j]]));
        let (v, r) = far_kernel::<f64x4, D>(c, yl, f64x4::from(*dy));
        (v.to_array(), r.to_array())
    }

    /// The constants of `far_kernel` for one piece (direction, its
    /// [`LineConsts`] and the ends).
    pub(crate) fn far_consts(
        &self,
        w: &[f64; D],
        k: &LineConsts,
        t0: f64,
        t1: f64,
    ) -> FarConsts<D> {
        let fin = |x: f64| if x.is_finite() { x.abs() } else { 0.0 };
        FarConsts {
            w: *w,
            inv_a: k.inv_a.hi,
            inv: k.inv,
            mult: k.mult * SQRT_PI_HALF,
            inv_two_s2: self.inv_two_s2.hi,
            t0,
            t1,
            tsum: fin(t0) + fin(t1),
        }
    }

    /// The constants of the `f32` kernel.
    pub(crate) fn consts32(&self) -> Consts32<D> {
        let mut c_hi = [0.0f32; D];
        let mut c_lo = [0.0f32; D];
        for j in 0..D {
            c_hi[j] = self.centre[j] as f32;
            c_lo[j] = (self.centre[j] - f64::from(c_hi[j])) as f32;
        }
        Consts32 {
            c_hi,
            c_lo,
            inv_s2: (1.0 / (self.sigma * SQRT_2)) as f32,
            inv_2s2: (1.0 / (2.0 * (self.sigma * self.sigma))) as f32,
            k: (self.line_norm * SQRT_PI_HALF) as f32,
        }
    }

    /// `f32` twin of [`Gaussian::segment_batch_f32`]: `∫_{t0}^{t1} F(o + t·d) dt`
    /// (`d` as given, not normalised: `t` is in units of `|d|`, and so is the
    /// integral; [conventions](crate#conventions)).
    ///
    /// `K/√a · e^{−ρ²/2σ²} · (erf(u1) − erf(u0))` with `ρ²` from the cross
    /// product, `q = (o − c_hi) − c_lo` (the centre split into two `f32`s, so
    /// a far-away centre is not rounded), this crate's `f32` `exp`
    /// (`2^n`·polynomial) and `erf` (the Abramowitz–Stegun 7.1.25–28 form with
    /// coefficients fitted for this crate, absolute error ≤ 3e−7 in `f32`).
    ///
    /// Error bound against the exact integral (asserted in the tests): with
    /// the line's peak `P = A·e^{−ρ²/2σ²} σ√(2π)/|d|`, `E = ρ²/2σ²` and
    /// `κ = |d|(|q| + |t0| + |t1|)/σ` (finite ends only), `|err| ≤ P·(1e−6 +
    /// expm1(B))` with `B = 1e−6·E + 2e−7·κ·(1 + √(2E))`: `B` bounds the error
    /// of the `f32` exponent `−E`, which the factor `e^{−E}` turns into a
    /// relative error of at most `e^B − 1`. An absolute bound relative to the
    /// peak that grows only with the `f32` conditioning of the inputs (a tail
    /// segment whose exact value is far below `P·1e−6` may come out as 0). The
    /// bound holds while `E < 86`: the `f32` exponential flushes to 0 below
    /// `e^{−87}`, so a line whose factor `e^{−E}` is below that gives 0
    /// whatever its peak (with `A = 10³⁰`, `σ = 1`, a line 14σ from the centre
    /// has the value `6.9e−13` and gives 0); results below the `f32` normal
    /// range carry a few `2⁻¹⁴⁹` absolute. Requires `A·σ` within the `f32`
    /// range.
    ///
    /// Release behaviour: never panics; infinite `t0`/`t1` are supported;
    /// `t0 > t1` gives the negated integral; NaN inputs or `d = 0` give an
    /// unspecified value (NaN or finite).
    #[must_use]
    pub fn segment_f32(
        &self,
        o: impl Into<[f32; D]>,
        d: impl Into<[f32; D]>,
        t0: f32,
        t1: f32,
    ) -> f32 {
        kernel32::<f32, D>(&self.consts32(), o.into(), d.into(), t0, t1)
    }

    /// SIMD batch (8 lanes) of [`Gaussian::segment_f32`] (directions as
    /// given, in units of `|d|` as the scalar twin), bit-identical to the
    /// scalar twin lane by lane; no allocation.
    ///
    /// # Errors
    /// [`ParamError::Length`] if the slices differ in length.
    pub fn segment_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        super::ray_batch(&SegK32(self.consts32()), rays, out)
    }

    /// `f32` transmittance `e^{−σ_t·∫F}` along `o + t·d`, `t ∈ [t0, t1]`: the
    /// scalar twin of [`Gaussian::transmittance_batch_f32`]. `d` is used as
    /// given and `∫F` is over `t` ([conventions](crate#conventions)), so this
    /// is the medium's transmittance for a unit `d`. With `ε` the
    /// absolute error of [`Gaussian::segment_f32`], the error is at most
    /// `T·(σ_t·ε + 3e−7)` (the crate's `f32` exponential, relative `3e−7`),
    /// for `τ < 86`; beyond, `T < e^{−86}` flushes to 0.
    #[must_use]
    pub fn transmittance_f32(
        &self,
        o: impl Into<[f32; D]>,
        d: impl Into<[f32; D]>,
        t0: f32,
        t1: f32,
        sigma_t: f32,
    ) -> f32 {
        transmit32::<f32, D>(&self.consts32(), o.into(), d.into(), t0, t1, sigma_t)
    }

    /// SIMD batch (8 lanes) of [`Gaussian::transmittance_f32`] (directions as
    /// given, as the scalar twin), bit-identical to the scalar twin lane by
    /// lane; no allocation.
    ///
    /// # Errors
    /// [`ParamError::Length`] if the slices differ in length.
    pub fn transmittance_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        sigma_t: f32,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        super::ray_batch(&TransmitK32(self.consts32(), sigma_t), rays, out)
    }
}

/// The index pairs `(i, k)` of the components `x_i ω_k − x_k ω_i` of a cross
/// product: one in 2D, three in 3D.
#[inline(always)]
fn cross_pairs<const D: usize>() -> &'static [(usize, usize)] {
    if D == 2 {
        &[(0, 1)]
    } else {
        &[(1, 2), (2, 0), (0, 1)]
    }
}

/// Per-direction constants of the `f64` segment integral.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LineConsts {
    /// `a = |ω|²` in double-double.
    a: Dd,
    /// `1/a` in double-double.
    inv_a: Dd,
    /// `√a/(σ√2)`.
    inv: f64,
    /// `A·σ√2/√a`.
    mult: f64,
}

/// Per-piece constants of `far_kernel`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FarConsts<const D: usize> {
    w: [f64; D],
    /// `1/a` (rounded).
    inv_a: f64,
    /// `√a/(σ√2)`.
    inv: f64,
    /// `A·σ√2/√a · √π/2`.
    mult: f64,
    /// `1/2σ²` (rounded).
    inv_two_s2: f64,
    t0: f64,
    t1: f64,
    /// `|t0| + |t1|` over the finite ends.
    tsum: f64,
}

/// `erfc(z)` for `0 ≤ z ≤ 26` in lanes: `e^{−z²}·erfcx(z)` with this crate's
/// lane exponential and polynomial `erfcx` (`crate::special`), relative error
/// at most `(14 + z²)·u`: `4u` for the exponential, `z²u` from rounding `z²`,
/// `8e−16 ≤ 7.3u` for `erfcx` and `u` for the product.
#[inline(always)]
fn erfc_lane<L: F64Lane>(z: L) -> L {
    exp_neg_lane(z * z) * erfcx_lane(z)
}

/// The one kernel of [`Gaussian::segment_fast`] and
/// [`Gaussian::segment_far4`]: the integral along `q + tω`, `t ∈ [t0, t1]`,
/// in plain `f64` from an offset `y ≈ q` (`|y_j − q_j| ≤ dy`), with a bound
/// `R` on its relative error: `(value, R)`.
///
/// `ρ² = |y × ω|²/a`, `t_c = −(y·ω)/a`, `u_i = (t_i − t_c)·√a/(σ√2)`,
/// `z_i = |u_i|`, `c_i = erfc(z_i)` (`erfc_lane`, relative error
/// `ε_i = (14 + z_i²)u`; `0` for `z_i ≥ 26`, an absolute error below
/// `6e−296` added to the error of `D`). On
/// one side of the foot `D = |c0 − c1|`; straddling it
/// `D = (1 − c0) + (1 − c1)` (`= erf(u1) + erf(−u0)`); value
/// `mult·e^{−ρ²/2σ²}·(√π/2)·D`. First-order error terms, each generous:
/// the exponent (`ρ²` from the offset error `δ = 2u|y|₁ + 2dy` and the
/// roundings) `|dE| ≤ (2ρδ + δ² + 8uρ²)/2σ²`; the arguments
/// `δu ≤ (δt_c + u(|t0| + |t1| + 2|t_c|))·√a/(σ√2) + u(|u0| + |u1|)` (finite
/// ends only) with `δt_c ≤ (D + 2)u|y|₁ + 2dy + 2u|t_c|`; `D` from its two
/// `erfc` (`ε0·c0 + ε1·c1`) and its roundings (`3u·D`), and its sensitivity
/// `|∂D/∂u_i| = (2/√π)e^{−u_i²}` at each end, at most
/// `min(1.13, 1.11·(2z_i + 1.5)·erfc(z_i))` (Mills' ratio, widened by
/// `e^{2z_i·δu} ≤ 1.11` for the whole uncertainty of `z_i`, and `1.13` where
/// `2z_i·δu > 0.1`); plus `8u`
/// for the exponential (`≤ 4u`) and the products. Unusable (`R = ∞`):
/// `R ≥ 10⁻³` (a first-order bound means nothing once it is large: found by
/// the `world` fuzz target), `E > 700`, a value below `1e−290`, or, on one
/// side of the foot, `c0 + c1 < 1e−280` (`erfc` near underflow has lost its
/// precision).
#[inline(always)]
pub(crate) fn far_kernel<L: F64Lane, const D: usize>(c: &FarConsts<D>, y: [L; D], dy: L) -> (L, L) {
    const U: f64 = f64::EPSILON / 2.0;
    let zero = L::splat(0.0);
    let one = L::splat(1.0);
    let u = L::splat(U);
    let mut b = zero;
    let mut y1 = zero;
    for j in 0..D {
        b = b + y[j] * L::splat(c.w[j]);
        y1 = y1 + y[j].abs();
    }
    let mut cr2 = zero;
    for &(i, m) in cross_pairs::<D>() {
        let x = y[i] * L::splat(c.w[m]) - y[m] * L::splat(c.w[i]);
        cr2 = cr2 + x * x;
    }
    let rho2 = cr2 * L::splat(c.inv_a);
    let tc = -(b * L::splat(c.inv_a));
    let inv = L::splat(c.inv);
    let u0 = (L::splat(c.t0) - tc) * inv;
    let u1 = (L::splat(c.t1) - tc) * inv;
    // Beyond z = 26, erfc(z) < 6e−296 is taken as 0 (an absolute error
    // below 6e−296, added to the error of D below).
    let lim = L::splat(26.0);
    let z0 = u0.abs().min(lim);
    let z1 = u1.abs().min(lim);
    let c0 = L::select(z0.lt(lim), erfc_lane(z0), zero);
    let c1 = L::select(z1.lt(lim), erfc_lane(z1), zero);
    let eps0 = (L::splat(14.0) + z0 * z0) * u;
    let eps1 = (L::splat(14.0) + z1 * z1) * u;
    let cut = L::select(z0.lt(lim), zero, L::splat(6e-296))
        + L::select(z1.lt(lim), zero, L::splat(6e-296));
    // Straddling: u0 < 0 < u1.
    let strad = L::and(u0.lt(zero), zero.lt(u1));
    let d_same = (c0 - c1).abs();
    let d_str = (one - c0) + (one - c1);
    let d = L::select(strad, d_str, d_same);
    let err_d = eps0 * c0 + eps1 * c1 + L::splat(3.0 * U) * d + cut;
    let e = rho2 * L::splat(c.inv_two_s2);
    let e_ok = e.le(L::splat(700.0));
    let ex = exp_neg_lane(e.min(L::splat(700.0)));
    let v = L::splat(c.mult) * ex * d;
    let rho = rho2.sqrt();
    let two = L::splat(2.0);
    // The perpendicular offset is off by at most δ = 2u|y|₁ + 2dy, so ρ² by
    // at most 2ρδ + δ² (the square matters where the computed ρ is ~0 but
    // the offset's error is not: found by the `world` fuzz target, a line
    // through an origin at 6e30 whose 7e3 offset from the centre is below
    // the rounding of the origin).
    let delta = two * u * y1 + two * dy;
    let de =
        (two * rho * delta + delta * delta + L::splat(8.0) * u * rho2) * L::splat(c.inv_two_s2);
    let atc = tc.abs();
    let dtc = L::splat((D as f64 + 2.0) * U) * y1 + two * dy + two * u * atc;
    // Infinite ends (a line) contribute no argument error.
    let inf = L::splat(f64::INFINITY);
    let fin = |x: L| {
        let ax = x.abs();
        L::select(ax.lt(inf), ax, zero)
    };
    let du = (dtc + u * (L::splat(c.tsum) + two * atc)) * inv + u * (fin(u0) + fin(u1));
    // |∂D/∂u_i| = (2/√π)e^{−u_i²} at each end, at most
    // min(1.13, (2z_i + 1.5)·erfc(z_i)) by Mills' ratio at the computed z_i;
    // over the whole uncertainty z_i ± δu the factor e^{−(z_i − δu)²} is at
    // most e^{2z_i·δu} ≤ 1.11 times larger while 2z_i·δu ≤ 0.1, and past
    // that only the global 1.13 holds. Where z_i ≥ 26 (c_i set to 0), the
    // derivative is below 1e−294 as long as δu ≤ 1. An infinite end
    // contributes nothing beyond that (a line's D does not depend on t_c).
    let end_sens = |z: L, c: L| {
        let local = (L::splat(1.11) * (L::splat(2.0) * z + L::splat(1.5)) * c).min(L::splat(1.13));
        let near = (L::splat(2.0) * z * du).le(L::splat(0.1));
        let far = L::select(du.le(one), L::splat(1e-294), L::splat(1.13));
        L::select(z.lt(lim), L::select(near, local, L::splat(1.13)), far)
    };
    let sens = end_sens(z0, c0) + end_sens(z1, c1);
    let rel = L::splat(1.01) * (de + (err_d + sens * du) / d + L::splat(8.0 * U));
    // On one side of the foot, D is a difference of erfc values, which
    // have lost their precision near underflow; straddling, D ≥ 1 − c0 is
    // never small that way.
    let mag = L::select(strad, one, c0 + c1);
    let usable = L::and(
        L::and(rel.lt(L::splat(1e-3)), e_ok),
        L::and(L::splat(1e-290).le(v.abs()), L::splat(1e-280).le(mag)),
    );
    (v, L::select(usable, rel, L::splat(f64::INFINITY)))
}

/// The `f32` segment integral as a [`super::RayKernel32`].
struct SegK32<const D: usize>(Consts32<D>);

impl<const D: usize> super::RayKernel32<D> for SegK32<D> {
    #[inline(always)]
    fn eval<L: F32Lane>(&self, o: [L; D], d: [L; D], t0: L, t1: L) -> L {
        kernel32::<L, D>(&self.0, o, d, t0, t1)
    }
}

/// The `f32` transmittance with `σ_t` as a [`super::RayKernel32`].
struct TransmitK32<const D: usize>(Consts32<D>, f32);

impl<const D: usize> super::RayKernel32<D> for TransmitK32<D> {
    #[inline(always)]
    fn eval<L: F32Lane>(&self, o: [L; D], d: [L; D], t0: L, t1: L) -> L {
        transmit32::<L, D>(&self.0, o, d, t0, t1, self.1)
    }
}

/// `e^{−σ_t·∫F}` from the segment kernel (the optical depth is `≥ 0` for
/// `t0 ≤ t1` and `σ_t ≥ 0`; its negation is clamped to `≤ 0` for the
/// exponential's domain).
#[inline(always)]
fn transmit32<L: F32Lane, const D: usize>(
    k: &Consts32<D>,
    o: [L; D],
    d: [L; D],
    t0: L,
    t1: L,
    sigma_t: f32,
) -> L {
    let tau = kernel32::<L, D>(k, o, d, t0, t1) * L::splat(sigma_t);
    exp_neg32((L::splat(0.0) - tau).min(L::splat(0.0)))
}

/// Per-integrand constants of the `f32` kernel.
#[derive(Clone, Copy)]
pub(crate) struct Consts32<const D: usize> {
    c_hi: [f32; D],
    c_lo: [f32; D],
    /// `1/(σ√2)`.
    inv_s2: f32,
    /// `1/(2σ²)`.
    inv_2s2: f32,
    /// `(2πσ²)^{−D/2} σ√2 · √π/2`; the integral is `k/√a · e^{−ρ²/2σ²} (erf(u1) − erf(u0))`.
    k: f32,
}

/// `e^{x}` for `x ≤ 0` (`0` below `−87`): `2^n · p(r)` with `n = ⌊x log₂e + ½⌋`,
/// `r = x − n ln 2` (Cody–Waite two-part `ln 2`), `p` the degree-7 Taylor
/// polynomial (|r| ≤ 0.35: truncation ≤ 6e−9), Horner without FMA. Relative
/// error ≤ 3e−7.
#[inline(always)]
pub(crate) fn exp_neg32<L: F32Lane>(x: L) -> L {
    let under = x.lt(L::splat(-87.0));
    let xc = x.max(L::splat(-87.0));
    let n = (xc * L::splat(core::f32::consts::LOG2_E) + L::splat(0.5)).floor();
    let r = (xc - n * L::splat(0.693_359_375)) - n * L::splat(-2.121_944_4e-4);
    let mut p = L::splat(1.0 / 5040.0);
    p = p * r + L::splat(1.0 / 720.0);
    p = p * r + L::splat(1.0 / 120.0);
    p = p * r + L::splat(1.0 / 24.0);
    p = p * r + L::splat(1.0 / 6.0);
    p = p * r + L::splat(0.5);
    p = p * r + L::splat(1.0);
    p = p * r + L::splat(1.0);
    L::select(under, L::splat(0.0), p * L::pow2i(n))
}

/// `erf(x)` in `f32`: `1 − e^{−x²}·P(t)`, `t = 1/(1 + 0.4|x|)`, odd extension,
/// where the degree-6 polynomial `P ≈ erfcx` was fitted for this crate by
/// iteratively reweighted least squares on the absolute error of `erf` over
/// `t ∈ (0, 1]` (the form of Abramowitz & Stegun 7.1.25–28, own coefficients).
/// Absolute error ≤ 1.2e−8 in exact arithmetic, ≤ 3e−7 with `f32` rounding
/// (measured). `±∞ ↦ ±1`.
#[inline(always)]
pub(crate) fn erf32<L: F32Lane>(x: L) -> L {
    let ax = x.abs();
    let t = L::splat(1.0) / (L::splat(1.0) + L::splat(0.4) * ax);
    let mut p = L::splat(-0.179_589_42);
    p = p * t + L::splat(0.607_486_67);
    p = p * t + L::splat(-0.163_771_06);
    p = p * t + L::splat(0.244_526_97);
    p = p * t + L::splat(0.296_928_97);
    p = p * t + L::splat(0.188_693_33);
    p = p * t + L::splat(0.005_724_541);
    let e = exp_neg32(-(ax * ax));
    let y = L::splat(1.0) - p * e;
    L::select(x.lt(L::splat(0.0)), -y, y)
}

/// The one `f32` kernel behind [`Gaussian::segment_f32`] and the batch.
#[inline(always)]
pub(crate) fn kernel32<L: F32Lane, const D: usize>(
    k: &Consts32<D>,
    o: [L; D],
    d: [L; D],
    t0: L,
    t1: L,
) -> L {
    let mut q = [L::splat(0.0); D];
    for j in 0..D {
        q[j] = (o[j] - L::splat(k.c_hi[j])) - L::splat(k.c_lo[j]);
    }
    let mut a = L::splat(0.0);
    let mut b = L::splat(0.0);
    for j in 0..D {
        a = a + d[j] * d[j];
        b = b + q[j] * d[j];
    }
    let cr2 = if D == 2 {
        let x = q[0] * d[1] - q[1] * d[0];
        x * x
    } else {
        let x = q[1] * d[2] - q[2] * d[1];
        let y = q[2] * d[0] - q[0] * d[2];
        let z = q[0] * d[1] - q[1] * d[0];
        x * x + y * y + z * z
    };
    let rho2 = cr2 / a;
    let tc = -(b / a);
    let sa = a.sqrt();
    let inv = sa * L::splat(k.inv_s2);
    let u0 = (t0 - tc) * inv;
    let u1 = (t1 - tc) * inv;
    let g = erf32(u1) - erf32(u0);
    let e = exp_neg32(-(rho2 * L::splat(k.inv_2s2)));
    (L::splat(k.k) / sa) * e * g
}

#[cfg(test)]
mod tests {
    use super::*;
    use wide::f32x8;

    #[test]
    fn kernels_agree_scalar_simd() {
        let g = Gaussian::<2>::normalised([0.3, 0.6], 0.05).unwrap();
        let k = g.consts32();
        let xs = [-3.0f32, -0.7, -0.1, 0.0, 0.2, 1.3, 2.5, f32::INFINITY];
        let v = kernel32::<f32x8, 2>(
            &k,
            [f32x8::from([0.1; 8]), f32x8::from([0.5; 8])],
            [f32x8::from([0.6; 8]), f32x8::from([0.8; 8])],
            f32x8::from([-1.0; 8]),
            f32x8::from(xs),
        )
        .to_array();
        for l in 0..8 {
            let s = kernel32::<f32, 2>(&k, [0.1, 0.5], [0.6, 0.8], -1.0, xs[l]);
            assert_eq!(s.to_bits(), v[l].to_bits());
        }
    }

    /// The far-image kernel in `f64x4` lanes equals its scalar twin bit for
    /// bit (values and bounds), across one-sided, straddling, infinite and
    /// clamped cases; `segment_far4` equals `segment_fast`'s kernel per lane.
    #[test]
    fn far_kernel_lanes_agree() {
        let g = Gaussian::<3>::normalised([0.3, 0.6, 0.1], 0.1).unwrap();
        let w = [0.6, 0.0, 0.8];
        let k = g.line_consts(&w);
        let mut rng = crate::Pcg32::new(0x2545_f491_4f6c_dd1d, 1);
        let mut uni = || f64::from(rng.next_u32()) / 4_294_967_296.0;
        let ends = [
            (-0.1, 0.1),
            (0.05, 0.3),
            (-0.4, -0.35),
            (-1.0, 2.0),
            (f64::NEG_INFINITY, 0.2),
            (-3.0, f64::INFINITY),
        ];
        let mut checked = 0;
        for &(t0, t1) in &ends {
            let c = g.far_consts(&w, &k, t0, t1);
            for _ in 0..200 {
                let y: [[f64; 3]; 4] =
                    core::array::from_fn(|_| core::array::from_fn(|_| 6.0 * uni() - 3.0));
                let dy: [f64; 4] = core::array::from_fn(|l| 1e-16 * (1.0 + y[l][0].abs()));
                let yl: [f64x4; 3] =
                    core::array::from_fn(|j| f64x4::from([y[0][j], y[1][j], y[2][j], y[3][j]]));
                let (v, r) = far_kernel::<f64x4, 3>(&c, yl, f64x4::from(dy));
                let (v, r) = (v.to_array(), r.to_array());
                let (v4, r4) = Gaussian::<3>::segment_far4(&c, &y, &dy);
                for l in 0..4 {
                    let (sv, sr) = far_kernel::<f64, 3>(&c, y[l], dy[l]);
                    assert_eq!(sv.to_bits(), v[l].to_bits(), "{y:?} {t0} {t1}");
                    assert_eq!(sr.to_bits(), r[l].to_bits(), "{y:?} {t0} {t1}");
                    assert_eq!(sv.to_bits(), v4[l].to_bits());
                    assert_eq!(sr.to_bits(), r4[l].to_bits());
                    checked += usize::from(sr.is_finite());
                }
            }
        }
        // Most cases have a usable bound (the comparison is not vacuous).
        assert!(checked > 2000, "{checked}");
    }

    #[test]
    fn exp_erf_f32() {
        for i in 0..2000 {
            let x = -87.0 + 87.0 * i as f64 / 2000.0;
            let e = f64::from(exp_neg32(x as f32));
            let r = libm::exp(f64::from(x as f32));
            assert!(((e - r) / r).abs() < 3e-7, "{x} {e} {r}");
            let x = -6.0 + 12.0 * i as f64 / 2000.0;
            let e = f64::from(erf32(x as f32));
            let r = libm::erf(f64::from(x as f32));
            assert!((e - r).abs() < 3e-7, "{x} {e} {r}");
        }
    }
}
