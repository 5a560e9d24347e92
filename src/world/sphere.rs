//! The sphere (3D) or disk (2D) `|x − c| < r`: [`Sphere`].
//!
//! # Numerics
//!
//! The segment integral is a chord length. For `q = p − c` and `a = |ω|²` the
//! line `p + tω` meets the sphere where `a t² + 2(q·ω) t + |q|² − r² = 0`, i.e.
//! `t± = (−b ± √Δ)/a` with `b = q·ω`, `Δ = b² − a(|q|² − r²)`, and the chord is
//! `2√Δ/a`. In `f64` the subtraction in `Δ` cancels catastrophically for tangent
//! and grazing lines (`Δ → 0` while `b²` and `a|q|²` stay of order `|q|²`), so
//! [`Sphere::segment`] evaluates `Δ` in double-double ([`crate::num::dd`]):
//!
//! 1. `q = p − c` exactly (`Dd::diff`);
//! 2. the origin is moved along the line to (nearly) the foot of the
//!    perpendicular, `q' = q + τω` with `τ ≈ −b/a` a double (`Dd::prod` is exact
//!    and the accurate double-double addition has a relative error `≤ 3u²` of
//!    its result, `u = 2⁻⁵³`), so that `|q'| ≈ dist(c, line)`; the step is
//!    repeated while the remaining offset along the line exceeds `2²⁶r` (a
//!    point given far along the line);
//! 3. `Δ = b'² − a(|q'|² − r²)` in double-double, where now the only
//!    cancellation is `|q'|²` against `r²`, harmless at `2⁻¹⁰⁴` precision;
//! 4. `√Δ` is rounded once more by a Newton step, and `t± = τ − b'/a ± √Δ/a`;
//! 5. an end `e ∈ {t0, t1}` within rounding distance of the chord is never
//!    subtracted from a rounded root: the quadratic is re-based at it,
//!    `a s² + 2b_e s + c_e = 0` for `s = t − e`, with `q_e = q + eω`,
//!    `b_e = q_e·ω` in double-double and `c_e = |q_e|² − r²` summed exactly
//!    from error-free products in four-fold precision
//!    ([`crate::num::sum_accurate`]; it cancels to about `h·L` against `r²`),
//!    (from an origin more than `10¹²` times farther away than the foot
//!    region, `q_e = q' + (e − τ)ω` is formed from the re-based `q'` in
//!    double-double instead: the expansion from `q` would cancel by `|q|²`,
//!    beyond even the four-fold sum) and its roots taken from the cancellation-free pair
//!    `s₁ = −(b_e + sign(b_e)√Δ)/a`, `s₂ = c_e/(a s₁)`, so a root next to the
//!    end (`c_e → 0`) keeps its relative accuracy. The clipped length is then
//!    one such quantity: `t1 − t0` (both ends inside), `t+ − t0` (exits inside),
//!    `t1 − t−` (enters inside) or `2h` (whole chord), never a difference of
//!    two rounded parameters.
//!
//! The result is the exact chord of the given `f64` inputs up to a **relative**
//! error of a few ulp (about `3u + 2⁻¹⁰⁴/(1 − d/r)` for a line at distance `d`
//! from the centre, i.e. a few ulp down to `1 − d/r ≈ 10⁻³⁰`; at most `7u`
//! when the fast path below answers) when the segment
//! ends do not cut the chord. When they do, the relative error is at most
//! `8u + 2⁻¹⁰⁰·(r/h + r²/h²)` for half chord `h`, **whatever the clipped
//! length** `L`: `≤ 1e−13` for segments of any length that straddle, end at
//! or lie next to the boundary, unless the line is within `h < 10⁻⁸r` of
//! tangency (the `r/h` term is the double-double conditioning of `b_e`, the
//! `r²/h²` term that of a near-tangent whole chord `2h`). A segment whose ends
//! are inside by more than `2⁻¹⁰⁰r²/h` has length exactly `fl(t1 − t0)`.
//! (Tested against exact dyadic arithmetic over radii `10⁻¹⁰⁰ … 1/2`, lengths
//! down to `10⁻¹⁵·2r`, straddling, ending at, starting at, inside and grazing,
//! in 2D and 3D: measured `≤ 3.8e−16` relative in every case.) Any finite
//! `p` is accepted (the repeated re-basing reaches the foot from as far as
//! `10³⁰⁸`), and `r ≥ 10⁻¹⁰⁰` (enforced: [`Sphere::RADIUS_MIN`]), so the squares
//! formed near the foot neither overflow nor underflow.
//!
//! **Fast path.** A finite segment first tries an `f64` shortcut of steps
//! 1–5: the quadratic re-based at `t0` (and, for a segment that enters the
//! ball and ends inside it, at `t1`), `b_e` and `c_e` summed from error-free
//! products and sums and rounded once ("double-`f64`", with rigorous bounds
//! `u|b_e| + 128u²M_b` and `u|c_e| + 256u²M_c` for the sizes `M` of the
//! summands), `Δ = b_e² − a c_e` from the exact square, and the same cancellation-free
//! roots. Every decision (which end is inside, on which side a root lies)
//! must hold with its error margin, and the length (`s+`, `−u−` or `2√Δ/a`)
//! is returned only when its run-time relative error bound is at most `7u`
//! (a whole chord seen from a far end, where `b_e² ≫ Δ`, is re-based at the
//! foot `t0 − b_e/a` first, where `Δ ≈ −a c_e` does not cancel);
//! otherwise the double-double path above decides. Lengths `0` and
//! `fl(t1 − t0)` are the exact path's bit for bit; others may differ from it
//! by a few ulp, within the bounds above. About 4× cheaper than the
//! double-double foot for an ordinary segment; infinite ends, near-tangent
//! lines, far origins and ends within rounding distance of the sphere go to
//! the exact path.
//!
//! The `f32` batch path ([`Sphere::segment_batch_f32`], one kernel generic
//! over the crate's `f32` lane type) uses the plain formula in `f32` with a
//! perpendicular decomposition (`d² = |q − (q·ω/a)ω|²`, `h² = (r² − d²)/a`):
//! see its docs for the error.
// `!(x > y)` is deliberate below: it also catches NaN (overflowing inputs).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{check_dim, check_finite, check_range, Ray};
use crate::error::ParamError;
use crate::num::lane::F32Lane;
use crate::num::{sum_accurate, two_prod, two_sum, Dd};
use crate::primitive::Rays32;
use core::f64::consts::PI;

/// Unit roundoff `u = 2⁻⁵³`.
const EPS: f64 = f64::EPSILON / 2.0;

/// `2⁻⁴⁰`: below `2⁻⁴⁰·a·r²` the double-double discriminant is recomputed
/// from the exact constant term (see `chord`).
const TWO_M40: f64 = 9.094947017729282e-13;

/// `2⁻⁹⁶` (the conditioning margin of the clipped chord, see `chord`).
const TWO_M96: f64 = f64::from_bits((1023 - 96) << 52);

/// The open sphere (`D = 3`) or disk (`D = 2`) `{x : |x − c| < r}` in free
/// space: any finite centre, radius `10⁻¹⁰⁰ ≤ r ≤ 10¹⁰⁰`.
///
/// The `f64` methods take a [`Ray`], whose direction is unit, so their
/// parameters and lengths are arc length; they are exact for the given `f64`
/// inputs up to the relative errors stated on each (see the [module
/// docs](self) for the algorithm). The `f32` methods take the ray `o + t·d`
/// as given (any finite non-zero `d`, not normalised: parameters and lengths
/// in units of `|d|`, arc length for a unit `d`) and use the centre and
/// radius rounded to `f32`. One convention for both, stated in the [crate
/// docs](crate#conventions).
///
/// ```
/// use linesample::world::{Ray, Sphere};
/// let s = Sphere::new([1e6, 0.0, 0.0], 1e-3)?;
/// // A ray from the origin grazing the sphere 1e-12 inside its rim:
/// let ray = Ray::new([0.0, 1e-3 - 1e-12, 0.0], [1.0, 0.0, 0.0])?;
/// let chord = s.chord(&ray);
/// let exact = 2.0 * (2e-3 * 1e-12 - 1e-24f64).sqrt();
/// assert!((chord - exact).abs() <= 1e-6 * exact); // (1e-12 is not a double)
/// # Ok::<(), linesample::ParamError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere<const D: usize> {
    centre: [f64; D],
    radius: f64,
    /// `r²` exactly.
    r2: Dd,
    /// The centre rounded to `f32`.
    centre32: [f32; D],
    /// `fl32(r32 · r32)`.
    r2_32: f32,
}

impl<const D: usize> Sphere<D> {
    /// Smallest accepted radius, `10⁻¹⁰⁰`: below about `10⁻¹⁵⁰` the squared
    /// quantities of the double-double chord underflow (found by fuzzing: a
    /// chord of a `10⁻¹⁵⁹` ball exceeded its diameter by `1.4e−7` relative).
    pub const RADIUS_MIN: f64 = 1e-100;
    /// Largest accepted radius, `10¹⁰⁰` (squares of distances up to a few
    /// radii stay far from overflow).
    pub const RADIUS_MAX: f64 = 1e100;

    /// The sphere of radius `radius` centred at `centre`.
    ///
    /// # Errors
    /// [`ParamError::Dimension`] unless `D ∈ {2, 3}`; [`ParamError::NonFinite`]
    /// (`centre`, `radius`); [`ParamError::OutOfRange`] (`radius`) unless
    /// [`Sphere::RADIUS_MIN`] `≤ r ≤` [`Sphere::RADIUS_MAX`].
    pub fn new(centre: impl Into<[f64; D]>, radius: f64) -> Result<Self, ParamError> {
        let centre = centre.into();
        check_dim::<D>()?;
        check_finite("centre", &centre)?;
        let radius = check_range("radius", radius, Self::RADIUS_MIN, Self::RADIUS_MAX)?;
        let r32 = radius as f32;
        Ok(Self {
            centre,
            radius,
            r2: Dd::prod(radius, radius),
            centre32: centre.map(|c| c as f32),
            r2_32: r32 * r32,
        })
    }

    /// The centre `c`.
    #[inline]
    #[must_use]
    pub fn centre(&self) -> [f64; D] {
        self.centre
    }

    /// The radius `r`.
    #[inline]
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// `r²` as an exact double-double.
    #[inline]
    pub(crate) fn r2(&self) -> Dd {
        self.r2
    }

    /// Area `πr²` (2D) or volume `4πr³/3` (3D) (may overflow to `∞` for
    /// `r ≳ 10¹⁰²/³` in 3D… never for the accepted radii in 2D).
    #[must_use]
    pub fn measure(&self) -> f64 {
        let r = self.radius;
        if D == 2 {
            PI * r * r
        } else {
            4.0 / 3.0 * PI * r * r * r
        }
    }

    /// `|x − c| < r`, decided exactly (double-double; a finite `x` that makes
    /// the squares overflow is outside).
    #[must_use]
    pub fn contains(&self, x: &[f64; D]) -> bool {
        let mut s = Dd::new(0.0);
        for j in 0..D {
            let q = Dd::diff(x[j], self.centre[j]);
            s = s.add(q.mul(q));
        }
        let d = s.sub(self.r2);
        d.hi < 0.0 || (d.hi == 0.0 && d.lo < 0.0)
    }

    /// `q = o − c` exactly.
    #[inline]
    fn offset(&self, o: &[f64; D]) -> [Dd; D] {
        core::array::from_fn(|j| Dd::diff(o[j], self.centre[j]))
    }

    /// The entry and exit parameters `t− < t+` where the ray's line crosses the
    /// sphere (arc length along the ray's unit direction, negative when behind
    /// the origin; [conventions](crate#conventions)), or `None` if the line
    /// misses the open sphere (a tangent line misses it).
    ///
    /// The discriminant is that of the chord (double-double, re-based at the
    /// foot of the perpendicular); the roots are the cancellation-free pair
    /// `−(b + sign(b)√Δ)/a` and `c/(a·that)` of the quadratic at the origin,
    /// with `c = |o − c|² − r²` summed exactly, so a root next to the origin
    /// (a ray leaving the surface) keeps its relative accuracy. Error: a few
    /// ulp relative for each root (measured `≤ 2.2e−16·4`, see the tests),
    /// except within about `2⁻¹⁰⁰` relative of tangency. An origin so far away
    /// that `|o − c|²` overflows (`≳ 10¹⁵⁴`) gives the roots as `t_m ± h`
    /// (midpoint and half chord), then still relatively accurate since both
    /// roots are then far from 0.
    #[must_use]
    pub fn hit(&self, ray: &Ray<D>) -> Option<(f64, f64)> {
        let q = self.offset(&ray.origin());
        let w = ray.dir().get();
        let f = foot(&q, &w, norm2(&w), self.r2)?;
        let (sm, sp) = rebased_roots(&q, &w, self.r2, f.af, f.sd, 0.0);
        if sm.is_finite() && sp.is_finite() && sm <= sp {
            Some((sm, sp))
        } else {
            Some((f.tm - f.h, f.tm + f.h))
        }
    }

    /// The chord length of the ray's whole line, `2√Δ/a` (a length: the ray's
    /// direction is unit, [conventions](crate#conventions)): relative error of a
    /// few ulp (about `3u + 2⁻¹⁰⁴/(1 − d/r)` for a line at distance `d` from
    /// the centre), 0 for a miss.
    #[must_use]
    pub fn chord(&self, ray: &Ray<D>) -> f64 {
        self.segment(ray, f64::NEG_INFINITY, f64::INFINITY)
    }

    /// `∫_{t0}^{t1} 1[|o + tω − c| < r] dt`: the chord clipped to `[t0, t1]`
    /// (either end may be infinite; `t` is arc length along the ray's unit `ω`,
    /// [conventions](crate#conventions)). Relative error a few ulp for an unclipped
    /// chord; `≤ 8u + 2⁻¹⁰⁰·(r/h + r²/h²)` (`h` the half chord) when an end
    /// clips it, **whatever the clipped length**: `≤ 1e−13` for segments of any
    /// length ending at, starting at or straddling the boundary unless the line
    /// is within `h < 10⁻⁸r` of tangency (see the module docs).
    ///
    /// Bad input (no panic): `t0 > t1` gives 0; a NaN end is unbounded on its
    /// side.
    #[must_use]
    pub fn segment(&self, ray: &Ray<D>, t0: f64, t1: f64) -> f64 {
        self.segment_offset(&self.offset(&ray.origin()), &ray.dir().get(), t0, t1)
    }

    /// [`Sphere::segment`] for the origin's offset `q = o − c` given exactly in
    /// double-double and any finite non-zero direction `w` (not necessarily
    /// unit; the parameter is in units of `|w|`).
    #[inline]
    pub(crate) fn segment_offset(&self, q: &[Dd; D], w: &[f64; D], t0: f64, t1: f64) -> f64 {
        chord(q, w, norm2(w), self.r2, t0, t1)
    }

    /// The `f32` chord kernel shared by the scalar twin and the SIMD batch.
    #[inline(always)]
    fn chord_lanes<L: F32Lane>(&self, o: [L; D], d: [L; D], t0: L, t1: L) -> L {
        let zero = L::splat(0.0);
        let mut q = [zero; D];
        for j in 0..D {
            q[j] = o[j] - L::splat(self.centre32[j]);
        }
        let mut a = d[0] * d[0];
        let mut b = q[0] * d[0];
        for j in 1..D {
            a = a + d[j] * d[j];
            b = b + q[j] * d[j];
        }
        let inv_a = L::splat(1.0) / a;
        let tm = -(b * inv_a);
        // Squared distance from the centre to the line, from the perpendicular
        // component (no cancellation of |q|² against (q·ω)²/a).
        let mut p2 = zero;
        for j in 0..D {
            let e = q[j] + tm * d[j];
            p2 = p2 + e * e;
        }
        let h2 = (L::splat(self.r2_32) - p2) * inv_a;
        let h = h2.max(zero).sqrt();
        let lo = t0.max(tm - h);
        let hi = t1.min(tm + h);
        (hi - lo).max(zero)
    }

    /// `f32` chord clipped to `[t0, t1]` along `o + t·d` (the scalar twin of
    /// [`Sphere::segment_batch_f32`]; `d` as given, not normalised, so `t0`,
    /// `t1` and the result are in units of `|d|`:
    /// [conventions](crate#conventions)): `q = o − c₃₂`, `a = |d|²`,
    /// `t_m = −(q·d)·(1/a)`, `h² = (r₃₂² − |q + t_m d|²)·(1/a)`, result
    /// `max(0, min(t1, t_m + h) − max(t0, t_m − h))` (one division, one square
    /// root, no FMA).
    ///
    /// Error against the exact chord of the `f32` inputs (centre and radius
    /// rounded to `f32`), for `|d| = 1` and `L = |o − c₃₂|`: the distance `d⊥`
    /// from the centre to the line is computed to a few `ε₃₂·L` absolute
    /// (`ε₃₂ = 2⁻²³`), so `h²` is off by about `δ = ε₃₂·(L·r + r²)` and the
    /// chord by about `min(δ/h, 2√δ)`: absolute, in units of `r`, `≈ ε₃₂·L/r`
    /// well inside (`h ≳ r`), growing to `≈ 2√(ε₃₂·L/r)` at tangency (the
    /// square-root singularity of the chord at `d⊥ = r`); clipping adds
    /// `≈ ε₃₂·(|t0| + |t1| + |t±|)`. The tests assert
    /// `|err| ≤ 4·[min(δ/h, 2√δ) + ε₃₂(|t0| + |t1| + |t_m| + h)] + 4ε₃₂r` for
    /// finite ends. Requires `r₃₂²` finite and normal (`10⁻¹⁹ ≲ r ≲ 10¹⁹`) and
    /// `d ≠ 0`; bad input (no panic): `t0 > t1` gives 0, a NaN or infinite
    /// origin gives 0, a NaN end is unbounded.
    #[must_use]
    pub fn segment_f32(
        &self,
        o: impl Into<[f32; D]>,
        d: impl Into<[f32; D]>,
        t0: f32,
        t1: f32,
    ) -> f32 {
        self.chord_lanes::<f32>(o.into(), d.into(), t0, t1)
    }

    /// SIMD batch (8 lanes) of [`Sphere::segment_f32`]: `out[i]` for ray `i`
    /// (pass `t0 = −∞`, `t1 = ∞` for whole chords; directions as given, in
    /// units of `|d|` as the scalar twin). Bit-identical to the scalar twin,
    /// lane by lane; no allocation.
    ///
    /// # Errors
    /// [`ParamError::Length`] if the slices differ in length.
    pub fn segment_batch_f32(
        &self,
        rays: &Rays32<'_, D>,
        out: &mut [f32],
    ) -> Result<(), ParamError> {
        super::ray_batch(self, rays, out)
    }
}

impl<const D: usize> super::RayKernel32<D> for Sphere<D> {
    #[inline(always)]
    fn eval<L: F32Lane>(&self, o: [L; D], d: [L; D], t0: L, t1: L) -> L {
        self.chord_lanes::<L>(o, d, t0, t1)
    }
}

/// The line's closest approach to the centre, from [`foot`]: the chord is
/// `[tm − h, tm + h]` with `h = sd/af`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Foot<const D: usize> {
    /// The parameter the origin was re-based to (near the foot).
    tau: f64,
    /// The same as a double-double (the exact sum of the shifts up to
    /// `3u²` relative).
    tau_dd: Dd,
    /// The re-based offset `q' = q + τω` (double-double).
    qp: [Dd; D],
    /// The origin is so far from the foot (`Σ|q_j| > 10¹²(Σ|q'_j| + r)`) that
    /// the four-fold sum of `|q + eω|² − r²` from `q` (error about
    /// `(62u)⁴|q|²`) would be worse than the double-double one from `q'`
    /// (about `24u²|q_e|²`): end quantities are then formed from `q'`.
    far: bool,
    /// `|ω|²` rounded.
    af: f64,
    /// `√Δ` (Newton-corrected), `Δ` the discriminant of the quadratic.
    sd: f64,
    /// Half chord `√Δ/a`.
    h: f64,
    /// Mid-chord parameter.
    tm: f64,
}

/// The double-double discriminant of the chord's quadratic and the chord's
/// midpoint (steps 1–4 of the algorithm in the module docs), or `None` for a
/// line that misses the open ball (including tangency and overflowing inputs).
#[inline]
pub(crate) fn foot<const D: usize>(q: &[Dd; D], w: &[f64; D], a: Dd, r2: Dd) -> Option<Foot<D>> {
    // Re-base at (nearly) the foot of the perpendicular: q' = q + τω, each
    // shift τ a double and exact as a product (Dd::prod). The rounding of τ
    // leaves q' about (D + 2)u|q| from the foot along ω; the double-double q'
    // holds that offset accurately, so a further pass shrinks it to about u
    // times itself. Passes continue while the offset exceeds r, so
    // |q'| ≲ dist + r afterwards (found by fuzzing: a whole line through
    // (2.4e35, 2.4e35) gave a chord of 2048 for r = 0.13, one through
    // (−7.3e211, …) 1.9e50); an ordinary ray (offset ≈ u|q| ≪ r) takes one
    // pass. Each pass shrinks the offset by about 2⁻⁵⁰, so 25 reach r from any
    // finite point (|p − c| ≤ 10³⁰⁸, r ≥ 10⁻¹⁰⁰).
    let rf = crate::num::scalar::sqrt(r2.hi);
    let sa = crate::num::scalar::sqrt(a.hi);
    let mut qp = *q;
    let mut tau = Dd::ZERO;
    // Σ|q_j| of the point the last shift was computed from (its rounding
    // sets the rejection slack below), and of the given point.
    let mut qn = 0.0;
    let mut q0n = 0.0;
    for pass in 0..25 {
        let mut bp = 0.0;
        let mut qpn = 0.0;
        for j in 0..D {
            bp += qp[j].hi * w[j];
            qpn += qp[j].hi.abs();
        }
        let t = -bp / a.hi;
        if pass == 0 {
            q0n = qpn;
        } else if !(t.abs() * sa > rf) {
            break;
        }
        for j in 0..D {
            qp[j] = qp[j].add(Dd::prod(t, w[j]));
        }
        tau = tau.add(Dd::new(t));
        qn = qpn;
    }
    let tau_dd = tau;
    let tau = tau.to_f64();
    let mut d2 = 0.0;
    let mut qpn = 0.0;
    for j in 0..D {
        d2 += qp[j].hi * qp[j].hi;
        qpn += qp[j].hi.abs();
    }
    // Quick, safe rejection: d2 is within a few ulp of the exact |q'|², and
    // |q'|² = dist² + a(τ − τ*)² with |τ − τ*| ≤ (D + 2)u|q| (τ* the exact
    // foot), which matters when r ≲ u|q| (a tiny ball seen from afar, whose
    // chords were once all rejected). Also rejects NaN from overflowing inputs.
    let far = !(q0n <= 1e12 * (qpn + rf));
    let slack = 8.0 * EPS * qn;
    if !(d2 <= r2.hi * (1.0 + 1e-12) + slack * slack) {
        return None;
    }
    let mut b = Dd::new(0.0);
    let mut qq = Dd::new(0.0);
    for j in 0..D {
        b = b.add(qp[j].mul(Dd::new(w[j])));
        qq = qq.add(qp[j].mul(qp[j]));
    }
    let mut delta = b.mul(b).sub(a.mul(qq.sub(r2)));
    if !(delta.hi > TWO_M40 * a.hi * r2.hi) {
        // Near tangency (or a miss) the double-double Δ has lost ≥ 40 of its
        // bits to |q'|² − r²: recompute it from the exact constant term at the
        // base point τ (Δ = b_e² − a·c_e does not depend on the base point;
        // fuzz finding: a line 1e-42 inside the tangent of r = 4.8e-4 got
        // h = 3e-127 for 3.2e-23 and then a chord of 1.5e63).
        // The exact sum is only as good as its condition number: its error
        // is ≈ γ⁴·Σ|terms| ≈ 2⁻¹⁸⁸|q|² (four-fold precision over ≤ 62 terms),
        // against ≈ 2⁻¹⁰⁰(|q'|² + r²) for the double-double Δ of the re-based
        // q' (the rounding of q' itself). The two meet near |q| ≈ 10¹³·(|q'| +
        // r), so the expansion is used unless the origin is `far` (10¹²),
        // the same rule by which `chord` re-bases its ends: Δ and the roots at
        // the ends then come from one computation. From a far point the
        // expansion cancels by |q|²/r² (fuzz finding: a line through
        // (2.4e35, 2.4e35, 2.4e35) got Δ = 2²³ from it); from a nearer one
        // the double-double Δ cannot resolve h² ≪ 2⁻¹⁰⁰r² (proptest finding:
        // r = 9.9e46, an origin 1.6e50 away on a line 8.95 inside the
        // tangent got h = 0.55 for 1.3e24, and a clipped chord of 1.6e48
        // from the roots re-based with the exact c_e).
        if !far {
            let (be, ce) = rebased_bc(q, w, r2, tau);
            delta = be.mul(be).sub(a.mul(ce));
        }
    }
    if !(delta.hi > 0.0) {
        return None;
    }
    let af = a.to_f64();
    let sd = delta.sqrt().hi;
    let h = sd / af;
    let tm = tau - b.to_f64() / af;
    Some(Foot {
        tau,
        tau_dd,
        qp,
        far,
        af,
        sd,
        h,
        tm,
    })
}

/// A quick `f64` test that the chord of `|y| < r` with `q + tω` misses
/// `[t0, t1]` by more than rounding: the line misses the ball, or the segment
/// ends before the chord starts or starts after it ends. Then the exact chord
/// is 0 and [`chord`] returns exactly `0.0`, so skipping it changes no bit.
///
/// With `q̂ = q.hi`, `t_m = −(q̂·ω)/a` and `e = q̂ + t_m ω` in `f64`, and
/// `S = Σ_j (|q̂_j| + |t_m ω_j|)`: `e` differs from the foot vector `e*`
/// (`e*·ω = 0`, `|e*| = d⊥`) by `(t_m − t*)ω + ρ` with `|ρ_j| ≤ 3u(|q̂_j| +
/// |t_m ω_j|)` (dropping `q.lo`, the product and the sum), so
/// `|fl(|e|²) − d⊥²| ≤ 6uS² + (D + 1)uS² + O(u²S²) ≤ 16uS²`; and
/// `|t_m − t*| ≤ (D + 2)uS`. The tests below add slack for every rounding in
/// them. `false` (run the full chord) whenever anything is not finite.
#[inline]
fn surely_empty<const D: usize>(
    q: &[Dd; D],
    w: &[f64; D],
    a: f64,
    r2: f64,
    t0: f64,
    t1: f64,
) -> bool {
    let mut b = 0.0;
    for j in 0..D {
        b += q[j].hi * w[j];
    }
    let tm = -b / a;
    let mut d2 = 0.0;
    let mut s = 0.0;
    for j in 0..D {
        let tw = tm * w[j];
        let e = q[j].hi + tw;
        d2 += e * e;
        s += q[j].hi.abs() + tw.abs();
    }
    let err = 16.0 * EPS * s * s;
    let r2_hi = r2 * (1.0 + 8.0 * EPS);
    if !(err.is_finite() && d2.is_finite()) {
        return false;
    }
    if d2 > r2_hi + err {
        return true;
    }
    let hmax = crate::num::scalar::sqrt(((r2_hi - d2 + err) / a).max(0.0)) * (1.0 + 8.0 * EPS);
    let mt = 8.0 * EPS * (s + tm.abs() + hmax);
    t1 < tm - hmax - mt || t0 > tm + hmax + mt
}

/// Relative error accepted from [`chord_fast`]: `7u`.
const FAST_REL: f64 = 7.0 * EPS;

/// The chord's quadratic re-based at a finite end `e`, in "double-`f64`"
/// (error-free products and sums, rounded once): `(b, eb, c, ec)` with
/// `b ≈ B = q_e·ω`, `c ≈ C = |q_e|² − r²` (`q_e = q + eω`) and rigorous bounds
/// `|b − B| ≤ eb`, `|c − C| ≤ ec`.
///
/// Per axis, `e·ω_j = p + p'` and `q_j.hi + p = s + s'` exactly, so
/// `q_e,j = s + l` with `l = s' + p' + q_j.lo` (`|l| ≤ 2u(|q_j| + |p|)`,
/// computed with error `≤ 4u²(|q_j| + |p|)`). `B` is the sum of the exact
/// products `s·ω_j` (accumulated by `two_sum`) plus the small terms
/// `l·ω_j` and every rounding error, `C` the same with `s²`, `2sl` and
/// `−r²`: the small terms total at most `9u·M` for `M_b = Σ(|q_j| + |p|)|ω_j|`,
/// `M_c = r² + Σ(|q_j| + |p|)²`, so their plain sum (≤ 10 terms) errs by at
/// most `90u²M`; with the dropped `l²` and the errors of `l`, the final
/// rounding and slack, `eb = u|b| + 128u²M_b`, `ec = u|c| + 256u²M_c`.
#[inline(always)]
fn end_quad<const D: usize>(q: &[Dd; D], w: &[f64; D], r2: Dd, e: f64) -> (f64, f64, f64, f64) {
    let (mut bs, mut blo, mut mb) = (0.0, 0.0, 0.0);
    let (mut cs, mut clo, mut mc) = (-r2.hi, -r2.lo, r2.hi);
    for j in 0..D {
        let (p, pe) = two_prod(e, w[j]);
        let (s, se) = two_sum(q[j].hi, p);
        let l = se + pe + q[j].lo;
        let (bp, bpe) = two_prod(s, w[j]);
        let (t, te) = two_sum(bs, bp);
        bs = t;
        blo += te + bpe + l * w[j];
        let (cp, cpe) = two_prod(s, s);
        let (t, te) = two_sum(cs, cp);
        cs = t;
        clo += te + cpe + 2.0 * s * l;
        let m = q[j].hi.abs() + p.abs();
        mb += m * w[j].abs();
        mc += m * m;
    }
    let b = bs + blo;
    let c = cs + clo;
    if !(mc > 1e-200 && b.is_finite() && c.is_finite()) {
        // Squares near the subnormal range lose relative accuracy, which the
        // bounds below do not model (the `world` fuzz target reached such a
        // case: a near-tangent chord of 8.6e−155 whose h² is subnormal), and
        // an overflowing end or offset has no bound at all: infinite bounds,
        // which fail every test of the fast path, so the exact path decides.
        return (b, f64::INFINITY, c, f64::INFINITY);
    }
    let eb = EPS * b.abs() + 128.0 * EPS * EPS * mb;
    let ec = EPS * c.abs() + 256.0 * EPS * EPS * mc;
    (b, eb, c, ec)
}

/// The roots `(s−, s+)` of `a s² + 2bs + c = 0` (`a = af`, known to `u`
/// relative) from [`end_quad`]'s `(b, eb, c, ec)`, with bounds on their
/// relative errors, and `√Δ` with its relative error; `None` unless `Δ` is
/// positive with a relative error below `1/16` (near tangency, or a miss,
/// the exact path decides).
///
/// `Δ = b² − af·c` from the exact square `b² = p + e` ([`two_prod`]) as
/// `(p − fl(af·c)) + e` (no fused operation, so the same bits in every build);
/// `|Δ̂ − Δ| ≤ u(|Δ̂| + |p − fl(af·c)|) + (2|b| + eb)eb + 2u|af·c| + af·ec`. Then `√Δ` has relative error `≤ 0.54·EΔ/Δ̂ + u`,
/// `k = −(b + sign(b)√Δ)` (no cancellation) `≤ (eb + rel_sd·√Δ)/|k| + u`, the
/// root `k/af` `≤ rel_k + 2u` and the root `c/k` `≤ ec/|c| + rel_k + u`
/// (all times 1.01 for the products of the small factors).
#[inline(always)]
fn fast_roots(af: f64, b: f64, eb: f64, c: f64, ec: f64) -> Option<[f64; 6]> {
    let ac = af * c;
    let (p, e) = two_prod(b, b);
    let pc = p - ac;
    let df = pc + e;
    let ed =
        (EPS * (df.abs() + pc.abs()) + (2.0 * b.abs() + eb) * eb + 2.0 * EPS * ac.abs() + af * ec)
            * 1.01;
    if !(df > 16.0 * ed) || !(df > 1e-250) {
        return None;
    }
    let sd = crate::num::scalar::sqrt(df);
    let rel_sd = 0.54 * (ed / df) + EPS;
    let k = if b >= 0.0 { -(b + sd) } else { sd - b };
    let rel_k = (eb + rel_sd * sd) / k.abs() + EPS;
    let big = k / af;
    let small = c / k;
    let rel_big = 1.01 * (rel_k + 2.0 * EPS);
    let rel_small = 1.01 * (ec / c.abs() + rel_k + EPS);
    let [sm, sp, rsm, rsp] = if b >= 0.0 {
        [big, small, rel_big, rel_small]
    } else {
        [small, big, rel_small, rel_big]
    };
    Some([sm, sp, rsm, rsp, sd, rel_sd])
}

/// The `f64` fast path of [`chord`] for a finite segment: the quadratic
/// re-based at `t0` (and, for a segment that enters the ball and ends inside
/// it, at `t1`) in double-`f64` ([`end_quad`], [`fast_roots`]), each case one
/// accurately computed quantity as in the exact path (exit `s+`, entry
/// `−u−`, whole chord `2√Δ/a`, or `t1 − t0`), returned only when its
/// rigorous relative error bound is at most `7u` (`FAST_REL`) and every
/// decision (which end is inside, which side a root is on) holds with
/// margin; otherwise `None` and the double-double path decides. Results
/// `0` and `t1 − t0` are those of the exact path, bit for bit.
#[inline]
fn chord_fast<const D: usize>(
    q: &[Dd; D],
    w: &[f64; D],
    af: f64,
    r2: Dd,
    t0: f64,
    t1: f64,
) -> Option<f64> {
    if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
        return None;
    }
    let len = t1 - t0;
    let (lo_len, hi_len) = (len * (1.0 - 2.0 * EPS), len * (1.0 + 2.0 * EPS));
    let (b, eb, c, ec) = end_quad(q, w, r2, t0);
    if !(c.abs() > ec) {
        return None;
    }
    let [sm, sp, rsm, rsp, sd, rel_sd] = fast_roots(af, b, eb, c, ec)?;
    // The decisions below use the first-order bounds: only while they are small.
    if !(rsm < 1e-6 && rsp < 1e-6) {
        return None;
    }
    if c < 0.0 {
        // t0 inside: the chord ends at t0 + s+.
        if sp * (1.0 + rsp) < lo_len {
            return (rsp <= FAST_REL).then_some(sp);
        }
        if sp * (1.0 - rsp) > hi_len {
            return Some(len);
        }
        return None;
    }
    // t0 outside: both roots on the side −b points to (Δ > 0 and C > 0 give
    // |B| > √(aC) > 0, so the sign of b is that of B once |b| > eb).
    if !(b.abs() > eb) {
        return None;
    }
    if b > 0.0 {
        return Some(0.0);
    }
    if sm * (1.0 - rsm) > hi_len {
        return Some(0.0);
    }
    if sp * (1.0 + rsp) < lo_len {
        // The whole chord 2√Δ/a.
        let rel = 1.01 * (rel_sd + 2.0 * EPS);
        if rel <= FAST_REL {
            return Some(2.0 * (sd / af));
        }
        // From an end far from the sphere Δ = b² − ac cancels (|b|² ≫ Δ):
        // re-based at (nearly) the foot t0 − b/a, b ≈ 0 and Δ ≈ −ac does not.
        let (bf, ebf, cf, ecf) = end_quad(q, w, r2, t0 - b / af);
        let [.., sdf, relf] = fast_roots(af, bf, ebf, cf, ecf)?;
        let rel = 1.01 * (relf + 2.0 * EPS);
        return (rel <= FAST_REL).then(|| 2.0 * (sdf / af));
    }
    if !(sm * (1.0 + rsm) < lo_len && sp * (1.0 - rsp) > hi_len) {
        return None;
    }
    // Enters inside the segment and t1 is inside: the length is −u−, the
    // entry root re-based at t1.
    let (b1, eb1, c1, ec1) = end_quad(q, w, r2, t1);
    if !(c1 < -ec1) {
        return None;
    }
    let [um, _, rum, ..] = fast_roots(af, b1, eb1, c1, ec1)?;
    (rum <= FAST_REL).then_some((-um).min(len))
}

/// Chord of the free-space ball `|y| < r` (`r² = r2`) with the line
/// `q + tω`, `t ∈ [t0, t1]`; `q` exact in double-double, `a = |ω|²`. See the
/// module docs for the algorithm and its error.
#[inline]
pub(crate) fn chord<const D: usize>(
    q: &[Dd; D],
    w: &[f64; D],
    a: Dd,
    r2: Dd,
    t0: f64,
    t1: f64,
) -> f64 {
    if surely_empty(q, w, a.hi, r2.hi, t0, t1) {
        return 0.0;
    }
    if let Some(v) = chord_fast(q, w, a.hi, r2, t0, t1) {
        return v;
    }
    let Some(f) = foot(q, w, a, r2) else {
        return 0.0;
    };
    let Foot {
        tau, af, sd, h, tm, ..
    } = f;
    let roots_at = |e: f64| {
        if f.far {
            rebased_roots_from_foot(&f.qp, w, r2, af, sd, Dd::new(e).sub(f.tau_dd))
        } else {
            rebased_roots(q, w, r2, af, sd, e)
        }
    };
    let (lo, hi) = (tm - h, tm + h);
    // A bound on |lo − t−| and |hi − t+| (t± the exact roots): the roundings of
    // τ, b/a, t_m and t_m ± h, and the conditioning of h (its absolute error is
    // ≈ 2⁻¹⁰⁴·r²/h, from Δ's). An end farther than `m` from both roots is on a
    // known side of each, so only an end within `m` needs the re-based roots.
    let m = 8.0 * EPS * (tau.abs() + tm.abs() + h) + TWO_M96 * (r2.hi / h);
    if t0 + m < lo && hi + m < t1 {
        // Clearly unclipped; still never longer than the segment itself (when
        // `tm ± h` round onto a zero-length segment far out on the line, found
        // by fuzzing).
        return (2.0 * h).min(t1 - t0);
    }
    // A NaN end is unbounded on its side.
    let t0 = if t0.is_nan() { f64::NEG_INFINITY } else { t0 };
    let t1 = if t1.is_nan() { f64::INFINITY } else { t1 };
    if !(t0 <= t1) || t1 + m < lo || hi + m < t0 {
        return 0.0;
    }
    // The clipped length, each case one accurately computed quantity (no
    // rounded root minus an end). With s± = t± − t0 and u± = t± − t1, the
    // roots of the quadratic re-based at each end (`rebased_roots`; an end
    // farther than `m` from the chord has known signs), and T = fl(t1 − t0):
    //   s− ≤ 0 ≤ u+ (both ends inside):  T,
    //   s− ≤ 0, u+ < 0 (exits inside):    min(T, s+),
    //   s− > 0 (enters inside):           min(T, −u−, 2h)   (−u− = T − s−).
    // The signs of s−, u+ are those of the re-based constant terms c_e, whose
    // double-double error is ≈ 2⁻¹⁰²|q_e|², so an end inside the boundary by
    // more than ≈ 2⁻¹⁰⁰r²/h (far below 1 ulp of e unless e ≈ 0) keeps T.
    let len = t1 - t0;
    if lo + m < t0 && t1 < hi - m {
        // Both ends clearly inside (the signs the re-based roots would give).
        return len;
    }
    let (sm, sp) = if lo <= t0 + m {
        roots_at(t0)
    } else {
        (f64::INFINITY, f64::INFINITY)
    };
    let (um, up) = if t1 <= hi + m {
        roots_at(t1)
    } else {
        (f64::NEG_INFINITY, f64::NEG_INFINITY)
    };
    if sm <= 0.0 {
        if !(sp > 0.0) {
            return 0.0;
        }
        if up >= 0.0 {
            return len;
        }
        return len.min(sp);
    }
    len.min(-um).min(2.0 * h).max(0.0)
}

/// The roots `(s−, s+)`, `s = t − e`, of the chord's quadratic re-based at the
/// finite end `e`: `a s² + 2 b_e s + c_e = 0` with `q_e = q + eω` (exact
/// products, ≈ 2⁻¹⁰⁴-relative sums), `b_e = q_e·ω`, `c_e = |q_e|² − r²` in
/// double-double and `√Δ = sd` (`Δ = b_e² − a c_e` is independent of `e`; the
/// caller's is computed where it does not cancel). The root of larger
/// magnitude is `−(b_e + sign(b_e)√Δ)/a` (no cancellation), the other `c_e`
/// over that numerator (the product of the roots is `c_e/a`), so a root near
/// the end (`c_e → 0`) keeps its relative accuracy.
#[inline]
pub(crate) fn rebased_roots<const D: usize>(
    q: &[Dd; D],
    w: &[f64; D],
    r2: Dd,
    af: f64,
    sd: f64,
    e: f64,
) -> (f64, f64) {
    let (b, c) = rebased_bc_filtered(q, w, r2, e);
    let (b, c) = (b.to_f64(), c.to_f64());
    if b >= 0.0 {
        let k = -(b + sd);
        (k / af, c / k)
    } else {
        let k = sd - b;
        (c / k, k / af)
    }
}

/// [`rebased_roots`] for an origin far from the foot of the perpendicular
/// (`Foot::far`): the quadratic is re-based at `e` from the re-based offset
/// `q' = q + τω` and `e' = e − τ` (double-double), `q_e = q' + e'ω`, with
/// `b_e` and `c_e = |q_e|² − r²` in double-double. Every error is then relative
/// to the local quantities (`q'`, `e'`, `r`: `≈ 24u²(|q_e|² + |e'|·|q_e|)`
/// absolute in `c_e`), not to `|q|²`, which from a far origin exceeds them by
/// up to `10⁶⁰` and defeats even the four-fold sum (found by the world tests:
/// an origin at `10³⁰` with an end at the boundary gave 0 for `1.1e−6`).
#[inline]
fn rebased_roots_from_foot<const D: usize>(
    qp: &[Dd; D],
    w: &[f64; D],
    r2: Dd,
    af: f64,
    sd: f64,
    e: Dd,
) -> (f64, f64) {
    let mut b = Dd::new(0.0);
    let mut c = Dd::new(0.0);
    for j in 0..D {
        let qe = qp[j].add(e.mul(Dd::new(w[j])));
        b = b.add(qe.mul(Dd::new(w[j])));
        c = c.add(qe.mul(qe));
    }
    let (b, c) = (b.to_f64(), c.sub(r2).to_f64());
    if b >= 0.0 {
        let k = -(b + sd);
        (k / af, c / k)
    } else {
        let k = sd - b;
        (c / k, k / af)
    }
}

/// [`rebased_bc`] through a filter: `c_e` in plain double-double
/// (`q_e = q + eω` by the accurate addition, relative error `≤ 3u²`; its
/// square `≤ 7u²` more; the sum of `D` non-negative squares `≤ 3Du²` more;
/// the subtraction of the exact `r²` `≤ 3u²|c_e|`), so
/// `|c_e − ĉ_e| ≤ 24u²·|q_e|² + 3u²|c_e|` (`u²` = `2⁻¹⁰⁶`, with slack for the
/// products of the small factors). When that bound is below `2⁻⁸⁰|c_e|`
/// (`|c_e| ≳ 7·10⁻⁷|q_e|²`, an end not within about `10⁻⁷r²/h` of the
/// boundary) the cheap value is returned, otherwise the exact one. Callers round
/// `c_e` to a double, so the two agree in every bit unless `c_e` lies within
/// `2⁻⁸⁰` relative of a rounding boundary (probability about `2⁻²⁷`), and the
/// accuracy of the roots is that of the exact `c_e` plus `2⁻⁸⁰` relative.
/// `b_e` is formed exactly as in [`rebased_bc`].
#[inline]
pub(crate) fn rebased_bc_filtered<const D: usize>(
    q: &[Dd; D],
    w: &[f64; D],
    r2: Dd,
    e: f64,
) -> (Dd, Dd) {
    const U2_24: f64 = 24.0 * f64::EPSILON * f64::EPSILON / 4.0;
    const TWO_M81: f64 = f64::from_bits((1023 - 81) << 52);
    let mut b = Dd::new(0.0);
    let mut s = Dd::new(0.0);
    for j in 0..D {
        let qe = q[j].add(Dd::prod(e, w[j]));
        b = b.add(qe.mul(Dd::new(w[j])));
        s = s.add(qe.mul(qe));
    }
    let c = s.sub(r2);
    if U2_24 * s.hi <= TWO_M81 * c.hi.abs() {
        return (b, c);
    }
    rebased_bc(q, w, r2, e)
}

/// `b_e = q_e·ω` (double-double) and `c_e = |q_e|² − r²` for `q_e = q + eω`.
///
/// `c_e` cancels to about `h·L` against `r²` for an end near the boundary (`L`
/// its distance to the root, `h` the half chord), and to `r² − d²` at the foot
/// of a near-tangent line, which a double-double sum would resolve only to
/// `2⁻¹⁰⁶r²`: it is formed exactly as a sum of error-free products (`q_j = hi +
/// lo` and `e·ω_j = p + p'` exactly, so `(q + eω)_j²` is 10 products of
/// doubles) summed in four-fold precision ([`sum_accurate`]).
#[inline]
pub(crate) fn rebased_bc<const D: usize>(q: &[Dd; D], w: &[f64; D], r2: Dd, e: f64) -> (Dd, Dd) {
    let mut b = Dd::new(0.0);
    let mut t = [0.0f64; 62];
    let mut n = 0;
    for j in 0..D {
        let qe = q[j].add(Dd::prod(e, w[j]));
        b = b.add(qe.mul(Dd::new(w[j])));
        let (ph, pl) = two_prod(e, w[j]);
        let parts = [q[j].hi, q[j].lo, ph, pl];
        for i in 0..4 {
            for k in i..4 {
                let (x, y) = two_prod(parts[i], parts[k]);
                let f = if i == k { 1.0 } else { 2.0 };
                t[n] = f * x;
                t[n + 1] = f * y;
                n += 2;
            }
        }
    }
    t[n] = -r2.hi;
    t[n + 1] = -r2.lo;
    n += 2;
    (b, sum_accurate(&mut t[..n]))
}

/// `|ω|²` in double-double.
#[inline]
pub(crate) fn norm2<const D: usize>(w: &[f64; D]) -> Dd {
    let mut a = Dd::new(0.0);
    for &x in w {
        a = a.add(Dd::prod(x, x));
    }
    a
}
